/* netlib/frame.c — the 16-byte message header and the handshake payloads
 * (HELLO/WELCOME, CHALLENGE, PROOF; layouts in net.h). Owns: their
 * little-endian encoding and decoding.
 * Never: trusts a length it decodes without checking it against the
 * bytes actually present. */
#include <string.h>

#include "net_internal.h"
#include "tessera/dev/util.h"

void net_header_encode(uint8_t out[TSR_NET_HEADER_BYTES], uint16_t version, uint8_t type, uint8_t flags, uint64_t len)
{
    net_put_u32(out, TSR_NET_MAGIC);
    net_put_u16(out + 4, version);
    out[6] = type;
    out[7] = flags;
    net_put_u64(out + 8, len);
}

void net_header_decode(const uint8_t in[TSR_NET_HEADER_BYTES], net_header *out)
{
    out->magic = net_get_u32(in);
    out->version = net_get_u16(in + 4);
    out->type = in[6];
    out->flags = in[7];
    out->len = net_get_u64(in + 8);
}

size_t net_hello_encode(uint8_t *out, uint32_t credits, uint64_t max_message_bytes, const char *name,
                        const uint8_t *auth, uint8_t features)
{
    size_t name_len = strlen(name);
    if (name_len > TSR_NET_NAME_MAX)
        name_len = TSR_NET_NAME_MAX;
    size_t at = 0;
    net_put_u32(out + at, credits);
    at += 4;
    net_put_u64(out + at, max_message_bytes);
    at += 8;
    net_put_u16(out + at, (uint16_t)name_len);
    at += 2;
    memcpy(out + at, name, name_len);
    at += name_len;
    out[at++] = auth ? 1 : 0;
    if (auth) {
        memcpy(out + at, auth, NET_AUTH_BYTES);
        at += NET_AUTH_BYTES;
    }
    if (features) /* absent when nothing is asked for: the v2 handshake byte for byte */
        out[at++] = features;
    return at;
}

int net_hello_decode(const uint8_t *in, uint64_t len, net_hello *out, tsr_error *err)
{
    memset(out, 0, sizeof *out);
    if (len < 15)
        return tsr_error_set(err, TSR_EPROTO, "handshake payload of %llu bytes is too short", (unsigned long long)len);
    out->credits = net_get_u32(in);
    out->max_message_bytes = net_get_u64(in + 4);
    uint64_t at = 12;
    uint16_t name_len = net_get_u16(in + at);
    at += 2;
    if (name_len > TSR_NET_NAME_MAX || at + name_len + 1 > len)
        return tsr_error_set(err, TSR_EPROTO, "handshake node name length %u does not fit", name_len);
    /* The name appears in one-line messages, refusals included. */
    tsr_text_sanitize(out->name, sizeof out->name, in + at, name_len);
    at += name_len;
    uint8_t auth = in[at++];
    if (auth > 1)
        return tsr_error_set(err, TSR_EPROTO, "handshake authentication mode %u is unknown", auth);
    out->has_auth = auth == 1;
    uint64_t fields = at + (out->has_auth ? NET_AUTH_BYTES : 0);
    if (fields != len && fields + 1 != len)
        return tsr_error_set(err, TSR_EPROTO, "handshake payload of %llu bytes does not match its fields",
                             (unsigned long long)len);
    if (out->has_auth)
        memcpy(out->auth, in + at, NET_AUTH_BYTES);
    if (fields + 1 == len) {
        out->features = in[fields];
        if (out->features & ~NET_FEATURE_SHM)
            return tsr_error_set(err, TSR_EPROTO, "handshake features 0x%02x are unknown", out->features);
        if (!out->features)
            return tsr_error_set(err, TSR_EPROTO, "handshake features byte 0 (absent when nothing is asked)");
    }
    if (out->credits == 0)
        return tsr_error_set(err, TSR_EPROTO, "handshake grants 0 credits");
    return TSR_OK;
}

int net_auth_decode(const uint8_t *in, uint64_t len, uint8_t out[NET_AUTH_BYTES], const char *what, tsr_error *err)
{
    if (len != NET_AUTH_BYTES)
        return tsr_error_set(err, TSR_EPROTO, "%s of %llu bytes (not %d)", what, (unsigned long long)len,
                             NET_AUTH_BYTES);
    memcpy(out, in, NET_AUTH_BYTES);
    return TSR_OK;
}
