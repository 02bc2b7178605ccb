/* core/wire/pack.c — packer runtime: buffer memory and flushing, replies, the
 * client-state mirrors (pixel store, vertex arrays, buffer bindings, the
 * client attribute stack) and the hand-written packers of `local` and
 * `custom` commands (client-array draws as one bulk payload, ShaderSource,
 * GetTexImage; formats in tessera/dev/wire.h). Generated packers (pack_gen.c) do
 * everything else. Owns only the packer's memory; never sends a host
 * pointer; never aborts: problems are recorded in the packer's error.
 * The mirrors of client state are in pack_mirror.c (pack_internal.h). */
#include "pack_internal.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/log.h"
#include "wire_gen.h"
#include "wire_internal.h"


void pack_record(tsr_packer *p, int code, const char *fmt, ...)
{
    if (p->error.code != TSR_OK)
        return;
    char msg[sizeof p->error.message];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    tsr_error_set(&p->error, code, "%s", msg);
    tsr_log(TSR_LOG_WARN, "packer: %s", msg);
}

static void use_normal_buffer(tsr_packer *p)
{
    p->mid = p->mem + TSR_WIRE_HEADER_SIZE + p->op_room;
    p->op = p->mid;
    p->op_limit = p->mid - p->op_room;
    p->data = p->mid;
    p->data_end = p->mid + p->data_room;
}

void tsr_packer_bbox_reset(tsr_packer *p)
{
    for (int i = 0; i < 4; i++) {
        p->bbox_min[i] = INFINITY;
        p->bbox_max[i] = -INFINITY;
    }
    p->bbox_nan = 0;
}

void tsr_packer_bbox_infinite(tsr_packer *p)
{
    for (int i = 0; i < 3; i++) {
        p->bbox_min[i] = -INFINITY;
        p->bbox_max[i] = INFINITY;
    }
}

int tsr_packer_bbox(const tsr_packer *p, float min[3], float max[3])
{
    if (p->bbox_nan) {
        for (int i = 0; i < 3; i++) {
            min[i] = -INFINITY;
            max[i] = INFINITY;
        }
        return 1;
    }
    for (int i = 0; i < 3; i++) {
        min[i] = p->bbox_min[i];
        max[i] = p->bbox_max[i];
    }
    return p->bbox_min[0] <= p->bbox_max[0];
}

tsr_packer *tsr_packer_create(size_t buffer_size, const tsr_pack_sink *sink, tsr_error *err)
{
    if (buffer_size < TSR_PACK_MIN_BUFFER) {
        tsr_error_set(err, TSR_EINVAL, "packer: buffer size %zu is below the minimum %u", buffer_size,
                      TSR_PACK_MIN_BUFFER);
        return NULL;
    }
    tsr_packer *p = calloc(1, sizeof *p);
    if (!p) {
        tsr_error_set(err, TSR_ENOMEM, "packer: out of memory");
        return NULL;
    }
    /* One opcode per 4 data bytes: Vertex3f streams (12 bytes per opcode)
     * fill the data first, End/PopMatrix-heavy ones the opcodes. */
    size_t usable = (buffer_size - TSR_WIRE_HEADER_SIZE) & ~(size_t)7;
    p->op_room = (usable / 5) & ~(size_t)7;
    p->data_room = usable - p->op_room;
    p->mem_size = TSR_WIRE_HEADER_SIZE + usable;
    p->mem = calloc(1, p->mem_size);
    if (!p->mem) {
        free(p);
        tsr_error_set(err, TSR_ENOMEM, "packer: out of memory for a %zu-byte buffer", buffer_size);
        return NULL;
    }
    if (sink)
        p->sink = *sink;
    use_normal_buffer(p);
    tsr_packer_bbox_reset(p);
    tsr_pixel_store_init(&p->pixels);
    return p;
}

void tsr_packer_destroy(tsr_packer *p)
{
    if (!p)
        return;
    free(p->mem);
    free(p->big);
    for (size_t i = 0; i < p->nstrings; i++)
        free(p->strings[i]);
    free(p->strings);
    tsr_wire_contexts_free(p->contexts);
    tsr_wire_selection_free(p->selection);
    tsr_packer_glsl_names_free(p->glsl_names);
    for (size_t i = 0; i < sizeof p->mapped / sizeof p->mapped[0]; i++)
        free(p->mapped[i].data);
    free(p);
}

size_t tsr_packer_pending(const tsr_packer *p) { return (size_t)(p->mid - p->op) + (size_t)(p->data - p->mid); }

int tsr_packer_flush(tsr_packer *p)
{
    size_t nops = (size_t)(p->mid - p->op);
    if (!nops)
        return 0;
    size_t padded = (size_t)tsr_wire_align8(nops);
    memset(p->mid - padded, 0, padded - nops);
    uint8_t *h = p->mid - padded - TSR_WIRE_HEADER_SIZE;
    size_t dlen = (size_t)(p->data - p->mid);
    tsr_wire_put_u32(h, TSR_WIRE_MAGIC);
    tsr_wire_put_u32(h + 4, (uint32_t)nops);
    tsr_wire_put_u64(h + 8, dlen);
    size_t size = TSR_WIRE_HEADER_SIZE + padded + dlen;
    int rc = 0;
    tsr_error e;
    tsr_error_clear(&e);
    if (p->sink.flush)
        rc = p->sink.flush(p->sink.ctx, h, size, &e);
    p->buffers_sent++;
    p->bytes_sent += size;
    if (p->big) {
        free(p->big);
        p->big = NULL;
    }
    use_normal_buffer(p);
    tsr_packer_bbox_reset(p);
    if (rc) {
        pack_record(p, rc, "flushing a %zu-byte buffer failed: %s", size, e.message);
        return rc;
    }
    return 0;
}

static uint8_t *place(tsr_packer *p, uint8_t opcode, size_t size, size_t align)
{
    uint8_t *d = (uint8_t *)(((uintptr_t)p->data + (align - 1)) & ~(uintptr_t)(align - 1));
    *--p->op = opcode;
    p->data = d + size;
    return d;
}

static int fits(const tsr_packer *p, uint64_t size, size_t align)
{
    uint8_t *d = (uint8_t *)(((uintptr_t)p->data + (align - 1)) & ~(uintptr_t)(align - 1));
    return p->op != p->op_limit && (uint64_t)(p->data_end - d) >= size;
}

static uint8_t *cmd_slow(tsr_packer *p, uint32_t opcode, uint64_t size, size_t align);

uint8_t *tsr_packer_cmd_slow(tsr_packer *p, uint32_t opcode, uint64_t size, size_t align)
{
    uint8_t *d = cmd_slow(p, opcode, size, align);
    return d ? d : p->discard;
}

static uint8_t *cmd_slow(tsr_packer *p, uint32_t opcode, uint64_t size, size_t align)
{
    if (p->mid != p->op)
        tsr_packer_flush(p);
    if (fits(p, size, align))
        return place(p, (uint8_t)opcode, (size_t)size, align);
    /* Larger than a whole buffer: a buffer of its own, sent on the next
     * command or flush. */
    if (size > SIZE_MAX / 2) {
        pack_record(p, TSR_ENOMEM, "command %s of %llu bytes cannot be packed", tsr_wire_opcode_name(opcode),
                    (unsigned long long)size);
        return NULL;
    }
    size_t room = (size_t)tsr_wire_align8(size);
    uint8_t *big = malloc(TSR_WIRE_HEADER_SIZE + 8 + room);
    if (!big) {
        pack_record(p, TSR_ENOMEM, "out of memory for a %llu-byte command", (unsigned long long)size);
        return NULL;
    }
    p->big = big;
    p->mid = big + TSR_WIRE_HEADER_SIZE + 8;
    p->op = p->mid;
    p->op_limit = p->mid - 1;
    p->data = p->mid;
    p->data_end = p->mid + room;
    return place(p, (uint8_t)opcode, (size_t)size, align);
}

uint8_t *tsr_packer_cmd_var(tsr_packer *p, uint32_t opcode, uint64_t size, size_t align)
{
    if (opcode < TSR_WIRE_EXTENDED) {
        if (!fits(p, size, align))
            return cmd_slow(p, opcode, size, align);
        return place(p, (uint8_t)opcode, (size_t)size, align);
    }
    if (size > UINT64_MAX - 8) {
        pack_record(p, TSR_ENOMEM, "command %s is too large", tsr_wire_opcode_name(opcode));
        return NULL;
    }
    uint8_t *h = fits(p, size + 8, 8) ? place(p, TSR_WIRE_EXTENDED, (size_t)(size + 8), 8)
                                      : cmd_slow(p, TSR_WIRE_EXTENDED, size + 8, 8);
    if (!h)
        return NULL;
    tsr_wire_put_u32(h, opcode);
    tsr_wire_put_u32(h + 4, size < TSR_WIRE_EXT_LEN_UNKNOWN ? (uint32_t)size : TSR_WIRE_EXT_LEN_UNKNOWN);
    return h + 8;
}

void tsr_packer_drop(tsr_packer *p, const char *command, const char *why)
{
    p->commands_dropped++;
    pack_record(p, TSR_EINVAL, "gl%s not sent: %s", command, why ? why : "invalid arguments");
}

const tsr_error *tsr_packer_error(const tsr_packer *p) { return &p->error; }

void tsr_packer_clear_error(tsr_packer *p) { tsr_error_clear(&p->error); }

const uint8_t *tsr_packer_request(tsr_packer *p, uint32_t id, size_t *size)
{
    if (tsr_packer_flush(p) != 0)
        return NULL;
    if (!p->sink.reply) {
        pack_record(p, TSR_ESTATE, "request %u needs a reply but the packer's sink has no reply channel", id);
        return NULL;
    }
    const uint8_t *r = NULL;
    size_t n = 0;
    tsr_error e;
    tsr_error_clear(&e);
    if (p->sink.reply(p->sink.ctx, id, &r, &n, &e) != 0 || !r) {
        pack_record(p, e.code ? e.code : TSR_EPROTO, "no reply to request %u: %s", id, e.message);
        return NULL;
    }
    p->reply_id = id;
    *size = n;
    return r;
}

void tsr_packer_reply_bad(tsr_packer *p, const char *command, const char *why)
{
    tsr_error e;
    tsr_error_set(&e, TSR_EPROTO, "reply to gl%s (request %u) is malformed: %s", command, p->reply_id,
                  why ? why : "it does not decode");
    pack_record(p, e.code, "%s", e.message);
    if (p->sink.reply_failed)
        p->sink.reply_failed(p->sink.ctx, p->reply_id, &e);
}

const uint8_t *tsr_packer_reply_item(tsr_packer *p, const uint8_t *r, size_t rsize, size_t *pos, uint64_t *len,
                                     const char *command)
{
    size_t q = (size_t)tsr_wire_align8(*pos);
    if (q > rsize || rsize - q < 8) {
        tsr_packer_reply_bad(p, command, "truncated");
        return NULL;
    }
    uint64_t n = tsr_wire_get_u64(r + q);
    q += 8;
    if (n > rsize - q) {
        char why[96];
        snprintf(why, sizeof why, "an item of %llu bytes beyond its end", (unsigned long long)n);
        tsr_packer_reply_bad(p, command, why);
        return NULL;
    }
    *len = n;
    *pos = q + (size_t)n;
    return r + q;
}

const GLubyte *tsr_packer_keep_string(tsr_packer *p, const uint8_t *s, uint64_t len)
{
    for (size_t i = 0; i < p->nstrings; i++)
        if (strlen(p->strings[i]) + 1 == len && !memcmp(p->strings[i], s, (size_t)len))
            return (const GLubyte *)p->strings[i];
    char **v = realloc(p->strings, (p->nstrings + 1) * sizeof *v);
    if (!v)
        return NULL;
    p->strings = v;
    char *copy = malloc((size_t)len + 1);
    if (!copy)
        return NULL;
    memcpy(copy, s, (size_t)len);
    copy[len] = '\0';
    p->strings[p->nstrings++] = copy;
    return (const GLubyte *)copy;
}

/* --- client-array draws ------------------------------------------------------ */

typedef struct draw_array {
    const tsr_client_array *a;
    uint32_t kind, index;
    uint64_t elem; /* bytes of one element */
} draw_array;

static int collect_arrays(tsr_packer *p, draw_array *out, const char *cmd)
{
    int n = 0;
    const tsr_client_arrays *s = &p->arrays;
    const struct {
        const tsr_client_array *a;
        uint32_t kind;
    } fixed[] = {
        {&s->vertex, TSR_WIRE_ARRAY_VERTEX},
        {&s->normal, TSR_WIRE_ARRAY_NORMAL},
        {&s->color, TSR_WIRE_ARRAY_COLOR},
        {&s->edge_flag, TSR_WIRE_ARRAY_EDGE_FLAG},
        {&s->secondary_color, TSR_WIRE_ARRAY_SECONDARY_COLOR},
        {&s->fog_coord, TSR_WIRE_ARRAY_FOG_COORD},
        {&s->index, TSR_WIRE_ARRAY_INDEX},
    };
    const size_t nfixed = sizeof fixed / sizeof fixed[0];
    for (size_t i = 0; i < TSR_PACK_ARRAYS; i++) {
        const tsr_client_array *a;
        uint32_t kind, index;
        if (i < nfixed) {
            a = fixed[i].a;
            kind = fixed[i].kind;
            index = 0;
        } else if (i < nfixed + TSR_PACK_TEXUNITS) {
            index = (uint32_t)(i - nfixed);
            a = &s->texcoord[index];
            kind = TSR_WIRE_ARRAY_TEXCOORD;
        } else {
            index = (uint32_t)(i - nfixed - TSR_PACK_TEXUNITS);
            a = &s->attrib[index];
            kind = TSR_WIRE_ARRAY_ATTRIB;
        }
        if (!a->enabled)
            continue;
        uint64_t ts = tsr_gl_type_size(a->type);
        uint64_t comps = kind == TSR_WIRE_ARRAY_NORMAL      ? 3
                         : kind == TSR_WIRE_ARRAY_EDGE_FLAG ? 1
                         : a->size == GL_BGRA               ? 4
                                                            : (uint64_t)a->size;
        if (kind == TSR_WIRE_ARRAY_EDGE_FLAG)
            ts = 1;
        if (!ts || !((a->size >= 1 && a->size <= 4) || a->size == GL_BGRA) || a->stride < 0) {
            pack_record(p, TSR_EINVAL, "gl%s not sent: an enabled array has size %d, type 0x%x, stride %d", cmd,
                        a->size, a->type, a->stride);
            return -1;
        }
        if (!a->buffer && !a->pointer) {
            pack_record(p, TSR_EINVAL, "gl%s not sent: an enabled client array has a NULL pointer", cmd);
            return -1;
        }
        out[n].a = a;
        out[n].kind = kind;
        out[n].index = index;
        out[n].elem = comps * ts;
        n++;
    }
    return n;
}

/* Bytes of the ARRAYS block for elements [lo, hi] (count 0: no arrays). */
static int arrays_size(const draw_array *v, int n, uint64_t lo, uint64_t hi, uint64_t *size)
{
    uint64_t s = 16;
    for (int i = 0; i < n; i++) {
        s += 48;
        if (v[i].a->buffer)
            continue;
        uint64_t bytes;
        if (__builtin_mul_overflow(hi - lo + 1, v[i].elem, &bytes) || bytes > (UINT64_MAX >> 2))
            return -1;
        s = tsr_wire_align8(s + bytes);
    }
    *size = s;
    return 0;
}

static void write_arrays(const tsr_packer *p, uint8_t *out, const draw_array *v, int n, uint64_t lo, uint64_t hi)
{
    tsr_wire_put_u32(out, p->arrays.array_buffer);
    tsr_wire_put_u32(out + 4, p->arrays.element_buffer);
    tsr_wire_put_u32(out + 8, p->arrays.active_texture);
    tsr_wire_put_u32(out + 12, (uint32_t)n);
    uint64_t q = 16;
    for (int i = 0; i < n; i++) {
        const tsr_client_array *a = v[i].a;
        uint8_t *r = out + q;
        memset(r, 0, 48);
        tsr_wire_put_u32(r, v[i].kind);
        tsr_wire_put_u32(r + 4, v[i].index);
        tsr_wire_put_u32(r + 8, (uint32_t)a->size);
        tsr_wire_put_u32(r + 12, a->type);
        tsr_wire_put_u32(r + 16, (uint32_t)(a->buffer ? a->stride : 0));
        tsr_wire_put_u32(r + 20, a->normalized);
        tsr_wire_put_u32(r + 24, a->buffer);
        q += 48;
        if (a->buffer) {
            tsr_wire_put_u64(r + 32, (uint64_t)(uintptr_t)a->pointer);
            tsr_wire_put_u64(r + 40, 0);
            continue;
        }
        uint64_t count = hi - lo + 1, elem = v[i].elem;
        uint64_t stride = a->stride ? (uint64_t)a->stride : elem;
        tsr_wire_put_u64(r + 32, lo);
        tsr_wire_put_u64(r + 40, count * elem);
        const uint8_t *src = (const uint8_t *)a->pointer + lo * stride;
        uint8_t *dst = out + q;
        if (stride == elem) {
            memcpy(dst, src, (size_t)(count * elem));
        } else {
            for (uint64_t k = 0; k < count; k++)
                memcpy(dst + k * elem, src + k * stride, (size_t)elem);
        }
        uint64_t end = q + count * elem;
        q = tsr_wire_align8(end);
        memset(out + end, 0, (size_t)(q - end));
    }
}

int tsr_client_array_position(const tsr_client_array *a, uint64_t i, float out[4])
{
    if (a->buffer || (a->type != GL_FLOAT && a->type != GL_DOUBLE && a->type != GL_INT && a->type != GL_SHORT) ||
        a->size < 1 || a->size > 4)
        return 0;
    size_t ts = tsr_gl_type_size(a->type);
    uint64_t stride = a->stride ? (uint64_t)a->stride : (uint64_t)a->size * ts;
    const uint8_t *e = (const uint8_t *)a->pointer + i * stride;
    out[0] = out[1] = out[2] = 0;
    out[3] = 1;
    for (int j = 0; j < a->size; j++) {
        switch (a->type) {
        case GL_FLOAT: {
            float f;
            memcpy(&f, e + 4 * j, 4);
            out[j] = f;
            break;
        }
        case GL_DOUBLE: {
            double d;
            memcpy(&d, e + 8 * j, 8);
            out[j] = (float)d;
            break;
        }
        case GL_INT: {
            GLint x;
            memcpy(&x, e + 4 * j, 4);
            out[j] = (float)x;
            break;
        }
        default: {
            GLshort x;
            memcpy(&x, e + 2 * j, 2);
            out[j] = (float)x;
            break;
        }
        }
    }
    return 1;
}

/* Feeds the positions of the vertex array, elements [lo, hi], into the
 * bounding box (a superset for DrawElements); arrays in buffer objects
 * make it infinite (their data never passes through the packer). */
static void bbox_of_vertex_array(tsr_packer *p, const draw_array *v, int n, uint64_t lo, uint64_t hi)
{
    for (int i = 0; i < n; i++) {
        if (v[i].kind != TSR_WIRE_ARRAY_VERTEX)
            continue;
        float c[4];
        for (uint64_t k = lo; k <= hi; k++) {
            if (!tsr_client_array_position(v[i].a, k, c)) {
                tsr_packer_bbox_infinite(p);
                return;
            }
            tsr_packer_bbox4(p, c[0], c[1], c[2], c[3]);
        }
        return;
    }
}

void tsr_packer_custom_DrawArrays(tsr_packer *p, GLenum mode, GLint first, GLsizei count)
{
    if (first < 0 || count < 0) {
        tsr_packer_local_error(p, GL_INVALID_VALUE);
        tsr_packer_drop(p, "DrawArrays", "negative first or count");
        return;
    }
    draw_array v[TSR_PACK_ARRAYS];
    int n = count ? collect_arrays(p, v, "DrawArrays") : 0;
    if (n < 0)
        return;
    uint64_t lo = (uint64_t)first, hi = (uint64_t)first + (uint64_t)count - 1, asize;
    if (arrays_size(v, n, lo, hi, &asize) != 0) {
        tsr_packer_drop(p, "DrawArrays", "arrays too large");
        return;
    }
    uint8_t *d = tsr_packer_cmd_var(p, TSR_OP_DrawArrays, 24 + asize, 8);
    if (!d)
        return;
    tsr_wire_put_u32(d, mode);
    tsr_wire_put_u32(d + 4, (uint32_t)first);
    tsr_wire_put_u32(d + 8, (uint32_t)count);
    tsr_wire_put_u32(d + 12, 0);
    tsr_wire_put_u64(d + 16, asize);
    write_arrays(p, d + 24, v, n, lo, hi);
    bbox_of_vertex_array(p, v, n, lo, hi);
}

static void index_range(const void *indices, GLsizei count, size_t isize, uint64_t *lo, uint64_t *hi)
{
    const uint8_t *ix = indices;
    *lo = UINT64_MAX;
    *hi = 0;
    for (GLsizei i = 0; i < count; i++) {
        uint64_t x = isize == 1 ? ix[i] : isize == 2 ? ((const GLushort *)indices)[i] : ((const GLuint *)indices)[i];
        *lo = x < *lo ? x : *lo;
        *hi = x > *hi ? x : *hi;
    }
}

/* The indices of a glDrawElements whose indices are in an element array
 * buffer while some of its arrays are in client memory (GL allows the
 * mix; piglit's draw-elements makes it): the packer sends the elements of
 * those arrays the indices reach, and only the receiver has the indices.
 * It asks for them (the buffer's size, then its bytes: two round trips for
 * a mix programs rarely make; VBO-only draws take none) and the draw
 * carries them inline, as a draw of client-memory indices, which the
 * receiver checks against the arrays sent; the program's element array
 * buffer binding is restored after it. A copy the caller frees, or NULL
 * when the draw is not sent: a buffer mapped (GL_INVALID_OPERATION, as
 * GL), indices past the buffer's end (GL leaves the result undefined:
 * nothing is drawn), no reply channel or no memory (dropped, logged). */
static void *element_buffer_indices(tsr_packer *p, GLsizei count, size_t isize, const void *indices)
{
    if (tsr_packer_buffer_mapped(p, GL_ELEMENT_ARRAY_BUFFER)) {
        tsr_packer_local_error(p, GL_INVALID_OPERATION);
        return NULL;
    }
    if (!p->sink.reply) {
        tsr_packer_drop(p, "DrawElements", "client-memory arrays with indices in a buffer need a reply channel");
        return NULL;
    }
    uint64_t offset = (uint64_t)(uintptr_t)indices, bytes = (uint64_t)count * isize;
    GLint size = -1;
    tsr_pack_GetBufferParameteriv(p, GL_ELEMENT_ARRAY_BUFFER, GL_BUFFER_SIZE, &size);
    if (size < 0 || offset > (uint64_t)size || bytes > (uint64_t)size - offset)
        return NULL;
    void *ix = calloc(1, bytes ? (size_t)bytes : 1);
    if (!ix) {
        tsr_packer_drop(p, "DrawElements", "no memory for the indices");
        return NULL;
    }
    int failed_before = p->error.code != 0;
    tsr_pack_GetBufferSubData(p, GL_ELEMENT_ARRAY_BUFFER, (GLintptr)offset, (GLsizeiptr)bytes, ix);
    if (!failed_before && p->error.code) {
        free(ix);
        return NULL;
    }
    return ix;
}

/* The element array buffer's bytes as the caller knows them (tilesort's
 * tracker), or none given (the packer asks the receiver when it must). */
typedef struct known_buffer {
    int given;
    const uint8_t *bytes; /* NULL: no data store, or mapped */
    uint64_t size;
} known_buffer;

static void draw_elements(tsr_packer *p, GLenum mode, GLsizei count, GLenum type, const void *indices,
                          const known_buffer *known);

void tsr_packer_custom_DrawElements(tsr_packer *p, GLenum mode, GLsizei count, GLenum type, const void *indices)
{
    draw_elements(p, mode, count, type, indices, NULL);
}

void tsr_packer_draw_elements_known(tsr_packer *p, GLenum mode, GLsizei count, GLenum type, const void *indices,
                                    const void *buffer_bytes, GLsizeiptr buffer_size)
{
    known_buffer k = {1, buffer_bytes, buffer_bytes && buffer_size > 0 ? (uint64_t)buffer_size : 0};
    draw_elements(p, mode, count, type, indices, &k);
}

/* The indices of a draw of client-memory arrays whose indices are in the
 * element array buffer, from the caller's copy of that buffer: a pointer
 * into it, or NULL when the draw is not sent (a mapped buffer is
 * GL_INVALID_OPERATION; indices past the buffer's end, where GL leaves the
 * result undefined, draw nothing). */
static const void *known_indices(tsr_packer *p, const known_buffer *k, GLsizei count, size_t isize, const void *indices)
{
    if (tsr_packer_buffer_mapped(p, GL_ELEMENT_ARRAY_BUFFER)) {
        tsr_packer_local_error(p, GL_INVALID_OPERATION);
        return NULL;
    }
    uint64_t offset = (uint64_t)(uintptr_t)indices, bytes = (uint64_t)count * isize;
    if (!k->bytes || offset > k->size || bytes > k->size - offset)
        return NULL;
    return k->bytes + offset;
}

/* glDrawElements with the mirror's element array buffer (0: indices in
 * client memory). */
static void draw_elements(tsr_packer *p, GLenum mode, GLsizei count, GLenum type, const void *indices,
                          const known_buffer *known)
{
    GLuint ibuf = p->arrays.element_buffer;
    size_t isize = type == GL_UNSIGNED_BYTE ? 1 : type == GL_UNSIGNED_SHORT ? 2 : type == GL_UNSIGNED_INT ? 4 : 0;
    if (count < 0 || !isize) {
        tsr_packer_local_error(p, count < 0 ? GL_INVALID_VALUE : GL_INVALID_ENUM);
        tsr_packer_drop(p, "DrawElements", "negative count or bad index type");
        return;
    }
    if (!ibuf && !indices && count) {
        tsr_packer_drop(p, "DrawElements", "NULL indices without an element array buffer");
        return;
    }
    draw_array v[TSR_PACK_ARRAYS];
    int n = count ? collect_arrays(p, v, "DrawElements") : 0;
    if (n < 0)
        return;
    uint64_t lo = 0, hi = 0;
    int inline_arrays = 0;
    for (int i = 0; i < n; i++)
        inline_arrays |= v[i].a->buffer == 0;
    void *fetched = NULL;
    if (inline_arrays) {
        if (ibuf && known) {
            if (!(indices = known_indices(p, known, count, isize, indices)))
                return;
            ibuf = 0;
        } else if (ibuf) {
            if (!(fetched = element_buffer_indices(p, count, isize, indices)))
                return;
            indices = fetched;
            ibuf = 0;
        }
        index_range(indices, count, isize, &lo, &hi);
    }
    uint64_t asize, ilen = ibuf ? 0 : (uint64_t)count * isize;
    if (arrays_size(v, n, lo, hi, &asize) != 0) {
        tsr_packer_drop(p, "DrawElements", "arrays too large");
        free(fetched);
        return;
    }
    uint64_t size = 24 + 8 + tsr_wire_align8(ilen) + 8 + asize;
    uint8_t *d = tsr_packer_cmd_var(p, TSR_OP_DrawElements, size, 8);
    if (!d) {
        free(fetched);
        return;
    }
    tsr_wire_put_u32(d, mode);
    tsr_wire_put_u32(d + 4, (uint32_t)count);
    tsr_wire_put_u32(d + 8, type);
    tsr_wire_put_u32(d + 12, ibuf);
    tsr_wire_put_u64(d + 16, ibuf ? (uint64_t)(uintptr_t)indices : 0);
    tsr_wire_put_u64(d + 24, ilen);
    if (ilen)
        memcpy(d + 32, indices, (size_t)ilen);
    memset(d + 32 + ilen, 0, (size_t)(tsr_wire_align8(ilen) - ilen));
    uint64_t q = 32 + tsr_wire_align8(ilen);
    tsr_wire_put_u64(d + q, asize);
    write_arrays(p, d + q + 8, v, n, lo, hi);
    bbox_of_vertex_array(p, v, n, lo, hi);
    free(fetched);
}

uint64_t tsr_packer_draw_bytes(tsr_packer *p, GLsizei count, GLenum index_type, uint64_t vertices)
{
    draw_array v[TSR_PACK_ARRAYS];
    int n = count > 0 && vertices ? collect_arrays(p, v, index_type ? "DrawElements" : "DrawArrays") : 0;
    uint64_t asize;
    if (n < 0 || arrays_size(v, n, 0, vertices ? vertices - 1 : 0, &asize) != 0)
        return 0;
    if (!index_type)
        return 1 + 24 + asize;
    uint64_t isize = index_type == GL_UNSIGNED_BYTE ? 1 : index_type == GL_UNSIGNED_SHORT ? 2 : 4;
    return 1 + 24 + 8 + tsr_wire_align8((uint64_t)count * isize) + 8 + asize;
}

static uint64_t source_length(const GLchar *s, const GLint *length, GLsizei i)
{
    if (length && length[i] >= 0)
        return (uint64_t)length[i];
    return strlen(s);
}

void tsr_packer_custom_ShaderSource(tsr_packer *p, GLuint shader, GLsizei count, const GLchar *const *string,
                                    const GLint *length)
{
    if (count < 0 || (count && !string)) {
        /* GL's answer (Mesa's too): GL_INVALID_VALUE, nothing changes. */
        tsr_packer_local_error(p, GL_INVALID_VALUE);
        return;
    }
    /* GL checks the name before it reads a string (piglit's
     * shadersource-errors hands a bad name a pointer that is no array of
     * strings): so does the packer, which would read them to send them. */
    GLenum name_error = tsr_packer_shader_name_error(p, shader);
    if (name_error) {
        tsr_packer_local_error(p, name_error);
        return;
    }
    uint64_t block = 0;
    for (GLsizei i = 0; i < count; i++) {
        if (!string[i]) {
            tsr_packer_drop(p, "ShaderSource", "a NULL string");
            return;
        }
        block = tsr_wire_align8(block) + 8 + source_length(string[i], length, i);
    }
    uint64_t llen = length ? (uint64_t)count * 4 : 0;
    uint64_t size = 16 + tsr_wire_align8(block) + 8 + llen;
    uint8_t *d = tsr_packer_cmd_var(p, TSR_OP_ShaderSource, size, 8);
    if (!d)
        return;
    tsr_wire_put_u32(d, shader);
    tsr_wire_put_u32(d + 4, (uint32_t)count);
    tsr_wire_put_u64(d + 8, string ? block : TSR_WIRE_NULL);
    uint64_t q = 0;
    uint8_t *b = d + 16;
    for (GLsizei i = 0; i < count; i++) {
        uint64_t end = tsr_wire_align8(q);
        memset(b + q, 0, (size_t)(end - q));
        q = end;
        uint64_t s = source_length(string[i], length, i);
        tsr_wire_put_u64(b + q, s);
        memcpy(b + q + 8, string[i], (size_t)s);
        q += 8 + s;
    }
    uint64_t end = tsr_wire_align8(q);
    memset(b + q, 0, (size_t)(end - q));
    uint8_t *l = b + end;
    tsr_wire_put_u64(l, length ? llen : TSR_WIRE_NULL);
    if (length && llen)
        memcpy(l + 8, length, (size_t)llen);
}

void tsr_packer_custom_GetTexImage(tsr_packer *p, GLenum target, GLint level, GLenum format, GLenum type, void *pixels)
{
    const GLint args[4] = {(GLint)target, level, (GLint)format, (GLint)type};
    if (tsr_packer_get_into_pack_buffer(p, TSR_OP_GetTexImage, args, 4, pixels))
        return;
    uint32_t id = p->next_request++;
    uint8_t *d = tsr_packer_cmd_var(p, TSR_OP_GetTexImage, 24, 8);
    if (!d)
        return;
    tsr_wire_put_u32(d, target);
    tsr_wire_put_u32(d + 4, (uint32_t)level);
    tsr_wire_put_u32(d + 8, format);
    tsr_wire_put_u32(d + 12, type);
    tsr_wire_put_u32(d + 16, id);
    tsr_wire_put_u32(d + 20, 0);
    size_t rsize = 0, pos = 0;
    uint64_t len;
    const uint8_t *r = tsr_packer_request(p, id, &rsize);
    if (!r)
        return;
    const uint8_t *whd = tsr_packer_reply_item(p, r, rsize, &pos, &len, "GetTexImage");
    if (!whd)
        return;
    if (len != 12) {
        tsr_packer_reply_bad(p, "GetTexImage", "its size item is not 12 bytes");
        return;
    }
    int32_t w = (int32_t)tsr_wire_get_u32(whd), h = (int32_t)tsr_wire_get_u32(whd + 4),
            depth = (int32_t)tsr_wire_get_u32(whd + 8);
    const uint8_t *img = tsr_packer_reply_item(p, r, rsize, &pos, &len, "GetTexImage");
    if (!img)
        return;
    tsr_pixel_layout lay;
    /* No layout: an empty level (0x0) or the application's unknown
     * format or type; nothing to copy either way. */
    if (tsr_pixel_layout_of(&p->pixels.pack, target == GL_TEXTURE_3D ? 3 : 2, w, h, depth, format, type, &lay) != 0)
        return;
    if (len != lay.extent) {
        char why[96];
        snprintf(why, sizeof why, "%llu image bytes, %llu expected", (unsigned long long)len,
                 (unsigned long long)lay.extent);
        tsr_packer_reply_bad(p, "GetTexImage", why);
        return;
    }
    if (pixels)
        tsr_pixel_copy_spans(&lay, h, depth, pixels, img);
}
