/* tests/faker/glx_offscreen_driver.c — faker_glx_offscreen MODE OUTDIR, under
 * Xvfb, linked against the faker's libGL.so.1, with TESSERA_CHAIN writing
 * OUTDIR/r-%04d.png. MODE is the drawable the program draws into, the
 * first (and only) one of its stream:
 *   pbuffer    glXCreatePbuffer 40x32 of a GLX_PBUFFER_BIT config;
 *   pixmap     glXCreatePixmap of a 24x20 X pixmap of the config's depth;
 *   glxpixmap  glXCreateGLXPixmap of a 32x16 X pixmap and a visual.
 * glXQueryDrawable gives its size (and config, preserved contents, largest
 * pbuffer); made current, the viewport is its size; a blue clear and a
 * green quad over the middle half read back with glReadPixels as exactly
 * w/2 x h/2 green pixels, the rest blue; glXGetCurrentDrawable is it;
 * glXSwapBuffers of it writes no frame (GLX: no effect on pbuffers and
 * pixmaps); it is destroyed. Then what is refused, with one log line
 * each: a pbuffer over 8192 wide (and GLX_LARGEST_PBUFFER gives 8192), a
 * pixmap of another depth than the config's, a pixmap that does not
 * exist, and destroying a pbuffer as a pixmap. */
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"

static void query_is(Display *dpy, GLXDrawable d, int attribute, const char *name, unsigned want)
{
    unsigned v = 12345;
    glXQueryDrawable(dpy, d, attribute, &v);
    printf("glXQueryDrawable %s: %u\n", name, v);
    CHECK(v == want, "%s is %u, expected %u", name, v, want);
}

/* Draws and reads back a w x h drawable that is current. */
static void draw_and_check(int w, int h)
{
    GLint vp[4] = {0};
    glGetIntegerv(GL_VIEWPORT, vp);
    printf("viewport: %d %d %d %d\n", vp[0], vp[1], vp[2], vp[3]);
    CHECK(vp[0] == 0 && vp[1] == 0 && vp[2] == w && vp[3] == h, "the viewport is not the drawable's %dx%d", w, h);
    glClearColor(0, 0, 1, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glColor3f(0, 1, 0);
    glBegin(GL_QUADS);
    glVertex2f(-0.5f, -0.5f);
    glVertex2f(0.5f, -0.5f);
    glVertex2f(0.5f, 0.5f);
    glVertex2f(-0.5f, 0.5f);
    glEnd();
    unsigned char *px = calloc((size_t)w * (size_t)h, 4);
    REQUIRE(px);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, px);
    long green = 0, blue = 0, other = 0;
    for (int i = 0; i < w * h; i++) {
        const unsigned char *p = px + 4 * i;
        if (p[0] == 0 && p[1] == 255 && p[2] == 0)
            green++;
        else if (p[0] == 0 && p[1] == 0 && p[2] == 255)
            blue++;
        else
            other++;
    }
    free(px);
    long want = (long)(w / 2) * (h / 2);
    printf("read back %dx%d: %ld green, %ld blue, %ld other\n", w, h, green, blue, other);
    CHECK(green == want && blue == (long)w * h - want && other == 0, "expected %ld green and %ld blue pixels", want,
          (long)w * h - want);
}

int main(int argc, char **argv)
{
    setvbuf(stdout, NULL, _IOLBF, 0); /* in order with the reports on stderr */
    if (argc != 3 || (strcmp(argv[1], "pbuffer") && strcmp(argv[1], "pixmap") && strcmp(argv[1], "glxpixmap"))) {
        fprintf(stderr, "usage: faker_glx_offscreen pbuffer|pixmap|glxpixmap OUTDIR\n");
        return 2;
    }
    const char *mode = argv[1], *dir = argv[2];
    Display *dpy = XOpenDisplay(NULL);
    REQUIRE(dpy, "no X display");
    int screen = DefaultScreen(dpy);
    bool pbuffer = !strcmp(mode, "pbuffer");
    const int attrs[] = {GLX_DRAWABLE_TYPE,
                         pbuffer ? GLX_PBUFFER_BIT : GLX_PIXMAP_BIT,
                         GLX_RENDER_TYPE,
                         GLX_RGBA_BIT,
                         GLX_DEPTH_SIZE,
                         24,
                         None};
    int n = 0;
    GLXFBConfig *configs = glXChooseFBConfig(dpy, screen, attrs, &n);
    REQUIRE(configs && n > 0, "glXChooseFBConfig (%s) gave %d configs", mode, n);
    GLXFBConfig config = configs[0];
    int config_id = 0, depth = 0, max_w = 0;
    glXGetFBConfigAttrib(dpy, config, GLX_FBCONFIG_ID, &config_id);
    glXGetFBConfigAttrib(dpy, config, GLX_BUFFER_SIZE, &depth);
    glXGetFBConfigAttrib(dpy, config, GLX_MAX_PBUFFER_WIDTH, &max_w);
    printf("%s: config %d of depth %d (largest pbuffer width %d)\n", mode, config_id, depth, max_w);

    int w, h;
    GLXDrawable d;
    Pixmap xpix = None;
    if (pbuffer) {
        w = 40, h = 32;
        const int pb_attrs[] = {GLX_PBUFFER_WIDTH, w, GLX_PBUFFER_HEIGHT, h, None};
        d = glXCreatePbuffer(dpy, config, pb_attrs);
    } else {
        bool glx13 = !strcmp(mode, "pixmap");
        w = glx13 ? 24 : 32, h = glx13 ? 20 : 16;
        xpix = XCreatePixmap(dpy, RootWindow(dpy, screen), (unsigned)w, (unsigned)h, (unsigned)depth);
        if (glx13) {
            d = glXCreatePixmap(dpy, config, xpix, NULL);
        } else {
            XVisualInfo *vi = glXGetVisualFromFBConfig(dpy, config);
            REQUIRE(vi, "no visual for the config");
            d = glXCreateGLXPixmap(dpy, vi, xpix);
            XFree(vi);
        }
    }
    REQUIRE(d != None, "the %s was not made", mode);
    CHECK(d != xpix, "the GLX drawable has the X pixmap's id");
    query_is(dpy, d, GLX_WIDTH, "GLX_WIDTH", (unsigned)w);
    query_is(dpy, d, GLX_HEIGHT, "GLX_HEIGHT", (unsigned)h);
    if (strcmp(mode, "glxpixmap")) /* a visual's config is the one glXGetConfig describes */
        query_is(dpy, d, GLX_FBCONFIG_ID, "GLX_FBCONFIG_ID", (unsigned)config_id);
    query_is(dpy, d, GLX_PRESERVED_CONTENTS, "GLX_PRESERVED_CONTENTS", pbuffer ? 1u : 0u);
    query_is(dpy, d, GLX_LARGEST_PBUFFER, "GLX_LARGEST_PBUFFER", 0u);

    GLXContext ctx = glXCreateNewContext(dpy, config, GLX_RGBA_TYPE, NULL, True);
    REQUIRE(ctx, "no context");
    REQUIRE(glXMakeContextCurrent(dpy, d, d, ctx), "glXMakeContextCurrent on the %s failed", mode);
    CHECK(glXGetCurrentDrawable() == d, "glXGetCurrentDrawable is not the %s", mode);
    draw_and_check(w, h);
    glXSwapBuffers(dpy, d);
    glFinish();
    char frame[4096];
    snprintf(frame, sizeof frame, "%s/r-0000.png", dir);
    CHECK(access(frame, F_OK) != 0, "glXSwapBuffers of a %s wrote a frame (%s)", mode, frame);
    CHECK(glXMakeContextCurrent(dpy, None, None, NULL));
    if (pbuffer)
        glXDestroyPbuffer(dpy, d);
    else if (!strcmp(mode, "pixmap"))
        glXDestroyPixmap(dpy, d);
    else
        glXDestroyGLXPixmap(dpy, d);

    /* Refusals (each logs one line): None, nothing made. */
    const int huge[] = {GLX_PBUFFER_WIDTH, 9000, GLX_PBUFFER_HEIGHT, 8, None};
    CHECK(glXCreatePbuffer(dpy, config, huge) == None, "a 9000-wide pbuffer was made");
    const int largest[] = {GLX_PBUFFER_WIDTH, 9000, GLX_PBUFFER_HEIGHT, 8, GLX_LARGEST_PBUFFER, True, None};
    GLXPbuffer big = glXCreatePbuffer(dpy, config, largest);
    CHECK(big != None, "GLX_LARGEST_PBUFFER: none made");
    query_is(dpy, big, GLX_WIDTH, "GLX_WIDTH of the largest", 8192u);
    query_is(dpy, big, GLX_LARGEST_PBUFFER, "GLX_LARGEST_PBUFFER of the largest", 1u);
    Pixmap one = XCreatePixmap(dpy, RootWindow(dpy, screen), 8, 8, 1);
    CHECK(glXCreatePixmap(dpy, config, one, NULL) == None, "a pixmap of depth 1 was taken for a depth-%d config",
          depth);
    CHECK(glXCreatePixmap(dpy, config, (Pixmap)0x7ffffff0, NULL) == None, "a pixmap that does not exist was taken");
    glXDestroyPixmap(dpy, big); /* not a pixmap: logged, nothing destroyed */
    query_is(dpy, big, GLX_WIDTH, "GLX_WIDTH after glXDestroyPixmap of a pbuffer", 8192u);
    glXDestroyPbuffer(dpy, big);
    XFreePixmap(dpy, one);
    if (xpix)
        XFreePixmap(dpy, xpix);
    glXDestroyContext(dpy, ctx);
    XFree(configs);
    XCloseDisplay(dpy);
    printf("%s: %s: %d failures\n", mode, harness_failures ? "FAIL" : "OK", harness_failures);
    return harness_failures ? 1 : 0;
}
