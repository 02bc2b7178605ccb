/* tests/faker/glx_resize_driver.c — faker_glx_resize OUTDIR, under Xvfb, linked
 * against the faker's libGL.so.1, with TESSERA_CHAIN writing
 * OUTDIR/r-%04d.png: FBConfigs of the server's TrueColor visuals, a 2.1
 * context from glXCreateContextAttribsARB (3.3 refused) sharing with a
 * glXCreateNewContext one, glXMakeContextCurrent and the GetCurrent*
 * answers, glXQueryDrawable sizes, swaps writing frames; then the window is
 * resized: after the program's own ConfigureNotify and its glViewport the
 * next frame has the new size, and the application's event mask on its
 * window is still exactly what it selected. Then EGL on X11 draws frame 2
 * into the same window: eglGetPlatformDisplay(EGL_PLATFORM_X11_KHR), a
 * config whose EGL_NATIVE_VISUAL_ID is a server visual,
 * eglCreatePlatformWindowSurface, eglSwapBuffers — the way Debian's
 * xscreensaver-gl hacks do it: the config chosen with EGL_OPENGL_ES_BIT,
 * EGL_OPENGL_API bound, an OpenGL 1.3 context, and glDrawBuffer(GL_BACK)
 * with no GL error. */
#define GLX_GLXEXT_PROTOTYPES 1
#define EGL_EGLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glx.h>
#include <GL/glxext.h>
#include <X11/Xlib.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "tessera/image.h"

static void frame_size(const char *dir, int frame, int w, int h)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/r-%04d.png", dir, frame);
    tsr_image img = {0};
    tsr_error err = {0};
    int rc = tsr_image_read_png(&img, path, &err);
    CHECK(rc == TSR_OK, "%s", err.message);
    if (rc != TSR_OK)
        return;
    printf("frame %d: %dx%d (expected %dx%d)\n", frame, img.width, img.height, w, h);
    CHECK(img.width == w && img.height == h, "frame %d is %dx%d, expected %dx%d", frame, img.width, img.height, w, h);
    /* Cleared to the frame's colour: red, then green. */
    const unsigned char *p = img.pixels + 4 * ((size_t)img.width * (size_t)(img.height / 2) + (size_t)img.width / 2);
    static const unsigned char want[3][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}};
    CHECK(!memcmp(p, want[frame], 3), "frame %d's centre is RGB %u %u %u, expected %u %u %u", frame, p[0], p[1], p[2],
          want[frame][0], want[frame][1], want[frame][2]);
    tsr_image_free(&img);
}

int main(int argc, char **argv)
{
    if (argc != 2)
        return 2;
    setvbuf(stdout, NULL, _IOLBF, 0); /* in order with the reports on stderr */
    Display *dpy = XOpenDisplay(NULL);
    REQUIRE(dpy, "no X display");
    int maj = 0, min = 0;
    CHECK(glXQueryVersion(dpy, &maj, &min) && maj == 1 && min == 4);
    CHECK(strstr(glXQueryExtensionsString(dpy, DefaultScreen(dpy)), "GLX_ARB_create_context") != NULL);
    static const int attrs[] = {GLX_DRAWABLE_TYPE,
                                GLX_WINDOW_BIT,
                                GLX_RENDER_TYPE,
                                GLX_RGBA_BIT,
                                GLX_DOUBLEBUFFER,
                                True,
                                GLX_DEPTH_SIZE,
                                24,
                                GLX_STENCIL_SIZE,
                                8,
                                None};
    int n = 0;
    GLXFBConfig *configs = glXChooseFBConfig(dpy, DefaultScreen(dpy), attrs, &n);
    REQUIRE(configs && n > 0, "glXChooseFBConfig gave %d configs", n);
    int v = 0;
    CHECK(glXGetFBConfigAttrib(dpy, configs[0], GLX_DOUBLEBUFFER, &v) == Success && v == True);
    XVisualInfo *vi = glXGetVisualFromFBConfig(dpy, configs[0]);
    CHECK(vi && vi->class == TrueColor);
    XSetWindowAttributes swa = {0};
    swa.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
    swa.event_mask = StructureNotifyMask | ExposureMask;
    Window win = XCreateWindow(dpy, RootWindow(dpy, vi->screen), 0, 0, 200, 100, 0, vi->depth, InputOutput, vi->visual,
                               CWColormap | CWEventMask, &swa);
    XMapWindow(dpy, win);

    static const int gl33[] = {GLX_CONTEXT_MAJOR_VERSION_ARB, 3, GLX_CONTEXT_MINOR_VERSION_ARB, 3, None};
    static const int gl21[] = {GLX_CONTEXT_MAJOR_VERSION_ARB, 2, GLX_CONTEXT_MINOR_VERSION_ARB, 1, None};
    CHECK(glXCreateContextAttribsARB(dpy, configs[0], NULL, True, gl33) == NULL);
    GLXContext first = glXCreateNewContext(dpy, configs[0], GLX_RGBA_TYPE, NULL, True);
    GLXContext ctx = glXCreateContextAttribsARB(dpy, configs[0], first, True, gl21);
    CHECK(first && ctx && glXIsDirect(dpy, ctx));
    CHECK(glXMakeContextCurrent(dpy, win, win, ctx));
    CHECK(glXGetCurrentContext() == ctx && glXGetCurrentDrawable() == win && glXGetCurrentReadDrawable() == win &&
          glXGetCurrentDisplay() == dpy);
    unsigned w = 0, h = 0;
    glXQueryDrawable(dpy, win, GLX_WIDTH, &w);
    glXQueryDrawable(dpy, win, GLX_HEIGHT, &h);
    CHECK(w == 200 && h == 100);
    CHECK(!strncmp((const char *)glGetString(GL_RENDERER), "tessera (", 9));
    glXSwapIntervalEXT(dpy, win, 1); /* accepted, no effect */

    glViewport(0, 0, 200, 100);
    glClearColor(1, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glXSwapBuffers(dpy, win); /* frame 0: 200x100 */

    XResizeWindow(dpy, win, 160, 120);
    XEvent ev;
    do
        XNextEvent(dpy, &ev);
    while (!(ev.type == ConfigureNotify && ev.xconfigure.width == 160 && ev.xconfigure.height == 120));
    glViewport(0, 0, 160, 120); /* the program's reshape */
    glClearColor(0, 1, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glXSwapBuffers(dpy, win); /* frame 1: 160x120 */
    glXQueryDrawable(dpy, win, GLX_WIDTH, &w);
    glXQueryDrawable(dpy, win, GLX_HEIGHT, &h);
    CHECK(w == 160 && h == 120);

    XWindowAttributes wa;
    CHECK(XGetWindowAttributes(dpy, win, &wa) && wa.your_event_mask == (StructureNotifyMask | ExposureMask));

    CHECK(glXMakeCurrent(dpy, None, NULL));
    CHECK(glXGetCurrentContext() == NULL);
    glXDestroyContext(dpy, ctx);
    glXDestroyContext(dpy, first);

    EGLDisplay edpy = eglGetPlatformDisplay(EGL_PLATFORM_X11_KHR, dpy, NULL);
    CHECK(edpy != EGL_NO_DISPLAY && eglInitialize(edpy, NULL, NULL) && eglBindAPI(EGL_OPENGL_API));
    static const EGLint eattrs[] = {EGL_SURFACE_TYPE, EGL_WINDOW_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig ec = NULL;
    EGLint en = 0, vid = 0;
    CHECK(eglChooseConfig(edpy, eattrs, &ec, 1, &en) && en == 1);
    CHECK(eglGetConfigAttrib(edpy, ec, EGL_NATIVE_VISUAL_ID, &vid) && vid != 0);
    XVisualInfo vtmpl = {.visualid = (VisualID)vid};
    int vn = 0;
    XVisualInfo *evi = XGetVisualInfo(dpy, VisualIDMask, &vtmpl, &vn);
    CHECK(evi && vn == 1 && evi->class == TrueColor);
    if (evi)
        XFree(evi);
    const EGLint es_attrs[] = {EGL_SURFACE_TYPE,
                               EGL_WINDOW_BIT,
                               EGL_COLOR_BUFFER_TYPE,
                               EGL_RGB_BUFFER,
                               EGL_RED_SIZE,
                               8,
                               EGL_DEPTH_SIZE,
                               8,
                               EGL_STENCIL_SIZE,
                               1,
                               EGL_RENDERABLE_TYPE,
                               EGL_OPENGL_ES_BIT,
                               EGL_NATIVE_VISUAL_ID,
                               vid,
                               EGL_NONE};
    EGLConfig es_config = NULL;
    CHECK(eglChooseConfig(edpy, es_attrs, &es_config, 1, &en) && en == 1);
    /* The one depth-stencil format with stencil: 24 and 8 (faker/configs.c). */
    EGLint es_depth = 0, es_stencil = 0;
    CHECK(eglGetConfigAttrib(edpy, es_config, EGL_DEPTH_SIZE, &es_depth) && es_depth == 24);
    CHECK(eglGetConfigAttrib(edpy, es_config, EGL_STENCIL_SIZE, &es_stencil) && es_stencil == 8);
    static const EGLint gl13[] = {EGL_CONTEXT_MAJOR_VERSION, 1, EGL_CONTEXT_MINOR_VERSION, 3, EGL_NONE};
    EGLContext ectx = eglCreateContext(edpy, ec, EGL_NO_CONTEXT, gl13);
    EGLSurface esurf = eglCreatePlatformWindowSurface(edpy, ec, &win, NULL);
    CHECK(ectx != EGL_NO_CONTEXT && esurf != EGL_NO_SURFACE);
    CHECK(eglMakeCurrent(edpy, esurf, esurf, ectx));
    EGLint ew = 0;
    CHECK(eglQuerySurface(edpy, esurf, EGL_WIDTH, &ew) && ew == 160);
    while (glGetError() != GL_NO_ERROR) {
    }
    glDrawBuffer(GL_BACK); /* a single-buffered renderer's GL_INVALID_OPERATION, unless the faker maps it */
    GLenum gl_error = glGetError();
    CHECK(gl_error == GL_NO_ERROR, "glDrawBuffer(GL_BACK): GL error 0x%x", gl_error);
    glClearColor(0, 0, 1, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    CHECK(eglSwapBuffers(edpy, esurf)); /* frame 2: 160x120 */
    CHECK(eglMakeCurrent(edpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT));
    CHECK(eglDestroySurface(edpy, esurf) && eglDestroyContext(edpy, ectx) && eglTerminate(edpy));

    frame_size(argv[1], 0, 200, 100);
    frame_size(argv[1], 1, 160, 120);
    frame_size(argv[1], 2, 160, 120);
    XFree(vi);
    XFree(configs);
    XDestroyWindow(dpy, win);
    XFreeColormap(dpy, swa.colormap);
    XCloseDisplay(dpy);
    printf("%s: %d failures\n", harness_failures ? "FAIL" : "OK", harness_failures);
    return harness_failures ? 1 : 0;
}
