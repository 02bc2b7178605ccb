/* examples/tilescenes.c — the scenes where sort-first goes wrong if it is
 * not done carefully, one per frame (frame % 8):
 *   0 lit, textured triangles          4 polygons crossing the eye plane
 *   1 display lists (nested, state)    5 a NaN and an Inf vertex
 *   2 vertex arrays (arrays, elements; 6 primitives covering the window; long
 *     points, wide lines, quads and       strips, fans, loops and polygons
 *     triangles that tilesort sorts    7 glDrawPixels, glBitmap, glRect across
 *     one by one, w <= 0 and NaN too)     tile borders
 *   3 wide lines, large points centred
 *     just outside tile edges
 * and two where sort-first degrades towards broadcast, which must stay
 * exact all the same (frame % 10):
 *   8 every primitive covers the whole window (each batch hits every tile)
 *   9 a state change between every primitive (batches of one triangle)
 * and one long primitive of each mode crossing many tiles, which small
 * batches cut into many pieces (frame % 15):
 *  10 triangle strips: culling and two-sided lighting (winding parity),
 *     flat and smooth
 *  11 a triangle fan, polygons (flat: the first vertex's colour), a quad
 *     strip (unsigned byte colours, homogeneous positions)
 *  12 polygon mode line/point: a polygon, triangles and quads with edge
 *     flags, a strip and a fan
 *  13 a wide flat line strip (integer vertices), line loops, wide lines,
 *     big points
 *  14 lit, textured, coloured triangle and quad lists
 * Tile edges fall on halves, thirds and quarters of the window in the
 * test configurations, so the edge scenes put their primitives at every
 * twelfth of the window, a few pixels to either side. Ordinary GL 1.x code;
 * deterministic per frame. */
#include <math.h>
#include <stdlib.h>

#include <GL/gl.h>

#include "common/exapp.h"

#define PI_F 3.14159265358979f

static GLuint texture, lists;

static void setup(void)
{
    glClearColor(0.1f, 0.12f, 0.15f, 1.0f);
    glEnable(GL_DEPTH_TEST);
    unsigned char img[16 * 16 * 4];
    for (int i = 0; i < 16 * 16; i++) {
        int on = ((i % 16) / 4 + (i / 16) / 4) & 1;
        img[4 * i] = (unsigned char)(on ? 230 : 30);
        img[4 * i + 1] = (unsigned char)(on ? 200 : 90);
        img[4 * i + 2] = (unsigned char)(on ? 60 : 200);
        img[4 * i + 3] = 255;
    }
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 16, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, img);
    glBindTexture(GL_TEXTURE_2D, 0);

    lists = glGenLists(4);
    glNewList(lists, GL_COMPILE); /* geometry only: placed by its box */
    glBegin(GL_TRIANGLES);
    for (int i = 0; i < 12; i++) {
        float a = 2 * PI_F * (float)i / 12.0f;
        glColor3f(0.5f + 0.5f * cosf(a), 0.5f + 0.5f * sinf(a), 0.6f);
        glVertex2f(0.2f * cosf(a), 0.2f * sinf(a));
        glVertex2f(0.2f * cosf(a + 0.4f), 0.2f * sinf(a + 0.4f));
        glVertex2f(0, 0);
    }
    glEnd();
    glEndList();
    glNewList(lists + 1, GL_COMPILE); /* state changes and a nested call */
    glPushMatrix();
    glTranslatef(0.45f, 0.3f, 0);
    glRotatef(30, 0, 0, 1);
    glCallList(lists);
    glPopMatrix();
    glColor3f(1, 1, 0); /* leaves the current colour changed */
    glEndList();
    glNewList(lists + 2, GL_COMPILE_AND_EXECUTE);
    glLineWidth(3);
    glEndList();
    glLineWidth(1);
    glNewList(lists + 3, GL_COMPILE); /* binds a texture: it must reach the servers first */
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, texture);
    glBegin(GL_QUADS);
    glColor3f(1, 1, 1);
    glTexCoord2f(0, 0);
    glVertex2f(-0.9f, -0.9f);
    glTexCoord2f(1, 0);
    glVertex2f(-0.3f, -0.9f);
    glTexCoord2f(1, 1);
    glVertex2f(-0.3f, -0.3f);
    glTexCoord2f(0, 1);
    glVertex2f(-0.9f, -0.3f);
    glEnd();
    glBindTexture(GL_TEXTURE_2D, 0);
    glDisable(GL_TEXTURE_2D);
    glEndList();
}

static void ortho(void)
{
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(-1, 1, -1, 1, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
}

/* Window x, y of the k-th twelfth in normalised device units. */
static float ndc(int k, int twelfths) { return -1.0f + 2.0f * (float)k / (float)twelfths; }

static void scene_lit(int frame)
{
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glFrustum(-0.6, 0.6, -0.45, 0.45, 1, 10);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glTranslatef(0, 0, -3);
    glRotatef(10.0f * (float)frame, 0.3f, 1, 0);
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    GLfloat pos[4] = {1, 2, 3, 0};
    glLightfv(GL_LIGHT0, GL_POSITION, pos);
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, texture);
    glBegin(GL_TRIANGLES);
    for (int i = 0; i < 40; i++) {
        float a = 2 * PI_F * (float)i / 40.0f, b = a + 2 * PI_F / 40.0f;
        glNormal3f(cosf(a), sinf(a), 0.5f);
        glTexCoord2f(0, 0);
        glVertex3f(cosf(a), sinf(a), -0.3f);
        glTexCoord2f(1, 0);
        glVertex3f(cosf(b), sinf(b), -0.3f);
        glTexCoord2f(0.5f, 1);
        glVertex3f(0, 0, 0.4f);
    }
    glEnd();
    glDisable(GL_TEXTURE_2D);
    glDisable(GL_LIGHTING);
}

static void scene_lists(int frame)
{
    ortho();
    /* the texture changes before the list that binds it runs */
    unsigned char texel[4] = {(unsigned char)(40 * frame), 250, 20, 255};
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexSubImage2D(GL_TEXTURE_2D, 0, frame % 16, 3, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, texel);
    glBindTexture(GL_TEXTURE_2D, 0);
    glCallList(lists + 3);
    glRotatef(5.0f * (float)frame, 0, 0, 1);
    glCallList(lists);
    glCallList(lists + 1);
    glTranslatef(-0.5f, -0.4f, 0);
    glCallList(lists); /* the current colour the list left */
    glBegin(GL_LINES);
    glVertex2f(-0.9f, 0.9f);
    glVertex2f(0.9f, -0.9f);
    glEnd();
    GLuint names[2] = {0, 1};
    glListBase(lists);
    glCallLists(2, GL_UNSIGNED_INT, names);
    glListBase(0);
}

static void scene_arrays(const exapp *app, int frame)
{
    ortho();
    enum { N = 64 };
    GLfloat v[N * 2], c[N * 3];
    GLushort idx[N];
    for (int i = 0; i < N; i++) {
        float a = 2 * PI_F * (float)i / N + 0.05f * (float)frame;
        v[2 * i] = 0.8f * cosf(a) * (i & 1 ? 1.0f : 0.5f);
        v[2 * i + 1] = 0.8f * sinf(a) * (i & 1 ? 1.0f : 0.5f);
        c[3 * i] = (float)i / N;
        c[3 * i + 1] = 1.0f - (float)i / N;
        c[3 * i + 2] = 0.5f;
        idx[i] = (GLushort)((i * 7) % N);
    }
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    glVertexPointer(2, GL_FLOAT, 0, v);
    glColorPointer(3, GL_FLOAT, 0, c);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, N);
    glTranslatef(0.1f, 0, 0);
    glDrawElements(GL_LINE_LOOP, N, GL_UNSIGNED_SHORT, idx);

    /* Independent primitives from arrays (tilesort sorts them one by one):
     * a grid of quads behind, wide points and lines centred just outside
     * the twelfths (tile edges), indexed triangles with homogeneous
     * positions, one crossing w = 0 and one with a NaN vertex. */
    glLoadIdentity();
    enum { QX = 12, QY = 9, PTS = 11 * 5 * 2, LNS = 11 * 2 * 4, TRI = 24 };
    static GLfloat qv[QX * QY * 4 * 3], qc[QX * QY * 4 * 3], pv[PTS * 2], pc[PTS * 3], lv[LNS * 2], lc[LNS * 3];
    static GLfloat tv[(TRI + 2) * 4], tc[(TRI + 2) * 3];
    static GLubyte ti[TRI * 3];
    float px = 2.0f / (float)app->width, py = 2.0f / (float)app->height;
    int n = 0;
    for (int y = 0; y < QY; y++)
        for (int x = 0; x < QX; x++)
            for (int c = 0; c < 4; c++, n++) {
                int cx = x + (c == 1 || c == 2), cy = y + (c >= 2);
                qv[3 * n] = -0.98f + 1.96f * (float)cx / QX;
                qv[3 * n + 1] = -0.98f + 1.96f * (float)cy / QY;
                qv[3 * n + 2] = -0.5f;
                qc[3 * n] = 0.2f + 0.05f * (float)((x + frame) % 12);
                qc[3 * n + 1] = 0.15f + 0.08f * (float)y;
                qc[3 * n + 2] = 0.3f + 0.1f * (float)c;
            }
    glVertexPointer(3, GL_FLOAT, 0, qv);
    glColorPointer(3, GL_FLOAT, 0, qc);
    glDrawArrays(GL_QUADS, 0, n);
    n = 0;
    for (int k = 1; k < 12; k++)
        for (int d = -4; d <= 4; d += 2, n += 2) {
            pv[2 * n] = ndc(k, 12) + (float)d * px;
            pv[2 * n + 1] = ndc((k * 5) % 11 + 1, 12);
            pv[2 * n + 2] = ndc((k * 7) % 11 + 1, 12);
            pv[2 * n + 3] = ndc(k, 12) + (float)d * py;
            for (int j = 0; j < 6; j++)
                pc[3 * n + j] = j % 3 == 0 ? (float)k / 12.0f : j % 3 == 1 ? 0.9f : 0.2f + 0.1f * (float)(frame % 5);
        }
    glPointSize(9 + (float)(frame % 3));
    glVertexPointer(2, GL_FLOAT, 0, pv);
    glColorPointer(3, GL_FLOAT, 0, pc);
    glDrawArrays(GL_POINTS, 0, n);
    n = 0;
    for (int k = 1; k < 12; k++)
        for (int d = -3; d <= 3; d += 6, n += 4) {
            float x = ndc(k, 12) + (float)d * px, y = ndc(k, 12) + (float)d * py;
            GLfloat seg[8] = {x, -0.9f, x, 0.9f, -0.9f, y, 0.9f, y};
            for (int j = 0; j < 8; j++)
                lv[2 * n + j] = seg[j];
            for (int j = 0; j < 12; j++)
                lc[3 * n + j] = j % 3 == 0 ? 0.9f : j % 3 == 1 ? (float)k / 12.0f : 0.1f * (float)(d + 4);
        }
    glLineWidth(5);
    glVertexPointer(2, GL_FLOAT, 0, lv);
    glColorPointer(3, GL_FLOAT, 0, lc);
    glDrawArrays(GL_LINES, 0, n);
    for (int i = 0; i < TRI + 2; i++) {
        float a = 2 * PI_F * (float)i / TRI + 0.03f * (float)frame, r = i % 2 ? 0.9f : 0.35f,
              w = 1.0f + 0.5f * (float)(i % 3);
        tv[4 * i] = r * cosf(a) * w;
        tv[4 * i + 1] = r * sinf(a) * w;
        tv[4 * i + 2] = 0.2f * w;
        tv[4 * i + 3] = w;
        tc[3 * i] = 0.5f + 0.5f * cosf(a);
        tc[3 * i + 1] = 0.5f + 0.5f * sinf(a);
        tc[3 * i + 2] = 0.8f;
    }
    tv[4 * 5 + 3] = -0.7f; /* crosses w = 0: its triangles go to every server */
    tv[4 * 11 + 1] = NAN;  /* a NaN vertex, likewise */
    for (int i = 0; i < TRI; i++) {
        ti[3 * i] = (GLubyte)i;
        ti[3 * i + 1] = (GLubyte)(i + 1);
        ti[3 * i + 2] = (GLubyte)((i * 5) % (TRI + 2));
    }
    glVertexPointer(4, GL_FLOAT, 0, tv);
    glColorPointer(3, GL_FLOAT, 0, tc);
    glDrawElements(GL_TRIANGLES, TRI * 3, GL_UNSIGNED_BYTE, ti);
    glPointSize(1);
    glLineWidth(1);
    glDisableClientState(GL_COLOR_ARRAY);
    glDisableClientState(GL_VERTEX_ARRAY);
}

static void scene_edges(const exapp *app, int frame)
{
    ortho();
    float px = 2.0f / (float)app->width, py = 2.0f / (float)app->height;
    glPointSize(9 + (float)(frame % 3));
    glLineWidth(7);
    glBegin(GL_POINTS);
    for (int k = 1; k < 12; k++)
        for (int s = -4; s <= 4; s += 2) {
            glColor3f((float)k / 12.0f, 0.8f, 0.3f);
            glVertex2f(ndc(k, 12) + (float)s * px, ndc((k * 5) % 11 + 1, 12));
            glVertex2f(ndc((k * 7) % 11 + 1, 12), ndc(k, 12) + (float)s * py);
        }
    glEnd();
    glBegin(GL_LINES);
    for (int k = 1; k < 12; k++) {
        glColor3f(0.9f, (float)k / 12.0f, 0.2f);
        glVertex2f(ndc(k, 12) + 3 * px, -0.95f);
        glVertex2f(ndc(k, 12) + 3 * px, 0.95f);
        glVertex2f(-0.95f, ndc(k, 12) - 3 * py);
        glVertex2f(0.95f, ndc(k, 12) - 3 * py);
    }
    glEnd();
    glPointSize(1);
    glLineWidth(1);
}

static void scene_eye_plane(int frame)
{
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glFrustum(-0.5, 0.5, -0.4, 0.4, 0.5, 20);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glRotatef(3.0f * (float)frame, 0, 1, 0);
    /* from in front of the eye to behind it: w <= 0 at some corners */
    glBegin(GL_TRIANGLES);
    glColor3f(1, 0.3f, 0.3f);
    glVertex3f(-0.3f, -0.2f, -2);
    glVertex3f(0.5f, -0.2f, -2);
    glVertex3f(0.1f, 0.3f, 3);
    glColor3f(0.3f, 1, 0.3f);
    glVertex3f(-1, 0.5f, -5);
    glVertex3f(2, -1, 1);
    glVertex3f(-2, -1, 1);
    glEnd();
}

static void scene_nan(void)
{
    ortho();
    float nan = nanf(""), inf = INFINITY;
    glBegin(GL_TRIANGLES);
    glColor3f(0.2f, 0.6f, 1);
    glVertex2f(-0.5f, -0.5f);
    glVertex2f(0.5f, -0.5f);
    glVertex2f(0, 0.5f);
    glColor3f(1, 0, 0);
    glVertex2f(nan, 0.1f);
    glVertex2f(0.6f, 0.6f);
    glVertex2f(0.9f, 0.2f);
    glVertex2f(-0.6f, 0.6f);
    glVertex2f(-0.9f, inf);
    glVertex2f(-0.9f, 0.2f);
    glEnd();
}

static void scene_big(int frame)
{
    ortho();
    glBegin(GL_QUADS); /* the whole window, and beyond */
    glColor3f(0.2f, 0.2f, 0.3f);
    glVertex2f(-3, -3);
    glColor3f(0.4f, 0.2f, 0.3f);
    glVertex2f(3, -3);
    glColor3f(0.2f, 0.5f, 0.3f);
    glVertex2f(3, 3);
    glVertex2f(-3, 3);
    glEnd();
    glDisable(GL_DEPTH_TEST);
    /* long primitives: they do not fit one small buffer */
    const GLenum modes[4] = {GL_TRIANGLE_STRIP, GL_TRIANGLE_FAN, GL_LINE_LOOP, GL_POLYGON};
    for (int m = 0; m < 4; m++) {
        glBegin(modes[m]);
        int n = 3000;
        for (int i = 0; i < n; i++) {
            float a = 2 * PI_F * (float)i / (float)n + 0.01f * (float)frame;
            float r = modes[m] == GL_TRIANGLE_STRIP ? (i & 1 ? 0.35f : 0.3f) : 0.2f + 0.02f * (float)m;
            glColor3f((float)m / 4.0f, (float)i / (float)n, 0.5f);
            float cx = m & 1 ? 0.45f : -0.45f, cy = m & 2 ? 0.45f : -0.45f;
            glVertex2f(cx + r * cosf(a), cy + r * sinf(a));
        }
        glEnd();
    }
    glEnable(GL_DEPTH_TEST);
}

static void scene_pixels(const exapp *app, int frame)
{
    ortho();
    glDisable(GL_DEPTH_TEST);
    enum { W = 37, H = 29 };
    unsigned char img[W * H * 4];
    for (int i = 0; i < W * H; i++) {
        img[4 * i] = (unsigned char)(i * 7);
        img[4 * i + 1] = (unsigned char)(i * 3 + frame);
        img[4 * i + 2] = (unsigned char)(255 - i);
        img[4 * i + 3] = 255;
    }
    GLubyte bits[16 * 16 / 8];
    for (int i = 0; i < (int)sizeof bits; i++)
        bits[i] = (GLubyte)(0xA5 ^ i);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (int k = 1; k < 12; k++) {
        /* centred on edges at halves, thirds, quarters */
        glRasterPos2f(ndc(k, 12) - (float)(W / 2) * 2.0f / (float)app->width,
                      ndc(12 - k, 12) - (float)(H / 2) * 2.0f / (float)app->height);
        glDrawPixels(W, H, GL_RGBA, GL_UNSIGNED_BYTE, img);
        glColor3f(1, 1, (float)k / 12.0f);
        glRasterPos2f(ndc(k, 12), ndc(k, 12));
        glBitmap(16, 16, 8, 8, 0, 0, bits);
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glColor3f(0.3f, 0.9f, 0.9f);
    glRectf(-0.05f, -0.9f, 0.05f, 0.9f);
    glEnable(GL_DEPTH_TEST);
}

static void scene_all_tiles(int frame)
{
    ortho();
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    for (int i = 0; i < 120; i++) {
        float a = 0.05f + 0.002f * (float)i, s = 1.1f + 0.01f * (float)((i + frame) % 7);
        glColor4f((float)(i % 5) / 5.0f, (float)(i % 3) / 3.0f, 0.5f, a);
        glBegin(GL_TRIANGLES); /* one triangle covering the window */
        glVertex2f(-s, -s);
        glVertex2f(3 * s, -s);
        glVertex2f(-s, 3 * s);
        glEnd();
    }
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
}

static void scene_tiny_batches(int frame)
{
    ortho();
    for (int i = 0; i < 1500; i++) {
        float x = -0.95f + 1.9f * (float)((i * 37) % 100) / 100.0f, y = -0.95f + 1.9f * (float)((i * 53) % 97) / 97.0f;
        glShadeModel(i & 1 ? GL_FLAT : GL_SMOOTH); /* a state change per primitive */
        glPushMatrix();
        glTranslatef(x, y, 0);
        glRotatef((float)(i * 7 + frame), 0, 0, 1);
        glBegin(GL_TRIANGLES);
        glColor3f(1, (float)(i % 10) / 10.0f, 0.2f);
        glVertex2f(0, 0);
        glColor3f(0.2f, 0.4f, 1);
        glVertex2f(0.04f, 0);
        glVertex2f(0, 0.04f);
        glEnd();
        glPopMatrix();
    }
    glShadeModel(GL_SMOOTH);
}

/* --- one long primitive of each mode, crossing many tiles (frames 10-14):
 * with small batches (batch_bytes=256) tilesort cuts each one many times
 * and reopens it (spus/tilesort/split.c); the tiles must stay exact. The
 * number of attribute calls per vertex varies, so cuts fall after odd and
 * even vertex counts. */

/* Point i of n on a spiral over most of the window. */
static void spiral(int i, int n, float turns, float wobble, float *x, float *y)
{
    float t = (float)i / (float)n, a = 2 * PI_F * turns * t;
    float r = 0.08f + 0.85f * t + ((i & 1) ? wobble : 0.0f);
    *x = r * cosf(a);
    *y = 0.95f * r * sinf(a);
}

static void scene_split_strips(int frame)
{
    ortho();
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE); /* a triangle whose parity flipped would be culled */
    glCullFace(GL_BACK);
    for (int s = 0; s < 2; s++) {
        glShadeModel(s ? GL_FLAT : GL_SMOOTH);
        glBegin(GL_TRIANGLE_STRIP);
        int n = 601 + s + frame % 2;
        for (int i = 0; i < n; i++) {
            float x, y;
            spiral(i, n, 3.0f, 0.07f, &x, &y);
            if (i % 5 == 2)
                glNormal3f(0, 0, 1); /* one more command: the cut's parity moves */
            glColor3f((float)(i % 7) / 7.0f, s ? 0.3f : (float)i / (float)n, (float)(i % 3) / 3.0f);
            glVertex2f(s ? -x * 0.9f : x, s ? -y * 0.9f : y);
        }
        glEnd();
    }
    glDisable(GL_CULL_FACE);
    /* two-sided lighting: the strip folds over itself, front faces red,
     * back faces blue; a flipped triangle would change colour */
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
    GLfloat front[4] = {0.9f, 0.3f, 0.2f, 1}, back[4] = {0.2f, 0.4f, 0.9f, 1};
    glMaterialfv(GL_FRONT, GL_AMBIENT_AND_DIFFUSE, front);
    glMaterialfv(GL_BACK, GL_AMBIENT_AND_DIFFUSE, back);
    glBegin(GL_TRIANGLE_STRIP);
    for (int i = 0; i < 403; i++) {
        float x = -0.95f + 1.9f * (float)(i / 2) / 201.0f;
        float fold = (i / 2) % 9 < 4 ? 1.0f : -1.0f; /* the band turns over every few quads */
        float y = 0.25f * sinf(6 * x + 0.1f * (float)frame) + ((i & 1) ? 0.12f * fold : -0.12f * fold);
        glNormal3f(0.3f * sinf(x * 5), 0.2f, 1);
        glVertex3f(x, y, 0);
    }
    glEnd();
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_FALSE);
    glDisable(GL_LIGHTING);
    glShadeModel(GL_SMOOTH);
    glEnable(GL_DEPTH_TEST);
}

static void scene_split_fans(int frame)
{
    ortho();
    glDisable(GL_DEPTH_TEST);
    /* a fan (flat: each triangle takes its last vertex's colour), in doubles */
    glShadeModel(GL_FLAT);
    glBegin(GL_TRIANGLE_FAN);
    glColor3f(1, 1, 1);
    glVertex3d(-0.45, 0.35, 0);
    for (int i = 0; i <= 500; i++) {
        float a = 2 * PI_F * (float)i / 500.0f + 0.02f * (float)frame, r = 0.5f + 0.08f * sinf(13 * a);
        glColor3f(0.5f + 0.5f * cosf(3 * a), (float)(i % 11) / 11.0f, 0.4f);
        glVertex3d(-0.45 + r * cosf(a), 0.35 + r * sinf(a), 0);
    }
    glEnd();
    /* polygons: flat takes the first vertex's colour, smooth blends */
    for (int s = 0; s < 2; s++) {
        glShadeModel(s ? GL_SMOOTH : GL_FLAT);
        glBegin(GL_POLYGON);
        for (int i = 0; i < 700; i++) {
            float a = 2 * PI_F * (float)i / 700.0f;
            if (i % 4 == 1)
                glTexCoord2f(a, 0); /* one more command now and then */
            glColor3f((float)(i % 5) / 5.0f, 0.3f + 0.6f * (float)i / 700.0f, s ? 0.9f : 0.1f);
            glVertex2f((s ? 0.5f : 0.45f) + 0.45f * cosf(a), (s ? -0.5f : 0.35f) + 0.42f * sinf(a));
        }
        glEnd();
    }
    /* a quad strip along the bottom (flat: each quad's last vertex), with
     * unsigned byte colours and homogeneous positions */
    glBegin(GL_QUAD_STRIP);
    for (int i = 0; i < 402; i++) {
        float x = -0.95f + 1.3f * (float)(i / 2) / 200.0f, y = -0.55f - 0.35f * (float)(i & 1);
        y += 0.08f * sinf(9 * x);
        glColor3ub((GLubyte)(i * 7), (GLubyte)(255 - i / 2), (GLubyte)(i % 3 * 100));
        glVertex4f(2 * x, 2 * y, 0, 2);
    }
    glEnd();
    glShadeModel(GL_SMOOTH);
    glEnable(GL_DEPTH_TEST);
}

static void scene_split_polygon_lines(int frame)
{
    ortho();
    glDisable(GL_DEPTH_TEST);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glLineWidth(3);
    /* a polygon drawn as lines: no internal edge may show where it is cut;
     * some of its own edges are hidden by edge flags */
    glBegin(GL_POLYGON);
    for (int i = 0; i < 500; i++) {
        float a = 2 * PI_F * (float)i / 500.0f + 0.01f * (float)frame;
        glEdgeFlag(i % 9 == 4 ? GL_FALSE : GL_TRUE);
        glColor3f(1, (float)(i % 6) / 6.0f, 0.3f);
        glVertex2f(-0.4f + 0.55f * cosf(a), 0.3f + 0.6f * sinf(a));
    }
    glEnd();
    glEdgeFlag(GL_TRUE);
    glLineWidth(1);
    /* triangles and quads as lines, edge flags varying per vertex */
    glBegin(GL_TRIANGLES);
    for (int i = 0; i < 360; i++) {
        int t = i / 3, c = i % 3;
        float x = -0.95f + 1.9f * (float)(t % 20) / 20.0f, y = -0.95f + 0.9f * (float)(t / 20) / 6.0f;
        glEdgeFlag((i % 4) != 1);
        glColor3f(0.2f + 0.04f * (float)(t % 20), 0.9f, (float)c / 3.0f);
        glVertex2f(x + (c == 1 ? 0.08f : 0.0f), y + (c == 2 ? 0.12f : 0.0f));
    }
    glEnd();
    glPolygonMode(GL_FRONT, GL_LINE);
    glPolygonMode(GL_BACK, GL_POINT);
    glPointSize(3);
    glBegin(GL_QUADS);
    for (int i = 0; i < 320; i++) {
        int q = i / 4, c = i % 4;
        float x = 0.15f + 0.8f * (float)(q % 8) / 8.0f, y = -0.1f + 0.9f * (float)(q / 8) / 10.0f;
        glEdgeFlag((i % 3) != 0);
        glColor3f(0.3f, (float)c / 4.0f, 1);
        float cx = (c == 1 || c == 2) ? 0.07f : 0.0f, cy = c >= 2 ? 0.06f : 0.0f;
        glVertex2f(x + ((q & 1) ? 0.07f - cx : cx), y + cy); /* odd quads wound backwards: points */
    }
    glEnd();
    glPointSize(1);
    /* a strip and a fan as lines (edge flags do not apply to them) */
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glBegin(GL_TRIANGLE_STRIP);
    for (int i = 0; i < 301; i++) {
        glColor3f(0.6f, 0.2f + 0.6f * (float)(i % 2), 0.9f);
        glVertex2f(-0.95f + 1.9f * (float)(i / 2) / 150.0f, 0.85f + ((i & 1) ? 0.08f : 0.0f));
    }
    glEnd();
    glBegin(GL_TRIANGLE_FAN);
    glVertex2f(0.55f, 0.55f);
    for (int i = 0; i <= 200; i++) {
        float a = PI_F * (float)i / 200.0f;
        glColor3f(0.9f, 0.9f, (float)(i % 4) / 4.0f);
        glVertex2f(0.55f + 0.4f * cosf(a), 0.55f + 0.3f * sinf(a));
    }
    glEnd();
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glEnable(GL_DEPTH_TEST);
}

static void scene_split_lines(const exapp *app, int frame)
{
    ortho();
    glDisable(GL_DEPTH_TEST);
    /* a wide, flat-shaded line strip in window coordinates (integers) */
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0, app->width, 0, app->height, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glShadeModel(GL_FLAT);
    glLineWidth(5);
    glBegin(GL_LINE_STRIP);
    for (int i = 0; i < 400; i++) {
        glColor3f((float)(i % 3) / 3.0f, 1, (float)(i % 8) / 8.0f);
        glVertex2i(20 + i * (app->width - 40) / 400, app->height / 2 + (i % 2 ? 1 : -1) * (60 + (i * 37 + frame) % 90));
    }
    glEnd();
    ortho();
    /* line loops, smooth and flat: the last piece closes back to the first
     * vertex, in the first vertex's colour when flat */
    for (int s = 0; s < 2; s++) {
        glShadeModel(s ? GL_FLAT : GL_SMOOTH);
        glLineWidth(s ? 3.0f : 1.0f);
        glBegin(GL_LINE_LOOP);
        for (int i = 0; i < 333; i++) {
            float a = 2 * PI_F * (float)i / 333.0f, r = (i & 1 ? 0.85f : 0.6f) - 0.2f * (float)s;
            glColor3f(s ? 1.0f : 0.3f, (float)i / 333.0f, (float)(i % 4) / 4.0f);
            glVertex2f(r * cosf(a), r * sinf(a) * 0.9f);
        }
        glEnd();
    }
    /* independent wide lines and big points */
    glLineWidth(2);
    glBegin(GL_LINES);
    for (int i = 0; i < 301; i++) { /* odd: the last vertex is ignored */
        glColor3f(0.2f, (float)(i % 10) / 10.0f, 1);
        glVertex2f(-0.9f + 1.8f * (float)((i * 53) % 101) / 101.0f, -0.9f + 1.8f * (float)((i * 29) % 97) / 97.0f);
    }
    glEnd();
    glPointSize(8);
    glBegin(GL_POINTS);
    for (int i = 0; i < 700; i++) {
        glColor3f(1, 0.5f, (float)(i % 9) / 9.0f);
        glVertex2f(-0.97f + 1.94f * (float)((i * 71) % 211) / 211.0f,
                   -0.97f + 1.94f * (float)((i * 43) % 199) / 199.0f);
    }
    glEnd();
    glPointSize(1);
    glLineWidth(1);
    glShadeModel(GL_SMOOTH);
    glEnable(GL_DEPTH_TEST);
}

static void scene_split_lit(int frame)
{
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glFrustum(-0.6, 0.6, -0.45, 0.45, 1, 10);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glTranslatef(0, 0, -2.2f);
    glRotatef(7.0f * (float)frame, 0.2f, 1, 0);
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glEnable(GL_COLOR_MATERIAL);
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, texture);
    /* one long triangle list and one long quad list: normals, texture
     * coordinates and colours per vertex are carried with each vertex */
    glBegin(GL_TRIANGLES);
    for (int i = 0; i < 40 * 12; i++) {
        int t = i / 3, c = i % 3;
        float a = 2 * PI_F * (float)t / 160.0f + (c == 1 ? 0.06f : 0.0f), r = c == 2 ? 0.5f : 1.0f;
        glNormal3f(cosf(a), sinf(a), 0.4f + 0.2f * (float)c);
        glTexCoord2f((float)c * 0.5f, (float)(t % 4) * 0.25f);
        glColor3f(0.5f + 0.5f * cosf(a), 0.8f, (float)c / 2.0f);
        glVertex3f(r * cosf(a), r * sinf(a) * 0.8f, -0.2f + 0.1f * (float)c);
    }
    glEnd();
    glBegin(GL_QUADS); /* lit quads are not cut (spus/tilesort/split.c): exact whole */
    for (int i = 0; i < 4 * 90; i++) {
        int q = i / 4, c = i % 4;
        float x = -1.2f + 2.4f * (float)(q % 15) / 15.0f + ((c == 1 || c == 2) ? 0.14f : 0.0f);
        float y = -0.9f + 0.3f * (float)(q / 15) + (c >= 2 ? 0.2f : 0.0f);
        glNormal3f(0.1f * (float)c, 0.3f, 1);
        glMultiTexCoord2f(GL_TEXTURE0, (c == 1 || c == 2) ? 1.0f : 0.0f, c >= 2 ? 1.0f : 0.0f);
        if (c == 0)
            glColor4f(0.9f, (float)(q % 6) / 6.0f, 0.5f, 1);
        glVertex3f(x, y, -0.6f);
    }
    glEnd();
    glDisable(GL_TEXTURE_2D);
    glDisable(GL_COLOR_MATERIAL);
    glDisable(GL_LIGHTING);
}

int main(int argc, char **argv)
{
    exapp app;
    if (!exapp_init(&app, "tilescenes", argc, argv, 640, 480))
        return app.exit_code;
    setup();
    glViewport(0, 0, app.width, app.height);
    for (int f = 0; f < app.frames; f++) {
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        switch (f % 15) {
        case 0: scene_lit(f); break;
        case 1: scene_lists(f); break;
        case 2: scene_arrays(&app, f); break;
        case 3: scene_edges(&app, f); break;
        case 4: scene_eye_plane(f); break;
        case 5: scene_nan(); break;
        case 6: scene_big(f); break;
        case 7: scene_pixels(&app, f); break;
        case 8: scene_all_tiles(f); break;
        case 9: scene_tiny_batches(f); break;
        case 10: scene_split_strips(f); break;
        case 11: scene_split_fans(f); break;
        case 12: scene_split_polygon_lines(f); break;
        case 13: scene_split_lines(&app, f); break;
        default: scene_split_lit(f); break;
        }
        if (!exapp_swap(&app))
            break;
    }
    return exapp_finish(&app);
}
