/* spus/render/appfbo.c — the program's own framebuffer objects and
 * renderbuffers (GL_EXT_framebuffer_object) next to the ones render draws
 * the window into (contexts.c, multisample.c).
 *
 * The program's framebuffer 0 is the window: binding 0 binds the current
 * context's window FBO in shared mode (GL's 0 in solo mode), and the
 * binding queries answer 0 for it. The program's names are its own: a
 * table maps each to the driver's name, so a name the program binds
 * without generating it (EXT allows that) never reaches one of render's
 * objects, and the driver's names of render's objects never reach the
 * program. While a program FBO is bound, glDrawBuffer/glReadBuffer and
 * reads act on it (buffers.c and multisample.c ask
 * render_app_fb_bound), a swap reads the window (render_end_frame
 * steps out of the program's FBO and back), and on a tile server the
 * tiles' scissor is off (scissor.c: the FBO's coordinates are its own,
 * and a wall draws it whole on every server).
 *
 * Owns: the two name tables, the entries of the extension's commands.
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

/* A name the driver never hands out in practice: an unknown program name
 * becomes it, so GL answers (and errs) as for any unknown name. */
#define UNKNOWN_NAME 0xFFFFFFFFu

static render_app_binding *binding(render_spu *r) { return r->shared ? &r->contexts[r->current].app : &r->solo_app; }

static GLuint window_fb(const render_spu *r) { return r->shared ? r->contexts[r->current].fbo : 0; }

bool render_app_fb_bound(render_spu *r) { return binding(r)->fb != 0; }

GLuint render_app_fb_or_window(const render_context *c) { return c->app.fb ? c->app.fb : c->fbo; }

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

static void render_GenFramebuffersEXT(void *self, GLsizei n, GLuint *ids)
{
    render_spu *r = self;
    gen_names(&r->app_fb_names, r->gl.GenFramebuffersEXT, n, ids);
}

static void render_BindFramebufferEXT(void *self, GLenum target, GLuint framebuffer)
{
    render_spu *r = self;
    GLuint d = framebuffer ? bind_name(&r->app_fb_names, r->gl.GenFramebuffersEXT, framebuffer) : window_fb(r);
    r->gl.BindFramebufferEXT(target, d);
    if (target == GL_FRAMEBUFFER_EXT && d != UNKNOWN_NAME)
        binding(r)->fb = framebuffer ? d : 0;
    render_scissor_refresh(r, render_current_scissor(r)); /* tiles are the window's (scissor.c) */
}

static void render_DeleteFramebuffersEXT(void *self, GLsizei n, const GLuint *ids)
{
    render_spu *r = self;
    if (n < 0) {
        r->gl.DeleteFramebuffersEXT(n, ids);
        return;
    }
    render_app_binding *b = binding(r);
    bool unbound = false;
    for (GLsizei i = 0; i < n; i++) {
        GLuint d = driver_of(&r->app_fb_names, ids[i]);
        if (!d)
            continue; /* unknown or 0: GL ignores those silently */
        names_drop(&r->app_fb_names, ids[i]);
        r->gl.DeleteFramebuffersEXT(1, &d);
        if (d == b->fb)
            b->fb = 0, unbound = true;
    }
    if (unbound) { /* GL went back to its 0; the program's 0 is the window */
        r->gl.BindFramebufferEXT(GL_FRAMEBUFFER_EXT, window_fb(r));
        render_scissor_refresh(r, render_current_scissor(r));
    }
}

static GLboolean render_IsFramebufferEXT(void *self, GLuint framebuffer)
{
    render_spu *r = self;
    GLuint d = driver_of(&r->app_fb_names, framebuffer);
    return d ? r->gl.IsFramebufferEXT(d) : GL_FALSE;
}

/* --- renderbuffers --------------------------------------------------------- */

static void render_GenRenderbuffersEXT(void *self, GLsizei n, GLuint *ids)
{
    render_spu *r = self;
    gen_names(&r->app_rb_names, r->gl.GenRenderbuffersEXT, n, ids);
}

static void render_BindRenderbufferEXT(void *self, GLenum target, GLuint renderbuffer)
{
    render_spu *r = self;
    GLuint d = bind_name(&r->app_rb_names, r->gl.GenRenderbuffersEXT, renderbuffer);
    r->gl.BindRenderbufferEXT(target, d);
    if (target == GL_RENDERBUFFER_EXT && d != UNKNOWN_NAME)
        binding(r)->rb = d;
}

static void render_DeleteRenderbuffersEXT(void *self, GLsizei n, const GLuint *ids)
{
    render_spu *r = self;
    if (n < 0) {
        r->gl.DeleteRenderbuffersEXT(n, ids);
        return;
    }
    render_app_binding *b = binding(r);
    for (GLsizei i = 0; i < n; i++) {
        GLuint d = driver_of(&r->app_rb_names, ids[i]);
        if (!d)
            continue;
        names_drop(&r->app_rb_names, ids[i]);
        r->gl.DeleteRenderbuffersEXT(1, &d); /* GL unbinds it where bound */
        if (d == b->rb)
            b->rb = 0;
    }
}

static GLboolean render_IsRenderbufferEXT(void *self, GLuint renderbuffer)
{
    render_spu *r = self;
    GLuint d = driver_of(&r->app_rb_names, renderbuffer);
    return d ? r->gl.IsRenderbufferEXT(d) : GL_FALSE;
}

static void render_FramebufferRenderbufferEXT(void *self, GLenum target, GLenum attachment, GLenum rbtarget,
                                              GLuint renderbuffer)
{
    render_spu *r = self;
    GLuint d = renderbuffer ? driver_of(&r->app_rb_names, renderbuffer) : 0;
    r->gl.FramebufferRenderbufferEXT(target, attachment, rbtarget, renderbuffer && !d ? UNKNOWN_NAME : d);
}

static void render_GetFramebufferAttachmentParameterivEXT(void *self, GLenum target, GLenum attachment, GLenum pname,
                                                          GLint *params)
{
    render_spu *r = self;
    r->gl.GetFramebufferAttachmentParameterivEXT(target, attachment, pname, params);
    if (pname != GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME_EXT)
        return;
    GLint type = GL_NONE;
    r->gl.GetFramebufferAttachmentParameterivEXT(target, attachment, GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE_EXT, &type);
    if (type == GL_RENDERBUFFER_EXT)
        *params = (GLint)program_of(&r->app_rb_names, (GLuint)*params);
}

/* The binding queries in the program's names (scissor.c's gets ask). */
bool render_app_fb_query(render_spu *r, GLenum pname, GLint *value)
{
    render_app_binding *b = binding(r);
    if (pname == GL_FRAMEBUFFER_BINDING_EXT || pname == GL_READ_FRAMEBUFFER_BINDING)
        *value = b->fb ? (GLint)program_of(&r->app_fb_names, b->fb) : 0;
    else if (pname == GL_RENDERBUFFER_BINDING_EXT)
        *value = b->rb ? (GLint)program_of(&r->app_rb_names, b->rb) : 0;
    else
        return false;
    return true;
}

/* A swap reads the window: out of the program's FBO for its length. */
void render_app_fb_leave(render_spu *r)
{
    if (binding(r)->fb)
        r->gl.BindFramebufferEXT(GL_FRAMEBUFFER_EXT, window_fb(r));
}

void render_app_fb_return(render_spu *r)
{
    if (binding(r)->fb)
        r->gl.BindFramebufferEXT(GL_FRAMEBUFFER_EXT, binding(r)->fb);
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
}
