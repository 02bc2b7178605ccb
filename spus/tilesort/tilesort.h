/* spus/tilesort/tilesort.h — the tilesort SPU's parts, shared by its files:
 * tilesort.c routes every GL call (tracker, geometry buffer, display
 * lists, frame commands) and send.c sends, with lists.c, arrays.c, frame.c
 * and gets.c (sharing the instance, instance.h); bucket.c turns a geometry
 * buffer's object-space box into the servers it must reach and owns the
 * tilings (fixed tiles, grid, load-balanced KD split); batch.c builds the
 * compact draws of a sorted array draw; split.c cuts a glBegin/glEnd
 * primitive that spans buffers into pieces, one per buffer.
 * Private to the SPU. */
#ifndef TSR_TILESORT_H
#define TSR_TILESORT_H

#include <stddef.h>
#include <stdint.h>
#include <GL/gl.h>

#include "tessera/error.h"
#include "tessera/dev/pack.h"
#include "tessera/dev/state.h"

typedef struct ts_rect {
    int x, y, w, h;
} ts_rect;

/* --- bucket.c ---------------------------------------------------------------- */

typedef enum ts_bucket_mode { TS_BROADCAST, TS_TILES, TS_GRID, TS_KD, TS_UNION } ts_bucket_mode;

/* Whether the mode re-splits the window every frame (kd, union). */
#define TS_BALANCED(mode) ((mode) == TS_KD || (mode) == TS_UNION)

/* Cost cells of the balanced modes (cost.c): at least TS_COST_CELLS_MIN
 * each way (one a pixel in a smaller window), cells of
 * TS_COST_CELL_PIXELS in a larger one, at most TS_COST_CELLS. Finer than
 * any server's region: with 32 servers on a 2048x1536 window the dense
 * regions are about 100 pixels wide, and union's whole-cell regions need
 * cells of 16 pixels to come within several percent of their share (64
 * cells of 32 pixels gave them 3 cells a region). */
#define TS_COST_CELLS_MIN 64
#define TS_COST_CELL_PIXELS 16
#define TS_COST_CELLS 128
/* Frames of per-server estimates kept to meet the servers' late reports. */
#define TS_COST_HISTORY 16
/* Frames never learnt from: the even split (cost.c) */
#define TS_COST_WARMUP 1
/* The noise of a report's log speed before any is measured: 0.1^2, a
 * server's time varied about 10 % from frame to frame on a fixed region
 * of the 8x4 isosurface (cost.c) */
#define TS_COST_NOISE 0.01

/* The cost model (cost.c). A server's render time is modelled as
 *   c0 + c_bytes x B + c_fill x F + c_area x A
 * B: the bytes of the primitives its region gets (their vertices), F: the
 * window-box area of those primitives inside the region (their fill), A:
 * the region's own pixels (clear, read-back of the tile: what an empty
 * region still costs), c0: a frame's fixed cost. B and F are estimated per
 * cell as the frame is sent; the coefficients are fitted to the servers'
 * measured times (least squares over the servers and the frames kept);
 * until the first fit they are the priors below, measured with the render
 * SPU (llvmpipe, one thread) on the isosurface (bench/README.md). */
enum { TS_TERM_FIXED, TS_TERM_BYTES, TS_TERM_FILL, TS_TERM_AREA, TS_TERMS };
#define TS_PRIOR_FIXED 3.5e-3 /* seconds a frame */
#define TS_PRIOR_BYTES 2.8e-9 /* seconds a byte */
#define TS_PRIOR_FILL 7.8e-9  /* seconds a pixel of primitive box */
#define TS_PRIOR_AREA 9.2e-9  /* seconds a pixel of region */

typedef struct ts_cost {
    int cols, rows;    /* cells */
    double *est_bytes; /* this frame's bytes per cell (cols x rows) */
    double *est_fill;  /* this frame's primitive box pixels per cell */
    double *
        map; /* what the split balances (seconds): the last frame's modelled cost, each cell times its server's ratio */
    double *ratio;         /* per server: its speed used by the split (1: typical; 0: none yet, 1 is used) */
    double *log_speed;     /* per server: log of measured time / the model's, smoothed, relative to the median */
    double *log_var;       /* per server: the noise variance left in log_speed; < 0: no report yet */
    double *last_log;      /* per server: its last report's log speed (NAN: none) */
    double *prev_log;      /* per server: the one before (NAN: none) */
    double noise;          /* variance of a report's log speed from one report to the next, smoothed */
    double *hist;          /* TS_COST_HISTORY rows of servers x TS_TERMS: each server's terms at that frame */
    double *measured;      /* TS_COST_HISTORY rows of servers: the seconds reported for that frame; < 0: none */
    uint8_t *learned;      /* TS_COST_HISTORY rows of servers: that report was learnt from (speeds) */
    uint8_t *first_draw;   /* TS_COST_HISTORY rows of servers: its first frame with geometry (not learnt from) */
    uint8_t *moved;        /* TS_COST_HISTORY rows of servers: its region differed from the frame before (cost.c) */
    uint8_t *drew;         /* per server: it has been sent geometry in a closed frame */
    uint64_t *region_sig;  /* per server: a hash of its tiles in the last closed frame */
    double coef[TS_TERMS]; /* the model's coefficients (seconds per unit) */
    uint64_t frame;        /* frames closed */
    uint64_t reports;      /* reports taken */
    uint64_t fits;         /* fits made */
} ts_cost;

typedef struct ts_tiling {
    ts_bucket_mode mode;
    size_t servers;
    ts_rect **tiles; /* tiles[s][0..ntiles[s]) */
    size_t *ntiles;
    size_t *cap;
    /* grid: cell (c, r) -> server; grid_bounds holds the grid_nx column
     * boundaries, then the grid_ny row boundaries (pixels, ascending) */
    int grid_cols, grid_rows, grid_nx, grid_ny;
    int *grid_owner;
    int *grid_bounds;
    /* balanced modes */
    int window_w, window_h;
    ts_cost cost;
    double damping;    /* fraction of the way to the new split taken per frame */
    double hysteresis; /* the split is kept while its predicted imbalance is within 1 + this */
    double smoothing;  /* weight of a new measurement in a server's ratio */
    int split_ready;
    struct ts_kd *kd;     /* kd: the tree's split positions */
    int *ucuts;           /* union: strip boundaries (cells), then each server's row boundaries */
    int ustrips;          /* union: strips */
    double predicted;     /* imbalance the last rebalance predicted for the split it kept or made */
    uint64_t split_frame; /* the first frame sent with the current split */
} ts_tiling;

/* Parses "S:X:Y:W:H,..." entries (already split by the options layer). */
int ts_tiling_init(ts_tiling *t, ts_bucket_mode mode, size_t servers, const char *const *items, size_t nitems,
                   const char *who, tsr_error *err);
void ts_tiling_free(ts_tiling *t);
/* option grid=C,R: (re)makes the tiling as C columns x R rows dividing a
 * w x h window (server r*C+c: column c, row r from the bottom). */
int ts_tiling_grid(ts_tiling *t, int cols, int rows, int w, int h, const char *who, tsr_error *err);
/* The window size became w x h: the balanced modes make its first
 * (uniform) split; other modes check that the tiles fit: -1 with `why`
 * naming both sizes and the first tile outside when they do not. */
int ts_tiling_window(ts_tiling *t, int w, int h, char *why, size_t why_size);
/* Marks in `hit` (one byte per server) the servers whose tiles meet the
 * window rectangle [x0, x1) x [y0, y1); returns how many. */
size_t ts_tiling_hit(const ts_tiling *t, int x0, int y0, int x1, int y1, uint8_t *hit);
/* Balanced modes: a flush (or a sorted primitive) of `bytes` covered
 * [x0, x1) x [y0, y1): its estimate is added to the cells it covers. */
void ts_tiling_add_cost(ts_tiling *t, int x0, int y0, int x1, int y1, double bytes);
/* Balanced modes: server s reported `seconds` for its frame `frame`, of
 * which `fault_seconds` were minor page faults. */
void ts_tiling_report(ts_tiling *t, size_t s, uint64_t frame, double seconds, double fault_seconds);
/* Balanced modes, at the end of a frame: re-split the window among the
 * servers from this frame's estimate and the measured ratios (damped,
 * kept within the hysteresis), reset the estimate. geometry[s]: the bytes
 * of geometry server s was sent in the frame (its first frame with any is
 * a warm-up, not learnt from: cost.c). Returns 1 when some server's region
 * changed. */
int ts_tiling_rebalance(ts_tiling *t, const uint64_t *geometry);

/* --- cost.c: the cost model of the balanced modes ------------------------- */
int ts_cost_init(ts_cost *c, size_t servers, int w, int h);
void ts_cost_free(ts_cost *c);
/* Cost of the pixel rectangle [x0, x1) x [y0, y1) in `cells` (est or map),
 * cells cut in part counted by the area inside. */
double ts_cost_region(const ts_cost *c, const double *cells, int w, int h, double x0, double y0, double x1, double y1);
/* The map for the next split (ts_cost.map) from the estimate and ratios;
 * records each server's estimate for this frame (its tiles now). */
void ts_cost_close_frame(ts_tiling *t, const uint64_t *geometry);
/* max / mean of the servers' costs on the map under the current tiles. */
double ts_cost_imbalance(const ts_tiling *t);
/* max / mean over the servers of the median time each reported for the
 * frames since `since` still in the history, leaving out a server's
 * first frame on a moved region, over the servers with such a report;
 * < 0 while fewer than three quarters of them (or than two) have one. */
double ts_cost_measured_imbalance(const ts_tiling *t, uint64_t since);

/* --- balance_kd.c, balance_union.c: the splits ----------------------------- */
/* (Re)builds the servers' tiles from ts_cost.map; shape: the first split
 * (uniform, no cost yet). Returns 1 when a region changed. */
int ts_kd_split(ts_tiling *t, int shape);
/* A copy of kd's split positions (NULL when none or out of memory), and
 * putting it back (freed either way; NULL: there were none). */
void *ts_kd_save(const ts_tiling *t);
void ts_kd_restore(ts_tiling *t, void *saved);
int ts_union_split(ts_tiling *t, int shape);
/* Replaces server s's tiles with r (or none when r is empty); returns 1
 * when they changed. */
int ts_tiling_set_one(ts_tiling *t, size_t s, ts_rect r);

/* --- the window-space box of a geometry buffer -------------------------------- */
/* Transforms the object-space box [mn, mx] by projection * modelview
 * (column-major) and the viewport to window coordinates, grows it by
 * `margin` pixels and clamps it to the window. Returns 1 with the integer
 * box [x0, x1) x [y0, y1) (possibly empty), or 0 when the box is unknown
 * (a corner at w <= 0, a non-finite value): then every server needs it. */
int ts_window_box(const GLfloat *projection, const GLfloat *modelview, const GLint *viewport, const float mn[3],
                  const float mx[3], double margin, int win_w, int win_h, int *x0, int *y0, int *x1, int *y1);

/* --- batch.c: a compact draw built primitive by primitive -------------------- */
typedef struct ts_batch {
    uint32_t *order; /* source vertex of each compact vertex */
    size_t nvert, vcap;
    uint32_t *index; /* indexed batches: the primitives' compact indices */
    size_t nidx, icap;
    uint32_t *keys, *values; /* source vertex + 1 -> compact vertex (0: empty) */
    size_t hcap;
} ts_batch;

/* Adds one primitive of n source vertices. Indexed: a vertex already in
 * the batch is used again, not added. Returns 0, or -1 when out of memory
 * or for source vertex UINT32_MAX (the primitive is then partly added). */
int ts_batch_add(ts_batch *b, const uint32_t *vertices, int n, int indexed);
void ts_batch_clear(ts_batch *b);
void ts_batch_free(ts_batch *b);

/* pm = projection * modelview (column-major), in double. */
void ts_clip_matrix(const GLfloat *projection, const GLfloat *modelview, double pm[16]);
/* The window-space box of n homogeneous object-space points under pm and
 * the viewport, as ts_window_box (0: unknown, every server needs it). */
int ts_points_box(const double pm[16], const GLint *viewport, const float (*pts)[4], int n, double margin, int win_w,
                  int win_h, int *x0, int *y0, int *x1, int *y1);

/* --- split.c: a glBegin/glEnd primitive cut across geometry buffers --------- */
/* A primitive that does not fit one geometry buffer is cut: each buffer
 * ending inside it is closed with glEnd (its box places it, like any
 * buffer), and the next one reopens it with glBegin and the vertices the
 * primitive still needs, each with the current attributes it had (the
 * header of split.c says what each mode carries and why it is exact). */

/* The current attributes (what a geometry buffer starts with, what a
 * carried vertex had). */
typedef struct ts_current {
    GLfloat color[4], normal[3], texcoord[TSR_STATE_UNITS][4];
    GLboolean edge_flag;
    GLfloat attrib[TSR_STATE_ATTRIBS][4];
} ts_current;
void ts_current_of(const tsr_state_values *v, ts_current *out);

typedef struct ts_split ts_split;
ts_split *ts_split_create(tsr_error *err);
void ts_split_destroy(ts_split *sp);
/* Whether the geometry buffer being filled starts inside a cut primitive
 * (its flush then goes through ts_split_piece even after glEnd). */
int ts_split_open(const ts_split *sp);
/* Before glEnd is packed: a line loop that was cut is closed with its
 * first vertex, sent through `route` (the SPU's own table: the geometry
 * buffer and the tracker); the attributes are put back to `now`. */
void ts_split_end(ts_split *sp, const tsr_dispatch *route, const ts_current *now);

enum {
    TS_SPLIT_PIECE = 1, /* send *out to the servers its box (with the carried vertices) touches */
    TS_SPLIT_WHOLE,     /* send *out to every server, and the rest of the primitive too (not cut) */
    TS_SPLIT_NOTHING,   /* send nothing (attributes only: the next piece restores them) */
};
/* State that keeps some modes from being cut (split.c says why). */
enum { TS_SPLIT_LINE_STIPPLE = 1u, TS_SPLIT_LIGHTING = 2u };
/* In the geometry sink, for a buffer that ends inside glBegin/glEnd
 * (ends_inside) or starts inside a cut primitive (ts_split_open): buf
 * holds its commands, start/end the current attributes at its start and
 * end. may_cut: 0 while a program is in use;
 * state: TS_SPLIT_* bits of what is enabled. The carried vertices are added to
 * box's bounding box (box is the geometry packer; its pixel store is how
 * images in buf were packed). Sets *out (valid until the next call).
 * Returns TS_SPLIT_*, or an error code (*out is then buf). */
int ts_split_piece(ts_split *sp, const uint8_t *buf, size_t size, const ts_current *start, const ts_current *end,
                   int ends_inside, int may_cut, unsigned state, tsr_packer *box, const uint8_t **out, size_t *out_size,
                   tsr_error *err);

#endif
