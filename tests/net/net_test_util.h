/* tests/net/net_test_util.h — helpers shared by the netlib tests: the
 * checks of tests/harness.h (stopping at the first failure), VmRSS from
 * /proc, clocks, and raw sockets that speak the wire format by hand (so
 * the tests hold netlib to its spec).
 * Never: hides a failure — every check failure exits 1 with a message. */
#ifndef TSR_NET_TEST_UTIL_H
#define TSR_NET_TEST_UTIL_H

#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/types.h>
#include <time.h>
#include <unistd.h>

#include <sodium.h>

#include "tessera/dev/net.h"

/* A failed check ends the program: the helpers below return nothing to
 * check, and later steps need the sockets and peers the earlier ones made. */
#define HARNESS_ON_FAIL exit(1)
#include "harness.h"

static inline int contains(const char *haystack, const char *needle) { return strstr(haystack, needle) != NULL; }

static inline uint64_t test_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000u + (uint64_t)ts.tv_nsec / 1000000u;
}

/* VmRSS of a process in KiB (pid 0 = this one), or -1. */
static inline long rss_kb(pid_t pid)
{
    char path[64], line[256];
    if (pid)
        snprintf(path, sizeof path, "/proc/%d/status", (int)pid);
    else
        snprintf(path, sizeof path, "/proc/self/status");
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    long kb = -1;
    while (fgets(line, sizeof line, f))
        if (!strncmp(line, "VmRSS:", 6)) {
            kb = strtol(line + 6, NULL, 10);
            break;
        }
    fclose(f);
    return kb;
}

/* Port of a "tcp://HOST:PORT" address text. */
static inline unsigned address_port(const char *address)
{
    const char *colon = strrchr(address, ':');
    return colon ? (unsigned)atoi(colon + 1) : 0;
}

static inline int raw_connect_loopback(unsigned port)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    CHECK(fd >= 0, "socket: %s", strerror(errno));
    struct sockaddr_in sa = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port)};
    sa.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    CHECK(connect(fd, (struct sockaddr *)&sa, sizeof sa) == 0, "connect to port %u: %s", port, strerror(errno));
    return fd;
}

static inline void raw_write_all(int fd, const void *data, size_t len)
{
    const uint8_t *p = data;
    while (len) {
        ssize_t n = send(fd, p, len, MSG_NOSIGNAL);
        CHECK(n > 0, "raw write: %s", strerror(errno));
        p += n;
        len -= (size_t)n;
    }
}

/* Reads exactly len bytes within timeout_ms. Returns 0, or -1 on end of
 * stream / error / time-out. */
static inline int raw_read_exact(int fd, void *data, size_t len, int timeout_ms)
{
    uint8_t *p = data;
    uint64_t end = test_now_ms() + (uint64_t)timeout_ms;
    while (len) {
        uint64_t now = test_now_ms();
        if (now >= end)
            return -1;
        struct pollfd pfd = {.fd = fd, .events = POLLIN};
        if (poll(&pfd, 1, (int)(end - now)) <= 0)
            return -1;
        ssize_t n = recv(fd, p, len, 0);
        if (n <= 0)
            return -1;
        p += n;
        len -= (size_t)n;
    }
    return 0;
}

static inline void put_le(uint8_t *p, uint64_t v, int bytes)
{
    for (int i = 0; i < bytes; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}
static inline uint64_t get_le(const uint8_t *p, int bytes)
{
    uint64_t v = 0;
    for (int i = bytes - 1; i >= 0; i--)
        v = v << 8 | p[i];
    return v;
}

/* A header written by hand from the layout documented in net.h. */
static inline void raw_header(uint8_t out[16], unsigned version, unsigned type, uint64_t len)
{
    put_le(out, 0x314E5354u, 4);
    put_le(out + 4, version, 2);
    out[6] = (uint8_t)type;
    out[7] = 0;
    put_le(out + 8, len, 8);
}

/* The handshake's proof, computed here from net.h's HANDSHAKE text with
 * libsodium directly (not netlib's code), so the tests hold netlib to it. */
static inline void spec_proof(const char *token, const char *role, const uint8_t nc[32], const uint8_t ns[32],
                              uint8_t out[32])
{
    static const char label[] = "tessera-net-2 handshake proof ";
    crypto_auth_hmacsha256_state st;
    crypto_auth_hmacsha256_init(&st, (const unsigned char *)token, strlen(token));
    crypto_auth_hmacsha256_update(&st, (const unsigned char *)label, sizeof label - 1);
    crypto_auth_hmacsha256_update(&st, (const unsigned char *)role, strlen(role) + 1);
    crypto_auth_hmacsha256_update(&st, nc, 32);
    crypto_auth_hmacsha256_update(&st, ns, 32);
    crypto_auth_hmacsha256_final(&st, out);
}

/* A HELLO frame (header included) written by hand: credits, max, name,
 * auth (0, or 1 followed by the 32-byte nonce). Returns its size. */
static inline size_t raw_hello(uint8_t *msg, const char *name, uint32_t credits, const uint8_t *nonce)
{
    size_t at = 16, nl = strlen(name);
    put_le(msg + at, credits, 4);
    at += 4;
    put_le(msg + at, 1u << 20, 8);
    at += 8;
    put_le(msg + at, nl, 2);
    at += 2;
    memcpy(msg + at, name, nl);
    at += nl;
    msg[at++] = nonce ? 1 : 0;
    if (nonce) {
        memcpy(msg + at, nonce, 32);
        at += 32;
    }
    raw_header(msg, TSR_NET_PROTOCOL_VERSION, 0x01, at - 16);
    return at;
}

/* Reads one message: its type, and its payload into buf (at most 4096
 * bytes; *len set). */
static inline int raw_read_msg(int fd, uint8_t *buf, size_t *len)
{
    uint8_t h[16];
    CHECK(raw_read_exact(fd, h, 16, 5000) == 0, "no message within 5 s");
    CHECK(get_le(h, 4) == 0x314E5354u, "magic 0x%08llx", (unsigned long long)get_le(h, 4));
    uint64_t n = get_le(h + 8, 8);
    CHECK(n <= 4096, "control message of %llu bytes", (unsigned long long)n);
    CHECK(raw_read_exact(fd, buf, (size_t)n, 5000) == 0, "payload of %llu bytes missing", (unsigned long long)n);
    *len = (size_t)n;
    return h[6];
}

/* Sends a HELLO (with a token: auth=1 and a fresh nonce, then the PROOF
 * the server's CHALLENGE asks for) and returns the type of the final
 * answer (2 WELCOME, 3 REFUSE). */
static inline int raw_handshake(int fd, const char *name, const char *token, uint32_t credits)
{
    uint8_t msg[16 + 512], nonce[32], buf[4096];
    randombytes_buf(nonce, sizeof nonce);
    size_t n = raw_hello(msg, name, credits, token ? nonce : NULL);
    raw_write_all(fd, msg, n);
    size_t len;
    int type = raw_read_msg(fd, buf, &len);
    if (type != 0x07)
        return type;
    CHECK(token && len == 32, "CHALLENGE of %zu bytes", len);
    uint8_t frame[16 + 32];
    raw_header(frame, TSR_NET_PROTOCOL_VERSION, 0x08, 32);
    spec_proof(token, "client", nonce, buf, frame + 16);
    raw_write_all(fd, frame, sizeof frame);
    return raw_read_msg(fd, buf, &len);
}

#endif
