/* spus/binaryswap/display.c — the final piece drawn on the display node:
 * DrawPixels of the piece's active pixels, scissored clears of its
 * background, over the display stream readback uses too
 * (spus/display_stream/display_stream.h). Owns nothing beyond its scratch images.
 * Never sends the display anything but the window, the final piece, the
 * frame's barriers and (rank 0) the swap. */
#include <inttypes.h>

#include "instance.h"
#include "layers.h"

/* A peer that cannot reach the display fails the run whatever on_error
 * says (its piece of every frame would be missing). */
static void display_failed(void *ctx, const tsr_error *err) { binaryswap_fatal(ctx, "%s", err->message); }

void binaryswap_display_init(binaryswap_spu *b, tsr_dispatch *table, const tsr_dispatch *next)
{
    b->display = (display_stream){.name = b->name,
                                  .options = b->options,
                                  .address_option = "display",
                                  .window = b->window,
                                  .barrier = BINARYSWAP_DISPLAY_BARRIER,
                                  .barrier_clients = (unsigned)b->nranks,
                                  .child = next,
                                  .on_failure = display_failed,
                                  .ctx = b};
    display_stream_follow_window(&b->display, table);
}

const tsr_dispatch *binaryswap_display(binaryswap_spu *b) { return display_stream_get(&b->display); }

/* The pixels [first, last] of a window `W` wide as at most three
 * rectangles {x, y, w, h}: a partial first row, whole rows, a partial last
 * row. */
static int span_rects(uint32_t W, uint32_t first, uint32_t last, int r[3][4])
{
    int w = (int)W, y0 = (int)(first / W), y1 = (int)(last / W), x0 = (int)(first % W), x1 = (int)(last % W), n = 0;
    if (y0 == y1) {
        r[0][0] = x0, r[0][1] = y0, r[0][2] = x1 - x0 + 1, r[0][3] = 1;
        return 1;
    }
    int ys = x0 ? y0 + 1 : y0, ye = x1 + 1 < w ? y1 - 1 : y1;
    if (x0)
        r[n][0] = x0, r[n][1] = y0, r[n][2] = w - x0, r[n][3] = 1, n++;
    if (ys <= ye)
        r[n][0] = 0, r[n][1] = ys, r[n][2] = w, r[n][3] = ye - ys + 1, n++;
    if (x1 + 1 < w)
        r[n][0] = 0, r[n][1] = y1, r[n][2] = x1 + 1, r[n][3] = 1, n++;
    return n;
}

/* Background over pixels [first, last] of the display's window: scissored
 * clears, a command each, no pixels. */
static void clear_span(const tsr_dispatch *d, uint32_t W, uint32_t first, uint32_t last)
{
    int r[3][4];
    int n = span_rects(W, first, last, r);
    tsr_call_Enable(d, GL_SCISSOR_TEST);
    for (int i = 0; i < n; i++) {
        tsr_call_Scissor(d, r[i][0], r[i][1], r[i][2], r[i][3]);
        tsr_call_Clear(d, GL_COLOR_BUFFER_BIT);
    }
    tsr_call_Disable(d, GL_SCISSOR_TEST); /* DrawPixels below must not be cut */
}

/* Scissored clears of the rectangles (the background: a command each, no
 * pixels); the scissor test is off again after them. */
static void clear_rects(const tsr_dispatch *d, const binaryswap_rect *r, size_t n)
{
    if (!n)
        return;
    tsr_call_Enable(d, GL_SCISSOR_TEST);
    for (size_t i = 0; i < n; i++) {
        tsr_call_Scissor(d, r[i].x, r[i].y, r[i].w, r[i].h);
        tsr_call_Clear(d, GL_COLOR_BUFFER_BIT);
    }
    tsr_call_Disable(d, GL_SCISSOR_TEST); /* DrawPixels must not be cut */
}

/* Puts this peer's final piece (pixels [start, start+count) of the window,
 * composited from every peer) into the display's frame, in this peer's
 * own context there. A depth-mode RGBA8 piece whose pixels from the first
 * to the last active one are all active is that span's colour plane as it
 * is: WindowPos2i + DrawPixels of the rectangles it crosses (span_rects),
 * the background before and after it as scissored clears. Any other piece
 * is drawn in bands (bands.h): one box per band around its active pixels
 * (inactive ones in it as the background), the rest of the piece as
 * scissored clears, so the display draws and the stream carries little
 * more than the active pixels. A piece without active pixels is clears
 * only, so no pixel of background travels. */
void binaryswap_place_piece(binaryswap_spu *b, const tsr_dispatch *d, const tsr_composite_sparse *in,
                            const void *background, uint32_t frame)
{
    uint32_t W = (uint32_t)in->window_width, end = in->start + in->count - 1;
    if (!in->active) {
        clear_span(d, W, in->start, end);
        return;
    }
    uint32_t lead = 0, trail = 0;
    for (uint32_t r = 0; r < in->nruns; r++) {
        lead += in->runs[2 * r];
        if (in->runs[2 * r + 1])
            break;
    }
    for (uint32_t r = in->nruns; r-- > 0;) {
        if (in->runs[2 * r + 1])
            break;
        trail += in->runs[2 * r];
    }
    uint32_t first = in->start + lead, last = end - trail;
    tsr_error err = {0};
    if (in->active == last - first + 1 && in->mode == TSR_COMPOSITE_DEPTH && in->color_format == TSR_COMPOSITE_RGBA8) {
        if (lead)
            clear_span(d, W, in->start, first - 1);
        if (trail)
            clear_span(d, W, last + 1, end);
        /* The active pixels are in's colour plane, in order. */
        int r[3][4];
        int n = span_rects(W, first, last, r);
        for (int i = 0; i < n; i++) {
            size_t at = (size_t)r[i][1] * W + (size_t)r[i][0] - first;
            tsr_call_WindowPos2i(d, r[i][0], r[i][1]);
            tsr_call_DrawPixels(d, r[i][2], r[i][3], GL_RGBA, GL_UNSIGNED_BYTE, in->color + at * 4);
        }
        return;
    }
    if (binaryswap_bands_plan(&b->bands, in, BINARYSWAP_CALL_PIXELS, &err) != TSR_OK)
        binaryswap_fatal(b, "frame %" PRIu32 ": %s", frame, err.message);
    clear_rects(d, b->bands.clears, b->bands.nclears);
    for (size_t i = 0; i < b->bands.nboxes; i++) {
        const binaryswap_rect *box = &b->bands.boxes[i];
        /* The box's rows: one view of them all, then each row's columns. */
        uint32_t from = (uint32_t)box->y * W + (uint32_t)box->x;
        uint32_t to = (uint32_t)(box->y + box->h - 1) * W + (uint32_t)(box->x + box->w - 1);
        if (tsr_composite_image_init(&b->piece, in->window_width, in->window_height, box->x, box->y, box->w, box->h,
                                     in->color_format, TSR_COMPOSITE_NODEPTH, &err) != TSR_OK ||
            tsr_composite_sparse_view(in, from, to - from + 1, &b->placed, &err) != TSR_OK)
            binaryswap_fatal(b, "frame %" PRIu32 ": %s", frame, err.message);
        for (int y = box->y; y < box->y + box->h; y++)
            if (tsr_composite_sparse_view(&b->placed, (uint32_t)y * W + (uint32_t)box->x, (uint32_t)box->w, &b->row,
                                          &err) != TSR_OK ||
                tsr_composite_sparse_to_dense(&b->row, background, &b->piece, &err) != TSR_OK)
                binaryswap_fatal(b, "frame %" PRIu32 ": %s", frame, err.message);
        const uint8_t *px = b->piece.color;
        if (in->color_format != TSR_COMPOSITE_RGBA8) {
            if (binaryswap_frame_rgba8(&b->piece, &b->frame8, &b->frame8_size, &err) != TSR_OK)
                binaryswap_fatal(b, "frame %" PRIu32 ": %s", frame, err.message);
            px = b->frame8;
        }
        tsr_call_WindowPos2i(d, box->x, box->y);
        tsr_call_DrawPixels(d, box->w, box->h, GL_RGBA, GL_UNSIGNED_BYTE, px);
    }
}
