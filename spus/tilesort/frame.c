/* spus/tilesort/frame.c — frames and the window: swaps, window commands,
 * and the window's pixels gathered back from the tiles.
 *
 * A swap or window command goes to every server and is flushed at once
 * (tilesort.c routes the other frame commands, Clear, Finish, barriers,
 * semaphores, the same way). The window's size places the tiles (and the
 * load balancer's first split); each swap closes the frame's statistics
 * and lets the load balancer re-split (bucket.c). Fixed pixel tiles are
 * checked against the window at each swap and read of pixels, not when
 * the window is made or resized: a program may open a small window and
 * grow it before it draws. glReadPixels is gathered
 * from every server whose tiles meet the rectangle; with assemble= the
 * whole window is gathered so before each swap and written as a PNG.
 *
 * Owns the window size and the frame count. Never reads pixels back before
 * the pending geometry is flushed: the servers must have drawn all the
 * application drew before the read. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "instance.h"
#include "tessera/dev/protocol.h"
#include "tessera/image.h"
#include "tessera/log.h"

static void frame_command_done(tilesort *t) { ts_flush_geometry(t); }

static void window_size(tilesort *t, GLsizei w, GLsizei h)
{
    if (w == t->win_w && h == t->win_h)
        return;
    t->win_w = w;
    t->win_h = h;
    char why[400];
    if (t->grid_cols) {
        tsr_error gerr = {0};
        if (ts_tiling_grid(&t->tiling, t->grid_cols, t->grid_rows, w, h, t->name, &gerr) != TSR_OK) {
            tsr_log(TSR_LOG_ERROR, "%s", gerr.message);
            tsr_stream_client_exit();
        }
    }
    /* Fixed tiles are checked against the window when a frame's pixels
     * are used (tiles_fit), not here: a program may open a small window
     * and resize it before it draws (glretrace opens 32x32 and resizes to
     * the trace's size). */
    t->tiles_misfit[0] = '\0';
    if (ts_tiling_window(&t->tiling, w, h, why, sizeof why) != 0)
        snprintf(t->tiles_misfit, sizeof t->tiles_misfit, "%s", why);
    t->tiling_version++;
}

/* At a swap or a read of pixels: fixed tiles reaching outside the window
 * end the application. A wall cropped or misplaced without a word is
 * worse than no wall: it ends as on a failed server (on_error), before
 * any tile of the frame is shown or written. */
static void tiles_fit(tilesort *t)
{
    if (!t->tiles_misfit[0])
        return;
    tsr_log(TSR_LOG_ERROR, "%s: %s", t->name, t->tiles_misfit);
    tsr_stream_client_exit();
}

/* A window command goes to every server at once; the window's size then
 * places the tiles (and the load balancer's first split). */
static void window_command(tilesort *t, tsr_entry entry, GLint window, GLsizei w, GLsizei h)
{
    ts_broadcast_next(t);
    ((tsr_fn_WindowSizeTSR)entry.fn)(entry.self, window, w, h);
    frame_command_done(t);
    window_size(t, w, h);
}

void ts_WindowCreateTSR(void *self, GLint window, GLsizei w, GLsizei h)
{
    tilesort *t = self;
    window_command(t, t->geo_table.WindowCreateTSR, window, w, h);
}

void ts_WindowSizeTSR(void *self, GLint window, GLsizei w, GLsizei h)
{
    tilesort *t = self;
    window_command(t, t->geo_table.WindowSizeTSR, window, w, h);
}

/* Each server answers for its own tiles; pixels outside every tile come
 * from the first server's answer. A program FBO bound (and not `window`):
 * every server holds all of it (fbo.c), the first one answers. */
static void gather_pixels(tilesort *t, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type, void *pixels,
                          int window)
{
    if (t->app_read_fb && !window) {
        tsr_call_ReadPixels(&ts_to_server(t)->table, x, y, w, h, format, type, pixels);
        return;
    }
    tiles_fit(t);
    ts_flush_geometry(t);
    const tsr_pixel_modes *pack = &tsr_state_values_of(t->ctx)->pixel_store.pack;
    tsr_pixel_layout l;
    /* (into a GL_PIXEL_PACK_BUFFER: pack_buffer.c, before this) */
    if (w <= 0 || h <= 0 || !pixels || tsr_pixel_layout_of(pack, 2, w, h, 1, format, type, &l) != 0 ||
        l.group_bytes == 0) {
        ts_server *s = ts_to_server(t);
        tsr_call_ReadPixels(&s->table, x, y, w, h, format, type, pixels);
        return;
    }
    uint8_t *tmp = malloc((size_t)l.extent);
    if (!tmp) {
        tsr_error e;
        tsr_error_set(&e, TSR_ENOMEM, "out of memory for glReadPixels (%d x %d)", (int)w, (int)h);
        ts_report(t, &e);
        return;
    }
    int first = 1;
    for (size_t i = 0; i < t->nservers; i++) {
        ts_server *s = &t->srv[i];
        if (tsr_stream_client_server_failed(t->client, i))
            continue;
        int meets = first;
        for (size_t k = 0; k < t->tiling.ntiles[i] && !meets; k++) {
            const ts_rect *r = &t->tiling.tiles[i][k];
            meets = r->x < x + w && x < r->x + r->w && r->y < y + h && y < r->y + r->h;
        }
        if (!meets)
            continue;
        ts_prepare_server(t, s, 0);
        tsr_call_ReadPixels(&s->table, x, y, w, h, format, type, tmp);
        if (first) {
            tsr_pixel_copy_spans(&l, h, 1, pixels, tmp);
            first = 0;
        }
        for (size_t k = 0; k < t->tiling.ntiles[i]; k++) {
            const ts_rect *r = &t->tiling.tiles[i][k];
            int cx0 = r->x > x ? r->x : x, cy0 = r->y > y ? r->y : y;
            int cx1 = r->x + r->w < x + w ? r->x + r->w : x + w, cy1 = r->y + r->h < y + h ? r->y + r->h : y + h;
            /* a tile beside the rectangle (the first server's always
             * answers) shares rows with it but no columns: nothing to
             * copy, not a row of negative width */
            if (cx1 <= cx0 || cy1 <= cy0)
                continue;
            for (int row = cy0; row < cy1; row++) {
                size_t at = (size_t)(l.first + (uint64_t)(row - y) * l.row_bytes + (uint64_t)(cx0 - x) * l.group_bytes);
                memcpy((uint8_t *)pixels + at, tmp + at, (size_t)((uint64_t)(cx1 - cx0) * l.group_bytes));
            }
        }
    }
    free(tmp);
}

void ts_ReadPixels(void *self, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type, void *pixels)
{
    if (!ts_pack_buffer_read_pixels(self, x, y, w, h, format, type, pixels))
        gather_pixels(self, x, y, w, h, format, type, pixels, 0);
}

/* Every live server's window (1) or the program's FBOs again (0), for
 * assemble=: its servers' own packers, sent before anything else reaches
 * them (ts_prepare_server flushes them first). */
static void bind_window(tilesort *t, int window)
{
    for (size_t i = 0; i < t->nservers; i++)
        if (!tsr_stream_client_server_failed(t->client, i)) {
            tsr_call_BindFramebufferEXT(&t->srv[i].table, GL_DRAW_FRAMEBUFFER, window ? 0 : t->app_fb);
            tsr_call_BindFramebufferEXT(&t->srv[i].table, GL_READ_FRAMEBUFFER, window ? 0 : t->app_read_fb);
        }
}

static void assemble_frame(tilesort *t)
{
    if (!t->assemble || t->win_w <= 0)
        return;
    /* read as RGBA bytes under the application's pack modes (the servers
     * hold them), then take the rows out tightly */
    const tsr_pixel_modes *pack = &tsr_state_values_of(t->ctx)->pixel_store.pack;
    tsr_pixel_layout l;
    if (tsr_pixel_layout_of(pack, 2, t->win_w, t->win_h, 1, GL_RGBA, GL_UNSIGNED_BYTE, &l) != 0)
        return;
    uint8_t *raw = calloc(1, (size_t)l.extent), *img = malloc((size_t)t->win_w * (size_t)t->win_h * 4);
    if (raw && img) {
        if (t->app_fb || t->app_read_fb) /* the frame is the window's, not the bound FBOs' */
            bind_window(t, 1);
        /* into client memory, whatever pack buffer the program has bound */
        GLuint pack_buffer = tsr_state_values_of(t->ctx)->pixel_pack_buffer;
        if (pack_buffer)
            tsr_call_BindBuffer(&t->normal, GL_PIXEL_PACK_BUFFER, 0);
        gather_pixels(t, 0, 0, t->win_w, t->win_h, GL_RGBA, GL_UNSIGNED_BYTE, raw, 1);
        if (pack_buffer)
            tsr_call_BindBuffer(&t->normal, GL_PIXEL_PACK_BUFFER, pack_buffer);
        if (t->app_fb || t->app_read_fb)
            bind_window(t, 0);
        for (int r = 0; r < t->win_h; r++)
            memcpy(img + (size_t)r * (size_t)t->win_w * 4, raw + l.first + (size_t)r * l.row_bytes,
                   (size_t)t->win_w * 4);
        char path[4096];
        tsr_error err = {0};
        size_t stride = (size_t)t->win_w * 4;
        if (tsr_image_frame_path(path, sizeof path, t->assemble, (int)t->frames, &err) != TSR_OK ||
            tsr_image_write_png_pixels(img, t->win_w, t->win_h, stride, true, t->assemble_alpha, path, &err) != TSR_OK)
            ts_report(t, &err);
    }
    free(raw);
    free(img);
}

void ts_SwapBuffersTSR(void *self, GLint window, GLbitfield flags)
{
    tilesort *t = self;
    tiles_fit(t);
    ts_flush_geometry(t);
    assemble_frame(t);
    t->broadcast_next = 1;
    /* each server is asked for its frame's render time (it comes back
     * with a later message: tessera/dev/protocol.h): the balanced modes'
     * cost, and every mode's statistics */
    tsr_call_SwapBuffersTSR(&t->geo_table, window, flags | TSR_NODE_SWAP_REPORT_COST);
    ts_flush_geometry(t);
    t->frames++;
    tsr_stream_client_count_frame(t->client);
    ts_keep_frame_row(t);
    for (size_t i = 0; i < t->nservers; i++) {
        t->srv[i].bytes += t->srv[i].frame_bytes;
        t->srv[i].frame_bytes = 0;
    }
    if (ts_tiling_rebalance(&t->tiling, t->frame_geometry))
        t->tiling_version++;
    memset(t->frame_geometry, 0, t->nservers * sizeof *t->frame_geometry);
    tsr_stream_client_take_costs(t->client);
}
