/* spus/binaryswap/strategies/radixk.c — radix-k: N is factored into
 * rounds of k (or the nearest divisor of what is left; a prime above k is
 * one round of its own), and in each round groups of k peers, each holding
 * the same region, split it k ways as direct send does. k = 2 on a power of
 * two is binary swap, k = N direct send. Pure schedule code. */
#include <stdio.h>
#include "strategy.h"
#include "strategy_internal.h"

/* Factors of n, each <= k where n allows (the lowest digit first). */
static int factor(int n, int k, int *f)
{
    int nf = 0;
    while (n > 1) {
        int pick = 0;
        for (int d = k < n ? k : n; d >= 2 && !pick; d--)
            if (n % d == 0)
                pick = d;
        if (!pick) /* smallest prime factor, above k */
            for (int d = 2; d <= n && !pick; d++)
                if (n % d == 0)
                    pick = d;
        f[nf++] = pick;
        n /= pick;
    }
    return nf;
}

int tsr_composite_plan_radixk(tsr_composite_schedule *s, int k, tsr_error *err)
{
    int n = s->nranks;
    if (k == 0)
        k = 4;
    if (k < 2)
        return tsr_error_set(err, TSR_EINVAL, "radixk: k must be at least 2 (got %d)", k);
    int f[8];
    int nf = factor(n, k, f);
    s->kind = TSR_COMPOSITE_RADIXK;
    s->k = k;
    snprintf(s->name, sizeof s->name, "radixk-%d", k);
    int rc = schedule_alloc(s, nf, err);
    if (rc)
        return rc;
    int vrank[TSR_COMPOSITE_MAX_PEERS];
    for (int r = 0; r < n; r++)
        vrank[r] = r;
    if (cs_build_rounds(s, 0, vrank, n, f, nf))
        return tsr_error_set(err, TSR_EINVAL, "radixk: pieces do not cover the window");
    return TSR_OK;
}
