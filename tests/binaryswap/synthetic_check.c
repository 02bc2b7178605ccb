/* tests/binaryswap/synthetic_check.c — checks a display's frame against the
 * composite of binaryswap's synthetic layers (spus/binaryswap/synthetic.h)
 * computed here by a plain loop: per pixel the nearest depth wins, equal
 * depth the lower rank, and a pixel no layer covers is opaque black. It
 * also checks the layers' coverage: `full` covers every pixel and each of
 * N peers is nearest on about 1/N of them; `ellipse` covers 40% of the
 * window per peer, at a different place per peer.
 * usage: synthetic_check full|ellipse WIDTH HEIGHT N FRAME.png
 * Prints FAIL: lines and exits 1 on any difference. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "synthetic.h"
#include "tessera/image.h"

static int bad;
#define FAIL(...) (fprintf(stderr, "FAIL: " __VA_ARGS__), fputc('\n', stderr), bad = 1)

int main(int argc, char **argv)
{
    if (argc != 6) {
        fprintf(stderr, "usage: synthetic_check full|ellipse WIDTH HEIGHT N FRAME.png\n");
        return 2;
    }
    tsr_error err = {0};
    int mode, W = atoi(argv[2]), H = atoi(argv[3]), n = atoi(argv[4]);
    if (tsr_composite_synthetic_parse(argv[1], &mode, &err) || mode == TSR_COMPOSITE_SYNTHETIC_OFF || W < 1 || H < 1 ||
        n < 1 || n > 64) {
        fprintf(stderr, "synthetic_check: bad arguments (%s)\n", err.message);
        return 2;
    }
    tsr_composite_image layers[64];
    memset(layers, 0, sizeof layers);
    size_t npix = (size_t)W * H;
    uint8_t *want = malloc(npix * 4);
    int *winner = malloc(npix * sizeof *winner);
    long wins[64] = {0}, covered[64] = {0};
    for (int r = 0; r < n; r++)
        if (tsr_composite_synthetic_layer(mode, W, H, r, n, &layers[r], &err)) {
            fprintf(stderr, "synthetic_check: %s\n", err.message);
            return 2;
        }
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float best = 1.0f;
            int who = -1;
            const uint8_t *c = NULL;
            for (int r = 0; r < n; r++) {
                const tsr_composite_image *l = &layers[r];
                if (x < l->x || x >= l->x + l->width || y < l->y || y >= l->y + l->height)
                    continue;
                size_t i = (size_t)(y - l->y) * l->width + (x - l->x);
                if (l->depth[i] < 1.0f)
                    covered[r]++;
                if (l->depth[i] < best) {
                    best = l->depth[i];
                    who = r;
                    c = l->color + 4 * i;
                }
            }
            size_t p = (size_t)y * W + x;
            static const uint8_t black[4] = {0, 0, 0, 255};
            memcpy(want + 4 * p, c ? c : black, 4);
            winner[p] = who;
            if (who >= 0)
                wins[who]++;
        }
    /* Coverage. */
    for (int r = 0; r < n; r++) {
        double share = (double)covered[r] / npix, won = (double)wins[r] / npix;
        printf("rank %d: covers %.4f of the window, nearest on %.4f\n", r, share, won);
        if (mode == TSR_COMPOSITE_SYNTHETIC_FULL) {
            if (covered[r] != (long)npix)
                FAIL("full layer of rank %d covers %ld of %zu pixels", r, covered[r], npix);
            if (fabs(won - 1.0 / n) > 0.25 / n + 2.0 / W)
                FAIL("rank %d is nearest on %.4f of the window, not about 1/%d", r, won, n);
        } else {
            if (fabs(share - 0.40) > 0.01 + 4.0 / (W < H ? W : H))
                FAIL("ellipse of rank %d covers %.4f of the window, not 0.40", r, share);
            for (int q = 0; q < r; q++)
                if (layers[q].x == layers[r].x && layers[q].y == layers[r].y)
                    FAIL("ellipses of ranks %d and %d are at one place", q, r);
        }
    }
    /* The display's frame. */
    tsr_image img = {0};
    if (tsr_image_read_png(&img, argv[5], &err)) {
        FAIL("%s", err.message);
        return 1;
    }
    if (img.width != W || img.height != H) {
        FAIL("%s is %dx%d, not %dx%d", argv[5], img.width, img.height, W, H);
        return 1;
    }
    long differ = 0;
    int first_x = -1, first_y = -1;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const uint8_t *got = img.pixels + (size_t)(H - 1 - y) * img.stride + 4 * (size_t)x;
            const uint8_t *w = want + 4 * ((size_t)y * W + x);
            if (memcmp(got, w, 3)) { /* RGB: the display's PNG alpha is its own */
                if (!differ++)
                    first_x = x, first_y = y;
            }
        }
    printf("%s: differing_pixels: %ld of %zu\n", argv[5], differ, npix);
    if (differ) {
        const uint8_t *got = img.pixels + (size_t)(H - 1 - first_y) * img.stride + 4 * (size_t)first_x;
        const uint8_t *w = want + 4 * ((size_t)first_y * W + first_x);
        FAIL("%ld pixels differ from the reference composite; first at (%d, %d) (GL rows): got %d,%d,%d, want "
             "%d,%d,%d (rank %d)",
             differ, first_x, first_y, got[0], got[1], got[2], w[0], w[1], w[2], winner[(size_t)first_y * W + first_x]);
    }
    for (int r = 0; r < n; r++)
        tsr_composite_image_free(&layers[r]);
    tsr_image_free(&img);
    free(want);
    free(winner);
    return bad;
}
