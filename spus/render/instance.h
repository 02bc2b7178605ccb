/* spus/render/instance.h — the render instance (render_spu) and the
 * functions its files call in one another. Private to the render plugin:
 * only the .c files of spus/render include it; plugin.c and the fuzz
 * targets that compile render in use render.h, other SPUs inherit render
 * through tessera/dev/render.h.
 *
 * The files, one job each:
 *   render.c   — life cycle: OSMesa loading, options, creation, destruction
 *   contexts.c — shared mode: several contexts on one window's FBOs
 *   scissor.c  — tiles and the application's scissor fitted to them
 *   textures.c — the texture budget and the texture names the fast
 *                DrawPixels keeps
 *   pixels.c   — Clear, CopyPixels, DrawPixels: the stencil record and
 *                the fast paths
 *   frame.c    — window size, swap: the frame read back and written out
 *   buffers.c  — front and back buffers of a double-buffered window
 *   multisample.c — a multisample window's buffers and their resolve
 *   appfbo.c   — the program's own framebuffer objects and renderbuffers
 *   xwindow.c  — window output: each frame shown in an X window
 *
 * Owns the types only. Never: state outside an instance. */
#ifndef RENDER_INSTANCE_H
#define RENDER_INSTANCE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <GL/osmesa.h>

#include "tessera/glprocs_gen.h"
#include "tessera/glsl_names.h"
#include "tessera/spu.h"
#include "tessera/tiles.h"

#include "budget.h"
#include "drawpixels.h"
#include "render.h"
#include "xwindow.h"

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
    void(GLAPIENTRY *RenderbufferStorageMultisample)(GLenum target, GLsizei samples, GLenum format, GLsizei w,
                                                     GLsizei h);
    void(GLAPIENTRY *GenFramebuffers)(GLsizei n, GLuint *ids);
    void(GLAPIENTRY *DeleteFramebuffers)(GLsizei n, const GLuint *ids);
    void(GLAPIENTRY *BindFramebuffer)(GLenum target, GLuint id);
    void(GLAPIENTRY *FramebufferRenderbuffer)(GLenum target, GLenum attachment, GLenum rbtarget, GLuint rb);
    void(GLAPIENTRY *FramebufferParameteri)(GLenum target, GLenum pname, GLint value);
    GLenum(GLAPIENTRY *CheckFramebufferStatus)(GLenum target);
    void(GLAPIENTRY *BlitFramebuffer)(GLint sx0, GLint sy0, GLint sx1, GLint sy1, GLint dx0, GLint dy0, GLint dx1,
                                      GLint dy1, GLbitfield mask, GLenum filter);
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
    bool in_begin;    /* between a glBegin and glEnd GL runs (not only compiles) */
    unsigned applied; /* tiles generation the real scissor was last set for */
    bool fitted;      /* the real scissor is fitted to tiles (else: the application's) */
} render_scissor;

/* The program's framebuffer object and renderbuffer bindings of one
 * context, in the driver's names (appfbo.c); fb (the draw framebuffer)
 * or read_fb 0: the window. */
typedef struct render_app_binding {
    GLuint fb, read_fb, rb;
} render_app_binding;

/* The program's names of its framebuffer objects (or renderbuffers) and
 * the driver's (appfbo.c); few per program, so a plain list. */
typedef struct render_name_pair {
    GLuint program, driver;
} render_name_pair;
typedef struct render_names {
    render_name_pair *pairs;
    size_t n, cap;
    GLuint max_program;
} render_names;

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
    /* The program's last glDrawBuffer/glReadBuffer names (0: none yet),
     * answered while the real state still matches them (buffers.c). */
    GLenum draw_name, read_name;
    /* A multisample window (multisample.c): `fbo` is on the multisample
     * renderbuffers, this one on the resolved ones, read through. */
    GLuint resolved_fbo;
    render_app_binding app;
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
    bool output_alpha;  /* option: PNGs keep the framebuffer's alpha (else RGB) */
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
    /* A double-buffered window (WindowBuffersTSR 2, buffers.c): color_rb is
     * its back buffer (attachment 0), front_rb its front (attachment 1). */
    bool double_buffered;
    GLuint front_rb;
    /* A multisample window (WindowSamplesTSR, multisample.c): client
     * contexts draw into these, `samples` samples a pixel, and color_rb,
     * front_rb and depth_rb hold them resolved; ms_fbo is context 0's FBO
     * on them, the resolve's source. 0: single-sampled. */
    int samples;
    GLuint ms_color_rb, ms_depth_rb, ms_front_rb, ms_fbo;
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
    render_box bounds;           /* bounding rectangle of the tiles */
    unsigned tiles_gen;          /* bumped whenever the tiles change; starts at 1 */
    bool released;               /* the renderbuffers were allocated tiled */
    render_scissor solo_sc;      /* the scissor before shared mode */
    render_app_binding solo_app; /* the program's bindings before shared mode */
    render_names app_fb_names, app_rb_names;
    int max_attrib_depth;
    render_context reader; /* reads the tiles back; never gets client commands */
    unsigned char *tile_pixels;
    size_t tile_pixels_size;
    render_xwindow *xwindow; /* window output (xwindow.h); NULL: none */

    /* Budgets per context (docs/render.md, "Budgets"); 0 = no limit. */
    uint64_t max_texture_bytes;
    uint64_t max_window_pixels;
    render_tex_table textures;
    render_fastdraw *fastdraw; /* drawpixels.h */
    /* The stream may have put a stencil value other than 0 in the window
     * (render_Clear says why it matters). */
    bool stencil_written;
} render_spu;

/* render.c */
int render_bind_framebuffer(render_spu *r, int width, int height, tsr_error *err);
__attribute__((format(printf, 2, 3))) void render_refuse(render_spu *r, const char *fmt, ...);

/* contexts.c */
int render_attach_context(render_spu *r, render_context *c, tsr_error *err);
int render_shared_make_current(render_spu *r, size_t index, tsr_error *err);
int render_shared_switch(render_spu *r, size_t index, tsr_error *err);
void render_destroy_retired(render_spu *r);
int render_shared_resize(render_spu *r, int width, int height, tsr_error *err);
int render_shared_enter(render_spu *r, tsr_error *err);
void render_ensure_current(render_spu *r);
void render_destroy_context(render_spu *r, size_t index);
void render_contexts_install(render_spu *r, tsr_dispatch *table);

/* scissor.c */
render_scissor *render_current_scissor(render_spu *r);
render_box render_box_intersect(render_box a, render_box b);
void render_scissor_refresh(render_spu *r, render_scissor *s);
int render_set_tiles(render_spu *r, tsr_tile *tiles, size_t count, tsr_error *err);
void render_Scissor(void *self, GLint x, GLint y, GLsizei width, GLsizei height);
void render_scissor_install(render_spu *r, tsr_dispatch *table);

/* textures.c */
void render_textures_install(render_spu *r, tsr_dispatch *table);

/* pixels.c */
void render_pixels_install(render_spu *r, tsr_dispatch *table);

/* buffers.c */
void render_buffers_swap(render_spu *r);
bool render_buffers_query(render_spu *r, GLenum pname, GLint *value);
void render_buffers_install(render_spu *r, tsr_dispatch *table);
/* multisample.c */
void render_ms_storage(render_spu *r, int width, int height);
void render_ms_attach(render_spu *r);
int render_ms_resolve(render_spu *r, tsr_error *err);
void render_ms_swap(render_spu *r);
bool render_ms_read_begin(render_spu *r);
void render_ms_read_end(render_spu *r, bool began);
void render_multisample_install(render_spu *r, tsr_dispatch *table);
/* appfbo.c */
bool render_app_fb_bound(render_spu *r);
bool render_app_read_fb_bound(render_spu *r);
void render_app_fb_rebind(render_spu *r, const render_context *c);
GLuint render_app_read_fb_or_window(const render_context *c);
GLuint render_app_rb(render_spu *r);
bool render_app_fb_query(render_spu *r, GLenum pname, GLint *value);
void render_app_fb_leave(render_spu *r);
void render_app_fb_return(render_spu *r);
void render_names_free(render_names *t);
void render_appfbo_install(render_spu *r, tsr_dispatch *table);
/* frame.c */
void render_frame_install(render_spu *r, tsr_dispatch *table);
int render_end_frame(render_spu *r, tsr_render_tile_fn each, void *ctx);

#endif
