/* spus/binaryswap — one peer of a sort-last compositing group: renders
 * exactly like `render` (it IS render: its class's super, tessera/spu.h,
 * so every GL call goes to a render instance of its own), and at every
 * SwapBuffers of its window, once render ended the frame
 * (tessera/dev/render.h), reads back the
 * colour and depth of its region of interest, composites it with its
 * peers' images, and the group's final frame goes to a display node (an
 * ordinary `tessera node` whose render chain writes the PNG). Owns, per
 * instance: the peer connections (netlib, one
 * tsr_net), the stream to the display (a `pack` chain of its own), the
 * read-back and frame buffers. Never: keeps state outside the instance,
 * sends the display anything but the window, its final piece (colour and
 * scissored clears), the frame's barriers and (rank 0) the swap,
 * or sends a peer a full frame of background (an empty peer's image is a
 * header).
 *
 * Files: instance.h lists them; this one creates the instance (options,
 * the group, the strategy asked for) and holds the class. */
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "instance.h"
#include "layers.h"
#include "synthetic.h"
#include "tessera/dev/client.h"
#include "tessera/log.h"

/* Alpha mode: the application's clear colour is the background the
 * display adds once; the peer itself clears to transparent black, so its
 * layer holds only what it drew. */
static void binaryswap_ClearColor(void *self, GLfloat red, GLfloat green, GLfloat blue, GLfloat alpha)
{
    binaryswap_spu *b = self;
    if (b->mode == TSR_COMPOSITE_ALPHA) {
        b->clear[0] = red;
        b->clear[1] = green;
        b->clear[2] = blue;
        b->clear[3] = alpha;
        red = green = blue = alpha = 0.0f;
    }
    ((tsr_fn_ClearColor)b->gl_clear_color.fn)(b->gl_clear_color.self, red, green, blue, alpha);
}

/* synthetic=: the generated layer replaces the framebuffer, so a clear
 * of it is work no pixel of the frame shows; rasterised at the frame's
 * finish, a full-window clear on each of 8 peers took the CPU the peers
 * composite with (bench/README.md). */
static void binaryswap_Clear_synthetic(void *self, GLbitfield mask)
{
    (void)self;
    (void)mask;
}

/* Alpha mode is exact only with a schedule that blends each pixel's layers
 * back to front in one place (tsr_composite_schedule_keeps_order): auto picks
 * among those, an explicit strategy that regroups the blend is refused.
 * The shape of a schedule depends on the peer count, not the window. */
static int alpha_strategy(binaryswap_spu *b, tsr_error *err)
{
    tsr_composite_schedule s;
    char why[160];
    int kind = b->kind == TSR_COMPOSITE_AUTO && b->nranks > 8 ? TSR_COMPOSITE_DIRECT : b->kind;
    if (tsr_composite_plan(kind, b->nranks, 64, 64, b->k, NULL, &s, err) != TSR_OK)
        return err->code;
    int ok = tsr_composite_schedule_keeps_order(&s, why, sizeof why);
    tsr_composite_schedule_free(&s);
    if (!ok)
        return tsr_error_set(err, TSR_EINVAL,
                             "mode=alpha with strategy %s for %d peers: %s; 8-bit and float rounding make that differ "
                             "from the back-to-front blend, use direct, gather or auto",
                             tsr_options_string(b->options, "strategy"), b->nranks, why);
    b->kind = kind;
    return TSR_OK;
}

static void window_size(void *ctx, int *w, int *h)
{
    binaryswap_spu *b = ctx;
    b->render_api->window_size(b->render, w, h);
}

/* render ends the frame of the peer's window, the peer composites it,
 * then the swap goes on (as render's own swap would pass it); another
 * window's swap is render's alone. */
static void binaryswap_SwapBuffersTSR(void *self, GLint window, GLbitfield flags)
{
    binaryswap_spu *b = self;
    if (window != b->window) {
        tsr_call_SwapBuffersTSR(b->super, window, flags);
        return;
    }
    int frame = b->render_api->end_frame(b->render, NULL, NULL);
    if (!b->render_api->tile_count(b->render))
        binaryswap_frame(b, frame);
    tsr_call_SwapBuffersTSR(b->child, window, flags);
}

/* The slots render (the super) implements itself, copied into `table`:
 * the region of interest wraps them as it wraps what it sees drawn. */
static void take_super_slots(tsr_dispatch *table, const tsr_dispatch *super, const tsr_dispatch *child)
{
    for (size_t i = 0; i < TSR_DISPATCH_COUNT; i++)
        if (super->slots[i].fn != child->slots[i].fn || super->slots[i].self != child->slots[i].self)
            table->slots[i] = super->slots[i];
}

static void binaryswap_destroy(void *self)
{
    binaryswap_spu *b = self;
    if (!b)
        return;
    binaryswap_roi_destroy(b->roi);
    binaryswap_release_held(b);
    display_stream_close(&b->display); /* sends what is left, waits for the display to run it */
    binaryswap_log_transport_stats(b);
    free(b->local_building);
    for (int i = 0; i < b->nranks; i++)
        if (b->conns[i])
            tsr_net_conn_close(b->conns[i]);
    if (b->listener)
        tsr_net_listener_close(b->listener);
    tsr_net_destroy(b->net);
    for (local_msg *m = b->local_head, *next; m; m = next) {
        next = m->next;
        free(m);
    }
    tsr_composite_executor_free(b->peer_ex);
    tsr_composite_executor_free(b->display_ex);
    if (b->plan.kind)
        tsr_composite_schedule_free(&b->plan);
    tsr_composite_image_free(&b->mine);
    tsr_composite_image_free(&b->frame);
    tsr_composite_image_free(&b->piece);
    tsr_composite_sparse_free(&b->placed);
    tsr_composite_sparse_free(&b->row);
    binaryswap_bands_free(&b->bands);
    tsr_composite_image_free(&b->layer);
    free(b->frame8);
    free(b->window_depth);
    if (b->stats_fd >= 0)
        close(b->stats_fd);
    free(b);
}

static void *binaryswap_create(const tsr_spu_init *init, tsr_error *err)
{
    binaryswap_spu *b = calloc(1, sizeof *b);
    if (!b) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    snprintf(b->name, sizeof b->name, "%s", init->instance_name);
    b->stats_fd = -1;
    if (!(b->render_api = tsr_render_api_of(init, err))) {
        free(b);
        return NULL;
    }
    b->render = init->super_instance;
    b->super = init->super;
    b->child = init->child;
    b->options = init->options;
    b->window = (int)tsr_options_int(init->options, "window");
    b->rank = (int)tsr_options_int(init->options, "rank");
    b->timeout_ms = (int)tsr_options_int(init->options, "timeout_ms");
    size_t npeers = tsr_options_count(init->options, "peers");
    size_t nexchange = tsr_options_count(init->options, "exchange");
    const char *display_address = tsr_options_string(init->options, "display");
    const char *mode = tsr_options_string(init->options, "mode");
    const char *strategy = tsr_options_string(init->options, "strategy");
    if (!display_address || !display_address[0]) {
        tsr_error_set(err, TSR_EINVAL,
                      "%s: option display is required: the display node (e.g. display=tcp://127.0.0.1:7000)", b->name);
        goto fail;
    }
    if (nexchange && npeers && nexchange != npeers) {
        tsr_error_set(err, TSR_EINVAL, "%s: exchange gives %zu addresses for %zu peers", b->name, nexchange, npeers);
        goto fail;
    }
    size_t n = nexchange ? nexchange : npeers ? npeers : 1;
    if (n > BINARYSWAP_MAX_PEERS) {
        tsr_error_set(err, TSR_EINVAL, "%s: %zu peers; at most %d", b->name, n, BINARYSWAP_MAX_PEERS);
        goto fail;
    }
    b->nranks = (int)n;
    if (b->rank >= b->nranks) {
        tsr_error_set(err, TSR_EINVAL, "%s: rank %d, but the group has %d peers (0..%d)", b->name, b->rank, b->nranks,
                      b->nranks - 1);
        goto fail;
    }
    for (size_t i = 0; i < n && b->nranks > 1; i++) {
        const char *a = nexchange ? tsr_options_string_at(init->options, "exchange", i) : NULL;
        if (a && (size_t)snprintf(b->exchange[i], sizeof b->exchange[i], "%s", a) >= sizeof b->exchange[i]) {
            tsr_error_set(err, TSR_EINVAL, "%s: exchange address too long: %s", b->name, a);
            goto fail;
        }
        tsr_error e = {0};
        const char *node = a ? NULL : tsr_options_string_at(init->options, "peers", i);
        if (node && !node[0]) {
            /* In situ: application peers have no address of their own. */
            char from_display[TSR_NET_ADDRESS_MAX + 16];
            snprintf(from_display, sizeof from_display, "%s", display_address);
            if (binaryswap_derive_exchange(from_display, b->exchange[i], sizeof b->exchange[i], (int)i + 1, &e) !=
                TSR_OK) {
                tsr_error_set(err, TSR_EINVAL, "%s: peer rank %zu: %s", b->name, i, e.message);
                goto fail;
            }
        } else if (node && binaryswap_derive_exchange(node, b->exchange[i], sizeof b->exchange[i], 0, &e) != TSR_OK) {
            tsr_error_set(err, TSR_EINVAL, "%s: peer rank %zu: %s", b->name, i, e.message);
            goto fail;
        }
        for (size_t j = 0; j < i; j++)
            if (!strcmp(b->exchange[i], b->exchange[j])) {
                tsr_error_set(err, TSR_EINVAL, "%s: peers %zu and %zu have one exchange address %s", b->name, j, i,
                              b->exchange[i]);
                goto fail;
            }
    }
    if (strcmp(mode, "depth") && strcmp(mode, "alpha")) {
        tsr_error_set(err, TSR_EINVAL, "%s: mode=%s: expected depth or alpha", b->name, mode);
        goto fail;
    }
    b->mode = strcmp(mode, "alpha") ? TSR_COMPOSITE_DEPTH : TSR_COMPOSITE_ALPHA;
    tsr_error e = {0};
    if (tsr_composite_kind_parse(strategy, &b->kind, &b->k, &e) != TSR_OK) {
        tsr_error_set(err, TSR_EINVAL, "%s: strategy=%s: %s", b->name, strategy, e.message);
        goto fail;
    }
    if (tsr_options_int(init->options, "k"))
        b->k = (int)tsr_options_int(init->options, "k");
    if (binaryswap_colour_parse(tsr_options_string(init->options, "colour"), &b->colour, &e) != TSR_OK ||
        binaryswap_view_order(init->options, b->mode == TSR_COMPOSITE_ALPHA, b->nranks, b->view, b->pos, &e) !=
            TSR_OK ||
        (b->mode == TSR_COMPOSITE_ALPHA && alpha_strategy(b, &e) != TSR_OK)) {
        tsr_error_set(err, TSR_EINVAL, "%s: %s", b->name, e.message);
        goto fail;
    }
    int has_box = 0;
    if (binaryswap_box_parse(init->options, b->box, &has_box, &e) != TSR_OK ||
        (has_box && b->mode != TSR_COMPOSITE_ALPHA &&
         tsr_error_set(&e, TSR_EINVAL, "box is for mode=alpha (depth mode composites in rank order)"))) {
        tsr_error_set(err, TSR_EINVAL, "%s: %s", b->name, e.message);
        goto fail;
    }
    if (tsr_composite_codec_parse(tsr_options_string(init->options, "codec"), &b->codec, &e) != TSR_OK) {
        tsr_error_set(err, TSR_EINVAL, "%s: codec=%s: %s", b->name, tsr_options_string(init->options, "codec"),
                      e.message);
        goto fail;
    }
    if (b->colour == TSR_COMPOSITE_RGBA32F && b->codec.color == TSR_COMPOSITE_CODEC_COLOR_YUV420) {
        tsr_error_set(err, TSR_EINVAL, "%s: codec=%s is for RGBA8 colour, not colour=rgba32f", b->name,
                      tsr_options_string(init->options, "codec"));
        goto fail;
    }
    if (tsr_composite_synthetic_parse(tsr_options_string(init->options, "synthetic"), &b->synthetic, &e) != TSR_OK) {
        tsr_error_set(err, TSR_EINVAL, "%s: %s", b->name, e.message);
        goto fail;
    }
    if (b->synthetic && (b->mode != TSR_COMPOSITE_DEPTH || b->colour != TSR_COMPOSITE_RGBA8)) {
        tsr_error_set(err, TSR_EINVAL,
                      "%s: synthetic=%s is a depth-mode RGBA8 layer: not with mode=alpha or colour=rgba32f", b->name,
                      tsr_options_string(init->options, "synthetic"));
        goto fail;
    }
    const char *stats = tsr_options_string(init->options, "stats");
    if (stats && stats[0] && (b->stats_fd = binaryswap_stats_open(stats, &e)) < 0) {
        tsr_error_set(err, TSR_EIO, "%s: %s", b->name, e.message);
        goto fail;
    }
    /* render's slots, the window commands (the display first, then
     * render) and the swap, all seen by the region of interest. */
    take_super_slots(init->table, init->super, init->child);
    binaryswap_display_init(b, init->table, init->super);
    tsr_set_SwapBuffersTSR(init->table, binaryswap_SwapBuffersTSR, b);
    if (!(b->roi = binaryswap_roi_create(init->table, window_size, b, err)))
        goto fail;
    /* alpha mode: the peers clear to transparent black (colour.c) */
    b->order_from_boxes = has_box && !tsr_options_count(init->options, "view_order");
    b->table = init->table;
    b->gl_clear_color = init->table->ClearColor;
    tsr_set_ClearColor(init->table, binaryswap_ClearColor, b);
    if (b->synthetic)
        tsr_set_Clear(init->table, binaryswap_Clear_synthetic, b);
    return b;
fail:
    if (b->stats_fd >= 0)
        close(b->stats_fd);
    free(b);
    return NULL;
}

static const tsr_option_spec binaryswap_options[] = {
    {.name = "display",
     .type = TSR_OPT_STRING,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "the display node every peer puts its final piece on: tcp://HOST:PORT or unix:PATH "
             "(required; a graph's to: fills it)"},
    {.name = "rank",
     .type = TSR_OPT_INT,
     .default_value = "0",
     .min = 0,
     .max = BINARYSWAP_MAX_PEERS - 1,
     .help = "this peer's place in the group, 0..N-1: depth ties go to the lower rank; rank 0 "
             "swaps the display's frame (a graph run sets it)"},
    {.name = "peers",
     .type = TSR_OPT_STRING_LIST,
     .default_value = "",
     .min = 0,
     .max = 0,
     .help = "every peer's node address in rank order, this one's included (a graph run sets "
             "it); the group has as many peers"},
    {.name = "exchange",
     .type = TSR_OPT_STRING_LIST,
     .default_value = "",
     .min = 0,
     .max = 0,
     .help = "where each peer listens for the others' images, in rank order; empty: derived "
             "from peers (unix:PATH.x, tcp://HOST:PORT+1). Without peers it gives the group"},
    {.name = "link_timeout_ms",
     .type = TSR_OPT_INT,
     .default_value = "60000",
     .min = 1,
     .max = 3600000.0,
     .help = "how long the peers wait for each other at the first frame (the mesh); later "
             "frames wait at most timeout_ms"},
    {.name = "strategy",
     .type = TSR_OPT_STRING,
     .default_value = "auto",
     .min = 1,
     .max = 0,
     .help = "how the group composites: auto (chosen from the peer count, window and last "
             "frame's bytes; logged), bswap (binary swap, any peer count), direct (direct "
             "send), radixk or radixk-K (radix-k), gather (all to rank 0)"},
    {.name = "k",
     .type = TSR_OPT_INT,
     .default_value = "0",
     .min = 0,
     .max = BINARYSWAP_MAX_PEERS,
     .help = "radix-k's radix (2..N; 2 is binary swap, N direct send); 0: radix-k chooses"},
    {.name = "codec",
     .type = TSR_OPT_STRING,
     .default_value = "rle",
     .min = 1,
     .max = 0,
     .help = "image messages: none, rle (active-pixel runs), erle (lossless per-channel RLE), "
             "lossy yuv420, depth16, depth24, or '+'-joined (erle+depth24)"},
    {.name = "shm",
     .type = TSR_OPT_BOOL,
     .default_value = "1",
     .min = 0,
     .max = 0,
     .help = "peers on unix: exchange addresses (one host) pass images through shared memory "
             "(memfd rings, only a descriptor crosses the socket); 0: through the socket. tcp:// "
             "peers always use TCP. Each peer logs the transport of every pair at info level"},
    {.name = "shm_drop",
     .type = TSR_OPT_BOOL,
     .default_value = "0",
     .min = 0,
     .max = 0,
     .help = "with shm: a peer drops its mapping of each received image once composited (the sender's "
             "pages stay), so a ring page is resident in one process, not in both (8 peers at 1920x1080: "
             "about 12 MiB less per peer, for re-faulting those pages every frame: about 1 ms of CPU per "
             "peer and frame there); off by default"},
    {.name = "mode",
     .type = TSR_OPT_STRING,
     .default_value = "depth",
     .min = 1,
     .max = 0,
     .help = "depth: the nearest fragment wins, equal depth goes to the lower rank; alpha: "
             "premultiplied layers (draw with BlendFunc(ONE, ONE_MINUS_SRC_ALPHA)) blended back to "
             "front in view_order, the application's ClearColor added once on the display (peers "
             "clear to 0); exact with direct, gather, auto (bswap and radix-k of several rounds "
             "regroup the blend and are refused for 3 or more peers)"},
    {.name = "view_order",
     .type = TSR_OPT_STRING_LIST,
     .default_value = "",
     .min = 0,
     .max = 0,
     .help = "mode=alpha: the ranks from front to back, e.g. [2, 0, 1]; empty: computed from "
             "every peer's box, else rank order (rank 0 in front)"},
    {.name = "box",
     .type = TSR_OPT_STRING_LIST,
     .default_value = "",
     .min = 0,
     .max = 0,
     .help = "mode=alpha: this peer's part's object-space bounding box [xmin, ymin, zmin, xmax, "
             "ymax, zmax] under the modelview at SwapBuffers; when every peer has one and "
             "view_order is empty, the view order is computed every frame (box centres, nearest "
             "first)"},
    {.name = "colour",
     .type = TSR_OPT_STRING,
     .default_value = "rgba8",
     .min = 1,
     .max = 0,
     .help = "rgba8 (as OSMesa holds it) or rgba32f (read as GL_FLOAT, composited in float, "
             "rounded once to RGBA8 on the display; the lossy yuv420 codec does not apply)"},
    {.name = "synthetic",
     .type = TSR_OPT_STRING,
     .default_value = "",
     .min = 0,
     .max = 0,
     .help = "benchmarks: composite a generated layer instead of the read-back, so only "
             "compositing is timed (the application's clears are skipped: the layer replaces the "
             "framebuffer): full (every pixel; each of N peers nearest on about 1/N) "
             "or ellipse (40% of the window, placed per rank); empty or off: the render's"},
    {.name = "stats",
     .type = TSR_OPT_STRING,
     .default_value = "",
     .min = 0,
     .max = 0,
     .help = "append one timing line per frame to this file (CLOCK_MONOTONIC ns of the swap, "
             "layer ready, rounds done; rank 0: frame assembled and drawn on the display, "
             "one round trip per frame), bytes sent, VmHWM/VmRSS; peers may share one file"},
    /* token, buffer_size, timeout_ms (also the peers' limit), on_error (the
     * display stream's; a failing peer always ends the process). */
    TSR_NODE_CLIENT_OPTION_SPECS,
};

static const tsr_spu_class binaryswap_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "binaryswap",
    .super = "render",
    .summary = "renders like render, then composites each frame's colour+depth with its peers "
               "(sort-last); each peer puts its final piece on a display node",
    .options = binaryswap_options,
    .option_count = sizeof binaryswap_options / sizeof binaryswap_options[0],
    .create = binaryswap_create,
    .destroy = binaryswap_destroy,
    .network = {.role = TSR_SPU_ROLE_PEERS,
                .display = "display",
                .rank = "rank",
                .peers = "peers",
                .token = TSR_NODE_CLIENT_TOKEN_OPTION},
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &binaryswap_class; }
