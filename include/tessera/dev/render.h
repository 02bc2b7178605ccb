/* tessera/dev/render.h — what an SPU that inherits render
 * (`.super = "render"`, tessera/spu.h) may ask of its super instance
 * beyond the dispatch table: the window's size, its tiles, ending a frame
 * without passing the swap on, and reading the finished frame. render's
 * class publishes it as tsr_spu_class.api; a subclass finds it in
 * tsr_spu_init.super_api (tsr_render_api_of below) and calls it with
 * tsr_spu_init.super_instance. readback and binaryswap are built this way.
 *
 * The pattern: the subclass leaves every GL call to render (the slots it
 * does not set fall through to its super) and sets SwapBuffersTSR. For
 * render's window (option `window`) it calls end_frame, does what it
 * does with the frame (read, send), then passes the swap to init->child
 * itself; for any other window it calls init->super's SwapBuffersTSR.
 *
 * Owns nothing. Never: a pixel read here sees a client's pixel-store,
 * pixel-transfer or pack-buffer state; the functions are called from the
 * thread that draws into the instance. */
#ifndef TESSERA_DEV_RENDER_H
#define TESSERA_DEV_RENDER_H

#include <stddef.h>
#include <stdint.h>

#include "tessera/error.h"
#include "tessera/spu.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Bumped when a member changes; members are only ever appended. */
#define TSR_RENDER_API_VERSION 1u

/* One tile of the frame: its rectangle in window pixels (origin
 * bottom-left) and its RGBA8 pixels, bottom row first, rows packed; valid
 * during the call only. `tile` is its index in the instance's tiles. */
typedef void (*tsr_render_tile_fn)(void *ctx, size_t tile, int x, int y, int width, int height,
                                   const unsigned char *rgba);

typedef struct tsr_render_api {
    uint32_t version; /* TSR_RENDER_API_VERSION of the render that filled it */
    /* The window's framebuffer size. */
    void (*window_size)(const void *render, int *width, int *height);
    /* How many tiles the instance owns (option tiles, or the last
     * TilesTSR); 0: it draws the whole window. */
    size_t (*tile_count)(const void *render);
    /* Ends the frame of render's window as its SwapBuffersTSR does (waits
     * for the drawing, writes the PNGs, shows window output) but does not
     * pass the swap on. With `each`, hands it every owned tile as read
     * back (or the whole window once when there are none). Returns the
     * frame's number, from 0. The frame stays in the framebuffer for
     * `read` until the next drawing command. */
    int (*end_frame)(void *render, tsr_render_tile_fn each, void *ctx);
    /* Reads the rectangle [x, y, w, h] of the frame as glReadPixels(format,
     * type) would with GL's default pixel-store and transfer state, rows
     * packed (e.g. GL_DEPTH_COMPONENT/GL_FLOAT for depth). The rectangle
     * must lie in the window. */
    int (*read)(void *render, int x, int y, int w, int h, unsigned format, unsigned type, void *pixels, tsr_error *err);
} tsr_render_api;

/* The api of init's super, checked: NULL with `err` naming the instance
 * when its super is not render (or a render too old for this header). */
static inline const tsr_render_api *tsr_render_api_of(const tsr_spu_init *init, tsr_error *err)
{
    const tsr_render_api *api = (const tsr_render_api *)init->super_api;
    if (!api || !init->super_instance || api->version < TSR_RENDER_API_VERSION) {
        tsr_error_set(err, TSR_EINVAL, "%s: its super SPU is not a render of API %u", init->instance_name,
                      (unsigned)TSR_RENDER_API_VERSION);
        return NULL;
    }
    return api;
}

#ifdef __cplusplus
}
#endif
#endif
