/* spus/binaryswap/strategies/plan.c — what every strategy shares: the
 * schedule's memory, the mixed-radix round builder (binary swap, direct
 * send and radix-k are all instances of it), the name parser and the
 * invariant checker. Pure computation: no I/O, no clocks, no state. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "strategy.h"
#include "strategy_internal.h"

int schedule_alloc(tsr_composite_schedule *s, int nrounds, tsr_error *err)
{
    s->ranks = calloc((size_t)s->nranks, sizeof *s->ranks);
    s->gather = calloc((size_t)s->nranks, sizeof *s->gather);
    if (!s->ranks || !s->gather)
        return tsr_error_set(err, TSR_ENOMEM, "composite schedule: no memory for %d ranks", s->nranks);
    for (int r = 0; r < s->nranks; r++) {
        s->ranks[r].nrounds = nrounds;
        if (!nrounds)
            continue;
        s->ranks[r].rounds = calloc((size_t)nrounds, sizeof *s->ranks[r].rounds);
        if (!s->ranks[r].rounds)
            return tsr_error_set(err, TSR_ENOMEM, "composite schedule: no memory for %d rounds", nrounds);
        for (int i = 0; i < nrounds; i++) {
            tsr_composite_round *rd = &s->ranks[r].rounds[i];
            rd->send = calloc((size_t)s->nranks, sizeof *rd->send);
            rd->recv = calloc((size_t)s->nranks, sizeof *rd->recv);
            if (!rd->send || !rd->recv)
                return tsr_error_set(err, TSR_ENOMEM, "composite schedule: no memory for round %d", i);
        }
    }
    return TSR_OK;
}

void tsr_composite_schedule_free(tsr_composite_schedule *s)
{
    if (s->ranks)
        for (int r = 0; r < s->nranks; r++) {
            for (int i = 0; i < s->ranks[r].nrounds && s->ranks[r].rounds; i++) {
                free(s->ranks[r].rounds[i].send);
                free(s->ranks[r].rounds[i].recv);
            }
            free(s->ranks[r].rounds);
        }
    free(s->ranks);
    free(s->gather);
    memset(s, 0, sizeof *s);
}

/* Piece j of k of a region: index arithmetic in 64 bits, so every pixel
 * lands in exactly one piece for any size (some pieces may be empty). */
static tsr_composite_region piece(tsr_composite_region r, int j, int k)
{
    uint64_t a = (uint64_t)r.count * (uint64_t)j / (uint64_t)k, b = (uint64_t)r.count * (uint64_t)(j + 1) / (uint64_t)k;
    tsr_composite_region p = {r.start + (uint32_t)a, (uint32_t)(b - a)};
    return p;
}

int cs_build_rounds(tsr_composite_schedule *s, int first_round, const int *vrank, int nv, const int *factors, int nf)
{
    tsr_composite_region whole = {0, (uint32_t)s->window_width * (uint32_t)s->window_height};
    tsr_composite_region cur[TSR_COMPOSITE_MAX_PEERS];
    for (int v = 0; v < nv; v++)
        cur[v] = whole;
    int stride = 1;
    for (int f = 0; f < nf; f++) {
        int k = factors[f];
        for (int v = 0; v < nv; v++) {
            int d = (v / stride) % k, base = v - d * stride;
            tsr_composite_round *rd = &s->ranks[vrank[v]].rounds[first_round + f];
            tsr_composite_region keep = piece(cur[v], d, k);
            rd->keep = keep;
            rd->nsend = rd->nrecv = 0;
            rd->self_index = 0;
            for (int j = 0; j < k; j++) {
                if (j == d) {
                    rd->self_index = keep.count ? rd->nrecv : 0;
                    continue;
                }
                tsr_composite_region give = piece(cur[v], j, k);
                int peer = vrank[base + j * stride];
                if (give.count)
                    rd->send[rd->nsend++] = (tsr_composite_xfer){peer, give};
                if (keep.count)
                    rd->recv[rd->nrecv++] = (tsr_composite_xfer){peer, keep};
            }
        }
        for (int v = 0; v < nv; v++)
            cur[v] = s->ranks[vrank[v]].rounds[first_round + f].keep;
        stride *= k;
    }
    /* Final pieces partition the window; gather them in window order. */
    s->ngather = 0;
    for (int v = 0; v < nv; v++)
        s->ranks[vrank[v]].final = cur[v];
    for (uint32_t at = 0; at < whole.count;) {
        int found = -1;
        for (int v = 0; v < nv; v++)
            if (cur[v].count && cur[v].start == at)
                found = v;
        if (found < 0)
            return -1;
        s->gather[s->ngather++] = (tsr_composite_xfer){vrank[found], cur[found]};
        at += cur[found].count;
    }
    return 0;
}

void cs_empty_round(tsr_composite_round *rd, tsr_composite_region keep)
{
    rd->nsend = rd->nrecv = 0;
    rd->self_index = 0;
    rd->keep = keep;
}

int tsr_composite_plan(int kind, int nranks, int window_width, int window_height, int k, const tsr_composite_hint *hint,
                       tsr_composite_schedule *out, tsr_error *err)
{
    memset(out, 0, sizeof *out);
    if (nranks < 1 || nranks > TSR_COMPOSITE_MAX_PEERS)
        return tsr_error_set(err, TSR_EINVAL, "composite schedule: %d peers (1..%d)", nranks, TSR_COMPOSITE_MAX_PEERS);
    if (window_width < 1 || window_height < 1 || window_width > TSR_COMPOSITE_MAX_SIDE ||
        window_height > TSR_COMPOSITE_MAX_SIDE)
        return tsr_error_set(err, TSR_EINVAL, "composite schedule: window %dx%d", window_width, window_height);
    out->nranks = nranks;
    out->window_width = window_width;
    out->window_height = window_height;
    char reason[sizeof out->reason] = "";
    if (kind == TSR_COMPOSITE_AUTO) {
        tsr_composite_choose(nranks, window_width, window_height, hint, &kind, &k, reason, sizeof reason);
    }
    int rc;
    switch (kind) {
    case TSR_COMPOSITE_BSWAP: rc = tsr_composite_plan_bswap(out, err); break;
    case TSR_COMPOSITE_DIRECT: rc = tsr_composite_plan_direct(out, err); break;
    case TSR_COMPOSITE_RADIXK: rc = tsr_composite_plan_radixk(out, k, err); break;
    case TSR_COMPOSITE_GATHER: rc = tsr_composite_plan_gather(out, err); break;
    default: return tsr_error_set(err, TSR_EINVAL, "composite schedule: unknown strategy %d", kind);
    }
    if (rc) {
        tsr_composite_schedule_free(out);
        return rc;
    }
    if (*reason)
        snprintf(out->reason, sizeof out->reason, "%s", reason);
    else
        snprintf(out->reason, sizeof out->reason, "%s requested", out->name);
    return TSR_OK;
}

int tsr_composite_kind_parse(const char *text, int *kind, int *k, tsr_error *err)
{
    *k = 0;
    if (!strcmp(text, "auto"))
        *kind = TSR_COMPOSITE_AUTO;
    else if (!strcmp(text, "bswap") || !strcmp(text, "binaryswap"))
        *kind = TSR_COMPOSITE_BSWAP;
    else if (!strcmp(text, "direct"))
        *kind = TSR_COMPOSITE_DIRECT;
    else if (!strcmp(text, "gather"))
        *kind = TSR_COMPOSITE_GATHER;
    else if (!strcmp(text, "radixk") || !strcmp(text, "radix-k"))
        *kind = TSR_COMPOSITE_RADIXK;
    else if (!strncmp(text, "radixk-", 7) || !strncmp(text, "radix-k-", 8)) {
        const char *n = text + (text[5] == '-' ? 8 : 7);
        char *end;
        long v = strtol(n, &end, 10);
        if (!*n || *end || v < 2 || v > TSR_COMPOSITE_MAX_PEERS)
            return tsr_error_set(err, TSR_EINVAL, "strategy '%s': k must be 2..%d", text, TSR_COMPOSITE_MAX_PEERS);
        *kind = TSR_COMPOSITE_RADIXK;
        *k = (int)v;
    } else {
        return tsr_error_set(err, TSR_EINVAL,
                             "strategy '%s': unknown (valid: auto, bswap, direct, radixk, radixk-K, gather)", text);
    }
    return TSR_OK;
}

/* ---- invariants ---------------------------------------------------------- */

typedef struct held {
    tsr_composite_region region;
    int lo, n; /* ranks lo..lo+n-1 composited into it */
} held;

static int inside(tsr_composite_region a, tsr_composite_region outer)
{
    return !a.count || (a.start >= outer.start && (uint64_t)a.start + a.count <= (uint64_t)outer.start + outer.count);
}

static int same(tsr_composite_region a, tsr_composite_region b) { return a.start == b.start && a.count == b.count; }

int tsr_composite_schedule_check(const tsr_composite_schedule *s, tsr_error *err)
{
    int n = s->nranks;
    tsr_composite_region whole = {0, (uint32_t)s->window_width * (uint32_t)s->window_height};
    held h[TSR_COMPOSITE_MAX_PEERS], next[TSR_COMPOSITE_MAX_PEERS];
    int rounds = n ? s->ranks[0].nrounds : 0;
    for (int r = 0; r < n; r++) {
        h[r] = (held){whole, r, 1};
        if (s->ranks[r].nrounds != rounds)
            return tsr_error_set(err, TSR_EINVAL, "%s: rank %d has %d rounds, rank 0 %d", s->name, r,
                                 s->ranks[r].nrounds, rounds);
    }
    for (int i = 0; i < rounds; i++) {
        for (int r = 0; r < n; r++) {
            const tsr_composite_round *rd = &s->ranks[r].rounds[i];
            /* every send has its receive, and the other way round */
            for (int j = 0; j < rd->nsend; j++) {
                const tsr_composite_xfer *x = &rd->send[j];
                if (x->peer < 0 || x->peer >= n || x->peer == r || !inside(x->region, h[r].region))
                    return tsr_error_set(err, TSR_EINVAL, "%s: round %d: rank %d sends a bad piece to %d", s->name, i,
                                         r, x->peer);
                const tsr_composite_round *o = &s->ranks[x->peer].rounds[i];
                int hits = 0;
                for (int q = 0; q < o->nrecv; q++)
                    hits += o->recv[q].peer == r && same(o->recv[q].region, x->region);
                if (hits != 1)
                    return tsr_error_set(err, TSR_EINVAL,
                                         "%s: round %d: rank %d's piece %u+%u to %d is received %d times", s->name, i,
                                         r, x->region.start, x->region.count, x->peer, hits);
            }
            for (int q = 0; q < rd->nrecv; q++) {
                const tsr_composite_xfer *x = &rd->recv[q];
                if (x->peer < 0 || x->peer >= n || !same(x->region, rd->keep))
                    return tsr_error_set(err, TSR_EINVAL, "%s: round %d: rank %d receives a bad piece from %d", s->name,
                                         i, r, x->peer);
                const tsr_composite_round *o = &s->ranks[x->peer].rounds[i];
                int hits = 0;
                for (int j = 0; j < o->nsend; j++)
                    hits += o->send[j].peer == r && same(o->send[j].region, x->region);
                if (hits != 1)
                    return tsr_error_set(err, TSR_EINVAL, "%s: round %d: rank %d expects a piece %d never sends",
                                         s->name, i, r, x->peer);
            }
            if (!inside(rd->keep, h[r].region))
                return tsr_error_set(err, TSR_EINVAL, "%s: round %d: rank %d keeps pixels it does not hold", s->name, i,
                                     r);
            /* composite order: adjacent rank intervals, front first */
            next[r] = (held){rd->keep, h[r].lo, h[r].n};
            if (rd->keep.count && rd->nrecv) {
                int lo = -1, end = -1;
                for (int q = 0; q <= rd->nrecv; q++) {
                    held p = q == rd->self_index ? h[r] : h[rd->recv[q < rd->self_index ? q : q - 1].peer];
                    if (q > 0 && p.lo != end)
                        return tsr_error_set(err, TSR_EINVAL,
                                             "%s: round %d: rank %d composites ranks %d.. after ..%d (not adjacent)",
                                             s->name, i, r, p.lo, end - 1);
                    if (q == 0)
                        lo = p.lo;
                    end = p.lo + p.n;
                }
                next[r] = (held){rd->keep, lo, end - lo};
            }
        }
        memcpy(h, next, sizeof(held) * (size_t)n);
    }
    /* gather: pieces in window order cover every pixel once, each with all ranks */
    uint32_t at = 0;
    for (int g = 0; g < s->ngather;) {
        tsr_composite_region reg = s->gather[g].region;
        if (reg.start != at || !reg.count)
            return tsr_error_set(err, TSR_EINVAL, "%s: gather piece %d starts at %u, expected %u", s->name, g,
                                 reg.start, at);
        int lo = -1, end = -1;
        for (; g < s->ngather && same(s->gather[g].region, reg); g++) {
            int r = s->gather[g].peer;
            if (r < 0 || r >= n || !same(s->ranks[r].final, reg) || !inside(reg, h[r].region))
                return tsr_error_set(err, TSR_EINVAL, "%s: gather piece %d from rank %d is not its final piece",
                                     s->name, g, r);
            if (lo < 0)
                lo = h[r].lo;
            else if (h[r].lo != end)
                return tsr_error_set(err, TSR_EINVAL, "%s: gather of %u+%u composites rank %d after ..%d", s->name,
                                     reg.start, reg.count, h[r].lo, end - 1);
            end = h[r].lo + h[r].n;
        }
        if (lo != 0 || end != n)
            return tsr_error_set(err, TSR_EINVAL, "%s: pixels %u+%u hold ranks %d..%d of 0..%d", s->name, reg.start,
                                 reg.count, lo, end - 1, n - 1);
        at += reg.count;
    }
    if (at != whole.count)
        return tsr_error_set(err, TSR_EINVAL, "%s: gather covers %u of %u pixels", s->name, at, whole.count);
    return TSR_OK;
}

/* Replays the schedule on rank intervals: every rank starts holding its
 * own layer; a round's composite takes the senders' intervals as they were
 * before the round (rounds are aligned: every rank has nrounds). */
int tsr_composite_schedule_keeps_order(const tsr_composite_schedule *s, char *why, size_t why_size)
{
    int first[TSR_COMPOSITE_MAX_PEERS], count[TSR_COMPOSITE_MAX_PEERS], nfirst[TSR_COMPOSITE_MAX_PEERS],
        ncount[TSR_COMPOSITE_MAX_PEERS];
    for (int r = 0; r < s->nranks; r++) {
        first[r] = r;
        count[r] = 1;
    }
    int nrounds = s->nranks ? s->ranks[0].nrounds : 0;
    for (int i = 0; i < nrounds; i++) {
        for (int r = 0; r < s->nranks; r++) {
            nfirst[r] = first[r];
            ncount[r] = count[r];
            const tsr_composite_round *rd = &s->ranks[r].rounds[i];
            if (!rd->nrecv)
                continue;
            /* the fold runs from the last piece: every piece before it
             * must be one layer */
            int n = rd->nrecv + 1, lo = TSR_COMPOSITE_MAX_PEERS, total = 0;
            for (int q = 0; q < n; q++) {
                int who = q == rd->self_index ? r : rd->recv[q < rd->self_index ? q : q - 1].peer;
                if (q < n - 1 && count[who] > 1) {
                    snprintf(why, why_size,
                             "round %d: rank %d blends ranks %d..%d, already blended, in front of others (the "
                             "blend would be regrouped)",
                             i, r, first[who], first[who] + count[who] - 1);
                    return 0;
                }
                lo = first[who] < lo ? first[who] : lo;
                total += count[who];
            }
            nfirst[r] = lo;
            ncount[r] = total;
        }
        memcpy(first, nfirst, sizeof first);
        memcpy(count, ncount, sizeof count);
    }
    /* the display: pieces of one region composited (gather) */
    for (int g = 0; g < s->ngather;) {
        int h = g;
        while (h < s->ngather && s->gather[h].region.start == s->gather[g].region.start &&
               s->gather[h].region.count == s->gather[g].region.count)
            h++;
        for (int q = g; q < h - 1; q++)
            if (count[s->gather[q].peer] > 1) {
                snprintf(why, why_size, "the display blends ranks %d..%d, already blended, in front of others",
                         first[s->gather[q].peer], first[s->gather[q].peer] + count[s->gather[q].peer] - 1);
                return 0;
            }
        g = h;
    }
    snprintf(why, why_size, "every pixel's layers are blended in one place, back to front");
    return 1;
}

int tsr_composite_schedule_display_composites(const tsr_composite_schedule *s)
{
    for (int g = 1; g < s->ngather; g++)
        if (same(s->gather[g].region, s->gather[g - 1].region))
            return 1;
    return 0;
}

uint64_t tsr_composite_schedule_link_bytes(const tsr_composite_schedule *s, int color_format, int depth_format,
                                           tsr_composite_codec c)
{
    uint64_t busiest = 0;
    int display = tsr_composite_schedule_display_composites(s);
    for (int p = 0; p < s->nranks; p++) {
        uint64_t to[TSR_COMPOSITE_MAX_PEERS] = {0}, to_display = 0;
        const tsr_composite_rank *R = &s->ranks[p];
        for (int i = 0; i < R->nrounds; i++)
            for (int j = 0; j < R->rounds[i].nsend; j++) {
                const tsr_composite_xfer *x = &R->rounds[i].send[j];
                if (x->peer >= 0 && x->peer < s->nranks)
                    to[x->peer] += tsr_composite_message_max_size(x->region.count, color_format, depth_format, c);
            }
        if (display && R->final.count)
            to_display = tsr_composite_message_max_size(R->final.count, color_format, depth_format, c);
        for (int q = 0; q < s->nranks; q++)
            if (q != p && to[q] + to_display > busiest)
                busiest = to[q] + to_display;
        if (s->nranks == 1 && to_display > busiest)
            busiest = to_display;
    }
    return busiest;
}
