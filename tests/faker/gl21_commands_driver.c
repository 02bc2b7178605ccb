/* tests/faker/gl21_commands_driver.c — faker_gl21_commands OUT.txt: the GL 1.0-2.1
 * commands added to the spec to complete the core (issue 27), each used
 * where its effect shows, on a 64x48 EGL pbuffer: the pixels they draw
 * and the answers of the gets, one labelled line each in OUT.txt (pixels
 * as a checksum of a read-back plus the centre pixel):
 *   RasterPos4d/2s/3sv and WindowPos3f/2sv placing glBitmap and
 *   glDrawPixels; PixelMapfv colour maps on glDrawPixels;
 *   LoadTransposeMatrixd and MultTransposeMatrixd placing geometry (the
 *   wall sorts it by the tracked matrices); MultiTexCoord2d/4sv texturing;
 *   SecondaryColor3ub with GL_COLOR_SUM; FogCoordd with coordinate fog;
 *   VertexAttrib4Nub/4Nusv/3s/2d read back; Index/ClearIndex/IndexMask
 *   in an RGBA context; CompressedTexImage2D (DXT1) drawn;
 *   AreTexturesResident, PrioritizeTextures, GetTexGendv,
 *   GetBufferSubData; IsShader/IsProgram, GetShaderSource,
 *   GetAttachedShaders, GetActiveAttrib/Uniform and a UniformMatrix3x2fv
 *   drawn by a program; occlusion queries (a wall sums its servers');
 *   MapBuffer/UnmapBuffer/GetBufferPointerv on a vertex buffer then drawn;
 *   ArrayElement, immediately and in a display list; the gets whose
 *   answer's size the GL's state decides (GetMap*, GetPixelMap*,
 *   GetUniform* of every GLSL 1.20 kind, GetCompressedTexImage), with
 *   guard values after each answer and their errors; glShaderSource on a
 *   name that is no shader, whose strings GL never reads.
 * Built with RECORDED_GL_NATIVE (faker_gl21_commands_native) it makes the same
 * calls on OSMesa directly: the runs through tessera must write the same
 * file (gl21_commands.sh). */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "recorded_gl.h"

#define W RECORDED_GL_W
#define H RECORDED_GL_H

static FILE *out;

static void frame(const char *label) { recorded_gl_frame(out, label); }

static void floats(const char *label, const GLfloat *v, int n)
{
    fprintf(out, "%s:", label);
    for (int i = 0; i < n; i++)
        fprintf(out, " %.6g", (double)v[i]);
    fprintf(out, "\n");
}

static void clear(void)
{
    glClearColor(0.1f, 0.1f, 0.2f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

static void quad(void)
{
    glBegin(GL_QUADS);
    glVertex2f(-0.6f, -0.6f);
    glVertex2f(0.6f, -0.6f);
    glVertex2f(0.6f, 0.6f);
    glVertex2f(-0.6f, 0.6f);
    glEnd();
}

static void raster_positions(void)
{
    static const GLubyte bits[8] = {0xff, 0x81, 0x81, 0x81, 0x81, 0x81, 0x81, 0xff};
    static GLubyte rgb[6 * 5 * 3];
    for (size_t i = 0; i < sizeof rgb; i++)
        rgb[i] = (GLubyte)(37 * i);
    clear();
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glColor3f(1, 1, 0);
    glRasterPos4d(-0.5, -0.5, 0.0, 1.0);
    glBitmap(8, 8, 0, 0, 0, 0, bits);
    glRasterPos2s(0, 0);
    glBitmap(8, 8, 0, 0, 0, 0, bits);
    static const GLshort p3[3] = {0, 0, 0};
    glRasterPos3sv(p3);
    glDrawPixels(6, 5, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    glWindowPos3f(50.0f, 5.0f, 0.0f);
    glDrawPixels(6, 5, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    static const GLshort wp[2] = {3, 40};
    glWindowPos2sv(wp);
    glBitmap(8, 8, 0, 0, 0, 0, bits);
    GLfloat pos[4];
    glGetFloatv(GL_CURRENT_RASTER_POSITION, pos);
    floats("raster position after WindowPos2sv", pos, 4);
    frame("RasterPos/WindowPos bitmaps and pixels");

    /* Red inverted and green halved by colour maps (fv, uiv), blue and
     * alpha by usv maps. Only red and green are compared: with GL_MAP_COLOR
     * on, llvmpipe's blue and alpha of a multi-pixel glDrawPixels are not
     * a function of the maps (natively: B and A maps of {1, 1} give blue
     * 215, 36, 104, ... for this image, while one pixel gives 255). */
    static const GLfloat inv[2] = {1.0f, 0.0f};
    glPixelMapfv(GL_PIXEL_MAP_R_TO_R, 2, inv);
    static const GLuint half[2] = {0, 0x80000000u};
    glPixelMapuiv(GL_PIXEL_MAP_G_TO_G, 2, half);
    static const GLushort full[2] = {0xffff, 0xffff};
    glPixelMapusv(GL_PIXEL_MAP_B_TO_B, 2, full);
    glPixelMapusv(GL_PIXEL_MAP_A_TO_A, 2, full);
    glPixelTransferi(GL_MAP_COLOR, GL_TRUE);
    glWindowPos2d(20.0, 20.0);
    glDrawPixels(6, 5, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    glPixelTransferi(GL_MAP_COLOR, GL_FALSE);
    /* Rows of 6 one-byte values, packed tight: at the default pack
     * alignment of 4 each row would take 8 bytes (38 in all). */
    GLubyte mapped[2][6 * 5];
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(20, 20, 6, 5, GL_RED, GL_UNSIGNED_BYTE, mapped[0]);
    glReadPixels(20, 20, 6, 5, GL_GREEN, GL_UNSIGNED_BYTE, mapped[1]);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    for (int k = 0; k < 2; k++) {
        fprintf(out, "PixelMap: mapped DrawPixels' %s:", k ? "green" : "red");
        for (int i = 0; i < 6 * 5; i++)
            fprintf(out, " %u", mapped[k][i]);
        fprintf(out, "\n");
    }
    GLint sizes[3] = {0, 0, 0};
    glGetIntegerv(GL_PIXEL_MAP_R_TO_R_SIZE, &sizes[0]);
    glGetIntegerv(GL_PIXEL_MAP_G_TO_G_SIZE, &sizes[1]);
    glGetIntegerv(GL_PIXEL_MAP_B_TO_B_SIZE, &sizes[2]);
    fprintf(out, "PixelMap sizes: %d %d %d\n", sizes[0], sizes[1], sizes[2]);
}

static void transpose_matrices(void)
{
    clear();
    /* a translation by (0.3, 0.2) and a scale, written row-major */
    static const GLdouble t[16] = {1, 0, 0, 0.3, 0, 1, 0, 0.2, 0, 0, 1, 0, 0, 0, 0, 1};
    static const GLdouble s[16] = {0.5, 0, 0, 0, 0, 0.7, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    glMatrixMode(GL_MODELVIEW);
    glLoadTransposeMatrixd(t);
    glMultTransposeMatrixd(s);
    glColor3f(0.2f, 0.9f, 0.4f);
    quad();
    GLfloat m[16];
    glGetFloatv(GL_MODELVIEW_MATRIX, m);
    floats("modelview after LoadTransposeMatrixd, MultTransposeMatrixd", m, 16);
    glLoadIdentity();
    frame("transposed double matrices");
}

static void attributes(void)
{
    static GLubyte tex[4 * 4 * 3];
    for (int i = 0; i < 16; i++) {
        tex[i * 3] = (GLubyte)(i * 16);
        tex[i * 3 + 1] = (GLubyte)(255 - i * 16);
        tex[i * 3 + 2] = (GLubyte)((i % 4) * 60);
    }
    GLuint name;
    glGenTextures(1, &name);
    glBindTexture(GL_TEXTURE_2D, name);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, 4, 4, 0, GL_RGB, GL_UNSIGNED_BYTE, tex);
    clear();
    glEnable(GL_TEXTURE_2D);
    glColor3f(1, 1, 1);
    glBegin(GL_QUADS);
    glMultiTexCoord2d(GL_TEXTURE0, 0.0, 0.0);
    glVertex2f(-0.8f, -0.8f);
    glMultiTexCoord2i(GL_TEXTURE0, 1, 0);
    glVertex2f(0.8f, -0.8f);
    static const GLshort st[4] = {1, 1, 0, 1};
    glMultiTexCoord4sv(GL_TEXTURE0, st);
    glVertex2f(0.8f, 0.8f);
    glMultiTexCoord3f(GL_TEXTURE0, 0.0f, 1.0f, 0.0f);
    glVertex2f(-0.8f, 0.8f);
    glEnd();
    glDisable(GL_TEXTURE_2D);
    glDeleteTextures(1, &name);
    frame("MultiTexCoord variants");

    clear();
    glEnable(GL_COLOR_SUM);
    glColor3f(0.3f, 0.1f, 0.1f);
    glSecondaryColor3ub(40, 200, 90);
    quad();
    glDisable(GL_COLOR_SUM);
    GLfloat sc[4];
    glGetFloatv(GL_CURRENT_SECONDARY_COLOR, sc);
    floats("GL_CURRENT_SECONDARY_COLOR", sc, 4);
    frame("SecondaryColor3ub with GL_COLOR_SUM");

    clear();
    glEnable(GL_FOG);
    glFogi(GL_FOG_MODE, GL_LINEAR);
    glFogf(GL_FOG_START, 0.0f);
    glFogf(GL_FOG_END, 10.0f);
    static const GLfloat fog_colour[4] = {0.9f, 0.2f, 0.2f, 1.0f};
    glFogfv(GL_FOG_COLOR, fog_colour);
    glFogi(GL_FOG_COORD_SRC, GL_FOG_COORD);
    glColor3f(0.1f, 0.1f, 0.9f);
    glBegin(GL_TRIANGLES);
    glFogCoordd(2.0);
    glVertex2f(-0.8f, -0.8f);
    static const GLfloat fc = 6.0f;
    glFogCoordfv(&fc);
    glVertex2f(0.8f, -0.8f);
    glFogCoordf(9.0f);
    glVertex2f(0.0f, 0.8f);
    glEnd();
    glDisable(GL_FOG);
    glFogi(GL_FOG_COORD_SRC, GL_FRAGMENT_DEPTH);
    GLfloat coord;
    glGetFloatv(GL_CURRENT_FOG_COORD, &coord);
    floats("GL_CURRENT_FOG_COORD", &coord, 1);
    frame("FogCoord fog");

    GLfloat v[4];
    glVertexAttrib4Nub(3, 255, 128, 0, 64);
    glGetVertexAttribfv(3, GL_CURRENT_VERTEX_ATTRIB, v);
    floats("VertexAttrib4Nub", v, 4);
    static const GLushort us[4] = {65535, 0, 32768, 1};
    glVertexAttrib4Nusv(4, us);
    glGetVertexAttribfv(4, GL_CURRENT_VERTEX_ATTRIB, v);
    floats("VertexAttrib4Nusv", v, 4);
    glVertexAttrib3s(5, -2, 7, 300);
    GLdouble d[4];
    glGetVertexAttribdv(5, GL_CURRENT_VERTEX_ATTRIB, d);
    fprintf(out, "VertexAttrib3s: %g %g %g %g\n", d[0], d[1], d[2], d[3]);
    glVertexAttrib2d(6, 0.25, -4.5);
    GLint iv[4];
    glGetVertexAttribiv(6, GL_CURRENT_VERTEX_ATTRIB, iv);
    fprintf(out, "VertexAttrib2d as integers: %d %d %d %d\n", iv[0], iv[1], iv[2], iv[3]);

    glClearIndex(3.0f);
    glIndexMask(0x5u);
    glIndexf(7.0f);
    GLfloat index[3];
    glGetFloatv(GL_INDEX_CLEAR_VALUE, &index[0]);
    glGetFloatv(GL_INDEX_WRITEMASK, &index[1]);
    glGetFloatv(GL_CURRENT_INDEX, &index[2]);
    floats("ClearIndex, IndexMask, Indexf in RGBA", index, 3);
}

static void textures_and_buffers(void)
{
    /* one DXT1 block: colour0 red, colour1 blue, every texel index 0..3 */
    static const GLubyte dxt1[8] = {0x00, 0xf8, 0x1f, 0x00, 0xe4, 0xe4, 0x1b, 0x1b};
    GLuint names[2];
    glGenTextures(2, names);
    glBindTexture(GL_TEXTURE_2D, names[0]);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glCompressedTexImage2D(GL_TEXTURE_2D, 0, GL_COMPRESSED_RGB_S3TC_DXT1_EXT, 4, 4, 0, 8, dxt1);
    GLint compressed = 0;
    glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_COMPRESSED, &compressed);
    fprintf(out, "CompressedTexImage2D: compressed %d error 0x%x\n", compressed, glGetError());
    clear();
    glEnable(GL_TEXTURE_2D);
    glColor3f(1, 1, 1);
    glBegin(GL_QUADS);
    glTexCoord2f(0, 0);
    glVertex2f(-0.8f, -0.8f);
    glTexCoord2f(1, 0);
    glVertex2f(0.8f, -0.8f);
    glTexCoord2f(1, 1);
    glVertex2f(0.8f, 0.8f);
    glTexCoord2f(0, 1);
    glVertex2f(-0.8f, 0.8f);
    glEnd();
    glDisable(GL_TEXTURE_2D);
    frame("CompressedTexImage2D DXT1 drawn");

    static const GLclampf prio[2] = {0.25f, 1.0f};
    glPrioritizeTextures(2, names, prio);
    GLfloat p = 0;
    glGetTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_PRIORITY, &p);
    floats("PrioritizeTextures: priority of the first", &p, 1);
    GLboolean resident[2] = {GL_FALSE, GL_FALSE};
    GLboolean all = glAreTexturesResident(2, names, resident);
    fprintf(out, "AreTexturesResident: %d\n", all);
    glDeleteTextures(2, names);

    glTexGeni(GL_S, GL_TEXTURE_GEN_MODE, GL_OBJECT_LINEAR);
    static const GLdouble plane[4] = {0.5, 0.25, 0.125, 2.0};
    glTexGendv(GL_S, GL_OBJECT_PLANE, plane);
    GLdouble got[4];
    glGetTexGendv(GL_S, GL_OBJECT_PLANE, got);
    fprintf(out, "GetTexGendv: %g %g %g %g\n", got[0], got[1], got[2], got[3]);

    GLuint buffer;
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    static const GLubyte bytes[16] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
    glBufferData(GL_ARRAY_BUFFER, sizeof bytes, bytes, GL_STATIC_DRAW);
    static const GLubyte patch[3] = {200, 201, 202};
    glBufferSubData(GL_ARRAY_BUFFER, 5, sizeof patch, patch);
    GLubyte back[8];
    glGetBufferSubData(GL_ARRAY_BUFFER, 3, sizeof back, back);
    fprintf(out, "GetBufferSubData:");
    for (int i = 0; i < 8; i++)
        fprintf(out, " %u", back[i]);
    fprintf(out, "\n");
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glDeleteBuffers(1, &buffer);
}

static void program(void)
{
    static const char *vs = "#version 120\n"
                            "attribute vec4 position;\n"
                            "attribute vec2 weight;\n"
                            "varying vec2 w;\n"
                            "void main() { w = weight; gl_Position = position; }\n";
    static const char *fs = "#version 120\n"
                            "uniform mat3x2 m;\n"
                            "varying vec2 w;\n"
                            "void main() { gl_FragColor = vec4(m * vec3(w, 1.0), 0.5, 1.0); }\n";
    GLuint v = glCreateShader(GL_VERTEX_SHADER), f = glCreateShader(GL_FRAGMENT_SHADER);
    glShaderSource(v, 1, &vs, NULL);
    glShaderSource(f, 1, &fs, NULL);
    glCompileShader(v);
    glCompileShader(f);
    GLuint prog = glCreateProgram();
    glAttachShader(prog, v);
    glAttachShader(prog, f);
    glBindAttribLocation(prog, 0, "position");
    glBindAttribLocation(prog, 1, "weight");
    glLinkProgram(prog);
    GLint linked = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &linked);
    fprintf(out, "linked: %d\n", linked);
    fprintf(out, "IsShader: %d %d IsProgram: %d %d\n", glIsShader(v), glIsShader(prog), glIsProgram(prog),
            glIsProgram(v));
    char src[256] = {0};
    GLsizei len = -1;
    glGetShaderSource(f, sizeof src, &len, src);
    fprintf(out, "GetShaderSource: %d %s", (int)len, strcmp(src, fs) == 0 ? "same text\n" : src);
    GLuint attached[4] = {0};
    GLsizei count = -1;
    glGetAttachedShaders(prog, 4, &count, attached);
    fprintf(out, "GetAttachedShaders: %d, the two shaders: %d\n", (int)count,
            count == 2 && ((attached[0] == v && attached[1] == f) || (attached[0] == f && attached[1] == v)));
    char name[64] = {0};
    GLint size = 0;
    GLenum type = 0;
    glGetActiveAttrib(prog, 0, sizeof name, &len, &size, &type, name);
    fprintf(out, "GetActiveAttrib 0: %s size %d type 0x%x\n", name, size, type);
    glGetActiveUniform(prog, 0, sizeof name, &len, &size, &type, name);
    fprintf(out, "GetActiveUniform 0: %s size %d type 0x%x\n", name, size, type);

    glUseProgram(prog);
    static const GLfloat m[6] = {0.5f, 0.1f, 0.2f, 0.6f, 0.1f, 0.2f};
    glUniformMatrix3x2fv(glGetUniformLocation(prog, "m"), 1, GL_FALSE, m);
    clear();
    glBegin(GL_TRIANGLES);
    glVertexAttrib2s(1, 0, 0);
    glVertexAttrib2d(0, -0.9, -0.9);
    glVertexAttrib2d(1, 1.0, 0.0);
    glVertexAttrib4Nsv(0, (const GLshort[4]){29490, -29490, 0, 32767});
    glVertexAttrib1d(1, 0.5);
    glVertexAttrib4s(0, 0, 1, 0, 1);
    glEnd();
    glUseProgram(0);
    frame("UniformMatrix3x2fv and VertexAttrib variants drawn by a program");
    glDeleteProgram(prog);
    glDeleteShader(v);
    glDeleteShader(f);
}

/* A vertex buffer read and rewritten through glMapBuffer, then drawn:
 * what the program wrote reaches the renderers at glUnmapBuffer. */
static void mapped_buffer(void)
{
    GLuint b;
    glGenBuffers(1, &b);
    glBindBuffer(GL_ARRAY_BUFFER, b);
    static const GLfloat tri[6] = {-0.9f, -0.9f, 0.1f, -0.9f, -0.4f, 0.2f};
    glBufferData(GL_ARRAY_BUFFER, sizeof tri, tri, GL_DYNAMIC_DRAW);
    GLfloat *m = glMapBuffer(GL_ARRAY_BUFFER, GL_READ_WRITE);
    void *pointer = NULL;
    glGetBufferPointerv(GL_ARRAY_BUFFER, GL_BUFFER_MAP_POINTER, &pointer);
    fprintf(out, "MapBuffer: %s, GetBufferPointerv gives it: %d\n", m ? "mapped" : "NULL", m && pointer == m);
    if (m) {
        floats("MapBuffer: the buffer's contents", m, 6);
        for (int i = 0; i < 6; i += 2)
            m[i] += 0.8f; /* moved right, across the wall's middle */
        m[5] = 0.9f;
    }
    fprintf(out, "UnmapBuffer: %d\n", glUnmapBuffer(GL_ARRAY_BUFFER));
    pointer = &pointer;
    glGetBufferPointerv(GL_ARRAY_BUFFER, GL_BUFFER_MAP_POINTER, &pointer);
    fprintf(out, "GetBufferPointerv after unmap: %s\n", pointer ? "not NULL" : "NULL");
    clear();
    glColor3f(0.9f, 0.6f, 0.1f);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(2, GL_FLOAT, 0, (const void *)0);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisableClientState(GL_VERTEX_ARRAY);
    GLfloat back[6];
    glGetBufferSubData(GL_ARRAY_BUFFER, 0, sizeof back, back);
    floats("GetBufferSubData after unmap", back, 6);
    /* mapped write-only: the untouched floats keep their values */
    GLfloat *w = glMapBuffer(GL_ARRAY_BUFFER, GL_WRITE_ONLY);
    if (w)
        w[1] = -0.5f;
    fprintf(out, "UnmapBuffer (write-only): %d\n", glUnmapBuffer(GL_ARRAY_BUFFER));
    glGetBufferSubData(GL_ARRAY_BUFFER, 0, sizeof back, back);
    floats("GetBufferSubData after a write-only map", back, 6);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glDeleteBuffers(1, &b);
    frame("drawn from a buffer written through glMapBuffer");
}

/* glArrayElement from client arrays of several types, immediately and
 * compiled into a display list (which keeps the values of the time of
 * compiling: the arrays change before the list is called). */
static void array_elements(void)
{
    static GLshort pos[4][3] = {{-50, -50, 0}, {60, -40, 0}, {40, 70, 0}, {-60, 50, 0}};
    static GLubyte colours[4][4] = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {255, 255, 0, 255}};
    static const GLfloat normals[4][3] = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}};
    clear();
    glMatrixMode(GL_MODELVIEW);
    glPushMatrix();
    glScalef(0.01f, 0.01f, 1.0f);
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    glEnableClientState(GL_NORMAL_ARRAY);
    glVertexPointer(3, GL_SHORT, 0, pos);
    glColorPointer(4, GL_UNSIGNED_BYTE, 0, colours);
    glNormalPointer(GL_FLOAT, 0, normals);
    glShadeModel(GL_SMOOTH);
    glBegin(GL_QUADS);
    for (int i = 0; i < 4; i++)
        glArrayElement(i);
    glEnd();
    frame("ArrayElement quad");
    GLuint list = glGenLists(1);
    glNewList(list, GL_COMPILE);
    glBegin(GL_TRIANGLES);
    glArrayElement(0);
    glArrayElement(1);
    glArrayElement(2);
    glEnd();
    glEndList();
    pos[0][0] = 90;
    colours[1][0] = 255;
    clear();
    glCallList(list);
    frame("ArrayElement compiled into a list, arrays changed after");
    glDeleteLists(list, 1);
    glDisableClientState(GL_VERTEX_ARRAY);
    glDisableClientState(GL_COLOR_ARRAY);
    glDisableClientState(GL_NORMAL_ARRAY);
    glPopMatrix();
}

/* Samples of a quad across all four tiles of a 2x2 wall, and of one
 * behind it half hidden by the depth test: a wall sums its servers'. */
static void occlusion(void)
{
    GLuint q[2];
    glGenQueries(2, q);
    clear();
    glEnable(GL_DEPTH_TEST);
    glBeginQuery(GL_SAMPLES_PASSED, q[0]);
    glColor3f(0.5f, 0.5f, 0.5f);
    quad();
    glEndQuery(GL_SAMPLES_PASSED);
    glBeginQuery(GL_SAMPLES_PASSED, q[1]);
    glColor3f(0.9f, 0.1f, 0.1f);
    glBegin(GL_QUADS);
    glVertex3f(-0.2f, -0.9f, 0.5f);
    glVertex3f(0.9f, -0.9f, 0.5f);
    glVertex3f(0.9f, 0.3f, -0.5f);
    glVertex3f(-0.2f, 0.3f, -0.5f);
    glEnd();
    glEndQuery(GL_SAMPLES_PASSED);
    glDisable(GL_DEPTH_TEST);
    GLuint samples[2] = {0, 0}, available = 0;
    GLint signed_samples = 0, bits = 0, current = -1;
    glGetQueryObjectuiv(q[0], GL_QUERY_RESULT, &samples[0]);
    glGetQueryObjectiv(q[1], GL_QUERY_RESULT, &signed_samples);
    glGetQueryObjectuiv(q[1], GL_QUERY_RESULT, &samples[1]);
    glGetQueryObjectuiv(q[1], GL_QUERY_RESULT_AVAILABLE, &available);
    glGetQueryiv(GL_SAMPLES_PASSED, GL_QUERY_COUNTER_BITS, &bits);
    glGetQueryiv(GL_SAMPLES_PASSED, GL_CURRENT_QUERY, &current);
    fprintf(out, "occlusion: %u %u (signed %d) available %u counter bits %s current %d IsQuery %d\n", samples[0],
            samples[1], signed_samples, available, bits > 0 ? "> 0" : "0", current, glIsQuery(q[0]));
    glDeleteQueries(2, q);
    fprintf(out, "IsQuery after delete: %d\n", glIsQuery(q[0]));
    frame("occlusion queries drawn");
}

/* The gets whose answer's size only the GL's state decides (the map's
 * order, the pixel map's size, the uniform's type, the compressed size):
 * each answer is printed with the buffer's guard values after it, so a
 * write past what GL writes shows as a difference from OSMesa. */
#define GUARDED 28 /* the largest answer (a 3x2 map of RGBA: 24 values) and 4 guards */
static void guarded(const char *label, const GLfloat *v)
{
    fprintf(out, "%s:", label);
    for (int i = 0; i < GUARDED; i++)
        fprintf(out, " %.6g", (double)v[i]);
    fprintf(out, " error 0x%x\n", glGetError());
}

static void guard(GLfloat *v)
{
    for (int i = 0; i < GUARDED; i++)
        v[i] = -777.0f;
}

static void sized_gets(void)
{
    GLfloat v[GUARDED];
    static const GLfloat curve[4][3] = {{-1, -1, 0}, {-0.5f, 1, 0}, {0.5f, -1, 0}, {1, 1, 0.5f}};
    glMap1f(GL_MAP1_VERTEX_3, 0.25f, 2.0f, 3, 4, &curve[0][0]);
    static const GLdouble patch[2][3][4] = {{{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}},
                                            {{1, 1, 0, 1}, {0, 1, 1, 1}, {1, 0, 1, 0.5}}};
    glMap2d(GL_MAP2_COLOR_4, 0, 1, 4, 3, -1, 1, 12, 2, &patch[0][0][0]);
    static const GLenum queries[3] = {GL_ORDER, GL_DOMAIN, GL_COEFF};
    for (int q = 0; q < 3; q++) {
        char label[64];
        guard(v);
        glGetMapfv(GL_MAP1_VERTEX_3, queries[q], v);
        snprintf(label, sizeof label, "GetMapfv MAP1_VERTEX_3 0x%x", queries[q]);
        guarded(label, v);
        GLdouble dv[GUARDED];
        for (int i = 0; i < GUARDED; i++)
            dv[i] = -777.0;
        glGetMapdv(GL_MAP2_COLOR_4, queries[q], dv);
        for (int i = 0; i < GUARDED; i++)
            v[i] = (GLfloat)dv[i];
        snprintf(label, sizeof label, "GetMapdv MAP2_COLOR_4 0x%x", queries[q]);
        guarded(label, v);
    }
    GLint iv[GUARDED];
    for (int i = 0; i < GUARDED; i++)
        iv[i] = -777;
    glGetMapiv(GL_MAP2_COLOR_4, GL_ORDER, iv);
    fprintf(out, "GetMapiv MAP2_COLOR_4 ORDER: %d %d %d error 0x%x\n", iv[0], iv[1], iv[2], glGetError());
    glGetMapiv(GL_TEXTURE_2D, GL_ORDER, iv);
    fprintf(out, "GetMapiv of no map: %d error 0x%x\n", iv[0], glGetError());

    static const GLfloat ramp[8] = {0, 0.125f, 0.25f, 0.375f, 0.5f, 0.625f, 0.75f, 1};
    glPixelMapfv(GL_PIXEL_MAP_R_TO_R, 8, ramp);
    static const GLuint indices[4] = {3, 2, 1, 0};
    glPixelMapuiv(GL_PIXEL_MAP_I_TO_I, 4, indices);
    guard(v);
    glGetPixelMapfv(GL_PIXEL_MAP_R_TO_R, v);
    guarded("GetPixelMapfv R_TO_R", v);
    guard(v);
    glGetPixelMapfv(GL_PIXEL_MAP_A_TO_A, v);
    guarded("GetPixelMapfv A_TO_A (default)", v);
    GLuint uv[6] = {777, 777, 777, 777, 777, 777};
    glGetPixelMapuiv(GL_PIXEL_MAP_I_TO_I, uv);
    fprintf(out, "GetPixelMapuiv I_TO_I: %u %u %u %u %u %u\n", uv[0], uv[1], uv[2], uv[3], uv[4], uv[5]);
    GLushort us[10] = {777, 777, 777, 777, 777, 777, 777, 777, 777, 777};
    glGetPixelMapusv(GL_PIXEL_MAP_R_TO_R, us);
    fprintf(out, "GetPixelMapusv R_TO_R:");
    for (int i = 0; i < 10; i++)
        fprintf(out, " %u", us[i]);
    fprintf(out, " error 0x%x\n", glGetError());

    static const char *fs = "#version 120\n"
                            "uniform float f;\n"
                            "uniform vec3 c;\n"
                            "uniform mat4 m;\n"
                            "uniform int k[3];\n"
                            "uniform ivec2 n;\n"
                            "uniform bool b;\n"
                            "uniform sampler2D s;\n"
                            "void main() { gl_FragColor = m * vec4(c * f, float(k[2] + n.y) * (b ? 1.0 : 0.5))"
                            " + texture2D(s, vec2(0.5)); }\n";
    GLuint shader = glCreateShader(GL_FRAGMENT_SHADER);
    glShaderSource(shader, 1, &fs, NULL);
    glCompileShader(shader);
    GLuint prog = glCreateProgram();
    glAttachShader(prog, shader);
    glLinkProgram(prog);
    glUseProgram(prog);
    glUniform1f(glGetUniformLocation(prog, "f"), 0.5f);
    glUniform3f(glGetUniformLocation(prog, "c"), 1, 2, 3);
    GLfloat m[16];
    for (int i = 0; i < 16; i++)
        m[i] = (GLfloat)i / 4;
    glUniformMatrix4fv(glGetUniformLocation(prog, "m"), 1, GL_FALSE, m);
    static const GLint k[3] = {7, 8, 9};
    glUniform1iv(glGetUniformLocation(prog, "k"), 3, k);
    glUniform2i(glGetUniformLocation(prog, "n"), -4, 5);
    glUniform1i(glGetUniformLocation(prog, "b"), 1);
    glUniform1i(glGetUniformLocation(prog, "s"), 3);
    static const char *names[] = {"f", "c", "m", "k", "k[2]", "n", "b", "s"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        char label[64];
        guard(v);
        glGetUniformfv(prog, glGetUniformLocation(prog, names[i]), v);
        snprintf(label, sizeof label, "GetUniformfv %s", names[i]);
        guarded(label, v);
        for (int j = 0; j < GUARDED; j++)
            iv[j] = -777;
        glGetUniformiv(prog, glGetUniformLocation(prog, names[i]), iv);
        fprintf(out, "GetUniformiv %s:", names[i]);
        for (int j = 0; j < 18; j++)
            fprintf(out, " %d", iv[j]);
        fprintf(out, " error 0x%x\n", glGetError());
    }
    guard(v);
    glGetUniformfv(prog, -1, v);
    guarded("GetUniformfv location -1", v);
    guard(v);
    glGetUniformfv(prog, 999, v);
    guarded("GetUniformfv location 999", v);
    glUseProgram(0);
    GLuint unlinked = glCreateProgram();
    guard(v);
    glGetUniformfv(unlinked, 0, v);
    guarded("GetUniformfv of an unlinked program", v);
    guard(v);
    glGetUniformfv(shader, 0, v);
    guarded("GetUniformfv of a shader", v);
    glDeleteProgram(unlinked);
    glDeleteProgram(prog);
    glDeleteShader(shader);

    /* two DXT1 blocks (8x4 texels), read back as they were given */
    static const GLubyte dxt1[16] = {0x00, 0xf8, 0x1f, 0x00, 0xe4, 0xe4, 0x1b, 0x1b,
                                     0xe0, 0x07, 0x00, 0xf8, 0x1b, 0x1b, 0xe4, 0xe4};
    GLuint tex;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glCompressedTexImage2D(GL_TEXTURE_2D, 0, GL_COMPRESSED_RGB_S3TC_DXT1_EXT, 8, 4, 0, 16, dxt1);
    GLubyte back[24];
    memset(back, 0x77, sizeof back);
    glGetCompressedTexImage(GL_TEXTURE_2D, 0, back);
    fprintf(out, "GetCompressedTexImage DXT1:");
    for (size_t i = 0; i < sizeof back; i++)
        fprintf(out, " %02x", back[i]);
    fprintf(out, " error 0x%x\n", glGetError());
    static const GLubyte rgba[4] = {1, 2, 3, 4};
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    memset(back, 0x77, sizeof back);
    glGetCompressedTexImage(GL_TEXTURE_2D, 0, back);
    fprintf(out, "GetCompressedTexImage of an uncompressed level: %02x error 0x%x\n", back[0], glGetError());
    /* images GL refuses itself, beyond any texture budget of a node: its
     * error, never a refusal that drops the client */
    glCopyTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 2, 2, 1 << 28, 1 << 28, 0);
    fprintf(out, "CopyTexImage2D 2^28 x 2^28: error 0x%x\n", glGetError());
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 1 << 20, 1 << 20, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    fprintf(out, "TexImage2D 2^20 x 2^20: error 0x%x\n", glGetError());
    glBindTexture(GL_TEXTURE_2D, 0);
    glDeleteTextures(1, &tex);
}

/* Client state the packer keeps: GL's errors all the same. */
static void client_state_errors(void)
{
    GLint units = 0;
    glGetIntegerv(GL_MAX_TEXTURE_COORDS, &units);
    glClientActiveTexture(GL_TEXTURE0 + (GLenum)units);
    fprintf(out, "ClientActiveTexture(GL_TEXTURE0 + GL_MAX_TEXTURE_COORDS %d): error 0x%x\n", units, glGetError());
    GLint active = -1;
    glGetIntegerv(GL_CLIENT_ACTIVE_TEXTURE, &active);
    fprintf(out, "CLIENT_ACTIVE_TEXTURE: 0x%x error 0x%x\n", (unsigned)active, glGetError());
    /* a limit of GL_ARB_texture_rectangle, which Mesa's GL 2.1 has and
     * piglit's max-texture-size asks (the wire sizes it now) */
    GLint rectangle = -1;
    glGetIntegerv(GL_MAX_RECTANGLE_TEXTURE_SIZE, &rectangle);
    fprintf(out, "MAX_RECTANGLE_TEXTURE_SIZE: %d error 0x%x\n", rectangle, glGetError());
    /* GL checks glShaderSource's name before it reads a string, so a bad
     * name's strings are never read (piglit's shadersource-errors passes
     * text where the array of strings belongs): a packer must not read
     * them either */
    static const char text[] = "void main() { gl_FragColor = vec4(1.0); }                ";
    const GLchar *const *not_strings = (const GLchar *const *)(const void *)text;
    GLuint shader = glCreateShader(GL_FRAGMENT_SHADER), prog = glCreateProgram();
    glShaderSource(shader + prog + 99, 1, not_strings, NULL);
    fprintf(out, "ShaderSource(a name never created): error 0x%x\n", glGetError());
    glShaderSource(prog, 1, not_strings, NULL);
    fprintf(out, "ShaderSource(a program's name): error 0x%x\n", glGetError());
    glDeleteShader(shader);
    glDeleteProgram(prog);
}

int main(int argc, char **argv)
{
    out = recorded_gl_start(argc, argv);
    raster_positions();
    transpose_matrices();
    attributes();
    textures_and_buffers();
    program();
    occlusion();
    mapped_buffer();
    array_elements();
    sized_gets();
    client_state_errors();
    recorded_gl_end(out, argv[1]);
    printf("gl21 commands: written to %s\n", argv[1]);
    return 0;
}
