/* faker/glx.c — GLX 1.4 of the faker's libGL.so.1 (and libGLX.so.0), on
 * faker/core.c. Never sends a GLX request: FBConfigs and visuals are the
 * formats of configs.c (what render draws) on the X server's TrueColor
 * visuals of depth 24 and 32, read from the application's Display
 * structure without a round trip, matched and sorted by GLX 1.4's rules
 * (glXChooseFBConfig; glXChooseVisual by GLX 1.2's, then the same order).
 * Contexts are faker contexts; GLX windows are the X windows
 * themselves; GLX pbuffers and pixmaps are off-screen tessera drawables of
 * their size, which a swap leaves alone (GLX 1.4, 3.3.10). Swap-interval
 * calls are accepted and have no effect. */
#define GLX_GLXEXT_PROTOTYPES 1
#include <GL/glx.h>
#include <GL/glxext.h>
#include <X11/Xutil.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "configs.h"
#include "tessera/log.h"

#define GLX_MAX_OFFSCREEN_SIDE 8192 /* pbuffers, as EGL's (egl.c) */
#define MAX_DISPLAYS 8

struct __GLXFBConfigRec {
    int id; /* GLX_FBCONFIG_ID, from 1 */
    int screen;
    VisualID visual;
    int depth; /* of the visual: 24 or 32 */
    /* What its visual stands for (glXGetConfig, glXCreateContext,
     * glXCreateGLXPixmap): at first a visual's first config; when several
     * share a visual (a server with fewer visuals than formats), the one
     * glXChooseVisual or glXGetVisualFromFBConfig last handed it out for. */
    _Atomic bool primary;
    tsr_faker_format f;
};

struct __GLXcontextRec {
    tsr_faker_context *ctx;
    Display *dpy;
    const struct __GLXFBConfigRec *config;
    GLXDrawable draw, read;
    bool destroyed; /* glXDestroyContext while current: freed at release */
};

typedef struct glx_display {
    Display *dpy;
    struct __GLXFBConfigRec *configs; /* every screen's, TSR_FAKER_FORMATS each */
    int nconfigs;
} glx_display;

static pthread_mutex_t glx_lock = PTHREAD_MUTEX_INITIALIZER;
static glx_display displays[MAX_DISPLAYS];
static int ndisplays;
static _Thread_local GLXContext cur;
static _Thread_local Display *cur_dpy;

static const char glx_extensions[] = "GLX_ARB_create_context GLX_ARB_create_context_profile "
                                     "GLX_ARB_get_proc_address GLX_EXT_swap_control GLX_EXT_visual_rating "
                                     "GLX_MESA_swap_control GLX_SGI_swap_control";

/* Every format of configs.c on every screen: format i takes the screen's
 * i-th usable visual, or shares one round the list when the screen has
 * fewer (an X server without GLX has one or two): no cap tied to the
 * number of visuals, and a visual's first config is its own. */
static void make_configs(glx_display *d)
{
    int screens = ScreenCount(d->dpy);
    d->configs = calloc((size_t)screens * TSR_FAKER_FORMATS, sizeof *d->configs);
    d->nconfigs = 0;
    for (int screen = 0; d->configs && screen < screens; screen++) {
        XVisualInfo *vis = NULL;
        int nvis = tsr_faker_visuals(d->dpy, screen, &vis);
        for (int i = 0; i < TSR_FAKER_FORMATS && nvis; i++) {
            struct __GLXFBConfigRec *c = &d->configs[d->nconfigs];
            *c = (struct __GLXFBConfigRec){.id = d->nconfigs + 1,
                                           .screen = screen,
                                           .visual = vis[i % nvis].visualid,
                                           .depth = vis[i % nvis].depth,
                                           .primary = i < nvis,
                                           .f = *tsr_faker_format_at(i)};
            d->nconfigs++;
        }
        free(vis);
    }
    if (!d->nconfigs)
        tsr_faker_log(TSR_LOG_ERROR, "display %s has no TrueColor visual of depth 24 or 32", DisplayString(d->dpy));
}

/* The configs of `dpy` (made on first use). */
static glx_display *display_of(Display *dpy)
{
    pthread_mutex_lock(&glx_lock);
    glx_display *d = NULL;
    for (int i = 0; i < ndisplays; i++)
        if (displays[i].dpy == dpy)
            d = &displays[i];
    if (!d && ndisplays < MAX_DISPLAYS) {
        d = &displays[ndisplays++];
        d->dpy = dpy;
        make_configs(d);
    }
    pthread_mutex_unlock(&glx_lock);
    return d;
}

static int config_attrib(const struct __GLXFBConfigRec *c, int attribute, int *value)
{
    switch (attribute) {
    case GLX_FBCONFIG_ID: *value = c->id; break;
    case GLX_BUFFER_SIZE: *value = 24 + c->f.alpha; break;
    case GLX_LEVEL: *value = 0; break;
    case GLX_DOUBLEBUFFER: *value = c->f.doublebuffer; break;
    case GLX_STEREO: *value = 0; break;
    case GLX_AUX_BUFFERS: *value = 0; break;
    case GLX_RED_SIZE:
    case GLX_GREEN_SIZE:
    case GLX_BLUE_SIZE: *value = 8; break;
    case GLX_ALPHA_SIZE: *value = c->f.alpha; break;
    case GLX_DEPTH_SIZE: *value = c->f.depth; break;
    case GLX_STENCIL_SIZE: *value = c->f.stencil; break;
    case GLX_ACCUM_RED_SIZE:
    case GLX_ACCUM_GREEN_SIZE:
    case GLX_ACCUM_BLUE_SIZE:
    case GLX_ACCUM_ALPHA_SIZE: *value = c->f.accum; break;
    case GLX_RENDER_TYPE: *value = GLX_RGBA_BIT; break;
    case GLX_DRAWABLE_TYPE: *value = GLX_WINDOW_BIT | GLX_PBUFFER_BIT | GLX_PIXMAP_BIT; break;
    case GLX_X_RENDERABLE: *value = True; break;
    case GLX_VISUAL_ID: *value = (int)c->visual; break;
    case GLX_X_VISUAL_TYPE: *value = GLX_TRUE_COLOR; break;
    /* Accumulation is drawn in software, as Mesa's GLX says of its own. */
    case GLX_CONFIG_CAVEAT: *value = c->f.accum ? GLX_SLOW_CONFIG : GLX_NONE; break;
    case GLX_TRANSPARENT_TYPE: *value = GLX_NONE; break;
    case GLX_TRANSPARENT_INDEX_VALUE:
    case GLX_TRANSPARENT_RED_VALUE:
    case GLX_TRANSPARENT_GREEN_VALUE:
    case GLX_TRANSPARENT_BLUE_VALUE:
    case GLX_TRANSPARENT_ALPHA_VALUE: *value = 0; break;
    case GLX_MAX_PBUFFER_WIDTH:
    case GLX_MAX_PBUFFER_HEIGHT: *value = GLX_MAX_OFFSCREEN_SIDE; break;
    case GLX_MAX_PBUFFER_PIXELS: *value = GLX_MAX_OFFSCREEN_SIDE * GLX_MAX_OFFSCREEN_SIDE; break;
    case GLX_SAMPLE_BUFFERS: *value = c->f.samples > 0; break;
    case GLX_SAMPLES: *value = c->f.samples; break;
    case GLX_SCREEN: *value = c->screen; break;
    case GLX_USE_GL: *value = True; break;
    case GLX_RGBA: *value = True; break;
    case GLX_FRAMEBUFFER_SRGB_CAPABLE_ARB: *value = False; break;
    default: return GLX_BAD_ATTRIBUTE;
    }
    return Success;
}

/* Does config c satisfy `want` = value (glXChooseFBConfig's rules)? */
static bool config_matches(const struct __GLXFBConfigRec *c, int attribute, int want)
{
    int have = 0;
    if (want == (int)GLX_DONT_CARE)
        return true;
    switch (attribute) {
    case GLX_BUFFER_SIZE:
    case GLX_RED_SIZE:
    case GLX_GREEN_SIZE:
    case GLX_BLUE_SIZE:
    case GLX_ALPHA_SIZE:
    case GLX_DEPTH_SIZE:
    case GLX_STENCIL_SIZE:
    case GLX_ACCUM_RED_SIZE:
    case GLX_ACCUM_GREEN_SIZE:
    case GLX_ACCUM_BLUE_SIZE:
    case GLX_ACCUM_ALPHA_SIZE:
    case GLX_AUX_BUFFERS:
    case GLX_SAMPLE_BUFFERS:
    case GLX_SAMPLES: config_attrib(c, attribute, &have); return have >= want; /* minimums */
    case GLX_RENDER_TYPE:
    case GLX_DRAWABLE_TYPE: config_attrib(c, attribute, &have); return (have & want) == want; /* masks */
    case GLX_CONFIG_CAVEAT:
    case GLX_TRANSPARENT_TYPE:
    case GLX_DOUBLEBUFFER:
    case GLX_STEREO:
    case GLX_X_RENDERABLE:
    case GLX_X_VISUAL_TYPE:
    case GLX_LEVEL:
    case GLX_FBCONFIG_ID:
    case GLX_VISUAL_ID: config_attrib(c, attribute, &have); return have == want; /* exact */
    case GLX_FRAMEBUFFER_SRGB_CAPABLE_ARB: return !want;
    default: return true; /* ignored */
    }
}

/* A size where a request of 0 prefers none and any other the largest
 * (GLX 1.4's colour, alpha, depth and accumulation rules). */
static int larger_or_zero(int a, int b)
{
    if (a == b)
        return 0;
    if (a == 0 || b == 0)
        return a == 0 ? -1 : 1;
    return b - a;
}

/* GLX 1.4's sort order (glXChooseFBConfig, table 3.4): caveat, colour
 * (red, green, blue are 8 everywhere), alpha, buffer size (smaller),
 * single before double buffer, depth, stencil (smaller), accumulation,
 * sample buffers and samples (smaller: single-sampled first); then the
 * config id, so the order is the same on every run. */
static int config_order(const void *pa, const void *pb)
{
    const struct __GLXFBConfigRec *a = *(const struct __GLXFBConfigRec *const *)pa;
    const struct __GLXFBConfigRec *b = *(const struct __GLXFBConfigRec *const *)pb;
    int d;
    if ((d = (a->f.accum != 0) - (b->f.accum != 0)))
        return d;
    if ((d = larger_or_zero(a->f.alpha, b->f.alpha)))
        return d;
    if ((d = a->f.alpha - b->f.alpha))
        return d;
    if ((d = (int)a->f.doublebuffer - (int)b->f.doublebuffer))
        return d;
    if ((d = larger_or_zero(a->f.depth, b->f.depth)))
        return d;
    if ((d = a->f.stencil - b->f.stencil))
        return d;
    if ((d = larger_or_zero(a->f.accum, b->f.accum)))
        return d;
    if ((d = (a->f.samples > 0) - (b->f.samples > 0)))
        return d;
    if ((d = a->f.samples - b->f.samples))
        return d;
    return a->id - b->id;
}

/* The config a visual stands for (its first), or NULL: not the faker's. */
static const struct __GLXFBConfigRec *find_visual_config(glx_display *d, VisualID visual)
{
    for (int i = 0; d && i < d->nconfigs; i++)
        if (d->configs[i].visual == visual && d->configs[i].primary)
            return &d->configs[i];
    return NULL;
}

static XVisualInfo *visual_info(Display *dpy, const struct __GLXFBConfigRec *c)
{
    if (!c)
        return NULL;
    XVisualInfo tmpl = {.visualid = c->visual, .screen = c->screen};
    int n = 0;
    return XGetVisualInfo(dpy, VisualIDMask | VisualScreenMask, &tmpl, &n);
}

/* --- visuals and FBConfigs ----------------------------------------------- */

GLXFBConfig *glXGetFBConfigs(Display *dpy, int screen, int *nelements)
{
    glx_display *d = display_of(dpy);
    int n = 0;
    GLXFBConfig *list = d ? malloc(((size_t)d->nconfigs + 1) * sizeof *list) : NULL;
    for (int i = 0; list && i < d->nconfigs; i++)
        if (d->configs[i].screen == screen)
            list[n++] = &d->configs[i];
    if (nelements)
        *nelements = n;
    if (list && !n) {
        free(list);
        list = NULL;
    }
    return list;
}

GLXFBConfig *glXChooseFBConfig(Display *dpy, int screen, const int *attrib_list, int *nelements)
{
    int n = 0;
    GLXFBConfig *all = glXGetFBConfigs(dpy, screen, &n), *out = all;
    /* GLX_FBCONFIG_ID given: every other attribute is ignored. */
    int by_id = (int)GLX_DONT_CARE;
    for (const int *a = attrib_list; a && a[0] != None; a += 2)
        if (a[0] == GLX_FBCONFIG_ID)
            by_id = a[1];
    int kept = 0;
    for (int i = 0; all && i < n; i++) {
        bool ok = true;
        if (by_id != (int)GLX_DONT_CARE)
            ok = all[i]->id == by_id;
        else
            for (const int *a = attrib_list; a && a[0] != None; a += 2)
                if (!config_matches(all[i], a[0], a[1]))
                    ok = false;
        if (ok)
            out[kept++] = all[i];
    }
    if (nelements)
        *nelements = kept;
    if (!kept) {
        free(all);
        return NULL;
    }
    qsort(out, (size_t)kept, sizeof *out, config_order);
    return out;
}

int glXGetFBConfigAttrib(Display *dpy, GLXFBConfig config, int attribute, int *value)
{
    (void)dpy;
    if (!config || !value)
        return GLX_BAD_ATTRIBUTE;
    return config_attrib(config, attribute, value);
}

/* Config c becomes what its visual stands for (see `primary`). */
static void hand_out(glx_display *d, const struct __GLXFBConfigRec *c)
{
    pthread_mutex_lock(&glx_lock);
    for (int i = 0; d && c && i < d->nconfigs; i++)
        if (d->configs[i].visual == c->visual && d->configs[i].screen == c->screen)
            d->configs[i].primary = &d->configs[i] == c;
    pthread_mutex_unlock(&glx_lock);
}

XVisualInfo *glXGetVisualFromFBConfig(Display *dpy, GLXFBConfig config)
{
    glx_display *d = display_of(dpy);
    hand_out(d, config);
    return visual_info(dpy, config);
}

/* The best of d's configs on `screen` for glXChooseVisual's list `want`
 * (GLX 1.2: double buffering exact, absent meaning single). */
static const struct __GLXFBConfigRec *choose_visual_config(glx_display *d, int screen, bool db, int want[][2],
                                                           int nwant)
{
    const struct __GLXFBConfigRec *best = NULL;
    for (int i = 0; d && i < d->nconfigs; i++) {
        const struct __GLXFBConfigRec *c = &d->configs[i];
        if (c->screen != screen || c->f.doublebuffer != db)
            continue;
        bool ok = true;
        for (int k = 0; k < nwant; k++)
            if (!config_matches(c, want[k][0], want[k][1]))
                ok = false;
        if (ok && (!best || config_order(&c, &best) < 0))
            best = c;
    }
    return best;
}

XVisualInfo *glXChooseVisual(Display *dpy, int screen, int *attribList)
{
    glx_display *d = display_of(dpy);
    bool rgba = false, db = false;
    int want[64][2];
    int nwant = 0;
    for (int *a = attribList; a && *a != None; a++) {
        switch (*a) {
        case GLX_USE_GL: break;
        case GLX_RGBA: rgba = true; break;
        case GLX_DOUBLEBUFFER: db = true; break;
        case GLX_STEREO:
            want[nwant][0] = GLX_STEREO;
            want[nwant][1] = 1;
            nwant++;
            break;
        default:
            if (nwant < 64) {
                want[nwant][0] = a[0];
                want[nwant][1] = a[1];
                nwant++;
            }
            a++;
        }
    }
    if (!rgba) { /* as Mesa: no colour-index visual, an RGBA one instead */
        static atomic_flag told = ATOMIC_FLAG_INIT;
        if (!atomic_flag_test_and_set(&told))
            tsr_faker_log(TSR_LOG_INFO, "glXChooseVisual without GLX_RGBA: colour index is not supported, an RGBA "
                                        "visual is chosen, as Mesa does (logged once)");
    }
    /* On a screen with fewer visuals than formats, a shared visual then
     * stands for the config chosen. */
    const struct __GLXFBConfigRec *c = choose_visual_config(d, screen, db, want, nwant);
    hand_out(d, c);
    return visual_info(dpy, c);
}

int glXGetConfig(Display *dpy, XVisualInfo *visual, int attrib, int *value)
{
    glx_display *d = display_of(dpy);
    const struct __GLXFBConfigRec *c = visual ? find_visual_config(d, visual->visualid) : NULL;
    if (!c) {
        if (attrib == GLX_USE_GL && value) {
            *value = False;
            return Success;
        }
        return GLX_BAD_VISUAL;
    }
    if (!value)
        return GLX_BAD_VALUE;
    return config_attrib(c, attrib, value) == Success ? Success : GLX_BAD_ATTRIBUTE;
}

/* The surface of a drawable; the first time, the application's requests
 * are made to reach the server first (XSync on its connection, the round
 * trip a real glXMakeCurrent makes; no event is read or dropped), so a
 * window it has just created exists for the faker's own connection. */
/* GLX pbuffers and pixmaps: off-screen tessera drawables of their size
 * (pbuffer surfaces of the core), named by an XID the application's
 * display allocates (XAllocID: taken from the client's own id range, no
 * request sent, so it never collides with the program's windows and
 * pixmaps). What is drawn into a GLX pixmap reaches the stream and its
 * frames, never the X pixmap: the faker draws nothing on the X server. */
typedef struct glx_offscreen {
    XID id;
    Display *dpy;
    tsr_faker_surface *s;
    const struct __GLXFBConfigRec *config;
    int width, height; /* as the program asked (a pbuffer) or the X pixmap's */
    bool pbuffer;      /* else a GLX pixmap */
    bool largest;      /* GLX_LARGEST_PBUFFER */
    bool preserved;    /* GLX_PRESERVED_CONTENTS */
    struct glx_offscreen *next;
} glx_offscreen;

static glx_offscreen *offscreens;

static glx_offscreen *offscreen_find_locked(Display *dpy, XID id)
{
    for (glx_offscreen *o = offscreens; o; o = o->next)
        if (o->id == id && o->dpy == dpy)
            return o;
    return NULL;
}

static glx_offscreen *offscreen_find(Display *dpy, XID id)
{
    pthread_mutex_lock(&glx_lock);
    glx_offscreen *o = id ? offscreen_find_locked(dpy, id) : NULL;
    pthread_mutex_unlock(&glx_lock);
    return o;
}

static tsr_faker_surface *drawable_surface(Display *dpy, GLXDrawable draw)
{
    glx_offscreen *o = offscreen_find(dpy, draw);
    if (o)
        return o->s;
    tsr_faker_surface *s = tsr_faker_surface_find(draw);
    if (s)
        return s;
    XSync(dpy, False);
    return tsr_faker_surface_window(DisplayString(dpy), draw);
}

/* --- contexts ------------------------------------------------------------ */

static GLXContext context_new(Display *dpy, const struct __GLXFBConfigRec *config, GLXContext share)
{
    GLXContext g = calloc(1, sizeof *g);
    if (!g)
        return NULL;
    g->ctx = tsr_faker_context_create(share ? share->ctx : NULL);
    if (!g->ctx) {
        free(g);
        return NULL;
    }
    g->dpy = dpy;
    g->config = config;
    return g;
}

GLXContext glXCreateContext(Display *dpy, XVisualInfo *vis, GLXContext shareList, Bool direct)
{
    (void)direct;
    glx_display *d = display_of(dpy);
    const struct __GLXFBConfigRec *c = vis ? find_visual_config(d, vis->visualid) : NULL;
    if (!c) {
        tsr_faker_log(TSR_LOG_ERROR, "glXCreateContext: visual 0x%lx is not one of the faker's",
                      vis ? (unsigned long)vis->visualid : 0ul);
        return NULL;
    }
    return context_new(dpy, c, shareList);
}

GLXContext glXCreateNewContext(Display *dpy, GLXFBConfig config, int renderType, GLXContext shareList, Bool direct)
{
    (void)direct;
    if (renderType != GLX_RGBA_TYPE || !config) {
        tsr_faker_log(TSR_LOG_ERROR, "glXCreateNewContext: only GLX_RGBA_TYPE with a config");
        return NULL;
    }
    return context_new(dpy, config, shareList);
}

GLXContext glXCreateContextAttribsARB(Display *dpy, GLXFBConfig config, GLXContext share_context, Bool direct,
                                      const int *attrib_list)
{
    (void)direct;
    int major = 1, minor = 0;
    for (const int *a = attrib_list; a && a[0] != None; a += 2) {
        if (a[0] == GLX_CONTEXT_MAJOR_VERSION_ARB)
            major = a[1];
        else if (a[0] == GLX_CONTEXT_MINOR_VERSION_ARB)
            minor = a[1];
        else if (a[0] == GLX_CONTEXT_PROFILE_MASK_ARB && a[1] == GLX_CONTEXT_ES2_PROFILE_BIT_EXT) {
            tsr_faker_log(TSR_LOG_ERROR, "glXCreateContextAttribsARB: OpenGL ES is not supported");
            return NULL;
        }
    }
    if (major > 2 || (major == 2 && minor > 1)) {
        tsr_faker_log(TSR_LOG_INFO, "glXCreateContextAttribsARB: OpenGL %d.%d asked, tessera has 2.1", major, minor);
        return NULL;
    }
    if (!config)
        return NULL;
    return context_new(dpy, config, share_context);
}

void glXDestroyContext(Display *dpy, GLXContext ctx)
{
    (void)dpy;
    if (!ctx)
        return;
    tsr_faker_context_destroy(ctx->ctx);
    if (cur == ctx) { /* freed at release; the faker context lives until then */
        ctx->destroyed = true;
        return;
    }
    free(ctx);
}

Bool glXMakeContextCurrent(Display *dpy, GLXDrawable draw, GLXDrawable read, GLXContext ctx)
{
    GLXContext old = cur;
    if (!ctx) {
        tsr_faker_make_current(NULL, NULL);
        if (old && old->destroyed)
            free(old);
        cur = NULL;
        cur_dpy = NULL;
        return True;
    }
    if (!draw) {
        tsr_faker_log(TSR_LOG_ERROR, "glXMakeCurrent: no drawable");
        return False;
    }
    if (read && read != draw)
        tsr_faker_log(TSR_LOG_WARN, "glXMakeContextCurrent: a read drawable other than the draw one is ignored");
    tsr_faker_surface *s = drawable_surface(dpy, draw);
    /* A window has the back buffer its config has (pbuffers and pixmaps
     * are single-buffered here); every drawable its samples. */
    if (s && ctx->config)
        tsr_faker_surface_set_config(s, ctx->config->f.doublebuffer && !offscreen_find(dpy, draw),
                                     ctx->config->f.samples);
    if (!s || !tsr_faker_make_current(ctx->ctx, s))
        return False;
    if (old && old != ctx && old->destroyed)
        free(old);
    cur = ctx;
    cur_dpy = dpy;
    ctx->draw = draw;
    ctx->read = read ? read : draw;
    return True;
}

Bool glXMakeCurrent(Display *dpy, GLXDrawable drawable, GLXContext ctx)
{
    return glXMakeContextCurrent(dpy, drawable, drawable, ctx);
}

void glXCopyContext(Display *dpy, GLXContext src, GLXContext dst, unsigned long mask)
{
    (void)dpy, (void)src, (void)dst, (void)mask;
    tsr_faker_log(TSR_LOG_WARN, "glXCopyContext is not supported: ignored");
}

int glXQueryContext(Display *dpy, GLXContext ctx, int attribute, int *value)
{
    (void)dpy;
    if (!ctx || !value)
        return GLX_BAD_CONTEXT;
    switch (attribute) {
    case GLX_FBCONFIG_ID: *value = ctx->config->id; return Success;
    case GLX_RENDER_TYPE: *value = GLX_RGBA_TYPE; return Success;
    case GLX_SCREEN: *value = ctx->config->screen; return Success;
    default: return GLX_BAD_ATTRIBUTE;
    }
}

Bool glXIsDirect(Display *dpy, GLXContext ctx)
{
    (void)dpy, (void)ctx;
    return True;
}

GLXContext glXGetCurrentContext(void) { return cur; }
GLXDrawable glXGetCurrentDrawable(void) { return cur ? cur->draw : None; }
GLXDrawable glXGetCurrentReadDrawable(void) { return cur ? cur->read : None; }
Display *glXGetCurrentDisplay(void) { return cur_dpy; }

/* --- drawables ----------------------------------------------------------- */

void glXSwapBuffers(Display *dpy, GLXDrawable drawable)
{
    static atomic_flag warned = ATOMIC_FLAG_INIT;
    if (!tsr_faker_current_context()) {
        if (!atomic_flag_test_and_set(&warned))
            tsr_faker_log(TSR_LOG_WARN, "glXSwapBuffers with no current context: ignored (logged once)");
        return;
    }
    if (offscreen_find(dpy, drawable))
        return; /* a pbuffer or pixmap: no effect (GLX 1.4, 3.3.10) */
    tsr_faker_surface *s = drawable_surface(dpy, drawable);
    if (!s)
        return;
    tsr_faker_swap(s);
}

GLXWindow glXCreateWindow(Display *dpy, GLXFBConfig config, Window win, const int *attribList)
{
    (void)dpy, (void)config, (void)attribList;
    return win;
}

void glXDestroyWindow(Display *dpy, GLXWindow window)
{
    (void)dpy;
    tsr_faker_surface_destroy(tsr_faker_surface_find(window));
}

/* --- pbuffers and pixmaps ------------------------------------------------ */

/* A config of dpy's table, or NULL (logged, naming the caller). */
static const struct __GLXFBConfigRec *known_config(Display *dpy, GLXFBConfig config, const char *caller)
{
    glx_display *d = display_of(dpy);
    for (int i = 0; d && i < d->nconfigs; i++)
        if (config == &d->configs[i])
            return config;
    tsr_faker_log(TSR_LOG_ERROR, "%s: not a GLXFBConfig of this display", caller);
    return NULL;
}

static XID offscreen_add(Display *dpy, const struct __GLXFBConfigRec *c, int w, int h, bool pbuffer, bool largest,
                         bool preserved, const char *caller)
{
    glx_offscreen *o = calloc(1, sizeof *o);
    tsr_faker_surface *s = o ? tsr_faker_surface_pbuffer(w, h) : NULL;
    if (!s) {
        free(o);
        tsr_faker_log(TSR_LOG_ERROR, "%s: out of memory", caller);
        return None;
    }
    *o = (glx_offscreen){.dpy = dpy,
                         .s = s,
                         .config = c,
                         .width = w,
                         .height = h,
                         .pbuffer = pbuffer,
                         .largest = largest,
                         .preserved = preserved};
    XLockDisplay(dpy);
    o->id = XAllocID(dpy);
    XUnlockDisplay(dpy);
    pthread_mutex_lock(&glx_lock);
    o->next = offscreens;
    offscreens = o;
    pthread_mutex_unlock(&glx_lock);
    return o->id;
}

/* Destroys the off-screen drawable `id` of the given kind; false: none. */
static bool offscreen_destroy(Display *dpy, XID id, bool pbuffer)
{
    pthread_mutex_lock(&glx_lock);
    glx_offscreen *o = NULL;
    for (glx_offscreen **p = &offscreens; *p; p = &(*p)->next)
        if ((*p)->id == id && (*p)->dpy == dpy && (*p)->pbuffer == pbuffer) {
            o = *p;
            *p = o->next;
            break;
        }
    pthread_mutex_unlock(&glx_lock);
    if (!o)
        return false;
    tsr_faker_surface_destroy(o->s);
    free(o);
    return true;
}

GLXPbuffer glXCreatePbuffer(Display *dpy, GLXFBConfig config, const int *attrib_list)
{
    const struct __GLXFBConfigRec *c = known_config(dpy, config, "glXCreatePbuffer");
    if (!c)
        return None;
    int w = 0, h = 0; /* GLX 1.4's defaults */
    bool largest = false, preserved = true;
    for (const int *a = attrib_list; a && a[0] != None; a += 2) {
        switch (a[0]) {
        case GLX_PBUFFER_WIDTH: w = a[1]; break;
        case GLX_PBUFFER_HEIGHT: h = a[1]; break;
        case GLX_LARGEST_PBUFFER: largest = a[1] != 0; break;
        case GLX_PRESERVED_CONTENTS: preserved = a[1] != 0; break;
        default: tsr_faker_log(TSR_LOG_ERROR, "glXCreatePbuffer: unknown attribute 0x%x", (unsigned)a[0]); return None;
        }
    }
    if (w < 0 || h < 0) {
        tsr_faker_log(TSR_LOG_ERROR, "glXCreatePbuffer: size %dx%d", w, h);
        return None;
    }
    if (w > GLX_MAX_OFFSCREEN_SIDE || h > GLX_MAX_OFFSCREEN_SIDE) {
        if (!largest) {
            tsr_faker_log(TSR_LOG_ERROR, "glXCreatePbuffer: %dx%d is over the largest pbuffer, %dx%d", w, h,
                          GLX_MAX_OFFSCREEN_SIDE, GLX_MAX_OFFSCREEN_SIDE);
            return None;
        }
        w = w > GLX_MAX_OFFSCREEN_SIDE ? GLX_MAX_OFFSCREEN_SIDE : w;
        h = h > GLX_MAX_OFFSCREEN_SIDE ? GLX_MAX_OFFSCREEN_SIDE : h;
    }
    return offscreen_add(dpy, c, w, h, true, largest, preserved, "glXCreatePbuffer");
}

void glXDestroyPbuffer(Display *dpy, GLXPbuffer pbuf)
{
    if (!offscreen_destroy(dpy, pbuf, true))
        tsr_faker_log(TSR_LOG_ERROR, "glXDestroyPbuffer: 0x%lx is not a GLXPbuffer", (unsigned long)pbuf);
}

/* A GLX pixmap of X pixmap `pixmap`: its size and depth are read over the
 * faker's connection (after the program's requests reached the server),
 * and its depth must be the config's, as GLX requires. */
static GLXPixmap pixmap_new(Display *dpy, const struct __GLXFBConfigRec *c, Pixmap pixmap, const char *caller)
{
    int w = 0, h = 0, depth = 0;
    XSync(dpy, False);
    if (!tsr_faker_drawable_geometry(DisplayString(dpy), pixmap, &w, &h, &depth)) {
        tsr_faker_log(TSR_LOG_ERROR, "%s: pixmap 0x%lx: cannot read its size (no such pixmap?)", caller,
                      (unsigned long)pixmap);
        return None;
    }
    if (depth != c->depth && depth != 24 + c->f.alpha) { /* its visual's, or its GLX_BUFFER_SIZE */
        tsr_faker_log(TSR_LOG_ERROR, "%s: pixmap 0x%lx has depth %d, its config depth %d", caller,
                      (unsigned long)pixmap, depth, c->depth);
        return None;
    }
    return offscreen_add(dpy, c, w, h, false, false, true, caller);
}

GLXPixmap glXCreatePixmap(Display *dpy, GLXFBConfig config, Pixmap pixmap, const int *attrib_list)
{
    const struct __GLXFBConfigRec *c = known_config(dpy, config, "glXCreatePixmap");
    if (!c)
        return None;
    if (attrib_list && attrib_list[0] != None) {
        tsr_faker_log(TSR_LOG_ERROR, "glXCreatePixmap: unknown attribute 0x%x", (unsigned)attrib_list[0]);
        return None;
    }
    return pixmap_new(dpy, c, pixmap, "glXCreatePixmap");
}

void glXDestroyPixmap(Display *dpy, GLXPixmap pixmap)
{
    if (!offscreen_destroy(dpy, pixmap, false))
        tsr_faker_log(TSR_LOG_ERROR, "glXDestroyPixmap: 0x%lx is not a GLXPixmap", (unsigned long)pixmap);
}

GLXPixmap glXCreateGLXPixmap(Display *dpy, XVisualInfo *visual, Pixmap pixmap)
{
    glx_display *d = display_of(dpy);
    /* The visual's config as glXGetConfig answers for it. */
    const struct __GLXFBConfigRec *c = visual ? find_visual_config(d, visual->visualid) : NULL;
    if (!c) {
        tsr_faker_log(TSR_LOG_ERROR, "glXCreateGLXPixmap: not a visual of the faker's configs");
        return None;
    }
    return pixmap_new(dpy, c, pixmap, "glXCreateGLXPixmap");
}

void glXDestroyGLXPixmap(Display *dpy, GLXPixmap pixmap)
{
    if (!offscreen_destroy(dpy, pixmap, false))
        tsr_faker_log(TSR_LOG_ERROR, "glXDestroyGLXPixmap: 0x%lx is not a GLXPixmap", (unsigned long)pixmap);
}

void glXQueryDrawable(Display *dpy, GLXDrawable draw, int attribute, unsigned int *value)
{
    if (!value)
        return;
    glx_offscreen *o = offscreen_find(dpy, draw);
    if (o) {
        switch (attribute) {
        case GLX_WIDTH: *value = (unsigned)o->width; break;
        case GLX_HEIGHT: *value = (unsigned)o->height; break;
        case GLX_PRESERVED_CONTENTS: *value = o->pbuffer && o->preserved; break;
        case GLX_LARGEST_PBUFFER: *value = o->pbuffer && o->largest; break;
        case GLX_FBCONFIG_ID: *value = (unsigned)o->config->id; break;
        default: *value = 0; break;
        }
        return;
    }
    tsr_faker_surface *s = drawable_surface(dpy, draw);
    int w = 0, h = 0;
    if (attribute == GLX_WIDTH || attribute == GLX_HEIGHT) {
        XSync(dpy, False); /* the program's XResizeWindow reaches the server first */
        tsr_faker_surface_x_size(s, &w, &h);
    }
    switch (attribute) {
    case GLX_WIDTH: *value = (unsigned)w; break;
    case GLX_HEIGHT: *value = (unsigned)h; break;
    case GLX_PRESERVED_CONTENTS:
    case GLX_LARGEST_PBUFFER: *value = 0; break;
    case GLX_FBCONFIG_ID: *value = cur && cur->draw == draw ? (unsigned)cur->config->id : 1u; break;
    case GLX_SWAP_INTERVAL_EXT: *value = 0; break;
    case GLX_MAX_SWAP_INTERVAL_EXT: *value = 1; break;
    default: *value = 0; break;
    }
}

void glXSelectEvent(Display *dpy, GLXDrawable draw, unsigned long event_mask)
{
    (void)dpy, (void)draw, (void)event_mask; /* no GLX events: nothing to select */
}

void glXGetSelectedEvent(Display *dpy, GLXDrawable draw, unsigned long *event_mask)
{
    (void)dpy, (void)draw;
    if (event_mask)
        *event_mask = 0;
}

void glXWaitGL(void) { tsr_faker_finish(); }
void glXWaitX(void)
{ /* the faker draws nothing on the X server */
}

/* Swap intervals: accepted, no effect (frames are not paced). */
void glXSwapIntervalEXT(Display *dpy, GLXDrawable drawable, int interval) { (void)dpy, (void)drawable, (void)interval; }
int glXSwapIntervalMESA(unsigned int interval)
{
    (void)interval;
    return 0;
}
int glXGetSwapIntervalMESA(void) { return 0; }
int glXSwapIntervalSGI(int interval) { return interval <= 0 ? GLX_BAD_VALUE : 0; }

/* --- strings and versions ------------------------------------------------ */

Bool glXQueryExtension(Display *dpy, int *errorb, int *event)
{
    (void)dpy;
    if (errorb)
        *errorb = 0;
    if (event)
        *event = 0;
    return True;
}

Bool glXQueryVersion(Display *dpy, int *maj, int *min)
{
    (void)dpy;
    if (maj)
        *maj = 1;
    if (min)
        *min = 4;
    return True;
}

const char *glXQueryExtensionsString(Display *dpy, int screen)
{
    (void)dpy, (void)screen;
    return glx_extensions;
}

const char *glXQueryServerString(Display *dpy, int screen, int name)
{
    (void)dpy, (void)screen;
    switch (name) {
    case GLX_VENDOR: return "tessera";
    case GLX_VERSION: return "1.4";
    case GLX_EXTENSIONS: return glx_extensions;
    default: return NULL;
    }
}

const char *glXGetClientString(Display *dpy, int name) { return glXQueryServerString(dpy, 0, name); }

/* --- GetProcAddress ------------------------------------------------------ */

#define P(name)                     \
    {                               \
#name, (void (*)(void))name \
    }
/* Every exported glX*, sorted (strcmp). */
static const tsr_faker_proc glx_procs[] = {
    P(glXChooseFBConfig),
    P(glXChooseVisual),
    P(glXCopyContext),
    P(glXCreateContext),
    P(glXCreateContextAttribsARB),
    P(glXCreateGLXPixmap),
    P(glXCreateNewContext),
    P(glXCreatePbuffer),
    P(glXCreatePixmap),
    P(glXCreateWindow),
    P(glXDestroyContext),
    P(glXDestroyGLXPixmap),
    P(glXDestroyPbuffer),
    P(glXDestroyPixmap),
    P(glXDestroyWindow),
    P(glXGetClientString),
    P(glXGetConfig),
    P(glXGetCurrentContext),
    P(glXGetCurrentDisplay),
    P(glXGetCurrentDrawable),
    P(glXGetCurrentReadDrawable),
    P(glXGetFBConfigAttrib),
    P(glXGetFBConfigs),
    P(glXGetProcAddress),
    P(glXGetProcAddressARB),
    P(glXGetSelectedEvent),
    P(glXGetSwapIntervalMESA),
    P(glXGetVisualFromFBConfig),
    P(glXIsDirect),
    P(glXMakeContextCurrent),
    P(glXMakeCurrent),
    P(glXQueryContext),
    P(glXQueryDrawable),
    P(glXQueryExtension),
    P(glXQueryExtensionsString),
    P(glXQueryServerString),
    P(glXQueryVersion),
    P(glXSelectEvent),
    P(glXSwapBuffers),
    P(glXSwapIntervalEXT),
    P(glXSwapIntervalMESA),
    P(glXSwapIntervalSGI),
    P(glXWaitGL),
    P(glXWaitX),
};
#undef P

__GLXextFuncPtr glXGetProcAddressARB(const GLubyte *procName)
{
    const char *name = (const char *)procName;
    if (!name)
        return NULL;
    void (*p)(void) = tsr_faker_lookup(glx_procs, sizeof glx_procs / sizeof glx_procs[0], name);
    return p ? p : tsr_faker_gl_proc(name);
}

__GLXextFuncPtr glXGetProcAddress(const GLubyte *procName) { return glXGetProcAddressARB(procName); }
