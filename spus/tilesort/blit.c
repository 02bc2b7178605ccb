/* spus/tilesort/blit.c — glBlitFramebuffer (GL_ARB_framebuffer_object,
 * GL_EXT_framebuffer_blit) on a wall (docs/walls.md, "Blits").
 *
 * A blit reads the read framebuffer and writes the draw framebuffer. Every
 * server holds a program FBO whole (fbo.c), the window only in its tiles.
 * A blit whose source is a program FBO goes to every server as it is:
 * each reads the whole source and writes the whole destination FBO, or
 * its own tiles of the window (render scissors what it draws into the
 * window to its tiles, and GL's blit honours the scissor).
 *
 * A blit whose source is the window would read pixels that no one server
 * holds. Its source rectangle is gathered from the servers as a copy's is
 * (copy.c: colour as GL_FLOAT RGBA, depth and stencil as
 * GL_UNSIGNED_INT_24_8, nothing lost) and given to the tracker as textures
 * of the window's size and formats (GL_RGBA8, GL_DEPTH24_STENCIL8:
 * render's window, so the values are the window's again and a depth or
 * stencil blit meets GL's rule that both sides' formats match) holding it
 * where the window does; every server blits from an FBO of those textures
 * with the same coordinates, destination, mask and filter as the
 * program's blit, so the same pixels. Same size and place, because Mesa
 * interpolates a scaled blit's source coordinates in floating point from
 * the source's place in its buffer: a rectangle-sized texture picked other
 * source pixels at some edges (faker_core_fbo_and_blits_* showed it). The
 * textures hold the rows top row first and the source rows are mirrored to
 * match, because a renderer's window is stored top row first (render's
 * contexts.c: GL_FRAMEBUFFER_FLIP_Y_MESA, as a window is) and Mesa blits
 * from it in that order. The rectangle gathered is the source clipped to
 * the window (GL clips a blit's source to its read framebuffer, and the
 * textures have the window's edges), one pixel wider on each side for
 * GL_LINEAR, which may read next to it; the rest of the textures is
 * undefined and never read. The FBO's name is the first server's
 * (glGenFramebuffers, the route every glGen* takes); it and the textures
 * are deleted after the blit.
 *
 * A blit GL refuses for its arguments (a mask or filter it does not take,
 * depth or stencil with GL_LINEAR), one inside glBegin/glEnd or during
 * selection or feedback, one whose source lies wholly outside the window,
 * and one compiled into a display list go to the servers unchanged: GL's
 * own error or no-op, answered once (gets.c); a listed blit from the
 * window replays on each server from its own tiles.
 *
 * Owns nothing. Never leaves the program's texture binding, pixel store
 * or transfer changed (the tracker puts them back before the servers see
 * them), never sends a server a blit from the window it does not hold. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "instance.h"

#define BLIT_MASKS (GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT)

static void send_unchanged(tilesort *t, GLint sx0, GLint sy0, GLint sx1, GLint sy1, GLint dx0, GLint dy0, GLint dx1,
                           GLint dy1, GLbitfield mask, GLenum filter)
{
    ts_broadcast_next(t);
    tsr_call_BlitFramebuffer(&t->geo_table, sx0, sy0, sx1, sy1, dx0, dy0, dx1, dy1, mask, filter);
    ts_flush_geometry(t);
}

/* The window's rectangle [x0, x1) x [y0, y1) a blit from it reads. */
typedef struct blit_source {
    GLint x0, y0, x1, y1;
} blit_source;

static int64_t lo(GLint a, GLint b) { return a < b ? a : b; }
static int64_t hi(GLint a, GLint b) { return a > b ? a : b; }
static GLint clamp_to(int64_t v, GLint size) { return (GLint)(v < 0 ? 0 : v > size ? size : v); }
/* A source row coordinate in the textures', which hold the window's rows
 * top row first: mirrored about the window's top (GL's int range kept). */
static GLint mirrored_y(const tilesort *t, GLint y)
{
    int64_t m = (int64_t)t->win_h - y;
    return (GLint)(m < INT32_MIN ? INT32_MIN : m > INT32_MAX ? INT32_MAX : m);
}

/* 0 when the source holds no pixel of the window. */
static int source_of(const tilesort *t, GLint sx0, GLint sy0, GLint sx1, GLint sy1, GLenum filter, blit_source *s)
{
    int margin = filter == GL_LINEAR;
    s->x0 = clamp_to(lo(sx0, sx1) - margin, t->win_w);
    s->x1 = clamp_to(hi(sx0, sx1) + margin, t->win_w);
    s->y0 = clamp_to(lo(sy0, sy1) - margin, t->win_h);
    s->y1 = clamp_to(hi(sy0, sy1) + margin, t->win_h);
    return s->x1 > s->x0 && s->y1 > s->y0;
}

/* Rows of `row_bytes` reversed in place (top row first). */
static void reverse_rows(unsigned char *pixels, size_t row_bytes, GLsizei h)
{
    unsigned char tmp[256];
    for (GLsizei a = 0, b = h - 1; a < b; a++, b--)
        for (size_t at = 0; at < row_bytes; at += sizeof tmp) {
            size_t n = row_bytes - at < sizeof tmp ? row_bytes - at : sizeof tmp;
            unsigned char *ra = pixels + (size_t)a * row_bytes + at, *rb = pixels + (size_t)b * row_bytes + at;
            memcpy(tmp, ra, n);
            memcpy(ra, rb, n);
            memcpy(rb, tmp, n);
        }
}

/* A texture of the tracker's of the window's size holding the gathered
 * pixels where the window holds them, top row first; 0 when out of memory
 * (reported). The unit's 2D binding is put back. */
static GLuint source_texture(tilesort *t, const blit_source *s, GLenum ifmt, GLenum format, GLenum type)
{
    GLsizei w = s->x1 - s->x0, h = s->y1 - s->y0;
    void *pixels = ts_copy_gather(t, s->x0, s->y0, w, h, format, type);
    if (!pixels)
        return 0;
    reverse_rows(pixels, (size_t)w * (format == GL_RGBA ? 4 * sizeof(GLfloat) : 4), h);
    const tsr_state_values *v = tsr_state_values_of(t->ctx);
    GLuint bound = v->image[v->active_texture].binding[TSR_TEX_2D], name = 0;
    tsr_call_GenTextures(&t->normal, 1, &name);
    tsr_call_BindTexture(&t->normal, GL_TEXTURE_2D, name);
    ts_copy_upload_2d(t, ifmt, t->win_w, t->win_h, s->x0, t->win_h - s->y1, w, h, format, type, pixels);
    tsr_call_BindTexture(&t->normal, GL_TEXTURE_2D, bound);
    free(pixels);
    return name;
}

static void blit_from_window(tilesort *t, const blit_source *s, GLint sx0, GLint sy0, GLint sx1, GLint sy1, GLint dx0,
                             GLint dy0, GLint dx1, GLint dy1, GLbitfield mask, GLenum filter)
{
    GLuint color = 0, depth_stencil = 0, fb = 0;
    if (mask & GL_COLOR_BUFFER_BIT) {
        color = source_texture(t, s, GL_RGBA8, GL_RGBA, GL_FLOAT);
        if (!color)
            return;
    }
    if (mask & (GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT)) {
        depth_stencil = source_texture(t, s, GL_DEPTH24_STENCIL8, GL_DEPTH_STENCIL, GL_UNSIGNED_INT_24_8);
        if (!depth_stencil) {
            if (color)
                tsr_call_DeleteTextures(&t->normal, 1, &color);
            return;
        }
    }
    tsr_call_GenFramebuffers(&t->normal, 1, &fb); /* the first server's name */
    ts_broadcast_next(t);
    const tsr_dispatch *to = &t->geo_table;
    if (color)
        ts_fbo_send_texture(t, GL_TEXTURE_2D, color);
    if (depth_stencil)
        ts_fbo_send_texture(t, GL_TEXTURE_2D, depth_stencil);
    tsr_call_BindFramebuffer(to, GL_READ_FRAMEBUFFER, fb);
    if (color)
        tsr_call_FramebufferTexture2D(to, GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color, 0);
    else
        tsr_call_ReadBuffer(to, GL_NONE); /* the FBO's own read buffer: no colour to read */
    if (depth_stencil)
        tsr_call_FramebufferTexture2D(to, GL_READ_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_TEXTURE_2D,
                                      depth_stencil, 0);
    tsr_call_BlitFramebuffer(to, sx0, mirrored_y(t, sy0), sx1, mirrored_y(t, sy1), dx0, dy0, dx1, dy1, mask, filter);
    tsr_call_BindFramebuffer(to, GL_READ_FRAMEBUFFER, 0); /* the program's read framebuffer: the window */
    tsr_call_DeleteFramebuffers(to, 1, &fb);
    ts_flush_geometry(t);
    GLuint textures[2] = {color ? color : depth_stencil, depth_stencil};
    tsr_call_DeleteTextures(&t->normal, color && depth_stencil ? 2 : 1, textures);
}

void ts_BlitFramebuffer(void *self, GLint sx0, GLint sy0, GLint sx1, GLint sy1, GLint dx0, GLint dy0, GLint dx1,
                        GLint dy1, GLbitfield mask, GLenum filter)
{
    tilesort *t = self;
    blit_source s;
    int refused = (mask & ~(GLbitfield)BLIT_MASKS) || (filter != GL_NEAREST && filter != GL_LINEAR) ||
                  ((mask & (GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT)) && filter != GL_NEAREST);
    if (t->app_read_fb || refused || !mask || t->in_begin || t->render_mode != GL_RENDER || t->win_w <= 0 ||
        !source_of(t, sx0, sy0, sx1, sy1, filter, &s)) {
        send_unchanged(t, sx0, sy0, sx1, sy1, dx0, dy0, dx1, dy1, mask, filter);
        return;
    }
    blit_from_window(t, &s, sx0, sy0, sx1, sy1, dx0, dy0, dx1, dy1, mask, filter);
}
