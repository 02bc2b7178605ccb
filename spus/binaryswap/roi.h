/* spus/binaryswap/roi.h — the region of interest from the geometry a peer
 * draws (roi.c says how). binaryswap only. */
#ifndef TSR_SPUS_BINARYSWAP_ROI_H
#define TSR_SPUS_BINARYSWAP_ROI_H

#include "tessera/dispatch.h"
#include "tessera/error.h"

typedef struct binaryswap_roi binaryswap_roi;

/* Wraps the slots set in `table` (render's own, which binaryswap takes
 * from its super, and binaryswap's window and swap): calls go on as
 * before, and the geometry's box is kept.
 * window_size(ctx) gives the window's size. */
binaryswap_roi *binaryswap_roi_create(tsr_dispatch *table, void (*window_size)(void *ctx, int *w, int *h), void *ctx,
                                      tsr_error *err);
void binaryswap_roi_destroy(binaryswap_roi *r);
/* At a swap: this frame's box [box[0], box[2]) x [box[1], box[3]) in
 * window pixels (all 0: nothing drawn), and 1 when it is known; 0 when
 * something was drawn that no box covers (then box[] is to be ignored).
 * Starts the next frame. */
int binaryswap_roi_frame(binaryswap_roi *r, int box[4]);

#endif
