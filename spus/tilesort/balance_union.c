/* spus/tilesort/balance_union.c — bucket=union: Samanta et al.'s
 * GRID_UNION, as one rectangle per server. The cells of the cost map
 * (cost.c, a fine grid finer than the regions) are merged greedily: the
 * window is cut across its longer side into strips of whole cells, a
 * strip for every few servers (about square regions), each strip as wide
 * as its servers' share of the cost (a sweep adding cell columns until
 * the running sum reaches the share, ending at whichever cell boundary is
 * nearer); then each strip's cells are swept the other way, one run of
 * whole cells per server. So every region is a union of grid cells, and
 * a rectangle; each boundary moves `damping` of the way to its new place
 * per frame.
 *
 * Owns the cut positions (cells). Never gives a server less than one cell
 * each way; a window with fewer cells than that needs falls back to kd. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tilesort.h"

/* Cuts n cells of costs line[0..n) into `parts` runs (cuts[0] = 0 .. cuts[parts]
 * = n), run j getting about weight[j] / sum of weights of the total, each
 * at least one cell. old: the previous cuts (NULL: none), approached by
 * `damping` of the way. */
static void greedy_cuts(const double *line, int n, int parts, const int *weight, const int *old, double damping,
                        int *cuts)
{
    double total = 0;
    int wsum = 0;
    for (int i = 0; i < n; i++)
        total += line[i];
    for (int j = 0; j < parts; j++)
        wsum += weight[j];
    cuts[0] = 0;
    cuts[parts] = n;
    double cum = 0;
    int i = 0, wbefore = 0;
    for (int j = 1; j < parts; j++) {
        wbefore += weight[j - 1];
        double target = total * (double)wbefore / (double)wsum;
        while (i < n && cum + line[i] < target) /* cum = cost of cells [0, i) */
            cum += line[i++];
        int cut = i;
        if (i < n && (cum + line[i]) - target < target - cum)
            cut = i + 1; /* the boundary after cell i is nearer the share */
        if (old)
            cut = (int)lround(old[j] + damping * (cut - old[j]));
        int lo = cuts[j - 1] + 1, hi = n - (parts - j);
        cuts[j] = cut < lo ? lo : cut > hi ? hi : cut;
    }
}

static int pixel_of(int cell, int cells, int pixels) { return (int)((long long)cell * pixels / cells); }

int ts_union_split(ts_tiling *t, int shape)
{
    const ts_cost *c = &t->cost;
    int P = (int)t->servers, W = t->window_w, H = t->window_h;
    int across_x = W >= H; /* strips are columns when the window is wide */
    int nu = across_x ? c->cols : c->rows, nv = across_x ? c->rows : c->cols;
    double eu = across_x ? W : H, ev = across_x ? H : W;
    int strips = (int)lround(sqrt((double)P * eu / ev));
    strips = strips < 1 ? 1 : strips > P ? P : strips;
    strips = strips > nu ? nu : strips;
    if ((P + strips - 1) / strips > nv) /* a strip's servers need a cell each */
        return ts_kd_split(t, shape);
    int *weight = malloc((size_t)strips * sizeof *weight);
    double *line = malloc((size_t)(nu > nv ? nu : nv) * sizeof *line);
    int *cuts = malloc((size_t)(strips + 1 + P + strips) * sizeof *cuts);
    if (!weight || !line || !cuts) {
        free(weight);
        free(line);
        free(cuts);
        return -1;
    }
    for (int k = 0; k < strips; k++)
        weight[k] = P / strips + (k < P % strips);
    const int *old = shape || t->ustrips != strips ? NULL : t->ucuts;
    int uniform = shape || !c->map;
    for (int u = 0; u < nu; u++) {
        line[u] = uniform ? 1.0 : 0.0;
        for (int v = 0; v < nv && !uniform; v++)
            line[u] += c->map[across_x ? v * c->cols + u : u * c->cols + v];
    }
    greedy_cuts(line, nu, strips, weight, old, t->damping, cuts);
    int *rows = cuts + strips + 1, changed = 0;
    size_t s = 0;
    for (int k = 0; k < strips; k++) {
        for (int v = 0; v < nv; v++) {
            line[v] = uniform ? 1.0 : 0.0;
            for (int u = cuts[k]; u < cuts[k + 1] && !uniform; u++)
                line[v] += c->map[across_x ? v * c->cols + u : u * c->cols + v];
        }
        int ones[TS_COST_CELLS];
        for (int j = 0; j < weight[k]; j++)
            ones[j] = 1;
        greedy_cuts(line, nv, weight[k], ones, old ? old + (rows - cuts) : NULL, t->damping, rows);
        int u0 = pixel_of(cuts[k], nu, (int)eu), u1 = pixel_of(cuts[k + 1], nu, (int)eu);
        for (int j = 0; j < weight[k]; j++, s++) {
            int v0 = pixel_of(rows[j], nv, (int)ev), v1 = pixel_of(rows[j + 1], nv, (int)ev);
            ts_rect r = across_x ? (ts_rect){u0, v0, u1 - u0, v1 - v0} : (ts_rect){v0, u0, v1 - v0, u1 - u0};
            changed |= ts_tiling_set_one(t, s, r);
        }
        rows += weight[k] + 1;
    }
    free(t->ucuts);
    t->ucuts = cuts;
    t->ustrips = strips;
    free(weight);
    free(line);
    return changed;
}
