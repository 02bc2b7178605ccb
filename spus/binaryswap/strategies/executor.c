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

struct tsr_cs_executor {
    const tsr_cs_schedule *s;
    tsr_image_codec codec;
    tsr_sparse_image cur, acc, tmp, piece;
    tsr_sparse_image *recv; /* one per possible sender */
    uint8_t *buf;
    size_t buf_cap;
    tsr_cs_stats stats;
};

tsr_cs_executor *tsr_cs_executor_new(const tsr_cs_schedule *s, tsr_image_codec c, tsr_error *err)
{
    tsr_cs_executor *ex = calloc(1, sizeof *ex);
    if (ex)
        ex->recv = calloc((size_t)s->nranks + 1, sizeof *ex->recv);
    if (!ex || !ex->recv) {
        free(ex);
        tsr_error_set(err, TSR_ENOMEM, "composite executor: no memory");
        return NULL;
    }
    ex->s = s;
    ex->codec = c;
    return ex;
}

void tsr_cs_executor_free(tsr_cs_executor *ex)
{
    if (!ex)
        return;
    tsr_sparse_image_free(&ex->cur);
    tsr_sparse_image_free(&ex->acc);
    tsr_sparse_image_free(&ex->tmp);
    tsr_sparse_image_free(&ex->piece);
    for (int i = 0; i <= ex->s->nranks; i++)
        tsr_sparse_image_free(&ex->recv[i]);
    free(ex->recv);
    free(ex->buf);
    free(ex);
}

void tsr_cs_executor_stats(const tsr_cs_executor *ex, tsr_cs_stats *out) { *out = ex->stats; }

static int send_piece(tsr_cs_executor *ex, const tsr_sparse_image *img, int to, const tsr_cs_transport *t,
                      tsr_error *err)
{
    size_t need = tsr_image_message_max_size(img->count, img->color_format, img->depth_format, ex->codec), len = 0;
    uint8_t *dst = ex->buf;
    size_t cap = ex->buf_cap;
    if (t->send_buffer) { /* where the transport sends from (shared memory) */
        if (!(dst = t->send_buffer(t->user, to, need, err)))
            return err->code ? err->code : TSR_EIO;
        cap = need;
    } else if (need > ex->buf_cap) {
        uint8_t *b = realloc(ex->buf, need);
        if (!b)
            return tsr_error_set(err, TSR_ENOMEM, "composite: no memory for a %zu-byte message", need);
        dst = ex->buf = b;
        cap = ex->buf_cap = need;
    }
    int rc = tsr_image_message_encode(img, ex->codec, dst, cap, &len, err);
    if (rc || (rc = t->send(t->user, to, dst, len, err)))
        return rc;
    ex->stats.bytes_sent += len;
    ex->stats.messages_sent++;
    return TSR_OK;
}

static int recv_piece(tsr_cs_executor *ex, int from, const tsr_image_message_header *expect, tsr_sparse_image *out,
                      const tsr_cs_transport *t, tsr_error *err)
{
    const void *data = NULL;
    size_t size = 0;
    int rc = t->recv(t->user, from, &data, &size, err);
    if (rc)
        return rc;
    ex->stats.bytes_received += size;
    ex->stats.messages_received++;
    if ((rc = tsr_image_message_decode(data, size, expect, out, err))) {
        char why[sizeof err->message];
        memcpy(why, err->message, sizeof why);
        return tsr_error_set(err, rc, "from peer %d: %s", from, why);
    }
    return TSR_OK;
}

/* Composites pieces[0..n) (front first) into *result; the intervals must
 * be adjacent, or the schedule and the messages disagree. Depth mode folds
 * front to back (the merge is associative: any grouping gives the same
 * bits). Alpha mode folds back to front, acc = pieces[i] over acc from the
 * last piece: with 8-bit (or float) rounding at every step "over" is not
 * associative, and this is the grouping of a serial back-to-front blend;
 * a schedule that keeps it exact (tsr_cs_schedule_keeps_order) hands this
 * fold single layers in front of a blended suffix. */
static int composite_in_order(tsr_cs_executor *ex, tsr_sparse_image **pieces, int n, tsr_sparse_image **result,
                              tsr_error *err)
{
    int back_first = n > 1 && pieces[0]->mode == TSR_COMPOSITE_ALPHA;
    tsr_sparse_image *acc = pieces[back_first ? n - 1 : 0];
    tsr_sparse_image *bufs[2] = {&ex->acc, &ex->tmp};
    int which = 0;
    for (int j = 1; j < n; j++) {
        tsr_sparse_image *next = pieces[back_first ? n - 1 - j : j];
        tsr_sparse_image *front = back_first ? next : acc, *back = back_first ? acc : next;
        if (front->rank + front->rank_count != back->rank)
            return tsr_error_set(
                err, TSR_EPROTO, "composite: piece of ranks %d..%d follows ranks %d..%d (not adjacent in the order)",
                back->rank, back->rank + back->rank_count - 1, front->rank, front->rank + front->rank_count - 1);
        tsr_sparse_image *out = bufs[which];
        if (out == acc)
            out = bufs[which ^= 1];
        int rc = tsr_sparse_image_merge(front, back, out, err);
        if (rc)
            return rc;
        ex->stats.pixels_merged += front->active + back->active;
        acc = out;
        which ^= 1;
    }
    *result = acc;
    return TSR_OK;
}

int tsr_cs_run_peer_rounds(tsr_cs_executor *ex, int rank, const tsr_cimage *mine, int mode, const tsr_cs_transport *t,
                           const tsr_sparse_image **final, tsr_error *err)
{
    *final = NULL;
    const tsr_cs_schedule *s = ex->s;
    if (rank < 0 || rank >= s->nranks)
        return tsr_error_set(err, TSR_EINVAL, "composite: rank %d outside 0..%d", rank, s->nranks - 1);
    if (mine->window_width != s->window_width || mine->window_height != s->window_height)
        return tsr_error_set(err, TSR_EINVAL, "composite: rank %d's window is %dx%d, the group's %dx%d", rank,
                             mine->window_width, mine->window_height, s->window_width, s->window_height);
    memset(&ex->stats, 0, sizeof ex->stats);
    uint32_t all = (uint32_t)s->window_width * (uint32_t)s->window_height;
    tsr_cimage me = *mine;
    me.rank = rank;
    int rc = tsr_sparse_image_compress(&me, mode, 0, all, &ex->cur, err);
    if (rc)
        return rc;
    const tsr_cs_rank *R = &s->ranks[rank];
    for (int i = 0; i < R->nrounds; i++) {
        const tsr_cs_round *rd = &R->rounds[i];
        /* pieces are views of the current image: encoded or merged at
         * once, never copied */
        for (int j = 0; j < rd->nsend; j++) {
            if ((rc = tsr_sparse_image_view(&ex->cur, rd->send[j].region.start, rd->send[j].region.count, &ex->piece,
                                            err)) ||
                (rc = send_piece(ex, &ex->piece, rd->send[j].peer, t, err)))
                return rc;
        }
        if (!rd->nrecv) {
            /* nothing to composite: keep a part (a copy), or all as it is */
            if (rd->keep.start == ex->cur.start && rd->keep.count == ex->cur.count)
                continue;
            if ((rc = tsr_sparse_image_split(&ex->cur, rd->keep.start, rd->keep.count, &ex->acc, err)))
                return rc;
            tsr_sparse_image t0 = ex->cur;
            ex->cur = ex->acc;
            ex->acc = t0;
            continue;
        }
        tsr_sparse_image *pieces[TSR_CS_MAX_PEERS + 1];
        int np = 0;
        if ((rc = tsr_sparse_image_view(&ex->cur, rd->keep.start, rd->keep.count, &ex->piece, err)))
            return rc;
        tsr_image_message_header expect;
        tsr_image_message_expect_any(&expect);
        expect.window_width = s->window_width;
        expect.window_height = s->window_height;
        expect.frame = mine->frame;
        expect.start = rd->keep.start;
        expect.count = rd->keep.count;
        expect.mode = mode;
        expect.color_format = mine->color_format;
        expect.depth_format = mine->depth_format;
        for (int q = 0; q <= rd->nrecv; q++) {
            if (q == rd->self_index) {
                pieces[np++] = &ex->piece;
                if (q == rd->nrecv)
                    break;
            }
            if (q < rd->nrecv) {
                int from = rd->recv[q].peer;
                if ((rc = recv_piece(ex, from, &expect, &ex->recv[from], t, err)))
                    return rc;
                pieces[np++] = &ex->recv[from];
            }
        }
        tsr_sparse_image *result = NULL;
        if ((rc = composite_in_order(ex, pieces, np, &result, err)))
            return rc;
        /* the result becomes the current image (swap, no copy) */
        tsr_sparse_image t0 = ex->cur;
        ex->cur = *result;
        *result = t0;
    }
    if (!R->final.count)
        return TSR_OK;
    if ((rc = tsr_sparse_image_view(&ex->cur, R->final.start, R->final.count, &ex->piece, err)))
        return rc;
    *final = &ex->piece;
    return TSR_OK;
}

int tsr_cs_run_peer(tsr_cs_executor *ex, int rank, const tsr_cimage *mine, int mode, const tsr_cs_transport *t,
                    tsr_error *err)
{
    const tsr_sparse_image *final = NULL;
    int rc = tsr_cs_run_peer_rounds(ex, rank, mine, mode, t, &final, err);
    if (rc || !final)
        return rc;
    return send_piece(ex, final, TSR_CS_DISPLAY(ex->s->nranks), t, err);
}

int tsr_cs_run_display(tsr_cs_executor *ex, uint32_t frame, int mode, int color_format, int depth_format,
                       const void *background, tsr_cimage *frame_out, const tsr_cs_transport *t, tsr_error *err)
{
    const tsr_cs_schedule *s = ex->s;
    memset(&ex->stats, 0, sizeof ex->stats);
    int rc = tsr_cimage_init(frame_out, s->window_width, s->window_height, 0, 0, s->window_width, s->window_height,
                             color_format, depth_format, err);
    if (rc)
        return rc;
    frame_out->frame = frame;
    for (int g = 0; g < s->ngather;) {
        tsr_cs_region reg = s->gather[g].region;
        tsr_sparse_image *pieces[TSR_CS_MAX_PEERS];
        int np = 0;
        tsr_image_message_header expect;
        tsr_image_message_expect_any(&expect);
        expect.window_width = s->window_width;
        expect.window_height = s->window_height;
        expect.frame = frame;
        expect.start = reg.start;
        expect.count = reg.count;
        expect.mode = mode;
        expect.color_format = color_format;
        expect.depth_format = depth_format;
        for (; g < s->ngather && s->gather[g].region.start == reg.start && s->gather[g].region.count == reg.count;
             g++) {
            int from = s->gather[g].peer;
            if ((rc = recv_piece(ex, from, &expect, &ex->recv[from], t, err)))
                return rc;
            pieces[np++] = &ex->recv[from];
        }
        tsr_sparse_image *result = NULL;
        if ((rc = composite_in_order(ex, pieces, np, &result, err)))
            return rc;
        if (result->rank != 0 || result->rank_count != s->nranks)
            return tsr_error_set(err, TSR_EPROTO, "composite: pixels %u+%u hold ranks %d..%d, not all of 0..%d",
                                 reg.start, reg.count, result->rank, result->rank + result->rank_count - 1,
                                 s->nranks - 1);
        if ((rc = tsr_sparse_image_to_dense(result, background, frame_out, err)))
            return rc;
    }
    return TSR_OK;
}
