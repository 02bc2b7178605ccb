/* tests/faker/fbo_driver.c — faker_fbo OUT.txt: GL_EXT_framebuffer_object,
 * which the faker offers because its seventeen commands are spec commands,
 * used where its effects show on a 64x48 EGL pbuffer: one labelled line
 * per answer or read-back in OUT.txt.
 *   a name bound before any glGen* (EXT creates it): an incomplete FBO of
 *     the program's, not one of render's (render's window FBOs take the
 *     driver's first names);
 *   an FBO with an 80x80 texture and a depth renderbuffer: its status, the
 *     attachment and renderbuffer queries, the bindings, glDrawBuffer's
 *     answer in it, a clear, a depth-tested drawing, a quad inside one
 *     wall tile's part of the window, an array draw and a glDrawPixels
 *     beyond the window's size read back (colour and depth),
 *     glGenerateMipmapEXT's level 1;
 *   framebuffer 0 is the window: the texture drawn into it, read back;
 *   incompleteness, the errors of a bad target, an unknown renderbuffer
 *     and storage without a renderbuffer bound; deleting the bound FBO
 *     (back to the window).
 * On the 2x2 wall of 32x24 tiles the FBO (80x80) is drawn whole on every
 * server and read back from one, and its texture is then drawn into the
 * window tile by tile (spus/tilesort/fbo.c). Built with RECORDED_GL_NATIVE
 * (faker_fbo_native) it makes the same calls on OSMesa directly: the runs
 * through tessera must write the same file. */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "recorded_gl.h"

/* Larger than the 64x48 window both ways: a clear or an image that went
 * by the window's size would miss part of it. */
#define SIDE 80

static FILE *out;


static void error_line(const char *label) { recorded_gl_error_line(out, label); }

static GLint get_int(GLenum pname) { return recorded_gl_int(pname); }

/* The bindings in the program's names, as whether they are `fb`/`rb`. */
static void bindings(const char *label, GLuint fb, GLuint rb)
{
    GLint f = get_int(GL_FRAMEBUFFER_BINDING_EXT), r = get_int(GL_RENDERBUFFER_BINDING_EXT);
    fprintf(out, "%s: framebuffer %s, renderbuffer %s\n", label,
            f == (GLint)fb ? (fb ? "the one bound" : "0") : "other",
            r == (GLint)rb ? (rb ? "the one bound" : "0") : "other");
}

static void read_square(const char *label)
{
    static unsigned char px[SIDE * SIDE * 4];
    static GLfloat depth[SIDE * SIDE];
    memset(px, 0, sizeof px);
    memset(depth, 0, sizeof depth);
    glReadPixels(0, 0, SIDE, SIDE, GL_RGBA, GL_UNSIGNED_BYTE, px);
    glReadPixels(0, 0, SIDE, SIDE, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
    const unsigned char *c = px + ((SIDE / 2) * SIDE + SIDE / 2) * 4;
    fprintf(out, "%s: colour %08x centre %u %u %u %u, depth %08x\n", label, recorded_gl_fnv(px, sizeof px), c[0], c[1],
            c[2], c[3], recorded_gl_fnv(depth, sizeof depth));
}

static void quad(GLfloat x0, GLfloat y0, GLfloat x1, GLfloat y1, GLfloat z)
{
    glBegin(GL_QUADS);
    glTexCoord2f(0, 0);
    glVertex3f(x0, y0, z);
    glTexCoord2f(1, 0);
    glVertex3f(x1, y0, z);
    glTexCoord2f(1, 1);
    glVertex3f(x1, y1, z);
    glTexCoord2f(0, 1);
    glVertex3f(x0, y1, z);
    glEnd();
}

/* FBO pixel p (of SIDE) as a coordinate under the FBO's viewport. */
static GLfloat ndc(int p) { return (GLfloat)p * 2.0f / SIDE - 1.0f; }

/* Drawn into the FBO where a wall's window tiles would place it wrongly,
 * each in a geometry buffer of its own (a state change between): a quad
 * whose window box is inside one 32x24 tile only, and an array draw
 * (large enough for tilesort to sort primitive by primitive) of 8x8-pixel
 * cells beyond the 64x48 window, where no tile is. */
static void beyond_the_window(void)
{
    glShadeModel(GL_FLAT);
    glColor3f(1, 1, 0);
    quad(ndc(40), ndc(30), ndc(56), ndc(44), 0.0f);
    glShadeModel(GL_SMOOTH);
    static GLfloat cells[(SIDE / 8) * (SIDE / 8) * 12];
    GLsizei n = 0;
    for (int j = 0; j < SIDE / 8; j++)
        for (int i = 0; i < SIDE / 8; i++) {
            if (8 * i < RECORDED_GL_W && 8 * j < RECORDED_GL_H)
                continue; /* inside the window's size */
            GLfloat x0 = ndc(8 * i), y0 = ndc(8 * j), x1 = ndc(8 * i + 7), y1 = ndc(8 * j + 7);
            GLfloat tri[12] = {x0, y0, x1, y0, x1, y1, x0, y0, x1, y1, x0, y1};
            memcpy(&cells[n * 2], tri, sizeof tri);
            n += 6;
        }
    glColor3f(1, 0, 1);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(2, GL_FLOAT, 0, cells);
    glDrawArrays(GL_TRIANGLES, 0, n);
    glDisableClientState(GL_VERTEX_ARRAY);
    fprintf(out, "beyond the window: %d triangles\n", (int)n / 3);
}

/* A name bound before any glGen*: EXT makes it a framebuffer of the
 * program's own, with nothing attached. */
static void ungenerated_name(void)
{
    glBindFramebufferEXT(GL_FRAMEBUFFER_EXT, 1);
    fprintf(out, "bound ungenerated 1: binding %d, glIsFramebufferEXT %d, status 0x%x\n",
            get_int(GL_FRAMEBUFFER_BINDING_EXT), glIsFramebufferEXT(1),
            glCheckFramebufferStatusEXT(GL_FRAMEBUFFER_EXT));
    glBindFramebufferEXT(GL_FRAMEBUFFER_EXT, 0);
    GLuint one = 1;
    glDeleteFramebuffersEXT(1, &one);
    fprintf(out, "deleted 1: glIsFramebufferEXT %d\n", glIsFramebufferEXT(1));
    error_line("ungenerated name");
}

static void render_to_texture(GLuint *tex_out)
{
    GLuint fb = 0, rb = 0, tex = 0;
    glGenFramebuffersEXT(1, &fb);
    glGenRenderbuffersEXT(1, &rb);
    glGenTextures(1, &tex);
    fprintf(out, "names: framebuffer %s, renderbuffer %s, unknown 4242 glIsFramebufferEXT %d glIsRenderbufferEXT %d\n",
            fb ? "nonzero" : "0", rb ? "nonzero" : "0", glIsFramebufferEXT(4242), glIsRenderbufferEXT(4242));
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, SIDE, SIDE, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindRenderbufferEXT(GL_RENDERBUFFER_EXT, rb);
    glRenderbufferStorageEXT(GL_RENDERBUFFER_EXT, GL_DEPTH_COMPONENT24, SIDE, SIDE);
    GLint w = 0, h = 0, format = 0, depth_bits = 0;
    glGetRenderbufferParameterivEXT(GL_RENDERBUFFER_EXT, GL_RENDERBUFFER_WIDTH_EXT, &w);
    glGetRenderbufferParameterivEXT(GL_RENDERBUFFER_EXT, GL_RENDERBUFFER_HEIGHT_EXT, &h);
    glGetRenderbufferParameterivEXT(GL_RENDERBUFFER_EXT, GL_RENDERBUFFER_INTERNAL_FORMAT_EXT, &format);
    glGetRenderbufferParameterivEXT(GL_RENDERBUFFER_EXT, GL_RENDERBUFFER_DEPTH_SIZE_EXT, &depth_bits);
    fprintf(out, "renderbuffer: %dx%d format 0x%x depth bits %d\n", w, h, format, depth_bits);
    glBindFramebufferEXT(GL_FRAMEBUFFER_EXT, fb);
    bindings("bound", fb, rb);
    fprintf(out, "empty FBO: status 0x%x\n", glCheckFramebufferStatusEXT(GL_FRAMEBUFFER_EXT));
    glFramebufferTexture2DEXT(GL_FRAMEBUFFER_EXT, GL_COLOR_ATTACHMENT0_EXT, GL_TEXTURE_2D, tex, 0);
    glFramebufferRenderbufferEXT(GL_FRAMEBUFFER_EXT, GL_DEPTH_ATTACHMENT_EXT, GL_RENDERBUFFER_EXT, rb);
    fprintf(out, "attached: status 0x%x\n", glCheckFramebufferStatusEXT(GL_FRAMEBUFFER_EXT));
    GLint type = 0, name = 0;
    glGetFramebufferAttachmentParameterivEXT(GL_FRAMEBUFFER_EXT, GL_COLOR_ATTACHMENT0_EXT,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE_EXT, &type);
    glGetFramebufferAttachmentParameterivEXT(GL_FRAMEBUFFER_EXT, GL_COLOR_ATTACHMENT0_EXT,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME_EXT, &name);
    fprintf(out, "colour attachment: type 0x%x, the texture %d\n", type, name == (GLint)tex);
    glGetFramebufferAttachmentParameterivEXT(GL_FRAMEBUFFER_EXT, GL_DEPTH_ATTACHMENT_EXT,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE_EXT, &type);
    glGetFramebufferAttachmentParameterivEXT(GL_FRAMEBUFFER_EXT, GL_DEPTH_ATTACHMENT_EXT,
                                             GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME_EXT, &name);
    fprintf(out, "depth attachment: type 0x%x, the renderbuffer %d\n", type, name == (GLint)rb);
    fprintf(out, "in the FBO: GL_DRAW_BUFFER 0x%x GL_READ_BUFFER 0x%x\n", get_int(GL_DRAW_BUFFER),
            get_int(GL_READ_BUFFER));
    glDrawBuffer(GL_COLOR_ATTACHMENT0_EXT);
    glReadBuffer(GL_COLOR_ATTACHMENT0_EXT);
    error_line("FBO set up");

    glViewport(0, 0, SIDE, SIDE);
    glClearColor(0.1f, 0.2f, 0.3f, 1.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glColor3f(1, 0, 0);
    quad(-0.75f, -0.75f, 0.5f, 0.5f, 0.25f);
    glColor3f(0, 1, 0);
    quad(-0.5f, -0.5f, 0.75f, 0.75f, -0.25f);
    glColor3f(0, 0, 1); /* behind the green: hidden where they overlap */
    quad(-1.0f, 0.0f, 0.0f, 1.0f, 0.5f);
    glDisable(GL_DEPTH_TEST);
    beyond_the_window();
    static unsigned char image[16 * 16 * 4];
    for (size_t i = 0; i < sizeof image; i++)
        image[i] = (unsigned char)(i * 7);
    glWindowPos2i(SIDE - 20, SIDE - 12); /* outside the window, inside the FBO */
    glDrawPixels(16, 16, GL_RGBA, GL_UNSIGNED_BYTE, image);
    read_square("drawn into the FBO");

    glBindTexture(GL_TEXTURE_2D, tex);
    glGenerateMipmapEXT(GL_TEXTURE_2D);
    GLint level1 = 0;
    glGetTexLevelParameteriv(GL_TEXTURE_2D, 1, GL_TEXTURE_WIDTH, &level1);
    fprintf(out, "glGenerateMipmapEXT: level 1 width %d\n", level1);
    glBindTexture(GL_TEXTURE_2D, 0);
    error_line("drawn");

    /* errors */
    glBindFramebufferEXT(GL_TEXTURE_2D, fb);
    error_line("glBindFramebufferEXT(GL_TEXTURE_2D)");
    glFramebufferRenderbufferEXT(GL_FRAMEBUFFER_EXT, GL_STENCIL_ATTACHMENT_EXT, GL_RENDERBUFFER_EXT, 4242);
    error_line("glFramebufferRenderbufferEXT of an unknown renderbuffer");
    glBindRenderbufferEXT(GL_RENDERBUFFER_EXT, 0);
    glRenderbufferStorageEXT(GL_RENDERBUFFER_EXT, GL_RGBA8, 4, 4);
    error_line("glRenderbufferStorageEXT with none bound");

    glBindFramebufferEXT(GL_FRAMEBUFFER_EXT, 0);
    bindings("back to 0", 0, 0);
    fprintf(out, "the window: status 0x%x GL_DRAW_BUFFER 0x%x GL_READ_BUFFER 0x%x\n",
            glCheckFramebufferStatusEXT(GL_FRAMEBUFFER_EXT), get_int(GL_DRAW_BUFFER), get_int(GL_READ_BUFFER));

    /* deleting the bound FBO goes back to the window */
    GLuint doomed = 0;
    glGenFramebuffersEXT(1, &doomed);
    glBindFramebufferEXT(GL_FRAMEBUFFER_EXT, doomed);
    glDeleteFramebuffersEXT(1, &doomed);
    bindings("deleted while bound", 0, 0);
    fprintf(out, "deleted: glIsFramebufferEXT %d\n", glIsFramebufferEXT(doomed));
    glDeleteFramebuffersEXT(1, &fb);
    glDeleteRenderbuffersEXT(1, &rb);
    fprintf(out, "deleted: glIsFramebufferEXT %d glIsRenderbufferEXT %d\n", glIsFramebufferEXT(fb),
            glIsRenderbufferEXT(rb));
    error_line("deleted");
    *tex_out = tex;
}

/* The texture drawn into the window (framebuffer 0). */
static void texture_to_window(GLuint tex)
{
    glViewport(0, 0, RECORDED_GL_W, RECORDED_GL_H);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    quad(-0.5f, -0.5f, 0.5f, 0.5f, 0.0f);
    glDisable(GL_TEXTURE_2D);
    recorded_gl_frame(out, "the FBO's texture drawn into the window");
    glDeleteTextures(1, &tex);
}

int main(int argc, char **argv)
{
    out = recorded_gl_start(argc, argv);
    int offered = recorded_gl_has_extension("GL_EXT_framebuffer_object");
    fprintf(out, "GL_EXT_framebuffer_object: %s\n", offered ? "offered" : "absent");
    if (offered) {
        GLuint tex = 0;
        bindings("at the start", 0, 0);
        ungenerated_name();
        render_to_texture(&tex);
        texture_to_window(tex);
    }
    recorded_gl_end(out, argv[1]);
    printf("GL_EXT_framebuffer_object: %s, written to %s\n", offered ? "offered" : "absent", argv[1]);
    return harness_failures ? 1 : 0;
}
