/* examples/tilescenes.c — the scenes where sort-first goes wrong if it is
 * not done carefully, one per frame (frame % 8):
 *   0 lit, textured triangles          4 polygons crossing the eye plane
 *   1 display lists (nested, state)    5 a NaN and an Inf vertex
 *   2 vertex arrays (arrays, elements) 6 primitives covering the window; long
 *   3 wide lines, large points centred    strips, fans, loops and polygons
 *     just outside tile edges          7 glDrawPixels, glBitmap, glRect across
 *                                         tile borders
 * and two where sort-first degrades towards broadcast, which must stay
 * exact all the same (frame % 10):
 *   8 every primitive covers the whole window (each batch hits every tile)
 *   9 a state change between every primitive (batches of one triangle)
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

static void setup(void) {
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

static void ortho(void) {
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(-1, 1, -1, 1, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
}

/* Window x, y of the k-th twelfth in normalised device units. */
static float ndc(int k, int twelfths) { return -1.0f + 2.0f * (float)k / (float)twelfths; }

static void scene_lit(int frame) {
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

static void scene_lists(int frame) {
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

static void scene_arrays(int frame) {
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
    glDisableClientState(GL_COLOR_ARRAY);
    glDisableClientState(GL_VERTEX_ARRAY);
}

static void scene_edges(const exapp *app, int frame) {
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

static void scene_eye_plane(int frame) {
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

static void scene_nan(void) {
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

static void scene_big(int frame) {
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

static void scene_pixels(const exapp *app, int frame) {
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

static void scene_all_tiles(int frame) {
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

static void scene_tiny_batches(int frame) {
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

int main(int argc, char **argv) {
    exapp app;
    if (!exapp_init(&app, "tilescenes", argc, argv, 640, 480))
        return app.exit_code;
    setup();
    glViewport(0, 0, app.width, app.height);
    for (int f = 0; f < app.frames; f++) {
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        switch (f % 10) {
        case 0: scene_lit(f); break;
        case 1: scene_lists(f); break;
        case 2: scene_arrays(f); break;
        case 3: scene_edges(&app, f); break;
        case 4: scene_eye_plane(f); break;
        case 5: scene_nan(); break;
        case 6: scene_big(f); break;
        case 7: scene_pixels(&app, f); break;
        case 8: scene_all_tiles(f); break;
        default: scene_tiny_batches(f); break;
        }
        if (!exapp_swap(&app))
            break;
    }
    return exapp_finish(&app);
}
