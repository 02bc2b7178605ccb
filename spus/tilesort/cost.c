/* spus/tilesort/cost.c — the cost model of the balanced modes (bucket=kd,
 * bucket=union).
 *
 * A server's render time is modelled as (tilesort.h, TS_TERM_*)
 *   c0 + c_bytes x B + c_fill x F + c_area x A
 * with B the bytes its region's primitives bring (their vertices: setup),
 * F the pixels of those primitives' window boxes inside the region (their
 * fill), A the region's own pixels (its clear and the read-back of the
 * tile at the swap, whatever it holds) and c0 what a frame costs a server
 * whatever its region (the swap, per-call overhead).
 *   the estimate: every flush and every sorted primitive adds its bytes and
 *     its box area to the cells of a fine grid (TS_COST_CELLS, finer than
 *     the regions), spread evenly over the cells its box covers. It is
 *     known the moment the frame is sent, so the very next frame starts
 *     from a good split before any time comes back.
 *   the measurement: each server reports the thread CPU time its chain
 *     spent on each frame (server/, tessera/dev/protocol.h
 *     TSR_NODE_MSG_COST), a frame or more later, less what its page
 *     faults cost (a one-time cost of moving onto new pixels); a server's
 *     first frame with geometry is not learnt from. Against each server's
 *     B, F, A in that frame (kept TS_COST_HISTORY frames) the coefficients
 *     are fitted by least squares over the servers and the frames kept
 *     (fit: non-negative, drawn towards the priors' mix where the data
 *     cannot tell two terms apart). The priors (tilesort.h) are the fit's
 *     result on this renderer, so the first split from the estimate is
 *     already a good one; the fit follows another renderer, or the tests'
 *     costs of 1 ns per byte. Then each server's speed (learn_speeds): its
 *     time over a + b x its estimate fitted over the frame's servers (a:
 *     what the frame costs a server whatever it draws), 2 for a server
 *     twice as slow as the others, smoothed, shrunk by the measurement
 *     noise, kept within 1/4 .. 4.
 * Why the fill and area terms: on the 8x4 isosurface an evenly split
 * frame's servers differ 7x in bytes but 1.7x in time, and a split that
 * balanced bytes alone (byte imbalance 1.11) left the large, sparsely
 * filled regions twice as slow as the rest (time imbalance 2.04). With the
 * fitted terms the same split's servers' mean times over 14 frames are
 * within 1.07 of each other (bench/README.md).
 * The map the split balances is the model's cost of every cell, multiplied
 * by the speed of the server that drew it. A server that has not reported
 * (or stalls) keeps its speed (1 until its first report).
 *
 * Owns the cost cells, the coefficients and the per-server history; never
 * sends anything and never waits for a report. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/log.h"
#include "tilesort.h"

static const double prior[TS_TERMS] = {TS_PRIOR_FIXED, TS_PRIOR_BYTES, TS_PRIOR_FILL, TS_PRIOR_AREA};

/* Cells across `pixels`: one a pixel up to TS_COST_CELLS_MIN, then
 * TS_COST_CELLS_MIN up to TS_COST_CELL_PIXELS x that, finer beyond
 * (cells of TS_COST_CELL_PIXELS) up to TS_COST_CELLS. */
static int cost_cells(int pixels)
{
    if (pixels <= TS_COST_CELLS_MIN)
        return pixels > 0 ? pixels : 1;
    int cells = pixels / TS_COST_CELL_PIXELS;
    return cells < TS_COST_CELLS_MIN ? TS_COST_CELLS_MIN : cells > TS_COST_CELLS ? TS_COST_CELLS : cells;
}

int ts_cost_init(ts_cost *c, size_t servers, int w, int h)
{
    ts_cost_free(c);
    c->cols = cost_cells(w);
    c->rows = cost_cells(h);
    size_t cells = (size_t)c->cols * (size_t)c->rows;
    c->est_bytes = calloc(cells, sizeof *c->est_bytes);
    c->est_fill = calloc(cells, sizeof *c->est_fill);
    c->map = calloc(cells, sizeof *c->map);
    c->ratio = calloc(servers, sizeof *c->ratio);
    c->log_speed = calloc(servers, sizeof *c->log_speed);
    c->log_var = malloc(servers * sizeof *c->log_var);
    c->last_log = malloc(servers * sizeof *c->last_log);
    c->prev_log = malloc(servers * sizeof *c->prev_log);
    c->hist = calloc(TS_COST_HISTORY * servers * TS_TERMS, sizeof *c->hist);
    c->measured = malloc(TS_COST_HISTORY * servers * sizeof *c->measured);
    c->learned = calloc(TS_COST_HISTORY * servers, 1);
    c->first_draw = calloc(TS_COST_HISTORY * servers, 1);
    c->moved = calloc(TS_COST_HISTORY * servers, 1);
    c->drew = calloc(servers, 1);
    c->region_sig = calloc(servers, sizeof *c->region_sig);
    if (!c->moved || !c->region_sig || !c->est_bytes || !c->est_fill || !c->map || !c->ratio || !c->log_speed ||
        !c->log_var || !c->last_log || !c->prev_log || !c->hist || !c->measured || !c->learned || !c->first_draw ||
        !c->drew)
        return -1;
    for (size_t s = 0; s < servers; s++) {
        c->log_var[s] = -1;
        c->last_log[s] = NAN;
        c->prev_log[s] = NAN;
    }
    c->noise = TS_COST_NOISE;
    for (size_t i = 0; i < TS_COST_HISTORY * servers; i++)
        c->measured[i] = -1;
    memcpy(c->coef, prior, sizeof c->coef);
    return 0;
}

void ts_cost_free(ts_cost *c)
{
    free(c->learned);
    free(c->first_draw);
    free(c->moved);
    free(c->drew);
    free(c->region_sig);
    free(c->est_bytes);
    free(c->est_fill);
    free(c->map);
    free(c->ratio);
    free(c->log_speed);
    free(c->log_var);
    free(c->last_log);
    free(c->prev_log);
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
    if (!TS_BALANCED(t->mode) || !c->est_bytes || x1 <= x0 || y1 <= y0 || t->window_w <= 0 || t->window_h <= 0)
        return;
    double cw = (double)t->window_w / c->cols, ch = (double)t->window_h / c->rows;
    int c0 = (int)(x0 / cw), c1 = (int)((x1 - 1) / cw), r0 = (int)(y0 / ch), r1 = (int)((y1 - 1) / ch);
    c1 = c1 >= c->cols ? c->cols - 1 : c1;
    r1 = r1 >= c->rows ? c->rows - 1 : r1;
    c0 = c0 > c1 ? c1 : c0;
    r0 = r0 > r1 ? r1 : r0;
    double n = (double)(c1 - c0 + 1) * (double)(r1 - r0 + 1);
    double per_bytes = bytes / n, per_fill = (double)(x1 - x0) * (double)(y1 - y0) / n;
    for (int r = r0; r <= r1; r++)
        for (int k = c0; k <= c1; k++) {
            c->est_bytes[r * c->cols + k] += per_bytes;
            c->est_fill[r * c->cols + k] += per_fill;
        }
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

static double servers_area(const ts_tiling *t, size_t s)
{
    double sum = 0;
    for (size_t i = 0; i < t->ntiles[s]; i++)
        sum += (double)t->tiles[s][i].w * (double)t->tiles[s][i].h;
    return sum;
}

void ts_tiling_report(ts_tiling *t, size_t s, uint64_t frame, double seconds, double fault_seconds)
{
    ts_cost *c = &t->cost;
    if (!TS_BALANCED(t->mode) || !c->hist || s >= t->servers || !(seconds >= 0) || !isfinite(seconds))
        return;
    /* what the region costs once its pages are in: the faults of moving
     * onto pixels the server had not drawn are paid once, not per frame */
    if (fault_seconds > 0 && isfinite(fault_seconds))
        seconds -= fmin(fault_seconds, 0.9 * seconds);
    c->reports++;
    /* only frames still in the history, and only closed ones */
    if (frame >= c->frame || c->frame - frame > TS_COST_HISTORY || frame < TS_COST_WARMUP)
        return;
    size_t at = (size_t)(frame % TS_COST_HISTORY) * t->servers + s;
    if (!c->first_draw[at])
        c->measured[at] = seconds;
}

/* The estimate of a region from its terms: what varies with the region. */
static double estimate(const double coef[TS_TERMS], const double *terms)
{
    return coef[TS_TERM_BYTES] * terms[TS_TERM_BYTES] + coef[TS_TERM_FILL] * terms[TS_TERM_FILL] +
           coef[TS_TERM_AREA] * terms[TS_TERM_AREA];
}

/* Solves the k x k system a x = b (k <= TS_TERMS) by elimination with
 * partial pivoting; 0 when it is singular. */
static int solve(int k, double a[TS_TERMS][TS_TERMS], double b[TS_TERMS], double x[TS_TERMS])
{
    for (int i = 0; i < k; i++) {
        int p = i;
        for (int r = i + 1; r < k; r++)
            p = fabs(a[r][i]) > fabs(a[p][i]) ? r : p;
        if (!(fabs(a[p][i]) > 0))
            return 0;
        for (int j = 0; j < k; j++) {
            double v = a[i][j];
            a[i][j] = a[p][j];
            a[p][j] = v;
        }
        double v = b[i];
        b[i] = b[p];
        b[p] = v;
        for (int r = 0; r < k; r++)
            if (r != i) {
                double f = a[r][i] / a[i][i];
                for (int j = i; j < k; j++)
                    a[r][j] -= f * a[i][j];
                b[r] -= f * b[i];
            }
    }
    for (int i = 0; i < k; i++)
        x[i] = b[i] / a[i][i];
    return 1;
}

/* Ridge weight of the priors, as a fraction of each term's own weight in
 * the data: enough to decide between terms the data cannot tell apart,
 * too little to hold a term the data contradict. */
#define TS_PRIOR_WEIGHT 0.01

/* Fits the coefficients to every report of the history (frame 0
 * excepted), each server's time over its speed: in units of the priors
 * (x_j = prior_j x term_j, so every column is in seconds), least squares
 * with a ridge drawing each towards its prior, non-negative (a negative
 * one is fixed at 0 and the rest fitted again). 0 when no frame is learnt. */
static int fit(ts_tiling *t)
{
    ts_cost *c = &t->cost;
    size_t n = t->servers;
    double ata[TS_TERMS][TS_TERMS] = {{0}}, aty[TS_TERMS] = {0};
    size_t rows = 0;
    for (uint64_t back = 1; back <= TS_COST_HISTORY && back <= c->frame; back++) {
        uint64_t f = c->frame - back;
        if (f < TS_COST_WARMUP)
            continue;
        size_t row = (size_t)(f % TS_COST_HISTORY) * n;
        for (size_t s = 0; s < n; s++) {
            double v = c->measured[row + s];
            if (v < 0)
                continue;
            const double *terms = &c->hist[(row + s) * TS_TERMS];
            /* a server known to be slower or faster than the others says
             * little about the coefficients (with its time over its speed
             * alone, the speed's error bent the fit: the 2x slow server of
             * the tests, given less, made the fixed part look larger
             * every frame until the split moved again) */
            double r = c->ratio[s] > 0 ? c->ratio[s] : 1.0, q = log(r) / 0.15;
            double x[TS_TERMS], y = v / r, w = (c->moved[row + s] ? 0.1 : 1.0) / (1.0 + q * q * q * q);
            for (int j = 0; j < TS_TERMS; j++)
                x[j] = prior[j] * (j == TS_TERM_FIXED ? 1.0 : terms[j]);
            for (int i = 0; i < TS_TERMS; i++) {
                for (int j = 0; j < TS_TERMS; j++)
                    ata[i][j] += w * x[i] * x[j];
                aty[i] += w * x[i] * y;
            }
            rows++;
        }
    }
    /* a fit on a few reports swings wide: the first reports to come in
     * are of the servers with the least to draw, all alike, and say
     * little about the terms (on the 8x4 isosurface, fitted on 9 to 19
     * of them, the region pixel's coefficient came out 0.3 to 18 times
     * what 200 gave, and the split made from it was the run's worst;
     * bench/README.md): the priors stay until a frame's worth of reports
     * (as many as there are servers) is in */
    if (!rows || rows < n)
        return 0;
    double scale = 0;
    for (int j = 0; j < TS_TERMS; j++)
        scale = fmax(scale, ata[j][j]);
    if (!(scale > 0))
        return 0;
    /* the priors' mix at the data's scale: the one factor alpha that fits
     * the times best with the priors' proportions (a report of 1 ns per
     * byte, as the tests make, is a thousandth of a rendered frame) */
    double xx = 0, xy = 0;
    for (int i = 0; i < TS_TERMS; i++) {
        xy += aty[i];
        for (int j = 0; j < TS_TERMS; j++)
            xx += ata[i][j];
    }
    double alpha = xx > 0 && xy > 0 ? xy / xx : 1.0;
    for (int j = 0; j < TS_TERMS; j++) {
        double ridge = TS_PRIOR_WEIGHT * ata[j][j] + 1e-9 * scale;
        ata[j][j] += ridge;
        aty[j] += ridge * alpha; /* towards m_j = alpha: the priors' mix */
    }
    int free_term[TS_TERMS] = {1, 1, 1, 1};
    double m[TS_TERMS] = {0};
    for (int pass = 0; pass < TS_TERMS; pass++) {
        int idx[TS_TERMS], k = 0;
        for (int j = 0; j < TS_TERMS; j++)
            if (free_term[j])
                idx[k++] = j;
        double a[TS_TERMS][TS_TERMS], b[TS_TERMS], x[TS_TERMS];
        for (int i = 0; i < k; i++) {
            for (int j = 0; j < k; j++)
                a[i][j] = ata[idx[i]][idx[j]];
            b[i] = aty[idx[i]];
        }
        if (!solve(k, a, b, x))
            return 0;
        int worst = -1;
        for (int i = 0; i < k; i++)
            if (x[i] < 0 && (worst < 0 || x[i] < x[worst]))
                worst = i;
        for (int j = 0; j < TS_TERMS; j++)
            m[j] = 0;
        for (int i = 0; i < k; i++)
            m[idx[i]] = x[i];
        if (worst < 0)
            break;
        free_term[idx[worst]] = 0;
        m[idx[worst]] = 0;
    }
    for (int j = 0; j < TS_TERMS; j++)
        c->coef[j] = prior[j] * fmax(m[j], 0.0);
    /* every pixel costs something: no region's cost is ever 0 */
    c->coef[TS_TERM_AREA] = fmax(c->coef[TS_TERM_AREA], 1e-3 * prior[TS_TERM_AREA]);
    c->fits++;
    tsr_log(
        TSR_LOG_DEBUG,
        "tilesort: fit %llu at frame %llu on %zu reports: fixed %.3g s, %.3g s a byte, %.3g s a box pixel, %.3g s a region pixel",
        (unsigned long long)c->fits, (unsigned long long)c->frame, rows, c->coef[TS_TERM_FIXED], c->coef[TS_TERM_BYTES],
        c->coef[TS_TERM_FILL], c->coef[TS_TERM_AREA]);
    return 1;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median_of(double *v, size_t k)
{
    qsort(v, k, sizeof *v, cmp_double);
    return k % 2 ? v[k / 2] : 0.5 * (v[k / 2 - 1] + v[k / 2]);
}

/* The servers' speeds from the reports of `frames`. Per frame, the
 * servers' times T against their estimates E are fitted as T = a + b E
 * (a: what a frame costs a server whatever its region holds; without it
 * a server with a small region looks slow, is given less, looks slower
 * still, and the split runs away), and log(T / (a + b E)) is smoothed per
 * server (`smoothing`: the newest report's weight; the first taken
 * whole), together with the noise left in it. What is used is that log
 * speed shrunk towards 0 by the noise (James-Stein's positive part: a
 * deviation the size of the noise counts for nothing, one far out of it
 * nearly whole). Measured on the 8x4 isosurface, a server's time varies
 * 10-13 % from frame to frame on the same region; taken whole as a speed,
 * that noise moved the split every frame. A server twice as slow (log
 * 0.69 against a noise of 0.1) is taken nearly whole at once. The noise
 * is measured as it happens: half the square of the change of a server's
 * log speed from its previous report, the median over a frame's servers
 * (TS_COST_NOISE before any), so a deterministic cost (the tests') has
 * none. Speeds are relative to the median server, so the coefficients
 * carry the scale (fitted on times over speeds, the two would otherwise
 * drift apart: measured, every speed sank to 0.3-0.5 in 12 frames while
 * the coefficients grew). */
/* What a server's newest log speed says once a lone outlier is set aside:
 * the median of it and the two before (with one before, the one nearer
 * 0). On the 8x4 isosurface a server on an unchanged region took twice
 * its usual time in one frame of three to ten, a different server each
 * time (20.0, 21.4, 19.8 ms against a median of 10-11); taken as a speed,
 * each such frame moved the split twice, there and back. A server that is
 * slower for good is slower in every report and is learnt as before (its
 * first report is taken whole). */
static double robust_log(double x, double last, double prev)
{
    if (!isfinite(last))
        return x;
    if (!isfinite(prev))
        return fabs(x) < fabs(last) ? x : last;
    double lo = fmin(x, fmin(last, prev)), hi = fmax(x, fmax(last, prev));
    return x + last + prev - lo - hi;
}

static void learn_speeds(ts_tiling *t, const uint64_t *frames, size_t nframes)
{
    ts_cost *c = &t->cost;
    size_t n = t->servers;
    double *v = malloc(3 * n * sizeof *v), *logs = v ? v + n : NULL, *pairs = v ? v + 2 * n : NULL;
    if (!v)
        return;
    for (size_t i = nframes; i-- > 0;) { /* oldest first */
        size_t row = (size_t)(frames[i] % TS_COST_HISTORY) * n, k = 0, np = 0;
        /* the frame's fit, over all its reports: T = a + b E */
        double se = 0, st = 0, see = 0, set = 0, a = 0, b = 0;
        for (size_t s = 0; s < n; s++) {
            double e = estimate(c->coef, &c->hist[(row + s) * TS_TERMS]), m = c->measured[row + s];
            if (m < 0)
                continue;
            k++;
            se += e;
            st += m;
            see += e * e;
            set += e * m;
        }
        double kk = (double)k, var = k ? see - se * se / kk : 0;
        if (k >= 2 && var > 1e-12 * see) {
            b = (set - se * st / kk) / var;
            a = (st - b * se) / kk;
        }
        if (!(b > 0) || !(a >= 0)) { /* no usable spread: no fixed part */
            a = 0;
            b = se > 0 ? st / se : 0;
        }
        k = 0;
        for (size_t s = 0; s < n; s++) { /* the frame's median: all its reports */
            double m = c->measured[row + s], predicted = a + b * estimate(c->coef, &c->hist[(row + s) * TS_TERMS]);
            logs[s] = m > 0 && predicted > 0 ? log(m / predicted) : NAN;
            if (isfinite(logs[s]))
                v[k++] = logs[s];
        }
        if (!k)
            continue;
        double mid = median_of(v, k);
        for (size_t s = 0; s < n; s++) {
            if (!isfinite(logs[s]) || c->learned[row + s])
                continue; /* each report is taken once */
            c->learned[row + s] = 1;
            if (c->moved[row + s] && !isfinite(c->last_log[s]))
                continue;
            double raw = fmin(fmax(logs[s] - mid, log(0.25)), log(4.0)), w = t->smoothing;
            double x = robust_log(raw, c->last_log[s], c->prev_log[s]);
            if (isfinite(c->last_log[s]))
                pairs[np++] = 0.5 * (raw - c->last_log[s]) * (raw - c->last_log[s]);
            c->prev_log[s] = c->last_log[s];
            c->last_log[s] = raw;
            if (c->log_var[s] < 0) {
                c->log_speed[s] = x;
                c->log_var[s] = c->noise;
            } else {
                c->log_speed[s] += w * (x - c->log_speed[s]);
                c->log_var[s] = (1 - w) * (1 - w) * c->log_var[s] + w * w * c->noise;
            }
        }
        if (np >= 2 || np == n)
            c->noise = median_of(pairs, np);
    }
    size_t k = 0;
    for (size_t s = 0; s < n; s++)
        if (c->log_var[s] >= 0)
            v[k++] = c->log_speed[s];
    double mid = k ? median_of(v, k) : 0;
    for (size_t s = 0; s < n; s++) {
        if (c->log_var[s] < 0)
            continue;
        c->log_speed[s] -= mid;
        double d = c->log_speed[s], sq = d * d;
        double keep = sq > 0 ? fmax(0.0, 1.0 - c->log_var[s] / sq) : 0.0;
        c->ratio[s] = exp(d * keep);
    }
    free(v);
}

/* Learns from the reports in that were not learnt from yet: the
 * coefficients are fitted again, then the servers' speeds. Frame 0 is
 * never learnt from: it is split evenly before any cost is known and
 * holds each server's start-up (50-120 ms against 7-10 for a later frame
 * on the 8x4 isosurface). Frame 1, the first on the balanced regions,
 * once cost 1.7 times a later frame, unevenly; two causes, both now taken
 * out of what is learnt: the servers that had drawn nothing in frame 0
 * compile their shaders then (those first frames with geometry are not
 * learnt from: ts_cost_close_frame), and a region's new pixels fault
 * their pages in (the servers' fault seconds are taken off:
 * ts_tiling_report). Fitted on frame 1 as it came, the area coefficient
 * came out 5 times the later frames'. */
static void learn(ts_tiling *t)
{
    ts_cost *c = &t->cost;
    size_t n = t->servers;
    uint64_t fresh[TS_COST_HISTORY];
    size_t nfresh = 0;
    /* a report is learnt from as soon as it is in: with 32 servers sharing
     * two cores, the last of a frame's 32 reports came 2 to 10 frames after
     * the first (measured), so waiting for whole frames left the balancer
     * blind for most of the run */
    for (uint64_t back = 1; back <= TS_COST_HISTORY && back <= c->frame; back++) {
        uint64_t f = c->frame - back;
        size_t row = (size_t)(f % TS_COST_HISTORY) * n, got = 0;
        for (size_t s = 0; s < n && f >= TS_COST_WARMUP; s++)
            got += c->measured[row + s] >= 0 && !c->learned[row + s];
        if (got)
            fresh[nfresh++] = f;
    }
    if (!nfresh)
        return;
    fit(t);
    learn_speeds(t, fresh, nfresh);
}

/* FNV-1a over a server's tiles: equal for equal regions. */
static uint64_t region_signature(const ts_tiling *t, size_t s)
{
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < t->ntiles[s]; i++) {
        const ts_rect *r = &t->tiles[s][i];
        const int v[4] = {r->x, r->y, r->w, r->h};
        for (int j = 0; j < 4; j++)
            for (int b = 0; b < 32; b += 8) {
                h ^= ((uint32_t)v[j] >> b) & 0xffu;
                h *= 1099511628211ull;
            }
    }
    return h;
}

void ts_cost_close_frame(ts_tiling *t, const uint64_t *geometry)
{
    ts_cost *c = &t->cost;
    size_t cells = (size_t)c->cols * (size_t)c->rows;
    size_t row = (size_t)(c->frame % TS_COST_HISTORY) * t->servers;
    for (size_t s = 0; s < t->servers; s++) {
        double *terms = &c->hist[(row + s) * TS_TERMS];
        terms[TS_TERM_FIXED] = 1;
        terms[TS_TERM_BYTES] = servers_cost(t, c->est_bytes, s);
        terms[TS_TERM_FILL] = servers_cost(t, c->est_fill, s);
        terms[TS_TERM_AREA] = servers_area(t, s);
        c->measured[row + s] = -1;
        c->learned[row + s] = 0;
        /* A server's first frame with geometry costs it two to three
         * times a later one on the same region (measured on the 8x4
         * isosurface: 23-37 ms against 9-11; servers that had drawn in the
         * even split took 10-14), whatever its region: llvmpipe compiles
         * its shaders then. Learnt from, it made every fresh server look
         * slow and the next split worse than the estimate's. */
        c->first_draw[row + s] = geometry[s] > 0 && !c->drew[s];
        c->drew[s] |= geometry[s] > 0;
        /* The first frame on a moved region costs more again, whatever
         * its faults (measured on the 8x4 isosurface: 21.8 ms against a
         * median of 10.3 on the frame after a move; the model learnt
         * from it predicted 1.75 for a split that then measured 1.13, and
         * re-split, and the next split's first frame was inflated in
         * turn). Such a report counts a tenth in the fit, and is taken as
         * a speed only once the server has reports to take its median
         * with (skipping them all, the slow server of the tests, whose
         * first balanced frame is a moved one, was learnt frames late). */
        uint64_t sig = region_signature(t, s);
        c->moved[row + s] = c->frame > 0 && sig != c->region_sig[s];
        c->region_sig[s] = sig;
    }
    c->frame++;
    learn(t);
    /* the map: each cell's modelled cost, weighted by the speed of the
     * server that owns its centre now (unowned cells: 1) */
    double cw = (double)t->window_w / c->cols, ch = (double)t->window_h / c->rows;
    double area = c->coef[TS_TERM_AREA] * cw * ch;
    for (int r = 0; r < c->rows; r++)
        for (int k = 0; k < c->cols; k++) {
            double x = (k + 0.5) * cw, y = (r + 0.5) * ch, ratio = 1.0;
            for (size_t s = 0; s < t->servers; s++)
                for (size_t i = 0; i < t->ntiles[s]; i++) {
                    const ts_rect *q = &t->tiles[s][i];
                    if (x >= q->x && x < q->x + q->w && y >= q->y && y < q->y + q->h && c->ratio[s] > 0)
                        ratio = c->ratio[s];
                }
            size_t i = (size_t)r * (size_t)c->cols + (size_t)k;
            c->map[i] =
                ratio * (c->coef[TS_TERM_BYTES] * c->est_bytes[i] + c->coef[TS_TERM_FILL] * c->est_fill[i] + area);
        }
    memset(c->est_bytes, 0, cells * sizeof *c->est_bytes);
    memset(c->est_fill, 0, cells * sizeof *c->est_fill);
}

double ts_cost_measured_imbalance(const ts_tiling *t, uint64_t since)
{
    const ts_cost *c = &t->cost;
    size_t n = t->servers;
    if (!c->hist || !n)
        return -1;
    uint64_t first = c->frame > TS_COST_HISTORY ? c->frame - TS_COST_HISTORY : 0;
    first = since > first ? since : first;
    double times[TS_COST_HISTORY], sum = 0, max = 0;
    size_t have = 0;
    for (size_t s = 0; s < n; s++) {
        size_t k = 0;
        for (uint64_t f = first; f < c->frame; f++) {
            size_t at = (size_t)(f % TS_COST_HISTORY) * n + s;
            if (c->measured[at] >= 0 && !c->moved[at])
                times[k++] = c->measured[at];
        }
        if (!k)
            continue;
        double m = median_of(times, k);
        sum += m;
        max = m > max ? m : max;
        have++;
    }
    /* With 32 servers on two cores the last reports of a frame come
     * frames after the first; waiting for every server left a standing
     * split unmeasured for frames and re-split on the prediction alone.
     * Three quarters of the servers (and at least two) measure it. */
    if (have < 2 || have * 4 < n * 3)
        return have == n && n ? 1.0 : -1;
    return sum > 0 ? max * (double)have / sum : 1.0;
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
