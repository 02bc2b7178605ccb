/* spus/binaryswap/strategies/auto.c — the automatic choice, from the peer
 * count, the window and the bytes an image encoded to last frame. The
 * reasoning, in the order the rules apply:
 *  - one peer: nothing to composite; its image goes to the display;
 *  - small images (all peers' bytes together under 256 KiB): a round costs
 *    more in latency than the display spends compositing, so gather;
 *  - up to 8 peers: direct send, one round, every peer busy, N(N-1) small
 *    messages (cheap on one host and on a LAN);
 *  - more: radix-k with k = 8 (or 4 when N has no factor 8), few rounds of
 *    few messages, as Kendall et al.'s radix-k measurements suggest.
 * Pure: no clocks, no state; the SPU logs `reason`. */
#include <stdio.h>
#include "strategy.h"

int tsr_composite_choose(int nranks, int window_width, int window_height, const tsr_composite_hint *hint, int *kind,
                         int *k, char *reason, size_t reason_size)
{
    uint64_t frame = (uint64_t)window_width * (uint64_t)window_height * 8;
    uint64_t bytes = hint && hint->image_bytes ? hint->image_bytes : frame;
    uint64_t total = bytes * (uint64_t)nranks;
    *k = 0;
    if (nranks == 1) {
        *kind = TSR_COMPOSITE_GATHER;
        snprintf(reason, reason_size, "auto: gather, one peer has nothing to composite");
    } else if (total < 256 * 1024) {
        *kind = TSR_COMPOSITE_GATHER;
        snprintf(reason, reason_size, "auto: gather, %d peers send %llu bytes in all (< 256 KiB): latency-bound",
                 nranks, (unsigned long long)total);
    } else if (nranks <= 8) {
        *kind = TSR_COMPOSITE_DIRECT;
        snprintf(reason, reason_size, "auto: direct, %d peers (<= 8), %llu bytes per image: one round", nranks,
                 (unsigned long long)bytes);
    } else {
        *kind = TSR_COMPOSITE_RADIXK;
        *k = nranks % 8 == 0 ? 8 : 4;
        snprintf(reason, reason_size,
                 "auto: radixk-%d, %d peers (> 8), %llu bytes per image: few rounds of few messages", *k, nranks,
                 (unsigned long long)bytes);
    }
    return TSR_OK;
}
