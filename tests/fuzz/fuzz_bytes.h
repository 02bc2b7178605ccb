/* tests/fuzz/fuzz_bytes.h — a growing byte buffer for the seed writers that
 * record what the real packer flushes (fuzz_ext, fuzz_render). Owns its
 * bytes (free them with free()). Never prints. */
#ifndef TSR_FUZZ_BYTES_H
#define TSR_FUZZ_BYTES_H

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <tessera/error.h>

typedef struct fuzz_bytes {
    uint8_t *bytes;
    size_t len, cap;
} fuzz_bytes;

/* Appends size bytes; who names the program in the out-of-memory error. */
static inline int fuzz_bytes_append(fuzz_bytes *b, const uint8_t *buf, size_t size, const char *who, tsr_error *err)
{
    if (b->len + size > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (cap < b->len + size)
            cap *= 2;
        uint8_t *p = realloc(b->bytes, cap);
        if (!p)
            return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", who);
        b->bytes = p;
        b->cap = cap;
    }
    memcpy(b->bytes + b->len, buf, size);
    b->len += size;
    return 0;
}

#endif
