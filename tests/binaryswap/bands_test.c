/* tests/binaryswap/bands_test.c — binaryswap's plan for drawing a partial
 * final piece on the display (spus/binaryswap/bands.h): for random and
 * adversarial pieces (random runs, all active, one active pixel, a piece
 * starting and ending mid-row, one-row and one-column windows, every
 * call cost from 0 up), the boxes and clears must cover every pixel of the
 * piece's range exactly once and nothing outside it, and every active
 * pixel must lie in a box; a column of active pixels in the middle of
 * whole rows must be sent as that column only.
 *   bands_check        exit status 0 when every case holds */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bands.h"

static unsigned rng = 2463534242u;
static unsigned next(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 17;
    rng ^= rng << 5;
    return rng;
}

static int failures;

/* Builds a piece of `count` pixels from `start` whose pixel i is active
 * when act[i]; checks the plan against it. Returns the box pixels. */
static uint64_t check(int W, int H, uint32_t start, uint32_t count, const unsigned char *act, uint32_t call,
                      const char *what)
{
    tsr_composite_sparse in = {0};
    in.window_width = W, in.window_height = H, in.start = start, in.count = count;
    in.mode = TSR_COMPOSITE_DEPTH, in.color_format = TSR_COMPOSITE_RGBA8, in.depth_format = TSR_COMPOSITE_DEPTH32F;
    uint32_t *runs = malloc(((size_t)count + 1) * 2 * sizeof *runs);
    uint32_t n = 0, i = 0;
    while (i < count) {
        uint32_t a = 0, b = 0;
        while (i < count && !act[i])
            a++, i++;
        while (i < count && act[i])
            b++, i++;
        runs[2 * n] = a, runs[2 * n + 1] = b, n++;
        in.active += b;
    }
    in.runs = runs, in.nruns = n;
    binaryswap_bands p = {0};
    tsr_error err = {0};
    if (binaryswap_bands_plan(&p, &in, call, &err) != TSR_OK) {
        fprintf(stderr, "FAIL: %s: %s\n", what, err.message);
        failures++;
    }
    unsigned char *hits = calloc((size_t)W * (size_t)H, 1);
    unsigned char *boxed = calloc((size_t)W * (size_t)H, 1);
    uint64_t box_pixels = 0;
    int bad = 0;
    for (int pass = 0; pass < 2; pass++) {
        const binaryswap_rect *r = pass ? p.clears : p.boxes;
        size_t nr = pass ? p.nclears : p.nboxes;
        for (size_t k = 0; k < nr; k++) {
            if (r[k].w <= 0 || r[k].h <= 0 || r[k].x < 0 || r[k].y < 0 || r[k].x + r[k].w > W || r[k].y + r[k].h > H) {
                fprintf(stderr, "FAIL: %s: %s %zu is [%d, %d, %d, %d] in a %dx%d window\n", what,
                        pass ? "clear" : "box", k, r[k].x, r[k].y, r[k].w, r[k].h, W, H);
                bad = 1;
                continue;
            }
            for (int y = r[k].y; y < r[k].y + r[k].h; y++)
                for (int x = r[k].x; x < r[k].x + r[k].w; x++) {
                    size_t at = (size_t)y * (size_t)W + (size_t)x;
                    hits[at]++;
                    if (!pass)
                        boxed[at] = 1, box_pixels++;
                }
        }
    }
    for (size_t at = 0; at < (size_t)W * (size_t)H && !bad; at++) {
        int inside = at >= start && at < (size_t)start + count;
        if (hits[at] != inside) {
            fprintf(stderr, "FAIL: %s: pixel %zu (%s the range) covered %d times\n", what, at,
                    inside ? "inside" : "outside", hits[at]);
            bad = 1;
        } else if (inside && act[at - start] && !boxed[at]) {
            fprintf(stderr, "FAIL: %s: active pixel %zu is in no box\n", what, at);
            bad = 1;
        }
    }
    failures += bad;
    free(hits);
    free(boxed);
    free(runs);
    binaryswap_bands_free(&p);
    return box_pixels;
}

int main(void)
{
    char what[160];
    /* Random sizes, ranges, densities and call costs. */
    for (int t = 0; t < 400; t++) {
        int W = 1 + (int)(next() % 97), H = 1 + (int)(next() % 61);
        uint32_t total = (uint32_t)W * (uint32_t)H;
        uint32_t start = next() % total, count = 1 + next() % (total - start);
        unsigned char *act = malloc(count);
        unsigned mode = next() % 4, density = next() % 100;
        for (uint32_t i = 0; i < count; i++) {
            uint32_t x = (start + i) % (uint32_t)W;
            switch (mode) {
            case 0: act[i] = next() % 100 < density; break;                         /* scattered */
            case 1: act[i] = x > (uint32_t)W / 3 && x < (uint32_t)W * 2 / 3; break; /* a column band */
            case 2: act[i] = i == count / 2; break;                                 /* one pixel */
            default: act[i] = 1; break;                                             /* all active */
            }
        }
        uint32_t calls[] = {0, 1, 8, 64, 8192, 1u << 30};
        uint32_t call = calls[next() % (sizeof calls / sizeof calls[0])];
        snprintf(what, sizeof what, "case %d (%dx%d, pixels %u+%u, mode %u, call %u)", t, W, H, start, count, mode,
                 call);
        check(W, H, start, count, act, call, what);
        free(act);
    }
    /* Whole rows of a wide window, active only in the middle column: the
     * boxes hold that column, not the rows. */
    {
        int W = 1920, H = 135;
        uint32_t count = (uint32_t)W * (uint32_t)H;
        unsigned char *act = malloc(count);
        for (uint32_t i = 0; i < count; i++)
            act[i] = i % (uint32_t)W >= 800 && i % (uint32_t)W < 1100;
        uint64_t sent = check(W, H, 0, count, act, 8192, "middle column of whole rows");
        if (sent != 300u * (uint64_t)H) {
            fprintf(stderr, "FAIL: middle column of whole rows: %llu pixels in boxes, expected %u\n",
                    (unsigned long long)sent, 300u * (unsigned)H);
            failures++;
        }
        free(act);
    }
    if (failures)
        fprintf(stderr, "bands_check: %d failing cases\n", failures);
    else
        printf("bands_check: 401 cases hold\n");
    return failures ? 1 : 0;
}
