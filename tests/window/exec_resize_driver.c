/* tests/window/exec_resize_driver.c — window_exec_resize FRAMES RESIZE_AT W H: an
 * ordinary GLX program (nothing of tessera in it) for `tessera exec`. It
 * opens a 320x240 window, draws FRAMES frames that depend only on the
 * frame number (a clear colour and triangles spanning the window, in
 * window-relative coordinates), and before frame RESIZE_AT resizes its
 * own window to W x H, waits for the ConfigureNotify and sets glViewport,
 * as a program does when the user resizes it. Two runs draw the same
 * frames whatever chain or graph they go through. */
#include <GL/gl.h>
#include <GL/glx.h>
#include <X11/Xlib.h>
#include <stdio.h>
#include <stdlib.h>

static void draw(int f, int w, int h)
{
    glViewport(0, 0, w, h);
    glClearColor((float)(f % 7) / 7.0f, 0.25f, 0.5f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0, 1, 0, 1, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glBegin(GL_TRIANGLES);
    for (int k = 0; k < 6; k++) {
        float a = (float)((f * 3 + k * 17) % 40) / 40.0f, b = (float)((f * 5 + k * 11) % 40) / 40.0f;
        glColor3f(a, b, 1.0f - a);
        glVertex2f(a, 0.05f);
        glVertex2f(0.95f, b);
        glVertex2f(1.0f - b, 0.95f);
    }
    glEnd();
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: window_exec_resize FRAMES RESIZE_AT W H\n");
        return 2;
    }
    int frames = atoi(argv[1]), at = atoi(argv[2]), w2 = atoi(argv[3]), h2 = atoi(argv[4]);
    Display *d = XOpenDisplay(NULL);
    if (!d) {
        fprintf(stderr, "window_exec_resize: cannot open display\n");
        return 1;
    }
    int attrs[] = {GLX_RGBA, GLX_DOUBLEBUFFER, GLX_RED_SIZE, 8,   GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE,
                   8,        GLX_DEPTH_SIZE,   24,           None};
    XVisualInfo *vi = glXChooseVisual(d, DefaultScreen(d), attrs);
    if (!vi) {
        fprintf(stderr, "window_exec_resize: no visual\n");
        return 1;
    }
    XSetWindowAttributes wa = {0};
    wa.colormap = XCreateColormap(d, RootWindow(d, vi->screen), vi->visual, AllocNone);
    wa.event_mask = StructureNotifyMask;
    Window win = XCreateWindow(d, RootWindow(d, vi->screen), 0, 0, 320, 240, 0, vi->depth, InputOutput, vi->visual,
                               CWColormap | CWEventMask, &wa);
    XStoreName(d, win, "window_exec_resize");
    XMapWindow(d, win);
    GLXContext ctx = glXCreateContext(d, vi, NULL, True);
    glXMakeCurrent(d, win, ctx);
    int w = 320, h = 240;
    for (int f = 0; f < frames; f++) {
        if (f == at) {
            XResizeWindow(d, win, (unsigned)w2, (unsigned)h2);
            XEvent e;
            do
                XWindowEvent(d, win, StructureNotifyMask, &e);
            while (e.type != ConfigureNotify || e.xconfigure.width != w2 || e.xconfigure.height != h2);
            w = w2;
            h = h2;
        }
        draw(f, w, h);
        glXSwapBuffers(d, win);
    }
    printf("window_exec_resize: %d frames, %dx%d from frame %d\n", frames, w2, h2, at);
    glXMakeCurrent(d, None, NULL);
    glXDestroyContext(d, ctx);
    XDestroyWindow(d, win);
    XCloseDisplay(d);
    return 0;
}
