/* spus/binaryswap/strategies/direct.c — direct send: one round in which
 * every peer owns one strip of the window (strip r of N, by pixel index)
 * and receives that strip from every other peer, compositing them in rank
 * order. N(N-1) messages, one round. Pure schedule code. */
#include <stdio.h>
#include "strategy.h"
#include "strategy_internal.h"

int tsr_composite_plan_direct(tsr_composite_schedule *s, tsr_error *err)
{
    int n = s->nranks;
    s->kind = TSR_COMPOSITE_DIRECT;
    s->k = n;
    snprintf(s->name, sizeof s->name, "direct");
    int rc = schedule_alloc(s, n > 1, err);
    if (rc)
        return rc;
    int vrank[TSR_COMPOSITE_MAX_PEERS];
    for (int r = 0; r < n; r++)
        vrank[r] = r;
    int factor = n;
    if (cs_build_rounds(s, 0, vrank, n, &factor, n > 1))
        return tsr_error_set(err, TSR_EINVAL, "direct: pieces do not cover the window");
    return TSR_OK;
}
