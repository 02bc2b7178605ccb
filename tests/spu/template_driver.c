/* tests/spu/template_driver.c — a third-party program built out of tree
 * against the installed headers and pkg-config file: runs the out-of-tree
 * `template` SPU in a chain and checks its counts. Usage: template_driver
 * SUMMARY_FILE. Owns nothing. Never: includes anything but installed headers. */
#include <stdio.h>

#include <tessera/chain.h>
#include <tessera/spu.h>

#include "template_counts.h"

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s SUMMARY_FILE\n", argv[0]);
        return 2;
    }
    tsr_error err;
    const tsr_spu_class *cls = tsr_spu_find("template", &err);
    if (!cls) {
        fprintf(stderr, "template_driver: %s\n", err.message);
        return 1;
    }
    printf("found SPU '%s': %s\n", cls->name, cls->summary);
    remove(argv[1]);
    char text[4096];
    snprintf(text, sizeof text, "template output=\"%s\"", argv[1]);
    tsr_chain *chain = tsr_chain_create(text, &err);
    if (!chain) {
        fprintf(stderr, "template_driver: %s\n", err.message);
        return 1;
    }
    template_expect sent = {0};
    template_send_frames(tsr_chain_head(chain), 3, 7, &sent);
    tsr_chain_destroy(chain);
    if (template_check_summary(argv[1], "template#1", &sent))
        return 1;
    printf("template counted vertices=%llu primitives=%llu swaps=%llu\n", sent.vertices, sent.primitives, sent.swaps);
    return 0;
}
