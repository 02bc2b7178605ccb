/* tests/spu/spu_test.h — a tiny runner for the SPU framework tests: each
 * program holds named test functions; ctest runs one per process by name
 * (`prog TEST_NAME [ARGS...]`), so one failure never hides another.
 * Owns: the runner (the checks and their count are tests/harness.h's).
 * Never: mocks tessera parts. */
#ifndef TSR_TESTS_SPU_TEST_H
#define TSR_TESTS_SPU_TEST_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

typedef struct spu_test_case {
    const char *name;
    void (*run)(void);
} spu_test_case;

/* Extra command-line arguments after the test name (directories etc.). */
static int spu_test_argc;
static char **spu_test_argv;

static int spu_test_main(const spu_test_case *tests, size_t count, int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s TEST [ARGS...]\ntests:\n", argv[0]);
        for (size_t i = 0; i < count; i++)
            fprintf(stderr, "  %s\n", tests[i].name);
        return 2;
    }
    spu_test_argc = argc - 2;
    spu_test_argv = argv + 2;
    for (size_t i = 0; i < count; i++) {
        if (strcmp(tests[i].name, argv[1]))
            continue;
        tests[i].run();
        if (harness_failures) {
            fprintf(stderr, "%s: %d check(s) failed\n", argv[1], harness_failures);
            return 1;
        }
        printf("%s: ok\n", argv[1]);
        return 0;
    }
    fprintf(stderr, "%s: no test named '%s'\n", argv[0], argv[1]);
    return 2;
}

#define SPU_TEST_MAIN(table) \
    int main(int argc, char **argv) { return spu_test_main(table, sizeof table / sizeof table[0], argc, argv); }

#endif
