/* tests/tilesort/program_scenes_driver.c — what unmodified programs did that the
 * examples did not, and that tilesort once drew wrong (issue 12, item 6:
 * the xscreensaver hacks through the 2x2 wall), one scene a frame:
 *   0 glMaterial inside glBegin/glEnd (moebius's wire mesh): a lit strip
 *     mesh across the window with a diffuse colour set before every
 *     vertex, then, outside, the material of before the mesh set again for
 *     a lit quad (a server must not keep the mesh's last material)
 *   1 vertex buffers bound in turn around each draw (romanboy): three
 *     buffers filled and unbound, then each glDrawElements binds the
 *     position buffer, points at it, binds the colour buffer, points at
 *     it, binds the index buffer, draws and unbinds, so no binding names
 *     the first buffer when the next state change comes
 *   2 client arrays enabled with glEnable(GL_VERTEX_ARRAY) and
 *     glEnable(GL_COLOR_ARRAY) instead of glEnableClientState, as piglit's
 *     gl-1.1-color-material-array does (Mesa takes both; tilesort drew
 *     nothing, a pack server died of SIGSEGV), disabled with glDisable
 *   3 user clip planes 6 and 7 (Mesa has 8; piglit's
 *     gl-1.0-user-clip-all-planes uses every one): the tracker kept 6, so
 *     the wall's servers never clipped with the last two
 *   4 glDrawPixels of GL_RGB/GL_SHORT with GL_UNPACK_SWAP_BYTES across
 *     every tile (piglit's draw-pixels): Mesa swaps wrongly once the
 *     scissor clips an image, and a tile's scissor clips it, so the
 *     servers drew the wrong pixels and one died of SIGSEGV; and the GL
 *     errors the wall must answer as GL does: glGetError inside
 *     glBegin/glEnd (GL_INVALID_OPERATION after glEnd) and a glDrawPixels
 *     whose packed type does not go with its format, pointer NULL
 *     (GL_INVALID_OPERATION; the packer dropped it unanswered), and a
 *     list of vertices called inside glBegin (no error: a tiled render
 *     set its scissor around the call there). A wrong error ends the
 *     program with status 1.
 *   5 glDrawPixels of GL_COLOR_INDEX images (GL_UNSIGNED_BYTE and
 *     GL_BITMAP, mapped to RGBA by glPixelMap, as piglit's
 *     gl-1.0-drawpixels-color-index) across the tile borders: Mesa reads
 *     past the end of its own converted image whenever a colour-index
 *     image is clipped, and a tile's scissor clips it (a server's
 *     heap-buffer-overflow under AddressSanitizer, wrong pixels without).
 *   6 a display list per glBitmap, all called with glCallLists, three
 *     deleted, all called again (piglit's gl-1.0-dlist-bitmap): glCallLists
 *     reaches the servers whole, and the servers kept their copies of the
 *     deleted lists and drew them.
 *   7 the same glMaterialfv before every glBegin of a lit mesh of quads
 *     (geodesic): the servers get the calls as the program made them
 *     (spus/tilesort/send.c says why; geodesic's capture differed from
 *     the 1x1 render by a pixel without). This scene's pixels matched
 *     before that too: it shows the calls, repeated and put in the
 *     geometry buffers, draw exactly on every server.
 * Built twice like the examples (examples/common/exapp.h): -native is the
 * reference. Deterministic. */
#define GL_GLEXT_PROTOTYPES 1
#include <stdio.h>
#include <GL/gl.h>
#include <GL/glext.h>

#include "common/exapp.h"

static void lit_mesh(void)
{
    static const GLfloat grey[4] = {0.3f, 0.3f, 0.3f, 1}, light[4] = {0.2f, 0.4f, 1, 0};
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glLightfv(GL_LIGHT0, GL_POSITION, light);
    glMaterialfv(GL_FRONT_AND_BACK, GL_DIFFUSE, grey);
    for (int row = 0; row < 12; row++) {
        glBegin(GL_TRIANGLE_STRIP);
        for (int col = 0; col <= 24; col++) {
            GLfloat c[4] = {(float)((col + row) % 3) / 2.0f, (float)(col % 2), (float)(row % 4) / 3.0f, 1};
            glMaterialfv(GL_FRONT_AND_BACK, GL_DIFFUSE, c);
            glNormal3f(0.1f * (float)(col % 5), 0.2f, 1);
            for (int k = 0; k < 2; k++)
                glVertex2f(-0.95f + 0.078f * (float)col, -0.9f + 0.12f * (float)(row + k));
        }
        glEnd();
    }
    /* the material of before the mesh again: only the tracker can know a
     * server lacks it */
    glMaterialfv(GL_FRONT_AND_BACK, GL_DIFFUSE, grey);
    glBegin(GL_QUADS);
    glNormal3f(0, 0, 1);
    glVertex2f(-0.5f, 0.55f);
    glVertex2f(0.5f, 0.55f);
    glVertex2f(0.5f, 0.95f);
    glVertex2f(-0.5f, 0.95f);
    glEnd();
    glDisable(GL_LIGHTING);
}

static void buffers_in_turn(void)
{
    enum { N = 16 };
    GLfloat pos[2 * N * N], col[3 * N * N];
    GLuint idx[6 * (N - 1) * (N - 1)];
    int n = 0;
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            int v = y * N + x;
            pos[2 * v] = -0.9f + 1.8f * (float)x / (N - 1);
            pos[2 * v + 1] = -0.9f + 1.8f * (float)y / (N - 1);
            col[3 * v] = (float)x / (N - 1);
            col[3 * v + 1] = (float)y / (N - 1);
            col[3 * v + 2] = (float)((x + y) % 2);
            if (x < N - 1 && y < N - 1) {
                GLuint q[6] = {v, v + 1, v + N, v + 1, v + N + 1, v + N};
                for (int k = 0; k < 6; k++)
                    idx[n++] = q[k];
            }
        }
    GLuint b[3];
    glGenBuffers(3, b);
    glBindBuffer(GL_ARRAY_BUFFER, b[0]);
    glBufferData(GL_ARRAY_BUFFER, sizeof pos, pos, GL_STATIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glBindBuffer(GL_ARRAY_BUFFER, b[1]);
    glBufferData(GL_ARRAY_BUFFER, sizeof col, col, GL_STATIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b[2]);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, sizeof idx, idx, GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    for (int draw = 0; draw < 3; draw++) {
        glLoadIdentity();
        glTranslatef(0.3f * (float)(draw - 1), 0.2f * (float)(draw - 1), 0);
        glScalef(0.6f, 0.6f, 1);
        glBindBuffer(GL_ARRAY_BUFFER, b[0]);
        glVertexPointer(2, GL_FLOAT, 0, (const void *)0);
        glEnableClientState(GL_VERTEX_ARRAY);
        glBindBuffer(GL_ARRAY_BUFFER, b[1]);
        glColorPointer(3, GL_FLOAT, 0, (const void *)0);
        glEnableClientState(GL_COLOR_ARRAY);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b[2]);
        glDrawElements(GL_TRIANGLES, n, GL_UNSIGNED_INT, (const void *)0);
        glDisableClientState(GL_VERTEX_ARRAY);
        glDisableClientState(GL_COLOR_ARRAY);
        glBindBuffer(GL_ARRAY_BUFFER, b[1]);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b[2]);
        glBindBuffer(GL_ARRAY_BUFFER, 0);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    }
    glLoadIdentity();
    glDeleteBuffers(3, b);
}

static void arrays_enabled_by_glenable(void)
{
    enum { N = 24 };
    GLfloat pos[N][2], col[N][4];
    for (int i = 0; i < N; i++) {
        pos[i][0] = -0.9f + 1.8f * (float)(i / 2) / (N / 2 - 1);
        pos[i][1] = i % 2 ? 0.8f : -0.7f + 0.05f * (float)i;
        col[i][0] = (float)(i % 3) / 2.0f;
        col[i][1] = (float)(i % 5) / 4.0f;
        col[i][2] = 1.0f - (float)i / N;
        col[i][3] = 1;
    }
    glVertexPointer(2, GL_FLOAT, 0, pos);
    glColorPointer(4, GL_FLOAT, 0, col);
    glEnable(GL_VERTEX_ARRAY);
    glEnable(GL_COLOR_ARRAY);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, N);
    glDisable(GL_COLOR_ARRAY);
    glColor3f(1, 1, 0);
    glDrawArrays(GL_LINE_STRIP, 0, N);
    glDisable(GL_VERTEX_ARRAY);
}

static void last_clip_planes(void)
{
    static const GLdouble right_of[4] = {1, 0, 0, 0.3}, below[4] = {0, -1, 0, 0.5};
    glPushMatrix();
    glRotatef(20, 0, 0, 1); /* planes are taken in eye space at glClipPlane */
    glClipPlane(GL_CLIP_PLANE0 + 6, right_of);
    glClipPlane(GL_CLIP_PLANE0 + 7, below);
    glPopMatrix();
    glEnable(GL_CLIP_PLANE0 + 6);
    glEnable(GL_CLIP_PLANE0 + 7);
    glColor3f(0.2f, 0.9f, 0.4f);
    glRectf(-0.95f, -0.95f, 0.95f, 0.95f);
    glDisable(GL_CLIP_PLANE0 + 7);
    glColor3f(0.9f, 0.2f, 0.6f);
    glRectf(-0.9f, 0.6f, 0.9f, 0.9f);
    glDisable(GL_CLIP_PLANE0 + 6);
}

static bool error_is(GLenum want, const char *what)
{
    GLenum e = glGetError();
    if (e == want)
        return true;
    fprintf(stderr, "program_scenes: FAIL: glGetError after %s: 0x%x, not 0x%x\n", what, e, want);
    return false;
}

static bool swapped_pixels_and_errors(void)
{
    enum { W = 600, H = 500 };
    static GLshort image[W * H * 3];
    for (int i = 0; i < W * H * 3; i++) {
        unsigned v = ((unsigned)i * 2654435761u >> 17) & 0x7fff; /* positive: not clamped */
        image[i] = (GLshort)(((v & 0xff) << 8) | (v >> 8));      /* stored swapped */
    }
    bool ok = error_is(GL_NO_ERROR, "the frame's start");
    glRasterPos2f(-0.9f, -0.9f);
    glPixelStorei(GL_UNPACK_SWAP_BYTES, GL_TRUE);
    glDrawPixels(W, H, GL_RGB, GL_SHORT, image);
    glPixelStorei(GL_UNPACK_SWAP_BYTES, GL_FALSE);
    ok = error_is(GL_NO_ERROR, "glDrawPixels with swapped bytes") && ok;
    glBegin(GL_POINTS);
    ok = error_is(GL_NO_ERROR, "glGetError inside glBegin (itself an error, answered 0)") && ok;
    glVertex2f(0.95f, 0.95f);
    glEnd();
    ok = error_is(GL_INVALID_OPERATION, "glEnd after a glGetError inside glBegin") && ok;
    glDrawPixels(4, 4, GL_BGR, GL_UNSIGNED_SHORT_5_6_5, NULL);
    ok = error_is(GL_INVALID_OPERATION, "glDrawPixels of GL_BGR with GL_UNSIGNED_SHORT_5_6_5") && ok;
    GLuint list = glGenLists(1);
    glNewList(list, GL_COMPILE);
    glColor3f(0.9f, 0.8f, 0.1f);
    glVertex2f(0.4f, -0.95f);
    glVertex2f(0.95f, -0.95f);
    glVertex2f(0.95f, 0.4f);
    glEndList();
    glBegin(GL_TRIANGLES);
    glCallList(list); /* legal: the list holds only vertices and colours */
    glEnd();
    glDeleteLists(list, 1);
    ok = error_is(GL_NO_ERROR, "a list of vertices called inside glBegin") && ok;
    return ok;
}

static void colour_index_pixels(void)
{
    static const GLfloat red[4] = {1, 0, 0.5f, 1}, green[4] = {0, 1, 0.25f, 1}, blue[4] = {0.2f, 0, 1, 1},
                         alpha[4] = {1, 1, 1, 1};
    glPixelMapfv(GL_PIXEL_MAP_I_TO_R, 4, red);
    glPixelMapfv(GL_PIXEL_MAP_I_TO_G, 4, green);
    glPixelMapfv(GL_PIXEL_MAP_I_TO_B, 4, blue);
    glPixelMapfv(GL_PIXEL_MAP_I_TO_A, 4, alpha);
    glPixelTransferi(GL_MAP_COLOR, GL_TRUE);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    /* bitmap rows of whole bytes: Mesa 22.3 reads a GL_COLOR_INDEX
     * GL_BITMAP image of another width as rows of exactly `width` bits, not
     * padded to a byte as GL says (an OSMesa program shows it) */
    enum { W = 90, H = 70, BITS_W = 96 };
    static GLubyte index[W * H], bits[BITS_W / 8 * H];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            index[y * W + x] = (GLubyte)((x / 7 + y / 5) % 4);
    for (int i = 0; i < (int)sizeof bits; i++)
        bits[i] = (GLubyte)(0x5a ^ (i * 29));
    /* each image crosses a border of the 2x2 wall's tiles (the window's
     * middle), at odd offsets; the bitmaps over all four tiles; every
     * image inside the window (Mesa misreads a clipped one natively too) */
    GLint view[4];
    glGetIntegerv(GL_VIEWPORT, view);
    int mx = view[2] / 2, my = view[3] / 2;
    glWindowPos2i(mx - 41, 20);
    glDrawPixels(W, H, GL_COLOR_INDEX, GL_UNSIGNED_BYTE, index);
    glWindowPos2i(13, my - 29);
    glDrawPixels(W, H, GL_COLOR_INDEX, GL_UNSIGNED_BYTE, index);
    glWindowPos2i(mx - 43, my - 37);
    glDrawPixels(BITS_W, H, GL_COLOR_INDEX, GL_BITMAP, bits);
    glWindowPos2i(mx - 3, my - 61);
    glDrawPixels(BITS_W, H, GL_COLOR_INDEX, GL_BITMAP, bits);
    glPixelTransferi(GL_MAP_COLOR, GL_FALSE);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
}

static void bitmaps_after_deleting_lists(void)
{
    enum { N = 12 };
    static GLubyte bits[16 * 12];
    for (int i = 0; i < (int)sizeof bits; i++)
        bits[i] = (GLubyte)(0xa5 ^ (i * 37));
    GLuint base = glGenLists(N);
    for (int i = 0; i < N; i++) {
        glNewList(base + (GLuint)i, GL_COMPILE);
        /* wide steps: the row of bitmaps crosses the middle of the window */
        glBitmap(128, 12, 0, 0, 27, (GLfloat)(i % 2 ? 9 : -5), bits);
        glEndList();
    }
    GLubyte ids[N];
    for (int i = 0; i < N; i++)
        ids[i] = (GLubyte)i;
    glListBase(base);
    glColor3f(0, 1, 1);
    glWindowPos2i(3, 40); /* every list called once: the servers hold them all */
    glCallLists(N, GL_UNSIGNED_BYTE, ids);
    glDeleteLists(base + 4, 3);
    glColor3f(1, 1, 0);
    glWindowPos2i(3, 100);
    glCallLists(N, GL_UNSIGNED_BYTE, ids);
    glListBase(0);
    glDeleteLists(base, N);
}

static void material_before_every_pair(void)
{
    static const GLfloat colour[4] = {0.26f, 0.21f, 0.23f, 1}, light[4] = {1, 1, 1, 0}, white[4] = {1, 1, 1, 1};
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glEnable(GL_NORMALIZE);
    glLightfv(GL_LIGHT0, GL_POSITION, light);
    glMaterialfv(GL_FRONT, GL_SPECULAR, white);
    glMaterialf(GL_FRONT, GL_SHININESS, 64);
    for (int row = 0; row < 16; row++)
        for (int col = 0; col < 16; col++) {
            glMaterialfv(GL_FRONT, GL_AMBIENT_AND_DIFFUSE, colour);
            float x = -0.98f + 0.1225f * (float)col, y = -0.98f + 0.1225f * (float)row;
            glBegin(GL_QUADS);
            for (int k = 0; k < 4; k++) {
                float dx = (k == 1 || k == 2) ? 0.12f : 0, dy = k >= 2 ? 0.12f : 0;
                glNormal3f(0.3f * (x + dx), 0.3f * (y + dy) - 0.1f, 0.7f + 0.05f * (float)((col + k) % 3));
                glVertex2f(x + dx, y + dy);
            }
            glEnd();
        }
    glMaterialfv(GL_FRONT, GL_SPECULAR, (const GLfloat[4]){0, 0, 0, 1});
    glDisable(GL_NORMALIZE);
    glDisable(GL_LIGHTING);
}

int main(int argc, char **argv)
{
    exapp app;
    if (!exapp_init(&app, "program_scenes", argc, argv, 320, 240))
        return app.exit_code;
    for (int f = 0; f < app.frames; f++) {
        glClearColor(0.05f, 0.05f, 0.1f, 1);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        if (f % 8 == 0)
            lit_mesh();
        else if (f % 8 == 1)
            buffers_in_turn();
        else if (f % 8 == 2)
            arrays_enabled_by_glenable();
        else if (f % 8 == 3)
            last_clip_planes();
        else if (f % 8 == 4) {
            if (!swapped_pixels_and_errors())
                app.exit_code = 1;
        } else if (f % 8 == 5)
            colour_index_pixels();
        else if (f % 8 == 6)
            bitmaps_after_deleting_lists();
        else
            material_before_every_pair();
        if (!exapp_swap(&app))
            break;
    }
    return exapp_finish(&app);
}
