/* bench/bench_unpack.c — how fast received buffers are validated, decoded
 * and dispatched: buffers made by the real packer are run through a real
 * unpacker into a table of no-ops (the end of every chain), so the figure
 * is the unpacker's own cost. Two streams: a realistic immediate-mode mix
 * (lit spheres as quad strips with normals, textured and coloured quads,
 * matrix and material changes per object) and pure glVertex3f.
 * Owns only its packer, unpacker and buffers; reports, never pass/fail.
 * Figures: unpack_dispatch_mcmds (the mix), unpack_dispatch_mix_gbps,
 * unpack_dispatch_vertex3f_mcmds, unpack_dispatch_vertex3f_gbps (one
 * buffer's worth, cache-resident like a just-received buffer), and
 * unpack_dispatch_mix_8mib_mcmds (an 8 MiB stream: buffers from memory). */
#include "bench_common.h"

#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>

#include "tessera/dev/pack.h"
#include "tessera/dispatch.h"
#include "tessera/dev/unpack.h"

/* Buffers of 256 KiB, the size a sending SPU flushes. */
#define BUFFER_SIZE (256u << 10)
#define MAX_BUFFERS 128

typedef struct stream {
    uint8_t *buf[MAX_BUFFERS];
    size_t size[MAX_BUFFERS];
    size_t count;
    uint64_t commands, bytes;
} stream;

static int keep_buffer(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    stream *s = ctx;
    if (s->count == MAX_BUFFERS)
        return tsr_error_set(err, TSR_ENOMEM, "bench_unpack: more than %d buffers", MAX_BUFFERS);
    uint8_t *copy = malloc(size);
    if (!copy)
        return tsr_error_set(err, TSR_ENOMEM, "bench_unpack: out of memory");
    memcpy(copy, buf, size);
    s->buf[s->count] = copy;
    s->size[s->count] = size;
    s->count++;
    s->commands += tsr_wire_get_u32(buf + 4);
    s->bytes += size;
    return 0;
}

/* One lit sphere as quad strips: the immediate-mode pattern of
 * examples/spheres (Normal3f + Vertex3f per vertex). */
static void sphere(const tsr_dispatch *gl, int stacks, int slices)
{
    for (int i = 0; i < stacks; i++) {
        float z0 = -1.0f + 2.0f * (float)i / (float)stacks;
        float z1 = -1.0f + 2.0f * (float)(i + 1) / (float)stacks;
        tsr_call_Begin(gl, GL_QUAD_STRIP);
        for (int j = 0; j <= slices; j++) {
            float x = (float)j / (float)slices, y = 1.0f - x;
            tsr_call_Normal3f(gl, x, y, z0);
            tsr_call_Vertex3f(gl, x, y, z0);
            tsr_call_Normal3f(gl, x, y, z1);
            tsr_call_Vertex3f(gl, x, y, z1);
        }
        tsr_call_End(gl);
    }
}

static void mix_object(const tsr_dispatch *gl, int k)
{
    static const GLfloat color[4] = {0.8f, 0.3f, 0.2f, 1.0f};
    tsr_call_PushMatrix(gl);
    tsr_call_Translatef(gl, (float)(k % 7), (float)(k % 5), -10.0f);
    tsr_call_Rotatef(gl, (float)k, 0, 1, 0);
    tsr_call_Materialfv(gl, GL_FRONT, GL_AMBIENT_AND_DIFFUSE, color);
    sphere(gl, 8, 16);
    /* A few textured, coloured quads (the texquads pattern). */
    tsr_call_BindTexture(gl, GL_TEXTURE_2D, (GLuint)(1 + k % 3));
    tsr_call_Begin(gl, GL_QUADS);
    for (int q = 0; q < 8; q++) {
        float x = (float)q;
        tsr_call_Color4ub(gl, 255, (GLubyte)(q * 30), 0, 255);
        tsr_call_TexCoord2f(gl, 0, 0);
        tsr_call_Vertex2f(gl, x, 0);
        tsr_call_TexCoord2f(gl, 1, 0);
        tsr_call_Vertex2f(gl, x + 1, 0);
        tsr_call_TexCoord2f(gl, 1, 1);
        tsr_call_Vertex2f(gl, x + 1, 1);
        tsr_call_TexCoord2f(gl, 0, 1);
        tsr_call_Vertex2f(gl, x, 1);
    }
    tsr_call_End(gl);
    tsr_call_PopMatrix(gl);
}

typedef enum { STREAM_MIX, STREAM_VERTEX3F } stream_kind;

/* Packs about `target_bytes` of the given stream with the real packer. */
static int build_stream(stream *s, stream_kind kind, size_t target_bytes)
{
    memset(s, 0, sizeof *s);
    tsr_pack_sink sink = {.flush = keep_buffer, .reply = NULL, .ctx = s};
    tsr_error err;
    tsr_error_clear(&err);
    tsr_packer *p = tsr_packer_create(BUFFER_SIZE, &sink, &err);
    tsr_dispatch *gl = malloc(sizeof *gl);
    if (!p || !gl) {
        fprintf(stderr, "bench_unpack: %s\n", err.message[0] ? err.message : "out of memory");
        tsr_packer_destroy(p);
        free(gl);
        return -1;
    }
    tsr_dispatch_fill_nop(gl);
    tsr_packer_fill_dispatch(p, gl);
    for (int k = 0; s->bytes + tsr_packer_pending(p) < target_bytes; k++) {
        if (kind == STREAM_MIX) {
            mix_object(gl, k);
        } else {
            for (int i = 0; i < 1024; i++)
                tsr_call_Vertex3f(gl, (float)i, (float)k, 1.0f);
        }
    }
    tsr_packer_flush(p);
    int rc = tsr_packer_error(p)->code == TSR_OK ? 0 : -1;
    if (rc)
        fprintf(stderr, "bench_unpack: packer: %s\n", tsr_packer_error(p)->message);
    tsr_packer_destroy(p);
    free(gl);
    return rc;
}

static void free_stream(stream *s)
{
    for (size_t i = 0; i < s->count; i++)
        free(s->buf[i]);
}

/* Decodes the stream `passes` times; returns seconds, or -1 on an error. */
static double time_unpack(tsr_unpacker *u, const stream *s, int passes)
{
    tsr_error err;
    double t0 = bench_now();
    for (int r = 0; r < passes; r++) {
        for (size_t i = 0; i < s->count; i++) {
            if (tsr_unpacker_run(u, s->buf[i], s->size[i], &err) != 0) {
                fprintf(stderr, "bench_unpack: %s\n", err.message);
                return -1;
            }
        }
    }
    return bench_now() - t0;
}

static int measure(const char *name, stream_kind kind, size_t stream_bytes, const bench_args *args, FILE *csv,
                   double *best_mcmds, double *best_gbps)
{
    stream s;
    if (build_stream(&s, kind, args->quick ? 64u << 10 : stream_bytes) != 0) {
        free_stream(&s);
        return -1;
    }
    tsr_dispatch *nop = malloc(sizeof *nop);
    tsr_error err;
    tsr_unpacker *u = nop ? tsr_unpacker_create(nop, NULL, NULL, &err) : NULL;
    if (!u) {
        fprintf(stderr, "bench_unpack: cannot create an unpacker\n");
        free(nop);
        free_stream(&s);
        return -1;
    }
    tsr_dispatch_fill_nop(nop);
    /* About 20 M commands per timed run (a few in --quick). */
    int passes = args->quick ? 2 : (int)(20000000u / (s.commands ? s.commands : 1)) + 1;
    *best_mcmds = 0;
    *best_gbps = 0;
    int rc = time_unpack(u, &s, 1) < 0 ? -1 : 0; /* warm-up */
    for (int r = 0; rc == 0 && r < args->repeats; r++) {
        double t = time_unpack(u, &s, passes);
        if (t < 0) {
            rc = -1;
            break;
        }
        double cmds = (double)s.commands * passes, bytes = (double)s.bytes * passes;
        double mcmds = cmds / t * 1e-6, gbps = bytes / t * 1e-9;
        if (mcmds > *best_mcmds)
            *best_mcmds = mcmds;
        if (gbps > *best_gbps)
            *best_gbps = gbps;
        if (csv)
            fprintf(csv, "%s,%d,%.0f,%.0f,%.6f,%.3f,%.3f,%.3f\n", name, r, cmds, bytes, t, mcmds, gbps,
                    (double)s.bytes / (double)s.commands);
    }
    tsr_unpacker_destroy(u);
    free(nop);
    free_stream(&s);
    return rc;
}

int main(int argc, char **argv)
{
    bench_args args;
    if (bench_parse_args(argc, argv, &args, NULL) != 0)
        return 2;
    FILE *csv =
        bench_csv_open(args.csv_path, "stream,repeat,commands,bytes,seconds,mcmds_per_s,gb_per_s,bytes_per_command");
    double mix_mcmds, mix_gbps, v_mcmds, v_gbps, big_mcmds, big_gbps;
    /* A just-received buffer is in cache (the receive wrote it): the main
     * figures decode one buffer's worth (fits L2). The 8 MiB stream shows
     * the cost when buffers come from memory. */
    int rc = measure("mix", STREAM_MIX, BUFFER_SIZE - 4096, &args, csv, &mix_mcmds, &mix_gbps);
    if (rc == 0)
        rc = measure("vertex3f", STREAM_VERTEX3F, BUFFER_SIZE - 4096, &args, csv, &v_mcmds, &v_gbps);
    if (rc == 0)
        rc = measure("mix_8mib", STREAM_MIX, 8u << 20, &args, csv, &big_mcmds, &big_gbps);
    if (csv)
        fclose(csv);
    if (rc != 0)
        return 1;
    bench_figure("unpack_dispatch_mcmds", mix_mcmds, 1);
    bench_figure("unpack_dispatch_mix_gbps", mix_gbps, 3);
    bench_figure("unpack_dispatch_vertex3f_mcmds", v_mcmds, 1);
    bench_figure("unpack_dispatch_vertex3f_gbps", v_gbps, 3);
    bench_figure("unpack_dispatch_mix_8mib_mcmds", big_mcmds, 1);
    return 0;
}
