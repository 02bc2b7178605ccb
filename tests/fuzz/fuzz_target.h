/* tests/fuzz/fuzz_target.h — the entry point every fuzz target except the
 * unpacker's (fuzz_unpack.h) defines, shared by its libFuzzer build
 * (LLVMFuzzerTestOneInput calls it) and its corpus replay (replay.c built
 * with TSR_FUZZ_TARGET), so both run an input exactly the same way.
 * Test code only; never part of a library. */
#ifndef TSR_TESTS_FUZZ_TARGET_H
#define TSR_TESTS_FUZZ_TARGET_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "tessera/error.h"

/* Runs one input through the decoder under test. Returns 0 when the input
 * was accepted, else the decoder's error code with its message copied into
 * `why` (may be NULL). A decoder that misbehaves (a sanitizer report, a
 * broken invariant the target checks) crashes instead: that is the test. */
int fuzz_target_explain(const uint8_t *data, size_t size, char *why, size_t why_size);

/* Breaks the run when a property the target checks does not hold: a trap,
 * so libFuzzer and the replay both report it with a stack. */
#define FUZZ_REQUIRE(cond)    \
    do {                      \
        if (!(cond))          \
            __builtin_trap(); \
    } while (0)

/* The error contract of every decoder here: a failure is a TSR_E* code
 * with a non-empty message, one line. Copies the message into `why`. */
static inline int fuzz_rejected(int rc, const tsr_error *err, char *why, size_t why_size)
{
    FUZZ_REQUIRE(rc != 0);
    FUZZ_REQUIRE(memchr(err->message, '\0', sizeof err->message) != NULL);
    FUZZ_REQUIRE(err->message[0] != '\0' && strchr(err->message, '\n') == NULL);
    if (why && why_size)
        snprintf(why, why_size, "%s", err->message);
    return rc;
}

#endif
