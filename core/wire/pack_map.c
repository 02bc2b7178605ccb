/* core/wire/pack_map.c — glMapBuffer, glUnmapBuffer and
 * glGetBufferPointerv for a packer, whose receiver holds the buffer
 * objects. glMapBuffer reads the bound buffer's size and contents from
 * the receiver (two requests) into client memory the program may read
 * and write; glUnmapBuffer sends that memory back as one glBufferSubData
 * of the whole buffer unless it was mapped GL_READ_ONLY, so what the
 * program wrote reaches the receiver at unmap, as GL says. The opcodes
 * MapBuffer and UnmapBuffer never travel: an unpacker refuses them
 * (unpack.c).
 *
 * Owns: the mapped copies (tsr_packer.mapped, one per target; freed at
 * unmap and by tsr_packer_destroy). A mapping belongs to the target, not
 * to the buffer object: rebinding the target while mapped (which GL
 * allows) is not followed. Never: maps twice, returns memory it does not
 * own. */
#include <stdlib.h>
#include <string.h>

#include "tessera/dev/pack.h"
#include "wire_gen.h"
#include "wire_internal.h"

static struct tsr_packer_mapping *mapping_of(tsr_packer *p, GLenum target)
{
    static const GLenum targets[4] = {GL_ARRAY_BUFFER, GL_ELEMENT_ARRAY_BUFFER, GL_PIXEL_PACK_BUFFER,
                                      GL_PIXEL_UNPACK_BUFFER};
    for (int i = 0; i < 4; i++)
        if (targets[i] == target) {
            p->mapped[i].target = target;
            return &p->mapped[i];
        }
    return NULL;
}

int tsr_packer_buffer_mapped(tsr_packer *p, GLenum target)
{
    const struct tsr_packer_mapping *m = mapping_of(p, target);
    return m && m->data;
}

/* The name bound to `target` in the mirrors. */
static GLuint bound_name(const tsr_packer *p, GLenum target)
{
    switch (target) {
    case GL_ARRAY_BUFFER: return p->arrays.array_buffer;
    case GL_ELEMENT_ARRAY_BUFFER: return p->arrays.element_buffer;
    case GL_PIXEL_PACK_BUFFER: return p->pixels.pack_buffer;
    case GL_PIXEL_UNPACK_BUFFER: return p->pixels.unpack_buffer;
    default: return 0;
    }
}

void tsr_packer_forget_mappings(tsr_packer *p, GLsizei n, const GLuint *buffers)
{
    for (size_t k = 0; k < sizeof p->mapped / sizeof p->mapped[0]; k++) {
        struct tsr_packer_mapping *m = &p->mapped[k];
        for (GLsizei i = 0; m->data && buffers && i < n; i++)
            if (buffers[i] && buffers[i] == m->buffer) {
                /* GL unmaps a deleted buffer; what was written is lost
                 * with it (nothing is sent) */
                free(m->data);
                m->data = NULL;
                m->size = 0;
                m->buffer = 0;
            }
    }
}

void *tsr_packer_custom_MapBuffer(tsr_packer *p, GLenum target, GLenum access)
{
    struct tsr_packer_mapping *m = mapping_of(p, target);
    if (!m || m->data || (access != GL_READ_ONLY && access != GL_WRITE_ONLY && access != GL_READ_WRITE))
        return NULL; /* GL: INVALID_ENUM or INVALID_OPERATION (already mapped), NULL */
    GLint size = 0;
    tsr_pack_GetBufferParameteriv(p, target, GL_BUFFER_SIZE, &size);
    if (size <= 0)
        return NULL; /* no buffer bound, or an empty one */
    void *data = malloc((size_t)size);
    if (!data) {
        tsr_packer_drop(p, "MapBuffer", "out of memory for the mapped copy");
        return NULL;
    }
    /* also for GL_WRITE_ONLY: the whole buffer goes back at unmap, so the
     * bytes the program leaves alone must be the receiver's */
    memset(data, 0, (size_t)size);
    tsr_pack_GetBufferSubData(p, target, 0, size, data);
    m->data = data;
    m->size = size;
    m->access = access;
    m->buffer = bound_name(p, target);
    return data;
}

GLboolean tsr_packer_custom_UnmapBuffer(tsr_packer *p, GLenum target)
{
    struct tsr_packer_mapping *m = mapping_of(p, target);
    if (!m || !m->data)
        return GL_FALSE; /* GL: INVALID_OPERATION, not mapped */
    if (m->access != GL_READ_ONLY)
        tsr_pack_BufferSubData(p, target, 0, m->size, m->data);
    free(m->data);
    m->data = NULL;
    m->size = 0;
    return GL_TRUE;
}

void tsr_packer_local_GetBufferPointerv(tsr_packer *p, GLenum target, GLenum pname, void **params)
{
    struct tsr_packer_mapping *m = mapping_of(p, target);
    if (params && pname == GL_BUFFER_MAP_POINTER)
        *params = m ? m->data : NULL;
}
