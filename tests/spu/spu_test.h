/* tests/spu/spu_test.h — a tiny runner for the SPU framework tests: each
 * program holds named test functions; ctest runs one per process by name
 * (`prog TEST_NAME [ARGS...]`), so one failure never hides another.
 * Owns: check macros and the failure count. Never: mocks tessera parts. */
#ifndef TSR_TESTS_SPU_TEST_H
#define TSR_TESTS_SPU_TEST_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct spu_test_case {
    const char *name;
    void (*run)(void);
} spu_test_case;

static int spu_test_failures;
/* Extra command-line arguments after the test name (directories etc.). */
static int spu_test_argc;
static char **spu_test_argv;

#define CHECK(cond)                                                                                \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);               \
            spu_test_failures++;                                                                   \
        }                                                                                          \
    } while (0)

#define CHECK_STR(actual, expected)                                                                \
    do {                                                                                           \
        const char *a_ = (actual), *e_ = (expected);                                               \
        if (!a_ || !e_ || strcmp(a_, e_)) {                                                        \
            fprintf(stderr, "%s:%d: CHECK_STR failed: %s\n  got:      %s\n  expected: %s\n",       \
                    __FILE__, __LINE__, #actual, a_ ? a_ : "(null)", e_ ? e_ : "(null)");          \
            spu_test_failures++;                                                                   \
        }                                                                                          \
    } while (0)

#define CHECK_CONTAINS(haystack, needle)                                                           \
    do {                                                                                           \
        const char *h_ = (haystack), *n_ = (needle);                                               \
        if (!h_ || !strstr(h_, n_)) {                                                              \
            fprintf(stderr, "%s:%d: '%s' does not contain '%s'\n", __FILE__, __LINE__,             \
                    h_ ? h_ : "(null)", n_);                                                       \
            spu_test_failures++;                                                                   \
        }                                                                                          \
    } while (0)

/* Fails the test at once (for preconditions later checks depend on). */
#define REQUIRE(cond)                                                                              \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: REQUIRE failed: %s\n", __FILE__, __LINE__, #cond);             \
            exit(1);                                                                               \
        }                                                                                          \
    } while (0)

static int spu_test_main(const spu_test_case *tests, size_t count, int argc, char **argv) {
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
        if (spu_test_failures) {
            fprintf(stderr, "%s: %d check(s) failed\n", argv[1], spu_test_failures);
            return 1;
        }
        printf("%s: ok\n", argv[1]);
        return 0;
    }
    fprintf(stderr, "%s: no test named '%s'\n", argv[0], argv[1]);
    return 2;
}

#define SPU_TEST_MAIN(table)                                                                       \
    int main(int argc, char **argv) {                                                              \
        return spu_test_main(table, sizeof table / sizeof table[0], argc, argv);                   \
    }

#endif
