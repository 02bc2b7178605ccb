/* spus/binaryswap/stats.h — binaryswap's `stats` option: one line per
 * composited frame per peer, appended to a file every peer of a group may
 * share (each line is one write(2) on an O_APPEND descriptor, so lines of
 * different processes never interleave). Times are CLOCK_MONOTONIC
 * nanoseconds, one clock for every process of the host, so a reader can
 * line up the peers' swaps with rank 0's frame-complete time (bench/run
 * binaryswap does). Owns the descriptor; never decides anything from the
 * figures, never prints them. */
#ifndef TSR_SPUS_BINARYSWAP_STATS_H
#define TSR_SPUS_BINARYSWAP_STATS_H

#include <stdint.h>
#include "tessera/error.h"

typedef struct binaryswap_frame_stats {
    uint32_t frame;
    int rank, nranks;
    int64_t swap_ns; /* the frame hook ran: the render's SwapBuffers */
    /* this process's CPU time (as cpu_ns) when the frame hook began: what
     * it spent before, since the last line, is the application's frame and
     * the render's finish, not compositing */
    int64_t hook_cpu_ns;
    int64_t ready_ns;      /* this peer's layer handed to the compositor */
    int64_t composited_ns; /* this peer's rounds done */
    int64_t assembled_ns;  /* this peer's final piece is final (gather: rank 0 assembled the frame; others 0) */
    int64_t sent_ns;       /* its piece (rank 0: and the swap) packed and handed to the display stream */
    int64_t displayed_ns;  /* rank 0: the display node answered after its swap (else 0) */
    uint64_t bytes_sent;   /* image bytes this peer sent */
    uint64_t final_filled; /* its final piece went to the display filled, not gathered (0 or 1) */
} binaryswap_frame_stats;

int64_t binaryswap_now_ns(void);
/* CLOCK_PROCESS_CPUTIME_ID in nanoseconds (every thread of the process). */
int64_t binaryswap_cpu_ns(void);
/* Opens (creates, appends to) `path`; -1 and TSR_EIO naming it on failure. */
int binaryswap_stats_open(const char *path, tsr_error *err);
/* Appends the frame's line, with this process's VmHWM, VmRSS and CPU time
 * (CLOCK_PROCESS_CPUTIME_ID, every thread: the part of a frame a loaded
 * machine's other processes do not inflate). */
void binaryswap_stats_write(int fd, const binaryswap_frame_stats *s);

#endif
