/* tests/faker/egl_surfaceless.c — EGL with no X server at all, linked
 * against the faker's libEGL.so.1 and libGL.so.1 (DISPLAY is unset by the
 * test): the surfaceless platform and EGL_DEFAULT_DISPLAY initialise,
 * OpenGL ES is refused (eglBindAPI: EGL_BAD_PARAMETER; ES configs: none),
 * an OpenGL context draws into a pbuffer and surfaceless, glGetString
 * names tessera and 2.1, glReadPixels reads back what glClear drew
 * through the chain's render SPU, and glRenderMode (not in the spec) is an
 * entry that returns 0 and warns once for two calls. */
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <stdio.h>
#include <string.h>

static int failures;
#define CHECK(cond)                                                                                \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            printf("FAIL line %d: %s (eglGetError 0x%x)\n", __LINE__, #cond, (unsigned)eglGetError()); \
            failures++;                                                                            \
        }                                                                                          \
    } while (0)

static void clear_and_read(GLfloat r, GLfloat g, GLfloat b, const unsigned char want[4])
{
    glClearColor(r, g, b, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    unsigned char px[4] = {0, 0, 0, 0};
    glReadPixels(3, 2, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, px);
    if (memcmp(px, want, 4) != 0) {
        printf("FAIL: read back %u %u %u %u, expected %u %u %u %u\n", px[0], px[1], px[2], px[3], want[0],
               want[1], want[2], want[3]);
        failures++;
    }
}

int main(void)
{
    EGLDisplay dpy = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    CHECK(dpy != EGL_NO_DISPLAY);
    EGLint major = 0, minor = 0;
    CHECK(eglInitialize(dpy, &major, &minor) && major == 1 && minor == 5);
    CHECK(strstr(eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS), "EGL_MESA_platform_surfaceless") != NULL);
    CHECK(!strcmp(eglQueryString(dpy, EGL_CLIENT_APIS), "OpenGL"));

    CHECK(!eglBindAPI(EGL_OPENGL_ES_API) && eglGetError() == EGL_BAD_PARAMETER);
    CHECK(eglBindAPI(EGL_OPENGL_API) && eglQueryAPI() == EGL_OPENGL_API);

    static const EGLint es_attrs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_ES2_BIT, EGL_NONE};
    EGLConfig config = NULL;
    EGLint n = -1;
    CHECK(eglChooseConfig(dpy, es_attrs, &config, 1, &n) && n == 0);
    static const EGLint attrs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                   EGL_RED_SIZE,     8,               EGL_DEPTH_SIZE,      24,
                                   EGL_NONE};
    CHECK(eglChooseConfig(dpy, attrs, &config, 1, &n) && n == 1);
    EGLint v = 0;
    CHECK(eglGetConfigAttrib(dpy, config, EGL_STENCIL_SIZE, &v) && v == 8);
    CHECK(eglGetConfigAttrib(dpy, config, EGL_SURFACE_TYPE, &v) && !(v & EGL_WINDOW_BIT));

    static const EGLint ctx_attrs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3, EGL_NONE};
    CHECK(eglCreateContext(dpy, config, EGL_NO_CONTEXT, ctx_attrs) == EGL_NO_CONTEXT);
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, NULL);
    CHECK(ctx != EGL_NO_CONTEXT);
    EGLContext ctx2 = eglCreateContext(dpy, config, ctx, NULL);
    CHECK(ctx2 != EGL_NO_CONTEXT);
    static const EGLint pb_attrs[] = {EGL_WIDTH, 64, EGL_HEIGHT, 48, EGL_NONE};
    EGLSurface pb = eglCreatePbufferSurface(dpy, config, pb_attrs);
    CHECK(pb != EGL_NO_SURFACE);
    CHECK(eglQuerySurface(dpy, pb, EGL_WIDTH, &v) && v == 64);
    CHECK(eglQuerySurface(dpy, pb, EGL_HEIGHT, &v) && v == 48);

    CHECK(eglMakeCurrent(dpy, pb, pb, ctx));
    CHECK(eglGetCurrentContext() == ctx && eglGetCurrentSurface(EGL_DRAW) == pb && eglGetCurrentDisplay() == dpy);
    const char *renderer = (const char *)glGetString(GL_RENDERER);
    const char *version = (const char *)glGetString(GL_VERSION);
    printf("GL_RENDERER \"%s\", GL_VERSION \"%s\"\n", renderer ? renderer : "(null)", version ? version : "(null)");
    CHECK(renderer && !strncmp(renderer, "tessera (", 9));
    CHECK(version && !strncmp(version, "2.1 ", 4));
    CHECK(!strcmp((const char *)glGetString(GL_VENDOR), "tessera"));
    clear_and_read(1.0f, 0.0f, 0.0f, (const unsigned char[]){255, 0, 0, 255});
    CHECK(eglSwapBuffers(dpy, pb));
    /* A registry function the spec lacks: an entry that warns once (the
     * test's command counts the lines) and returns 0. */
    GLint (*render_mode)(GLenum) = (GLint (*)(GLenum))eglGetProcAddress("glRenderMode");
    CHECK(render_mode != NULL);
    if (render_mode) {
        CHECK(render_mode(GL_SELECT) == 0);
        CHECK(render_mode(GL_RENDER) == 0);
    }
    CHECK(eglQueryContext(dpy, ctx, EGL_CONTEXT_CLIENT_TYPE, &v) && v == EGL_OPENGL_API);

    /* A second context, surfaceless; then back to the first. */
    CHECK(eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx2));
    CHECK(eglGetCurrentContext() == ctx2 && eglGetCurrentSurface(EGL_DRAW) == EGL_NO_SURFACE);
    CHECK(eglMakeCurrent(dpy, pb, pb, ctx));
    clear_and_read(0.0f, 1.0f, 0.0f, (const unsigned char[]){0, 255, 0, 255});

    CHECK(eglDestroyContext(dpy, ctx2));
    CHECK(eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT));
    CHECK(eglGetCurrentContext() == EGL_NO_CONTEXT);
    CHECK(glGetString(GL_VENDOR) == NULL); /* nothing current: calls do nothing */
    CHECK(eglDestroySurface(dpy, pb));
    CHECK(eglDestroyContext(dpy, ctx));
    CHECK(eglReleaseThread());
    CHECK(eglTerminate(dpy));

    /* EGL_DEFAULT_DISPLAY with no X server: surfaceless, pbuffer configs. */
    EGLDisplay def = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    CHECK(def != EGL_NO_DISPLAY && eglInitialize(def, NULL, NULL));
    CHECK(eglChooseConfig(def, attrs, &config, 1, &n) && n == 1);
    CHECK(eglTerminate(def));
    printf("%s: %d failures\n", failures ? "FAIL" : "OK", failures);
    return failures ? 1 : 0;
}
