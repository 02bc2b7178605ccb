/* tests/fuzz/fuzz_render.c — command buffers into a real OSMesa render SPU
 * with per-client budgets on (issue 10, item 12; defects 5 and 6 live
 * there). One input is a received stream, split into wire buffers the way
 * fuzz_unpack_one does, decoded by an unpacker with small limits (as a
 * server node's, tessera/dev/unpack.h) into a fresh render instance with
 * a small texture and window budget; replies are read byte by byte. A
 * failure must be TSR_EPROTO/TSR_ENOMEM with a message. Nothing is kept
 * between inputs (a crash reproduces from its file alone).
 *
 * Built three ways from this file (tests/fuzz.cmake):
 *   FUZZ_RENDER_FUZZER  fuzz_render, the libFuzzer target (TESSERA_FUZZ)
 *   FUZZ_RENDER_REPLAY  fuzz_render_replay DIR|FILE...: runs files without
 *                       libFuzzer (ctest, every build): ok-* must decode,
 *                       refused-BUDGET-* must fail naming BUDGET, others
 *                       only must not crash
 *   FUZZ_RENDER_SEEDS   fuzz_render_seeds OUTDIR: writes the seeds with
 *                       the real packer and checks each as the replay does
 * The render SPU is render's own sources (compiled into the binary, with
 * the fuzzer's instrumentation in fuzz_render), registered in-process as
 * "fuzz_render" with render's options but window output's. */
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <GL/gl.h>
#include <GL/glext.h>

#include "fuzz_bytes.h"
#include "render.h"
#include "tessera/chain.h"
#include "tessera/dev/pack.h"
#include "tessera/dev/unpack.h"
#include "tessera/dev/wire.h"
#include "tessera/dispatch.h"
#include "tessera/spu.h"

/* Small budgets, so inputs reach them. */
#define FUZZ_CHAIN "fuzz_render max_texture_bytes=262144 max_window_pixels=16384"
static const tsr_unpack_limits fuzz_limits = {.max_output = 1 << 20, .max_vertices = 4096, .max_buffer_bytes = 65536};

static const tsr_option_spec fuzz_render_options[] = {RENDER_OPTION_SPECS};
static const tsr_spu_class fuzz_render_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "fuzz_render",
    .summary = "render.c, compiled into the fuzz target",
    .options = fuzz_render_options,
    .option_count = sizeof fuzz_render_options / sizeof fuzz_render_options[0],
    .create = render_spu_create,
    .destroy = render_spu_destroy,
};

static int read_reply(void *ctx, uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    (void)err;
    uint32_t *sum = ctx;
    *sum ^= id;
    for (size_t i = 0; i < size; i++)
        *sum = *sum * 31u + data[i];
    size_t pos = 0;
    while (pos < size) {
        uint64_t len;
        if (size - pos < 8)
            __builtin_trap();
        memcpy(&len, data + pos, 8);
        if (len > size - pos - 8)
            __builtin_trap();
        pos = (pos + 8 + (size_t)len + 7u) & ~(size_t)7u;
    }
    return 0;
}

/* Runs one input; returns 0 or the first error (its message in `why`). */
static int fuzz_render_run(const uint8_t *data, size_t size, char *why, size_t why_size)
{
    static int registered;
    tsr_error err = {0};
    if (!registered && tsr_spu_register(&fuzz_render_class, &err) != TSR_OK) {
        fprintf(stderr, "fuzz_render: %s\n", err.message);
        abort();
    }
    registered = 1;
    tsr_chain *chain = tsr_chain_create(FUZZ_CHAIN, &err);
    if (!chain) {
        fprintf(stderr, "fuzz_render: chain: %s\n", err.message);
        abort(); /* the harness is broken, not the input */
    }
    uint32_t sum = 0;
    tsr_unpacker *u = tsr_unpacker_create(tsr_chain_head(chain), read_reply, &sum, &err);
    if (!u || tsr_unpacker_set_limits(u, &fuzz_limits, &err) != TSR_OK)
        abort();
    int first_error = 0;
    size_t pos = 0;
    do {
        size_t rest = size - pos;
        tsr_error header_err;
        size_t n = tsr_wire_buffer_size(data + pos, rest, &header_err);
        if (n == 0 || n > rest)
            n = rest;
        tsr_error_clear(&err);
        int rc = tsr_unpacker_run(u, data + pos, n, &err);
        if (rc == TSR_UNPACK_YIELDED)
            rc = 0; /* nothing here blocks; a yield ends the buffer */
        if (rc != 0 && ((rc != TSR_EPROTO && rc != TSR_ENOMEM) || err.code != rc || !err.message[0]))
            __builtin_trap(); /* the error contract */
        if (rc != 0 && !first_error) {
            first_error = rc;
            if (why && why_size)
                snprintf(why, why_size, "%s", err.message);
        }
        pos += n;
        /* A budgeted stream that failed is dropped by a server: so here. */
    } while (pos < size && !first_error);
    tsr_unpacker_destroy(u);
    tsr_chain_destroy(chain);
    return first_error;
}

#ifdef FUZZ_RENDER_FUZZER
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_render_run(data, size, NULL, 0);
    return 0;
}
#endif

#if defined(FUZZ_RENDER_REPLAY) || defined(FUZZ_RENDER_SEEDS)
/* ok-*: must decode; refused-BUDGET-*: must fail naming BUDGET=; other
 * names must only not crash. Prints one line per failure. */
static int check_input(const char *name, const uint8_t *data, size_t size)
{
    char why[600] = "";
    uint8_t *exact = malloc(size ? size : 1); /* ASan sees a read past the end */
    if (!exact)
        return -1;
    memcpy(exact, data, size);
    int rc = fuzz_render_run(exact, size, why, sizeof why);
    free(exact);
    const char *base = strrchr(name, '/') ? strrchr(name, '/') + 1 : name;
    if (!strncmp(base, "ok-", 3) && rc != 0) {
        fprintf(stderr, "FAIL: %s must decode, got: %s\n", name, why);
        return -1;
    }
    if (!strncmp(base, "refused-", 8)) {
        char budget[64];
        const char *dash = strchr(base + 8, '-');
        size_t n = dash ? (size_t)(dash - base - 8) : 0;
        if (!n || n >= sizeof budget - 1) {
            fprintf(stderr, "FAIL: %s: name a budget: refused-BUDGET-what.bin\n", name);
            return -1;
        }
        memcpy(budget, base + 8, n);
        budget[n] = '=';
        budget[n + 1] = '\0';
        if (rc == 0 || !strstr(why, budget)) {
            fprintf(stderr, "FAIL: %s must be refused naming %s got: %s\n", name, budget, rc ? why : "no error");
            return -1;
        }
    }
    return 0;
}
#endif

#ifdef FUZZ_RENDER_REPLAY
static int replay_path(const char *path, size_t *count)
{
    struct stat st;
    if (stat(path, &st) != 0) {
        fprintf(stderr, "fuzz_render_replay: %s: %s\n", path, strerror(errno));
        return -1;
    }
    if (S_ISDIR(st.st_mode)) {
        DIR *d = opendir(path);
        if (!d) {
            fprintf(stderr, "fuzz_render_replay: %s: %s\n", path, strerror(errno));
            return -1;
        }
        int status = 0;
        struct dirent *e;
        while ((e = readdir(d))) {
            if (e->d_name[0] == '.')
                continue;
            char sub[4096];
            snprintf(sub, sizeof sub, "%s/%s", path, e->d_name);
            status |= replay_path(sub, count);
        }
        closedir(d);
        return status;
    }
    FILE *f = fopen(path, "rb");
    uint8_t *buf = f ? malloc((size_t)st.st_size + 1) : NULL;
    size_t n = buf ? fread(buf, 1, (size_t)st.st_size, f) : 0;
    int bad = !f || !buf || n != (size_t)st.st_size;
    if (f)
        fclose(f);
    if (bad) {
        fprintf(stderr, "fuzz_render_replay: %s: read failed\n", path);
        free(buf);
        return -1;
    }
    int rc = check_input(path, buf, n);
    free(buf);
    (*count)++;
    return rc;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: fuzz_render_replay DIR|FILE...\n");
        return 2;
    }
    size_t count = 0;
    int status = 0;
    for (int i = 1; i < argc; i++)
        status |= replay_path(argv[i], &count);
    printf("fuzz_render_replay: %zu inputs, %s\n", count, status ? "FAILED" : "all behaved");
    return status ? 1 : 0;
}
#endif

#ifdef FUZZ_RENDER_SEEDS
/* What the packer flushed for one scenario. */
typedef fuzz_bytes capture;

static int capture_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    return fuzz_bytes_append(ctx, buf, size, "fuzz_render_seeds", err);
}

/* The seeds never read a reply (a server would answer; the fuzz input is
 * only what goes in): the packer carries on without it. */
static int no_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    (void)ctx, (void)data, (void)size;
    return tsr_error_set(err, TSR_EIO, "seed reply %u not read", id);
}

static void triangle(const tsr_dispatch *d)
{
    tsr_call_Begin(d, GL_TRIANGLES);
    tsr_call_Color3f(d, 1, 0, 0);
    tsr_call_Vertex2f(d, -0.5f, -0.5f);
    tsr_call_Vertex2f(d, 0.5f, -0.5f);
    tsr_call_Vertex2f(d, 0.0f, 0.5f);
    tsr_call_End(d);
}

static const GLfloat quad[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
static const GLushort quad_indices[6] = {0, 1, 2, 0, 2, 3};
static const GLfloat small[18]; /* a 72-byte buffer */

static void scenario(const char *name, const tsr_dispatch *d)
{
    static unsigned char pixels[64 * 64 * 4];
    tsr_call_WindowCreateTSR(d, 0, 64, 64);
    tsr_call_ClearColor(d, 0.25f, 0.5f, 0.75f, 1);
    tsr_call_Clear(d, GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (!strcmp(name, "ok-triangle-swap")) {
        triangle(d);
    } else if (!strcmp(name, "ok-texture-quad")) {
        static unsigned char texels[16 * 16 * 4];
        for (size_t i = 0; i < sizeof texels; i++)
            texels[i] = (unsigned char)(i * 7);
        tsr_call_BindTexture(d, GL_TEXTURE_2D, 3);
        tsr_call_TexParameteri(d, GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        tsr_call_TexImage2D(d, GL_TEXTURE_2D, 0, GL_RGBA, 16, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
        tsr_call_TexImage2D(d, GL_TEXTURE_2D, 0, GL_RGBA, 16, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
        tsr_call_Enable(d, GL_TEXTURE_2D);
        tsr_call_Begin(d, GL_QUADS);
        tsr_call_TexCoord2f(d, 0, 0), tsr_call_Vertex2f(d, -1, -1);
        tsr_call_TexCoord2f(d, 1, 0), tsr_call_Vertex2f(d, 1, -1);
        tsr_call_TexCoord2f(d, 1, 1), tsr_call_Vertex2f(d, 1, 1);
        tsr_call_TexCoord2f(d, 0, 1), tsr_call_Vertex2f(d, -1, 1);
        tsr_call_End(d);
        GLuint names[1] = {3};
        tsr_call_DeleteTextures(d, 1, names);
    } else if (!strcmp(name, "ok-client-arrays")) {
        tsr_call_VertexPointer(d, 3, GL_FLOAT, 0, quad);
        tsr_call_EnableClientState(d, GL_VERTEX_ARRAY);
        tsr_call_DrawArrays(d, GL_TRIANGLE_FAN, 0, 4);
        tsr_call_DrawElements(d, GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, quad_indices);
        tsr_call_DisableClientState(d, GL_VERTEX_ARRAY);
    } else if (!strcmp(name, "ok-buffer-objects")) {
        tsr_call_BindBuffer(d, GL_ARRAY_BUFFER, 1);
        tsr_call_BufferData(d, GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
        tsr_call_BindBuffer(d, GL_ELEMENT_ARRAY_BUFFER, 2);
        tsr_call_BufferData(d, GL_ELEMENT_ARRAY_BUFFER, sizeof quad_indices, quad_indices, GL_STATIC_DRAW);
        tsr_call_VertexPointer(d, 3, GL_FLOAT, 0, NULL);
        tsr_call_EnableClientState(d, GL_VERTEX_ARRAY);
        tsr_call_DrawArrays(d, GL_TRIANGLE_FAN, 0, 4);
        tsr_call_DrawElements(d, GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, NULL);
        tsr_call_DisableClientState(d, GL_VERTEX_ARRAY);
        GLuint names[2] = {1, 2};
        tsr_call_DeleteBuffers(d, 2, names);
    } else if (!strcmp(name, "ok-display-list-readback")) {
        tsr_call_NewList(d, 5, GL_COMPILE);
        triangle(d);
        tsr_call_EndList(d);
        tsr_call_CallList(d, 5);
        tsr_call_ReadPixels(d, 0, 0, 64, 64, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
        tsr_call_CopyTexImage2D(d, GL_TEXTURE_2D, 0, GL_RGBA, 0, 0, 32, 32, 0);
    } else if (!strcmp(name, "ok-contexts")) {
        tsr_call_ContextCreateTSR(d, 1);
        tsr_call_MakeCurrentTSR(d, 0, 1);
        triangle(d);
        tsr_call_MakeCurrentTSR(d, 0, 0);
        tsr_call_ContextDestroyTSR(d, 1);
    } else if (!strcmp(name, "refused-max_texture_bytes-teximage")) {
        for (GLuint t = 1; t <= 4; t++) {
            tsr_call_BindTexture(d, GL_TEXTURE_2D, t);
            tsr_call_TexImage2D(d, GL_TEXTURE_2D, 0, GL_RGBA, 256, 128, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
        }
    } else if (!strcmp(name, "refused-max_vertices-no-arrays")) {
        tsr_call_DrawArrays(d, GL_POINTS, 2147483647, 2147483647);
    } else if (!strcmp(name, "refused-max_buffer_bytes-bufferdata")) {
        tsr_call_BindBuffer(d, GL_ARRAY_BUFFER, 1);
        tsr_call_BufferData(d, GL_ARRAY_BUFFER, 1 << 20, NULL, GL_STATIC_DRAW);
    } else if (!strcmp(name, "refused-max_reply_bytes-readpixels")) {
        tsr_call_ReadPixels(d, 0, 0, 16384, 16384, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    } else if (!strcmp(name, "refused-max_window_pixels-window")) {
        tsr_call_WindowSizeTSR(d, 0, 16384, 16384);
    } else if (!strcmp(name, "bad-draw-past-vertex-buffer")) {
        tsr_call_BindBuffer(d, GL_ARRAY_BUFFER, 1);
        tsr_call_BufferData(d, GL_ARRAY_BUFFER, sizeof small, small, GL_STATIC_DRAW);
        tsr_call_VertexPointer(d, 3, GL_FLOAT, 0, NULL);
        tsr_call_EnableClientState(d, GL_VERTEX_ARRAY);
        tsr_call_DrawArrays(d, GL_POINTS, 2147483647, 2147483647);
    } else if (!strcmp(name, "bad-draw-past-index-buffer")) {
        tsr_call_BindBuffer(d, GL_ARRAY_BUFFER, 1);
        tsr_call_BufferData(d, GL_ARRAY_BUFFER, sizeof small, small, GL_STATIC_DRAW);
        tsr_call_BindBuffer(d, GL_ELEMENT_ARRAY_BUFFER, 2);
        tsr_call_BufferData(d, GL_ELEMENT_ARRAY_BUFFER, sizeof small, small, GL_STATIC_DRAW);
        tsr_call_VertexPointer(d, 3, GL_FLOAT, 0, NULL);
        tsr_call_EnableClientState(d, GL_VERTEX_ARRAY);
        tsr_call_DrawElements(d, GL_POINTS, 2147483647, GL_UNSIGNED_INT, NULL);
    }
    tsr_call_SwapBuffersTSR(d, 0, 0);
}

int main(int argc, char **argv)
{
    static const char *const names[] = {
        "ok-triangle-swap",
        "ok-texture-quad",
        "ok-client-arrays",
        "ok-buffer-objects",
        "ok-display-list-readback",
        "ok-contexts",
        "refused-max_texture_bytes-teximage",
        "refused-max_vertices-no-arrays",
        "refused-max_buffer_bytes-bufferdata",
        "refused-max_reply_bytes-readpixels",
        "refused-max_window_pixels-window",
        "bad-draw-past-vertex-buffer",
        "bad-draw-past-index-buffer",
    };
    if (argc != 2) {
        fprintf(stderr, "usage: fuzz_render_seeds OUTDIR\n");
        return 2;
    }
    int status = 0;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        capture c = {0};
        tsr_pack_sink sink = {.flush = capture_flush, .reply = no_reply, .ctx = &c};
        tsr_error err = {0};
        tsr_packer *p = tsr_packer_create(1 << 16, &sink, &err);
        tsr_dispatch *d = calloc(1, sizeof *d);
        if (!p || !d) {
            fprintf(stderr, "fuzz_render_seeds: %s\n", p ? "out of memory" : err.message);
            return 1;
        }
        tsr_packer_fill_dispatch(p, d);
        scenario(names[i], d);
        tsr_packer_flush(p);
        tsr_packer_destroy(p);
        free(d);
        char path[4096];
        snprintf(path, sizeof path, "%s/%s.bin", argv[1], names[i]);
        int bad = check_input(path, c.bytes, c.len);
        /* bad-*: the unpacker must refuse them (a read past a buffer). */
        if (!bad && !strncmp(names[i], "bad-", 4)) {
            char why[600] = "";
            if (fuzz_render_run(c.bytes, c.len, why, sizeof why) == 0 || !strstr(why, "lie")) {
                fprintf(stderr, "FAIL: %s must be refused as a read past its buffer, got: %s\n", names[i], why);
                bad = 1;
            }
        }
        FILE *f = bad ? NULL : fopen(path, "wb");
        if (!bad && (!f || fwrite(c.bytes, 1, c.len, f) != c.len)) {
            fprintf(stderr, "fuzz_render_seeds: %s: %s\n", path, strerror(errno));
            bad = 1;
        }
        if (f)
            fclose(f);
        status |= bad;
        free(c.bytes);
    }
    printf("fuzz_render_seeds: %zu seeds %s\n", sizeof names / sizeof names[0], status ? "FAILED" : "written");
    return status;
}
#endif
