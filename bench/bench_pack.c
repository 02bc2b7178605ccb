/* bench/bench_pack.c — how fast glVertex3f is packed: calls go through a
 * dispatch table filled by tsr_packer_fill_dispatch (exactly how an SPU's
 * table reaches the generated packer), with the bounding box kept, into a
 * sink that takes each full buffer. Against it, memcpy of the same number
 * of bytes in buffer-sized chunks, measured in the same run.
 * Owns only its packer and buffers; reports figures, never pass/fail.
 * Figures: pack_vertex3f_bbox_mcalls, pack_vertex3f_bbox_gbps, memcpy_gbps,
 * pack_vertex3f_bytes_per_call, and pack_vertex3f_bbox_inline_mcalls (the
 * generated inline packer called directly, without the table). */
#include "bench_common.h"

#include <stdlib.h>
#include <string.h>

#include "tessera/dev/pack.h"
#include "wire_gen.h"
#include "tessera/dispatch.h"

/* 1 MiB buffers: the size a sending SPU uses by default; a buffer of
 * commands stays in L2 while it is written. */
#define BUFFER_SIZE (1u << 20)
/* The app's vertex data: 4096 vertices (48 KiB, L1/L2 resident), so the
 * loop measures packing, not computing coordinates. */
#define VERTEX_COUNT 4096u

typedef struct sink_stats {
    uint64_t buffers, bytes;
    size_t largest;
} sink_stats;

/* The receiving end of a sending SPU: takes the buffer and lets it go (the
 * I/O thread would queue it). Only counts, so packing is what is timed. */
static int count_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    (void)err;
    sink_stats *s = ctx;
    bench_keep(buf);
    s->buffers++;
    s->bytes += size;
    if (size > s->largest)
        s->largest = size;
    return 0;
}

static float *make_vertices(void)
{
    float *v = malloc(VERTEX_COUNT * 3 * sizeof *v);
    if (!v)
        return NULL;
    /* A sphere-ish cloud: coordinates change every call, so the box's
     * min/max comparisons see real data rather than constants. */
    uint32_t seed = 12345u;
    for (unsigned i = 0; i < VERTEX_COUNT * 3; i++) {
        seed = seed * 1664525u + 1013904223u;
        v[i] = (float)(seed >> 8) / (float)(1u << 24) * 2.0f - 1.0f;
    }
    return v;
}

static double time_pack(const tsr_dispatch *table, tsr_packer *p, const float *v, uint64_t calls)
{
    double t0 = bench_now();
    uint64_t done = 0;
    while (done < calls) {
        uint64_t n = calls - done < VERTEX_COUNT ? calls - done : VERTEX_COUNT;
        for (uint64_t i = 0; i < n; i++)
            tsr_call_Vertex3f(table, v[3 * i], v[3 * i + 1], v[3 * i + 2]);
        done += n;
    }
    tsr_packer_flush(p);
    return bench_now() - t0;
}

/* The same calls without the table: the generated inline packer called
 * directly, as code compiled against the packer (a tilesort client) can.
 * The difference to time_pack is the cost of the indirect call. */
static double time_pack_inline(tsr_packer *p, const float *v, uint64_t calls)
{
    double t0 = bench_now();
    uint64_t done = 0;
    while (done < calls) {
        uint64_t n = calls - done < VERTEX_COUNT ? calls - done : VERTEX_COUNT;
        for (uint64_t i = 0; i < n; i++)
            tsr_pack_Vertex3f(p, v[3 * i], v[3 * i + 1], v[3 * i + 2]);
        done += n;
    }
    tsr_packer_flush(p);
    return bench_now() - t0;
}

static double time_memcpy(uint8_t *dst, const uint8_t *src, size_t chunk, uint64_t bytes)
{
    double t0 = bench_now();
    uint64_t done = 0;
    while (done < bytes) {
        size_t n = bytes - done < chunk ? (size_t)(bytes - done) : chunk;
        memcpy(dst, src, n);
        bench_keep(dst);
        done += n;
    }
    return bench_now() - t0;
}

int main(int argc, char **argv)
{
    bench_args args;
    if (bench_parse_args(argc, argv, &args, NULL) != 0)
        return 2;
    const uint64_t calls = args.quick ? 100000u : 20000000u;

    float *vertices = make_vertices();
    uint8_t *src = malloc(BUFFER_SIZE), *dst = malloc(BUFFER_SIZE);
    if (!vertices || !src || !dst) {
        fprintf(stderr, "bench_pack: out of memory\n");
        return 1;
    }
    memset(src, 0x5a, BUFFER_SIZE);
    memset(dst, 0, BUFFER_SIZE);

    sink_stats stats = {0};
    tsr_pack_sink sink = {.flush = count_flush, .reply = NULL, .ctx = &stats};
    tsr_error err;
    tsr_error_clear(&err);
    tsr_packer *packer = tsr_packer_create(BUFFER_SIZE, &sink, &err);
    if (!packer) {
        fprintf(stderr, "bench_pack: %s\n", err.message);
        return 1;
    }
    tsr_dispatch table;
    tsr_dispatch_fill_nop(&table);
    tsr_packer_fill_dispatch(packer, &table);

    FILE *csv = bench_csv_open(args.csv_path, "benchmark,repeat,calls,bytes,seconds,mcalls_per_s,gb_per_s");
    double best_pack = 0, best_copy = 0, best_inline = 0;
    uint64_t bytes = 0;
    /* Warm-up: page in the buffers, settle the clock. */
    time_pack(&table, packer, vertices, calls / 10 + 1);
    for (int r = 0; r < args.repeats; r++) {
        uint64_t before = stats.bytes;
        double tp = time_pack(&table, packer, vertices, calls);
        bytes = stats.bytes - before;
        double tc = time_memcpy(dst, src, stats.largest ? stats.largest : BUFFER_SIZE, bytes);
        double ti = time_pack_inline(packer, vertices, calls);
        if ((double)calls / ti > best_inline)
            best_inline = (double)calls / ti;
        double rate = (double)calls / tp, gbps = (double)bytes / tp * 1e-9;
        double copy_gbps = (double)bytes / tc * 1e-9;
        if (rate > best_pack)
            best_pack = rate;
        if (copy_gbps > best_copy)
            best_copy = copy_gbps;
        if (csv) {
            fprintf(csv, "pack_vertex3f_bbox,%d,%llu,%llu,%.6f,%.3f,%.3f\n", r, (unsigned long long)calls,
                    (unsigned long long)bytes, tp, rate * 1e-6, gbps);
            fprintf(csv, "memcpy,%d,,%llu,%.6f,,%.3f\n", r, (unsigned long long)bytes, tc, copy_gbps);
            fprintf(csv, "pack_vertex3f_bbox_inline,%d,%llu,%llu,%.6f,%.3f,%.3f\n", r, (unsigned long long)calls,
                    (unsigned long long)bytes, ti, (double)calls / ti * 1e-6, (double)bytes / ti * 1e-9);
        }
    }
    if (csv)
        fclose(csv);

    float bmin[3], bmax[3];
    /* The box must have been kept (it is reset per flush; pack a few more
     * vertices to read one back) — otherwise the figure would be a lie. */
    for (unsigned i = 0; i < 16; i++)
        tsr_call_Vertex3f(&table, vertices[3 * i], vertices[3 * i + 1], vertices[3 * i + 2]);
    if (!tsr_packer_bbox(packer, bmin, bmax) || bmin[0] > bmax[0]) {
        fprintf(stderr, "bench_pack: the packer kept no bounding box\n");
        return 1;
    }
    const tsr_error *perr = tsr_packer_error(packer);
    if (perr->code != TSR_OK) {
        fprintf(stderr, "bench_pack: packer error: %s\n", perr->message);
        return 1;
    }

    bench_figure("pack_vertex3f_bbox_mcalls", best_pack * 1e-6, 1);
    bench_figure("pack_vertex3f_bbox_gbps", best_pack * (double)bytes / (double)calls * 1e-9, 3);
    bench_figure("memcpy_gbps", best_copy, 3);
    bench_figure("pack_vertex3f_bytes_per_call", (double)bytes / (double)calls, 3);
    bench_figure("pack_vertex3f_bbox_inline_mcalls", best_inline * 1e-6, 1);

    tsr_packer_destroy(packer);
    free(vertices);
    free(src);
    free(dst);
    return 0;
}
