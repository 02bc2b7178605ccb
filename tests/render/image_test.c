/* tests/render/image_test.c — tests of tsr_image (core/image/image.c): PNG
 * round trips, conversion of every PNG colour type to RGBA8, compare,
 * row flip, frame patterns, error messages; also writes the fixture PNGs
 * the imgdiff CLI tests use. One behaviour per subcommand; each exits 0 on
 * success and prints what broke otherwise. Input files are written with
 * libpng directly, so the reader is checked against an independent writer. */
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/image.h"

#include "harness.h"

/* A deterministic test picture: every channel varies, alpha included. */
static void fill_pattern(tsr_image *img)
{
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            uint8_t *p = img->pixels + (size_t)y * img->stride + 4 * (size_t)x;
            p[0] = (uint8_t)(x * 7 + y);
            p[1] = (uint8_t)(y * 5 + 3);
            p[2] = (uint8_t)(x ^ y);
            p[3] = (uint8_t)(255 - x - y);
        }
}

static char *join(const char *dir, const char *file)
{
    static char buf[4][1024];
    static int next;
    char *out = buf[next++ % 4];
    snprintf(out, sizeof buf[0], "%s/%s", dir, file);
    return out;
}

/* Writes `rows` with libpng in the given colour type / depth (no tessera
 * code involved), optionally with a palette or a tRNS chunk. */
static int write_raw_png(const char *path, int w, int h, int color_type, int bit_depth, png_bytep *rows,
                         const png_color *palette, int palette_len, const png_color_16 *trans_color, int interlace)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        fclose(f);
        return -1;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, bit_depth, color_type,
                 interlace ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (palette)
        png_set_PLTE(png, info, palette, palette_len);
    if (trans_color)
        png_set_tRNS(png, info, NULL, 0, trans_color);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return fclose(f);
}

static const uint8_t *pixel_at(const tsr_image *img, int x, int y)
{
    return img->pixels + (size_t)y * img->stride + 4 * (size_t)x;
}

static int test_roundtrip(const char *dir)
{
    tsr_image a, b;
    tsr_error err = {0};
    CHECK(tsr_image_alloc(&a, 37, 23, &err) == TSR_OK, "%s", err.message);
    fill_pattern(&a);
    const char *path = join(dir, "roundtrip.png");
    CHECK(tsr_image_write_png(&a, path, &err) == TSR_OK, "%s", err.message);
    CHECK(tsr_image_read_png(&b, path, &err) == TSR_OK, "%s", err.message);
    CHECK(b.width == 37 && b.height == 23, "size %dx%d", b.width, b.height);
    if (b.pixels)
        CHECK(memcmp(a.pixels, b.pixels, a.stride * (size_t)a.height) == 0, "pixels changed");

    /* bottom-up writing stores the rows flipped */
    const char *flipped_path = join(dir, "roundtrip_bottom_up.png");
    tsr_image c;
    CHECK(tsr_image_write_png_pixels(a.pixels, a.width, a.height, a.stride, true, true, flipped_path, &err) == TSR_OK,
          "%s", err.message);
    CHECK(tsr_image_read_png(&c, flipped_path, &err) == TSR_OK, "%s", err.message);
    tsr_image_flip_rows(c.pixels, c.height, c.stride);
    if (c.pixels)
        CHECK(memcmp(a.pixels, c.pixels, a.stride * (size_t)a.height) == 0,
              "bottom-up write + flip does not give the original");
    tsr_image_free(&a);
    tsr_image_free(&b);
    tsr_image_free(&c);
    return harness_failures;
}

static int test_convert(const char *dir)
{
    enum { W = 5, H = 3 };
    tsr_error err = {0};
    tsr_image img;

    /* 8-bit grey: r = g = b = grey, a = 255 */
    png_byte grey[H][W];
    png_bytep grey_rows[H];
    for (int y = 0; y < H; y++) {
        grey_rows[y] = grey[y];
        for (int x = 0; x < W; x++)
            grey[y][x] = (png_byte)(40 * x + y);
    }
    const char *p = join(dir, "grey8.png");
    CHECK(write_raw_png(p, W, H, PNG_COLOR_TYPE_GRAY, 8, grey_rows, NULL, 0, NULL, 0) == 0, "writing %s", p);
    CHECK(tsr_image_read_png(&img, p, &err) == TSR_OK, "%s", err.message);
    if (img.pixels) {
        const uint8_t *px = pixel_at(&img, 3, 2);
        CHECK(px[0] == 122 && px[1] == 122 && px[2] == 122 && px[3] == 255, "grey8 pixel = %d %d %d %d", px[0], px[1],
              px[2], px[3]);
    }
    tsr_image_free(&img);

    /* interlaced 16-bit RGB: high bytes kept, alpha 255 */
    png_byte rgb16[H][W * 6];
    png_bytep rgb16_rows[H];
    for (int y = 0; y < H; y++) {
        rgb16_rows[y] = rgb16[y];
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3; c++) {
                rgb16[y][6 * x + 2 * c] = (png_byte)(10 * x + 50 * c + y); /* high byte */
                rgb16[y][6 * x + 2 * c + 1] = 0xee;                        /* low byte */
            }
    }
    p = join(dir, "rgb16_interlaced.png");
    CHECK(write_raw_png(p, W, H, PNG_COLOR_TYPE_RGB, 16, rgb16_rows, NULL, 0, NULL, 1) == 0, "writing %s", p);
    CHECK(tsr_image_read_png(&img, p, &err) == TSR_OK, "%s", err.message);
    if (img.pixels) {
        const uint8_t *px = pixel_at(&img, 4, 1);
        CHECK(px[0] == 41 && px[1] == 91 && px[2] == 141 && px[3] == 255, "rgb16 pixel = %d %d %d %d", px[0], px[1],
              px[2], px[3]);
    }
    tsr_image_free(&img);

    /* 4-bit palette with a tRNS-free palette: colours looked up */
    png_color palette[3] = {{255, 0, 0}, {0, 255, 0}, {10, 20, 30}};
    png_byte pal[H][(W + 1) / 2];
    png_bytep pal_rows[H];
    for (int y = 0; y < H; y++) {
        pal_rows[y] = pal[y];
        memset(pal[y], 0, sizeof pal[y]);
        for (int x = 0; x < W; x++) {
            int index = (x + y) % 3;
            pal[y][x / 2] |= (png_byte)(index << (x % 2 ? 0 : 4));
        }
    }
    p = join(dir, "palette4.png");
    CHECK(write_raw_png(p, W, H, PNG_COLOR_TYPE_PALETTE, 4, pal_rows, palette, 3, NULL, 0) == 0, "writing %s", p);
    CHECK(tsr_image_read_png(&img, p, &err) == TSR_OK, "%s", err.message);
    if (img.pixels) {
        const uint8_t *px = pixel_at(&img, 3, 1); /* index (3 + 1) % 3 = 1: green */
        CHECK(px[0] == 0 && px[1] == 255 && px[2] == 0 && px[3] == 255, "palette pixel = %d %d %d %d", px[0], px[1],
              px[2], px[3]);
        px = pixel_at(&img, 4, 0); /* index 1 */
        CHECK(px[1] == 255, "palette pixel (4,0) green = %d", px[1]);
        px = pixel_at(&img, 2, 0); /* index 2 */
        CHECK(px[0] == 10 && px[1] == 20 && px[2] == 30, "palette pixel (2,0) = %d %d %d", px[0], px[1], px[2]);
    }
    tsr_image_free(&img);

    /* grey + alpha */
    png_byte ga[H][W * 2];
    png_bytep ga_rows[H];
    for (int y = 0; y < H; y++) {
        ga_rows[y] = ga[y];
        for (int x = 0; x < W; x++) {
            ga[y][2 * x] = (png_byte)(x * 30);
            ga[y][2 * x + 1] = (png_byte)(200 - y);
        }
    }
    p = join(dir, "grey_alpha.png");
    CHECK(write_raw_png(p, W, H, PNG_COLOR_TYPE_GRAY_ALPHA, 8, ga_rows, NULL, 0, NULL, 0) == 0, "writing %s", p);
    CHECK(tsr_image_read_png(&img, p, &err) == TSR_OK, "%s", err.message);
    if (img.pixels) {
        const uint8_t *px = pixel_at(&img, 2, 2);
        CHECK(px[0] == 60 && px[1] == 60 && px[2] == 60 && px[3] == 198, "grey+alpha pixel = %d %d %d %d", px[0], px[1],
              px[2], px[3]);
    }
    tsr_image_free(&img);

    /* RGB with a tRNS colour key: that colour becomes transparent */
    png_byte rgb[H][W * 3];
    png_bytep rgb_rows[H];
    for (int y = 0; y < H; y++) {
        rgb_rows[y] = rgb[y];
        for (int x = 0; x < W; x++) {
            rgb[y][3 * x] = (png_byte)(x == 1 ? 9 : 100);
            rgb[y][3 * x + 1] = (png_byte)(x == 1 ? 8 : 100);
            rgb[y][3 * x + 2] = (png_byte)(x == 1 ? 7 : 100);
        }
    }
    png_color_16 key = {.red = 9, .green = 8, .blue = 7};
    p = join(dir, "rgb_trns.png");
    CHECK(write_raw_png(p, W, H, PNG_COLOR_TYPE_RGB, 8, rgb_rows, NULL, 0, &key, 0) == 0, "writing %s", p);
    CHECK(tsr_image_read_png(&img, p, &err) == TSR_OK, "%s", err.message);
    if (img.pixels) {
        CHECK(pixel_at(&img, 1, 0)[3] == 0, "keyed pixel alpha = %d", pixel_at(&img, 1, 0)[3]);
        CHECK(pixel_at(&img, 2, 0)[3] == 255, "other pixel alpha = %d", pixel_at(&img, 2, 0)[3]);
    }
    tsr_image_free(&img);
    return harness_failures;
}

static int test_compare(void)
{
    tsr_image a, b;
    tsr_error err = {0};
    tsr_image_diff d;
    tsr_image_alloc(&a, 10, 8, &err);
    tsr_image_alloc(&b, 10, 8, &err);
    fill_pattern(&a);
    fill_pattern(&b);
    CHECK(tsr_image_compare(&a, &b, 0, &d, &err) == TSR_OK, "%s", err.message);
    CHECK(d.differing_pixels == 0 && d.max_channel_error == 0 && isinf(d.psnr_db), "identical: %llu %d %f",
          (unsigned long long)d.differing_pixels, d.max_channel_error, d.psnr_db);

    /* two pixels off: one by 3 in red, one by 10 in alpha */
    uint8_t *p1 = b.pixels + 2 * b.stride + 4 * 3;
    p1[0] = (uint8_t)(p1[0] + 3);
    uint8_t *p2 = b.pixels + 5 * b.stride + 4 * 7;
    p2[3] = (uint8_t)(p2[3] - 10);
    CHECK(tsr_image_compare(&a, &b, 0, &d, &err) == TSR_OK, "%s", err.message);
    CHECK(d.differing_pixels == 2, "differing %llu", (unsigned long long)d.differing_pixels);
    CHECK(d.max_channel_error == 10, "max error %d", d.max_channel_error);
    double mse = (9.0 + 100.0) / (10.0 * 8.0 * 4.0);
    double expected_psnr = 10.0 * log10(255.0 * 255.0 / mse);
    CHECK(fabs(d.psnr_db - expected_psnr) < 1e-9, "psnr %f, expected %f", d.psnr_db, expected_psnr);
    CHECK(tsr_image_compare(&a, &b, 3, &d, &err) == TSR_OK && d.differing_pixels == 1, "tolerance 3: differing %llu",
          (unsigned long long)d.differing_pixels);
    CHECK(tsr_image_compare(&a, &b, 10, &d, &err) == TSR_OK && d.differing_pixels == 0, "tolerance 10: differing %llu",
          (unsigned long long)d.differing_pixels);

    tsr_image c;
    tsr_image_alloc(&c, 10, 9, &err);
    CHECK(tsr_image_compare(&a, &c, 0, &d, &err) == TSR_EINVAL, "size mismatch accepted");
    CHECK(strstr(err.message, "10x8") && strstr(err.message, "10x9"), "mismatch message lacks sizes: %s", err.message);
    tsr_image_free(&a);
    tsr_image_free(&b);
    tsr_image_free(&c);
    return harness_failures;
}

static int test_flip(void)
{
    tsr_image a, b;
    tsr_error err = {0};
    /* wide enough that a row is swapped in several chunks */
    tsr_image_alloc(&a, 700, 5, &err);
    tsr_image_alloc(&b, 700, 5, &err);
    fill_pattern(&a);
    fill_pattern(&b);
    tsr_image_flip_rows(b.pixels, b.height, b.stride);
    for (int y = 0; y < 5; y++)
        CHECK(memcmp(a.pixels + (size_t)y * a.stride, b.pixels + (size_t)(4 - y) * b.stride, a.stride) == 0,
              "row %d not mirrored", y);
    tsr_image_flip_rows(b.pixels, b.height, b.stride);
    CHECK(memcmp(a.pixels, b.pixels, a.stride * 5) == 0, "flipping twice is not identity");
    tsr_image_free(&a);
    tsr_image_free(&b);
    return harness_failures;
}

static int test_errors(const char *dir)
{
    tsr_image img;
    tsr_error err = {0};
    const char *missing = join(dir, "does-not-exist.png");
    CHECK(tsr_image_read_png(&img, missing, &err) == TSR_ENOENT, "missing file: code %d", err.code);
    CHECK(strstr(err.message, missing) != NULL, "message lacks the path: %s", err.message);

    const char *text = join(dir, "not-a-png.png");
    FILE *f = fopen(text, "w");
    fputs("this is not a PNG file at all\n", f);
    fclose(f);
    CHECK(tsr_image_read_png(&img, text, &err) == TSR_EINVAL, "text file accepted");
    CHECK(strstr(err.message, text) && strstr(err.message, "not a PNG"), "message: %s", err.message);

    /* a valid PNG cut in half: libpng's error comes back, naming the file */
    tsr_image a;
    tsr_image_alloc(&a, 64, 64, &err);
    fill_pattern(&a);
    const char *whole = join(dir, "whole.png");
    tsr_image_write_png(&a, whole, &err);
    tsr_image_free(&a);
    f = fopen(whole, "rb");
    unsigned char buf[4096];
    size_t n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    const char *cut = join(dir, "truncated.png");
    f = fopen(cut, "wb");
    fwrite(buf, 1, n / 2, f);
    fclose(f);
    CHECK(tsr_image_read_png(&img, cut, &err) == TSR_EINVAL, "truncated PNG accepted");
    CHECK(strstr(err.message, cut) && strstr(err.message, "bad PNG"), "message: %s", err.message);
    CHECK(img.pixels == NULL && img.width == 0, "image not cleared after a failed read");

    const char *no_dir = join(dir, "no/such/dir/x.png");
    tsr_image_alloc(&a, 4, 4, &err);
    CHECK(tsr_image_write_png(&a, no_dir, &err) == TSR_ENOENT, "write into missing dir: %d", err.code);
    CHECK(strstr(err.message, no_dir) != NULL, "message lacks the path: %s", err.message);
    tsr_image_free(&a);
    CHECK(tsr_image_alloc(&a, 0, 5, &err) == TSR_EINVAL, "0-wide image allocated");
    return harness_failures;
}

static int test_frame_path(void)
{
    char out[64];
    tsr_error err = {0};
    CHECK(tsr_image_frame_path(out, sizeof out, "out/f-%04d.png", 7, &err) == TSR_OK && !strcmp(out, "out/f-0007.png"),
          "got '%s' (%s)", out, err.message);
    CHECK(tsr_image_frame_path(out, sizeof out, "100%%-%d.png", 3, &err) == TSR_OK && !strcmp(out, "100%-3.png"),
          "got '%s' (%s)", out, err.message);
    CHECK(tsr_image_frame_path(out, sizeof out, "still.png", 3, &err) == TSR_OK && !strcmp(out, "still.png"),
          "got '%s'", out);
    const char *bad[] = {"f-%s.png", "f-%d-%d.png", "f-%n.png", "f-%123d.png", "f-%", "%ld"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        CHECK(tsr_image_frame_path(out, sizeof out, bad[i], 1, &err) == TSR_EINVAL, "pattern '%s' accepted", bad[i]);
        CHECK(strstr(err.message, bad[i]) != NULL, "message lacks the pattern: %s", err.message);
    }
    CHECK(tsr_image_frame_path(out, 8, "longer-than-eight-%d.png", 1, &err) == TSR_EINVAL, "overlong name accepted");
    return harness_failures;
}

/* Fixtures for the imgdiff CLI tests: base.png, base_copy.png,
 * one_pixel_off.png (one red channel +3), small.png (other size),
 * not_png.png (text). */
static int write_fixtures(const char *dir)
{
    tsr_image a;
    tsr_error err = {0};
    if (tsr_image_alloc(&a, 48, 32, &err) != TSR_OK)
        return fprintf(stderr, "%s\n", err.message), 1;
    fill_pattern(&a);
    a.pixels[0] = 100; /* keep +3 in range below */
    int rc = tsr_image_write_png(&a, join(dir, "base.png"), &err) |
             tsr_image_write_png(&a, join(dir, "base_copy.png"), &err);
    uint8_t *p = a.pixels + 10 * a.stride + 4 * 20;
    p[0] = (uint8_t)(p[0] < 250 ? p[0] + 3 : p[0] - 3);
    rc |= tsr_image_write_png(&a, join(dir, "one_pixel_off.png"), &err);
    tsr_image_free(&a);
    tsr_image_alloc(&a, 48, 31, &err);
    rc |= tsr_image_write_png(&a, join(dir, "small.png"), &err);
    tsr_image_free(&a);
    FILE *f = fopen(join(dir, "not_png.png"), "w");
    if (!f)
        return fprintf(stderr, "cannot write fixtures into %s\n", dir), 1;
    fputs("plain text\n", f);
    fclose(f);
    if (rc)
        fprintf(stderr, "%s\n", err.message);
    return rc != 0;
}

/* expect-size FILE W H: the PNG exists and has that size. */
static int expect_size(const char *path, int w, int h)
{
    tsr_image img;
    tsr_error err = {0};
    CHECK(tsr_image_read_png(&img, path, &err) == TSR_OK, "%s", err.message);
    CHECK(img.width == w && img.height == h, "%s is %dx%d, expected %dx%d", path, img.width, img.height, w, h);
    tsr_image_free(&img);
    return harness_failures;
}

/* The colour type libpng finds in `path` (PNG_COLOR_TYPE_*), or -1. */
static int png_colour_type(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    int type = -1;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (info && !setjmp(png_jmpbuf(png))) {
        png_init_io(png, f);
        png_read_info(png, info);
        type = png_get_color_type(png, info);
    }
    png_destroy_read_struct(&png, &info, NULL);
    fclose(f);
    return type;
}

/* tsr_image_write_png_pixels without keep_alpha writes an RGB file of the same RGB bytes: read
 * back, every alpha is 255 and every colour byte is the one given. */
static int test_rgb(const char *dir)
{
    tsr_image a, b;
    tsr_error err = {0};
    CHECK(tsr_image_alloc(&a, 29, 17, &err) == TSR_OK, "%s", err.message);
    fill_pattern(&a);
    for (int i = 0; i < a.width * a.height; i++)
        a.pixels[(size_t)i * 4 + 3] = (uint8_t)(i % 7); /* mostly transparent */
    const char *path = join(dir, "rgb.png");
    CHECK(tsr_image_write_png_pixels(a.pixels, a.width, a.height, a.stride, true, false, path, &err) == TSR_OK, "%s",
          err.message);
    CHECK(png_colour_type(path) == PNG_COLOR_TYPE_RGB, "colour type %d, not RGB", png_colour_type(path));
    CHECK(tsr_image_read_png(&b, path, &err) == TSR_OK, "%s", err.message);
    if (b.pixels) {
        tsr_image_flip_rows(b.pixels, b.height, b.stride);
        int wrong = 0;
        for (int i = 0; i < a.width * a.height; i++) {
            const uint8_t *p = a.pixels + (size_t)i * 4, *q = b.pixels + (size_t)i * 4;
            wrong += p[0] != q[0] || p[1] != q[1] || p[2] != q[2] || q[3] != 255;
        }
        CHECK(wrong == 0, "%d pixels changed colour or are not opaque", wrong);
    }
    tsr_image_free(&a);
    tsr_image_free(&b);
    return harness_failures;
}

/* Prints "FILE: RGB" or "FILE: RGBA min_alpha N" (the smallest alpha). */
static int print_channels(const char *path)
{
    int type = png_colour_type(path);
    if (type != PNG_COLOR_TYPE_RGB && type != PNG_COLOR_TYPE_RGB_ALPHA) {
        fprintf(stderr, "%s: not an 8-bit RGB or RGBA PNG (colour type %d)\n", path, type);
        return 1;
    }
    if (type == PNG_COLOR_TYPE_RGB) {
        printf("%s: RGB\n", path);
        return 0;
    }
    tsr_image img;
    tsr_error err = {0};
    if (tsr_image_read_png(&img, path, &err) != TSR_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    int min_alpha = 255;
    for (int i = 0; i < img.width * img.height; i++)
        if (img.pixels[(size_t)i * 4 + 3] < min_alpha)
            min_alpha = img.pixels[(size_t)i * 4 + 3];
    printf("%s: RGBA min_alpha %d\n", path, min_alpha);
    tsr_image_free(&img);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc >= 3 && !strcmp(argv[1], "rgb"))
        return test_rgb(argv[2]) != 0;
    if (argc >= 3 && !strcmp(argv[1], "channels"))
        return print_channels(argv[2]);
    if (argc >= 3 && !strcmp(argv[1], "roundtrip"))
        return test_roundtrip(argv[2]) != 0;
    if (argc >= 3 && !strcmp(argv[1], "convert"))
        return test_convert(argv[2]) != 0;
    if (argc >= 2 && !strcmp(argv[1], "compare"))
        return test_compare() != 0;
    if (argc >= 2 && !strcmp(argv[1], "flip"))
        return test_flip() != 0;
    if (argc >= 3 && !strcmp(argv[1], "errors"))
        return test_errors(argv[2]) != 0;
    if (argc >= 2 && !strcmp(argv[1], "frame-path"))
        return test_frame_path() != 0;
    if (argc >= 3 && !strcmp(argv[1], "fixtures"))
        return write_fixtures(argv[2]);
    if (argc >= 5 && !strcmp(argv[1], "expect-size"))
        return expect_size(argv[2], atoi(argv[3]), atoi(argv[4])) != 0;
    fprintf(stderr, "usage: image_test roundtrip DIR | convert DIR | compare | flip | errors DIR |\n"
                    "       frame-path | fixtures DIR | expect-size FILE W H | rgb DIR | channels FILE\n");
    return 2;
}
