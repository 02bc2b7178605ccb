/* spus/render/pixels.c — the commands that write pixels outside the
 * vertex pipeline: Clear, CopyPixels and DrawPixels. They keep the record
 * of whether the stream ever wrote a stencil value (so a depth clear can
 * clear the stencil too, in one fill) and send DrawPixels and colour
 * clears to the fast paths (drawpixels.h).
 *
 * Owns: nothing beyond the instance's stencil_written flag.
 * Never: changes a pixel GL would not (the stencil is cleared only while
 * every stencil value is still 0), rewrites a clear compiled into a list. */
#include <stdlib.h>

#include "instance.h"
#include "tessera/dev/pixel.h"

/* A depth clear that keeps the stencil (no GL_STENCIL_BUFFER_BIT) makes
 * llvmpipe rewrite every packed 24/8 depth-stencil word through a mask,
 * about 1.6 times a clear of both (git show 56d9c59:bench/results/sortlast/README.md).
 * The stencil changes only through the stencil test, a stencil clear, or
 * stencil DrawPixels/CopyPixels (the commands tessera carries); while the
 * stream has done none of them with another value than 0, every stencil
 * value is 0 (or undefined, never yet written), so clearing it to 0 too
 * changes no pixel, and the clear is one fill. A clear compiled into a
 * display list is left as it is: the list may run after the stencil was
 * used. */
static void render_Clear(void *self, GLbitfield mask)
{
    render_spu *r = self;
    bool compiling = render_current_scissor(r)->list_mode != 0;
    if (mask & GL_STENCIL_BUFFER_BIT) {
        GLint value = 0;
        if (!compiling && !r->stencil_written)
            r->gl.GetIntegerv(GL_STENCIL_CLEAR_VALUE, &value);
        if (compiling || value != 0)
            r->stencil_written = true;
    } else if ((mask & GL_DEPTH_BUFFER_BIT) && !compiling && !r->stencil_written) {
        GLint value = -1;
        r->gl.GetIntegerv(GL_STENCIL_CLEAR_VALUE, &value);
        if (value == 0)
            mask |= GL_STENCIL_BUFFER_BIT;
    }
    if (mask == GL_COLOR_BUFFER_BIT && !compiling && render_fastdraw_clear(r->fastdraw, &r->gl, r->width, r->height))
        return;
    r->gl.Clear(mask);
}

static void render_CopyPixels(void *self, GLint x, GLint y, GLsizei width, GLsizei height, GLenum type)
{
    render_spu *r = self;
    if (type != GL_COLOR && type != GL_DEPTH)
        r->stencil_written = true;
    r->gl.CopyPixels(x, y, width, height, type);
}

/* Bytes GL_UNPACK_SWAP_BYTES swaps as one unit for `type` (1: none). */
static size_t swap_unit(GLenum type)
{
    switch (type) {
    case GL_UNSIGNED_SHORT_5_6_5:
    case GL_UNSIGNED_SHORT_5_6_5_REV:
    case GL_UNSIGNED_SHORT_4_4_4_4:
    case GL_UNSIGNED_SHORT_4_4_4_4_REV:
    case GL_UNSIGNED_SHORT_5_5_5_1:
    case GL_UNSIGNED_SHORT_1_5_5_5_REV: return 2;
    case GL_UNSIGNED_INT_8_8_8_8:
    case GL_UNSIGNED_INT_8_8_8_8_REV:
    case GL_UNSIGNED_INT_10_10_10_2:
    case GL_UNSIGNED_INT_2_10_10_10_REV:
    case GL_UNSIGNED_INT_24_8:
    case GL_UNSIGNED_INT_10F_11F_11F_REV:
    case GL_UNSIGNED_INT_5_9_9_9_REV:
    case GL_FLOAT_32_UNSIGNED_INT_24_8_REV: return 4;
    case GL_BITMAP: return 1;
    default: {
        size_t n = tsr_gl_type_size(type);
        return n ? n : 1;
    }
    }
}

/* Mesa (OSMesa 22.3, llvmpipe) draws a glDrawPixels image with
 * GL_UNPACK_SWAP_BYTES wrongly once the scissor clips it: it skips the
 * clipped-off part before swapping and reads pixels of the wrong place,
 * past the image's end when enough is clipped (a tile server died of
 * SIGSEGV in GL_RGB/GL_SHORT; piglit's draw-pixels on a wall). A tile's
 * scissor clips what the application never clipped, so on a tiled
 * server the bytes are swapped here and the image drawn unswapped.
 * Returns the image to draw (pixels, or a swapped copy in *scratch). */
static const void *swapped_here(render_spu *r, GLsizei width, GLsizei height, GLenum format, GLenum type,
                                const void *pixels, void **scratch)
{
    *scratch = NULL;
    size_t unit = swap_unit(type);
    if (!r->ntiles || !pixels || unit < 2 || width <= 0 || height <= 0 || render_current_scissor(r)->list_mode)
        return pixels;
    GLint swap = 0, buffer = 0;
    r->gl.GetIntegerv(GL_UNPACK_SWAP_BYTES, &swap);
    r->gl.GetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &buffer);
    if (!swap || buffer)
        return pixels;
    tsr_pixel_modes m = {0};
    GLint v;
    r->gl.GetIntegerv(GL_UNPACK_ROW_LENGTH, &v), m.row_length = v;
    r->gl.GetIntegerv(GL_UNPACK_SKIP_ROWS, &v), m.skip_rows = v;
    r->gl.GetIntegerv(GL_UNPACK_SKIP_PIXELS, &v), m.skip_pixels = v;
    r->gl.GetIntegerv(GL_UNPACK_ALIGNMENT, &v), m.alignment = v;
    tsr_pixel_layout lay;
    if (tsr_pixel_layout_of(&m, 2, width, height, 1, format, type, &lay) != 0 || !lay.extent)
        return pixels;
    unsigned char *copy = malloc(lay.extent);
    if (!copy)
        return pixels;
    /* rows and skips start at multiples of the unit (GL 2.1 3.6.4: a row
     * is padded only when its elements are smaller than the alignment) */
    const unsigned char *src = pixels;
    size_t whole = lay.extent - lay.extent % unit;
    for (size_t at = 0; at < whole; at += unit)
        for (size_t b = 0; b < unit; b++)
            copy[at + b] = src[at + unit - 1 - b];
    for (size_t at = whole; at < lay.extent; at++)
        copy[at] = src[at];
    r->gl.PixelStorei(GL_UNPACK_SWAP_BYTES, GL_FALSE);
    *scratch = copy;
    return copy;
}

static void render_DrawPixels(void *self, GLsizei width, GLsizei height, GLenum format, GLenum type, const void *pixels)
{
    render_spu *r = self;
    if (format == GL_STENCIL_INDEX || format == GL_DEPTH_STENCIL)
        r->stencil_written = true;
    void *scratch;
    const void *image = swapped_here(r, width, height, format, type, pixels, &scratch);
    render_fastdraw_draw(r->fastdraw, &r->gl, r->width, r->height, width, height, format, type, image);
    if (scratch) {
        r->gl.PixelStorei(GL_UNPACK_SWAP_BYTES, GL_TRUE);
        free(scratch);
    }
}

void render_pixels_install(render_spu *r, tsr_dispatch *table)
{
    tsr_set_Clear(table, render_Clear, r);
    tsr_set_CopyPixels(table, render_CopyPixels, r);
    tsr_set_DrawPixels(table, render_DrawPixels, r);
}
