/* examples/psubmit.c — parallel submission: N processes (ranks) draw one
 * picture together through one server node (`tessera node --clients N`),
 * in the style of Igehy, Stoll and Hanrahan's parallel graphics interface.
 * The scene is a grid of lit spheres and cubes, turning every frame; rank
 * r draws the objects i with i % N == r. Each frame:
 *     rank 0 clears; barrier 1; every rank draws its objects; barrier 2;
 *     rank 0 swaps
 * so the clear comes before anybody draws and the swap after everybody
 * drew; the depth test makes the picture independent of the order the
 * server interleaves the ranks' objects in. Every rank sets up the same
 * state in its own context. Only rank 0 swaps (the server ends frames with
 * the first client that swaps).
 *
 * The native build (psubmit-native) draws the whole scene in one process:
 * the reference. Options: --rank R --ranks N (tessera build; default 0 of
 * 1) plus the harness's (common/exapp.h). Owns only its drawing. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>

#include "common/exapp.h"
#ifndef EXAPP_NATIVE
#include "tessera/gltsr_gen.h" /* glBarrierCreateTSR, glBarrierExecTSR, ... */
#endif

#define GRID_X 6
#define GRID_Y 4
#define OBJECTS (GRID_X * GRID_Y)
#define MAX_RANKS 64
#define PI_F 3.14159265358979f
#define BARRIER_CLEARED 1
#define BARRIER_DRAWN 2

static void sphere(int slices, int stacks)
{
    for (int i = 0; i < stacks; i++) {
        float lat0 = PI_F * (-0.5f + (float)i / (float)stacks);
        float lat1 = PI_F * (-0.5f + (float)(i + 1) / (float)stacks);
        glBegin(GL_QUAD_STRIP);
        for (int j = 0; j <= slices; j++) {
            float lon = 2.0f * PI_F * (float)j / (float)slices;
            float c = cosf(lon), s = sinf(lon);
            glNormal3f(cosf(lat1) * c, cosf(lat1) * s, sinf(lat1));
            glVertex3f(cosf(lat1) * c, cosf(lat1) * s, sinf(lat1));
            glNormal3f(cosf(lat0) * c, cosf(lat0) * s, sinf(lat0));
            glVertex3f(cosf(lat0) * c, cosf(lat0) * s, sinf(lat0));
        }
        glEnd();
    }
}

static void cube(void)
{
    static const GLfloat n[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    glBegin(GL_QUADS);
    for (int f = 0; f < 6; f++) {
        /* Two axes spanning the face, perpendicular to its normal. */
        GLfloat u[3] = {n[f][1] != 0 || n[f][2] != 0 ? 1.0f : 0.0f, n[f][0] != 0 ? 1.0f : 0.0f, 0};
        GLfloat v[3] = {n[f][1] * u[2] - n[f][2] * u[1], n[f][2] * u[0] - n[f][0] * u[2],
                        n[f][0] * u[1] - n[f][1] * u[0]};
        static const float corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        glNormal3fv(n[f]);
        for (int k = 0; k < 4; k++)
            glVertex3f(n[f][0] + corner[k][0] * u[0] + corner[k][1] * v[0],
                       n[f][1] + corner[k][0] * u[1] + corner[k][1] * v[1],
                       n[f][2] + corner[k][0] * u[2] + corner[k][1] * v[2]);
    }
    glEnd();
}

static void setup(const exapp *app)
{
    glViewport(0, 0, app->width, app->height);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    double aspect = (double)app->width / (double)app->height;
    glFrustum(-0.6 * aspect, 0.6 * aspect, -0.6, 0.6, 1.5, 40.0);
    glMatrixMode(GL_MODELVIEW);
    glClearColor(0.08f, 0.08f, 0.1f, 1.0f);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_CULL_FACE);
    glEnable(GL_NORMALIZE);
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glEnable(GL_LIGHT1);
    GLfloat warm[4] = {1.0f, 0.9f, 0.8f, 1}, cool[4] = {0.3f, 0.4f, 0.9f, 1};
    glLightfv(GL_LIGHT0, GL_DIFFUSE, warm);
    glLightfv(GL_LIGHT0, GL_SPECULAR, warm);
    glLightfv(GL_LIGHT1, GL_DIFFUSE, cool);
}

/* Object i of frame `frame`, with its own material and spin. */
static void draw_object(int i, int frame)
{
    int gx = i % GRID_X, gy = i / GRID_X;
    GLfloat diffuse[4] = {0.3f + 0.7f * (float)gx / (GRID_X - 1), 0.3f + 0.6f * (float)gy / (GRID_Y - 1),
                          0.9f - 0.5f * (float)gx / (GRID_X - 1), 1};
    GLfloat specular[4] = {0.8f, 0.8f, 0.8f, 1};
    glMaterialfv(GL_FRONT, GL_AMBIENT_AND_DIFFUSE, diffuse);
    glMaterialfv(GL_FRONT, GL_SPECULAR, specular);
    glMaterialf(GL_FRONT, GL_SHININESS, 10.0f + 8.0f * (float)(i % 5));
    glPushMatrix();
    /* Alternate rows sit deeper, so objects overlap and depth matters. */
    glTranslatef(2.1f * ((float)gx - (GRID_X - 1) / 2.0f), 2.1f * ((float)gy - (GRID_Y - 1) / 2.0f),
                 (gy % 2) ? -1.5f : 0.0f);
    glRotatef(9.0f * (float)frame + 15.0f * (float)i, 0.3f, 1.0f, 0.2f);
    glScalef(1.25f, 1.25f, 1.25f);
    if (i % 3 == 0) {
        glScalef(0.7f, 0.7f, 0.7f);
        cube();
    } else {
        sphere(20, 14);
    }
    glPopMatrix();
}

static void draw_share(int rank, int ranks, int frame)
{
    glLoadIdentity();
    GLfloat key[4] = {-5, 6, 4, 0}, fill[4] = {6, -3, 2, 0};
    glLightfv(GL_LIGHT0, GL_POSITION, key);
    glLightfv(GL_LIGHT1, GL_POSITION, fill);
    glTranslatef(0, 0, -14.0f);
    glRotatef(-18.0f + 2.0f * (float)frame, 1, 0, 0);
    for (int i = 0; i < OBJECTS; i++)
        if (i % ranks == rank)
            draw_object(i, frame);
}

static int parse_rank_arg(const char *name, const char *value, int min, int max, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(value, &end, 10);
    if (errno || end == value || *end || v < min || v > max) {
        fprintf(stderr, "psubmit: bad %s '%s' (expected %d..%d)\n", name, value, min, max);
        return -1;
    }
    *out = (int)v;
    return 0;
}

int main(int argc, char **argv)
{
    /* --rank and --ranks are ours; the rest goes to the harness. */
    int rank = 0, ranks = 1;
    char **rest = calloc((size_t)argc + 1, sizeof *rest);
    if (!rest)
        return 1;
    int nrest = 0;
    rest[nrest++] = argv[0];
    for (int i = 1; i < argc; i++) {
        int is_rank = !strcmp(argv[i], "--rank"), is_ranks = !strcmp(argv[i], "--ranks");
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help"))
            printf("psubmit: --rank R --ranks N (default 0 of 1): this process draws objects i with\n"
                   "i %% N == R of a %d-object scene; rank 0 clears and swaps, barriers around both.\n"
                   "The native build draws the whole scene. Harness options:\n",
                   OBJECTS);
        if (is_rank || is_ranks) {
            if (i + 1 >= argc) {
                fprintf(stderr, "psubmit: option %s needs a value\n", argv[i]);
                free(rest);
                return 2;
            }
            if (parse_rank_arg(argv[i], argv[i + 1], is_rank ? 0 : 1, is_rank ? MAX_RANKS - 1 : MAX_RANKS,
                               is_rank ? &rank : &ranks) != 0) {
                free(rest);
                return 2;
            }
            i++;
            continue;
        }
        rest[nrest++] = argv[i];
    }
    if (rank >= ranks) {
        fprintf(stderr, "psubmit: --rank %d must be below --ranks %d\n", rank, ranks);
        free(rest);
        return 2;
    }
#ifdef EXAPP_NATIVE
    /* The reference draws everything itself. */
    rank = 0;
    ranks = 1;
#endif
    exapp app;
    if (!exapp_init(&app, "psubmit", nrest, rest, 640, 480)) {
        free(rest);
        return exapp_finish(&app);
    }
    setup(&app);
#ifndef EXAPP_NATIVE
    /* Every rank creates both barriers; the server keeps the first. */
    glBarrierCreateTSR(BARRIER_CLEARED, (GLuint)ranks);
    glBarrierCreateTSR(BARRIER_DRAWN, (GLuint)ranks);
#endif
    for (int f = 0; f < app.frames; f++) {
        if (rank == 0)
            glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
#ifndef EXAPP_NATIVE
        glBarrierExecTSR(BARRIER_CLEARED);
#endif
        draw_share(rank, ranks, f);
#ifndef EXAPP_NATIVE
        glBarrierExecTSR(BARRIER_DRAWN);
#endif
        if (rank == 0 && !exapp_swap(&app))
            break;
    }
#ifndef EXAPP_NATIVE
    glBarrierDestroyTSR(BARRIER_CLEARED);
    glBarrierDestroyTSR(BARRIER_DRAWN);
#endif
    free(rest);
    return exapp_finish(&app);
}
