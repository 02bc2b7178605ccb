/* tests/tilesort/select_feedback_driver.c — selection and feedback passes as
 * programs run them (glSelectBuffer/glFeedbackBuffer, glRenderMode, the
 * name stack, glPassThrough), printed record by record on stdout: the
 * test (tilesort.sh records) runs the -native build (OSMesa itself, the
 * reference) and this one through render, pack -> node -> render and a
 * tile wall, and wants the same lines and the same frames.
 *
 * Every frame: glRenderMode(GL_SELECT) before any glSelectBuffer (GL
 * raises GL_INVALID_OPERATION; Mesa enters the mode all the same, so the
 * quad after it is not drawn and the next glSelectBuffer is refused);
 * a selection pass whose primitives fall in every tile of a 2x2 wall and
 * across its edges, one outside the view volume, names pushed and loaded
 * around them, a display list holding glLoadName, a large glDrawArrays
 * (a wall sorts those primitive by primitive), a long line strip (a
 * wall cuts those into buffers); the same with a selection buffer too
 * small (-1, the buffer full); a feedback pass of points, a strip, a
 * polygon, glBitmap and glPassThrough markers in GL_3D_COLOR; one too
 * small (-1); then a drawn frame that shows no primitive of the passes
 * (GL draws nothing in them). Depths and coordinates are printed as exact
 * bit patterns. Built twice like the examples (examples/common/exapp.h). */
#include <GL/gl.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "common/exapp.h"

enum { STRIP = 3000, ARRAY_TRIS = 600 };

static float strip[STRIP][2];
static float tris[ARRAY_TRIS * 3][2];

static void print_uints(const char *what, GLint ret, const GLuint *v, int n)
{
    printf("%s: returned %d:", what, ret);
    for (int i = 0; i < n; i++)
        printf(" %08x", v[i]);
    printf("\n");
}

static void print_floats(const char *what, GLint ret, const GLfloat *v, int n)
{
    printf("%s: returned %d:", what, ret);
    for (int i = 0; i < n; i++) {
        unsigned bits;
        memcpy(&bits, &v[i], 4);
        printf(" %08x", bits);
    }
    printf("\n");
}

static void print_state(const char *when)
{
    GLint mode = 0, depth = -1;
    glGetIntegerv(GL_RENDER_MODE, &mode);
    glGetIntegerv(GL_NAME_STACK_DEPTH, &depth);
    printf("%s: error 0x%x, mode 0x%x, name stack depth %d\n", when, glGetError(), mode, depth);
}

static void setup_view(int frame)
{
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(-1, 1, -1, 1, -2, 2);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glRotatef(7.0f * (float)frame, 0, 0, 1);
}

static void quad(float x0, float y0, float x1, float y1, float z)
{
    glBegin(GL_QUADS);
    glVertex3f(x0, y0, z);
    glVertex3f(x1, y0, z);
    glVertex3f(x1, y1, z + 0.25f);
    glVertex3f(x0, y1, z + 0.25f);
    glEnd();
}

/* The primitives of the selection pass (names around them). */
static void select_scene(GLuint list)
{
    glInitNames();
    glPushName(0);
    glLoadName(1); /* the lower-left tile only */
    quad(-0.9f, -0.9f, -0.6f, -0.6f, 0.1f);
    glLoadName(2); /* the upper-right tile only */
    /* a state change: the geometry after it is a buffer of its own, which
     * a wall sorts by its box (the name commands go to every server) */
    glDepthFunc(GL_LESS);
    glBegin(GL_TRIANGLES);
    glVertex3f(0.5f, 0.5f, -0.5f);
    glVertex3f(0.9f, 0.6f, -0.3f);
    glVertex3f(0.7f, 0.9f, 0.2f);
    glEnd();
    glPushName(3); /* across the middle, in all four tiles */
    quad(-0.2f, -0.2f, 0.2f, 0.2f, -0.7f);
    glPushName(33);
    glBegin(GL_POINTS);
    glVertex3f(0.0f, 0.0f, 0.9f);
    glEnd();
    glPopName();
    glPopName();
    glLoadName(4); /* outside the view volume: no hit */
    quad(3.0f, 3.0f, 4.0f, 4.0f, 0.0f);
    glLoadName(5); /* left of the middle, in two tiles */
    glCallList(list);
    glLoadName(6); /* many small triangles from arrays, everywhere */
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(2, GL_FLOAT, 0, tris);
    glDrawArrays(GL_TRIANGLES, 0, ARRAY_TRIS * 3);
    glDisableClientState(GL_VERTEX_ARRAY);
    glLoadName(7); /* a long strip across the window */
    glBegin(GL_LINE_STRIP);
    for (int i = 0; i < STRIP; i++)
        glVertex2fv(strip[i]);
    glEnd();
    glLoadName(8); /* a hit on one side only: depth range of a thin line */
    glBegin(GL_LINES);
    glVertex3f(0.3f, -0.8f, 0.6f);
    glVertex3f(0.8f, -0.3f, -0.6f);
    glEnd();
}

static void selection(GLuint list, GLsizei size, const char *what)
{
    static GLuint buf[4096];
    memset(buf, 0xee, sizeof buf);
    glSelectBuffer(size, buf);
    glRenderMode(GL_SELECT);
    print_state(what);
    select_scene(list);
    print_state(what);
    GLint hits = glRenderMode(GL_RENDER);
    print_uints(what, hits, buf, size + 2); /* and two values GL must not write */
    print_state(what);
}

static void feedback_scene(void)
{
    glPassThrough(1.0f);
    glColor3f(1, 0, 0);
    glBegin(GL_POINTS);
    glVertex3f(-0.5f, 0.5f, 0.25f);
    glVertex3f(0.5f, -0.5f, -0.25f);
    glEnd();
    glPassThrough(2.0f);
    glColor3f(0, 1, 0);
    glBegin(GL_LINE_STRIP);
    for (int i = 0; i < 40; i++)
        glVertex2f(-0.95f + 0.048f * (float)i, 0.3f * sinf(0.4f * (float)i));
    glEnd();
    glColor3f(0, 0, 1);
    glDepthFunc(GL_LESS); /* the polygon in a buffer of its own */
    glBegin(GL_POLYGON);
    glVertex3f(-0.3f, -0.6f, 0.0f);
    glVertex3f(0.4f, -0.5f, 0.1f);
    glVertex3f(0.5f, 0.2f, 0.2f);
    glVertex3f(-0.1f, 0.6f, 0.3f);
    glVertex3f(-0.5f, 0.0f, 0.4f);
    glEnd();
    glPassThrough(3.0f);
    /* rows of 4 bytes: GL reads each row padded to GL_UNPACK_ALIGNMENT (4) */
    static const GLubyte bits[8 * 4] = {0xff, 0, 0, 0, 0x81, 0, 0, 0, 0x81, 0, 0, 0, 0x81, 0, 0, 0,
                                        0x81, 0, 0, 0, 0x81, 0, 0, 0, 0x81, 0, 0, 0, 0xff, 0, 0, 0};
    glRasterPos2f(0.1f, 0.1f);
    glBitmap(8, 8, 0, 0, 10, 0, bits);
    glBegin(GL_LINES); /* clipped at the view volume */
    glVertex3f(-1.5f, -0.2f, 0.0f);
    glVertex3f(1.5f, 0.2f, 0.0f);
    glEnd();
}

static void feedback(GLsizei size, GLenum type, const char *what)
{
    static GLfloat buf[4096];
    memset(buf, 0xee, sizeof buf);
    glFeedbackBuffer(size, type, buf);
    glRenderMode(GL_FEEDBACK);
    print_state(what);
    feedback_scene();
    GLint n = glRenderMode(GL_RENDER);
    print_floats(what, n, buf, size + 2);
    print_state(what);
}

int main(int argc, char **argv)
{
    exapp app;
    if (!exapp_init(&app, "select_feedback", argc, argv, 320, 240))
        return app.exit_code;
    for (int i = 0; i < STRIP; i++) {
        float a = (float)i / (float)(STRIP - 1);
        strip[i][0] = -0.95f + 1.9f * a;
        strip[i][1] = 0.8f * sinf(12.0f * a);
    }
    for (int i = 0; i < ARRAY_TRIS; i++) {
        float x = -0.95f + 1.9f * (float)(i % 30) / 30.0f, y = -0.95f + 1.9f * (float)(i / 30) / 20.0f;
        tris[3 * i][0] = x, tris[3 * i][1] = y;
        tris[3 * i + 1][0] = x + 0.03f, tris[3 * i + 1][1] = y;
        tris[3 * i + 2][0] = x, tris[3 * i + 2][1] = y + 0.03f;
    }
    GLuint list = glGenLists(1);
    glNewList(list, GL_COMPILE);
    glPushName(50);
    quad(-0.7f, -0.1f, -0.3f, 0.1f, 0.5f);
    glPopName();
    glEndList();
    glEnable(GL_DEPTH_TEST);
    for (int f = 0; f < app.frames; f++) {
        glClearColor(0.1f, 0.1f, 0.2f, 1);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        setup_view(f);
        printf("frame %d\n", f);
        /* no selection buffer yet (first frame): an error, and in Mesa
         * the mode changes anyway */
        if (f == 0) {
            GLint r = glRenderMode(GL_SELECT);
            printf("select without a buffer: returned %d\n", r);
            print_state("select without a buffer");
            glColor3f(1, 1, 0);
            quad(-0.2f, 0.5f, 0.2f, 0.9f, 0.0f);
        }
        selection(list, 4000, "selection");
        selection(list, 9, "selection overflow");
        feedback(4000, GL_3D_COLOR, "feedback 3D colour");
        feedback(7, GL_2D, "feedback overflow");
        /* what the frame shows: drawn in GL_RENDER mode */
        glColor3f(0.8f, 0.8f, 0.8f);
        quad(-0.5f, -0.9f, -0.1f, -0.5f, 0.0f);
        if (!exapp_swap(&app))
            break;
    }
    return exapp_finish(&app);
}
