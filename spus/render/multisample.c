/* spus/render/multisample.c — a multisample window (docs/render.md,
 * "Multisample windows"). A window told WindowSamplesTSR(window, n) is
 * drawn by every client context into renderbuffers of n samples a pixel
 * (colour, the front's too when double-buffered, depth-stencil), as Mesa
 * draws a window of a multisample visual into multisample buffers. The
 * single-sampled renderbuffers of shared mode (contexts.c) then hold the
 * window resolved: glBlitFramebuffer, in context 0, from its FBO on the
 * multisample renderbuffers to its own, at each swap (the frame is read
 * from those: frame.c) and before every read of the window a program
 * makes (glReadPixels, glCopyPixels, glCopyTexImage*, glCopyTexSubImage*),
 * which then reads through the client context's second FBO, on the
 * resolved renderbuffers, as a driver reads a multisample window resolved.
 * Colour is averaged over the samples; depth and stencil are one sample's
 * (GL leaves the choice to the implementation; Mesa's blit takes sample 0).
 *
 * Owns: the multisample renderbuffers and their storage, context 0's FBO
 * on them, the resolve, the read framebuffer during a program's read.
 * Never: reads or writes a frame (frame.c), changes what a client context
 * has bound once its read is done, resolves while a display list is only
 * being compiled (the read then happens at glCallList, from the
 * multisample buffers: a copy compiled into a list in a multisample window
 * is GL_INVALID_OPERATION, as reading a multisample FBO is). */
#include "tessera/log.h"

#include "instance.h"

#ifndef GL_READ_FRAMEBUFFER
#define GL_READ_FRAMEBUFFER 0x8CA8
#define GL_DRAW_FRAMEBUFFER 0x8CA9
#endif

/* Gives the multisample renderbuffers storage at width x height (1x1 to
 * let go of it), in the current context (renderbuffers belong to the
 * share group). */
void render_ms_storage(render_spu *r, int width, int height)
{
    if (!r->samples)
        return;
    const GLuint rbs[3] = {r->ms_color_rb, r->ms_depth_rb, r->ms_front_rb};
    for (int i = 0; i < 3; i++) {
        if (!rbs[i])
            continue;
        r->fbo.BindRenderbuffer(GL_RENDERBUFFER, rbs[i]);
        r->fbo.RenderbufferStorageMultisample(GL_RENDERBUFFER, r->samples, i == 1 ? GL_DEPTH24_STENCIL8 : GL_RGBA8,
                                              width > 0 ? width : 1, height > 0 ? height : 1);
    }
    r->fbo.BindRenderbuffer(GL_RENDERBUFFER, render_app_rb(r));
}

/* Attaches `fbo` (bound to GL_FRAMEBUFFER by the caller) to the
 * multisample renderbuffers. */
void render_ms_attach(render_spu *r)
{
    r->fbo.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, r->ms_color_rb);
    r->fbo.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, r->ms_depth_rb);
    if (r->ms_front_rb)
        r->fbo.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, r->ms_front_rb);
}

/* The rectangle a resolve covers: a tiled server's tiles only (the rest
 * of its renderbuffers is never drawn, and touching it would fill pages
 * pages.c gave back). */
static render_box resolve_box(const render_spu *r)
{
    return r->ntiles ? r->bounds : (render_box){0, 0, r->width, r->height};
}

/* Context 0 is current: its FBO's read and draw buffers are set for one
 * blit each attachment, its scissor test off, all put back after. */
static void resolve_in_context0(render_spu *r)
{
    GLuint own = render_app_read_fb_or_window(&r->contexts[0]);
    GLint draw = GL_COLOR_ATTACHMENT0;
    r->gl.GetIntegerv(GL_DRAW_BUFFER, &draw);
    GLboolean scissor = r->gl.IsEnabled(GL_SCISSOR_TEST);
    r->gl.Disable(GL_SCISSOR_TEST);
    r->fbo.BindFramebuffer(GL_READ_FRAMEBUFFER, r->ms_fbo);
    render_box b = resolve_box(r);
    for (int i = 0; i < (r->ms_front_rb ? 2 : 1); i++) {
        GLenum attachment = i ? GL_COLOR_ATTACHMENT1 : GL_COLOR_ATTACHMENT0;
        r->gl.ReadBuffer(attachment);
        r->gl.DrawBuffer(attachment);
        GLbitfield mask = GL_COLOR_BUFFER_BIT | (i ? 0 : GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
        r->fbo.BlitFramebuffer(b.x, b.y, b.x + b.w, b.y + b.h, b.x, b.y, b.x + b.w, b.y + b.h, mask, GL_NEAREST);
    }
    r->fbo.BindFramebuffer(GL_READ_FRAMEBUFFER, own);
    r->gl.DrawBuffer((GLenum)draw);
    if (scissor)
        r->gl.Enable(GL_SCISSOR_TEST);
}

/* Resolves the window into the single-sampled renderbuffers; the current
 * context is current again after (the switches finish each context, so
 * the resolve sees what the client drew and the client what it wrote). */
int render_ms_resolve(render_spu *r, tsr_error *err)
{
    if (!r->samples || !r->ms_fbo || r->width < 1 || r->height < 1)
        return TSR_OK;
    size_t back = r->current;
    if (render_shared_switch(r, 0, err) != TSR_OK)
        return err->code;
    resolve_in_context0(r);
    return render_shared_switch(r, back, err);
}

/* Copies the multisample back buffer to the multisample front (the swap
 * of a double-buffered multisample window; context 0 is current, its
 * scissor test off). */
void render_ms_swap(render_spu *r)
{
    if (!r->samples || !r->ms_fbo || !r->ms_front_rb)
        return;
    r->fbo.BindFramebuffer(GL_FRAMEBUFFER, r->ms_fbo);
    r->gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
    r->gl.DrawBuffer(GL_COLOR_ATTACHMENT1);
    r->fbo.BlitFramebuffer(0, 0, r->width, r->height, 0, 0, r->width, r->height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    render_app_fb_rebind(r, &r->contexts[0]);
}

/* Before a program's read of the window: resolves it and points the
 * current client context's read framebuffer at the resolved buffers, the
 * read buffer its own. Returns whether render_ms_read_end must undo it. */
bool render_ms_read_begin(render_spu *r)
{
    if (!r->samples || !r->shared || render_current_scissor(r)->list_mode == GL_COMPILE || render_app_read_fb_bound(r))
        return false; /* (a program FBO is read as it is: appfbo.c) */
    render_context *c = &r->contexts[r->current];
    if (!c->resolved_fbo)
        return false;
    GLint read = GL_NONE;
    r->gl.GetIntegerv(GL_READ_BUFFER, &read);
    tsr_error err = {0};
    if (render_ms_resolve(r, &err) != TSR_OK) {
        tsr_log(TSR_LOG_ERROR, "%s: resolving the multisample window: %s", r->name, err.message);
        return false;
    }
    r->fbo.BindFramebuffer(GL_READ_FRAMEBUFFER, c->resolved_fbo);
    r->gl.ReadBuffer((GLenum)read);
    return true;
}

void render_ms_read_end(render_spu *r, bool began)
{
    if (began)
        r->fbo.BindFramebuffer(GL_READ_FRAMEBUFFER, r->contexts[r->current].fbo);
}

static void render_ReadPixels(void *self, GLint x, GLint y, GLsizei width, GLsizei height, GLenum format, GLenum type,
                              void *pixels)
{
    render_spu *r = self;
    bool began = render_ms_read_begin(r);
    r->gl.ReadPixels(x, y, width, height, format, type, pixels);
    render_ms_read_end(r, began);
}

static void render_CopyTexSubImage1D(void *self, GLenum target, GLint level, GLint xoffset, GLint x, GLint y,
                                     GLsizei width)
{
    render_spu *r = self;
    bool began = render_ms_read_begin(r);
    r->gl.CopyTexSubImage1D(target, level, xoffset, x, y, width);
    render_ms_read_end(r, began);
}

static void render_CopyTexSubImage2D(void *self, GLenum target, GLint level, GLint xoffset, GLint yoffset, GLint x,
                                     GLint y, GLsizei width, GLsizei height)
{
    render_spu *r = self;
    bool began = render_ms_read_begin(r);
    r->gl.CopyTexSubImage2D(target, level, xoffset, yoffset, x, y, width, height);
    render_ms_read_end(r, began);
}

static void render_CopyTexSubImage3D(void *self, GLenum target, GLint level, GLint xoffset, GLint yoffset,
                                     GLint zoffset, GLint x, GLint y, GLsizei width, GLsizei height)
{
    render_spu *r = self;
    bool began = render_ms_read_begin(r);
    r->gl.CopyTexSubImage3D(target, level, xoffset, yoffset, zoffset, x, y, width, height);
    render_ms_read_end(r, began);
}

/* Gives the window its multisample renderbuffers: shared mode, storage
 * at the window's size, every context's FBO attached again. */
static int make_multisample(render_spu *r, GLint samples, tsr_error *err)
{
    if (!r->shared && render_shared_enter(r, err) != TSR_OK)
        return err->code;
    size_t back = r->current;
    if (render_shared_switch(r, 0, err) != TSR_OK)
        return err->code;
    r->samples = samples;
    r->fbo.GenRenderbuffers(1, &r->ms_color_rb);
    r->fbo.GenRenderbuffers(1, &r->ms_depth_rb);
    if (r->front_rb)
        r->fbo.GenRenderbuffers(1, &r->ms_front_rb);
    render_ms_storage(r, r->width, r->height);
    r->generation++;
    if (render_shared_make_current(r, 0, err) != TSR_OK)
        return err->code;
    return render_shared_switch(r, back, err);
}

static void render_WindowSamplesTSR(void *self, GLint window, GLint samples)
{
    render_spu *r = self;
    if (window == r->window) {
        tsr_error err = {0};
        GLint most = 0;
        render_ensure_current(r);
        r->gl.GetIntegerv(GL_MAX_SAMPLES, &most);
        if (samples < 2 || samples > most)
            tsr_log(TSR_LOG_ERROR, "%s: WindowSamplesTSR(%d, %d): the renderer draws 2 to %d samples, ignored", r->name,
                    (int)window, (int)samples, (int)most);
        else if (r->samples)
            tsr_log(TSR_LOG_ERROR, "%s: WindowSamplesTSR(%d, %d): the window is multisampled already, ignored", r->name,
                    (int)window, (int)samples);
        else if (make_multisample(r, samples, &err) != TSR_OK)
            tsr_log(TSR_LOG_ERROR, "%s: WindowSamplesTSR(%d, %d): %s", r->name, (int)window, (int)samples, err.message);
    }
    tsr_call_WindowSamplesTSR(r->child, window, samples);
}

void render_multisample_install(render_spu *r, tsr_dispatch *table)
{
    tsr_set_WindowSamplesTSR(table, render_WindowSamplesTSR, r);
    tsr_set_ReadPixels(table, render_ReadPixels, r);
    tsr_set_CopyTexSubImage1D(table, render_CopyTexSubImage1D, r);
    tsr_set_CopyTexSubImage2D(table, render_CopyTexSubImage2D, r);
    tsr_set_CopyTexSubImage3D(table, render_CopyTexSubImage3D, r);
}
