/* spus/render/appfbo.c — the program's own framebuffer objects and
 * renderbuffers (GL_EXT_framebuffer_object, and GL_ARB_framebuffer_object's
 * core names for the same objects) next to the ones render draws the
 * window into (contexts.c, multisample.c).
 *
 * The program's framebuffer 0 is the window: binding 0 binds the current
 * context's window FBO in shared mode (GL's 0 in solo mode), and the
 * binding queries answer 0 for it. The read and the draw framebuffer are
 * bound apart (GL_READ_FRAMEBUFFER, GL_DRAW_FRAMEBUFFER; GL_FRAMEBUFFER is
 * both), so a glBlitFramebuffer between the window and an FBO reads and
 * writes what GL's would: the window FBO is flipped as a window is
 * (contexts.c), and Mesa's blit honours that. The program's names are its own: a
 * table maps each to the driver's name, so a name the program binds
 * without generating it (EXT allows that) never reaches one of render's
 * objects, and the driver's names of render's objects never reach the
 * program. While a program FBO is bound for drawing, glDrawBuffer(s), the
 * clear and draw fast paths act on it (buffers.c and pixels.c ask
 * render_app_fb_bound) and on a tile server the tiles' scissor is off
 * (scissor.c: the FBO's coordinates are its own, and a wall draws it
 * whole on every server); while one is bound for reading, glReadBuffer
 * and reads act on it (render_app_read_fb_bound, multisample.c). A swap
 * reads the window (render_end_frame steps out of the program's FBOs and
 * back).
 *
 * Owns: the two name tables, the entries of both extensions' commands.
 * Never: touches render's own FBOs beyond binding the window's one for
 * the program's 0, keeps an object's state (GL keeps it). */
#include <stdint.h>
#include <stdlib.h>

#include "instance.h"

#ifndef GL_FRAMEBUFFER_EXT
#define GL_FRAMEBUFFER_EXT 0x8D40
#define GL_RENDERBUFFER_EXT 0x8D41
#define GL_FRAMEBUFFER_BINDING_EXT 0x8CA6
#define GL_RENDERBUFFER_BINDING_EXT 0x8CA7
#define GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE_EXT 0x8CD0
#define GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME_EXT 0x8CD1
#endif
#ifndef GL_READ_FRAMEBUFFER_BINDING
#define GL_READ_FRAMEBUFFER_BINDING 0x8CAA
#endif
#ifndef GL_READ_FRAMEBUFFER
#define GL_READ_FRAMEBUFFER 0x8CA8
#define GL_DRAW_FRAMEBUFFER 0x8CA9
#endif

/* A name the driver never hands out in practice: an unknown program name
 * becomes it, so GL answers (and errs) as for any unknown name. */
#define UNKNOWN_NAME 0xFFFFFFFFu

static render_app_binding *binding(render_spu *r) { return r->shared ? &r->contexts[r->current].app : &r->solo_app; }

static GLuint window_fb(const render_spu *r) { return r->shared ? r->contexts[r->current].fbo : 0; }

bool render_app_fb_bound(render_spu *r) { return binding(r)->fb != 0; }

bool render_app_read_fb_bound(render_spu *r) { return binding(r)->read_fb != 0; }

GLuint render_app_read_fb_or_window(const render_context *c) { return c->app.read_fb ? c->app.read_fb : c->fbo; }

/* Binds context `c`'s draw and read framebuffers as the program has them
 * (its FBOs or the window's), after render bound its own (c current). */
void render_app_fb_rebind(render_spu *r, const render_context *c)
{
    r->fbo.BindFramebuffer(GL_DRAW_FRAMEBUFFER, c->app.fb ? c->app.fb : c->fbo);
    r->fbo.BindFramebuffer(GL_READ_FRAMEBUFFER, render_app_read_fb_or_window(c));
}

GLuint render_app_rb(render_spu *r) { return binding(r)->rb; }

/* --- name tables ----------------------------------------------------------- */

static GLuint driver_of(const render_names *t, GLuint name)
{
    for (size_t i = 0; i < t->n; i++)
        if (t->pairs[i].program == name)
            return t->pairs[i].driver;
    return 0;
}

static GLuint program_of(const render_names *t, GLuint driver)
{
    for (size_t i = 0; i < t->n; i++)
        if (t->pairs[i].driver == driver)
            return t->pairs[i].program;
    return 0;
}

static bool names_put(render_names *t, GLuint program, GLuint driver)
{
    if (t->n == t->cap) {
        size_t cap = t->cap ? t->cap * 2 : 16;
        render_name_pair *p = realloc(t->pairs, cap * sizeof *p);
        if (!p)
            return false;
        t->pairs = p;
        t->cap = cap;
    }
    t->pairs[t->n++] = (render_name_pair){program, driver};
    if (program > t->max_program)
        t->max_program = program;
    return true;
}

static void names_drop(render_names *t, GLuint program)
{
    for (size_t i = 0; i < t->n; i++)
        if (t->pairs[i].program == program) {
            t->pairs[i] = t->pairs[--t->n];
            return;
        }
}

/* The program's name of a driver-made object: the driver's own when the
 * program does not use it already (it may have bound it ungenerated). */
static GLuint adopt(render_names *t, GLuint driver)
{
    GLuint name = driver;
    if (!name || driver_of(t, name))
        name = t->max_program + 1;
    while (!name || driver_of(t, name))
        name++;
    return names_put(t, name, driver) ? name : 0;
}

void render_names_free(render_names *t)
{
    free(t->pairs);
    *t = (render_names){0};
}

typedef void(GLAPIENTRY *gen_fn)(GLsizei n, GLuint *ids);

static void gen_names(render_names *t, gen_fn gen, GLsizei n, GLuint *ids)
{
    gen(n, ids); /* the driver's names (and its error for n < 0) */
    for (GLsizei i = 0; i > -1 && i < n; i++)
        ids[i] = adopt(t, ids[i]);
}

/* The driver's object for a name the program binds: a new one when the
 * program never had it (EXT's glBind* creates it). */
static GLuint bind_name(render_names *t, gen_fn gen, GLuint name)
{
    if (!name)
        return 0;
    GLuint d = driver_of(t, name);
    if (!d) {
        gen(1, &d);
        if (!d || !names_put(t, name, d))
            return UNKNOWN_NAME;
    }
    return d;
}

/* --- framebuffers ---------------------------------------------------------- */

typedef void(GLAPIENTRY *bind_fn)(GLenum target, GLuint name);
typedef void(GLAPIENTRY *delete_fn)(GLsizei n, const GLuint *ids);
typedef GLboolean(GLAPIENTRY *is_fn)(GLuint name);

static void bind_framebuffer(render_spu *r, bind_fn bind, gen_fn gen, GLenum target, GLuint framebuffer)
{
    GLuint d = framebuffer ? bind_name(&r->app_fb_names, gen, framebuffer) : window_fb(r);
    bind(target, d); /* GL's error for another target, or for an unknown name in a core context */
    if (d == UNKNOWN_NAME)
        return;
    render_app_binding *b = binding(r);
    GLuint now = framebuffer ? d : 0;
    if (target == GL_FRAMEBUFFER_EXT || target == GL_DRAW_FRAMEBUFFER)
        b->fb = now;
    if (target == GL_FRAMEBUFFER_EXT || target == GL_READ_FRAMEBUFFER)
        b->read_fb = now;
    render_scissor_refresh(r, render_current_scissor(r)); /* tiles are the window's (scissor.c) */
}

static void render_GenFramebuffersEXT(void *self, GLsizei n, GLuint *ids)
{
    render_spu *r = self;
    gen_names(&r->app_fb_names, r->gl.GenFramebuffersEXT, n, ids);
}

static void render_GenFramebuffers(void *self, GLsizei n, GLuint *ids)
{
    render_spu *r = self;
    gen_names(&r->app_fb_names, r->gl.GenFramebuffers, n, ids);
}

static void render_BindFramebufferEXT(void *self, GLenum target, GLuint framebuffer)
{
    render_spu *r = self;
    bind_framebuffer(r, r->gl.BindFramebufferEXT, r->gl.GenFramebuffersEXT, target, framebuffer);
}

static void render_BindFramebuffer(void *self, GLenum target, GLuint framebuffer)
{
    render_spu *r = self;
    bind_framebuffer(r, r->gl.BindFramebuffer, r->gl.GenFramebuffers, target, framebuffer);
}

static void delete_framebuffers(render_spu *r, delete_fn del, GLsizei n, const GLuint *ids)
{
    if (n < 0) {
        del(n, ids);
        return;
    }
    render_app_binding *b = binding(r);
    bool draw_gone = false, read_gone = false;
    for (GLsizei i = 0; i < n; i++) {
        GLuint d = driver_of(&r->app_fb_names, ids[i]);
        if (!d)
            continue; /* unknown or 0: GL ignores those silently */
        names_drop(&r->app_fb_names, ids[i]);
        del(1, &d);
        if (d == b->fb)
            b->fb = 0, draw_gone = true;
        if (d == b->read_fb)
            b->read_fb = 0, read_gone = true;
    }
    /* GL went back to its 0 for each binding deleted; the program's 0 is the window */
    if (draw_gone)
        r->gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, window_fb(r));
    if (read_gone)
        r->gl.BindFramebuffer(GL_READ_FRAMEBUFFER, window_fb(r));
    if (draw_gone)
        render_scissor_refresh(r, render_current_scissor(r));
}

static void render_DeleteFramebuffersEXT(void *self, GLsizei n, const GLuint *ids)
{
    render_spu *r = self;
    delete_framebuffers(r, r->gl.DeleteFramebuffersEXT, n, ids);
}

static void render_DeleteFramebuffers(void *self, GLsizei n, const GLuint *ids)
{
    render_spu *r = self;
    delete_framebuffers(r, r->gl.DeleteFramebuffers, n, ids);
}

static GLboolean render_IsFramebufferEXT(void *self, GLuint framebuffer)
{
    render_spu *r = self;
    GLuint d = driver_of(&r->app_fb_names, framebuffer);
    return d ? r->gl.IsFramebufferEXT(d) : GL_FALSE;
}

static GLboolean render_IsFramebuffer(void *self, GLuint framebuffer)
{
    render_spu *r = self;
    GLuint d = driver_of(&r->app_fb_names, framebuffer);
    return d ? r->gl.IsFramebuffer(d) : GL_FALSE;
}

/* A blit writes the window's stencil like a glDrawPixels of it
 * (pixels.c's render_Clear says why render minds). */
static void render_BlitFramebuffer(void *self, GLint sx0, GLint sy0, GLint sx1, GLint sy1, GLint dx0, GLint dy0,
                                   GLint dx1, GLint dy1, GLbitfield mask, GLenum filter)
{
    render_spu *r = self;
    if ((mask & GL_STENCIL_BUFFER_BIT) && !render_app_fb_bound(r))
        r->stencil_written = true;
    r->gl.BlitFramebuffer(sx0, sy0, sx1, sy1, dx0, dy0, dx1, dy1, mask, filter);
}

/* --- renderbuffers --------------------------------------------------------- */

static void render_GenRenderbuffersEXT(void *self, GLsizei n, GLuint *ids)
{
    render_spu *r = self;
    gen_names(&r->app_rb_names, r->gl.GenRenderbuffersEXT, n, ids);
}

static void render_GenRenderbuffers(void *self, GLsizei n, GLuint *ids)
{
    render_spu *r = self;
    gen_names(&r->app_rb_names, r->gl.GenRenderbuffers, n, ids);
}

static void bind_renderbuffer(render_spu *r, bind_fn bind, gen_fn gen, GLenum target, GLuint renderbuffer)
{
    GLuint d = bind_name(&r->app_rb_names, gen, renderbuffer);
    bind(target, d);
    if (target == GL_RENDERBUFFER_EXT && d != UNKNOWN_NAME)
        binding(r)->rb = d;
}

static void render_BindRenderbufferEXT(void *self, GLenum target, GLuint renderbuffer)
{
    render_spu *r = self;
    bind_renderbuffer(r, r->gl.BindRenderbufferEXT, r->gl.GenRenderbuffersEXT, target, renderbuffer);
}

static void render_BindRenderbuffer(void *self, GLenum target, GLuint renderbuffer)
{
    render_spu *r = self;
    bind_renderbuffer(r, r->gl.BindRenderbuffer, r->gl.GenRenderbuffers, target, renderbuffer);
}

static void delete_renderbuffers(render_spu *r, delete_fn del, GLsizei n, const GLuint *ids)
{
    if (n < 0) {
        del(n, ids);
        return;
    }
    render_app_binding *b = binding(r);
    for (GLsizei i = 0; i < n; i++) {
        GLuint d = driver_of(&r->app_rb_names, ids[i]);
        if (!d)
            continue;
        names_drop(&r->app_rb_names, ids[i]);
        del(1, &d); /* GL unbinds it where bound */
        if (d == b->rb)
            b->rb = 0;
    }
}

static void render_DeleteRenderbuffersEXT(void *self, GLsizei n, const GLuint *ids)
{
    render_spu *r = self;
    delete_renderbuffers(r, r->gl.DeleteRenderbuffersEXT, n, ids);
}

static void render_DeleteRenderbuffers(void *self, GLsizei n, const GLuint *ids)
{
    render_spu *r = self;
    delete_renderbuffers(r, r->gl.DeleteRenderbuffers, n, ids);
}

static GLboolean is_renderbuffer(render_spu *r, is_fn is, GLuint renderbuffer)
{
    GLuint d = driver_of(&r->app_rb_names, renderbuffer);
    return d ? is(d) : GL_FALSE;
}

static GLboolean render_IsRenderbufferEXT(void *self, GLuint renderbuffer)
{
    render_spu *r = self;
    return is_renderbuffer(r, r->gl.IsRenderbufferEXT, renderbuffer);
}

static GLboolean render_IsRenderbuffer(void *self, GLuint renderbuffer)
{
    render_spu *r = self;
    return is_renderbuffer(r, r->gl.IsRenderbuffer, renderbuffer);
}

/* The driver's renderbuffer for a program's name given to an attachment. */
static GLuint attached_rb(render_spu *r, GLuint renderbuffer)
{
    GLuint d = renderbuffer ? driver_of(&r->app_rb_names, renderbuffer) : 0;
    return renderbuffer && !d ? UNKNOWN_NAME : d;
}

static void render_FramebufferRenderbufferEXT(void *self, GLenum target, GLenum attachment, GLenum rbtarget,
                                              GLuint renderbuffer)
{
    render_spu *r = self;
    r->gl.FramebufferRenderbufferEXT(target, attachment, rbtarget, attached_rb(r, renderbuffer));
}

static void render_FramebufferRenderbuffer(void *self, GLenum target, GLenum attachment, GLenum rbtarget,
                                           GLuint renderbuffer)
{
    render_spu *r = self;
    r->gl.FramebufferRenderbuffer(target, attachment, rbtarget, attached_rb(r, renderbuffer));
}

typedef void(GLAPIENTRY *attachment_get_fn)(GLenum target, GLenum attachment, GLenum pname, GLint *params);

#ifndef GL_FRAMEBUFFER_DEFAULT
#define GL_FRAMEBUFFER_DEFAULT 0x8218
#endif

/* Whether `target`'s binding is the program's framebuffer 0, which render
 * draws into a window FBO of its own (shared mode; in solo mode GL's own
 * 0 is bound and answers for itself). */
static bool window_bound(render_spu *r, GLenum target)
{
    render_app_binding *b = binding(r);
    return r->shared && (target == GL_READ_FRAMEBUFFER ? b->read_fb : b->fb) == 0;
}

/* An attachment name of a default framebuffer (GL 3.0 section 6.1.3:
 * GL_FRONT_LEFT, GL_BACK_LEFT, GL_DEPTH, GL_STENCIL, ...) as the window
 * FBO's attachment holding that buffer (contexts.c, buffers.c: the back
 * buffer at 0 and the front at 1 when double-buffered, else the one colour
 * buffer at 0, which Mesa answers for the back too); an attachment render
 * leaves empty for a buffer
 * the window lacks, which GL answers as GL_NONE; 0 for any other name. */
static GLenum window_attachment(const render_spu *r, GLenum attachment)
{
    const GLenum none = GL_COLOR_ATTACHMENT0 + 7; /* render attaches 0 and 1 only */
    switch (attachment) {
    case GL_FRONT_LEFT:
    case GL_FRONT: return r->double_buffered ? GL_COLOR_ATTACHMENT1 : GL_COLOR_ATTACHMENT0;
    case GL_BACK_LEFT:
    case GL_BACK: return GL_COLOR_ATTACHMENT0; /* single-buffered: its one buffer, as Mesa answers */
    case GL_FRONT_RIGHT:
    case GL_BACK_RIGHT:
    case GL_AUX0:
    case GL_AUX1:
    case GL_AUX2:
    case GL_AUX3: return none;
    case GL_DEPTH: return GL_DEPTH_ATTACHMENT;
    case GL_STENCIL: return GL_STENCIL_ATTACHMENT;
    default: return 0;
    }
}

/* The program's answers: a renderbuffer attachment's name in the
 * program's names; a buffer of the window as GL answers for a default
 * framebuffer (type GL_FRAMEBUFFER_DEFAULT, name 0, the sizes and types
 * of render's window buffers), asked by the window's buffer names
 * (piglit's pixel probes ask the read buffer's component type so). */
static void attachment_parameter(render_spu *r, attachment_get_fn get, GLenum target, GLenum attachment, GLenum pname,
                                 GLint *params)
{
    GLenum in_window = window_bound(r, target) ? window_attachment(r, attachment) : 0;
    get(target, in_window ? in_window : attachment, pname, params);
    if (pname != GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME_EXT && pname != GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE_EXT)
        return;
    GLint type = GL_NONE;
    get(target, in_window ? in_window : attachment, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE_EXT, &type);
    if (in_window && type != GL_NONE)
        *params = pname == GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE_EXT ? GL_FRAMEBUFFER_DEFAULT : 0;
    else if (pname == GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME_EXT && type == GL_RENDERBUFFER_EXT)
        *params = (GLint)program_of(&r->app_rb_names, (GLuint)*params);
}

static void render_GetFramebufferAttachmentParameterivEXT(void *self, GLenum target, GLenum attachment, GLenum pname,
                                                          GLint *params)
{
    render_spu *r = self;
    attachment_parameter(r, r->gl.GetFramebufferAttachmentParameterivEXT, target, attachment, pname, params);
}

static void render_GetFramebufferAttachmentParameteriv(void *self, GLenum target, GLenum attachment, GLenum pname,
                                                       GLint *params)
{
    render_spu *r = self;
    attachment_parameter(r, r->gl.GetFramebufferAttachmentParameteriv, target, attachment, pname, params);
}

/* The binding queries in the program's names (scissor.c's gets ask);
 * GL_FRAMEBUFFER_BINDING is GL_DRAW_FRAMEBUFFER_BINDING. */
bool render_app_fb_query(render_spu *r, GLenum pname, GLint *value)
{
    render_app_binding *b = binding(r);
    if (pname == GL_FRAMEBUFFER_BINDING_EXT)
        *value = b->fb ? (GLint)program_of(&r->app_fb_names, b->fb) : 0;
    else if (pname == GL_READ_FRAMEBUFFER_BINDING)
        *value = b->read_fb ? (GLint)program_of(&r->app_fb_names, b->read_fb) : 0;
    else if (pname == GL_RENDERBUFFER_BINDING_EXT)
        *value = b->rb ? (GLint)program_of(&r->app_rb_names, b->rb) : 0;
    else
        return false;
    return true;
}

/* A swap reads the window: out of the program's FBOs for its length. */
void render_app_fb_leave(render_spu *r)
{
    if (binding(r)->fb || binding(r)->read_fb)
        r->gl.BindFramebuffer(GL_FRAMEBUFFER, window_fb(r));
}

void render_app_fb_return(render_spu *r)
{
    render_app_binding *b = binding(r);
    if (b->fb)
        r->gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, b->fb);
    if (b->read_fb)
        r->gl.BindFramebuffer(GL_READ_FRAMEBUFFER, b->read_fb);
}

void render_appfbo_install(render_spu *r, tsr_dispatch *table)
{
    tsr_set_GenFramebuffersEXT(table, render_GenFramebuffersEXT, r);
    tsr_set_BindFramebufferEXT(table, render_BindFramebufferEXT, r);
    tsr_set_DeleteFramebuffersEXT(table, render_DeleteFramebuffersEXT, r);
    tsr_set_IsFramebufferEXT(table, render_IsFramebufferEXT, r);
    tsr_set_GenRenderbuffersEXT(table, render_GenRenderbuffersEXT, r);
    tsr_set_BindRenderbufferEXT(table, render_BindRenderbufferEXT, r);
    tsr_set_DeleteRenderbuffersEXT(table, render_DeleteRenderbuffersEXT, r);
    tsr_set_IsRenderbufferEXT(table, render_IsRenderbufferEXT, r);
    tsr_set_FramebufferRenderbufferEXT(table, render_FramebufferRenderbufferEXT, r);
    tsr_set_GetFramebufferAttachmentParameterivEXT(table, render_GetFramebufferAttachmentParameterivEXT, r);
    tsr_set_GenFramebuffers(table, render_GenFramebuffers, r);
    tsr_set_BindFramebuffer(table, render_BindFramebuffer, r);
    tsr_set_DeleteFramebuffers(table, render_DeleteFramebuffers, r);
    tsr_set_IsFramebuffer(table, render_IsFramebuffer, r);
    tsr_set_GenRenderbuffers(table, render_GenRenderbuffers, r);
    tsr_set_BindRenderbuffer(table, render_BindRenderbuffer, r);
    tsr_set_DeleteRenderbuffers(table, render_DeleteRenderbuffers, r);
    tsr_set_IsRenderbuffer(table, render_IsRenderbuffer, r);
    tsr_set_FramebufferRenderbuffer(table, render_FramebufferRenderbuffer, r);
    tsr_set_GetFramebufferAttachmentParameteriv(table, render_GetFramebufferAttachmentParameteriv, r);
    tsr_set_BlitFramebuffer(table, render_BlitFramebuffer, r);
}
