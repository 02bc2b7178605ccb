/* core/util/clock.c — the one monotonic clock (tessera/dev/util.h): seconds
 * on CLOCK_MONOTONIC, for intervals (the origin is arbitrary). Owns nothing.
 * Never: a second copy elsewhere; wall-clock time for durations. */
#include "tessera/dev/util.h"

#include <time.h>

double tsr_now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}
