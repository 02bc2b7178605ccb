/* tests/composite/fuzz_composite_message.h — the fuzz entry point for image
 * messages (tessera/dev/composite.h), shared by the libFuzzer target
 * (fuzz_composite_message) and the corpus replay in composite_test. */
#ifndef TSR_TESTS_FUZZ_COMPOSITE_MESSAGE_H
#define TSR_TESTS_FUZZ_COMPOSITE_MESSAGE_H

#include <stddef.h>
#include <stdint.h>

/* Decodes one message; a decoded image is then split, merged with a blank
 * image, assembled and re-encoded with every codec (each within its
 * advertised worst case). Returns 0 when the message decoded, 1 when it
 * was rejected; aborts when a decoded image breaks an invariant. */
int fuzz_composite_message_one(const uint8_t *data, size_t size);

#endif
