/* bench/icet/icet_composite.c — times IceT (Kitware's MPI sort-last
 * compositing library) on the inputs of tessera's binaryswap bench, so
 * tessera's composite_8x1080p_ms can be judged against the library the
 * target in issue 11 names. Run under mpirun, one rank per peer:
 *
 *   mpirun -np N icet_composite [--size WxH] [--frames F] [--warmup W]
 *       [--coverage full|ellipse|both] [--configs all|NAME,...]
 *       [--summary FILE] [--frames-csv FILE] [--label TEXT]
 *
 * Every rank makes the layer bench/binaryswap.sh hands each tessera peer (the
 * same generator, spus/binaryswap/synthetic.c, compiled in: RGBA8 colour +
 * float depth, rank r of N), expands it to the full-window buffers
 * icetCompositeImage takes (an ellipse layer's box is given to IceT as its
 * valid-pixels viewport, so IceT treats the rest as background and never
 * reads it), and composites it with IceT in depth mode into one tile of the
 * whole window whose display is rank 0 (IceT's display is one of the
 * compositing ranks, tessera's is a separate process). Configurations: each
 * single-image strategy under the sequential multi-tile strategy, the same
 * under reduce, and direct (every rank sends its image to the display),
 * with image interlacing on and off; image collection is on (the frame ends
 * on rank 0).
 *
 * Timing, per frame: MPI_Barrier (all layers ready: the start tessera's
 * bench takes, the last peer's layer handed over), then each rank reads
 * CLOCK_MONOTONIC (one clock for all ranks on this host) and calls
 * icetCompositeImage. The frame's time is from the earliest barrier exit
 * to rank 0's return (rank 0 then holds the composited frame); the time to
 * the last rank's return is kept too. Median over the frames after the
 * warm-up ones. The first warm-up frame of every configuration is checked:
 * rank 0's image against the depth-nearest of the N layers (lower rank on
 * equal depth) computed here, and the number of differing pixels printed.
 *
 * Owns only its buffers; knows nothing of tessera's compositor (only the
 * layer generator and the image struct it fills). */
#include <IceT.h>
#include <IceTMPI.h>
#include <mpi.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "synthetic.h"

typedef struct {
    const char *name;
    IceTEnum multi, single;
    int interlace;
} config;

#define CFG(m, s, mi, si)                                                              \
    {m "-" s "-interlace", ICET_STRATEGY_##mi, ICET_SINGLE_IMAGE_STRATEGY_##si, 1},    \
    {                                                                                  \
        m "-" s "-nointerlace", ICET_STRATEGY_##mi, ICET_SINGLE_IMAGE_STRATEGY_##si, 0 \
    }

static const config configs[] = {
    CFG("sequential", "automatic", SEQUENTIAL, AUTOMATIC),
    CFG("sequential", "bswap", SEQUENTIAL, BSWAP),
    CFG("sequential", "bswap_folding", SEQUENTIAL, BSWAP_FOLDING),
    CFG("sequential", "radixk", SEQUENTIAL, RADIXK),
    CFG("sequential", "radixkr", SEQUENTIAL, RADIXKR),
    CFG("sequential", "tree", SEQUENTIAL, TREE),
    CFG("reduce", "automatic", REDUCE, AUTOMATIC),
    CFG("reduce", "bswap", REDUCE, BSWAP),
    CFG("reduce", "bswap_folding", REDUCE, BSWAP_FOLDING),
    CFG("reduce", "radixk", REDUCE, RADIXK),
    CFG("reduce", "radixkr", REDUCE, RADIXKR),
    CFG("reduce", "tree", REDUCE, TREE),
    /* direct ignores the single-image strategy: every rank sends its image
     * to the tile's display, which composites them all. */
    CFG("direct", "none", DIRECT, AUTOMATIC),
};
enum { NCONFIGS = sizeof configs / sizeof configs[0] };

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

static void die(const char *what)
{
    fprintf(stderr, "icet_composite: %s\n", what);
    MPI_Abort(MPI_COMM_WORLD, 1);
    exit(1);
}

/* The layer of `rank` as full-window planes (background outside its
 * region) and its region as IceT's viewport {x, y, width, height}. */
static void make_layer(int mode, int w, int h, int rank, int n, uint8_t *color, float *depth, IceTInt vp[4])
{
    tsr_composite_image img = {0};
    tsr_error err = {0};
    if (tsr_composite_synthetic_layer(mode, w, h, rank, n, &img, &err) != TSR_OK)
        die(err.message);
    memset(color, 0, (size_t)w * (size_t)h * 4);
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++)
        depth[i] = 1.0f;
    for (int y = 0; y < img.height; y++) {
        size_t dst = (size_t)(img.y + y) * (size_t)w + (size_t)img.x, src = (size_t)y * (size_t)img.width;
        memcpy(color + 4 * dst, img.color + 4 * src, (size_t)img.width * 4);
        memcpy(depth + dst, img.depth + src, (size_t)img.width * sizeof(float));
    }
    vp[0] = img.x, vp[1] = img.y, vp[2] = img.width, vp[3] = img.height;
    tsr_composite_image_free(&img);
}

/* The depth-nearest of the n layers (the lower rank on equal depth): the
 * frame tessera's depth mode defines. */
static void expected_frame(int mode, int w, int h, int n, uint8_t *out)
{
    size_t px = (size_t)w * (size_t)h;
    uint8_t *c = malloc(px * 4);
    float *d = malloc(px * sizeof(float)), *best = malloc(px * sizeof(float));
    if (!c || !d || !best)
        die("out of memory (expected frame)");
    IceTInt vp[4];
    for (int r = 0; r < n; r++) {
        make_layer(mode, w, h, r, n, c, d, vp);
        for (size_t i = 0; i < px; i++)
            if (r == 0 || d[i] < best[i]) {
                best[i] = d[i];
                memcpy(out + 4 * i, c + 4 * i, 4);
            }
    }
    free(c), free(d), free(best);
}

static void usage(void)
{
    fprintf(stderr, "usage: mpirun -np N icet_composite [--size WxH] [--frames F] [--warmup W]\n"
                    "    [--coverage full|ellipse|both] [--configs all|NAME,...] [--summary FILE]\n"
                    "    [--frames-csv FILE] [--label TEXT]\nconfigurations:");
    for (int i = 0; i < NCONFIGS; i++)
        fprintf(stderr, " %s", configs[i].name);
    fprintf(stderr, "\n");
}

static int wanted(const char *list, const char *name)
{
    if (!strcmp(list, "all"))
        return 1;
    size_t len = strlen(name);
    for (const char *p = list; *p;) {
        const char *e = strchr(p, ',');
        size_t l = e ? (size_t)(e - p) : strlen(p);
        if (l == len && !strncmp(p, name, l))
            return 1;
        p += l + (e ? 1 : 0);
    }
    return 0;
}

int main(int argc, char **argv)
{
    MPI_Init(&argc, &argv);
    int rank, n;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &n);

    int w = 1920, h = 1080, frames = 20, warmup = 2;
    const char *coverage = "both", *list = "all", *summary = NULL, *frames_csv = NULL, *label = "";
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            if (rank == 0)
                usage();
            MPI_Finalize();
            return 0;
        }
        if (!v) {
            if (rank == 0)
                usage();
            MPI_Finalize();
            return 2;
        }
        if (!strcmp(a, "--size") && sscanf(v, "%dx%d", &w, &h) == 2 && w > 0 && h > 0)
            ;
        else if (!strcmp(a, "--frames") && (frames = atoi(v)) > 0)
            ;
        else if (!strcmp(a, "--warmup") && (warmup = atoi(v)) >= 1)
            ;
        else if (!strcmp(a, "--coverage") && (!strcmp(v, "full") || !strcmp(v, "ellipse") || !strcmp(v, "both")))
            coverage = v;
        else if (!strcmp(a, "--configs"))
            list = v;
        else if (!strcmp(a, "--summary"))
            summary = v;
        else if (!strcmp(a, "--frames-csv"))
            frames_csv = v;
        else if (!strcmp(a, "--label"))
            label = v;
        else {
            if (rank == 0) {
                fprintf(stderr, "icet_composite: bad argument %s %s\n", a, v);
                usage();
            }
            MPI_Finalize();
            return 2;
        }
        i++;
    }

    IceTCommunicator comm = icetCreateMPICommunicator(MPI_COMM_WORLD);
    IceTContext ctx = icetCreateContext(comm);
    (void)ctx;
    icetResetTiles();
    icetAddTile(0, 0, w, h, 0);
    icetPhysicalRenderSize(w, h);
    icetSetColorFormat(ICET_IMAGE_COLOR_RGBA_UBYTE);
    icetSetDepthFormat(ICET_IMAGE_DEPTH_FLOAT);
    icetCompositeMode(ICET_COMPOSITE_MODE_Z_BUFFER);
    icetEnable(ICET_COLLECT_IMAGES);
    icetDiagnostics(ICET_DIAG_ERRORS | ICET_DIAG_ALL_NODES);

    size_t px = (size_t)w * (size_t)h;
    uint8_t *color = malloc(px * 4), *expected = rank == 0 ? malloc(px * 4) : NULL;
    float *depth = malloc(px * sizeof(float));
    int total = warmup + frames;
    double *times = malloc(sizeof(double) * 4 * (size_t)n * (size_t)total);
    if (!color || !depth || !times || (rank == 0 && !expected))
        die("out of memory");
    const IceTDouble identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    const IceTFloat background[4] = {0, 0, 0, 0};

    FILE *sum = NULL, *fcsv = NULL;
    if (rank == 0 && summary) {
        sum = fopen(summary, "a");
        if (!sum)
            die("cannot open --summary file");
    }
    if (rank == 0 && frames_csv) {
        fcsv = fopen(frames_csv, "a");
        if (!fcsv)
            die("cannot open --frames-csv file");
    }

    for (int cov = 0; cov < 2; cov++) {
        const char *cname = cov ? "ellipse" : "full";
        if (strcmp(coverage, "both") && strcmp(coverage, cname))
            continue;
        int mode = cov ? TSR_COMPOSITE_SYNTHETIC_ELLIPSE : TSR_COMPOSITE_SYNTHETIC_FULL;
        IceTInt vp[4];
        make_layer(mode, w, h, rank, n, color, depth, vp);
        /* A full layer covers the window: no viewport, IceT reads it all
         * (as it does when it is given none). */
        const IceTInt *valid = mode == TSR_COMPOSITE_SYNTHETIC_ELLIPSE ? vp : NULL;
        if (rank == 0)
            expected_frame(mode, w, h, n, expected);

        for (int c = 0; c < NCONFIGS; c++) {
            const config *cf = &configs[c];
            if (!wanted(list, cf->name))
                continue;
            icetStrategy(cf->multi);
            icetSingleImageStrategy(cf->single);
            if (cf->interlace)
                icetEnable(ICET_INTERLACE_IMAGES);
            else
                icetDisable(ICET_INTERLACE_IMAGES);
            long diff = -1;
            for (int f = 0; f < total; f++) {
                MPI_Barrier(MPI_COMM_WORLD);
                double t0 = now_ms();
                IceTImage img = icetCompositeImage(color, depth, valid, identity, identity, background);
                double t1 = now_ms();
                if (icetGetError() != ICET_NO_ERROR)
                    die("IceT reported an error");
                IceTDouble draw_s = 0;
                IceTInt bytes = 0;
                icetGetDoublev(ICET_TOTAL_DRAW_TIME, &draw_s);
                icetGetIntegerv(ICET_BYTES_SENT, &bytes);
                if (f == 0 && rank == 0) {
                    if (icetImageIsNull(img) || icetImageGetWidth(img) != w || icetImageGetHeight(img) != h)
                        die("rank 0 got no whole-window image from IceT");
                    const IceTUByte *got = icetImageGetColorcub(img);
                    diff = 0;
                    for (size_t i = 0; i < px; i++)
                        diff += memcmp(got + 4 * i, expected + 4 * i, 4) != 0;
                }
                double mine[4] = {t0, t1, draw_s * 1e3, (double)bytes};
                MPI_Gather(mine, 4, MPI_DOUBLE, times + (size_t)f * 4 * (size_t)n, 4, MPI_DOUBLE, 0, MPI_COMM_WORLD);
            }
            if (rank != 0)
                continue;
            double *d0 = malloc(sizeof(double) * (size_t)frames * 4);
            if (!d0)
                die("out of memory");
            double *dall = d0 + frames, *ddraw = d0 + 2 * frames, *dbytes = d0 + 3 * frames;
            for (int f = warmup; f < total; f++) {
                const double *t = times + (size_t)f * 4 * (size_t)n;
                double start = t[0], end_all = t[1], draw = 0, bytes = 0;
                for (int r = 0; r < n; r++) {
                    start = t[4 * r] < start ? t[4 * r] : start;
                    end_all = t[4 * r + 1] > end_all ? t[4 * r + 1] : end_all;
                    draw = t[4 * r + 2] > draw ? t[4 * r + 2] : draw;
                    bytes += t[4 * r + 3];
                }
                int k = f - warmup;
                d0[k] = t[1] - start, dall[k] = end_all - start, ddraw[k] = draw, dbytes[k] = bytes;
                if (fcsv)
                    fprintf(fcsv, "%s,%d,%s,%s,%d,%.3f,%.3f,%.3f,%.0f\n", label, n, cname, cf->name, k, d0[k], dall[k],
                            draw, bytes);
            }
            double m0 = median(d0, frames), mall = median(dall, frames), mdraw = median(ddraw, frames),
                   mbytes = median(dbytes, frames);
            printf("icet peers=%d coverage=%s config=%s frames=%d median_ms=%.3f median_all_ranks_ms=%.3f "
                   "median_icet_draw_ms=%.3f median_bytes_sent=%.0f diff_pixels=%ld\n",
                   n, cname, cf->name, frames, m0, mall, mdraw, mbytes, diff);
            fflush(stdout);
            if (sum)
                fprintf(sum, "%s,%d,%s,%s,%d,%.3f,%.3f,%.3f,%.0f,%ld\n", label, n, cname, cf->name, frames, m0, mall,
                        mdraw, mbytes, diff);
            free(d0);
        }
    }
    if (sum)
        fclose(sum);
    if (fcsv)
        fclose(fcsv);
    free(color), free(depth), free(expected), free(times);
    icetDestroyContext(ctx);
    icetDestroyMPICommunicator(comm);
    MPI_Finalize();
    return 0;
}
