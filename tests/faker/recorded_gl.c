/* tests/faker/recorded_gl.c — see recorded_gl.h. */
#ifdef RECORDED_GL_NATIVE
#include <GL/osmesa.h>
#else
#include <EGL/egl.h>
#endif
#include <GL/gl.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "recorded_gl.h"

#ifdef RECORDED_GL_NATIVE
static OSMesaContext context;
#else
static EGLDisplay display = EGL_NO_DISPLAY;
static EGLContext context = EGL_NO_CONTEXT;
static EGLSurface surface = EGL_NO_SURFACE;
#endif

uint32_t recorded_gl_fnv(const void *data, size_t n)
{
    const unsigned char *p = data;
    uint32_t h = 2166136261u;
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * 16777619u;
    return h;
}

FILE *recorded_gl_start(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s OUT.txt\n", argv[0]);
        exit(2);
    }
    FILE *out = fopen(argv[1], "w");
    REQUIRE(out, "cannot write %s", argv[1]);
#ifdef RECORDED_GL_NATIVE
    static unsigned char buffer[RECORDED_GL_W * RECORDED_GL_H * 4];
    context = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, NULL);
    REQUIRE(context && OSMesaMakeCurrent(context, buffer, GL_UNSIGNED_BYTE, RECORDED_GL_W, RECORDED_GL_H),
            "an OSMesa context");
#else
    display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    REQUIRE(display != EGL_NO_DISPLAY && eglInitialize(display, NULL, NULL) && eglBindAPI(EGL_OPENGL_API),
            "EGL display");
    static const EGLint config_attrs[] = {
        EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_DEPTH_SIZE, 24, EGL_STENCIL_SIZE, 8,
        EGL_NONE};
    EGLConfig config;
    EGLint n = 0;
    REQUIRE(eglChooseConfig(display, config_attrs, &config, 1, &n) && n == 1, "an EGL config");
    context = eglCreateContext(display, config, EGL_NO_CONTEXT, NULL);
    static const EGLint surface_attrs[] = {EGL_WIDTH, RECORDED_GL_W, EGL_HEIGHT, RECORDED_GL_H, EGL_NONE};
    surface = eglCreatePbufferSurface(display, config, surface_attrs);
    REQUIRE(context && surface && eglMakeCurrent(display, surface, surface, context), "an EGL context and pbuffer");
#endif
    glViewport(0, 0, RECORDED_GL_W, RECORDED_GL_H);
    return out;
}

void recorded_gl_end(FILE *out, const char *path)
{
    fprintf(out, "glGetError at the end: 0x%x\n", glGetError());
    glFinish();
    REQUIRE(fclose(out) == 0, "cannot write %s", path);
#ifdef RECORDED_GL_NATIVE
    OSMesaDestroyContext(context);
#else
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display, context);
    eglDestroySurface(display, surface);
    eglTerminate(display);
#endif
}

void recorded_gl_frame(FILE *out, const char *label)
{
    static unsigned char px[RECORDED_GL_W * RECORDED_GL_H * 4];
    memset(px, 0, sizeof px);
    glReadPixels(0, 0, RECORDED_GL_W, RECORDED_GL_H, GL_RGBA, GL_UNSIGNED_BYTE, px);
    const unsigned char *c = px + ((RECORDED_GL_H / 2) * RECORDED_GL_W + RECORDED_GL_W / 2) * 4;
    fprintf(out, "%s: frame %08x centre %u %u %u %u\n", label, recorded_gl_fnv(px, sizeof px), c[0], c[1], c[2], c[3]);
}

int recorded_gl_has_extension(const char *name)
{
    const char *all = (const char *)glGetString(GL_EXTENSIONS);
    size_t n = strlen(name);
    for (const char *p = all; p && (p = strstr(p, name)) != NULL; p += n)
        if ((p == all || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return 1;
    return 0;
}

void recorded_gl_error_line(FILE *out, const char *label)
{
    fprintf(out, "%s: glGetError 0x%x\n", label, glGetError());
}

int recorded_gl_int(unsigned pname)
{
    GLint v = -7;
    glGetIntegerv((GLenum)pname, &v);
    return v;
}
