/* tests/wire/make_seeds_test.c — writes a seed corpus for the unpacker fuzzer:
 * real wire buffers packed from real command streams (every command with
 * random valid arguments, immediate mode split across buffers, client-array
 * draws, pixel uploads under odd pixel-store modes, shader sources), one
 * file per buffer, and checks that each decodes cleanly.
 * Usage: wire_make_seeds OUTDIR   (exit 0 when every seed decodes). */
#include <GL/gl.h>
#include <GL/glext.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "tessera/dev/pack.h"
#include "tessera/dev/unpack.h"
#include "wire_test_gen.h"

typedef struct seeds {
    const char *dir;
    int count, bad;
} seeds;

static int write_seed(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    seeds *s = ctx;
    char path[4096];
    snprintf(path, sizeof path, "%s/seed-%03d.bin", s->dir, s->count++);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(buf, 1, size, f) != size) {
        if (f)
            fclose(f);
        return tsr_error_set(err, TSR_EIO, "%s: %s", path, strerror(errno));
    }
    fclose(f);
    int rc = tsr_unpack_fuzz_one(buf, size);
    if (rc) {
        fprintf(stderr, "%s does not decode (%d)\n", path, rc);
        s->bad++;
    }
    return 0;
}

/* Replies are not part of the corpus: answer every request with zeros
 * of the sizes the packer expects by decoding into the recorder. */
typedef struct answer {
    seeds *s;
    tsr_recorder rec;
    tsr_dispatch table;
    tsr_unpacker *u;
    uint8_t *reply;
    size_t len;
} answer;

static int answer_store(void *ctx, uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    (void)id;
    answer *a = ctx;
    free(a->reply);
    a->reply = malloc(size + 1);
    if (!a->reply)
        return tsr_error_set(err, TSR_ENOMEM, "out of memory");
    memcpy(a->reply, data, size);
    a->len = size;
    return 0;
}

static int answer_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    answer *a = ctx;
    if (write_seed(a->s, buf, size, err) != 0)
        return err->code;
    return tsr_unpacker_run(a->u, buf, size, err);
}

static int answer_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    (void)id;
    (void)err;
    answer *a = ctx;
    *data = a->reply;
    *size = a->len;
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: wire_make_seeds OUTDIR\n");
        return 2;
    }
    mkdir(argv[1], 0777);
    seeds s = {.dir = argv[1]};
    answer a = {.s = &s};
    tsr_recorder_init(&a.rec);
    tsr_recorder_fill(&a.table, &a.rec);
    tsr_error err;
    a.u = tsr_unpacker_create(&a.table, answer_store, &a, &err);
    tsr_pack_sink sink = {.flush = answer_flush, .reply = answer_reply, .ctx = &a};
    tsr_packer *p = tsr_packer_create(8192, &sink, &err);
    if (!p || !a.u) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    tsr_dispatch t, expect;
    tsr_packer_fill_dispatch(p, &t);
    tsr_recorder expect_rec;
    tsr_recorder_init(&expect_rec);
    tsr_recorder_fill(&expect, &expect_rec);

    /* Every packable command with random valid arguments. */
    uint64_t rng = 12345;
    char msg[512];
    for (int slot = 0; slot < TSR_DISPATCH_COUNT; slot++)
        tsr_wire_test_call(slot, &expect, &t, &rng, msg, sizeof msg);
    tsr_packer_flush(p);

    /* Immediate mode across several buffers. */
    tsr_call_Begin(&t, GL_TRIANGLE_STRIP);
    for (int i = 0; i < 700; i++) {
        tsr_call_Color4ub(&t, (GLubyte)i, 0, 255, 255);
        tsr_call_TexCoord2f(&t, (float)i, 0.5f);
        tsr_call_Vertex3f(&t, (float)i, (float)(i % 7), 0);
    }
    tsr_call_End(&t);
    tsr_packer_flush(p);

    /* Client-array draws. */
    static float pos[64][3];
    static GLubyte col[64][4];
    for (int i = 0; i < 64; i++) {
        pos[i][0] = (float)i;
        col[i][1] = (GLubyte)i;
    }
    static const GLushort idx[] = {1, 5, 9, 40, 63, 2};
    tsr_call_VertexPointer(&t, 3, GL_FLOAT, 0, pos);
    tsr_call_ColorPointer(&t, 4, GL_UNSIGNED_BYTE, 0, col);
    tsr_call_EnableClientState(&t, GL_VERTEX_ARRAY);
    tsr_call_EnableClientState(&t, GL_COLOR_ARRAY);
    tsr_call_DrawArrays(&t, GL_TRIANGLES, 3, 30);
    tsr_call_DrawElements(&t, GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, idx);
    tsr_packer_flush(p);

    /* Pixel uploads under non-default pixel-store modes. */
    static uint8_t img[64 * 64 * 4];
    tsr_call_PixelStorei(&t, GL_UNPACK_ALIGNMENT, 1);
    tsr_call_PixelStorei(&t, GL_UNPACK_ROW_LENGTH, 40);
    tsr_call_PixelStorei(&t, GL_UNPACK_SKIP_ROWS, 3);
    tsr_call_TexImage2D(&t, GL_TEXTURE_2D, 0, GL_RGBA, 31, 17, 0, GL_RGBA, GL_UNSIGNED_BYTE, img);
    tsr_call_Bitmap(&t, 33, 9, 0, 0, 1, 1, img);
    const GLchar *src[] = {"void main(){}", "// end"};
    tsr_call_ShaderSource(&t, 1, 2, src, NULL);
    tsr_packer_flush(p);

    fprintf(stderr, "%d seeds written to %s, %d do not decode\n", s.count, s.dir, s.bad);
    tsr_packer_destroy(p);
    tsr_unpacker_destroy(a.u);
    tsr_recorder_clear(&a.rec);
    tsr_recorder_clear(&expect_rec);
    free(a.reply);
    return s.bad || s.count < 10 ? 1 : 0;
}
