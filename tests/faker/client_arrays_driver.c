/* tests/faker/client_arrays_driver.c — faker_client_arrays OUT.txt: the
 * client-array commands of GL 1.1-2.0 beyond glDrawArrays/glDrawElements
 * (issue 27 item 5), on a 64x48 EGL pbuffer, one labelled line each in
 * OUT.txt (pixels as a checksum of a read-back plus the centre pixel):
 *   glSecondaryColorPointer (with GL_COLOR_SUM) and glFogCoordPointer
 *   (coordinate fog) read by glDrawArrays, glDrawRangeElements,
 *   glMultiDrawArrays, glMultiDrawElements and glArrayElement; a draw of
 *   many small triangles across the wall's tiles (a tilesort wall sorts it
 *   primitive by primitive, gathering every array); glIndexPointer read
 *   by a draw in an RGBA context (no effect on pixels, as GL says);
 *   glMultiDrawArrays compiled into a display list, the arrays changed
 *   before it is called (it keeps the values of the time of compiling);
 *   glGetPointerv and glGetVertexAttribPointerv answering the program's
 *   own pointers; glDrawElements of client arrays with its indices in an
 *   element array buffer; and the GL errors of bad calls (negative
 *   counts, end below start, unknown modes and types).
 * Built with RECORDED_GL_NATIVE (faker_client_arrays_native) it makes
 * the same calls on OSMesa directly: the runs through tessera must write
 * the same file (gl21_commands.sh runs both). */
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

static void error(const char *label) { fprintf(out, "%s: glGetError 0x%x\n", label, glGetError()); }

static void clear(void)
{
    glClearColor(0.1f, 0.1f, 0.2f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
}

/* Four quads of two triangles each, one per quarter of the window (so
 * each lies on its own tile of a 2x2 wall), and one across the middle. */
static GLfloat pos[5 * 4][2];
static GLubyte primary[5 * 4][4];
static GLshort secondary[5 * 4][3];
static GLfloat fog[5 * 4];
static GLdouble fog_d[5 * 4];
static GLint colour_index[5 * 4];

static void fill_arrays(void)
{
    static const GLfloat centre[5][2] = {{-0.5f, -0.5f}, {0.5f, -0.5f}, {0.5f, 0.5f}, {-0.5f, 0.5f}, {0.0f, 0.0f}};
    static const GLfloat corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int q = 0; q < 5; q++) {
        GLfloat size = q == 4 ? 0.25f : 0.4f;
        for (int k = 0; k < 4; k++) {
            int v = 4 * q + k;
            pos[v][0] = centre[q][0] + size * corner[k][0];
            pos[v][1] = centre[q][1] + size * corner[k][1];
            primary[v][0] = (GLubyte)(40 * q + 30 * k);
            primary[v][1] = (GLubyte)(200 - 35 * q);
            primary[v][2] = (GLubyte)(60 * k);
            primary[v][3] = 255;
            secondary[v][0] = (GLshort)(4000 * k);
            secondary[v][1] = (GLshort)(6000 * q);
            secondary[v][2] = (GLshort)(32767 - 5000 * k);
            fog[v] = 0.2f * (GLfloat)k + 0.1f * (GLfloat)q;
            fog_d[v] = 1.0 - fog[v];
            colour_index[v] = 3 * v + 1;
        }
    }
}

static void enable_arrays(void)
{
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    glEnableClientState(GL_SECONDARY_COLOR_ARRAY);
    glEnableClientState(GL_FOG_COORD_ARRAY);
    glVertexPointer(2, GL_FLOAT, 0, pos);
    glColorPointer(4, GL_UNSIGNED_BYTE, 0, primary);
    glSecondaryColorPointer(3, GL_SHORT, 0, secondary);
    glFogCoordPointer(GL_FLOAT, 0, fog);
    glEnable(GL_COLOR_SUM);
    glEnable(GL_FOG);
    glFogi(GL_FOG_COORD_SRC, GL_FOG_COORD);
    glFogi(GL_FOG_MODE, GL_LINEAR);
    glFogf(GL_FOG_START, 0.0f);
    glFogf(GL_FOG_END, 1.0f);
    static const GLfloat fog_colour[4] = {0.9f, 0.8f, 0.2f, 1.0f};
    glFogfv(GL_FOG_COLOR, fog_colour);
}

static void disable_arrays(void)
{
    glDisableClientState(GL_VERTEX_ARRAY);
    glDisableClientState(GL_COLOR_ARRAY);
    glDisableClientState(GL_SECONDARY_COLOR_ARRAY);
    glDisableClientState(GL_FOG_COORD_ARRAY);
    glDisable(GL_COLOR_SUM);
    glDisable(GL_FOG);
}

static const GLubyte quad_indices[5][6] = {
    {0, 1, 2, 0, 2, 3}, {4, 5, 6, 4, 6, 7}, {8, 9, 10, 8, 10, 11}, {12, 13, 14, 12, 14, 15}, {16, 17, 18, 16, 18, 19}};

static void draws(void)
{
    clear();
    glDrawArrays(GL_QUADS, 0, 20);
    frame("DrawArrays with secondary colour and fog coordinate arrays");

    clear();
    glDrawRangeElements(GL_TRIANGLES, 8, 11, 6, GL_UNSIGNED_BYTE, quad_indices[2]);
    glDrawRangeElements(GL_TRIANGLES, 16, 19, 6, GL_UNSIGNED_BYTE, quad_indices[4]);
    frame("DrawRangeElements");

    clear();
    static const GLint first[3] = {0, 8, 16};
    static const GLsizei count[3] = {4, 0, 4};
    glMultiDrawArrays(GL_TRIANGLE_FAN, first, count, 3);
    frame("MultiDrawArrays");

    clear();
    static const GLushort short_indices[2][6] = {{4, 5, 6, 4, 6, 7}, {12, 13, 14, 12, 14, 15}};
    const void *const indices[3] = {short_indices[0], quad_indices[0], short_indices[1]};
    static const GLsizei counts[3] = {6, 0, 6};
    glMultiDrawElements(GL_TRIANGLES, counts, GL_UNSIGNED_SHORT, indices, 3);
    frame("MultiDrawElements");

    clear();
    glFogCoordPointer(GL_DOUBLE, 0, fog_d);
    glBegin(GL_QUADS);
    for (int i = 0; i < 20; i++)
        glArrayElement(i);
    glEnd();
    glFogCoordPointer(GL_FLOAT, 0, fog);
    frame("ArrayElement with double fog coordinates");

    /* An index array in an RGBA context is read and has no effect. */
    clear();
    glIndexPointer(GL_INT, 0, colour_index);
    glEnableClientState(GL_INDEX_ARRAY);
    glDrawArrays(GL_QUADS, 0, 8);
    glArrayElement(0);
    glDisableClientState(GL_INDEX_ARRAY);
    frame("DrawArrays with an index array");

    /* Indices in an element array buffer, arrays in client memory (GL
     * allows the mix, piglit's draw-elements makes it): the receiver has
     * the indices, a packer or a wall must find which array elements to
     * send. */
    clear();
    GLuint ibo = 0;
    glGenBuffers(1, &ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, sizeof quad_indices, quad_indices, GL_STATIC_DRAW);
    glDrawElements(GL_TRIANGLES, 12, GL_UNSIGNED_BYTE, (const void *)(uintptr_t)6);
    GLint bound = -1;
    glGetIntegerv(GL_ELEMENT_ARRAY_BUFFER_BINDING, &bound);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    glDeleteBuffers(1, &ibo);
    frame("DrawElements of client arrays with indices in a buffer");
    fprintf(out, "element array buffer still bound after them: %s\n", bound == (GLint)ibo ? "yes" : "no");
    error("draws");
}

/* Many small triangles over the whole window: a wall sorts them one by
 * one, so every array is gathered per tile. */
static void many_triangles(void)
{
    enum { N = 24 * 16 * 3 };
    static GLfloat v[N][2];
    static GLshort s[N][3];
    static GLfloat f[N];
    static GLubyte c[N][4];
    int n = 0;
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 24; x++) {
            GLfloat x0 = -0.95f + (GLfloat)x * 0.08f, y0 = -0.95f + (GLfloat)y * 0.12f;
            const GLfloat corners[3][2] = {{x0, y0}, {x0 + 0.07f, y0}, {x0, y0 + 0.1f}};
            for (int k = 0; k < 3; k++, n++) {
                v[n][0] = corners[k][0];
                v[n][1] = corners[k][1];
                s[n][0] = (GLshort)(x * 1300);
                s[n][1] = (GLshort)(y * 2000);
                s[n][2] = (GLshort)(k * 10000);
                f[n] = (GLfloat)(x + y) / 40.0f;
                c[n][0] = (GLubyte)(10 * x);
                c[n][1] = (GLubyte)(15 * y);
                c[n][2] = (GLubyte)(80 * k);
                c[n][3] = 255;
            }
        }
    glVertexPointer(2, GL_FLOAT, 0, v);
    glColorPointer(4, GL_UNSIGNED_BYTE, 0, c);
    glSecondaryColorPointer(3, GL_SHORT, 0, s);
    glFogCoordPointer(GL_FLOAT, 0, f);
    clear();
    static const GLint first[2] = {0, N / 2};
    static const GLsizei count[2] = {N / 2, N / 2};
    glMultiDrawArrays(GL_TRIANGLES, first, count, 2);
    frame("MultiDrawArrays of many small triangles");
    enable_arrays(); /* the shared arrays again */
}

/* Compiled into a list, glMultiDrawArrays keeps the arrays' values of the
 * time of compiling. */
static void display_list(void)
{
    static const GLint first[2] = {0, 12};
    static const GLsizei count[2] = {4, 4};
    GLuint list = glGenLists(1);
    glNewList(list, GL_COMPILE);
    glMultiDrawArrays(GL_QUADS, first, count, 2);
    glEndList();
    GLfloat saved = pos[0][0];
    GLshort saved_secondary = secondary[13][1];
    pos[0][0] = 0.9f;
    secondary[13][1] = 32767;
    clear();
    glCallList(list);
    frame("MultiDrawArrays compiled into a list, arrays changed after");
    clear();
    glMultiDrawArrays(GL_QUADS, first, count, 2);
    frame("MultiDrawArrays with the changed arrays");
    pos[0][0] = saved;
    secondary[13][1] = saved_secondary;
    glDeleteLists(list, 1);
    error("display list");
}

static void pointers(void)
{
    void *p = NULL;
    glGetPointerv(GL_SECONDARY_COLOR_ARRAY_POINTER, &p);
    fprintf(out, "GetPointerv secondary colour: %s\n", p == (void *)secondary ? "the program's" : "other");
    glGetPointerv(GL_FOG_COORD_ARRAY_POINTER, &p);
    fprintf(out, "GetPointerv fog coordinate: %s\n", p == (void *)fog ? "the program's" : "other");
    glGetPointerv(GL_INDEX_ARRAY_POINTER, &p);
    fprintf(out, "GetPointerv index: %s\n", p == (void *)colour_index ? "the program's" : "other");
    /* the arrays' attributes, kept on the client side too (no draw
     * follows: the strides are only asked about) */
    glSecondaryColorPointer(3, GL_SHORT, 8, secondary);
    glFogCoordPointer(GL_FLOAT, 12, fog);
    GLint sc[3], fc[2], ix[2], vs = -1;
    glGetIntegerv(GL_SECONDARY_COLOR_ARRAY_SIZE, &sc[0]);
    glGetIntegerv(GL_SECONDARY_COLOR_ARRAY_TYPE, &sc[1]);
    glGetIntegerv(GL_SECONDARY_COLOR_ARRAY_STRIDE, &sc[2]);
    glGetIntegerv(GL_FOG_COORD_ARRAY_TYPE, &fc[0]);
    glGetIntegerv(GL_FOG_COORD_ARRAY_STRIDE, &fc[1]);
    glGetIntegerv(GL_INDEX_ARRAY_TYPE, &ix[0]);
    glGetIntegerv(GL_INDEX_ARRAY_STRIDE, &ix[1]);
    glGetIntegerv(GL_VERTEX_ARRAY_SIZE, &vs);
    GLboolean fog_on = GL_FALSE, index_on = GL_TRUE;
    glGetBooleanv(GL_FOG_COORD_ARRAY, &fog_on);
    glGetBooleanv(GL_INDEX_ARRAY, &index_on);
    GLfloat colour_size = 0;
    glGetFloatv(GL_COLOR_ARRAY_SIZE, &colour_size);
    GLdouble texcoord_size = 0;
    glGetDoublev(GL_TEXTURE_COORD_ARRAY_SIZE, &texcoord_size);
    fprintf(out,
            "array gets: secondary colour %d 0x%x %d, fog coordinate 0x%x %d (enabled %d), index 0x%x %d (enabled "
            "%d), vertex size %d, colour size %g, texture coordinate size %g\n",
            sc[0], sc[1], sc[2], fc[0], fc[1], fog_on, ix[0], ix[1], index_on, vs, (double)colour_size, texcoord_size);
    static const GLfloat attrib[4][4];
    glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, 0, attrib);
    p = NULL;
    glGetVertexAttribPointerv(3, GL_VERTEX_ATTRIB_ARRAY_POINTER, &p);
    fprintf(out, "GetVertexAttribPointerv 3: %s\n", p == (void *)attrib ? "the program's" : "other");
    glGetVertexAttribPointerv(5, GL_VERTEX_ATTRIB_ARRAY_POINTER, &p);
    fprintf(out, "GetVertexAttribPointerv 5 (never set): %s\n", p ? "not NULL" : "NULL");
    error("pointers");
    glGetVertexAttribPointerv(3, GL_VERTEX_ATTRIB_ARRAY_SIZE, &p);
    error("GetVertexAttribPointerv of another pname");
    glGetVertexAttribPointerv(4096, GL_VERTEX_ATTRIB_ARRAY_POINTER, &p);
    error("GetVertexAttribPointerv of attribute 4096");
}

static void errors(void)
{
    static const GLint first[2] = {0, 4};
    static const GLsizei count[2] = {4, 4}, negative[2] = {4, -1};
    const void *const indices[2] = {quad_indices[0], quad_indices[1]};
    clear();
    glMultiDrawArrays(GL_TRIANGLE_FAN, first, count, -1);
    error("MultiDrawArrays drawcount -1");
    glMultiDrawArrays(GL_TRIANGLE_FAN, first, negative, 2);
    error("MultiDrawArrays a count -1");
    glMultiDrawArrays(0x1234, first, count, 2);
    error("MultiDrawArrays mode 0x1234");
    glMultiDrawElements(GL_TRIANGLES, count, GL_FLOAT, indices, 2);
    error("MultiDrawElements type GL_FLOAT");
    glMultiDrawElements(GL_TRIANGLES, negative, GL_UNSIGNED_BYTE, indices, 2);
    error("MultiDrawElements a count -1");
    glMultiDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_BYTE, indices, -2);
    error("MultiDrawElements drawcount -2");
    glDrawRangeElements(GL_TRIANGLES, 3, 0, 6, GL_UNSIGNED_BYTE, quad_indices[0]);
    error("DrawRangeElements end below start");
    glDrawRangeElements(GL_TRIANGLES, 0, 3, -6, GL_UNSIGNED_BYTE, quad_indices[0]);
    error("DrawRangeElements count -6");
    glDrawRangeElements(GL_TRIANGLES, 0, 3, 6, GL_SHORT, quad_indices[0]);
    error("DrawRangeElements type GL_SHORT");
    glDrawArrays(GL_TRIANGLES, 0, -3);
    error("DrawArrays count -3");
    glDrawElements(GL_TRIANGLES, -3, GL_UNSIGNED_BYTE, quad_indices[0]);
    error("DrawElements count -3");
    glSecondaryColorPointer(2, GL_FLOAT, 0, fog);
    error("SecondaryColorPointer size 2");
    glFogCoordPointer(GL_INT, 0, fog);
    error("FogCoordPointer type GL_INT");
    glIndexPointer(GL_FLOAT, -4, fog);
    error("IndexPointer stride -4");
    void *p = NULL;
    glGetPointerv(GL_SECONDARY_COLOR_ARRAY_POINTER, &p);
    fprintf(out, "GetPointerv secondary colour after the refused calls: %s\n",
            p == (void *)secondary ? "the program's" : "other");
    frame("nothing drawn by the refused calls");
}

int main(int argc, char **argv)
{
    out = recorded_gl_start(argc, argv);
    fill_arrays();
    enable_arrays();
    draws();
    many_triangles();
    display_list();
    pointers();
    errors();
    disable_arrays();
    recorded_gl_end(out, argv[1]);
    printf("client arrays: written to %s\n", argv[1]);
    return 0;
}
