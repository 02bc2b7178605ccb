/* spus/binaryswap/bands.h — how a peer's final piece is drawn on the
 * display when it has background pixels among its active ones (partial
 * layers): the piece's rows are cut into bands of consecutive rows, each
 * band drawn as one box (WindowPos2i + DrawPixels, its inactive pixels as
 * the background) around the band's active pixels, and the rest of the
 * band as scissored clears, which carry no pixels. The boxes and clears
 * together cover every pixel of the piece's range exactly once, and every
 * active pixel lies in a box. Bands are chosen to minimise the pixels sent
 * plus a fixed cost per DrawPixels (call_pixels), so a piece whose active
 * pixels span the window's width in every row is a single box, and one
 * that covers the middle of each row sends the middle only.
 *
 * Owns: the plan's arrays (reused from call to call). Never: reads or
 * writes pixels, calls GL. */
#ifndef TSR_SPUS_BINARYSWAP_BANDS_H
#define TSR_SPUS_BINARYSWAP_BANDS_H

#include <stddef.h>
#include <stdint.h>

#include "tessera/dev/composite.h"

typedef struct binaryswap_rect {
    int x, y, w, h; /* window pixels, origin bottom-left as GL's */
} binaryswap_rect;

typedef struct binaryswap_bands {
    binaryswap_rect *boxes;  /* DrawPixels of these, bottom to top */
    binaryswap_rect *clears; /* scissored clears of these */
    size_t nboxes, nclears, boxes_cap, clears_cap;
    /* scratch: per row of the piece, its active columns and the best plan
     * of the rows below it */
    int32_t *lo, *hi;
    uint64_t *cost;
    uint32_t *from;
    size_t rows_cap;
} binaryswap_bands;

/* Plans `in` (a final piece: a range of the window), replacing p's boxes
 * and clears. call_pixels: the cost of one more DrawPixels, counted in
 * pixels sent (a band merges rows while that costs less than a call).
 * Out of memory is TSR_ENOMEM. */
int binaryswap_bands_plan(binaryswap_bands *p, const tsr_composite_sparse *in, uint32_t call_pixels, tsr_error *err);
void binaryswap_bands_free(binaryswap_bands *p);

#endif
