/* spus/render/render.c — the render SPU: draws the stream with OSMesa into
 * an offscreen framebuffer of the window's size and writes a PNG per
 * SwapBuffersTSR (one per owned tile on a wall's tile server), bit-identical
 * to the same program drawn by OSMesa directly. A static library
 * (render.h) that the `render` plugin and `readback` build on.
 *
 * Owns, per instance: the dlopen'ed OSMesa handle, its contexts (RGBA,
 * depth 24, stencil 8, accum 0: exactly the native reference's,
 * examples/common/exapp.c), the framebuffer, the owned tiles, the
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
 * docs/render.md describes the behaviour in detail (framebuffer size,
 * output names, shared mode for several contexts, tiles, memory) and the
 * measurements behind it. */
#include <dlfcn.h>
#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <GL/osmesa.h>

#include "tessera/dev/unpack.h"
#include "tessera/glprocs_gen.h"
#include "tessera/glsl_names.h"
#include "tessera/image.h"
#include "tessera/log.h"
#include "tessera/spu.h"
#include "tessera/tiles.h"

#include "budget.h"
#include "drawpixels.h"
#include "pages.h"
#include "render.h"

#define RENDER_DEFAULT_SIDE 512

/* The OSMesa functions this SPU calls, resolved with dlsym. */
typedef struct osmesa_api {
    OSMesaContext (*CreateContextExt)(GLenum format, GLint depth, GLint stencil, GLint accum, OSMesaContext sharelist);
    GLboolean (*MakeCurrent)(OSMesaContext ctx, void *buffer, GLenum type, GLsizei width, GLsizei height);
    void (*DestroyContext)(OSMesaContext ctx);
    OSMesaContext (*GetCurrentContext)(void);
    OSMESAproc (*GetProcAddress)(const char *name);
} osmesa_api;

/* Framebuffer-object entries for shared mode; not in the spec (clients
 * never send them), so resolved here. */
typedef struct fbo_api {
    void(GLAPIENTRY *GenRenderbuffers)(GLsizei n, GLuint *ids);
    void(GLAPIENTRY *DeleteRenderbuffers)(GLsizei n, const GLuint *ids);
    void(GLAPIENTRY *BindRenderbuffer)(GLenum target, GLuint id);
    void(GLAPIENTRY *RenderbufferStorage)(GLenum target, GLenum format, GLsizei w, GLsizei h);
    void(GLAPIENTRY *GenFramebuffers)(GLsizei n, GLuint *ids);
    void(GLAPIENTRY *DeleteFramebuffers)(GLsizei n, const GLuint *ids);
    void(GLAPIENTRY *BindFramebuffer)(GLenum target, GLuint id);
    void(GLAPIENTRY *FramebufferRenderbuffer)(GLenum target, GLenum attachment, GLenum rbtarget, GLuint rb);
    void(GLAPIENTRY *FramebufferParameteri)(GLenum target, GLenum pname, GLint value);
    GLenum(GLAPIENTRY *CheckFramebufferStatus)(GLenum target);
} fbo_api;

#ifndef GL_FRAMEBUFFER_FLIP_Y_MESA
#define GL_FRAMEBUFFER_FLIP_Y_MESA 0x8BBB
#endif

/* A rectangle of window pixels, origin bottom-left. */
typedef struct render_box {
    int x, y, w, h;
} render_box;

/* Deeper than any GL attribute stack (Mesa: 16); the real depth is
 * GL_MAX_ATTRIB_STACK_DEPTH, read at creation. */
#define RENDER_ATTRIB_DEPTH 64

/* What one PushAttrib saved of the scissor (docs/render.md, "Tiles"). */
typedef struct scissor_saved {
    GLbitfield mask;
    render_box box;
    bool enabled;
} scissor_saved;

/* The application's scissor state of one context, as it set it (the real
 * GL scissor may be narrowed to the tiles). */
typedef struct render_scissor {
    render_box box;
    bool enabled;
    scissor_saved stack[RENDER_ATTRIB_DEPTH];
    int depth;
    GLenum list_mode; /* mode of the display list being compiled, 0: none */
    unsigned applied; /* tiles generation the real scissor was last set for */
    bool fitted;      /* the real scissor is fitted to tiles (else: the application's) */
} render_scissor;

/* One context of shared mode; contexts[0] is the instance's own. */
/* Left clients' contexts kept before the window is given new storage to
 * free them (shared_resize): bounds their memory on a node that serves
 * many clients in turn at one window size. */
#define RENDER_RETIRED_MAX 8

typedef struct render_context {
    int id;
    OSMesaContext osmesa;
    GLuint fbo;        /* this context's FBO on the shared renderbuffers */
    unsigned attached; /* renderbuffer generation the FBO was attached at */
    bool window_seen;  /* its first window command reset viewport/scissor */
    render_scissor sc;
} render_context;

typedef struct render_spu {
    char name[96];
    void *library; /* dlopen handle of libOSMesa */
    osmesa_api osmesa;
    OSMesaContext context;
    tsr_gl_procs gl;       /* every GL entry, through OSMesaGetProcAddress */
    tsr_glsl_names *names; /* the stream's shader/program names -> the driver's */
    const tsr_dispatch *child;

    const char *output; /* option; owned by the chain, valid until destroy */
    int window;         /* which window id this instance renders */
    int fixed_width, fixed_height;
    bool window_seen; /* a WindowCreate/Size arrived for `window` */

    unsigned char *buffer; /* width * height RGBA, bottom row first */
    int width, height;
    int frame; /* number of the next frame written */

    /* Shared mode (docs/render.md, "Several contexts, one window"): entered
     * by the first ContextCreateTSR. */
    bool shared;
    fbo_api fbo;
    render_context *contexts; /* [0] = `context` */
    size_t ncontexts, contexts_cap;
    size_t current;            /* index into contexts */
    GLuint color_rb, depth_rb; /* the window: shared by every context */
    /* Contexts of clients that left, kept alive until the shared
     * renderbuffers are next given new storage (or deleted): Mesa caches a
     * renderbuffer's surface with the context that last validated it and
     * releases it through that context when the storage changes, so a
     * context destroyed before then leaves a dangling pointer that the next
     * resize calls through (a crash seen when a dropped client was followed
     * by another client's WindowCreateTSR). */
    OSMesaContext *retired;
    size_t nretired, retired_cap;
    unsigned generation;    /* bumped when the renderbuffers are resized */
    unsigned char dummy[4]; /* 1x1 drawable: contexts draw through FBOs */

    /* Tiles (docs/render.md, "Tiles"): none = the whole window. */
    tsr_tile *tiles;
    size_t ntiles;
    render_box bounds;      /* bounding rectangle of the tiles */
    unsigned tiles_gen;     /* bumped whenever the tiles change; starts at 1 */
    bool released;          /* the renderbuffers were allocated tiled */
    render_scissor solo_sc; /* the scissor before shared mode */
    int max_attrib_depth;
    render_context reader; /* reads the tiles back; never gets client commands */
    unsigned char *tile_pixels;
    size_t tile_pixels_size;
    render_hooks hooks; /* render.h: what an SPU built on render does with each frame */

    /* Budgets per context (docs/render.md, "Budgets"); 0 = no limit. */
    uint64_t max_texture_bytes;
    uint64_t max_window_pixels;
    render_tex_table textures;
    render_fastdraw *fastdraw; /* drawpixels.h */
    /* The stream may have put a stencil value other than 0 in the window
     * (render_Clear says why it matters). */
    bool stencil_written;
} render_spu;

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
static int bind_framebuffer(render_spu *r, int width, int height, tsr_error *err)
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

/* --- tiles: the scissor ---------------------------------------------------- */

/* The scissor state of the context commands go to now. */
static render_scissor *current_scissor(render_spu *r) { return r->shared ? &r->contexts[r->current].sc : &r->solo_sc; }

static render_box box_intersect(render_box a, render_box b)
{
    long long x0 = a.x > b.x ? a.x : b.x, y0 = a.y > b.y ? a.y : b.y;
    long long x1 = (long long)a.x + a.w, y1 = (long long)a.y + a.h;
    long long bx1 = (long long)b.x + b.w, by1 = (long long)b.y + b.h;
    if (bx1 < x1)
        x1 = bx1;
    if (by1 < y1)
        y1 = by1;
    if (x1 <= x0 || y1 <= y0)
        return (render_box){0, 0, 0, 0};
    return (render_box){(int)x0, (int)y0, (int)(x1 - x0), (int)(y1 - y0)};
}

/* Real scissor := the application's own (inside a display list, whose
 * scissor commands GL runs unseen by us). */
static void scissor_set_raw(render_spu *r, const render_scissor *s)
{
    r->gl.Scissor(s->box.x, s->box.y, s->box.w, s->box.h);
    if (s->enabled)
        r->gl.Enable(GL_SCISSOR_TEST);
    else
        r->gl.Disable(GL_SCISSOR_TEST);
}

/* Sets the current context's real scissor: the application's when there
 * are no tiles; else always enabled, on the application's box (when its
 * test is enabled) intersected with the tiles' bounding rectangle. Not
 * while a list is compiled (it would be compiled too): EndList does it. */
static void scissor_apply(render_spu *r, render_scissor *s)
{
    if (s->list_mode)
        return;
    s->applied = r->tiles_gen;
    s->fitted = r->ntiles > 0;
    if (!r->ntiles) {
        scissor_set_raw(r, s);
        return;
    }
    render_box e = s->enabled ? box_intersect(s->box, r->bounds) : r->bounds;
    r->gl.Enable(GL_SCISSOR_TEST);
    r->gl.Scissor(e.x, e.y, e.w, e.h);
}

/* Reads the application's scissor back from GL (below). */
static void scissor_sync(render_spu *r, render_scissor *s);

/* Catches up with tiles that changed while this context was not current.
 * Without tiles, display lists run unwatched (no cost per CallList), so
 * the record is read back from GL before it is fitted to tiles. */
static void scissor_refresh(render_spu *r, render_scissor *s)
{
    if (s->applied == r->tiles_gen || s->list_mode)
        return;
    if (!s->fitted && r->ntiles)
        scissor_sync(r, s);
    scissor_apply(r, s);
}

/* Reads the application's scissor back from GL after GL ran commands we
 * did not see (a display list's), while the real state was the raw one. */
static void scissor_sync(render_spu *r, render_scissor *s)
{
    GLint box[4] = {0, 0, 0, 0}, depth = 0;
    r->gl.GetIntegerv(GL_SCISSOR_BOX, box);
    s->box = (render_box){box[0], box[1], box[2], box[3]};
    s->enabled = r->gl.IsEnabled(GL_SCISSOR_TEST) == GL_TRUE;
    /* A list may push or pop attributes: follow GL's depth. What a list
     * pushed is unknown here; it is recorded as saving no scissor state. */
    r->gl.GetIntegerv(GL_ATTRIB_STACK_DEPTH, &depth);
    if (depth > RENDER_ATTRIB_DEPTH)
        depth = RENDER_ATTRIB_DEPTH;
    while (s->depth > depth)
        s->depth--;
    while (s->depth < depth)
        s->stack[s->depth++] = (scissor_saved){.mask = 0};
}

/* --- shared mode ----------------------------------------------------------- */

/* Makes `c` current on this thread with its FBO attached to the current
 * renderbuffers. */
static int attach_context(render_spu *r, render_context *c, tsr_error *err)
{
    if (r->osmesa.GetCurrentContext() != c->osmesa &&
        !r->osmesa.MakeCurrent(c->osmesa, r->dummy, GL_UNSIGNED_BYTE, 1, 1))
        return tsr_error_set(err, TSR_EIO, "%s: OSMesaMakeCurrent failed for context %d", r->name, c->id);
    if (!c->fbo) {
        r->fbo.GenFramebuffers(1, &c->fbo);
        r->fbo.BindFramebuffer(GL_FRAMEBUFFER, c->fbo);
        r->fbo.FramebufferParameteri(GL_FRAMEBUFFER, GL_FRAMEBUFFER_FLIP_Y_MESA, GL_TRUE);
        c->attached = r->generation - 1;
    }
    if (c->attached != r->generation) {
        r->fbo.BindFramebuffer(GL_FRAMEBUFFER, c->fbo);
        r->fbo.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, r->color_rb);
        r->fbo.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, r->depth_rb);
        GLenum status = r->fbo.CheckFramebufferStatus(GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE)
            return tsr_error_set(err, TSR_EIO, "%s: context %d: framebuffer incomplete (0x%x)", r->name, c->id, status);
        c->attached = r->generation;
    }
    return TSR_OK;
}

/* Makes contexts[index] current on this thread with its FBO attached to
 * the current renderbuffers and its scissor fitted to the tiles. */
static int shared_make_current(render_spu *r, size_t index, tsr_error *err)
{
    if (attach_context(r, &r->contexts[index], err) != TSR_OK)
        return err->code;
    r->current = index;
    scissor_refresh(r, &r->contexts[index].sc);
    return TSR_OK;
}

/* Finishes the current context (so a context switched to next sees all
 * it drew: llvmpipe contexts rasterise independently) and makes
 * contexts[index] current. */
static int shared_switch(render_spu *r, size_t index, tsr_error *err)
{
    if (r->osmesa.GetCurrentContext() == r->contexts[index].osmesa && r->current == index)
        return TSR_OK;
    if (r->osmesa.GetCurrentContext())
        r->gl.Finish();
    return shared_make_current(r, index, err);
}

/* The surfaces the retired contexts made were released (through them)
 * when the storage they viewed was replaced or deleted, so they can go. */
static void destroy_retired(render_spu *r)
{
    for (size_t i = 0; i < r->nretired; i++) {
        if (r->osmesa.GetCurrentContext() == r->retired[i])
            r->osmesa.MakeCurrent(NULL, NULL, 0, 0, 0);
        r->osmesa.DestroyContext(r->retired[i]);
    }
    r->nretired = 0;
}

/* (Re)allocates the shared renderbuffers at width x height, in context 0
 * (renderbuffers belong to the share group), and the readback buffer;
 * then makes the current context current again. */
static int shared_resize(render_spu *r, int width, int height, tsr_error *err)
{
    if (width == r->width && height == r->height)
        return TSR_OK;
    /* The readback buffer of an untiled frame comes with its first swap
     * (shared_read_frame); a tiled server never needs one this size. */
    free(r->buffer);
    r->buffer = NULL;
    r->width = width;
    r->height = height;
    size_t back = r->current;
    if (shared_switch(r, 0, err) != TSR_OK)
        return err->code;
    /* Tiled: give back the zero pages llvmpipe wrote into the new storage
     * (pages.h); below a few MiB it is not worth a look at the maps. */
    size_t bytes = (size_t)width * (size_t)height * 4;
    bool release = r->ntiles > 0 && bytes >= ((size_t)4 << 20);
    render_page_map before = {0};
    if (release) {
        /* Old storage goes first: freed memory that the new storage then
         * reused would look old to the comparison of the maps. */
        r->fbo.BindRenderbuffer(GL_RENDERBUFFER, r->color_rb);
        r->fbo.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, 1, 1);
        r->fbo.BindRenderbuffer(GL_RENDERBUFFER, r->depth_rb);
        r->fbo.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, 1, 1);
        r->gl.Finish();
        render_pages_snapshot(&before);
    }
    r->fbo.BindRenderbuffer(GL_RENDERBUFFER, r->color_rb);
    r->fbo.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    r->fbo.BindRenderbuffer(GL_RENDERBUFFER, r->depth_rb);
    r->fbo.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);
    r->fbo.BindRenderbuffer(GL_RENDERBUFFER, 0);
    destroy_retired(r);
    if (release) {
        size_t given = render_pages_release(&before, bytes);
        render_pages_free(&before);
        tsr_log(TSR_LOG_DEBUG, "%s: %dx%d renderbuffers: %zu KiB of zero pages given back", r->name, width, height,
                given >> 10);
    }
    r->released = r->ntiles > 0;
    r->generation++;
    if (shared_make_current(r, 0, err) != TSR_OK)
        return err->code;
    return shared_switch(r, back, err);
}

/* Enters shared mode: resolves the FBO entries, puts context 0 on the
 * shared renderbuffers at the current size. */
static int shared_enter(render_spu *r, tsr_error *err)
{
    struct {
        const char *symbol;
        void **slot;
    } wanted[] = {
        {"glGenRenderbuffers", (void **)&r->fbo.GenRenderbuffers},
        {"glDeleteRenderbuffers", (void **)&r->fbo.DeleteRenderbuffers},
        {"glBindRenderbuffer", (void **)&r->fbo.BindRenderbuffer},
        {"glRenderbufferStorage", (void **)&r->fbo.RenderbufferStorage},
        {"glGenFramebuffers", (void **)&r->fbo.GenFramebuffers},
        {"glDeleteFramebuffers", (void **)&r->fbo.DeleteFramebuffers},
        {"glBindFramebuffer", (void **)&r->fbo.BindFramebuffer},
        {"glFramebufferRenderbuffer", (void **)&r->fbo.FramebufferRenderbuffer},
        {"glFramebufferParameteri", (void **)&r->fbo.FramebufferParameteri},
        {"glCheckFramebufferStatus", (void **)&r->fbo.CheckFramebufferStatus},
    };
    for (size_t i = 0; i < sizeof wanted / sizeof wanted[0]; i++) {
        *wanted[i].slot = (void *)r->osmesa.GetProcAddress(wanted[i].symbol);
        if (!*wanted[i].slot)
            return tsr_error_set(err, TSR_ENOENT, "%s: OSMesa has no %s (needed for several contexts)", r->name,
                                 wanted[i].symbol);
    }
    r->contexts = calloc(4, sizeof *r->contexts);
    if (!r->contexts)
        return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", r->name);
    r->contexts_cap = 4;
    r->ncontexts = 1;
    r->contexts[0] = (render_context){.id = 0, .osmesa = r->context, .window_seen = r->window_seen, .sc = r->solo_sc};
    r->current = 0;
    r->shared = true;
    /* Context 0 leaves the window-sized user buffer (shared_resize frees
     * and replaces it; OSMesa would copy into it at every glFinish). */
    if (!r->osmesa.MakeCurrent(r->context, r->dummy, GL_UNSIGNED_BYTE, 1, 1))
        return tsr_error_set(err, TSR_EIO, "%s: OSMesaMakeCurrent failed for context 0", r->name);
    r->fbo.GenRenderbuffers(1, &r->color_rb);
    r->fbo.GenRenderbuffers(1, &r->depth_rb);
    int width = r->width, height = r->height;
    r->width = r->height = 0; /* force the allocation */
    return shared_resize(r, width, height, err);
}

static size_t find_context(const render_spu *r, GLint id)
{
    for (size_t i = 0; i < r->ncontexts; i++)
        if (r->contexts[i].id == id)
            return i;
    return SIZE_MAX;
}

static void ensure_current(render_spu *r)
{
    tsr_error err = {0};
    if (r->shared) {
        if (r->osmesa.GetCurrentContext() != r->contexts[r->current].osmesa &&
            shared_make_current(r, r->current, &err) != TSR_OK)
            tsr_log(TSR_LOG_ERROR, "%s", err.message);
        return;
    }
    if (r->osmesa.GetCurrentContext() == r->context)
        return;
    if (bind_framebuffer(r, r->width, r->height, &err) != TSR_OK)
        tsr_log(TSR_LOG_ERROR, "%s", err.message);
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

/* --- tiles: ownership --------------------------------------------------------- */

/* Takes `tiles` (malloc'ed; ownership passes here; NULL/0 = the whole
 * window). The first tiles put the instance in shared mode (FBOs: OSMesa's
 * window buffer would be copied whole at every glFinish: docs/render.md,
 * "Memory"),
 * and renderbuffers allocated before any tiles are allocated again so the
 * pages outside the tiles are given back (their pixels are lost: tiles
 * come before the first frame). */
static int set_tiles(render_spu *r, tsr_tile *tiles, size_t count, tsr_error *err)
{
    free(r->tiles);
    r->tiles = tiles;
    r->ntiles = count;
    r->tiles_gen++;
    if (count) {
        long long x0 = tiles[0].x, y0 = tiles[0].y, x1 = x0, y1 = y0;
        for (size_t i = 0; i < count; i++) {
            long long tx1 = (long long)tiles[i].x + tiles[i].width;
            long long ty1 = (long long)tiles[i].y + tiles[i].height;
            x0 = tiles[i].x < x0 ? tiles[i].x : x0;
            y0 = tiles[i].y < y0 ? tiles[i].y : y0;
            x1 = tx1 > x1 ? tx1 : x1;
            y1 = ty1 > y1 ? ty1 : y1;
        }
        r->bounds = (render_box){(int)x0, (int)y0, (int)(x1 - x0), (int)(y1 - y0)};
        if (!r->shared) {
            if (shared_enter(r, err) != TSR_OK)
                return err->code;
        } else if (!r->released) {
            int w = r->width, h = r->height;
            r->width = r->height = 0; /* force the allocation */
            if (shared_resize(r, w, h, err) != TSR_OK)
                return err->code;
        }
    }
    scissor_refresh(r, current_scissor(r));
    return TSR_OK;
}

static void render_TilesTSR(void *self, GLint window, GLsizei count, const GLint *rects)
{
    render_spu *r = self;
    if (window == r->window) {
        tsr_tile *tiles = NULL;
        const char *bad = NULL;
        GLsizei i = 0;
        if (count < 0 || (count > 0 && !rects))
            bad = "bad count";
        else if (count > 0 && !(tiles = calloc((size_t)count, sizeof *tiles)))
            bad = "out of memory";
        for (; !bad && i < count; i++) {
            const GLint *q = rects + 4 * i;
            if (q[0] < 0 || q[1] < 0 || q[2] < 1 || q[3] < 1 || q[0] >= TSR_TILES_MAX_SIDE ||
                q[1] >= TSR_TILES_MAX_SIDE || q[2] > TSR_TILES_MAX_SIDE || q[3] > TSR_TILES_MAX_SIDE)
                bad = "x, y must be 0..16383 and width, height 1..16384";
            else
                tiles[i] = (tsr_tile){.x = q[0], .y = q[1], .width = q[2], .height = q[3]};
        }
        tsr_error err = {0};
        if (bad) {
            free(tiles);
            if (i > 0)
                tsr_log(TSR_LOG_ERROR, "%s: TilesTSR(%d, %d): rectangle %d [%d, %d, %d, %d]: %s, ignored", r->name,
                        (int)window, (int)count, (int)i - 1, rects[4 * (i - 1)], rects[4 * (i - 1) + 1],
                        rects[4 * (i - 1) + 2], rects[4 * (i - 1) + 3], bad);
            else
                tsr_log(TSR_LOG_ERROR, "%s: TilesTSR(%d, %d): %s, ignored", r->name, (int)window, (int)count, bad);
        } else if (set_tiles(r, tiles, (size_t)count, &err) != TSR_OK) {
            tsr_log(TSR_LOG_ERROR, "%s: TilesTSR: %s", r->name, err.message);
        }
    }
    tsr_call_TilesTSR(r->child, window, count, rects);
}

/* --- budgets ------------------------------------------------------------------ */

/* A command of the stream this instance must not run: the stream fails
 * with this line (a server node drops its client, naming it), or, in the
 * application's own process, the line is logged. The caller skips it. */
__attribute__((format(printf, 2, 3))) static void refuse(render_spu *r, const char *fmt, ...)
{
    char text[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    if (!tsr_unpacker_refuse("%s: %s", r->name, text))
        tsr_log(TSR_LOG_ERROR, "%s: %s, skipped", r->name, text);
}

/* The context whose budget a command is charged to. */
static GLint budget_owner(const render_spu *r) { return r->shared ? r->contexts[r->current].id : 0; }

/* The glGet enum of the texture bound for a TexImage target; 0 for proxy
 * targets (no storage) and targets GL refuses itself. */
static GLenum binding_of(GLenum target)
{
    switch (target) {
    case GL_TEXTURE_1D: return GL_TEXTURE_BINDING_1D;
    case GL_TEXTURE_2D: return GL_TEXTURE_BINDING_2D;
    case GL_TEXTURE_3D: return GL_TEXTURE_BINDING_3D;
    case GL_TEXTURE_RECTANGLE: return GL_TEXTURE_BINDING_RECTANGLE;
    case GL_TEXTURE_CUBE_MAP_POSITIVE_X:
    case GL_TEXTURE_CUBE_MAP_NEGATIVE_X:
    case GL_TEXTURE_CUBE_MAP_POSITIVE_Y:
    case GL_TEXTURE_CUBE_MAP_NEGATIVE_Y:
    case GL_TEXTURE_CUBE_MAP_POSITIVE_Z:
    case GL_TEXTURE_CUBE_MAP_NEGATIVE_Z: return GL_TEXTURE_BINDING_CUBE_MAP;
    default: return 0;
    }
}

/* Whether a texture image of width x height x depth may be specified now
 * (true: the caller runs it; the table then holds it). The texture bound
 * is asked of GL, so display lists and attribute stacks that bound it are
 * followed. Inside a list being compiled nothing is allocated yet: only
 * an image larger than the whole budget is refused there. */
static bool texture_admit(render_spu *r, const char *command, GLenum target, GLint level, GLint internalformat,
                          GLsizei width, GLsizei height, GLsizei depth, GLint border)
{
    GLenum binding = binding_of(target);
    if (!binding || level < 0 || border < 0 || border > 1)
        return true; /* no storage, or GL's own error */
    int64_t b2 = 2 * (int64_t)border;
    uint64_t bytes = render_tex_image_bytes(internalformat, width + b2, height + (height > 1 || border ? b2 : 0),
                                            depth + (depth > 1 || border ? b2 : 0));
    if (!bytes)
        return true;
    GLint owner = budget_owner(r);
    uint64_t max = r->max_texture_bytes;
    if (current_scissor(r)->list_mode) {
        if (max && bytes > max) {
            refuse(r,
                   "%s(target 0x%x, level %d, %dx%dx%d) in a display list: %llu bytes are over the texture "
                   "budget max_texture_bytes=%llu of context %d",
                   command, target, level, (int)width, (int)height, (int)depth, (unsigned long long)bytes,
                   (unsigned long long)max, (int)owner);
            return false;
        }
        return true;
    }
    GLint name = 0;
    r->gl.GetIntegerv(binding, &name);
    render_tex_image *old = render_tex_find(&r->textures, (GLuint)name, owner, target, level);
    uint64_t held = render_tex_held(&r->textures, owner) - (old && old->owner == owner ? old->bytes : 0);
    if (max && (bytes > max || held > max - bytes)) {
        refuse(r,
               "%s(target 0x%x, level %d, %dx%dx%d, texture %d): %llu bytes are over the texture budget "
               "max_texture_bytes=%llu of context %d (%llu bytes held)",
               command, target, level, (int)width, (int)height, (int)depth, (int)name, (unsigned long long)bytes,
               (unsigned long long)max, (int)owner, (unsigned long long)held);
        return false;
    }
    if (render_tex_set(&r->textures, (GLuint)name, owner, target, level, bytes) != 0) {
        refuse(r, "%s: out of memory for the texture table", command);
        return false;
    }
    return true;
}

static void render_TexImage1D(void *self, GLenum target, GLint level, GLint internalformat, GLsizei width, GLint border,
                              GLenum format, GLenum type, const void *pixels)
{
    render_spu *r = self;
    if (texture_admit(r, "TexImage1D", target, level, internalformat, width, 1, 1, border))
        r->gl.TexImage1D(target, level, internalformat, width, border, format, type, pixels);
}

static void render_TexImage2D(void *self, GLenum target, GLint level, GLint internalformat, GLsizei width,
                              GLsizei height, GLint border, GLenum format, GLenum type, const void *pixels)
{
    render_spu *r = self;
    if (texture_admit(r, "TexImage2D", target, level, internalformat, width, height, 1, border))
        r->gl.TexImage2D(target, level, internalformat, width, height, border, format, type, pixels);
}

static void render_TexImage3D(void *self, GLenum target, GLint level, GLint internalformat, GLsizei width,
                              GLsizei height, GLsizei depth, GLint border, GLenum format, GLenum type,
                              const void *pixels)
{
    render_spu *r = self;
    if (texture_admit(r, "TexImage3D", target, level, internalformat, width, height, depth, border))
        r->gl.TexImage3D(target, level, internalformat, width, height, depth, border, format, type, pixels);
}

static void render_CopyTexImage1D(void *self, GLenum target, GLint level, GLenum internalformat, GLint x, GLint y,
                                  GLsizei width, GLint border)
{
    render_spu *r = self;
    if (texture_admit(r, "CopyTexImage1D", target, level, (GLint)internalformat, width, 1, 1, border))
        r->gl.CopyTexImage1D(target, level, internalformat, x, y, width, border);
}

static void render_CopyTexImage2D(void *self, GLenum target, GLint level, GLenum internalformat, GLint x, GLint y,
                                  GLsizei width, GLsizei height, GLint border)
{
    render_spu *r = self;
    if (texture_admit(r, "CopyTexImage2D", target, level, (GLint)internalformat, width, height, 1, border))
        r->gl.CopyTexImage2D(target, level, internalformat, x, y, width, height, border);
}

/* Texture names the client binds or deletes may be ones the fast
 * DrawPixels keeps (drawpixels.h): it lets go of them first. */
static void render_BindTexture(void *self, GLenum target, GLuint texture)
{
    render_spu *r = self;
    render_fastdraw_client_name(r->fastdraw, &r->gl, texture, current_scissor(r)->list_mode != 0);
    r->gl.BindTexture(target, texture);
}

static GLboolean render_IsTexture(void *self, GLuint texture)
{
    render_spu *r = self;
    return render_fastdraw_owns(r->fastdraw, texture) ? GL_FALSE : r->gl.IsTexture(texture);
}

static void render_DeleteTextures(void *self, GLsizei n, const GLuint *textures)
{
    render_spu *r = self;
    for (GLsizei i = 0; i < n && textures; i++)
        render_fastdraw_client_name(r->fastdraw, &r->gl, textures[i], false);
    r->gl.DeleteTextures(n, textures);
    for (GLsizei i = 0; i < n && textures; i++)
        render_tex_forget(&r->textures, textures[i]);
}

/* --- the commands this SPU implements itself ------------------------------ */

/* The scissor commands (docs/render.md, "Tiles"): the application's state
 * is recorded, the real one is fitted to the tiles. */
static void render_Scissor(void *self, GLint x, GLint y, GLsizei width, GLsizei height)
{
    render_spu *r = self;
    render_scissor *s = current_scissor(r);
    /* Compiled into a list, or an error GL reports and ignores. */
    if (s->list_mode || width < 0 || height < 0) {
        r->gl.Scissor(x, y, width, height);
        return;
    }
    s->box = (render_box){x, y, width, height};
    if (r->ntiles)
        scissor_apply(r, s);
    else
        r->gl.Scissor(x, y, width, height);
}

static void enable_cap(render_spu *r, GLenum cap, bool on)
{
    render_scissor *s = current_scissor(r);
    if (cap == GL_STENCIL_TEST && on)
        r->stencil_written = true; /* (also when compiled into a list: it may run) */
    if (cap != GL_SCISSOR_TEST || s->list_mode || !r->ntiles) {
        if (on)
            r->gl.Enable(cap);
        else
            r->gl.Disable(cap);
        if (cap == GL_SCISSOR_TEST && !s->list_mode)
            s->enabled = on;
        return;
    }
    s->enabled = on;
    scissor_apply(r, s);
}

static void render_Enable(void *self, GLenum cap) { enable_cap(self, cap, true); }
static void render_Disable(void *self, GLenum cap) { enable_cap(self, cap, false); }

static void render_PushAttrib(void *self, GLbitfield mask)
{
    render_spu *r = self;
    render_scissor *s = current_scissor(r);
    r->gl.PushAttrib(mask);
    /* GL refuses a push beyond its depth (stack overflow) and so do we. */
    if (!s->list_mode && s->depth < r->max_attrib_depth)
        s->stack[s->depth++] = (scissor_saved){mask, s->box, s->enabled};
}

static void render_PopAttrib(void *self)
{
    render_spu *r = self;
    render_scissor *s = current_scissor(r);
    r->gl.PopAttrib();
    if (s->list_mode || s->depth == 0)
        return;
    scissor_saved e = s->stack[--s->depth];
    if (e.mask & GL_SCISSOR_BIT) {
        s->box = e.box;
        s->enabled = e.enabled;
    } else if (e.mask & GL_ENABLE_BIT) {
        s->enabled = e.enabled;
    }
    /* GL restored what the real scissor was at the push, perhaps fitted
     * to other tiles: set it again. */
    if (e.mask & (GL_SCISSOR_BIT | GL_ENABLE_BIT))
        scissor_apply(r, s);
}

/* Display lists run scissor commands inside GL where we cannot see them:
 * run them on the application's own scissor and read it back after. */
static void before_list(render_spu *r, render_scissor *s)
{
    if (s->fitted)
        scissor_set_raw(r, s);
}

static void after_list(render_spu *r, render_scissor *s)
{
    scissor_sync(r, s);
    if (r->ntiles || s->applied != r->tiles_gen)
        scissor_apply(r, s);
}

static void render_CallList(void *self, GLuint list)
{
    render_spu *r = self;
    render_scissor *s = current_scissor(r);
    if (s->list_mode || !s->fitted) {
        r->gl.CallList(list);
        return;
    }
    before_list(r, s);
    r->gl.CallList(list);
    after_list(r, s);
}

static void render_CallLists(void *self, GLsizei n, GLenum type, const void *lists)
{
    render_spu *r = self;
    render_scissor *s = current_scissor(r);
    if (s->list_mode || !s->fitted) {
        r->gl.CallLists(n, type, lists);
        return;
    }
    before_list(r, s);
    r->gl.CallLists(n, type, lists);
    after_list(r, s);
}

static void render_NewList(void *self, GLuint list, GLenum mode)
{
    render_spu *r = self;
    render_scissor *s = current_scissor(r);
    bool execute = mode == GL_COMPILE_AND_EXECUTE;
    if (s->list_mode) {
        r->gl.NewList(list, mode); /* GL's error: already compiling */
        return;
    }
    if (execute)
        before_list(r, s);
    r->gl.NewList(list, mode);
    GLint index = 0;
    r->gl.GetIntegerv(GL_LIST_INDEX, &index);
    if (list != 0 && (GLuint)index == list && (mode == GL_COMPILE || execute))
        s->list_mode = mode;
    else if (execute && s->fitted)
        scissor_apply(r, s); /* NewList failed: back to the fitted scissor */
}

static void render_EndList(void *self)
{
    render_spu *r = self;
    render_scissor *s = current_scissor(r);
    r->gl.EndList();
    GLenum mode = s->list_mode;
    s->list_mode = 0;
    if (mode == GL_COMPILE_AND_EXECUTE)
        after_list(r, s);
    else if (mode)
        scissor_refresh(r, s);
}

/* glGet of the scissor: the application's values, not the fitted ones
 * (inside a compile-and-execute list the real state is the application's). */
static bool scissor_query(render_spu *r, GLenum pname, double out[4], int *n)
{
    render_scissor *s = current_scissor(r);
    if (!s->fitted || s->list_mode == GL_COMPILE_AND_EXECUTE)
        return false; /* the real state is the application's */
    if (pname == GL_SCISSOR_BOX) {
        out[0] = s->box.x;
        out[1] = s->box.y;
        out[2] = s->box.w;
        out[3] = s->box.h;
        *n = 4;
        return true;
    }
    if (pname == GL_SCISSOR_TEST) {
        out[0] = s->enabled;
        *n = 1;
        return true;
    }
    return false;
}

static void render_GetIntegerv(void *self, GLenum pname, GLint *data)
{
    render_spu *r = self;
    double v[4];
    int n;
    if (!scissor_query(r, pname, v, &n)) {
        r->gl.GetIntegerv(pname, data);
        return;
    }
    for (int i = 0; i < n; i++)
        data[i] = (GLint)v[i];
}

static void render_GetFloatv(void *self, GLenum pname, GLfloat *data)
{
    render_spu *r = self;
    double v[4];
    int n;
    if (!scissor_query(r, pname, v, &n)) {
        r->gl.GetFloatv(pname, data);
        return;
    }
    for (int i = 0; i < n; i++)
        data[i] = (GLfloat)v[i];
}

static void render_GetDoublev(void *self, GLenum pname, GLdouble *data)
{
    render_spu *r = self;
    double v[4];
    int n;
    if (!scissor_query(r, pname, v, &n)) {
        r->gl.GetDoublev(pname, data);
        return;
    }
    for (int i = 0; i < n; i++)
        data[i] = v[i];
}

static void render_GetBooleanv(void *self, GLenum pname, GLboolean *data)
{
    render_spu *r = self;
    double v[4];
    int n;
    if (!scissor_query(r, pname, v, &n)) {
        r->gl.GetBooleanv(pname, data);
        return;
    }
    for (int i = 0; i < n; i++)
        data[i] = v[i] != 0.0 ? GL_TRUE : GL_FALSE;
}

static GLboolean render_IsEnabled(void *self, GLenum cap)
{
    render_spu *r = self;
    double v[4];
    int n;
    if (cap == GL_SCISSOR_TEST && scissor_query(r, cap, v, &n))
        return v[0] != 0.0 ? GL_TRUE : GL_FALSE;
    return r->gl.IsEnabled(cap);
}

/* Where "the first window command of this context" is remembered. */
static bool *window_seen_flag(render_spu *r)
{
    return r->shared ? &r->contexts[r->current].window_seen : &r->window_seen;
}

static void resize_window(render_spu *r, GLsizei width, GLsizei height, const char *command)
{
    if (r->fixed_width) {
        ensure_current(r);
        *window_seen_flag(r) = true;
        return;
    }
    uint64_t max_pixels = r->max_window_pixels ? r->max_window_pixels : (uint64_t)RENDER_MAX_SIDE * RENDER_MAX_SIDE;
    if (width >= 1 && height >= 1 && (uint64_t)width * (uint64_t)height > max_pixels) {
        refuse(r, "%s(%d, %d, %d): %llu pixels are over the window budget max_window_pixels=%llu", command, r->window,
               (int)width, (int)height, (unsigned long long)width * (unsigned long long)height,
               (unsigned long long)max_pixels);
        ensure_current(r);
        return;
    }
    if (width < 1 || height < 1 || width > RENDER_MAX_SIDE || height > RENDER_MAX_SIDE) {
        tsr_log(TSR_LOG_ERROR, "%s: %s(%d, %d, %d): size out of range 1..%d, ignored", r->name, command, r->window,
                (int)width, (int)height, RENDER_MAX_SIDE);
        ensure_current(r);
        return;
    }
    tsr_error err = {0};
    if ((r->shared ? shared_resize(r, width, height, &err) : bind_framebuffer(r, width, height, &err)) != TSR_OK) {
        tsr_log(TSR_LOG_ERROR, "%s", err.message);
        return;
    }
    bool *seen = window_seen_flag(r);
    if (!*seen) {
        r->gl.Viewport(0, 0, width, height);
        render_Scissor(r, 0, 0, width, height);
        *seen = true;
    }
}

static void render_WindowCreateTSR(void *self, GLint window, GLsizei width, GLsizei height)
{
    render_spu *r = self;
    if (window == r->window)
        resize_window(r, width, height, "WindowCreateTSR");
    tsr_call_WindowCreateTSR(r->child, window, width, height);
}

static void render_WindowSizeTSR(void *self, GLint window, GLsizei width, GLsizei height)
{
    render_spu *r = self;
    if (window == r->window)
        resize_window(r, width, height, "WindowSizeTSR");
    tsr_call_WindowSizeTSR(r->child, window, width, height);
}

/* Shared mode: reads the shared colour buffer into r->buffer through
 * context 0 (its pack state is never changed, unlike a client's). */
static void shared_read_frame(render_spu *r)
{
    tsr_error err = {0};
    if (!r->buffer && !(r->buffer = malloc((size_t)r->width * (size_t)r->height * 4))) {
        tsr_log(TSR_LOG_ERROR, "%s: out of memory for a %dx%d frame", r->name, r->width, r->height);
        return;
    }
    size_t back = r->current;
    if (shared_switch(r, 0, &err) != TSR_OK ||
        (r->gl.ReadPixels(0, 0, r->width, r->height, GL_RGBA, GL_UNSIGNED_BYTE, r->buffer),
         shared_switch(r, back, &err)) != TSR_OK)
        tsr_log(TSR_LOG_ERROR, "%s", err.message);
}

/* The file of one tile: the output pattern's, with "-tN" (N = the tile's
 * index in the tile list) put before the extension when there are several. */
static int tile_path(char *out, size_t size, const char *pattern, int frame, size_t tile, size_t ntiles, tsr_error *err)
{
    if (tsr_image_frame_path(out, size, pattern, frame, err) != TSR_OK)
        return err->code;
    if (ntiles == 1)
        return TSR_OK;
    char suffix[32];
    int n = snprintf(suffix, sizeof suffix, "-t%zu", tile);
    size_t len = strlen(out);
    if (len + (size_t)n + 1 > size)
        return tsr_error_set(err, TSR_EINVAL, "file name too long for tile %zu", tile);
    const char *slash = strrchr(out, '/');
    char *dot = strrchr(slash ? slash : out, '.');
    size_t at = dot ? (size_t)(dot - out) : len;
    memmove(out + at + n, out + at, len - at + 1);
    memcpy(out + at, suffix, (size_t)n);
    return TSR_OK;
}

/* Tiled swap: every context has finished (switching finishes the outgoing
 * one), the reader context reads each tile's pixels — and only those —
 * and writes one PNG per tile. The reader is a context of its own so no
 * client's pixel-store, pixel-transfer or read-buffer state applies. */
static void tiled_write_frame(render_spu *r, int frame)
{
    tsr_error err = {0};
    size_t back = r->current;
    if (r->osmesa.GetCurrentContext())
        r->gl.Finish();
    if (!r->reader.osmesa) {
        r->reader = (render_context){.id = -1};
        r->reader.osmesa = r->osmesa.CreateContextExt(OSMESA_RGBA, 24, 8, 0, r->context);
        if (!r->reader.osmesa) {
            tsr_log(TSR_LOG_ERROR, "%s: frame %d: OSMesaCreateContextExt failed for the tile reader", r->name, frame);
            return;
        }
    }
    if (attach_context(r, &r->reader, &err) != TSR_OK) {
        tsr_log(TSR_LOG_ERROR, "%s: frame %d: %s", r->name, frame, err.message);
    } else {
        render_box window = {0, 0, r->width, r->height};
        for (size_t i = 0; i < r->ntiles; i++) {
            const tsr_tile *t = &r->tiles[i];
            render_box b = box_intersect((render_box){t->x, t->y, t->width, t->height}, window);
            if (!b.w) {
                tsr_log(TSR_LOG_ERROR, "%s: frame %d: tile %zu [%d, %d, %d, %d] is outside the %dx%d window", r->name,
                        frame, i, t->x, t->y, t->width, t->height, r->width, r->height);
                continue;
            }
            size_t need = (size_t)b.w * (size_t)b.h * 4;
            if (need > r->tile_pixels_size) {
                unsigned char *p = realloc(r->tile_pixels, need);
                if (!p) {
                    tsr_log(TSR_LOG_ERROR, "%s: frame %d: out of memory for tile %zu", r->name, frame, i);
                    continue;
                }
                r->tile_pixels = p;
                r->tile_pixels_size = need;
            }
            r->gl.ReadPixels(b.x, b.y, b.w, b.h, GL_RGBA, GL_UNSIGNED_BYTE, r->tile_pixels);
            if (r->hooks.image)
                r->hooks.image(r->hooks.ctx, frame, i, b.x, b.y, b.w, b.h, r->tile_pixels);
            char path[PATH_MAX];
            if (r->output[0] &&
                (tile_path(path, sizeof path, r->output, frame, i, r->ntiles, &err) != TSR_OK ||
                 tsr_image_write_png_rgba(r->tile_pixels, b.w, b.h, (size_t)b.w * 4, true, path, &err) != TSR_OK))
                tsr_log(TSR_LOG_ERROR, "%s: frame %d: tile %zu: %s", r->name, frame, i, err.message);
        }
    }
    if (shared_make_current(r, back, &err) != TSR_OK)
        tsr_log(TSR_LOG_ERROR, "%s", err.message);
    if (r->hooks.done)
        r->hooks.done(r->hooks.ctx, frame, r->window, r->width, r->height);
}

/* The frame's drawing done before it is read or shown. glFinish would do,
 * but in solo mode OSMesa then copies the whole window into the user
 * buffer (docs/render.md), which only a PNG and the image hook read; a
 * `frame` hook reads with render_spu_read. Without those readers a
 * one-pixel read waits for the rasteriser as glFinish does and copies 4
 * bytes: a 1920x1080 frame skips an 8 MB copy. */
static void finish_frame(render_spu *r)
{
    if (r->shared || r->output[0] || r->hooks.image || r->width < 1 || r->height < 1) {
        r->gl.Finish();
        return;
    }
    unsigned char pixel[4];
    tsr_error err = {0};
    if (render_spu_read(r, 0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixel, &err) != TSR_OK)
        r->gl.Finish();
}

static void render_SwapBuffersTSR(void *self, GLint window, GLbitfield flags)
{
    render_spu *r = self;
    if (window == r->window && r->ntiles) {
        ensure_current(r);
        tiled_write_frame(r, r->frame++);
    } else if (window == r->window) {
        ensure_current(r);
        finish_frame(r);
        /* Only a PNG or the image hook reads the copy; without them the
         * frame stays in the shared renderbuffers (a `frame` hook reads
         * from there with render_spu_read). */
        if (r->shared && (r->output[0] || r->hooks.image))
            shared_read_frame(r);
        int frame = r->frame++;
        if (r->output[0]) {
            char path[PATH_MAX];
            tsr_error err = {0};
            if (tsr_image_frame_path(path, sizeof path, r->output, frame, &err) != TSR_OK ||
                tsr_image_write_png_rgba(r->buffer, r->width, r->height, (size_t)r->width * 4, true, path, &err) !=
                    TSR_OK)
                tsr_log(TSR_LOG_ERROR, "%s: frame %d: %s", r->name, frame, err.message);
        }
        if (r->hooks.frame)
            r->hooks.frame(r->hooks.ctx, frame, r);
        if (r->hooks.image && r->buffer)
            r->hooks.image(r->hooks.ctx, frame, 0, 0, 0, r->width, r->height, r->buffer);
        if (r->hooks.done)
            r->hooks.done(r->hooks.ctx, frame, r->window, r->width, r->height);
    }
    tsr_call_SwapBuffersTSR(r->child, window, flags);
}

void render_spu_size(const void *instance, int *width, int *height)
{
    const render_spu *r = instance;
    *width = r->width;
    *height = r->height;
}

/* Reads with the current context's client state saved and GL's defaults
 * set, so the client's pack and transfer state never applies. */
static void read_default_state(render_spu *r, int x, int y, int w, int h, GLenum format, GLenum type, void *pixels)
{
    GLint pack_buffer = 0;
    r->gl.GetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &pack_buffer);
    if (pack_buffer)
        r->gl.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    r->gl.PushClientAttrib(GL_CLIENT_PIXEL_STORE_BIT);
    r->gl.PushAttrib(GL_PIXEL_MODE_BIT);
    static const GLenum zero[] = {GL_PACK_ROW_LENGTH, GL_PACK_SKIP_ROWS,    GL_PACK_SKIP_PIXELS, GL_PACK_SWAP_BYTES,
                                  GL_PACK_LSB_FIRST,  GL_PACK_IMAGE_HEIGHT, GL_PACK_SKIP_IMAGES};
    for (size_t i = 0; i < sizeof zero / sizeof zero[0]; i++)
        r->gl.PixelStorei(zero[i], 0);
    r->gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    static const GLenum one[] = {GL_RED_SCALE, GL_GREEN_SCALE, GL_BLUE_SCALE, GL_ALPHA_SCALE, GL_DEPTH_SCALE};
    static const GLenum none[] = {GL_RED_BIAS, GL_GREEN_BIAS, GL_BLUE_BIAS, GL_ALPHA_BIAS, GL_DEPTH_BIAS};
    for (size_t i = 0; i < 5; i++) {
        r->gl.PixelTransferf(one[i], 1.0f);
        r->gl.PixelTransferf(none[i], 0.0f);
    }
    r->gl.PixelTransferi(GL_MAP_COLOR, GL_FALSE);
    r->gl.PixelTransferi(GL_MAP_STENCIL, GL_FALSE);
    r->gl.ReadPixels(x, y, w, h, format, type, pixels);
    r->gl.PopAttrib();
    r->gl.PopClientAttrib();
    if (pack_buffer)
        r->gl.BindBuffer(GL_PIXEL_PACK_BUFFER, (GLuint)pack_buffer);
}

int render_spu_read(void *instance, int x, int y, int w, int h, unsigned format, unsigned type, void *pixels,
                    tsr_error *err)
{
    render_spu *r = instance;
    if (x < 0 || y < 0 || w < 0 || h < 0 || x > r->width - w || y > r->height - h)
        return tsr_error_set(err, TSR_EINVAL, "%s: read [%d, %d, %d, %d] outside the %dx%d window", r->name, x, y, w, h,
                             r->width, r->height);
    if (!w || !h)
        return TSR_OK;
    ensure_current(r);
    if (!r->shared) {
        read_default_state(r, x, y, w, h, format, type, pixels);
        return TSR_OK;
    }
    /* Shared mode: context 0's pixel state is never a client's. */
    size_t back = r->current;
    if (shared_switch(r, 0, err) != TSR_OK)
        return err->code;
    r->gl.ReadPixels(x, y, w, h, format, type, pixels);
    return shared_switch(r, back, err);
}

/* Room for one more context; false when out of memory. */
static bool grow_contexts(render_spu *r)
{
    if (r->ncontexts < r->contexts_cap)
        return true;
    render_context *c = realloc(r->contexts, 2 * r->contexts_cap * sizeof *c);
    if (!c)
        return false;
    r->contexts = c;
    r->contexts_cap *= 2;
    return true;
}

static void render_ContextCreateTSR(void *self, GLint context)
{
    render_spu *r = self;
    tsr_error err = {0};
    if (context <= 0 || (r->shared && find_context(r, context) != SIZE_MAX)) {
        tsr_log(TSR_LOG_ERROR, "%s: ContextCreateTSR(%d): %s, ignored", r->name, (int)context,
                context <= 0 ? "ids start at 1" : "context exists");
    } else if (!r->shared && shared_enter(r, &err) != TSR_OK) {
        tsr_log(TSR_LOG_ERROR, "%s: ContextCreateTSR(%d): %s", r->name, (int)context, err.message);
    } else if (!grow_contexts(r)) {
        tsr_log(TSR_LOG_ERROR, "%s: ContextCreateTSR(%d): out of memory", r->name, (int)context);
    } else {
        /* Same attributes as context 0, in its share group. */
        OSMesaContext c = r->osmesa.CreateContextExt(OSMESA_RGBA, 24, 8, 0, r->context);
        if (!c) {
            tsr_log(TSR_LOG_ERROR, "%s: ContextCreateTSR(%d): OSMesaCreateContextExt failed", r->name, (int)context);
        } else {
            size_t back = r->current, index = r->ncontexts++;
            r->contexts[index] = (render_context){.id = context, .osmesa = c};
            /* A window system sets viewport and scissor to the window when a
             * context is first made current on it. */
            if (shared_switch(r, index, &err) != TSR_OK)
                tsr_log(TSR_LOG_ERROR, "%s", err.message);
            r->gl.Viewport(0, 0, r->width, r->height);
            render_Scissor(r, 0, 0, r->width, r->height);
            if (shared_switch(r, back, &err) != TSR_OK)
                tsr_log(TSR_LOG_ERROR, "%s", err.message);
        }
    }
    tsr_call_ContextCreateTSR(r->child, context);
}

static void render_MakeCurrentTSR(void *self, GLint window, GLint context)
{
    render_spu *r = self;
    size_t index = r->shared ? find_context(r, context) : (context == 0 ? 0 : SIZE_MAX);
    tsr_error err = {0};
    if (index == SIZE_MAX)
        tsr_log(TSR_LOG_ERROR, "%s: MakeCurrentTSR(%d, %d): no such context, ignored", r->name, (int)window,
                (int)context);
    else if (r->shared && shared_switch(r, index, &err) != TSR_OK)
        tsr_log(TSR_LOG_ERROR, "%s", err.message);
    else if (!r->shared)
        ensure_current(r);
    tsr_call_MakeCurrentTSR(r->child, window, context);
}

static void destroy_context(render_spu *r, size_t index)
{
    render_context *c = &r->contexts[index];
    if (c->fbo) {
        tsr_error err = {0};
        if (shared_make_current(r, index, &err) == TSR_OK)
            r->fbo.DeleteFramebuffers(1, &c->fbo);
    }
    if (r->osmesa.GetCurrentContext() == c->osmesa)
        r->osmesa.MakeCurrent(NULL, NULL, 0, 0, 0);
    if (r->nretired == r->retired_cap) {
        size_t cap = r->retired_cap ? 2 * r->retired_cap : RENDER_RETIRED_MAX;
        OSMesaContext *more = realloc(r->retired, cap * sizeof *more);
        if (!more) {
            /* Out of memory: destroyed now, as before this list existed. */
            r->osmesa.DestroyContext(c->osmesa);
            return;
        }
        r->retired = more;
        r->retired_cap = cap;
    }
    r->retired[r->nretired++] = c->osmesa;
}

static void render_ContextDestroyTSR(void *self, GLint context)
{
    render_spu *r = self;
    size_t index = r->shared && context > 0 ? find_context(r, context) : SIZE_MAX;
    if (index == SIZE_MAX) {
        tsr_log(TSR_LOG_ERROR, "%s: ContextDestroyTSR(%d): no such context, ignored", r->name, (int)context);
    } else {
        GLint current_id = r->contexts[r->current].id;
        tsr_error err = {0};
        if (shared_switch(r, index, &err) == TSR_OK)
            r->gl.Finish();
        destroy_context(r, index);
        render_tex_forget_owner_defaults(&r->textures, context);
        r->contexts[index] = r->contexts[--r->ncontexts];
        /* Back to the context that was current, or to context 0. */
        size_t back = find_context(r, current_id);
        if (shared_make_current(r, back == SIZE_MAX ? 0 : back, &err) != TSR_OK)
            tsr_log(TSR_LOG_ERROR, "%s", err.message);
        if (r->nretired >= RENDER_RETIRED_MAX) {
            /* New storage at the same size frees them; the window's pixels
             * go with it, which is why this waits for this many to leave. */
            int width = r->width, height = r->height;
            r->width = r->height = 0;
            if (shared_resize(r, width, height, &err) != TSR_OK)
                tsr_log(TSR_LOG_ERROR, "%s", err.message);
        }
    }
    tsr_call_ContextDestroyTSR(r->child, context);
}

/* Shared mode draws into FBO colour attachment 0: the window buffer names
 * a single-buffered OSMesa window accepts mean that attachment. */
static GLenum shared_buffer_name(const render_spu *r, GLenum buf)
{
    if (r->shared && (buf == GL_FRONT || buf == GL_FRONT_LEFT || buf == GL_LEFT || buf == GL_FRONT_AND_BACK))
        return GL_COLOR_ATTACHMENT0;
    return buf;
}

/* A depth clear that keeps the stencil (no GL_STENCIL_BUFFER_BIT) makes
 * llvmpipe rewrite every packed 24/8 depth-stencil word through a mask,
 * about 1.6 times a clear of both (bench/results/sortlast/README.md).
 * The stencil changes only through the stencil test, a stencil clear, or
 * stencil DrawPixels/CopyPixels (the commands tessera carries); while the
 * stream has done none of them with another value than 0, every stencil
 * value is 0 (or undefined, never yet written), so clearing it to 0 too
 * changes no pixel, and the clear is one fill. A clear compiled into a
 * display list is left as it is: the list may run after the stencil was
 * used. */
static void render_Clear(void *self, GLbitfield mask)
{
    render_spu *r = self;
    bool compiling = current_scissor(r)->list_mode != 0;
    if (mask & GL_STENCIL_BUFFER_BIT) {
        GLint value = 0;
        if (!compiling && !r->stencil_written)
            r->gl.GetIntegerv(GL_STENCIL_CLEAR_VALUE, &value);
        if (compiling || value != 0)
            r->stencil_written = true;
    } else if ((mask & GL_DEPTH_BUFFER_BIT) && !compiling && !r->stencil_written) {
        GLint value = -1;
        r->gl.GetIntegerv(GL_STENCIL_CLEAR_VALUE, &value);
        if (value == 0)
            mask |= GL_STENCIL_BUFFER_BIT;
    }
    if (mask == GL_COLOR_BUFFER_BIT && !compiling && render_fastdraw_clear(r->fastdraw, &r->gl, r->width, r->height))
        return;
    r->gl.Clear(mask);
}

static void render_CopyPixels(void *self, GLint x, GLint y, GLsizei width, GLsizei height, GLenum type)
{
    render_spu *r = self;
    if (type != GL_COLOR && type != GL_DEPTH)
        r->stencil_written = true;
    r->gl.CopyPixels(x, y, width, height, type);
}

static void render_DrawPixels(void *self, GLsizei width, GLsizei height, GLenum format, GLenum type, const void *pixels)
{
    render_spu *r = self;
    if (format == GL_STENCIL_INDEX || format == GL_DEPTH_STENCIL)
        r->stencil_written = true;
    render_fastdraw_draw(r->fastdraw, &r->gl, r->width, r->height, width, height, format, type, pixels);
}

static void render_DrawBuffer(void *self, GLenum buf)
{
    render_spu *r = self;
    r->gl.DrawBuffer(shared_buffer_name(r, buf));
}

static void render_ReadBuffer(void *self, GLenum buf)
{
    render_spu *r = self;
    r->gl.ReadBuffer(shared_buffer_name(r, buf));
}

/* --- life cycle ---------------------------------------------------------- */

static void render_destroy(void *self)
{
    render_spu *r = self;
    if (!r)
        return;
    if (r->reader.osmesa) {
        tsr_error err = {0};
        if (r->reader.fbo && attach_context(r, &r->reader, &err) == TSR_OK)
            r->fbo.DeleteFramebuffers(1, &r->reader.fbo);
        if (r->osmesa.GetCurrentContext() == r->reader.osmesa)
            r->osmesa.MakeCurrent(NULL, NULL, 0, 0, 0);
        r->osmesa.DestroyContext(r->reader.osmesa);
    }
    if (r->shared) {
        for (size_t i = r->ncontexts; i-- > 1;)
            destroy_context(r, i);
        tsr_error err = {0};
        if (shared_make_current(r, 0, &err) == TSR_OK) {
            render_fastdraw_release(r->fastdraw, &r->gl);
            if (r->contexts[0].fbo)
                r->fbo.DeleteFramebuffers(1, &r->contexts[0].fbo);
            GLuint rbs[2] = {r->color_rb, r->depth_rb};
            r->fbo.DeleteRenderbuffers(2, rbs);
        }
        destroy_retired(r);
        free(r->retired);
        free(r->contexts);
    }
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
    free(r->buffer);
    free(r->tiles);
    free(r->tile_pixels);
    render_tex_free(&r->textures);
    render_fastdraw_destroy(r->fastdraw, r->name);
    tsr_glsl_names_destroy(r->names);
    free(r);
}

void *render_spu_create(const tsr_spu_init *init, const render_hooks *hooks, tsr_error *err)
{
    render_spu *r = calloc(1, sizeof *r);
    if (!r) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    snprintf(r->name, sizeof r->name, "%s", init->instance_name);
    r->child = init->child;
    if (hooks)
        r->hooks = *hooks;
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
    r->context = r->osmesa.CreateContextExt(OSMESA_RGBA, 24, 8, 0, NULL);
    if (!r->context) {
        tsr_error_set(err, TSR_EIO, "%s: OSMesaCreateContextExt(RGBA, 24, 8, 0) failed", r->name);
        goto fail;
    }
    int width = r->fixed_width ? r->fixed_width : RENDER_DEFAULT_SIDE;
    int height = r->fixed_height ? r->fixed_height : RENDER_DEFAULT_SIDE;
    if (bind_framebuffer(r, width, height, err) != TSR_OK)
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
        if (set_tiles(r, tiles, count, err) != TSR_OK)
            goto fail;
    }

    tsr_gl_procs_fill_dispatch(&r->gl, init->table);
    tsr_set_WindowCreateTSR(init->table, render_WindowCreateTSR, r);
    tsr_set_WindowSizeTSR(init->table, render_WindowSizeTSR, r);
    tsr_set_SwapBuffersTSR(init->table, render_SwapBuffersTSR, r);
    tsr_set_ContextCreateTSR(init->table, render_ContextCreateTSR, r);
    tsr_set_ContextDestroyTSR(init->table, render_ContextDestroyTSR, r);
    tsr_set_MakeCurrentTSR(init->table, render_MakeCurrentTSR, r);
    tsr_set_DrawBuffer(init->table, render_DrawBuffer, r);
    tsr_set_DrawPixels(init->table, render_DrawPixels, r);
    tsr_set_Clear(init->table, render_Clear, r);
    tsr_set_CopyPixels(init->table, render_CopyPixels, r);
    tsr_set_ReadBuffer(init->table, render_ReadBuffer, r);
    tsr_set_TilesTSR(init->table, render_TilesTSR, r);
    tsr_set_Scissor(init->table, render_Scissor, r);
    tsr_set_Enable(init->table, render_Enable, r);
    tsr_set_Disable(init->table, render_Disable, r);
    tsr_set_PushAttrib(init->table, render_PushAttrib, r);
    tsr_set_PopAttrib(init->table, render_PopAttrib, r);
    tsr_set_CallList(init->table, render_CallList, r);
    tsr_set_CallLists(init->table, render_CallLists, r);
    tsr_set_NewList(init->table, render_NewList, r);
    tsr_set_EndList(init->table, render_EndList, r);
    tsr_set_GetIntegerv(init->table, render_GetIntegerv, r);
    tsr_set_GetFloatv(init->table, render_GetFloatv, r);
    tsr_set_GetDoublev(init->table, render_GetDoublev, r);
    tsr_set_GetBooleanv(init->table, render_GetBooleanv, r);
    tsr_set_IsEnabled(init->table, render_IsEnabled, r);
    tsr_set_TexImage1D(init->table, render_TexImage1D, r);
    tsr_set_TexImage2D(init->table, render_TexImage2D, r);
    tsr_set_TexImage3D(init->table, render_TexImage3D, r);
    tsr_set_CopyTexImage1D(init->table, render_CopyTexImage1D, r);
    tsr_set_CopyTexImage2D(init->table, render_CopyTexImage2D, r);
    tsr_set_DeleteTextures(init->table, render_DeleteTextures, r);
    tsr_set_BindTexture(init->table, render_BindTexture, r);
    tsr_set_IsTexture(init->table, render_IsTexture, r);
    /* last: wraps the shader/program slots set above (tessera/glsl_names.h) */
    if (!(r->names = tsr_glsl_names_create(init->table, err)))
        goto fail;
    return r;
fail:
    render_destroy(r);
    return NULL;
}

void render_spu_destroy(void *instance) { render_destroy(instance); }
