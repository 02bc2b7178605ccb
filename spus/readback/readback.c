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
 * The stream to the display is created at the first window command, image
 * or swap, not with the instance: a node builds its chain once at start-up
 * only to check it (server/node.h), and that probe must not count as one of
 * the display's clients. Failing to reach the display follows on_error,
 * like a display that fails later (pack's policy, tessera/dev/client.h): exit
 * (the default) ends the process with status 1 after one line naming the
 * display; drop logs it once and goes on, writing only the tile PNGs.
 *
 * Why render's library and not `.super = "render"` (spu.h): a super
 * instance shares the chain's child and keeps its frame to itself; the
 * tile pixels are read inside render's swap by its own reader context
 * (no client's pixel-store state applies), which no dispatch slot exposes,
 * and render would pass the node's context commands on to the display. */
#include <inttypes.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tessera/dev/client.h"
#include "render.h"
#include "tessera/chain.h"
#include "tessera/log.h"
#include "tessera/spu.h"

typedef struct readback_spu {
    char name[96];
    void *render;              /* render.h instance: draws, writes tile PNGs, calls image() */
    tsr_dispatch down;         /* render's child: the chain's child, window and swap seen here */
    const tsr_dispatch *child; /* the chain's child */
    const tsr_options *options;
    int window, rank;
    unsigned peers, barrier;
    tsr_chain *out; /* pack to the display; NULL until first needed */
    const tsr_dispatch *display;
    bool failed; /* the display could not be reached: images are dropped */
} readback_spu;

/* The options passed through to the pack SPU that carries the images. */
static const char *const pack_keys[] = {"server", "token", "buffer_size", "timeout_ms", "on_error"};
#define PACK_KEYS (sizeof pack_keys / sizeof pack_keys[0])

/* The display stream, created on first use (header comment); NULL when it
 * cannot be. */
static const tsr_dispatch *display(readback_spu *rb)
{
    if (rb->display || rb->failed)
        return rb->display;
    char numbers[2][24];
    snprintf(numbers[0], sizeof numbers[0], "%" PRId64, tsr_options_int(rb->options, "buffer_size"));
    snprintf(numbers[1], sizeof numbers[1], "%" PRId64, tsr_options_int(rb->options, "timeout_ms"));
    const char *values[PACK_KEYS] = {tsr_options_string(rb->options, "server"),
                                     tsr_options_string(rb->options, "token"), numbers[0], numbers[1],
                                     tsr_options_string(rb->options, "on_error")};
    tsr_chain_link link = {.spu = "pack", .keys = pack_keys, .values = values, .option_count = PACK_KEYS};
    tsr_error err = {0};
    rb->out = tsr_chain_create_links(&link, 1, &err);
    if (!rb->out) {
        rb->failed = true;
        tsr_log(TSR_LOG_ERROR, "%s: display %s: %s", rb->name, values[0], err.message);
        if (!strcmp(values[4], "exit")) {
            /* The failure policy of a display that fails later (pack's,
             * tessera/dev/client.h): frames that reach no display are a failed
             * run. _exit: other threads (netlib's, llvmpipe's) are running. */
            tsr_log(TSR_LOG_ERROR, "%s: ending the server (on_error=exit)", rb->name);
            fflush(NULL);
            _exit(TSR_NODE_CLIENT_EXIT_STATUS);
        }
        tsr_log(TSR_LOG_ERROR, "%s: on_error=drop: tile images are not sent", rb->name);
        return NULL;
    }
    rb->display = tsr_chain_head(rb->out);
    tsr_call_BarrierCreateTSR(rb->display, rb->barrier, rb->peers);
    return rb->display;
}

static void readback_image(void *ctx, int frame, size_t tile, int x, int y, int width, int height,
                           const unsigned char *rgba)
{
    (void)frame;
    (void)tile;
    readback_spu *rb = ctx;
    const tsr_dispatch *d = display(rb);
    if (!d)
        return;
    tsr_call_WindowPos2i(d, x, y);
    tsr_call_DrawPixels(d, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
}

static void readback_WindowCreateTSR(void *self, GLint window, GLsizei width, GLsizei height)
{
    readback_spu *rb = self;
    const tsr_dispatch *d = window == rb->window ? display(rb) : NULL;
    if (d)
        tsr_call_WindowCreateTSR(d, window, width, height);
    tsr_call_WindowCreateTSR(rb->child, window, width, height);
}

static void readback_WindowSizeTSR(void *self, GLint window, GLsizei width, GLsizei height)
{
    readback_spu *rb = self;
    const tsr_dispatch *d = window == rb->window ? display(rb) : NULL;
    if (d)
        tsr_call_WindowSizeTSR(d, window, width, height);
    tsr_call_WindowSizeTSR(rb->child, window, width, height);
}

/* render has read and sent this frame's tiles (readback_image): fence the
 * frame on the display (header comment). */
static void readback_SwapBuffersTSR(void *self, GLint window, GLbitfield flags)
{
    readback_spu *rb = self;
    const tsr_dispatch *d = window == rb->window ? display(rb) : NULL;
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
    render_spu_destroy(rb->render);
    /* No BarrierDestroyTSR: another tile server may not have reached the
     * frame's last barrier yet; the display forgets it when it ends. */
    tsr_chain_destroy(rb->out); /* sends what is left, waits for the display to run it */
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
    rb->child = init->child;
    rb->options = init->options;
    rb->window = (int)tsr_options_int(init->options, "window");
    rb->rank = (int)tsr_options_int(init->options, "rank");
    rb->peers = (unsigned)tsr_options_int(init->options, "peers");
    rb->barrier = (unsigned)tsr_options_int(init->options, "barrier");
    const char *server = tsr_options_string(init->options, "server");
    if (!server || !server[0]) {
        tsr_error_set(err, TSR_EINVAL,
                      "%s: option server is required: the display node (e.g. server=tcp://127.0.0.1:7000)", rb->name);
        free(rb);
        return NULL;
    }
    /* render passes what it does not keep to `down`: the chain's child,
     * with the window and swap commands seen here first. */
    rb->down = *init->child;
    tsr_set_WindowCreateTSR(&rb->down, readback_WindowCreateTSR, rb);
    tsr_set_WindowSizeTSR(&rb->down, readback_WindowSizeTSR, rb);
    tsr_set_SwapBuffersTSR(&rb->down, readback_SwapBuffersTSR, rb);
    tsr_spu_init render_init = *init;
    render_init.child = &rb->down;
    render_hooks hooks = {.image = readback_image, .ctx = rb};
    rb->render = render_spu_create(&render_init, &hooks, err);
    if (!rb->render) {
        free(rb);
        return NULL;
    }
    return rb;
}

static const tsr_option_spec readback_options[] = {
    RENDER_OPTION_SPECS,
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
