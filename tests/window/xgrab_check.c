/* tests/window/xgrab_check.c — window_xgrab NAME PNG [PNG...]: finds the X
 * window called NAME (WM_NAME, searched from the root of $DISPLAY), reads
 * its pixels with XGetImage and compares them with each PNG: the window's
 * pixels are turned into RGB through its visual's channel masks (whatever
 * their order) and rows are taken top first, as PNG stores them. Prints
 * one line per PNG with the differing pixel count; exits 0 when one of the
 * PNGs has 0 differing pixels (printed as "match: PNG"), 1 otherwise.
 * Several PNGs: the window may show the frame before the newest one when
 * the program was stopped between writing a PNG and drawing its window. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <X11/Xlib.h>
#include <X11/Xutil.h>

#include "tessera/image.h"

static Window find(Display *d, Window w, const char *name)
{
    char *wm = NULL;
    if (XFetchName(d, w, &wm) && wm) {
        int same = !strcmp(wm, name);
        XFree(wm);
        if (same)
            return w;
    }
    Window root, parent, *kids = NULL;
    unsigned n = 0;
    Window found = 0;
    if (XQueryTree(d, w, &root, &parent, &kids, &n)) {
        for (unsigned i = 0; i < n && !found; i++)
            found = find(d, kids[i], name);
        if (kids)
            XFree(kids);
    }
    return found;
}

static int shift_of(unsigned long m)
{
    int s = 0;
    while (m && !(m & 1)) {
        m >>= 1;
        s++;
    }
    return s;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: window_xgrab NAME PNG [PNG...]\n");
        return 2;
    }
    Display *d = XOpenDisplay(NULL);
    if (!d) {
        fprintf(stderr, "window_xgrab: cannot open display %s\n", XDisplayName(NULL));
        return 1;
    }
    Window w = find(d, DefaultRootWindow(d), argv[1]);
    if (!w) {
        fprintf(stderr, "window_xgrab: no window named \"%s\" on %s\n", argv[1], XDisplayName(NULL));
        return 1;
    }
    XWindowAttributes wa;
    XGetWindowAttributes(d, w, &wa);
    XImage *img = XGetImage(d, w, 0, 0, (unsigned)wa.width, (unsigned)wa.height, AllPlanes, ZPixmap);
    if (!img) {
        fprintf(stderr, "window_xgrab: XGetImage of window 0x%lx failed\n", w);
        return 1;
    }
    unsigned long masks[3] = {wa.visual->red_mask, wa.visual->green_mask, wa.visual->blue_mask};
    int shifts[3] = {shift_of(masks[0]), shift_of(masks[1]), shift_of(masks[2])};
    printf("window \"%s\" 0x%lx: %dx%d, depth %d, masks r %06lx g %06lx b %06lx, %d bits per pixel, %s\n", argv[1], w,
           wa.width, wa.height, wa.depth, masks[0], masks[1], masks[2], img->bits_per_pixel,
           img->byte_order == LSBFirst ? "LSBFirst" : "MSBFirst");
    int matched = 0;
    for (int a = 2; a < argc; a++) {
        tsr_image png = {0};
        tsr_error err = {0};
        if (tsr_image_read_png(&png, argv[a], &err) != TSR_OK) {
            printf("%s: %s\n", argv[a], err.message);
            continue;
        }
        if (png.width != wa.width || png.height != wa.height) {
            printf("%s: %dx%d, the window is %dx%d\n", argv[a], png.width, png.height, wa.width, wa.height);
            tsr_image_free(&png);
            continue;
        }
        long differ = 0, nonblack = 0;
        for (int y = 0; y < wa.height; y++)
            for (int x = 0; x < wa.width; x++) {
                unsigned long v = XGetPixel(img, x, y);
                const unsigned char *p = png.pixels + ((size_t)y * (size_t)png.width + (size_t)x) * 4;
                int same = 1;
                for (int c = 0; c < 3; c++)
                    same &= (int)((v & masks[c]) >> shifts[c]) == p[c];
                differ += !same;
                nonblack += (p[0] | p[1] | p[2]) != 0;
            }
        printf("%s: %ld differing pixels of %dx%d (%ld not black in the PNG)\n", argv[a], differ, wa.width, wa.height,
               nonblack);
        if (!differ && nonblack && !matched) {
            printf("match: %s\n", argv[a]);
            matched = 1;
        }
        tsr_image_free(&png);
    }
    XDestroyImage(img);
    XCloseDisplay(d);
    return matched ? 0 : 1;
}
