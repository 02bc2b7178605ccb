/* tests/faker/egl_threads_test.c — faker_egl_threads [THREADS [FRAMES]], with no
 * X server, linked against the faker's libEGL.so.1 and libGL.so.1: THREADS
 * (2-4, default 3) threads, each with its own context and 64x48 pbuffer,
 * released together by a barrier every frame, draw FRAMES (default 12)
 * different frames at the same time (a clear and 40 depth-tested
 * triangles of that thread's and frame's colours), read each back with
 * glReadPixels and compare it with the same frame drawn beforehand by the
 * main thread alone: 0 differing pixels, every frame of every thread.
 * Then a context made with a current context of another thread as its
 * share list is made current while that thread has its share list
 * current (one share group is one stream, shared by the two threads;
 * tests/faker/egl_share_threads_driver.c draws with it), but a context current
 * on another thread is not (EGL_BAD_ACCESS) until that thread releases it.
 * Last, a share-list context made while its share list is already current
 * on another thread, which calls its plain table and makes no GL call:
 * its MakeCurrent waits the bounded 3 s and fails (EGL_BAD_ACCESS, one log
 * line), and succeeds once that thread made one glClear (where it moves to
 * the stream's locked table). */
#include <EGL/egl.h>
#include <GL/gl.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

#define W 64
#define H 48
#define MAX_THREADS 4
#define MAX_FRAMES 64
#define TRIANGLES 40

static EGLDisplay dpy;
static EGLConfig config;
static int nthreads = 3, nframes = 12;
static unsigned char *reference[MAX_THREADS][MAX_FRAMES];
static pthread_barrier_t barrier;

/* Thread `t`'s frame `f`: a pure function of (t, f), so the threaded
 * drawing can be compared with the single-threaded one. */
static void draw(int t, int f)
{
    unsigned seed = (unsigned)(t * 7919 + f * 104729 + 1);
    float rnd[TRIANGLES * 12];
    for (size_t i = 0; i < sizeof rnd / sizeof rnd[0]; i++) {
        seed = seed * 1103515245u + 12345u;
        rnd[i] = (float)((seed >> 8) & 0xffff) / 65535.0f;
    }
    glViewport(0, 0, W, H);
    glEnable(GL_DEPTH_TEST);
    glClearColor(0.25f * (float)t, (float)f / (float)nframes, 0.5f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glBegin(GL_TRIANGLES);
    for (int i = 0; i < TRIANGLES; i++) {
        const float *r = rnd + 12 * i;
        glColor3f(r[0], r[1], (float)t / 4.0f);
        for (int v = 0; v < 3; v++)
            glVertex3f(2.0f * r[3 + 3 * v] - 1.0f, 2.0f * r[4 + 3 * v] - 1.0f, 2.0f * r[5 + 3 * v] - 1.0f);
    }
    glEnd();
}

static unsigned char *read_frame(void)
{
    unsigned char *px = calloc((size_t)W * H, 4);
    if (px)
        glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, px);
    return px;
}

static long differing(const unsigned char *a, const unsigned char *b)
{
    long n = 0;
    for (size_t i = 0; i < (size_t)W * H; i++)
        n += memcmp(a + 4 * i, b + 4 * i, 4) != 0;
    return n;
}

typedef struct worker {
    int t;
    int made;       /* the context and pbuffer were made and current */
    long bad;       /* pixels that differ from the reference, all frames */
    int bad_frames; /* frames with any */
} worker;

static void *run(void *arg)
{
    worker *w = arg;
    static const EGLint pb_attrs[] = {EGL_WIDTH, W, EGL_HEIGHT, H, EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, NULL);
    EGLSurface pb = eglCreatePbufferSurface(dpy, config, pb_attrs);
    w->made = ctx != EGL_NO_CONTEXT && pb != EGL_NO_SURFACE && eglMakeCurrent(dpy, pb, pb, ctx);
    for (int f = 0; f < nframes; f++) {
        pthread_barrier_wait(&barrier); /* every thread draws frame f at once */
        if (!w->made)
            continue;
        draw(w->t, f);
        unsigned char *px = read_frame();
        long d = px && reference[w->t][f] ? differing(px, reference[w->t][f]) : W * H;
        if (d) {
            fprintf(stderr, "thread %d frame %d: %ld of %d pixels differ from the single-threaded frame\n", w->t, f, d,
                    W * H);
            w->bad_frames++;
        }
        w->bad += d;
        free(px);
        eglSwapBuffers(dpy, pb);
    }
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroySurface(dpy, pb);
    eglDestroyContext(dpy, ctx);
    eglReleaseThread();
    return NULL;
}

/* The share-list refusal: thread A keeps `a` current until told to stop. */
static pthread_mutex_t holder_mu = PTHREAD_MUTEX_INITIALIZER;
static pthread_cond_t holder_cv = PTHREAD_COND_INITIALIZER;
static int holder_state; /* hold: 0 start, 1 current, 2 release, 3 released (hold_plain: 1-5) */
static EGLContext holder_ctx;

static void holder_set(int state)
{
    pthread_mutex_lock(&holder_mu);
    holder_state = state;
    pthread_cond_broadcast(&holder_cv);
    pthread_mutex_unlock(&holder_mu);
}

static void holder_wait(int state)
{
    pthread_mutex_lock(&holder_mu);
    while (holder_state != state)
        pthread_cond_wait(&holder_cv, &holder_mu);
    pthread_mutex_unlock(&holder_mu);
}

/* The late share list: thread B keeps `plain` current, idle until told. */
static EGLContext plain_ctx;

static void *hold_plain(void *arg)
{
    (void)arg;
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, plain_ctx);
    glClear(GL_COLOR_BUFFER_BIT);
    holder_set(1);
    holder_wait(2);               /* no GL call meanwhile */
    glClear(GL_COLOR_BUFFER_BIT); /* a check point */
    holder_set(3);
    holder_wait(4);
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglReleaseThread();
    holder_set(5);
    return NULL;
}

static void *hold(void *arg)
{
    (void)arg;
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, holder_ctx);
    glClear(GL_COLOR_BUFFER_BIT);
    holder_set(1);
    holder_wait(2);
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglReleaseThread();
    holder_set(3);
    return NULL;
}

int main(int argc, char **argv)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    if (argc > 1)
        nthreads = atoi(argv[1]);
    if (argc > 2)
        nframes = atoi(argv[2]);
    if (nthreads < 1 || nthreads > MAX_THREADS || nframes < 1 || nframes > MAX_FRAMES) {
        fprintf(stderr, "usage: faker_egl_threads [THREADS 1-%d [FRAMES 1-%d]]\n", MAX_THREADS, MAX_FRAMES);
        return 2;
    }
    dpy = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    REQUIRE(dpy != EGL_NO_DISPLAY && eglInitialize(dpy, NULL, NULL), "eglInitialize: 0x%x", (unsigned)eglGetError());
    REQUIRE(eglBindAPI(EGL_OPENGL_API));
    static const EGLint attrs[] = {
        EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_DEPTH_SIZE, 24, EGL_NONE};
    EGLint n = 0;
    REQUIRE(eglChooseConfig(dpy, attrs, &config, 1, &n) && n == 1, "eglChooseConfig: 0x%x", (unsigned)eglGetError());

    /* The reference: every thread's frames, drawn by this thread alone. */
    static const EGLint pb_attrs[] = {EGL_WIDTH, W, EGL_HEIGHT, H, EGL_NONE};
    EGLContext ref_ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, NULL);
    EGLSurface ref_pb = eglCreatePbufferSurface(dpy, config, pb_attrs);
    REQUIRE(ref_ctx != EGL_NO_CONTEXT && ref_pb != EGL_NO_SURFACE && eglMakeCurrent(dpy, ref_pb, ref_pb, ref_ctx),
            "reference context: 0x%x", (unsigned)eglGetError());
    for (int t = 0; t < nthreads; t++)
        for (int f = 0; f < nframes; f++) {
            draw(t, f);
            reference[t][f] = read_frame();
            REQUIRE(reference[t][f]);
        }
    /* Frames of different threads differ, so a mix-up cannot pass. */
    for (int t = 1; t < nthreads; t++)
        CHECK(differing(reference[0][0], reference[t][0]) > W * H / 2, "threads 0 and %d draw alike", t);
    CHECK(eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT));

    pthread_barrier_init(&barrier, NULL, (unsigned)nthreads);
    pthread_t tid[MAX_THREADS];
    worker workers[MAX_THREADS] = {{0}};
    for (int t = 0; t < nthreads; t++) {
        workers[t].t = t;
        REQUIRE(pthread_create(&tid[t], NULL, run, &workers[t]) == 0);
    }
    for (int t = 0; t < nthreads; t++) {
        pthread_join(tid[t], NULL);
        printf("thread %d: %s, %d frames, %ld differing pixels in %d frames\n", workers[t].t,
               workers[t].made ? "context and pbuffer current" : "NOT CURRENT", nframes, workers[t].bad,
               workers[t].bad_frames);
        CHECK(workers[t].made, "thread %d could not make its context current", t);
        CHECK(workers[t].bad == 0, "thread %d: %ld pixels differ", t, workers[t].bad);
    }
    pthread_barrier_destroy(&barrier);

    /* A share list drawing through its plain table on another thread (the
     * first sharing of the program: its stream is not shared yet). */
    plain_ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, NULL);
    REQUIRE(plain_ctx != EGL_NO_CONTEXT);
    pthread_t holder;
    REQUIRE(pthread_create(&holder, NULL, hold_plain, NULL) == 0);
    holder_wait(1);
    EGLContext late = eglCreateContext(dpy, config, plain_ctx, NULL);
    REQUIRE(late != EGL_NO_CONTEXT);
    EGLBoolean refused = !eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, late);
    EGLint why = eglGetError();
    printf("share-list context while its share list idles on its plain table on another thread: %s (0x%x)\n",
           refused ? "refused" : "made current", (unsigned)why);
    CHECK(refused && why == EGL_BAD_ACCESS, "eglMakeCurrent gave 0x%x", (unsigned)why);
    holder_set(2);
    holder_wait(3);
    EGLBoolean made = eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, late);
    printf("after that thread's glClear: %s (0x%x)\n", made ? "made current" : "refused", (unsigned)eglGetError());
    CHECK(made, "still refused after the other thread's glClear");
    glClear(GL_COLOR_BUFFER_BIT);
    CHECK(eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT));
    holder_set(4);
    holder_wait(5);
    pthread_join(holder, NULL);
    eglDestroyContext(dpy, late);
    eglDestroyContext(dpy, plain_ctx);

    /* Share lists across threads drawing at once: allowed; a context
     * current on another thread: refused, then allowed once released. */
    holder_ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, NULL);
    EGLContext shared = eglCreateContext(dpy, config, holder_ctx, NULL);
    REQUIRE(holder_ctx != EGL_NO_CONTEXT && shared != EGL_NO_CONTEXT);
    REQUIRE(pthread_create(&holder, NULL, hold, NULL) == 0);
    holder_wait(1);
    made = eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, shared);
    printf("share-list context while its share list is current on another thread: %s (0x%x)\n",
           made ? "made current" : "refused", (unsigned)eglGetError());
    CHECK(made, "the share-list context was refused");
    glClear(GL_COLOR_BUFFER_BIT);
    refused = !eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, holder_ctx);
    why = eglGetError();
    printf("a context current on another thread: %s (0x%x)\n", refused ? "refused" : "made current", (unsigned)why);
    CHECK(refused && why == EGL_BAD_ACCESS, "eglMakeCurrent gave 0x%x", (unsigned)why);
    holder_set(2);
    holder_wait(3);
    pthread_join(holder, NULL);
    CHECK(eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, holder_ctx), "after release: 0x%x",
          (unsigned)eglGetError());
    CHECK(eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT));
    eglDestroyContext(dpy, shared);
    eglDestroyContext(dpy, holder_ctx);


    for (int t = 0; t < nthreads; t++)
        for (int f = 0; f < nframes; f++)
            free(reference[t][f]);
    eglDestroySurface(dpy, ref_pb);
    eglDestroyContext(dpy, ref_ctx);
    eglTerminate(dpy);
    printf("%s: %d failures\n", harness_failures ? "FAIL" : "OK", harness_failures);
    return harness_failures ? 1 : 0;
}
