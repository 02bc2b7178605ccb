/* tests/fuzz/fuzz_unpack.h — the one entry point shared by the libFuzzer
 * target (fuzz_unpack.c) and the corpus replay (replay.c), so both run an
 * input exactly the same way. Test code only; never part of libtessera. */
#ifndef TSR_TESTS_FUZZ_UNPACK_H
#define TSR_TESTS_FUZZ_UNPACK_H

#include <stddef.h>
#include <stdint.h>

/* Feeds `data` to one unpacker as a received stream: a sequence of wire
 * buffers, each as long as its header says (what is left after the last
 * whole buffer, or after a header that does not parse, goes in as one final
 * buffer). Decoded calls go into a table that reads every argument the
 * unpacker hands over, and every reply is read byte by byte, so a pointer
 * or length the unpacker got wrong shows up under ASan.
 * Returns 0 when every buffer decoded, else the first error code (TSR_E*).
 * Never crashes on any input: that is what is being tested. */
int fuzz_unpack_one(const uint8_t *data, size_t size);
/* The same, also copying the first error's message into `why` (may be
 * NULL) so tools can say why an input was rejected. */
int fuzz_unpack_explain(const uint8_t *data, size_t size, char *why, size_t why_size);

#endif
