/* tests/fuzz/fuzz_ctl.c — fuzz target for the mothership's control messages,
 * both directions (mothership/control.h): the key=value codec (tsr_ctl_parse)
 * and what each side then reads from a message of that kind, including the
 * chain a CONFIG or LINKS carries (tsr_ctl_chain_parse) and the
 * TESSERA_CHAIN text an app node makes of it (tsr_chain_links_text, read
 * back with the chain text parser). Owns nothing between inputs.
 * Input: byte 0 picks the message kind (of the eight), the rest is the
 * payload as it arrives in a netlib message. Checked properties: a
 * rejection is TSR_EPROTO with a one-line message; every field is
 * key=value with a non-empty key; encoding the decoded fields again
 * (tsr_ctl_add) decodes to the same fields; links with well-formed names
 * survive the trip through chain text unchanged. */
#include "fuzz_target.h"

#include <stdbool.h>
#include <stdlib.h>

#include "chain.h"
#include "control.h"

static const unsigned kinds[] = {TSR_MS_MSG_JOIN,   TSR_MS_MSG_READY, TSR_MS_MSG_STATS,  TSR_MS_MSG_DONE,
                                 TSR_MS_MSG_CONFIG, TSR_MS_MSG_STOP,  TSR_MS_MSG_REFUSE, TSR_MS_MSG_LINKS};

/* The fields each receiver reads (control.h), as strings and numbers. */
static const char *const string_fields[] = {"name", "host",  "address", "message", "app_stats", "sort_first",
                                            "role", "links", "listen",  "token",   "reason",    "listen_port"};
static const char *const number_fields[] = {
    "rank",    "pid",    "frames", "buffers",      "bytes_in",   "bytes_out",       "busy_seconds",   "clients",
    "elapsed", "status", "signal", "heartbeat_ms", "timeout_ms", "idle_timeout_ms", "blocked_seconds"};

static bool plain_spu(const char *s)
{
    if (!*s)
        return false;
    for (; *s; s++)
        if (!((*s >= 'a' && *s <= 'z') || (*s >= '0' && *s <= '9') || *s == '_'))
            return false;
    return true;
}

static bool plain_key(const char *s) { return *s && s[strcspn(s, "= \t\r\n\f\v!\"")] == '\0'; }

/* The receiving node's half for CONFIG/LINKS: the links, and the chain text
 * an application gets from them. */
static int check_chain(const tsr_ctl *msg, char *why, size_t why_size)
{
    tsr_ctl_chain chain;
    tsr_error err = {0};
    int rc = tsr_ctl_chain_parse(msg, &chain, &err);
    if (rc != TSR_OK) {
        FUZZ_REQUIRE(rc == TSR_EPROTO || rc == TSR_ENOMEM);
        return fuzz_rejected(rc, &err, why, why_size);
    }
    FUZZ_REQUIRE(chain.count >= 1);
    size_t options = 0;
    bool plain = true;
    for (size_t i = 0; i < chain.count; i++) {
        const tsr_chain_link *l = &chain.links[i];
        plain = plain && plain_spu(l->spu);
        for (size_t k = 0; k < l->option_count; k++)
            plain = plain && plain_key(l->keys[k]) && strlen(l->values[k]) < 100000;
        options += l->option_count;
    }
    FUZZ_REQUIRE(options == chain.option_count);
    char *text = tsr_chain_links_text(chain.links, chain.count, &err);
    FUZZ_REQUIRE(text != NULL);
    tsr_chain_text back;
    rc = tsr_chain_text_parse(text, &back, &err);
    if (plain) {
        /* tessera/chain.h: the text reads back exactly these links. */
        FUZZ_REQUIRE(rc == TSR_OK && back.count == chain.count);
        for (size_t i = 0; i < chain.count; i++) {
            const tsr_chain_link *a = &chain.links[i], *b = &back.links[i];
            FUZZ_REQUIRE(!strcmp(a->spu, b->spu) && a->option_count == b->option_count);
            for (size_t k = 0; k < a->option_count; k++)
                FUZZ_REQUIRE(!strcmp(a->keys[k], b->keys[k]) && !strcmp(a->values[k], b->values[k]));
        }
    }
    if (rc == TSR_OK)
        tsr_chain_text_free(&back);
    free(text);
    tsr_ctl_chain_free(&chain);
    return TSR_OK;
}

/* The sending side: the decoded fields encoded again decode to themselves
 * (a carriage return in a value becomes a blank, control.h). */
static void check_reencode(const tsr_ctl *msg)
{
    tsr_ctl_out out;
    tsr_ctl_out_init(&out);
    for (size_t i = 0; i < msg->count; i++)
        tsr_ctl_add(&out, msg->keys[i], msg->values[i]);
    FUZZ_REQUIRE(!out.failed);
    tsr_ctl *again = malloc(sizeof *again);
    FUZZ_REQUIRE(again != NULL);
    tsr_error err = {0};
    FUZZ_REQUIRE(tsr_ctl_parse(again, out.text ? out.text : "", out.len, &err) == TSR_OK);
    FUZZ_REQUIRE(again->count == msg->count);
    for (size_t i = 0; i < msg->count; i++) {
        FUZZ_REQUIRE(!strcmp(again->keys[i], msg->keys[i]));
        const char *a = again->values[i], *b = msg->values[i];
        for (; *a && *b; a++, b++)
            FUZZ_REQUIRE(*a == *b || (*a == ' ' && *b == '\r'));
        FUZZ_REQUIRE(*a == *b);
    }
    tsr_ctl_free(again);
    free(again);
    tsr_ctl_out_free(&out);
}

int fuzz_target_explain(const uint8_t *data, size_t size, char *why, size_t why_size)
{
    if (size == 0)
        return TSR_OK;
    unsigned kind = kinds[data[0] % (sizeof kinds / sizeof kinds[0])];
    /* An exact-size copy of the payload, as netlib hands it over. */
    uint8_t *payload = malloc(size - 1 ? size - 1 : 1);
    tsr_ctl *msg = malloc(sizeof *msg);
    FUZZ_REQUIRE(payload && msg);
    memcpy(payload, data + 1, size - 1);
    tsr_error err = {0};
    int rc = tsr_ctl_parse(msg, payload, size - 1, &err);
    free(payload);
    if (rc != TSR_OK) {
        FUZZ_REQUIRE(rc == TSR_EPROTO || rc == TSR_ENOMEM);
        free(msg);
        return fuzz_rejected(rc, &err, why, why_size);
    }
    for (size_t i = 0; i < msg->count; i++) {
        FUZZ_REQUIRE(msg->keys[i][0] != '\0' && !strchr(msg->keys[i], '=') && !strchr(msg->keys[i], '\n'));
        FUZZ_REQUIRE(!strchr(msg->values[i], '\n'));
        /* The first fields only: all of them would make each input quadratic. */
        FUZZ_REQUIRE(i >= 64 || tsr_ctl_get(msg, msg->keys[i]) != NULL);
    }
    size_t sum = 0;
    for (size_t i = 0; i < sizeof string_fields / sizeof string_fields[0]; i++) {
        const char *v = tsr_ctl_get(msg, string_fields[i]);
        sum += v ? strlen(v) : 0;
    }
    double total = 0;
    for (size_t i = 0; i < sizeof number_fields / sizeof number_fields[0]; i++)
        total += tsr_ctl_number(msg, number_fields[i], 0);
    (void)sum, (void)total;
    FUZZ_REQUIRE(strcmp(tsr_ctl_kind_name(kind), "unknown") != 0);
    check_reencode(msg);
    rc = TSR_OK;
    if (kind == TSR_MS_MSG_LINKS || (kind == TSR_MS_MSG_CONFIG && !tsr_ctl_get(msg, "links")))
        rc = check_chain(msg, why, why_size);
    tsr_ctl_free(msg);
    free(msg);
    return rc;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_target_explain(data, size, NULL, 0);
    return 0;
}
