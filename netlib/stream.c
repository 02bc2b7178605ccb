/* netlib/stream.c — for tests and benchmarks that stream N bytes through a
 * connection: a deterministic byte pattern and FNV-1a to verify it.
 * Owns: the pattern's definition (word k of seed s is splitmix64(k ^ s),
 * little-endian). Never: keeps state between calls. */
#include <stdlib.h>
#include <string.h>

#include "net_internal.h"

static uint64_t splitmix64(uint64_t x)
{
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

void tsr_net_pattern_fill(void *dst, uint64_t offset, size_t len, uint64_t seed)
{
    uint8_t *d = dst;
    while (len) {
        uint64_t word = splitmix64((offset >> 3) ^ seed);
        unsigned byte = (unsigned)(offset & 7);
        if (byte == 0 && len >= 8) {
            net_put_u64(d, word);
            d += 8;
            offset += 8;
            len -= 8;
        } else {
            *d++ = (uint8_t)(word >> (8 * byte));
            offset++;
            len--;
        }
    }
}

uint64_t tsr_net_fnv1a(uint64_t hash, const void *data, size_t len)
{
    const uint8_t *p = data;
    for (size_t i = 0; i < len; i++) {
        hash ^= p[i];
        hash *= 0x100000001b3ull;
    }
    return hash;
}
