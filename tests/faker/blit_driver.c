/* tests/faker/blit_driver.c — faker_blit OUT.txt: GL_ARB_framebuffer_object
 * (GL 3.0's core-named FBO commands) and glBlitFramebuffer, which the
 * faker offers because their commands are spec commands (glBlitFramebufferEXT
 * of GL_EXT_framebuffer_blit is gl.xml's alias), used where their effects
 * show on the 64x48 EGL pbuffer: one labelled line per answer or read-back.
 *   an 80x80 FBO of a texture and a GL_DEPTH24_STENCIL8 renderbuffer made
 *     with the core names: its status, attachment, renderbuffer and binding
 *     queries (the read and draw bindings apart), a depth- and
 *     stencil-tested drawing read back;
 *   blits with the read and draw framebuffers bound apart: the FBO into
 *     the window scaled and flipped across the wall's tile borders
 *     (GL_NEAREST and GL_LINEAR, the latter through glBlitFramebufferEXT);
 *     the window into itself from one tile's part to another's, colour,
 *     depth and stencil; the window into the FBO, mirrored; a
 *     multisample renderbuffer (glRenderbufferStorageMultisample) resolved
 *     into the FBO;
 *   a layer of a 3D texture (glFramebufferTextureLayer) cleared and read;
 *   glGenerateMipmap of the drawn texture; the blits' errors; an occlusion
 *     query counted in the FBO (a wall answers one server's count).
 * On the 2x2 wall of 32x24 tiles the FBOs are whole on every server and a
 * blit from the window is gathered from the tiles (spus/tilesort/blit.c).
 * Built with RECORDED_GL_NATIVE (faker_blit_native) it makes the same
 * calls on OSMesa directly: the runs through tessera must write the same
 * file. */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "recorded_gl.h"

#ifdef RECORDED_GL_NATIVE
/* libOSMesa exports no glBlitFramebufferEXT: Mesa's is the same entry as
 * glBlitFramebuffer (gl.xml's alias), which the faker's alias jumps to. */
#define glBlitFramebufferEXT glBlitFramebuffer
#endif

#define SIDE 80

static FILE *out;

static void error_line(const char *label) { recorded_gl_error_line(out, label); }

static GLint get_int(GLenum pname) { return recorded_gl_int(pname); }

/* Colour, depth and stencil of a rectangle of the read framebuffer. */
static void read_rect(const char *label, GLint x, GLint y, GLsizei w, GLsizei h)
{
    static unsigned char px[SIDE * SIDE * 4], stencil[SIDE * SIDE];
    static GLfloat depth[SIDE * SIDE];
    memset(px, 0, sizeof px);
    memset(depth, 0, sizeof depth);
    memset(stencil, 0, sizeof stencil);
    size_t n = (size_t)w * (size_t)h;
    glReadPixels(x, y, w, h, GL_RGBA, GL_UNSIGNED_BYTE, px);
    glReadPixels(x, y, w, h, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
    glReadPixels(x, y, w, h, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, stencil);
    const unsigned char *c = px + ((h / 2) * w + w / 2) * 4;
    fprintf(out, "%s: colour %08x centre %u %u %u %u, depth %08x, stencil %08x\n", label, recorded_gl_fnv(px, n * 4),
            c[0], c[1], c[2], c[3], recorded_gl_fnv(depth, n * sizeof *depth), recorded_gl_fnv(stencil, n));
}

static void quad(GLfloat x0, GLfloat y0, GLfloat x1, GLfloat y1, GLfloat z)
{
    glBegin(GL_QUADS);
    glVertex3f(x0, y0, z);
    glVertex3f(x1, y0, z);
    glVertex3f(x1, y1, z);
    glVertex3f(x0, y1, z);
    glEnd();
}

/* Coloured, depth-tested quads that leave a stencil pattern. */
static void scene(GLfloat shift)
{
    glClearColor(0.1f, 0.2f, 0.3f, 1.0f);
    glClearDepth(1.0);
    glClearStencil(3);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_ALWAYS, 0x41, 0xff);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    glColor3f(1, 0, 0);
    quad(-0.8f + shift, -0.7f, 0.4f, 0.5f, 0.25f);
    glStencilFunc(GL_ALWAYS, 0x82, 0xff);
    glColor3f(0, 1, 0);
    quad(-0.4f, -0.5f + shift, 0.75f, 0.8f, -0.25f);
    glColor3f(0, 0, 1);
    quad(-1.0f, 0.1f, 0.1f - shift, 1.0f, 0.5f);
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_DEPTH_TEST);
}

static GLuint make_fbo(GLuint *tex_out, GLuint *rb_out)
{
    GLuint fb = 0, rb = 0, tex = 0;
    glGenFramebuffers(1, &fb);
    glGenRenderbuffers(1, &rb);
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, SIDE, SIDE, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, SIDE, SIDE);
    GLint w = 0, stencil_bits = 0;
    glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_WIDTH, &w);
    glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_STENCIL_SIZE, &stencil_bits);
    fprintf(out, "renderbuffer: width %d stencil bits %d, glIsRenderbuffer %d, binding is it %d\n", w, stencil_bits,
            glIsRenderbuffer(rb), get_int(GL_RENDERBUFFER_BINDING) == (GLint)rb);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, rb);
    GLint type = 0, name = 0;
    glGetFramebufferAttachmentParameteriv(GL_FRAMEBUFFER, GL_STENCIL_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE,
                                          &type);
    glGetFramebufferAttachmentParameteriv(GL_FRAMEBUFFER, GL_STENCIL_ATTACHMENT, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME,
                                          &name);
    fprintf(out, "core FBO: status 0x%x glIsFramebuffer %d, stencil attachment type 0x%x the renderbuffer %d\n",
            glCheckFramebufferStatus(GL_FRAMEBUFFER), glIsFramebuffer(fb), type, name == (GLint)rb);
    glViewport(0, 0, SIDE, SIDE);
    scene(0.0f);
    read_rect("drawn into the FBO", 0, 0, SIDE, SIDE);
    error_line("FBO drawn");
    /* a wall draws the FBO whole on every server: one server's count */
    GLuint query = 0, samples = 0;
    glGenQueries(1, &query);
    glBeginQuery(GL_SAMPLES_PASSED, query);
    quad(-0.5f, -0.5f, 0.5f, 0.5f, 0.0f);
    glEndQuery(GL_SAMPLES_PASSED);
    glGetQueryObjectuiv(query, GL_QUERY_RESULT, &samples);
    glDeleteQueries(1, &query);
    fprintf(out, "occlusion query in the FBO: %u samples\n", samples);
    *tex_out = tex;
    *rb_out = rb;
    return fb;
}

/* The window's buffers as a default framebuffer's attachments (what
 * piglit's pixel probes ask of the read buffer). */
static void window_attachments(void)
{
    static const GLenum names[] = {GL_FRONT_LEFT, GL_BACK_LEFT, GL_DEPTH, GL_STENCIL};
    static const GLenum pnames[] = {GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, GL_FRAMEBUFFER_ATTACHMENT_COMPONENT_TYPE,
                                    GL_FRAMEBUFFER_ATTACHMENT_RED_SIZE, GL_FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE,
                                    GL_FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        fprintf(out, "window attachment 0x%x:", names[i]);
        for (size_t k = 0; k < sizeof pnames / sizeof pnames[0]; k++) {
            GLint v = -7;
            glGetFramebufferAttachmentParameteriv(GL_READ_FRAMEBUFFER, names[i], pnames[k], &v);
            fprintf(out, " 0x%x (error 0x%x)", v, glGetError());
        }
        fprintf(out, "\n");
    }
}

/* Read and draw framebuffers bound apart, and the bindings' answers. */
static void bind_apart(GLuint read, GLuint draw, GLuint fb)
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, read);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, draw);
    fprintf(out, "bound read %s draw %s: read binding %s, draw binding %s\n", read ? "FBO" : "window",
            draw ? "FBO" : "window", get_int(GL_READ_FRAMEBUFFER_BINDING) == (GLint)read ? "right" : "wrong",
            get_int(GL_DRAW_FRAMEBUFFER_BINDING) == (GLint)draw ? "right" : "wrong");
    (void)fb;
}

static void blits(GLuint fb)
{
    /* the FBO into the window, across both tile borders, scaled and flipped */
    glViewport(0, 0, RECORDED_GL_W, RECORDED_GL_H);
    bind_apart(0, 0, fb);
    scene(0.1f);
    bind_apart(fb, 0, fb);
    glBlitFramebuffer(0, 0, SIDE, SIDE, 60, 4, 10, 44, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBlitFramebufferEXT(10, 10, 30, 30, 2, 30, 30, 46, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    glBlitFramebuffer(20, 20, 52, 44, 16, 12, 48, 36, GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT, GL_NEAREST);
    error_line("FBO into the window");
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    read_rect("the window after the FBO's blits", 0, 0, RECORDED_GL_W, RECORDED_GL_H);

    /* the window into itself: the top right tile's part onto the bottom
     * left's, flipped both ways, scaled down, partly outside */
    glBlitFramebuffer(36, 26, 60, 46, 2, 2, 26, 22, GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT,
                      GL_NEAREST);
    read_rect("the window after its blit between tiles", 0, 0, RECORDED_GL_W, RECORDED_GL_H);
    glBlitFramebuffer(8, 8, 40, 32, 63, 47, 41, 33, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST); /* apart: GL leaves an overlap undefined */
    read_rect("the window after its flipped blit", 0, 0, RECORDED_GL_W, RECORDED_GL_H);
    glBlitFramebuffer(20, 14, 44, 34, 0, 26, 12, 36, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    read_rect("the window after its scaled blit", 0, 0, RECORDED_GL_W, RECORDED_GL_H);
    glBlitFramebuffer(-10, -6, 12, 10, 40, 2, 62, 18, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    error_line("the window into itself");
    read_rect("the window after its own blits", 0, 0, RECORDED_GL_W, RECORDED_GL_H);

    /* the window into the FBO, mirrored, with the program's scissor */
    bind_apart(0, fb, fb);
    glEnable(GL_SCISSOR_TEST);
    glScissor(4, 4, 70, 70);
    glBlitFramebuffer(0, 0, RECORDED_GL_W, RECORDED_GL_H, SIDE, 0, 0, SIDE,
                      GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT, GL_NEAREST);
    glDisable(GL_SCISSOR_TEST);
    error_line("the window into the FBO");
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fb);
    read_rect("the FBO after the window's blit", 0, 0, SIDE, SIDE);

    /* errors: GL's own, once */
    glBlitFramebuffer(0, 0, 8, 8, 0, 0, 8, 8, GL_DEPTH_BUFFER_BIT, GL_LINEAR);
    error_line("depth with GL_LINEAR");
    glBlitFramebuffer(0, 0, 8, 8, 0, 0, 8, 8, 0x10, GL_NEAREST);
    error_line("a mask GL does not know");
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glBlitFramebuffer(0, 0, 8, 8, 0, 0, 8, 8, GL_COLOR_BUFFER_BIT, GL_TEXTURE_2D);
    error_line("a filter GL does not know, from the window");
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

/* A multisample renderbuffer drawn and resolved into the FBO. */
static void resolve(GLuint fb)
{
    GLuint ms_fb = 0, ms_rb = 0;
    glGenFramebuffers(1, &ms_fb);
    glGenRenderbuffers(1, &ms_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, ms_rb);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, 4, GL_RGBA8, SIDE, SIDE);
    GLint samples = 0;
    glGetRenderbufferParameteriv(GL_RENDERBUFFER, GL_RENDERBUFFER_SAMPLES, &samples);
    glBindFramebuffer(GL_FRAMEBUFFER, ms_fb);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, ms_rb);
    fprintf(out, "multisample FBO: samples %d status 0x%x\n", samples, glCheckFramebufferStatus(GL_FRAMEBUFFER));
    glViewport(0, 0, SIDE, SIDE);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glColor3f(1, 1, 0);
    glBegin(GL_TRIANGLES); /* slanted edges: partly covered pixels */
    glVertex2f(-0.9f, -0.8f);
    glVertex2f(0.85f, -0.3f);
    glVertex2f(-0.2f, 0.9f);
    glEnd();
    bind_apart(ms_fb, fb, fb);
    glBlitFramebuffer(0, 0, SIDE, SIDE, 0, 0, SIDE, SIDE, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    error_line("resolved");
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    read_rect("the FBO after the resolve", 0, 0, SIDE, SIDE);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &ms_fb);
    glDeleteRenderbuffers(1, &ms_rb);
    fprintf(out, "deleted: glIsFramebuffer %d glIsRenderbuffer %d\n", glIsFramebuffer(ms_fb), glIsRenderbuffer(ms_rb));
}

/* A layer of a 3D texture as the colour attachment. */
static void layer(void)
{
    GLuint fb = 0, tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_3D, tex);
    glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA8, 8, 8, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glBindTexture(GL_TEXTURE_3D, 0);
    glGenFramebuffers(1, &fb);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, tex, 0, 2);
    GLint got = -1;
    glGetFramebufferAttachmentParameteriv(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_FRAMEBUFFER_ATTACHMENT_TEXTURE_LAYER,
                                          &got);
    fprintf(out, "3D layer: status 0x%x layer %d\n", glCheckFramebufferStatus(GL_FRAMEBUFFER), got);
    glClearColor(0.25f, 0.5f, 0.75f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    static unsigned char texels[8 * 8 * 4 * 4];
    glBindTexture(GL_TEXTURE_3D, tex);
    glGetTexImage(GL_TEXTURE_3D, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    glBindTexture(GL_TEXTURE_3D, 0);
    fprintf(out, "3D layer cleared: texels %08x, layer 2 first %u %u %u\n", recorded_gl_fnv(texels, sizeof texels),
            texels[2 * 256], texels[2 * 256 + 1], texels[2 * 256 + 2]);
    glDeleteFramebuffers(1, &fb);
    glDeleteTextures(1, &tex);
    error_line("3D layer");
}

int main(int argc, char **argv)
{
    out = recorded_gl_start(argc, argv);
    int offered = recorded_gl_has_extension("GL_ARB_framebuffer_object"),
        blit = recorded_gl_has_extension("GL_EXT_framebuffer_blit");
    fprintf(out, "GL_ARB_framebuffer_object: %s, GL_EXT_framebuffer_blit: %s\n", offered ? "offered" : "absent",
            blit ? "offered" : "absent");
    if (offered && blit) {
        GLuint tex = 0, rb = 0;
        window_attachments();
        GLuint fb = make_fbo(&tex, &rb);
        blits(fb);
        resolve(fb);
        layer();
        glBindTexture(GL_TEXTURE_2D, tex);
        glGenerateMipmap(GL_TEXTURE_2D);
        GLint level1 = 0;
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 1, GL_TEXTURE_WIDTH, &level1);
        fprintf(out, "glGenerateMipmap: level 1 width %d\n", level1);
        glBindTexture(GL_TEXTURE_2D, 0);
        glDeleteFramebuffers(1, &fb);
        glDeleteRenderbuffers(1, &rb);
        glDeleteTextures(1, &tex);
        error_line("the end");
        recorded_gl_frame(out, "the window at the end");
    }
    recorded_gl_end(out, argv[1]);
    printf("GL_ARB_framebuffer_object: %s, written to %s\n", offered ? "offered" : "absent", argv[1]);
    return harness_failures ? 1 : 0;
}
