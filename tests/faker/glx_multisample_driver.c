/* tests/faker/glx_multisample_driver.c — faker_glx_multisample OUT.txt,
 * under Xvfb: a window of a multisample GLX config (glXChooseFBConfig with
 * GLX_SAMPLE_BUFFERS 1 and GLX_SAMPLES 2, as piglit's samples=2 tests ask;
 * double-buffered, depth and stencil) drawn with GL_MULTISAMPLE: rotated
 * triangles through the depth and stencil tests, then every way a program
 * reads the window. Each answer is one labelled line in OUT.txt: the
 * config's sample sizes and what GL_SAMPLE_BUFFERS and GL_SAMPLES answer;
 * the window read with glReadPixels (colour, depth, stencil: an FNV-1a
 * hash of the bytes and how many colour pixels are neither background nor
 * a triangle's colour, the edges the samples blend), the window copied
 * whole with glCopyTexImage2D (resolved, as Mesa resolves it there),
 * glCopyPixels into the window then read, glCopyTexImage2D and
 * glCopyTexSubImage2D of parts read back with glGetTexImage, what the X
 * window shows after the swap (XGetImage: Mesa's resolved picture) and the
 * back read after it. The first colour read and the whole-window copy are
 * also written to OUT.txt.rgba and OUT.txt.resolved.rgba, and what the X
 * window shows to OUT.txt.displayed.rgba, so a difference can be counted
 * by pixel (and the frame tessera writes compared with what Mesa shows).
 * Linked against the faker's libGL (faker_glx_multisample) it runs through
 * tessera; against Mesa's (faker_glx_multisample_native) it gives the
 * answers to match (glx_multisample.sh). */
#include <GL/gl.h>
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"

#define W 64
#define H 48

static FILE *out;

static uint32_t fnv1a(const unsigned char *p, size_t n)
{
    uint32_t h = 2166136261u;
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * 16777619u;
    return h;
}

/* Pixels that are neither the clear colour nor a triangle's pure colour:
 * edge pixels the samples blend (0 when nothing is multisampled). */
static int blended(const unsigned char *rgba, size_t n)
{
    int count = 0;
    for (size_t i = 0; i < n; i++) {
        const unsigned char *p = rgba + 4 * i;
        bool pure = (p[0] == 0 || p[0] == 255) && (p[1] == 0 || p[1] == 255) && (p[2] == 0 || p[2] == 255);
        count += !pure;
    }
    return count;
}

static void write_rgba(const char *path, const unsigned char *rgba, size_t size)
{
    FILE *f = fopen(path, "wb");
    REQUIRE(f && fwrite(rgba, size, 1, f) == 1, "cannot write %s", path);
    fclose(f);
}

/* The window read with glReadPixels: colour on a line of its own (Mesa
 * reads one sample of a multisample window there: glx_multisample.sh),
 * depth and stencil on another. */
static void read_window(const char *label, const char *rgba_path)
{
    static unsigned char rgba[W * H * 4];
    static GLuint depth[W * H];
    static unsigned char stencil[W * H];
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    glReadPixels(0, 0, W, H, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, depth);
    glReadPixels(0, 0, W, H, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, stencil);
    fprintf(out, "%s colour: %08x blended %d\n", label, fnv1a(rgba, sizeof rgba), blended(rgba, W * H));
    fprintf(out, "%s: depth %08x stencil %08x error 0x%x\n", label, fnv1a((const unsigned char *)depth, sizeof depth),
            fnv1a(stencil, sizeof stencil), glGetError());
    if (rgba_path)
        write_rgba(rgba_path, rgba, sizeof rgba);
}

/* The window resolved as Mesa resolves it for glCopyTexImage2D: copied
 * whole into a texture and read back from there. */
static void resolved_window(const char *label, const char *rgba_path)
{
    static unsigned char rgba[W * H * 4];
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glCopyTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 0, 0, W, H, 0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    glDeleteTextures(1, &t);
    fprintf(out, "%s: %08x blended %d error 0x%x\n", label, fnv1a(rgba, sizeof rgba), blended(rgba, W * H),
            glGetError());
    if (rgba_path)
        write_rgba(rgba_path, rgba, sizeof rgba);
}

/* What the X window shows after a swap (Mesa's GLX puts its resolved back
 * buffer there; the faker draws nothing on the X server). */
static void displayed(Display *dpy, Window win, const char *rgba_path)
{
    static unsigned char rgba[W * H * 4];
    XImage *image = XGetImage(dpy, win, 0, 0, W, H, AllPlanes, ZPixmap);
    REQUIRE(image, "XGetImage failed");
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            unsigned long p = XGetPixel(image, x, H - 1 - y);
            unsigned char *o = rgba + 4 * (y * W + x);
            o[0] = (unsigned char)(p >> 16), o[1] = (unsigned char)(p >> 8), o[2] = (unsigned char)p, o[3] = 255;
        }
    XDestroyImage(image);
    fprintf(out, "displayed: %08x blended %d\n", fnv1a(rgba, sizeof rgba), blended(rgba, W * H));
    write_rgba(rgba_path, rgba, sizeof rgba);
}

/* A triangle about the centre, turned by `degrees`, at depth z. */
static void triangle(float degrees, float z, float r, float g, float b)
{
    glPushMatrix();
    glTranslatef(W / 2.0f, H / 2.0f, 0);
    glRotatef(degrees, 0, 0, 1);
    glColor3f(r, g, b);
    glBegin(GL_TRIANGLES);
    glVertex3f(-25, -17, z);
    glVertex3f(23, -9, z);
    glVertex3f(-3, 21, z);
    glEnd();
    glPopMatrix();
}

static void scene(void)
{
    glClearColor(0, 0, 0, 1);
    glClearDepth(1);
    glClearStencil(0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    glEnable(GL_MULTISAMPLE);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_ALWAYS, 1, 0xff);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    triangle(17, -0.5f, 1, 0, 0);
    glStencilFunc(GL_ALWAYS, 2, 0xff);
    triangle(-41, 0.25f, 0, 1, 1); /* behind the first where they overlap */
    glDisable(GL_STENCIL_TEST);
    glDisable(GL_DEPTH_TEST);
}

int main(int argc, char **argv)
{
    REQUIRE(argc == 2, "usage: faker_glx_multisample OUT.txt");
    out = fopen(argv[1], "w");
    REQUIRE(out, "cannot write %s", argv[1]);
    char rgba_path[4096];
    snprintf(rgba_path, sizeof rgba_path, "%s.rgba", argv[1]);
    Display *dpy = XOpenDisplay(NULL);
    REQUIRE(dpy, "no X display");
    static const int attrs[] = {GLX_DRAWABLE_TYPE,
                                GLX_WINDOW_BIT,
                                GLX_RENDER_TYPE,
                                GLX_RGBA_BIT,
                                GLX_RED_SIZE,
                                8,
                                GLX_GREEN_SIZE,
                                8,
                                GLX_BLUE_SIZE,
                                8,
                                GLX_DOUBLEBUFFER,
                                True,
                                GLX_DEPTH_SIZE,
                                24,
                                GLX_STENCIL_SIZE,
                                8,
                                GLX_SAMPLE_BUFFERS,
                                1,
                                GLX_SAMPLES,
                                2,
                                None};
    int n = 0;
    GLXFBConfig *configs = glXChooseFBConfig(dpy, DefaultScreen(dpy), attrs, &n);
    REQUIRE(configs && n > 0, "no multisample config");
    int sample_buffers = -1, samples = -1;
    glXGetFBConfigAttrib(dpy, configs[0], GLX_SAMPLE_BUFFERS, &sample_buffers);
    glXGetFBConfigAttrib(dpy, configs[0], GLX_SAMPLES, &samples);
    fprintf(out, "config: sample buffers %d samples %d\n", sample_buffers, samples);
    XVisualInfo *vi = glXGetVisualFromFBConfig(dpy, configs[0]);
    REQUIRE(vi, "no visual");
    XSetWindowAttributes swa = {.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone)};
    Window win = XCreateWindow(dpy, RootWindow(dpy, vi->screen), 0, 0, W, H, 0, vi->depth, InputOutput, vi->visual,
                               CWColormap, &swa);
    XMapWindow(dpy, win);
    XSync(dpy, False);
    GLXContext ctx = glXCreateNewContext(dpy, configs[0], GLX_RGBA_TYPE, NULL, True);
    REQUIRE(ctx && glXMakeCurrent(dpy, win, ctx), "no context");
    GLint gl_sample_buffers = -1, gl_samples = -1;
    glGetIntegerv(GL_SAMPLE_BUFFERS, &gl_sample_buffers);
    glGetIntegerv(GL_SAMPLES, &gl_samples);
    fprintf(out, "gets: GL_SAMPLE_BUFFERS %d GL_SAMPLES %d GL_MULTISAMPLE %d error 0x%x\n", gl_sample_buffers,
            gl_samples, glIsEnabled(GL_MULTISAMPLE), glGetError());
    glViewport(0, 0, W, H);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0, W, 0, H, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();

    scene();
    read_window("drawn", rgba_path);
    char resolved_path[4096];
    snprintf(resolved_path, sizeof resolved_path, "%s.resolved.rgba", argv[1]);
    resolved_window("resolved", resolved_path);

    /* glCopyPixels: the lower left quarter onto the upper right, read
     * back (the copy reads the window as glReadPixels does). */
    glRasterPos2i(W / 2, H / 2);
    glCopyPixels(0, 0, W / 2, H / 2, GL_COLOR);
    read_window("copypixels", NULL);

    /* glCopyTexImage2D and glCopyTexSubImage2D, read back from the texture. */
    static unsigned char tex[32 * 32 * 4];
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    scene();
    glCopyTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 8, 4, 32, 32, 0);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, tex);
    fprintf(out, "copyteximage: %08x blended %d error 0x%x\n", fnv1a(tex, sizeof tex), blended(tex, 32 * 32),
            glGetError());
    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 4, 4, 30, 12, 20, 20);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, tex);
    fprintf(out, "copytexsubimage: %08x blended %d error 0x%x\n", fnv1a(tex, sizeof tex), blended(tex, 32 * 32),
            glGetError());

    /* The swap: the back still holds the frame (read after it). */
    scene();
    resolved_window("frame", NULL);
    glXSwapBuffers(dpy, win);
    glXWaitGL();
    XSync(dpy, False);
    char displayed_path[4096];
    snprintf(displayed_path, sizeof displayed_path, "%s.displayed.rgba", argv[1]);
    displayed(dpy, win, displayed_path);
    glReadBuffer(GL_BACK);
    read_window("swapped", NULL);

    glXMakeCurrent(dpy, None, NULL);
    glXDestroyContext(dpy, ctx);
    XDestroyWindow(dpy, win);
    XFree(vi);
    XFree(configs);
    XCloseDisplay(dpy);
    fclose(out);
    return harness_failures ? 1 : 0;
}
