/* core/state/state_map.c — glMapBuffer, glMapBufferRange,
 * glFlushMappedBufferRange, glUnmapBuffer and glGetBufferPointerv on the
 * tracker's own copy of a buffer object (vertex, index and pixel unpack
 * buffers, which only the stream writes, and pixel pack buffers, which a
 * wall writes into the tracker's copy itself: spus/tilesort/pack_buffer.c).
 * The program gets the tracker's copy itself (from the range's offset), so
 * a read mapping gives the tracked bytes and what it writes is the tracked
 * contents; glUnmapBuffer of a write mapping makes it a new version of
 * the buffer, which the next diff sends whole to every renderer that uses
 * it (tilesort's servers, late joiners), as the packer's glBufferSubData
 * would. The invalidate and unsynchronized bits change nothing here (the
 * copy is never busy), and a GL_MAP_FLUSH_EXPLICIT_BIT mapping keeps what
 * the program wrote outside the ranges it flushed, as a driver that maps
 * its storage does (GL leaves those bytes undefined).
 *
 * The errors are GL's, in Mesa's order (core/wire/pack_map.c lists them;
 * tsr_map_range_error, shared with the packer, checks the range and the
 * bits): raised with st_error, the call changing nothing.
 *
 * Owns nothing beyond the bufobj's mapping fields. Never hands out memory
 * other than the bufobj's data; a glBufferData while mapped frees it (GL
 * unmaps the buffer then too: the old pointer is invalid). */
#include "state_internal.h"
#include "tessera/dev/pack.h"


/* The buffer bound to `target`, or NULL with GL's error raised: an unknown
 * target GL_INVALID_ENUM, none bound GL_INVALID_OPERATION. */
static st_bufobj *bound_or_error(tsr_state_ctx *c, GLenum target)
{
    st_bufobj *b = st_bound_buffer(c, target);
    if (!b)
        st_error(c, target == GL_ARRAY_BUFFER || target == GL_ELEMENT_ARRAY_BUFFER || target == GL_PIXEL_PACK_BUFFER ||
                            target == GL_PIXEL_UNPACK_BUFFER
                        ? GL_INVALID_OPERATION
                        : GL_INVALID_ENUM);
    return b;
}

static int refused(tsr_state_ctx *c, GLenum e)
{
    if (e)
        st_error(c, e);
    return e != 0;
}

/* Whether `length` bytes from `offset` (neither negative) pass `size`
 * bytes, without the sum overflowing. */
static int past_end(GLintptr offset, GLsizeiptr length, GLsizeiptr size)
{
    return offset > size || length > size - offset;
}

static void *map(tsr_state_ctx *c, st_bufobj *b, GLintptr offset, GLsizeiptr length, GLbitfield access)
{
    if (refused(c, b->mapped ? GL_INVALID_OPERATION : !b->data || length <= 0 ? GL_OUT_OF_MEMORY : 0))
        return NULL;
    b->mapped = 1;
    b->map_access = access;
    b->map_offset = offset;
    b->map_length = length;
    return b->data + offset;
}

static void *st_MapBuffer(void *self, GLenum target, GLenum access)
{
    tsr_state_ctx *c = self;
    GLbitfield bits = access == GL_READ_ONLY    ? GL_MAP_READ_BIT
                      : access == GL_WRITE_ONLY ? GL_MAP_WRITE_BIT
                      : access == GL_READ_WRITE ? GL_MAP_READ_BIT | GL_MAP_WRITE_BIT
                                                : 0;
    if (refused(c, bits ? 0 : GL_INVALID_ENUM))
        return NULL;
    st_bufobj *b = bound_or_error(c, target);
    return b ? map(c, b, 0, b->size, bits) : NULL;
}

static void *st_MapBufferRange(void *self, GLenum target, GLintptr offset, GLsizeiptr length, GLbitfield access)
{
    tsr_state_ctx *c = self;
    st_bufobj *b = bound_or_error(c, target);
    if (!b || refused(c, tsr_map_range_error(offset, length, access)) ||
        refused(c, past_end(offset, length, b->size) ? GL_INVALID_VALUE : 0))
        return NULL;
    return map(c, b, offset, length, access);
}

static void st_FlushMappedBufferRange(void *self, GLenum target, GLintptr offset, GLsizeiptr length)
{
    tsr_state_ctx *c = self;
    st_bufobj *b = bound_or_error(c, target);
    if (b)
        refused(c, offset < 0 || length < 0                                     ? GL_INVALID_VALUE
                   : !b->mapped || !(b->map_access & GL_MAP_FLUSH_EXPLICIT_BIT) ? GL_INVALID_OPERATION
                   : past_end(offset, length, b->map_length)                    ? GL_INVALID_VALUE
                                                                                : 0);
    /* the bytes are the tracked copy already; the unmap makes the version */
}

static GLboolean st_UnmapBuffer(void *self, GLenum target)
{
    tsr_state_ctx *c = self;
    st_bufobj *b = bound_or_error(c, target);
    if (!b || refused(c, b->mapped ? 0 : GL_INVALID_OPERATION))
        return GL_FALSE;
    b->mapped = 0;
    if (b->map_access & GL_MAP_WRITE_BIT) {
        b->version++;
        st_mark(c, TSR_SM_BUFBIND);
    }
    return GL_TRUE;
}

static void st_GetBufferPointerv(void *self, GLenum target, GLenum pname, void **params)
{
    st_bufobj *b = st_bound_buffer(self, target);
    if (params && pname == GL_BUFFER_MAP_POINTER)
        *params = b && b->mapped ? b->data + b->map_offset : NULL;
}

void st_map_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d)
{
#define SET(name) tsr_set_##name(d, st_##name, c)
    SET(MapBuffer);
    SET(MapBufferRange);
    SET(FlushMappedBufferRange);
    SET(UnmapBuffer);
    SET(GetBufferPointerv);
#undef SET
}
