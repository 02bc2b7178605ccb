/* tests/binaryswap/behind_viewer_driver.c — a scene for binaryswap's region of
 * interest (issue 11, item 2): geometry that straddles the eye plane and
 * geometry wholly behind the viewer, under a perspective projection, so
 * that boxes have corners at w <= 0. Built twice like the examples
 * (examples/common/exapp.h): behind_viewer-native is the reference,
 * behind_viewer enters a chain. With --part K/N it draws share K of the
 * triangles (exapp_part_range), immediate mode and client arrays alike.
 * The frames turn the scene a little, so boxes move. --bounds (the tessera
 * build; the native one ignores it) also sends BoundsInfoTSR with a box
 * around the eye, which covers the whole window. Used by
 * tests/binaryswap.cmake (binaryswap_bounds_behind_viewer,
 * binaryswap_roi_bounds_info_is_honoured). */
#include <GL/gl.h>
#include <stdbool.h>

#include "common/exapp.h"

#ifndef EXAPP_NATIVE
void glBoundsInfoTSR(const GLfloat *bounds); /* libtessera_gl's, not in GL/gl.h */
#endif

#define TRIS 8

/* Triangle i: x, y, z of its three corners (eye space at frame 0: the eye
 * at the origin looking down -z; z > 0 is behind it). */
static const float tris[TRIS][9] = {
    /* a floor from behind the viewer to far ahead (straddles the eye plane) */
    {-3, -1, 4, 3, -1, 4, 3, -1, -12},
    {-3, -1, 4, 3, -1, -12, -3, -1, -12},
    /* a wall on the left, reaching behind the viewer */
    {-1.5f, -1, 3, -1.5f, 2, 3, -1.5f, 2, -9},
    {-1.5f, -1, 3, -1.5f, 2, -9, -1.5f, -1, -9},
    /* wholly behind the viewer: draws nothing */
    {-1, -1, 2, 1, -1, 2, 0, 1, 3},
    /* in front, small: ordinary */
    {0.2f, 0, -3, 0.8f, 0, -3, 0.5f, 0.6f, -3.5f},
    /* crossing the eye plane right in front of the eye (near plane cut) */
    {-0.3f, 0.4f, 1, 0.3f, 0.4f, 1, 0, 0.2f, -2},
    /* far ahead, crossing the far plane */
    {-0.5f, 0.5f, -10, 0.5f, 0.5f, -30, 0, 1, -10},
};

static const float colors[TRIS][3] = {
    {0.3f, 0.6f, 0.3f}, {0.2f, 0.5f, 0.2f}, {0.7f, 0.3f, 0.3f}, {0.6f, 0.2f, 0.2f},
    {1, 1, 0},          {0.2f, 0.3f, 0.9f}, {0.9f, 0.6f, 0.1f}, {0.6f, 0.6f, 0.9f},
};

static void draw(const exapp *app, int frame, bool bounds)
{
    glClearColor(0.05f, 0.05f, 0.1f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glViewport(0, 0, app->width, app->height);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    double aspect = (double)app->width / app->height;
    glFrustum(-0.5 * aspect, 0.5 * aspect, -0.5, 0.5, 1.0, 20.0);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glRotatef(6.0f * (float)frame, 0, 1, 0);
#ifndef EXAPP_NATIVE
    if (bounds) {
        static const GLfloat around_the_eye[6] = {-1, -1, -1, 1, 1, 1};
        glBoundsInfoTSR(around_the_eye);
    }
#else
    (void)bounds;
#endif
    long first = 0, n = exapp_part_range(app, TRIS, &first);
    /* the first half of the share immediate, the rest from client arrays */
    long half = n / 2;
    glBegin(GL_TRIANGLES);
    for (long i = first; i < first + half; i++) {
        glColor3fv(colors[i]);
        for (int v = 0; v < 3; v++)
            glVertex3fv(&tris[i][3 * v]);
    }
    glEnd();
    float pos[TRIS * 9], col[TRIS * 9];
    int count = 0;
    for (long i = first + half; i < first + n; i++)
        for (int v = 0; v < 3; v++, count++)
            for (int c = 0; c < 3; c++) {
                pos[count * 3 + c] = tris[i][3 * v + c];
                col[count * 3 + c] = colors[i][c];
            }
    if (count) {
        glEnableClientState(GL_VERTEX_ARRAY);
        glEnableClientState(GL_COLOR_ARRAY);
        glVertexPointer(3, GL_FLOAT, 0, pos);
        glColorPointer(3, GL_FLOAT, 0, col);
        glDrawArrays(GL_TRIANGLES, 0, count);
        glDisableClientState(GL_COLOR_ARRAY);
        glDisableClientState(GL_VERTEX_ARRAY);
    }
}

int main(int argc, char **argv)
{
    exapp app;
    bool bounds = false;
    if (!exapp_init_flag(&app, "behind_viewer", argc, argv, 96, 72, "--bounds",
                         "  --bounds        send BoundsInfoTSR with a box around the eye (the tessera build)", &bounds))
        return exapp_finish(&app);
    for (int f = 0; f < app.frames; f++) {
        draw(&app, f, bounds);
        if (!exapp_swap(&app))
            break;
    }
    return exapp_finish(&app);
}
