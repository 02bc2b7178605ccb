/* spus/binaryswap/strategies/strategy.h — sort-last compositing schedules
 * (binary swap, direct send, radix-k, gather to one, auto) and the executor
 * that runs one rank's part of a schedule over a transport the caller
 * supplies (send/receive callbacks: TCP, shared memory or in-memory queues,
 * the strategies do not know which).
 *
 * Owns: schedules (tsr_composite_schedule, plain data, freed with
 * tsr_composite_schedule_free), the executor's scratch images, and the queues of
 * the in-process transport (tsr_composite_memnet). Never: opens sockets, logs or
 * keeps process-wide state; a strategy is a pure function of (peer count,
 * window, k).
 *
 * Participants: ranks 0..nranks-1 are the peers, in compositing order
 * (depth mode: rank order; alpha mode: the caller maps view order to
 * ranks). The display is participant TSR_COMPOSITE_DISPLAY(nranks) == nranks; in
 * situ it may live in the same process as rank 0 (the transport then
 * delivers to itself).
 *
 * Regions are pixel index ranges of the window (tessera/dev/composite.h).
 * In each round a rank sends pieces of its current image, receives pieces
 * of its kept region from others, and composites them in the listed order
 * (each piece covers an interval of ranks adjacent to the next, front
 * first). After the last round each rank owns its final piece (maybe
 * empty), and the display receives every final piece and assembles the
 * frame (gather: compositing there in order when pieces overlap, as the
 * gather-to-one strategy does).
 *
 * Use (in an SPU, per frame):
 *
 *   tsr_composite_schedule s;                      // once per (N, window, strategy)
 *   tsr_composite_plan(TSR_COMPOSITE_AUTO, N, W, H, 0, &hint, &s, &err);  // s.reason says why
 *   tsr_composite_executor *ex = tsr_composite_executor_new(&s, codec, &err);
 *   tsr_composite_transport t = {.user = me, .send = my_send, .recv = my_recv};
 *   tsr_composite_run_peer(ex, rank, &mine, &t, &err);          // every peer
 *   tsr_composite_run_display(ex, background, &frame, &t, &err);  // display only
 */
#ifndef TSR_SPUS_BINARYSWAP_STRATEGY_H
#define TSR_SPUS_BINARYSWAP_STRATEGY_H

#include <stddef.h>
#include <stdint.h>
#include "tessera/dev/composite.h"
#include "tessera/error.h"

#define TSR_COMPOSITE_MAX_PEERS 64
#define TSR_COMPOSITE_DISPLAY(nranks) (nranks)

typedef enum tsr_composite_kind {
    TSR_COMPOSITE_AUTO = 0,
    TSR_COMPOSITE_BSWAP = 1,  /* binary swap, extra peers folded first */
    TSR_COMPOSITE_DIRECT = 2, /* direct send: every peer composites one strip from everyone */
    TSR_COMPOSITE_RADIXK = 3, /* radix-k with k (k=2: binary swap, k=N: direct send) */
    TSR_COMPOSITE_GATHER = 4, /* every peer sends its whole image to the display */
} tsr_composite_kind;

typedef struct tsr_composite_region {
    uint32_t start, count;
} tsr_composite_region;

typedef struct tsr_composite_xfer {
    int peer;                    /* to (send) or from (recv) */
    tsr_composite_region region; /* the pixels sent or received */
} tsr_composite_xfer;

typedef struct tsr_composite_round {
    int nsend;
    tsr_composite_xfer *send; /* pieces of this rank's current image */
    int nrecv;
    tsr_composite_xfer *recv;  /* pieces of `keep`, all with region == keep, in composite order */
    int self_index;            /* where this rank's own piece goes in that order (0..nrecv) */
    tsr_composite_region keep; /* this rank's image covers this after the round */
} tsr_composite_round;

typedef struct tsr_composite_rank {
    int nrounds;
    tsr_composite_round *rounds;
    tsr_composite_region final; /* piece owned after the last round (count 0: none) */
} tsr_composite_rank;

typedef struct tsr_composite_schedule {
    int kind; /* the strategy that made it (never AUTO) */
    int k;    /* radix (radix-k), 2 for bswap, nranks for direct */
    int nranks;
    int window_width, window_height;
    tsr_composite_rank *ranks; /* nranks entries */
    /* Display gather: pieces received, in composite order (final pieces of
     * ranks; overlapping pieces are composited front first). */
    int ngather;
    tsr_composite_xfer *gather;
    char reason[160]; /* why this strategy (for AUTO: from the inputs) */
    char name[32];    /* "bswap", "direct", "radixk-4", "gather" */
} tsr_composite_schedule;

/* What `auto` weighs: the bytes one peer's image encoded to last frame
 * (0 when unknown: assume a full frame) and whether the display is a
 * separate process. */
typedef struct tsr_composite_hint {
    uint64_t image_bytes;
    int display_separate;
} tsr_composite_hint;

/* Builds the schedule of `kind` for nranks (1..64) peers in a window.
 * `k` is radix-k's radix (2..nranks; 0 picks one); other kinds ignore it.
 * Bad arguments are TSR_EINVAL naming them. */
int tsr_composite_plan(int kind, int nranks, int window_width, int window_height, int k, const tsr_composite_hint *hint,
                       tsr_composite_schedule *out, tsr_error *err);
void tsr_composite_schedule_free(tsr_composite_schedule *s);
/* Parses "auto", "bswap", "direct", "radixk", "radixk-K" ("radix-k" too),
 * "gather"; *k gets K (0 when not given). */
int tsr_composite_kind_parse(const char *text, int *kind, int *k, tsr_error *err);
/* Checks the invariants every schedule must hold (sends match receives,
 * regions inside the window, each pixel of the window ends in exactly one
 * final piece with all ranks composited into it, composite orders are
 * adjacent intervals). TSR_EINVAL naming the first violation. */
int tsr_composite_schedule_check(const tsr_composite_schedule *s, tsr_error *err);

/* Whether the schedule keeps alpha mode exact: every composite it makes,
 * folded back to front (the executor's alpha order), puts only single
 * layers in front of the accumulated suffix, so every pixel is the serial
 * back-to-front blend L0 over (L1 over (... over Ln-1)) bit for bit,
 * whatever the rounding of "over". True for gather, direct send, one round
 * of radix-k (k >= N) and any schedule for 1 or 2 peers; false for binary
 * swap and multi-round radix-k with 3 or more peers, which regroup the
 * blend ((L0 over L1) over (L2 over L3)) and, with 8-bit or float
 * rounding, differ from the serial blend in the last bit. Writes the
 * reason (the first regrouping composite) into why. */
int tsr_composite_schedule_keeps_order(const tsr_composite_schedule *s, char *why, size_t why_size);

/* Per-strategy builders (one file each); tsr_composite_plan dispatches to them. */
int tsr_composite_plan_bswap(tsr_composite_schedule *s, tsr_error *err);
int tsr_composite_plan_direct(tsr_composite_schedule *s, tsr_error *err);
int tsr_composite_plan_radixk(tsr_composite_schedule *s, int k, tsr_error *err);
int tsr_composite_plan_gather(tsr_composite_schedule *s, tsr_error *err);
int tsr_composite_choose(int nranks, int window_width, int window_height, const tsr_composite_hint *hint, int *kind,
                         int *k, char *reason, size_t reason_size);

/* ---- executor ------------------------------------------------------------ */

typedef struct tsr_composite_transport {
    void *user;
    /* Sends a message to participant `to`. `data` is the executor's and is
     * reused after the call returns: send or copy it before returning. */
    int (*send)(void *user, int to, const void *data, size_t size, tsr_error *err);
    /* Receives the next message from participant `from` (blocking, with the
     * transport's own time-out; an error names the peer). The buffer stays
     * valid until the next recv call. */
    int (*recv)(void *user, int from, const void **data, size_t *size, tsr_error *err);
    /* Optional (NULL: the executor encodes into a buffer of its own): a
     * buffer of at least max_size bytes for the next message to `to`. The
     * executor encodes straight into it and passes it to send (data == the
     * buffer, size <= max_size), so a transport over shared memory gets
     * the message where it travels, never copied. NULL return: the error. */
    void *(*send_buffer)(void *user, int to, size_t max_size, tsr_error *err);
} tsr_composite_transport;

typedef struct tsr_composite_executor tsr_composite_executor;

/* An executor for schedule `s` (which must outlive it) and codec `c`. */
tsr_composite_executor *tsr_composite_executor_new(const tsr_composite_schedule *s, tsr_composite_codec c,
                                                   tsr_error *err);
void tsr_composite_executor_free(tsr_composite_executor *ex);

/* Runs rank `rank`'s rounds for one frame on its read-back image `mine`
 * (any region of interest of the schedule's window; rank and frame taken
 * from it) and sends its final piece to the display. */
int tsr_composite_run_peer(tsr_composite_executor *ex, int rank, const tsr_composite_image *mine, int mode,
                           const tsr_composite_transport *t, tsr_error *err);
/* The same rounds without the send to the display: *final is the rank's
 * final piece (a view of the executor's image, valid until its next run;
 * NULL when the rank owns none), composited from every rank whenever the
 * schedule places pieces directly (tsr_composite_schedule_display_composites is
 * false). A caller that puts the pieces on the display itself (the SPU's
 * display node, one piece from each peer) uses this. With `fill` (the
 * background colour, as tsr_composite_sparse_to_dense writes it) the final
 * piece may come back from a dense strip with its background pixels
 * filled in and counted as active: for a caller that draws it as it is
 * and merges it with nothing; NULL: never. */
int tsr_composite_run_peer_rounds(tsr_composite_executor *ex, int rank, const tsr_composite_image *mine, int mode,
                                  const tsr_composite_transport *t, const void *fill,
                                  const tsr_composite_sparse **final, tsr_error *err);
/* Whether the display composites (some region's pieces come from more
 * than one rank, as in gather to one) rather than only placing the final
 * pieces, each of which then holds every rank. */
int tsr_composite_schedule_display_composites(const tsr_composite_schedule *s);
/* The most bytes one participant sends another in one frame of this
 * schedule, every message at its largest (tsr_composite_message_max_size of
 * its region), over every ordered
 * pair of peers (participants are positions: the caller may map them to
 * any ranks); when the display composites, a peer's final piece on top
 * (it travels to rank 0, which may be any position). A shared-memory
 * ring of this size (plus room for small messages and the transport's
 * per-message rounding) holds a frame's
 * messages on its connection, and no second frame behind them. */
uint64_t tsr_composite_schedule_link_bytes(const tsr_composite_schedule *s, int color_format, int depth_format,
                                           tsr_composite_codec c);
/* The display's part: receives the final pieces of frame `frame` and writes
 * the whole window into `frame_out` (initialised here to the window, RGBA8
 * or the schedule's colour format), inactive pixels as `background`. */
int tsr_composite_run_display(tsr_composite_executor *ex, uint32_t frame, int mode, int color_format, int depth_format,
                              const void *background, tsr_composite_image *frame_out, const tsr_composite_transport *t,
                              tsr_error *err);

/* ---- in-process transport ----------------------------------------------- */

/* Queues between `participants` endpoints in one process (threads); a
 * receive waits at most timeout_ms. Endpoint i's transport: _transport. */
typedef struct tsr_composite_memnet tsr_composite_memnet;
tsr_composite_memnet *tsr_composite_memnet_new(int participants, int timeout_ms, tsr_error *err);
void tsr_composite_memnet_transport(tsr_composite_memnet *m, int me, tsr_composite_transport *out);
/* Drops every message still queued; returns how many (the first one's
 * endpoints in *from, *to): a finished frame leaves none. */
int tsr_composite_memnet_drain(tsr_composite_memnet *m, int *from, int *to);
void tsr_composite_memnet_free(tsr_composite_memnet *m);

/* Statistics of the last run (bytes and messages this executor sent). */
typedef struct tsr_composite_stats {
    uint64_t bytes_sent, messages_sent, bytes_received, messages_received;
    uint64_t pixels_merged; /* active pixels composited */
    uint64_t final_filled;  /* final pieces handed back filled (tsr_composite_run_peer_rounds' fill) */
} tsr_composite_stats;
void tsr_composite_executor_stats(const tsr_composite_executor *ex, tsr_composite_stats *out);
/* Bytes of pixel planes (colour and depth) the executor's images own now,
 * views excluded: what it keeps from frame to frame. */
size_t tsr_composite_executor_pixel_bytes(const tsr_composite_executor *ex);

#endif
