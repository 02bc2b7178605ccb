/* core/wire/pack_map.c — glMapBuffer, glMapBufferRange,
 * glFlushMappedBufferRange, glUnmapBuffer and glGetBufferPointerv for a
 * packer, whose receiver holds the buffer objects. A mapping is client
 * memory holding a copy of the mapped range: read from the receiver
 * (glGetBufferSubData, after glGetBufferParameteriv of the size) unless
 * the program invalidated the range or the buffer, since then GL leaves
 * the old bytes undefined. What the program wrote goes back as
 * glBufferSubData: the whole range at unmap for a GL_MAP_WRITE_BIT
 * mapping, or, for one with GL_MAP_FLUSH_EXPLICIT_BIT, each range the
 * program flushes, at its glFlushMappedBufferRange (GL leaves bytes written
 * and never flushed undefined: they are not sent). A mapping for reading
 * only sends nothing. The opcodes MapBuffer, MapBufferRange,
 * FlushMappedBufferRange and UnmapBuffer never travel: an unpacker refuses
 * them (unpack.c).
 *
 * The errors are GL's (Mesa's checks, in its order), raised here as the
 * packer's local error: a target other than the four buffer targets of GL
 * 2.1 GL_INVALID_ENUM; no buffer bound, a buffer already mapped, a length
 * of 0, neither read nor write, read with an invalidate or unsynchronized
 * bit, flush-explicit without write GL_INVALID_OPERATION; a negative
 * offset or length, an unknown bit or a range past the buffer's end
 * GL_INVALID_VALUE. A flush of a buffer not mapped or not mapped with
 * GL_MAP_FLUSH_EXPLICIT_BIT is GL_INVALID_OPERATION, one past the mapped
 * range GL_INVALID_VALUE.
 *
 * Owns: the mapped copies (tsr_packer.mapped, one per mapped buffer
 * object, found by the name bound to the call's target in the mirrors;
 * freed at unmap, when the buffer is deleted, and by tsr_packer_destroy).
 * Never: maps a buffer twice, returns memory it does not own, sends bytes
 * the program did not declare written. */
#include <stdlib.h>
#include <string.h>

#include "tessera/dev/pack.h"
#include "wire_gen.h"
#include "wire_internal.h"

enum {
    MAP_ALL_BITS = GL_MAP_READ_BIT | GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_RANGE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT |
                   GL_MAP_FLUSH_EXPLICIT_BIT | GL_MAP_UNSYNCHRONIZED_BIT,
    MAP_INVALIDATES = GL_MAP_INVALIDATE_RANGE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT,
};

#define MAPPING_SLOTS (sizeof((tsr_packer *)0)->mapped / sizeof((tsr_packer *)0)->mapped[0])

/* The name bound to `target` in the mirrors; *known 0 for a target that
 * is not a buffer target of GL 2.1. */
static GLuint bound_name(const tsr_packer *p, GLenum target, int *known)
{
    *known = 1;
    switch (target) {
    case GL_ARRAY_BUFFER: return p->arrays.array_buffer;
    case GL_ELEMENT_ARRAY_BUFFER: return p->arrays.element_buffer;
    case GL_PIXEL_PACK_BUFFER: return p->pixels.pack_buffer;
    case GL_PIXEL_UNPACK_BUFFER: return p->pixels.unpack_buffer;
    default: *known = 0; return 0;
    }
}

static struct tsr_packer_mapping *mapping_of_buffer(tsr_packer *p, GLuint buffer)
{
    for (size_t i = 0; buffer && i < MAPPING_SLOTS; i++)
        if (p->mapped[i].data && p->mapped[i].buffer == buffer)
            return &p->mapped[i];
    return NULL;
}

/* GL's error for a call on the buffer bound to `target` (0 when there is
 * one): an unknown target, or no buffer bound. */
static GLenum target_error(const tsr_packer *p, GLenum target, GLuint *name)
{
    int known;
    *name = bound_name(p, target, &known);
    return !known ? GL_INVALID_ENUM : !*name ? GL_INVALID_OPERATION : 0;
}

/* Raises `e` when it is an error; returns whether it was. */
static int refused(tsr_packer *p, GLenum e)
{
    if (e)
        tsr_packer_local_error(p, e);
    return e != 0;
}

int tsr_packer_buffer_mapped(tsr_packer *p, GLenum target)
{
    int known;
    return mapping_of_buffer(p, bound_name(p, target, &known)) != NULL;
}

static void unmap(struct tsr_packer_mapping *m)
{
    free(m->data);
    memset(m, 0, sizeof *m);
}

void tsr_packer_forget_mappings(tsr_packer *p, GLsizei n, const GLuint *buffers)
{
    for (GLsizei i = 0; buffers && i < n; i++) {
        struct tsr_packer_mapping *m = mapping_of_buffer(p, buffers[i]);
        if (m)
            unmap(m); /* GL unmaps a deleted buffer; what was written is lost with it (nothing is sent) */
    }
}

GLenum tsr_map_range_error(GLintptr offset, GLsizeiptr length, GLbitfield access)
{
    if (offset < 0 || length < 0)
        return GL_INVALID_VALUE;
    if (length == 0)
        return GL_INVALID_OPERATION;
    if (access & ~(GLbitfield)MAP_ALL_BITS)
        return GL_INVALID_VALUE;
    if (!(access & (GL_MAP_READ_BIT | GL_MAP_WRITE_BIT)))
        return GL_INVALID_OPERATION;
    if ((access & GL_MAP_READ_BIT) && (access & (MAP_INVALIDATES | GL_MAP_UNSYNCHRONIZED_BIT)))
        return GL_INVALID_OPERATION;
    if ((access & GL_MAP_FLUSH_EXPLICIT_BIT) && !(access & GL_MAP_WRITE_BIT))
        return GL_INVALID_OPERATION;
    return 0;
}

/* Whether `length` bytes from `offset` (neither negative) pass `size`
 * bytes, without the sum overflowing. */
static int past_end(GLintptr offset, GLsizeiptr length, GLsizeiptr size)
{
    return offset > size || length > size - offset;
}

/* Maps `length` bytes from `offset` (whole: the whole buffer, glMapBuffer)
 * of buffer `name`, bound to `target`, once the earlier checks passed. */
static void *map_range(tsr_packer *p, const char *command, GLenum target, GLuint name, GLintptr offset,
                       GLsizeiptr length, int whole, GLbitfield access)
{
    GLint size = 0;
    tsr_pack_GetBufferParameteriv(p, target, GL_BUFFER_SIZE, &size);
    if (whole)
        length = size;
    if (refused(p, !whole && past_end(offset, length, size) ? GL_INVALID_VALUE
                   : mapping_of_buffer(p, name)             ? GL_INVALID_OPERATION /* already mapped */
                   : length <= 0 ? GL_OUT_OF_MEMORY /* glMapBuffer of a buffer without storage */
                                 : 0))
        return NULL;
    struct tsr_packer_mapping *m = NULL;
    for (size_t i = 0; !m && i < MAPPING_SLOTS; i++)
        if (!p->mapped[i].data)
            m = &p->mapped[i];
    void *data = m ? calloc(1, (size_t)length) : NULL;
    if (!data) {
        /* every slot taken needs five buffers mapped at once, through
         * rebinding: refused as a driver out of room for mappings is */
        tsr_packer_local_error(p, GL_OUT_OF_MEMORY);
        tsr_packer_drop(p, command, m ? "out of memory for the mapped copy" : "more than four buffers mapped");
        return NULL;
    }
    /* also for a write mapping: the range goes back whole at unmap (or in
     * flushed parts), so the bytes the program leaves alone must be the
     * receiver's; an invalidated range's old bytes are undefined */
    if (!(access & MAP_INVALIDATES))
        tsr_pack_GetBufferSubData(p, target, offset, length, data);
    *m =
        (struct tsr_packer_mapping){.access = access, .buffer = name, .offset = offset, .length = length, .data = data};
    return data;
}

void *tsr_packer_custom_MapBuffer(tsr_packer *p, GLenum target, GLenum access)
{
    GLbitfield bits = access == GL_READ_ONLY    ? GL_MAP_READ_BIT
                      : access == GL_WRITE_ONLY ? GL_MAP_WRITE_BIT
                      : access == GL_READ_WRITE ? GL_MAP_READ_BIT | GL_MAP_WRITE_BIT
                                                : 0;
    GLuint name;
    if (refused(p, !bits ? GL_INVALID_ENUM : target_error(p, target, &name)))
        return NULL;
    return map_range(p, "MapBuffer", target, name, 0, 0, 1, bits);
}

void *tsr_packer_custom_MapBufferRange(tsr_packer *p, GLenum target, GLintptr offset, GLsizeiptr length,
                                       GLbitfield access)
{
    GLuint name;
    GLenum e = target_error(p, target, &name);
    if (refused(p, e ? e : tsr_map_range_error(offset, length, access)))
        return NULL;
    return map_range(p, "MapBufferRange", target, name, offset, length, 0, access);
}

void tsr_packer_custom_FlushMappedBufferRange(tsr_packer *p, GLenum target, GLintptr offset, GLsizeiptr length)
{
    GLuint name;
    GLenum e = target_error(p, target, &name);
    const struct tsr_packer_mapping *m = mapping_of_buffer(p, name);
    if (refused(p, e                                                ? e
                   : offset < 0 || length < 0                       ? GL_INVALID_VALUE
                   : !m || !(m->access & GL_MAP_FLUSH_EXPLICIT_BIT) ? GL_INVALID_OPERATION
                   : past_end(offset, length, m->length)            ? GL_INVALID_VALUE
                                                                    : 0))
        return;
    if (length > 0)
        tsr_pack_BufferSubData(p, target, m->offset + offset, length, (const uint8_t *)m->data + offset);
}

GLboolean tsr_packer_custom_UnmapBuffer(tsr_packer *p, GLenum target)
{
    GLuint name;
    GLenum e = target_error(p, target, &name);
    struct tsr_packer_mapping *m = mapping_of_buffer(p, name);
    if (refused(p, e ? e : !m ? GL_INVALID_OPERATION : 0))
        return GL_FALSE;
    if ((m->access & GL_MAP_WRITE_BIT) && !(m->access & GL_MAP_FLUSH_EXPLICIT_BIT))
        tsr_pack_BufferSubData(p, target, m->offset, m->length, m->data);
    unmap(m);
    return GL_TRUE;
}

/* glMapBuffer's access enum of a mapping, as Mesa gives it back for
 * GL_BUFFER_ACCESS (also for a glMapBufferRange mapping). */
GLenum tsr_map_access_enum(GLbitfield access)
{
    if ((access & GL_MAP_READ_BIT) && !(access & GL_MAP_WRITE_BIT))
        return GL_READ_ONLY;
    if ((access & GL_MAP_WRITE_BIT) && !(access & GL_MAP_READ_BIT))
        return GL_WRITE_ONLY;
    return GL_READ_WRITE;
}

int tsr_packer_answer_buffer_mapping(tsr_packer *p, GLenum target, GLenum pname, GLint *params)
{
    int known;
    const struct tsr_packer_mapping *m = mapping_of_buffer(p, bound_name(p, target, &known));
    if (!m || !params)
        return 0;
    switch (pname) {
    case GL_BUFFER_MAPPED: *params = GL_TRUE; return 1;
    case GL_BUFFER_ACCESS: *params = (GLint)tsr_map_access_enum(m->access); return 1;
    case GL_BUFFER_ACCESS_FLAGS: *params = (GLint)m->access; return 1;
    case GL_BUFFER_MAP_OFFSET: *params = (GLint)m->offset; return 1;
    case GL_BUFFER_MAP_LENGTH: *params = (GLint)m->length; return 1;
    default: return 0;
    }
}

void tsr_packer_local_GetBufferPointerv(tsr_packer *p, GLenum target, GLenum pname, void **params)
{
    int known;
    const struct tsr_packer_mapping *m = mapping_of_buffer(p, bound_name(p, target, &known));
    if (params && pname == GL_BUFFER_MAP_POINTER)
        *params = m ? m->data : NULL;
}
