/* spus/tilesort/tilesort.h — the tilesort SPU's parts, shared by its files:
 * tilesort.c routes every GL call (tracker, geometry buffer, display
 * lists, frame commands) and sends; bucket.c turns a geometry buffer's
 * object-space box into the servers it must reach and owns the tilings
 * (fixed tiles, grid, load-balanced KD split).
 * Private to the SPU. */
#ifndef TSR_TILESORT_H
#define TSR_TILESORT_H

#include <stddef.h>
#include <stdint.h>
#include <GL/gl.h>

#include "tessera/error.h"

typedef struct ts_rect {
    int x, y, w, h;
} ts_rect;

/* --- bucket.c ---------------------------------------------------------------- */

typedef enum ts_bucket_mode { TS_BROADCAST, TS_TILES, TS_GRID, TS_BALANCE } ts_bucket_mode;

/* Cost cells of the load-balanced mode: the window is divided into at most
 * TS_COST_CELLS x TS_COST_CELLS cells; each flush adds its bytes to the
 * cells its window box covers. */
#define TS_COST_CELLS 64

typedef struct ts_tiling {
    ts_bucket_mode mode;
    size_t servers;
    ts_rect **tiles;        /* tiles[s][0..ntiles[s]) */
    size_t *ntiles;
    size_t *cap;
    /* grid: cell (c, r) -> server; grid_bounds holds the grid_nx column
     * boundaries, then the grid_ny row boundaries (pixels, ascending) */
    int grid_cols, grid_rows, grid_nx, grid_ny;
    int *grid_owner;
    int *grid_bounds;
    /* load balance */
    int window_w, window_h;
    double *cost;           /* cost_cols x cost_rows, this frame */
    int cost_cols, cost_rows;
    double damping;         /* fraction of the way to the new split taken per frame */
    int split_ready;
    struct ts_kd *kd;       /* the KD tree's split positions */
} ts_tiling;

/* Parses "S:X:Y:W:H,..." entries (already split by the options layer). */
int ts_tiling_init(ts_tiling *t, ts_bucket_mode mode, size_t servers, const char *const *items, size_t nitems,
                   const char *who, tsr_error *err);
void ts_tiling_free(ts_tiling *t);
/* The window size became w x h: the load-balanced mode makes its first
 * (uniform) split; other modes check that tiles fit (a warning otherwise). */
void ts_tiling_window(ts_tiling *t, int w, int h);
/* Marks in `hit` (one byte per server) the servers whose tiles meet the
 * window rectangle [x0, x1) x [y0, y1); returns how many. */
size_t ts_tiling_hit(const ts_tiling *t, int x0, int y0, int x1, int y1, uint8_t *hit);
/* Load balance: a flush of `bytes` covered [x0, x1) x [y0, y1). */
void ts_tiling_add_cost(ts_tiling *t, int x0, int y0, int x1, int y1, double bytes);
/* Load balance, at the end of a frame: re-split the window among the
 * servers from this frame's costs (damped), reset the costs. Returns 1 when
 * some server's region changed. */
int ts_tiling_rebalance(ts_tiling *t);

/* --- the window-space box of a geometry buffer -------------------------------- */
/* Transforms the object-space box [mn, mx] by projection * modelview
 * (column-major) and the viewport to window coordinates, grows it by
 * `margin` pixels and clamps it to the window. Returns 1 with the integer
 * box [x0, x1) x [y0, y1) (possibly empty), or 0 when the box is unknown
 * (a corner at w <= 0, a non-finite value): then every server needs it. */
int ts_window_box(const GLfloat *projection, const GLfloat *modelview, const GLint *viewport, const float mn[3],
                  const float mx[3], double margin, int win_w, int win_h, int *x0, int *y0, int *x1, int *y1);

#endif
