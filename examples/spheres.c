/* examples/spheres.c — lit spheres from display lists: a ring of spheres
 * with different materials under three coloured lights, rotating a little
 * every frame. Ordinary GL 1.x code; owns only its drawing (the harness in
 * common/exapp.c owns the context and output). Deterministic per frame.
 *
 * --part K/N (sort-last): the primitives are the quad strips (one latitude
 * band of one sphere), numbered in draw order: the ring's spheres, then the
 * centre sphere, SPHERE_STACKS bands each; share K draws the run
 * exapp_part_range gives it, so shares end in the middle of spheres.
 * --overlap pulls the ring in until its spheres cut into each other and
 * into the centre sphere: interpenetrating objects across share borders.
 *
 * --alpha A (sort-last alpha mode): another scene, ALPHA_SPHERES
 * translucent spheres of opacity A in a diagonal row receding from the
 * viewer, sphere 0 nearest, each in its own depth slab, turning about the
 * view axis (so the view order never changes). The primitives are whole
 * spheres (convex: with back faces culled each pixel gets at most one
 * fragment of each), share K takes a contiguous run, so rank order is
 * front-to-back order, and each share draws its spheres back to front,
 * premultiplied (colour times A, BlendFunc(ONE, ONE_MINUS_SRC_ALPHA)),
 * shaded per vertex by the program (no GL lighting: its colour could not
 * be premultiplied). Cleared to transparent black, or to --background
 * R,G,B (opaque) when given. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>

#include "common/exapp.h"

#define SPHERE_COUNT 7
#define PI_F 3.14159265358979f
#define SPHERE_SLICES 32
#define SPHERE_STACKS 20
#define STRIP_COUNT ((SPHERE_COUNT + 1) * SPHERE_STACKS)
#define ALPHA_SPHERES 8

/* Band i of a unit sphere: one latitude quad strip with per-vertex normals. */
static void emit_band(int i, int slices, int stacks)
{
    float lat0 = PI_F * (-0.5f + (float)i / (float)stacks);
    float lat1 = PI_F * (-0.5f + (float)(i + 1) / (float)stacks);
    glBegin(GL_QUAD_STRIP);
    for (int j = 0; j <= slices; j++) {
        float lon = 2.0f * PI_F * (float)j / (float)slices;
        float cx = cosf(lon), sy = sinf(lon);
        float x0 = cosf(lat0) * cx, y0 = cosf(lat0) * sy, z0 = sinf(lat0);
        float x1 = cosf(lat1) * cx, y1 = cosf(lat1) * sy, z1 = sinf(lat1);
        glNormal3f(x1, y1, z1);
        glVertex3f(x1, y1, z1);
        glNormal3f(x0, y0, z0);
        glVertex3f(x0, y0, z0);
    }
    glEnd();
}

static void set_material(int i)
{
    static const GLfloat diffuse[SPHERE_COUNT][4] = {
        {0.9f, 0.2f, 0.2f, 1}, {0.2f, 0.8f, 0.3f, 1}, {0.2f, 0.3f, 0.9f, 1},   {0.9f, 0.8f, 0.2f, 1},
        {0.8f, 0.3f, 0.8f, 1}, {0.2f, 0.8f, 0.8f, 1}, {0.85f, 0.85f, 0.85f, 1}};
    GLfloat ambient[4] = {diffuse[i][0] * 0.2f, diffuse[i][1] * 0.2f, diffuse[i][2] * 0.2f, 1};
    GLfloat specular[4] = {0.9f, 0.9f, 0.9f, 1};
    glMaterialfv(GL_FRONT, GL_AMBIENT, ambient);
    glMaterialfv(GL_FRONT, GL_DIFFUSE, diffuse[i]);
    glMaterialfv(GL_FRONT, GL_SPECULAR, specular);
    glMaterialf(GL_FRONT, GL_SHININESS, 8.0f + 16.0f * (float)i);
}

/* Sphere number `sphere` (in draw order) from its band lists, only the
 * bands of this process's share (header comment). */
static void call_sphere(const exapp *app, GLuint band_lists, int sphere)
{
    long first = 0, count = exapp_part_range(app, STRIP_COUNT, &first);
    for (int i = 0; i < SPHERE_STACKS; i++) {
        long strip = (long)sphere * SPHERE_STACKS + i;
        if (strip >= first && strip < first + count)
            glCallList(band_lists + (GLuint)i);
    }
}

static void setup(const exapp *app, bool overlap, GLuint *sphere_list, GLuint *ring_list)
{
    glViewport(0, 0, app->width, app->height);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    double aspect = (double)app->width / (double)app->height;
    glFrustum(-0.5 * aspect, 0.5 * aspect, -0.5, 0.5, 1.0, 30.0);
    glMatrixMode(GL_MODELVIEW);

    glClearColor(0.05f, 0.05f, 0.12f, 1.0f);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glShadeModel(GL_SMOOTH);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glEnable(GL_NORMALIZE);
    glEnable(GL_LIGHTING);
    GLfloat global_ambient[4] = {0.15f, 0.15f, 0.15f, 1};
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, global_ambient);

    static const GLfloat light_color[3][4] = {{1.0f, 0.95f, 0.9f, 1}, {0.4f, 0.5f, 1.0f, 1}, {1.0f, 0.5f, 0.3f, 1}};
    for (int i = 0; i < 3; i++) {
        glLightfv(GL_LIGHT0 + i, GL_DIFFUSE, light_color[i]);
        glLightfv(GL_LIGHT0 + i, GL_SPECULAR, light_color[i]);
        glEnable(GL_LIGHT0 + i);
    }
    glLightf(GL_LIGHT2, GL_CONSTANT_ATTENUATION, 0.5f);
    glLightf(GL_LIGHT2, GL_LINEAR_ATTENUATION, 0.1f);

    *sphere_list = glGenLists(SPHERE_STACKS + 1);
    *ring_list = *sphere_list + SPHERE_STACKS;
    for (int i = 0; i < SPHERE_STACKS; i++) {
        glNewList(*sphere_list + (GLuint)i, GL_COMPILE);
        emit_band(i, SPHERE_SLICES, SPHERE_STACKS);
        glEndList();
    }

    /* The ring nests the sphere list: display lists calling lists. */
    glNewList(*ring_list, GL_COMPILE);
    for (int i = 0; i < SPHERE_COUNT; i++) {
        float angle = 360.0f * (float)i / (float)SPHERE_COUNT;
        glPushMatrix();
        glRotatef(angle, 0, 1, 0);
        glTranslatef(overlap ? 1.2f : 2.2f, 0.35f * (float)(i % 3) - 0.35f, 0);
        glScalef(0.55f, 0.55f, 0.55f);
        set_material(i);
        call_sphere(app, *sphere_list, i);
        glPopMatrix();
    }
    glEndList();
}

static void draw(const exapp *app, GLuint sphere_list, GLuint ring_list, int frame)
{
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glLoadIdentity();

    /* Lights in eye space, one of them orbiting with the frame number. */
    GLfloat key[4] = {-4, 5, 3, 0};
    GLfloat fill[4] = {5, -2, 2, 0};
    float t = 0.4f * (float)frame;
    GLfloat orbit[4] = {3.0f * cosf(t), 1.0f, -6.0f + 3.0f * sinf(t), 1};
    glLightfv(GL_LIGHT0, GL_POSITION, key);
    glLightfv(GL_LIGHT1, GL_POSITION, fill);
    glLightfv(GL_LIGHT2, GL_POSITION, orbit);

    glTranslatef(0, 0, -7.5f);
    glRotatef(20.0f, 1, 0, 0);
    glRotatef(12.0f * (float)frame, 0, 1, 0);
    glCallList(ring_list);

    /* A big centre sphere, drawn straight from the list with its own material. */
    glPushMatrix();
    glRotatef(-30.0f * (float)frame, 0, 0, 1);
    glScalef(1.1f, 1.1f, 1.1f);
    set_material(SPHERE_COUNT - 1);
    call_sphere(app, sphere_list, SPHERE_COUNT);
    glPopMatrix();
}

/* The alpha scene's band i of sphere s: colour per vertex, lit by one
 * eye-space direction, premultiplied by the opacity. */
static void emit_alpha_band(int s, int i, float alpha)
{
    static const float colour[ALPHA_SPHERES][3] = {{0.9f, 0.2f, 0.2f},    {0.2f, 0.8f, 0.3f}, {0.2f, 0.3f, 0.9f},
                                                   {0.9f, 0.8f, 0.2f},    {0.8f, 0.3f, 0.8f}, {0.2f, 0.8f, 0.8f},
                                                   {0.85f, 0.85f, 0.85f}, {0.9f, 0.5f, 0.1f}};
    float lat0 = PI_F * (-0.5f + (float)i / (float)SPHERE_STACKS);
    float lat1 = PI_F * (-0.5f + (float)(i + 1) / (float)SPHERE_STACKS);
    glBegin(GL_QUAD_STRIP);
    for (int j = 0; j <= SPHERE_SLICES; j++) {
        float lon = 2.0f * PI_F * (float)j / (float)SPHERE_SLICES;
        for (int e = 0; e < 2; e++) {
            float lat = e ? lat0 : lat1;
            float x = cosf(lat) * cosf(lon), y = cosf(lat) * sinf(lon), z = sinf(lat);
            float lit = 0.35f + 0.65f * fmaxf(0.0f, 0.4f * x + 0.5f * y + 0.77f * z);
            glColor4f(colour[s][0] * lit * alpha, colour[s][1] * lit * alpha, colour[s][2] * lit * alpha, alpha);
            glVertex3f(x, y, z);
        }
    }
    glEnd();
}

/* The alpha scene (header comment): this share's spheres, back to front. */
static void draw_alpha(const exapp *app, float alpha, int frame)
{
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glLoadIdentity();
    glTranslatef(0, 0, -6.0f);
    glRotatef(9.0f * (float)frame, 0, 0, 1);
    long first = 0, count = exapp_part_range(app, ALPHA_SPHERES, &first);
    for (long s = first + count - 1; s >= first; s--) {
        glPushMatrix();
        glTranslatef(-0.9f + 0.22f * (float)s, 0.5f - 0.12f * (float)s, 1.6f - 1.1f * (float)s);
        glScalef(0.55f, 0.55f, 0.55f);
        for (int i = 0; i < SPHERE_STACKS; i++)
            emit_alpha_band((int)s, i, alpha);
        glPopMatrix();
    }
}

static void setup_alpha(const exapp *app, const float *background)
{
    glViewport(0, 0, app->width, app->height);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    double aspect = (double)app->width / (double)app->height;
    glFrustum(-0.5 * aspect, 0.5 * aspect, -0.5, 0.5, 1.0, 30.0);
    glMatrixMode(GL_MODELVIEW);
    if (background)
        glClearColor(background[0], background[1], background[2], 1.0f);
    else
        glClearColor(0, 0, 0, 0);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glShadeModel(GL_SMOOTH);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
}

/* Takes --alpha A and --background R,G,B out of argv (the harness knows
 * one flag of its own); false with a message on a bad value. */
static bool take_alpha_options(int *argc, char **argv, float *alpha, float *background, bool *has_background)
{
    int out = 1;
    for (int i = 1; i < *argc; i++) {
        char *end = NULL;
        if (!strcmp(argv[i], "--alpha") && i + 1 < *argc) {
            *alpha = strtof(argv[++i], &end);
            if (*end || !(*alpha > 0.0f && *alpha <= 1.0f)) {
                fprintf(stderr, "spheres: bad --alpha (expected 0 < A <= 1): %s\n", argv[i]);
                return false;
            }
        } else if (!strcmp(argv[i], "--background") && i + 1 < *argc) {
            const char *text = argv[++i];
            int used = 0;
            if (sscanf(text, "%f,%f,%f%n", &background[0], &background[1], &background[2], &used) != 3 || text[used]) {
                fprintf(stderr, "spheres: bad --background (expected R,G,B in 0..1): %s\n", text);
                return false;
            }
            *has_background = true;
        } else {
            argv[out++] = argv[i];
        }
    }
    *argc = out;
    return true;
}

int main(int argc, char **argv)
{
    exapp app;
    bool overlap = false, has_background = false;
    float alpha = 0.0f, background[3] = {0, 0, 0};
    if (!take_alpha_options(&argc, argv, &alpha, background, &has_background))
        return 2;
    if (!exapp_init_flag(&app, "spheres", argc, argv, 640, 480, "--overlap",
                         "  --overlap       pull the ring in: spheres cut into each other and the centre\n"
                         "  --alpha A       translucent scene of opacity A, premultiplied, back to front per\n"
                         "                  share (sort-last alpha mode; cleared to transparent black)\n"
                         "  --background R,G,B  with --alpha: clear to this opaque colour instead",
                         &overlap))
        return exapp_finish(&app);
    if (alpha > 0.0f) {
        setup_alpha(&app, has_background ? background : NULL);
        for (int f = 0; f < app.frames; f++) {
            draw_alpha(&app, alpha, f);
            if (!exapp_swap(&app))
                break;
        }
        return exapp_finish(&app);
    }
    GLuint sphere_list, ring_list;
    setup(&app, overlap, &sphere_list, &ring_list);
    for (int f = 0; f < app.frames; f++) {
        draw(&app, sphere_list, ring_list, f);
        if (!exapp_swap(&app))
            break;
    }
    glDeleteLists(sphere_list, SPHERE_STACKS + 1);
    return exapp_finish(&app);
}
