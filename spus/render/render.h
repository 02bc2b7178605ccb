/* spus/render/render.h — the render SPU's implementation as a library
 * (tessera_render_core, static), shared by the `render` plugin (plugin.c)
 * and the SPUs that render exactly like it and then do more with the
 * frame (`readback`, spus/readback). Owns nothing itself: an instance is
 * what render.c's header comment describes (docs/render.md in detail).
 * Never to be copied: an SPU that needs render's drawing links this
 * library and passes hooks.
 *
 * Hooks: `image` is called at every swap of the instance's window, after
 * the frame's pixels were read and written out (PNGs), before the swap
 * goes on to the child: once per owned tile (its rectangle in window
 * pixels, origin bottom-left, and its RGBA8 pixels, bottom row first,
 * rows packed), or once with the whole window when there are no tiles.
 * The pixels are valid during the call only.
 *
 * `frame` is called at every swap of the instance's window when it has no
 * tiles, after the frame was finished and written out, before `image`:
 * the place to read more of the frame than its colour (depth, a region)
 * with render_spu_read while the frame is still in the framebuffer.
 *
 * `done` is called at every swap of the instance's window after the last
 * `image` of the frame, with the stream's window id and the window's size
 * (window output shows the frame's tiles then, spus/render/xwindow.h). */
#ifndef TSR_SPUS_RENDER_RENDER_H
#define TSR_SPUS_RENDER_RENDER_H

#include <stddef.h>

#include "tessera/dev/render.h"
#include "tessera/spu.h"

#define RENDER_MAX_SIDE 16384

/* Per-client budgets (docs/render.md, "Budgets"): defaults with room for
 * every example and benchmark (4096x3072 walls, 1920x1080 sort-last). */
#define RENDER_DEFAULT_MAX_TEXTURE_BYTES "536870912"
#define RENDER_DEFAULT_MAX_WINDOW_PIXELS "16777216"

typedef struct render_hooks {
    void (*image)(void *ctx, int frame, size_t tile, int x, int y, int width, int height, const unsigned char *rgba);
    void (*frame)(void *ctx, int frame, void *render);
    void (*done)(void *ctx, int frame, int window, int width, int height);
    void *ctx;
} render_hooks;

/* As a plugin's create and destroy; `hooks` may be NULL. The instance
 * sets its slots in init->table and calls init->child with what it passes
 * on (window, swap, context and tiles commands). */
void *render_spu_create(const tsr_spu_init *init, const render_hooks *hooks, tsr_error *err);
void render_spu_destroy(void *instance);

/* The window's framebuffer size. */
void render_spu_size(const void *instance, int *width, int *height);
/* tessera/dev/render.h's tile_count and end_frame, which the plugin
 * publishes for its subclasses. */
size_t render_spu_tile_count(const void *instance);
int render_spu_end_frame(void *instance, tsr_render_tile_fn each, void *ctx);
/* Reads the rectangle [x, y, w, h] of the current frame (from a `frame`
 * hook) as glReadPixels(format, type) would with GL's default pixel-store
 * and pixel-transfer state, rows packed, whatever state the client set:
 * e.g. GL_DEPTH_COMPONENT/GL_FLOAT for depth. The rectangle must lie in
 * the window. */
int render_spu_read(void *instance, int x, int y, int w, int h, unsigned format, unsigned type, void *pixels,
                    tsr_error *err);

/* render's options; an SPU built on it lists them among its own. */
#define RENDER_OPTION_SPECS                                                                    \
    {.name = "output",                                                                         \
     .type = TSR_OPT_STRING,                                                                   \
     .default_value = "",                                                                      \
     .min = 1,                                                                                 \
     .max = 0,                                                                                 \
     .help = "PNG file per frame, one %d for the frame number (out/f-%04d.png); "              \
             "the directory must exist; each file is written whole under a temporary "         \
             "name and renamed; a name without %d is refused unless output_overwrite=1; "      \
             "empty: write nothing"},                                                          \
        {.name = "output_overwrite",                                                           \
         .type = TSR_OPT_BOOL,                                                                 \
         .default_value = "false",                                                             \
         .min = 1,                                                                             \
         .max = 0,                                                                             \
         .help = "allow an output name without %d: every frame replaces the one file, "        \
                 "which holds the last frame"},                                                \
        {.name = "output_alpha",                                                               \
         .type = TSR_OPT_BOOL,                                                                 \
         .default_value = "false",                                                             \
         .min = 1,                                                                             \
         .max = 0,                                                                             \
         .help = "write the framebuffer's alpha into the PNGs (RGBA, e.g. for sort-last "      \
                 "alpha layers); false: RGB, what the window shows"},                          \
        {.name = "width",                                                                      \
         .type = TSR_OPT_INT,                                                                  \
         .default_value = "0",                                                                 \
         .min = 0,                                                                             \
         .max = RENDER_MAX_SIDE,                                                               \
         .help = "framebuffer width; 0: follow the window (512 until it is known)"},           \
        {.name = "height",                                                                     \
         .type = TSR_OPT_INT,                                                                  \
         .default_value = "0",                                                                 \
         .min = 0,                                                                             \
         .max = RENDER_MAX_SIDE,                                                               \
         .help = "framebuffer height; 0: follow the window (512 until it is known)"},          \
        {.name = "window",                                                                     \
         .type = TSR_OPT_INT,                                                                  \
         .default_value = "0",                                                                 \
         .min = 0,                                                                             \
         .max = 2147483647.0,                                                                  \
         .help = "window id whose WindowCreate/Size/SwapBuffers this instance follows"},       \
        {.name = "max_texture_bytes",                                                          \
         .type = TSR_OPT_INT,                                                                  \
         .default_value = RENDER_DEFAULT_MAX_TEXTURE_BYTES,                                    \
         .min = 0,                                                                             \
         .max = 9.0e15,                                                                        \
         .help = "texture bytes each context (each client of a shared node) may hold; "        \
                 "a TexImage beyond it fails that client's stream; 0: no limit"},              \
        {.name = "max_window_pixels",                                                          \
         .type = TSR_OPT_INT,                                                                  \
         .default_value = RENDER_DEFAULT_MAX_WINDOW_PIXELS,                                    \
         .min = 0,                                                                             \
         .max = 268435456.0,                                                                   \
         .help = "largest window (width x height) the stream may ask for with "                \
                 "WindowCreateTSR/WindowSizeTSR; beyond it fails the stream; 0: 16384x16384"}, \
        {.name = "fast_drawpixels",                                                            \
         .type = TSR_OPT_BOOL,                                                                 \
         .default_value = "true",                                                              \
         .min = 1,                                                                             \
         .max = 0,                                                                             \
         .help = "draw RGBA8 DrawPixels, and scissored colour Clears, as a texture upload "    \
                 "and framebuffer blit when the GL state makes that identical (no fragment "   \
                 "operations, zoom 1, default pixel transfer); false: always glDrawPixels "    \
                 "and glClear"},                                                               \
    {                                                                                          \
        .name = "tiles", .type = TSR_OPT_STRING, .default_value = "", .min = 1, .max = 0,      \
        .help = "rectangles of the window this server owns, X:Y:W:H,X:Y:W:H (a graph node's "  \
                "tiles:); draws them at full-window coordinates, writes one PNG per tile "     \
                "(-tN before the extension when several); a TilesTSR replaces them; empty: "   \
                "the whole window"                                                             \
    }

#endif
