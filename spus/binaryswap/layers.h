/* spus/binaryswap/layers.h — what the binaryswap SPU needs for alpha mode
 * and float colour, kept out of binaryswap.c: the view order (order.c) and
 * the colour layers (colour.c). Owns nothing; never keeps state of its
 * own (every function works on what the caller passes). */
#ifndef TSR_SPUS_BINARYSWAP_LAYERS_H
#define TSR_SPUS_BINARYSWAP_LAYERS_H

#include <stddef.h>
#include <stdint.h>

#include "tessera/dev/composite.h"
#include "tessera/error.h"
#include "tessera/options.h"

/* The compositing order of the group (order.c). Depth mode: rank order.
 * Alpha mode: the option `view_order` (ranks, front first; empty: rank 0
 * in front, rank order). Fills view[p] = the rank at position p and
 * pos[rank] = its position. A list that is not a permutation of 0..N-1 is
 * TSR_EINVAL naming the entry. */
int binaryswap_view_order(const tsr_options *o, int alpha, int nranks, int *view, int *pos, tsr_error *err);

/* The view order computed per frame (order.c): `box` is this peer's
 * object-space bounding box (xmin, ymin, zmin, xmax, ymax, zmax) under the
 * modelview current at SwapBuffers. Each peer sends the others the
 * distance of its box's centre in front of the eye (-z in eye space) and
 * every peer sorts the same numbers: nearest first, equal distance in rank
 * order. Right for parts that are separable along the view axis (convex
 * parts in depth slabs); the graph's view_order, when given, wins. */
int binaryswap_box_parse(const tsr_options *o, float box[6], int *has, tsr_error *err);
float binaryswap_box_distance(const float box[6], const float modelview[16]);
void binaryswap_order_by_distance(const float *distance, int nranks, int *view, int *pos);

/* `colour`: "rgba8" or "rgba32f" (colour.c). */
int binaryswap_colour_parse(const char *text, int *color_format, tsr_error *err);

/* An application's ClearColor as the RGBA8 background the display adds
 * once: round(clamp(c, 0, 1) * 255) per channel. */
void binaryswap_background_rgba8(const float rgba[4], uint8_t out[4]);

/* Reads the rectangle (x, y, w, h) of a W x H window's colour in
 * `color_format` into `out` (RGBA8 as GL_UNSIGNED_BYTE, RGBA32F as
 * GL_FLOAT), with depth copied from `depth` (w*h floats) when not NULL
 * (else NODEPTH). `read` is tsr_render_api.read (tessera/dev/render.h). */
typedef int (*binaryswap_read_fn)(void *render, int x, int y, int w, int h, unsigned format, unsigned type,
                                  void *pixels, tsr_error *err);
int binaryswap_read_colour(binaryswap_read_fn read, void *render, int W, int H, int x, int y, int w, int h,
                           int color_format, const float *depth, tsr_composite_image *out, tsr_error *err);

/* The display's float frame as RGBA8: round(clamp(v, 0, 1) * 255), the
 * one rounding of float colour. `*buf` grows as needed. */
int binaryswap_frame_rgba8(const tsr_composite_image *frame, uint8_t **buf, size_t *cap, tsr_error *err);

#endif
