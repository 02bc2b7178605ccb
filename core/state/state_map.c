/* core/state/state_map.c — glMapBuffer, glUnmapBuffer and
 * glGetBufferPointerv on the tracker's own copy of a buffer object (vertex,
 * index and pixel unpack buffers, which only the stream writes, and pixel
 * pack buffers, which a wall writes into the tracker's copy itself:
 * spus/tilesort/pack_buffer.c). The program gets the tracker's
 * copy itself, so what it writes is the tracked contents; glUnmapBuffer
 * makes it a new version of the buffer, which the next diff sends to every
 * renderer that uses it (tilesort's servers, late joiners), as the
 * packer's glBufferSubData would.
 *
 * Owns nothing beyond the bufobj's `mapped` flag. Never hands out memory
 * other than the bufobj's data; a glBufferData while mapped frees it (GL
 * unmaps the buffer then too: the old pointer is invalid). */
#include "state_internal.h"


static void *st_MapBuffer(void *self, GLenum target, GLenum access)
{
    tsr_state_ctx *c = self;
    st_bufobj *b = st_bound_buffer(c, target);
    if (!b || b->mapped || !b->data || (access != GL_READ_ONLY && access != GL_WRITE_ONLY && access != GL_READ_WRITE))
        return NULL;
    b->mapped = 1;
    b->map_access = access;
    return b->data;
}

static GLboolean st_UnmapBuffer(void *self, GLenum target)
{
    tsr_state_ctx *c = self;
    st_bufobj *b = st_bound_buffer(c, target);
    if (!b || !b->mapped)
        return GL_FALSE;
    b->mapped = 0;
    if (b->map_access != GL_READ_ONLY) {
        b->version++;
        st_mark(c, TSR_SM_BUFBIND);
    }
    return GL_TRUE;
}

static void st_GetBufferPointerv(void *self, GLenum target, GLenum pname, void **params)
{
    st_bufobj *b = st_bound_buffer(self, target);
    if (params && pname == GL_BUFFER_MAP_POINTER)
        *params = b && b->mapped ? b->data : NULL;
}

void st_map_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d)
{
#define SET(name) tsr_set_##name(d, st_##name, c)
    SET(MapBuffer);
    SET(UnmapBuffer);
    SET(GetBufferPointerv);
#undef SET
}
