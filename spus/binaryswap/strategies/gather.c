/* spus/binaryswap/strategies/gather.c — gather to one, the baseline
 * Chromium's readback with depth gave: no rounds; every peer sends its
 * whole image to the display, which composites them in rank order. Pure
 * schedule code. */
#include <stdio.h>
#include "strategy.h"
#include "strategy_internal.h"

int tsr_composite_plan_gather(tsr_composite_schedule *s, tsr_error *err)
{
    s->kind = TSR_COMPOSITE_GATHER;
    s->k = s->nranks;
    snprintf(s->name, sizeof s->name, "gather");
    int rc = schedule_alloc(s, 0, err);
    if (rc)
        return rc;
    tsr_composite_region whole = {0, (uint32_t)s->window_width * (uint32_t)s->window_height};
    s->ngather = 0;
    for (int r = 0; r < s->nranks; r++) {
        s->ranks[r].final = whole;
        s->gather[s->ngather++] = (tsr_composite_xfer){r, whole};
    }
    return TSR_OK;
}
