/* tests/tilesort/texture_units_driver.c — texture image units past the 8
 * coordinate units (GL_MAX_TEXTURE_COORDS) up to
 * GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, as shader programs use them; every
 * answer printed on stdout: the test (tilesort.sh records) runs the
 * -native build (OSMesa itself, the reference) and this one through
 * render, pack -> node -> render and a tile wall, and wants the same lines
 * and the same frames.
 *
 * Each frame draws a row of quads, one per unit of `units` below, each
 * with a fragment shader sampling a 1x1 texture of its own colour bound on
 * that unit only (so a unit whose binding does not reach a server draws
 * black there); every frame binds unit 40 and 150 to other textures, so
 * the bindings change between frames (the wall's per-frame diff), and one
 * LOD bias is set past the coordinate units. Then the answers: every unit
 * selected in turn and GL_ACTIVE_TEXTURE asked back; the unit one past the
 * last (GL_INVALID_ENUM); what GL refuses past the coordinate units
 * (texgen enables and calls, coordinate replacement, the texture matrix
 * get: GL_INVALID_OPERATION) and what it takes there without an error
 * (a texture target's enable, the environment, the texture matrix); the
 * bindings and LOD bias a glPushAttrib(GL_TEXTURE_BIT) saves there and
 * glPopAttrib restores. Built twice like the examples
 * (examples/common/exapp.h). */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <stdio.h>

#include "common/exapp.h"

static const GLuint units[] = {0, 3, 7, 8, 9, 15, 16, 31, 32, 40, 63, 64, 100, 150, 191};
enum { NUNITS = sizeof units / sizeof units[0], NTEX = NUNITS + 2 };

static void errors(const char *what)
{
    GLenum first = glGetError();
    GLenum second = glGetError();
    printf("%s: error 0x%x then 0x%x\n", what, first, second);
}

static GLuint build_program(void)
{
    static const GLchar *const vs = "void main() { gl_Position = ftransform(); }";
    static const GLchar *const fs = "uniform sampler2D s; void main() { gl_FragColor = texture2D(s, vec2(0.5)); }";
    GLuint v = glCreateShader(GL_VERTEX_SHADER), f = glCreateShader(GL_FRAGMENT_SHADER), p = glCreateProgram();
    glShaderSource(v, 1, &vs, NULL);
    glShaderSource(f, 1, &fs, NULL);
    glCompileShader(v);
    glCompileShader(f);
    glAttachShader(p, v);
    glAttachShader(p, f);
    glLinkProgram(p);
    GLint linked = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &linked);
    printf("program linked: %d\n", linked);
    return p;
}

/* 1x1 textures, texture i of colour (i * 37 % 256, i * 91 % 256, 255 - i *
 * 13), bound on units[i]; the two spares (NUNITS and NUNITS + 1) take
 * turns on units 40 and 150 in the frames. */
static void make_textures(GLuint *tex, GLint max_units)
{
    glGenTextures(NTEX, tex);
    for (int i = 0; i < NTEX; i++) {
        GLubyte px[4] = {(GLubyte)(i * 37 % 256), (GLubyte)(i * 91 % 256), (GLubyte)(255 - i * 13), 255};
        GLuint u = i < NUNITS ? units[i] : (GLuint)(1 + i - NUNITS); /* the spares: units 1 and 2 */
        if ((GLint)u >= max_units)
            continue;
        glActiveTexture(GL_TEXTURE0 + u);
        glBindTexture(GL_TEXTURE_2D, tex[i]);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, px);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    glActiveTexture(GL_TEXTURE0);
    errors("textures made");
}

static void scene(int frame, GLuint program, const GLuint *tex, GLint max_units)
{
    glClearColor(0.1f, 0.1f, 0.2f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0, NUNITS, 0, 1, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    /* the per-frame changes: units 40 and 150 swap between two textures */
    glActiveTexture(GL_TEXTURE0 + 40);
    glBindTexture(GL_TEXTURE_2D, tex[frame % 2 ? NUNITS : 9]);
    if (max_units > 150) {
        glActiveTexture(GL_TEXTURE0 + 150);
        glBindTexture(GL_TEXTURE_2D, tex[frame % 2 ? 13 : NUNITS + 1]);
    }
    glActiveTexture(GL_TEXTURE0 + 5);
    glUseProgram(program);
    GLint loc = glGetUniformLocation(program, "s");
    for (int i = 0; i < NUNITS; i++) {
        if ((GLint)units[i] >= max_units)
            continue;
        glUniform1i(loc, (GLint)units[i]);
        /* the quads cross the tiles: rows at two heights */
        float y0 = i % 2 ? 0.1f : 0.45f;
        glBegin(GL_QUADS);
        glVertex2f((float)i + 0.1f, y0);
        glVertex2f((float)i + 0.9f, y0);
        glVertex2f((float)i + 0.9f, y0 + 0.45f);
        glVertex2f((float)i + 0.1f, y0 + 0.45f);
        glEnd();
    }
    glUseProgram(0);
    errors("scene");
}

static void answers(GLint max_units, GLint coord_units)
{
    int right = 0;
    for (GLint u = 0; u < max_units; u++) {
        GLint got = -1;
        glActiveTexture(GL_TEXTURE0 + (GLenum)u);
        glGetIntegerv(GL_ACTIVE_TEXTURE, &got);
        right += got == GL_TEXTURE0 + u;
    }
    printf("GL_ACTIVE_TEXTURE answered %d of %d units\n", right, max_units);
    errors("every unit selected");
    glActiveTexture(GL_TEXTURE0 + (GLenum)max_units);
    errors("glActiveTexture(one past the last unit)");
    GLint active = -1;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    printf("active unit after it: %d\n", active - GL_TEXTURE0);

    int refused = 0;
    for (GLint u = coord_units; u < max_units; u++) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)u);
        glEnable(GL_TEXTURE_GEN_S);
        refused += glGetError() == GL_INVALID_OPERATION;
    }
    printf("glEnable(GL_TEXTURE_GEN_S) refused on %d of %d units past the coordinate units\n", refused,
           max_units - coord_units);
    glActiveTexture(GL_TEXTURE0 + (GLenum)coord_units);
    glEnable(GL_TEXTURE_2D);
    errors("glEnable(GL_TEXTURE_2D) past the coordinate units");
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    errors("glTexEnvi(GL_TEXTURE_ENV_MODE) past the coordinate units");
    glTexEnvi(GL_POINT_SPRITE, GL_COORD_REPLACE, GL_TRUE);
    errors("glTexEnvi(GL_COORD_REPLACE) past the coordinate units");
    glTexGeni(GL_S, GL_TEXTURE_GEN_MODE, GL_OBJECT_LINEAR);
    errors("glTexGeni past the coordinate units");
    glMatrixMode(GL_TEXTURE);
    glLoadIdentity();
    glTranslatef(1, 2, 3);
    errors("texture matrix calls past the coordinate units");
    GLfloat m[16] = {0};
    glGetFloatv(GL_TEXTURE_MATRIX, m);
    errors("glGetFloatv(GL_TEXTURE_MATRIX) past the coordinate units");
    glMatrixMode(GL_MODELVIEW);

    GLfloat bias = -1;
    glActiveTexture(GL_TEXTURE0 + 40);
    glTexEnvf(GL_TEXTURE_FILTER_CONTROL, GL_TEXTURE_LOD_BIAS, 1.5f);
    glGetTexEnvfv(GL_TEXTURE_FILTER_CONTROL, GL_TEXTURE_LOD_BIAS, &bias);
    printf("LOD bias of unit 40: %g\n", bias);
    errors("LOD bias past the coordinate units");

    GLint before = -1, changed = -1, after = -1;
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &before);
    glPushAttrib(GL_TEXTURE_BIT);
    glBindTexture(GL_TEXTURE_2D, 0);
    glTexEnvf(GL_TEXTURE_FILTER_CONTROL, GL_TEXTURE_LOD_BIAS, 0.0f);
    glActiveTexture(GL_TEXTURE0 + 9);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &changed);
    glPopAttrib();
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &after);
    glGetTexEnvfv(GL_TEXTURE_FILTER_CONTROL, GL_TEXTURE_LOD_BIAS, &bias);
    printf("glPopAttrib(GL_TEXTURE_BIT): unit %d, binding %s (unit 9 had %d), LOD bias %g\n", active - GL_TEXTURE0,
           before == after ? "restored" : "lost", changed, bias);
    errors("push and pop past the coordinate units");
    glActiveTexture(GL_TEXTURE0);
}

int main(int argc, char **argv)
{
    exapp app;
    if (!exapp_init(&app, "texture_units", argc, argv, 320, 240))
        return app.exit_code;
    GLint max_units = 0, coord_units = 0;
    glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &max_units);
    glGetIntegerv(GL_MAX_TEXTURE_COORDS, &coord_units);
    printf("units: %d image, %d coordinate\n", max_units, coord_units);
    GLuint program = build_program();
    GLuint tex[NTEX];
    make_textures(tex, max_units);
    for (int f = 0; f < app.frames; f++) {
        printf("frame %d\n", f);
        scene(f, program, tex, max_units);
        answers(max_units, coord_units);
        if (!exapp_swap(&app))
            break;
    }
    glDeleteTextures(NTEX, tex);
    glDeleteProgram(program);
    return exapp_finish(&app);
}
