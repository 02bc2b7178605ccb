/* spus/tilesort/cost.c — the cost model of the balanced modes (bucket=kd,
 * bucket=union).
 *
 * Two halves, combined:
 *   the estimate: every flush and every sorted primitive adds to the cells
 *     of a fine grid (TS_COST_CELLS, finer than the regions) what it is
 *     guessed to cost: its bytes (its vertices) and the area of its window
 *     box (its fill), spread evenly over the cells the box covers, plus a
 *     small cost per window pixel (clear, swap, read-back). It is known
 *     the moment the frame is sent, so the very next frame starts from a
 *     good split before any time comes back.
 *   the measurement: each server reports the thread CPU time its chain
 *     spent on each frame (server/, tessera/dev/protocol.h
 *     TSR_NODE_MSG_COST), a frame or more later. Against the estimate of
 *     each server's regions in that frame (kept TS_COST_HISTORY frames)
 *     the times are fitted as a + b x estimate over the servers, and a
 *     server's speed is its time over the fit's (learn_speeds): 2 for a
 *     server twice as slow as the estimate says. Speeds are smoothed and
 *     kept within 1/4 .. 4.
 * The map the split balances is the estimate with every cell multiplied by
 * the speed of the server that drew it: where the time is spent comes from
 * the estimate, how much each server's share weighs from the measurement.
 * A server that has not reported (or stalls) keeps its speed (1 until its
 * first report, which is taken whole).
 *
 * Owns the cost cells and the per-server history; never sends anything and
 * never waits for a report. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tilesort.h"

int ts_cost_init(ts_cost *c, size_t servers, int w, int h)
{
    free(c->est);
    free(c->map);
    free(c->ratio);
    free(c->hist);
    free(c->measured);
    free(c->learned);
    memset(c, 0, sizeof *c);
    c->cols = w < TS_COST_CELLS ? (w > 0 ? w : 1) : TS_COST_CELLS;
    c->rows = h < TS_COST_CELLS ? (h > 0 ? h : 1) : TS_COST_CELLS;
    size_t cells = (size_t)c->cols * (size_t)c->rows;
    c->est = calloc(cells, sizeof *c->est);
    c->map = calloc(cells, sizeof *c->map);
    c->ratio = calloc(servers, sizeof *c->ratio);
    c->hist = calloc(TS_COST_HISTORY * servers, sizeof *c->hist);
    c->measured = malloc(TS_COST_HISTORY * servers * sizeof *c->measured);
    c->learned = calloc(TS_COST_HISTORY, 1);
    if (!c->est || !c->map || !c->ratio || !c->hist || !c->measured || !c->learned)
        return -1;
    for (size_t i = 0; i < TS_COST_HISTORY * servers; i++)
        c->measured[i] = -1;
    return 0;
}

void ts_cost_free(ts_cost *c)
{
    free(c->learned);
    free(c->est);
    free(c->map);
    free(c->ratio);
    free(c->hist);
    free(c->measured);
    memset(c, 0, sizeof *c);
}

double ts_cost_region(const ts_cost *c, const double *cells, int w, int h, double x0, double y0, double x1, double y1)
{
    double cw = (double)w / c->cols, ch = (double)h / c->rows;
    int c0 = (int)floor(x0 / cw), c1 = (int)ceil(x1 / cw), r0 = (int)floor(y0 / ch), r1 = (int)ceil(y1 / ch);
    double sum = 0;
    for (int r = r0 < 0 ? 0 : r0; r < r1 && r < c->rows; r++) {
        double oy = fmin(y1, (r + 1) * ch) - fmax(y0, r * ch);
        if (oy <= 0)
            continue;
        for (int k = c0 < 0 ? 0 : c0; k < c1 && k < c->cols; k++) {
            double ox = fmin(x1, (k + 1) * cw) - fmax(x0, k * cw);
            if (ox > 0)
                sum += cells[r * c->cols + k] * (ox * oy) / (cw * ch);
        }
    }
    return sum;
}

void ts_tiling_add_cost(ts_tiling *t, int x0, int y0, int x1, int y1, double bytes)
{
    ts_cost *c = &t->cost;
    if (!TS_BALANCED(t->mode) || !c->est || x1 <= x0 || y1 <= y0 || t->window_w <= 0 || t->window_h <= 0)
        return;
    double cw = (double)t->window_w / c->cols, ch = (double)t->window_h / c->rows;
    int c0 = (int)(x0 / cw), c1 = (int)((x1 - 1) / cw), r0 = (int)(y0 / ch), r1 = (int)((y1 - 1) / ch);
    c1 = c1 >= c->cols ? c->cols - 1 : c1;
    r1 = r1 >= c->rows ? c->rows - 1 : r1;
    c0 = c0 > c1 ? c1 : c0;
    r0 = r0 > r1 ? r1 : r0;
    double est = bytes * TS_EST_PER_BYTE + (double)(x1 - x0) * (double)(y1 - y0) * TS_EST_PER_PIXEL;
    double per = est / ((double)(c1 - c0 + 1) * (double)(r1 - r0 + 1));
    for (int r = r0; r <= r1; r++)
        for (int k = c0; k <= c1; k++)
            c->est[r * c->cols + k] += per;
}

static double servers_cost(const ts_tiling *t, const double *cells, size_t s)
{
    double sum = 0;
    for (size_t i = 0; i < t->ntiles[s]; i++) {
        const ts_rect *r = &t->tiles[s][i];
        sum += ts_cost_region(&t->cost, cells, t->window_w, t->window_h, r->x, r->y, r->x + r->w, r->y + r->h);
    }
    return sum;
}

void ts_tiling_report(ts_tiling *t, size_t s, uint64_t frame, double seconds)
{
    ts_cost *c = &t->cost;
    if (!TS_BALANCED(t->mode) || !c->hist || s >= t->servers || !(seconds >= 0) || !isfinite(seconds))
        return;
    c->reports++;
    /* only frames still in the history, and only closed ones */
    if (frame >= c->frame || c->frame - frame > TS_COST_HISTORY)
        return;
    c->measured[(size_t)(frame % TS_COST_HISTORY) * t->servers + s] = seconds;
}

/* Learns the servers' speeds from the frames of the history whose reports
 * are in (each frame once): the servers' times T against their estimates
 * E are fitted as T = a + b E over the servers (a: what a frame costs a
 * server whatever its region holds; b: seconds per estimate unit), and a
 * server's speed is its T over the fit's a + b E. The fixed part matters:
 * without it a server with a small region looks slow (its T is mostly
 * overhead), is given less, looks slower still, and the split runs away. */
static void learn_speeds(ts_tiling *t)
{
    ts_cost *c = &t->cost;
    size_t n = t->servers;
    for (uint64_t back = 1; back <= TS_COST_HISTORY && back <= c->frame; back++) {
        uint64_t f = c->frame - back;
        size_t row = (size_t)(f % TS_COST_HISTORY) * n;
        if (c->learned[f % TS_COST_HISTORY])
            continue;
        /* frame 0 is split evenly, before any cost is known: its regions
         * have little in common with the balanced ones, and a speed learnt
         * there (the estimate's local error averaged over an unrelated
         * region) threw the first balanced splits off (the 8x4 isosurface
         * went from 1.13 to 1.71 when frame 0's reports came in, 1.31 with
         * them learnt at a quarter weight). A server's own slowness is
         * then learnt from frame 1, and shows from frame 3. */
        if (f == 0) {
            c->learned[0] = 1;
            continue;
        }
        size_t got = 0;
        double se = 0, st = 0, see = 0, set = 0;
        for (size_t s = 0; s < n; s++)
            if (c->measured[row + s] >= 0) {
                double e = c->hist[row + s], v = c->measured[row + s];
                got++;
                se += e;
                st += v;
                see += e * e;
                set += e * v;
            }
        /* a frame is learnt from once every server reported, or, when some
         * never do (a stalled server), once it is about to leave the history */
        if (!got || (got < n && back < TS_COST_HISTORY))
            continue;
        c->learned[f % TS_COST_HISTORY] = 1;
        double k = (double)got, var = see - se * se / k, a = 0, b = 0;
        if (got >= 2 && var > 1e-12 * see) {
            b = (set - se * st / k) / var;
            a = (st - b * se) / k;
        }
        if (!(b > 0) || !(a >= 0)) { /* no usable spread: no fixed part */
            a = 0;
            b = se > 0 ? st / se : 0;
        }
        if (!(b > 0))
            continue;
        for (size_t s = 0; s < n; s++) {
            double v = c->measured[row + s], predicted = a + b * c->hist[row + s];
            if (v < 0 || !(predicted > 0))
                continue;
            double speed = v / predicted;
            speed = speed < 0.25 ? 0.25 : speed > 4.0 ? 4.0 : speed;
            c->ratio[s] = c->ratio[s] > 0 ? c->ratio[s] + t->smoothing * (speed - c->ratio[s]) : speed;
        }
    }
}

void ts_cost_close_frame(ts_tiling *t)
{
    ts_cost *c = &t->cost;
    size_t cells = (size_t)c->cols * (size_t)c->rows;
    double base = TS_EST_BASE_PER_PIXEL * (double)t->window_w * (double)t->window_h / (double)cells;
    for (size_t i = 0; i < cells; i++)
        c->est[i] += base; /* never 0: every region costs something, nothing divides by 0 */
    learn_speeds(t);
    size_t row = (size_t)(c->frame % TS_COST_HISTORY) * t->servers;
    c->learned[c->frame % TS_COST_HISTORY] = 0;
    for (size_t s = 0; s < t->servers; s++) {
        c->hist[row + s] = servers_cost(t, c->est, s);
        c->measured[row + s] = -1;
    }
    /* the map: each cell weighted by the speed of the server that owns its
     * centre now (unowned cells: 1) */
    double cw = (double)t->window_w / c->cols, ch = (double)t->window_h / c->rows;
    for (int r = 0; r < c->rows; r++)
        for (int k = 0; k < c->cols; k++) {
            double x = (k + 0.5) * cw, y = (r + 0.5) * ch, ratio = 1.0;
            for (size_t s = 0; s < t->servers; s++)
                for (size_t i = 0; i < t->ntiles[s]; i++) {
                    const ts_rect *q = &t->tiles[s][i];
                    if (x >= q->x && x < q->x + q->w && y >= q->y && y < q->y + q->h && c->ratio[s] > 0)
                        ratio = c->ratio[s];
                }
            c->map[r * c->cols + k] = c->est[r * c->cols + k] * ratio;
        }
    memset(c->est, 0, cells * sizeof *c->est);
    c->frame++;
}

double ts_cost_imbalance(const ts_tiling *t)
{
    double sum = 0, max = 0;
    for (size_t s = 0; s < t->servers; s++) {
        double v = servers_cost(t, t->cost.map, s);
        sum += v;
        max = v > max ? v : max;
    }
    return sum > 0 ? max * (double)t->servers / sum : 1.0;
}
