/* tests/fuzz/fuzz_ext.c — fuzz target for the tessera extension commands
 * (TilesTSR, WindowCreate/Size/DestroyTSR, SwapBuffersTSR, BoundsInfoTSR,
 * ContextCreate/Destroy and MakeCurrentTSR, the barrier and semaphore
 * commands, CreateShader/ProgramTSR) as a server decodes and handles them:
 * the input is a received stream (wire buffers, each as long as its header
 * says, the rest as one last buffer) decoded by the real unpacker into a
 * real render SPU (OSMesa, a fixed 64x64 framebuffer, no output file)
 * whose sources are compiled into this program and registered in-process,
 * so coverage measures render's handlers. Only the *TSR slots reach the
 * SPU; every other command ends in a no-op (drawing into render with
 * budgets is the command-buffer target's job). One render instance per
 * process, reset after each input (server_get, server_reset).
 * Checked: the unpacker's error contract (TSR_EPROTO/TSR_ENOMEM with a
 * message), and whatever ASan/UBSan see in the handlers.
 * Built with TSR_FUZZ_SEEDS it is fuzz_ext_seeds OUTDIR: streams of every
 * extension command made by the real packer, named ok-*.bin. */
#include "fuzz_bytes.h"
#include "fuzz_target.h"

#include <stdlib.h>

#include "tessera/chain.h"
#include "tessera/dev/pack.h"
#include "tessera/dev/unpack.h"
#include "tessera/dispatch.h"
#include "tessera/gltsr_gen.h"
#include "tessera/spu.h"

#define FUZZ_MAX_OUTPUT ((uint64_t)16 << 20)

const tsr_spu_class *tsr_spu_describe(void);

static int read_reply(void *ctx, uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    (void)err;
    uint32_t *sum = ctx;
    *sum ^= id;
    for (size_t i = 0; i < size; i++)
        *sum = *sum * 31u + data[i];
    return 0;
}

/* One render instance serves every input of the process, as a server's
 * render serves its clients one after another: creating an OSMesa
 * context (and JIT-compiling its first shaders) costs more than 100 ms,
 * which would leave the fuzzer a few inputs a second. Each input is one
 * client: what it changed is undone after it (its contexts destroyed,
 * context 0 current, the tiles of the `tiles` option back), so an input
 * runs against the same starting state whatever ran before it. */
typedef struct server {
    tsr_chain *chain;
    tsr_dispatch table; /* the unpacker's target: *TSR slots only */
    tsr_entry create_context;
    GLint contexts[64]; /* created by the current input, to destroy */
    size_t context_count;
    int overflow;
} server;

static void server_ContextCreateTSR(void *self, GLint context)
{
    server *s = self;
    if (s->context_count < sizeof s->contexts / sizeof s->contexts[0])
        s->contexts[s->context_count++] = context;
    else
        s->overflow = 1;
    ((tsr_fn_ContextCreateTSR)s->create_context.fn)(s->create_context.self, context);
}

static int is_extension(int slot)
{
    const char *name = tsr_dispatch_name(slot);
    size_t n = name ? strlen(name) : 0;
    return n > 3 && !strcmp(name + n - 3, "TSR");
}

static server *server_get(void)
{
    static server *s;
    if (s)
        return s;
    s = calloc(1, sizeof *s);
    FUZZ_REQUIRE(s != NULL);
    tsr_error err = {0};
    /* render, compiled in, is found before any plugin of that name. */
    FUZZ_REQUIRE(tsr_spu_register(tsr_spu_describe(), &err) == TSR_OK);
    s->chain = tsr_chain_create("render width=64 height=64", &err);
    FUZZ_REQUIRE(s->chain != NULL);
    const tsr_dispatch *head = tsr_chain_head(s->chain);
    tsr_dispatch_fill_nop(&s->table);
    for (int slot = 0; slot < TSR_DISPATCH_COUNT; slot++)
        if (is_extension(slot))
            s->table.slots[slot] = head->slots[slot];
    s->create_context = head->ContextCreateTSR;
    tsr_set_ContextCreateTSR(&s->table, server_ContextCreateTSR, s);
    return s;
}

/* What a client's disconnect undoes, through the same handlers. */
static void server_reset(server *s)
{
    const tsr_dispatch *head = tsr_chain_head(s->chain);
    tsr_call_MakeCurrentTSR(head, 0, 0);
    for (size_t i = 0; i < s->context_count; i++)
        if (s->contexts[i] != 0)
            tsr_call_ContextDestroyTSR(head, s->contexts[i]);
    tsr_call_MakeCurrentTSR(head, 0, 0);
    tsr_call_TilesTSR(head, 0, 0, NULL);
    s->context_count = 0;
    FUZZ_REQUIRE(!s->overflow); /* more contexts than tracked: raise the limit */
}

static int decode(const uint8_t *data, size_t size, char *why, size_t why_size)
{
    server *s = server_get();
    tsr_error err = {0};
    uint32_t sum = 0;
    tsr_unpacker *u = tsr_unpacker_create(&s->table, read_reply, &sum, &err);
    FUZZ_REQUIRE(u != NULL);
    u->max_output = FUZZ_MAX_OUTPUT;
    int first = TSR_OK;
    size_t pos = 0;
    do {
        size_t rest = size - pos;
        tsr_error header_err;
        size_t n = tsr_wire_buffer_size(data + pos, rest, &header_err);
        if (n == 0 || n > rest)
            n = rest;
        tsr_error_clear(&err);
        int rc = tsr_unpacker_run(u, data + pos, n, &err);
        if (rc != TSR_OK) {
            FUZZ_REQUIRE(rc == TSR_EPROTO || rc == TSR_ENOMEM);
            if (first == TSR_OK)
                first = fuzz_rejected(rc, &err, why, why_size);
        }
        pos += n;
    } while (pos < size);
    tsr_unpacker_destroy(u);
    server_reset(s);
    return first;
}

#ifndef TSR_FUZZ_SEEDS

int fuzz_target_explain(const uint8_t *data, size_t size, char *why, size_t why_size)
{
    return decode(data, size, why, why_size);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    decode(data, size, NULL, 0);
    return 0;
}

#else /* TSR_FUZZ_SEEDS */

typedef fuzz_bytes capture;

static int capture_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    return fuzz_bytes_append(ctx, buf, size, "fuzz_ext_seeds", err);
}

static void tiles(const tsr_dispatch *gl)
{
    static const GLint two[8] = {0, 0, 32, 64, 32, 0, 32, 64};
    static const GLint four[16] = {0, 0, 32, 32, 32, 0, 32, 32, 0, 32, 32, 32, 32, 32, 32, 32};
    static const GLint outside[4] = {48, 48, 100, 100};
    tsr_call_WindowCreateTSR(gl, 0, 64, 64);
    tsr_call_TilesTSR(gl, 0, 2, two);
    tsr_call_SwapBuffersTSR(gl, 0, 0);
    tsr_call_TilesTSR(gl, 0, 4, four);
    tsr_call_SwapBuffersTSR(gl, 0, 0);
    tsr_call_TilesTSR(gl, 0, 1, outside);
    tsr_call_SwapBuffersTSR(gl, 0, 0);
    tsr_call_TilesTSR(gl, 0, 0, NULL);
    tsr_call_TilesTSR(gl, 1, 2, two);
    tsr_call_SwapBuffersTSR(gl, 0, 0);
}

static void windows(const tsr_dispatch *gl)
{
    tsr_call_WindowCreateTSR(gl, 0, 64, 64);
    tsr_call_WindowSizeTSR(gl, 0, 32, 16);
    tsr_call_SwapBuffersTSR(gl, 0, 0);
    tsr_call_WindowCreateTSR(gl, 2, 8, 8);
    tsr_call_WindowSizeTSR(gl, 2, 16, 16);
    tsr_call_SwapBuffersTSR(gl, 2, 1);
    tsr_call_WindowDestroyTSR(gl, 2);
    tsr_call_WindowDestroyTSR(gl, 0);
}

static void contexts(const tsr_dispatch *gl)
{
    tsr_call_ContextCreateTSR(gl, 1);
    tsr_call_ContextCreateTSR(gl, 2);
    tsr_call_MakeCurrentTSR(gl, 0, 1);
    tsr_call_WindowCreateTSR(gl, 0, 64, 64);
    tsr_call_SwapBuffersTSR(gl, 0, 0);
    tsr_call_MakeCurrentTSR(gl, 0, 2);
    tsr_call_SwapBuffersTSR(gl, 0, 0);
    tsr_call_MakeCurrentTSR(gl, 0, 7);
    tsr_call_ContextDestroyTSR(gl, 2);
    tsr_call_MakeCurrentTSR(gl, 0, 1);
    tsr_call_ContextDestroyTSR(gl, 1);
}

static void sync(const tsr_dispatch *gl)
{
    tsr_call_BarrierCreateTSR(gl, 1, 2);
    tsr_call_BarrierExecTSR(gl, 1);
    tsr_call_BarrierDestroyTSR(gl, 1);
    tsr_call_SemaphoreCreateTSR(gl, 3, 1);
    tsr_call_SemaphorePTSR(gl, 3);
    tsr_call_SemaphoreVTSR(gl, 3);
    tsr_call_SemaphoreDestroyTSR(gl, 3);
}

static void misc(const tsr_dispatch *gl)
{
    static const GLfloat bounds[6] = {-1, -1, -1, 1, 1, 1};
    tsr_call_WindowCreateTSR(gl, 0, 64, 64);
    tsr_call_BoundsInfoTSR(gl, bounds);
    tsr_call_CreateShaderTSR(gl, 5, GL_VERTEX_SHADER);
    tsr_call_CreateProgramTSR(gl, 6);
    tsr_call_SwapBuffersTSR(gl, 0, 0);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s OUTDIR\n", argv[0]);
        return 2;
    }
    static const struct {
        const char *name;
        void (*fn)(const tsr_dispatch *gl);
    } scenarios[] = {{"tiles", tiles}, {"windows", windows}, {"contexts", contexts}, {"sync", sync}, {"misc", misc}};
    for (size_t s = 0; s < sizeof scenarios / sizeof scenarios[0]; s++) {
        capture c = {0};
        tsr_error err = {0};
        tsr_pack_sink sink = {.flush = capture_flush, .ctx = &c};
        tsr_packer *p = tsr_packer_create(TSR_PACK_MIN_BUFFER * 4, &sink, &err);
        tsr_dispatch *gl = malloc(sizeof *gl);
        if (!p || !gl)
            return fprintf(stderr, "fuzz_ext_seeds: %s\n", err.message), 1;
        tsr_dispatch_fill_nop(gl);
        tsr_packer_fill_dispatch(p, gl);
        scenarios[s].fn(gl);
        tsr_packer_flush(p);
        if (tsr_packer_error(p)->code != TSR_OK)
            return fprintf(stderr, "fuzz_ext_seeds: %s: %s\n", scenarios[s].name, tsr_packer_error(p)->message), 1;
        char why[512] = "";
        if (decode(c.bytes, c.len, why, sizeof why) != TSR_OK)
            return fprintf(stderr, "fuzz_ext_seeds: %s: rejected: %s\n", scenarios[s].name, why), 1;
        char path[4096];
        snprintf(path, sizeof path, "%s/ok-%s.bin", argv[1], scenarios[s].name);
        FILE *f = fopen(path, "wb");
        if (!f || fwrite(c.bytes, 1, c.len, f) != c.len || fclose(f) != 0)
            return fprintf(stderr, "fuzz_ext_seeds: %s: cannot write\n", path), 1;
        tsr_packer_destroy(p);
        free(gl);
        free(c.bytes);
    }
    return 0;
}

#endif
