/* spus/binaryswap/strategies/executor.c — runs one participant's part of
 * a schedule for one frame: pieces are split from the sparse image,
 * encoded, handed to the caller's send callback; received messages are
 * decoded (checked against what the schedule expects: frame, window,
 * region, formats) and composited front to back. The transport is the
 * caller's; the executor only computes.
 *
 * Owns: its scratch images and message buffer (reused frame to frame).
 * Never: does I/O itself, keeps state outside the executor. */
#include <stdlib.h>
#include <string.h>
#include "strategy.h"

/* A final strip is filled with background rather than gathered when at
 * most 1/this of it is background: those pixels then travel to the
 * display (4 bytes each), as a box around scattered holes would send them
 * anyway. */
#define FILL_FINAL_BACKGROUND_SHARE 8

struct tsr_composite_executor {
    const tsr_composite_schedule *s;
    tsr_composite_codec codec;
    /* cur: this rank's image once composited; acc/tmp: merge outputs;
     * piece: the kept part of the read-back (planes of its own, kept from
     * frame to frame: turning it into a view would free them, and the next frame
     * would map and fault in fresh pages; merged in place it trades planes
     * with cur instead of being copied); view: a view of cur; in: the received
     * message (a view of it, or decoded); first: alpha mode's copy of a
     * received piece that starts a fold. One received message at a time:
     * each is merged as it arrives, before the next is asked for. */
    tsr_composite_sparse cur, acc, tmp, piece, view, in, first;
    tsr_composite_sparse layer_view; /* the kept part as a view of a full read-back (keep_of_readback) */
    tsr_composite_fold strip;        /* depth mode's running composite of a region that takes many pieces */
    uint8_t *buf;
    size_t buf_cap;
    tsr_composite_stats stats;
};

tsr_composite_executor *tsr_composite_executor_new(const tsr_composite_schedule *s, tsr_composite_codec c,
                                                   tsr_error *err)
{
    tsr_composite_executor *ex = calloc(1, sizeof *ex);
    if (!ex) {
        tsr_error_set(err, TSR_ENOMEM, "composite executor: no memory");
        return NULL;
    }
    ex->s = s;
    ex->codec = c;
    return ex;
}

void tsr_composite_executor_free(tsr_composite_executor *ex)
{
    if (!ex)
        return;
    tsr_composite_sparse_free(&ex->cur);
    tsr_composite_sparse_free(&ex->acc);
    tsr_composite_sparse_free(&ex->tmp);
    tsr_composite_sparse_free(&ex->piece);
    tsr_composite_sparse_free(&ex->view);
    tsr_composite_sparse_free(&ex->in);
    tsr_composite_sparse_free(&ex->first);
    tsr_composite_sparse_free(&ex->layer_view);
    tsr_composite_fold_free(&ex->strip);
    free(ex->buf);
    free(ex);
}

void tsr_composite_executor_stats(const tsr_composite_executor *ex, tsr_composite_stats *out) { *out = ex->stats; }

static size_t owned_pixel_bytes(const tsr_composite_sparse *img)
{
    if (img->borrowed || !img->pixel_capacity)
        return 0;
    return img->pixel_capacity * (tsr_composite_color_bytes(img->color_format) + (img->depth ? sizeof(float) : 0));
}

size_t tsr_composite_executor_pixel_bytes(const tsr_composite_executor *ex)
{
    return owned_pixel_bytes(&ex->cur) + owned_pixel_bytes(&ex->acc) + owned_pixel_bytes(&ex->tmp) +
           owned_pixel_bytes(&ex->piece) + owned_pixel_bytes(&ex->view) + owned_pixel_bytes(&ex->in) +
           owned_pixel_bytes(&ex->first) + owned_pixel_bytes(&ex->layer_view) + owned_pixel_bytes(&ex->strip.acc);
}

/* The buffer the next message to `to` is encoded into: the transport's own
 * (shared memory) when it offers one, else the executor's. */
static uint8_t *message_buffer(tsr_composite_executor *ex, int to, size_t need, const tsr_composite_transport *t,
                               size_t *cap, tsr_error *err)
{
    if (t->send_buffer) {
        uint8_t *dst = t->send_buffer(t->user, to, need, err);
        if (!dst && !err->code)
            tsr_error_set(err, TSR_EIO, "composite: no buffer for a message to participant %d", to);
        *cap = need;
        return dst;
    }
    if (need > ex->buf_cap) {
        uint8_t *b = realloc(ex->buf, need);
        if (!b) {
            tsr_error_set(err, TSR_ENOMEM, "composite: no memory for a %zu-byte message", need);
            return NULL;
        }
        ex->buf = b;
        ex->buf_cap = need;
    }
    *cap = ex->buf_cap;
    return ex->buf;
}

static int sent(tsr_composite_executor *ex, int to, uint8_t *dst, size_t len, const tsr_composite_transport *t,
                tsr_error *err)
{
    int rc = t->send(t->user, to, dst, len, err);
    if (rc)
        return rc;
    ex->stats.bytes_sent += len;
    ex->stats.messages_sent++;
    return TSR_OK;
}

/* Messages reserve the bound of the very image they carry, not the worst
 * case of the region: in a shared-memory ring the space reserved decides
 * where the next message goes, so the pages in use follow the bytes sent. */
static int send_piece(tsr_composite_executor *ex, const tsr_composite_sparse *img, int to,
                      const tsr_composite_transport *t, tsr_error *err)
{
    size_t need = tsr_composite_message_bound(img, ex->codec), cap = 0, len = 0;
    uint8_t *dst = message_buffer(ex, to, need, t, &cap, err);
    if (!dst)
        return err->code;
    int rc = tsr_composite_message_encode(img, ex->codec, dst, cap, &len, err);
    return rc ? rc : sent(ex, to, dst, len, t, err);
}

/* A region of the read-back itself (before this rank composited anything):
 * encoded from the dense image straight into the message, so the pixels
 * sent are copied once and never held as a sparse copy. */
static int send_dense(tsr_composite_executor *ex, const tsr_composite_image *mine, int mode, tsr_composite_region reg,
                      int to, const tsr_composite_transport *t, tsr_error *err)
{
    int rc = tsr_composite_sparse_compress_runs(mine, mode, reg.start, reg.count, &ex->tmp, err);
    if (rc)
        return rc;
    size_t need = tsr_composite_message_bound(&ex->tmp, ex->codec), cap = 0, len = 0;
    uint8_t *dst = message_buffer(ex, to, need, t, &cap, err);
    if (!dst)
        return err->code;
    rc = tsr_composite_message_encode_dense(mine, &ex->tmp, ex->codec, dst, cap, &len, err);
    return rc ? rc : sent(ex, to, dst, len, t, err);
}

/* The kept part of the read-back, to composite into. When the read-back
 * is the whole window and every pixel of the part is active (full layers,
 * depth mode, RGBA8), a view of the read-back's own planes: no copy is
 * made, and the first merge writes the composite straight into the
 * executor's image. When a dense strip will fold the part (depth mode,
 * `pieces` >= 3, some pixel inactive), only its runs, with *readback set:
 * the strip takes the pixels from the read-back itself.
 * Else compressed into ex->piece. */
static int keep_of_readback(tsr_composite_executor *ex, const tsr_composite_image *mine, int mode,
                            tsr_composite_region reg, int pieces, tsr_composite_sparse **keep,
                            const tsr_composite_image **readback, tsr_error *err)
{
    int rc;
    *readback = NULL;
    int whole = mine->color_format == TSR_COMPOSITE_RGBA8 && mine->x == 0 && mine->y == 0 &&
                mine->width == mine->window_width && mine->height == mine->window_height;
    if (mode == TSR_COMPOSITE_DEPTH && (whole || pieces >= 3)) {
        tsr_composite_sparse *v = whole ? &ex->layer_view : &ex->piece;
        if ((rc = tsr_composite_sparse_compress_runs(mine, mode, reg.start, reg.count, v, err)))
            return rc;
        if (pieces >= 3 && v->active < reg.count) {
            *keep = v;
            *readback = mine;
            return TSR_OK;
        }
        if (whole && v->active == reg.count) {
            v->color = (uint8_t *)mine->color + (size_t)reg.start * 4;
            v->depth = mine->depth + reg.start;
            v->pixel_capacity = 0;
            v->borrowed = 1;
            *keep = v;
            return TSR_OK;
        }
    }
    *keep = &ex->piece;
    return tsr_composite_sparse_compress(mine, mode, reg.start, reg.count, &ex->piece, err);
}

/* Receives the next message from `from` into ex->in: a view of it when the
 * codec leaves the pixels raw (valid until the next receive), decoded
 * otherwise. */
static int recv_piece(tsr_composite_executor *ex, int from, const tsr_composite_message_header *expect,
                      const tsr_composite_transport *t, tsr_error *err)
{
    const void *data = NULL;
    size_t size = 0;
    int rc = t->recv(t->user, from, &data, &size, err);
    if (rc)
        return rc;
    ex->stats.bytes_received += size;
    ex->stats.messages_received++;
    if ((rc = tsr_composite_message_view(data, size, expect, &ex->in, err))) {
        char why[sizeof err->message];
        memcpy(why, err->message, sizeof why);
        return tsr_error_set(err, rc, "from peer %d: %s", from, why);
    }
    return TSR_OK;
}

/* One step of a fold: *acc becomes `piece` merged in front of it
 * (in_front) or behind it. The intervals must be adjacent, or the
 * schedule and the messages disagree. The output is whichever of the two
 * merge buffers is not an input. */
static int adjacent(const tsr_composite_sparse *front, const tsr_composite_sparse *back, tsr_error *err)
{
    if (front->rank + front->rank_count != back->rank)
        return tsr_error_set(
            err, TSR_EPROTO, "composite: piece of ranks %d..%d follows ranks %d..%d (not adjacent in the order)",
            back->rank, back->rank + back->rank_count - 1, front->rank, front->rank + front->rank_count - 1);
    return TSR_OK;
}

static int fold(tsr_composite_executor *ex, tsr_composite_sparse **acc, const tsr_composite_sparse *piece, int in_front,
                tsr_error *err)
{
    const tsr_composite_sparse *front = in_front ? piece : *acc, *back = in_front ? *acc : piece;
    int rc = adjacent(front, back, err);
    if (rc)
        return rc;
    tsr_composite_sparse *a = *acc;
    if (a->mode == TSR_COMPOSITE_DEPTH && a->color_format == TSR_COMPOSITE_RGBA8 && !a->borrowed && a->runs &&
        piece->mode == a->mode && piece->color_format == a->color_format && piece->depth_format == a->depth_format &&
        piece->window_width == a->window_width && piece->window_height == a->window_height &&
        piece->start == a->start && piece->count == a->count && piece->nruns == a->nruns &&
        piece->active == a->active && !memcmp(piece->runs, a->runs, (size_t)a->nruns * 2 * sizeof *a->runs)) {
        /* The same runs (full layers, as a rendered scene's often are): the
         * merge keeps them, so the pixels are merged in place into acc's
         * own planes (the kernel allows the aliasing) instead of into a
         * fresh image, which writes a 1/N frame less per fold. */
        tsr_composite_depth_rgba8(a->active, front->color, front->depth, back->color, back->depth, a->color, a->depth);
        a->rank = front->rank;
        a->rank_count = front->rank_count + back->rank_count;
        ex->stats.pixels_merged += 2 * (uint64_t)a->active;
        return TSR_OK;
    }
    tsr_composite_sparse *out = *acc == &ex->acc ? &ex->tmp : &ex->acc;
    rc = tsr_composite_sparse_merge(front, back, out, err);
    if (rc)
        return rc;
    ex->stats.pixels_merged += front->active + back->active;
    *acc = out;
    return TSR_OK;
}

/* fold's step for the dense strip (ex->strip, tsr_composite_fold). */
static int strip_add(tsr_composite_executor *ex, const tsr_composite_sparse *piece, int in_front, tsr_error *err)
{
    tsr_composite_fold *f = &ex->strip;
    int rc = in_front ? adjacent(piece, &f->acc, err) : adjacent(&f->acc, piece, err);
    if (rc)
        return rc;
    ex->stats.pixels_merged += piece->active + f->acc.active;
    return tsr_composite_fold_add(f, piece, in_front, err);
}

/* Composites the pieces of one region, in composite order p[0..n) (front
 * first): p[i] is from[i]'s message, or `self` where from[i] < 0. Each
 * received piece is merged as soon as it arrives. Depth mode folds out
 * from `self` (the merge is associative: any grouping of adjacent
 * intervals gives the same bits), so the running image is always the
 * executor's own. Alpha mode folds back to front, acc = p[i] over acc from
 * the last piece: with 8-bit (or float) rounding at every step "over" is
 * not associative, and this is the grouping of a serial back-to-front
 * blend; a schedule that keeps it exact (tsr_composite_schedule_keeps_order)
 * hands this fold single layers in front of a blended suffix. The result
 * is ex->acc, ex->tmp, self, or (one received piece alone) ex->in. */
static int composite_region(tsr_composite_executor *ex, const int *from, int n, tsr_composite_sparse *self,
                            const tsr_composite_image *readback, const void *fill, int mode,
                            const tsr_composite_message_header *expect, const tsr_composite_transport *t,
                            tsr_composite_sparse **result, tsr_error *err)
{
    int rc, at = -1;
    for (int i = 0; i < n && at < 0; i++)
        if (from[i] < 0)
            at = i;
    tsr_composite_sparse *acc = NULL;
    if (mode != TSR_COMPOSITE_ALPHA && at >= 0) {
        /* Two or more pieces into a partly covered region (a merge of the
         * same runs is in place already, and one piece is one merge): the
         * dense strip writes each piece's pixels once instead of the
         * growing union at every step. */
        int strip = n >= 3 && self->active < self->count;
        if (readback && !strip)
            return tsr_error_set(err, TSR_EINVAL, "composite: a read-back's runs alone, and no strip to fold them");
        if (strip && (rc = readback ? tsr_composite_fold_begin_dense(&ex->strip, readback, self, err)
                                    : tsr_composite_fold_begin(&ex->strip, self, err)))
            return rc;
        acc = self;
        for (int i = at - 1; i >= 0; i--)
            if ((rc = recv_piece(ex, from[i], expect, t, err)) ||
                (rc = strip ? strip_add(ex, &ex->in, 1, err) : fold(ex, &acc, &ex->in, 1, err)))
                return rc;
        for (int i = at + 1; i < n; i++)
            if ((rc = recv_piece(ex, from[i], expect, t, err)) ||
                (rc = strip ? strip_add(ex, &ex->in, 0, err) : fold(ex, &acc, &ex->in, 0, err)))
                return rc;
        if (strip) {
            /* A final piece with little background is drawn as the strip
             * is (its background filled in), not gathered first. */
            tsr_composite_fold *f = &ex->strip;
            if (fill && f->acc.count - f->acc.active <= f->acc.count / FILL_FINAL_BACKGROUND_SHARE) {
                if ((rc = tsr_composite_fold_fill(f, fill, err)))
                    return rc;
                ex->stats.final_filled++;
                acc = &f->acc;
            } else {
                if ((rc = tsr_composite_fold_end(f, &ex->acc, err)))
                    return rc;
                acc = &ex->acc;
            }
        }
        *result = acc;
        return TSR_OK;
    }
    for (int i = n - 1; i >= 0; i--) {
        const tsr_composite_sparse *p = self;
        if (from[i] >= 0) {
            if ((rc = recv_piece(ex, from[i], expect, t, err)))
                return rc;
            p = &ex->in;
        }
        if (!acc && i > 0 && p == &ex->in) {
            /* it must outlive the next receive: a copy of its own */
            if ((rc = tsr_composite_sparse_split(p, p->start, p->count, &ex->first, err)))
                return rc;
            acc = &ex->first;
        } else if (!acc) {
            acc = (tsr_composite_sparse *)p;
        } else if ((rc = fold(ex, &acc, p, 1, err))) { /* from the back: p is in front */
            return rc;
        }
    }
    *result = acc;
    return TSR_OK;
}

static void expect_region(tsr_composite_message_header *e, const tsr_composite_schedule *s, uint32_t frame,
                          tsr_composite_region reg, int mode, int color_format, int depth_format)
{
    tsr_composite_message_expect_any(e);
    e->window_width = s->window_width;
    e->window_height = s->window_height;
    e->frame = frame;
    e->start = reg.start;
    e->count = reg.count;
    e->mode = mode;
    e->color_format = color_format;
    e->depth_format = depth_format;
}

int tsr_composite_run_peer_rounds(tsr_composite_executor *ex, int rank, const tsr_composite_image *mine, int mode,
                                  const tsr_composite_transport *t, const void *fill,
                                  const tsr_composite_sparse **final, tsr_error *err)
{
    *final = NULL;
    const tsr_composite_schedule *s = ex->s;
    if (rank < 0 || rank >= s->nranks)
        return tsr_error_set(err, TSR_EINVAL, "composite: rank %d outside 0..%d", rank, s->nranks - 1);
    if (mine->window_width != s->window_width || mine->window_height != s->window_height)
        return tsr_error_set(err, TSR_EINVAL, "composite: rank %d's window is %dx%d, the group's %dx%d", rank,
                             mine->window_width, mine->window_height, s->window_width, s->window_height);
    if (mode != TSR_COMPOSITE_DEPTH && mode != TSR_COMPOSITE_ALPHA)
        return tsr_error_set(err, TSR_EINVAL, "composite: unknown mode %d", mode);
    if (mode == TSR_COMPOSITE_DEPTH && mine->depth_format != TSR_COMPOSITE_DEPTH32F)
        return tsr_error_set(err, TSR_EINVAL, "composite: depth mode needs a depth plane");
    memset(&ex->stats, 0, sizeof ex->stats);
    tsr_composite_image me = *mine;
    me.rank = rank;
    /* Until this rank composites something its image is the read-back
     * itself (`dense`): sends are encoded from it, the kept part of it is
     * compressed alone. No sparse copy of the whole layer is ever made. */
    int dense = 1, rc;
    const tsr_composite_rank *R = &s->ranks[rank];
    for (int i = 0; i < R->nrounds; i++) {
        const tsr_composite_round *rd = &R->rounds[i];
        for (int j = 0; j < rd->nsend; j++) {
            if (dense)
                rc = send_dense(ex, &me, mode, rd->send[j].region, rd->send[j].peer, t, err);
            else if (!(rc = tsr_composite_sparse_view(&ex->cur, rd->send[j].region.start, rd->send[j].region.count,
                                                      &ex->view, err)))
                rc = send_piece(ex, &ex->view, rd->send[j].peer, t, err); /* a view: encoded at once */
            if (rc)
                return rc;
        }
        if (!rd->nrecv) {
            /* nothing to composite: keep a part (the read-back already
             * covers it; a composited image is cut, a copy) */
            if (dense || (rd->keep.start == ex->cur.start && rd->keep.count == ex->cur.count))
                continue;
            if ((rc = tsr_composite_sparse_split(&ex->cur, rd->keep.start, rd->keep.count, &ex->acc, err)))
                return rc;
            tsr_composite_sparse t0 = ex->cur;
            ex->cur = ex->acc;
            ex->acc = t0;
            continue;
        }
        int from[TSR_COMPOSITE_MAX_PEERS + 1], np = 0;
        for (int q = 0; q <= rd->nrecv; q++) {
            if (q == rd->self_index)
                from[np++] = -1;
            if (q < rd->nrecv)
                from[np++] = rd->recv[q].peer;
        }
        tsr_composite_sparse *keep = &ex->view;
        const tsr_composite_image *readback = NULL;
        if (dense)
            rc = keep_of_readback(ex, &me, mode, rd->keep, np, &keep, &readback, err);
        else
            rc = tsr_composite_sparse_view(&ex->cur, rd->keep.start, rd->keep.count, keep, err);
        if (rc)
            return rc;
        if (keep == &ex->layer_view) {
            /* cur is no input of this round: its planes take the first
             * merge (into ex->acc, swapped back below), so one piece-sized
             * buffer serves frame after frame */
            tsr_composite_sparse t0 = ex->acc;
            ex->acc = ex->cur;
            ex->cur = t0;
        }
        tsr_composite_message_header expect;
        expect_region(&expect, s, mine->frame, rd->keep, mode, mine->color_format, mine->depth_format);
        /* the last round's composite is the final piece itself */
        int last = i == R->nrounds - 1 && R->final.start == rd->keep.start && R->final.count == rd->keep.count;
        tsr_composite_sparse *result = NULL;
        if ((rc = composite_region(ex, from, np, keep, readback, last ? fill : NULL, mode, &expect, t, &result, err)))
            return rc;
        if (result == keep && keep == &ex->piece) {
            /* The kept piece, merged in place (full layers), becomes the
             * current image; the old current image's planes serve the next
             * frame's kept piece. No copy, and no third piece-sized buffer. */
            tsr_composite_sparse t0 = ex->cur;
            ex->cur = ex->piece;
            ex->piece = t0;
            dense = 0;
            continue;
        }
        if (result == &ex->in || result == keep) {
            /* a piece alone (no merge made): cur needs a copy of its own */
            if ((rc = tsr_composite_sparse_split(result, result->start, result->count, &ex->acc, err)))
                return rc;
            result = &ex->acc;
        }
        /* the result becomes the current image (swap, no copy) */
        tsr_composite_sparse t0 = ex->cur;
        ex->cur = *result;
        *result = t0;
        dense = 0;
    }
    if (!R->final.count)
        return TSR_OK;
    /* nothing composited (gather, one peer): the final piece is compressed
     * from the read-back; else a view of the composited image */
    tsr_composite_sparse *out = dense ? &ex->piece : &ex->view;
    if (dense)
        rc = tsr_composite_sparse_compress(&me, mode, R->final.start, R->final.count, out, err);
    else
        rc = tsr_composite_sparse_view(&ex->cur, R->final.start, R->final.count, out, err);
    if (rc)
        return rc;
    *final = out;
    return TSR_OK;
}

int tsr_composite_run_peer(tsr_composite_executor *ex, int rank, const tsr_composite_image *mine, int mode,
                           const tsr_composite_transport *t, tsr_error *err)
{
    const tsr_composite_schedule *s = ex->s;
    if (rank >= 0 && rank < s->nranks && !s->ranks[rank].nrounds && s->ranks[rank].final.count &&
        mine->window_width == s->window_width && mine->window_height == s->window_height) {
        /* the read-back as it is goes to the display: encoded from it */
        memset(&ex->stats, 0, sizeof ex->stats);
        tsr_composite_image me = *mine;
        me.rank = rank;
        return send_dense(ex, &me, mode, s->ranks[rank].final, TSR_COMPOSITE_DISPLAY(s->nranks), t, err);
    }
    const tsr_composite_sparse *final = NULL;
    int rc = tsr_composite_run_peer_rounds(ex, rank, mine, mode, t, NULL, &final,
                                           err); /* the display may merge it: no fill */
    if (rc || !final)
        return rc;
    return send_piece(ex, final, TSR_COMPOSITE_DISPLAY(s->nranks), t, err);
}

int tsr_composite_run_display(tsr_composite_executor *ex, uint32_t frame, int mode, int color_format, int depth_format,
                              const void *background, tsr_composite_image *frame_out, const tsr_composite_transport *t,
                              tsr_error *err)
{
    const tsr_composite_schedule *s = ex->s;
    memset(&ex->stats, 0, sizeof ex->stats);
    int rc = tsr_composite_image_init(frame_out, s->window_width, s->window_height, 0, 0, s->window_width,
                                      s->window_height, color_format, depth_format, err);
    if (rc)
        return rc;
    frame_out->frame = frame;
    for (int g = 0; g < s->ngather;) {
        tsr_composite_region reg = s->gather[g].region;
        int from[TSR_COMPOSITE_MAX_PEERS], np = 0;
        for (; g < s->ngather && s->gather[g].region.start == reg.start && s->gather[g].region.count == reg.count; g++)
            from[np++] = s->gather[g].peer;
        tsr_composite_message_header expect;
        expect_region(&expect, s, frame, reg, mode, color_format, depth_format);
        tsr_composite_sparse *result = NULL;
        if ((rc = composite_region(ex, from, np, NULL, NULL, NULL, mode, &expect, t, &result, err)))
            return rc;
        if (result->rank != 0 || result->rank_count != s->nranks)
            return tsr_error_set(err, TSR_EPROTO, "composite: pixels %u+%u hold ranks %d..%d, not all of 0..%d",
                                 reg.start, reg.count, result->rank, result->rank + result->rank_count - 1,
                                 s->nranks - 1);
        /* at once: a received piece is valid until the next receive */
        if ((rc = tsr_composite_sparse_to_dense(result, background, frame_out, err)))
            return rc;
    }
    return TSR_OK;
}
