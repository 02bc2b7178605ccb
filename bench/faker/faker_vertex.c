/* bench/faker/faker_vertex.c — glVertex3f through the faker's exported
 * symbol (libGL.so.1 of the faker, opened with dlopen as a program's
 * loader would bind it), with an EGL surfaceless context current, into the
 * pack SPU's packer with the bounding box kept (the chain is
 * bench_packsink: the packer with a counting sink in place of the socket).
 * Against it, in the same run and process, the figure of bench_pack: the
 * same calls through a dispatch table filled by tsr_packer_fill_dispatch.
 * The difference is the faker's own cost: the exported entry, the calling
 * thread's current context, its table. One thread, one core. Then a
 * context is made with the current one as its share list, which makes the
 * stream shared (faker/core.c): the same calls through the locked table
 * (the faker's lock and a check of the chain's current context around
 * each call), the cost a share group drawn from several threads pays.
 * usage: bench_faker_vertex FAKER_DIR PACKSINK_DIR [--quick] [--csv FILE]
 * Figures: faker_vertex3f_mcalls, pack_vertex3f_bbox_mcalls,
 * faker_vs_pack, faker_vertex3f_shared_mcalls, faker_shared_vs_plain.
 * Never pass/fail. */
#include "bench_common.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <dlfcn.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/dev/pack.h"
#include "tessera/dispatch.h"

#define VERTEX_COUNT 4096u

typedef void (*vertex3f_fn)(GLfloat, GLfloat, GLfloat);
typedef void (*begin_fn)(GLenum);
typedef void (*end_fn)(void);

static float *make_vertices(void)
{
    float *v = malloc(VERTEX_COUNT * 3 * sizeof *v);
    uint32_t seed = 12345u;
    for (unsigned i = 0; v && i < VERTEX_COUNT * 3; i++) {
        seed = seed * 1664525u + 1013904223u;
        v[i] = (float)(seed >> 8) / (float)(1u << 24) * 2.0f - 1.0f;
    }
    return v;
}

static double time_exported(vertex3f_fn vertex3f, const float *v, uint64_t calls)
{
    double t0 = bench_now();
    for (uint64_t done = 0; done < calls;) {
        uint64_t n = calls - done < VERTEX_COUNT ? calls - done : VERTEX_COUNT;
        for (uint64_t i = 0; i < n; i++)
            vertex3f(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
        done += n;
    }
    return bench_now() - t0;
}

static double time_table(const tsr_dispatch *table, const float *v, uint64_t calls)
{
    double t0 = bench_now();
    for (uint64_t done = 0; done < calls;) {
        uint64_t n = calls - done < VERTEX_COUNT ? calls - done : VERTEX_COUNT;
        for (uint64_t i = 0; i < n; i++)
            tsr_call_Vertex3f(table, v[3 * i], v[3 * i + 1], v[3 * i + 2]);
        done += n;
    }
    return bench_now() - t0;
}

static int count_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    (void)err;
    bench_keep(buf);
    *(uint64_t *)ctx += size;
    return 0;
}

static void *open_or_die(const char *dir, const char *name)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    void *h = dlopen(path, RTLD_NOW | RTLD_GLOBAL);
    if (!h) {
        fprintf(stderr, "bench_faker_vertex: %s\n", dlerror());
        exit(1);
    }
    return h;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: bench_faker_vertex FAKER_DIR PACKSINK_DIR [--quick] [--csv FILE]\n");
        return 2;
    }
    bench_args args;
    if (bench_parse_args(argc - 2, argv + 2, &args, NULL) != 0)
        return 2;
    const uint64_t calls = args.quick ? 100000u : 20000000u;
    setenv("TESSERA_SPU_PATH", argv[2], 1);
    setenv("TESSERA_CHAIN", "bench_packsink", 1);

    void *egl = open_or_die(argv[1], "libEGL.so.1");
    void *gl = open_or_die(argv[1], "libGL.so.1");
#define LOAD(lib, type, name) type name = (type)dlsym(lib, #name)
    LOAD(egl, PFNEGLGETPLATFORMDISPLAYPROC, eglGetPlatformDisplay);
    LOAD(egl, PFNEGLINITIALIZEPROC, eglInitialize);
    LOAD(egl, PFNEGLBINDAPIPROC, eglBindAPI);
    LOAD(egl, PFNEGLCHOOSECONFIGPROC, eglChooseConfig);
    LOAD(egl, PFNEGLCREATECONTEXTPROC, eglCreateContext);
    LOAD(egl, PFNEGLCREATEPBUFFERSURFACEPROC, eglCreatePbufferSurface);
    LOAD(egl, PFNEGLMAKECURRENTPROC, eglMakeCurrent);
    LOAD(egl, PFNEGLTERMINATEPROC, eglTerminate);
    LOAD(egl, PFNEGLDESTROYCONTEXTPROC, eglDestroyContext);
    LOAD(egl, PFNEGLDESTROYSURFACEPROC, eglDestroySurface);
    LOAD(gl, end_fn, glFinish);
    LOAD(gl, vertex3f_fn, glVertex3f);
    LOAD(gl, begin_fn, glBegin);
    LOAD(gl, end_fn, glEnd);
#undef LOAD
    if (!eglGetPlatformDisplay || !eglMakeCurrent || !glFinish || !eglDestroyContext || !eglDestroySurface ||
        !glVertex3f || !glBegin || !glEnd) {
        fprintf(stderr, "bench_faker_vertex: the faker lacks an EGL or GL entry point\n");
        return 1;
    }
    EGLDisplay dpy = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    static const EGLint config_attrs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                          EGL_NONE};
    static const EGLint pbuffer_attrs[] = {EGL_WIDTH, 64, EGL_HEIGHT, 64, EGL_NONE};
    EGLConfig config;
    EGLint n = 0;
    if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, NULL, NULL) || !eglBindAPI(EGL_OPENGL_API) ||
        !eglChooseConfig(dpy, config_attrs, &config, 1, &n) || n != 1) {
        fprintf(stderr, "bench_faker_vertex: no surfaceless EGL display/config from the faker\n");
        return 1;
    }
    EGLContext ctx = eglCreateContext(dpy, config, EGL_NO_CONTEXT, NULL);
    EGLSurface pb = eglCreatePbufferSurface(dpy, config, pbuffer_attrs);
    if (ctx == EGL_NO_CONTEXT || pb == EGL_NO_SURFACE || !eglMakeCurrent(dpy, pb, pb, ctx)) {
        fprintf(stderr, "bench_faker_vertex: cannot make a faker context current\n");
        return 1;
    }

    float *v = make_vertices();
    uint64_t table_bytes = 0;
    tsr_pack_sink sink = {.flush = count_flush, .ctx = &table_bytes};
    tsr_error err;
    tsr_error_clear(&err);
    tsr_packer *packer = tsr_packer_create(1u << 20, &sink, &err);
    if (!v || !packer) {
        fprintf(stderr, "bench_faker_vertex: %s\n", packer ? "out of memory" : err.message);
        return 1;
    }
    tsr_dispatch table;
    tsr_dispatch_fill_nop(&table);
    tsr_packer_fill_dispatch(packer, &table);

    FILE *csv = bench_csv_open(args.csv_path, "benchmark,repeat,calls,seconds,mcalls_per_s");
    glBegin(GL_POINTS);
    tsr_call_Begin(&table, GL_POINTS);
    time_exported(glVertex3f, v, calls / 10 + 1); /* warm-up: page in the buffers */
    time_table(&table, v, calls / 10 + 1);
    double best_faker = 0, best_table = 0;
    for (int r = 0; r < args.repeats; r++) {
        /* Interleaved, so a change of the machine's load hits both. */
        double tf = time_exported(glVertex3f, v, calls), tt = time_table(&table, v, calls);
        if ((double)calls / tf > best_faker)
            best_faker = (double)calls / tf;
        if ((double)calls / tt > best_table)
            best_table = (double)calls / tt;
        if (csv) {
            fprintf(csv, "faker_vertex3f,%d,%llu,%.6f,%.3f\n", r, (unsigned long long)calls, tf, calls / tf * 1e-6);
            fprintf(csv, "pack_vertex3f_bbox,%d,%llu,%.6f,%.3f\n", r, (unsigned long long)calls, tt, calls / tt * 1e-6);
        }
    }
    /* The shared stream: every call through the locked table from here. */
    EGLContext share = eglCreateContext(dpy, config, ctx, NULL);
    if (share == EGL_NO_CONTEXT) {
        fprintf(stderr, "bench_faker_vertex: cannot make a share-list context\n");
        return 1;
    }
    time_exported(glVertex3f, v, calls / 10 + 1);
    double best_shared = 0;
    for (int r = 0; r < args.repeats; r++) {
        double ts = time_exported(glVertex3f, v, calls);
        if ((double)calls / ts > best_shared)
            best_shared = (double)calls / ts;
        if (csv)
            fprintf(csv, "faker_vertex3f_shared,%d,%llu,%.6f,%.3f\n", r, (unsigned long long)calls, ts,
                    calls / ts * 1e-6);
    }
    glEnd();
    tsr_call_End(&table);
    glFinish(); /* bench_packsink prints what it packed */
    if (csv)
        fclose(csv);
    tsr_packer_flush(packer);
    if (tsr_packer_error(packer)->code != TSR_OK) {
        fprintf(stderr, "bench_faker_vertex: packer error: %s\n", tsr_packer_error(packer)->message);
        return 1;
    }
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroySurface(dpy, pb);
    eglDestroyContext(dpy, share);
    eglDestroyContext(dpy, ctx);
    eglTerminate(dpy);
    bench_figure("faker_vertex3f_mcalls", best_faker * 1e-6, 1);
    bench_figure("pack_vertex3f_bbox_mcalls", best_table * 1e-6, 1);
    bench_figure("faker_vs_pack", best_faker / best_table, 3);
    bench_figure("faker_vertex3f_shared_mcalls", best_shared * 1e-6, 1);
    bench_figure("faker_shared_vs_plain", best_shared / best_faker, 3);
    tsr_packer_destroy(packer);
    free(v);
    return 0;
}
