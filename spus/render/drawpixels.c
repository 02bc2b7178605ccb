/* spus/render/drawpixels.c — render's fast glDrawPixels (drawpixels.h).
 *
 * The identity with glDrawPixels (GL 2.1, 3.6.4-3.6.5 and chapter 4):
 * with format RGBA/BGRA of unsigned bytes, no pixel transfer (scale 1,
 * bias 0, no colour map, no imaging-subset stage), zoom 1 and an integer
 * valid raster position, pixel (i, j) becomes a fragment at (x+i, y+j)
 * carrying exactly the bytes given. What then could change it is each
 * per-fragment stage: texturing (the fragments take the raster texture
 * coordinates), colour sum (and lighting, which forces it), fog, a
 * fragment program or shader, alpha/stencil/depth tests, blending, logic
 * op, the colour mask, sRGB writes, multisampling. With all of them off
 * what is left is the pixel ownership (the window) and the scissor; both
 * are applied here by clipping the rectangle, and the blit then writes
 * the same bytes to the same draw buffers. Dithering (on by default) does
 * not move a value the 8-bit buffer represents exactly, which every value
 * here is; the tests compare with it on.
 *
 * The blit is given flipped in y from rows uploaded bottom-up reversed:
 * llvmpipe's window buffers are stored top-down, so that pair is a plain
 * copy (a blit with the scissor test on is not: the scissor is clipped
 * here and the test switched off around the blit). */
#include <stdlib.h>
#include <string.h>

#include "tessera/log.h"

#include "drawpixels.h"

#ifndef GL_READ_FRAMEBUFFER
#define GL_READ_FRAMEBUFFER 0x8CA8
#define GL_DRAW_FRAMEBUFFER 0x8CA9
#define GL_READ_FRAMEBUFFER_BINDING 0x8CAA
#endif
#ifndef GL_COLOR_ATTACHMENT0
#define GL_COLOR_ATTACHMENT0 0x8CE0
#define GL_FRAMEBUFFER_COMPLETE 0x8CD5
#endif
#ifndef GL_FRAGMENT_PROGRAM_ARB
#define GL_FRAGMENT_PROGRAM_ARB 0x8804
#endif
#ifndef GL_FRAGMENT_SHADER_ATI
#define GL_FRAGMENT_SHADER_ATI 0x8920
#endif
#ifndef GL_FRAMEBUFFER_SRGB
#define GL_FRAMEBUFFER_SRGB 0x8DB9
#endif
#ifndef GL_DEPTH_BOUNDS_TEST_EXT
#define GL_DEPTH_BOUNDS_TEST_EXT 0x8890
#endif
#ifndef GL_TEXTURE_RECTANGLE_ARB
#define GL_TEXTURE_RECTANGLE_ARB 0x84F5
#endif
#ifndef GL_RASTERIZER_DISCARD
#define GL_RASTERIZER_DISCARD 0x8C89
#endif

#define FASTDRAW_MAX_UNITS 32
#define FILL_ROWS 32 /* rows of a clear's fill texture */
#define FASTDRAW_MAX_DRAW_BUFFERS 16
#define FASTDRAW_GEN_TRIES 8 /* names refused for being a list's, at most, before the texture is per call again */

typedef struct render_fastdraw_tex {
    GLuint name; /* 0: none yet */
    GLsizei width, height;
} render_fastdraw_tex;

struct render_fastdraw {
    bool enabled, probed, usable;
    /* What the context knows (probed at the first call, current then). */
    bool imaging, fragment_program, ati_fragment_shader, srgb, depth_bounds, rectangle, discard;
    GLint units, draw_buffers, max_texture;
    void(GLAPIENTRY *GenFramebuffers)(GLsizei n, GLuint *ids);
    void(GLAPIENTRY *DeleteFramebuffers)(GLsizei n, const GLuint *ids);
    void(GLAPIENTRY *BindFramebuffer)(GLenum target, GLuint id);
    void(GLAPIENTRY *FramebufferTexture2D)(GLenum target, GLenum attachment, GLenum textarget, GLuint tex, GLint level);
    GLenum(GLAPIENTRY *CheckFramebufferStatus)(GLenum target);
    void(GLAPIENTRY *BlitFramebuffer)(GLint sx0, GLint sy0, GLint sx1, GLint sy1, GLint dx0, GLint dy0, GLint dx1,
                                      GLint dy1, GLbitfield mask, GLenum filter);
    tsr_proc (*lookup)(const char *name, void *ctx);
    void *lookup_ctx;
    unsigned char *rows; /* the clipped rectangle, rows reversed */
    size_t rows_size;
    unsigned char *fill; /* fill_pixels pixels of the colour fill_rgba */
    size_t fill_pixels;
    unsigned char fill_rgba[4];
    /* The textures the rows and the fill are uploaded into, kept from call
     * to call: llvmpipe zeroes a texture's storage when it is created, a
     * cost as large as the upload itself for a full window. They grow to
     * the largest rectangle drawn. The fill texture holds fill_rgba over
     * fill_w x fill_h once uploaded. */
    render_fastdraw_tex draw_tex, fill_tex;
    GLsizei fill_w, fill_h;
    unsigned char fill_tex_rgba[4];
    /* Names the client bound while compiling a list: a CallList may bind
     * them at any time later, so a texture of ours never takes one. */
    GLuint *list_names;
    size_t nlist_names, list_names_cap;
    bool per_call; /* no memory to record them: textures live for one call again */
    uint64_t fast, total, clears_fast, clears;
};

render_fastdraw *render_fastdraw_create(tsr_proc (*lookup)(const char *name, void *ctx), void *ctx, bool enabled)
{
    render_fastdraw *f = calloc(1, sizeof *f);
    if (!f)
        return NULL;
    f->enabled = enabled;
    f->lookup = lookup;
    f->lookup_ctx = ctx;
    return f;
}

void render_fastdraw_destroy(render_fastdraw *f, const char *instance_name)
{
    if (!f)
        return;
    if (f->total)
        tsr_log(TSR_LOG_INFO, "%s: DrawPixels: %llu of %llu calls took the texture-blit path", instance_name,
                (unsigned long long)f->fast, (unsigned long long)f->total);
    if (f->clears)
        tsr_log(TSR_LOG_INFO, "%s: scissored colour Clear: %llu of %llu calls took the texture-blit path",
                instance_name, (unsigned long long)f->clears_fast, (unsigned long long)f->clears);
    free(f->rows);
    free(f->fill);
    free(f->list_names);
    free(f);
}

static void forget_tex(render_fastdraw_tex *t) { memset(t, 0, sizeof *t); }

void render_fastdraw_release(render_fastdraw *f, const tsr_gl_procs *gl)
{
    if (!f)
        return;
    GLuint names[2];
    GLsizei n = 0;
    if (f->draw_tex.name)
        names[n++] = f->draw_tex.name;
    if (f->fill_tex.name)
        names[n++] = f->fill_tex.name;
    if (n)
        gl->DeleteTextures(n, names);
    forget_tex(&f->draw_tex);
    forget_tex(&f->fill_tex);
    f->fill_w = f->fill_h = 0;
}

static bool in_list_names(const render_fastdraw *f, GLuint name)
{
    for (size_t i = 0; i < f->nlist_names; i++)
        if (f->list_names[i] == name)
            return true;
    return false;
}

bool render_fastdraw_owns(const render_fastdraw *f, GLuint name)
{
    return f && name && (name == f->draw_tex.name || name == f->fill_tex.name);
}

void render_fastdraw_client_name(render_fastdraw *f, const tsr_gl_procs *gl, GLuint name, bool compiling)
{
    if (!f || !name)
        return;
    if (compiling && !in_list_names(f, name)) {
        if (f->nlist_names == f->list_names_cap) {
            size_t cap = f->list_names_cap ? 2 * f->list_names_cap : 16;
            GLuint *more = realloc(f->list_names, cap * sizeof *more);
            if (more) {
                f->list_names = more;
                f->list_names_cap = cap;
            }
        }
        if (f->nlist_names < f->list_names_cap)
            f->list_names[f->nlist_names++] = name;
        else
            f->per_call = true; /* a name not recorded could be ours later */
    }
    /* The client takes the name (it may bind a name it never generated):
     * it must find the default object GL would give it, not ours. Ours is
     * bound nowhere between calls, so deleting it unbinds nothing. */
    render_fastdraw_tex *t = name == f->draw_tex.name ? &f->draw_tex : name == f->fill_tex.name ? &f->fill_tex : NULL;
    if (t) {
        gl->DeleteTextures(1, &t->name);
        forget_tex(t);
        if (t == &f->fill_tex)
            f->fill_w = f->fill_h = 0;
    }
}

/* A name for a texture of ours: none a list of the client binds, none the
 * client holds (GenTextures never returns a name in use). False when no
 * such name came (the caller uses the names it got for one call). */
static bool gen_name(render_fastdraw *f, const tsr_gl_procs *gl, GLuint *out)
{
    if (f->per_call)
        return false;
    GLuint refused[FASTDRAW_GEN_TRIES];
    int n = 0;
    bool ok = false;
    for (; n < FASTDRAW_GEN_TRIES; n++) {
        GLuint name = 0;
        gl->GenTextures(1, &name);
        if (!in_list_names(f, name)) {
            *out = name;
            ok = true;
            break;
        }
        refused[n] = name;
    }
    if (n)
        gl->DeleteTextures(n, refused);
    return ok;
}

void render_fastdraw_counts(const render_fastdraw *f, uint64_t *fast, uint64_t *total)
{
    *fast = f->fast;
    *total = f->total;
}

void render_fastdraw_clear_counts(const render_fastdraw *f, uint64_t *fast, uint64_t *total)
{
    *fast = f->clears_fast;
    *total = f->clears;
}

static bool has_extension(const char *list, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return true;
    return false;
}

static void probe(render_fastdraw *f, const tsr_gl_procs *gl)
{
    f->probed = true;
    struct {
        const char *name;
        void **slot;
    } wanted[] = {
        {"glGenFramebuffers", (void **)&f->GenFramebuffers},
        {"glDeleteFramebuffers", (void **)&f->DeleteFramebuffers},
        {"glBindFramebuffer", (void **)&f->BindFramebuffer},
        {"glFramebufferTexture2D", (void **)&f->FramebufferTexture2D},
        {"glCheckFramebufferStatus", (void **)&f->CheckFramebufferStatus},
        {"glBlitFramebuffer", (void **)&f->BlitFramebuffer},
    };
    for (size_t i = 0; i < sizeof wanted / sizeof wanted[0]; i++)
        if (!(*wanted[i].slot = (void *)f->lookup(wanted[i].name, f->lookup_ctx)))
            return;
    const char *ext = (const char *)gl->GetString(GL_EXTENSIONS);
    if (!ext)
        return;
    f->imaging = has_extension(ext, "GL_ARB_imaging");
    f->fragment_program = has_extension(ext, "GL_ARB_fragment_program");
    f->ati_fragment_shader = has_extension(ext, "GL_ATI_fragment_shader");
    f->srgb = has_extension(ext, "GL_EXT_framebuffer_sRGB") || has_extension(ext, "GL_ARB_framebuffer_sRGB");
    f->depth_bounds = has_extension(ext, "GL_EXT_depth_bounds_test");
    f->rectangle = has_extension(ext, "GL_ARB_texture_rectangle") || has_extension(ext, "GL_NV_texture_rectangle");
    const char *version = (const char *)gl->GetString(GL_VERSION);
    f->discard = (version && version[0] >= '3' && version[0] <= '9' && version[1] == '.') ||
                 has_extension(ext, "GL_EXT_transform_feedback");
    gl->GetIntegerv(GL_MAX_TEXTURE_UNITS, &f->units);
    gl->GetIntegerv(GL_MAX_DRAW_BUFFERS, &f->draw_buffers);
    gl->GetIntegerv(GL_MAX_TEXTURE_SIZE, &f->max_texture);
    if (f->units > FASTDRAW_MAX_UNITS || f->draw_buffers > FASTDRAW_MAX_DRAW_BUFFERS || f->units < 1 ||
        f->draw_buffers < 1)
        return;
    f->usable = true;
}

/* What a blit shares with a colour Clear: both write every pixel of the
 * (scissored) window rectangle once, in one colour buffer, all channels,
 * with no multisample resolve or sRGB encoding on the way, and neither is
 * discarded. */
static bool writes_one_buffer(const render_fastdraw *f, const tsr_gl_procs *gl)
{
    if ((f->srgb && gl->IsEnabled(GL_FRAMEBUFFER_SRGB)) || (f->discard && gl->IsEnabled(GL_RASTERIZER_DISCARD)))
        return false;
    GLint v = 0;
    gl->GetIntegerv(GL_SAMPLE_BUFFERS, &v);
    if (v)
        return false;
    GLboolean mask[4] = {0, 0, 0, 0};
    gl->GetBooleanv(GL_COLOR_WRITEMASK, mask);
    if (!mask[0] || !mask[1] || !mask[2] || !mask[3])
        return false;
    GLint buffer = GL_NONE;
    gl->GetIntegerv(GL_DRAW_BUFFER0, &buffer);
    if (buffer == GL_NONE)
        return false;
    for (GLint i = 1; i < f->draw_buffers; i++) {
        gl->GetIntegerv((GLenum)(GL_DRAW_BUFFER0 + i), &buffer);
        if (buffer != GL_NONE)
            return false;
    }
    return true;
}

/* Every fragment stage off, so a fragment keeps the bytes it was given. */
static bool fragments_untouched(const render_fastdraw *f, const tsr_gl_procs *gl)
{
    static const GLenum off[] = {GL_ALPHA_TEST,     GL_DEPTH_TEST, GL_STENCIL_TEST, GL_BLEND,
                                 GL_COLOR_LOGIC_OP, GL_FOG,        GL_COLOR_SUM,    GL_LIGHTING};
    for (size_t i = 0; i < sizeof off / sizeof off[0]; i++)
        if (gl->IsEnabled(off[i]))
            return false;
    if ((f->fragment_program && gl->IsEnabled(GL_FRAGMENT_PROGRAM_ARB)) ||
        (f->ati_fragment_shader && gl->IsEnabled(GL_FRAGMENT_SHADER_ATI)) ||
        (f->depth_bounds && gl->IsEnabled(GL_DEPTH_BOUNDS_TEST_EXT)) || !writes_one_buffer(f, gl))
        return false;
    GLint v = 0;
    gl->GetIntegerv(GL_CURRENT_PROGRAM, &v);
    if (v)
        return false;
    /* Texturing on any unit (fixed function uses each enabled one). */
    GLint active = GL_TEXTURE0;
    gl->GetIntegerv(GL_ACTIVE_TEXTURE, &active);
    bool textured = false;
    for (GLint u = 0; u < f->units && !textured; u++) {
        gl->ActiveTexture((GLenum)(GL_TEXTURE0 + u));
        textured = gl->IsEnabled(GL_TEXTURE_1D) || gl->IsEnabled(GL_TEXTURE_2D) || gl->IsEnabled(GL_TEXTURE_3D) ||
                   gl->IsEnabled(GL_TEXTURE_CUBE_MAP) || (f->rectangle && gl->IsEnabled(GL_TEXTURE_RECTANGLE_ARB));
    }
    gl->ActiveTexture((GLenum)active);
    return !textured;
}

/* No pixel transfer stage changes a colour component. */
static bool transfer_identity(const render_fastdraw *f, const tsr_gl_procs *gl)
{
    GLboolean map = GL_FALSE;
    gl->GetBooleanv(GL_MAP_COLOR, &map);
    if (map)
        return false;
    static const GLenum scale[] = {GL_RED_SCALE, GL_GREEN_SCALE, GL_BLUE_SCALE, GL_ALPHA_SCALE};
    static const GLenum bias[] = {GL_RED_BIAS, GL_GREEN_BIAS, GL_BLUE_BIAS, GL_ALPHA_BIAS};
    for (int i = 0; i < 4; i++) {
        GLfloat s = 0, b = 1;
        gl->GetFloatv(scale[i], &s);
        gl->GetFloatv(bias[i], &b);
        if (s != 1.0f || b != 0.0f)
            return false;
    }
    if (f->imaging) {
        static const GLenum stages[] = {GL_COLOR_TABLE,
                                        GL_POST_CONVOLUTION_COLOR_TABLE,
                                        GL_POST_COLOR_MATRIX_COLOR_TABLE,
                                        GL_CONVOLUTION_1D,
                                        GL_CONVOLUTION_2D,
                                        GL_SEPARABLE_2D,
                                        GL_HISTOGRAM,
                                        GL_MINMAX};
        for (size_t i = 0; i < sizeof stages / sizeof stages[0]; i++)
            if (gl->IsEnabled(stages[i]))
                return false;
        static const GLenum more[] = {
            GL_POST_CONVOLUTION_RED_SCALE,   GL_POST_CONVOLUTION_GREEN_SCALE,  GL_POST_CONVOLUTION_BLUE_SCALE,
            GL_POST_CONVOLUTION_ALPHA_SCALE, GL_POST_COLOR_MATRIX_RED_SCALE,   GL_POST_COLOR_MATRIX_GREEN_SCALE,
            GL_POST_COLOR_MATRIX_BLUE_SCALE, GL_POST_COLOR_MATRIX_ALPHA_SCALE, GL_POST_CONVOLUTION_RED_BIAS,
            GL_POST_CONVOLUTION_GREEN_BIAS,  GL_POST_CONVOLUTION_BLUE_BIAS,    GL_POST_CONVOLUTION_ALPHA_BIAS,
            GL_POST_COLOR_MATRIX_RED_BIAS,   GL_POST_COLOR_MATRIX_GREEN_BIAS,  GL_POST_COLOR_MATRIX_BLUE_BIAS,
            GL_POST_COLOR_MATRIX_ALPHA_BIAS};
        for (size_t i = 0; i < sizeof more / sizeof more[0]; i++) {
            GLfloat v = 0;
            gl->GetFloatv(more[i], &v);
            if (v != (i < 8 ? 1.0f : 0.0f))
                return false;
        }
        GLfloat m[16];
        gl->GetFloatv(GL_COLOR_MATRIX, m);
        for (int i = 0; i < 16; i++)
            if (m[i] != (i % 5 == 0 ? 1.0f : 0.0f))
                return false;
    }
    return true;
}

/* The rectangle [x0, x1) x [y0, y1) intersected with [bx, bx+bw) x .... */
static void clip(GLint *x0, GLint *y0, GLint *x1, GLint *y1, GLint bx, GLint by, GLint bw, GLint bh)
{
    if (*x0 < bx)
        *x0 = bx;
    if (*y0 < by)
        *y0 = by;
    if (*x1 > bx + bw)
        *x1 = bx + bw;
    if (*y1 > by + bh)
        *y1 = by + bh;
}

/* Uploads `rows` (cw x ch pixels of `format`, tightly packed, the top row
 * first; NULL: the texture holds them already) into the kept texture *t,
 * grown first when smaller (the texture's other texels are never read),
 * and blits them 1:1 to [x0, x1) x [y0, y1) given flipped in y (llvmpipe's
 * plain copy), with the scissor test off around the blit; the texture
 * binding, unpack state (`unpack`: the application's row length, skip
 * rows, skip pixels, alignment), read framebuffer and scissor test are the
 * application's again after it. Without a name fit for a kept texture the
 * upload goes into one made and deleted here.
 * ch may be less than y1 - y0 when every row is the same (a fill): the
 * ch rows are then blitted again until [y0, y1) is covered.
 * False when the framebuffer is incomplete (nothing drawn). */
static bool upload_blit(render_fastdraw *f, const tsr_gl_procs *gl, render_fastdraw_tex *t, const unsigned char *rows,
                        size_t cw, size_t ch, GLenum format, GLint x0, GLint y0, GLint x1, GLint y1,
                        const GLint unpack[4], bool scissor)
{
    GLint texture = 0, read_fb = 0;
    gl->GetIntegerv(GL_TEXTURE_BINDING_2D, &texture);
    gl->GetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read_fb);
    render_fastdraw_tex once = {0, 0, 0};
    if (!t->name && !gen_name(f, gl, &t->name))
        t = &once;
    if (!t->name)
        gl->GenTextures(1, &t->name);
    gl->BindTexture(GL_TEXTURE_2D, t->name);
    gl->PixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    gl->PixelStorei(GL_UNPACK_SKIP_ROWS, 0);
    gl->PixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    if ((size_t)t->width < cw || (size_t)t->height < ch) {
        GLsizei w = (size_t)t->width < cw ? (GLsizei)cw : t->width,
                h = (size_t)t->height < ch ? (GLsizei)ch : t->height;
        gl->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, format, GL_UNSIGNED_BYTE, NULL);
        t->width = w;
        t->height = h;
    }
    if (rows)
        gl->TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, (GLsizei)cw, (GLsizei)ch, format, GL_UNSIGNED_BYTE, rows);
    gl->PixelStorei(GL_UNPACK_ROW_LENGTH, unpack[0]);
    gl->PixelStorei(GL_UNPACK_SKIP_ROWS, unpack[1]);
    gl->PixelStorei(GL_UNPACK_SKIP_PIXELS, unpack[2]);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, unpack[3]);
    GLuint fb = 0;
    f->GenFramebuffers(1, &fb);
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, fb);
    f->FramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->name, 0);
    bool complete = f->CheckFramebufferStatus(GL_READ_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    if (complete) {
        if (scissor)
            gl->Disable(GL_SCISSOR_TEST);
        for (GLint yb = y0; yb < y1; yb += (GLint)ch) {
            GLint h = y1 - yb < (GLint)ch ? y1 - yb : (GLint)ch;
            f->BlitFramebuffer(0, 0, (GLint)cw, h, x0, yb + h, x1, yb, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        }
        if (scissor)
            gl->Enable(GL_SCISSOR_TEST);
    }
    f->BindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)read_fb);
    f->DeleteFramebuffers(1, &fb);
    gl->BindTexture(GL_TEXTURE_2D, (GLuint)texture);
    if (t == &once)
        gl->DeleteTextures(1, &once.name);
    return complete;
}

/* The fast path; false (having changed nothing) when the state does not
 * allow it. */
static bool draw_fast(render_fastdraw *f, const tsr_gl_procs *gl, GLint window_width, GLint window_height,
                      GLsizei width, GLsizei height, GLenum format, const unsigned char *pixels)
{
    GLint v = 0;
    gl->GetIntegerv(GL_LIST_INDEX, &v); /* compiling a display list */
    if (v)
        return false;
    gl->GetIntegerv(GL_RENDER_MODE, &v);
    if (v != GL_RENDER)
        return false;
    gl->GetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &v);
    if (v)
        return false;
    GLboolean valid = GL_FALSE;
    gl->GetBooleanv(GL_CURRENT_RASTER_POSITION_VALID, &valid);
    if (!valid)
        return false;
    GLfloat pos[4], zoom[2];
    gl->GetFloatv(GL_CURRENT_RASTER_POSITION, pos);
    gl->GetFloatv(GL_ZOOM_X, &zoom[0]);
    gl->GetFloatv(GL_ZOOM_Y, &zoom[1]);
    if (zoom[0] != 1.0f || zoom[1] != 1.0f)
        return false;
    /* An integer raster position: pixel (i, j) lands on (x+i, y+j). */
    const GLfloat far = (GLfloat)(1 << 24); /* bounded first: the casts below stay defined */
    if (!(pos[0] >= -far && pos[0] <= far && pos[1] >= -far && pos[1] <= far) || pos[0] != (GLfloat)(GLint)pos[0] ||
        pos[1] != (GLfloat)(GLint)pos[1])
        return false;
    if (!transfer_identity(f, gl) || !fragments_untouched(f, gl))
        return false;
    GLint unpack[4]; /* row length, skip rows, skip pixels, alignment */
    gl->GetIntegerv(GL_UNPACK_ROW_LENGTH, &unpack[0]);
    gl->GetIntegerv(GL_UNPACK_SKIP_ROWS, &unpack[1]);
    gl->GetIntegerv(GL_UNPACK_SKIP_PIXELS, &unpack[2]);
    gl->GetIntegerv(GL_UNPACK_ALIGNMENT, &unpack[3]);
    if (unpack[0] < 0 || unpack[1] < 0 || unpack[2] < 0 || unpack[3] < 1)
        return false;

    /* Pixel ownership and the scissor, applied by clipping. */
    GLint x0 = (GLint)pos[0], y0 = (GLint)pos[1];
    GLint x1 = x0 + width, y1 = y0 + height;
    clip(&x0, &y0, &x1, &y1, 0, 0, window_width, window_height);
    bool scissor = gl->IsEnabled(GL_SCISSOR_TEST) == GL_TRUE;
    if (scissor) {
        GLint box[4] = {0, 0, 0, 0};
        gl->GetIntegerv(GL_SCISSOR_BOX, box);
        clip(&x0, &y0, &x1, &y1, box[0], box[1], box[2], box[3]);
    }
    if (x1 <= x0 || y1 <= y0)
        return true; /* every fragment discarded: nothing to draw */
    size_t cw = (size_t)(x1 - x0), ch = (size_t)(y1 - y0);
    size_t need = cw * ch * 4;
    if (need > f->rows_size) {
        unsigned char *rows = realloc(f->rows, need);
        if (!rows)
            return false;
        f->rows = rows;
        f->rows_size = need;
    }
    /* Source rows as GL unpacks them (GL 2.1 3.6.4: component size 1). */
    size_t row_pixels = unpack[0] > 0 ? (size_t)unpack[0] : (size_t)width;
    size_t a = (size_t)unpack[3];
    size_t stride = (row_pixels * 4 + a - 1) / a * a;
    const unsigned char *src = pixels + (size_t)unpack[1] * stride + (size_t)unpack[2] * 4;
    size_t sx = (size_t)(x0 - (GLint)pos[0]), sy = (size_t)(y0 - (GLint)pos[1]);
    for (size_t j = 0; j < ch; j++)
        memcpy(f->rows + (ch - 1 - j) * cw * 4, src + (sy + j) * stride + sx * 4, cw * 4);

    return upload_blit(f, gl, &f->draw_tex, f->rows, cw, ch, format, x0, y0, x1, y1, unpack, scissor);
}

/* Clear: the clear colour, when it is a value the 8-bit buffer holds
 * exactly (each channel, clamped to [0, 1], k / 255.0f as a float, which GL 2.1 2.14.9's
 * conversion, f * 255 rounded to the nearest integer, gives back as k, and
 * which dithering therefore cannot move), as the bytes RGBA. */
static bool clear_bytes(const tsr_gl_procs *gl, unsigned char rgba[4])
{
    GLfloat c[4] = {-1, -1, -1, -1};
    gl->GetFloatv(GL_COLOR_CLEAR_VALUE, c);
    for (int i = 0; i < 4; i++) {
        if (c[i] != c[i]) /* NaN */
            return false;
        /* a fixed-point buffer takes the value clamped (GL 3.0 keeps it unclamped until then) */
        if (c[i] < 0.0f)
            c[i] = 0.0f;
        if (c[i] > 1.0f)
            c[i] = 1.0f;
        long k = (long)(c[i] * 255.0f + 0.5f);
        if ((GLfloat)k / 255.0f != c[i])
            return false;
        rgba[i] = (unsigned char)k;
    }
    return true;
}

static bool clear_fast(render_fastdraw *f, const tsr_gl_procs *gl, GLint window_width, GLint window_height)
{
    /* Unscissored, llvmpipe clears with a fill already. */
    if (gl->IsEnabled(GL_SCISSOR_TEST) != GL_TRUE)
        return false;
    GLint v = 0;
    gl->GetIntegerv(GL_LIST_INDEX, &v);
    if (v)
        return false;
    gl->GetIntegerv(GL_RENDER_MODE, &v);
    if (v != GL_RENDER)
        return false;
    gl->GetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &v); /* the upload would read it */
    if (v)
        return false;
    unsigned char rgba[4];
    if (!writes_one_buffer(f, gl) || !clear_bytes(gl, rgba))
        return false;
    GLint x0 = 0, y0 = 0, x1 = window_width, y1 = window_height;
    GLint box[4] = {0, 0, 0, 0};
    gl->GetIntegerv(GL_SCISSOR_BOX, box);
    clip(&x0, &y0, &x1, &y1, box[0], box[1], box[2], box[3]);
    if (x1 <= x0 || y1 <= y0)
        return true; /* nothing inside the scissor box */
    /* At most FILL_ROWS rows are uploaded, then blitted again down the box. */
    size_t cw = (size_t)(x1 - x0), ch = (size_t)(y1 - y0) < FILL_ROWS ? (size_t)(y1 - y0) : FILL_ROWS, n = cw * ch;
    if (n > f->fill_pixels || memcmp(rgba, f->fill_rgba, 4)) {
        if (n > f->fill_pixels) {
            unsigned char *fill = realloc(f->fill, n * 4);
            if (!fill)
                return false;
            f->fill = fill;
            f->fill_pixels = n;
        }
        for (size_t i = 0; i < f->fill_pixels; i++)
            memcpy(f->fill + i * 4, rgba, 4);
        memcpy(f->fill_rgba, rgba, 4);
    }
    GLint unpack[4];
    gl->GetIntegerv(GL_UNPACK_ROW_LENGTH, &unpack[0]);
    gl->GetIntegerv(GL_UNPACK_SKIP_ROWS, &unpack[1]);
    gl->GetIntegerv(GL_UNPACK_SKIP_PIXELS, &unpack[2]);
    gl->GetIntegerv(GL_UNPACK_ALIGNMENT, &unpack[3]);
    /* The fill texture already holds this colour over cw x ch: no upload. */
    bool held =
        f->fill_tex.name && !memcmp(rgba, f->fill_tex_rgba, 4) && (size_t)f->fill_w >= cw && (size_t)f->fill_h >= ch;
    if (!upload_blit(f, gl, &f->fill_tex, held ? NULL : f->fill, cw, ch, GL_RGBA, x0, y0, x1, y1, unpack, true))
        return false;
    if (!held && f->fill_tex.name) {
        memcpy(f->fill_tex_rgba, rgba, 4);
        f->fill_w = (GLsizei)cw;
        f->fill_h = (GLsizei)ch;
    }
    return true;
}

bool render_fastdraw_clear(render_fastdraw *f, const tsr_gl_procs *gl, int window_width, int window_height)
{
    f->clears++;
    if (f->enabled && !f->probed)
        probe(f, gl);
    if (f->enabled && f->usable && clear_fast(f, gl, window_width, window_height)) {
        f->clears_fast++;
        return true;
    }
    return false;
}

void render_fastdraw_draw(render_fastdraw *f, const tsr_gl_procs *gl, int window_width, int window_height,
                          GLsizei width, GLsizei height, GLenum format, GLenum type, const void *pixels)
{
    f->total++;
    if (f->enabled && !f->probed)
        probe(f, gl);
    if (f->enabled && f->usable && width > 0 && height > 0 && pixels && width <= f->max_texture &&
        height <= f->max_texture && type == GL_UNSIGNED_BYTE && (format == GL_RGBA || format == GL_BGRA) &&
        draw_fast(f, gl, window_width, window_height, width, height, format, pixels)) {
        f->fast++;
        return;
    }
    gl->DrawPixels(width, height, format, type, pixels);
}
