/* tests/spu/names_lint_sample.c — what names_lint must find (the core as
 * it was before SPUs declared their roles, lines marked FIND) and what it
 * must let pass (lines marked PASS): comments naming pack, tilesort or
 * readback, ordinary words, control-message fields. Never compiled. */
#include <string.h>

static const char *const network_spus[] = {"pack", "replicate"}; /* FIND x2 */

static int check_readback(const char *spu) /* FIND */ { return !strcmp(spu, "tilesort"); /* FIND */ }

static void chain_text(struct sb *b, const struct spu_class *cls)
{
    if (spu_has_option(cls, "servers"))                         /* FIND */
        sb_option(b, "token", "T");                             /* FIND */
    if (!strcmp(l->keys[k], "tiles"))                           /* FIND */
        sb_str(b, "pack server=tcp://127.0.0.1:7000 ! render"); /* FIND x2 */
}

/* PASS from here on: the words as words, and control fields. */
static void legit(struct out *out, const char *token)
{
    ctl_add(out, "role", is_server ? "server" : "app");
    ctl_add(out, "token", token);
    printf("render %.3f s, tiles packed\n", busy);
    fprintf(stderr, "listen on loopback only\n");
    tsr_packer_flush(packer); /* pack, render and print are words here */
}
