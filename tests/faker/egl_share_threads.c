/* tests/faker/egl_share_threads.c — faker_egl_share_threads MODE [FRAMES
 * [RAW]], with no X server, linked against the faker's libEGL.so.1 and
 * libGL.so.1: a loader thread and a drawing thread with contexts of ONE
 * share group, drawing at the same time. The loader makes the textures
 * and display lists (glGenTextures, glGenLists) and, frame after frame,
 * uploads frame f+1's texture and compiles its list into one of two slots
 * (then glFinish and a signal) while the drawing thread draws frame f
 * from the other slot into its 64x48 pbuffer (clear, glCallList of the
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
#ifdef SHARE_NATIVE
#include <GL/osmesa.h>
#else
#include <EGL/egl.h>
#endif
#include <GL/gl.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

#define W 64
#define H 48
#define TEX 16
#define MAX_FRAMES 32
#define QUADS 6

#ifndef SHARE_NATIVE
static EGLDisplay dpy;
static EGLConfig config;
#endif
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
/* The hand-over: `loaded` frames have their slot ready, `drawn` frames are
 * read back (their slot may be loaded again). */
static pthread_mutex_t mu = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t cv = PTHREAD_COND_INITIALIZER;
static int loaded, drawn, started, loader_failed, drawer_failed;
static EGLContext draw_ctx, load_ctx;
static EGLSurface draw_pb;

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
        load_ctx = eglCreateContext(dpy, config, draw_ctx, NULL);
    }
    if (load_ctx == EGL_NO_CONTEXT || !eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, load_ctx)) {
        fprintf(stderr, "loader: cannot make its context current: 0x%x\n", (unsigned)eglGetError());
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
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglReleaseThread();
    return NULL;
}

static void *drawer(void *arg)
{
    (void)arg;
    if (!eglMakeCurrent(dpy, draw_pb, draw_pb, draw_ctx)) {
        fprintf(stderr, "drawer: cannot make its context current: 0x%x\n", (unsigned)eglGetError());
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
            eglSwapBuffers(dpy, draw_pb);
        }
        if (!wait_for(&loaded, f + 1))
            break;
        draw(f);
        threaded[f] = read_frame();
        eglSwapBuffers(dpy, draw_pb);
        set(&drawn, f + 1);
    }
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglReleaseThread();
    return NULL;
}
int main(int argc, char **argv)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    if (argc < 2 || (strcmp(argv[1], "created") && strcmp(argv[1], "joined"))) {
        fprintf(stderr, "usage: faker_egl_share_threads created|joined [FRAMES 2-%d [RAW]]\n", MAX_FRAMES);
        return 2;
    }
    joined = !strcmp(argv[1], "joined");
    if (argc > 2)
        nframes = atoi(argv[2]);
    if (nframes < 2 || nframes > MAX_FRAMES) {
        fprintf(stderr, "faker_egl_share_threads: FRAMES %s is not 2-%d\n", argv[2], MAX_FRAMES);
        return 2;
    }
    const char *raw = argc > 3 ? argv[3] : NULL;
    dpy = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    REQUIRE(dpy != EGL_NO_DISPLAY && eglInitialize(dpy, NULL, NULL), "eglInitialize: 0x%x", (unsigned)eglGetError());
    REQUIRE(eglBindAPI(EGL_OPENGL_API));
    static const EGLint attrs[] = {
        EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_DEPTH_SIZE, 24, EGL_NONE};
    EGLint n = 0;
    REQUIRE(eglChooseConfig(dpy, attrs, &config, 1, &n) && n == 1, "eglChooseConfig: 0x%x", (unsigned)eglGetError());
    static const EGLint pb_attrs[] = {EGL_WIDTH, W, EGL_HEIGHT, H, EGL_NONE};

    /* The reference: one thread, one context, the same order. */
    EGLContext ref_ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, NULL);
    EGLSurface ref_pb = eglCreatePbufferSurface(dpy, config, pb_attrs);
    REQUIRE(ref_ctx != EGL_NO_CONTEXT && ref_pb != EGL_NO_SURFACE && eglMakeCurrent(dpy, ref_pb, ref_pb, ref_ctx),
            "reference context: 0x%x", (unsigned)eglGetError());
    make_names();
    load(0, 0);
    for (int f = 0; f < nframes; f++) {
        draw(f);
        reference[f] = read_frame();
        REQUIRE(reference[f]);
        eglSwapBuffers(dpy, ref_pb);
        if (f + 1 < nframes)
            load((f + 1) % 2, f + 1);
    }
    /* Frames differ from each other, so a stale texture or list cannot pass. */
    for (int f = 1; f < nframes; f++)
        CHECK(differing(reference[f - 1], reference[f]) > 0, "frames %d and %d are alike", f - 1, f);
    CHECK(eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT));

    draw_ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, NULL);
    draw_pb = eglCreatePbufferSurface(dpy, config, pb_attrs);
    REQUIRE(draw_ctx != EGL_NO_CONTEXT && draw_pb != EGL_NO_SURFACE);
    if (!joined) {
        load_ctx = eglCreateContext(dpy, config, draw_ctx, NULL);
        REQUIRE(load_ctx != EGL_NO_CONTEXT);
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
    eglDestroyContext(dpy, load_ctx);
    eglDestroyContext(dpy, draw_ctx);
    eglDestroySurface(dpy, draw_pb);
    eglDestroySurface(dpy, ref_pb);
    eglDestroyContext(dpy, ref_ctx);
    eglTerminate(dpy);
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
