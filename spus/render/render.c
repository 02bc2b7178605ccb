/* spus/render/render.c — the render SPU: draws the stream with OSMesa into
 * an offscreen framebuffer of the window's size and writes a PNG per
 * SwapBuffersTSR (one per owned tile on a wall's tile server), bit-identical
 * to the same program drawn by OSMesa directly; optionally shows each
 * frame in an X window too (xwindow.c). Compiled into the `render` plugin
 * (plugin.c: its class); SPUs that render like it and do more inherit it
 * through the SPU class's super (tessera/dev/render.h).
 *
 * Owns, per instance: the dlopen'ed OSMesa handle, its contexts (RGBA,
 * depth 24, stencil 8, accum 16: exactly the native reference's,
 * examples/common/exapp.c; the largest of every config the faker offers,
 * faker/configs.c), the framebuffer, the owned tiles, the
 * application's scissor state per context, and the frame counter.
 *
 * Never: links against gl* symbols (every GL entry comes from
 * OSMesaGetProcAddress, so it cannot bind to libtessera_gl's own gl* in
 * the same process); keeps state outside the instance; moves the
 * application's viewport or projection for tiles (only the scissor
 * changes); creates the output directory (a typo fails at once).
 *
 * Callers: OSMesa's current context is per thread. A thread that switches
 * between two render instances' tables must send a window or swap command
 * to the instance it switches to before drawing.
 *
 * This file is the instance's life cycle: OSMesa loaded, options checked,
 * the table filled, everything freed. The other jobs have a file each
 * (instance.h, which holds the instance, lists them): contexts.c (shared
 * mode), scissor.c (tiles and the scissor), textures.c (the texture
 * budget), pixels.c (Clear, CopyPixels, DrawPixels), frame.c (window
 * size and frame output), buffers.c (front and back buffers), xwindow.c
 * (window output).
 *
 * docs/render.md describes the behaviour in detail (framebuffer size,
 * output names, shared mode for several contexts, tiles, memory) and the
 * measurements behind it. */
#include <dlfcn.h>
#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tessera/dev/unpack.h"
#include "tessera/image.h"
#include "tessera/log.h"

#include "instance.h"

#define RENDER_DEFAULT_SIDE 512

static const char *const osmesa_library_names[] = {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"};

static int load_osmesa(render_spu *r, tsr_error *err)
{
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
        return tsr_error_set(err, TSR_ENOENT, "%s: cannot load OSMesa (libOSMesa.so.8): %s", r->name, last_error);
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
            return tsr_error_set(err, TSR_ENOENT, "%s: OSMesa has no %s", r->name, wanted[i].symbol);
    }
    return TSR_OK;
}

static tsr_proc osmesa_getproc(const char *gl_name, void *ctx)
{
    render_spu *r = ctx;
    return (tsr_proc)r->osmesa.GetProcAddress(gl_name);
}

/* Points the context at a framebuffer of width x height (reallocated when
 * the size changes) and makes it current on this thread. */
int render_bind_framebuffer(render_spu *r, int width, int height, tsr_error *err)
{
    if (width != r->width || height != r->height || !r->buffer) {
        unsigned char *buffer = calloc((size_t)width * (size_t)height, 4);
        if (!buffer)
            return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory for a %dx%d framebuffer", r->name, width, height);
        free(r->buffer);
        r->buffer = buffer;
        r->width = width;
        r->height = height;
    }
    if (!r->osmesa.MakeCurrent(r->context, r->buffer, GL_UNSIGNED_BYTE, width, height))
        return tsr_error_set(err, TSR_EIO, "%s: OSMesaMakeCurrent failed for %dx%d", r->name, width, height);
    return TSR_OK;
}

/* The output pattern must number its frames (or overwrite=1 say it need
 * not), and its directory part (checked with frame 0) must be an existing,
 * writable directory. */
static int check_output(render_spu *r, bool overwrite, tsr_error *err)
{
    if (!r->output[0])
        return TSR_OK;
    if (tsr_image_check_frame_pattern(r->name, "output", r->output, overwrite, "output_overwrite", err) != TSR_OK)
        return err->code;
    char path[PATH_MAX];
    tsr_error pattern_err = {0};
    if (tsr_image_frame_path(path, sizeof path, r->output, 0, &pattern_err) != TSR_OK)
        return tsr_error_set(err, TSR_EINVAL, "%s: option output: %s", r->name, pattern_err.message);
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
        return tsr_error_set(err, TSR_ENOENT, "%s: option output=%s: directory '%s': %s", r->name, r->output, dir,
                             strerror(errno));
    if (!S_ISDIR(st.st_mode))
        return tsr_error_set(err, TSR_EINVAL, "%s: option output=%s: '%s' is not a directory", r->name, r->output, dir);
    if (access(dir, W_OK | X_OK) != 0)
        return tsr_error_set(err, TSR_EIO, "%s: option output=%s: directory '%s': %s", r->name, r->output, dir,
                             strerror(errno));
    return TSR_OK;
}

/* A command of the stream this instance must not run: the stream fails
 * with this line (a server node drops its client, naming it), or, in the
 * application's own process, the line is logged. The caller skips it. */
__attribute__((format(printf, 2, 3))) void render_refuse(render_spu *r, const char *fmt, ...)
{
    char text[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    if (!tsr_unpacker_refuse("%s: %s", r->name, text))
        tsr_log(TSR_LOG_ERROR, "%s: %s, skipped", r->name, text);
}

/* --- life cycle ---------------------------------------------------------- */

static void render_destroy(void *self)
{
    render_spu *r = self;
    if (!r)
        return;
    if (r->reader.osmesa) {
        tsr_error err = {0};
        if (r->reader.fbo && render_attach_context(r, &r->reader, &err) == TSR_OK)
            r->fbo.DeleteFramebuffers(1, &r->reader.fbo);
        if (r->osmesa.GetCurrentContext() == r->reader.osmesa)
            r->osmesa.MakeCurrent(NULL, NULL, 0, 0, 0);
        r->osmesa.DestroyContext(r->reader.osmesa);
    }
    if (r->shared) {
        for (size_t i = r->ncontexts; i-- > 1;)
            render_destroy_context(r, i);
        tsr_error err = {0};
        if (render_shared_make_current(r, 0, &err) == TSR_OK) {
            render_fastdraw_release(r->fastdraw, &r->gl);
            if (r->contexts[0].fbo)
                r->fbo.DeleteFramebuffers(1, &r->contexts[0].fbo);
            if (r->ms_fbo)
                r->fbo.DeleteFramebuffers(1, &r->ms_fbo);
            GLuint rbs[6] = {r->color_rb, r->depth_rb, r->front_rb, r->ms_color_rb, r->ms_depth_rb, r->ms_front_rb};
            r->fbo.DeleteRenderbuffers(6, rbs); /* 0s are ignored */
        }
        render_destroy_retired(r);
        free(r->retired);
        free(r->contexts);
    }
    render_names_free(&r->app_fb_names); /* the objects went with their contexts */
    render_names_free(&r->app_rb_names);
    if (r->context) {
        /* Leave no thread pointing at a context about to be freed. */
        if (r->osmesa.GetCurrentContext() == r->context) {
            render_fastdraw_release(r->fastdraw, &r->gl);
            r->osmesa.MakeCurrent(NULL, NULL, 0, 0, 0);
        }
        r->osmesa.DestroyContext(r->context);
    }
    if (r->library)
        dlclose(r->library);
    render_xwindow_destroy(r->xwindow);
    free(r->buffer);
    free(r->tiles);
    free(r->tile_pixels);
    render_tex_free(&r->textures);
    render_fastdraw_destroy(r->fastdraw, r->name);
    tsr_glsl_names_destroy(r->names);
    free(r);
}

void *render_spu_create(const tsr_spu_init *init, tsr_error *err)
{
    render_spu *r = calloc(1, sizeof *r);
    if (!r) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    snprintf(r->name, sizeof r->name, "%s", init->instance_name);
    r->child = init->child;
    /* Window output first: a bad x_ option or an X display that cannot be
     * opened fails the instance before OSMesa is loaded. */
    tsr_error xerr = {0};
    if (!(r->xwindow = render_xwindow_create(init, &xerr)) && xerr.code) {
        tsr_error_set(err, xerr.code, "%s", xerr.message);
        goto fail;
    }
    r->output = tsr_options_string(init->options, "output");
    if (!r->output)
        r->output = "";
    r->window = (int)tsr_options_int(init->options, "window");
    r->fixed_width = (int)tsr_options_int(init->options, "width");
    r->fixed_height = (int)tsr_options_int(init->options, "height");
    r->max_texture_bytes = (uint64_t)tsr_options_int(init->options, "max_texture_bytes");
    r->max_window_pixels = (uint64_t)tsr_options_int(init->options, "max_window_pixels");
    if ((r->fixed_width == 0) != (r->fixed_height == 0)) {
        tsr_error_set(err, TSR_EINVAL, "%s: options width=%d and height=%d: give both or neither", r->name,
                      r->fixed_width, r->fixed_height);
        goto fail;
    }
    r->output_alpha = tsr_options_bool(init->options, "output_alpha");
    if (check_output(r, tsr_options_bool(init->options, "output_overwrite"), err) != TSR_OK ||
        load_osmesa(r, err) != TSR_OK)
        goto fail;
    if (tsr_gl_procs_load(&r->gl, osmesa_getproc, r, err) != TSR_OK) {
        char detail[sizeof err->message];
        snprintf(detail, sizeof detail, "%s", err->message);
        tsr_error_set(err, TSR_ENOENT, "%s: %.400s", r->name, detail);
        goto fail;
    }
    if (!(r->fastdraw =
              render_fastdraw_create(osmesa_getproc, r, tsr_options_bool(init->options, "fast_drawpixels")))) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", r->name);
        goto fail;
    }
    /* Same attributes as the native reference: see the header comment. */
    r->context = r->osmesa.CreateContextExt(OSMESA_RGBA, 24, 8, 16, NULL);
    if (!r->context) {
        tsr_error_set(err, TSR_EIO, "%s: OSMesaCreateContextExt(RGBA, 24, 8, 16) failed", r->name);
        goto fail;
    }
    int width = r->fixed_width ? r->fixed_width : RENDER_DEFAULT_SIDE;
    int height = r->fixed_height ? r->fixed_height : RENDER_DEFAULT_SIDE;
    if (render_bind_framebuffer(r, width, height, err) != TSR_OK)
        goto fail;
    /* GL's initial scissor: the drawable's size, test disabled. */
    r->solo_sc.box = (render_box){0, 0, width, height};
    r->tiles_gen = 1;
    r->solo_sc.applied = 1;
    r->max_attrib_depth = 16;
    r->gl.GetIntegerv(GL_MAX_ATTRIB_STACK_DEPTH, &r->max_attrib_depth);
    if (r->max_attrib_depth > RENDER_ATTRIB_DEPTH)
        r->max_attrib_depth = RENDER_ATTRIB_DEPTH;
    const char *tiles_text = tsr_options_string(init->options, "tiles");
    if (tiles_text && tiles_text[0]) {
        tsr_tile *tiles;
        size_t count;
        tsr_error tiles_err = {0};
        if (tsr_tiles_parse(tiles_text, false, &tiles, &count, &tiles_err) != TSR_OK) {
            tsr_error_set(err, TSR_EINVAL, "%s: option tiles=%s: %s", r->name, tiles_text, tiles_err.message);
            goto fail;
        }
        if (render_set_tiles(r, tiles, count, err) != TSR_OK)
            goto fail;
    }

    tsr_gl_procs_fill_dispatch(&r->gl, init->table);
    render_frame_install(r, init->table);
    render_contexts_install(r, init->table);
    render_buffers_install(r, init->table);
    render_multisample_install(r, init->table);
    render_appfbo_install(r, init->table);
    render_pixels_install(r, init->table);
    render_scissor_install(r, init->table);
    render_textures_install(r, init->table);
    /* last: wraps the shader/program slots set above (tessera/glsl_names.h) */
    if (!(r->names = tsr_glsl_names_create(init->table, err)))
        goto fail;
    return r;
fail:
    render_destroy(r);
    return NULL;
}

void render_spu_destroy(void *instance) { render_destroy(instance); }
