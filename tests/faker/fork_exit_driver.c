/* tests/faker/fork_exit_driver.c — a program under the faker forks a child that
 * calls exit() (as xscreensaver's hacks do when their child cannot exec
 * xscreensaver-getimage), then goes on drawing: the child must leave the
 * parent's chain alone. Surfaceless EGL into a 32x24 pbuffer, 2 frames
 * before the fork and 4 after; the test (tests/faker.cmake) runs it with
 * a capture SPU and checks the capture holds all 6 glClear (a pbuffer
 * swap is no frame). Before the fix
 * the child's exit ended the chain: it finished the parent's capture file
 * after 2 frames (the parent's later records then contradict its header)
 * and, through pack, sent on the parent's connection. */
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include "harness.h"

#define EGL_SAYS "eglGetError 0x%x", (unsigned)eglGetError()

static void frames(EGLDisplay dpy, EGLSurface pb, int n, float r)
{
    for (int i = 0; i < n; i++) {
        glClearColor(r, (float)i / (float)n, 0.5f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        CHECK(eglSwapBuffers(dpy, pb), EGL_SAYS);
    }
}

int main(void)
{
    EGLDisplay dpy = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    CHECK(dpy != EGL_NO_DISPLAY && eglInitialize(dpy, NULL, NULL) && eglBindAPI(EGL_OPENGL_API), EGL_SAYS);
    static const EGLint attrs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = NULL;
    EGLint n = 0;
    CHECK(eglChooseConfig(dpy, attrs, &config, 1, &n) && n == 1, EGL_SAYS);
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, NULL);
    static const EGLint pb_attrs[] = {EGL_WIDTH, 32, EGL_HEIGHT, 24, EGL_NONE};
    EGLSurface pb = eglCreatePbufferSurface(dpy, config, pb_attrs);
    CHECK(ctx != EGL_NO_CONTEXT && pb != EGL_NO_SURFACE && eglMakeCurrent(dpy, pb, pb, ctx), EGL_SAYS);
    frames(dpy, pb, 2, 0.2f);
    pid_t child = fork();
    CHECK(child >= 0, "fork failed");
    if (child == 0)
        exit(1); /* atexit handlers run here, in the child */
    int status = 0;
    /* How the child ends is not checked: OSMesa's own exit handler joins
     * its rasteriser threads, which a forked child does not have, and may
     * crash there (Mesa's, whatever the faker does). */
    CHECK(waitpid(child, &status, 0) == child, "waitpid failed");
    frames(dpy, pb, 4, 0.8f);
    CHECK(eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT), EGL_SAYS);
    CHECK(eglDestroySurface(dpy, pb) && eglDestroyContext(dpy, ctx), EGL_SAYS);
    return harness_failures ? 1 : 0;
}
