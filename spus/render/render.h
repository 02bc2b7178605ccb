/* spus/render/render.h — what the render plugin's class (plugin.c)
 * calls of render's implementation (render.c and the files instance.h
 * lists, compiled into the plugin): create and destroy an instance, the
 * calls behind tessera/dev/render.h, and render's option list. The fuzz
 * targets that compile render's sources in (tests/fuzz.cmake) register
 * their own class with the same calls.
 *
 * Owns nothing itself: an instance is what render.c's header comment
 * describes (docs/render.md in detail). Never: reached from another SPU's
 * sources; an SPU that renders like render and does more with the frame
 * inherits it through the SPU class's super (tessera/dev/render.h). */
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

/* As a plugin's create and destroy. The instance sets its slots in
 * init->table and calls init->child with what it passes on (window, swap,
 * context and tiles commands); it makes window output (xwindow.h) when
 * window_output asks for it. */
void *render_spu_create(const tsr_spu_init *init, tsr_error *err);
void render_spu_destroy(void *instance);

/* The window's framebuffer size. */
void render_spu_size(const void *instance, int *width, int *height);
/* tessera/dev/render.h's tile_count and end_frame, which the plugin
 * publishes for its subclasses. */
size_t render_spu_tile_count(const void *instance);
int render_spu_end_frame(void *instance, tsr_render_tile_fn each, void *ctx);
/* Reads the rectangle [x, y, w, h] of the current frame (after
 * end_frame) as glReadPixels(format, type) would with GL's default
 * pixel-store and pixel-transfer state, rows packed, whatever state the
 * client set: e.g. GL_DEPTH_COMPONENT/GL_FLOAT for depth. The rectangle
 * must lie in the window. */
int render_spu_read(void *instance, int x, int y, int w, int h, unsigned format, unsigned type, void *pixels,
                    tsr_error *err);

/* render's options except window output's (xwindow.h): the plugin
 * lists both, the fuzz targets only these (no window output). */
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
