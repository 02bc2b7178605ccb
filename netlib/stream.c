/* netlib/stream.c — streaming N bytes through a connection, for tests and
 * benchmarks: a deterministic byte pattern, FNV-1a, send and verify loops.
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

int tsr_net_stream_send(tsr_net_conn *conn, unsigned kind, uint64_t total_bytes, size_t message_bytes, int timeout_ms,
                        tsr_error *err)
{
    if (message_bytes == 0)
        return tsr_error_set(err, TSR_EINVAL, "net: stream message size must be above 0");
    for (uint64_t at = 0; at < total_bytes;) {
        size_t n = total_bytes - at < message_bytes ? (size_t)(total_bytes - at) : message_bytes;
        uint8_t *buf = malloc(n);
        if (!buf)
            return tsr_error_set(err, TSR_ENOMEM, "net: out of memory for a %zu-byte message", n);
        tsr_net_pattern_fill(buf, at, n, 0);
        int rc = tsr_net_send_owned(conn, kind, buf, n, NULL, NULL, timeout_ms, err);
        if (rc) {
            free(buf);
            return rc;
        }
        at += n;
    }
    return TSR_OK;
}

int tsr_net_stream_recv(tsr_net_conn *conn, uint64_t total_bytes, int timeout_ms, tsr_error *err)
{
    enum { CHUNK = 65536 };
    uint8_t *expect = malloc(CHUNK);
    if (!expect)
        return tsr_error_set(err, TSR_ENOMEM, "net: out of memory");
    int rc = TSR_OK;
    for (uint64_t at = 0; at < total_bytes && rc == TSR_OK;) {
        tsr_net_msg msg;
        int got = tsr_net_recv(conn, &msg, timeout_ms, err);
        if (got <= 0) {
            rc = got < 0 ? got
                         : tsr_error_set(err, TSR_EIO, "net: stream from %s ended after %llu of %llu bytes",
                                         tsr_net_conn_address(conn), (unsigned long long)at,
                                         (unsigned long long)total_bytes);
            break;
        }
        if (msg.len > total_bytes - at)
            rc = tsr_error_set(err, TSR_EPROTO, "net: stream from %s is longer than %llu bytes",
                               tsr_net_conn_address(conn), (unsigned long long)total_bytes);
        for (uint64_t done = 0; rc == TSR_OK && done < msg.len;) {
            size_t n = msg.len - done < CHUNK ? (size_t)(msg.len - done) : CHUNK;
            tsr_net_pattern_fill(expect, at + done, n, 0);
            if (memcmp(expect, (uint8_t *)msg.data + done, n)) {
                size_t i = 0;
                while (expect[i] == ((uint8_t *)msg.data)[done + i])
                    i++;
                rc = tsr_error_set(err, TSR_EPROTO, "net: stream from %s differs at byte %llu",
                                   tsr_net_conn_address(conn), (unsigned long long)(at + done + i));
            }
            done += n;
        }
        at += msg.len;
        tsr_net_msg_release(&msg);
    }
    free(expect);
    return rc;
}
