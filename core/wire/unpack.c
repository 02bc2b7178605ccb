/* core/wire/unpack.c — unpacker runtime: buffer header checks, output and reply
 * scratch, and the hand-written decoders of `custom` commands (client-array
 * draws, ShaderSource, GetTexImage; formats in tessera/dev/wire.h). The generated
 * decoder (unpack_gen.c) does the rest. Owns only the unpacker's scratch;
 * never reads outside the buffer, never dispatches an unchecked pointer. */
#include "tessera/dev/unpack.h"

#include <stdlib.h>
#include <string.h>

#include "tessera/dev/wire.h"
#include "wire_gen.h"
#include "wire_internal.h"

static int grow(uint8_t **buf, size_t *cap, size_t need)
{
    if (need <= *cap)
        return 0;
    size_t n = *cap ? *cap : 4096;
    while (n < need) {
        if (n > SIZE_MAX / 2)
            return -1;
        n *= 2;
    }
    uint8_t *p = realloc(*buf, n);
    if (!p)
        return -1;
    *buf = p;
    *cap = n;
    return 0;
}

tsr_unpacker *tsr_unpacker_create(const tsr_dispatch *target, tsr_reply_fn reply, void *reply_ctx, tsr_error *err)
{
    tsr_unpacker *u = calloc(1, sizeof *u);
    if (!u) {
        tsr_error_set(err, TSR_ENOMEM, "unpacker: out of memory");
        return NULL;
    }
    u->target = target;
    u->reply = reply;
    u->reply_ctx = reply_ctx;
    u->max_output = TSR_UNPACK_MAX_OUTPUT;
    tsr_pixel_store_init(&u->pixels);
    return u;
}

void tsr_unpacker_destroy(tsr_unpacker *u)
{
    if (!u)
        return;
    free(u->aligned);
    free(u->out);
    free(u->rbuf);
    free(u->ptrs);
    free(u);
}

size_t tsr_wire_buffer_size(const void *buf, size_t size, tsr_error *err)
{
    const uint8_t *b = buf;
    if (size < TSR_WIRE_HEADER_SIZE) {
        tsr_error_set(err, TSR_EPROTO, "wire buffer of %zu bytes is shorter than its %u-byte header", size,
                      TSR_WIRE_HEADER_SIZE);
        return 0;
    }
    uint32_t magic = tsr_wire_get_u32(b);
    if (magic != TSR_WIRE_MAGIC) {
        tsr_error_set(err, TSR_EPROTO, "wire buffer has bad magic 0x%08x (expected 0x%08x)", magic, TSR_WIRE_MAGIC);
        return 0;
    }
    uint64_t nops = tsr_wire_get_u32(b + 4);
    uint64_t len = tsr_wire_get_u64(b + 8);
    uint64_t total = TSR_WIRE_HEADER_SIZE + tsr_wire_align8(nops);
    if (len > SIZE_MAX - total) {
        tsr_error_set(err, TSR_EPROTO, "wire buffer header claims %llu data bytes", (unsigned long long)len);
        return 0;
    }
    return (size_t)(total + len);
}

int tsr_unpacker_run(tsr_unpacker *u, const void *buf, size_t size, tsr_error *err)
{
    tsr_error local;
    if (!err)
        err = &local;
    tsr_error_clear(err);
    size_t total = tsr_wire_buffer_size(buf, size, err);
    if (!total)
        return err->code;
    if (total != size)
        return tsr_error_set(err, TSR_EPROTO, "wire buffer header describes %zu bytes, %zu received", total, size);
    const uint8_t *b = buf;
    if ((uintptr_t)b & 7u) {
        /* Fields are read in place (fixed-count pointers are handed to the
         * target), so the data must be 8-aligned as it was when packed. */
        if (grow(&u->aligned, &u->aligned_cap, size) != 0)
            return tsr_error_set(err, TSR_ENOMEM, "unpacker: out of memory copying a %zu-byte buffer", size);
        memcpy(u->aligned, b, size);
        b = u->aligned;
    }
    uint32_t nops = tsr_wire_get_u32(b + 4);
    uint64_t len = tsr_wire_get_u64(b + 8);
    const uint8_t *data = b + TSR_WIRE_HEADER_SIZE + tsr_wire_align8(nops);
    u->buffers++;
    u->commands += nops;
    u->yield = 0;
    u->resume_command = 0;
    u->resume_pos = 0;
    u->paused_data = data;
    u->paused_nops = nops;
    u->paused_len = (size_t)len;
    return tsr_unpacker_resume(u, err);
}

int tsr_unpacker_resume(tsr_unpacker *u, tsr_error *err)
{
    tsr_error local;
    if (!err)
        err = &local;
    if (!u->paused_data)
        return tsr_error_set(err, TSR_ESTATE, "unpacker: no paused buffer to resume");
    int rc = tsr_unpack_commands(u, u->target, u->paused_data, u->paused_nops, u->paused_len, err);
    if (rc != TSR_UNPACK_YIELDED) {
        /* Finished or failed: nothing left to resume. */
        u->paused_data = NULL;
        u->resume_command = 0;
        u->resume_pos = 0;
    }
    return rc;
}

int tsr_unpacker_outputs(tsr_unpacker *u, int n, const uint64_t *sizes, uint8_t **ptrs)
{
    uint64_t total = 0;
    for (int i = 0; i < n; i++) {
        if (sizes[i] > u->max_output || total > u->max_output)
            return -1;
        total += tsr_wire_align8(sizes[i]);
    }
    if (total > u->max_output)
        return -1;
    if (grow(&u->out, &u->out_cap, (size_t)total + 8) != 0)
        return -1;
    memset(u->out, 0, (size_t)total + 8);
    size_t pos = 0;
    for (int i = 0; i < n; i++) {
        ptrs[i] = u->out + pos;
        pos += (size_t)tsr_wire_align8(sizes[i]);
    }
    return 0;
}

static int put_item(tsr_unpacker *u, size_t *pos, const void *bytes, uint64_t len)
{
    size_t need = *pos + 8 + (size_t)tsr_wire_align8(len);
    if (grow(&u->rbuf, &u->rcap, need) != 0)
        return -1;
    tsr_wire_put_u64(u->rbuf + *pos, len);
    if (len)
        memcpy(u->rbuf + *pos + 8, bytes, (size_t)len);
    memset(u->rbuf + *pos + 8 + len, 0, (size_t)(tsr_wire_align8(len) - len));
    *pos = need;
    return 0;
}

int tsr_unpacker_reply(tsr_unpacker *u, uint32_t id, const void *ret, uint64_t ret_len, int n, const uint64_t *sizes,
                       uint8_t *const *ptrs, tsr_error *err)
{
    if (!u->reply)
        return 0;
    size_t pos = 0;
    if (ret_len != TSR_WIRE_NULL && put_item(u, &pos, ret, ret_len) != 0)
        return tsr_error_set(err, TSR_ENOMEM, "unpacker: out of memory building reply %u", id);
    for (int i = 0; i < n; i++)
        if (put_item(u, &pos, ptrs[i], sizes[i]) != 0)
            return tsr_error_set(err, TSR_ENOMEM, "unpacker: out of memory building reply %u", id);
    return u->reply(u->reply_ctx, id, u->rbuf, pos, err);
}

/* --- client-array draws ---------------------------------------------------- */

#define MAX_ARRAYS 64

typedef struct array_rec {
    uint32_t kind, index, type, normalized, buffer;
    int32_t size, stride;
    uint64_t offset, dlen, elem;
    const uint8_t *data;
} array_rec;

typedef struct arrays_hdr {
    uint32_t array_buffer, element_buffer, active_texture, count;
    array_rec rec[MAX_ARRAYS];
} arrays_hdr;

static uint64_t elem_size(const array_rec *r)
{
    uint64_t ts = tsr_gl_type_size(r->type);
    if (r->kind == TSR_WIRE_ARRAY_NORMAL)
        return 3 * ts;
    if (r->kind == TSR_WIRE_ARRAY_EDGE_FLAG)
        return 1;
    if (r->size == GL_BGRA)
        return 4 * ts;
    return (uint64_t)r->size * ts;
}

#define BAD(...) return tsr_error_set(err, TSR_EPROTO, __VA_ARGS__)

/* Parses the ARRAYS block [p, p+plen) of `cmd` (data offset `at`). */
static int parse_arrays(const uint8_t *p, uint64_t plen, arrays_hdr *h, const char *cmd, size_t at, tsr_error *err)
{
    if (plen < 16)
        BAD("command %s at data offset %zu: array block of %llu bytes is truncated", cmd, at, (unsigned long long)plen);
    h->array_buffer = tsr_wire_get_u32(p);
    h->element_buffer = tsr_wire_get_u32(p + 4);
    h->active_texture = tsr_wire_get_u32(p + 8);
    h->count = tsr_wire_get_u32(p + 12);
    if (h->count > MAX_ARRAYS)
        BAD("command %s at data offset %zu: %u arrays (at most %d)", cmd, at, h->count, MAX_ARRAYS);
    if (h->active_texture >= 32)
        BAD("command %s at data offset %zu: client texture unit %u out of range", cmd, at, h->active_texture);
    uint64_t q = 16;
    for (uint32_t i = 0; i < h->count; i++) {
        array_rec *r = &h->rec[i];
        if (plen - q < 48)
            BAD("command %s at data offset %zu: array record %u is truncated", cmd, at, i);
        const uint8_t *a = p + q;
        r->kind = tsr_wire_get_u32(a);
        r->index = tsr_wire_get_u32(a + 4);
        r->size = (int32_t)tsr_wire_get_u32(a + 8);
        r->type = tsr_wire_get_u32(a + 12);
        r->stride = (int32_t)tsr_wire_get_u32(a + 16);
        r->normalized = tsr_wire_get_u32(a + 20);
        r->buffer = tsr_wire_get_u32(a + 24);
        r->offset = tsr_wire_get_u64(a + 32);
        r->dlen = tsr_wire_get_u64(a + 40);
        q += 48;
        if (r->kind < TSR_WIRE_ARRAY_VERTEX || r->kind > TSR_WIRE_ARRAY_ATTRIB)
            BAD("command %s at data offset %zu: array record %u has unknown kind %u", cmd, at, i, r->kind);
        if ((r->kind == TSR_WIRE_ARRAY_TEXCOORD && r->index >= 32) ||
            (r->kind == TSR_WIRE_ARRAY_ATTRIB && r->index >= 64))
            BAD("command %s at data offset %zu: array record %u has index %u out of range", cmd, at, i, r->index);
        if (!((r->size >= 1 && r->size <= 4) || r->size == GL_BGRA))
            BAD("command %s at data offset %zu: array record %u has size %d", cmd, at, i, r->size);
        if (r->stride < 0)
            BAD("command %s at data offset %zu: array record %u has negative stride %d", cmd, at, i, r->stride);
        r->elem = elem_size(r);
        if (!r->elem)
            BAD("command %s at data offset %zu: array record %u has unknown type 0x%x", cmd, at, i, r->type);
        if (r->buffer) {
            if (r->dlen)
                BAD("command %s at data offset %zu: array record %u in buffer %u carries data", cmd, at, i, r->buffer);
            r->data = NULL;
            continue;
        }
        if (r->dlen > plen - q)
            BAD("command %s at data offset %zu: array record %u length %llu beyond the buffer", cmd, at, i,
                (unsigned long long)r->dlen);
        if (r->dlen % r->elem)
            BAD("command %s at data offset %zu: array record %u length %llu is not a multiple of %llu", cmd, at, i,
                (unsigned long long)r->dlen, (unsigned long long)r->elem);
        uint64_t skip;
        if (__builtin_mul_overflow(r->offset, r->elem, &skip) || skip > UINTPTR_MAX / 2)
            BAD("command %s at data offset %zu: array record %u first index %llu overflows", cmd, at, i,
                (unsigned long long)r->offset);
        r->data = p + q;
        q += r->dlen;
        q = tsr_wire_align8(q);
        if (q > plen)
            q = plen;
    }
    return 0;
}

/* True when every index in [lo, hi] lies inside every inline array. */
static int range_covered(const arrays_hdr *h, uint64_t lo, uint64_t hi)
{
    for (uint32_t i = 0; i < h->count; i++) {
        const array_rec *r = &h->rec[i];
        if (r->buffer)
            continue;
        uint64_t n = r->dlen / r->elem;
        if (lo < r->offset || hi - r->offset >= n)
            return 0;
    }
    return 1;
}

static GLenum array_cap(uint32_t kind)
{
    switch (kind) {
    case TSR_WIRE_ARRAY_VERTEX: return GL_VERTEX_ARRAY;
    case TSR_WIRE_ARRAY_NORMAL: return GL_NORMAL_ARRAY;
    case TSR_WIRE_ARRAY_COLOR: return GL_COLOR_ARRAY;
    case TSR_WIRE_ARRAY_EDGE_FLAG: return GL_EDGE_FLAG_ARRAY;
    default: return GL_TEXTURE_COORD_ARRAY;
    }
}

static void set_arrays(const tsr_dispatch *d, const arrays_hdr *h)
{
    for (uint32_t i = 0; i < h->count; i++) {
        const array_rec *r = &h->rec[i];
        /* Inline data: the pointer addresses element `offset` at the first
         * byte sent (integer arithmetic: it may point before the data). */
        const void *ptr = r->buffer ? (const void *)(uintptr_t)r->offset
                                    : (const void *)((uintptr_t)r->data - (uintptr_t)(r->offset * r->elem));
        GLsizei stride = r->buffer ? r->stride : 0;
        tsr_call_BindBuffer(d, GL_ARRAY_BUFFER, r->buffer);
        switch (r->kind) {
        case TSR_WIRE_ARRAY_VERTEX: tsr_call_VertexPointer(d, r->size, r->type, stride, ptr); break;
        case TSR_WIRE_ARRAY_NORMAL: tsr_call_NormalPointer(d, r->type, stride, ptr); break;
        case TSR_WIRE_ARRAY_COLOR: tsr_call_ColorPointer(d, r->size, r->type, stride, ptr); break;
        case TSR_WIRE_ARRAY_EDGE_FLAG: tsr_call_EdgeFlagPointer(d, stride, ptr); break;
        case TSR_WIRE_ARRAY_TEXCOORD:
            tsr_call_ClientActiveTexture(d, GL_TEXTURE0 + r->index);
            tsr_call_TexCoordPointer(d, r->size, r->type, stride, ptr);
            break;
        case TSR_WIRE_ARRAY_ATTRIB:
            tsr_call_VertexAttribPointer(d, r->index, r->size, r->type, (GLboolean)(r->normalized != 0), stride, ptr);
            tsr_call_EnableVertexAttribArray(d, r->index);
            continue;
        }
        tsr_call_EnableClientState(d, array_cap(r->kind));
    }
}

static void restore_arrays(const tsr_dispatch *d, const arrays_hdr *h)
{
    int had_texcoord = 0;
    for (uint32_t i = 0; i < h->count; i++) {
        const array_rec *r = &h->rec[i];
        if (r->kind == TSR_WIRE_ARRAY_ATTRIB) {
            tsr_call_DisableVertexAttribArray(d, r->index);
            continue;
        }
        if (r->kind == TSR_WIRE_ARRAY_TEXCOORD) {
            tsr_call_ClientActiveTexture(d, GL_TEXTURE0 + r->index);
            had_texcoord = 1;
        }
        tsr_call_DisableClientState(d, array_cap(r->kind));
    }
    if (had_texcoord)
        tsr_call_ClientActiveTexture(d, GL_TEXTURE0 + h->active_texture);
    if (h->count)
        tsr_call_BindBuffer(d, GL_ARRAY_BUFFER, h->array_buffer);
}

/* Reads "u64 P, P bytes" at *q; returns the block or NULL (err set). */
static const uint8_t *read_block(const uint8_t *b, size_t len, size_t *q, uint64_t *plen, const char *cmd, size_t at,
                                 tsr_error *err)
{
    *q = (size_t)tsr_wire_align8(*q);
    if (*q > len || len - *q < 8) {
        tsr_error_set(err, TSR_EPROTO, "command %s at data offset %zu: truncated before a block length", cmd, at);
        return NULL;
    }
    *plen = tsr_wire_get_u64(b + *q);
    *q += 8;
    if (*plen > len - *q) {
        tsr_error_set(err, TSR_EPROTO, "command %s at data offset %zu: block length %llu beyond the buffer", cmd, at,
                      (unsigned long long)*plen);
        return NULL;
    }
    const uint8_t *p = b + *q;
    *q += (size_t)*plen;
    return p;
}

int tsr_unpack_custom_DrawArrays(tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len, size_t *pos,
                                 tsr_error *err)
{
    (void)u;
    size_t at = (size_t)tsr_wire_align8(*pos);
    if (at > len || len - at < 16)
        BAD("command DrawArrays at data offset %zu: truncated", *pos);
    GLenum mode = tsr_wire_get_u32(b + at);
    GLint first = (GLint)tsr_wire_get_u32(b + at + 4);
    GLsizei count = (GLsizei)tsr_wire_get_u32(b + at + 8);
    if (first < 0 || count < 0)
        BAD("command DrawArrays at data offset %zu: negative first %d or count %d", at, first, count);
    size_t q = at + 16;
    uint64_t plen;
    const uint8_t *p = read_block(b, len, &q, &plen, "DrawArrays", at, err);
    if (!p)
        return err->code;
    arrays_hdr h;
    if (parse_arrays(p, plen, &h, "DrawArrays", at, err) != 0)
        return err->code;
    if (count > 0 && !range_covered(&h, (uint64_t)first, (uint64_t)first + (uint64_t)count - 1))
        BAD("command DrawArrays at data offset %zu: vertices %d..%d lie outside the arrays sent", at, first,
            first + count - 1);
    set_arrays(d, &h);
    tsr_call_DrawArrays(d, mode, first, count);
    restore_arrays(d, &h);
    *pos = q;
    return 0;
}

int tsr_unpack_custom_DrawElements(tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len, size_t *pos,
                                   tsr_error *err)
{
    (void)u;
    size_t at = (size_t)tsr_wire_align8(*pos);
    if (at > len || len - at < 24)
        BAD("command DrawElements at data offset %zu: truncated", *pos);
    GLenum mode = tsr_wire_get_u32(b + at);
    GLsizei count = (GLsizei)tsr_wire_get_u32(b + at + 4);
    GLenum type = tsr_wire_get_u32(b + at + 8);
    GLuint index_buffer = tsr_wire_get_u32(b + at + 12);
    uint64_t index_offset = tsr_wire_get_u64(b + at + 16);
    if (count < 0)
        BAD("command DrawElements at data offset %zu: negative count %d", at, count);
    size_t isize = type == GL_UNSIGNED_BYTE ? 1 : type == GL_UNSIGNED_SHORT ? 2 : type == GL_UNSIGNED_INT ? 4 : 0;
    if (!isize)
        BAD("command DrawElements at data offset %zu: index type 0x%x", at, type);
    size_t q = at + 24;
    uint64_t ilen;
    const uint8_t *indices = read_block(b, len, &q, &ilen, "DrawElements", at, err);
    if (!indices)
        return err->code;
    if (index_buffer ? ilen != 0 : ilen != (uint64_t)count * isize)
        BAD("command DrawElements at data offset %zu: %llu index bytes for %d indices", at, (unsigned long long)ilen,
            count);
    uint64_t plen;
    const uint8_t *p = read_block(b, len, &q, &plen, "DrawElements", at, err);
    if (!p)
        return err->code;
    arrays_hdr h;
    if (parse_arrays(p, plen, &h, "DrawElements", at, err) != 0)
        return err->code;
    int inline_arrays = 0;
    for (uint32_t i = 0; i < h.count; i++)
        inline_arrays |= h.rec[i].buffer == 0;
    if (inline_arrays && count > 0) {
        if (index_buffer)
            BAD("command DrawElements at data offset %zu: inline arrays with indices in buffer %u", at, index_buffer);
        /* Every index must address data that was sent. */
        uint64_t lo = UINT64_MAX, hi = 0;
        for (GLsizei i = 0; i < count; i++) {
            uint64_t v = isize == 1   ? indices[i]
                         : isize == 2 ? tsr_wire_get_u16(indices + 2 * i)
                                      : tsr_wire_get_u32(indices + 4 * i);
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
        if (!range_covered(&h, lo, hi))
            BAD("command DrawElements at data offset %zu: indices %llu..%llu lie outside the arrays sent", at,
                (unsigned long long)lo, (unsigned long long)hi);
    }
    set_arrays(d, &h);
    tsr_call_BindBuffer(d, GL_ELEMENT_ARRAY_BUFFER, index_buffer);
    tsr_call_DrawElements(d, mode, count, type,
                          index_buffer ? (const void *)(uintptr_t)index_offset : (const void *)indices);
    restore_arrays(d, &h);
    tsr_call_BindBuffer(d, GL_ELEMENT_ARRAY_BUFFER, h.element_buffer);
    *pos = q;
    return 0;
}

int tsr_unpack_custom_ShaderSource(tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len, size_t *pos,
                                   tsr_error *err)
{
    size_t at = (size_t)tsr_wire_align8(*pos);
    if (at > len || len - at < 8)
        BAD("command ShaderSource at data offset %zu: truncated", *pos);
    GLuint shader = tsr_wire_get_u32(b + at);
    GLsizei count = (GLsizei)tsr_wire_get_u32(b + at + 4);
    if (count < 0)
        BAD("command ShaderSource at data offset %zu: negative count %d", at, count);
    size_t q = at + 8;
    uint64_t plen = 0;
    const uint8_t *p = NULL;
    int null_strings = len - q >= 8 && tsr_wire_get_u64(b + q) == TSR_WIRE_NULL;
    if (null_strings) {
        if (count)
            BAD("command ShaderSource at data offset %zu: NULL strings for count %d", at, count);
        q += 8;
    } else if (!(p = read_block(b, len, &q, &plen, "ShaderSource", at, err))) {
        return err->code;
    }
    if ((uint64_t)count > plen / 8)
        BAD("command ShaderSource at data offset %zu: %d strings cannot fit %llu bytes", at, count,
            (unsigned long long)plen);
    uint64_t llen;
    q = (size_t)tsr_wire_align8(q);
    if (q > len || len - q < 8)
        BAD("command ShaderSource at data offset %zu: truncated before the length array", at);
    llen = tsr_wire_get_u64(b + q);
    q += 8;
    const GLint *length = NULL;
    if (llen != TSR_WIRE_NULL) {
        if (llen > len - q || llen != (uint64_t)count * 4)
            BAD("command ShaderSource at data offset %zu: length array of %llu bytes for %d strings", at,
                (unsigned long long)llen, count);
        length = (const GLint *)(b + q);
        q += (size_t)llen;
    }
    /* Copy each string with a NUL after it: with a NULL (or negative)
     * length GL reads up to the NUL, otherwise exactly length[i] bytes. */
    uint64_t sizes[2] = {(uint64_t)count * sizeof(char *), plen + (uint64_t)count};
    uint8_t *ptrs[2];
    if (tsr_unpacker_outputs(u, 2, sizes, ptrs) != 0)
        BAD("command ShaderSource at data offset %zu: %llu bytes of source are too large", at,
            (unsigned long long)plen);
    const GLchar **strings = (const GLchar **)(void *)ptrs[0];
    char *text = (char *)ptrs[1];
    uint64_t sq = 0;
    for (GLsizei i = 0; i < count; i++) {
        sq = tsr_wire_align8(sq);
        if (sq > plen || plen - sq < 8)
            BAD("command ShaderSource at data offset %zu: string %d is truncated", at, i);
        uint64_t s = tsr_wire_get_u64(p + sq);
        sq += 8;
        if (s > plen - sq)
            BAD("command ShaderSource at data offset %zu: string %d length %llu beyond the block", at, i,
                (unsigned long long)s);
        GLint li;
        if (length && (memcpy(&li, length + i, 4), li >= 0) && (uint64_t)li != s)
            BAD("command ShaderSource at data offset %zu: string %d has %llu bytes, length says %d", at, i,
                (unsigned long long)s, li);
        memcpy(text, p + sq, (size_t)s);
        text[s] = '\0';
        strings[i] = text;
        text += s + 1;
        sq += s;
    }
    tsr_call_ShaderSource(d, shader, count, null_strings ? NULL : strings, length);
    *pos = q;
    return 0;
}

int tsr_unpack_custom_GetTexImage(tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len, size_t *pos,
                                  tsr_error *err)
{
    size_t at = (size_t)tsr_wire_align8(*pos);
    if (at > len || len - at < 24)
        BAD("command GetTexImage at data offset %zu: truncated", *pos);
    GLenum target = tsr_wire_get_u32(b + at);
    GLint level = (GLint)tsr_wire_get_u32(b + at + 4);
    GLenum format = tsr_wire_get_u32(b + at + 8);
    GLenum type = tsr_wire_get_u32(b + at + 12);
    uint32_t id = tsr_wire_get_u32(b + at + 16);
    GLint whd[3] = {0, 0, 0};
    tsr_call_GetTexLevelParameteriv(d, target, level, GL_TEXTURE_WIDTH, &whd[0]);
    tsr_call_GetTexLevelParameteriv(d, target, level, GL_TEXTURE_HEIGHT, &whd[1]);
    tsr_call_GetTexLevelParameteriv(d, target, level, GL_TEXTURE_DEPTH, &whd[2]);
    tsr_pixel_layout lay;
    int dims = target == GL_TEXTURE_3D ? 3 : 2;
    if (tsr_pixel_layout_of(&u->pixels.pack, dims, whd[0], whd[1], whd[2], format, type, &lay) != 0)
        memset(&lay, 0, sizeof lay); /* GL raises the error itself and writes nothing */
    uint64_t sizes[1] = {lay.extent};
    uint8_t *ptrs[1];
    if (tsr_unpacker_outputs(u, 1, sizes, ptrs) != 0)
        BAD("command GetTexImage at data offset %zu: image of %llu bytes is too large", at,
            (unsigned long long)lay.extent);
    tsr_call_GetTexImage(d, target, level, format, type, ptrs[0]);
    *pos = at + 24;
    if (!u->reply)
        return 0;
    /* Item 0: the level's size; item 1: the image. Built by hand because
     * the generic builder handles one return value. */
    uint64_t s2[2] = {12, lay.extent};
    uint8_t *p2[2] = {(uint8_t *)whd, ptrs[0]};
    return tsr_unpacker_reply(u, id, NULL, TSR_WIRE_NULL, 2, s2, p2, err);
}

/* --- fuzzing ---------------------------------------------------------------- */

int tsr_unpack_fuzz_one(const uint8_t *data, size_t size)
{
    tsr_dispatch *nop = malloc(sizeof *nop);
    if (!nop)
        return TSR_ENOMEM;
    tsr_dispatch_fill_nop(nop);
    tsr_error err;
    tsr_unpacker *u = tsr_unpacker_create(nop, NULL, NULL, &err);
    int rc = u ? tsr_unpacker_run(u, data, size, &err) : TSR_ENOMEM;
    tsr_unpacker_destroy(u);
    free(nop);
    return rc;
}
