/* tests/render/quad_diagonal_test.c — the Mesa behaviour behind the one known
 * inexactness of a wall (tests/faker/sweep_exact.sh, engine): with OSMesa
 * alone (no tessera), llvmpipe cuts a GL_QUADS quad into triangles along
 * one diagonal or the other depending on the rest of the draw it is in.
 *
 * Quad A (left half of the window, smooth-lit with a different normal at
 * each corner, so the two diagonals give different colours) is drawn
 *   alone:    glBegin(GL_QUADS) A glEnd
 *   +outside: glBegin(GL_QUADS) A B glEnd, B in the right half crossing
 *             the window's top edge (so it must be clipped)
 *   +inside:  glBegin(GL_QUADS) A C glEnd, C in the right half, inside
 * and as GL_TRIANGLES 0,1,2 0,2,3 and 0,1,3 1,2,3, alone and beside B.
 * Measured on Mesa 22.3 llvmpipe: A alone (and beside C) is A as 0,1,2
 * 0,2,3; A beside B is A as 0,1,3 1,2,3 (4888 of its 4949 pixels differ,
 * up to 68 levels); triangles are the same in every draw. So a quad's
 * pixels depend on whether the draw Mesa makes of it (consecutive
 * glBegin/glEnd pairs up to a state change, up to 64 of them, cut where
 * the 64 KiB immediate-mode buffer wraps) holds a vertex that needs
 * clipping. A wall server gets a subset of the stream, with state diffs
 * in between, so its draws differ from the whole window's: engine's lit
 * quads came out 1-3 levels off (every failing capture became exact with
 * each glBegin/glEnd made its own draw on both sides). Only GL_QUADS:
 * the same pair (A then B, each its own glBegin/glEnd, one draw) as
 * GL_QUAD_STRIP, GL_POLYGON, GL_TRIANGLE_FAN or GL_TRIANGLE_STRIP changed
 * no pixel of A; as GL_QUADS, 4888.
 *
 * Exits 0 while llvmpipe behaves so, 1 (saying so) when it no longer does:
 * then sweep_exact.sh's tolerance for engine may be removable. */
#include <GL/gl.h>
#include <GL/osmesa.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { W = 320, H = 240 };

typedef enum { AS_QUADS, AS_TRIANGLES_012_023, AS_TRIANGLES_013_123 } shape;
typedef enum { ALONE, WITH_OUTSIDE, WITH_INSIDE } partner;

static void quad(shape s, float x0, float y0, float x1, float y1)
{
    static const int quads[] = {0, 1, 2, 3}, t012[] = {0, 1, 2, 0, 2, 3}, t013[] = {0, 1, 3, 1, 2, 3};
    const int *order = s == AS_QUADS ? quads : s == AS_TRIANGLES_012_023 ? t012 : t013;
    int n = s == AS_QUADS ? 4 : 6;
    const float xs[4] = {x0, x1, x1, x0}, ys[4] = {y0, y0, y1, y1};
    for (int j = 0; j < n; j++) {
        int i = order[j];
        glNormal3f(i & 1 ? 0.3f : -0.3f, i & 2 ? 0.2f : -0.2f, 0.9f);
        glVertex3f(xs[i], ys[i], 0.37f * xs[i] - 0.21f * ys[i]);
    }
}

static int render(unsigned char *pixels, shape s, partner p)
{
    OSMesaContext c = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, NULL);
    if (!c || !OSMesaMakeCurrent(c, pixels, GL_UNSIGNED_BYTE, W, H))
        return -1;
    glViewport(0, 0, W, H);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glMatrixMode(GL_PROJECTION);
    glFrustum(-0.75, 0.75, -0.5625, 0.5625, 1.5, 70);
    glMatrixMode(GL_MODELVIEW);
    glTranslatef(0, 0, -20);
    glRotatef(23.5f, 1, 0, 0);
    glRotatef(-31.25f, 0, 1, 0);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glEnable(GL_NORMALIZE);
    const GLfloat position[] = {7, 7, 12, 1}, specular[] = {0.8f, 0.8f, 0.8f, 1}, yellow[] = {1, 1, 0, 1};
    glLightfv(GL_LIGHT0, GL_POSITION, position);
    glLightfv(GL_LIGHT0, GL_SPECULAR, specular);
    glMaterialfv(GL_FRONT, GL_AMBIENT_AND_DIFFUSE, yellow);
    glMaterialfv(GL_FRONT, GL_SPECULAR, specular);
    glMateriali(GL_FRONT, GL_SHININESS, 20);
    glBegin(s == AS_QUADS ? GL_QUADS : GL_TRIANGLES);
    quad(s, -9, -4, -2, 3); /* A */
    if (p == WITH_OUTSIDE)
        quad(s, 3, 4, 6, 12); /* B: crosses the top edge */
    if (p == WITH_INSIDE)
        quad(s, 3, -2, 6, 2); /* C */
    glEnd();
    glFinish();
    OSMesaDestroyContext(c);
    return 0;
}

/* Pixels of the left half (A's; B and C draw only in the right half) that differ. */
static int left_half_differs(const unsigned char *a, const unsigned char *b)
{
    int n = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W / 2; x++)
            n += memcmp(a + (y * W + x) * 4, b + (y * W + x) * 4, 4) != 0;
    return n;
}

static int lit_left_half(const unsigned char *a)
{
    int n = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W / 2; x++)
            n += a[(y * W + x) * 4] != 0;
    return n;
}

int main(void)
{
    static unsigned char alone[W * H * 4], outside[W * H * 4], inside[W * H * 4], t012[W * H * 4], t013[W * H * 4],
        t012_outside[W * H * 4];
    if (render(alone, AS_QUADS, ALONE) || render(outside, AS_QUADS, WITH_OUTSIDE) ||
        render(inside, AS_QUADS, WITH_INSIDE) || render(t012, AS_TRIANGLES_012_023, ALONE) ||
        render(t013, AS_TRIANGLES_013_123, ALONE) || render(t012_outside, AS_TRIANGLES_012_023, WITH_OUTSIDE)) {
        fprintf(stderr, "FAIL: no OSMesa context\n");
        return 2;
    }
    int a = lit_left_half(alone);
    int by_outside = left_half_differs(alone, outside), by_inside = left_half_differs(alone, inside);
    int alone_012 = left_half_differs(alone, t012), outside_013 = left_half_differs(outside, t013);
    int triangles_by_outside = left_half_differs(t012, t012_outside);
    printf("quad A: %d pixels\n", a);
    printf("A beside an edge-crossing quad in its draw: %d pixels differ from A alone\n", by_outside);
    printf("A beside an inside quad in its draw: %d differ\n", by_inside);
    printf("A alone against A as triangles 0,1,2 0,2,3: %d differ\n", alone_012);
    printf("A beside the edge-crossing quad against A as triangles 0,1,3 1,2,3: %d differ\n", outside_013);
    printf("A as triangles beside the edge-crossing triangles: %d differ from them alone\n", triangles_by_outside);
    if (a < 1000) {
        fprintf(stderr, "FAIL: quad A is not in view (%d pixels)\n", a);
        return 2;
    }
    if (by_inside || triangles_by_outside || alone_012 || outside_013 || by_outside < a / 2) {
        printf("llvmpipe no longer cuts a quad by what else its draw holds as measured on Mesa 22.3: "
               "tests/faker/sweep_exact.sh's tolerance for engine may be removable\n");
        return 1;
    }
    printf("ok: llvmpipe cuts a quad along 0-2 alone, along 1-3 when its draw holds a vertex to clip\n");
    return 0;
}
