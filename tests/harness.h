/* tests/harness.h — the checks every C test uses (tests/CMakeLists.txt puts
 * tests/ on every test's include path, so it is `#include "harness.h"`):
 *
 *   CHECK(cond[, fmt, ...])           cond holds; the optional printf-style
 *                                     message (a string literal) says what
 *                                     was seen instead
 *   CHECK_OK(call, err)               a call returning a tsr_error code
 *                                     returns TSR_OK; err is its tsr_error
 *                                     (the includer has tessera/error.h)
 *   CHECK_STR(actual, expected)       two C strings are equal (NULL never is)
 *   CHECK_CONTAINS(haystack, needle)  needle occurs in haystack
 *   REQUIRE(cond[, fmt, ...])         like CHECK, but exits 1 at once (for
 *                                     preconditions later checks depend on)
 *
 * A failed check prints one report on stderr naming the place and the
 * condition, "FILE:LINE: check failed: COND[: MESSAGE]", then does
 * HARNESS_ON_FAIL. By default that counts the failure in harness_failures
 * and goes on, so one run reports every broken check; the test exits
 * non-zero when harness_failures is. A test whose later steps cannot run
 * after a failure defines HARNESS_ON_FAIL before including this header:
 *   #define HARNESS_ON_FAIL exit(1)     stop the program (net tests)
 *   #define HARNESS_ON_FAIL return 1    leave the int-returning test function
 *
 * Calling CHECK(cond) without a message leaves `...` empty: C23 allows it,
 * GCC and Clang accept it in C11 (warning only under -pedantic, which
 * tessera does not use).
 * Owns: the failure count. Never: hides a failure or mocks tessera parts. */
#ifndef TSR_TESTS_HARNESS_H
#define TSR_TESTS_HARNESS_H

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Failed checks so far (HARNESS_ON_FAIL's default counts here). */
static int harness_failures __attribute__((unused));

#ifndef HARNESS_ON_FAIL
#define HARNESS_ON_FAIL harness_failures++
#endif

/* Prints "FILE:LINE: check failed: COND" and then `fmt` (": " plus the
 * caller's message, or just ": " when there is none). */
__attribute__((format(printf, 4, 5))) static inline void harness_report_(const char *file, int line, const char *cond,
                                                                         const char *fmt, ...)
{
    fprintf(stderr, "%s:%d: check failed: %s", file, line, cond);
    if (strcmp(fmt, ": ") != 0) {
        va_list ap;
        va_start(ap, fmt);
        vfprintf(stderr, fmt, ap);
        va_end(ap);
    }
    fputc('\n', stderr);
    fflush(stderr);
}

#define CHECK(cond, ...)                                                  \
    do {                                                                  \
        if (!(cond)) {                                                    \
            harness_report_(__FILE__, __LINE__, #cond, ": " __VA_ARGS__); \
            HARNESS_ON_FAIL;                                              \
        }                                                                 \
    } while (0)

#define REQUIRE(cond, ...)                                                \
    do {                                                                  \
        if (!(cond)) {                                                    \
            harness_report_(__FILE__, __LINE__, #cond, ": " __VA_ARGS__); \
            exit(1);                                                      \
        }                                                                 \
    } while (0)

#define CHECK_OK(call, err)                                                                                      \
    do {                                                                                                         \
        int harness_rc_ = (call);                                                                                \
        if (harness_rc_ != TSR_OK) {                                                                             \
            harness_report_(__FILE__, __LINE__, #call " == TSR_OK", ": got %s: %s", tsr_error_name(harness_rc_), \
                            (err).message);                                                                      \
            HARNESS_ON_FAIL;                                                                                     \
        }                                                                                                        \
    } while (0)

#define CHECK_STR(actual, expected)                                                                            \
    do {                                                                                                       \
        const char *harness_a_ = (actual), *harness_e_ = (expected);                                           \
        if (!harness_a_ || !harness_e_ || strcmp(harness_a_, harness_e_)) {                                    \
            harness_report_(__FILE__, __LINE__, #actual " == " #expected, ":\n  got:      %s\n  expected: %s", \
                            harness_a_ ? harness_a_ : "(null)", harness_e_ ? harness_e_ : "(null)");           \
            HARNESS_ON_FAIL;                                                                                   \
        }                                                                                                      \
    } while (0)

#define CHECK_CONTAINS(haystack, needle)                                                                        \
    do {                                                                                                        \
        const char *harness_h_ = (haystack), *harness_n_ = (needle);                                            \
        if (!harness_h_ || !harness_n_ || !strstr(harness_h_, harness_n_)) {                                    \
            harness_report_(__FILE__, __LINE__, #haystack " contains " #needle, ": '%s' does not contain '%s'", \
                            harness_h_ ? harness_h_ : "(null)", harness_n_ ? harness_n_ : "(null)");            \
            HARNESS_ON_FAIL;                                                                                    \
        }                                                                                                       \
    } while (0)

#endif
