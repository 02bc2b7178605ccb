/* spus/binaryswap — one peer of a sort-last compositing group: renders
 * exactly like `render` (it IS render: spus/render's library, render.h,
 * with a frame hook), and at every SwapBuffers of its window reads back the
 * colour and depth of its region of interest, composites it with its
 * peers' images, and the group's final frame goes to a display node (an
 * ordinary `tessera node` whose render chain writes the PNG). Owns, per
 * instance: the render instance, the peer connections (netlib, one
 * tsr_net), the stream to the display (a `pack` chain of its own), the
 * read-back and frame buffers. Never: keeps state outside the instance,
 * sends the display anything but the window, its final piece (colour and
 * scissored clears), the frame's barriers and (rank 0) the swap,
 * or sends a peer a full frame of background (an empty peer's image is a
 * header).
 *
 * Group. `rank` (0..N-1) and `peers` (every peer's node address, rank
 * order) come from the graph (TSR_SPU_ROLE_PEERS); N is the number of
 * peers. Peers exchange images on their own listening sockets, one per
 * peer: `exchange` gives their addresses in rank order, else each is
 * derived from the peer's node address (unix:PATH -> unix:PATH.x;
 * tcp://HOST:PORT -> tcp://HOST:PORT+1) or, in situ (application peers
 * have no address: the graph run gives empty ones), from the display's
 * and the rank R (unix:PATH.peerR; tcp://HOST:PORT+1+R). The mesh is made at the first
 * swap: every peer listens, connects to every lower rank (retrying until
 * timeout_ms while that peer is not listening yet) and accepts the higher
 * ranks; the first message on a connection names the connecting rank.
 *
 * Region of interest (read_layer). At a swap only the colour and depth
 * of the window-space box of the frame's geometry are read and sent
 * (roi.c: the box of every vertex render was given, placed with the
 * matrices it was drawn with, clipped in homogeneous space where it
 * reaches behind the viewer, never dropped). When the frame drew
 * something no box covers, the depth buffer of the whole window is read
 * (GL_DEPTH_COMPONENT/GL_FLOAT, as OSMesa gives it) and the box of pixels
 * with depth < 1.0 (the cleared value) found instead. A peer that drew
 * nothing sends the header alone.
 *
 * Compositing (composite_frame below): one of the strategies of
 * strategies/ (strategy.h: binary swap for any peer count, direct send,
 * radix-k, gather to one, auto), planned once per window size and run by
 * its executor over this SPU's transport (transport_send/recv): peers are
 * participants 0..N-1 over the mesh; only when the display composites
 * (gather to one) does the display participant N run, in rank 0's process
 * (rank 0's own final piece is queued locally). Depth
 * mode: the nearest depth wins, equal depth goes to the lower rank, so the
 * result is the single-process render of the parts drawn in rank order
 * with GL_LESS, bit for bit, for every strategy and arrival order. Pixels
 * no peer drew get the background colour, read from a pixel rank 0 left
 * at depth 1.0 (exactly what GL's clear produced; when rank 0 left none,
 * it covered the window and no pixel is background; every peer takes its
 * own, as every application clears to the same colour). Every peer then
 * puts its final piece into the display's frame itself (composite_frame:
 * a graph's display node counts every peer among its clients), and rank
 * 0 swaps there.
 *
 * Alpha mode and float colour (layers.h, order.c, colour.c; README.md):
 * the colour of the geometry's box (or of the whole window when that is
 * unknown) is composited as a premultiplied layer, in
 * view_order, folded back to front (the serial blend's grouping) by a
 * schedule that keeps that grouping; the peer clears to transparent black
 * (ClearColor is taken here) and the display adds the application's clear
 * colour once. colour=rgba32f composites GL_FLOAT colour.
 *
 * Failures: a peer that does not answer within timeout_ms, a connection
 * that breaks, a message whose frame, rank, window size or region is not
 * what it must be: one line naming the peer (rank and address), then the
 * process ends with status 1 (on_error=exit, the default, as readback
 * does: a frame that cannot be composited is a failed run). */
#include <inttypes.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "bands.h"
#include "layers.h"
#include "net.h"
#include "render.h"
#include "roi.h"
#include "stats.h"
#include "strategy.h"
#include "synthetic.h"
#include "tessera/chain.h"
#include "tessera/dev/client.h"
#include "tessera/dev/util.h"
#include "tessera/log.h"
#include "tessera/spu.h"

#define BSWAP_MAX_PEERS 64
#define BSWAP_MAGIC 0x494c5354u /* "TSLI" */
#define BSWAP_KIND_HELLO (TSR_NET_KIND_FIRST_USER + 0)
#define BSWAP_KIND_IMAGE (TSR_NET_KIND_FIRST_USER + 1)
#define BSWAP_KIND_ORDER (TSR_NET_KIND_FIRST_USER + 2)  /* alpha mode: a box's distance */
#define BSWAP_KIND_ENDING (TSR_NET_KIND_FIRST_USER + 3) /* a peer's last word: the line it ends on */
/* The group's frame fence on the display node (its parallel API, server/node.h). */
#define BSWAP_DISPLAY_BARRIER 0x54534c42u /* "TSLB" */
/* What one more DrawPixels of a partial piece costs, in pixels sent (the
 * display's per-call state checks and texture, a command): a band of the
 * piece grows while that is cheaper than a call (bands.h). */
#define BSWAP_CALL_PIXELS 8192u

/* A message queued for this process's own display participant (rank 0
 * sends its final piece to itself). */
typedef struct local_msg {
    struct local_msg *next;
    size_t size;
    uint8_t data[];
} local_msg;

typedef struct bswap_spu {
    char name[96];
    void *render;
    bswap_roi *roi; /* the region of interest from the geometry (roi.c) */
    tsr_dispatch down;
    const tsr_dispatch *child;
    const tsr_options *options;
    int window, rank, nranks, timeout_ms;
    char exchange[BSWAP_MAX_PEERS][TSR_NET_ADDRESS_MAX];

    tsr_net *net;
    tsr_net_listener *listener;
    tsr_net_conn *conns[BSWAP_MAX_PEERS]; /* conns[rank] stays NULL */
    bool linked;
    bool meshed;     /* every peer linked and its HELLO read: a peer's last word may follow */
    bool composited; /* a frame's messages went out and their releases are not yet awaited */

    tsr_chain *out; /* pack to the display; NULL until first needed */
    const tsr_dispatch *display;
    bool display_failed;

    int kind, k;           /* strategy asked for (tsr_cs_kind) and radix */
    tsr_image_codec codec; /* of image messages */
    tsr_cs_schedule plan;  /* for plan_width x plan_height; kind 0: none yet */
    int plan_width, plan_height;
    tsr_cs_executor *peer_ex, *display_ex; /* display_ex: rank 0 only */
    uint64_t last_bytes;                   /* this peer's bytes sent last frame (auto's hint) */
    tsr_net_msg held;                      /* the message recv handed out last */
    bool holding;
    local_msg *local_head, *local_tail; /* rank 0 -> its own display participant */
    local_msg *local_given;             /* handed out by recv, freed at the next */
    local_msg *local_building;          /* given by send_buffer, queued by send */
    void *reserved;                     /* send_buffer's buffer for a peer (netlib's) */

    uint32_t frames; /* frames composited */
    float *window_depth;
    size_t window_depth_size;
    tsr_cimage mine;         /* this frame's region of interest */
    tsr_cimage frame;        /* rank 0, when the display composites (gather): the assembled frame */
    bswap_bands bands;       /* how this peer's final piece is drawn (partial pieces) */
    tsr_sparse_image placed; /* the rows of one box of the final piece (a view) */
    tsr_sparse_image row;    /* one row of it (a view of placed) */
    tsr_cimage piece;        /* ... as the colour the display draws (the box) */
    uint8_t background[4];
    bool has_background; /* background[] is a pixel this peer left cleared */

    /* alpha mode and float colour (layers.h) */
    int mode, colour;                                /* tsr_composite_mode, tsr_ci_color_format */
    int view[BSWAP_MAX_PEERS], pos[BSWAP_MAX_PEERS]; /* position -> rank, rank -> position */
    tsr_entry gl_clear_color;                        /* render's ClearColor */
    const tsr_dispatch *table;                       /* this instance's (GetFloatv) */
    float box[6];                                    /* this part's object-space box */
    bool order_from_boxes;                           /* box given, view_order not */
    float clear[4];                                  /* the application's clear colour (alpha mode) */
    tsr_cimage layer;                                /* alpha or float: what is composited */
    uint8_t *frame8;                                 /* float colour: the frame as RGBA8 */
    size_t frame8_size;
    int synthetic;            /* TSR_SYNTHETIC_*: a generated layer instead of the read-back */
    int stats_fd;             /* stats= file, or -1 */
    tsr_bswap_frame_stats st; /* this frame's times */
} bswap_spu;

/* Ends the process after one line: other threads (netlib's, llvmpipe's)
 * are running, so _exit. */
static void bswap_fatal(bswap_spu *b, const char *fmt, ...) __attribute__((format(printf, 2, 3), noreturn));
static void bswap_fatal(bswap_spu *b, const char *fmt, ...)
{
    char what[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    tsr_log(TSR_LOG_ERROR, "%s: %s", b->name, what);
    tsr_log(TSR_LOG_ERROR, "%s: ending (a frame that cannot be composited fails the run)", b->name);
    fflush(NULL);
    /* What this peer already sent (its HELLO, an image) and the line it
     * ends on reach the others before it goes, so they name the real
     * fault (a peer killed before this one), not its vanishing. */
    /* While the mesh forms, a peer reads a HELLO first from each link and
     * names a failure there itself: only a formed mesh hears last words. */
    tsr_error ignored = {0};
    for (int r = 0; b->meshed && r < b->nranks && r < BSWAP_MAX_PEERS; r++)
        if (b->conns[r])
            tsr_net_send(b->conns[r], BSWAP_KIND_ENDING, what, strlen(what), 100, &ignored);
    for (int r = 0; r < b->nranks && r < BSWAP_MAX_PEERS; r++)
        if (b->conns[r])
            tsr_net_conn_flush(b->conns[r], 200);
    _exit(TSR_NODE_CLIENT_EXIT_STATUS);
}

static int64_t now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* --- addresses ----------------------------------------------------------- */

/* The exchange address of a peer whose node listens at `node` (header). */
static int derive_exchange(const char *node, char *out, size_t size, int display_rank, tsr_error *err)
{
    if (!strncmp(node, "unix:", 5)) {
        int n =
            display_rank ? snprintf(out, size, "%s.peer%d", node, display_rank - 1) : snprintf(out, size, "%s.x", node);
        if (n < 0 || (size_t)n >= size)
            return tsr_error_set(err, TSR_EINVAL, "address too long: %s", node);
        return TSR_OK;
    }
    const char *colon = strrchr(node, ':');
    if (!strncmp(node, "tcp://", 6) && colon && colon > node + 5) {
        char *end;
        long port = strtol(colon + 1, &end, 10);
        if (*end || port <= 0 || port >= 65535)
            return tsr_error_set(err, TSR_EINVAL, "cannot derive an exchange address from %s (give exchange=)", node);
        long to = display_rank ? port + display_rank : port + 1;
        if (to >= 65536)
            return tsr_error_set(err, TSR_EINVAL, "cannot derive an exchange address from %s (give exchange=)", node);
        if ((size_t)snprintf(out, size, "%.*s:%ld", (int)(colon - node), node, to) >= size)
            return tsr_error_set(err, TSR_EINVAL, "address too long: %s", node);
        return TSR_OK;
    }
    return tsr_error_set(err, TSR_EINVAL, "cannot derive an exchange address from %s (give exchange=)", node);
}

static const char *peer_address(const bswap_spu *b, int rank) { return b->exchange[rank]; }

/* --- the display ------------------------------------------------------------ */

static const char *const pack_keys[] = {"server", "token", "buffer_size", "timeout_ms", "on_error"};
#define PACK_KEYS (sizeof pack_keys / sizeof pack_keys[0])

/* The display stream, created on first use (not in create: a node builds
 * its chain once at start-up only to check it). */
static const tsr_dispatch *display(bswap_spu *b)
{
    if (b->display || b->display_failed)
        return b->display;
    char numbers[2][24];
    snprintf(numbers[0], sizeof numbers[0], "%" PRId64, tsr_options_int(b->options, "buffer_size"));
    snprintf(numbers[1], sizeof numbers[1], "%" PRId64, tsr_options_int(b->options, "timeout_ms"));
    const char *values[PACK_KEYS] = {tsr_options_string(b->options, "display"), tsr_options_string(b->options, "token"),
                                     numbers[0], numbers[1], tsr_options_string(b->options, "on_error")};
    tsr_chain_link link = {.spu = "pack", .keys = pack_keys, .values = values, .option_count = PACK_KEYS};
    tsr_error err = {0};
    b->out = tsr_chain_create_links(&link, 1, &err);
    if (!b->out) {
        bswap_fatal(b, "display %s: %s", values[0], err.message);
    }
    b->display = tsr_chain_head(b->out);
    tsr_call_BarrierCreateTSR(b->display, BSWAP_DISPLAY_BARRIER, (GLuint)b->nranks);
    return b->display;
}

static void bswap_WindowCreateTSR(void *self, GLint window, GLsizei width, GLsizei height)
{
    bswap_spu *b = self;
    const tsr_dispatch *d = window == b->window ? display(b) : NULL;
    if (d)
        tsr_call_WindowCreateTSR(d, window, width, height);
    tsr_call_WindowCreateTSR(b->child, window, width, height);
}

static void bswap_WindowSizeTSR(void *self, GLint window, GLsizei width, GLsizei height)
{
    bswap_spu *b = self;
    const tsr_dispatch *d = window == b->window ? display(b) : NULL;
    if (d)
        tsr_call_WindowSizeTSR(d, window, width, height);
    tsr_call_WindowSizeTSR(b->child, window, width, height);
}

/* --- the peer mesh ---------------------------------------------------------- */

/* Each direction's shared-memory ring (unix: peers) holds what the
 * schedule sends on one connection in one frame, each message at its
 * largest (tsr_image_message_max_size of its region), and no more: the
 * peers release every message of a frame before its barrier, and each
 * frame starts with the rings empty (await_releases), so the frame's
 * messages go at the ring's start, one after the other, and always fit
 * without waiting for a partner's progress. A bigger ring would only let
 * a sender that has not yet heard of its partner's release write the next
 * frame behind the last one: pages resident in both processes, in every
 * ring (direct send at 8 peers: 7 pieces out and 7 in). The participants
 * are positions in the compositing order (alpha mode may map them to any
 * ranks), so the ring takes the busiest pair of positions, and the
 * display's pieces (when the display composites, they travel to rank 0)
 * on top (tsr_cs_schedule_link_bytes). BSWAP_RING_SPARE is room for the
 * small messages beside the images (the mesh's hello, alpha mode's box
 * distances) and for netlib rounding each ring message up to 64 bytes (a
 * link carries a few messages a frame: at most one per round and the
 * final piece). The rings are made at the first frame; after the window
 * grows, a message larger than its ring goes through the socket. */
#define BSWAP_RING_SPARE ((uint64_t)64 << 10)

static uint64_t ring_bytes(const bswap_spu *b)
{
    int depth = b->mode == TSR_COMPOSITE_DEPTH ? TSR_CI_DEPTH32F : TSR_CI_NODEPTH;
    uint64_t page = (uint64_t)sysconf(_SC_PAGESIZE);
    uint64_t want = tsr_cs_schedule_link_bytes(&b->plan, b->colour, depth, b->codec) + BSWAP_RING_SPARE;
    want = (want + page - 1) / page * page;
    return want > ((uint64_t)16 << 30) ? (uint64_t)16 << 30 : want;
}

static void plan(bswap_spu *b, int W, int H);

static void link_peers(bswap_spu *b, int W, int H)
{
    if (b->linked)
        return;
    b->linked = true;
    if (b->nranks == 1)
        return;
    tsr_error err = {0};
    char node_name[64];
    snprintf(node_name, sizeof node_name, "binaryswap-rank-%d", b->rank);
    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.node_name = node_name;
    cfg.token = tsr_options_string(b->options, "token");
    cfg.max_message_bytes = (uint64_t)1 << 31;
    plan(b, W, H); /* the rings are sized for what its schedule sends */
    cfg.shm_ring_bytes = tsr_options_bool(b->options, "shm") ? ring_bytes(b) : 0;
    cfg.shm_drop_released = tsr_options_bool(b->options, "shm_drop");
    if (b->timeout_ms > 0) {
        cfg.idle_timeout_ms = (uint32_t)b->timeout_ms;
        cfg.connect_timeout_ms = cfg.handshake_timeout_ms = (uint32_t)b->timeout_ms;
    }
    if (!(b->net = tsr_net_create(&cfg, &err)))
        bswap_fatal(b, "%s", err.message);
    if (!(b->listener = tsr_net_listen(b->net, peer_address(b, b->rank), &err))) {
        bswap_fatal(b, "rank %d cannot listen for its peers: %s", b->rank, err.message);
    }
    /* Peers reach their first frame at different times (start-up, their
     * share's first draw): the mesh has its own, longer limit. */
    int link_ms = (int)tsr_options_int(b->options, "link_timeout_ms");
    int64_t deadline = now_ms() + link_ms;
    for (int i = 0; i < b->rank; i++) {
        for (;;) {
            /* A Unix socket that is not there yet would be one more logged
             * refusal per try: wait for the file instead. */
            const char *a = peer_address(b, i);
            struct stat st;
            if (!strncmp(a, "unix:", 5) && stat(a + 5, &st) != 0 && now_ms() < deadline) {
                usleep(10000);
                continue;
            }
            b->conns[i] = tsr_net_connect(b->net, peer_address(b, i), &err);
            if (b->conns[i] || now_ms() >= deadline)
                break;
            usleep(20000); /* that peer does not listen yet */
        }
        if (!b->conns[i]) {
            bswap_fatal(b, "peer rank %d (%s) cannot be reached: %s", i, peer_address(b, i), err.message);
        }
        int32_t me[3] = {b->rank, W, H};
        if (tsr_net_send(b->conns[i], BSWAP_KIND_HELLO, me, sizeof me, b->timeout_ms, &err) != TSR_OK) {
            bswap_fatal(b, "peer rank %d (%s): %s", i, peer_address(b, i), err.message);
        }
    }
    for (int n = b->rank + 1; n < b->nranks; n++) {
        int64_t left = deadline - now_ms();
        tsr_net_conn *c = tsr_net_accept(b->listener, left > 0 ? (int)left : 1, &err);
        if (!c) {
            int missing = -1;
            for (int k = b->rank + 1; k < b->nranks && missing < 0; k++)
                if (!b->conns[k])
                    missing = k;
            bswap_fatal(b, "peer rank %d (%s) did not connect within %d ms (link_timeout_ms): %s", missing,
                        peer_address(b, missing), link_ms, err.message);
        }
        tsr_net_msg msg;
        int32_t hello[3] = {-1, 0, 0}, who = -1;
        int rc = tsr_net_recv(c, &msg, b->timeout_ms > 0 ? b->timeout_ms : TSR_NET_WAIT_FOREVER, &err);
        if (rc == 1) {
            if (msg.kind == BSWAP_KIND_HELLO && msg.len == sizeof hello)
                memcpy(hello, msg.data, sizeof hello);
            tsr_net_msg_release(&msg);
        }
        who = hello[0];
        if (who <= b->rank || who >= b->nranks || b->conns[who]) {
            bswap_fatal(b, "a peer at %s did not say which rank it is (or said %d)", tsr_net_conn_address(c), who);
        }
        b->conns[who] = c;
        if (hello[1] != W || hello[2] != H)
            bswap_fatal(
                b, "frame 0: peer rank %d (%s) draws a %" PRId32 "x%" PRId32 " window, not %dx%d (window sizes differ)",
                who, peer_address(b, who), hello[1], hello[2], W, H);
    }
    tsr_log(TSR_LOG_DEBUG, "%s: rank %d of %d linked to its peers", b->name, b->rank, b->nranks);
    b->meshed = true;
    for (int i = 0; i < b->nranks; i++)
        if (b->conns[i])
            tsr_log(TSR_LOG_INFO, "%s: transport rank %d <-> rank %d (%s): %s", b->name, b->rank, i, peer_address(b, i),
                    tsr_net_conn_transport(b->conns[i]));
}

/* --- read-back -------------------------------------------------------------- */

static bool grow(void **p, size_t *cap, size_t need)
{
    if (need <= *cap)
        return true;
    void *q = realloc(*p, need);
    if (!q)
        return false;
    *p = q;
    *cap = need;
    return true;
}

/* Reads the box [box[0], box[2]) x [box[1], box[3]) that holds all this
 * frame drew (roi.c): its colour and depth, nothing else. */
static void read_box(bswap_spu *b, uint32_t frame, int W, int H, const int box[4])
{
    tsr_error err = {0};
    int x = box[0], y = box[1], w = box[2] - box[0], h = box[3] - box[1];
    if (tsr_cimage_init(&b->mine, W, H, x, y, w, h, TSR_CI_RGBA8, TSR_CI_DEPTH32F, &err) != TSR_OK)
        bswap_fatal(b, "%s", err.message);
    b->mine.rank = b->rank;
    b->mine.frame = frame;
    if (w && (render_spu_read(b->render, x, y, w, h, GL_RGBA, GL_UNSIGNED_BYTE, b->mine.color, &err) != TSR_OK ||
              render_spu_read(b->render, x, y, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, b->mine.depth, &err) != TSR_OK))
        bswap_fatal(b, "%s", err.message);
    /* The background: a pixel outside the box (nothing was drawn there
     * since the clear), else one inside it that kept the cleared depth. */
    int bx = -1, by = -1;
    if (x > 0 || !w)
        bx = 0, by = 0;
    else if (x + w < W)
        bx = x + w, by = y;
    else if (y > 0)
        bx = 0, by = 0;
    else if (y + h < H)
        bx = 0, by = y + h;
    b->has_background = bx >= 0;
    if (b->has_background) {
        if (render_spu_read(b->render, bx, by, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, b->background, &err) != TSR_OK)
            bswap_fatal(b, "%s", err.message);
    } else {
        for (size_t i = 0; i < (size_t)w * (size_t)h && !b->has_background; i++)
            if (!(b->mine.depth[i] < 1.0f)) {
                memcpy(b->background, b->mine.color + 4 * i, 4);
                b->has_background = true;
            }
    }
    tsr_log(TSR_LOG_DEBUG,
            "%s: frame %" PRIu32 ": rank %d region [%d, %d, %d, %d] of %dx%d from the geometry's box; read %dx%d "
            "depth, %dx%d colour",
            b->name, frame, b->rank, x, y, w, h, W, H, w, h, w, h);
}

/* Reads this frame's region of interest into b->mine (header comment):
 * the box of what was drawn (roi.c) when it is known, else the box of the
 * pixels with depth < 1.0, found in the whole window's depth. */
static void read_layer(bswap_spu *b, uint32_t frame)
{
    int W = 0, H = 0;
    render_spu_size(b->render, &W, &H);
    tsr_error err = {0};
    int box[4];
    if (bswap_roi_frame(b->roi, box)) {
        read_box(b, frame, W, H, box);
        return;
    }
    size_t pixels = (size_t)W * (size_t)H;
    if (!grow((void **)&b->window_depth, &b->window_depth_size, pixels * sizeof(float) + 1))
        bswap_fatal(b, "%s", "out of memory for the depth buffer");
    if (render_spu_read(b->render, 0, 0, W, H, GL_DEPTH_COMPONENT, GL_FLOAT, b->window_depth, &err) != TSR_OK)
        bswap_fatal(b, "%s", err.message);
    int x0 = W, y0 = H, x1 = -1, y1 = -1;
    size_t bg_index = SIZE_MAX;
    for (int y = 0; y < H; y++) {
        const float *row = b->window_depth + (size_t)y * (size_t)W;
        for (int x = 0; x < W; x++) {
            if (row[x] < 1.0f) {
                if (x < x0)
                    x0 = x;
                if (x > x1)
                    x1 = x;
                if (y < y0)
                    y0 = y;
                y1 = y;
            } else if (bg_index == SIZE_MAX) {
                bg_index = (size_t)y * (size_t)W + (size_t)x;
            }
        }
    }
    int x = 0, y = 0, w = 0, h = 0;
    if (x1 >= 0) {
        x = x0;
        y = y0;
        w = x1 - x0 + 1;
        h = y1 - y0 + 1;
    }
    if (tsr_cimage_init(&b->mine, W, H, x, y, w, h, TSR_CI_RGBA8, TSR_CI_DEPTH32F, &err) != TSR_OK)
        bswap_fatal(b, "%s", err.message);
    b->mine.rank = b->rank;
    b->mine.frame = frame;
    if (w && render_spu_read(b->render, x, y, w, h, GL_RGBA, GL_UNSIGNED_BYTE, b->mine.color, &err) != TSR_OK)
        bswap_fatal(b, "%s", err.message);
    for (int r = 0; r < h; r++)
        memcpy(b->mine.depth + (size_t)r * (size_t)w, b->window_depth + (size_t)(y + r) * (size_t)W + (size_t)x,
               (size_t)w * sizeof(float));
    b->has_background = bg_index != SIZE_MAX;
    if (b->has_background && render_spu_read(b->render, (int)(bg_index % (size_t)W), (int)(bg_index / (size_t)W), 1, 1,
                                             GL_RGBA, GL_UNSIGNED_BYTE, b->background, &err) != TSR_OK)
        bswap_fatal(b, "%s", err.message);
    tsr_log(TSR_LOG_DEBUG,
            "%s: frame %" PRIu32 ": rank %d region [%d, %d, %d, %d] of %dx%d from the depth buffer; read %dx%d depth, "
            "%dx%d colour",
            b->name, frame, b->rank, x, y, w, h, W, H, W, H, w, h);
}

/* The synthetic layer (synthetic.h) in place of the read-back: made once
 * per window size (the compositor only reads it), so a frame costs no
 * read-back and no generation, only compositing. No pixel of the layer
 * came from GL, so the background is opaque black. */
static void synthetic_layer(bswap_spu *b, int W, int H, uint32_t frame)
{
    tsr_error err = {0};
    if (b->mine.window_width != W || b->mine.window_height != H || !b->mine.color) {
        if (tsr_synthetic_layer(b->synthetic, W, H, b->rank, b->nranks, &b->mine, &err) != TSR_OK)
            bswap_fatal(b, "%s", err.message);
    }
    b->mine.rank = b->rank;
    b->mine.frame = frame;
    static const uint8_t black[4] = {0, 0, 0, 255};
    memcpy(b->background, black, sizeof black);
    b->has_background = true;
}

/* --- the transport the strategies run over ---------------------------------- */

static void release_held(bswap_spu *b)
{
    if (b->holding)
        tsr_net_msg_release(&b->held);
    b->holding = false;
    free(b->local_given);
    b->local_given = NULL;
}

/* The line a peer ended on (bswap_fatal sends it to every other peer),
 * from `msg`, or else from what `peer` sent before its link failed (looked
 * through without waiting); false when there is none. */
static bool last_word(bswap_spu *b, int peer, const tsr_net_msg *msg, char *out, size_t size)
{
    if (msg && msg->kind == BSWAP_KIND_ENDING) {
        tsr_text_sanitize(out, size, msg->data, (size_t)msg->len);
        return true;
    }
    if (peer < 0 || peer >= b->nranks || !b->conns[peer])
        return false;
    tsr_net_msg m;
    tsr_error ignored = {0};
    while (tsr_net_recv(b->conns[peer], &m, 0, &ignored) == 1) {
        bool ending = m.kind == BSWAP_KIND_ENDING;
        if (ending)
            tsr_text_sanitize(out, size, m.data, (size_t)m.len);
        tsr_net_msg_release(&m);
        if (ending)
            return true;
    }
    return false;
}

/* True with *err set when `peer` ended on a fault of its own and said
 * so (in `msg`, or before its link failed): the fault comes first, then
 * who passed it on. */
static bool peer_ended_on(bswap_spu *b, int peer, const tsr_net_msg *msg, tsr_error *err)
{
    char said[sizeof err->message / 2];
    if (!last_word(b, peer, msg, said, sizeof said))
        return false;
    /* its frame is this one's: the caller names it once */
    const char *fault = said;
    unsigned frame;
    int at = 0;
    if (sscanf(said, "frame %u: %n", &frame, &at) == 1 && at > 0)
        fault += at;
    tsr_error_set(err, TSR_EIO, "%s (said peer rank %d (%s), which ended on it)", fault, peer, peer_address(b, peer));
    return true;
}

/* A failure on the link to `peer` (`what`: how it showed here), unless
 * `peer` ended on a fault of its own (peer_ended_on). */
static int peer_failed(bswap_spu *b, int peer, int code, const tsr_net_msg *msg, const char *what, tsr_error *err)
{
    if (peer_ended_on(b, peer, msg, err))
        return err->code;
    return tsr_error_set(err, code ? code : TSR_EIO, "peer rank %d (%s): %s", peer, peer_address(b, peer), what);
}

/* Where the executor encodes its next message to `to`: shared memory the
 * peer maps (netlib's ring on unix: peers; elsewhere a buffer netlib
 * sends from), or the local message itself for rank 0's own display. */
static void *transport_send_buffer(void *user, int to, size_t max_size, tsr_error *err)
{
    bswap_spu *b = user;
    if (to == b->nranks && b->rank == 0) {
        free(b->local_building);
        if (!(b->local_building = malloc(sizeof *b->local_building + max_size))) {
            tsr_error_set(err, TSR_ENOMEM, "out of memory for a %zu-byte image", max_size);
            return NULL;
        }
        return b->local_building->data;
    }
    /* `to` is a position in the compositing order, as in transport_send */
    int peer = to == b->nranks ? 0 : to >= 0 && to < b->nranks ? b->view[to] : -1;
    if (peer < 0 || peer >= b->nranks || !b->conns[peer]) {
        tsr_error_set(err, TSR_EINVAL, "no connection to participant %d", to);
        return NULL;
    }
    tsr_error e = {0};
    int rc = tsr_net_send_reserve(b->conns[peer], max_size, &b->reserved,
                                  b->timeout_ms > 0 ? b->timeout_ms : TSR_NET_WAIT_FOREVER, &e);
    if (rc != TSR_OK) {
        peer_failed(b, peer, rc, NULL, rc == TSR_ETIMEDOUT ? "took no image within timeout_ms" : e.message, err);
        return NULL;
    }
    return b->reserved;
}

/* Participant `to`: a peer rank over its connection, or the display
 * participant (nranks), which lives in rank 0's process. */
static int transport_send(void *user, int to, const void *data, size_t size, tsr_error *err)
{
    bswap_spu *b = user;
    if (to == b->nranks && b->rank == 0) {
        local_msg *m = b->local_building;
        if (m && data == m->data) {
            b->local_building = NULL; /* encoded in place */
        } else if (!(m = malloc(sizeof *m + size))) {
            return tsr_error_set(err, TSR_ENOMEM, "out of memory for a %zu-byte image", size);
        } else {
            memcpy(m->data, data, size);
        }
        m->next = NULL;
        m->size = size;
        if (b->local_tail)
            b->local_tail->next = m;
        else
            b->local_head = m;
        b->local_tail = m;
        return TSR_OK;
    }
    int peer = to == b->nranks ? 0 : to >= 0 && to < b->nranks ? b->view[to] : -1;
    if (peer < 0 || peer >= b->nranks || !b->conns[peer])
        return tsr_error_set(err, TSR_EINVAL, "no connection to participant %d", to);
    tsr_error e = {0};
    int wait = b->timeout_ms > 0 ? b->timeout_ms : TSR_NET_WAIT_FOREVER;
    bool in_place = b->reserved && data == b->reserved;
    b->reserved = NULL;
    int rc = in_place ? tsr_net_send_commit(b->conns[peer], BSWAP_KIND_IMAGE, size, wait, &e)
                      : tsr_net_send(b->conns[peer], BSWAP_KIND_IMAGE, data, size, wait, &e);
    if (rc != TSR_OK)
        return peer_failed(b, peer, rc, NULL, rc == TSR_ETIMEDOUT ? "took no image within timeout_ms" : e.message, err);
    b->last_bytes += size;
    return TSR_OK;
}

static int transport_recv(void *user, int from, const void **data, size_t *size, tsr_error *err)
{
    bswap_spu *b = user;
    release_held(b);
    if (from >= 0 && from < b->nranks)
        from = b->view[from]; /* a position in the compositing order: its rank */
    if (from == b->rank) {
        local_msg *m = b->local_head;
        if (!m)
            return tsr_error_set(err, TSR_EPROTO, "rank %d waits for an image from itself that was never sent",
                                 b->rank);
        b->local_head = m->next;
        if (!b->local_head)
            b->local_tail = NULL;
        b->local_given = m;
        *data = m->data;
        *size = m->size;
        return TSR_OK;
    }
    if (from < 0 || from >= b->nranks || !b->conns[from])
        return tsr_error_set(err, TSR_EINVAL, "no connection to participant %d", from);
    tsr_error e = {0};
    int rc = tsr_net_recv(b->conns[from], &b->held, b->timeout_ms > 0 ? b->timeout_ms : TSR_NET_WAIT_FOREVER, &e);
    if (rc != 1)
        return peer_failed(b, from, rc == 0 ? TSR_EIO : rc, NULL,
                           rc == 0               ? "ended before sending its image"
                           : rc == TSR_ETIMEDOUT ? "sent no image within timeout_ms"
                                                 : e.message,
                           err);
    b->holding = true;
    if (b->held.kind == BSWAP_KIND_ENDING)
        return peer_failed(b, from, TSR_EIO, &b->held, "", err);
    if (b->held.kind != BSWAP_KIND_IMAGE)
        return tsr_error_set(err, TSR_EPROTO, "peer rank %d (%s): a message of kind %u, not an image", from,
                             peer_address(b, from), b->held.kind);
    *data = b->held.data;
    *size = (size_t)b->held.len;
    return TSR_OK;
}

/* The schedule for this window (planned again when the size changes). */
static void plan(bswap_spu *b, int W, int H)
{
    if (b->plan.kind && b->plan_width == W && b->plan_height == H)
        return;
    tsr_error err = {0};
    tsr_cs_executor_free(b->peer_ex);
    tsr_cs_executor_free(b->display_ex);
    b->peer_ex = b->display_ex = NULL;
    if (b->plan.kind)
        tsr_cs_schedule_free(&b->plan);
    tsr_cs_hint hint = {.image_bytes = b->last_bytes, .display_separate = 0};
    if (tsr_cs_plan(b->kind, b->nranks, W, H, b->k, &hint, &b->plan, &err) != TSR_OK ||
        !(b->peer_ex = tsr_cs_executor_new(&b->plan, b->codec, &err)) ||
        (b->rank == 0 && !(b->display_ex = tsr_cs_executor_new(&b->plan, b->codec, &err))))
        bswap_fatal(b, "%s", err.message);
    b->plan_width = W;
    b->plan_height = H;
    if (b->rank == 0) {
        char codec[64];
        tsr_log(TSR_LOG_INFO, "%s: strategy %s for %d peers, %dx%d window, codec %s: %s", b->name, b->plan.name,
                b->nranks, W, H, tsr_image_codec_name(b->codec, codec, sizeof codec), b->plan.reason);
    }
}

static void stats_frame(bswap_spu *b, uint32_t frame)
{
    if (b->stats_fd < 0)
        return;
    b->st.frame = frame;
    b->st.rank = b->rank;
    b->st.nranks = b->nranks;
    b->st.bytes_sent = b->last_bytes;
    tsr_bswap_stats_write(b->stats_fd, &b->st);
}

/* The pixels [first, last] of a window `W` wide as at most three
 * rectangles {x, y, w, h}: a partial first row, whole rows, a partial last
 * row. */
static int span_rects(uint32_t W, uint32_t first, uint32_t last, int r[3][4])
{
    int w = (int)W, y0 = (int)(first / W), y1 = (int)(last / W), x0 = (int)(first % W), x1 = (int)(last % W), n = 0;
    if (y0 == y1) {
        r[0][0] = x0, r[0][1] = y0, r[0][2] = x1 - x0 + 1, r[0][3] = 1;
        return 1;
    }
    int ys = x0 ? y0 + 1 : y0, ye = x1 + 1 < w ? y1 - 1 : y1;
    if (x0)
        r[n][0] = x0, r[n][1] = y0, r[n][2] = w - x0, r[n][3] = 1, n++;
    if (ys <= ye)
        r[n][0] = 0, r[n][1] = ys, r[n][2] = w, r[n][3] = ye - ys + 1, n++;
    if (x1 + 1 < w)
        r[n][0] = 0, r[n][1] = y1, r[n][2] = x1 + 1, r[n][3] = 1, n++;
    return n;
}

/* Background over pixels [first, last] of the display's window: scissored
 * clears, a command each, no pixels. */
static void clear_span(const tsr_dispatch *d, uint32_t W, uint32_t first, uint32_t last)
{
    int r[3][4];
    int n = span_rects(W, first, last, r);
    tsr_call_Enable(d, GL_SCISSOR_TEST);
    for (int i = 0; i < n; i++) {
        tsr_call_Scissor(d, r[i][0], r[i][1], r[i][2], r[i][3]);
        tsr_call_Clear(d, GL_COLOR_BUFFER_BIT);
    }
    tsr_call_Disable(d, GL_SCISSOR_TEST); /* DrawPixels below must not be cut */
}

/* Scissored clears of the rectangles (the background: a command each, no
 * pixels); the scissor test is off again after them. */
static void clear_rects(const tsr_dispatch *d, const bswap_rect *r, size_t n)
{
    if (!n)
        return;
    tsr_call_Enable(d, GL_SCISSOR_TEST);
    for (size_t i = 0; i < n; i++) {
        tsr_call_Scissor(d, r[i].x, r[i].y, r[i].w, r[i].h);
        tsr_call_Clear(d, GL_COLOR_BUFFER_BIT);
    }
    tsr_call_Disable(d, GL_SCISSOR_TEST); /* DrawPixels must not be cut */
}

/* Puts this peer's final piece (pixels [start, start+count) of the window,
 * composited from every peer) into the display's frame, in this peer's
 * own context there. A depth-mode RGBA8 piece whose pixels from the first
 * to the last active one are all active is that span's colour plane as it
 * is: WindowPos2i + DrawPixels of the rectangles it crosses (span_rects),
 * the background before and after it as scissored clears. Any other piece
 * is drawn in bands (bands.h): one box per band around its active pixels
 * (inactive ones in it as the background), the rest of the piece as
 * scissored clears, so the display draws and the stream carries little
 * more than the active pixels. A piece without active pixels is clears
 * only, so no pixel of background travels. */
static void place_piece(bswap_spu *b, const tsr_dispatch *d, const tsr_sparse_image *in, const void *background,
                        uint32_t frame)
{
    uint32_t W = (uint32_t)in->window_width, end = in->start + in->count - 1;
    if (!in->active) {
        clear_span(d, W, in->start, end);
        return;
    }
    uint32_t lead = 0, trail = 0;
    for (uint32_t r = 0; r < in->nruns; r++) {
        lead += in->runs[2 * r];
        if (in->runs[2 * r + 1])
            break;
    }
    for (uint32_t r = in->nruns; r-- > 0;) {
        if (in->runs[2 * r + 1])
            break;
        trail += in->runs[2 * r];
    }
    uint32_t first = in->start + lead, last = end - trail;
    tsr_error err = {0};
    if (in->active == last - first + 1 && in->mode == TSR_COMPOSITE_DEPTH && in->color_format == TSR_CI_RGBA8) {
        if (lead)
            clear_span(d, W, in->start, first - 1);
        if (trail)
            clear_span(d, W, last + 1, end);
        /* The active pixels are in's colour plane, in order. */
        int r[3][4];
        int n = span_rects(W, first, last, r);
        for (int i = 0; i < n; i++) {
            size_t at = (size_t)r[i][1] * W + (size_t)r[i][0] - first;
            tsr_call_WindowPos2i(d, r[i][0], r[i][1]);
            tsr_call_DrawPixels(d, r[i][2], r[i][3], GL_RGBA, GL_UNSIGNED_BYTE, in->color + at * 4);
        }
        return;
    }
    if (bswap_bands_plan(&b->bands, in, BSWAP_CALL_PIXELS, &err) != TSR_OK)
        bswap_fatal(b, "frame %" PRIu32 ": %s", frame, err.message);
    clear_rects(d, b->bands.clears, b->bands.nclears);
    for (size_t i = 0; i < b->bands.nboxes; i++) {
        const bswap_rect *box = &b->bands.boxes[i];
        /* The box's rows: one view of them all, then each row's columns. */
        uint32_t from = (uint32_t)box->y * W + (uint32_t)box->x;
        uint32_t to = (uint32_t)(box->y + box->h - 1) * W + (uint32_t)(box->x + box->w - 1);
        if (tsr_cimage_init(&b->piece, in->window_width, in->window_height, box->x, box->y, box->w, box->h,
                            in->color_format, TSR_CI_NODEPTH, &err) != TSR_OK ||
            tsr_sparse_image_view(in, from, to - from + 1, &b->placed, &err) != TSR_OK)
            bswap_fatal(b, "frame %" PRIu32 ": %s", frame, err.message);
        for (int y = box->y; y < box->y + box->h; y++)
            if (tsr_sparse_image_view(&b->placed, (uint32_t)y * W + (uint32_t)box->x, (uint32_t)box->w, &b->row,
                                      &err) != TSR_OK ||
                tsr_sparse_image_to_dense(&b->row, background, &b->piece, &err) != TSR_OK)
                bswap_fatal(b, "frame %" PRIu32 ": %s", frame, err.message);
        const uint8_t *px = b->piece.color;
        if (in->color_format != TSR_CI_RGBA8) {
            if (bswap_frame_rgba8(&b->piece, &b->frame8, &b->frame8_size, &err) != TSR_OK)
                bswap_fatal(b, "frame %" PRIu32 ": %s", frame, err.message);
            px = b->frame8;
        }
        tsr_call_WindowPos2i(d, box->x, box->y);
        tsr_call_DrawPixels(d, box->w, box->h, GL_RGBA, GL_UNSIGNED_BYTE, px);
    }
}

/* Every peer released the last frame's messages before the display's
 * barrier, so what a connection still counts as out is a CREDIT on its
 * way: waiting for it here (no peer's progress is needed) starts this
 * frame's messages at their rings' start (ring_bytes), on the pages the
 * last frame used. */
static void await_releases(bswap_spu *b, uint32_t frame)
{
    if (!b->composited)
        return;
    for (int i = 0; i < b->nranks; i++) {
        tsr_error err = {0}, why = {0};
        if (i != b->rank && b->conns[i] &&
            tsr_net_conn_wait_returned(b->conns[i], b->timeout_ms > 0 ? b->timeout_ms : TSR_NET_WAIT_FOREVER, &err) !=
                TSR_OK) {
            peer_failed(b, i, err.code, NULL, err.message, &why);
            bswap_fatal(b, "frame %" PRIu32 ": %s", frame, why.message);
        }
    }
    b->composited = false;
}

/* Composites this frame with the group (the strategy's schedule) and puts
 * it on the display node, which is an ordinary shared-mode server with one
 * context per peer drawing into one window (server/node.h), as readback's
 * tile servers use it:
 *   every peer: its final piece (place_piece), straight from its process;
 *               the final pieces cover the window once
 *   every peer: BarrierExecTSR     every piece has landed
 *   rank 0: SwapBuffersTSR         the display writes the frame
 *   every peer: BarrierExecTSR     no piece of the next frame lands before
 * So no final piece travels twice and no peer assembles the frame. Only when
 * the display composites (gather to one: the same pixels from every peer)
 * does rank 0 run that part and place the frame it assembled. Colour only
 * travels to the display. */
static void composite_frame(bswap_spu *b, uint32_t frame)
{
    tsr_error err = {0};
    await_releases(b, frame);
    const tsr_cimage *mine = &b->mine;
    if (b->mode == TSR_COMPOSITE_ALPHA || b->colour != TSR_CI_RGBA8)
        mine = &b->layer;
    plan(b, mine->window_width, mine->window_height);
    b->last_bytes = 0;
    tsr_cs_transport t = {
        .user = b, .send = transport_send, .recv = transport_recv, .send_buffer = transport_send_buffer};
    /* A peer without a background pixel covered the whole window, so no
     * pixel of the frame is background and any colour does. */
    if (b->mode == TSR_COMPOSITE_ALPHA)
        bswap_background_rgba8(b->clear, b->background);
    float background_f[4];
    for (int c = 0; c < 4; c++)
        background_f[c] = (float)b->background[c] / 255.0f;
    const void *background = b->colour == TSR_CI_RGBA8 ? (const void *)b->background : (const void *)background_f;
    bool at_display = tsr_cs_schedule_display_composites(&b->plan);
    const tsr_sparse_image *final = NULL;
    /* place_piece draws the final piece as it is: it may come back filled */
    int rc = at_display
                 ? tsr_cs_run_peer(b->peer_ex, b->pos[b->rank], mine, b->mode, &t, &err)
                 : tsr_cs_run_peer_rounds(b->peer_ex, b->pos[b->rank], mine, b->mode, &t, background, &final, &err);
    if (rc != TSR_OK)
        bswap_fatal(b, "frame %" PRIu32 ": %s", frame, err.message);
    b->st.composited_ns = tsr_bswap_now_ns();
    tsr_cs_stats cs;
    tsr_cs_executor_stats(b->peer_ex, &cs);
    b->st.final_filled = cs.final_filled;
    tsr_log(TSR_LOG_DEBUG, "%s: frame %" PRIu32 ": rank %d sent %" PRIu64 " bytes to its peers", b->name, frame,
            b->rank, b->last_bytes);
    const tsr_dispatch *d = display(b);
    if (!at_display) {
        b->st.assembled_ns = b->st.composited_ns; /* the piece is final */
        if (final) {
            /* c / 255 is converted back to exactly c */
            tsr_call_ClearColor(d, background_f[0], background_f[1], background_f[2], background_f[3]);
            place_piece(b, d, final, background, frame);
        }
    } else if (b->rank == 0) {
        if (tsr_cs_run_display(b->display_ex, frame, b->mode, b->colour,
                               b->mode == TSR_COMPOSITE_DEPTH ? TSR_CI_DEPTH32F : TSR_CI_NODEPTH, background, &b->frame,
                               &t, &err) != TSR_OK)
            bswap_fatal(b, "frame %" PRIu32 ": %s", frame, err.message);
        const uint8_t *pixels = b->frame.color;
        if (b->colour != TSR_CI_RGBA8) {
            if (bswap_frame_rgba8(&b->frame, &b->frame8, &b->frame8_size, &err) != TSR_OK)
                bswap_fatal(b, "frame %" PRIu32 ": %s", frame, err.message);
            pixels = b->frame8;
        }
        b->st.assembled_ns = tsr_bswap_now_ns();
        tsr_call_WindowPos2i(d, 0, 0);
        tsr_call_DrawPixels(d, b->frame.width, b->frame.height, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    }
    release_held(b);
    tsr_call_BarrierExecTSR(d, BSWAP_DISPLAY_BARRIER);
    if (b->rank == 0)
        tsr_call_SwapBuffersTSR(d, b->window, 0);
    tsr_call_BarrierExecTSR(d, BSWAP_DISPLAY_BARRIER);
    if (b->rank == 0) {
        b->st.sent_ns = tsr_bswap_now_ns();
        if (b->stats_fd >= 0) {
            /* A reply comes after the display node swapped, which it does
             * after every peer's piece landed (the barrier): the time the
             * frame is there (one round trip per frame, stats only). */
            GLint viewport[4];
            tsr_call_GetIntegerv(d, GL_VIEWPORT, viewport);
            b->st.displayed_ns = tsr_bswap_now_ns();
        }
    } else {
        b->st.sent_ns = tsr_bswap_now_ns();
    }
    stats_frame(b, frame);
    b->composited = true;
}

static void exchange_order(bswap_spu *b, uint32_t frame);

/* render's frame hook: the frame is finished and still in the framebuffer. */
static void bswap_frame(void *ctx, int frame, void *render)
{
    (void)render;
    bswap_spu *b = ctx;
    b->st = (tsr_bswap_frame_stats){.swap_ns = tsr_bswap_now_ns(),
                                    .hook_cpu_ns = b->stats_fd >= 0 ? tsr_bswap_cpu_ns() : 0};
    display(b);
    int W = 0, H = 0;
    render_spu_size(b->render, &W, &H);
    link_peers(b, W, H);
    tsr_error err = {0};
    if (b->order_from_boxes && b->nranks > 1) {
        await_releases(b, (uint32_t)frame); /* the box distances go at the rings' start too */
        exchange_order(b, (uint32_t)frame);
    }
    if (b->mode == TSR_COMPOSITE_ALPHA) {
        /* Translucent geometry often leaves depth alone (DepthMask false),
         * so the depth buffer cannot find the region: the geometry's box
         * (roi.c) when known, else the whole window; outside what was
         * drawn the layer is the transparent clear, which compress drops. */
        int box[4] = {0, 0, W, H};
        if (!bswap_roi_frame(b->roi, box)) {
            box[0] = box[1] = 0;
            box[2] = W;
            box[3] = H;
        }
        if (bswap_read_colour(render_spu_read, b->render, W, H, box[0], box[1], box[2] - box[0], box[3] - box[1],
                              b->colour, NULL, &b->layer, &err))
            bswap_fatal(b, "%s", err.message);
        tsr_log(TSR_LOG_DEBUG, "%s: frame %d: rank %d alpha region [%d, %d, %d, %d] of %dx%d", b->name, frame, b->rank,
                box[0], box[1], box[2] - box[0], box[3] - box[1], W, H);
    } else if (b->synthetic) {
        synthetic_layer(b, W, H, (uint32_t)frame);
    } else {
        read_layer(b, (uint32_t)frame);
        if (b->colour != TSR_CI_RGBA8 &&
            bswap_read_colour(render_spu_read, b->render, W, H, b->mine.x, b->mine.y, b->mine.width, b->mine.height,
                              b->colour, b->mine.depth, &b->layer, &err))
            bswap_fatal(b, "%s", err.message);
    }
    b->layer.rank = b->rank;
    b->layer.frame = b->mine.frame = (uint32_t)frame;
    b->st.ready_ns = tsr_bswap_now_ns();
    composite_frame(b, (uint32_t)frame);
    b->frames++;
}

/* Alpha mode with boxes: this frame's view order (layers.h). Every peer
 * sends every other its box's distance, then reads theirs: a few bytes
 * on each connection, before the frame's images. */
static void exchange_order(bswap_spu *b, uint32_t frame)
{
    float mv[16], dist[BSWAP_MAX_PEERS];
    tsr_call_GetFloatv(b->table, GL_MODELVIEW_MATRIX, mv);
    dist[b->rank] = bswap_box_distance(b->box, mv);
    uint32_t bits;
    memcpy(&bits, &dist[b->rank], 4);
    uint8_t msg8[8];
    for (int i = 0; i < 4; i++) {
        msg8[i] = (uint8_t)(frame >> (8 * i));
        msg8[4 + i] = (uint8_t)(bits >> (8 * i));
    }
    int wait = b->timeout_ms > 0 ? b->timeout_ms : TSR_NET_WAIT_FOREVER;
    tsr_error err = {0};
    for (int r = 0; r < b->nranks; r++)
        if (r != b->rank && tsr_net_send(b->conns[r], BSWAP_KIND_ORDER, msg8, sizeof msg8, wait, &err) != TSR_OK) {
            tsr_error why = {0};
            peer_failed(b, r, err.code, NULL, err.message, &why);
            bswap_fatal(b, "frame %" PRIu32 ": %s", frame, why.message);
        }
    for (int r = 0; r < b->nranks; r++) {
        if (r == b->rank)
            continue;
        tsr_net_msg msg;
        int rc = tsr_net_recv(b->conns[r], &msg, wait, &err);
        bool ok = false;
        uint32_t their_frame = 0, their_bits = 0;
        tsr_error why = {0};
        if ((rc != 1 || msg.kind == BSWAP_KIND_ENDING) && peer_ended_on(b, r, rc == 1 ? &msg : NULL, &why))
            bswap_fatal(b, "frame %" PRIu32 ": %s", frame, why.message);
        if (rc == 1) {
            if (msg.kind == BSWAP_KIND_ORDER && msg.len == 8) {
                const uint8_t *m = msg.data;
                for (int i = 0; i < 4; i++) {
                    their_frame |= (uint32_t)m[i] << (8 * i);
                    their_bits |= (uint32_t)m[4 + i] << (8 * i);
                }
                memcpy(&dist[r], &their_bits, 4);
                ok = their_frame == frame && dist[r] == dist[r];
            }
            tsr_net_msg_release(&msg);
        }
        if (!ok)
            bswap_fatal(b, "frame %" PRIu32 ": peer rank %d (%s) %s", frame, r, peer_address(b, r),
                        rc == 1   ? "sent no box distance for this frame (does every peer have a box?)"
                        : rc == 0 ? "ended before sending its box distance"
                                  : "sent no box distance within timeout_ms");
    }
    bswap_order_by_distance(dist, b->nranks, b->view, b->pos);
    tsr_log(TSR_LOG_DEBUG, "%s: frame %" PRIu32 ": rank %d is at position %d of the view order (distance %g)", b->name,
            frame, b->rank, b->pos[b->rank], (double)dist[b->rank]);
}

/* Alpha mode: the application's clear colour is the background the
 * display adds once; the peer itself clears to transparent black, so its
 * layer holds only what it drew. */
static void bswap_ClearColor(void *self, GLfloat red, GLfloat green, GLfloat blue, GLfloat alpha)
{
    bswap_spu *b = self;
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
static void bswap_Clear_synthetic(void *self, GLbitfield mask)
{
    (void)self;
    (void)mask;
}

/* Alpha mode is exact only with a schedule that blends each pixel's layers
 * back to front in one place (tsr_cs_schedule_keeps_order): auto picks
 * among those, an explicit strategy that regroups the blend is refused.
 * The shape of a schedule depends on the peer count, not the window. */
static int alpha_strategy(bswap_spu *b, tsr_error *err)
{
    tsr_cs_schedule s;
    char why[160];
    int kind = b->kind == TSR_CS_AUTO && b->nranks > 8 ? TSR_CS_DIRECT : b->kind;
    if (tsr_cs_plan(kind, b->nranks, 64, 64, b->k, NULL, &s, err) != TSR_OK)
        return err->code;
    int ok = tsr_cs_schedule_keeps_order(&s, why, sizeof why);
    tsr_cs_schedule_free(&s);
    if (!ok)
        return tsr_error_set(err, TSR_EINVAL,
                             "mode=alpha with strategy %s for %d peers: %s; 8-bit and float rounding make that differ "
                             "from the back-to-front blend, use direct, gather or auto",
                             tsr_options_string(b->options, "strategy"), b->nranks, why);
    b->kind = kind;
    return TSR_OK;
}

/* --- the class -------------------------------------------------------------- */

static void window_size(void *ctx, int *w, int *h) { render_spu_size(((bswap_spu *)ctx)->render, w, h); }

/* One line per peer pair at the end of the run: which transport carried
 * this peer's images to each peer and back, and how much of it. */
static void log_transport_stats(const bswap_spu *b)
{
    for (int i = 0; i < b->nranks; i++) {
        if (!b->conns[i])
            continue;
        tsr_net_stats st;
        tsr_net_conn_stats(b->conns[i], &st);
        tsr_log(TSR_LOG_INFO,
                "%s: transport stats rank %d -> rank %d: %s; sent %" PRIu64 " messages %" PRIu64 " bytes (%" PRIu64
                " messages %" PRIu64 " bytes through shared memory); received %" PRIu64 " messages %" PRIu64
                " bytes (%" PRIu64 " messages %" PRIu64 " bytes through shared memory)",
                b->name, b->rank, i, tsr_net_conn_transport(b->conns[i]), st.messages_sent, st.bytes_sent,
                st.messages_sent_shm, st.bytes_sent_shm, st.messages_received, st.bytes_received,
                st.messages_received_shm, st.bytes_received_shm);
    }
}

static void bswap_destroy(void *self)
{
    bswap_spu *b = self;
    if (!b)
        return;
    render_spu_destroy(b->render);
    bswap_roi_destroy(b->roi);
    release_held(b);
    tsr_chain_destroy(b->out); /* sends what is left, waits for the display to run it */
    log_transport_stats(b);
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
    tsr_cs_executor_free(b->peer_ex);
    tsr_cs_executor_free(b->display_ex);
    if (b->plan.kind)
        tsr_cs_schedule_free(&b->plan);
    tsr_cimage_free(&b->mine);
    tsr_cimage_free(&b->frame);
    tsr_cimage_free(&b->piece);
    tsr_sparse_image_free(&b->placed);
    tsr_sparse_image_free(&b->row);
    bswap_bands_free(&b->bands);
    tsr_cimage_free(&b->layer);
    free(b->frame8);
    free(b->window_depth);
    if (b->stats_fd >= 0)
        close(b->stats_fd);
    free(b);
}

static void *bswap_create(const tsr_spu_init *init, tsr_error *err)
{
    bswap_spu *b = calloc(1, sizeof *b);
    if (!b) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    snprintf(b->name, sizeof b->name, "%s", init->instance_name);
    b->stats_fd = -1;
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
    if (n > BSWAP_MAX_PEERS) {
        tsr_error_set(err, TSR_EINVAL, "%s: %zu peers; at most %d", b->name, n, BSWAP_MAX_PEERS);
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
            if (derive_exchange(from_display, b->exchange[i], sizeof b->exchange[i], (int)i + 1, &e) != TSR_OK) {
                tsr_error_set(err, TSR_EINVAL, "%s: peer rank %zu: %s", b->name, i, e.message);
                goto fail;
            }
        } else if (node && derive_exchange(node, b->exchange[i], sizeof b->exchange[i], 0, &e) != TSR_OK) {
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
    if (tsr_cs_kind_parse(strategy, &b->kind, &b->k, &e) != TSR_OK) {
        tsr_error_set(err, TSR_EINVAL, "%s: strategy=%s: %s", b->name, strategy, e.message);
        goto fail;
    }
    if (tsr_options_int(init->options, "k"))
        b->k = (int)tsr_options_int(init->options, "k");
    if (bswap_colour_parse(tsr_options_string(init->options, "colour"), &b->colour, &e) != TSR_OK ||
        bswap_view_order(init->options, b->mode == TSR_COMPOSITE_ALPHA, b->nranks, b->view, b->pos, &e) != TSR_OK ||
        (b->mode == TSR_COMPOSITE_ALPHA && alpha_strategy(b, &e) != TSR_OK)) {
        tsr_error_set(err, TSR_EINVAL, "%s: %s", b->name, e.message);
        goto fail;
    }
    int has_box = 0;
    if (bswap_box_parse(init->options, b->box, &has_box, &e) != TSR_OK ||
        (has_box && b->mode != TSR_COMPOSITE_ALPHA &&
         tsr_error_set(&e, TSR_EINVAL, "box is for mode=alpha (depth mode composites in rank order)"))) {
        tsr_error_set(err, TSR_EINVAL, "%s: %s", b->name, e.message);
        goto fail;
    }
    if (tsr_image_codec_parse(tsr_options_string(init->options, "codec"), &b->codec, &e) != TSR_OK) {
        tsr_error_set(err, TSR_EINVAL, "%s: codec=%s: %s", b->name, tsr_options_string(init->options, "codec"),
                      e.message);
        goto fail;
    }
    if (b->colour == TSR_CI_RGBA32F && b->codec.color == TSR_CODEC_COLOR_YUV420) {
        tsr_error_set(err, TSR_EINVAL, "%s: codec=%s is for RGBA8 colour, not colour=rgba32f", b->name,
                      tsr_options_string(init->options, "codec"));
        goto fail;
    }
    if (tsr_synthetic_parse(tsr_options_string(init->options, "synthetic"), &b->synthetic, &e) != TSR_OK) {
        tsr_error_set(err, TSR_EINVAL, "%s: %s", b->name, e.message);
        goto fail;
    }
    if (b->synthetic && (b->mode != TSR_COMPOSITE_DEPTH || b->colour != TSR_CI_RGBA8)) {
        tsr_error_set(err, TSR_EINVAL,
                      "%s: synthetic=%s is a depth-mode RGBA8 layer: not with mode=alpha or colour=rgba32f", b->name,
                      tsr_options_string(init->options, "synthetic"));
        goto fail;
    }
    const char *stats = tsr_options_string(init->options, "stats");
    if (stats && stats[0] && (b->stats_fd = tsr_bswap_stats_open(stats, &e)) < 0) {
        tsr_error_set(err, TSR_EIO, "%s: %s", b->name, e.message);
        goto fail;
    }
    b->down = *init->child;
    tsr_set_WindowCreateTSR(&b->down, bswap_WindowCreateTSR, b);
    tsr_set_WindowSizeTSR(&b->down, bswap_WindowSizeTSR, b);
    tsr_spu_init render_init = *init;
    render_init.child = &b->down;
    render_hooks hooks = {.frame = bswap_frame, .ctx = b};
    b->render = render_spu_create(&render_init, &hooks, err);
    if (!b->render)
        goto fail;
    if (!(b->roi = bswap_roi_create(init->table, window_size, b, err))) {
        render_spu_destroy(b->render);
        goto fail;
    }
    /* alpha mode: the peers clear to transparent black (colour.c) */
    b->order_from_boxes = has_box && !tsr_options_count(init->options, "view_order");
    b->table = init->table;
    b->gl_clear_color = init->table->ClearColor;
    tsr_set_ClearColor(init->table, bswap_ClearColor, b);
    if (b->synthetic)
        tsr_set_Clear(init->table, bswap_Clear_synthetic, b);
    return b;
fail:
    if (b->stats_fd >= 0)
        close(b->stats_fd);
    free(b);
    return NULL;
}

static const tsr_option_spec bswap_options[] = {
    RENDER_OPTION_SPECS,
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
     .max = BSWAP_MAX_PEERS - 1,
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
     .max = BSWAP_MAX_PEERS,
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

static const tsr_spu_class bswap_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "binaryswap",
    .summary = "renders like render, then composites each frame's colour+depth with its peers "
               "(sort-last); each peer puts its final piece on a display node",
    .options = bswap_options,
    .option_count = sizeof bswap_options / sizeof bswap_options[0],
    .create = bswap_create,
    .destroy = bswap_destroy,
    .network = {.role = TSR_SPU_ROLE_PEERS,
                .display = "display",
                .rank = "rank",
                .peers = "peers",
                .token = TSR_NODE_CLIENT_TOKEN_OPTION},
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &bswap_class; }
