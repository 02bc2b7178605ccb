/* bench/bench_composite.c — sort-last compositing kernels and codecs
 * (tessera/dev/composite.h): one pairwise depth merge of two full
 * 1920x1080 RGBA8+depth frames against a memcpy of one such frame in the
 * same run, and every image codec's encode/decode time, size and error at
 * 1024x768 and 1920x1080. Prints figures; never pass/fail.
 *
 * The merged frames are two interpenetrating shaded surfaces (each wins
 * about half the window in large coherent areas, as rendered geometry
 * does); merge_random_vs_memcpy repeats the merge with per-pixel random
 * depths, the worst case for the write traffic.
 *
 * Then each strategy in one process (a thread per peer and the display,
 * the in-process transport: every message copied once, as a socket would),
 * N = 2, 4, 8 peers at 1920x1080, each peer a full-window layer winning
 * about 1/N of the pixels: wall time from "all images read back" to the
 * assembled frame and the CPU time of all threads together (medians of
 * the frames), and the bytes sent per frame. On 2 shared vCPUs the threads
 * share the cores with everything else, so the CPU time is the figure to
 * compare. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "bench_common.h"
#include "strategy.h"
#include "synthetic.h"
#include "tessera/dev/composite.h"

static uint64_t rs = 0x9e3779b97f4a7c15ull;
static uint32_t rnd(void)
{
    rs ^= rs << 13;
    rs ^= rs >> 7;
    rs ^= rs << 17;
    return (uint32_t)(rs >> 11);
}

static void *alloc64(size_t n)
{
    void *p = NULL;
    if (posix_memalign(&p, 64, n))
        abort();
    memset(p, 0, n);
    return p;
}

/* Surface s of a frame: tilted, rippled, shaded; `random`: noise depths. */
static void fill(uint8_t *c, float *d, int W, int H, int s, int random)
{
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            double u = (double)x / W, v = (double)y / H;
            double z = s ? 0.3 + 0.4 * u + 0.05 * sin(12 * v) : 0.7 - 0.4 * u + 0.05 * cos(9 * v);
            if (random)
                z = (rnd() % 100000) / 100001.0;
            d[i] = (float)z;
            c[4 * i] = (uint8_t)(255 * z);
            c[4 * i + 1] = (uint8_t)(128 + 100 * sin(20 * u));
            c[4 * i + 2] = (uint8_t)(s ? 200 : 50);
            c[4 * i + 3] = 255;
        }
}

/* A rendered-looking peer image: shaded spheres over background. */
static void scene(tsr_composite_image *img, int W, int H)
{
    tsr_error err;
    if (tsr_composite_image_init(img, W, H, 0, 0, W, H, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, &err))
        abort();
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            uint8_t *c = img->color + 4 * i;
            c[0] = c[1] = c[2] = 0;
            c[3] = 0;
            img->depth[i] = 1.0f;
            for (int k = 0; k < 5; k++) {
                double cx = W * (0.2 + 0.15 * k), cy = H * (0.3 + 0.1 * (k % 3)), r = H * 0.18;
                double dx = (x - cx) / r, dy = (y - cy) / r, r2 = dx * dx + dy * dy;
                if (r2 < 1) {
                    double z = sqrt(1 - r2), dep = 0.5 - 0.2 * z + 0.05 * k;
                    if (dep < img->depth[i]) {
                        double l = 0.2 + 0.8 * fmax(0, 0.5 * dx + 0.3 * dy + 0.8 * z);
                        c[0] = (uint8_t)(255 * l * (k % 2 ? 0.9 : 0.3));
                        c[1] = (uint8_t)(255 * l * 0.6);
                        c[2] = (uint8_t)(255 * l * (k % 2 ? 0.2 : 0.9));
                        c[3] = 255;
                        img->depth[i] = (float)dep;
                    }
                }
            }
        }
}

static double best_merge(int W, int H, int random, int repeats, double *memcpy_s)
{
    size_t n = (size_t)W * H;
    uint8_t *fc = alloc64(n * 4), *bc = alloc64(n * 4), *bc0 = alloc64(n * 4), *mc = alloc64(n * 4);
    float *fd = alloc64(n * 4), *bd = alloc64(n * 4), *bd0 = alloc64(n * 4), *md = alloc64(n * 4);
    fill(fc, fd, W, H, 0, random);
    fill(bc0, bd0, W, H, 1, random);
    double best = 1e9, bestcpy = 1e9;
    for (int r = 0; r < repeats; r++) {
        /* memcpy of one frame (colour + depth planes) */
        double t0 = bench_now();
        memcpy(mc, bc0, n * 4);
        memcpy(md, bd0, n * 4);
        double t1 = bench_now();
        bench_keep(mc);
        bench_keep(md);
        if (t1 - t0 < bestcpy)
            bestcpy = t1 - t0;
        /* merge the front frame into a fresh back frame, in place */
        memcpy(bc, bc0, n * 4);
        memcpy(bd, bd0, n * 4);
        t0 = bench_now();
        tsr_composite_depth_rgba8(n, fc, fd, bc, bd, bc, bd);
        t1 = bench_now();
        bench_keep(bc);
        bench_keep(bd);
        if (t1 - t0 < best)
            best = t1 - t0;
    }
    free(fc), free(bc), free(bc0), free(mc), free(fd), free(bd), free(bd0), free(md);
    *memcpy_s = bestcpy;
    return best;
}

static double psnr8(const uint8_t *a, const uint8_t *b, size_t n)
{
    double se = 0;
    for (size_t i = 0; i < n; i++)
        se += ((double)a[i] - b[i]) * ((double)a[i] - b[i]);
    return se == 0 ? INFINITY : 10 * log10(255.0 * 255.0 * (double)n / se);
}

/* ---- strategies in one process ------------------------------------------- */

typedef struct bjob {
    tsr_composite_executor *ex;
    tsr_composite_image *img;
    tsr_composite_transport t;
    int rank, rc;
    tsr_error err;
} bjob;

static void *bpeer(void *arg)
{
    bjob *j = arg;
    j->rc = tsr_composite_run_peer(j->ex, j->rank, j->img, TSR_COMPOSITE_DEPTH, &j->t, &j->err);
    return NULL;
}

static double now_wall(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec / 1e9;
}

/* CPU time of the whole process (every peer thread and the display): on
 * a loaded machine the wall time mostly measures the other processes. */
static double now_cpu(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + (double)t.tv_nsec / 1e9;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* One group of n peers (a thread each) and the display over the in-memory
 * transport, `frames` frames: medians of CPU and wall ms per frame, the
 * bytes all peers sent per frame, and the last frame in *final. */
typedef struct group_result {
    double cpu_ms, wall_ms;
    uint64_t bytes;
    char name[32];
} group_result;

static void run_group(const char *strategy, tsr_composite_codec codec, int n, int W, int H, tsr_composite_image *imgs,
                      int frames, tsr_composite_image *final, group_result *res)
{
    tsr_error err = {0};
    int kind, k;
    if (tsr_composite_kind_parse(strategy, &kind, &k, &err))
        abort();
    tsr_composite_schedule s;
    tsr_composite_hint hint = {0, 1};
    if (tsr_composite_plan(kind, n, W, H, k, &hint, &s, &err)) {
        fprintf(stderr, "bench_composite: %s n=%d: %s\n", strategy, n, err.message);
        exit(1);
    }
    tsr_composite_memnet *net = tsr_composite_memnet_new(n + 1, 120000, &err);
    bjob *jobs = calloc((size_t)n, sizeof *jobs);
    pthread_t *th = calloc((size_t)n, sizeof *th);
    for (int r = 0; r < n; r++) {
        jobs[r] = (bjob){.ex = tsr_composite_executor_new(&s, codec, &err), .img = &imgs[r], .rank = r};
        tsr_composite_memnet_transport(net, r, &jobs[r].t);
    }
    tsr_composite_transport dt;
    tsr_composite_memnet_transport(net, n, &dt);
    tsr_composite_executor *dex = tsr_composite_executor_new(&s, codec, &err);
    static const uint8_t bg[4] = {0, 0, 0, 255};
    double ms[64], cpu[64];
    uint64_t bytes = 0;
    for (int f = 0; f < frames; f++) {
        double t0 = now_wall(), c0 = now_cpu();
        for (int r = 0; r < n; r++)
            pthread_create(&th[r], NULL, bpeer, &jobs[r]);
        int rc = tsr_composite_run_display(dex, 1, TSR_COMPOSITE_DEPTH, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, bg,
                                           final, &dt, &err);
        for (int r = 0; r < n; r++)
            pthread_join(th[r], NULL);
        ms[f] = (now_wall() - t0) * 1e3;
        cpu[f] = (now_cpu() - c0) * 1e3;
        if (rc) {
            fprintf(stderr, "bench_composite: %s n=%d: %s\n", s.name, n, err.message);
            exit(1);
        }
        for (int r = 0; r < n; r++)
            if (jobs[r].rc) {
                fprintf(stderr, "bench_composite: %s n=%d rank %d: %s\n", s.name, n, r, jobs[r].err.message);
                exit(1);
            }
        bytes = 0;
        for (int r = 0; r < n; r++) {
            tsr_composite_stats st;
            tsr_composite_executor_stats(jobs[r].ex, &st);
            bytes += st.bytes_sent;
        }
    }
    qsort(ms, (size_t)frames, sizeof *ms, cmp_double);
    qsort(cpu, (size_t)frames, sizeof *cpu, cmp_double);
    res->cpu_ms = cpu[frames / 2];
    res->wall_ms = ms[frames / 2];
    res->bytes = bytes;
    snprintf(res->name, sizeof res->name, "%s", s.name);
    for (int r = 0; r < n; r++)
        tsr_composite_executor_free(jobs[r].ex);
    tsr_composite_executor_free(dex);
    tsr_composite_memnet_free(net);
    tsr_composite_schedule_free(&s);
    free(jobs);
    free(th);
}

static tsr_composite_image *make_layers(int mode, int n, int W, int H)
{
    tsr_error err = {0};
    tsr_composite_image *imgs = calloc((size_t)n, sizeof *imgs);
    for (int r = 0; r < n; r++) {
        if (tsr_composite_synthetic_layer(mode, W, H, r, n, &imgs[r], &err))
            abort();
        imgs[r].frame = 1;
    }
    return imgs;
}

static void free_layers(tsr_composite_image *imgs, int n)
{
    for (int r = 0; r < n; r++)
        tsr_composite_image_free(&imgs[r]);
    free(imgs);
}

/* Every strategy at N = 2, 4, 8, 16 on synthetic full and ellipse layers
 * (spus/binaryswap/synthetic.h, the multi-process benchmark's input). */
static void bench_strategies(const bench_args *a, FILE *csv)
{
    static const char *names[] = {"gather", "direct", "bswap", "radixk-4", "auto"};
    int W = a->quick ? 64 : 1920, H = a->quick ? 36 : 1080, frames = a->quick ? 1 : 5;
    tsr_error err;
    tsr_composite_codec codec;
    tsr_composite_codec_parse("rle", &codec, &err);
    for (int partial = 0; partial < 2; partial++)
        for (int n = 2; n <= 16; n *= 2) {
            tsr_composite_image *imgs =
                make_layers(partial ? TSR_COMPOSITE_SYNTHETIC_ELLIPSE : TSR_COMPOSITE_SYNTHETIC_FULL, n, W, H);
            for (size_t si = 0; si < sizeof names / sizeof *names; si++) {
                tsr_composite_image frame = {0};
                group_result g;
                run_group(names[si], codec, n, W, H, imgs, frames, &frame, &g);
                printf("strategy_%s_%s_n%d: cpu_ms %.2f wall_ms %.2f bytes_per_frame %llu (%s)\n", names[si],
                       partial ? "partial" : "full", n, g.cpu_ms, g.wall_ms, (unsigned long long)g.bytes, g.name);
                if (csv)
                    fprintf(csv, "%s,%s,%d,%.3f,%.3f,%llu,%s\n", names[si], partial ? "partial" : "full", n, g.cpu_ms,
                            g.wall_ms, (unsigned long long)g.bytes, g.name);
                tsr_composite_image_free(&frame);
            }
            free_layers(imgs, n);
        }
}

/* Every codec at N = 2, 4, 8 and 1024x768 / 1920x1080 (strategy auto,
 * synthetic full layers): time per frame against the colour PSNR of the
 * final frame relative to the lossless one (codec none) of the same run. */
static void bench_codec_sweep(const bench_args *a, FILE *csv)
{
    static const char *codecs[] = {"none", "rle", "erle", "yuv420", "depth16", "depth24"};
    int sizes[2][2] = {{1024, 768}, {1920, 1080}}, frames = a->quick ? 1 : 5;
    for (int si = 0; si < 2; si++)
        for (int n = 2; n <= 8; n *= 2) {
            int W = a->quick ? sizes[si][0] / 16 : sizes[si][0], H = a->quick ? sizes[si][1] / 16 : sizes[si][1];
            tsr_composite_image *imgs = make_layers(TSR_COMPOSITE_SYNTHETIC_FULL, n, W, H);
            tsr_composite_image lossless = {0};
            for (size_t ci = 0; ci < sizeof codecs / sizeof *codecs; ci++) {
                tsr_error err;
                tsr_composite_codec c;
                tsr_composite_codec_parse(codecs[ci], &c, &err);
                tsr_composite_image frame = {0};
                group_result g;
                run_group("auto", c, n, W, H, imgs, frames, ci ? &frame : &lossless, &g);
                double p = ci ? psnr8(lossless.color, frame.color, (size_t)W * H * 4) : INFINITY;
                printf("sweep_%s_%dx%d_n%d: cpu_ms %.2f wall_ms %.2f bytes_per_frame %llu psnr_db %.1f (%s)\n",
                       codecs[ci], W, H, n, g.cpu_ms, g.wall_ms, (unsigned long long)g.bytes, p, g.name);
                if (csv)
                    fprintf(csv, "%s,%dx%d,%d,%.3f,%.3f,%llu,%.2f,%s\n", codecs[ci], W, H, n, g.cpu_ms, g.wall_ms,
                            (unsigned long long)g.bytes, isinf(p) ? 99.0 : p, g.name);
                tsr_composite_image_free(&frame);
            }
            tsr_composite_image_free(&lossless);
            free_layers(imgs, n);
        }
}

/* The path of a second CSV next to the first: NAME.csv -> NAME-SUFFIX.csv. */
static FILE *side_csv(const char *csv_path, const char *suffix, const char *header)
{
    if (!csv_path)
        return NULL;
    char path[1024];
    snprintf(path, sizeof path, "%s", csv_path);
    char *dot = strrchr(path, '.');
    if (dot)
        *dot = 0;
    strncat(path, suffix, sizeof path - strlen(path) - 1);
    return bench_csv_open(path, header);
}

int main(int argc, char **argv)
{
    bench_args a;
    if (bench_parse_args(argc, argv, &a, "") < 0)
        return 2;
    int repeats = a.quick ? 1 : (a.repeats > 0 ? a.repeats : 15);
    int W = a.quick ? 64 : 1920, H = a.quick ? 36 : 1080;
    double cpy = 0, cpy_r = 0;
    double merge = best_merge(W, H, 0, repeats, &cpy);
    double merge_r = best_merge(W, H, 1, repeats, &cpy_r);
    size_t n = (size_t)W * H;
    printf("composite_kernel: %s\n", tsr_composite_kernel_name());
    bench_figure("merge_ns_per_pixel", merge * 1e9 / (double)n, 3);
    bench_figure("memcpy_frame_ms", cpy * 1e3, 3);
    bench_figure("merge_vs_memcpy", merge / cpy, 3);
    bench_figure("merge_random_ns_per_pixel", merge_r * 1e9 / (double)n, 3);
    bench_figure("merge_random_vs_memcpy", merge_r / cpy_r, 3);

    FILE *csv = bench_csv_open(a.csv_path, "size,codec,encode_ms,decode_ms,bytes,ratio,psnr_db,depth_max_error");
    static const char *codecs[] = {"none", "rle", "erle", "yuv420", "depth16", "depth24", "yuv420+depth16"};
    int sizes[2][2] = {{1024, 768}, {1920, 1080}};
    for (int si = 0; si < 2; si++) {
        int w = a.quick ? sizes[si][0] / 16 : sizes[si][0], h = a.quick ? sizes[si][1] / 16 : sizes[si][1];
        tsr_composite_image img = {0}, back = {0}, ref = {0};
        tsr_composite_sparse s = {0}, d = {0};
        tsr_error err;
        scene(&img, w, h);
        tsr_composite_sparse_compress(&img, TSR_COMPOSITE_DEPTH, 0, (uint32_t)(w * h), &s, &err);
        static const uint8_t bg[4] = {0, 0, 0, 0};
        tsr_composite_image_init(&ref, w, h, 0, 0, w, h, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, &err);
        tsr_composite_sparse_to_dense(&s, bg, &ref, &err);
        size_t frame_bytes = (size_t)w * h * 8;
        for (size_t ci = 0; ci < sizeof codecs / sizeof *codecs; ci++) {
            tsr_composite_codec c;
            tsr_composite_codec_parse(codecs[ci], &c, &err);
            size_t cap = tsr_composite_message_max_size(s.count, s.color_format, s.depth_format, c), len = 0;
            uint8_t *buf = malloc(cap);
            double enc = 1e9, dec = 1e9;
            for (int r = 0; r < (a.quick ? 1 : 7); r++) {
                double t0 = bench_now();
                tsr_composite_message_encode(&s, c, buf, cap, &len, &err);
                double t1 = bench_now();
                tsr_composite_message_decode(buf, len, NULL, &d, &err);
                double t2 = bench_now();
                enc = fmin(enc, t1 - t0);
                dec = fmin(dec, t2 - t1);
            }
            tsr_composite_image_init(&back, w, h, 0, 0, w, h, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, &err);
            tsr_composite_sparse_to_dense(&d, bg, &back, &err);
            double p = psnr8(ref.color, back.color, (size_t)w * h * 4), dz = 0;
            for (size_t i = 0; i < (size_t)w * h; i++)
                dz = fmax(dz, fabs((double)ref.depth[i] - back.depth[i]));
            char name[96];
            snprintf(name, sizeof name, "codec_%s_%dx%d", codecs[ci], w, h);
            for (char *q = name; *q; q++)
                if (*q == '+')
                    *q = '_';
            printf("%s: encode_ms %.3f decode_ms %.3f bytes %zu ratio %.3f psnr_db %.1f depth_max_error %.2g\n", name,
                   enc * 1e3, dec * 1e3, len, (double)len / frame_bytes, p, dz);
            if (csv)
                fprintf(csv, "%dx%d,%s,%.4f,%.4f,%zu,%.4f,%.2f,%.3g\n", w, h, codecs[ci], enc * 1e3, dec * 1e3, len,
                        (double)len / frame_bytes, isinf(p) ? 99.0 : p, dz);
            free(buf);
        }
        tsr_composite_image_free(&img);
        tsr_composite_image_free(&back);
        tsr_composite_image_free(&ref);
        tsr_composite_sparse_free(&s);
        tsr_composite_sparse_free(&d);
    }
    if (csv)
        fclose(csv);
    /* strategies and the codec sweep: CSVs next to the first */
    FILE *scsv =
        side_csv(a.csv_path, "-strategies.csv", "strategy,coverage,peers,cpu_ms,wall_ms,bytes_per_frame,chosen");
    bench_strategies(&a, scsv);
    if (scsv)
        fclose(scsv);
    FILE *ccsv = side_csv(a.csv_path, "-codecs.csv", "codec,size,peers,cpu_ms,wall_ms,bytes_per_frame,psnr_db,chosen");
    bench_codec_sweep(&a, ccsv);
    if (ccsv)
        fclose(ccsv);
    return 0;
}
