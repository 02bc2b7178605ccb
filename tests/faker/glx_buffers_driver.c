/* tests/faker/glx_buffers_driver.c — faker_glx_buffers OUT.txt, under Xvfb: a
 * double-buffered GLX window (64x48) whose front and back buffers are
 * drawn, cleared, read and swapped the ways piglit's drawbuffer-modes,
 * front-invalidate-back and read-front do, each answer one labelled line
 * in OUT.txt: the initial GL_DOUBLEBUFFER, GL_DRAW_BUFFER and
 * GL_READ_BUFFER; for glDrawBuffer of GL_FRONT_AND_BACK, GL_BACK,
 * GL_FRONT, GL_LEFT, GL_BACK_LEFT, GL_FRONT_LEFT and GL_NONE the error,
 * the get and what each buffer then holds; a clear of the front kept
 * through back-buffer work; a swap (the front shows the last frame, the
 * back keeps it) and drawing into the front after it; glCopyPixels from
 * the front into the back. Linked against the faker's libGL (faker_glx_buffers) it
 * runs through tessera; linked against Mesa's (faker_glx_buffers_native)
 * it gives the answers to match (glx_buffers.sh). */
#include <GL/gl.h>
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"

#define W 64
#define H 48

static FILE *out;

static const char *name_of(GLint e)
{
    switch (e) {
    case GL_NONE: return "NONE";
    case GL_FRONT: return "FRONT";
    case GL_BACK: return "BACK";
    case GL_FRONT_AND_BACK: return "FRONT_AND_BACK";
    case GL_LEFT: return "LEFT";
    case GL_FRONT_LEFT: return "FRONT_LEFT";
    case GL_BACK_LEFT: return "BACK_LEFT";
    default: return "other";
    }
}

/* The centre pixel and a corner pixel of buffer `buf`. */
static void probe(const char *label, GLenum buf)
{
    unsigned char centre[4] = {0}, corner[4] = {0};
    glReadBuffer(buf);
    glReadPixels(W / 2, H / 2, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, centre);
    glReadPixels(2, 2, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, corner);
    fprintf(out, "%s %s: centre %u %u %u corner %u %u %u\n", label, name_of((GLint)buf), centre[0], centre[1],
            centre[2], corner[0], corner[1], corner[2]);
}

static void rect(float r, float g, float b)
{
    glColor3f(r, g, b);
    glRecti(W / 4, H / 4, 3 * W / 4, 3 * H / 4);
}

static void answers(const char *label)
{
    GLint draw = -1, read = -1;
    GLboolean db = 2;
    glGetIntegerv(GL_DRAW_BUFFER, &draw);
    glGetIntegerv(GL_READ_BUFFER, &read);
    glGetBooleanv(GL_DOUBLEBUFFER, &db);
    fprintf(out, "%s: error 0x%x draw %s read %s double %d\n", label, glGetError(), name_of(draw), name_of(read), db);
}

int main(int argc, char **argv)
{
    REQUIRE(argc == 2, "usage: faker_glx_buffers OUT.txt");
    out = fopen(argv[1], "w");
    REQUIRE(out, "cannot write %s", argv[1]);
    Display *dpy = XOpenDisplay(NULL);
    REQUIRE(dpy, "no X display");
    int attrs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, None};
    XVisualInfo *vi = glXChooseVisual(dpy, DefaultScreen(dpy), attrs);
    REQUIRE(vi, "no double-buffered RGBA visual");
    XSetWindowAttributes swa = {.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone)};
    Window win = XCreateWindow(dpy, RootWindow(dpy, vi->screen), 0, 0, W, H, 0, vi->depth, InputOutput, vi->visual,
                               CWColormap, &swa);
    XMapWindow(dpy, win);
    XSync(dpy, False);
    GLXContext ctx = glXCreateContext(dpy, vi, NULL, True);
    REQUIRE(ctx && glXMakeCurrent(dpy, win, ctx), "no context");
    glViewport(0, 0, W, H);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0, W, 0, H, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    answers("initial");

    /* drawbuffer-modes: each buffer name cleared grey-blue and a rect
     * drawn; both buffers then read. The front is cleared first so the
     * first answers do not depend on a new window's undefined pixels. */
    glDrawBuffer(GL_FRONT_AND_BACK);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    static const GLenum modes[] = {GL_FRONT_AND_BACK, GL_BACK, GL_FRONT, GL_LEFT, GL_BACK_LEFT, GL_FRONT_LEFT, GL_NONE};
    for (size_t i = 0; i < sizeof modes / sizeof modes[0]; i++) {
        char label[64];
        snprintf(label, sizeof label, "drawbuffer %s", name_of((GLint)modes[i]));
        glDrawBuffer(modes[i]);
        /* Colours k/5 are exact in 8 bits: no rounding left to chance. */
        glClearColor(0.2f, 0.2f, 0.2f * (float)(i % 5), 1);
        glClear(GL_COLOR_BUFFER_BIT);
        rect(0.2f * (float)((i + 1) % 5), 0.8f, 0.4f);
        answers(label);
        probe(label, GL_BACK);
        probe(label, GL_FRONT);
    }

    /* front-invalidate-back: the front's clear survives back-buffer work. */
    glDrawBuffer(GL_FRONT);
    glClearColor(0, 1, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawBuffer(GL_BACK);
    glDrawBuffer(GL_FRONT);
    glReadBuffer(GL_BACK);
    glDrawBuffer(GL_BACK);
    glClearColor(1, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    probe("invalidate", GL_FRONT);
    probe("invalidate", GL_BACK);

    /* read-front: a frame drawn in the back, swapped; the front shows it
     * and the back keeps it. (Mesa's GLX on Xvfb reads a stale front here
     * once the front was drawn into: glx_buffers.sh checks this line
     * against the back's instead.) */
    glClearColor(0, 0, 1, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    rect(0, 1, 0);
    glXSwapBuffers(dpy, win);
    probe("swapped", GL_FRONT);
    probe("swapped", GL_BACK);
    answers("swapped");

    /* Drawing into the front after the swap (cleared first, so what
     * follows does not depend on the swap), then the back changed alone. */
    glDrawBuffer(GL_FRONT);
    glClearColor(0.2f, 0.6f, 0.4f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    rect(1, 1, 0);
    glDrawBuffer(GL_BACK);
    glClearColor(0.6f, 0, 0.6f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glFinish();
    probe("front drawn", GL_FRONT);
    probe("front drawn", GL_BACK);

    /* The front copied into the back. */
    glReadBuffer(GL_FRONT);
    glDrawBuffer(GL_BACK);
    glRasterPos2i(0, 0);
    glCopyPixels(0, 0, W, H, GL_COLOR);
    probe("copied", GL_BACK);
    answers("copied");

    /* Display lists compile the names too. */
    GLuint list = glGenLists(1);
    glNewList(list, GL_COMPILE);
    glDrawBuffer(GL_FRONT);
    glClearColor(1, 0.4f, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawBuffer(GL_BACK);
    glEndList();
    glCallList(list);
    probe("list", GL_FRONT);
    probe("list", GL_BACK);
    answers("list");

    glXMakeCurrent(dpy, None, NULL);
    glXDestroyContext(dpy, ctx);
    XDestroyWindow(dpy, win);
    XFree(vi);
    XCloseDisplay(dpy);
    fclose(out);
    return harness_failures ? 1 : 0;
}
