/* tests/faker/glx_share_driver.c — faker_glx_share OUTDIR, under Xvfb, linked
 * against the faker's libGL.so.1, with TESSERA_CHAIN writing
 * OUTDIR/r-%04d.png: a display list and a texture made in one GLX context
 * are used by a second context created with the first as its share list,
 * current on the same window: glIsList/glIsTexture answer true there,
 * frame 0 (glCallList of a green quad over a blue clear) has a green centre
 * and a blue corner, frame 1 (a quad textured with the shared 2x2 red
 * texture, GL_REPLACE) a red centre. */
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "tessera/image.h"

static void quad(void)
{
    glBegin(GL_QUADS);
    glTexCoord2f(0, 0);
    glVertex2f(-0.5f, -0.5f);
    glTexCoord2f(1, 0);
    glVertex2f(0.5f, -0.5f);
    glTexCoord2f(1, 1);
    glVertex2f(0.5f, 0.5f);
    glTexCoord2f(0, 1);
    glVertex2f(-0.5f, 0.5f);
    glEnd();
}

static void pixel_is(const char *dir, int frame, int x, int y, const unsigned char want[3])
{
    char path[4096];
    snprintf(path, sizeof path, "%s/r-%04d.png", dir, frame);
    tsr_image img = {0};
    tsr_error err = {0};
    int rc = tsr_image_read_png(&img, path, &err);
    CHECK(rc == TSR_OK, "%s", err.message);
    if (rc != TSR_OK)
        return;
    const unsigned char *p = img.pixels + (size_t)y * img.stride + 4 * (size_t)x;
    printf("frame %d (%d, %d): RGB %u %u %u\n", frame, x, y, p[0], p[1], p[2]);
    CHECK(!memcmp(p, want, 3), "frame %d at (%d, %d) is RGB %u %u %u, expected %u %u %u", frame, x, y, p[0], p[1], p[2],
          want[0], want[1], want[2]);
    tsr_image_free(&img);
}

int main(int argc, char **argv)
{
    if (argc != 2)
        return 2;
    setvbuf(stdout, NULL, _IOLBF, 0); /* in order with the reports on stderr */
    Display *dpy = XOpenDisplay(NULL);
    REQUIRE(dpy, "no X display");
    static const int attrs[] = {
        GLX_DRAWABLE_TYPE, GLX_WINDOW_BIT, GLX_RENDER_TYPE, GLX_RGBA_BIT, GLX_DOUBLEBUFFER, True, None};
    int n = 0;
    GLXFBConfig *configs = glXChooseFBConfig(dpy, DefaultScreen(dpy), attrs, &n);
    REQUIRE(configs && n > 0, "glXChooseFBConfig gave %d configs", n);
    XVisualInfo *vi = glXGetVisualFromFBConfig(dpy, configs[0]);
    REQUIRE(vi, "no visual for the config");
    XSetWindowAttributes swa = {0};
    swa.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
    Window win = XCreateWindow(dpy, RootWindow(dpy, vi->screen), 0, 0, 64, 64, 0, vi->depth, InputOutput, vi->visual,
                               CWColormap, &swa);
    XMapWindow(dpy, win);

    GLXContext a = glXCreateNewContext(dpy, configs[0], GLX_RGBA_TYPE, NULL, True);
    GLXContext b = glXCreateNewContext(dpy, configs[0], GLX_RGBA_TYPE, a, True);
    REQUIRE(a && b, "contexts not made");

    /* Context a makes the objects and draws nothing. */
    CHECK(glXMakeContextCurrent(dpy, win, win, a));
    GLuint list = glGenLists(1);
    CHECK(list != 0);
    glNewList(list, GL_COMPILE);
    glColor3f(0, 1, 0);
    quad();
    glEndList();
    GLuint tex = 0;
    glGenTextures(1, &tex);
    CHECK(tex != 0);
    glBindTexture(GL_TEXTURE_2D, tex);
    static const unsigned char red[2 * 2 * 4] = {255, 0, 0, 255, 255, 0, 0, 255, 255, 0, 0, 255, 255, 0, 0, 255};
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 2, 2, 0, GL_RGBA, GL_UNSIGNED_BYTE, red);
    glFinish();

    /* Context b uses them. */
    CHECK(glXMakeContextCurrent(dpy, win, win, b));
    CHECK(glIsList(list) == GL_TRUE, "list %u is not a list in the sharing context", list);
    CHECK(glIsTexture(tex) == GL_TRUE, "texture %u is not a texture in the sharing context", tex);
    glViewport(0, 0, 64, 64);
    glClearColor(0, 0, 1, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glCallList(list);
    glXSwapBuffers(dpy, win); /* frame 0 */
    glClear(GL_COLOR_BUFFER_BIT);
    glEnable(GL_TEXTURE_2D);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    quad();
    glXSwapBuffers(dpy, win); /* frame 1 */
    GLenum gl_error = glGetError();
    CHECK(gl_error == GL_NO_ERROR, "GL error 0x%x", gl_error);

    CHECK(glXMakeCurrent(dpy, None, NULL));
    glXDestroyContext(dpy, b);
    glXDestroyContext(dpy, a);

    static const unsigned char green[3] = {0, 255, 0}, blue[3] = {0, 0, 255}, red3[3] = {255, 0, 0};
    pixel_is(argv[1], 0, 32, 32, green);
    pixel_is(argv[1], 0, 2, 2, blue);
    pixel_is(argv[1], 1, 32, 32, red3);
    XFree(vi);
    XFree(configs);
    XDestroyWindow(dpy, win);
    XFreeColormap(dpy, swa.colormap);
    XCloseDisplay(dpy);
    printf("%s: %d failures\n", harness_failures ? "FAIL" : "OK", harness_failures);
    return harness_failures ? 1 : 0;
}
