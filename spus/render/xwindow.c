/* spus/render/xwindow.c — render's window output (xwindow.h). Each frame's
 * tiles are kept as frame.c reads them back (render_xwindow_image) and
 * shown when the frame ends (render_xwindow_done): converted once into an
 * XImage of the target window's visual (its channel masks, bits per pixel
 * and byte order, rows top first as X wants them) and sent with XShmPutImage or XPutImage over
 * this instance's own connection, then XSync, so that the server holds the
 * frame before the next one is drawn.
 *
 * x11: a window of its own, made at the first frame, the size of the
 * bounding box of the frame's tiles (the whole window without tiles), or
 * x_size, or the screen (fullscreen). app: the drawable that the faker
 * recorded for the stream's window (tessera/dev/native.h), each tile at its
 * own place in it; its visual is read once per drawable.
 *
 * Xlib reports protocol errors through one process-wide handler; in a
 * program's own process that handler is the program's, so it is replaced
 * only around the one request that may fail for reasons outside our
 * control (XShmAttach when the server cannot share our memory) and put
 * back at once. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ipc.h>
#include <sys/shm.h>

#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/extensions/XShm.h>

#include "tessera/dev/native.h"
#include "tessera/log.h"
#include "tessera/options.h"

#include "xwindow.h"

enum { XW_OWN = 1, XW_APP = 2 };

typedef struct xw_tile {
    int x, y, w, h;      /* window pixels, origin bottom-left */
    unsigned char *rgba; /* bottom row first, rows packed */
    size_t cap;
} xw_tile;

struct render_xwindow {
    char name[64];
    char title[256];
    int mode;
    tsr_native_windows *app_windows; /* the chain's (window_output=app) */
    char display_name[256];
    Display *dpy;
    int pos_x, pos_y, size_w, size_h;
    bool fullscreen, want_shm, shm_ok;
    /* the target drawable and what was read of it */
    Window win;
    bool own_window;
    Visual *visual;
    int depth;
    GC gc;
    /* the image, recreated when the frame's size changes */
    XImage *img;
    XShmSegmentInfo shm;
    bool img_shm;
    /* the frame being finished */
    xw_tile *tiles;
    size_t ntiles, tiles_cap;
    bool warned;
    unsigned long told; /* the window the path was logged for */
};

/* The error catcher: errors of the display being guarded, on the thread
 * that guards it, are counted; any other error goes to the handler that
 * was there before (the program's). Thread-local so two instances on two
 * threads never see each other's. */
static _Thread_local Display *guard_dpy;
static _Thread_local int guard_errors;
static int (*guard_prev)(Display *, XErrorEvent *);

static int guard_handler(Display *d, XErrorEvent *e)
{
    if (d == guard_dpy) {
        guard_errors++;
        return 0;
    }
    return guard_prev ? guard_prev(d, e) : 0;
}

static void guard_begin(Display *d)
{
    XSync(d, False);
    guard_dpy = d;
    guard_errors = 0;
    int (*old)(Display *, XErrorEvent *) = XSetErrorHandler(guard_handler);
    if (old != guard_handler)
        guard_prev = old;
}

/* The number of errors since guard_begin. */
static int guard_end(Display *d)
{
    XSync(d, False);
    XSetErrorHandler(guard_prev);
    guard_dpy = NULL;
    return guard_errors;
}

static void image_free(render_xwindow *x)
{
    if (!x->img)
        return;
    if (x->img_shm) {
        XShmDetach(x->dpy, &x->shm);
        XSync(x->dpy, False);
        XDestroyImage(x->img);
        shmdt(x->shm.shmaddr);
    } else {
        XDestroyImage(x->img);
    }
    x->img = NULL;
    x->img_shm = false;
}

/* An XImage of w x h for the target's visual: shared memory when possible. */
static bool image_make(render_xwindow *x, int w, int h)
{
    if (x->img && x->img->width == w && x->img->height == h)
        return true;
    image_free(x);
    if (x->shm_ok) {
        XImage *img =
            XShmCreateImage(x->dpy, x->visual, (unsigned)x->depth, ZPixmap, NULL, &x->shm, (unsigned)w, (unsigned)h);
        if (img) {
            x->shm.shmid = shmget(IPC_PRIVATE, (size_t)img->bytes_per_line * (size_t)h, IPC_CREAT | 0600);
            if (x->shm.shmid >= 0) {
                x->shm.shmaddr = img->data = shmat(x->shm.shmid, NULL, 0);
                /* Marked for removal now: it goes when both sides detach,
                 * also when this process dies. */
                shmctl(x->shm.shmid, IPC_RMID, NULL);
                if (x->shm.shmaddr != (char *)-1) {
                    x->shm.readOnly = True;
                    guard_begin(x->dpy);
                    XShmAttach(x->dpy, &x->shm);
                    if (!guard_end(x->dpy)) {
                        x->img = img;
                        x->img_shm = true;
                        return true;
                    }
                    shmdt(x->shm.shmaddr);
                }
            }
            img->data = NULL;
            XDestroyImage(img);
        }
        tsr_log(TSR_LOG_INFO, "%s: MIT-SHM not usable with display %s: plain XPutImage", x->name,
                DisplayString(x->dpy));
        x->shm_ok = false;
    }
    XImage *img =
        XCreateImage(x->dpy, x->visual, (unsigned)x->depth, ZPixmap, 0, NULL, (unsigned)w, (unsigned)h, 32, 0);
    if (!img)
        return false;
    img->data = malloc((size_t)img->bytes_per_line * (size_t)h);
    if (!img->data) {
        XDestroyImage(img);
        return false;
    }
    x->img = img;
    return true;
}

static int mask_shift(unsigned long m)
{
    int s = 0;
    while (m && !(m & 1)) {
        m >>= 1;
        s++;
    }
    return s;
}

static int mask_bits(unsigned long m)
{
    int b = 0;
    for (; m; m &= m - 1)
        b++;
    return b;
}

/* Tile t into the image with its top-left corner at (dx, dy), X order. */
static void image_put_tile(render_xwindow *x, const xw_tile *t, int dx, int dy)
{
    XImage *img = x->img;
    unsigned long masks[3] = {img->red_mask, img->green_mask, img->blue_mask};
    int shift[3], bits[3];
    for (int c = 0; c < 3; c++) {
        shift[c] = mask_shift(masks[c]);
        bits[c] = mask_bits(masks[c]);
    }
    bool fast = img->bits_per_pixel == 32 && bits[0] == 8 && bits[1] == 8 && bits[2] == 8;
    for (int row = 0; row < t->h; row++) {
        int iy = dy + row;
        if (iy < 0 || iy >= img->height)
            continue;
        /* rgba is bottom row first: image row `row` is tile row h-1-row */
        const unsigned char *src = t->rgba + (size_t)(t->h - 1 - row) * (size_t)t->w * 4;
        unsigned char *dst = (unsigned char *)img->data + (size_t)iy * (size_t)img->bytes_per_line;
        for (int col = 0; col < t->w; col++) {
            int ix = dx + col;
            if (ix < 0 || ix >= img->width)
                continue;
            const unsigned char *p = src + (size_t)col * 4;
            unsigned long v = 0;
            for (int c = 0; c < 3; c++) {
                unsigned long ch =
                    bits[c] >= 8 ? (unsigned long)p[c] << (bits[c] - 8) : (unsigned long)p[c] >> (8 - bits[c]);
                v |= ch << shift[c];
            }
            if (fast) {
                unsigned char *q = dst + (size_t)ix * 4;
                if (img->byte_order == LSBFirst) {
                    q[0] = (unsigned char)v, q[1] = (unsigned char)(v >> 8), q[2] = (unsigned char)(v >> 16),
                    q[3] = (unsigned char)(v >> 24);
                } else {
                    q[3] = (unsigned char)v, q[2] = (unsigned char)(v >> 8), q[1] = (unsigned char)(v >> 16),
                    q[0] = (unsigned char)(v >> 24);
                }
            } else {
                XPutPixel(img, ix, iy, v);
            }
        }
    }
}

/* The target's visual must be TrueColor (or DirectColor) to take pixels
 * as channel masks. */
static bool read_visual(render_xwindow *x, Visual *v, int depth)
{
    if (v->class != TrueColor && v->class != DirectColor) {
        tsr_log(TSR_LOG_ERROR, "%s: window 0x%lx has a visual of class %d, not TrueColor: no window output", x->name,
                x->win, v->class);
        return false;
    }
    x->visual = v;
    x->depth = depth;
    return true;
}

static bool own_window(render_xwindow *x, int w, int h)
{
    if (x->win)
        return true;
    int scr = DefaultScreen(x->dpy);
    XVisualInfo want = {.screen = scr, .class = TrueColor, .depth = 24}, *vi;
    int n = 0;
    vi = XGetVisualInfo(x->dpy, VisualScreenMask | VisualClassMask | VisualDepthMask, &want, &n);
    if (!vi || !n) {
        tsr_log(TSR_LOG_ERROR, "%s: display %s has no TrueColor visual of depth 24: no window output", x->name,
                DisplayString(x->dpy));
        if (vi)
            XFree(vi);
        return false;
    }
    Visual *visual = vi[0].visual;
    XFree(vi);
    if (x->fullscreen) {
        w = DisplayWidth(x->dpy, scr);
        h = DisplayHeight(x->dpy, scr);
    } else if (x->size_w && x->size_h) {
        w = x->size_w;
        h = x->size_h;
    }
    XSetWindowAttributes a = {0};
    a.colormap = XCreateColormap(x->dpy, RootWindow(x->dpy, scr), visual, AllocNone);
    a.background_pixel = 0;
    a.border_pixel = 0;
    a.override_redirect = x->fullscreen ? True : False;
    x->win = XCreateWindow(x->dpy, RootWindow(x->dpy, scr), x->fullscreen ? 0 : x->pos_x, x->fullscreen ? 0 : x->pos_y,
                           (unsigned)w, (unsigned)h, 0, 24, InputOutput, visual,
                           CWColormap | CWBackPixel | CWBorderPixel | CWOverrideRedirect, &a);
    XSizeHints hints = {.flags = USPosition | USSize, .x = x->pos_x, .y = x->pos_y, .width = w, .height = h};
    XSetWMNormalHints(x->dpy, x->win, &hints);
    XStoreName(x->dpy, x->win, x->title[0] ? x->title : x->name);
    XMapRaised(x->dpy, x->win);
    x->own_window = true;
    x->gc = XCreateGC(x->dpy, x->win, 0, NULL);
    XSync(x->dpy, False);
    return read_visual(x, visual, 24);
}

static bool app_window(render_xwindow *x, int window)
{
    char dpy_name[256];
    unsigned long xid = 0;
    if (!tsr_native_window_get(x->app_windows, window, dpy_name, sizeof dpy_name, &xid)) {
        if (!x->warned)
            tsr_log(TSR_LOG_ERROR,
                    "%s: window_output=app: window %d has no X drawable of the program in this process "
                    "(run the program under the faker: tessera exec)",
                    x->name, window);
        x->warned = true;
        return false;
    }
    if (x->dpy && xid == x->win)
        return true;
    if (x->dpy && strcmp(dpy_name, x->display_name) != 0) {
        image_free(x);
        if (x->gc)
            XFreeGC(x->dpy, x->gc);
        x->gc = NULL;
        XCloseDisplay(x->dpy);
        x->dpy = NULL;
    }
    if (!x->dpy) {
        snprintf(x->display_name, sizeof x->display_name, "%s", dpy_name);
        x->dpy = XOpenDisplay(dpy_name[0] ? dpy_name : NULL);
        if (!x->dpy) {
            tsr_log(TSR_LOG_ERROR, "%s: cannot open X display \"%s\": no window output", x->name,
                    XDisplayName(dpy_name[0] ? dpy_name : NULL));
            return false;
        }
        int major, minor;
        Bool pixmaps;
        x->shm_ok = x->want_shm && XShmQueryVersion(x->dpy, &major, &minor, &pixmaps);
    }
    image_free(x);
    if (x->gc)
        XFreeGC(x->dpy, x->gc);
    x->gc = NULL;
    x->win = xid;
    XWindowAttributes wa;
    guard_begin(x->dpy);
    Status got = XGetWindowAttributes(x->dpy, x->win, &wa);
    if (guard_end(x->dpy) || !got) {
        tsr_log(TSR_LOG_ERROR, "%s: cannot read window 0x%lx of display %s", x->name, xid, DisplayString(x->dpy));
        x->win = 0;
        return false;
    }
    x->gc = XCreateGC(x->dpy, x->win, 0, NULL);
    return read_visual(x, wa.visual, wa.depth);
}

render_xwindow *render_xwindow_create(const tsr_spu_init *init, tsr_error *err)
{
    const char *mode = tsr_options_string(init->options, "window_output");
    if (!mode || !strcmp(mode, "none"))
        return NULL;
    render_xwindow *x = calloc(1, sizeof *x);
    if (!x) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    snprintf(x->name, sizeof x->name, "%s", init->instance_name);
    x->mode = !strcmp(mode, "app") ? XW_APP : XW_OWN;
    x->app_windows = init->native_windows;
    x->want_shm = tsr_options_bool(init->options, "x_shm");
    x->fullscreen = tsr_options_bool(init->options, "fullscreen");
    const char *title = tsr_options_string(init->options, "x_title");
    snprintf(x->title, sizeof x->title, "%s", title ? title : "");
    const char *names[2] = {"x_position", "x_size"};
    int *vals[2][2] = {{&x->pos_x, &x->pos_y}, {&x->size_w, &x->size_h}};
    for (int k = 0; k < 2; k++) {
        if (tsr_options_count(init->options, names[k]) != 2) {
            tsr_error_set(err, TSR_EINVAL, "%s: option %s takes two numbers (%s)", x->name, names[k],
                          k ? "W,H" : "X,Y");
            free(x);
            return NULL;
        }
        *vals[k][0] = (int)tsr_options_int_at(init->options, names[k], 0);
        *vals[k][1] = (int)tsr_options_int_at(init->options, names[k], 1);
    }
    if ((x->size_w == 0) != (x->size_h == 0)) {
        tsr_error_set(err, TSR_EINVAL, "%s: option x_size=%d,%d: give both or neither", x->name, x->size_w, x->size_h);
        free(x);
        return NULL;
    }
    if (x->mode == XW_OWN) {
        const char *d = tsr_options_string(init->options, "x_display");
        snprintf(x->display_name, sizeof x->display_name, "%s", d ? d : "");
        x->dpy = XOpenDisplay(x->display_name[0] ? x->display_name : NULL);
        if (!x->dpy) {
            tsr_error_set(err, TSR_EIO, "%s: window_output=x11: cannot open X display \"%s\"", x->name,
                          XDisplayName(x->display_name[0] ? x->display_name : NULL));
            free(x);
            return NULL;
        }
        int major, minor;
        Bool pixmaps;
        x->shm_ok = x->want_shm && XShmQueryVersion(x->dpy, &major, &minor, &pixmaps);
    }
    return x;
}

void render_xwindow_destroy(render_xwindow *x)
{
    if (!x)
        return;
    if (x->dpy) {
        image_free(x);
        if (x->gc)
            XFreeGC(x->dpy, x->gc);
        if (x->own_window)
            XDestroyWindow(x->dpy, x->win);
        XCloseDisplay(x->dpy);
    }
    for (size_t i = 0; i < x->tiles_cap; i++)
        free(x->tiles[i].rgba);
    free(x->tiles);
    free(x);
}

void render_xwindow_image(render_xwindow *x, int x0, int y0, int width, int height, const unsigned char *rgba)
{
    if (x->ntiles == x->tiles_cap) {
        size_t cap = x->tiles_cap ? 2 * x->tiles_cap : 4;
        xw_tile *t = realloc(x->tiles, cap * sizeof *t);
        if (!t)
            return;
        memset(t + x->tiles_cap, 0, (cap - x->tiles_cap) * sizeof *t);
        x->tiles = t;
        x->tiles_cap = cap;
    }
    xw_tile *t = &x->tiles[x->ntiles];
    size_t need = (size_t)width * (size_t)height * 4;
    if (need > t->cap) {
        unsigned char *p = realloc(t->rgba, need);
        if (!p)
            return;
        t->rgba = p;
        t->cap = need;
    }
    memcpy(t->rgba, rgba, need);
    t->x = x0, t->y = y0, t->w = width, t->h = height;
    x->ntiles++;
}

void render_xwindow_done(render_xwindow *x, int frame, int window, int width, int height)
{
    size_t n = x->ntiles;
    x->ntiles = 0;
    if (!n || width <= 0 || height <= 0)
        return;
    /* Own window: the tiles' bounding box (window pixels, bottom-left
     * origin); app: the whole program window. */
    int bx0 = 0, by0 = 0, bx1 = width, by1 = height;
    if (x->mode == XW_OWN) {
        bx0 = by0 = 1 << 30;
        bx1 = by1 = -(1 << 30);
        for (size_t i = 0; i < n; i++) {
            const xw_tile *t = &x->tiles[i];
            bx0 = t->x < bx0 ? t->x : bx0;
            by0 = t->y < by0 ? t->y : by0;
            bx1 = t->x + t->w > bx1 ? t->x + t->w : bx1;
            by1 = t->y + t->h > by1 ? t->y + t->h : by1;
        }
        if (!own_window(x, bx1 - bx0, by1 - by0))
            return;
    } else if (!app_window(x, window)) {
        return;
    }
    int iw = bx1 - bx0, ih = by1 - by0;
    if (!image_make(x, iw, ih)) {
        tsr_log(TSR_LOG_ERROR, "%s: frame %d: cannot make a %dx%d X image", x->name, frame, iw, ih);
        return;
    }
    if (n > 1 || x->tiles[0].w != iw || x->tiles[0].h != ih)
        memset(x->img->data, 0, (size_t)x->img->bytes_per_line * (size_t)ih);
    for (size_t i = 0; i < n; i++) {
        const xw_tile *t = &x->tiles[i];
        /* X rows go down from the top: a tile's top row is at by1-(y+h). */
        image_put_tile(x, t, t->x - bx0, by1 - (t->y + t->h));
    }
    if (x->told != x->win) {
        tsr_log(TSR_LOG_INFO, "%s: window output to %s window 0x%lx on %s with %s", x->name,
                x->own_window ? "its own" : "the program's", x->win, DisplayString(x->dpy),
                x->img_shm ? "XShmPutImage" : "XPutImage");
        x->told = x->win;
    }
    /* Guarded: the program may have destroyed its window, which must not
     * end the program through Xlib's default handler. */
    guard_begin(x->dpy);
    if (x->img_shm)
        XShmPutImage(x->dpy, x->win, x->gc, x->img, 0, 0, 0, 0, (unsigned)iw, (unsigned)ih, False);
    else
        XPutImage(x->dpy, x->win, x->gc, x->img, 0, 0, 0, 0, (unsigned)iw, (unsigned)ih);
    if (guard_end(x->dpy) && !x->warned) {
        tsr_log(TSR_LOG_ERROR, "%s: frame %d: the X server refused the image for window 0x%lx (logged once)", x->name,
                frame, x->win);
        x->warned = true;
    }
}
