/* tests/wire/pixel_osmesa_test.c — generated and wire code against real GL
 * (OSMesa), two tests:
 *  wire_pixel_extents_match_osmesa: for random pack pixel-store modes,
 *   formats and sizes, the bytes glReadPixels writes must be exactly the
 *   spans tsr_pixel_layout_of predicts, all below the predicted extent
 *   (pack and unpack share the layout code, so this also covers uploads);
 *  wire_glprocs_resolve_in_osmesa: every Khronos command of the spec
 *   resolves through OSMesaGetProcAddress and the generated trampolines
 *   reach it.
 * Links OSMesa directly and never libtessera_gl. */
#include <GL/osmesa.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/dev/pixel.h"
#include "tessera/glprocs_gen.h"

/* A failed check leaves the test function (later steps need what it made). */
#define HARNESS_ON_FAIL return 1
#include "harness.h"

static uint64_t next(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static tsr_proc get_proc(const char *name, void *ctx)
{
    (void)ctx;
    return (tsr_proc)OSMesaGetProcAddress(name);
}

static int glprocs_resolve(void)
{
    static tsr_gl_procs procs;
    static tsr_dispatch d;
    tsr_error err;
    tsr_error_clear(&err);
    CHECK(tsr_gl_procs_load(&procs, get_proc, NULL, &err) == TSR_OK, "%s", err.message);
    tsr_dispatch_fill_nop(&d);
    tsr_gl_procs_fill_dispatch(&procs, &d);
    tsr_call_ClearColor(&d, 1.0f, 0.0f, 0.0f, 1.0f);
    tsr_call_Clear(&d, GL_COLOR_BUFFER_BIT);
    GLubyte px[4] = {0, 0, 0, 0};
    tsr_call_PixelStorei(&d, GL_PACK_ALIGNMENT, 4);
    tsr_call_ReadPixels(&d, 3, 3, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, px);
    CHECK(px[0] == 255 && px[1] == 0 && px[3] == 255, "trampolines reach OSMesa (pixel %u %u %u %u)", px[0], px[1],
          px[2], px[3]);
    CHECK(tsr_call_GetError(&d) == GL_NO_ERROR, "no GL error");
    return 0;
}

static int pixel_extents(void);

int main(int argc, char **argv)
{
    static GLubyte fb[32 * 32 * 4];
    OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 16, 0, 0, NULL);
    CHECK(ctx && OSMesaMakeCurrent(ctx, fb, GL_UNSIGNED_BYTE, 32, 32), "OSMesa context");
    int rc = argc > 1 && !strcmp(argv[1], "glprocs") ? glprocs_resolve() : pixel_extents();
    OSMesaDestroyContext(ctx);
    return rc;
}

static int pixel_extents(void)
{
    glClearColor(0.2f, 0.4f, 0.6f, 0.8f);
    glClearDepth(0.5);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    static const GLenum pairs[][2] = {
        {GL_RGBA, GL_UNSIGNED_BYTE},
        {GL_RGB, GL_UNSIGNED_BYTE},
        {GL_LUMINANCE, GL_FLOAT},
        {GL_RGBA, GL_UNSIGNED_SHORT_4_4_4_4},
        {GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT},
        {GL_BGRA, GL_UNSIGNED_INT_8_8_8_8_REV},
        {GL_ALPHA, GL_UNSIGNED_BYTE},
        {GL_RGB, GL_SHORT},
    };
    static const int aligns[] = {1, 2, 4, 8};
    uint64_t rng = 7;
    int checked = 0;
    for (int iter = 0; iter < 400; iter++) {
        tsr_pixel_store ps;
        tsr_pixel_store_init(&ps);
        int w = 1 + (int)(next(&rng) % 9), h = 1 + (int)(next(&rng) % 9);
        const GLenum *pair = pairs[next(&rng) % (sizeof pairs / sizeof pairs[0])];
        const int set[][2] = {
            {GL_PACK_ALIGNMENT, aligns[next(&rng) % 4]},
            {GL_PACK_ROW_LENGTH, next(&rng) % 2 ? 0 : w + (int)(next(&rng) % 7)},
            {GL_PACK_SKIP_PIXELS, (int)(next(&rng) % 5)},
            {GL_PACK_SKIP_ROWS, (int)(next(&rng) % 4)},
        };
        for (size_t k = 0; k < 4; k++) {
            glPixelStorei((GLenum)set[k][0], set[k][1]);
            tsr_pixel_store_set(&ps, (GLenum)set[k][0], set[k][1]);
        }
        tsr_pixel_layout lay;
        CHECK(tsr_pixel_layout_of(&ps.pack, 2, w, h, 1, pair[0], pair[1], &lay) == 0, "layout");
        size_t n = (size_t)lay.extent + 256;
        uint8_t *a = malloc(n), *b = malloc(n), *want = calloc(1, n);
        memset(a, 0xCD, n);
        memset(b, 0x32, n);
        glReadPixels(1, 2, w, h, pair[0], pair[1], a);
        glReadPixels(1, 2, w, h, pair[0], pair[1], b);
        CHECK(glGetError() == GL_NO_ERROR, "ReadPixels 0x%x/0x%x", pair[0], pair[1]);
        /* Mark the predicted spans. */
        uint8_t *ones = malloc(n);
        memset(ones, 1, n);
        tsr_pixel_copy_spans(&lay, h, 1, want, ones);
        free(ones);
        for (size_t i = 0; i < n; i++) {
            int written = a[i] != 0xCD || b[i] != 0x32;
            CHECK(written == want[i],
                  "byte %zu %s (w %d h %d format 0x%x type 0x%x align %d row_length %d skip %d,%d extent %llu)", i,
                  written ? "written but not predicted" : "predicted but not written", w, h, pair[0], pair[1],
                  ps.pack.alignment, ps.pack.row_length, ps.pack.skip_pixels, ps.pack.skip_rows,
                  (unsigned long long)lay.extent);
        }
        CHECK(lay.extent == 0 || want[lay.extent - 1], "the extent ends at the last byte written");
        free(a);
        free(b);
        free(want);
        checked++;
    }
    fprintf(stderr, "%d ReadPixels layouts match OSMesa\n", checked);
    return 0;
}
