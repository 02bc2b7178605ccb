/* spus/render/frame.c — render's window and frames: WindowCreateTSR and
 * WindowSizeTSR give the framebuffer its size (within the window budget),
 * SwapBuffersTSR finishes the frame, reads it back (the whole window, or
 * each owned tile through a reader context of its own) and writes it out
 * as PNGs and to window output (xwindow.h); render_spu_end_frame,
 * render_spu_read and render_spu_size are what the plugin publishes to a
 * subclass (tessera/dev/render.h).
 *
 * Owns: the frame counter's use, the tile read-back buffer, the reader
 * context. Never: applies a client's pixel-store or transfer state to a
 * read, creates the output directory, writes a frame of another window. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/image.h"
#include "tessera/log.h"

#include "instance.h"

/* Where "the first window command of this context" is remembered. */
static bool *window_seen_flag(render_spu *r)
{
    return r->shared ? &r->contexts[r->current].window_seen : &r->window_seen;
}

static void resize_window(render_spu *r, GLsizei width, GLsizei height, const char *command)
{
    if (r->fixed_width) {
        render_ensure_current(r);
        *window_seen_flag(r) = true;
        return;
    }
    uint64_t max_pixels = r->max_window_pixels ? r->max_window_pixels : (uint64_t)RENDER_MAX_SIDE * RENDER_MAX_SIDE;
    if (width >= 1 && height >= 1 && (uint64_t)width * (uint64_t)height > max_pixels) {
        render_refuse(r, "%s(%d, %d, %d): %llu pixels are over the window budget max_window_pixels=%llu", command,
                      r->window, (int)width, (int)height, (unsigned long long)width * (unsigned long long)height,
                      (unsigned long long)max_pixels);
        render_ensure_current(r);
        return;
    }
    if (width < 1 || height < 1 || width > RENDER_MAX_SIDE || height > RENDER_MAX_SIDE) {
        tsr_log(TSR_LOG_ERROR, "%s: %s(%d, %d, %d): size out of range 1..%d, ignored", r->name, command, r->window,
                (int)width, (int)height, RENDER_MAX_SIDE);
        render_ensure_current(r);
        return;
    }
    tsr_error err = {0};
    if ((r->shared ? render_shared_resize(r, width, height, &err) : render_bind_framebuffer(r, width, height, &err)) !=
        TSR_OK) {
        tsr_log(TSR_LOG_ERROR, "%s", err.message);
        return;
    }
    bool *seen = window_seen_flag(r);
    if (!*seen) {
        r->gl.Viewport(0, 0, width, height);
        render_Scissor(r, 0, 0, width, height);
        *seen = true;
    }
}

static void render_WindowCreateTSR(void *self, GLint window, GLsizei width, GLsizei height)
{
    render_spu *r = self;
    if (window == r->window)
        resize_window(r, width, height, "WindowCreateTSR");
    tsr_call_WindowCreateTSR(r->child, window, width, height);
}

static void render_WindowSizeTSR(void *self, GLint window, GLsizei width, GLsizei height)
{
    render_spu *r = self;
    if (window == r->window)
        resize_window(r, width, height, "WindowSizeTSR");
    tsr_call_WindowSizeTSR(r->child, window, width, height);
}

/* Shared mode: reads the shared colour buffer into r->buffer through
 * context 0 (its pack state is never changed, unlike a client's). */
static void shared_read_frame(render_spu *r)
{
    tsr_error err = {0};
    if (!r->buffer && !(r->buffer = malloc((size_t)r->width * (size_t)r->height * 4))) {
        tsr_log(TSR_LOG_ERROR, "%s: out of memory for a %dx%d frame", r->name, r->width, r->height);
        return;
    }
    size_t back = r->current;
    if (render_shared_switch(r, 0, &err) != TSR_OK ||
        (r->gl.ReadPixels(0, 0, r->width, r->height, GL_RGBA, GL_UNSIGNED_BYTE, r->buffer),
         render_shared_switch(r, back, &err)) != TSR_OK)
        tsr_log(TSR_LOG_ERROR, "%s", err.message);
}

/* The file of one tile: the output pattern's, with "-tN" (N = the tile's
 * index in the tile list) put before the extension when there are several. */
static int tile_path(char *out, size_t size, const char *pattern, int frame, size_t tile, size_t ntiles, tsr_error *err)
{
    if (tsr_image_frame_path(out, size, pattern, frame, err) != TSR_OK)
        return err->code;
    if (ntiles == 1)
        return TSR_OK;
    char suffix[32];
    int n = snprintf(suffix, sizeof suffix, "-t%zu", tile);
    size_t len = strlen(out);
    if (len + (size_t)n + 1 > size)
        return tsr_error_set(err, TSR_EINVAL, "file name too long for tile %zu", tile);
    const char *slash = strrchr(out, '/');
    char *dot = strrchr(slash ? slash : out, '.');
    size_t at = dot ? (size_t)(dot - out) : len;
    memmove(out + at + n, out + at, len - at + 1);
    memcpy(out + at, suffix, (size_t)n);
    return TSR_OK;
}

/* A frame's PNG: RGB, what the window shows, unless output_alpha asks
 * for the framebuffer's alpha too (a sort-last alpha layer needs it; a
 * viewer would show an alpha-0 background as transparent). The pixels are
 * glReadPixels' rows, bottom row first. */
static int write_frame_png(const render_spu *r, const unsigned char *pixels, int w, int h, const char *path,
                           tsr_error *err)
{
    return tsr_image_write_png_pixels(pixels, w, h, (size_t)w * 4, true, r->output_alpha, path, err);
}

/* Tiled swap: every context has finished (switching finishes the outgoing
 * one), the reader context reads each tile's pixels — and only those —
 * and writes one PNG per tile. The reader is a context of its own so no
 * client's pixel-store, pixel-transfer or read-buffer state applies. */
static void tiled_write_frame(render_spu *r, int frame, tsr_render_tile_fn each, void *ctx)
{
    tsr_error err = {0};
    size_t back = r->current;
    if (r->osmesa.GetCurrentContext())
        r->gl.Finish();
    if (!r->reader.osmesa) {
        r->reader = (render_context){.id = -1};
        r->reader.osmesa = r->osmesa.CreateContextExt(OSMESA_RGBA, 24, 8, 16, r->context);
        if (!r->reader.osmesa) {
            tsr_log(TSR_LOG_ERROR, "%s: frame %d: OSMesaCreateContextExt failed for the tile reader", r->name, frame);
            return;
        }
    }
    if (render_attach_context(r, &r->reader, &err) != TSR_OK) {
        tsr_log(TSR_LOG_ERROR, "%s: frame %d: %s", r->name, frame, err.message);
    } else {
        render_box window = {0, 0, r->width, r->height};
        for (size_t i = 0; i < r->ntiles; i++) {
            const tsr_tile *t = &r->tiles[i];
            render_box b = render_box_intersect((render_box){t->x, t->y, t->width, t->height}, window);
            if (!b.w) {
                tsr_log(TSR_LOG_ERROR, "%s: frame %d: tile %zu [%d, %d, %d, %d] is outside the %dx%d window", r->name,
                        frame, i, t->x, t->y, t->width, t->height, r->width, r->height);
                continue;
            }
            size_t need = (size_t)b.w * (size_t)b.h * 4;
            if (need > r->tile_pixels_size) {
                unsigned char *p = realloc(r->tile_pixels, need);
                if (!p) {
                    tsr_log(TSR_LOG_ERROR, "%s: frame %d: out of memory for tile %zu", r->name, frame, i);
                    continue;
                }
                r->tile_pixels = p;
                r->tile_pixels_size = need;
            }
            r->gl.ReadPixels(b.x, b.y, b.w, b.h, GL_RGBA, GL_UNSIGNED_BYTE, r->tile_pixels);
            if (r->xwindow)
                render_xwindow_image(r->xwindow, b.x, b.y, b.w, b.h, r->tile_pixels);
            if (each)
                each(ctx, i, b.x, b.y, b.w, b.h, r->tile_pixels);
            char path[PATH_MAX];
            if (r->output[0] && (tile_path(path, sizeof path, r->output, frame, i, r->ntiles, &err) != TSR_OK ||
                                 write_frame_png(r, r->tile_pixels, b.w, b.h, path, &err) != TSR_OK))
                tsr_log(TSR_LOG_ERROR, "%s: frame %d: tile %zu: %s", r->name, frame, i, err.message);
        }
    }
    if (render_shared_make_current(r, back, &err) != TSR_OK)
        tsr_log(TSR_LOG_ERROR, "%s", err.message);
    if (r->xwindow)
        render_xwindow_done(r->xwindow, frame, r->window, r->width, r->height);
}

/* The frame's drawing done before it is read or shown. glFinish would do,
 * but in solo mode OSMesa then copies the whole window into the user
 * buffer (docs/render.md), which only a PNG, window output and `each`
 * read; a subclass reads with render_spu_read. Without those readers a
 * one-pixel read waits for the rasteriser as glFinish does and copies 4
 * bytes: a 1920x1080 frame skips an 8 MB copy. */
static void finish_frame(render_spu *r, bool whole)
{
    if (r->shared || whole || r->width < 1 || r->height < 1) {
        r->gl.Finish();
        return;
    }
    unsigned char pixel[4];
    tsr_error err = {0};
    if (render_spu_read(r, 0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixel, &err) != TSR_OK)
        r->gl.Finish();
}

/* The frame of r's window ended: finished, read back where someone reads
 * it (PNGs, window output, `each`: tessera/dev/render.h), written out; the
 * swap itself is the caller's to pass on. Returns the frame's number. */
int render_end_frame(render_spu *r, tsr_render_tile_fn each, void *ctx)
{
    tsr_error resolve_err = {0};
    if (render_ms_resolve(r, &resolve_err) != TSR_OK) /* multisample.c: the frame is the window resolved */
        tsr_log(TSR_LOG_ERROR, "%s: swap: %s", r->name, resolve_err.message);
    if (r->double_buffered)
        render_buffers_swap(r); /* the frame is what the front shows now */
    render_ensure_current(r);
    int frame = r->frame++;
    if (r->ntiles) {
        tiled_write_frame(r, frame, each, ctx);
        return frame;
    }
    /* Only a PNG, window output or `each` reads the whole window; without
     * them the frame stays in the framebuffer (a subclass reads from there
     * with render_spu_read). */
    bool whole = r->output[0] || r->xwindow || each;
    finish_frame(r, whole);
    if (r->shared && whole)
        shared_read_frame(r);
    if (r->output[0]) {
        char path[PATH_MAX];
        tsr_error err = {0};
        if (tsr_image_frame_path(path, sizeof path, r->output, frame, &err) != TSR_OK ||
            write_frame_png(r, r->buffer, r->width, r->height, path, &err) != TSR_OK)
            tsr_log(TSR_LOG_ERROR, "%s: frame %d: %s", r->name, frame, err.message);
    }
    if (r->xwindow && r->buffer)
        render_xwindow_image(r->xwindow, 0, 0, r->width, r->height, r->buffer);
    if (each && r->buffer)
        each(ctx, 0, 0, 0, r->width, r->height, r->buffer);
    if (r->xwindow)
        render_xwindow_done(r->xwindow, frame, r->window, r->width, r->height);
    return frame;
}

static void render_SwapBuffersTSR(void *self, GLint window, GLbitfield flags)
{
    render_spu *r = self;
    if (window == r->window) {
        render_app_fb_leave(r); /* the frame is the window's (appfbo.c) */
        render_end_frame(r, NULL, NULL);
        render_app_fb_return(r);
    }
    tsr_call_SwapBuffersTSR(r->child, window, flags);
}

size_t render_spu_tile_count(const void *instance) { return ((const render_spu *)instance)->ntiles; }

int render_spu_end_frame(void *instance, tsr_render_tile_fn each, void *ctx)
{
    render_app_fb_leave(instance);
    int frame = render_end_frame(instance, each, ctx);
    render_app_fb_return(instance);
    return frame;
}

void render_spu_size(const void *instance, int *width, int *height)
{
    const render_spu *r = instance;
    *width = r->width;
    *height = r->height;
}

/* Reads with the current context's client state saved and GL's defaults
 * set, so the client's pack and transfer state never applies. */
static void read_default_state(render_spu *r, int x, int y, int w, int h, GLenum format, GLenum type, void *pixels)
{
    GLint pack_buffer = 0;
    r->gl.GetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &pack_buffer);
    if (pack_buffer)
        r->gl.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    r->gl.PushClientAttrib(GL_CLIENT_PIXEL_STORE_BIT);
    r->gl.PushAttrib(GL_PIXEL_MODE_BIT);
    static const GLenum zero[] = {GL_PACK_ROW_LENGTH, GL_PACK_SKIP_ROWS,    GL_PACK_SKIP_PIXELS, GL_PACK_SWAP_BYTES,
                                  GL_PACK_LSB_FIRST,  GL_PACK_IMAGE_HEIGHT, GL_PACK_SKIP_IMAGES};
    for (size_t i = 0; i < sizeof zero / sizeof zero[0]; i++)
        r->gl.PixelStorei(zero[i], 0);
    r->gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    static const GLenum one[] = {GL_RED_SCALE, GL_GREEN_SCALE, GL_BLUE_SCALE, GL_ALPHA_SCALE, GL_DEPTH_SCALE};
    static const GLenum none[] = {GL_RED_BIAS, GL_GREEN_BIAS, GL_BLUE_BIAS, GL_ALPHA_BIAS, GL_DEPTH_BIAS};
    for (size_t i = 0; i < 5; i++) {
        r->gl.PixelTransferf(one[i], 1.0f);
        r->gl.PixelTransferf(none[i], 0.0f);
    }
    r->gl.PixelTransferi(GL_MAP_COLOR, GL_FALSE);
    r->gl.PixelTransferi(GL_MAP_STENCIL, GL_FALSE);
    r->gl.ReadPixels(x, y, w, h, format, type, pixels);
    r->gl.PopAttrib();
    r->gl.PopClientAttrib();
    if (pack_buffer)
        r->gl.BindBuffer(GL_PIXEL_PACK_BUFFER, (GLuint)pack_buffer);
}

int render_spu_read(void *instance, int x, int y, int w, int h, unsigned format, unsigned type, void *pixels,
                    tsr_error *err)
{
    render_spu *r = instance;
    if (x < 0 || y < 0 || w < 0 || h < 0 || x > r->width - w || y > r->height - h)
        return tsr_error_set(err, TSR_EINVAL, "%s: read [%d, %d, %d, %d] outside the %dx%d window", r->name, x, y, w, h,
                             r->width, r->height);
    if (!w || !h)
        return TSR_OK;
    render_ensure_current(r);
    if (!r->shared) {
        read_default_state(r, x, y, w, h, format, type, pixels);
        return TSR_OK;
    }
    /* Shared mode: context 0's pixel state is never a client's. */
    size_t back = r->current;
    if (render_shared_switch(r, 0, err) != TSR_OK)
        return err->code;
    r->gl.ReadPixels(x, y, w, h, format, type, pixels);
    return render_shared_switch(r, back, err);
}

void render_frame_install(render_spu *r, tsr_dispatch *table)
{
    tsr_set_WindowCreateTSR(table, render_WindowCreateTSR, r);
    tsr_set_WindowSizeTSR(table, render_WindowSizeTSR, r);
    tsr_set_SwapBuffersTSR(table, render_SwapBuffersTSR, r);
}
