/* netlib/frame.c — the 16-byte message header and the HELLO/WELCOME
 * payload (layouts in net.h). Owns: their little-endian encoding.
 * Never: trusts a length it decodes without checking it against the
 * bytes actually present. */
#include <string.h>

#include "net_internal.h"

void net_header_encode(uint8_t out[TSR_NET_HEADER_BYTES], uint16_t version, uint8_t type, uint64_t len)
{
    net_put_u32(out, TSR_NET_MAGIC);
    net_put_u16(out + 4, version);
    out[6] = type;
    out[7] = 0;
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

size_t net_hello_encode(uint8_t *out, uint32_t credits, uint64_t max_message_bytes, const char *name, const char *token)
{
    size_t name_len = strlen(name), token_len = token ? strlen(token) : 0;
    if (name_len > TSR_NET_NAME_MAX)
        name_len = TSR_NET_NAME_MAX;
    if (token_len > TSR_NET_TOKEN_MAX)
        token_len = TSR_NET_TOKEN_MAX;
    size_t at = 0;
    net_put_u32(out + at, credits);
    at += 4;
    net_put_u64(out + at, max_message_bytes);
    at += 8;
    net_put_u16(out + at, (uint16_t)name_len);
    at += 2;
    memcpy(out + at, name, name_len);
    at += name_len;
    net_put_u16(out + at, (uint16_t)token_len);
    at += 2;
    if (token_len)
        memcpy(out + at, token, token_len);
    return at + token_len;
}

int net_hello_decode(const uint8_t *in, uint64_t len, net_hello *out, tsr_error *err)
{
    memset(out, 0, sizeof *out);
    if (len < 16)
        return tsr_error_set(err, TSR_EPROTO, "handshake payload of %llu bytes is too short", (unsigned long long)len);
    out->credits = net_get_u32(in);
    out->max_message_bytes = net_get_u64(in + 4);
    uint64_t at = 12;
    uint16_t name_len = net_get_u16(in + at);
    at += 2;
    if (name_len > TSR_NET_NAME_MAX || at + name_len + 2 > len)
        return tsr_error_set(err, TSR_EPROTO, "handshake node name length %u does not fit", name_len);
    memcpy(out->name, in + at, name_len);
    at += name_len;
    for (size_t i = 0; i < name_len; i++) /* names appear in one-line messages */
        if ((unsigned char)out->name[i] < 0x20 || out->name[i] == 0x7f)
            out->name[i] = '?';
    uint16_t token_len = net_get_u16(in + at);
    at += 2;
    if (token_len > TSR_NET_TOKEN_MAX || at + token_len != len)
        return tsr_error_set(err, TSR_EPROTO, "handshake token length %u does not fit", token_len);
    memcpy(out->token, in + at, token_len);
    out->token_len = token_len;
    if (out->credits == 0)
        return tsr_error_set(err, TSR_EPROTO, "handshake grants 0 credits");
    return TSR_OK;
}
