/* spus/binaryswap/synthetic.c — the generated layers of synthetic.h. The
 * shapes are chosen so the composite is easy to predict and not trivial:
 * full layers are depth ramps shifted by 1/N per peer (peer r is nearest
 * where the ramp restarts, a band of 1/N of the width whose edges ripple
 * with y, so no two layers tie), ellipses are shaded domes that overlap
 * and interpenetrate. Colours are smooth (a colour per peer, shaded by
 * depth), as rendered surfaces are, so lossy codecs see realistic input. */
#include "synthetic.h"

#include <math.h>
#include <string.h>

int tsr_composite_synthetic_parse(const char *text, int *mode, tsr_error *err)
{
    if (!text || !text[0] || !strcmp(text, "off"))
        *mode = TSR_COMPOSITE_SYNTHETIC_OFF;
    else if (!strcmp(text, "full"))
        *mode = TSR_COMPOSITE_SYNTHETIC_FULL;
    else if (!strcmp(text, "ellipse"))
        *mode = TSR_COMPOSITE_SYNTHETIC_ELLIPSE;
    else
        return tsr_error_set(err, TSR_EINVAL, "synthetic=%s: expected full, ellipse or off", text);
    return TSR_OK;
}

/* A peer's hue: well-separated colours for neighbouring ranks. */
static void hue(int rank, double shade, uint8_t *c)
{
    double h = fmod(rank * 0.381966, 1.0) * 6.0;
    double f = h - floor(h), rgb[3];
    switch ((int)h) {
    case 0: rgb[0] = 1, rgb[1] = f, rgb[2] = 0; break;
    case 1: rgb[0] = 1 - f, rgb[1] = 1, rgb[2] = 0; break;
    case 2: rgb[0] = 0, rgb[1] = 1, rgb[2] = f; break;
    case 3: rgb[0] = 0, rgb[1] = 1 - f, rgb[2] = 1; break;
    case 4: rgb[0] = f, rgb[1] = 0, rgb[2] = 1; break;
    default: rgb[0] = 1, rgb[1] = 0, rgb[2] = 1 - f; break;
    }
    for (int i = 0; i < 3; i++)
        c[i] = (uint8_t)lrint(255.0 * (0.15 + 0.85 * rgb[i]) * shade);
    c[3] = 255;
}

int tsr_composite_synthetic_layer(int mode, int width, int height, int rank, int nranks, tsr_composite_image *out,
                                  tsr_error *err)
{
    if (mode != TSR_COMPOSITE_SYNTHETIC_FULL && mode != TSR_COMPOSITE_SYNTHETIC_ELLIPSE)
        return tsr_error_set(err, TSR_EINVAL, "synthetic layer: mode %d is neither full nor ellipse", mode);
    if (nranks < 1 || rank < 0 || rank >= nranks || width < 1 || height < 1)
        return tsr_error_set(err, TSR_EINVAL, "synthetic layer: rank %d of %d peers, %dx%d window", rank, nranks, width,
                             height);
    if (mode == TSR_COMPOSITE_SYNTHETIC_FULL) {
        if (tsr_composite_image_init(out, width, height, 0, 0, width, height, TSR_COMPOSITE_RGBA8,
                                     TSR_COMPOSITE_DEPTH32F, err) != TSR_OK)
            return err->code;
        for (int y = 0; y < height; y++) {
            double ripple = 0.25 / nranks * sin(6.2831853 * 2.0 * y / height);
            for (int x = 0; x < width; x++) {
                double u = ((double)x + 0.5) / width - (double)rank / nranks + ripple;
                u -= floor(u);
                size_t i = (size_t)y * (size_t)width + (size_t)x;
                /* Depths in [0.1, 0.9), never the cleared 1.0; two peers'
                 * ramps differ by at least 0.8/N, so no pixel ties. */
                out->depth[i] = (float)(0.1 + 0.8 * u);
                hue(rank, 1.0 - 0.6 * u, out->color + 4 * i);
            }
        }
    } else {
        /* Semi-axes 0.3568 of the window: pi * 0.3568^2 = 40.0%; centres
         * kept within [0.357, 0.643] so the ellipse is never clipped. */
        const double a = 0.3568;
        double cu = a + (1 - 2 * a) * fmod(0.5 + rank * 0.618034, 1.0);
        double cv = a + (1 - 2 * a) * fmod(0.5 + rank * 0.754878, 1.0);
        double cx = cu * width, cy = cv * height, ax = a * width, ay = a * height;
        int x0 = (int)floor(cx - ax), x1 = (int)ceil(cx + ax), y0 = (int)floor(cy - ay), y1 = (int)ceil(cy + ay);
        x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
        x1 = x1 > width ? width : x1, y1 = y1 > height ? height : y1;
        int w = x1 - x0, h = y1 - y0;
        if (tsr_composite_image_init(out, width, height, x0, y0, w, h, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F,
                                     err) != TSR_OK)
            return err->code;
        double base = 0.35 + 0.3 * fmod(rank * 0.437, 1.0);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                double dx = (x0 + x + 0.5 - cx) / ax, dy = (y0 + y + 0.5 - cy) / ay, r2 = dx * dx + dy * dy;
                size_t i = (size_t)y * (size_t)w + (size_t)x;
                uint8_t *c = out->color + 4 * i;
                if (r2 < 1) {
                    double z = sqrt(1 - r2);
                    out->depth[i] = (float)(base - 0.3 * z);
                    hue(rank, 0.3 + 0.7 * z, c);
                } else {
                    out->depth[i] = 1.0f;
                    memset(c, 0, 4);
                }
            }
    }
    out->rank = rank;
    return TSR_OK;
}
