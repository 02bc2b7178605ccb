/* tests/spu/two_instances_test.c — two instances of one plugin in one
 * process: the `template` SPU (built from spus/template) in two chains at
 * once, fed interleaved streams, must count independently; passthrough
 * instances sit around them. Arguments after the test name: TEMPLATE_DIR
 * WORK_DIR. Owns nothing. Never: relies on creation order for results. */
#include <stdlib.h>

#include "spu_test.h"
#include "template_counts.h"
#include "tessera/spu.h"

static void test_two_instances(void)
{
    const char *template_dir = spu_test_argv[0], *work = spu_test_argv[1];
    setenv("TESSERA_SPU_PATH", template_dir, 1);
    char out_a[4096], out_b[4096], text_a[8192 + 64], text_b[8192 + 64];
    snprintf(out_a, sizeof out_a, "%s/two_instances_a.txt", work);
    snprintf(out_b, sizeof out_b, "%s/two_instances_b.txt", work);
    remove(out_a);
    remove(out_b);
    snprintf(text_a, sizeof text_a, "template output=\"%s\" ! passthrough", out_a);
    snprintf(text_b, sizeof text_b, "passthrough ! template output=\"%s\" forward=no", out_b);

    tsr_error err;
    tsr_chain *a = tsr_chain_create(text_a, &err);
    if (!a)
        fprintf(stderr, "chain a: %s\n", err.message);
    REQUIRE(a);
    tsr_chain *b = tsr_chain_create(text_b, &err);
    if (!b)
        fprintf(stderr, "chain b: %s\n", err.message);
    REQUIRE(b);

    template_expect sent_a = {0}, sent_b = {0};
    for (int round = 0; round < 3; round++) {
        template_send_frames(tsr_chain_head(a), 1, 2 + round, &sent_a);
        template_send_frames(tsr_chain_head(b), 2, 5, &sent_b);
    }
    CHECK(sent_a.vertices != sent_b.vertices); /* the streams differ */
    tsr_chain_destroy(b);
    tsr_chain_destroy(a);
    CHECK(template_check_summary(out_a, "template#1", &sent_a) == 0);
    CHECK(template_check_summary(out_b, "template#1", &sent_b) == 0);
}

static void test_two_instances_in_one_chain(void)
{
    const char *template_dir = spu_test_argv[0], *work = spu_test_argv[1];
    setenv("TESSERA_SPU_PATH", template_dir, 1);
    char out_1[4096], out_2[4096], text[12288];
    snprintf(out_1, sizeof out_1, "%s/one_chain_1.txt", work);
    snprintf(out_2, sizeof out_2, "%s/one_chain_2.txt", work);
    snprintf(text, sizeof text, "template output=%s ! template output=%s", out_1, out_2);
    tsr_error err;
    tsr_chain *chain = tsr_chain_create(text, &err);
    if (!chain)
        fprintf(stderr, "chain: %s\n", err.message);
    REQUIRE(chain);
    template_expect sent = {0};
    template_send_frames(tsr_chain_head(chain), 4, 3, &sent);
    tsr_chain_destroy(chain);
    /* The first forwards everything, so both saw the same stream. */
    CHECK(template_check_summary(out_1, "template#1", &sent) == 0);
    CHECK(template_check_summary(out_2, "template#2", &sent) == 0);
}

static const spu_test_case tests[] = {
    {"spu_two_instances_one_process", test_two_instances},
    {"spu_two_instances_one_chain", test_two_instances_in_one_chain},
};

SPU_TEST_MAIN(tests)
