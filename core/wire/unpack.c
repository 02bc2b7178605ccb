/* core/wire/unpack.c — unpacker runtime: buffer header checks, output and reply
 * scratch, and the hand-written decoders of `custom` commands (client-array
 * draws, ShaderSource, GetTexImage; formats in tessera/dev/wire.h). The generated
 * decoder (unpack_gen.c) does the rest. Owns only the unpacker's scratch;
 * never reads outside the buffer, never dispatches an unchecked pointer. */
#include "tessera/dev/unpack.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/glext.h>

#include "tessera/dev/wire.h"
#include "wire_gen.h"
#include "wire_internal.h"

/* The unpacker decoding on this thread now, for tsr_unpacker_refuse: a
 * thread decodes one stream at a time (nested replays save and restore). */
static _Thread_local tsr_unpacker *decoding;

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

/* --- buffer objects (limits on) ------------------------------------------- */

/* What a budgeted stream's buffer objects are: name -> size in bytes, an
 * open-addressing table (name 0 marks a free slot: GL never names a
 * buffer 0), and the names bound to the targets BufferData can size. */
enum { BOUND_ARRAY, BOUND_ELEMENT, BOUND_PACK, BOUND_UNPACK, BOUND_TARGETS };

typedef struct buffer_slot {
    uint32_t name; /* 0: free */
    uint32_t dead; /* deleted (a tombstone) */
    uint64_t size;
} buffer_slot;

struct tsr_unpack_buffers {
    buffer_slot *slots;
    size_t cap, used; /* used counts tombstones too */
    uint64_t total;   /* bytes of every live buffer */
    uint32_t bound[BOUND_TARGETS];
};

static void buffers_free(struct tsr_unpack_buffers *b)
{
    if (b)
        free(b->slots);
    free(b);
}

static int bound_index(GLenum target)
{
    switch (target) {
    case GL_ARRAY_BUFFER: return BOUND_ARRAY;
    case GL_ELEMENT_ARRAY_BUFFER: return BOUND_ELEMENT;
    case GL_PIXEL_PACK_BUFFER: return BOUND_PACK;
    case GL_PIXEL_UNPACK_BUFFER: return BOUND_UNPACK;
    default: return -1;
    }
}

static size_t slot_hash(uint32_t name, size_t cap) { return (size_t)(name * 2654435761u) & (cap - 1); }

/* The live slot of `name`, or NULL. */
static buffer_slot *buffer_find(const struct tsr_unpack_buffers *b, uint32_t name)
{
    if (!name || !b->cap)
        return NULL;
    for (size_t i = slot_hash(name, b->cap), n = 0; n < b->cap; i = (i + 1) & (b->cap - 1), n++) {
        buffer_slot *s = &b->slots[i];
        if (!s->name)
            return NULL;
        if (s->name == name && !s->dead)
            return s;
    }
    return NULL;
}

/* The slot for `name`, made when missing; NULL when out of memory. */
static buffer_slot *buffer_slot_for(struct tsr_unpack_buffers *b, uint32_t name)
{
    buffer_slot *s = buffer_find(b, name);
    if (s)
        return s;
    if ((b->used + 1) * 2 > b->cap) {
        size_t cap = b->cap ? b->cap * 2 : 64;
        buffer_slot *slots = calloc(cap, sizeof *slots);
        if (!slots)
            return NULL;
        size_t used = 0;
        for (size_t i = 0; i < b->cap; i++) {
            buffer_slot *o = &b->slots[i];
            if (!o->name || o->dead)
                continue;
            size_t j = slot_hash(o->name, cap);
            while (slots[j].name)
                j = (j + 1) & (cap - 1);
            slots[j] = *o;
            used++;
        }
        free(b->slots);
        b->slots = slots;
        b->cap = cap;
        b->used = used;
    }
    size_t i = slot_hash(name, b->cap);
    while (b->slots[i].name && !b->slots[i].dead)
        i = (i + 1) & (b->cap - 1);
    if (!b->slots[i].name)
        b->used++;
    b->slots[i] = (buffer_slot){.name = name};
    return &b->slots[i];
}

/* Bytes of buffer `name` as the stream sized it; 0 when it never did. */
static uint64_t buffer_size(const tsr_unpacker *u, uint32_t name)
{
    const buffer_slot *s = u->objects ? buffer_find(u->objects, name) : NULL;
    return s ? s->size : 0;
}

void tsr_unpacker_note_BindBuffer(tsr_unpacker *u, GLenum target, GLuint buffer)
{
    if (target == GL_PIXEL_PACK_BUFFER)
        u->pixels.pack_buffer = buffer;
    else if (target == GL_PIXEL_UNPACK_BUFFER)
        u->pixels.unpack_buffer = buffer;
    int k = bound_index(target);
    if (u->objects && k >= 0)
        u->objects->bound[k] = buffer;
}

void tsr_unpacker_note_DeleteBuffers(tsr_unpacker *u, GLsizei n, const GLuint *buffers)
{
    for (GLsizei i = 0; buffers && i < n; i++) {
        if (buffers[i] && buffers[i] == u->pixels.pack_buffer)
            u->pixels.pack_buffer = 0;
        if (buffers[i] && buffers[i] == u->pixels.unpack_buffer)
            u->pixels.unpack_buffer = 0;
    }
    struct tsr_unpack_buffers *b = u->objects;
    for (GLsizei i = 0; b && i < n; i++) {
        buffer_slot *s = buffer_find(b, buffers[i]);
        if (s) {
            b->total -= s->size;
            s->dead = 1;
            s->size = 0;
        }
        for (int k = 0; k < BOUND_TARGETS; k++)
            if (b->bound[k] == buffers[i])
                b->bound[k] = 0;
    }
}

/* The pixel store and buffer bindings of the stream's other contexts. */
typedef struct unpack_context_state {
    GLint context;
    tsr_pixel_store pixels;
    uint32_t bound[BOUND_TARGETS];
} unpack_context_state;

static void unpack_mirrors_reset(tsr_unpacker *u)
{
    tsr_pixel_store_init(&u->pixels);
    if (u->objects)
        memset(u->objects->bound, 0, sizeof u->objects->bound);
}

/* Out of memory for a context's state: that context then starts from GL's
 * initial values when made current again (its commands still run). */
void tsr_unpacker_note_MakeCurrent(tsr_unpacker *u, GLint context)
{
    if (u->context_known && context == u->context)
        return;
    if (u->context_known) {
        unpack_context_state *s = tsr_wire_contexts_find(u->contexts, u->context);
        if (!s)
            s = tsr_wire_contexts_add(&u->contexts, u->context, sizeof *s);
        if (s) {
            s->pixels = u->pixels;
            if (u->objects)
                memcpy(s->bound, u->objects->bound, sizeof s->bound);
        }
    }
    const unpack_context_state *s = tsr_wire_contexts_find(u->contexts, context);
    if (s) {
        u->pixels = s->pixels;
        if (u->objects)
            memcpy(u->objects->bound, s->bound, sizeof s->bound);
    } else if (u->context_known) {
        unpack_mirrors_reset(u);
    }
    u->context = context;
    u->context_known = 1;
}

void tsr_unpacker_note_ContextDestroy(tsr_unpacker *u, GLint context)
{
    tsr_wire_contexts_remove(u->contexts, context);
    tsr_wire_selection_forget(u->selection, context);
    if (u->context_known && context == u->context) {
        unpack_mirrors_reset(u);
        u->context_known = 0;
    }
}

int tsr_unpacker_check_BufferData(tsr_unpacker *u, GLenum target, GLsizeiptr size, tsr_error *err)
{
    struct tsr_unpack_buffers *b = u->objects;
    int k = bound_index(target);
    /* GL refuses these itself and changes nothing. */
    if (!b || k < 0 || size < 0 || !b->bound[k])
        return 0;
    uint32_t name = b->bound[k];
    buffer_slot *s = buffer_slot_for(b, name);
    if (!s)
        return tsr_error_set(err, TSR_ENOMEM, "command BufferData: out of memory for the buffer table");
    uint64_t others = b->total - s->size;
    uint64_t max = u->limits.max_buffer_bytes;
    if (max && (uint64_t)size > max - (others < max ? others : max))
        return tsr_error_set(err, TSR_EPROTO,
                             "command BufferData(target 0x%x, buffer %u, %lld bytes): over the buffer budget "
                             "max_buffer_bytes=%llu (%llu bytes in the stream's other buffers)",
                             target, name, (long long)size, (unsigned long long)max, (unsigned long long)others);
    b->total = others + (uint64_t)size;
    s->size = (uint64_t)size;
    return 0;
}

void tsr_unpack_limits_defaults(tsr_unpack_limits *limits)
{
    *limits = (tsr_unpack_limits){.max_output = TSR_UNPACK_MAX_OUTPUT,
                                  .max_vertices = TSR_UNPACK_DEFAULT_MAX_VERTICES,
                                  .max_buffer_bytes = TSR_UNPACK_DEFAULT_MAX_BUFFER_BYTES};
}

int tsr_unpacker_set_limits(tsr_unpacker *u, const tsr_unpack_limits *limits, tsr_error *err)
{
    if (!u->objects && !(u->objects = calloc(1, sizeof *u->objects)))
        return tsr_error_set(err, TSR_ENOMEM, "unpacker: out of memory");
    u->limits = *limits;
    u->max_output = limits->max_output ? limits->max_output : UINT64_MAX / 4;
    u->limited = 1;
    return TSR_OK;
}

int tsr_unpacker_budgeted(void) { return decoding != NULL && decoding->limited; }

int tsr_unpacker_refuse(const char *fmt, ...)
{
    tsr_unpacker *u = decoding;
    if (!u)
        return 0;
    if (!u->refused) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(u->refusal, sizeof u->refusal, fmt, ap);
        va_end(ap);
        u->refused = 1;
    }
    tsr_unpacker_yield(u);
    return 1;
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
    buffers_free(u->objects);
    tsr_wire_contexts_free(u->contexts);
    tsr_wire_selection_free(u->selection);
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
    u->buffer_vertices = 0;
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
    tsr_unpacker *outer = decoding;
    decoding = u;
    int rc = tsr_unpack_commands(u, u->target, u->paused_data, u->paused_nops, u->paused_len, err);
    decoding = outer;
    if (u->refused) {
        /* An SPU refused a command (tsr_unpacker_refuse): the stream fails. */
        u->refused = 0;
        rc = tsr_error_set(err, TSR_EPROTO, "%s", u->refusal);
    }
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
    /* Saturating: each term and the running total stay below 2^63. */
    uint64_t total = 0, cap = UINT64_MAX / 4;
    for (int i = 0; i < n; i++) {
        uint64_t a = sizes[i] > cap ? cap : tsr_wire_align8(sizes[i]);
        total = total > cap ? total : total + a;
    }
    if (total > u->max_output) {
        snprintf(u->outputs_why, sizeof u->outputs_why,
                 "outputs of %llu bytes are over the reply budget max_reply_bytes=%llu",
                 (unsigned long long)(n == 1 ? sizes[0] : total), (unsigned long long)u->max_output);
        return -1;
    }
    if (grow(&u->out, &u->out_cap, (size_t)total + 8) != 0) {
        snprintf(u->outputs_why, sizeof u->outputs_why, "out of memory for %llu bytes of outputs",
                 (unsigned long long)total);
        return -1;
    }
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
        if (r->kind < TSR_WIRE_ARRAY_VERTEX || r->kind > TSR_WIRE_ARRAY_INDEX)
            BAD("command %s at data offset %zu: array record %u has unknown kind %u", cmd, at, i, r->kind);
        if ((r->kind == TSR_WIRE_ARRAY_TEXCOORD && r->index >= 32) ||
            (r->kind == TSR_WIRE_ARRAY_ATTRIB && r->index >= 64))
            BAD("command %s at data offset %zu: array record %u has index %u out of range", cmd, at, i, r->index);
        if (!((r->size >= 1 && r->size <= 4) || r->size == GL_BGRA))
            BAD("command %s at data offset %zu: array record %u has size %d", cmd, at, i, r->size);
        /* the receiver's GL refuses any other, and a refused pointer
         * would leave its array at the last draw's (freed) data */
        if ((r->kind == TSR_WIRE_ARRAY_SECONDARY_COLOR && r->size != 3) ||
            ((r->kind == TSR_WIRE_ARRAY_FOG_COORD || r->kind == TSR_WIRE_ARRAY_INDEX) && r->size != 1) ||
            (r->kind == TSR_WIRE_ARRAY_SECONDARY_COLOR && (r->type < GL_BYTE || r->type > GL_FLOAT) &&
             r->type != GL_DOUBLE) ||
            (r->kind == TSR_WIRE_ARRAY_FOG_COORD && r->type != GL_FLOAT && r->type != GL_DOUBLE) ||
            (r->kind == TSR_WIRE_ARRAY_INDEX && r->type != GL_UNSIGNED_BYTE && r->type != GL_SHORT &&
             r->type != GL_INT && r->type != GL_FLOAT && r->type != GL_DOUBLE))
            BAD("command %s at data offset %zu: array record %u of kind %u has size %d, type 0x%x", cmd, at, i, r->kind,
                r->size, r->type);
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

/* With limits on: a draw of `count` vertices (or indices) is charged to
 * the buffer's vertex budget. A draw with no arrays reads nothing and is
 * valid GL, so this alone bounds it. */
static int charge_vertices(tsr_unpacker *u, const char *cmd, size_t at, uint64_t count, tsr_error *err)
{
    uint64_t max = u->limits.max_vertices;
    if (!u->limited || !max)
        return 0;
    uint64_t used = u->buffer_vertices;
    if (count > max || used > max - count)
        BAD("command %s at data offset %zu: %llu vertices are over the vertex budget max_vertices=%llu per "
            "buffer (%llu already drawn in this buffer)",
            cmd, at, (unsigned long long)count, (unsigned long long)max, (unsigned long long)used);
    u->buffer_vertices = used + count;
    return 0;
}

/* With limits on: every array in a buffer object must hold vertex `hi`
 * (the highest one the draw reads) inside the bytes the stream gave that
 * buffer; GL's robustness rules let a reader refuse a draw that reads
 * past them. */
static int buffers_cover(const tsr_unpacker *u, const arrays_hdr *h, uint64_t hi, const char *cmd, size_t at,
                         tsr_error *err)
{
    if (!u->limited)
        return 0;
    for (uint32_t i = 0; i < h->count; i++) {
        const array_rec *r = &h->rec[i];
        if (!r->buffer)
            continue;
        uint64_t stride = r->stride ? (uint64_t)r->stride : r->elem, end;
        uint64_t size = buffer_size(u, r->buffer);
        if (__builtin_mul_overflow(hi, stride, &end) || __builtin_add_overflow(end, r->offset, &end) ||
            __builtin_add_overflow(end, r->elem, &end) || end > size)
            BAD("command %s at data offset %zu: vertex %llu of array record %u lies past the %llu bytes of "
                "buffer %u",
                cmd, at, (unsigned long long)hi, i, (unsigned long long)size, r->buffer);
    }
    return 0;
}

static GLenum array_cap(uint32_t kind)
{
    switch (kind) {
    case TSR_WIRE_ARRAY_VERTEX: return GL_VERTEX_ARRAY;
    case TSR_WIRE_ARRAY_NORMAL: return GL_NORMAL_ARRAY;
    case TSR_WIRE_ARRAY_COLOR: return GL_COLOR_ARRAY;
    case TSR_WIRE_ARRAY_EDGE_FLAG: return GL_EDGE_FLAG_ARRAY;
    case TSR_WIRE_ARRAY_SECONDARY_COLOR: return GL_SECONDARY_COLOR_ARRAY;
    case TSR_WIRE_ARRAY_FOG_COORD: return GL_FOG_COORD_ARRAY;
    case TSR_WIRE_ARRAY_INDEX: return GL_INDEX_ARRAY;
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
        case TSR_WIRE_ARRAY_SECONDARY_COLOR: tsr_call_SecondaryColorPointer(d, r->size, r->type, stride, ptr); break;
        case TSR_WIRE_ARRAY_FOG_COORD: tsr_call_FogCoordPointer(d, r->type, stride, ptr); break;
        case TSR_WIRE_ARRAY_INDEX: tsr_call_IndexPointer(d, r->type, stride, ptr); break;
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
        BAD("command DrawArrays at data offset %zu: vertices %d..%lld lie outside the arrays sent", at, first,
            (long long)first + count - 1);
    if (count > 0 && (buffers_cover(u, &h, (uint64_t)first + (uint64_t)count - 1, "DrawArrays", at, err) != 0 ||
                      charge_vertices(u, "DrawArrays", at, (uint64_t)count, err) != 0))
        return err->code;
    set_arrays(d, &h);
    tsr_call_DrawArrays(d, mode, first, count);
    restore_arrays(d, &h);
    *pos = q;
    return 0;
}

int tsr_unpack_custom_DrawElements(tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len, size_t *pos,
                                   tsr_error *err)
{
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
    if (inline_arrays && count > 0 && index_buffer)
        BAD("command DrawElements at data offset %zu: inline arrays with indices in buffer %u", at, index_buffer);
    if (count > 0 && index_buffer && u->limited) {
        /* The indices must lie inside their buffer; their values are not
         * known here (the stream's buffer contents are not kept). */
        uint64_t size = buffer_size(u, index_buffer), end;
        if (__builtin_mul_overflow((uint64_t)count, (uint64_t)isize, &end) ||
            __builtin_add_overflow(end, index_offset, &end) || end > size)
            BAD("command DrawElements at data offset %zu: %d indices at offset %llu lie past the %llu bytes of "
                "buffer %u",
                at, count, (unsigned long long)index_offset, (unsigned long long)size, index_buffer);
    } else if (count > 0 && (inline_arrays || u->limited)) {
        /* Every index must address data that was sent (or sized). */
        uint64_t lo = UINT64_MAX, hi = 0;
        for (GLsizei i = 0; i < count; i++) {
            uint64_t v = isize == 1   ? indices[i]
                         : isize == 2 ? tsr_wire_get_u16(indices + 2 * i)
                                      : tsr_wire_get_u32(indices + 4 * i);
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
        if (inline_arrays && !range_covered(&h, lo, hi))
            BAD("command DrawElements at data offset %zu: indices %llu..%llu lie outside the arrays sent", at,
                (unsigned long long)lo, (unsigned long long)hi);
        if (buffers_cover(u, &h, hi, "DrawElements", at, err) != 0)
            return err->code;
    }
    if (count > 0 && charge_vertices(u, "DrawElements", at, (uint64_t)count, err) != 0)
        return err->code;
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

/* MapBuffer, MapBufferRange, FlushMappedBufferRange and UnmapBuffer never
 * travel (pack_map.c sends BufferSubData). */
static int never_sent(const char *name, size_t pos, tsr_error *err)
{
    return tsr_error_set(err, TSR_EPROTO,
                         "command %s at data offset %zu: never sent (a packer sends the mapped buffer as "
                         "BufferSubData at UnmapBuffer or FlushMappedBufferRange)",
                         name, pos);
}

int tsr_unpack_custom_MapBuffer(struct tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len,
                                size_t *pos, tsr_error *err)
{
    (void)u, (void)d, (void)b, (void)len;
    return never_sent("MapBuffer", *pos, err);
}

int tsr_unpack_custom_MapBufferRange(struct tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len,
                                     size_t *pos, tsr_error *err)
{
    (void)u, (void)d, (void)b, (void)len;
    return never_sent("MapBufferRange", *pos, err);
}

int tsr_unpack_custom_FlushMappedBufferRange(struct tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b,
                                             size_t len, size_t *pos, tsr_error *err)
{
    (void)u, (void)d, (void)b, (void)len;
    return never_sent("FlushMappedBufferRange", *pos, err);
}

int tsr_unpack_custom_UnmapBuffer(struct tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len,
                                  size_t *pos, tsr_error *err)
{
    (void)u, (void)d, (void)b, (void)len;
    return never_sent("UnmapBuffer", *pos, err);
}

int tsr_unpack_custom_ArrayElement(struct tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len,
                                   size_t *pos, tsr_error *err)
{
    (void)u, (void)d, (void)b, (void)len;
    return tsr_error_set(err, TSR_EPROTO,
                         "command ArrayElement at data offset %zu: never sent (a packer sends the elements "
                         "as immediate-mode commands)",
                         *pos);
}
