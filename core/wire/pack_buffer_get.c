/* core/wire/pack_buffer_get.c — gets that write into a pixel pack buffer
 * (GL 2.1 pixel buffer objects): with a GL_PIXEL_PACK_BUFFER bound, the
 * pointer of glReadPixels, glGetTexImage, glGetPolygonStipple,
 * glGetPixelMap* and glGetCompressedTexImage is an offset into that buffer
 * and the answer stays in GL's memory. The packer sends such a get as one
 * PackBufferGetTSR (the get's opcode, its arguments, the offset) with no
 * reply; the unpacker makes the get itself with the offset as the pointer,
 * only while a pack buffer is bound on its side (GL then bounds-checks the
 * write in the buffer), so a stream never has the receiver's GL write to
 * an address of its choosing. Owns nothing. Never: writes the program's
 * memory, waits for a reply. */
#include <string.h>

#include "tessera/dev/pack.h"
#include "wire_gen.h"
#include "wire_internal.h"

#define BAD(...) return tsr_error_set(err, TSR_EPROTO, __VA_ARGS__)

enum { PACK_BUFFER_GET_ARGS = 6, PACK_BUFFER_GET_BYTES = 4 + 4 * PACK_BUFFER_GET_ARGS + 4 + 8 };

int tsr_packer_get_into_pack_buffer(tsr_packer *p, uint32_t command, const GLint *args, int nargs, const void *offset)
{
    if (!p->pixels.pack_buffer)
        return 0;
    GLint all[PACK_BUFFER_GET_ARGS] = {0};
    for (int i = 0; i < nargs && i < PACK_BUFFER_GET_ARGS; i++)
        all[i] = args[i];
    tsr_packer_custom_PackBufferGetTSR(p, command, all, (GLintptr)(uintptr_t)offset);
    return 1;
}

void tsr_packer_custom_PackBufferGetTSR(tsr_packer *p, GLuint command, const GLint *args, GLintptr offset)
{
    uint8_t *d = tsr_packer_cmd_var(p, TSR_OP_PackBufferGetTSR, PACK_BUFFER_GET_BYTES, 8);
    if (!d)
        return;
    tsr_wire_put_u32(d, command);
    for (int i = 0; i < PACK_BUFFER_GET_ARGS; i++)
        tsr_wire_put_u32(d + 4 + 4 * i, (uint32_t)(args ? args[i] : 0));
    tsr_wire_put_u32(d + 28, 0);
    tsr_wire_put_u64(d + 32, (uint64_t)offset);
}

int tsr_unpack_custom_PackBufferGetTSR(tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len,
                                       size_t *pos, tsr_error *err)
{
    size_t at = (size_t)tsr_wire_align8(*pos);
    if (at > len || len - at < PACK_BUFFER_GET_BYTES)
        BAD("command PackBufferGetTSR at data offset %zu: truncated", *pos);
    uint32_t command = tsr_wire_get_u32(b + at);
    GLint a[PACK_BUFFER_GET_ARGS];
    for (int i = 0; i < PACK_BUFFER_GET_ARGS; i++)
        a[i] = (GLint)tsr_wire_get_u32(b + at + 4 + 4 * i);
    void *offset = (void *)(uintptr_t)tsr_wire_get_u64(b + at + 32);
    if (!u->pixels.pack_buffer)
        BAD("command PackBufferGetTSR at data offset %zu: no pixel pack buffer bound", at);
    switch (command) {
    case TSR_OP_ReadPixels: tsr_call_ReadPixels(d, a[0], a[1], a[2], a[3], (GLenum)a[4], (GLenum)a[5], offset); break;
    case TSR_OP_GetTexImage: tsr_call_GetTexImage(d, (GLenum)a[0], a[1], (GLenum)a[2], (GLenum)a[3], offset); break;
    case TSR_OP_GetPolygonStipple: tsr_call_GetPolygonStipple(d, offset); break;
    case TSR_OP_GetPixelMapfv: tsr_call_GetPixelMapfv(d, (GLenum)a[0], offset); break;
    case TSR_OP_GetPixelMapuiv: tsr_call_GetPixelMapuiv(d, (GLenum)a[0], offset); break;
    case TSR_OP_GetPixelMapusv: tsr_call_GetPixelMapusv(d, (GLenum)a[0], offset); break;
    case TSR_OP_GetCompressedTexImage: tsr_call_GetCompressedTexImage(d, (GLenum)a[0], a[1], offset); break;
    default: BAD("command PackBufferGetTSR at data offset %zu: %u is no get into a pack buffer", at, command);
    }
    *pos = at + PACK_BUFFER_GET_BYTES;
    return 0;
}
