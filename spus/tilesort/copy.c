/* spus/tilesort/copy.c — copies of the window's pixels on a wall:
 * glCopyPixels and glCopyTexImage1D/2D, glCopyTexSubImage1D/2D/3D.
 *
 * Each server holds only its tiles of the window, so a copy whose source
 * rectangle lies on other servers' tiles would read pixels that server
 * never drew. Here the source rectangle is gathered from the servers as
 * glReadPixels is (frame.c), then given back as what GL defines the copy
 * to be: glCopyPixels draws the pixels at the current raster position as
 * glDrawPixels does (to every server, each drawing its tiles), and
 * glCopyTex(Sub)Image is the glTexImage/glTexSubImage of those pixels
 * through the tracker, so every server (and one that draws with the
 * texture later) gets the same image. A copy costs a gather: one round
 * trip to every server whose tiles meet the rectangle, and the pixels
 * back (docs/walls.md).
 *
 * The pixels are read in a form that loses nothing (colour as GL_FLOAT
 * RGBA, depth as GL_UNSIGNED_INT or GL_FLOAT, stencil as GL_UNSIGNED_INT,
 * both as GL_UNSIGNED_INT_24_8 or, for a float depth texture,
 * GL_FLOAT_32_UNSIGNED_INT_24_8_REV), with the pixel transfer modes set to
 * identity for the read: GL applies them once to a copy (GL 2.1 sections
 * 3.6.3 and 4.3.3), and the draw or the upload applies the program's own.
 * Around each step the pack or unpack modes are tight and no pixel buffer
 * is bound; everything changed is put back through the tracker, so a
 * server only ever gets the program's state in its diff.
 *
 * A call GL would refuse, or one this file cannot substitute exactly (a
 * texture level the tracker does not hold, an internal format it does not
 * know, an offset into a border, selection or feedback, inside
 * glBegin/glEnd), is sent unchanged to every server as before: GL's own
 * error is raised there (glGetError gathers it once, gets.c), and a valid
 * one copies what each server holds. So is a glCopyPixels while the
 * program's framebuffer object is bound: every server holds it whole
 * (fbo.c).
 *
 * Owns nothing. Never leaves the program's pixel store, pixel transfer or
 * pixel buffer bindings changed, and never sends a server a copy whose
 * source it does not hold. */
#include <stdlib.h>
#include <string.h>

#include "instance.h"

/* --- the state a copy sets around its steps --------------------------------- */

typedef struct copy_saved {
    tsr_pixel_modes modes;
    GLuint buffer;
} copy_saved;

/* The pixel store of one side (pack or unpack) as (pname, value, GL's
 * default) rows. */
static void store_rows(int pack, const tsr_pixel_modes *m, GLint rows[8][3])
{
    const GLint r[8][3] = {
        {pack ? GL_PACK_ROW_LENGTH : GL_UNPACK_ROW_LENGTH, m->row_length, 0},
        {pack ? GL_PACK_IMAGE_HEIGHT : GL_UNPACK_IMAGE_HEIGHT, m->image_height, 0},
        {pack ? GL_PACK_SKIP_PIXELS : GL_UNPACK_SKIP_PIXELS, m->skip_pixels, 0},
        {pack ? GL_PACK_SKIP_ROWS : GL_UNPACK_SKIP_ROWS, m->skip_rows, 0},
        {pack ? GL_PACK_SKIP_IMAGES : GL_UNPACK_SKIP_IMAGES, m->skip_images, 0},
        {pack ? GL_PACK_ALIGNMENT : GL_UNPACK_ALIGNMENT, m->alignment, 4},
        {pack ? GL_PACK_SWAP_BYTES : GL_UNPACK_SWAP_BYTES, m->swap_bytes, 0},
        {pack ? GL_PACK_LSB_FIRST : GL_UNPACK_LSB_FIRST, m->lsb_first, 0},
    };
    memcpy(rows, r, sizeof r);
}

/* Sets the pack (pack=1) or unpack modes to GL's defaults and unbinds
 * that side's pixel buffer, through the tilesort's own routes (tracker and
 * the geometry packer's mirrors); `saved` keeps what was there. */
static void tight_store(tilesort *t, int pack, copy_saved *saved)
{
    const tsr_state_values *v = tsr_state_values_of(t->ctx);
    saved->modes = pack ? v->pixel_store.pack : v->pixel_store.unpack;
    saved->buffer = pack ? v->pixel_pack_buffer : v->pixel_unpack_buffer;
    GLint rows[8][3];
    store_rows(pack, &saved->modes, rows);
    for (int i = 0; i < 8; i++)
        if (rows[i][1] != rows[i][2])
            tsr_call_PixelStorei(&t->normal, (GLenum)rows[i][0], rows[i][2]);
    if (saved->buffer)
        tsr_call_BindBuffer(&t->normal, pack ? GL_PIXEL_PACK_BUFFER : GL_PIXEL_UNPACK_BUFFER, 0);
}

static void restore_store(tilesort *t, int pack, const copy_saved *saved)
{
    GLint rows[8][3];
    store_rows(pack, &saved->modes, rows);
    for (int i = 0; i < 8; i++)
        if (rows[i][1] != rows[i][2])
            tsr_call_PixelStorei(&t->normal, (GLenum)rows[i][0], rows[i][1]);
    if (saved->buffer)
        tsr_call_BindBuffer(&t->normal, pack ? GL_PIXEL_PACK_BUFFER : GL_PIXEL_UNPACK_BUFFER, saved->buffer);
}

typedef struct copy_transfer {
    GLfloat scale[5], bias[5];
    GLint index_shift, index_offset;
    GLboolean map_color, map_stencil;
} copy_transfer;

static const GLenum scale_names[5] = {GL_RED_SCALE, GL_GREEN_SCALE, GL_BLUE_SCALE, GL_ALPHA_SCALE, GL_DEPTH_SCALE};
static const GLenum bias_names[5] = {GL_RED_BIAS, GL_GREEN_BIAS, GL_BLUE_BIAS, GL_ALPHA_BIAS, GL_DEPTH_BIAS};

/* Puts the pixel transfer modes to `to`, sending only what differs from
 * the tracker's (scales 1, biases 0, no shift, offset or map: identity). */
static void set_transfer(tilesort *t, const copy_transfer *to)
{
    const tsr_state_values *v = tsr_state_values_of(t->ctx);
    for (int i = 0; i < 5; i++) {
        if (v->transfer_scale[i] != to->scale[i])
            tsr_call_PixelTransferf(&t->normal, scale_names[i], to->scale[i]);
        if (v->transfer_bias[i] != to->bias[i])
            tsr_call_PixelTransferf(&t->normal, bias_names[i], to->bias[i]);
    }
    if (v->index_shift != to->index_shift)
        tsr_call_PixelTransferi(&t->normal, GL_INDEX_SHIFT, to->index_shift);
    if (v->index_offset != to->index_offset)
        tsr_call_PixelTransferi(&t->normal, GL_INDEX_OFFSET, to->index_offset);
    if (v->map_color != to->map_color)
        tsr_call_PixelTransferi(&t->normal, GL_MAP_COLOR, to->map_color);
    if (v->map_stencil != to->map_stencil)
        tsr_call_PixelTransferi(&t->normal, GL_MAP_STENCIL, to->map_stencil);
}

static copy_transfer transfer_now(const tilesort *t)
{
    const tsr_state_values *v = tsr_state_values_of(t->ctx);
    copy_transfer c;
    memcpy(c.scale, v->transfer_scale, sizeof c.scale);
    memcpy(c.bias, v->transfer_bias, sizeof c.bias);
    c.index_shift = v->index_shift;
    c.index_offset = v->index_offset;
    c.map_color = v->map_color;
    c.map_stencil = v->map_stencil;
    return c;
}

/* --- the gather ----------------------------------------------------------------- */

/* Bytes of one pixel read as `format`/`type` (the forms read_source uses). */
static size_t pixel_bytes(GLenum format, GLenum type)
{
    return format == GL_RGBA ? 4 * sizeof(GLfloat) : type == GL_FLOAT_32_UNSIGNED_INT_24_8_REV ? 8 : 4;
}

/* The window's rectangle (x, y, w, h), w and h > 0, read from the servers
 * that hold it with the pixel transfer at identity, tightly packed; NULL
 * when out of memory (reported). Pixels outside every tile and outside
 * the window are 0 (GL leaves them undefined). */
static void *read_source(tilesort *t, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type)
{
    size_t bytes = (size_t)w * (size_t)h * pixel_bytes(format, type);
    void *pixels = calloc(1, bytes);
    if (!pixels) {
        tsr_error e;
        tsr_error_set(&e, TSR_ENOMEM, "out of memory for a copy of %d x %d pixels", (int)w, (int)h);
        ts_report(t, &e);
        return NULL;
    }
    copy_transfer program = transfer_now(t), identity = {{1, 1, 1, 1, 1}, {0}, 0, 0, GL_FALSE, GL_FALSE};
    copy_saved pack;
    set_transfer(t, &identity);
    tight_store(t, 1, &pack);
    ts_ReadPixels(t, x, y, w, h, format, type, pixels);
    restore_store(t, 1, &pack);
    set_transfer(t, &program);
    return pixels;
}

/* The copy is not substituted: every server gets it unchanged, as the
 * generic route sent it before (its GL error, or its own tiles' copy). */
#define SEND_UNCHANGED(t, call)                   \
    do {                                          \
        ts_broadcast_next(t);                     \
        const tsr_dispatch *to = &(t)->geo_table; \
        call;                                     \
    } while (0)

/* A glCopyPixels of the window outside glBegin/glEnd. While a program
 * framebuffer object is bound for reading (fbo.c) the source is that FBO,
 * which every server holds whole: each server's own copy is exact (into
 * the FBO bound for drawing, or its own tiles of the window), and it goes
 * unchanged. (A texture copy from it is
 * still substituted: ts_ReadPixels then reads the first server's FBO, and
 * the tracker gets the image, which it could not know otherwise.) */
static int from_window(const tilesort *t) { return !t->in_begin && !t->app_read_fb; }

/* --- glCopyPixels ------------------------------------------------------------------ */

/* GL 2.1 section 4.3.3: CopyPixels reads the rectangle as ReadPixels
 * would, applies the pixel transfer once, and then draws it at the raster
 * position exactly as DrawPixels draws (zoom, fragment colour: the pixels'
 * for GL_COLOR, the raster colour for depth and stencil; texturing, fog
 * and every fragment operation; nothing when the raster position is
 * invalid, which each server knows for itself). So the gathered pixels
 * are read with the transfer at identity and drawn with glDrawPixels under
 * the program's transfer. */
void ts_CopyPixels(void *self, GLint x, GLint y, GLsizei w, GLsizei h, GLenum type)
{
    tilesort *t = self;
    GLenum format = type == GL_COLOR           ? GL_RGBA
                    : type == GL_DEPTH         ? GL_DEPTH_COMPONENT
                    : type == GL_STENCIL       ? GL_STENCIL_INDEX
                    : type == GL_DEPTH_STENCIL ? GL_DEPTH_STENCIL
                                               : GL_NONE;
    GLenum read_type = type == GL_COLOR ? GL_FLOAT : type == GL_DEPTH_STENCIL ? GL_UNSIGNED_INT_24_8 : GL_UNSIGNED_INT;
    /* selection and feedback draw no pixel (and feed back a copy token):
     * the one server running the pass copies (gets.c: ts_RenderMode) */
    if (format == GL_NONE || w <= 0 || h <= 0 || !from_window(t) || t->render_mode != GL_RENDER) {
        SEND_UNCHANGED(t, tsr_call_CopyPixels(to, x, y, w, h, type));
        return;
    }
    void *pixels = read_source(t, x, y, w, h, format, read_type);
    if (!pixels)
        return;
    copy_saved unpack;
    tight_store(t, 0, &unpack);
    tsr_call_DrawPixels(&t->normal, w, h, format, read_type, pixels);
    restore_store(t, 0, &unpack);
    free(pixels);
}

/* --- glCopyTexImage and glCopyTexSubImage ------------------------------------------- */

/* How the source of a copy into internal format `ifmt` is read: depth
 * for depth formats, depth and stencil for depth-stencil ones, RGBA as
 * floats for every colour format GL 2.1 and the offered extensions name
 * (GL_ARB_texture_float's among them); 0 for a format not known here
 * (GL refuses it, or it is copied unchanged). */
static int source_form(GLint ifmt, GLenum *format, GLenum *type)
{
    switch (ifmt) {
    case GL_DEPTH_COMPONENT:
    case GL_DEPTH_COMPONENT16:
    case GL_DEPTH_COMPONENT24:
    case GL_DEPTH_COMPONENT32:
        *format = GL_DEPTH_COMPONENT;
        *type = GL_UNSIGNED_INT;
        return 1;
    case GL_DEPTH_COMPONENT32F:
        *format = GL_DEPTH_COMPONENT;
        *type = GL_FLOAT;
        return 1;
    case GL_DEPTH_STENCIL:
    case GL_DEPTH24_STENCIL8:
        *format = GL_DEPTH_STENCIL;
        *type = GL_UNSIGNED_INT_24_8;
        return 1;
    case GL_DEPTH32F_STENCIL8:
        *format = GL_DEPTH_STENCIL;
        *type = GL_FLOAT_32_UNSIGNED_INT_24_8_REV;
        return 1;
    case GL_ALPHA:
    case GL_ALPHA4:
    case GL_ALPHA8:
    case GL_ALPHA12:
    case GL_ALPHA16:
    case GL_LUMINANCE:
    case GL_LUMINANCE4:
    case GL_LUMINANCE8:
    case GL_LUMINANCE12:
    case GL_LUMINANCE16:
    case GL_LUMINANCE_ALPHA:
    case GL_LUMINANCE4_ALPHA4:
    case GL_LUMINANCE6_ALPHA2:
    case GL_LUMINANCE8_ALPHA8:
    case GL_LUMINANCE12_ALPHA4:
    case GL_LUMINANCE12_ALPHA12:
    case GL_LUMINANCE16_ALPHA16:
    case GL_INTENSITY:
    case GL_INTENSITY4:
    case GL_INTENSITY8:
    case GL_INTENSITY12:
    case GL_INTENSITY16:
    case GL_RGB:
    case GL_R3_G3_B2:
    case GL_RGB4:
    case GL_RGB5:
    case GL_RGB8:
    case GL_RGB10:
    case GL_RGB12:
    case GL_RGB16:
    case GL_RGBA:
    case GL_RGBA2:
    case GL_RGBA4:
    case GL_RGB5_A1:
    case GL_RGBA8:
    case GL_RGB10_A2:
    case GL_RGBA12:
    case GL_RGBA16:
    case GL_SRGB:
    case GL_SRGB8:
    case GL_SRGB_ALPHA:
    case GL_SRGB8_ALPHA8:
    case GL_SLUMINANCE:
    case GL_SLUMINANCE8:
    case GL_SLUMINANCE_ALPHA:
    case GL_SLUMINANCE8_ALPHA8:
    case GL_COMPRESSED_ALPHA:
    case GL_COMPRESSED_LUMINANCE:
    case GL_COMPRESSED_LUMINANCE_ALPHA:
    case GL_COMPRESSED_INTENSITY:
    case GL_COMPRESSED_RGB:
    case GL_COMPRESSED_RGBA:
    case GL_COMPRESSED_SRGB:
    case GL_COMPRESSED_SRGB_ALPHA:
    case GL_COMPRESSED_SLUMINANCE:
    case GL_COMPRESSED_SLUMINANCE_ALPHA:
    case GL_RGBA32F_ARB:
    case GL_RGB32F_ARB:
    case GL_ALPHA32F_ARB:
    case GL_INTENSITY32F_ARB:
    case GL_LUMINANCE32F_ARB:
    case GL_LUMINANCE_ALPHA32F_ARB:
    case GL_RGBA16F_ARB:
    case GL_RGB16F_ARB:
    case GL_ALPHA16F_ARB:
    case GL_INTENSITY16F_ARB:
    case GL_LUMINANCE16F_ARB:
    case GL_LUMINANCE_ALPHA16F_ARB:
    /* what Mesa makes of the generic compressed formats, which a
     * program may name too */
    case GL_COMPRESSED_RGB_S3TC_DXT1_EXT:
    case GL_COMPRESSED_RGBA_S3TC_DXT1_EXT:
    case GL_COMPRESSED_RGBA_S3TC_DXT3_EXT:
    case GL_COMPRESSED_RGBA_S3TC_DXT5_EXT:
    case GL_COMPRESSED_SRGB_S3TC_DXT1_EXT:
    case GL_COMPRESSED_SRGB_ALPHA_S3TC_DXT1_EXT:
    case GL_COMPRESSED_SRGB_ALPHA_S3TC_DXT3_EXT:
    case GL_COMPRESSED_SRGB_ALPHA_S3TC_DXT5_EXT:
    case GL_COMPRESSED_LUMINANCE_LATC1_EXT:
    case GL_COMPRESSED_SIGNED_LUMINANCE_LATC1_EXT:
    case GL_COMPRESSED_LUMINANCE_ALPHA_LATC2_EXT:
    case GL_COMPRESSED_SIGNED_LUMINANCE_ALPHA_LATC2_EXT:
        *format = GL_RGBA;
        *type = GL_FLOAT;
        return 1;
    default: return 0;
    }
}

/* The targets glCopyTexImage/glCopyTexSubImage of `dims` dimensions take
 * (GL 2.1 section 3.8.2; the rectangle target of GL_ARB_texture_rectangle). */
static int copy_target(int dims, GLenum target)
{
    if (dims == 1)
        return target == GL_TEXTURE_1D;
    if (dims == 3)
        return target == GL_TEXTURE_3D;
    return target == GL_TEXTURE_2D || target == GL_TEXTURE_RECTANGLE_ARB ||
           (target >= GL_TEXTURE_CUBE_MAP_POSITIVE_X && target <= GL_TEXTURE_CUBE_MAP_NEGATIVE_Z);
}

/* The image (x, y, w, h) of the window for an upload, or NULL (then the
 * copy goes unchanged; reported when out of memory). An empty one needs
 * no read: `*empty` is set and NULL returned. */
static void *texture_source(tilesort *t, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type, int *empty)
{
    *empty = w == 0 || h == 0;
    if (*empty)
        return NULL;
    return read_source(t, x, y, w, h, format, type);
}

/* The largest texture of a copy's target (1D and 2D, cube map faces,
 * rectangle), asked of the first server once (it cannot change). */
static GLint max_size(tilesort *t, int cube, int rect)
{
    int k = cube ? 1 : rect ? 2 : 0;
    if (t->copy_max_size[k] <= 0) {
        static const GLenum pnames[3] = {GL_MAX_TEXTURE_SIZE, GL_MAX_CUBE_MAP_TEXTURE_SIZE,
                                         GL_MAX_RECTANGLE_TEXTURE_SIZE_ARB};
        ts_GetIntegerv(t, pnames[k], &t->copy_max_size[k]);
    }
    return t->copy_max_size[k];
}

/* GL 2.1 section 3.8.2: CopyTexImage takes the image exactly as CopyPixels
 * would (pixel transfer included) and defines it as TexImage would. A
 * level or size beyond the renderer's limit goes unchanged to the servers,
 * which raise GL's error: the source is not read. */
static int copy_image_ok(tilesort *t, int dims, GLenum target, GLint level, GLint ifmt, GLsizei w, GLsizei h,
                         GLint border, GLenum *format, GLenum *type)
{
    int cube = target >= GL_TEXTURE_CUBE_MAP_POSITIVE_X && target <= GL_TEXTURE_CUBE_MAP_NEGATIVE_Z;
    int rect = target == GL_TEXTURE_RECTANGLE_ARB;
    if (!copy_target(dims, target) || !source_form(ifmt, format, type) || level < 0 || w < 0 || h < 0)
        return 0;
    if (border != 0 && (border != 1 || rect))
        return 0;
    GLint max = max_size(t, cube, rect), levels = 0;
    while ((max >> levels) > 1)
        levels++;
    if (max <= 0 || level > levels || (rect && level != 0))
        return 0;
    GLint most = (max >> level) + 2 * border;
    if (w > most || w < 2 * border || (dims == 2 && (h > most || h < 2 * border)))
        return 0;
    return !cube || w == h; /* cube map faces are square */
}

void ts_CopyTexImage1D(void *self, GLenum target, GLint level, GLenum ifmt, GLint x, GLint y, GLsizei w, GLint border)
{
    tilesort *t = self;
    GLenum format, type;
    int empty;
    if (t->in_begin || !copy_image_ok(t, 1, target, level, (GLint)ifmt, w, 1, border, &format, &type)) {
        SEND_UNCHANGED(t, tsr_call_CopyTexImage1D(to, target, level, ifmt, x, y, w, border));
        return;
    }
    void *pixels = texture_source(t, x, y, w, 1, format, type, &empty);
    if (!pixels && !empty)
        return;
    copy_saved unpack;
    tight_store(t, 0, &unpack);
    tsr_call_TexImage1D(&t->normal, target, level, (GLint)ifmt, w, border, format, type, pixels);
    restore_store(t, 0, &unpack);
    free(pixels);
}

void ts_CopyTexImage2D(void *self, GLenum target, GLint level, GLenum ifmt, GLint x, GLint y, GLsizei w, GLsizei h,
                       GLint border)
{
    tilesort *t = self;
    GLenum format, type;
    int empty;
    if (t->in_begin || !copy_image_ok(t, 2, target, level, (GLint)ifmt, w, h, border, &format, &type)) {
        SEND_UNCHANGED(t, tsr_call_CopyTexImage2D(to, target, level, ifmt, x, y, w, h, border));
        return;
    }
    void *pixels = texture_source(t, x, y, w, h, format, type, &empty);
    if (!pixels && !empty)
        return;
    copy_saved unpack;
    tight_store(t, 0, &unpack);
    tsr_call_TexImage2D(&t->normal, target, level, (GLint)ifmt, w, h, border, format, type, pixels);
    restore_store(t, 0, &unpack);
    free(pixels);
}

/* CopyTexSubImage: the level must be one the tracker holds (its
 * glTexSubImage changes only those), inside it and off its border (GL
 * takes an offset into the border; the tracker does not), of an internal
 * format known here (as the program gave it). Else it goes unchanged. */
static int copy_sub_ok(tilesort *t, int dims, GLenum target, GLint level, GLint xo, GLint yo, GLint zo, GLsizei w,
                       GLsizei h, GLenum *format, GLenum *type)
{
    if (!copy_target(dims, target) || level < 0 || w <= 0 || h <= 0)
        return 0;
    GLint iw, ih, id, border, ifmt = 0;
    if (!tsr_state_get_tex_level_parameteriv(t->ctx, target, level, GL_TEXTURE_WIDTH, &iw) ||
        !tsr_state_get_tex_level_parameteriv(t->ctx, target, level, GL_TEXTURE_HEIGHT, &ih) ||
        !tsr_state_get_tex_level_parameteriv(t->ctx, target, level, GL_TEXTURE_DEPTH, &id) ||
        !tsr_state_get_tex_level_parameteriv(t->ctx, target, level, GL_TEXTURE_BORDER, &border))
        return 0;
    if (xo < 0 || yo < 0 || zo < 0 || xo + w > iw - border || yo + h > ih - (dims >= 2 ? border : 0) ||
        zo + 1 > id - (dims == 3 ? border : 0))
        return 0;
    if (!tsr_state_tex_level_requested_format(t->ctx, target, level, &ifmt))
        return 0;
    /* glTexImage's 1 to 4 (glCopyTexImage takes none: GL_INVALID_ENUM) */
    if (ifmt >= 1 && ifmt <= 4)
        ifmt = GL_RGBA;
    return source_form(ifmt, format, type);
}

void ts_CopyTexSubImage1D(void *self, GLenum target, GLint level, GLint xo, GLint x, GLint y, GLsizei w)
{
    tilesort *t = self;
    GLenum format, type;
    if (t->in_begin || !copy_sub_ok(t, 1, target, level, xo, 0, 0, w, 1, &format, &type)) {
        SEND_UNCHANGED(t, tsr_call_CopyTexSubImage1D(to, target, level, xo, x, y, w));
        return;
    }
    void *pixels = read_source(t, x, y, w, 1, format, type);
    if (!pixels)
        return;
    copy_saved unpack;
    tight_store(t, 0, &unpack);
    tsr_call_TexSubImage1D(&t->normal, target, level, xo, w, format, type, pixels);
    restore_store(t, 0, &unpack);
    free(pixels);
}

void ts_CopyTexSubImage2D(void *self, GLenum target, GLint level, GLint xo, GLint yo, GLint x, GLint y, GLsizei w,
                          GLsizei h)
{
    tilesort *t = self;
    GLenum format, type;
    if (t->in_begin || !copy_sub_ok(t, 2, target, level, xo, yo, 0, w, h, &format, &type)) {
        SEND_UNCHANGED(t, tsr_call_CopyTexSubImage2D(to, target, level, xo, yo, x, y, w, h));
        return;
    }
    void *pixels = read_source(t, x, y, w, h, format, type);
    if (!pixels)
        return;
    copy_saved unpack;
    tight_store(t, 0, &unpack);
    tsr_call_TexSubImage2D(&t->normal, target, level, xo, yo, w, h, format, type, pixels);
    restore_store(t, 0, &unpack);
    free(pixels);
}

void ts_CopyTexSubImage3D(void *self, GLenum target, GLint level, GLint xo, GLint yo, GLint zo, GLint x, GLint y,
                          GLsizei w, GLsizei h)
{
    tilesort *t = self;
    GLenum format, type;
    if (t->in_begin || !copy_sub_ok(t, 3, target, level, xo, yo, zo, w, h, &format, &type)) {
        SEND_UNCHANGED(t, tsr_call_CopyTexSubImage3D(to, target, level, xo, yo, zo, x, y, w, h));
        return;
    }
    void *pixels = read_source(t, x, y, w, h, format, type);
    if (!pixels)
        return;
    copy_saved unpack;
    tight_store(t, 0, &unpack);
    tsr_call_TexSubImage3D(&t->normal, target, level, xo, yo, zo, w, h, 1, format, type, pixels);
    restore_store(t, 0, &unpack);
    free(pixels);
}

/* --- for blit.c ------------------------------------------------------------------ */

void *ts_copy_gather(tilesort *t, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type)
{
    return read_source(t, x, y, w, h, format, type);
}

/* A texture image of w x h texels of internal format `ifmt` in the bound
 * 2D texture through the tracker, undefined but for the sub-image at
 * (x, y) of pixels (sw x sh) gathered as format/type: unpacked tightly
 * with the pixel transfer at identity (the pixels are the window's as they
 * are; a blit applies no transfer), the program's modes put back after. */
void ts_copy_upload_2d(tilesort *t, GLenum ifmt, GLsizei w, GLsizei h, GLint x, GLint y, GLsizei sw, GLsizei sh,
                       GLenum format, GLenum type, const void *pixels)
{
    copy_transfer program = transfer_now(t), identity = {{1, 1, 1, 1, 1}, {0}, 0, 0, GL_FALSE, GL_FALSE};
    copy_saved unpack;
    set_transfer(t, &identity);
    tight_store(t, 0, &unpack);
    tsr_call_TexImage2D(&t->normal, GL_TEXTURE_2D, 0, (GLint)ifmt, w, h, 0, format, type, NULL);
    tsr_call_TexSubImage2D(&t->normal, GL_TEXTURE_2D, 0, x, y, sw, sh, format, type, pixels);
    restore_store(t, 0, &unpack);
    set_transfer(t, &program);
}
