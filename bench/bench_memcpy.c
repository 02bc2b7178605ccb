/* bench/bench_memcpy.c — the memory-bandwidth reference of the sort-last
 * figures (bench/binaryswap.sh): memcpy of one 1920x1080 RGBA8 + 32-bit
 * depth frame (16.6 MB, colour and depth planes), best of the repeats,
 * the same measurement bench_composite prints as memcpy_frame_ms. A
 * separate program so a multi-process run can take its reference in the
 * same minutes as its frames. Prints figures; never pass/fail. */
#include <stdlib.h>
#include <string.h>
#include "bench_common.h"

int main(int argc, char **argv)
{
    bench_args a;
    if (bench_parse_args(argc, argv, &a, "") < 0)
        return 2;
    int repeats = a.quick ? 2 : (a.repeats > 0 ? a.repeats : 15);
    size_t n = a.quick ? 64 * 36 : (size_t)1920 * 1080;
    uint8_t *src = NULL, *dst = NULL;
    if (posix_memalign((void **)&src, 64, n * 8) || posix_memalign((void **)&dst, 64, n * 8))
        return 1;
    memset(src, 1, n * 8);
    memset(dst, 2, n * 8);
    double best = 1e9;
    for (int r = 0; r < repeats; r++) {
        double t0 = bench_now();
        memcpy(dst, src, n * 4);                 /* colour */
        memcpy(dst + n * 4, src + n * 4, n * 4); /* depth */
        double t1 = bench_now();
        bench_keep(dst);
        if (t1 - t0 < best)
            best = t1 - t0;
    }
    /* 6 decimals: the --quick frame (64x36) copies in about a microsecond,
     * which 3 decimals rounded to 0 (and composite_vs_memcpy to inf) */
    bench_figure("memcpy_frame_ms", best * 1e3, 6);
    free(src);
    free(dst);
    return 0;
}
