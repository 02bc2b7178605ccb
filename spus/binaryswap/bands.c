/* spus/binaryswap/bands.c — the bands a final piece is drawn in (bands.h).
 *
 * Rows are those the piece's range crosses; the first and last may be
 * partial (the range starts or ends mid-row), and such a row is a band of
 * its own, so that every band's rows cover the same columns. The plan is
 * the cheapest cut of the rows into bands (dynamic programming over the
 * rows, bands up to BAND_ROWS tall): a band with active pixels costs
 * call_pixels plus its box's pixels plus a little per side clear; one
 * without costs a clear. */
#include "bands.h"

#include <stdlib.h>

#define BAND_ROWS 256 /* bounds the search at rows x BAND_ROWS steps */

static int grow(void **ptr, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap)
        return 0;
    size_t n = *cap ? *cap : 16;
    while (n < need)
        n *= 2;
    void *q = realloc(*ptr, n * size);
    if (!q)
        return -1;
    *ptr = q;
    *cap = n;
    return 0;
}

static int push(binaryswap_rect **list, size_t *n, size_t *cap, int x, int y, int w, int h)
{
    if (w <= 0 || h <= 0)
        return 0;
    if (grow((void **)list, cap, *n + 1, sizeof **list))
        return -1;
    (*list)[(*n)++] = (binaryswap_rect){x, y, w, h};
    return 0;
}

/* Grows every row array to `rows` (they share one capacity). */
static int grow_rows(binaryswap_bands *p, size_t rows)
{
    if (rows <= p->rows_cap)
        return 0;
    int32_t *lo = realloc(p->lo, rows * sizeof *lo);
    if (!lo)
        return -1;
    p->lo = lo;
    int32_t *hi = realloc(p->hi, rows * sizeof *hi);
    if (!hi)
        return -1;
    p->hi = hi;
    uint64_t *cost = realloc(p->cost, (rows + 1) * sizeof *cost);
    if (!cost)
        return -1;
    p->cost = cost;
    uint32_t *from = realloc(p->from, (rows + 1) * sizeof *from);
    if (!from)
        return -1;
    p->from = from;
    p->rows_cap = rows;
    return 0;
}

int binaryswap_bands_plan(binaryswap_bands *p, const tsr_composite_sparse *in, uint32_t call_pixels, tsr_error *err)
{
    p->nboxes = p->nclears = 0;
    if (!in->count)
        return TSR_OK;
    uint32_t W = (uint32_t)in->window_width, end = in->start + in->count - 1;
    uint32_t y0 = in->start / W, rows = end / W - y0 + 1;
    if (grow_rows(p, rows))
        return tsr_error_set(err, TSR_ENOMEM, "out of memory for the bands of %u rows", rows);
    /* The active columns of each row: [lo, hi], empty when lo > hi. */
    for (uint32_t r = 0; r < rows; r++)
        p->lo[r] = (int32_t)W, p->hi[r] = -1;
    uint32_t pos = in->start;
    for (uint32_t i = 0; i < in->nruns; i++) {
        pos += in->runs[2 * i];
        for (uint32_t n = in->runs[2 * i + 1]; n;) {
            uint32_t x = pos % W, len = W - x < n ? W - x : n, r = pos / W - y0;
            if ((int32_t)x < p->lo[r])
                p->lo[r] = (int32_t)x;
            if ((int32_t)(x + len - 1) > p->hi[r])
                p->hi[r] = (int32_t)(x + len - 1);
            pos += len;
            n -= len;
        }
    }
    /* Partial first and last rows stand alone (r == 0 / r == rows - 1). */
    int first_partial = in->start % W != 0 || (rows == 1 && end % W != W - 1);
    int last_partial = end % W != W - 1;
    uint64_t side = call_pixels / 16 + 1; /* a scissored clear: a command, no pixels */
    p->cost[0] = 0;
    for (uint32_t i = 1; i <= rows; i++) {
        p->cost[i] = UINT64_MAX;
        int32_t lo = (int32_t)W, hi = -1;
        uint32_t stop = i > BAND_ROWS ? i - BAND_ROWS : 0;
        for (uint32_t j = i; j-- > stop;) {
            /* band: rows j .. i-1 */
            if (p->lo[j] < lo)
                lo = p->lo[j];
            if (p->hi[j] > hi)
                hi = p->hi[j];
            if (i - j > 1 && ((j == 0 && first_partial) || (i == rows && last_partial)))
                break; /* a partial row only in a band of its own */
            uint64_t c;
            if (hi < lo) {
                c = side;
            } else {
                uint32_t cx0 = j == 0 ? in->start % W : 0, cx1 = i == rows ? end % W : W - 1;
                c = call_pixels + (uint64_t)(hi - lo + 1) * (i - j) + side * ((uint32_t)lo > cx0) +
                    side * ((uint32_t)hi < cx1);
            }
            if (p->cost[j] + c < p->cost[i])
                p->cost[i] = p->cost[j] + c, p->from[i] = j;
        }
    }
    /* Walk back from the top row, then reverse into bottom-to-top order. */
    for (uint32_t i = rows; i > 0; i = p->from[i]) {
        uint32_t j = p->from[i];
        int y = (int)(y0 + j), h = (int)(i - j);
        int cx0 = j == 0 ? (int)(in->start % W) : 0, cx1 = i == rows ? (int)(end % W) : (int)W - 1;
        int32_t lo = (int32_t)W, hi = -1;
        for (uint32_t r = j; r < i; r++) {
            if (p->lo[r] < lo)
                lo = p->lo[r];
            if (p->hi[r] > hi)
                hi = p->hi[r];
        }
        int rc = 0;
        if (hi < lo) {
            rc = push(&p->clears, &p->nclears, &p->clears_cap, cx0, y, cx1 - cx0 + 1, h);
        } else {
            rc = push(&p->boxes, &p->nboxes, &p->boxes_cap, lo, y, hi - lo + 1, h) ||
                 push(&p->clears, &p->nclears, &p->clears_cap, cx0, y, lo - cx0, h) ||
                 push(&p->clears, &p->nclears, &p->clears_cap, hi + 1, y, cx1 - hi, h);
        }
        if (rc)
            return tsr_error_set(err, TSR_ENOMEM, "out of memory for the bands of %u rows", rows);
    }
    for (size_t a = 0, z = p->nboxes; a + 1 < z; a++, z--) {
        binaryswap_rect t = p->boxes[a];
        p->boxes[a] = p->boxes[z - 1];
        p->boxes[z - 1] = t;
    }
    return TSR_OK;
}

void binaryswap_bands_free(binaryswap_bands *p)
{
    free(p->boxes);
    free(p->clears);
    free(p->lo);
    free(p->hi);
    free(p->cost);
    free(p->from);
    *p = (binaryswap_bands){0};
}
