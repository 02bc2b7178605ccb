/* tests/faker/egl_surfaceless_test.c — EGL with no X server at all, linked
 * against the faker's libEGL.so.1 and libGL.so.1 (DISPLAY is unset by the
 * test): the surfaceless platform and EGL_DEFAULT_DISPLAY initialise,
 * OpenGL ES is refused (eglBindAPI: EGL_BAD_PARAMETER; ES configs: none),
 * an OpenGL context draws into a pbuffer and surfaceless, glGetString
 * names tessera and 2.1, glReadPixels reads back what glClear drew
 * through the chain's render SPU, and glGetMinmaxParameteriv (the imaging
 * subset, not in the spec) is an entry that writes nothing and warns once
 * for two calls. */
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"

/* CHECK(cond, EGL_SAYS): the report adds what eglGetError says once cond
 * has failed (it is read only then). */
#define EGL_SAYS "eglGetError 0x%x", (unsigned)eglGetError()

static void clear_and_read(GLfloat r, GLfloat g, GLfloat b, const unsigned char want[4])
{
    glClearColor(r, g, b, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    unsigned char px[4] = {0, 0, 0, 0};
    glReadPixels(3, 2, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, px);
    CHECK(!memcmp(px, want, 4), "read back %u %u %u %u, expected %u %u %u %u", px[0], px[1], px[2], px[3], want[0],
          want[1], want[2], want[3]);
}

int main(void)
{
    EGLDisplay dpy = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    CHECK(dpy != EGL_NO_DISPLAY, EGL_SAYS);
    EGLint major = 0, minor = 0;
    CHECK(eglInitialize(dpy, &major, &minor) && major == 1 && minor == 5, EGL_SAYS);
    CHECK(strstr(eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS), "EGL_MESA_platform_surfaceless") != NULL, EGL_SAYS);
    CHECK(!strcmp(eglQueryString(dpy, EGL_CLIENT_APIS), "OpenGL"), EGL_SAYS);

    CHECK(!eglBindAPI(EGL_OPENGL_ES_API) && eglGetError() == EGL_BAD_PARAMETER, EGL_SAYS);
    CHECK(eglBindAPI(EGL_OPENGL_API) && eglQueryAPI() == EGL_OPENGL_API, EGL_SAYS);

    /* Configs match an ES renderable type (xscreensaver's way: choose for
     * ES, bind OpenGL, make an OpenGL 1.3 context), but are conformant for
     * OpenGL only, and no ES context can be made (the bind is refused). */
    static const EGLint es_attrs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_ES_BIT, EGL_NONE};
    static const EGLint es_conformant[] = {EGL_CONFORMANT, EGL_OPENGL_ES2_BIT, EGL_NONE};
    EGLConfig config = NULL;
    EGLint n = -1;
    CHECK(eglChooseConfig(dpy, es_conformant, &config, 1, &n) && n == 0, EGL_SAYS);
    CHECK(eglChooseConfig(dpy, es_attrs, &config, 1, &n) && n == 1, EGL_SAYS);
    static const EGLint gl13[] = {EGL_CONTEXT_MAJOR_VERSION, 1, EGL_CONTEXT_MINOR_VERSION, 3, EGL_NONE};
    EGLContext es_chosen = eglCreateContext(dpy, config, EGL_NO_CONTEXT, gl13);
    CHECK(es_chosen != EGL_NO_CONTEXT, EGL_SAYS);
    EGLint api = 0;
    CHECK(eglQueryContext(dpy, es_chosen, EGL_CONTEXT_CLIENT_TYPE, &api) && api == EGL_OPENGL_API, EGL_SAYS);
    CHECK(eglDestroyContext(dpy, es_chosen), EGL_SAYS);
    static const EGLint attrs[] = {
        EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_RED_SIZE, 8, EGL_DEPTH_SIZE, 24,
        EGL_NONE};
    CHECK(eglChooseConfig(dpy, attrs, &config, 1, &n) && n == 1, EGL_SAYS);
    EGLint v = 0;
    /* EGL 1.5's order: no stencil asked, the smallest (none) first. */
    CHECK(eglGetConfigAttrib(dpy, config, EGL_STENCIL_SIZE, &v) && v == 0, EGL_SAYS);
    CHECK(eglGetConfigAttrib(dpy, config, EGL_DEPTH_SIZE, &v) && v == 24, EGL_SAYS);
    CHECK(eglGetConfigAttrib(dpy, config, EGL_SURFACE_TYPE, &v) && !(v & EGL_WINDOW_BIT), EGL_SAYS);

    static const EGLint ctx_attrs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3, EGL_NONE};
    CHECK(eglCreateContext(dpy, config, EGL_NO_CONTEXT, ctx_attrs) == EGL_NO_CONTEXT, EGL_SAYS);
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, NULL);
    CHECK(ctx != EGL_NO_CONTEXT, EGL_SAYS);
    EGLContext ctx2 = eglCreateContext(dpy, config, ctx, NULL);
    CHECK(ctx2 != EGL_NO_CONTEXT, EGL_SAYS);
    static const EGLint pb_attrs[] = {EGL_WIDTH, 64, EGL_HEIGHT, 48, EGL_NONE};
    EGLSurface pb = eglCreatePbufferSurface(dpy, config, pb_attrs);
    CHECK(pb != EGL_NO_SURFACE, EGL_SAYS);
    CHECK(eglQuerySurface(dpy, pb, EGL_WIDTH, &v) && v == 64, EGL_SAYS);
    CHECK(eglQuerySurface(dpy, pb, EGL_HEIGHT, &v) && v == 48, EGL_SAYS);

    CHECK(eglMakeCurrent(dpy, pb, pb, ctx), EGL_SAYS);
    CHECK(eglGetCurrentContext() == ctx && eglGetCurrentSurface(EGL_DRAW) == pb && eglGetCurrentDisplay() == dpy,
          EGL_SAYS);
    const char *renderer = (const char *)glGetString(GL_RENDERER);
    const char *version = (const char *)glGetString(GL_VERSION);
    printf("GL_RENDERER \"%s\", GL_VERSION \"%s\"\n", renderer ? renderer : "(null)", version ? version : "(null)");
    CHECK(renderer && !strncmp(renderer, "tessera (", 9), EGL_SAYS);
    CHECK(version && !strncmp(version, "2.1 ", 4), EGL_SAYS);
    CHECK(!strcmp((const char *)glGetString(GL_VENDOR), "tessera"), EGL_SAYS);
    clear_and_read(1.0f, 0.0f, 0.0f, (const unsigned char[]){255, 0, 0, 255});
    CHECK(eglSwapBuffers(dpy, pb), EGL_SAYS);
    /* A registry function the spec lacks: an entry that warns once (the
     * test's command counts the lines) and writes nothing. */
    void (*get_minmax)(GLenum, GLenum, GLint *) =
        (void (*)(GLenum, GLenum, GLint *))eglGetProcAddress("glGetMinmaxParameteriv");
    CHECK(get_minmax != NULL, EGL_SAYS);
    if (get_minmax) {
        GLint format = -7;
        get_minmax(GL_MINMAX, GL_MINMAX_FORMAT, &format);
        get_minmax(GL_MINMAX, GL_MINMAX_FORMAT, &format);
        CHECK(format == -7, EGL_SAYS);
    }
    CHECK(eglQueryContext(dpy, ctx, EGL_CONTEXT_CLIENT_TYPE, &v) && v == EGL_OPENGL_API, EGL_SAYS);

    /* A second context, surfaceless; then back to the first. */
    CHECK(eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx2), EGL_SAYS);
    CHECK(eglGetCurrentContext() == ctx2 && eglGetCurrentSurface(EGL_DRAW) == EGL_NO_SURFACE, EGL_SAYS);
    CHECK(eglMakeCurrent(dpy, pb, pb, ctx), EGL_SAYS);
    clear_and_read(0.0f, 1.0f, 0.0f, (const unsigned char[]){0, 255, 0, 255});

    CHECK(eglDestroyContext(dpy, ctx2), EGL_SAYS);
    CHECK(eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT), EGL_SAYS);
    CHECK(eglGetCurrentContext() == EGL_NO_CONTEXT, EGL_SAYS);
    CHECK(glGetString(GL_VENDOR) == NULL, EGL_SAYS); /* nothing current: calls do nothing */
    CHECK(eglDestroySurface(dpy, pb), EGL_SAYS);
    CHECK(eglDestroyContext(dpy, ctx), EGL_SAYS);
    CHECK(eglReleaseThread(), EGL_SAYS);
    CHECK(eglTerminate(dpy), EGL_SAYS);

    /* EGL_DEFAULT_DISPLAY with no X server: surfaceless, pbuffer configs. */
    EGLDisplay def = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    CHECK(def != EGL_NO_DISPLAY && eglInitialize(def, NULL, NULL), EGL_SAYS);
    CHECK(eglChooseConfig(def, attrs, &config, 1, &n) && n == 1, EGL_SAYS);
    CHECK(eglTerminate(def), EGL_SAYS);
    printf("%s: %d failures\n", harness_failures ? "FAIL" : "OK", harness_failures);
    return harness_failures ? 1 : 0;
}
