/* spus/binaryswap/compositing.c — the frame hook: plans the group's
 * strategy for the window, reads this peer's layer (layer.c), runs its part
 * of the schedule over the mesh (mesh.c) and puts the final piece on the
 * display (display.c). Owns the schedule and its executors. Never talks to
 * a socket itself.
 *
 * Compositing (composite_frame): one of the strategies of
 * strategies/ (strategy.h: binary swap for any peer count, direct send,
 * radix-k, gather to one, auto), planned once per window size and run by
 * its executor over this SPU's transport (mesh.c): peers are
 * participants 0..N-1 over the mesh; only when the display composites
 * (gather to one) does the display participant N run, in rank 0's process
 * (rank 0's own final piece is queued locally). Depth
 * mode: the nearest depth wins, equal depth goes to the lower rank, so the
 * result is the single-process render of the parts drawn in rank order
 * with GL_LESS, bit for bit, for every strategy and arrival order. Pixels
 * no peer drew get the background colour, read from a pixel rank 0 left
 * at depth 1.0 (exactly what GL's clear produced; when rank 0 left none,
 * it covered the window and no pixel is background; every peer takes its
 * own, as every application clears to the same colour). Every peer then
 * puts its final piece into the display's frame itself (composite_frame:
 * a graph's display node counts every peer among its clients), and rank
 * 0 swaps there.
 *
 * Alpha mode and float colour (layers.h, order.c, colour.c; README.md):
 * the colour of the geometry's box (or of the whole window when that is
 * unknown) is composited as a premultiplied layer, in
 * view_order, folded back to front (the serial blend's grouping) by a
 * schedule that keeps that grouping; the peer clears to transparent black
 * (ClearColor is taken in binaryswap.c) and the display adds the
 * application's clear colour once. colour=rgba32f composites GL_FLOAT
 * colour. */
#include <inttypes.h>
#include <stdint.h>
#include <string.h>

#include "instance.h"
#include "layers.h"
#include "tessera/log.h"

/* The schedule for this window (planned again when the size changes). */
void binaryswap_plan(binaryswap_spu *b, int W, int H)
{
    if (b->plan.kind && b->plan_width == W && b->plan_height == H)
        return;
    tsr_error err = {0};
    tsr_composite_executor_free(b->peer_ex);
    tsr_composite_executor_free(b->display_ex);
    b->peer_ex = b->display_ex = NULL;
    if (b->plan.kind)
        tsr_composite_schedule_free(&b->plan);
    tsr_composite_hint hint = {.image_bytes = b->last_bytes, .display_separate = 0};
    if (tsr_composite_plan(b->kind, b->nranks, W, H, b->k, &hint, &b->plan, &err) != TSR_OK ||
        !(b->peer_ex = tsr_composite_executor_new(&b->plan, b->codec, &err)) ||
        (b->rank == 0 && !(b->display_ex = tsr_composite_executor_new(&b->plan, b->codec, &err))))
        binaryswap_fatal(b, "%s", err.message);
    b->plan_width = W;
    b->plan_height = H;
    if (b->rank == 0) {
        char codec[64];
        tsr_log(TSR_LOG_INFO, "%s: strategy %s for %d peers, %dx%d window, codec %s: %s", b->name, b->plan.name,
                b->nranks, W, H, tsr_composite_codec_name(b->codec, codec, sizeof codec), b->plan.reason);
    }
}

/* Composites this frame with the group (the strategy's schedule) and puts
 * it on the display node, which is an ordinary shared-mode server with one
 * context per peer drawing into one window (server/node.h), as readback's
 * tile servers use it:
 *   every peer: its final piece (place_piece), straight from its process;
 *               the final pieces cover the window once
 *   every peer: BarrierExecTSR     every piece has landed
 *   rank 0: SwapBuffersTSR         the display writes the frame
 *   every peer: BarrierExecTSR     no piece of the next frame lands before
 * So no final piece travels twice and no peer assembles the frame. Only when
 * the display composites (gather to one: the same pixels from every peer)
 * does rank 0 run that part and place the frame it assembled. Colour only
 * travels to the display. */
static void composite_frame(binaryswap_spu *b, uint32_t frame)
{
    tsr_error err = {0};
    binaryswap_await_releases(b, frame);
    const tsr_composite_image *mine = &b->mine;
    if (b->mode == TSR_COMPOSITE_ALPHA || b->colour != TSR_COMPOSITE_RGBA8)
        mine = &b->layer;
    binaryswap_plan(b, mine->window_width, mine->window_height);
    b->last_bytes = 0;
    tsr_composite_transport t = {.user = b,
                                 .send = binaryswap_transport_send,
                                 .recv = binaryswap_transport_recv,
                                 .send_buffer = binaryswap_transport_send_buffer};
    /* A peer without a background pixel covered the whole window, so no
     * pixel of the frame is background and any colour does. */
    if (b->mode == TSR_COMPOSITE_ALPHA)
        binaryswap_background_rgba8(b->clear, b->background);
    float background_f[4];
    for (int c = 0; c < 4; c++)
        background_f[c] = (float)b->background[c] / 255.0f;
    const void *background =
        b->colour == TSR_COMPOSITE_RGBA8 ? (const void *)b->background : (const void *)background_f;
    bool at_display = tsr_composite_schedule_display_composites(&b->plan);
    const tsr_composite_sparse *final = NULL;
    /* place_piece draws the final piece as it is: it may come back filled */
    int rc = at_display ? tsr_composite_run_peer(b->peer_ex, b->pos[b->rank], mine, b->mode, &t, &err)
                        : tsr_composite_run_peer_rounds(b->peer_ex, b->pos[b->rank], mine, b->mode, &t, background,
                                                        &final, &err);
    if (rc != TSR_OK)
        binaryswap_fatal(b, "frame %" PRIu32 ": %s", frame, err.message);
    b->st.composited_ns = binaryswap_now_ns();
    tsr_composite_stats cs;
    tsr_composite_executor_stats(b->peer_ex, &cs);
    b->st.final_filled = cs.final_filled;
    tsr_log(TSR_LOG_DEBUG, "%s: frame %" PRIu32 ": rank %d sent %" PRIu64 " bytes to its peers", b->name, frame,
            b->rank, b->last_bytes);
    const tsr_dispatch *d = binaryswap_display(b);
    if (!at_display) {
        b->st.assembled_ns = b->st.composited_ns; /* the piece is final */
        if (final) {
            /* c / 255 is converted back to exactly c */
            tsr_call_ClearColor(d, background_f[0], background_f[1], background_f[2], background_f[3]);
            binaryswap_place_piece(b, d, final, background, frame);
        }
    } else if (b->rank == 0) {
        if (tsr_composite_run_display(b->display_ex, frame, b->mode, b->colour,
                                      b->mode == TSR_COMPOSITE_DEPTH ? TSR_COMPOSITE_DEPTH32F : TSR_COMPOSITE_NODEPTH,
                                      background, &b->frame, &t, &err) != TSR_OK)
            binaryswap_fatal(b, "frame %" PRIu32 ": %s", frame, err.message);
        const uint8_t *pixels = b->frame.color;
        if (b->colour != TSR_COMPOSITE_RGBA8) {
            if (binaryswap_frame_rgba8(&b->frame, &b->frame8, &b->frame8_size, &err) != TSR_OK)
                binaryswap_fatal(b, "frame %" PRIu32 ": %s", frame, err.message);
            pixels = b->frame8;
        }
        b->st.assembled_ns = binaryswap_now_ns();
        tsr_call_WindowPos2i(d, 0, 0);
        tsr_call_DrawPixels(d, b->frame.width, b->frame.height, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    }
    binaryswap_release_held(b);
    tsr_call_BarrierExecTSR(d, BINARYSWAP_DISPLAY_BARRIER);
    if (b->rank == 0)
        tsr_call_SwapBuffersTSR(d, b->window, 0);
    tsr_call_BarrierExecTSR(d, BINARYSWAP_DISPLAY_BARRIER);
    if (b->rank == 0) {
        b->st.sent_ns = binaryswap_now_ns();
        if (b->stats_fd >= 0) {
            /* A reply comes after the display node swapped, which it does
             * after every peer's piece landed (the barrier): the time the
             * frame is there (one round trip per frame, stats only). */
            GLint viewport[4];
            tsr_call_GetIntegerv(d, GL_VIEWPORT, viewport);
            b->st.displayed_ns = binaryswap_now_ns();
        }
    } else {
        b->st.sent_ns = binaryswap_now_ns();
    }
    binaryswap_stats_frame(b, frame);
    b->composited = true;
}

/* render has ended the frame (tessera/dev/render.h, end_frame): it is
 * finished and still in the framebuffer. */
void binaryswap_frame(binaryswap_spu *b, int frame)
{
    b->st = (binaryswap_frame_stats){.swap_ns = binaryswap_now_ns(),
                                     .hook_cpu_ns = b->stats_fd >= 0 ? binaryswap_cpu_ns() : 0};
    binaryswap_display(b);
    int W = 0, H = 0;
    b->render_api->window_size(b->render, &W, &H);
    binaryswap_link_peers(b, W, H);
    tsr_error err = {0};
    if (b->order_from_boxes && b->nranks > 1) {
        binaryswap_await_releases(b, (uint32_t)frame); /* the box distances go at the rings' start too */
        binaryswap_exchange_order(b, (uint32_t)frame);
    }
    if (b->mode == TSR_COMPOSITE_ALPHA) {
        /* Translucent geometry often leaves depth alone (DepthMask false),
         * so the depth buffer cannot find the region: the geometry's box
         * (roi.c) when known, else the whole window; outside what was
         * drawn the layer is the transparent clear, which compress drops. */
        int box[4] = {0, 0, W, H};
        if (!binaryswap_roi_frame(b->roi, box)) {
            box[0] = box[1] = 0;
            box[2] = W;
            box[3] = H;
        }
        if (binaryswap_read_colour(b->render_api->read, b->render, W, H, box[0], box[1], box[2] - box[0],
                                   box[3] - box[1], b->colour, NULL, &b->layer, &err))
            binaryswap_fatal(b, "%s", err.message);
        tsr_log(TSR_LOG_DEBUG, "%s: frame %d: rank %d alpha region [%d, %d, %d, %d] of %dx%d", b->name, frame, b->rank,
                box[0], box[1], box[2] - box[0], box[3] - box[1], W, H);
    } else if (b->synthetic) {
        binaryswap_synthetic_layer(b, W, H, (uint32_t)frame);
    } else {
        binaryswap_read_layer(b, (uint32_t)frame);
        if (b->colour != TSR_COMPOSITE_RGBA8 &&
            binaryswap_read_colour(b->render_api->read, b->render, W, H, b->mine.x, b->mine.y, b->mine.width,
                                   b->mine.height, b->colour, b->mine.depth, &b->layer, &err))
            binaryswap_fatal(b, "%s", err.message);
    }
    b->layer.rank = b->rank;
    b->layer.frame = b->mine.frame = (uint32_t)frame;
    b->st.ready_ns = binaryswap_now_ns();
    composite_frame(b, (uint32_t)frame);
    b->frames++;
}
