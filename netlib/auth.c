/* netlib/auth.c — the handshake's challenge-response: fresh nonces and
 * proofs of the shared token (wire layout in net.h, HANDSHAKE).
 * Owns: the only use of libsodium in netlib (sodium_init once per
 * process, randombytes_buf, HMAC-SHA256 and its constant-time compare).
 * Never: puts the token on the wire, writes its own cryptography, or
 * compares secrets with memcmp. */
#include <pthread.h>
#include <sodium.h>
#include <string.h>

#include "net_internal.h"

static pthread_once_t init_once = PTHREAD_ONCE_INIT;
static int init_result = -1;

static void init_sodium(void) { init_result = sodium_init(); }

int net_auth_init(tsr_error *err)
{
    pthread_once(&init_once, init_sodium);
    if (init_result < 0) /* 1 = already initialised by someone else: fine */
        return tsr_error_set(err, TSR_EIO, "net: libsodium failed to initialise (no random source?)");
    return TSR_OK;
}

void net_auth_nonce(uint8_t out[NET_AUTH_BYTES]) { randombytes_buf(out, NET_AUTH_BYTES); }

void net_auth_proof(const char *token, const char *role, const uint8_t client_nonce[NET_AUTH_BYTES],
                    const uint8_t server_nonce[NET_AUTH_BYTES], uint8_t out[NET_AUTH_BYTES])
{
    /* The label and role (with its terminator) keep a proof from being
     * valid for the other direction or for any other use of the token. */
    static const char label[] = "tessera-net-2 handshake proof ";
    crypto_auth_hmacsha256_state st;
    crypto_auth_hmacsha256_init(&st, (const unsigned char *)token, strlen(token));
    crypto_auth_hmacsha256_update(&st, (const unsigned char *)label, sizeof label - 1);
    crypto_auth_hmacsha256_update(&st, (const unsigned char *)role, strlen(role) + 1);
    crypto_auth_hmacsha256_update(&st, client_nonce, NET_AUTH_BYTES);
    crypto_auth_hmacsha256_update(&st, server_nonce, NET_AUTH_BYTES);
    crypto_auth_hmacsha256_final(&st, out);
    sodium_memzero(&st, sizeof st);
}

bool net_auth_equal(const uint8_t a[NET_AUTH_BYTES], const uint8_t b[NET_AUTH_BYTES])
{
    return crypto_verify_32(a, b) == 0;
}
