/* tests/apitrace/frames_compare.c — apitrace_frames_compare [--all] [--from K] A_DIR B_DIR MIN_PSNR:
 * the frames of two replays of one trace, side by side. Each directory's
 * *.png files, sorted by name, are its frames in order (glretrace's
 * snapshots are named by call number, render's and tilesort's by frame
 * number, both zero-padded). There must be as many in B as in A, each the
 * same size as A's, and each equal to A's in R, G and B (alpha is not
 * compared: a window shows none) or, when MIN_PSNR is a number, at least
 * MIN_PSNR dB of PSNR over R, G and B; MIN_PSNR "exact" allows no pixel
 * to differ. With --from K, frames 0..K-1 are counted but not compared
 * (replay.py: Mesa draws a replay's frame 0 natively before it takes the
 * window's new size). A's last frame must hold more than one colour, so a replay
 * that draws nothing cannot pass against another that draws nothing.
 * Prints one line per frame that is not equal (or every frame with
 * --all) and a summary "frames N equal E within P, worst W dB"; exits 0
 * when all agree, 1 otherwise, 2 on bad input. */
#include <dirent.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/image.h"

#define MAX_FRAMES 4096

static int by_name(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* The *.png names of `dir`, sorted; the count, or -1 (message printed). */
static int list_frames(const char *dir, char **names)
{
    DIR *d = opendir(dir);
    if (!d) {
        fprintf(stderr, "apitrace_frames_compare: cannot open the folder %s\n", dir);
        return -1;
    }
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        size_t len = strlen(e->d_name);
        if (len < 5 || e->d_name[0] == '.' || strcmp(e->d_name + len - 4, ".png") != 0)
            continue;
        if (n == MAX_FRAMES) {
            fprintf(stderr, "apitrace_frames_compare: %s holds more than %d frames\n", dir, MAX_FRAMES);
            closedir(d);
            return -1;
        }
        names[n++] = strdup(e->d_name);
    }
    closedir(d);
    qsort(names, (size_t)n, sizeof *names, by_name);
    return n;
}

typedef struct rgb_diff {
    uint64_t differing; /* pixels whose R, G or B differ */
    int max_error;      /* largest difference of one of R, G, B */
    double psnr;        /* over R, G, B; INFINITY when equal */
} rgb_diff;

static rgb_diff compare_rgb(const tsr_image *a, const tsr_image *b)
{
    rgb_diff d = {0, 0, INFINITY};
    double squares = 0;
    for (int y = 0; y < a->height; y++) {
        const uint8_t *pa = a->pixels + (size_t)y * a->stride, *pb = b->pixels + (size_t)y * b->stride;
        for (int x = 0; x < a->width; x++, pa += 4, pb += 4) {
            int differs = 0;
            for (int c = 0; c < 3; c++) {
                int e = abs((int)pa[c] - (int)pb[c]);
                if (e) {
                    differs = 1;
                    squares += (double)e * e;
                    d.max_error = e > d.max_error ? e : d.max_error;
                }
            }
            d.differing += (uint64_t)differs;
        }
    }
    if (d.differing) {
        double mse = squares / (3.0 * a->width * a->height);
        d.psnr = 10.0 * log10(255.0 * 255.0 / mse);
    }
    return d;
}

static bool one_colour(const tsr_image *img)
{
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++)
            if (memcmp(img->pixels + (size_t)y * img->stride + 4 * (size_t)x, img->pixels, 3) != 0)
                return false;
    return true;
}

static bool read_frame(tsr_image *img, const char *dir, const char *name)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    tsr_error err = {0};
    if (tsr_image_read_png(img, path, &err) != TSR_OK) {
        fprintf(stderr, "apitrace_frames_compare: %s\n", err.message);
        return false;
    }
    return true;
}

int main(int argc, char **argv)
{
    bool all = false;
    int from = 0;
    for (;;) {
        if (argc > 1 && !strcmp(argv[1], "--all")) {
            all = true;
            argc--, argv++;
        } else if (argc > 2 && !strcmp(argv[1], "--from")) {
            from = atoi(argv[2]);
            argc -= 2, argv += 2;
        } else {
            break;
        }
    }
    if (argc != 4 || from < 0) {
        fprintf(stderr, "usage: apitrace_frames_compare [--all] [--from K] A_DIR B_DIR MIN_PSNR|exact\n");
        return 2;
    }
    const char *adir = argv[1], *bdir = argv[2];
    bool exact = !strcmp(argv[3], "exact");
    char *end;
    double min_psnr = exact ? INFINITY : strtod(argv[3], &end);
    if (!exact && (end == argv[3] || *end || !(min_psnr > 0))) {
        fprintf(stderr, "apitrace_frames_compare: MIN_PSNR '%s' is neither a positive number nor 'exact'\n", argv[3]);
        return 2;
    }
    static char *anames[MAX_FRAMES], *bnames[MAX_FRAMES];
    int na = list_frames(adir, anames), nb = list_frames(bdir, bnames);
    if (na < 0 || nb < 0)
        return 2;
    int status = 0;
    if (na == 0) {
        printf("FAIL: %s holds no frame\n", adir);
        return 1;
    }
    if (na != nb) {
        printf("FAIL: %d frames in %s but %d in %s\n", na, adir, nb, bdir);
        status = 1;
    }
    int n = na < nb ? na : nb, equal = 0, within = 0;
    double worst = INFINITY;
    for (int i = from; i < n; i++) {
        tsr_image a = {0}, b = {0};
        if (!read_frame(&a, adir, anames[i]) || !read_frame(&b, bdir, bnames[i])) {
            tsr_image_free(&a);
            return 2;
        }
        if (i == na - 1 && one_colour(&a)) {
            printf("FAIL: %s/%s, the last frame, is all one colour (RGB %u %u %u): the trace draws nothing to "
                   "compare\n",
                   adir, anames[i], a.pixels[0], a.pixels[1], a.pixels[2]);
            status = 1;
        }
        if (a.width != b.width || a.height != b.height) {
            printf("FAIL frame %d: %s/%s is %dx%d, %s/%s %dx%d\n", i, adir, anames[i], a.width, a.height, bdir,
                   bnames[i], b.width, b.height);
            status = 1;
        } else {
            rgb_diff d = compare_rgb(&a, &b);
            bool ok = d.differing == 0 || d.psnr >= min_psnr;
            equal += d.differing == 0;
            within += d.differing != 0 && ok;
            worst = d.psnr < worst ? d.psnr : worst;
            if (!ok)
                status = 1;
            if (all || d.differing)
                printf("%s frame %d (%s, %s): %llu px differ in RGB, max %d, PSNR %.2f dB\n", ok ? "ok" : "FAIL", i,
                       anames[i], bnames[i], (unsigned long long)d.differing, d.max_error, d.psnr);
        }
        tsr_image_free(&a);
        tsr_image_free(&b);
    }
    char skipped[64] = "";
    if (from > 0)
        snprintf(skipped, sizeof skipped, " (frames 0-%d not compared)", from - 1);
    if (isinf(worst))
        printf("frames %d/%d equal %d within %d, worst inf dB%s\n", nb, na, equal, within, skipped);
    else
        printf("frames %d/%d equal %d within %d, worst %.2f dB%s\n", nb, na, equal, within, worst, skipped);
    for (int i = 0; i < na; i++)
        free(anames[i]);
    for (int i = 0; i < nb; i++)
        free(bnames[i]);
    return status;
}
