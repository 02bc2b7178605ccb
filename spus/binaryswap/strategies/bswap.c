/* spus/binaryswap/strategies/bswap.c — binary swap for any peer count.
 * With p the largest power of two <= N, the first N - p pairs of
 * neighbours (2j, 2j+1) fold first: 2j+1 sends its whole image to 2j (an
 * adjacent interval, so equal depth still goes to the lower rank), then p
 * participants swap halves for log2(p) rounds. Pure schedule code. */
#include <stdio.h>
#include "strategy.h"
#include "strategy_internal.h"

int tsr_composite_plan_bswap(tsr_composite_schedule *s, tsr_error *err)
{
    int n = s->nranks, p = 1, logp = 0;
    while (p * 2 <= n) {
        p *= 2;
        logp++;
    }
    int extra = n - p, fold = extra > 0;
    s->kind = TSR_COMPOSITE_BSWAP;
    s->k = 2;
    snprintf(s->name, sizeof s->name, "bswap");
    int rc = schedule_alloc(s, fold + logp, err);
    if (rc)
        return rc;
    tsr_composite_region whole = {0, (uint32_t)s->window_width * (uint32_t)s->window_height}, none = {0, 0};
    int vrank[TSR_COMPOSITE_MAX_PEERS], nv = 0;
    for (int r = 0; r < n; r++) {
        if (r < 2 * extra && r % 2 == 1) {
            /* folded: hands everything to its left neighbour, then idles */
            tsr_composite_round *rd = &s->ranks[r].rounds[0];
            cs_empty_round(rd, none);
            rd->send[rd->nsend++] = (tsr_composite_xfer){r - 1, whole};
            for (int i = 1; i < fold + logp; i++)
                cs_empty_round(&s->ranks[r].rounds[i], none);
            s->ranks[r].final = none;
            continue;
        }
        if (fold) {
            tsr_composite_round *rd = &s->ranks[r].rounds[0];
            cs_empty_round(rd, whole);
            if (r < 2 * extra) {
                rd->recv[rd->nrecv++] = (tsr_composite_xfer){r + 1, whole};
                rd->self_index = 0;
            }
        }
        vrank[nv++] = r;
    }
    int factors[8];
    for (int i = 0; i < logp; i++)
        factors[i] = 2;
    if (cs_build_rounds(s, fold, vrank, nv, factors, logp))
        return tsr_error_set(err, TSR_EINVAL, "bswap: pieces do not cover the window");
    return TSR_OK;
}
