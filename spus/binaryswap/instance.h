/* spus/binaryswap/instance.h — one binaryswap peer (binaryswap.c's header
 * comment says what it does) and what its files call across one another:
 * binaryswap.c (creation, options, the class), mesh.c (peer mesh and the
 * transport the strategies run over), layer.c (read-back of this peer's
 * layer), compositing.c (the frame hook: plan and run the strategy),
 * display.c (the final piece drawn on the display, over the display stream
 * readback shares, spus/display_stream/display_stream.h),
 * stats.c (the stats= lines, transport statistics). Private to the SPU.
 * Owns the instance struct; never state outside it. */
#ifndef TSR_SPUS_BINARYSWAP_INSTANCE_H
#define TSR_SPUS_BINARYSWAP_INSTANCE_H

#include <stdbool.h>
#include <stdint.h>

#include "bands.h"
#include "display_stream.h"
#include "tessera/dev/net.h"
#include "roi.h"
#include "stats.h"
#include "strategy.h"
#include "tessera/chain.h"
#include "tessera/dev/render.h"
#include "tessera/spu.h"

#define BINARYSWAP_MAX_PEERS 64
#define BINARYSWAP_KIND_HELLO (TSR_NET_KIND_FIRST_USER + 0)
#define BINARYSWAP_KIND_IMAGE (TSR_NET_KIND_FIRST_USER + 1)
#define BINARYSWAP_KIND_ORDER (TSR_NET_KIND_FIRST_USER + 2)  /* alpha mode: a box's distance */
#define BINARYSWAP_KIND_ENDING (TSR_NET_KIND_FIRST_USER + 3) /* a peer's last word: the line it ends on */
/* The group's frame fence on the display node (its parallel API, server/node.h). */
#define BINARYSWAP_DISPLAY_BARRIER 0x54534c42u /* "TSLB" */
/* What one more DrawPixels of a partial piece costs, in pixels sent (the
 * display's per-call state checks and texture, a command): a band of the
 * piece grows while that is cheaper than a call (bands.h). */
#define BINARYSWAP_CALL_PIXELS 8192u

/* A message queued for this process's own display participant (rank 0
 * sends its final piece to itself). */
typedef struct local_msg {
    struct local_msg *next;
    size_t size;
    uint8_t data[];
} local_msg;

typedef struct binaryswap_spu {
    char name[96];
    const tsr_render_api *render_api; /* the super's (tessera/dev/render.h) */
    void *render;                     /* the super instance: draws, writes PNGs */
    binaryswap_roi *roi;              /* the region of interest from the geometry (roi.c) */
    const tsr_dispatch *super;        /* render's table */
    const tsr_dispatch *child;
    const tsr_options *options;
    int window, rank, nranks, timeout_ms;
    char exchange[BINARYSWAP_MAX_PEERS][TSR_NET_ADDRESS_MAX];

    tsr_net *net;
    tsr_net_listener *listener;
    tsr_net_conn *conns[BINARYSWAP_MAX_PEERS]; /* conns[rank] stays NULL */
    bool linked;
    bool meshed;     /* every peer linked and its HELLO read: a peer's last word may follow */
    bool composited; /* a frame's messages went out and their releases are not yet awaited */

    display_stream display; /* to the display node (readback's too) */

    int kind, k;                 /* strategy asked for (tsr_composite_kind) and radix */
    tsr_composite_codec codec;   /* of image messages */
    tsr_composite_schedule plan; /* for plan_width x plan_height; kind 0: none yet */
    int plan_width, plan_height;
    tsr_composite_executor *peer_ex, *display_ex; /* display_ex: rank 0 only */
    uint64_t last_bytes;                          /* this peer's bytes sent last frame (auto's hint) */
    tsr_net_msg held;                             /* the message recv handed out last */
    bool holding;
    local_msg *local_head, *local_tail; /* rank 0 -> its own display participant */
    local_msg *local_given;             /* handed out by recv, freed at the next */
    local_msg *local_building;          /* given by send_buffer, queued by send */
    void *reserved;                     /* send_buffer's buffer for a peer (netlib's) */

    uint32_t frames; /* frames composited */
    float *window_depth;
    size_t window_depth_size;
    tsr_composite_image mine;    /* this frame's region of interest */
    tsr_composite_image frame;   /* rank 0, when the display composites (gather): the assembled frame */
    binaryswap_bands bands;      /* how this peer's final piece is drawn (partial pieces) */
    tsr_composite_sparse placed; /* the rows of one box of the final piece (a view) */
    tsr_composite_sparse row;    /* one row of it (a view of placed) */
    tsr_composite_image piece;   /* ... as the colour the display draws (the box) */
    uint8_t background[4];
    bool has_background; /* background[] is a pixel this peer left cleared */

    /* alpha mode and float colour (layers.h) */
    int mode, colour;                                          /* tsr_composite_mode, tsr_composite_color_format */
    int view[BINARYSWAP_MAX_PEERS], pos[BINARYSWAP_MAX_PEERS]; /* position -> rank, rank -> position */
    tsr_entry gl_clear_color;                                  /* render's ClearColor */
    const tsr_dispatch *table;                                 /* this instance's (GetFloatv) */
    float box[6];                                              /* this part's object-space box */
    bool order_from_boxes;                                     /* box given, view_order not */
    float clear[4];                                            /* the application's clear colour (alpha mode) */
    tsr_composite_image layer;                                 /* alpha or float: what is composited */
    uint8_t *frame8;                                           /* float colour: the frame as RGBA8 */
    size_t frame8_size;
    int synthetic;             /* TSR_COMPOSITE_SYNTHETIC_*: a generated layer instead of the read-back */
    int stats_fd;              /* stats= file, or -1 */
    binaryswap_frame_stats st; /* this frame's times */
} binaryswap_spu;

/* mesh.c */
/* One line naming the fault, the peers told (a formed mesh), then the
 * process ends with status 1. */
void binaryswap_fatal(binaryswap_spu *b, const char *fmt, ...) __attribute__((format(printf, 2, 3), noreturn));
/* The exchange address of a peer whose node listens at `node`; with
 * display_rank R > 0, of application peer R-1 from the display's address. */
int binaryswap_derive_exchange(const char *node, char *out, size_t size, int display_rank, tsr_error *err);
static inline const char *binaryswap_peer_address(const binaryswap_spu *b, int rank) { return b->exchange[rank]; }
void binaryswap_link_peers(binaryswap_spu *b, int W, int H);
void binaryswap_release_held(binaryswap_spu *b);
void *binaryswap_transport_send_buffer(void *user, int to, size_t max_size, tsr_error *err);
int binaryswap_transport_send(void *user, int to, const void *data, size_t size, tsr_error *err);
int binaryswap_transport_recv(void *user, int from, const void **data, size_t *size, tsr_error *err);
void binaryswap_await_releases(binaryswap_spu *b, uint32_t frame);
void binaryswap_exchange_order(binaryswap_spu *b, uint32_t frame);

/* layer.c */
void binaryswap_read_layer(binaryswap_spu *b, uint32_t frame);
void binaryswap_synthetic_layer(binaryswap_spu *b, int W, int H, uint32_t frame);

/* compositing.c */
void binaryswap_plan(binaryswap_spu *b, int W, int H);
/* What the peer does with each frame of its window that render ended. */
void binaryswap_frame(binaryswap_spu *b, int frame);

/* display.c */
/* Sets up the display stream (made at first use) and points `table`'s
 * window commands at it, then at `next`. */
void binaryswap_display_init(binaryswap_spu *b, tsr_dispatch *table, const tsr_dispatch *next);
/* The display's table (a peer that cannot reach it ends). */
const tsr_dispatch *binaryswap_display(binaryswap_spu *b);
void binaryswap_place_piece(binaryswap_spu *b, const tsr_dispatch *d, const tsr_composite_sparse *in,
                            const void *background, uint32_t frame);

/* stats.c */
void binaryswap_stats_frame(binaryswap_spu *b, uint32_t frame);
void binaryswap_log_transport_stats(const binaryswap_spu *b);

#endif
