/* spus/tilesort/pack_buffer.c — gets into the program's pixel pack buffer
 * on a wall (GL 2.1 pixel buffer objects). With a GL_PIXEL_PACK_BUFFER
 * bound, the pointer of glReadPixels, glGetTexImage, glGetPolygonStipple,
 * glGetPixelMap* and glGetCompressedTexImage is an offset into that
 * buffer, and the tracker keeps the buffer's bytes, which every server
 * gets from it (and glMapBuffer reads). So the answer is made as into
 * client memory and written into the buffer through the tracker with
 * glBufferSubData:
 *   glReadPixels: gathered from the tiles as always (frame.c), the pack
 *     buffer unbound meanwhile, into a copy of the buffer's bytes it
 *     covers (so the bytes GL leaves alone between rows stay);
 *   the other gets: asked of the first live server, into its own copy of
 *     the buffer (its packer sends PackBufferGetTSR), then that server's
 *     whole buffer is read back (one more round trip and the buffer's size
 *     in bytes: these gets are rare next to glReadPixels).
 * A call GL refuses (a region past the buffer's end, a bad format) goes
 * to one server, which raises the error and writes nothing. Owns nothing.
 * Never: writes through a pointer that is an offset. */
#include <stdlib.h>
#include <string.h>

#include "instance.h"

static GLuint pack_buffer(tilesort *t) { return tsr_state_values_of(t->ctx)->pixel_pack_buffer; }

int ts_pack_buffer_read_pixels(tilesort *t, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type,
                               void *pixels)
{
    GLuint buffer = pack_buffer(t);
    if (!buffer)
        return 0;
    const tsr_state_values *v = tsr_state_values_of(t->ctx);
    tsr_pixel_layout l;
    GLsizeiptr size = 0;
    const uint8_t *bytes = tsr_state_buffer_bytes(t->ctx, GL_PIXEL_PACK_BUFFER, &size);
    uint64_t offset = (uint64_t)(uintptr_t)pixels;
    if (w <= 0 || h <= 0 || !bytes || tsr_pixel_layout_of(&v->pixel_store.pack, 2, w, h, 1, format, type, &l) != 0 ||
        l.group_bytes == 0 || offset > (uint64_t)size || l.extent > (uint64_t)size - offset) {
        tsr_call_ReadPixels(&ts_to_server(t)->table, x, y, w, h, format, type, pixels);
        return 1;
    }
    uint8_t *copy = malloc(l.extent ? (size_t)l.extent : 1);
    if (!copy) {
        tsr_error e;
        tsr_error_set(&e, TSR_ENOMEM, "out of memory for glReadPixels into a pack buffer (%d x %d)", (int)w, (int)h);
        ts_report(t, &e);
        return 1;
    }
    memcpy(copy, bytes + offset, (size_t)l.extent);
    tsr_call_BindBuffer(&t->normal, GL_PIXEL_PACK_BUFFER, 0);
    ts_ReadPixels(t, x, y, w, h, format, type, copy);
    tsr_call_BindBuffer(&t->normal, GL_PIXEL_PACK_BUFFER, buffer);
    tsr_call_BufferSubData(&t->normal, GL_PIXEL_PACK_BUFFER, (GLintptr)offset, (GLsizeiptr)l.extent, copy);
    free(copy);
    return 1;
}

/* After server `s` wrote a get's answer into its pack buffer: the buffer
 * read back from it and given to the tracker, for every server. */
static void pull_pack_buffer(tilesort *t, ts_server *s)
{
    GLsizeiptr size = 0;
    if (!tsr_state_buffer_bytes(t->ctx, GL_PIXEL_PACK_BUFFER, &size) || size <= 0)
        return;
    uint8_t *copy = malloc((size_t)size);
    if (!copy) {
        tsr_error e;
        tsr_error_set(&e, TSR_ENOMEM, "out of memory for a pack buffer of %lld bytes", (long long)size);
        ts_report(t, &e);
        return;
    }
    tsr_call_GetBufferSubData(&s->table, GL_PIXEL_PACK_BUFFER, 0, size, copy);
    tsr_call_BufferSubData(&t->normal, GL_PIXEL_PACK_BUFFER, 0, size, copy);
    free(copy);
}

int ts_pack_buffer_stipple(tilesort *t, GLubyte *mask)
{
    if (!pack_buffer(t))
        return 0;
    ts_server *s = ts_to_server(t);
    tsr_call_GetPolygonStipple(&s->table, mask);
    pull_pack_buffer(t, s);
    return 1;
}

/* The gets a server answers (tilesort.c's R_SERVER route), with the pull
 * when a pack buffer is bound. */
#define SERVER_GET(call)                \
    do {                                \
        tilesort *t = self;             \
        ts_server *s = ts_to_server(t); \
        call;                           \
        if (pack_buffer(t))             \
            pull_pack_buffer(t, s);     \
    } while (0)

void ts_GetTexImage(void *self, GLenum target, GLint level, GLenum format, GLenum type, void *pixels)
{
    SERVER_GET(tsr_call_GetTexImage(&s->table, target, level, format, type, pixels));
}

void ts_GetCompressedTexImage(void *self, GLenum target, GLint level, void *img)
{
    SERVER_GET(tsr_call_GetCompressedTexImage(&s->table, target, level, img));
}

void ts_GetPixelMapfv(void *self, GLenum map, GLfloat *values)
{
    SERVER_GET(tsr_call_GetPixelMapfv(&s->table, map, values));
}

void ts_GetPixelMapuiv(void *self, GLenum map, GLuint *values)
{
    SERVER_GET(tsr_call_GetPixelMapuiv(&s->table, map, values));
}

void ts_GetPixelMapusv(void *self, GLenum map, GLushort *values)
{
    SERVER_GET(tsr_call_GetPixelMapusv(&s->table, map, values));
}
