/* bench/bench_common.h — what every benchmark program shares: a CPU-time
 * clock, the `figure: value` output line, the CSV writer and the common
 * command line (--quick, --csv PATH). Benchmarks only report numbers; they
 * never decide pass or fail, and they never touch global process state. */
#ifndef TSR_BENCH_COMMON_H
#define TSR_BENCH_COMMON_H

#include <stdint.h>
#include <stdio.h>

typedef struct bench_args {
    int quick;            /* tiny workload: only proves the program runs */
    const char *csv_path; /* NULL: no CSV */
    int repeats;          /* timed repetitions; the best one is reported */
} bench_args;

/* Parses --quick, --csv PATH, --repeats N; prints usage and returns -1 on
 * anything else. */
int bench_parse_args(int argc, char **argv, bench_args *args, const char *usage_extra);

/* Seconds of CPU time the calling thread has used (CLOCK_THREAD_CPUTIME_ID).
 * The micro benchmarks are single-threaded and never sleep, so this equals
 * their wall time on an idle core, and on a shared machine the time the
 * thread spent descheduled does not count against the code measured. */
double bench_now(void);

/* Prints "name: value" with `decimals` digits after the point, flushed. */
void bench_figure(const char *name, double value, int decimals);

/* CSV output: opens `path` (NULL gives NULL) and writes the header line. */
FILE *bench_csv_open(const char *path, const char *header);

/* Keeps the compiler from discarding a computed value or a buffer's
 * contents (the benchmark loops must do the real work). */
static inline void bench_keep(const void *p) { __asm__ __volatile__("" : : "r"(p) : "memory"); }

#endif
