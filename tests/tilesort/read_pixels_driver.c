/* tests/tilesort/read_pixels_driver.c — glReadPixels of rectangles that meet only
 * some of a wall's tiles, as piglit's probes read them (issue 27, item 8:
 * gl-1.0-texgen died with SIGSEGV inside tilesort on a 2x2 wall; one probe
 * of one pixel beside the first server's tile, in the same rows, made the
 * gather copy a row of negative width).
 *
 * Each frame clears the window to a 4x4 checker of distinct colours (cells
 * of the window, not of the tiles: edges fall inside tiles) with scissored
 * clears, then reads back single pixels on a lattice, the pixels on both
 * sides of the 2x2 tile edges, and rectangles inside one tile, beside the
 * first tile, and across all four, as RGBA bytes and as RGB floats (piglit's
 * probes), each into a buffer with guard bytes after it. Every value must
 * be the cell's colour and every guard byte untouched: otherwise one line
 * names the read and the program exits 1. Built twice like the examples
 * (examples/common/exapp.h): -native checks the reads against OSMesa
 * itself, so the expectations are GL's, not tessera's. */
#include <GL/gl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/exapp.h"

enum { CELLS = 4, GUARD = 64 };

static int width, height, failures;

static void cell_colour(int x, int y, unsigned char rgba[4])
{
    int cx = x * CELLS / width, cy = y * CELLS / height, k = cy * CELLS + cx;
    rgba[0] = (unsigned char)(15 * k);
    rgba[1] = (unsigned char)(255 - 15 * k);
    rgba[2] = (unsigned char)(k % 2 ? 255 : 51);
    rgba[3] = 255;
}

static void draw_checker(void)
{
    glEnable(GL_SCISSOR_TEST);
    for (int cy = 0; cy < CELLS; cy++)
        for (int cx = 0; cx < CELLS; cx++) {
            int x0 = (cx * width + CELLS - 1) / CELLS, y0 = (cy * height + CELLS - 1) / CELLS;
            int x1 = ((cx + 1) * width + CELLS - 1) / CELLS, y1 = ((cy + 1) * height + CELLS - 1) / CELLS;
            unsigned char c[4];
            cell_colour(x0, y0, c);
            glScissor(x0, y0, x1 - x0, y1 - y0);
            glClearColor(c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f, 1);
            glClear(GL_COLOR_BUFFER_BIT);
        }
    glDisable(GL_SCISSOR_TEST);
}

static void fail(const char *what, int x, int y, int w, int h, int px, int py)
{
    if (failures++ < 20)
        fprintf(stderr, "read_pixels: %s reading %dx%d at (%d, %d): pixel (%d, %d)\n", what, w, h, x, y, px, py);
}

/* One read as RGBA bytes and one as RGB floats, each checked whole. */
static void check_read(int x, int y, int w, int h)
{
    size_t n = (size_t)w * (size_t)h;
    unsigned char *b = malloc(n * 4 + GUARD);
    float *f = malloc(n * 3 * sizeof *f + GUARD);
    if (!b || !f) {
        fprintf(stderr, "read_pixels: out of memory\n");
        exit(1);
    }
    memset(b, 0xab, n * 4 + GUARD);
    memset(f, 0xab, n * 3 * sizeof *f + GUARD);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(x, y, w, h, GL_RGBA, GL_UNSIGNED_BYTE, b);
    glReadPixels(x, y, w, h, GL_RGB, GL_FLOAT, f);
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            unsigned char want[4];
            cell_colour(x + i, y + j, want);
            size_t at = (size_t)j * (size_t)w + (size_t)i;
            if (memcmp(b + at * 4, want, 4) != 0)
                fail("wrong RGBA bytes", x, y, w, h, x + i, y + j);
            for (int c = 0; c < 3; c++) {
                float d = f[at * 3 + (size_t)c] - want[c] / 255.0f;
                if (d > 0.5f / 255 || d < -0.5f / 255) {
                    fail("wrong RGB floats", x, y, w, h, x + i, y + j);
                    break;
                }
            }
        }
    const unsigned char *gb = b + n * 4, *gf = (const unsigned char *)(f + n * 3);
    for (int g = 0; g < GUARD; g++)
        if (gb[g] != 0xab || gf[g] != 0xab) {
            fail("bytes written past the buffer", x, y, w, h, -1, -1);
            break;
        }
    free(b);
    free(f);
}

static void check_reads(void)
{
    int mx = width / 2, my = height / 2; /* the 2x2 wall's tile edges */
    for (int y = 3; y < height; y += 97)
        for (int x = 5; x < width; x += 89)
            check_read(x, y, 1, 1);
    int xs[] = {0, mx - 1, mx, width - 1}, ys[] = {0, my - 1, my, height - 1};
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++)
            check_read(xs[i], ys[j], 1, 1);
    check_read(mx + 13, 13, 1, 1);             /* beside the first tile, in its rows */
    check_read(13, my + 13, 1, 1);             /* above it, in its columns */
    check_read(mx + 20, 4, 7, 5);              /* inside the second tile only */
    check_read(mx - 9, my - 7, 18, 14);        /* across all four */
    check_read(mx - 3, 10, 6, 3);              /* across the first two */
    check_read(width - 12, height - 9, 12, 9); /* the last tile's corner */
}

int main(int argc, char **argv)
{
    exapp app;
    if (!exapp_init(&app, "read_pixels", argc, argv, 320, 240))
        return app.exit_code;
    width = app.width;
    height = app.height;
    for (int f = 0; f < app.frames; f++) {
        draw_checker();
        check_reads();
        if (!exapp_swap(&app))
            break;
    }
    int code = exapp_finish(&app);
    if (failures) {
        fprintf(stderr, "read_pixels: %d reads wrong\n", failures);
        return 1;
    }
    return code;
}
