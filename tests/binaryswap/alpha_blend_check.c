/* tests/binaryswap/alpha_blend_check.c — the reference of alpha mode: a serial
 * back-to-front blend of the peers' layers, each a PNG the part rendered
 * natively (cleared to transparent black), written here as plain loops
 * independent of the compositing library, and compared with the display's
 * PNG.
 *
 *   acc = (0, 0, 0, 0); for the layers from the back: acc = layer over acc;
 *   then acc over the background (added once).
 *
 * rgba8:   over per channel: f + round(b * (255 - fa) / 255), at most 255
 *          (binaryswap's rule, tessera/dev/composite.h), so every step
 *          rounds as the compositor must.
 * rgba32f: the bytes as c / 255.0f, over in float (f + b * (1 - fa)), one
 *          rounding at the end: round(clamp(v, 0, 1) * 255).
 *
 * rgba8-front-to-back: the same steps grouped the other way, acc = acc over
 *          layer from the front, as a regrouping schedule (binary swap)
 *          would: the test shows its scene tells the two apart.
 *
 * usage: alpha_blend rgba8|rgba32f|rgba8-front-to-back DISPLAY.png BACKGROUND.png|none
 *        LAYER0.png [LAYER1.png ...]   (layers in view order, front first;
 *        BACKGROUND.png: its pixel (0, 0) is the background colour)
 * Prints "differing_pixels: N" and the first differing pixel; exit status
 * 0 when N is 0, 1 when not, 2 on bad input. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/image.h"

#define MAX_LAYERS 64

static unsigned over8(unsigned f, unsigned b, unsigned fa)
{
    unsigned v = f + (b * (255u - fa) + 127u) / 255u;
    return v > 255u ? 255u : v;
}

static unsigned byte_of(float v)
{
    if (!(v > 0.0f))
        return 0;
    if (v >= 1.0f)
        return 255;
    return (unsigned)lrintf(v * 255.0f);
}

static int load(tsr_image *img, const char *path)
{
    tsr_error err = {0};
    if (tsr_image_read_png(img, path, &err) != TSR_OK) {
        fprintf(stderr, "alpha_blend: %s\n", err.message);
        return 0;
    }
    return 1;
}

int main(int argc, char **argv)
{
    if (argc < 5 ||
        (strcmp(argv[1], "rgba8") && strcmp(argv[1], "rgba32f") && strcmp(argv[1], "rgba8-front-to-back")) ||
        argc - 4 > MAX_LAYERS) {
        fprintf(stderr, "usage: alpha_blend rgba8|rgba32f|rgba8-front-to-back DISPLAY.png BACKGROUND.png|none "
                        "LAYER0.png ...\n");
        return 2;
    }
    int f32 = !strcmp(argv[1], "rgba32f"), ftb = !strcmp(argv[1], "rgba8-front-to-back"), n = argc - 4;
    tsr_image shown = {0}, layers[MAX_LAYERS] = {{0}};
    unsigned bg[4] = {0, 0, 0, 0};
    if (!load(&shown, argv[2]))
        return 2;
    if (strcmp(argv[3], "none")) {
        tsr_image b = {0};
        if (!load(&b, argv[3]))
            return 2;
        for (int c = 0; c < 4; c++)
            bg[c] = b.pixels[c];
        tsr_image_free(&b);
    }
    for (int i = 0; i < n; i++) {
        if (!load(&layers[i], argv[4 + i]))
            return 2;
        if (layers[i].width != shown.width || layers[i].height != shown.height) {
            fprintf(stderr, "alpha_blend: %s is %dx%d, the display's frame %dx%d\n", argv[4 + i], layers[i].width,
                    layers[i].height, shown.width, shown.height);
            return 2;
        }
    }
    long differing = 0, first = -1;
    unsigned want[4] = {0};
    size_t pixels = (size_t)shown.width * (size_t)shown.height;
    for (size_t p = 0; p < pixels; p++) {
        unsigned out[4];
        if (ftb) {
            unsigned acc[4] = {0, 0, 0, 0};
            for (int i = 0; i < n; i++) {
                const uint8_t *L = layers[i].pixels + 4 * p;
                unsigned next[4];
                for (int c = 0; c < 4; c++)
                    next[c] = over8(acc[c], L[c], acc[3]);
                memcpy(acc, next, sizeof acc);
            }
            for (int c = 0; c < 4; c++)
                out[c] = over8(acc[c], bg[c], acc[3]);
        } else if (!f32) {
            unsigned acc[4] = {0, 0, 0, 0};
            for (int i = n - 1; i >= 0; i--) {
                const uint8_t *L = layers[i].pixels + 4 * p;
                unsigned next[4];
                for (int c = 0; c < 4; c++)
                    next[c] = over8(L[c], acc[c], L[3]);
                memcpy(acc, next, sizeof acc);
            }
            for (int c = 0; c < 4; c++)
                out[c] = over8(acc[c], bg[c], acc[3]);
        } else {
            float acc[4] = {0, 0, 0, 0};
            for (int i = n - 1; i >= 0; i--) {
                const uint8_t *L = layers[i].pixels + 4 * p;
                float keep = 1.0f - (float)L[3] / 255.0f, next[4];
                for (int c = 0; c < 4; c++)
                    next[c] = (float)L[c] / 255.0f + acc[c] * keep;
                memcpy(acc, next, sizeof acc);
            }
            float keep = 1.0f - acc[3];
            for (int c = 0; c < 4; c++)
                out[c] = byte_of(acc[c] + ((float)bg[c] / 255.0f) * keep);
        }
        const uint8_t *got = shown.pixels + 4 * p;
        if (got[0] != out[0] || got[1] != out[1] || got[2] != out[2] || got[3] != out[3]) {
            if (first < 0) {
                first = (long)p;
                memcpy(want, out, sizeof want);
            }
            differing++;
        }
    }
    printf("differing_pixels: %ld\n", differing);
    if (first >= 0) {
        const uint8_t *got = shown.pixels + 4 * first;
        printf("first at x %ld, row %ld from the top: display %u,%u,%u,%u, serial blend %u,%u,%u,%u\n",
               first % shown.width, first / shown.width, got[0], got[1], got[2], got[3], want[0], want[1], want[2],
               want[3]);
    }
    tsr_image_free(&shown);
    for (int i = 0; i < n; i++)
        tsr_image_free(&layers[i]);
    return differing ? 1 : 0;
}
