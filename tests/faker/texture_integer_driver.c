/* tests/faker/texture_integer_driver.c — faker_texture_integer OUT.txt:
 * GL_EXT_texture_integer, the extension the faker offers because its six
 * commands are spec commands, used where its effects show on a 64x48 EGL
 * pbuffer: one labelled line per answer or read-back in OUT.txt.
 *   the name in GL_EXTENSIONS, glGetBooleanv(GL_RGBA_INTEGER_MODE_EXT);
 *   glClearColorIiEXT/IuiEXT: the one clear colour GL keeps, read back as
 *     floats after an integer one (Mesa keeps the integers' bits), restored
 *     by glPopAttrib, replaced by glClearColor, and a clear of the
 *     fixed-point window with it (Mesa reads the bits as floats);
 *   glTexParameterIivEXT/IuivEXT: integer border colours of two textures
 *     read back with glGetTexParameterIivEXT/IuivEXT after switching
 *     between them, across types (the same bits in Mesa), a float border
 *     read as integers, other pnames as glTexParameteriv, and
 *     glPushAttrib/glPopAttrib(GL_TEXTURE_BIT) around a change;
 *   images of integer internal formats in every integer format (RGBA,
 *     RGB, ALPHA, LUMINANCE, LUMINANCE_ALPHA, BGRA, RED) and type, their
 *     sizes and component types, read back with glGetTexImage.
 * On the 2x2 wall the tracker answers the integer border colours it keeps
 * and sends the state to every server; the other answers come from a
 * server. Built with RECORDED_GL_NATIVE (faker_texture_integer_native) it
 * makes the same calls on OSMesa directly: the runs through tessera must
 * write the same file (gl21_commands.sh). */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "recorded_gl.h"

static FILE *out;

static void ints(const char *label, const GLint *v, int n)
{
    fprintf(out, "%s:", label);
    for (int i = 0; i < n; i++)
        fprintf(out, " %d", v[i]);
    fprintf(out, "\n");
}

static void uints(const char *label, const GLuint *v, int n)
{
    fprintf(out, "%s:", label);
    for (int i = 0; i < n; i++)
        fprintf(out, " 0x%08x", v[i]);
    fprintf(out, "\n");
}

/* Floats as their bits: an integer clear colour read as floats may be any
 * bit pattern. */
static void float_bits(const char *label, const GLfloat *v, int n)
{
    GLuint bits[4];
    memcpy(bits, v, sizeof(GLfloat) * (size_t)n);
    uints(label, bits, n);
}


static void clear_colour(void)
{
    GLboolean integer_mode = 7;
    glGetBooleanv(GL_RGBA_INTEGER_MODE_EXT, &integer_mode);
    fprintf(out, "GL_RGBA_INTEGER_MODE_EXT: %d\n", integer_mode);
    GLfloat c[4];
    glClearColor(0.25f, 0.5f, 0.75f, 1.0f);
    glPushAttrib(GL_COLOR_BUFFER_BIT);
    glClearColorIiEXT(-7, 300, 1 << 20, 2);
    glGetFloatv(GL_COLOR_CLEAR_VALUE, c);
    float_bits("clear colour after glClearColorIiEXT, as floats", c, 4);
    glPopAttrib();
    glGetFloatv(GL_COLOR_CLEAR_VALUE, c);
    float_bits("clear colour after glPopAttrib", c, 4);
    /* 0.5, 0.25, 0.0, 1.0 as bits: a fixed-point buffer cleared with them */
    glClearColorIuiEXT(0x3f000000u, 0x3e800000u, 0u, 0x3f800000u);
    glGetFloatv(GL_COLOR_CLEAR_VALUE, c);
    float_bits("clear colour after glClearColorIuiEXT, as floats", c, 4);
    glClear(GL_COLOR_BUFFER_BIT);
    recorded_gl_frame(out, "window cleared with glClearColorIuiEXT's bits");
    glClearColor(0.1f, 0.2f, 0.3f, 0.4f);
    glGetFloatv(GL_COLOR_CLEAR_VALUE, c);
    float_bits("clear colour after glClearColor", c, 4);
}

static GLuint new_texture(void)
{
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
}

static void border(const char *label)
{
    GLint i[4] = {-1, -1, -1, -1};
    GLuint u[4] = {1, 1, 1, 1};
    char text[160];
    glGetTexParameterIivEXT(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, i);
    snprintf(text, sizeof text, "%s: glGetTexParameterIivEXT", label);
    ints(text, i, 4);
    glGetTexParameterIuivEXT(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, u);
    snprintf(text, sizeof text, "%s: glGetTexParameterIuivEXT", label);
    uints(text, u, 4);
}

static void texture_parameters(void)
{
    static const GLint signed_border[4] = {-3, 70000, 5, -2147483647};
    static const GLuint unsigned_border[4] = {0xfffffff0u, 1u, 0x80000000u, 42u};
    static const GLfloat float_border[4] = {0.25f, 0.5f, 0.125f, 1.0f};
    GLuint a = new_texture();
    glTexParameterIivEXT(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, signed_border);
    GLuint b = new_texture();
    glTexParameterIuivEXT(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, unsigned_border);
    GLuint f = new_texture();
    glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, float_border);
    glBindTexture(GL_TEXTURE_2D, a);
    border("texture a, border by glTexParameterIivEXT");
    glBindTexture(GL_TEXTURE_2D, b);
    border("texture b, border by glTexParameterIuivEXT");
    glBindTexture(GL_TEXTURE_2D, f);
    border("texture f, border by glTexParameterfv");

    /* other pnames: as glTexParameteriv */
    glBindTexture(GL_TEXTURE_2D, a);
    static const GLint wrap = GL_CLAMP_TO_EDGE, filter = GL_LINEAR;
    static const GLuint base_level = 2;
    glTexParameterIivEXT(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, &wrap);
    glTexParameterIuivEXT(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, &base_level);
    glTexParameterIivEXT(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, &filter);
    GLint v[3] = {0, 0, 0};
    glGetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, &v[0]);
    glGetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, &v[1]);
    glGetTexParameterIivEXT(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, &v[2]);
    ints("texture a: wrap s, base level, mag filter set by glTexParameterI*", v, 3);
    GLuint min_filter = 0;
    glGetTexParameterIuivEXT(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, &min_filter);
    fprintf(out, "texture a: min filter by glGetTexParameterIuivEXT: 0x%x\n", min_filter);

    /* GL_TEXTURE_BIT saves the bound textures' parameters */
    glPushAttrib(GL_TEXTURE_BIT);
    static const GLint other[4] = {1, 2, 3, 4};
    glTexParameterIivEXT(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, other);
    border("texture a, border changed inside glPushAttrib(GL_TEXTURE_BIT)");
    glPopAttrib();
    border("texture a after glPopAttrib");
    glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, float_border);
    GLfloat fv[4];
    glGetTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, fv);
    float_bits("texture a, border by glTexParameterfv again: glGetTexParameterfv", fv, 4);
    glBindTexture(GL_TEXTURE_2D, b);
    border("texture b again");
    glBindTexture(GL_TEXTURE_2D, 0);
    GLuint names[3] = {a, b, f};
    glDeleteTextures(3, names);
}

typedef struct int_image {
    const char *label;
    GLint internal_format;
    GLenum format, type;
    int components, bytes; /* bytes of one component */
} int_image;

static void integer_images(void)
{
    static const int_image images[] = {
        {"RGBA8UI", GL_RGBA8UI_EXT, GL_RGBA_INTEGER_EXT, GL_UNSIGNED_BYTE, 4, 1},
        {"RGB16I", GL_RGB16I_EXT, GL_RGB_INTEGER_EXT, GL_SHORT, 3, 2},
        {"ALPHA32I", GL_ALPHA32I_EXT, GL_ALPHA_INTEGER_EXT, GL_INT, 1, 4},
        {"LUMINANCE8UI", GL_LUMINANCE8UI_EXT, GL_LUMINANCE_INTEGER_EXT, GL_UNSIGNED_BYTE, 1, 1},
        {"LUMINANCE_ALPHA16I", GL_LUMINANCE_ALPHA16I_EXT, GL_LUMINANCE_ALPHA_INTEGER_EXT, GL_SHORT, 2, 2},
        {"INTENSITY32UI", GL_INTENSITY32UI_EXT, GL_RED_INTEGER_EXT, GL_UNSIGNED_INT, 1, 4},
        {"RGBA16UI from BGRA", GL_RGBA16UI_EXT, GL_BGRA_INTEGER_EXT, GL_UNSIGNED_SHORT, 4, 2},
    };
    static const GLenum types[] = {GL_TEXTURE_RED_TYPE,       GL_TEXTURE_ALPHA_TYPE,      GL_TEXTURE_LUMINANCE_TYPE,
                                   GL_TEXTURE_INTENSITY_TYPE, GL_TEXTURE_INTERNAL_FORMAT, GL_TEXTURE_WIDTH};
    enum { SIDE = 5 }; /* rows of odd lengths: the pixel store's alignment matters */
    static unsigned char data[SIDE * SIDE * 4 * 4], back[SIDE * SIDE * 4 * 4];
    for (size_t i = 0; i < sizeof data; i++)
        data[i] = (unsigned char)(i * 29 + 3);
    for (size_t k = 0; k < sizeof images / sizeof images[0]; k++) {
        const int_image *im = &images[k];
        char text[160];
        GLuint t = new_texture();
        glTexImage2D(GL_TEXTURE_2D, 0, im->internal_format, SIDE, SIDE, 0, im->format, im->type, data);
        GLint v[sizeof types / sizeof types[0]];
        for (size_t i = 0; i < sizeof types / sizeof types[0]; i++) {
            v[i] = -1;
            glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, types[i], &v[i]);
        }
        snprintf(text, sizeof text, "%s: component types, internal format, width", im->label);
        ints(text, v, (int)(sizeof types / sizeof types[0]));
        size_t row = (size_t)SIDE * (size_t)(im->components * im->bytes);
        size_t stride = (row + 3) / 4 * 4; /* GL_PACK_ALIGNMENT 4 */
        memset(back, 0xa5, sizeof back);
        glGetTexImage(GL_TEXTURE_2D, 0, im->format, im->type, back);
        fprintf(out, "%s read back: %08x first row equal %d\n", im->label,
                recorded_gl_fnv(back, stride * (SIDE - 1) + row), !memcmp(back, data, row));
        glBindTexture(GL_TEXTURE_2D, 0);
        glDeleteTextures(1, &t);
    }
}

int main(int argc, char **argv)
{
    out = recorded_gl_start(argc, argv);
    int offered = recorded_gl_has_extension("GL_EXT_texture_integer");
    fprintf(out, "GL_EXT_texture_integer: %s\n", offered ? "offered" : "absent");
    clear_colour();
    texture_parameters();
    integer_images();
    recorded_gl_end(out, argv[1]);
    CHECK(offered, "GL_EXT_texture_integer is not in GL_EXTENSIONS");
    printf("GL_EXT_texture_integer: written to %s\n", argv[1]);
    return harness_failures ? 1 : 0;
}
