/* tests/fuzz/fuzz_reply.c — fuzz target for the client's reply parser: the
 * real packer (what the stream client runs, client/client.c) decoding the
 * replies a server sends to its requests (glGet*, glGen*, glIs*,
 * glReadPixels, glGetTexImage, ...; tessera/dev/wire.h section 5) into the
 * application's outputs. Owns one packer per input; nothing between inputs.
 * Input: records, each u16 slot, u32 seed, u32 n, then n bytes: the
 * command in dispatch slot `slot` is called on the packer with the random
 * valid arguments `seed` gives (the generated wire-test calls, whose
 * outputs are heap blocks of the size GL would write, so a reply item the
 * packer copies too far is an ASan report), and every request it makes is
 * answered with those n bytes. The real server's reply would come instead
 * of them; the corpus holds such real replies (made by the real unpacker,
 * `fuzz_reply_seeds`). Checked: a reply the packer refuses is an error with
 * a one-line message, never a crash; a request gets exactly its reply.
 * Built with TSR_FUZZ_SEEDS it is fuzz_reply_seeds OUTDIR, which writes the
 * ok-* seeds: every packable command that makes a request, answered by a
 * real unpacker over the recording table (wire_test_gen.h). */
#include "fuzz_target.h"

#include <stdlib.h>

#include "tessera/dev/pack.h"
#include "tessera/dispatch.h"
#include "tessera/dev/wire.h"
#include "wire_test_gen.h"

#define RECORD_HEADER 10

typedef struct run {
    tsr_dispatch *gl, *expect;
    tsr_recorder recorder;
    tsr_packer *packer;
} run;

static int run_open(run *r, const tsr_pack_sink *sink)
{
    memset(r, 0, sizeof *r);
    tsr_error err = {0};
    r->gl = malloc(sizeof *r->gl);
    r->expect = malloc(sizeof *r->expect);
    r->packer = tsr_packer_create(TSR_PACK_MIN_BUFFER * 16, sink, &err);
    if (!r->gl || !r->expect || !r->packer)
        return TSR_ENOMEM;
    tsr_recorder_init(&r->recorder);
    tsr_recorder_fill(r->expect, &r->recorder);
    tsr_dispatch_fill_nop(r->gl);
    tsr_packer_fill_dispatch(r->packer, r->gl);
    return TSR_OK;
}

static void run_close(run *r)
{
    tsr_packer_destroy(r->packer);
    tsr_recorder_clear(&r->recorder);
    free(r->expect);
    free(r->gl);
}

/* One command on the packer; its outputs are compared with the recording
 * table's, which only matters for the seeds (a fuzzed reply differs). */
static void call_slot(run *r, int slot, uint32_t seed, char *msg, size_t msg_size)
{
    uint64_t rng = seed ? seed : 1;
    tsr_wire_test_call(slot, r->expect, r->gl, &rng, msg, msg_size);
}

#ifndef TSR_FUZZ_SEEDS

typedef struct answer {
    uint8_t *reply; /* exact-size copy of this record's reply bytes */
    size_t size;
    uint64_t requests;
} answer;

static int discard_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    (void)ctx, (void)buf, (void)size, (void)err;
    return 0;
}

static int give_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    (void)id, (void)err;
    answer *a = ctx;
    a->requests++;
    *data = a->reply;
    *size = a->size;
    return 0;
}

static uint32_t get_u32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}


int fuzz_target_explain(const uint8_t *data, size_t size, char *why, size_t why_size)
{
    answer a = {0};
    tsr_pack_sink sink = {.flush = discard_flush, .reply = give_reply, .ctx = &a};
    run r;
    if (run_open(&r, &sink) != TSR_OK) {
        run_close(&r);
        return TSR_ENOMEM;
    }
    int first = TSR_OK;
    size_t pos = 0;
    while (size - pos >= RECORD_HEADER) {
        int slot = (int)((data[pos] | data[pos + 1] << 8) % TSR_DISPATCH_COUNT);
        uint32_t seed = get_u32(data + pos + 2);
        size_t n = get_u32(data + pos + 6);
        pos += RECORD_HEADER;
        if (n > size - pos)
            n = size - pos;
        a.reply = malloc(n ? n : 1);
        FUZZ_REQUIRE(a.reply != NULL);
        memcpy(a.reply, data + pos, n);
        a.size = n;
        pos += n;
        if (tsr_wire_test_packable(slot) == 1) {
            char msg[256];
            call_slot(&r, slot, seed, msg, sizeof msg);
            const tsr_error *e = tsr_packer_error(r.packer);
            if (e->code != TSR_OK) {
                if (first == TSR_OK)
                    first = fuzz_rejected(e->code, e, why, why_size);
                tsr_packer_clear_error(r.packer);
            }
        }
        free(a.reply);
        a.reply = NULL;
        tsr_recorder_clear(&r.recorder);
        tsr_recorder_init(&r.recorder);
    }
    run_close(&r);
    return first;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_target_explain(data, size, NULL, 0);
    return 0;
}

#else /* TSR_FUZZ_SEEDS */

#include "tessera/dev/unpack.h"

/* The server side for the seeds: a real unpacker over the recording table
 * decodes what the packer flushed and produces the reply. */
typedef struct server {
    tsr_dispatch table;
    tsr_recorder gl;
    tsr_unpacker *unpacker;
    uint8_t *reply;
    size_t size;
    int replies;
} server;

static int keep_reply(void *ctx, uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    (void)id, (void)err;
    server *s = ctx;
    free(s->reply);
    s->reply = malloc(size ? size : 1);
    if (!s->reply)
        return tsr_error_set(err, TSR_ENOMEM, "fuzz_reply_seeds: out of memory");
    memcpy(s->reply, data, size);
    s->size = size;
    s->replies++;
    return 0;
}

static int serve_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    server *s = ctx;
    return tsr_unpacker_run(s->unpacker, buf, size, err);
}

static int serve_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    (void)id;
    server *s = ctx;
    if (!s->reply)
        return tsr_error_set(err, TSR_EPROTO, "fuzz_reply_seeds: the unpacker made no reply");
    *data = s->reply;
    *size = s->size;
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s OUTDIR\n", argv[0]);
        return 2;
    }
    int written = 0;
    for (int slot = 0; slot < TSR_DISPATCH_COUNT; slot++) {
        if (tsr_wire_test_packable(slot) != 1)
            continue;
        for (uint32_t seed = 1; seed <= 2; seed++) {
            server *s = calloc(1, sizeof *s);
            tsr_error err = {0};
            tsr_recorder_init(&s->gl);
            tsr_recorder_fill(&s->table, &s->gl);
            s->unpacker = tsr_unpacker_create(&s->table, keep_reply, s, &err);
            tsr_pack_sink sink = {.flush = serve_flush, .reply = serve_reply, .ctx = s};
            run r;
            if (!s->unpacker || run_open(&r, &sink) != TSR_OK) {
                fprintf(stderr, "fuzz_reply_seeds: cannot start: %s\n", err.message);
                return 1;
            }
            char msg[256] = "";
            call_slot(&r, slot, seed, msg, sizeof msg);
            const tsr_error *e = tsr_packer_error(r.packer);
            int ok = e->code == TSR_OK;
            if (!ok || s->replies > 1)
                fprintf(stderr, "fuzz_reply_seeds: gl%s: %s\n", tsr_dispatch_name(slot),
                        ok ? "more than one request" : e->message);
            if (ok && s->replies == 1) {
                char path[4096];
                snprintf(path, sizeof path, "%s/ok-%s-%u.bin", argv[1], tsr_dispatch_name(slot), seed);
                FILE *f = fopen(path, "wb");
                uint8_t h[RECORD_HEADER] = {(uint8_t)slot,
                                            (uint8_t)(slot >> 8),
                                            (uint8_t)seed,
                                            0,
                                            0,
                                            0,
                                            (uint8_t)s->size,
                                            (uint8_t)(s->size >> 8),
                                            (uint8_t)(s->size >> 16),
                                            (uint8_t)(s->size >> 24)};
                if (!f || fwrite(h, 1, sizeof h, f) != sizeof h || fwrite(s->reply, 1, s->size, f) != s->size ||
                    fclose(f) != 0) {
                    fprintf(stderr, "fuzz_reply_seeds: %s: cannot write\n", path);
                    return 1;
                }
                written++;
            }
            run_close(&r);
            tsr_unpacker_destroy(s->unpacker);
            tsr_recorder_clear(&s->gl);
            free(s->reply);
            free(s);
            if (!ok)
                return 1;
        }
    }
    printf("fuzz_reply_seeds: %d seeds written\n", written);
    return written > 0 ? 0 : 1;
}

#endif
