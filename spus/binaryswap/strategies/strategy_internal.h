/* spus/binaryswap/strategies/strategy_internal.h — what the strategy files
 * share with plan.c (not for the SPU). Owns nothing. */
#ifndef TSR_SPUS_BINARYSWAP_STRATEGY_INTERNAL_H
#define TSR_SPUS_BINARYSWAP_STRATEGY_INTERNAL_H

#include "strategy.h"

/* Allocates ranks, gather list and `nrounds` rounds per rank (each with
 * room for nranks sends and receives). */
int schedule_alloc(tsr_composite_schedule *s, int nrounds, tsr_error *err);
/* Fills rounds first_round.. of the virtual participants vrank[0..nv) (real
 * ranks, in compositing order) as a mixed-radix exchange with the given
 * factors (product nv), the lowest digit first, then their final pieces and
 * the gather list. Returns 0, or -1 when the pieces do not cover the window. */
int cs_build_rounds(tsr_composite_schedule *s, int first_round, const int *vrank, int nv, const int *factors, int nf);
void cs_empty_round(tsr_composite_round *rd, tsr_composite_region keep);

#endif
