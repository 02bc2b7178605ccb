/* spus/tilesort/bucket.c — which servers a geometry buffer must reach.
 *
 * A buffer's object-space box is taken to window space with the
 * application's own matrices and viewport (ts_window_box), grown by the
 * line width / point size, and tested against the tiling:
 *   broadcast  every server, always (the baseline tilesort is measured
 *              against);
 *   tiles      every tile of every server is tested (any layout);
 *   grid       the tiles form a grid of columns and rows (sizes may differ,
 *              e.g. 3x3 of 1024x768): the box's column and row ranges are
 *              found by binary search, so the cost does not grow with the
 *              number of tiles;
 *   kd         one rectangle per server, re-split every frame by recursive
 *              median splits of the cost (balance_kd.c; `balance` is its
 *              alias);
 *   union      one rectangle per server, whole cells of the cost grid
 *              merged greedily (balance_union.c).
 * The balanced modes (kd, union) split from cost.c's map: a per-primitive
 * estimate of this frame, weighted per server by the render time the
 * servers measured and reported. A new split is made only when the kept
 * one's predicted imbalance is above 1 + hysteresis, and not while the
 * servers' measured times on it are within 1 + 2 x hysteresis, unless the
 * prediction is above 1 + 3 x hysteresis.
 * Owns the tilings; never sends anything. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/log.h"
#include "tilesort.h"

static int rect_meets(const ts_rect *r, int x0, int y0, int x1, int y1)
{
    return r->x < x1 && x0 < r->x + r->w && r->y < y1 && y0 < r->y + r->h;
}

static int push_tile(ts_tiling *t, size_t s, ts_rect r)
{
    if (t->ntiles[s] == t->cap[s]) {
        size_t cap = t->cap[s] ? 2 * t->cap[s] : 4;
        ts_rect *n = realloc(t->tiles[s], cap * sizeof *n);
        if (!n)
            return -1;
        t->tiles[s] = n;
        t->cap[s] = cap;
    }
    t->tiles[s][t->ntiles[s]++] = r;
    return 0;
}

static int cmp_int(const void *a, const void *b)
{
    int x = *(const int *)a, y = *(const int *)b;
    return (x > y) - (x < y);
}

/* Distinct sorted values of v[0..n) into v; returns their count. */
static int distinct(int *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_int);
    int k = 0;
    for (int i = 0; i < n; i++)
        if (!k || v[k - 1] != v[i])
            v[k++] = v[i];
    return k;
}

static int find_index(const int *starts, int n, int value)
{
    for (int i = 0; i < n; i++)
        if (starts[i] == value)
            return i;
    return -1;
}

static int build_grid(ts_tiling *t, const char *who, tsr_error *err)
{
    size_t total = 0;
    for (size_t s = 0; s < t->servers; s++)
        total += t->ntiles[s];
    int *xs = malloc((2 * total + 2) * sizeof *xs), *ys = malloc((2 * total + 2) * sizeof *ys);
    if (!xs || !ys) {
        free(xs);
        free(ys);
        return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", who);
    }
    int nx = 0, ny = 0;
    for (size_t s = 0; s < t->servers; s++)
        for (size_t i = 0; i < t->ntiles[s]; i++) {
            const ts_rect *r = &t->tiles[s][i];
            xs[nx++] = r->x;
            xs[nx++] = r->x + r->w;
            ys[ny++] = r->y;
            ys[ny++] = r->y + r->h;
        }
    nx = distinct(xs, nx);
    ny = distinct(ys, ny);
    int cols = nx - 1, rows = ny - 1;
    int *owner = malloc((size_t)(cols > 0 ? cols : 1) * (size_t)(rows > 0 ? rows : 1) * sizeof *owner);
    if (!owner) {
        free(xs);
        free(ys);
        return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", who);
    }
    for (int i = 0; i < cols * rows; i++)
        owner[i] = -1;
    int rc = TSR_OK;
    for (size_t s = 0; s < t->servers && rc == TSR_OK; s++)
        for (size_t i = 0; i < t->ntiles[s] && rc == TSR_OK; i++) {
            const ts_rect *r = &t->tiles[s][i];
            int c0 = find_index(xs, nx, r->x), c1 = find_index(xs, nx, r->x + r->w);
            int r0 = find_index(ys, ny, r->y), r1 = find_index(ys, ny, r->y + r->h);
            if (c1 != c0 + 1 || r1 != r0 + 1)
                rc = tsr_error_set(err, TSR_EINVAL,
                                   "%s: bucket=grid: tile [%d, %d, %d, %d] of server %zu spans several grid "
                                   "cells (tiles must form columns and rows; use bucket=tiles)",
                                   who, r->x, r->y, r->w, r->h, s);
            else if (owner[r0 * cols + c0] != -1)
                rc = tsr_error_set(err, TSR_EINVAL, "%s: bucket=grid: tile [%d, %d, %d, %d] is given twice", who, r->x,
                                   r->y, r->w, r->h);
            else
                owner[r0 * cols + c0] = (int)s;
        }
    for (int i = 0; i < cols * rows && rc == TSR_OK; i++)
        if (owner[i] == -1)
            rc = tsr_error_set(err, TSR_EINVAL,
                               "%s: bucket=grid: no server has the grid cell at [%d, %d] (tiles must cover a "
                               "full grid; use bucket=tiles)",
                               who, xs[i % cols], ys[i / cols]);
    if (rc != TSR_OK) {
        free(xs);
        free(ys);
        free(owner);
        return rc;
    }
    t->grid_cols = cols;
    t->grid_rows = rows;
    t->grid_owner = owner;
    t->grid_nx = nx;
    t->grid_ny = ny;
    int *bounds = malloc((size_t)(nx + ny) * sizeof *bounds);
    if (!bounds) {
        free(xs);
        free(ys);
        return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", who);
    }
    memcpy(bounds, xs, (size_t)nx * sizeof *bounds);
    memcpy(bounds + nx, ys, (size_t)ny * sizeof *bounds);
    free(xs);
    free(ys);
    t->grid_bounds = bounds;
    return TSR_OK;
}

int ts_tiling_init(ts_tiling *t, ts_bucket_mode mode, size_t servers, const char *const *items, size_t nitems,
                   const char *who, tsr_error *err)
{
    memset(t, 0, sizeof *t);
    t->mode = mode;
    t->servers = servers;
    t->damping = 1.0;
    t->hysteresis = 0.1;
    t->smoothing = 0.5;
    t->tiles = calloc(servers, sizeof *t->tiles);
    t->ntiles = calloc(servers, sizeof *t->ntiles);
    t->cap = calloc(servers, sizeof *t->cap);
    if (!t->tiles || !t->ntiles || !t->cap)
        return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", who);
    for (size_t i = 0; i < nitems; i++) {
        long s, x, y, w, h;
        char tail;
        if (sscanf(items[i], "%ld:%ld:%ld:%ld:%ld%c", &s, &x, &y, &w, &h, &tail) != 5)
            return tsr_error_set(err, TSR_EINVAL, "%s: tiles: '%s' is not SERVER:X:Y:WIDTH:HEIGHT (e.g. 0:0:0:512:384)",
                                 who, items[i]);
        if (s < 0 || (size_t)s >= servers)
            return tsr_error_set(err, TSR_EINVAL, "%s: tiles: '%s' names server %ld, but there are %zu servers", who,
                                 items[i], s, servers);
        if (x < 0 || y < 0 || w < 1 || h < 1 || x + w > 65536 || y + h > 65536)
            return tsr_error_set(err, TSR_EINVAL, "%s: tiles: '%s' is outside 0..65536 or empty", who, items[i]);
        for (size_t o = 0; o < servers; o++)
            for (size_t k = 0; k < t->ntiles[o]; k++)
                if (rect_meets(&t->tiles[o][k], (int)x, (int)y, (int)(x + w), (int)(y + h)))
                    return tsr_error_set(err, TSR_EINVAL, "%s: tiles: '%s' overlaps tile %d:%d:%d:%d:%d", who, items[i],
                                         (int)o, t->tiles[o][k].x, t->tiles[o][k].y, t->tiles[o][k].w,
                                         t->tiles[o][k].h);
        if (push_tile(t, (size_t)s, (ts_rect){(int)x, (int)y, (int)w, (int)h}) != 0)
            return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", who);
    }
    if (mode == TS_TILES || mode == TS_GRID) {
        if (!nitems)
            return tsr_error_set(err, TSR_EINVAL,
                                 "%s: bucket=%s needs the servers' tiles (option tiles=SERVER:X:Y:W:H,...; "
                                 "tessera run fills it from the servers' tiles:)",
                                 who, mode == TS_GRID ? "grid" : "tiles");
        for (size_t s = 0; s < servers; s++)
            if (!t->ntiles[s])
                return tsr_error_set(err, TSR_EINVAL, "%s: tiles: server %zu has no tile", who, s);
    }
    if (mode == TS_GRID)
        return build_grid(t, who, err);
    return TSR_OK;
}

int ts_tiling_grid(ts_tiling *t, int cols, int rows, int w, int h, const char *who, tsr_error *err)
{
    if (w < cols || h < rows)
        return tsr_error_set(err, TSR_EINVAL, "%s: grid=%d,%d: the program's window %dx%d has fewer pixels than cells",
                             who, cols, rows, w, h);
    size_t n = (size_t)cols * (size_t)rows;
    char(*text)[128] = calloc(n, sizeof *text);
    const char **items = calloc(n, sizeof *items);
    if (!text || !items) {
        free(text);
        free(items);
        return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", who);
    }
    /* Server r * cols + c: column c from the left, row r from the bottom,
     * as a wall's tiles: [[0, 0, ..]] is server 0 (examples/graphs). */
    for (int r = 0; r < rows; r++)
        for (int c = 0; c < cols; c++) {
            size_t s = (size_t)r * (size_t)cols + (size_t)c;
            long x0 = (long)c * w / cols, x1 = (long)(c + 1) * w / cols;
            long y0 = (long)r * h / rows, y1 = (long)(r + 1) * h / rows;
            snprintf(text[s], sizeof text[s], "%zu:%ld:%ld:%ld:%ld", s, x0, y0, x1 - x0, y1 - y0);
            items[s] = text[s];
        }
    double damping = t->damping;
    ts_tiling_free(t);
    int rc = ts_tiling_init(t, TS_GRID, n, items, n, who, err);
    t->damping = damping;
    free(text);
    free(items);
    return rc;
}

void ts_tiling_free(ts_tiling *t)
{
    for (size_t s = 0; t->tiles && s < t->servers; s++)
        free(t->tiles[s]);
    free(t->tiles);
    free(t->ntiles);
    free(t->cap);
    free(t->grid_owner);
    free(t->grid_bounds);
    ts_cost_free(&t->cost);
    free(t->kd);
    free(t->ucuts);
    memset(t, 0, sizeof *t);
}

/* First index i with bounds[i + 1] > v (the cell containing v), clamped. */
static int cell_of(const int *bounds, int n, int v)
{
    int lo = 0, hi = n - 2;
    if (hi < 0)
        return 0;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (bounds[mid] <= v)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

size_t ts_tiling_hit(const ts_tiling *t, int x0, int y0, int x1, int y1, uint8_t *hit)
{
    size_t n = 0;
    memset(hit, 0, t->servers);
    if (t->mode == TS_BROADCAST) {
        memset(hit, 1, t->servers);
        return t->servers;
    }
    if (x1 <= x0 || y1 <= y0)
        return 0;
    if (t->mode == TS_GRID) {
        const int *xs = t->grid_bounds, *ys = t->grid_bounds + t->grid_nx;
        int nx = t->grid_nx, ny = t->grid_ny;
        if (x1 <= xs[0] || x0 >= xs[nx - 1] || y1 <= ys[0] || y0 >= ys[ny - 1])
            return 0;
        int c0 = cell_of(xs, nx, x0), c1 = cell_of(xs, nx, x1 - 1);
        int r0 = cell_of(ys, ny, y0), r1 = cell_of(ys, ny, y1 - 1);
        for (int r = r0; r <= r1; r++)
            for (int c = c0; c <= c1; c++) {
                int s = t->grid_owner[r * t->grid_cols + c];
                if (!hit[s]) {
                    hit[s] = 1;
                    n++;
                }
            }
        return n;
    }
    for (size_t s = 0; s < t->servers; s++)
        for (size_t i = 0; i < t->ntiles[s]; i++)
            if (rect_meets(&t->tiles[s][i], x0, y0, x1, y1)) {
                hit[s] = 1;
                n++;
                break;
            }
    return n;
}

/* --- balanced modes ---------------------------------------------------------- */

int ts_tiling_set_one(ts_tiling *t, size_t s, ts_rect r)
{
    int has = r.w > 0 && r.h > 0;
    int changed = t->ntiles[s] != (size_t)has || (has && memcmp(&t->tiles[s][0], &r, sizeof r) != 0);
    t->ntiles[s] = 0;
    if (has)
        push_tile(t, s, r);
    return changed;
}

static int split(ts_tiling *t, int shape)
{
    return t->mode == TS_UNION ? ts_union_split(t, shape) : ts_kd_split(t, shape);
}

int ts_tiling_window(ts_tiling *t, int w, int h, char *why, size_t why_size)
{
    if (!TS_BALANCED(t->mode)) {
        int need_w = 0, need_h = 0;
        const ts_rect *worst = NULL;
        size_t worst_server = 0;
        for (size_t s = 0; s < t->servers; s++)
            for (size_t i = 0; i < t->ntiles[s]; i++) {
                const ts_rect *r = &t->tiles[s][i];
                need_w = r->x + r->w > need_w ? r->x + r->w : need_w;
                need_h = r->y + r->h > need_h ? r->y + r->h : need_h;
                if (!worst && (r->x + r->w > w || r->y + r->h > h)) {
                    worst = r;
                    worst_server = s;
                }
            }
        if (worst) {
            snprintf(why, why_size,
                     "the program's window is %dx%d but the tiles cover %dx%d (tile [%d, %d, %d, %d] of server %zu "
                     "reaches outside it): give the graph's window: and tiles: the size of the window the program "
                     "opens",
                     w, h, need_w, need_h, worst->x, worst->y, worst->w, worst->h, worst_server);
            return -1;
        }
        return 0;
    }
    if (w == t->window_w && h == t->window_h && t->split_ready)
        return 0;
    t->window_w = w;
    t->window_h = h;
    if (ts_cost_init(&t->cost, t->servers, w, h) != 0 || split(t, 1) < 0) {
        tsr_log(TSR_LOG_ERROR, "tilesort: out of memory for the load balancer; sending to every server");
        t->mode = TS_BROADCAST;
        return 0;
    }
    if ((size_t)w < t->servers && (size_t)h < t->servers)
        tsr_log(TSR_LOG_WARN, "tilesort: a %dx%d window is too small to give each of %zu servers a pixel", w, h,
                t->servers);
    t->predicted = 1.0;
    t->split_frame = 0;
    t->split_ready = 1;
    return 0;
}

/* The balanced modes' split as it is (one rectangle or none per server,
 * and kd's or union's own positions), to put back when a new one is not
 * worth its move. */
typedef struct split_saved {
    ts_rect *rects;
    uint8_t *has;
    void *kd;
    int *ucuts;
    int ustrips;
} split_saved;

static int save_split(const ts_tiling *t, split_saved *v)
{
    memset(v, 0, sizeof *v);
    size_t ncuts = t->ucuts ? (size_t)t->ustrips + 1 + t->servers + (size_t)t->ustrips : 0;
    v->rects = malloc(t->servers * sizeof *v->rects);
    v->has = malloc(t->servers);
    v->ucuts = ncuts ? malloc(ncuts * sizeof *v->ucuts) : NULL;
    v->kd = ts_kd_save(t);
    if (!v->rects || !v->has || (ncuts && !v->ucuts) || (t->kd && !v->kd)) {
        free(v->rects);
        free(v->has);
        free(v->ucuts);
        free(v->kd);
        return -1;
    }
    for (size_t s = 0; s < t->servers; s++) {
        v->has[s] = t->ntiles[s] > 0;
        v->rects[s] = v->has[s] ? t->tiles[s][0] : (ts_rect){0, 0, 0, 0};
    }
    if (ncuts)
        memcpy(v->ucuts, t->ucuts, ncuts * sizeof *v->ucuts);
    v->ustrips = t->ustrips;
    return 0;
}

static void drop_split(split_saved *v)
{
    free(v->rects);
    free(v->has);
    free(v->ucuts);
    free(v->kd);
}

static void restore_split(ts_tiling *t, split_saved *v)
{
    for (size_t s = 0; s < t->servers; s++)
        ts_tiling_set_one(t, s, v->has[s] ? v->rects[s] : (ts_rect){0, 0, 0, 0});
    ts_kd_restore(t, v->kd);
    v->kd = NULL;
    free(t->ucuts);
    t->ucuts = v->ucuts;
    t->ustrips = v->ustrips;
    v->ucuts = NULL;
    drop_split(v);
}

int ts_tiling_rebalance(ts_tiling *t, const uint64_t *geometry)
{
    if (!TS_BALANCED(t->mode) || !t->split_ready)
        return 0;
    ts_cost_close_frame(t, geometry);
    /* hysteresis: a split that still balances the new map within
     * 1 + hysteresis is kept, so a static scene settles instead of
     * trembling by a cell or a pixel; and when even a new split would not
     * come within that, so is one the new split would not beat by more
     * than 1 + hysteresis times (union's whole cells balance the 8x4
     * isosurface to about 1.11, above 1.1: its split moved every frame
     * between equally good ones) */
    double now = ts_cost_imbalance(t);
    if (now <= 1.0 + t->hysteresis) {
        t->predicted = now;
        return 0;
    }
    /* ... and a split the servers' own times show within 1 + 2 x
     * hysteresis is kept unless the map predicts it past 1 + 3 x: each
     * move costs its servers a slow first frame, and the model's error on
     * a region can exceed the hysteresis (8x4 isosurface: a split measured
     * at 1.20 and 1.21 was predicted 1.26, moved, and its next frame
     * measured 1.59) */
    double seen = ts_cost_measured_imbalance(t, t->split_frame);
    if (seen >= 0 && seen <= 1.0 + 2 * t->hysteresis && now <= 1.0 + 3 * t->hysteresis) {
        t->predicted = now;
        tsr_log(TSR_LOG_DEBUG, "tilesort: frame %llu: split kept, measured at %.3f (predicted %.3f)",
                (unsigned long long)t->cost.frame, seen, now);
        return 0;
    }
    split_saved saved;
    int have_saved = save_split(t, &saved) == 0;
    int changed = split(t, 0);
    if (changed < 0) {
        if (have_saved)
            restore_split(t, &saved);
        tsr_log(TSR_LOG_ERROR, "tilesort: out of memory for the load balancer; the split stays");
        return 0;
    }
    double next = ts_cost_imbalance(t);
    if (have_saved && changed && next > 1.0 + t->hysteresis && now <= next * (1.0 + t->hysteresis)) {
        restore_split(t, &saved);
        t->predicted = now;
        tsr_log(TSR_LOG_DEBUG, "tilesort: frame %llu: split kept at a predicted %.3f (a new one: %.3f)",
                (unsigned long long)t->cost.frame, now, next);
        return 0;
    }
    tsr_log(TSR_LOG_DEBUG, "tilesort: frame %llu: %s at a predicted %.3f (the old one: %.3f)",
            (unsigned long long)t->cost.frame, changed ? "split again" : "split unchanged", next, now);
    if (have_saved)
        drop_split(&saved);
    t->predicted = next;
    if (changed)
        t->split_frame = t->cost.frame;
    return changed;
}

/* --- window-space box --------------------------------------------------------- */

/* The box code is the core's (core/wire/box.c, shared with binaryswap);
 * a corner at w <= 0 stays unknown here: every server gets the buffer. */
void ts_clip_matrix(const GLfloat *p, const GLfloat *m, double pm[16]) { tsr_box_clip_matrix(p, m, pm); }

static int unpack_box(int ok, const int box[4], int *x0, int *y0, int *x1, int *y1)
{
    if (ok) {
        *x0 = box[0];
        *y0 = box[1];
        *x1 = box[2];
        *y1 = box[3];
    }
    return ok;
}

int ts_window_box(const GLfloat *p, const GLfloat *m, const GLint *vp, const float mn[3], const float mx[3],
                  double margin, int win_w, int win_h, int *x0, int *y0, int *x1, int *y1)
{
    int box[4];
    return unpack_box(tsr_box_window(p, m, vp, mn, mx, margin, 0, win_w, win_h, box), box, x0, y0, x1, y1);
}

int ts_points_box(const double pm[16], const GLint *vp, const float (*pts)[4], int n, double margin, int win_w,
                  int win_h, int *x0, int *y0, int *x1, int *y1)
{
    int box[4];
    return unpack_box(tsr_box_points_window(pm, vp, pts, n, margin, 0, win_w, win_h, box), box, x0, y0, x1, y1);
}
