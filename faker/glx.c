/* faker/glx.c — GLX 1.4 of the faker's libGL.so.1, on faker/core.c. Never
 * sends a GLX request: visuals and FBConfigs are the X server's TrueColor
 * visuals of depth 24 and 32 (two configs each, double- and
 * single-buffered; RGB 8 8 8, alpha 8 on depth 32, depth 24, stencil 8, no
 * accum, no multisample, as the render SPU draws), read from the
 * application's Display structure without a round trip. Contexts are
 * faker contexts; GLX windows are the X windows themselves. Swap-interval
 * calls are accepted and have no effect. */
#define GLX_GLXEXT_PROTOTYPES 1
#include <GL/glx.h>
#include <GL/glxext.h>
#include <X11/Xutil.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "faker_gl.h"
#include "tessera/log.h"

#define MAX_CONFIGS 64
#define MAX_DISPLAYS 8

struct __GLXFBConfigRec {
    int id; /* GLX_FBCONFIG_ID, from 1 */
    int screen;
    VisualID visual;
    int depth; /* of the visual: 24 or 32 */
    bool doublebuffer;
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
    struct __GLXFBConfigRec configs[MAX_CONFIGS];
    int nconfigs;
} glx_display;

static pthread_mutex_t glx_lock = PTHREAD_MUTEX_INITIALIZER;
static glx_display displays[MAX_DISPLAYS];
static int ndisplays;
static _Thread_local GLXContext cur;
static _Thread_local Display *cur_dpy;

static const char glx_extensions[] = "GLX_ARB_create_context GLX_ARB_create_context_profile "
                                     "GLX_ARB_get_proc_address GLX_EXT_swap_control "
                                     "GLX_MESA_swap_control GLX_SGI_swap_control";

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
        d->nconfigs = 0;
        for (int screen = 0; screen < ScreenCount(dpy); screen++) {
            static const int depths[] = {24, 32};
            for (int k = 0; k < 2; k++) {
                XVisualInfo tmpl = {.screen = screen, .depth = depths[k], .class = TrueColor};
                int n = 0;
                XVisualInfo *vis = XGetVisualInfo(dpy, VisualScreenMask | VisualDepthMask | VisualClassMask, &tmpl, &n);
                for (int v = 0; v < n; v++) {
                    if (vis[v].bits_per_rgb != 8 || d->nconfigs + 2 > MAX_CONFIGS)
                        continue;
                    for (int db = 1; db >= 0; db--) {
                        struct __GLXFBConfigRec *c = &d->configs[d->nconfigs];
                        c->id = d->nconfigs + 1;
                        c->screen = screen;
                        c->visual = vis[v].visualid;
                        c->depth = vis[v].depth;
                        c->doublebuffer = db;
                        d->nconfigs++;
                    }
                }
                if (vis)
                    XFree(vis);
            }
        }
        if (!d->nconfigs)
            tsr_faker_log(TSR_LOG_ERROR, "display %s has no TrueColor visual of depth 24 or 32", DisplayString(dpy));
    }
    pthread_mutex_unlock(&glx_lock);
    return d;
}

static int config_attrib(const struct __GLXFBConfigRec *c, int attribute, int *value)
{
    switch (attribute) {
    case GLX_FBCONFIG_ID: *value = c->id; break;
    case GLX_BUFFER_SIZE: *value = c->depth; break;
    case GLX_LEVEL: *value = 0; break;
    case GLX_DOUBLEBUFFER: *value = c->doublebuffer; break;
    case GLX_STEREO: *value = 0; break;
    case GLX_AUX_BUFFERS: *value = 0; break;
    case GLX_RED_SIZE:
    case GLX_GREEN_SIZE:
    case GLX_BLUE_SIZE: *value = 8; break;
    case GLX_ALPHA_SIZE: *value = c->depth == 32 ? 8 : 0; break;
    case GLX_DEPTH_SIZE: *value = 24; break;
    case GLX_STENCIL_SIZE: *value = 8; break;
    case GLX_ACCUM_RED_SIZE:
    case GLX_ACCUM_GREEN_SIZE:
    case GLX_ACCUM_BLUE_SIZE:
    case GLX_ACCUM_ALPHA_SIZE: *value = 0; break;
    case GLX_RENDER_TYPE: *value = GLX_RGBA_BIT; break;
    case GLX_DRAWABLE_TYPE: *value = GLX_WINDOW_BIT; break;
    case GLX_X_RENDERABLE: *value = True; break;
    case GLX_VISUAL_ID: *value = (int)c->visual; break;
    case GLX_X_VISUAL_TYPE: *value = GLX_TRUE_COLOR; break;
    case GLX_CONFIG_CAVEAT: *value = GLX_NONE; break;
    case GLX_TRANSPARENT_TYPE: *value = GLX_NONE; break;
    case GLX_TRANSPARENT_INDEX_VALUE:
    case GLX_TRANSPARENT_RED_VALUE:
    case GLX_TRANSPARENT_GREEN_VALUE:
    case GLX_TRANSPARENT_BLUE_VALUE:
    case GLX_TRANSPARENT_ALPHA_VALUE: *value = 0; break;
    case GLX_MAX_PBUFFER_WIDTH:
    case GLX_MAX_PBUFFER_HEIGHT: *value = 0; break;
    case GLX_MAX_PBUFFER_PIXELS: *value = 0; break;
    case GLX_SAMPLE_BUFFERS:
    case GLX_SAMPLES: *value = 0; break;
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
        config_attrib(c, attribute, &have);
        return want == (int)GLX_NONE ? have == (int)GLX_NONE : have == want;
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

static const struct __GLXFBConfigRec *find_visual_config(glx_display *d, VisualID visual, bool db)
{
    for (int i = 0; d && i < d->nconfigs; i++)
        if (d->configs[i].visual == visual && d->configs[i].doublebuffer == db)
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
    int kept = 0;
    for (int i = 0; all && i < n; i++) {
        bool ok = true;
        bool db_given = false;
        for (const int *a = attrib_list; a && a[0] != None; a += 2) {
            if (a[0] == GLX_DOUBLEBUFFER)
                db_given = true;
            if (!config_matches(all[i], a[0], a[1]))
                ok = false;
        }
        (void)db_given; /* default GLX_DONT_CARE */
        if (ok)
            out[kept++] = all[i];
    }
    if (nelements)
        *nelements = kept;
    if (!kept) {
        free(all);
        return NULL;
    }
    return out;
}

int glXGetFBConfigAttrib(Display *dpy, GLXFBConfig config, int attribute, int *value)
{
    (void)dpy;
    if (!config || !value)
        return GLX_BAD_ATTRIBUTE;
    return config_attrib(config, attribute, value);
}

XVisualInfo *glXGetVisualFromFBConfig(Display *dpy, GLXFBConfig config) { return visual_info(dpy, config); }

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
    if (!rgba) {
        tsr_faker_log(TSR_LOG_WARN, "glXChooseVisual: colour-index visuals are not supported");
        return NULL;
    }
    for (int i = 0; d && i < d->nconfigs; i++) {
        const struct __GLXFBConfigRec *c = &d->configs[i];
        if (c->screen != screen || c->doublebuffer != db)
            continue;
        bool ok = true;
        for (int k = 0; k < nwant; k++)
            if (want[k][0] != GLX_LEVEL && !config_matches(c, want[k][0], want[k][1]))
                ok = false;
        if (ok)
            return visual_info(dpy, c);
    }
    return NULL;
}

int glXGetConfig(Display *dpy, XVisualInfo *visual, int attrib, int *value)
{
    glx_display *d = display_of(dpy);
    const struct __GLXFBConfigRec *c = visual ? find_visual_config(d, visual->visualid, true) : NULL;
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
static tsr_faker_surface *drawable_surface(Display *dpy, GLXDrawable draw)
{
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
    const struct __GLXFBConfigRec *c = vis ? find_visual_config(d, vis->visualid, true) : NULL;
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

void glXQueryDrawable(Display *dpy, GLXDrawable draw, int attribute, unsigned int *value)
{
    if (!value)
        return;
    tsr_faker_surface *s = drawable_surface(dpy, draw);
    int w = 0, h = 0;
    tsr_faker_surface_size(s, &w, &h);
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
    P(glXCreateNewContext),
    P(glXCreateWindow),
    P(glXDestroyContext),
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
