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
#include <string.h>

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
    /* (the fast paths know the window's size, not a program FBO's: appfbo.c) */
    if (mask == GL_COLOR_BUFFER_BIT && !compiling && !render_app_fb_bound(r) &&
        render_fastdraw_clear(r->fastdraw, &r->gl, r->width, r->height))
        return;
    r->gl.Clear(mask);
}

static void render_CopyPixels(void *self, GLint x, GLint y, GLsizei width, GLsizei height, GLenum type)
{
    render_spu *r = self;
    if (type != GL_COLOR && type != GL_DEPTH)
        r->stencil_written = true;
    bool began = render_ms_read_begin(r); /* a multisample window is read resolved */
    r->gl.CopyPixels(x, y, width, height, type);
    render_ms_read_end(r, began);
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

/* A colour-index image cut to the scissor box, tight (no skips, rows of
 * one byte alignment), and where to draw it from. */
typedef struct clipped_index_image {
    void *pixels; /* NULL: draw the image as it is */
    GLsizei width, height;
    GLenum type;    /* of the copy */
    GLint dx, dy;   /* from the raster position to its first pixel */
    GLint saved[4]; /* the program's ROW_LENGTH, SKIP_ROWS, SKIP_PIXELS, ALIGNMENT */
} clipped_index_image;

static const GLenum unpack_modes[4] = {GL_UNPACK_ROW_LENGTH, GL_UNPACK_SKIP_ROWS, GL_UNPACK_SKIP_PIXELS,
                                       GL_UNPACK_ALIGNMENT};

/* Copies the w x h part at (dx, dy) of a colour-index image laid out as
 * `lay` under `m` into a tight image; a GL_BITMAP's bits become indices
 * 0 and 1 of one byte each (GL takes each bit for such an index, GL 2.1
 * section 3.6.4), so the copy is always GL_UNSIGNED_BYTE or the image's
 * own index type. Bitmap rows are read as GL lays them out (padded to a
 * byte and the alignment); Mesa 22.3 reads a colour-index bitmap whose
 * width is not a whole number of bytes as rows of exactly `width` bits,
 * so only such an image, cut by a tile, differs from Mesa's drawing. */
static void *copy_index_part(const unsigned char *src, const tsr_pixel_modes *m, const tsr_pixel_layout *lay,
                             GLenum type, GLsizei dx, GLsizei dy, GLsizei w, GLsizei h)
{
    size_t row_out = type == GL_BITMAP ? (size_t)w : (size_t)w * lay->group_bytes;
    unsigned char *out = malloc((size_t)h * row_out);
    if (!out)
        return NULL;
    for (GLsizei y = 0; y < h; y++) {
        const unsigned char *row = src + (uint64_t)(m->skip_rows + dy + y) * lay->row_bytes;
        unsigned char *dst = out + (size_t)y * row_out;
        if (type != GL_BITMAP) {
            memcpy(dst, row + (uint64_t)(m->skip_pixels + dx) * lay->group_bytes, row_out);
            continue;
        }
        /* bit i of a row is pixel i, in the order GL_UNPACK_LSB_FIRST says */
        for (GLsizei x = 0; x < w; x++) {
            size_t at = (size_t)m->skip_pixels + (size_t)dx + (size_t)x;
            dst[x] = (unsigned char)(row[at / 8] >> (m->lsb_first ? at % 8 : 7 - at % 8) & 1);
        }
    }
    return out;
}

/* f rounded half away from zero, as lroundf does (and Mesa with it for
 * the raster position), without libm: a float is exact as a double, and
 * so is its fraction. */
static long round_half_away(float f)
{
    double d = f;
    long whole = (long)d;
    double fraction = d - (double)whole;
    return fraction >= 0.5 ? whole + 1 : fraction <= -0.5 ? whole - 1 : whole;
}

/* Mesa (OSMesa 22.3, llvmpipe) reads past the end of its own converted
 * image when it draws a GL_COLOR_INDEX image (GL_BITMAP or an index type)
 * of which any pixel is skipped: clipped by the scissor box or the window,
 * or skipped by GL_UNPACK_SKIP_PIXELS/ROWS (a standalone OSMesa program
 * under AddressSanitizer: heap-buffer-overflow, 40 to 88 bytes past a
 * block of Mesa's, in every clipped case tried; unclipped images of the
 * same sizes read nothing past it). A program that never clips its image
 * gets that on a wall, since a tile's scissor clips what the window did
 * not (a tile server of piglit's gl-1.0-drawpixels-color-index), so on a
 * tiled server the part inside the scissor box is copied into a tight
 * image and drawn from the raster position moved onto it: Mesa then clips
 * and skips nothing, and the pixels are the ones GL would draw. Only where
 * GL's clipping is that simple: pixel zoom 1, render mode GL_RENDER, a
 * valid raster position, the program's pixels in memory. */
static bool index_image_clipped_here(render_spu *r, GLsizei width, GLsizei height, GLenum format, GLenum type,
                                     const void *pixels, clipped_index_image *c)
{
    memset(c, 0, sizeof *c);
    if (!r->ntiles || format != GL_COLOR_INDEX || !pixels || width <= 0 || height <= 0 ||
        render_current_scissor(r)->list_mode || r->gl.IsEnabled(GL_SCISSOR_TEST) != GL_TRUE)
        return false;
    GLint v = 0, box[4] = {0, 0, 0, 0};
    GLfloat zoom[2] = {0, 0}, raster[4] = {0, 0, 0, 0};
    r->gl.GetIntegerv(GL_RENDER_MODE, &v);
    if (v != GL_RENDER)
        return false;
    r->gl.GetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &v);
    if (v)
        return false;
    r->gl.GetIntegerv(GL_CURRENT_RASTER_POSITION_VALID, &v);
    r->gl.GetFloatv(GL_ZOOM_X, &zoom[0]);
    r->gl.GetFloatv(GL_ZOOM_Y, &zoom[1]);
    if (!v || zoom[0] != 1.0f || zoom[1] != 1.0f)
        return false;
    r->gl.GetFloatv(GL_CURRENT_RASTER_POSITION, raster);
    r->gl.GetIntegerv(GL_SCISSOR_BOX, box);
    /* where GL puts the image's first pixel: the raster position rounded
     * half away from zero, as Mesa does */
    long x0 = round_half_away(raster[0]), y0 = round_half_away(raster[1]);
    long cx0 = x0 > box[0] ? x0 : box[0], cy0 = y0 > box[1] ? y0 : box[1];
    long cx1 = x0 + width < (long)box[0] + box[2] ? x0 + width : (long)box[0] + box[2];
    long cy1 = y0 + height < (long)box[1] + box[3] ? y0 + height : (long)box[1] + box[3];
    if (cx0 == x0 && cy0 == y0 && cx1 == x0 + width && cy1 == y0 + height)
        return false; /* inside the box: nothing is clipped */
    for (int i = 0; i < 4; i++)
        r->gl.GetIntegerv(unpack_modes[i], &c->saved[i]);
    GLint lsb = 0;
    r->gl.GetIntegerv(GL_UNPACK_LSB_FIRST, &lsb);
    tsr_pixel_modes m = {.row_length = c->saved[0],
                         .skip_rows = c->saved[1],
                         .skip_pixels = c->saved[2],
                         .alignment = c->saved[3],
                         .lsb_first = lsb != 0};
    tsr_pixel_layout lay;
    if (tsr_pixel_layout_of(&m, 2, width, height, 1, format, type, &lay) != 0 || !lay.extent)
        return false;
    if (cx1 > cx0 && cy1 > cy0) {
        c->width = (GLsizei)(cx1 - cx0);
        c->height = (GLsizei)(cy1 - cy0);
        c->dx = (GLint)(cx0 - x0);
        c->dy = (GLint)(cy0 - y0);
        c->pixels = copy_index_part(pixels, &m, &lay, type, c->dx, c->dy, c->width, c->height);
        c->type = type == GL_BITMAP ? GL_UNSIGNED_BYTE : type;
        if (!c->pixels)
            return false;
    } else {
        /* nothing inside: a 0 x 0 image keeps GL's checks of the call */
        c->pixels = malloc(1);
        c->type = type;
        if (!c->pixels)
            return false;
    }
    r->gl.PixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    r->gl.PixelStorei(GL_UNPACK_SKIP_ROWS, 0);
    r->gl.PixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    r->gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    /* a bitmap of no pixels moves the raster position and draws nothing;
     * the moves are whole pixels, so the position comes back exactly */
    r->gl.Bitmap(0, 0, 0, 0, (GLfloat)c->dx, (GLfloat)c->dy, NULL);
    return true;
}

static void index_image_clip_done(render_spu *r, clipped_index_image *c)
{
    r->gl.Bitmap(0, 0, 0, 0, (GLfloat)-c->dx, (GLfloat)-c->dy, NULL);
    for (int i = 0; i < 4; i++)
        r->gl.PixelStorei(unpack_modes[i], c->saved[i]);
    free(c->pixels);
}

static void render_DrawPixels(void *self, GLsizei width, GLsizei height, GLenum format, GLenum type, const void *pixels)
{
    render_spu *r = self;
    if (format == GL_STENCIL_INDEX || format == GL_DEPTH_STENCIL)
        r->stencil_written = true;
    void *scratch;
    const void *image = swapped_here(r, width, height, format, type, pixels, &scratch);
    clipped_index_image part;
    if (render_app_fb_bound(r))
        r->gl.DrawPixels(width, height, format, type, image);
    else if (index_image_clipped_here(r, width, height, format, type, image, &part)) {
        render_fastdraw_draw(r->fastdraw, &r->gl, r->width, r->height, part.width, part.height, format, part.type,
                             part.pixels);
        index_image_clip_done(r, &part);
    } else
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
