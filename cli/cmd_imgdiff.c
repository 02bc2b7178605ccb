/* cli/cmd_imgdiff.c — `tessera imgdiff A.png B.png [--tolerance N] [--max-pixels N]`.
 * Owns the command's argument parsing and its three-line report; the
 * pixel work is tsr_image_compare. Both headers are read before either
 * image is decoded, so a size mismatch or a size over --max-pixels costs
 * no memory. Exit 0 within tolerance, 1 when pixels differ, 2 on usage
 * errors or unreadable / mismatched input. */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "tessera/image.h"

/* Default bound of what one file may claim: 256 MiB of RGBA, above every
 * frame an example or benchmark writes (a 4096x3072 wall is 12.6 Mpixels). */
#define IMGDIFF_MAX_PIXELS (8192ull * 8192ull)

static void imgdiff_usage(FILE *out)
{
    fprintf(out,
            "usage: tessera imgdiff A.png B.png [--tolerance N] [--max-pixels N]\n\n"
            "Compares two PNG images of the same size pixel by pixel and prints:\n"
            "  differing_pixels: N     pixels with any channel off by more than N\n"
            "  max_channel_error: N    largest difference of one channel (0..255)\n"
            "  psnr_db: X              PSNR over R, G, B, A in dB (inf when identical)\n\n"
            "options:\n"
            "  --tolerance N   allowed per-channel difference, 0..255 (default 0)\n"
            "  --max-pixels N  refuse, before decoding, a file whose header claims more than\n"
            "                  N pixels (width x height; default %llu = 8192x8192)\n"
            "  -h, --help      show this help\n\n"
            "Exit codes: 0 no pixel differs by more than the tolerance, 1 some do,\n"
            "2 usage error, missing or unreadable file, not a PNG, size mismatch or\n"
            "over --max-pixels (both headers are read before any pixel).\n",
            (unsigned long long)IMGDIFF_MAX_PIXELS);
}

static int parse_max_pixels(const char *text, uint64_t *out)
{
    char *end;
    errno = 0;
    unsigned long long v = strtoull(text, &end, 10);
    if (errno || end == text || *end || text[0] == '-' || v < 1)
        return -1;
    *out = v;
    return 0;
}

static int parse_tolerance(const char *text, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (errno || end == text || *end || v < 0 || v > 255)
        return -1;
    *out = (int)v;
    return 0;
}

int cmd_imgdiff(int argc, char **argv)
{
    const char *paths[2] = {NULL, NULL};
    int npaths = 0;
    int tolerance = 0;
    uint64_t max_pixels = IMGDIFF_MAX_PIXELS;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (!strcmp(arg, "-h") || !strcmp(arg, "--help")) {
            imgdiff_usage(stdout);
            return TSR_EXIT_OK;
        }
        const char *value = NULL;
        if (!strcmp(arg, "--max-pixels") || !strncmp(arg, "--max-pixels=", 13)) {
            const char *v = arg[12] == '=' ? arg + 13 : i + 1 < argc ? argv[++i] : NULL;
            if (!v) {
                fprintf(stderr, "tessera imgdiff: --max-pixels needs a value\n");
                return TSR_EXIT_USAGE;
            }
            if (parse_max_pixels(v, &max_pixels) != 0) {
                fprintf(stderr, "tessera imgdiff: bad --max-pixels '%s' (expected a number of pixels, 1 or more)\n", v);
                return TSR_EXIT_USAGE;
            }
            continue;
        }
        if (!strcmp(arg, "--tolerance")) {
            if (i + 1 >= argc) {
                fprintf(stderr, "tessera imgdiff: --tolerance needs a value\n");
                return TSR_EXIT_USAGE;
            }
            value = argv[++i];
        } else if (!strncmp(arg, "--tolerance=", 12)) {
            value = arg + 12;
        } else if (arg[0] == '-' && arg[1] != '\0') {
            fprintf(stderr, "tessera imgdiff: unknown option '%s' (see --help)\n", arg);
            return TSR_EXIT_USAGE;
        } else {
            if (npaths == 2) {
                fprintf(stderr, "tessera imgdiff: too many files ('%s'); expected two\n", arg);
                return TSR_EXIT_USAGE;
            }
            paths[npaths++] = arg;
            continue;
        }
        if (parse_tolerance(value, &tolerance) != 0) {
            fprintf(stderr, "tessera imgdiff: bad --tolerance '%s' (expected 0..255)\n", value);
            return TSR_EXIT_USAGE;
        }
    }
    if (npaths != 2) {
        fprintf(stderr, "tessera imgdiff: expected two PNG files (see --help)\n");
        return TSR_EXIT_USAGE;
    }

    /* Headers first: a mismatch or an oversized claim is refused before
     * any pixel is decoded. */
    int sizes[2][2];
    tsr_error err = {0};
    for (int k = 0; k < 2; k++)
        if (tsr_image_read_png_size(paths[k], UINT64_MAX, &sizes[k][0], &sizes[k][1], &err) != TSR_OK) {
            fprintf(stderr, "tessera imgdiff: %s\n", err.message);
            return TSR_EXIT_USAGE;
        }
    if (sizes[0][0] != sizes[1][0] || sizes[0][1] != sizes[1][1]) {
        fprintf(stderr, "tessera imgdiff: size mismatch: %s is %dx%d, %s is %dx%d\n", paths[0], sizes[0][0],
                sizes[0][1], paths[1], sizes[1][0], sizes[1][1]);
        return TSR_EXIT_USAGE;
    }
    uint64_t pixels = (uint64_t)sizes[0][0] * (uint64_t)sizes[0][1];
    if (pixels > max_pixels) {
        fprintf(stderr, "tessera imgdiff: %s claims %dx%d = %llu pixels, more than --max-pixels %llu\n", paths[0],
                sizes[0][0], sizes[0][1], (unsigned long long)pixels, (unsigned long long)max_pixels);
        return TSR_EXIT_USAGE;
    }
    tsr_image a = {0}, b = {0};
    if (tsr_image_read_png_limited(&a, paths[0], max_pixels, &err) != TSR_OK ||
        tsr_image_read_png_limited(&b, paths[1], max_pixels, &err) != TSR_OK) {
        fprintf(stderr, "tessera imgdiff: %s\n", err.message);
        tsr_image_free(&a);
        return TSR_EXIT_USAGE;
    }
    if (a.width != b.width || a.height != b.height) { /* a file changed under us */
        fprintf(stderr, "tessera imgdiff: size mismatch: %s is %dx%d, %s is %dx%d\n", paths[0], a.width, a.height,
                paths[1], b.width, b.height);
        tsr_image_free(&a);
        tsr_image_free(&b);
        return TSR_EXIT_USAGE;
    }
    tsr_image_diff diff;
    int rc = tsr_image_compare(&a, &b, tolerance, &diff, &err);
    tsr_image_free(&a);
    tsr_image_free(&b);
    if (rc != TSR_OK) {
        fprintf(stderr, "tessera imgdiff: %s\n", err.message);
        return TSR_EXIT_USAGE;
    }
    printf("differing_pixels: %llu\n", (unsigned long long)diff.differing_pixels);
    printf("max_channel_error: %d\n", diff.max_channel_error);
    if (isinf(diff.psnr_db))
        printf("psnr_db: inf\n");
    else
        printf("psnr_db: %.2f\n", diff.psnr_db);
    return diff.differing_pixels == 0 ? TSR_EXIT_OK : TSR_EXIT_FAIL;
}
