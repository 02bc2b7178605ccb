/* spus/binaryswap/colour.c — the colour layers binaryswap composites:
 * RGBA8 as OSMesa holds it, or RGBA32F (`colour: rgba32f`: read with
 * GL_FLOAT, composited in float, rounded once to RGBA8 on the display),
 * and the background of alpha mode. Where float colour is exact: depth
 * mode selects pixels, so float and RGBA8 give the same frame; alpha mode
 * blends in float with one rounding at the end, and equals a serial
 * back-to-front float blend of the same layers for the schedules that keep
 * the order (tsr_composite_schedule_keeps_order), as RGBA8 does. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>

#include "layers.h"

int binaryswap_colour_parse(const char *text, int *color_format, tsr_error *err)
{
    if (!strcmp(text, "rgba8"))
        *color_format = TSR_COMPOSITE_RGBA8;
    else if (!strcmp(text, "rgba32f"))
        *color_format = TSR_COMPOSITE_RGBA32F;
    else
        return tsr_error_set(err, TSR_EINVAL, "colour=%s: expected rgba8 or rgba32f", text);
    return TSR_OK;
}

static uint8_t to_byte(float v)
{
    if (!(v > 0.0f))
        return 0; /* negative and NaN */
    if (v >= 1.0f)
        return 255;
    return (uint8_t)lrintf(v * 255.0f);
}

void binaryswap_background_rgba8(const float rgba[4], uint8_t out[4])
{
    for (int c = 0; c < 4; c++)
        out[c] = to_byte(rgba[c]);
}

int binaryswap_read_colour(binaryswap_read_fn read, void *render, int W, int H, int x, int y, int w, int h,
                           int color_format, const float *depth, tsr_composite_image *out, tsr_error *err)
{
    int rc = tsr_composite_image_init(out, W, H, x, y, w, h, color_format,
                                      depth ? TSR_COMPOSITE_DEPTH32F : TSR_COMPOSITE_NODEPTH, err);
    if (rc || !w || !h)
        return rc;
    unsigned type = color_format == TSR_COMPOSITE_RGBA32F ? GL_FLOAT : GL_UNSIGNED_BYTE;
    if ((rc = read(render, x, y, w, h, GL_RGBA, type, out->color, err)))
        return rc;
    if (depth)
        memcpy(out->depth, depth, (size_t)w * (size_t)h * sizeof(float));
    return TSR_OK;
}

int binaryswap_frame_rgba8(const tsr_composite_image *frame, uint8_t **buf, size_t *cap, tsr_error *err)
{
    size_t n = (size_t)frame->width * (size_t)frame->height * 4;
    if (n > *cap) {
        uint8_t *p = realloc(*buf, n);
        if (!p)
            return tsr_error_set(err, TSR_ENOMEM, "out of memory for a %dx%d frame", frame->width, frame->height);
        *buf = p;
        *cap = n;
    }
    const float *v = (const float *)(const void *)frame->color;
    for (size_t i = 0; i < n; i++)
        (*buf)[i] = to_byte(v[i]);
    return TSR_OK;
}
