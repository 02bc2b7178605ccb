/* faker/egl.c — EGL 1.5 of the faker's libEGL.so.1, on faker/core.c (in
 * libGL.so.1). Platforms: X11 (EGL_PLATFORM_X11_KHR/EXT, eglGetDisplay of a
 * Display * or EGL_DEFAULT_DISPLAY, which opens $DISPLAY) and surfaceless
 * (EGL_PLATFORM_SURFACELESS_MESA; also what EGL_DEFAULT_DISPLAY becomes
 * with no X server). OpenGL only: eglBindAPI(EGL_OPENGL_ES_API) is
 * refused with EGL_BAD_PARAMETER and a log line, so no ES context can be
 * made. Configs are configs.c's formats without accumulation (RGBA8 and
 * RGB8, depth 24 with or without stencil 8, 16 or none), each on an X
 * visual of the screen (shared when there are fewer visuals), matched and
 * sorted by EGL 1.5's rules; the surfaceless display's are pbuffer-only.
 *
 * EGL_RENDERABLE_TYPE also carries the OpenGL ES bits: xscreensaver 6 as
 * Debian builds it (EGL with GLES3 support, no jwzgles) asks
 * eglChooseConfig for EGL_OPENGL_ES_BIT (EGL_OPENGL_ES3_BIT for hacks
 * preferring GLSL), then binds EGL_OPENGL_API and creates an OpenGL 1.3
 * context on that config — which Mesa allows because its configs carry
 * every API's bit. Without the ES bits those programs find no config at
 * all. EGL_CONFORMANT stays EGL_OPENGL_BIT alone: the only API a context
 * can be made for. */
#define EGL_EGLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "configs.h"
#include "tessera/log.h"

/* configs.c's double-buffered formats without accumulation (EGL has
 * neither attribute: a window surface is double-buffered). */
#define MAX_CONFIGS (TSR_FAKER_FORMATS / 2)
/* See the header comment: matching, not what a context can be. */
#define RENDERABLE_BITS (EGL_OPENGL_BIT | EGL_OPENGL_ES_BIT | EGL_OPENGL_ES2_BIT | EGL_OPENGL_ES3_BIT)
#define MAX_DISPLAYS 8

typedef struct egl_config {
    EGLint id;
    VisualID visual; /* 0: pbuffers only */
    tsr_faker_format f;
} egl_config;

typedef struct egl_display {
    EGLenum platform;
    Display *x;   /* NULL: surfaceless */
    bool own_x;   /* opened here (EGL_DEFAULT_DISPLAY) */
    void *native; /* what the application passed */
    bool initialized;
    egl_config configs[MAX_CONFIGS];
    int nconfigs;
} egl_display;

typedef struct egl_context {
    tsr_faker_context *ctx;
    egl_display *dpy;
    const egl_config *config;
    bool destroyed;
} egl_context;

typedef struct egl_surface {
    tsr_faker_surface *s;
    egl_display *dpy;
    const egl_config *config;
    EGLint type; /* EGL_WINDOW_BIT or EGL_PBUFFER_BIT */
    bool destroyed;
} egl_surface;

static pthread_mutex_t egl_lock = PTHREAD_MUTEX_INITIALIZER;
static egl_display displays[MAX_DISPLAYS];
static int ndisplays;
static _Thread_local EGLint last_error = EGL_SUCCESS;
static _Thread_local EGLenum bound_api = EGL_OPENGL_API;
static _Thread_local egl_context *cur_ctx;
static _Thread_local egl_surface *cur_draw, *cur_read;
static _Thread_local egl_display *cur_dpy;

static const char egl_client_extensions[] = "EGL_EXT_client_extensions EGL_EXT_platform_base "
                                            "EGL_KHR_platform_x11 EGL_EXT_platform_x11 "
                                            "EGL_MESA_platform_surfaceless";
static const char egl_display_extensions[] = "EGL_KHR_create_context EGL_KHR_surfaceless_context";

static EGLBoolean fail(EGLint error)
{
    last_error = error;
    return EGL_FALSE;
}

static EGLBoolean ok(void)
{
    last_error = EGL_SUCCESS;
    return EGL_TRUE;
}

static egl_display *display_get(EGLDisplay d)
{
    for (int i = 0; i < ndisplays; i++)
        if ((EGLDisplay)&displays[i] == d)
            return &displays[i];
    return NULL;
}

static egl_display *initialized(EGLDisplay d)
{
    egl_display *e = display_get(d);
    if (!e)
        last_error = EGL_BAD_DISPLAY;
    else if (!e->initialized) {
        last_error = EGL_NOT_INITIALIZED;
        e = NULL;
    }
    return e;
}

static EGLDisplay display_for(EGLenum platform, void *native)
{
    pthread_mutex_lock(&egl_lock);
    egl_display *e = NULL;
    for (int i = 0; i < ndisplays && !e; i++)
        if (displays[i].platform == platform && displays[i].native == native)
            e = &displays[i];
    if (!e && ndisplays < MAX_DISPLAYS) {
        e = &displays[ndisplays++];
        memset(e, 0, sizeof *e);
        e->platform = platform;
        e->native = native;
    }
    pthread_mutex_unlock(&egl_lock);
    if (!e)
        last_error = EGL_BAD_ALLOC;
    return e ? (EGLDisplay)e : EGL_NO_DISPLAY;
}

EGLDisplay eglGetPlatformDisplay(EGLenum platform, void *native_display, const EGLAttrib *attrib_list)
{
    (void)attrib_list;
    if (platform != EGL_PLATFORM_X11_KHR && platform != EGL_PLATFORM_SURFACELESS_MESA) {
        tsr_faker_log(TSR_LOG_ERROR, "eglGetPlatformDisplay: platform 0x%x is not supported (X11, surfaceless)",
                      (unsigned)platform);
        last_error = EGL_BAD_PARAMETER;
        return EGL_NO_DISPLAY;
    }
    return display_for(platform, platform == EGL_PLATFORM_SURFACELESS_MESA ? NULL : native_display);
}

EGLDisplay eglGetPlatformDisplayEXT(EGLenum platform, void *native_display, const EGLint *attrib_list)
{
    (void)attrib_list;
    return eglGetPlatformDisplay(platform, native_display, NULL);
}

EGLDisplay eglGetDisplay(EGLNativeDisplayType display_id)
{
    return display_for(EGL_PLATFORM_X11_KHR, (void *)display_id);
}

/* The formats on the screen's visuals, one each while there are enough
 * (configs.c); with no X display, pbuffer configs with no visual. */
static void add_configs(egl_display *e)
{
    XVisualInfo *vis = NULL;
    int nvis = e->x ? tsr_faker_visuals(e->x, DefaultScreen(e->x), &vis) : 0;
    e->nconfigs = 0;
    for (int i = 0; i < TSR_FAKER_FORMATS && e->nconfigs < MAX_CONFIGS; i++) {
        const tsr_faker_format *f = tsr_faker_format_at(i);
        if (!f->doublebuffer || f->accum)
            continue;
        int k = e->nconfigs++;
        e->configs[k] = (egl_config){k + 1, nvis ? vis[k % nvis].visualid : 0, *f};
    }
    free(vis);
}

EGLBoolean eglInitialize(EGLDisplay dpy, EGLint *major, EGLint *minor)
{
    egl_display *e = display_get(dpy);
    if (!e)
        return fail(EGL_BAD_DISPLAY);
    if (!e->initialized) {
        if (e->platform == EGL_PLATFORM_X11_KHR) {
            e->x = e->native;
            if (!e->x) {
                e->x = XOpenDisplay(NULL);
                e->own_x = e->x != NULL;
                if (!e->x)
                    tsr_faker_log(TSR_LOG_INFO, "EGL_DEFAULT_DISPLAY: no X display, surfaceless");
            }
        }
        add_configs(e);
        e->initialized = true;
    }
    if (major)
        *major = 1;
    if (minor)
        *minor = 5;
    return ok();
}

EGLBoolean eglTerminate(EGLDisplay dpy)
{
    egl_display *e = display_get(dpy);
    if (!e)
        return fail(EGL_BAD_DISPLAY);
    e->initialized = false;
    return ok();
}

static EGLint config_value(const egl_display *e, const egl_config *c, EGLint attribute, bool *known)
{
    *known = true;
    switch (attribute) {
    case EGL_BUFFER_SIZE: return 24 + c->f.alpha;
    case EGL_RED_SIZE:
    case EGL_GREEN_SIZE:
    case EGL_BLUE_SIZE: return 8;
    case EGL_ALPHA_SIZE: return c->f.alpha;
    case EGL_DEPTH_SIZE: return c->f.depth;
    case EGL_STENCIL_SIZE: return c->f.stencil;
    case EGL_CONFIG_ID: return c->id;
    case EGL_CONFIG_CAVEAT: return EGL_NONE;
    case EGL_LEVEL: return 0;
    case EGL_NATIVE_RENDERABLE: return EGL_FALSE;
    case EGL_NATIVE_VISUAL_ID: return (EGLint)c->visual;
    case EGL_NATIVE_VISUAL_TYPE: return c->visual ? TrueColor : EGL_NONE;
    case EGL_SAMPLES: return c->f.samples;
    case EGL_SAMPLE_BUFFERS: return c->f.samples > 0;
    case EGL_SURFACE_TYPE: return EGL_PBUFFER_BIT | (c->visual && e->x ? EGL_WINDOW_BIT : 0);
    case EGL_TRANSPARENT_TYPE: return EGL_NONE;
    case EGL_TRANSPARENT_RED_VALUE:
    case EGL_TRANSPARENT_GREEN_VALUE:
    case EGL_TRANSPARENT_BLUE_VALUE: return 0;
    case EGL_RENDERABLE_TYPE: return RENDERABLE_BITS;
    case EGL_CONFORMANT: return EGL_OPENGL_BIT;
    case EGL_COLOR_BUFFER_TYPE: return EGL_RGB_BUFFER;
    case EGL_LUMINANCE_SIZE:
    case EGL_ALPHA_MASK_SIZE: return 0;
    case EGL_BIND_TO_TEXTURE_RGB:
    case EGL_BIND_TO_TEXTURE_RGBA: return EGL_FALSE;
    case EGL_MAX_PBUFFER_WIDTH:
    case EGL_MAX_PBUFFER_HEIGHT: return 8192;
    case EGL_MAX_PBUFFER_PIXELS: return 8192 * 8192;
    case EGL_MIN_SWAP_INTERVAL: return 0;
    case EGL_MAX_SWAP_INTERVAL: return 1;
    default: *known = false; return 0;
    }
}

static bool config_matches(const egl_display *e, const egl_config *c, const EGLint *attrib_list)
{
    /* EGL_CONFIG_ID given: every other attribute is ignored (EGL 1.5, 3.4.1.2). */
    for (const EGLint *a = attrib_list; a && a[0] != EGL_NONE; a += 2)
        if (a[0] == EGL_CONFIG_ID && a[1] != EGL_DONT_CARE)
            return c->id == a[1];
    for (const EGLint *a = attrib_list; a && a[0] != EGL_NONE; a += 2) {
        EGLint want = a[1];
        bool known;
        EGLint have = config_value(e, c, a[0], &known);
        if (want == EGL_DONT_CARE || !known)
            continue;
        switch (a[0]) {
        case EGL_SURFACE_TYPE:
        case EGL_RENDERABLE_TYPE:
        case EGL_CONFORMANT:
            if ((have & want) != want)
                return false;
            break;
        case EGL_CONFIG_ID:
        case EGL_NATIVE_VISUAL_TYPE:
        case EGL_COLOR_BUFFER_TYPE:
        case EGL_LEVEL:
        case EGL_CONFIG_CAVEAT:
        case EGL_TRANSPARENT_TYPE:
        case EGL_NATIVE_RENDERABLE:
        case EGL_BIND_TO_TEXTURE_RGB:
        case EGL_BIND_TO_TEXTURE_RGBA:
            if (have != want)
                return false;
            break;
        case EGL_MAX_PBUFFER_WIDTH:
        case EGL_MAX_PBUFFER_HEIGHT:
        case EGL_MAX_PBUFFER_PIXELS:
        case EGL_NATIVE_VISUAL_ID:
        case EGL_MIN_SWAP_INTERVAL:
        case EGL_MAX_SWAP_INTERVAL: break; /* ignored by eglChooseConfig */
        default:
            if (have < want)
                return false;
        }
    }
    return true;
}

EGLBoolean eglGetConfigs(EGLDisplay dpy, EGLConfig *configs, EGLint config_size, EGLint *num_config)
{
    egl_display *e = initialized(dpy);
    if (!e)
        return EGL_FALSE;
    if (!num_config)
        return fail(EGL_BAD_PARAMETER);
    EGLint n = 0;
    for (int i = 0; i < e->nconfigs; i++) {
        if (configs && n < config_size)
            configs[n] = (EGLConfig)&e->configs[i];
        if (!configs || n < config_size)
            n++;
    }
    *num_config = n;
    return ok();
}

/* EGL 1.5's sort order (3.4.1.2): the sum of the colour sizes asked for
 * (larger first; red, green and blue are 8 everywhere, so alpha decides
 * when it is asked for), buffer size, sample buffers, samples, depth and
 * stencil (smaller first), then the config id. */
typedef struct egl_ranked {
    const egl_config *c;
    int colour; /* bits of the asked-for components */
} egl_ranked;

static int egl_order(const void *pa, const void *pb)
{
    const egl_ranked *a = pa, *b = pb;
    int d;
    if ((d = b->colour - a->colour))
        return d;
    if ((d = a->c->f.alpha - b->c->f.alpha))
        return d;
    if ((d = (a->c->f.samples > 0) - (b->c->f.samples > 0)))
        return d;
    if ((d = a->c->f.samples - b->c->f.samples))
        return d;
    if ((d = a->c->f.depth - b->c->f.depth))
        return d;
    if ((d = a->c->f.stencil - b->c->f.stencil))
        return d;
    return a->c->id - b->c->id;
}

EGLBoolean eglChooseConfig(EGLDisplay dpy, const EGLint *attrib_list, EGLConfig *configs, EGLint config_size,
                           EGLint *num_config)
{
    egl_display *e = initialized(dpy);
    if (!e)
        return EGL_FALSE;
    if (!num_config)
        return fail(EGL_BAD_PARAMETER);
    bool alpha_asked = false;
    for (const EGLint *a = attrib_list; a && a[0] != EGL_NONE; a += 2)
        if (a[0] == EGL_ALPHA_SIZE && a[1] != EGL_DONT_CARE && a[1] > 0)
            alpha_asked = true;
    egl_ranked ranked[MAX_CONFIGS];
    int n = 0;
    for (int i = 0; i < e->nconfigs; i++)
        if (config_matches(e, &e->configs[i], attrib_list))
            ranked[n++] = (egl_ranked){&e->configs[i], alpha_asked ? e->configs[i].f.alpha : 0};
    qsort(ranked, (size_t)n, sizeof ranked[0], egl_order);
    EGLint out = 0;
    for (int i = 0; i < n; i++) {
        if (configs && out < config_size)
            configs[out] = (EGLConfig)ranked[i].c;
        if (!configs || out < config_size)
            out++;
    }
    *num_config = out;
    return ok();
}

static const egl_config *config_of(const egl_display *e, EGLConfig config)
{
    for (int i = 0; i < e->nconfigs; i++)
        if ((EGLConfig)&e->configs[i] == config)
            return &e->configs[i];
    return NULL;
}

EGLBoolean eglGetConfigAttrib(EGLDisplay dpy, EGLConfig config, EGLint attribute, EGLint *value)
{
    egl_display *e = initialized(dpy);
    if (!e)
        return EGL_FALSE;
    const egl_config *c = config_of(e, config);
    if (!c)
        return fail(EGL_BAD_CONFIG);
    bool known;
    EGLint v = config_value(e, c, attribute, &known);
    if (!known)
        return fail(EGL_BAD_ATTRIBUTE);
    if (value)
        *value = v;
    return ok();
}

EGLBoolean eglBindAPI(EGLenum api)
{
    if (api != EGL_OPENGL_API) {
        tsr_faker_log(TSR_LOG_ERROR, "eglBindAPI(0x%x): only EGL_OPENGL_API; OpenGL ES is not supported by tessera",
                      (unsigned)api);
        return fail(EGL_BAD_PARAMETER);
    }
    bound_api = api;
    return ok();
}

EGLenum eglQueryAPI(void) { return bound_api; }

EGLContext eglCreateContext(EGLDisplay dpy, EGLConfig config, EGLContext share_context, const EGLint *attrib_list)
{
    egl_display *e = initialized(dpy);
    if (!e)
        return EGL_NO_CONTEXT;
    const egl_config *c = config == EGL_NO_CONFIG_KHR ? &e->configs[0] : config_of(e, config);
    if (!c) {
        last_error = EGL_BAD_CONFIG;
        return EGL_NO_CONTEXT;
    }
    EGLint major = 1, minor = 0;
    for (const EGLint *a = attrib_list; a && a[0] != EGL_NONE; a += 2) {
        if (a[0] == EGL_CONTEXT_MAJOR_VERSION)
            major = a[1];
        else if (a[0] == EGL_CONTEXT_MINOR_VERSION)
            minor = a[1];
    }
    if (major > 2 || (major == 2 && minor > 1)) {
        tsr_faker_log(TSR_LOG_ERROR, "eglCreateContext: OpenGL %d.%d asked, tessera has 2.1", (int)major, (int)minor);
        last_error = EGL_BAD_MATCH;
        return EGL_NO_CONTEXT;
    }
    egl_context *share = share_context;
    egl_context *x = calloc(1, sizeof *x);
    if (!x) {
        last_error = EGL_BAD_ALLOC;
        return EGL_NO_CONTEXT;
    }
    x->ctx = tsr_faker_context_create(share ? share->ctx : NULL);
    if (!x->ctx) {
        free(x);
        last_error = EGL_BAD_ALLOC;
        return EGL_NO_CONTEXT;
    }
    x->dpy = e;
    x->config = c;
    last_error = EGL_SUCCESS;
    return x;
}

EGLBoolean eglDestroyContext(EGLDisplay dpy, EGLContext ctx)
{
    if (!initialized(dpy))
        return EGL_FALSE;
    egl_context *x = ctx;
    if (!x)
        return fail(EGL_BAD_CONTEXT);
    tsr_faker_context_destroy(x->ctx);
    if (x == cur_ctx)
        x->destroyed = true;
    else
        free(x);
    return ok();
}

static EGLSurface window_surface(egl_display *e, const egl_config *c, unsigned long xid)
{
    if (!e->x || !c->visual) {
        last_error = EGL_BAD_MATCH;
        return EGL_NO_SURFACE;
    }
    /* The application's requests reach the server first (see glx.c). */
    tsr_faker_surface *s = tsr_faker_surface_find(xid);
    if (!s) {
        XSync(e->x, False);
        s = tsr_faker_surface_window(DisplayString(e->x), xid);
    }
    if (!s) {
        last_error = EGL_BAD_NATIVE_WINDOW;
        return EGL_NO_SURFACE;
    }
    /* An EGL window surface renders to its back buffer (EGL_RENDER_BUFFER). */
    tsr_faker_surface_set_config(s, true, c->f.samples);
    egl_surface *x = calloc(1, sizeof *x);
    if (!x) {
        last_error = EGL_BAD_ALLOC;
        return EGL_NO_SURFACE;
    }
    *x = (egl_surface){.s = s, .dpy = e, .config = c, .type = EGL_WINDOW_BIT};
    last_error = EGL_SUCCESS;
    return x;
}

EGLSurface eglCreateWindowSurface(EGLDisplay dpy, EGLConfig config, EGLNativeWindowType win, const EGLint *attrib_list)
{
    (void)attrib_list;
    egl_display *e = initialized(dpy);
    if (!e)
        return EGL_NO_SURFACE;
    const egl_config *c = config_of(e, config);
    if (!c) {
        last_error = EGL_BAD_CONFIG;
        return EGL_NO_SURFACE;
    }
    return window_surface(e, c, (unsigned long)win);
}

EGLSurface eglCreatePlatformWindowSurface(EGLDisplay dpy, EGLConfig config, void *native_window,
                                          const EGLAttrib *attrib_list)
{
    (void)attrib_list;
    if (!native_window) {
        last_error = EGL_BAD_NATIVE_WINDOW;
        return EGL_NO_SURFACE;
    }
    /* X11: native_window points at the Window. */
    return eglCreateWindowSurface(dpy, config, *(Window *)native_window, NULL);
}

EGLSurface eglCreatePlatformWindowSurfaceEXT(EGLDisplay dpy, EGLConfig config, void *native_window,
                                             const EGLint *attrib_list)
{
    (void)attrib_list;
    return eglCreatePlatformWindowSurface(dpy, config, native_window, NULL);
}

EGLSurface eglCreatePbufferSurface(EGLDisplay dpy, EGLConfig config, const EGLint *attrib_list)
{
    egl_display *e = initialized(dpy);
    if (!e)
        return EGL_NO_SURFACE;
    const egl_config *c = config_of(e, config);
    if (!c) {
        last_error = EGL_BAD_CONFIG;
        return EGL_NO_SURFACE;
    }
    EGLint w = 0, h = 0;
    for (const EGLint *a = attrib_list; a && a[0] != EGL_NONE; a += 2) {
        if (a[0] == EGL_WIDTH)
            w = a[1];
        else if (a[0] == EGL_HEIGHT)
            h = a[1];
    }
    if (w < 0 || h < 0 || w > 8192 || h > 8192) {
        last_error = EGL_BAD_PARAMETER;
        return EGL_NO_SURFACE;
    }
    egl_surface *x = calloc(1, sizeof *x);
    tsr_faker_surface *s = x ? tsr_faker_surface_pbuffer(w, h) : NULL;
    if (!s) {
        free(x);
        last_error = EGL_BAD_ALLOC;
        return EGL_NO_SURFACE;
    }
    *x = (egl_surface){.s = s, .dpy = e, .config = c, .type = EGL_PBUFFER_BIT};
    tsr_faker_surface_set_config(s, false, c->f.samples);
    last_error = EGL_SUCCESS;
    return x;
}

static void surface_free(egl_surface *x)
{
    tsr_faker_surface_destroy(x->s);
    free(x);
}

EGLBoolean eglDestroySurface(EGLDisplay dpy, EGLSurface surface)
{
    if (!initialized(dpy))
        return EGL_FALSE;
    egl_surface *x = surface;
    if (!x)
        return fail(EGL_BAD_SURFACE);
    if (x == cur_draw || x == cur_read)
        x->destroyed = true;
    else
        surface_free(x);
    return ok();
}

static void release_old(egl_context *ctx, egl_surface *draw, egl_surface *read)
{
    if (cur_ctx && cur_ctx != ctx && cur_ctx->destroyed)
        free(cur_ctx);
    if (cur_draw && cur_draw != draw && cur_draw != read && cur_draw->destroyed)
        surface_free(cur_draw);
    if (cur_read && cur_read != cur_draw && cur_read != draw && cur_read != read && cur_read->destroyed)
        surface_free(cur_read);
}

EGLBoolean eglMakeCurrent(EGLDisplay dpy, EGLSurface draw, EGLSurface read, EGLContext ctx)
{
    egl_display *e = display_get(dpy);
    if (!e && !(dpy == EGL_NO_DISPLAY && ctx == EGL_NO_CONTEXT))
        return fail(EGL_BAD_DISPLAY);
    egl_context *c = ctx;
    egl_surface *d = draw, *r = read;
    if (!c) {
        if (d || r)
            return fail(EGL_BAD_MATCH);
        tsr_faker_make_current(NULL, NULL);
        release_old(NULL, NULL, NULL);
        cur_ctx = NULL;
        cur_draw = cur_read = NULL;
        cur_dpy = NULL;
        return ok();
    }
    if (!e->initialized)
        return fail(EGL_NOT_INITIALIZED);
    if ((d == NULL) != (r == NULL))
        return fail(EGL_BAD_MATCH);
    if (r && r != d)
        tsr_faker_log(TSR_LOG_WARN, "eglMakeCurrent: a read surface other than the draw one is ignored");
    if (!tsr_faker_make_current(c->ctx, d ? d->s : NULL))
        return fail(tsr_faker_make_current_refused_busy() ? EGL_BAD_ACCESS : EGL_BAD_ALLOC);
    release_old(c, d, r);
    cur_ctx = c;
    cur_draw = d;
    cur_read = r;
    cur_dpy = e;
    return ok();
}

EGLBoolean eglSwapBuffers(EGLDisplay dpy, EGLSurface surface)
{
    if (!initialized(dpy))
        return EGL_FALSE;
    egl_surface *x = surface;
    if (!x)
        return fail(EGL_BAD_SURFACE);
    if (!cur_ctx || x != cur_draw)
        return fail(EGL_BAD_SURFACE);
    if (x->type == EGL_WINDOW_BIT)
        tsr_faker_swap(x->s);
    return ok();
}

EGLBoolean eglSwapInterval(EGLDisplay dpy, EGLint interval)
{
    (void)interval; /* accepted, no effect */
    if (!initialized(dpy))
        return EGL_FALSE;
    return ok();
}

EGLBoolean eglQuerySurface(EGLDisplay dpy, EGLSurface surface, EGLint attribute, EGLint *value)
{
    if (!initialized(dpy))
        return EGL_FALSE;
    egl_surface *x = surface;
    if (!x)
        return fail(EGL_BAD_SURFACE);
    int w = 0, h = 0;
    if (attribute == EGL_WIDTH || attribute == EGL_HEIGHT) {
        if (x->dpy->x && x->type == EGL_WINDOW_BIT)
            XSync(x->dpy->x, False);            /* the program's XResizeWindow reaches the server first */
        tsr_faker_surface_x_size(x->s, &w, &h); /* the window's size now, as Mesa answers */
    }
    EGLint v;
    switch (attribute) {
    case EGL_WIDTH: v = w; break;
    case EGL_HEIGHT: v = h; break;
    case EGL_CONFIG_ID: v = x->config->id; break;
    case EGL_RENDER_BUFFER: v = x->type == EGL_WINDOW_BIT ? EGL_BACK_BUFFER : EGL_SINGLE_BUFFER; break;
    case EGL_SWAP_BEHAVIOR: v = EGL_BUFFER_DESTROYED; break;
    case EGL_LARGEST_PBUFFER:
    case EGL_MIPMAP_TEXTURE:
    case EGL_MIPMAP_LEVEL: v = 0; break;
    case EGL_TEXTURE_FORMAT:
    case EGL_TEXTURE_TARGET: v = EGL_NO_TEXTURE; break;
    case EGL_MULTISAMPLE_RESOLVE: v = EGL_MULTISAMPLE_RESOLVE_DEFAULT; break;
    case EGL_HORIZONTAL_RESOLUTION:
    case EGL_VERTICAL_RESOLUTION:
    case EGL_PIXEL_ASPECT_RATIO: v = EGL_UNKNOWN; break;
    case EGL_VG_ALPHA_FORMAT: v = EGL_VG_ALPHA_FORMAT_NONPRE; break;
    case EGL_VG_COLORSPACE: v = EGL_VG_COLORSPACE_sRGB; break;
    case EGL_GL_COLORSPACE: v = EGL_GL_COLORSPACE_LINEAR; break;
    default: return fail(EGL_BAD_ATTRIBUTE);
    }
    if (value)
        *value = v;
    return ok();
}

EGLBoolean eglSurfaceAttrib(EGLDisplay dpy, EGLSurface surface, EGLint attribute, EGLint value)
{
    (void)attribute, (void)value;
    if (!initialized(dpy))
        return EGL_FALSE;
    return surface ? ok() : fail(EGL_BAD_SURFACE);
}

EGLBoolean eglQueryContext(EGLDisplay dpy, EGLContext ctx, EGLint attribute, EGLint *value)
{
    if (!initialized(dpy))
        return EGL_FALSE;
    egl_context *x = ctx;
    if (!x)
        return fail(EGL_BAD_CONTEXT);
    EGLint v;
    switch (attribute) {
    case EGL_CONFIG_ID: v = x->config->id; break;
    case EGL_CONTEXT_CLIENT_TYPE: v = EGL_OPENGL_API; break;
    case EGL_CONTEXT_CLIENT_VERSION: v = 2; break;
    case EGL_RENDER_BUFFER:
        v = x == cur_ctx && cur_draw ? (cur_draw->type == EGL_WINDOW_BIT ? EGL_BACK_BUFFER : EGL_SINGLE_BUFFER)
                                     : EGL_NONE;
        break;
    default: return fail(EGL_BAD_ATTRIBUTE);
    }
    if (value)
        *value = v;
    return ok();
}

const char *eglQueryString(EGLDisplay dpy, EGLint name)
{
    if (dpy == EGL_NO_DISPLAY) {
        if (name == EGL_EXTENSIONS) {
            last_error = EGL_SUCCESS;
            return egl_client_extensions;
        }
        if (name == EGL_VERSION) {
            last_error = EGL_SUCCESS;
            return "1.5 tessera";
        }
        last_error = EGL_BAD_DISPLAY;
        return NULL;
    }
    if (!initialized(dpy))
        return NULL;
    last_error = EGL_SUCCESS;
    switch (name) {
    case EGL_VENDOR: return "tessera";
    case EGL_VERSION: return "1.5 tessera";
    case EGL_CLIENT_APIS: return "OpenGL";
    case EGL_EXTENSIONS: return egl_display_extensions;
    default: last_error = EGL_BAD_PARAMETER; return NULL;
    }
}

EGLint eglGetError(void)
{
    EGLint e = last_error;
    last_error = EGL_SUCCESS;
    return e;
}

EGLContext eglGetCurrentContext(void) { return cur_ctx ? (EGLContext)cur_ctx : EGL_NO_CONTEXT; }
EGLDisplay eglGetCurrentDisplay(void) { return cur_dpy ? (EGLDisplay)cur_dpy : EGL_NO_DISPLAY; }

EGLSurface eglGetCurrentSurface(EGLint readdraw)
{
    if (readdraw != EGL_DRAW && readdraw != EGL_READ) {
        last_error = EGL_BAD_PARAMETER;
        return EGL_NO_SURFACE;
    }
    egl_surface *s = readdraw == EGL_DRAW ? cur_draw : cur_read;
    return s ? (EGLSurface)s : EGL_NO_SURFACE;
}

EGLBoolean eglReleaseThread(void)
{
    if (cur_ctx)
        eglMakeCurrent((EGLDisplay)cur_dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    bound_api = EGL_OPENGL_API;
    return ok();
}

EGLBoolean eglWaitClient(void)
{
    tsr_faker_finish();
    return ok();
}

EGLBoolean eglWaitGL(void) { return eglWaitClient(); }

EGLBoolean eglWaitNative(EGLint engine)
{
    (void)engine;
    return ok();
}

#define P(name)                     \
    {                               \
#name, (void (*)(void))name \
    }
/* Every exported egl*, sorted (strcmp). */
static const tsr_faker_proc egl_procs[] = {
    P(eglBindAPI),
    P(eglChooseConfig),
    P(eglCreateContext),
    P(eglCreatePbufferSurface),
    P(eglCreatePlatformWindowSurface),
    P(eglCreatePlatformWindowSurfaceEXT),
    P(eglCreateWindowSurface),
    P(eglDestroyContext),
    P(eglDestroySurface),
    P(eglGetConfigAttrib),
    P(eglGetConfigs),
    P(eglGetCurrentContext),
    P(eglGetCurrentDisplay),
    P(eglGetCurrentSurface),
    P(eglGetDisplay),
    P(eglGetError),
    P(eglGetPlatformDisplay),
    P(eglGetPlatformDisplayEXT),
    P(eglGetProcAddress),
    P(eglInitialize),
    P(eglMakeCurrent),
    P(eglQueryAPI),
    P(eglQueryContext),
    P(eglQueryString),
    P(eglQuerySurface),
    P(eglReleaseThread),
    P(eglSurfaceAttrib),
    P(eglSwapBuffers),
    P(eglSwapInterval),
    P(eglTerminate),
    P(eglWaitClient),
    P(eglWaitGL),
    P(eglWaitNative),
};
#undef P

__eglMustCastToProperFunctionPointerType eglGetProcAddress(const char *procname)
{
    void (*p)(void) = tsr_faker_lookup(egl_procs, sizeof egl_procs / sizeof egl_procs[0], procname);
    return p ? p : tsr_faker_gl_proc(procname);
}
