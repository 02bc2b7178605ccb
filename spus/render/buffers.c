/* spus/render/buffers.c — the window's colour buffers as the program
 * named them (docs/render.md, "Front and back buffers"). A window told
 * WindowBuffersTSR(window, 2) is double-buffered as Mesa's are: the
 * shared renderbuffer (contexts.c) is its back buffer, FBO colour
 * attachment 0, and a second renderbuffer of the same size its front,
 * attachment 1; glDrawBuffer/glReadBuffer/glDrawBuffers map GL_BACK,
 * GL_FRONT, GL_FRONT_AND_BACK and GL_LEFT onto them, the gets of those
 * names and of GL_DOUBLEBUFFER answer in the program's names (through
 * scissor.c's glGet*), and each
 * swap copies the back buffer to the front (the back keeps its pixels, as
 * in Mesa's software drivers). A window left single-buffered has one
 * buffer, attachment 0, which GL_FRONT, GL_FRONT_LEFT, GL_LEFT and
 * GL_FRONT_AND_BACK name (GL_BACK is the renderer's error, as natively).
 *
 * Owns: the front renderbuffer's creation and the swap's copy.
 * Never: reads or writes a frame (frame.c), changes a client context's
 * state (the copy runs in context 0, which no client draws with). */
#include "tessera/log.h"

#include "instance.h"

/* The FBO attachment a window buffer name means for drawing (-1: both
 * buffers; 0: not a window buffer name, passed on as it is). */
static GLenum attachment_of(const render_spu *r, GLenum buf, bool *both)
{
    *both = false;
    if (!r->shared)
        return 0;
    if (!r->double_buffered) {
        switch (buf) {
        case GL_FRONT:
        case GL_FRONT_LEFT:
        case GL_LEFT:
        case GL_FRONT_AND_BACK: return GL_COLOR_ATTACHMENT0;
        default: return 0;
        }
    }
    switch (buf) {
    case GL_BACK:
    case GL_BACK_LEFT: return GL_COLOR_ATTACHMENT0;
    case GL_FRONT:
    case GL_FRONT_LEFT: return GL_COLOR_ATTACHMENT1;
    case GL_LEFT:
    case GL_FRONT_AND_BACK: *both = true; return GL_COLOR_ATTACHMENT1;
    default: return 0;
    }
}

/* The current context's names, or NULL while compiling a list (the
 * command then only goes into the list). */
static render_context *naming_context(render_spu *r)
{
    if (!r->shared || render_current_scissor(r)->list_mode == GL_COMPILE)
        return NULL;
    return &r->contexts[r->current];
}

static void render_DrawBuffer(void *self, GLenum buf)
{
    render_spu *r = self;
    if (render_app_fb_bound(r)) { /* the program's FBO: its own names (appfbo.c) */
        r->gl.DrawBuffer(buf);
        return;
    }
    bool both;
    GLenum a = attachment_of(r, buf, &both);
    render_context *c = naming_context(r);
    if (c)
        c->draw_name = buf;
    if (both) {
        static const GLenum pair[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
        r->gl.DrawBuffers(2, pair);
    } else {
        r->gl.DrawBuffer(a ? a : buf);
    }
}

/* Reading GL_LEFT or GL_FRONT_AND_BACK of a double-buffered window reads
 * its front, as Mesa does. */
static void render_ReadBuffer(void *self, GLenum buf)
{
    render_spu *r = self;
    if (render_app_read_fb_bound(r)) {
        r->gl.ReadBuffer(buf);
        return;
    }
    bool both;
    GLenum a = attachment_of(r, buf, &both);
    render_context *c = naming_context(r);
    if (c)
        c->read_name = buf;
    r->gl.ReadBuffer(a ? a : buf);
}

/* glDrawBuffers takes only the single-buffer names (GL_FRONT_LEFT,
 * GL_BACK_LEFT, GL_NONE, ...); the others stay the renderer's error. */
static void render_DrawBuffers(void *self, GLsizei n, const GLenum *bufs)
{
    render_spu *r = self;
    GLenum mapped[16];
    if (!r->shared || n < 0 || n > 16 || !bufs || render_app_fb_bound(r)) {
        r->gl.DrawBuffers(n, bufs);
        return;
    }
    render_context *c = naming_context(r);
    if (c)
        c->draw_name = 0;
    for (GLsizei i = 0; i < n; i++) {
        bool both;
        GLenum a = bufs[i] == GL_FRONT_LEFT || bufs[i] == GL_BACK_LEFT ? attachment_of(r, bufs[i], &both) : 0;
        mapped[i] = a ? a : bufs[i];
    }
    r->gl.DrawBuffers(n, mapped);
}

/* An attachment back to the window's name for it. */
static GLint window_name_of(const render_spu *r, GLint value)
{
    if (value == GL_COLOR_ATTACHMENT0)
        return r->double_buffered ? GL_BACK : GL_FRONT;
    if (value == GL_COLOR_ATTACHMENT1)
        return GL_FRONT;
    return value;
}

/* Answers GL_DRAW_BUFFER(0..), GL_READ_BUFFER and GL_DOUBLEBUFFER in the
 * program's names; false for every other pname (scissor.c's gets ask). */
bool render_buffers_query(render_spu *r, GLenum pname, GLint *value)
{
    if (!r->shared || (pname == GL_READ_BUFFER ? render_app_read_fb_bound(r) : render_app_fb_bound(r)))
        return false;
    if (pname == GL_DOUBLEBUFFER) {
        *value = r->double_buffered;
        return true;
    }
    if (pname != GL_DRAW_BUFFER && pname != GL_READ_BUFFER && !(pname >= GL_DRAW_BUFFER0 && pname <= GL_DRAW_BUFFER15))
        return false;
    GLint v = GL_NONE;
    r->gl.GetIntegerv(pname, &v);
    /* The name the program gave, while the real buffers are still what it
     * maps to (a glPopAttrib or a list may have changed them since). */
    const render_context *c = &r->contexts[r->current];
    GLenum name = pname == GL_READ_BUFFER ? c->read_name : pname == GL_DRAW_BUFFER1 ? 0 : c->draw_name;
    if (name && (pname == GL_DRAW_BUFFER || pname == GL_DRAW_BUFFER0 || pname == GL_READ_BUFFER)) {
        bool both;
        GLenum a = attachment_of(r, name, &both);
        GLint second = GL_NONE;
        if (pname != GL_READ_BUFFER)
            r->gl.GetIntegerv(GL_DRAW_BUFFER1, &second);
        bool same = pname == GL_READ_BUFFER ? (GLenum)v == (a ? a : name)
                    : both                  ? v == GL_COLOR_ATTACHMENT0 && second == GL_COLOR_ATTACHMENT1
                                            : (GLenum)v == (a ? a : name) && second == GL_NONE;
        if (same) {
            *value = (GLint)name;
            return true;
        }
    }
    if ((pname == GL_DRAW_BUFFER || pname == GL_DRAW_BUFFER0) && v == GL_COLOR_ATTACHMENT0 && r->double_buffered) {
        GLint second = GL_NONE;
        r->gl.GetIntegerv(GL_DRAW_BUFFER1, &second);
        if (second == GL_COLOR_ATTACHMENT1) {
            *value = GL_FRONT_AND_BACK;
            return true;
        }
    }
    if (pname == GL_DRAW_BUFFER1 && v == GL_COLOR_ATTACHMENT1 && r->double_buffered) {
        GLint first = GL_NONE;
        r->gl.GetIntegerv(GL_DRAW_BUFFER0, &first);
        if (first == GL_COLOR_ATTACHMENT0) {
            *value = GL_NONE;
            return true;
        }
    }
    *value = window_name_of(r, v);
    return true;
}

/* Gives the window its front buffer: shared mode, a second renderbuffer
 * at the window's size, every context's FBO attached to it again. */
static int make_double(render_spu *r, tsr_error *err)
{
    if (!r->shared && render_shared_enter(r, err) != TSR_OK)
        return err->code;
    size_t back = r->current;
    if (render_shared_switch(r, 0, err) != TSR_OK)
        return err->code;
    r->fbo.GenRenderbuffers(1, &r->front_rb);
    r->fbo.BindRenderbuffer(GL_RENDERBUFFER, r->front_rb);
    r->fbo.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, r->width > 0 ? r->width : 1, r->height > 0 ? r->height : 1);
    r->fbo.BindRenderbuffer(GL_RENDERBUFFER, render_app_rb(r));
    if (r->samples) { /* the front is multisampled too (multisample.c) */
        r->fbo.GenRenderbuffers(1, &r->ms_front_rb);
        render_ms_storage(r, r->width, r->height);
    }
    r->double_buffered = true;
    r->generation++;
    if (render_shared_make_current(r, 0, err) != TSR_OK)
        return err->code;
    /* Context 0 reads frames: from the back, which the swap has just
     * copied to the front. */
    r->gl.DrawBuffer(GL_COLOR_ATTACHMENT0);
    r->gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
    return render_shared_switch(r, back, err);
}

static void render_WindowBuffersTSR(void *self, GLint window, GLint buffers)
{
    render_spu *r = self;
    if (window == r->window) {
        tsr_error err = {0};
        if (buffers != 1 && buffers != 2)
            tsr_log(TSR_LOG_ERROR, "%s: WindowBuffersTSR(%d, %d): a window has 1 or 2 colour buffers, ignored", r->name,
                    (int)window, (int)buffers);
        else if (buffers == 2 && !r->double_buffered && make_double(r, &err) != TSR_OK)
            tsr_log(TSR_LOG_ERROR, "%s: WindowBuffersTSR(%d, 2): %s", r->name, (int)window, err.message);
        else if (buffers == 1 && r->double_buffered)
            tsr_log(TSR_LOG_ERROR, "%s: WindowBuffersTSR(%d, 1): the window is double-buffered already, ignored",
                    r->name, (int)window);
    }
    tsr_call_WindowBuffersTSR(r->child, window, buffers);
}

/* The swap: the back buffer copied to the front in context 0 (its scissor
 * test off, its read and draw buffers set for the copy and put back). */
void render_buffers_swap(render_spu *r)
{
    if (!r->double_buffered || r->width < 1 || r->height < 1)
        return;
    tsr_error err = {0};
    size_t back = r->current;
    if (render_shared_switch(r, 0, &err) != TSR_OK) {
        tsr_log(TSR_LOG_ERROR, "%s: swap: %s", r->name, err.message);
        return;
    }
    r->gl.PushAttrib(GL_SCISSOR_BIT | GL_COLOR_BUFFER_BIT | GL_PIXEL_MODE_BIT);
    r->gl.Disable(GL_SCISSOR_TEST);
    r->gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
    r->gl.DrawBuffer(GL_COLOR_ATTACHMENT1);
    r->fbo.BlitFramebuffer(0, 0, r->width, r->height, 0, 0, r->width, r->height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    render_ms_swap(r);
    r->gl.PopAttrib();
    if (render_shared_switch(r, back, &err) != TSR_OK)
        tsr_log(TSR_LOG_ERROR, "%s: swap: %s", r->name, err.message);
}

void render_buffers_install(render_spu *r, tsr_dispatch *table)
{
    tsr_set_WindowBuffersTSR(table, render_WindowBuffersTSR, r);
    tsr_set_DrawBuffer(table, render_DrawBuffer, r);
    tsr_set_ReadBuffer(table, render_ReadBuffer, r);
    tsr_set_DrawBuffers(table, render_DrawBuffers, r);
}
