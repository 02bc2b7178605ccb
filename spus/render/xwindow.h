/* spus/render/xwindow.h — render's window output (option window_output):
 * each frame shown in an X window, either a window of its own (x11: a wall
 * node's screen, with x_display, x_position, x_size, fullscreen) or drawn
 * back into the program's own window (app: the drawable the faker recorded
 * in tessera/dev/native.h, as remote-rendering tools draw into the
 * application's window). PNG output is independent: both can be on.
 *
 * Owns, per instance: its own Xlib connection, its window (x11), one
 * XImage (MIT-SHM when the server offers it and the attach succeeds, else
 * plain PutImage), and the frame's tile images until the frame ends.
 * Never: touches the program's X connection, event mask or events; keeps
 * state outside the instance; makes a frame fail (X trouble is logged, the
 * frame's PNGs are still written). */
#ifndef TSR_SPUS_RENDER_XWINDOW_H
#define TSR_SPUS_RENDER_XWINDOW_H

#include <stddef.h>

#include "tessera/spu.h"

typedef struct render_xwindow render_xwindow;

/* NULL with err clear when window_output is none; NULL with err set on a
 * bad option or an X display that cannot be opened. */
render_xwindow *render_xwindow_create(const tsr_spu_init *init, tsr_error *err);
void render_xwindow_destroy(render_xwindow *x);

/* Keeps a copy of one tile (window pixels, origin bottom-left, RGBA8
 * bottom row first) of the frame being finished; frame.c calls it for
 * each tile it reads back (or once with the whole window). */
void render_xwindow_image(render_xwindow *x, int x0, int y0, int width, int height, const unsigned char *rgba);
/* Shows the tiles kept since the last call (frame.c, at the frame's end);
 * `frame` is its number for the log, `window` the stream's window id,
 * width x height the window's size. */
void render_xwindow_done(render_xwindow *x, int frame, int window, int width, int height);

/* The options above, for render's option list. */
#define RENDER_XWINDOW_OPTION_SPECS                                                                       \
    {.name = "window_output",                                                                             \
     .type = TSR_OPT_ENUM,                                                                                \
     .default_value = "none",                                                                             \
     .choices = "none|x11|app",                                                                           \
     .help = "also show each frame in an X window: x11 a window of its own (a wall node's screen), "      \
             "app drawn back into the program's own window (under the faker: tessera exec); "             \
             "none: PNGs only"},                                                                          \
        {.name = "x_display",                                                                             \
         .type = TSR_OPT_STRING,                                                                          \
         .default_value = "",                                                                             \
         .min = 1,                                                                                        \
         .max = 0,                                                                                        \
         .help = "X display of window_output=x11 (empty: $DISPLAY); app uses the program's display"},     \
        {.name = "x_position",                                                                            \
         .type = TSR_OPT_INT_LIST,                                                                        \
         .default_value = "0,0",                                                                          \
         .min = -32768,                                                                                   \
         .max = 32767,                                                                                    \
         .help = "X,Y of window_output=x11's window on the screen"},                                      \
        {.name = "x_size",                                                                                \
         .type = TSR_OPT_INT_LIST,                                                                        \
         .default_value = "0,0",                                                                          \
         .min = 0,                                                                                        \
         .max = 32767,                                                                                    \
         .help = "W,H of window_output=x11's window; the frame is drawn at its top-left corner, "         \
                 "clipped; 0,0: the frame's size (the bounding box of the node's tiles)"},                \
        {.name = "x_title",                                                                               \
         .type = TSR_OPT_STRING,                                                                          \
         .default_value = "",                                                                             \
         .min = 1,                                                                                        \
         .max = 0,                                                                                        \
         .help = "window_output=x11: the window's title (WM_NAME; empty: the instance name, render#1)"},  \
        {.name = "fullscreen",                                                                            \
         .type = TSR_OPT_BOOL,                                                                            \
         .default_value = "false",                                                                        \
         .min = 1,                                                                                        \
         .max = 0,                                                                                        \
         .help = "window_output=x11: a window covering the screen, without decorations "                  \
                 "(override-redirect); the frame at its top-left corner"},                                \
    {                                                                                                     \
        .name = "x_shm", .type = TSR_OPT_BOOL, .default_value = "true", .min = 1, .max = 0,               \
        .help = "use MIT-SHM (XShmPutImage) when the X server offers it and shares memory with this host" \
    }

#endif
