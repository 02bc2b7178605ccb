/* spus/binaryswap/synthetic.h — generated colour+depth layers that stand in
 * for a peer's read-back (binaryswap's `synthetic` option), so a run times
 * compositing alone: the benchmarks (bench/run binaryswap, bench_composite)
 * and the tests hand the compositor exactly these layers.
 *
 *   full     every pixel covered; peer r's depth is smallest on about 1/N
 *            of the window (a vertical band per peer, its edges rippled),
 *            so each of N peers wins about 1/N of the pixels;
 *   ellipse  an ellipse of 40% of the window (inside it, wherever it is),
 *            centred at a different place per peer; the layer's region is
 *            the ellipse's box, pixels outside the ellipse at depth 1.0.
 *
 * A layer is a pure function of (mode, window, rank, N): no state, no
 * randomness, so a test can regenerate any peer's layer. Owns nothing
 * beyond the image it fills; never renders, reads GL or logs. */
#ifndef TSR_SPUS_BINARYSWAP_SYNTHETIC_H
#define TSR_SPUS_BINARYSWAP_SYNTHETIC_H

#include "tessera/dev/composite.h"
#include "tessera/error.h"

enum { TSR_COMPOSITE_SYNTHETIC_OFF = 0, TSR_COMPOSITE_SYNTHETIC_FULL = 1, TSR_COMPOSITE_SYNTHETIC_ELLIPSE = 2 };

/* "" or "off": TSR_COMPOSITE_SYNTHETIC_OFF; "full", "ellipse"; anything else is
 * TSR_EINVAL naming the value and the choices. */
int tsr_composite_synthetic_parse(const char *text, int *mode, tsr_error *err);

/* Fills `out` (tsr_composite_image_init'ed here, RGBA8 + 32-bit float depth) with
 * peer `rank` of `nranks`'s layer of a width x height window. */
int tsr_composite_synthetic_layer(int mode, int width, int height, int rank, int nranks, tsr_composite_image *out,
                                  tsr_error *err);

#endif
