/* bench/bench_common.c — clock, figure lines and CSV files for the
 * benchmark programs (see bench_common.h). Owns no state between calls;
 * must never exit the process on its own except for a usage error. */
#include "bench_common.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

int bench_parse_args(int argc, char **argv, bench_args *args, const char *usage_extra)
{
    args->quick = 0;
    args->csv_path = NULL;
    args->repeats = 7;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--quick") == 0) {
            args->quick = 1;
        } else if (strcmp(argv[i], "--csv") == 0 && i + 1 < argc) {
            args->csv_path = argv[++i];
        } else if (strcmp(argv[i], "--repeats") == 0 && i + 1 < argc) {
            args->repeats = atoi(argv[++i]);
            if (args->repeats < 1) {
                fprintf(stderr, "%s: --repeats needs a positive number\n", argv[0]);
                return -1;
            }
        } else {
            fprintf(stderr, "usage: %s [--quick] [--csv PATH] [--repeats N]%s\n", argv[0],
                    usage_extra ? usage_extra : "");
            return -1;
        }
    }
    if (args->quick)
        args->repeats = 1;
    return 0;
}

double bench_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

void bench_figure(const char *name, double value, int decimals)
{
    printf("%s: %.*f\n", name, decimals, value);
    fflush(stdout);
}

FILE *bench_csv_open(const char *path, const char *header)
{
    if (!path)
        return NULL;
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "bench: cannot write %s\n", path);
        return NULL;
    }
    fprintf(f, "%s\n", header);
    return f;
}
