/* spus/render — draws the stream with OSMesa into an offscreen framebuffer
 * of the window's size and writes a PNG per SwapBuffersTSR. Owns, per
 * instance: the dlopen'ed OSMesa handle, one context, its framebuffer and
 * the frame counter. Never links against gl* symbols: every GL entry comes
 * from OSMesaGetProcAddress (so it cannot bind to the faker's own gl* when
 * both live in one process); never keeps state outside the instance.
 *
 * Context: RGBA, depth 24, stencil 8, accum 0 — exactly what the native
 * reference (examples/common/exapp.c, EXAPP_NATIVE) creates, so a stream
 * drawn here is bit-identical to the program drawn by OSMesa directly.
 *
 * Framebuffer size: the `width`/`height` options when non-zero (window
 * sizes are then ignored); otherwise the size of the last WindowCreateTSR
 * or WindowSizeTSR for this SPU's `window`, and 512x512 until one arrives.
 * The first window command resets viewport and scissor to the window, as a
 * window system does when a context is first made current on a window.
 * WindowDestroyTSR changes nothing here (it passes on to the child); the
 * framebuffer lives as long as the instance.
 *
 * Output: `output` is a pattern with one %d for the frame number (frames
 * count swaps of `window` from 0); empty = write nothing. Its directory
 * must exist when the instance is created (it is not created here, so a
 * typo fails at once instead of scattering files).
 *
 * Threads: OSMesa's current context is per thread. The context is made
 * current on the creating thread, and again by every window or swap
 * command that finds another context current on the calling thread. GL
 * calls go straight to OSMesa (no per-call check), so they reach the
 * context current on the calling thread: a thread that switches between
 * two render instances' tables must send one of those commands to the
 * instance it switches to before drawing. */
#include <dlfcn.h>
#include <errno.h>
#include <limits.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <GL/osmesa.h>

#include "tessera/glprocs_gen.h"
#include "tessera/image.h"
#include "tessera/log.h"
#include "tessera/spu.h"

#define RENDER_DEFAULT_SIDE 512
#define RENDER_MAX_SIDE 16384

/* The OSMesa functions this SPU calls, resolved with dlsym. */
typedef struct osmesa_api {
    OSMesaContext (*CreateContextExt)(GLenum format, GLint depth, GLint stencil, GLint accum,
                                      OSMesaContext sharelist);
    GLboolean (*MakeCurrent)(OSMesaContext ctx, void *buffer, GLenum type, GLsizei width,
                             GLsizei height);
    void (*DestroyContext)(OSMesaContext ctx);
    OSMesaContext (*GetCurrentContext)(void);
    OSMESAproc (*GetProcAddress)(const char *name);
} osmesa_api;

typedef struct render_spu {
    char name[96];
    void *library;             /* dlopen handle of libOSMesa */
    osmesa_api osmesa;
    OSMesaContext context;
    tsr_gl_procs gl;           /* every GL entry, through OSMesaGetProcAddress */
    const tsr_dispatch *child;

    const char *output;        /* option; owned by the chain, valid until destroy */
    int window;                /* which window id this instance renders */
    int fixed_width, fixed_height;
    bool window_seen;          /* a WindowCreate/Size arrived for `window` */

    unsigned char *buffer;     /* width * height RGBA, bottom row first */
    int width, height;
    int frame;                 /* number of the next frame written */
} render_spu;

static const char *const osmesa_library_names[] = {"libOSMesa.so.8", "libOSMesa.so.6",
                                                    "libOSMesa.so"};

static int load_osmesa(render_spu *r, tsr_error *err) {
    const char *last_error = "not found";
    for (size_t i = 0; i < sizeof osmesa_library_names / sizeof osmesa_library_names[0]; i++) {
        /* RTLD_LOCAL: OSMesa's gl* never become visible to the process.
         * RTLD_NODELETE: llvmpipe keeps threads and LLVM state that must
         * not be unmapped when the last instance goes away. */
        r->library = dlopen(osmesa_library_names[i], RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
        if (r->library)
            break;
        last_error = dlerror();
    }
    if (!r->library)
        return tsr_error_set(err, TSR_ENOENT, "%s: cannot load OSMesa (libOSMesa.so.8): %s",
                             r->name, last_error);
    struct {
        const char *symbol;
        void **slot;
    } wanted[] = {
        {"OSMesaCreateContextExt", (void **)&r->osmesa.CreateContextExt},
        {"OSMesaMakeCurrent", (void **)&r->osmesa.MakeCurrent},
        {"OSMesaDestroyContext", (void **)&r->osmesa.DestroyContext},
        {"OSMesaGetCurrentContext", (void **)&r->osmesa.GetCurrentContext},
        {"OSMesaGetProcAddress", (void **)&r->osmesa.GetProcAddress},
    };
    for (size_t i = 0; i < sizeof wanted / sizeof wanted[0]; i++) {
        *wanted[i].slot = dlsym(r->library, wanted[i].symbol);
        if (!*wanted[i].slot)
            return tsr_error_set(err, TSR_ENOENT, "%s: OSMesa has no %s", r->name,
                                 wanted[i].symbol);
    }
    return TSR_OK;
}

static tsr_proc osmesa_getproc(const char *gl_name, void *ctx) {
    render_spu *r = ctx;
    return (tsr_proc)r->osmesa.GetProcAddress(gl_name);
}

/* Points the context at a framebuffer of width x height (reallocated when
 * the size changes) and makes it current on this thread. */
static int bind_framebuffer(render_spu *r, int width, int height, tsr_error *err) {
    if (width != r->width || height != r->height || !r->buffer) {
        unsigned char *buffer = calloc((size_t)width * (size_t)height, 4);
        if (!buffer)
            return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory for a %dx%d framebuffer",
                                 r->name, width, height);
        free(r->buffer);
        r->buffer = buffer;
        r->width = width;
        r->height = height;
    }
    if (!r->osmesa.MakeCurrent(r->context, r->buffer, GL_UNSIGNED_BYTE, width, height))
        return tsr_error_set(err, TSR_EIO, "%s: OSMesaMakeCurrent failed for %dx%d", r->name,
                             width, height);
    return TSR_OK;
}

static void ensure_current(render_spu *r) {
    if (r->osmesa.GetCurrentContext() == r->context)
        return;
    tsr_error err = {0};
    if (bind_framebuffer(r, r->width, r->height, &err) != TSR_OK)
        tsr_log(TSR_LOG_ERROR, "%s", err.message);
}

/* The directory part of the output pattern (checked with frame 0) must be
 * an existing, writable directory. */
static int check_output(render_spu *r, tsr_error *err) {
    if (!r->output[0])
        return TSR_OK;
    char path[PATH_MAX];
    tsr_error pattern_err = {0};
    if (tsr_image_frame_path(path, sizeof path, r->output, 0, &pattern_err) != TSR_OK)
        return tsr_error_set(err, TSR_EINVAL, "%s: option output: %s", r->name,
                             pattern_err.message);
    char *slash = strrchr(path, '/');
    const char *dir = ".";
    if (slash == path)
        dir = "/";
    else if (slash) {
        *slash = '\0';
        dir = path;
    }
    struct stat st;
    if (stat(dir, &st) != 0)
        return tsr_error_set(err, TSR_ENOENT, "%s: option output=%s: directory '%s': %s",
                             r->name, r->output, dir, strerror(errno));
    if (!S_ISDIR(st.st_mode))
        return tsr_error_set(err, TSR_EINVAL, "%s: option output=%s: '%s' is not a directory",
                             r->name, r->output, dir);
    if (access(dir, W_OK | X_OK) != 0)
        return tsr_error_set(err, TSR_EIO, "%s: option output=%s: directory '%s': %s", r->name,
                             r->output, dir, strerror(errno));
    return TSR_OK;
}

/* --- the commands this SPU implements itself ------------------------------ */

static void resize_window(render_spu *r, GLsizei width, GLsizei height, const char *command) {
    if (r->fixed_width) {
        ensure_current(r);
        r->window_seen = true;
        return;
    }
    if (width < 1 || height < 1 || width > RENDER_MAX_SIDE || height > RENDER_MAX_SIDE) {
        tsr_log(TSR_LOG_ERROR, "%s: %s(%d, %d, %d): size out of range 1..%d, ignored", r->name,
                command, r->window, (int)width, (int)height, RENDER_MAX_SIDE);
        ensure_current(r);
        return;
    }
    tsr_error err = {0};
    if (bind_framebuffer(r, width, height, &err) != TSR_OK) {
        tsr_log(TSR_LOG_ERROR, "%s", err.message);
        return;
    }
    if (!r->window_seen) {
        r->gl.Viewport(0, 0, width, height);
        r->gl.Scissor(0, 0, width, height);
        r->window_seen = true;
    }
}

static void render_WindowCreateTSR(void *self, GLint window, GLsizei width, GLsizei height) {
    render_spu *r = self;
    if (window == r->window)
        resize_window(r, width, height, "WindowCreateTSR");
    tsr_call_WindowCreateTSR(r->child, window, width, height);
}

static void render_WindowSizeTSR(void *self, GLint window, GLsizei width, GLsizei height) {
    render_spu *r = self;
    if (window == r->window)
        resize_window(r, width, height, "WindowSizeTSR");
    tsr_call_WindowSizeTSR(r->child, window, width, height);
}

static void render_SwapBuffersTSR(void *self, GLint window, GLbitfield flags) {
    render_spu *r = self;
    if (window == r->window) {
        ensure_current(r);
        r->gl.Finish();
        int frame = r->frame++;
        if (r->output[0]) {
            char path[PATH_MAX];
            tsr_error err = {0};
            if (tsr_image_frame_path(path, sizeof path, r->output, frame, &err) != TSR_OK ||
                tsr_image_write_png_rgba(r->buffer, r->width, r->height, (size_t)r->width * 4,
                                         true, path, &err) != TSR_OK)
                tsr_log(TSR_LOG_ERROR, "%s: frame %d: %s", r->name, frame, err.message);
        }
    }
    tsr_call_SwapBuffersTSR(r->child, window, flags);
}

/* --- life cycle ---------------------------------------------------------- */

static void render_destroy(void *self) {
    render_spu *r = self;
    if (!r)
        return;
    if (r->context) {
        /* Leave no thread pointing at a context about to be freed. */
        if (r->osmesa.GetCurrentContext() == r->context)
            r->osmesa.MakeCurrent(NULL, NULL, 0, 0, 0);
        r->osmesa.DestroyContext(r->context);
    }
    if (r->library)
        dlclose(r->library);
    free(r->buffer);
    free(r);
}

static void *render_create(const tsr_spu_init *init, tsr_error *err) {
    render_spu *r = calloc(1, sizeof *r);
    if (!r) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    snprintf(r->name, sizeof r->name, "%s", init->instance_name);
    r->child = init->child;
    r->output = tsr_options_string(init->options, "output");
    if (!r->output)
        r->output = "";
    r->window = (int)tsr_options_int(init->options, "window");
    r->fixed_width = (int)tsr_options_int(init->options, "width");
    r->fixed_height = (int)tsr_options_int(init->options, "height");
    if ((r->fixed_width == 0) != (r->fixed_height == 0)) {
        tsr_error_set(err, TSR_EINVAL,
                      "%s: options width=%d and height=%d: give both or neither", r->name,
                      r->fixed_width, r->fixed_height);
        goto fail;
    }
    if (check_output(r, err) != TSR_OK || load_osmesa(r, err) != TSR_OK)
        goto fail;
    if (tsr_gl_procs_load(&r->gl, osmesa_getproc, r, err) != TSR_OK) {
        char detail[sizeof err->message];
        snprintf(detail, sizeof detail, "%s", err->message);
        tsr_error_set(err, TSR_ENOENT, "%s: %.400s", r->name, detail);
        goto fail;
    }
    /* Same attributes as the native reference: see the header comment. */
    r->context = r->osmesa.CreateContextExt(OSMESA_RGBA, 24, 8, 0, NULL);
    if (!r->context) {
        tsr_error_set(err, TSR_EIO, "%s: OSMesaCreateContextExt(RGBA, 24, 8, 0) failed", r->name);
        goto fail;
    }
    int width = r->fixed_width ? r->fixed_width : RENDER_DEFAULT_SIDE;
    int height = r->fixed_height ? r->fixed_height : RENDER_DEFAULT_SIDE;
    if (bind_framebuffer(r, width, height, err) != TSR_OK)
        goto fail;

    tsr_gl_procs_fill_dispatch(&r->gl, init->table);
    tsr_set_WindowCreateTSR(init->table, render_WindowCreateTSR, r);
    tsr_set_WindowSizeTSR(init->table, render_WindowSizeTSR, r);
    tsr_set_SwapBuffersTSR(init->table, render_SwapBuffersTSR, r);
    return r;
fail:
    render_destroy(r);
    return NULL;
}

static const tsr_option_spec render_options[] = {
    {.name = "output", .type = TSR_OPT_STRING, .default_value = "", .min = 1, .max = 0,
     .help = "PNG file per frame, one %d for the frame number (out/f-%04d.png); "
             "the directory must exist; empty: write nothing"},
    {.name = "width", .type = TSR_OPT_INT, .default_value = "0", .min = 0,
     .max = RENDER_MAX_SIDE,
     .help = "framebuffer width; 0: follow the window (512 until it is known)"},
    {.name = "height", .type = TSR_OPT_INT, .default_value = "0", .min = 0,
     .max = RENDER_MAX_SIDE,
     .help = "framebuffer height; 0: follow the window (512 until it is known)"},
    {.name = "window", .type = TSR_OPT_INT, .default_value = "0", .min = 0, .max = 2147483647.0,
     .help = "window id whose WindowCreate/Size/SwapBuffers this instance follows"},
};

static const tsr_spu_class render_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "render",
    .summary = "draws with OSMesa offscreen and writes a PNG per swap",
    .options = render_options,
    .option_count = sizeof render_options / sizeof render_options[0],
    .create = render_create,
    .destroy = render_destroy,
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &render_class; }
