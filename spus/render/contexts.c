/* spus/render/contexts.c — render's shared mode (docs/render.md, "Several
 * contexts, one window"): the first ContextCreateTSR (or the first tiles)
 * moves the instance onto framebuffer objects, so that every client
 * context draws into one pair of shared renderbuffers (the window), and
 * ContextCreateTSR, MakeCurrentTSR and ContextDestroyTSR manage those
 * contexts (buffers.c maps the window's buffer names onto the FBO's colour
 * attachments).
 *
 * Owns: the contexts, the shared renderbuffers and their generation, the
 * retired contexts of clients that left, the FBO entries.
 *
 * Never: reads or writes frames (frame.c), touches the scissor beyond
 * refreshing it on a switch (scissor.c), destroys a context whose
 * surfaces Mesa may still release (they wait in `retired`). */
#include <stdint.h>
#include <stdlib.h>

#include "tessera/log.h"

#include "instance.h"
#include "pages.h"

/* --- shared mode ----------------------------------------------------------- */

/* Makes `c` current on this thread with its FBO attached to the current
 * renderbuffers. */
int render_attach_context(render_spu *r, render_context *c, tsr_error *err)
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
        /* A multisample window (multisample.c): client contexts draw into
         * the multisample renderbuffers and read the resolved ones through
         * a second FBO; context 0 resolves from an FBO of its own. */
        bool client_ms = r->samples && c->id > 0;
        GLuint *second = !r->samples ? NULL : client_ms ? &c->resolved_fbo : c->id == 0 ? &r->ms_fbo : NULL;
        if (second && !*second) {
            r->fbo.GenFramebuffers(1, second);
            r->fbo.BindFramebuffer(GL_FRAMEBUFFER, *second);
            r->fbo.FramebufferParameteri(GL_FRAMEBUFFER, GL_FRAMEBUFFER_FLIP_Y_MESA, GL_TRUE);
        }
        for (int pass = 0; pass < (second ? 2 : 1); pass++) {
            r->fbo.BindFramebuffer(GL_FRAMEBUFFER, pass ? *second : c->fbo);
            if (pass ? !client_ms : client_ms) {
                render_ms_attach(r);
            } else {
                r->fbo.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, r->color_rb);
                r->fbo.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                                               r->depth_rb);
                if (r->front_rb)
                    r->fbo.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, r->front_rb);
            }
            GLenum status = r->fbo.CheckFramebufferStatus(GL_FRAMEBUFFER);
            if (status != GL_FRAMEBUFFER_COMPLETE)
                return tsr_error_set(err, TSR_EIO, "%s: context %d: framebuffer%s incomplete (0x%x)", r->name, c->id,
                                     pass ? " (multisample resolve)" : "", status);
        }
        render_app_fb_rebind(r, c); /* appfbo.c: the program's, if bound */
        c->attached = r->generation;
    }
    return TSR_OK;
}

/* Makes contexts[index] current on this thread with its FBO attached to
 * the current renderbuffers and its scissor fitted to the tiles. */
int render_shared_make_current(render_spu *r, size_t index, tsr_error *err)
{
    if (render_attach_context(r, &r->contexts[index], err) != TSR_OK)
        return err->code;
    r->current = index;
    render_scissor_refresh(r, &r->contexts[index].sc);
    return TSR_OK;
}

/* Finishes the current context (so a context switched to next sees all
 * it drew: llvmpipe contexts rasterise independently) and makes
 * contexts[index] current. */
int render_shared_switch(render_spu *r, size_t index, tsr_error *err)
{
    if (r->osmesa.GetCurrentContext() == r->contexts[index].osmesa && r->current == index)
        return TSR_OK;
    if (r->osmesa.GetCurrentContext())
        r->gl.Finish();
    return render_shared_make_current(r, index, err);
}

/* The surfaces the retired contexts made were released (through them)
 * when the storage they viewed was replaced or deleted, so they can go. */
void render_destroy_retired(render_spu *r)
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
int render_shared_resize(render_spu *r, int width, int height, tsr_error *err)
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
    if (render_shared_switch(r, 0, err) != TSR_OK)
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
        if (r->front_rb) {
            r->fbo.BindRenderbuffer(GL_RENDERBUFFER, r->front_rb);
            r->fbo.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, 1, 1);
        }
        render_ms_storage(r, 1, 1);
        r->gl.Finish();
        render_pages_snapshot(&before);
    }
    r->fbo.BindRenderbuffer(GL_RENDERBUFFER, r->color_rb);
    r->fbo.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    r->fbo.BindRenderbuffer(GL_RENDERBUFFER, r->depth_rb);
    r->fbo.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);
    if (r->front_rb) {
        r->fbo.BindRenderbuffer(GL_RENDERBUFFER, r->front_rb);
        r->fbo.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    }
    r->fbo.BindRenderbuffer(GL_RENDERBUFFER, render_app_rb(r));
    render_ms_storage(r, width, height);
    render_destroy_retired(r);
    if (release) {
        size_t given = render_pages_release(&before, bytes);
        render_pages_free(&before);
        tsr_log(TSR_LOG_DEBUG, "%s: %dx%d renderbuffers: %zu KiB of zero pages given back", r->name, width, height,
                given >> 10);
    }
    r->released = r->ntiles > 0;
    r->generation++;
    if (render_shared_make_current(r, 0, err) != TSR_OK)
        return err->code;
    return render_shared_switch(r, back, err);
}

/* Enters shared mode: resolves the FBO entries, puts context 0 on the
 * shared renderbuffers at the current size. */
int render_shared_enter(render_spu *r, tsr_error *err)
{
    struct {
        const char *symbol;
        void **slot;
    } wanted[] = {
        {"glGenRenderbuffers", (void **)&r->fbo.GenRenderbuffers},
        {"glDeleteRenderbuffers", (void **)&r->fbo.DeleteRenderbuffers},
        {"glBindRenderbuffer", (void **)&r->fbo.BindRenderbuffer},
        {"glRenderbufferStorage", (void **)&r->fbo.RenderbufferStorage},
        {"glRenderbufferStorageMultisample", (void **)&r->fbo.RenderbufferStorageMultisample},
        {"glGenFramebuffers", (void **)&r->fbo.GenFramebuffers},
        {"glDeleteFramebuffers", (void **)&r->fbo.DeleteFramebuffers},
        {"glBindFramebuffer", (void **)&r->fbo.BindFramebuffer},
        {"glFramebufferRenderbuffer", (void **)&r->fbo.FramebufferRenderbuffer},
        {"glFramebufferParameteri", (void **)&r->fbo.FramebufferParameteri},
        {"glCheckFramebufferStatus", (void **)&r->fbo.CheckFramebufferStatus},
        {"glBlitFramebuffer", (void **)&r->fbo.BlitFramebuffer},
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
    r->contexts[0] = (render_context){
        .id = 0, .osmesa = r->context, .window_seen = r->window_seen, .sc = r->solo_sc, .app = r->solo_app};
    r->current = 0;
    r->shared = true;
    /* Context 0 leaves the window-sized user buffer (render_shared_resize frees
     * and replaces it; OSMesa would copy into it at every glFinish). */
    if (!r->osmesa.MakeCurrent(r->context, r->dummy, GL_UNSIGNED_BYTE, 1, 1))
        return tsr_error_set(err, TSR_EIO, "%s: OSMesaMakeCurrent failed for context 0", r->name);
    r->fbo.GenRenderbuffers(1, &r->color_rb);
    r->fbo.GenRenderbuffers(1, &r->depth_rb);
    int width = r->width, height = r->height;
    r->width = r->height = 0; /* force the allocation */
    return render_shared_resize(r, width, height, err);
}

static size_t find_context(const render_spu *r, GLint id)
{
    for (size_t i = 0; i < r->ncontexts; i++)
        if (r->contexts[i].id == id)
            return i;
    return SIZE_MAX;
}

void render_ensure_current(render_spu *r)
{
    tsr_error err = {0};
    if (r->shared) {
        if (r->osmesa.GetCurrentContext() != r->contexts[r->current].osmesa &&
            render_shared_make_current(r, r->current, &err) != TSR_OK)
            tsr_log(TSR_LOG_ERROR, "%s", err.message);
        return;
    }
    if (r->osmesa.GetCurrentContext() == r->context)
        return;
    if (render_bind_framebuffer(r, r->width, r->height, &err) != TSR_OK)
        tsr_log(TSR_LOG_ERROR, "%s", err.message);
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
    } else if (!r->shared && render_shared_enter(r, &err) != TSR_OK) {
        tsr_log(TSR_LOG_ERROR, "%s: ContextCreateTSR(%d): %s", r->name, (int)context, err.message);
    } else if (!grow_contexts(r)) {
        tsr_log(TSR_LOG_ERROR, "%s: ContextCreateTSR(%d): out of memory", r->name, (int)context);
    } else {
        /* Same attributes as context 0, in its share group. */
        OSMesaContext c = r->osmesa.CreateContextExt(OSMESA_RGBA, 24, 8, 16, r->context);
        if (!c) {
            tsr_log(TSR_LOG_ERROR, "%s: ContextCreateTSR(%d): OSMesaCreateContextExt failed", r->name, (int)context);
        } else {
            size_t back = r->current, index = r->ncontexts++;
            r->contexts[index] = (render_context){.id = context, .osmesa = c};
            /* A window system sets viewport and scissor to the window when a
             * context is first made current on it. */
            if (render_shared_switch(r, index, &err) != TSR_OK)
                tsr_log(TSR_LOG_ERROR, "%s", err.message);
            r->gl.Viewport(0, 0, r->width, r->height);
            render_Scissor(r, 0, 0, r->width, r->height);
            if (render_shared_switch(r, back, &err) != TSR_OK)
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
    else if (r->shared && render_shared_switch(r, index, &err) != TSR_OK)
        tsr_log(TSR_LOG_ERROR, "%s", err.message);
    else if (!r->shared)
        render_ensure_current(r);
    tsr_call_MakeCurrentTSR(r->child, window, context);
}

void render_destroy_context(render_spu *r, size_t index)
{
    render_context *c = &r->contexts[index];
    if (c->fbo) {
        tsr_error err = {0};
        if (render_shared_make_current(r, index, &err) == TSR_OK) {
            r->fbo.DeleteFramebuffers(1, &c->fbo);
            if (c->resolved_fbo)
                r->fbo.DeleteFramebuffers(1, &c->resolved_fbo);
        }
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
        if (render_shared_switch(r, index, &err) == TSR_OK)
            r->gl.Finish();
        render_destroy_context(r, index);
        render_tex_forget_owner_defaults(&r->textures, context);
        r->contexts[index] = r->contexts[--r->ncontexts];
        /* Back to the context that was current, or to context 0. */
        size_t back = find_context(r, current_id);
        if (render_shared_make_current(r, back == SIZE_MAX ? 0 : back, &err) != TSR_OK)
            tsr_log(TSR_LOG_ERROR, "%s", err.message);
        if (r->nretired >= RENDER_RETIRED_MAX) {
            /* New storage at the same size frees them; the window's pixels
             * go with it, which is why this waits for this many to leave. */
            int width = r->width, height = r->height;
            r->width = r->height = 0;
            if (render_shared_resize(r, width, height, &err) != TSR_OK)
                tsr_log(TSR_LOG_ERROR, "%s", err.message);
        }
    }
    tsr_call_ContextDestroyTSR(r->child, context);
}

void render_contexts_install(render_spu *r, tsr_dispatch *table)
{
    tsr_set_ContextCreateTSR(table, render_ContextCreateTSR, r);
    tsr_set_ContextDestroyTSR(table, render_ContextDestroyTSR, r);
    tsr_set_MakeCurrentTSR(table, render_MakeCurrentTSR, r);
}
