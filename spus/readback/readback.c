/* spus/readback — a tile server that renders exactly like `render` (it IS
 * render: spus/render's implementation, render.h, with a hook) and after
 * every frame streams the images of its tiles to a display node, as
 * Chromium's readback SPU did. Owns, per instance: the render instance, the
 * stream to the display (a `pack` chain of its own) and the frame protocol
 * below. Never sends the display anything but window commands, images,
 * barriers and swaps (the server's own context commands stay here).
 *
 * The display node is an ordinary server (`tessera node`, shared mode,
 * server/node.h) whose chain draws: every tile server is one of its
 * clients, drawing into one shared window through a context of its own.
 * Per frame each tile server sends, for each tile, WindowPos2i(x, y) and
 * DrawPixels(w, h, RGBA, UNSIGNED_BYTE): with the display context's
 * default state (no zoom, no pixel transfer, no fragment operations) the
 * pixels land unchanged, so the assembled window is bit-identical to the
 * tiles, which are bit-identical to a full-window render. Then:
 *   BarrierExecTSR(barrier)   every tile of the frame has arrived;
 *   SwapBuffersTSR            from rank 0 only: the display writes the frame;
 *   BarrierExecTSR(barrier)   no tile of the next frame is drawn before that.
 * The barrier is created once, before the first image, for `peers`
 * clients (0: every client of the display node). Ranks other than 0 send
 * no swap: the display's node would drop them anyway (only one client's
 * swaps end frames), but sending none keeps which one counts fixed.
 *
 * The stream to the display (spus/display_stream, shared with binaryswap) is
 * created at the first window command, image or swap, not with the
 * instance. Failing to reach the display follows on_error,
 * like a display that fails later (pack's policy, tessera/dev/client.h): exit
 * (the default) ends the process with status 1 after one line naming the
 * display; drop logs it once and goes on, writing only the tile PNGs.
 *
 * How it is render: its class's super is render (tessera/spu.h), so every
 * GL call it does not take goes to a render instance of its own, which
 * draws, owns the tiles and writes the tile PNGs. It takes the window
 * commands (the display follows the window) and the swap of render's
 * window: render ends the frame (tessera/dev/render.h, end_frame) and
 * hands over each tile it reads back; this SPU sends them, fences the
 * frame on the display and passes the swap on. */
#include <stdio.h>
#include <stdlib.h>

#include "display_stream.h"
#include "tessera/dev/client.h"
#include "tessera/dev/render.h"
#include "tessera/log.h"
#include "tessera/spu.h"

typedef struct readback_spu {
    char name[96];
    const tsr_render_api *render_api; /* the super's (tessera/dev/render.h) */
    void *render;                     /* the super instance: draws, writes tile PNGs */
    const tsr_dispatch *super;        /* its table */
    const tsr_dispatch *child;        /* the chain's child */
    int window, rank;
    unsigned barrier;
    display_stream display; /* the stream to the display */
} readback_spu;

/* One tile of the frame render ends (tsr_render_tile_fn) to the display. */
static void readback_tile(void *ctx, size_t tile, int x, int y, int width, int height, const unsigned char *rgba)
{
    (void)tile;
    readback_spu *rb = ctx;
    const tsr_dispatch *d = display_stream_get(&rb->display);
    if (!d)
        return;
    tsr_call_WindowPos2i(d, x, y);
    tsr_call_DrawPixels(d, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
}

/* render ends the frame and hands over its tiles (readback_tile); then
 * the frame is fenced on the display (header comment) and the swap goes
 * on. Another window's swap is render's alone. */
static void readback_SwapBuffersTSR(void *self, GLint window, GLbitfield flags)
{
    readback_spu *rb = self;
    if (window != rb->window) {
        tsr_call_SwapBuffersTSR(rb->super, window, flags);
        return;
    }
    rb->render_api->end_frame(rb->render, readback_tile, rb);
    const tsr_dispatch *d = display_stream_get(&rb->display);
    if (d) {
        tsr_call_BarrierExecTSR(d, rb->barrier);
        if (rb->rank == 0)
            tsr_call_SwapBuffersTSR(d, window, flags);
        tsr_call_BarrierExecTSR(d, rb->barrier);
    }
    tsr_call_SwapBuffersTSR(rb->child, window, flags);
}

static void readback_destroy(void *self)
{
    readback_spu *rb = self;
    if (!rb)
        return;
    /* No BarrierDestroyTSR: another tile server may not have reached the
     * frame's last barrier yet; the display forgets it when it ends. */
    display_stream_close(&rb->display); /* sends what is left, waits for the display to run it */
    free(rb);
}

static void *readback_create(const tsr_spu_init *init, tsr_error *err)
{
    readback_spu *rb = calloc(1, sizeof *rb);
    if (!rb) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    snprintf(rb->name, sizeof rb->name, "%s", init->instance_name);
    if (!(rb->render_api = tsr_render_api_of(init, err))) {
        free(rb);
        return NULL;
    }
    rb->render = init->super_instance;
    rb->super = init->super;
    rb->child = init->child;
    rb->window = (int)tsr_options_int(init->options, "window");
    rb->rank = (int)tsr_options_int(init->options, "rank");
    rb->barrier = (unsigned)tsr_options_int(init->options, "barrier");
    rb->display = (display_stream){.name = rb->name,
                                   .options = init->options,
                                   .address_option = "server",
                                   .window = rb->window,
                                   .barrier = rb->barrier,
                                   .barrier_clients = (unsigned)tsr_options_int(init->options, "peers"),
                                   .child = init->super,
                                   .on_failure = display_stream_on_error};
    rb->display.ctx = &rb->display;
    const char *server = tsr_options_string(init->options, "server");
    if (!server || !server[0]) {
        tsr_error_set(err, TSR_EINVAL,
                      "%s: option server is required: the display node (e.g. server=tcp://127.0.0.1:7000)", rb->name);
        free(rb);
        return NULL;
    }
    /* The window commands reach the display first, then render; the
     * rest of the stream is render's (the slots left empty). */
    display_stream_follow_window(&rb->display, init->table);
    tsr_set_SwapBuffersTSR(init->table, readback_SwapBuffersTSR, rb);
    return rb;
}

static const tsr_option_spec readback_options[] = {
    /* render's option (the super gets it too), declared here as well so a
     * graph run fills it: network.tiles names an option of this class. */
    {.name = "tiles",
     .type = TSR_OPT_STRING,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "rectangles of the window this server owns, X:Y:W:H,... (a graph node's tiles:): render, "
             "its super, draws them and sends each to the display; empty: the whole window"},
    {.name = "server",
     .type = TSR_OPT_STRING,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "the display node the tile images go to: tcp://HOST:PORT or unix:PATH (required; "
             "a graph's to: fills it)"},
    {.name = "rank",
     .type = TSR_OPT_INT,
     .default_value = "0",
     .min = 0,
     .max = 2147483647.0,
     .help = "this server's place among the display's clients: rank 0 sends the swap that ends "
             "each frame (a graph run sets it: the display's first sender is 0)"},
    {.name = "peers",
     .type = TSR_OPT_INT,
     .default_value = "0",
     .min = 0,
     .max = 2147483647.0,
     .help = "clients of the frame barrier on the display; 0: every client of the display node"},
    {.name = "barrier",
     .type = TSR_OPT_INT,
     .default_value = "1380073291",
     .min = 0,
     .max = 4294967295.0,
     .help = "name of the frame barrier on the display (every tile server must use the same)"},
    TSR_NODE_CLIENT_OPTION_SPECS, /* passed on to the pack stream to the display */
};

static const tsr_spu_class readback_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "readback",
    .super = "render",
    .summary = "renders like render (tiles, tile PNGs), then streams each frame's tile images "
               "to a display node that assembles the window",
    .options = readback_options,
    .option_count = sizeof readback_options / sizeof readback_options[0],
    .create = readback_create,
    .destroy = readback_destroy,
    /* A tile server sending its images to one display: `server` is the
     * display's address, `tiles` this node's own tiles (render draws them)
     * and `rank` its place among the display's senders (rank 0 swaps).
     * `peers` here counts the barrier's clients: not the role's peers. */
    .network = {.role = TSR_SPU_ROLE_DISPLAY,
                .display = "server",
                .tiles = "tiles",
                .rank = "rank",
                .token = TSR_NODE_CLIENT_TOKEN_OPTION},
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &readback_class; }
