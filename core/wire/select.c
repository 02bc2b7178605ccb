/* core/wire/select.c — selection and feedback on the wire (glSelectBuffer,
 * glFeedbackBuffer, glRenderMode; format in tessera/dev/wire.h).
 *
 * The program's selection and feedback buffers are client memory that GL
 * fills while the mode is GL_SELECT or GL_FEEDBACK, and the program reads
 * once glRenderMode has left that mode. So the packer keeps the program's
 * pointers and sends only their sizes; the unpacker gives its GL buffers of
 * its own (kept per context, for as long as GL may write them) and answers
 * glRenderMode with the return value, the mode left and the mode now, and
 * the values its GL wrote into the buffer of the mode left; the packer
 * copies those values into the program's buffer. What glRenderMode returns
 * and what the buffer holds are then the receiving GL's, exactly.
 *
 * Owns the packer's per-context pointers and the unpacker's buffers. Never
 * writes a program's buffer past the size the program gave; never sends a
 * host pointer; never frees a buffer the receiving GL may still hold (a
 * glSelectBuffer GL refuses leaves it the previous one: such buffers are
 * kept until their context is destroyed). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pack_internal.h"
#include "tessera/dev/wire.h"
#include "wire_gen.h"
#include "wire_internal.h"

#define BAD(...) return tsr_error_set(err, TSR_EPROTO, __VA_ARGS__)

enum { SEL, FB, KINDS }; /* the selection buffer, the feedback buffer */

/* A buffer of `cap` 4-byte values (the unpacker's own memory). */
typedef struct sel_block {
    void *mem;
    GLsizei cap;
} sel_block;

typedef struct sel_record {
    int32_t context; /* the stream's context it belongs to */
    int known;       /* 0: before the stream's first MakeCurrentTSR */
    GLenum mode;     /* packer: the mode the receiver reported last */
    /* packer: the program's buffer and the size it gave; unpacker: the
     * buffer last given to GL and its size */
    void *buf[KINDS];
    GLsizei size[KINDS];
    sel_block *kept; /* unpacker: every buffer given to GL, freed with the record */
    size_t nkept;
} sel_record;

struct tsr_wire_selection {
    sel_record *r;
    size_t n, cap;
};

static void record_free(sel_record *r)
{
    for (size_t i = 0; i < r->nkept; i++)
        free(r->kept[i].mem);
    free(r->kept);
}

void tsr_wire_selection_free(tsr_wire_selection *s)
{
    for (size_t i = 0; s && i < s->n; i++)
        record_free(&s->r[i]);
    if (s)
        free(s->r);
    free(s);
}

void tsr_wire_selection_forget(tsr_wire_selection *s, GLint context)
{
    for (size_t i = 0; s && i < s->n; i++)
        if (s->r[i].known && s->r[i].context == context) {
            record_free(&s->r[i]);
            s->r[i] = s->r[--s->n];
            return;
        }
}

/* The record of the stream's current context (`known` 0: no MakeCurrentTSR
 * yet), made when missing; NULL when out of memory. A stream's first
 * context keeps what was set before its MakeCurrentTSR, as the other
 * mirrors do. */
static sel_record *record_of(tsr_wire_selection **sp, int known, int32_t context, int make)
{
    tsr_wire_selection *s = *sp;
    sel_record *unknown = NULL;
    for (size_t i = 0; s && i < s->n; i++) {
        if (s->r[i].known == known && (!known || s->r[i].context == context))
            return &s->r[i];
        if (!s->r[i].known)
            unknown = &s->r[i];
    }
    if (known && unknown) {
        unknown->known = 1;
        unknown->context = context;
        return unknown;
    }
    if (!make)
        return NULL;
    if (!s && !(s = *sp = calloc(1, sizeof *s)))
        return NULL;
    if (s->n == s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 4;
        sel_record *r = realloc(s->r, cap * sizeof *r);
        if (!r)
            return NULL;
        s->r = r;
        s->cap = cap;
    }
    sel_record *r = &s->r[s->n++];
    *r = (sel_record){.context = context, .known = known, .mode = GL_RENDER};
    return r;
}

/* --- packer ------------------------------------------------------------------- */

static sel_record *pack_record_now(tsr_packer *p, int make)
{
    return record_of(&p->selection, p->context_known, p->context, make);
}

GLenum tsr_packer_render_mode(tsr_packer *p)
{
    const sel_record *r = pack_record_now(p, 0);
    return r ? r->mode : GL_RENDER;
}

int tsr_packer_answer_GetPointerv(tsr_packer *p, GLenum pname, void **params)
{
    if (pname != GL_SELECTION_BUFFER_POINTER && pname != GL_FEEDBACK_BUFFER_POINTER)
        return 0;
    const sel_record *r = pack_record_now(p, 0);
    if (params)
        *params = r ? r->buf[pname == GL_SELECTION_BUFFER_POINTER ? SEL : FB] : NULL;
    return 1;
}

/* The program's buffer becomes the one GL will fill, unless GL refuses the
 * call: a negative size, or the mode that fills it is on (GL 2.1, 5.2 and
 * 5.3: INVALID_VALUE, INVALID_OPERATION; the receiver raises them). */
static void keep_client_buffer(tsr_packer *p, int kind, GLsizei size, void *buffer)
{
    sel_record *r = pack_record_now(p, 1);
    if (!r) {
        pack_record(p, TSR_ENOMEM, "out of memory keeping the %s buffer", kind == SEL ? "selection" : "feedback");
        return;
    }
    if (size < 0 || r->mode == (kind == SEL ? GL_SELECT : GL_FEEDBACK))
        return;
    r->buf[kind] = buffer;
    r->size[kind] = size;
}

void tsr_packer_custom_SelectBuffer(tsr_packer *p, GLsizei size, GLuint *buffer)
{
    uint8_t *d = tsr_packer_cmd_var(p, TSR_OP_SelectBuffer, 8, 8);
    if (!d)
        return;
    tsr_wire_put_u32(d, (uint32_t)size);
    tsr_wire_put_u32(d + 4, 0);
    keep_client_buffer(p, SEL, size, buffer);
}

void tsr_packer_custom_FeedbackBuffer(tsr_packer *p, GLsizei size, GLenum type, GLfloat *buffer)
{
    uint8_t *d = tsr_packer_cmd_var(p, TSR_OP_FeedbackBuffer, 8, 8);
    if (!d)
        return;
    tsr_wire_put_u32(d, (uint32_t)size);
    tsr_wire_put_u32(d + 4, type);
    if (type == GL_2D || type == GL_3D || type == GL_3D_COLOR || type == GL_3D_COLOR_TEXTURE ||
        type == GL_4D_COLOR_TEXTURE)
        keep_client_buffer(p, FB, size, buffer);
}

GLint tsr_packer_custom_RenderMode(tsr_packer *p, GLenum mode)
{
    uint32_t id = p->next_request++;
    uint8_t *d = tsr_packer_cmd_var(p, TSR_OP_RenderMode, 8, 8);
    if (!d)
        return 0;
    tsr_wire_put_u32(d, mode);
    tsr_wire_put_u32(d + 4, id);
    size_t rsize = 0, pos = 0;
    uint64_t len;
    const uint8_t *r = tsr_packer_request(p, id, &rsize);
    if (!r)
        return 0;
    const uint8_t *ret = tsr_packer_reply_item(p, r, rsize, &pos, &len, "RenderMode");
    if (!ret)
        return 0;
    if (len != 4) {
        tsr_packer_reply_bad(p, "RenderMode", "its return value is not 4 bytes");
        return 0;
    }
    const uint8_t *modes = tsr_packer_reply_item(p, r, rsize, &pos, &len, "RenderMode");
    if (!modes)
        return 0;
    if (len != 8) {
        tsr_packer_reply_bad(p, "RenderMode", "its modes item is not 8 bytes");
        return 0;
    }
    const uint8_t *values = tsr_packer_reply_item(p, r, rsize, &pos, &len, "RenderMode");
    if (!values)
        return 0;
    GLenum left = tsr_wire_get_u32(modes), now = tsr_wire_get_u32(modes + 4);
    sel_record *rec = pack_record_now(p, 1);
    if (!rec) {
        pack_record(p, TSR_ENOMEM, "out of memory keeping the render mode");
        return (GLint)tsr_wire_get_u32(ret);
    }
    rec->mode = now;
    int kind = left == GL_SELECT ? SEL : left == GL_FEEDBACK ? FB : -1;
    if (len % 4 || (kind < 0 && len)) {
        tsr_packer_reply_bad(p, "RenderMode", "its values do not fit the mode left");
        return 0;
    }
    if (kind >= 0 && rec->buf[kind]) {
        /* never past the size the program gave (a receiver whose GL kept a
         * larger buffer, after a glSelectBuffer it refused, says more) */
        uint64_t n = len / 4, room = rec->size[kind] > 0 ? (uint64_t)rec->size[kind] : 0;
        memcpy(rec->buf[kind], values, (size_t)((n < room ? n : room) * 4));
    }
    return (GLint)tsr_wire_get_u32(ret);
}

/* --- unpacker ------------------------------------------------------------------- */

static sel_record *unpack_record_now(tsr_unpacker *u)
{
    return record_of(&u->selection, u->context_known, u->context, 1);
}

/* A buffer of `size` values GL may fill: the record's, reused when it is
 * large enough, else a new one (the old one stays kept: GL may still hold
 * it if it refuses this call), at least twice the old one's size, so a
 * stream asking for one more value each time keeps few buffers. NULL when
 * out of memory or over the limit. */
static void *buffer_for(tsr_unpacker *u, sel_record *r, int kind, GLsizei size)
{
    GLsizei want = size > 0 ? size : 1;
    uint64_t limit = u->max_output / 4;
    for (size_t i = 0; i < r->nkept; i++)
        if (r->kept[i].mem == r->buf[kind]) {
            if (r->kept[i].cap >= want)
                return r->buf[kind];
            uint64_t twice = 2 * (uint64_t)r->kept[i].cap;
            if (twice > (uint64_t)want && twice <= limit && twice <= INT32_MAX)
                want = (GLsizei)twice;
        }
    if ((uint64_t)size > limit)
        return NULL;
    sel_block *k = realloc(r->kept, (r->nkept + 1) * sizeof *k);
    if (!k)
        return NULL;
    r->kept = k;
    void *mem = calloc((size_t)want, 4);
    if (!mem)
        return NULL;
    r->kept[r->nkept++] = (sel_block){.mem = mem, .cap = want};
    return mem;
}

static GLenum current_mode(const tsr_dispatch *d)
{
    GLint mode = GL_RENDER;
    tsr_call_GetIntegerv(d, GL_RENDER_MODE, &mode);
    return (GLenum)mode;
}

/* SelectBuffer and FeedbackBuffer: i32 size, u32 type (0 for SelectBuffer). */
static int unpack_buffer(tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len, size_t *pos,
                         tsr_error *err, int kind)
{
    const char *name = kind == SEL ? "SelectBuffer" : "FeedbackBuffer";
    size_t at = (size_t)tsr_wire_align8(*pos);
    if (at > len || len - at < 8)
        BAD("command %s at data offset %zu: truncated", name, *pos);
    GLsizei size = (GLsizei)tsr_wire_get_u32(b + at);
    GLenum type = tsr_wire_get_u32(b + at + 4);
    sel_record *r = unpack_record_now(u);
    if (!r)
        return tsr_error_set(err, TSR_ENOMEM, "command %s: out of memory for the buffer's record", name);
    void *buf;
    if (size < 0 || current_mode(d) == (kind == SEL ? GL_SELECT : GL_FEEDBACK)) {
        /* GL refuses it and keeps its buffer: nothing new to give it */
        static GLfloat unused;
        buf = r->buf[kind] ? r->buf[kind] : &unused;
    } else if (!(buf = buffer_for(u, r, kind, size))) {
        BAD("command %s at data offset %zu: a buffer of %d values is too large (max_reply_bytes %llu)", name, at, size,
            (unsigned long long)u->max_output);
    } else {
        r->buf[kind] = buf;
        r->size[kind] = size;
    }
    if (kind == SEL)
        tsr_call_SelectBuffer(d, size, buf);
    else
        tsr_call_FeedbackBuffer(d, size, type, buf);
    *pos = at + 8;
    return 0;
}

int tsr_unpack_custom_SelectBuffer(struct tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len,
                                   size_t *pos, tsr_error *err)
{
    return unpack_buffer(u, d, b, len, pos, err, SEL);
}

int tsr_unpack_custom_FeedbackBuffer(struct tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len,
                                     size_t *pos, tsr_error *err)
{
    return unpack_buffer(u, d, b, len, pos, err, FB);
}

/* The buffer GL fills in the mode being left and how many values it holds
 * (`max` at most): GL's own pointer when it is one of the record's buffers
 * (after a refused glSelectBuffer it is not the newest), else the newest. */
static const void *filled_buffer(const tsr_dispatch *d, const sel_record *r, int kind, GLsizei *max)
{
    void *gl = NULL;
    tsr_call_GetPointerv(d, kind == SEL ? GL_SELECTION_BUFFER_POINTER : GL_FEEDBACK_BUFFER_POINTER, &gl);
    GLint size = 0;
    tsr_call_GetIntegerv(d, kind == SEL ? GL_SELECTION_BUFFER_SIZE : GL_FEEDBACK_BUFFER_SIZE, &size);
    for (size_t i = 0; gl && i < r->nkept; i++)
        if (r->kept[i].mem == gl) {
            *max = size < r->kept[i].cap ? (size > 0 ? size : 0) : r->kept[i].cap;
            return gl;
        }
    *max = r->size[kind] > 0 ? r->size[kind] : 0;
    return r->buf[kind];
}

/* The values GL wrote: on overflow (return -1) the whole buffer; selection:
 * the `hits` records (each: name count n, min and max depth, n names);
 * feedback: `ret` values. */
static GLsizei values_written(int kind, GLint ret, const GLuint *buf, GLsizei max)
{
    if (!buf || ret < 0)
        return buf ? max : 0;
    if (kind == FB)
        return ret < max ? ret : max;
    uint64_t at = 0;
    for (GLint h = 0; h < ret && at < (uint64_t)max; h++)
        at += 3 + (uint64_t)buf[at];
    return at < (uint64_t)max ? (GLsizei)at : max;
}

int tsr_unpack_custom_RenderMode(struct tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len,
                                 size_t *pos, tsr_error *err)
{
    size_t at = (size_t)tsr_wire_align8(*pos);
    if (at > len || len - at < 8)
        BAD("command RenderMode at data offset %zu: truncated", *pos);
    GLenum mode = tsr_wire_get_u32(b + at);
    uint32_t id = tsr_wire_get_u32(b + at + 4);
    *pos = at + 8;
    GLenum left = current_mode(d);
    int kind = left == GL_SELECT ? SEL : left == GL_FEEDBACK ? FB : -1;
    const void *buf = NULL;
    GLsizei max = 0;
    if (kind >= 0) {
        sel_record *r = unpack_record_now(u);
        if (!r)
            return tsr_error_set(err, TSR_ENOMEM, "command RenderMode: out of memory for the buffer's record");
        buf = filled_buffer(d, r, kind, &max);
    }
    GLint ret = tsr_call_RenderMode(d, mode);
    uint32_t modes[2] = {left, current_mode(d)};
    GLsizei n = kind >= 0 ? values_written(kind, ret, buf, max) : 0;
    if (!u->reply)
        return 0;
    uint64_t sizes[2] = {sizeof modes, (uint64_t)n * 4};
    uint8_t *ptrs[2] = {(uint8_t *)modes, (uint8_t *)(uintptr_t)buf};
    return tsr_unpacker_reply(u, id, &ret, 4, 2, sizes, ptrs, err);
}
