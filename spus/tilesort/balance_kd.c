/* spus/tilesort/balance_kd.c — bucket=kd (and its alias balance): Samanta
 * et al.'s KD-SPLIT. The window is split recursively, P - 1 axial lines,
 * into exactly one rectangle per server: a node covering `count` servers
 * splits its region across its longer side (fixed when the window size is
 * known, so regions keep their neighbours) at the median of the cost map
 * (cost.c), the position whose lower side holds count/2 of the count
 * servers' share. Each frame a split moves `damping` of the way towards
 * that position.
 *
 * Owns the KD tree's split positions; never a region narrower than one
 * pixel (a window at least as wide and high as the servers need). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tilesort.h"

/* Node k covers servers [first, first + count); internal nodes split their
 * region along `axis` at `at` (pixels from the window origin), children
 * 2k+1 (servers [first, first + count/2)) and 2k+2. */
struct ts_kd {
    int axis; /* 0: x, 1: y */
    double at;
};

static int kd_visit(ts_tiling *t, size_t k, double x0, double y0, double x1, double y1, size_t first, size_t count,
                    int shape)
{
    if (count == 1)
        return ts_tiling_set_one(t, first,
                                 (ts_rect){(int)lround(x0), (int)lround(y0), (int)lround(x1) - (int)lround(x0),
                                           (int)lround(y1) - (int)lround(y0)});
    struct ts_kd *node = &t->kd[k];
    size_t left = count / 2;
    double share = (double)left / (double)count;
    double lo, hi;
    if (shape) {
        node->axis = (x1 - x0) >= (y1 - y0) ? 0 : 1;
        lo = node->axis == 0 ? x0 : y0;
        hi = node->axis == 0 ? x1 : y1;
        node->at = lo + (hi - lo) * share;
    } else {
        lo = node->axis == 0 ? x0 : y0;
        hi = node->axis == 0 ? x1 : y1;
        const ts_cost *c = &t->cost;
        int w = t->window_w, h = t->window_h;
        double total = ts_cost_region(c, c->map, w, h, x0, y0, x1, y1);
        double target = node->at;
        if (total > 0) {
            /* bisect the position whose lower side holds `share` of the cost */
            double a = lo, b = hi;
            for (int it = 0; it < 40; it++) {
                double m = 0.5 * (a + b);
                double v = node->axis == 0 ? ts_cost_region(c, c->map, w, h, x0, y0, m, y1)
                                           : ts_cost_region(c, c->map, w, h, x0, y0, x1, m);
                if (v < share * total)
                    a = m;
                else
                    b = m;
            }
            target = 0.5 * (a + b);
        }
        node->at += t->damping * (target - node->at);
    }
    /* every server keeps at least one pixel row or column per side */
    double min_lo = lo + (double)left, max_hi = hi - (double)(count - left);
    if (min_lo <= max_hi)
        node->at = fmin(fmax(node->at, min_lo), max_hi);
    double at = round(node->at);
    int changed = 0;
    if (node->axis == 0) {
        changed |= kd_visit(t, 2 * k + 1, x0, y0, at, y1, first, left, shape);
        changed |= kd_visit(t, 2 * k + 2, at, y0, x1, y1, first + left, count - left, shape);
    } else {
        changed |= kd_visit(t, 2 * k + 1, x0, y0, x1, at, first, left, shape);
        changed |= kd_visit(t, 2 * k + 2, x0, at, x1, y1, first + left, count - left, shape);
    }
    return changed;
}

static size_t kd_nodes(const ts_tiling *t)
{
    size_t n = 1;
    while (n < t->servers)
        n *= 2;
    return 2 * n;
}

void *ts_kd_save(const ts_tiling *t)
{
    if (!t->kd)
        return NULL;
    void *copy = malloc(kd_nodes(t) * sizeof *t->kd);
    if (copy)
        memcpy(copy, t->kd, kd_nodes(t) * sizeof *t->kd);
    return copy;
}

void ts_kd_restore(ts_tiling *t, void *saved)
{
    if (saved && t->kd)
        memcpy(t->kd, saved, kd_nodes(t) * sizeof *t->kd);
    else if (!saved) { /* there were none: a split made since starts afresh */
        free(t->kd);
        t->kd = NULL;
    }
    free(saved);
}

int ts_kd_split(ts_tiling *t, int shape)
{
    if (!t->kd && !(t->kd = calloc(kd_nodes(t), sizeof *t->kd)))
        return -1;
    return kd_visit(t, 0, 0, 0, t->window_w, t->window_h, 0, t->servers, shape);
}
