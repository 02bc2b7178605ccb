/* tests/faker/egl_share_threads_driver.c — faker_egl_share_threads MODE [FRAMES
 * [RAW]], with no X server, linked against the faker's libEGL.so.1 and
 * libGL.so.1 (built with SHARE_GLX, faker_glx_share_threads: the same
 * under Xvfb through GLX, the drawing thread in an X window, the loader on
 * a 1x1 GLX pbuffer, XInitThreads): a loader thread and a drawing thread
 * with contexts of ONE
 * share group, drawing at the same time. The loader makes the textures
 * and display lists (glGenTextures, glGenLists) and, frame after frame,
 * uploads frame f+1's texture and compiles its list into one of two slots
 * (then glFinish and a signal) while the drawing thread draws frame f
 * from the other slot into its 64x48 pbuffer or window (clear, glCallList of the
 * list, a textured quad of its own) and reads it back. Every frame must
 * equal the same frames drawn by one thread with one context (0 differing
 * pixels). MODE:
 *   created   both contexts are made before either thread runs;
 *   joined    the loader makes its context (sharing the drawing thread's)
 *             on its own thread while the drawing thread already draws
 *             (a loading screen until the first texture is there), so the
 *             drawing thread's context moves to the shared stream's locked
 *             table at one of its check points.
 * RAW: the threaded frames are also written there (one after the other,
 * RGBA), so runs through other chains can be compared byte for byte.
 * Built with SHARE_NATIVE (faker_egl_share_threads_native, linked with
 * libOSMesa instead of the faker), `native FRAMES RAW` draws the same
 * frames in the single-threaded order with OSMesa itself and writes them
 * to RAW: the native render the faker's runs are compared with. */
#if defined(SHARE_NATIVE)
#include <GL/osmesa.h>
#elif defined(SHARE_GLX)
#include <GL/glx.h>
#include <X11/Xlib.h>
#else
#include <EGL/egl.h>
#endif
#include <GL/gl.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

#define W 64
#define H 48
#define TEX 16
#define MAX_FRAMES 32
#define QUADS 6

static int nframes = 8;
static unsigned char *reference[MAX_FRAMES];
#ifndef SHARE_NATIVE
static int joined;
static unsigned char *threaded[MAX_FRAMES];
#endif

/* The shared objects (made by whoever loads). */
static GLuint tex[2], list_base;

/* Frame f's texture and list: pure functions of f. */
static void load(int slot, int f)
{
    unsigned char px[TEX * TEX * 4];
    for (int y = 0; y < TEX; y++)
        for (int x = 0; x < TEX; x++) {
            unsigned char *p = px + 4 * (y * TEX + x);
            p[0] = (unsigned char)(x * 16 + f * 29);
            p[1] = (unsigned char)(y * 16 + f * 53);
            p[2] = (unsigned char)(((x ^ y) & 1) ? 255 - f * 17 : f * 11);
            p[3] = 255;
        }
    glBindTexture(GL_TEXTURE_2D, tex[slot]);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, TEX, TEX, 0, GL_RGBA, GL_UNSIGNED_BYTE, px);
    glBindTexture(GL_TEXTURE_2D, 0);
    glNewList(list_base + (GLuint)slot, GL_COMPILE);
    glBegin(GL_TRIANGLES);
    for (int i = 0; i < QUADS; i++) {
        float a = 0.3f * (float)(i + f), x = -0.9f + 0.3f * (float)i, y = -0.8f + 0.1f * (float)((i * 7 + f) % 9);
        glColor3f(1.0f, 0.5f + 0.08f * (float)i, 0.3f + 0.05f * (float)f);
        glTexCoord2f(0.0f, 0.0f);
        glVertex3f(x, y, -0.5f);
        glTexCoord2f(1.0f, 0.2f * a);
        glVertex3f(x + 0.5f, y + 0.1f, 0.2f);
        glTexCoord2f(0.5f, 1.0f);
        glVertex3f(x + 0.2f, y + 0.7f, 0.5f);
    }
    glEnd();
    glEndList();
}

static void make_names(void)
{
    glGenTextures(2, tex);
    list_base = glGenLists(2);
}

/* Frame f, drawn with slot f % 2. */
static void draw(int f)
{
    int slot = f % 2;
    glViewport(0, 0, W, H);
    glClearColor(0.1f, 0.02f * (float)f, 0.3f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_TEXTURE_2D);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    glBindTexture(GL_TEXTURE_2D, tex[slot]);
    glCallList(list_base + (GLuint)slot);
    glBegin(GL_QUADS);
    glColor3f(1.0f, 1.0f, 1.0f);
    glTexCoord2f(0.0f, 0.0f);
    glVertex2f(0.2f, 0.1f);
    glTexCoord2f(1.0f, 0.0f);
    glVertex2f(0.9f, 0.1f);
    glTexCoord2f(1.0f, 1.0f);
    glVertex2f(0.9f, 0.9f);
    glTexCoord2f(0.0f, 1.0f);
    glVertex2f(0.2f, 0.9f);
    glEnd();
    glBindTexture(GL_TEXTURE_2D, 0);
    glDisable(GL_TEXTURE_2D);
    glDisable(GL_DEPTH_TEST);
}

static unsigned char *read_frame(void)
{
    unsigned char *px = calloc((size_t)W * H, 4);
    if (px) {
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, px);
    }
    return px;
}

#ifndef SHARE_NATIVE
static long differing(const unsigned char *a, const unsigned char *b)
{
    long n = 0;
    for (size_t i = 0; i < (size_t)W * H; i++)
        n += memcmp(a + 4 * i, b + 4 * i, 4) != 0;
    return n;
}
/* The window system: contexts (void *) and surfaces (uintptr_t; 0:
 * none) of EGL or GLX, for the same threads below. */
#ifdef SHARE_GLX
static Display *dpy;
static GLXFBConfig config;

static int ws_init(void)
{
    XInitThreads();
    dpy = XOpenDisplay(NULL);
    if (!dpy)
        return 0;
    static const int attrs[] = {GLX_DRAWABLE_TYPE,
                                GLX_WINDOW_BIT | GLX_PBUFFER_BIT,
                                GLX_RENDER_TYPE,
                                GLX_RGBA_BIT,
                                GLX_DOUBLEBUFFER,
                                True,
                                GLX_DEPTH_SIZE,
                                24,
                                None};
    int n = 0;
    GLXFBConfig *c = glXChooseFBConfig(dpy, DefaultScreen(dpy), attrs, &n);
    if (!c || n < 1)
        return 0;
    config = c[0];
    XFree(c);
    return 1;
}

static void *ws_context(void *share) { return glXCreateNewContext(dpy, config, GLX_RGBA_TYPE, share, True); }

static uintptr_t ws_pbuffer(int w, int h)
{
    const int attrs[] = {GLX_PBUFFER_WIDTH, w, GLX_PBUFFER_HEIGHT, h, None};
    return glXCreatePbuffer(dpy, config, attrs);
}

/* The drawing thread's: an X window of W x H. */
static uintptr_t ws_frame_surface(void)
{
    XVisualInfo *vi = glXGetVisualFromFBConfig(dpy, config);
    if (!vi)
        return 0;
    XSetWindowAttributes swa = {0};
    swa.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
    Window win = XCreateWindow(dpy, RootWindow(dpy, vi->screen), 0, 0, W, H, 0, vi->depth, InputOutput, vi->visual,
                               CWColormap, &swa);
    XFree(vi);
    XMapWindow(dpy, win);
    return win;
}

static uintptr_t ws_loader_surface(void) { return ws_pbuffer(1, 1); }
static int ws_make_current(uintptr_t s, void *ctx) { return glXMakeContextCurrent(dpy, s, s, ctx); }
static void ws_swap(uintptr_t s) { glXSwapBuffers(dpy, s); }
static unsigned ws_error(void) { return 0; }
static void ws_release_thread(void) {}
static void ws_destroy_context(void *ctx) { glXDestroyContext(dpy, ctx); }
static void ws_destroy_pbuffer(uintptr_t s) { glXDestroyPbuffer(dpy, s); }
static void ws_destroy_frame_surface(uintptr_t s) { XDestroyWindow(dpy, s); }
static void ws_end(void) { XCloseDisplay(dpy); }
#else
static EGLDisplay dpy;
static EGLConfig config;

static int ws_init(void)
{
    dpy = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, NULL, NULL) || !eglBindAPI(EGL_OPENGL_API))
        return 0;
    static const EGLint attrs[] = {
        EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_DEPTH_SIZE, 24, EGL_NONE};
    EGLint n = 0;
    return eglChooseConfig(dpy, attrs, &config, 1, &n) && n == 1;
}

static void *ws_context(void *share) { return eglCreateContext(dpy, config, share, NULL); }

static uintptr_t ws_pbuffer(int w, int h)
{
    const EGLint attrs[] = {EGL_WIDTH, w, EGL_HEIGHT, h, EGL_NONE};
    return (uintptr_t)eglCreatePbufferSurface(dpy, config, attrs);
}

static uintptr_t ws_frame_surface(void) { return ws_pbuffer(W, H); }
static uintptr_t ws_loader_surface(void) { return 0; } /* surfaceless */

static int ws_make_current(uintptr_t s, void *ctx)
{
    return eglMakeCurrent(dpy, (EGLSurface)s, (EGLSurface)s, ctx ? ctx : EGL_NO_CONTEXT);
}

static void ws_swap(uintptr_t s) { eglSwapBuffers(dpy, (EGLSurface)s); }
static unsigned ws_error(void) { return (unsigned)eglGetError(); }
static void ws_release_thread(void) { eglReleaseThread(); }
static void ws_destroy_context(void *ctx) { eglDestroyContext(dpy, ctx); }
static void ws_destroy_pbuffer(uintptr_t s) { eglDestroySurface(dpy, (EGLSurface)s); }
static void ws_destroy_frame_surface(uintptr_t s) { eglDestroySurface(dpy, (EGLSurface)s); }
static void ws_end(void) { eglTerminate(dpy); }
#endif

/* The hand-over: `loaded` frames have their slot ready, `drawn` frames are
 * read back (their slot may be loaded again). */
static pthread_mutex_t mu = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t cv = PTHREAD_COND_INITIALIZER;
static int loaded, drawn, started, loader_failed, drawer_failed;
static void *draw_ctx, *load_ctx;
static uintptr_t draw_surface, load_surface;

static void set(int *v, int value)
{
    pthread_mutex_lock(&mu);
    *v = value;
    pthread_cond_broadcast(&cv);
    pthread_mutex_unlock(&mu);
}

static int get(const int *v)
{
    pthread_mutex_lock(&mu);
    int x = *v;
    pthread_mutex_unlock(&mu);
    return x;
}

/* Waits until *v >= value or a thread failed; 0 when it failed. */
static int wait_for(const int *v, int value)
{
    pthread_mutex_lock(&mu);
    while (*v < value && !loader_failed && !drawer_failed)
        pthread_cond_wait(&cv, &mu);
    int ok = *v >= value;
    pthread_mutex_unlock(&mu);
    return ok;
}

static void *loader(void *arg)
{
    (void)arg;
    if (joined) {
        wait_for(&started, 1); /* the drawing thread draws already */
        load_ctx = ws_context(draw_ctx);
    }
    if (!load_ctx || !ws_make_current(load_surface, load_ctx)) {
        fprintf(stderr, "loader: cannot make its context current: 0x%x\n", ws_error());
        set(&loader_failed, 1);
        return NULL;
    }
    make_names();
    for (int f = 0; f < nframes; f++) {
        if (!wait_for(&drawn, f - 1)) /* frame f-2 used this slot */
            break;
        load(f % 2, f);
        glFinish(); /* the drawing thread may use them once this returns */
        set(&loaded, f + 1);
    }
    ws_make_current(0, NULL);
    ws_release_thread();
    return NULL;
}

static void *drawer(void *arg)
{
    (void)arg;
    if (!ws_make_current(draw_surface, draw_ctx)) {
        fprintf(stderr, "drawer: cannot make its context current: 0x%x\n", ws_error());
        set(&drawer_failed, 1);
        return NULL;
    }
    set(&started, 1);
    for (int f = 0; f < nframes; f++) {
        /* A loading screen while frame f's objects are not there (frames
         * it draws are not compared): a drawing loop does not block. */
        while (!get(&loaded) && !get(&loader_failed)) {
            glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
            glClear(GL_COLOR_BUFFER_BIT);
            ws_swap(draw_surface);
        }
        if (!wait_for(&loaded, f + 1))
            break;
        draw(f);
        threaded[f] = read_frame();
        ws_swap(draw_surface);
        set(&drawn, f + 1);
    }
    ws_make_current(0, NULL);
    ws_release_thread();
    return NULL;
}
int main(int argc, char **argv)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    if (argc < 2 || (strcmp(argv[1], "created") && strcmp(argv[1], "joined"))) {
        fprintf(stderr, "usage: %s created|joined [FRAMES 2-%d [RAW]]\n", argv[0], MAX_FRAMES);
        return 2;
    }
    joined = !strcmp(argv[1], "joined");
    if (argc > 2)
        nframes = atoi(argv[2]);
    if (nframes < 2 || nframes > MAX_FRAMES) {
        fprintf(stderr, "%s: FRAMES %s is not 2-%d\n", argv[0], argv[2], MAX_FRAMES);
        return 2;
    }
    const char *raw = argc > 3 ? argv[3] : NULL;
    REQUIRE(ws_init(), "no display or config: 0x%x", ws_error());

    /* The reference: one thread, one context, the same order. */
    void *ref_ctx = ws_context(NULL);
    uintptr_t ref_pb = ws_pbuffer(W, H);
    REQUIRE(ref_ctx && ref_pb && ws_make_current(ref_pb, ref_ctx), "reference context: 0x%x", ws_error());
    make_names();
    load(0, 0);
    for (int f = 0; f < nframes; f++) {
        draw(f);
        reference[f] = read_frame();
        REQUIRE(reference[f]);
        ws_swap(ref_pb);
        if (f + 1 < nframes)
            load((f + 1) % 2, f + 1);
    }
    /* Frames differ from each other, so a stale texture or list cannot pass. */
    for (int f = 1; f < nframes; f++)
        CHECK(differing(reference[f - 1], reference[f]) > 0, "frames %d and %d are alike", f - 1, f);
    CHECK(ws_make_current(0, NULL));

    draw_ctx = ws_context(NULL);
    draw_surface = ws_frame_surface();
    load_surface = ws_loader_surface();
    REQUIRE(draw_ctx && draw_surface);
    if (!joined) {
        load_ctx = ws_context(draw_ctx);
        REQUIRE(load_ctx);
    }
    pthread_t lt, dt;
    REQUIRE(pthread_create(&dt, NULL, drawer, NULL) == 0);
    REQUIRE(pthread_create(&lt, NULL, loader, NULL) == 0);
    pthread_join(lt, NULL);
    pthread_join(dt, NULL);
    CHECK(!loader_failed && !drawer_failed, "a thread could not make its context current");

    long bad = 0;
    int bad_frames = 0, missing = 0;
    FILE *out = raw ? fopen(raw, "wb") : NULL;
    if (raw)
        CHECK(out != NULL, "cannot write %s", raw);
    for (int f = 0; f < nframes; f++) {
        if (!threaded[f]) {
            missing++;
            continue;
        }
        long d = differing(threaded[f], reference[f]);
        if (d) {
            fprintf(stderr, "frame %d: %ld of %d pixels differ from the single-threaded frame\n", f, d, W * H);
            bad_frames++;
        }
        bad += d;
        if (out)
            fwrite(threaded[f], 4, (size_t)W * H, out);
    }
    if (out)
        CHECK(fclose(out) == 0, "cannot write %s", raw);
    printf("%s: loader and drawing threads of one share group: %d frames, %d missing, %ld differing pixels in %d "
           "frames\n",
           argv[1], nframes, missing, bad, bad_frames);
    CHECK(missing == 0, "%d frames were not drawn", missing);
    CHECK(bad == 0, "%ld pixels differ", bad);

    for (int f = 0; f < nframes; f++) {
        free(reference[f]);
        free(threaded[f]);
    }
    ws_destroy_context(load_ctx);
    ws_destroy_context(draw_ctx);
    ws_destroy_context(ref_ctx);
    ws_destroy_pbuffer(ref_pb);
    if (load_surface)
        ws_destroy_pbuffer(load_surface);
    ws_destroy_frame_surface(draw_surface);
    ws_end();
    printf("%s: %d failures\n", harness_failures ? "FAIL" : "OK", harness_failures);
    return harness_failures ? 1 : 0;
}
#else
int main(int argc, char **argv)
{
    if (argc != 4 || strcmp(argv[1], "native") || (nframes = atoi(argv[2])) < 2 || nframes > MAX_FRAMES) {
        fprintf(stderr, "usage: faker_egl_share_threads_native native FRAMES(2-%d) RAW\n", MAX_FRAMES);
        return 2;
    }
    static unsigned char buffer[W * H * 4];
    OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, NULL);
    REQUIRE(ctx && OSMesaMakeCurrent(ctx, buffer, GL_UNSIGNED_BYTE, W, H), "OSMesa context");
    FILE *out = fopen(argv[3], "wb");
    REQUIRE(out, "cannot write %s", argv[3]);
    make_names();
    load(0, 0);
    for (int f = 0; f < nframes; f++) {
        draw(f);
        reference[f] = read_frame();
        REQUIRE(reference[f]);
        fwrite(reference[f], 4, (size_t)W * H, out);
        free(reference[f]);
        if (f + 1 < nframes)
            load((f + 1) % 2, f + 1);
    }
    CHECK(fclose(out) == 0, "cannot write %s", argv[3]);
    OSMesaDestroyContext(ctx);
    printf("native: %d frames drawn with OSMesa into %s\n", nframes, argv[3]);
    return harness_failures ? 1 : 0;
}
#endif
