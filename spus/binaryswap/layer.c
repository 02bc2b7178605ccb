/* spus/binaryswap/layer.c — the read-back of this peer's layer at a swap:
 * the colour and depth of its region of interest, or the synthetic layer
 * that replaces it in benchmarks. Owns the instance's window depth buffer
 * and its `mine` image. Never sends anything.
 *
 * Region of interest (read_layer). At a swap only the colour and depth
 * of the window-space box of the frame's geometry are read and sent
 * (roi.c: the box of every vertex render was given, placed with the
 * matrices it was drawn with, clipped in homogeneous space where it
 * reaches behind the viewer, never dropped). When the frame drew
 * something no box covers, the depth buffer of the whole window is read
 * (GL_DEPTH_COMPONENT/GL_FLOAT, as OSMesa gives it) and the box of pixels
 * with depth < 1.0 (the cleared value) found instead. A peer that drew
 * nothing sends the header alone. */
#include <inttypes.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "instance.h"
#include "synthetic.h"
#include "tessera/log.h"

static bool grow(void **p, size_t *cap, size_t need)
{
    if (need <= *cap)
        return true;
    void *q = realloc(*p, need);
    if (!q)
        return false;
    *p = q;
    *cap = need;
    return true;
}

/* Reads the box [box[0], box[2]) x [box[1], box[3]) that holds all this
 * frame drew (roi.c): its colour and depth, nothing else. */
static void read_box(binaryswap_spu *b, uint32_t frame, int W, int H, const int box[4])
{
    tsr_error err = {0};
    int x = box[0], y = box[1], w = box[2] - box[0], h = box[3] - box[1];
    if (tsr_composite_image_init(&b->mine, W, H, x, y, w, h, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, &err) !=
        TSR_OK)
        binaryswap_fatal(b, "%s", err.message);
    b->mine.rank = b->rank;
    b->mine.frame = frame;
    if (w && (b->render_api->read(b->render, x, y, w, h, GL_RGBA, GL_UNSIGNED_BYTE, b->mine.color, &err) != TSR_OK ||
              b->render_api->read(b->render, x, y, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, b->mine.depth, &err) != TSR_OK))
        binaryswap_fatal(b, "%s", err.message);
    /* The background: a pixel outside the box (nothing was drawn there
     * since the clear), else one inside it that kept the cleared depth. */
    int bx = -1, by = -1;
    if (x > 0 || !w)
        bx = 0, by = 0;
    else if (x + w < W)
        bx = x + w, by = y;
    else if (y > 0)
        bx = 0, by = 0;
    else if (y + h < H)
        bx = 0, by = y + h;
    b->has_background = bx >= 0;
    if (b->has_background) {
        if (b->render_api->read(b->render, bx, by, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, b->background, &err) != TSR_OK)
            binaryswap_fatal(b, "%s", err.message);
    } else {
        for (size_t i = 0; i < (size_t)w * (size_t)h && !b->has_background; i++)
            if (!(b->mine.depth[i] < 1.0f)) {
                memcpy(b->background, b->mine.color + 4 * i, 4);
                b->has_background = true;
            }
    }
    tsr_log(TSR_LOG_DEBUG,
            "%s: frame %" PRIu32 ": rank %d region [%d, %d, %d, %d] of %dx%d from the geometry's box; read %dx%d "
            "depth, %dx%d colour",
            b->name, frame, b->rank, x, y, w, h, W, H, w, h, w, h);
}

/* Reads this frame's region of interest into b->mine (header comment):
 * the box of what was drawn (roi.c) when it is known, else the box of the
 * pixels with depth < 1.0, found in the whole window's depth. */
void binaryswap_read_layer(binaryswap_spu *b, uint32_t frame)
{
    int W = 0, H = 0;
    b->render_api->window_size(b->render, &W, &H);
    tsr_error err = {0};
    int box[4];
    if (binaryswap_roi_frame(b->roi, box)) {
        read_box(b, frame, W, H, box);
        return;
    }
    size_t pixels = (size_t)W * (size_t)H;
    if (!grow((void **)&b->window_depth, &b->window_depth_size, pixels * sizeof(float) + 1))
        binaryswap_fatal(b, "%s", "out of memory for the depth buffer");
    if (b->render_api->read(b->render, 0, 0, W, H, GL_DEPTH_COMPONENT, GL_FLOAT, b->window_depth, &err) != TSR_OK)
        binaryswap_fatal(b, "%s", err.message);
    int x0 = W, y0 = H, x1 = -1, y1 = -1;
    size_t bg_index = SIZE_MAX;
    for (int y = 0; y < H; y++) {
        const float *row = b->window_depth + (size_t)y * (size_t)W;
        for (int x = 0; x < W; x++) {
            if (row[x] < 1.0f) {
                if (x < x0)
                    x0 = x;
                if (x > x1)
                    x1 = x;
                if (y < y0)
                    y0 = y;
                y1 = y;
            } else if (bg_index == SIZE_MAX) {
                bg_index = (size_t)y * (size_t)W + (size_t)x;
            }
        }
    }
    int x = 0, y = 0, w = 0, h = 0;
    if (x1 >= 0) {
        x = x0;
        y = y0;
        w = x1 - x0 + 1;
        h = y1 - y0 + 1;
    }
    if (tsr_composite_image_init(&b->mine, W, H, x, y, w, h, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, &err) !=
        TSR_OK)
        binaryswap_fatal(b, "%s", err.message);
    b->mine.rank = b->rank;
    b->mine.frame = frame;
    if (w && b->render_api->read(b->render, x, y, w, h, GL_RGBA, GL_UNSIGNED_BYTE, b->mine.color, &err) != TSR_OK)
        binaryswap_fatal(b, "%s", err.message);
    for (int r = 0; r < h; r++)
        memcpy(b->mine.depth + (size_t)r * (size_t)w, b->window_depth + (size_t)(y + r) * (size_t)W + (size_t)x,
               (size_t)w * sizeof(float));
    b->has_background = bg_index != SIZE_MAX;
    if (b->has_background && b->render_api->read(b->render, (int)(bg_index % (size_t)W), (int)(bg_index / (size_t)W), 1,
                                                 1, GL_RGBA, GL_UNSIGNED_BYTE, b->background, &err) != TSR_OK)
        binaryswap_fatal(b, "%s", err.message);
    tsr_log(TSR_LOG_DEBUG,
            "%s: frame %" PRIu32 ": rank %d region [%d, %d, %d, %d] of %dx%d from the depth buffer; read %dx%d depth, "
            "%dx%d colour",
            b->name, frame, b->rank, x, y, w, h, W, H, W, H, w, h);
}

/* The synthetic layer (synthetic.h) in place of the read-back: made once
 * per window size (the compositor only reads it), so a frame costs no
 * read-back and no generation, only compositing. No pixel of the layer
 * came from GL, so the background is opaque black. */
void binaryswap_synthetic_layer(binaryswap_spu *b, int W, int H, uint32_t frame)
{
    tsr_error err = {0};
    if (b->mine.window_width != W || b->mine.window_height != H || !b->mine.color) {
        if (tsr_composite_synthetic_layer(b->synthetic, W, H, b->rank, b->nranks, &b->mine, &err) != TSR_OK)
            binaryswap_fatal(b, "%s", err.message);
    }
    b->mine.rank = b->rank;
    b->mine.frame = frame;
    static const uint8_t black[4] = {0, 0, 0, 255};
    memcpy(b->background, black, sizeof black);
    b->has_background = true;
}
