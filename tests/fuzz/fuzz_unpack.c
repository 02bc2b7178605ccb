/* tests/fuzz/fuzz_unpack.c — libFuzzer target for the unpacker (built only
 * with -DTESSERA_FUZZ=ON and clang; see tests/fuzz.cmake). Owns nothing: it
 * forwards each input to fuzz_unpack_one(), which the corpus replay test
 * also uses. Never filters inputs: rejecting them is the unpacker's job. */
#include "fuzz_unpack.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_unpack_one(data, size);
    return 0;
}
