/* tests/fuzz/fuzz_png.c — fuzz target for the PNG reader that `tessera
 * imgdiff` uses (tsr_image_read_png, core/image/image.c): the input is a
 * PNG file. It is written to a scratch file of this process (the reader
 * takes a path, as imgdiff gives it) and read; an image that reads is
 * compared with itself, written with the project's writer and read back.
 * Owns the scratch file (removed at exit) and one image per input.
 * Checked: a rejection is a one-line message and leaves the image zeroed;
 * an accepted image has sides in 1..TSR_IMAGE_MAX_SIDE, every pixel byte
 * readable (ASan), no difference from itself, and survives the round trip
 * through the writer unchanged.
 * Built with TSR_FUZZ_SEEDS it is fuzz_png_seeds OUTDIR, writing ok-*.png
 * seeds with the project's writer. */
#include "fuzz_target.h"

#include <stdbool.h>
#include <stdlib.h>
#include <unistd.h>

#include "tessera/image.h"

#ifndef TSR_FUZZ_SEEDS

static char scratch[2][4096];

static void remove_scratch(void)
{
    for (int i = 0; i < 2; i++)
        if (scratch[i][0])
            unlink(scratch[i]);
}

static const char *scratch_path(int i)
{
    if (!scratch[0][0]) {
        const char *dir = getenv("TMPDIR");
        for (int k = 0; k < 2; k++)
            snprintf(scratch[k], sizeof scratch[k], "%s/fuzz-png-%ld-%d.png", dir && *dir ? dir : "/tmp",
                     (long)getpid(), k);
        atexit(remove_scratch);
    }
    return scratch[i];
}


int fuzz_target_explain(const uint8_t *data, size_t size, char *why, size_t why_size)
{
    const char *path = scratch_path(0);
    FILE *f = fopen(path, "wb");
    FUZZ_REQUIRE(f != NULL);
    FUZZ_REQUIRE(fwrite(data, 1, size, f) == size && fclose(f) == 0);
    tsr_image img;
    memset(&img, 0xa5, sizeof img);
    tsr_error err = {0};
    int rc = tsr_image_read_png(&img, path, &err);
    if (rc != TSR_OK) {
        FUZZ_REQUIRE(img.pixels == NULL && img.width == 0 && img.height == 0);
        return fuzz_rejected(rc, &err, why, why_size);
    }
    FUZZ_REQUIRE(img.width >= 1 && img.width <= TSR_IMAGE_MAX_SIDE);
    FUZZ_REQUIRE(img.height >= 1 && img.height <= TSR_IMAGE_MAX_SIDE);
    FUZZ_REQUIRE(img.stride == (size_t)img.width * 4 && img.pixels != NULL);
    tsr_image_diff diff;
    FUZZ_REQUIRE(tsr_image_compare(&img, &img, 0, &diff, &err) == TSR_OK);
    FUZZ_REQUIRE(diff.differing_pixels == 0 && diff.max_channel_error == 0);
    /* The writer's output reads back as the same pixels. Skipped for very
     * large images only to keep each run short (reading was the test). */
    if ((uint64_t)img.width * (uint64_t)img.height <= 1u << 20) {
        const char *copy = scratch_path(1);
        FUZZ_REQUIRE(tsr_image_write_png(&img, copy, &err) == TSR_OK);
        tsr_image back = {0};
        FUZZ_REQUIRE(tsr_image_read_png(&back, copy, &err) == TSR_OK);
        FUZZ_REQUIRE(back.width == img.width && back.height == img.height);
        FUZZ_REQUIRE(!memcmp(back.pixels, img.pixels, img.stride * (size_t)img.height));
        tsr_image_free(&back);
    }
    tsr_image_free(&img);
    return TSR_OK;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_target_explain(data, size, NULL, 0);
    return 0;
}

#else /* TSR_FUZZ_SEEDS */

/* Small images in the shapes the project writes (render frames, tiles,
 * imgdiff fixtures): odd sizes, alpha, gradients, a flat image. */
int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s OUTDIR\n", argv[0]);
        return 2;
    }
    static const int sizes[][2] = {{1, 1}, {7, 5}, {16, 16}, {33, 2}, {64, 48}};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        for (int pattern = 0; pattern < 2; pattern++) {
            tsr_image img = {0};
            tsr_error err = {0};
            if (tsr_image_alloc(&img, sizes[s][0], sizes[s][1], &err) != TSR_OK)
                return fprintf(stderr, "fuzz_png_seeds: %s\n", err.message), 1;
            for (int y = 0; y < img.height; y++)
                for (int x = 0; x < img.width; x++) {
                    uint8_t *p = img.pixels + (size_t)y * img.stride + (size_t)x * 4;
                    p[0] = pattern ? 40 : (uint8_t)(x * 255 / img.width);
                    p[1] = pattern ? 80 : (uint8_t)(y * 255 / img.height);
                    p[2] = pattern ? 120 : (uint8_t)((x ^ y) * 37);
                    p[3] = pattern ? 255 : (uint8_t)(255 - x);
                }
            char path[4096];
            snprintf(path, sizeof path, "%s/ok-%dx%d-%s.png", argv[1], img.width, img.height,
                     pattern ? "flat" : "gradient");
            if (tsr_image_write_png(&img, path, &err) != TSR_OK)
                return fprintf(stderr, "fuzz_png_seeds: %s\n", err.message), 1;
            tsr_image_free(&img);
        }
    }
    return 0;
}

#endif
