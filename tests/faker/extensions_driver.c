/* tests/faker/extensions_driver.c — faker_extensions OUT.txt: the registry
 * extensions without commands that spec/gl_extensions.txt has the faker
 * offer, each used where its effect shows, on a 64x48 EGL pbuffer with
 * depth and stencil: one labelled line per read-back (a checksum plus a
 * sample) or get answer in OUT.txt.
 *   every listed name is in GL_EXTENSIONS (natively: OSMesa has it);
 *   GL_ARB_depth_texture: a GL_DEPTH_COMPONENT24 image, its sizes, read
 *     back with glGetTexImage, drawn as luminance and, GL_ARB_shadow and
 *     GL_EXT_shadow_funcs, with R compared by GL_LEQUAL and GL_GREATER;
 *   GL_ARB_texture_float: GL_RGBA32F and GL_LUMINANCE32F images, their
 *     component types, read back as floats, drawn;
 *   GL_EXT_packed_depth_stencil: glDrawPixels and glReadPixels of the
 *     window's GL_DEPTH_STENCIL as GL_UNSIGNED_INT_24_8, the stencil it
 *     wrote used by a stencil test; a GL_DEPTH24_STENCIL8 image read back;
 *   GL_ARB_depth_buffer_float: the same with
 *     GL_FLOAT_32_UNSIGNED_INT_24_8_REV; GL_DEPTH32F_STENCIL8 and
 *     GL_DEPTH_COMPONENT32F images;
 *   GL_ARB_texture_non_power_of_two: a 3x5 texture drawn;
 *   GL_EXT_texture_swizzle, GL_ARB_texture_swizzle: a texel drawn through
 *     a swizzle set per component and as RGBA, both gets answered;
 *   GL_EXT_stencil_wrap: GL_INCR_WRAP past 255 and GL_DECR_WRAP past 0
 *     (also by glStencilOpSeparate), the stencil read back and tested;
 *   GL_ARB_texture_env_combine, _crossbar, _dot3 (and the EXT combine
 *     and dot3): two units combined, the second interpolating the first
 *     unit's texel with its own, scaled; a GL_DOT3_RGB; settings read back;
 *   GL_ARB_explicit_attrib_location: a GLSL 1.10 attribute at location 3;
 *   pixel buffer objects (GL 2.1, GL_ARB/EXT_pixel_buffer_object):
 *     glTexImage2D, glTexSubImage2D, glDrawPixels, glBitmap and
 *     glPolygonStipple reading a GL_PIXEL_UNPACK_BUFFER at offsets;
 *     glReadPixels (across the wall's tiles, with a row length),
 *     glGetTexImage, glGetPolygonStipple and glGetPixelMapusv writing
 *     into a GL_PIXEL_PACK_BUFFER at offsets, one past its end refused;
 *     both buffers mapped back.
 * Built with RECORDED_GL_NATIVE (faker_extensions_native) it makes the same calls
 * on OSMesa directly: the runs through tessera must write the same file
 * (gl21_commands.sh). EXTENSIONS_TABLE is spec/gl_extensions.txt. */
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

static void ints(const char *label, const GLint *v, int n)
{
    fprintf(out, "%s:", label);
    for (int i = 0; i < n; i++)
        fprintf(out, " %d", v[i]);
    fprintf(out, "\n");
}

static void clear(void)
{
    glClearColor(0.1f, 0.1f, 0.2f, 1.0f);
    glClearDepth(1.0);
    glClearStencil(0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
}

static void textured_quad(GLfloat r)
{
    glBegin(GL_QUADS);
    glTexCoord3f(0, 0, r);
    glVertex2f(-0.7f, -0.7f);
    glTexCoord3f(1, 0, r);
    glVertex2f(0.7f, -0.7f);
    glTexCoord3f(1, 1, r);
    glVertex2f(0.7f, 0.7f);
    glTexCoord3f(0, 1, r);
    glVertex2f(-0.7f, 0.7f);
    glEnd();
}


/* Each listed name, offered or not; returns how many are not. */
static int listed_extensions(const char *table)
{
    FILE *f = fopen(table, "r");
    REQUIRE(f, "cannot read %s", table);
    char line[1024];
    int absent = 0, listed = 0;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#' || line[0] == '\n' || line[0] == '-') /* '-': withheld, not offered */
            continue;
        line[strcspn(line, "\t\n")] = '\0';
        int has = recorded_gl_has_extension(line);
        fprintf(out, "%s: %s\n", line, has ? "offered" : "absent");
        absent += !has;
        listed++;
    }
    fclose(f);
    fprintf(out, "listed extensions: %d\n", listed);
    return absent;
}

static void tex_sizes(const char *label, GLenum target)
{
    static const GLenum pnames[] = {GL_TEXTURE_WIDTH,      GL_TEXTURE_HEIGHT,      GL_TEXTURE_INTERNAL_FORMAT,
                                    GL_TEXTURE_RED_SIZE,   GL_TEXTURE_ALPHA_SIZE,  GL_TEXTURE_LUMINANCE_SIZE,
                                    GL_TEXTURE_DEPTH_SIZE, GL_TEXTURE_STENCIL_SIZE};
    GLint v[sizeof pnames / sizeof pnames[0]];
    for (size_t i = 0; i < sizeof pnames / sizeof pnames[0]; i++) {
        v[i] = -1;
        glGetTexLevelParameteriv(target, 0, pnames[i], &v[i]);
    }
    ints(label, v, (int)(sizeof pnames / sizeof pnames[0]));
}

static void tex_types(const char *label)
{
    static const GLenum pnames[] = {GL_TEXTURE_RED_TYPE,   GL_TEXTURE_GREEN_TYPE,     GL_TEXTURE_BLUE_TYPE,
                                    GL_TEXTURE_ALPHA_TYPE, GL_TEXTURE_LUMINANCE_TYPE, GL_TEXTURE_INTENSITY_TYPE,
                                    GL_TEXTURE_DEPTH_TYPE};
    GLint v[sizeof pnames / sizeof pnames[0]];
    for (size_t i = 0; i < sizeof pnames / sizeof pnames[0]; i++) {
        v[i] = -1;
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, pnames[i], &v[i]);
    }
    ints(label, v, (int)(sizeof pnames / sizeof pnames[0]));
}

static void new_texture(void)
{
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

static void depth_texture(void)
{
    static GLfloat depth[8 * 8];
    for (int i = 0; i < 8 * 8; i++)
        depth[i] = (GLfloat)((i * 37) % 64) / 63.0f;
    new_texture();
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, 8, 8, 0, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
    tex_sizes("depth texture sizes", GL_TEXTURE_2D);
    static GLushort back[8 * 8];
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT, back);
    fprintf(out, "depth texture read back: %08x first %u last %u\n", recorded_gl_fnv(back, sizeof back), back[0],
            back[63]);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    clear();
    glEnable(GL_TEXTURE_2D);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    glTexParameteri(GL_TEXTURE_2D, GL_DEPTH_TEXTURE_MODE, GL_LUMINANCE);
    textured_quad(0.5f);
    frame("depth texture as luminance");
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_R_TO_TEXTURE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    clear();
    textured_quad(0.5f);
    frame("depth texture compared with r 0.5");
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_GREATER);
    clear();
    textured_quad(0.25f);
    frame("depth texture compared with r 0.25 by GL_GREATER");
    GLint mode = 0, func = 0;
    glGetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, &mode);
    glGetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, &func);
    fprintf(out, "compare mode: 0x%x function 0x%x\n", mode, func);
    glDisable(GL_TEXTURE_2D);
}

static void texture_float(void)
{
    static GLfloat rgba[4 * 4 * 4];
    for (int i = 0; i < 4 * 4 * 4; i++)
        rgba[i] = (GLfloat)(i % 7) * 0.37f - 0.5f;
    new_texture();
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, 4, 4, 0, GL_RGBA, GL_FLOAT, rgba);
    tex_sizes("RGBA32F sizes", GL_TEXTURE_2D);
    tex_types("RGBA32F component types");
    static GLfloat back[4 * 4 * 4];
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, back);
    fprintf(out, "RGBA32F read back: %08x equal %d\n", recorded_gl_fnv(back, sizeof back),
            !memcmp(back, rgba, sizeof back));
    clear();
    glEnable(GL_TEXTURE_2D);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    textured_quad(0);
    frame("RGBA32F drawn");
    new_texture();
    glTexImage2D(GL_TEXTURE_2D, 0, GL_LUMINANCE32F_ARB, 4, 4, 0, GL_LUMINANCE, GL_FLOAT, rgba);
    tex_types("LUMINANCE32F component types");
    clear();
    textured_quad(0);
    frame("LUMINANCE32F drawn");
    glDisable(GL_TEXTURE_2D);
}

/* Draws a 16x16 depth-stencil image at (26, 18) as `type` (the centre
 * and the four tiles of the wall), reads the whole window back as `type`,
 * then draws green where the stencil it wrote is 0x5a. */
static void depth_stencil_pixels(const char *label, GLenum type)
{
    size_t bpp = type == GL_UNSIGNED_INT_24_8 ? 4 : 8;
    static unsigned char image[16 * 16 * 8], window[W * H * 8];
    for (int i = 0; i < 16 * 16; i++) {
        uint32_t stencil = i % 3 ? 0x5a : 0x21;
        if (type == GL_UNSIGNED_INT_24_8) {
            uint32_t v = ((uint32_t)(i * 65521u) & 0xffffffu) << 8 | stencil;
            memcpy(image + 4 * i, &v, 4);
        } else {
            float d = (float)(i % 17) / 16.0f;
            uint32_t s = stencil;
            memcpy(image + 8 * i, &d, 4);
            memcpy(image + 8 * i + 4, &s, 4);
        }
    }
    char text[128];
    clear();
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glWindowPos2i(26, 18);
    glDrawPixels(16, 16, GL_DEPTH_STENCIL, type, image);
    glDisable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    memset(window, 0xcc, sizeof window);
    glReadPixels(0, 0, W, H, GL_DEPTH_STENCIL, type, window);
    /* the unused bits of GL_FLOAT_32_UNSIGNED_INT_24_8_REV are undefined */
    if (bpp == 8)
        for (int i = 0; i < W * H; i++)
            window[8 * i + 5] = window[8 * i + 6] = window[8 * i + 7] = 0;
    const unsigned char *inside = window + (size_t)(20 * W + 30) * bpp;
    uint32_t first;
    memcpy(&first, inside, 4);
    fprintf(out, "%s read back: %08x at (30, 20) %08x\n", label, recorded_gl_fnv(window, (size_t)W * H * bpp), first);
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_EQUAL, 0x5a, 0xff);
    glColor3f(0.0f, 1.0f, 0.0f);
    glRecti(-1, -1, 1, 1);
    glDisable(GL_STENCIL_TEST);
    snprintf(text, sizeof text, "%s drawn where its stencil is 0x5a", label);
    frame(text);
}

static void packed_depth_stencil(void)
{
    depth_stencil_pixels("DEPTH_STENCIL UNSIGNED_INT_24_8", GL_UNSIGNED_INT_24_8);
    static GLuint image[4 * 4];
    for (int i = 0; i < 4 * 4; i++)
        image[i] = (GLuint)(i * 0x0f0f0f00u) | (GLuint)i;
    new_texture();
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH24_STENCIL8, 4, 4, 0, GL_DEPTH_STENCIL, GL_UNSIGNED_INT_24_8, image);
    tex_sizes("DEPTH24_STENCIL8 sizes", GL_TEXTURE_2D);
    static GLuint back[4 * 4];
    glGetTexImage(GL_TEXTURE_2D, 0, GL_DEPTH_STENCIL, GL_UNSIGNED_INT_24_8, back);
    fprintf(out, "DEPTH24_STENCIL8 read back: %08x equal %d\n", recorded_gl_fnv(back, sizeof back),
            !memcmp(back, image, sizeof back));
}

static void depth_buffer_float(void)
{
    depth_stencil_pixels("DEPTH_STENCIL FLOAT_32_UNSIGNED_INT_24_8_REV", GL_FLOAT_32_UNSIGNED_INT_24_8_REV);
    static GLfloat depth[4 * 4];
    for (int i = 0; i < 4 * 4; i++)
        depth[i] = (GLfloat)i / 15.0f;
    new_texture();
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, 4, 4, 0, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
    tex_sizes("DEPTH_COMPONENT32F sizes", GL_TEXTURE_2D);
    tex_types("DEPTH_COMPONENT32F component types");
    static GLfloat back[4 * 4];
    glGetTexImage(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT, GL_FLOAT, back);
    fprintf(out, "DEPTH_COMPONENT32F read back: equal %d\n", !memcmp(back, depth, sizeof back));
    new_texture();
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH32F_STENCIL8, 4, 4, 0, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
    tex_sizes("DEPTH32F_STENCIL8 sizes", GL_TEXTURE_2D);
}

static void non_power_of_two(void)
{
    static GLubyte rgba[3 * 5 * 4];
    for (int i = 0; i < 3 * 5 * 4; i++)
        rgba[i] = (GLubyte)(i * 41);
    new_texture();
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 3, 5, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    tex_sizes("3x5 texture sizes", GL_TEXTURE_2D);
    clear();
    glEnable(GL_TEXTURE_2D);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    textured_quad(0);
    glDisable(GL_TEXTURE_2D);
    frame("3x5 texture drawn");
}

/* GL_INCR_WRAP and GL_DECR_WRAP: the stencil wraps at 0 and 255 where
 * GL_INCR/GL_DECR clamp; each count of front-facing quads leaves its own
 * stencil value, read back and used by a stencil test that draws. */
static void stencil_wrap(void)
{
    glPushAttrib(GL_ENABLE_BIT);
    glDisable(GL_DEPTH_TEST); /* every quad passes: the pass ops count them */
    glDisable(GL_TEXTURE_2D);
    clear();
    glClearStencil(254);
    glClear(GL_STENCIL_BUFFER_BIT);
    glClearStencil(0);
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_ALWAYS, 0, ~0u);
    glStencilOp(GL_KEEP, GL_KEEP, GL_INCR_WRAP);
    glColor3f(0.3f, 0.3f, 0.3f);
    for (int i = 0; i < 3; i++) /* 254 -> 255 -> 0 -> 1 */
        textured_quad(0);
    GLubyte stencil[2] = {0, 0};
    glReadPixels(RECORDED_GL_W / 2, RECORDED_GL_H / 2, 1, 1, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, &stencil[0]);
    glStencilOpSeparate(GL_FRONT_AND_BACK, GL_KEEP, GL_KEEP, GL_DECR_WRAP);
    for (int i = 0; i < 2; i++) /* 1 -> 0 -> 255 */
        textured_quad(0);
    glReadPixels(RECORDED_GL_W / 2, RECORDED_GL_H / 2, 1, 1, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, &stencil[1]);
    GLint op = 0;
    glGetIntegerv(GL_STENCIL_PASS_DEPTH_PASS, &op);
    fprintf(out, "stencil after 3 INCR_WRAP from 254: %u, then 2 DECR_WRAP: %u, op 0x%x\n", stencil[0], stencil[1], op);
    glStencilFunc(GL_EQUAL, 255, ~0u);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    glColor3f(0.9f, 0.6f, 0.1f);
    glBegin(GL_QUADS);
    glVertex2f(-1, -1);
    glVertex2f(1, -1);
    glVertex2f(1, 1);
    glVertex2f(-1, 1);
    glEnd();
    glPopAttrib();
    frame("GL_EXT_stencil_wrap: drawn where the stencil wrapped to 255");
}

/* A texture read through its swizzle (blue, red, one, green), set one by
 * one and as RGBA; the answers of both gets. */
static void texture_swizzle(void)
{
    static const GLubyte texel[4] = {200, 100, 50, 25};
    new_texture();
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, texel);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_R, GL_BLUE);
    static const GLint rgba[4] = {GL_BLUE, GL_RED, GL_ONE, GL_GREEN};
    glTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_RGBA, rgba);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_A, GL_ZERO);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_G, GL_TEXTURE_2D); /* not a source: GL_INVALID_ENUM */
    fprintf(out, "swizzle set: error 0x%x\n", glGetError());
    GLint got[4] = {0, 0, 0, 0}, one = 0;
    glGetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_RGBA, got);
    glGetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_G, &one);
    fprintf(out, "GL_TEXTURE_SWIZZLE_RGBA: 0x%x 0x%x 0x%x 0x%x, G 0x%x\n", got[0], got[1], got[2], got[3], one);
    clear();
    glEnable(GL_TEXTURE_2D);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    textured_quad(0);
    glDisable(GL_BLEND);
    glDisable(GL_TEXTURE_2D);
    frame("GL_EXT_texture_swizzle: a texel read as (b, r, 1, 0)");
}

/* GL 1.3-1.4 texture combiners, which GL_ARB_texture_env_combine,
 * _dot3 and _crossbar (and the EXT ones) name: two units, the second
 * combining its own texel with the first unit's (a crossbar source) by
 * GL_INTERPOLATE against the environment colour, scaled; then a GL_DOT3_RGB
 * of a texel with the primary colour; every setting read back. */
static void texture_env_combine(void)
{
    static const GLubyte texel0[2 * 2 * 4] = {250, 40, 10, 255, 20, 230, 40, 255, 30, 60, 240, 128, 200, 200, 20, 64};
    static const GLubyte texel1[2 * 2 * 4] = {128, 200, 64, 255, 255, 128, 0, 255, 0, 64, 128, 255, 192, 192, 192, 255};
    GLuint tex[2];
    glGenTextures(2, tex);
    for (int u = 0; u < 2; u++) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)u);
        glBindTexture(GL_TEXTURE_2D, tex[u]);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 2, 2, 0, GL_RGBA, GL_UNSIGNED_BYTE, u ? texel1 : texel0);
        glEnable(GL_TEXTURE_2D);
        glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
    }
    glActiveTexture(GL_TEXTURE0);
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, GL_REPLACE);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC0_RGB, GL_TEXTURE);
    glActiveTexture(GL_TEXTURE1);
    static const GLfloat env[4] = {0.25f, 0.5f, 0.75f, 0.5f};
    glTexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, env);
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, GL_INTERPOLATE);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC0_RGB, GL_TEXTURE0); /* the crossbar: unit 0's texel */
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC1_RGB, GL_TEXTURE);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC2_RGB, GL_CONSTANT);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND2_RGB, GL_SRC_ALPHA);
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_ALPHA, GL_ADD_SIGNED);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC0_ALPHA, GL_PREVIOUS);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC1_ALPHA, GL_TEXTURE);
    glTexEnvi(GL_TEXTURE_ENV, GL_OPERAND1_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glTexEnvf(GL_TEXTURE_ENV, GL_RGB_SCALE, 2.0f);
    GLint got[6];
    glGetTexEnviv(GL_TEXTURE_ENV, GL_COMBINE_RGB, &got[0]);
    glGetTexEnviv(GL_TEXTURE_ENV, GL_SRC0_RGB, &got[1]);
    glGetTexEnviv(GL_TEXTURE_ENV, GL_OPERAND2_RGB, &got[2]);
    glGetTexEnviv(GL_TEXTURE_ENV, GL_COMBINE_ALPHA, &got[3]);
    glGetTexEnviv(GL_TEXTURE_ENV, GL_OPERAND1_ALPHA, &got[4]);
    GLfloat scale = 0;
    glGetTexEnvfv(GL_TEXTURE_ENV, GL_RGB_SCALE, &scale);
    got[5] = (GLint)scale;
    ints("combine settings of unit 1", got, 6);
    clear();
    glBegin(GL_QUADS);
    glMultiTexCoord2f(GL_TEXTURE0, 0, 0);
    glMultiTexCoord2f(GL_TEXTURE1, 0, 0);
    glVertex2f(-0.7f, -0.7f);
    glMultiTexCoord2f(GL_TEXTURE0, 1, 0);
    glMultiTexCoord2f(GL_TEXTURE1, 1, 0);
    glVertex2f(0.7f, -0.7f);
    glMultiTexCoord2f(GL_TEXTURE0, 1, 1);
    glMultiTexCoord2f(GL_TEXTURE1, 1, 1);
    glVertex2f(0.7f, 0.7f);
    glMultiTexCoord2f(GL_TEXTURE0, 0, 1);
    glMultiTexCoord2f(GL_TEXTURE1, 0, 1);
    glVertex2f(-0.7f, 0.7f);
    glEnd();
    frame("GL_ARB_texture_env_combine and _crossbar: unit 1 interpolates unit 0's texel with its own");
    glDisable(GL_TEXTURE_2D);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    glActiveTexture(GL_TEXTURE0);
    glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, GL_DOT3_RGB);
    glTexEnvi(GL_TEXTURE_ENV, GL_SRC1_RGB, GL_PRIMARY_COLOR);
    clear();
    glColor3f(0.9f, 0.6f, 0.2f);
    textured_quad(0);
    glColor3f(1, 1, 1);
    frame("GL_ARB_texture_env_dot3: a texel dotted with the primary colour");
    glDisable(GL_TEXTURE_2D);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    glDeleteTextures(2, tex);
    fprintf(out, "texture combiners: error 0x%x\n", glGetError());
}

static void explicit_attrib_location(void)
{
    static const char *vs = "#version 110\n"
                            "#extension GL_ARB_explicit_attrib_location : require\n"
                            /* GLSL 1.10 allows layout on `in`, never on `attribute` */
                            "layout(location = 3) in vec4 where;\n"
                            "varying vec4 colour;\n"
                            "void main() { gl_Position = where; colour = vec4(0.2, 0.9, 0.4, 1.0); }\n";
    static const char *fs = "#version 110\nvarying vec4 colour;\nvoid main() { gl_FragColor = colour; }\n";
    GLuint v = glCreateShader(GL_VERTEX_SHADER), f = glCreateShader(GL_FRAGMENT_SHADER), p = glCreateProgram();
    glShaderSource(v, 1, &vs, NULL);
    glShaderSource(f, 1, &fs, NULL);
    glCompileShader(v);
    glCompileShader(f);
    glAttachShader(p, v);
    glAttachShader(p, f);
    glLinkProgram(p);
    GLint compiled = 0, linked = 0;
    glGetShaderiv(v, GL_COMPILE_STATUS, &compiled);
    glGetProgramiv(p, GL_LINK_STATUS, &linked);
    fprintf(out, "explicit location: compiled %d linked %d location %d\n", compiled, linked,
            glGetAttribLocation(p, "where"));
    glUseProgram(p);
    clear();
    /* attribute 3 is no vertex: glVertex provokes each (its position unused) */
    static const GLfloat where[3][2] = {{-0.8f, -0.8f}, {0.8f, -0.6f}, {0.1f, 0.9f}};
    glBegin(GL_TRIANGLES);
    for (int i = 0; i < 3; i++) {
        glVertexAttrib2fv(3, where[i]);
        glVertex2f(0.0f, 0.0f);
    }
    glEnd();
    glUseProgram(0);
    frame("attribute at location 3 drawn");
}

/* GL 2.1 pixel unpack buffers: each image call's pointer is an offset into
 * the bound buffer (not client memory, which holds other bytes here). */
static void unpack_buffer(void)
{
    enum { LEAD = 24, TEX = 8 * 8 * 4, STIPPLE = 32 * 4, BITS = 16 * 4 }; /* bitmap rows: 4-aligned */
    static GLubyte data[LEAD + TEX + STIPPLE + BITS];
    for (size_t i = 0; i < sizeof data; i++)
        data[i] = (GLubyte)(i * 97 + 13);
    GLuint buffer;
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, buffer);
    glBufferData(GL_PIXEL_UNPACK_BUFFER, sizeof data, data, GL_STATIC_DRAW);
    GLint bound = 0;
    glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &bound);
    fprintf(out, "unpack buffer bound: %d\n", bound == (GLint)buffer);
    new_texture();
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 8, 8, 0, GL_RGBA, GL_UNSIGNED_BYTE, (const void *)(uintptr_t)LEAD);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 2, 2, 4, 4, GL_RGBA, GL_UNSIGNED_BYTE, (const void *)(uintptr_t)(LEAD + 4));
    clear();
    glEnable(GL_TEXTURE_2D);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    textured_quad(0);
    glDisable(GL_TEXTURE_2D);
    frame("texture from an unpack buffer drawn");
    clear();
    glWindowPos2i(20, 14);
    glDrawPixels(8, 8, GL_RGBA, GL_UNSIGNED_BYTE, (const void *)(uintptr_t)LEAD);
    glColor3f(0.9f, 0.8f, 0.1f);
    glWindowPos2i(30, 20);
    glBitmap(16, 16, 0, 0, 0, 0, (const GLubyte *)(uintptr_t)(LEAD + TEX + STIPPLE));
    frame("glDrawPixels and glBitmap from an unpack buffer");
    glPolygonStipple((const GLubyte *)(uintptr_t)(LEAD + TEX));
    clear();
    glEnable(GL_POLYGON_STIPPLE);
    glColor3f(0.2f, 0.7f, 0.9f);
    glRecti(-1, -1, 1, 1);
    glDisable(GL_POLYGON_STIPPLE);
    frame("polygon stipple from an unpack buffer");
    const GLubyte *mapped = glMapBuffer(GL_PIXEL_UNPACK_BUFFER, GL_READ_ONLY);
    fprintf(out, "unpack buffer mapped: %s\n",
            mapped && !memcmp(mapped, data, sizeof data) ? "its data" : "other bytes");
    if (mapped)
        glUnmapBuffer(GL_PIXEL_UNPACK_BUFFER);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glDeleteBuffers(1, &buffer);
}

/* FNV-1a of `n` bytes: one line shows a whole buffer. */
static uint32_t fnv(const GLubyte *b, size_t n)
{
    uint32_t h = 2166136261u;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 16777619u;
    return h;
}

/* Pixel buffer objects, the pack side (GL 2.1, GL_ARB_pixel_buffer_object):
 * gets whose answer goes into a GL_PIXEL_PACK_BUFFER at offsets, the
 * buffer mapped back: glReadPixels of a region across the wall's tiles
 * with a row length that leaves bytes between rows alone, glGetTexImage,
 * glGetPolygonStipple, glGetPixelMapusv; a read past the buffer's end
 * (GL_INVALID_OPERATION, nothing written). */
static void pack_buffer(void)
{
    enum { SIZE = 8192, READ_AT = 16, TEX_AT = 4096, STIPPLE_AT = 4608, MAP_AT = 4864 };
    static GLubyte fill[SIZE];
    for (size_t i = 0; i < sizeof fill; i++)
        fill[i] = (GLubyte)(i * 31 + 7);
    clear();
    glColor3f(0.9f, 0.3f, 0.5f);
    glRectf(-0.6f, -0.5f, 0.4f, 0.7f);
    glColor3f(0.1f, 0.8f, 0.3f);
    glRectf(-0.2f, -0.9f, 0.9f, 0.1f);
    glColor3f(1, 1, 1);
    GLuint tex = 0;
    static GLubyte texels[4 * 4 * 4];
    for (size_t i = 0; i < sizeof texels; i++)
        texels[i] = (GLubyte)(i * 13 + 1);
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 4, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    static const GLushort map[4] = {0, 20000, 40000, 65535};
    glPixelMapusv(GL_PIXEL_MAP_R_TO_R, 4, map);
    GLuint buffer;
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, buffer);
    glBufferData(GL_PIXEL_PACK_BUFFER, SIZE, fill, GL_STREAM_READ);
    glPixelStorei(GL_PACK_ROW_LENGTH, 40);
    glReadPixels(10, 6, 30, 20, GL_RGBA, GL_UNSIGNED_BYTE, (void *)(uintptr_t)READ_AT);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, (void *)(uintptr_t)TEX_AT);
    glGetPolygonStipple((GLubyte *)(uintptr_t)STIPPLE_AT);
    glGetPixelMapusv(GL_PIXEL_MAP_R_TO_R, (GLushort *)(uintptr_t)MAP_AT);
    fprintf(out, "gets into a pack buffer: error 0x%x\n", glGetError());
    glReadPixels(0, 0, 64, 48, GL_RGBA, GL_UNSIGNED_BYTE, (void *)(uintptr_t)(SIZE - 64));
    fprintf(out, "glReadPixels past the pack buffer's end: error 0x%x\n", glGetError());
    const GLubyte *mapped = glMapBuffer(GL_PIXEL_PACK_BUFFER, GL_READ_ONLY);
    if (mapped) {
        fprintf(out, "pack buffer: fnv %08x, read-back fnv %08x, texture %s, stipple fnv %08x, map %u %u %u %u\n",
                fnv(mapped, SIZE), fnv(mapped + READ_AT, 40 * 4 * 20),
                memcmp(mapped + TEX_AT, texels, sizeof texels) ? "other bytes" : "its texels",
                fnv(mapped + STIPPLE_AT, 128), ((const GLushort *)(mapped + MAP_AT))[0],
                ((const GLushort *)(mapped + MAP_AT))[1], ((const GLushort *)(mapped + MAP_AT))[2],
                ((const GLushort *)(mapped + MAP_AT))[3]);
        glUnmapBuffer(GL_PIXEL_PACK_BUFFER);
    } else {
        fprintf(out, "pack buffer: not mapped, error 0x%x\n", glGetError());
    }
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glDeleteBuffers(1, &buffer);
    /* a buffer deleted while mapped is unmapped by GL (piglit's
     * gl-2.1-pbo does it): the next buffer maps */
    for (int k = 0; k < 2; k++) {
        glGenBuffers(1, &buffer);
        glBindBuffer(GL_PIXEL_PACK_BUFFER, buffer);
        glBufferData(GL_PIXEL_PACK_BUFFER, 64, NULL, GL_STREAM_READ);
        glReadPixels(30, 22, 4, 4, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
        mapped = glMapBuffer(GL_PIXEL_PACK_BUFFER, GL_READ_ONLY);
        fprintf(out, "pack buffer %d mapped: %s, fnv %08x\n", k, mapped ? "yes" : "no", mapped ? fnv(mapped, 64) : 0);
        glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
        glDeleteBuffers(1, &buffer);
    }
    static const GLushort identity[1] = {0};
    glPixelMapusv(GL_PIXEL_MAP_R_TO_R, 1, identity);
    glDeleteTextures(1, &tex);
    fprintf(out, "pack buffer: error 0x%x\n", glGetError());
}

int main(int argc, char **argv)
{
    out = recorded_gl_start(argc, argv);
    int absent = listed_extensions(EXTENSIONS_TABLE);
    depth_texture();
    texture_float();
    packed_depth_stencil();
    depth_buffer_float();
    non_power_of_two();
    stencil_wrap();
    texture_swizzle();
    texture_env_combine();
    explicit_attrib_location();
    unpack_buffer();
    pack_buffer();
    recorded_gl_end(out, argv[1]);
    CHECK(absent == 0, "%d listed extensions are not in GL_EXTENSIONS", absent);
    printf("offered extensions: written to %s\n", argv[1]);
    return harness_failures ? 1 : 0;
}
