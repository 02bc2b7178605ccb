/* tests/faker/map_buffer_range_driver.c — faker_map_buffer_range OUT.txt:
 * GL_ARB_map_buffer_range (glMapBufferRange, glFlushMappedBufferRange)
 * on a 64x48 EGL pbuffer, one labelled line per answer or read-back in
 * OUT.txt:
 *   the extension is offered (natively: OSMesa has it);
 *   glGetBufferParameteriv of the mapping (mapped, access, flags, offset,
 *     length) while mapped, also by glMapBuffer, and after the unmap;
 *   each access bit on a range in the middle of a buffer: GL_MAP_READ_BIT
 *     gives the buffer's bytes and GetBufferPointerv the pointer;
 *     GL_MAP_WRITE_BIT alone, with GL_MAP_READ_BIT, with
 *     GL_MAP_INVALIDATE_RANGE_BIT, GL_MAP_INVALIDATE_BUFFER_BIT or
 *     GL_MAP_UNSYNCHRONIZED_BIT writes part of the range and the buffer
 *     read back whole (glGetBufferSubData) shows it with the other bytes
 *     as they were (after an invalidation, only the range is shown: GL
 *     leaves the rest undefined); GL_MAP_FLUSH_EXPLICIT_BIT writes two
 *     parts and flushes them, one while a display list is compiled
 *     (GL runs the flush at once);
 *   vertices written through a range mapping, drawn across the wall's
 *     middle;
 *   a pixel pack buffer glReadPixels wrote (across the wall's tiles),
 *     a range of it mapped for reading: the renderers' bytes;
 *   a pixel unpack buffer written through an invalidating mapping,
 *     drawn with glDrawPixels;
 *   every error Mesa raises (target, no buffer, range, bits, a buffer
 *     already mapped, a flush of a buffer not mapped or not mapped for
 *     explicit flushes or past the range, an unmap of a buffer not mapped)
 *     with what the call returns.
 * Built with RECORDED_GL_NATIVE (faker_map_buffer_range_native) it makes
 * the same calls on OSMesa directly: the runs through tessera must write
 * the same file (gl21_commands.sh). */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "recorded_gl.h"

static FILE *out;

enum { SIZE = 64, AT = 16, LEN = 32 };

static void clear(void)
{
    glClearColor(0.1f, 0.1f, 0.2f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
}

static void bytes(const char *label, const GLubyte *b, int n)
{
    fprintf(out, "%s:", label);
    for (int i = 0; i < n; i++)
        fprintf(out, "%s%02x", i % 8 ? "" : " ", b[i]);
    fprintf(out, "\n");
}

/* A buffer of SIZE bytes i * 3 + 1 bound to GL_ARRAY_BUFFER. */
static GLuint fresh_buffer(void)
{
    GLubyte fill[SIZE];
    for (int i = 0; i < SIZE; i++)
        fill[i] = (GLubyte)(i * 3 + 1);
    GLuint b;
    glGenBuffers(1, &b);
    glBindBuffer(GL_ARRAY_BUFFER, b);
    glBufferData(GL_ARRAY_BUFFER, SIZE, fill, GL_DYNAMIC_DRAW);
    return b;
}

/* glUnmapBuffer of GL_ARRAY_BUFFER, its answer and then its error (two
 * statements: the order of a call's arguments is unspecified). */
static void unmap(const char *label)
{
    GLboolean done = glUnmapBuffer(GL_ARRAY_BUFFER);
    fprintf(out, "%s: %d, error 0x%x\n", label, done, glGetError());
}

/* The whole buffer, or (whole 0) only the mapped range, read back. */
static void read_back(const char *label, int whole)
{
    GLubyte back[SIZE];
    memset(back, 0xee, sizeof back);
    glGetBufferSubData(GL_ARRAY_BUFFER, 0, SIZE, back);
    char l[128];
    snprintf(l, sizeof l, "%s, read back%s", label, whole ? "" : " (the range)");
    if (whole)
        bytes(l, back, SIZE);
    else
        bytes(l, back + AT, LEN);
}

/* glGetBufferParameteriv of the mapping's pnames on GL_ARRAY_BUFFER. */
static void mapping_state(const char *label)
{
    static const GLenum pnames[] = {GL_BUFFER_SIZE,         GL_BUFFER_MAPPED,     GL_BUFFER_ACCESS,
                                    GL_BUFFER_ACCESS_FLAGS, GL_BUFFER_MAP_OFFSET, GL_BUFFER_MAP_LENGTH};
    fprintf(out, "%s: size, mapped, access, flags, offset, length:", label);
    for (size_t i = 0; i < sizeof pnames / sizeof pnames[0]; i++) {
        GLint v = -1;
        glGetBufferParameteriv(GL_ARRAY_BUFFER, pnames[i], &v);
        fprintf(out, " 0x%x", (unsigned)v);
    }
    fprintf(out, ", error 0x%x\n", glGetError());
}

/* One mapping of [AT, AT + LEN) with `access`: the bytes written are
 * 0xa0 + i at every third byte of the range, and the buffer read back. */
static void write_range(const char *label, GLbitfield access, int whole)
{
    GLuint b = fresh_buffer();
    GLubyte *m = glMapBufferRange(GL_ARRAY_BUFFER, AT, LEN, access);
    fprintf(out, "%s: %s, error 0x%x\n", label, m ? "mapped" : "NULL", glGetError());
    if (m) {
        mapping_state("  while mapped");
        if (access & GL_MAP_READ_BIT)
            bytes("  its bytes", m, LEN);
        for (int i = 0; i < LEN; i += 3)
            m[i] = (GLubyte)(0xa0 + i);
        if (access & (GL_MAP_INVALIDATE_RANGE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT))
            for (int i = 0; i < LEN; i++)
                if (i % 3)
                    m[i] = (GLubyte)i; /* the old bytes are undefined: all written */
        unmap("  UnmapBuffer");
    }
    read_back(label, whole);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glDeleteBuffers(1, &b);
}

static void access_bits(void)
{
    GLuint b = fresh_buffer();
    GLubyte *m = glMapBufferRange(GL_ARRAY_BUFFER, AT, LEN, GL_MAP_READ_BIT);
    void *pointer = NULL;
    glGetBufferPointerv(GL_ARRAY_BUFFER, GL_BUFFER_MAP_POINTER, &pointer);
    fprintf(out, "READ: %s, GetBufferPointerv gives it: %d, error 0x%x\n", m ? "mapped" : "NULL", m && pointer == m,
            glGetError());
    if (m)
        bytes("  its bytes", m, LEN);
    fprintf(out, "  UnmapBuffer: %d\n", glUnmapBuffer(GL_ARRAY_BUFFER));
    pointer = &pointer;
    glGetBufferPointerv(GL_ARRAY_BUFFER, GL_BUFFER_MAP_POINTER, &pointer);
    fprintf(out, "  GetBufferPointerv after unmap: %s\n", pointer ? "not NULL" : "NULL");
    mapping_state("  after unmap");
    void *whole = glMapBuffer(GL_ARRAY_BUFFER, GL_WRITE_ONLY);
    mapping_state("  glMapBuffer(GL_WRITE_ONLY)");
    if (whole)
        glUnmapBuffer(GL_ARRAY_BUFFER);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glDeleteBuffers(1, &b);

    write_range("WRITE", GL_MAP_WRITE_BIT, 1);
    write_range("READ|WRITE", GL_MAP_READ_BIT | GL_MAP_WRITE_BIT, 1);
    write_range("WRITE|INVALIDATE_RANGE", GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_RANGE_BIT, 1);
    write_range("WRITE|INVALIDATE_BUFFER", GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT, 0);
    write_range("WRITE|UNSYNCHRONIZED", GL_MAP_WRITE_BIT | GL_MAP_UNSYNCHRONIZED_BIT, 1);
    write_range("READ|WRITE|UNSYNCHRONIZED refused", GL_MAP_READ_BIT | GL_MAP_WRITE_BIT | GL_MAP_UNSYNCHRONIZED_BIT, 1);

    /* explicit flushes: two parts written and flushed (offsets within
     * the range), the second while a display list is compiled; nothing
     * written outside them */
    b = fresh_buffer();
    m = glMapBufferRange(GL_ARRAY_BUFFER, AT, LEN, GL_MAP_WRITE_BIT | GL_MAP_FLUSH_EXPLICIT_BIT);
    fprintf(out, "WRITE|FLUSH_EXPLICIT: %s, error 0x%x\n", m ? "mapped" : "NULL", glGetError());
    if (m) {
        memset(m + 2, 0x55, 4);
        glFlushMappedBufferRange(GL_ARRAY_BUFFER, 2, 4);
        fprintf(out, "  FlushMappedBufferRange 2+4: error 0x%x\n", glGetError());
        memset(m + 20, 0x66, 12);
        GLuint list = glGenLists(1);
        glNewList(list, GL_COMPILE);
        glFlushMappedBufferRange(GL_ARRAY_BUFFER, 20, 12);
        glEndList();
        glDeleteLists(list, 1);
        fprintf(out, "  FlushMappedBufferRange 20+12 in a list: error 0x%x\n", glGetError());
        glFlushMappedBufferRange(GL_ARRAY_BUFFER, 0, 0);
        fprintf(out, "  FlushMappedBufferRange of 0 bytes: error 0x%x\n", glGetError());
        unmap("  UnmapBuffer");
    }
    read_back("WRITE|FLUSH_EXPLICIT", 1);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glDeleteBuffers(1, &b);
}

/* Vertices written through mappings, drawn: a triangle's x moved right
 * (across the wall's middle) through a READ|WRITE mapping of its x and y,
 * the last vertex replaced through an invalidating one. */
static void drawn(void)
{
    static const GLfloat tri[6] = {-0.9f, -0.9f, 0.1f, -0.9f, -0.4f, 0.2f};
    GLuint b;
    glGenBuffers(1, &b);
    glBindBuffer(GL_ARRAY_BUFFER, b);
    glBufferData(GL_ARRAY_BUFFER, sizeof tri, tri, GL_DYNAMIC_DRAW);
    GLfloat *m = glMapBufferRange(GL_ARRAY_BUFFER, 0, 4 * sizeof(GLfloat), GL_MAP_READ_BIT | GL_MAP_WRITE_BIT);
    if (m) {
        m[0] += 0.8f;
        m[2] += 0.8f;
        glUnmapBuffer(GL_ARRAY_BUFFER);
    }
    m = glMapBufferRange(GL_ARRAY_BUFFER, 4 * sizeof(GLfloat), 2 * sizeof(GLfloat),
                         GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_RANGE_BIT);
    if (m) {
        m[0] = 0.4f;
        m[1] = 0.9f;
        glUnmapBuffer(GL_ARRAY_BUFFER);
    }
    clear();
    glColor3f(0.9f, 0.6f, 0.1f);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(2, GL_FLOAT, 0, (const void *)0);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisableClientState(GL_VERTEX_ARRAY);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glDeleteBuffers(1, &b);
    recorded_gl_frame(out, "drawn from vertices written through glMapBufferRange");
}

/* A pack buffer the renderers wrote (glReadPixels of a region across the
 * four tiles of the wall), a range of it mapped for reading; an unpack
 * buffer written through a mapping that invalidates it, drawn. */
static void pixel_buffers(void)
{
    enum { PACK = 40 * 30 * 4, PACK_AT = 1000, PACK_LEN = 2400 };
    clear();
    glColor3f(0.9f, 0.3f, 0.5f);
    glRectf(-0.6f, -0.5f, 0.4f, 0.7f);
    glColor3f(0.1f, 0.8f, 0.3f);
    glRectf(-0.2f, -0.9f, 0.9f, 0.1f);
    GLuint pack;
    glGenBuffers(1, &pack);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, pack);
    glBufferData(GL_PIXEL_PACK_BUFFER, PACK, NULL, GL_STREAM_READ);
    glReadPixels(12, 9, 40, 30, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    const GLubyte *m = glMapBufferRange(GL_PIXEL_PACK_BUFFER, PACK_AT, PACK_LEN, GL_MAP_READ_BIT);
    fprintf(out, "pack buffer range mapped: %s, fnv %08x, error 0x%x\n", m ? "yes" : "no",
            m ? recorded_gl_fnv(m, PACK_LEN) : 0, glGetError());
    if (m)
        bytes("  its first bytes", m, 16);
    fprintf(out, "  UnmapBuffer: %d\n", glUnmapBuffer(GL_PIXEL_PACK_BUFFER));
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glDeleteBuffers(1, &pack);

    GLuint unpack;
    glGenBuffers(1, &unpack);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, unpack);
    glBufferData(GL_PIXEL_UNPACK_BUFFER, 16 * 8 * 4, NULL, GL_STREAM_DRAW);
    GLubyte *w =
        glMapBufferRange(GL_PIXEL_UNPACK_BUFFER, 0, 16 * 8 * 4, GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT);
    if (w) {
        for (int i = 0; i < 16 * 8 * 4; i++)
            w[i] = (GLubyte)(i % 4 == 3 ? 255 : i * 7);
        glUnmapBuffer(GL_PIXEL_UNPACK_BUFFER);
    }
    clear();
    glWindowPos2i(24, 20);
    glDrawPixels(16, 8, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glDeleteBuffers(1, &unpack);
    recorded_gl_frame(out, "glDrawPixels from an unpack buffer written through glMapBufferRange");
}

static void map_error(const char *label, GLenum target, GLintptr offset, GLsizeiptr length, GLbitfield access)
{
    void *m = glMapBufferRange(target, offset, length, access);
    fprintf(out, "MapBufferRange %s: %s, error 0x%x\n", label, m ? "mapped" : "NULL", glGetError());
}

static void flush_error(const char *label, GLintptr offset, GLsizeiptr length)
{
    glFlushMappedBufferRange(GL_ARRAY_BUFFER, offset, length);
    fprintf(out, "FlushMappedBufferRange %s: error 0x%x\n", label, glGetError());
}

static void errors(void)
{
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    map_error("with no buffer bound", GL_ARRAY_BUFFER, 0, 4, GL_MAP_READ_BIT);
    flush_error("with no buffer bound", 0, 4);
    GLuint b = fresh_buffer();
    map_error("of a texture target", GL_TEXTURE_2D, 0, 4, GL_MAP_READ_BIT);
    map_error("at offset -1", GL_ARRAY_BUFFER, -1, 4, GL_MAP_READ_BIT);
    map_error("of length -1", GL_ARRAY_BUFFER, 0, -1, GL_MAP_READ_BIT);
    map_error("of length 0", GL_ARRAY_BUFFER, 0, 0, GL_MAP_READ_BIT);
    map_error("with an unknown bit", GL_ARRAY_BUFFER, 0, 4, GL_MAP_READ_BIT | 0x8000);
    map_error("neither read nor write", GL_ARRAY_BUFFER, 0, 4, GL_MAP_INVALIDATE_RANGE_BIT);
    map_error("READ|INVALIDATE_RANGE", GL_ARRAY_BUFFER, 0, 4, GL_MAP_READ_BIT | GL_MAP_INVALIDATE_RANGE_BIT);
    map_error("READ|INVALIDATE_BUFFER", GL_ARRAY_BUFFER, 0, 4, GL_MAP_READ_BIT | GL_MAP_INVALIDATE_BUFFER_BIT);
    map_error("READ|UNSYNCHRONIZED", GL_ARRAY_BUFFER, 0, 4, GL_MAP_READ_BIT | GL_MAP_UNSYNCHRONIZED_BIT);
    map_error("READ|FLUSH_EXPLICIT", GL_ARRAY_BUFFER, 0, 4, GL_MAP_READ_BIT | GL_MAP_FLUSH_EXPLICIT_BIT);
    map_error("past the end", GL_ARRAY_BUFFER, SIZE - 4, 8, GL_MAP_READ_BIT);
    map_error("of the last byte", GL_ARRAY_BUFFER, SIZE - 1, 1, GL_MAP_READ_BIT);
    map_error("again while mapped", GL_ARRAY_BUFFER, 0, 4, GL_MAP_READ_BIT);
    void *whole = glMapBuffer(GL_ARRAY_BUFFER, GL_READ_ONLY);
    fprintf(out, "MapBuffer while mapped: %s, error 0x%x\n", whole ? "mapped" : "NULL", glGetError());
    flush_error("of a mapping without FLUSH_EXPLICIT", 0, 1);
    unmap("UnmapBuffer");
    unmap("UnmapBuffer not mapped");
    flush_error("not mapped", 0, 1);
    map_error("for explicit flushes", GL_ARRAY_BUFFER, 8, 16, GL_MAP_WRITE_BIT | GL_MAP_FLUSH_EXPLICIT_BIT);
    flush_error("at offset -1", -1, 4);
    flush_error("of length -1", 0, -1);
    flush_error("past the range", 12, 8);
    flush_error("of the range's end", 12, 4);
    unmap("UnmapBuffer");
    read_back("after the errors", 1);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glDeleteBuffers(1, &b);
}

int main(int argc, char **argv)
{
    out = recorded_gl_start(argc, argv);
    fprintf(out, "GL_ARB_map_buffer_range: %s\n",
            recorded_gl_has_extension("GL_ARB_map_buffer_range") ? "offered" : "absent");
    access_bits();
    drawn();
    pixel_buffers();
    errors();
    recorded_gl_end(out, argv[1]);
    return 0;
}
