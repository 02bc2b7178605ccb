/* tests/fuzz/fuzz_chain.c — fuzz target for the chain text and option
 * parsers (tessera/chain.h: "spu key=value ! spu ..." as `tessera node
 * --chain` and TESSERA_CHAIN give it; core/spu/chain.c, options.c): the
 * input is the text; each link is then checked the way tsr_chain_create
 * checks it before creating anything (the SPU found among the real plugins
 * of this build, its options parsed and validated against the class's
 * declarations). Owns the parsed links of one input.
 * Checked: a rejection is a one-line message; the text of the parsed links
 * (tsr_chain_links_text) parses back to exactly the same links. */
#include "fuzz_target.h"

#include <stdlib.h>

#include "chain.h"
#include "tessera/spu.h"

static void check_round_trip(const tsr_chain_text *parsed)
{
    tsr_error err = {0};
    char *text = tsr_chain_links_text(parsed->links, parsed->count, &err);
    FUZZ_REQUIRE(text != NULL);
    tsr_chain_text back;
    FUZZ_REQUIRE(tsr_chain_text_parse(text, &back, &err) == TSR_OK);
    FUZZ_REQUIRE(back.count == parsed->count);
    for (size_t i = 0; i < back.count; i++) {
        const tsr_chain_link *a = &parsed->links[i], *b = &back.links[i];
        FUZZ_REQUIRE(!strcmp(a->spu, b->spu) && a->option_count == b->option_count);
        for (size_t k = 0; k < a->option_count; k++)
            FUZZ_REQUIRE(!strcmp(a->keys[k], b->keys[k]) && !strcmp(a->values[k], b->values[k]));
    }
    tsr_chain_text_free(&back);
    free(text);
}

int fuzz_target_explain(const uint8_t *data, size_t size, char *why, size_t why_size)
{
    char *text = malloc(size + 1);
    FUZZ_REQUIRE(text != NULL);
    memcpy(text, data, size);
    text[size] = '\0';
    tsr_chain_text parsed;
    tsr_error err = {0};
    int rc = tsr_chain_text_parse(text, &parsed, &err);
    free(text);
    if (rc != TSR_OK)
        return fuzz_rejected(rc, &err, why, why_size);
    FUZZ_REQUIRE(parsed.count >= 1);
    check_round_trip(&parsed);
    for (size_t i = 0; i < parsed.count && rc == TSR_OK; i++) {
        const tsr_chain_link *l = &parsed.links[i];
        const tsr_spu_class *cls = tsr_spu_find(l->spu, &err);
        if (!cls) {
            rc = fuzz_rejected(err.code ? err.code : TSR_ENOENT, &err, why, why_size);
            break;
        }
        rc = tsr_spu_check_options(cls, l->keys, l->values, l->option_count, &err);
        if (rc != TSR_OK)
            rc = fuzz_rejected(rc, &err, why, why_size);
    }
    tsr_chain_text_free(&parsed);
    return rc;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_target_explain(data, size, NULL, 0);
    return 0;
}
