/* spus/tilesort/fbo.c — the program's framebuffer objects on a wall
 * (GL_EXT_framebuffer_object and GL_ARB_framebuffer_object's core names
 * for the same objects; docs/walls.md, "Framebuffer objects").
 *
 * A sort-first wall divides the window, not an FBO: a picture drawn into
 * an FBO is a texture or a renderbuffer the program later uses anywhere
 * in the window (or reads back), so each server needs all of it. The wall
 * renders FBOs replicated, which is exact: every FBO command goes to every
 * live server, each first brought up to date with the tracked state (and
 * given the texture it attaches, which a diff sends only when bound), and
 * while a program FBO is bound every geometry buffer, array draw, list
 * call and frame command goes to every server unsorted (send.c's
 * choose_targets, arrays.c's draw_sorted) and render leaves its tiles'
 * scissor off (spus/render/scissor.c), so every server holds the same
 * whole FBO. glGen* and the queries go to the first live server (the
 * generic R_SERVER route): the others make an object of the same name when
 * it is first bound (render's appfbo.c, as EXT and a compatibility
 * context allow), and a glReadPixels while an FBO is bound for reading
 * reads that one server's FBO (frame.c). The draw and the read binding
 * are kept apart (GL_DRAW_FRAMEBUFFER and GL_READ_FRAMEBUFFER): drawing
 * is routed by the one, reads and blits (blit.c) by the other.
 *
 * The draw and read buffers are the framebuffer's state in GL, not the
 * context's: while a program FBO is bound they go to every server and
 * their gets to the first one, and the tracker keeps the window's (its
 * diffs would otherwise carry an FBO's GL_COLOR_ATTACHMENT0 to the window).
 *
 * Owns the instance's app_fb and app_read_fb (the program's bound draw
 * and read framebuffers, 0: the window; one per instance, since the
 * instance follows one context).
 * Never: sends an FBO command to a server before that server's state diff
 * (a command must find the state and objects the program made before it),
 * lets the tracker take a draw or read buffer set inside an FBO. */
#include <string.h>

#include "instance.h"

/* What comes next goes to every live server, each after its diff, and is
 * sent at once (the R_FRAME route's steps, tilesort.c). */
static void to_every_server_begin(tilesort *t) { ts_broadcast_next(t); }
static void to_every_server_end(tilesort *t) { ts_flush_geometry(t); }

int ts_fbo_command(const char *name)
{
    static const char *const names[] = {"BindFramebufferEXT",
                                        "DeleteFramebuffersEXT",
                                        "BindRenderbufferEXT",
                                        "DeleteRenderbuffersEXT",
                                        "RenderbufferStorageEXT",
                                        "FramebufferTexture1DEXT",
                                        "FramebufferTexture2DEXT",
                                        "FramebufferTexture3DEXT",
                                        "FramebufferRenderbufferEXT",
                                        "GenerateMipmapEXT",
                                        "BindFramebuffer",
                                        "DeleteFramebuffers",
                                        "BindRenderbuffer",
                                        "DeleteRenderbuffers",
                                        "RenderbufferStorage",
                                        "RenderbufferStorageMultisample",
                                        "FramebufferTexture1D",
                                        "FramebufferTexture2D",
                                        "FramebufferTexture3D",
                                        "FramebufferTextureLayer",
                                        "FramebufferRenderbuffer"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!strcmp(names[i], name))
            return 1;
    return 0;
}

/* GL_FRAMEBUFFER binds both; any other target is GL's error and the
 * bindings stay. */
static void note_binding(tilesort *t, GLenum target, GLuint framebuffer)
{
    if (target == GL_FRAMEBUFFER_EXT || target == GL_DRAW_FRAMEBUFFER) {
        t->app_fb = framebuffer;
        if (framebuffer)
            ts_queries_fbo_bound(t);
    }
    if (target == GL_FRAMEBUFFER_EXT || target == GL_READ_FRAMEBUFFER)
        t->app_read_fb = framebuffer;
}

void ts_BindFramebufferEXT(void *self, GLenum target, GLuint framebuffer)
{
    tilesort *t = self;
    to_every_server_begin(t);
    tsr_call_BindFramebufferEXT(&t->geo_table, target, framebuffer);
    to_every_server_end(t);
    note_binding(t, target, framebuffer);
}

void ts_BindFramebuffer(void *self, GLenum target, GLuint framebuffer)
{
    tilesort *t = self;
    to_every_server_begin(t);
    tsr_call_BindFramebuffer(&t->geo_table, target, framebuffer);
    to_every_server_end(t);
    note_binding(t, target, framebuffer);
}

/* Deleting a bound FBO binds 0, the window, in its place. */
static void note_deleted(tilesort *t, GLsizei n, const GLuint *framebuffers)
{
    for (GLsizei i = 0; i < n && framebuffers; i++) {
        if (framebuffers[i] && framebuffers[i] == t->app_fb)
            t->app_fb = 0;
        if (framebuffers[i] && framebuffers[i] == t->app_read_fb)
            t->app_read_fb = 0;
    }
}

void ts_DeleteFramebuffersEXT(void *self, GLsizei n, const GLuint *framebuffers)
{
    tilesort *t = self;
    to_every_server_begin(t);
    tsr_call_DeleteFramebuffersEXT(&t->geo_table, n, framebuffers);
    to_every_server_end(t);
    note_deleted(t, n, framebuffers);
}

void ts_DeleteFramebuffers(void *self, GLsizei n, const GLuint *framebuffers)
{
    tilesort *t = self;
    to_every_server_begin(t);
    tsr_call_DeleteFramebuffers(&t->geo_table, n, framebuffers);
    to_every_server_end(t);
    note_deleted(t, n, framebuffers);
}

/* The texture object a glFramebufferTexture*EXT names, on every live
 * server before the call (a diff gives a server only the textures bound
 * when it is sent: the program may have unbound it since). It goes into
 * each server's own packer, which its diff follows before the call. */
void ts_fbo_send_texture(tilesort *t, GLenum textarget, GLuint texture)
{
    GLenum target = textarget >= GL_TEXTURE_CUBE_MAP_POSITIVE_X && textarget <= GL_TEXTURE_CUBE_MAP_NEGATIVE_Z
                        ? (GLenum)GL_TEXTURE_CUBE_MAP
                        : textarget;
    if (!texture)
        return;
    for (size_t i = 0; i < t->nservers; i++)
        if (!tsr_stream_client_server_failed(t->client, i))
            tsr_state_send_texture(t->ctx, t->srv[i].shadow, target, texture, &t->srv[i].table);
}

/* glFramebufferTexture1D/2D(EXT) and 3D: the texture, then the call, to
 * every live server after its diff (`call` is the command the program
 * made, in the EXT or the core name). */
typedef void (*attach_2d_fn)(const tsr_dispatch *d, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                             GLint level);
typedef void (*attach_3d_fn)(const tsr_dispatch *d, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                             GLint level, GLint zoffset);

static void attach(tilesort *t, attach_2d_fn call, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                   GLint level)
{
    to_every_server_begin(t);
    ts_fbo_send_texture(t, textarget, texture);
    call(&t->geo_table, target, attachment, textarget, texture, level);
    to_every_server_end(t);
}

static void attach_3d(tilesort *t, attach_3d_fn call, GLenum target, GLenum attachment, GLenum textarget,
                      GLuint texture, GLint level, GLint zoffset)
{
    to_every_server_begin(t);
    ts_fbo_send_texture(t, textarget, texture);
    call(&t->geo_table, target, attachment, textarget, texture, level, zoffset);
    to_every_server_end(t);
}

void ts_FramebufferTexture1DEXT(void *self, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                                GLint level)
{
    attach(self, tsr_call_FramebufferTexture1DEXT, target, attachment, textarget, texture, level);
}

void ts_FramebufferTexture2DEXT(void *self, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                                GLint level)
{
    attach(self, tsr_call_FramebufferTexture2DEXT, target, attachment, textarget, texture, level);
}

void ts_FramebufferTexture3DEXT(void *self, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                                GLint level, GLint zoffset)
{
    attach_3d(self, tsr_call_FramebufferTexture3DEXT, target, attachment, textarget, texture, level, zoffset);
}

void ts_FramebufferTexture1D(void *self, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                             GLint level)
{
    attach(self, tsr_call_FramebufferTexture1D, target, attachment, textarget, texture, level);
}

void ts_FramebufferTexture2D(void *self, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                             GLint level)
{
    attach(self, tsr_call_FramebufferTexture2D, target, attachment, textarget, texture, level);
}

void ts_FramebufferTexture3D(void *self, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                             GLint level, GLint zoffset)
{
    attach_3d(self, tsr_call_FramebufferTexture3D, target, attachment, textarget, texture, level, zoffset);
}

/* A layer of a 3D texture (the one layered target the tracker keeps; the
 * array targets are not offered). */
void ts_FramebufferTextureLayer(void *self, GLenum target, GLenum attachment, GLuint texture, GLint level, GLint layer)
{
    tilesort *t = self;
    to_every_server_begin(t);
    ts_fbo_send_texture(t, GL_TEXTURE_3D, texture);
    tsr_call_FramebufferTextureLayer(&t->geo_table, target, attachment, texture, level, layer);
    to_every_server_end(t);
}

/* glGenerateMipmap(EXT) is tracked (an upload of the texture, so its
 * level gets ask a server, which made the levels) and every live server
 * is given it at once: its levels come from what level 0 holds now, which
 * an FBO may draw into again before the servers' next diff. */
static void generate_mipmap(tilesort *t, GLenum target)
{
    if (target != GL_TEXTURE_1D && target != GL_TEXTURE_2D && target != GL_TEXTURE_3D &&
        target != GL_TEXTURE_CUBE_MAP) { /* the tracker takes no such target: the servers raise GL's error */
        to_every_server_begin(t);
        tsr_call_GenerateMipmapEXT(&t->geo_table, target);
        to_every_server_end(t);
        return;
    }
    ts_flush_before_state(t);
    tsr_call_GenerateMipmap(&t->track_table, target);
    for (size_t i = 0; i < t->nservers; i++)
        if (!tsr_stream_client_server_failed(t->client, i))
            ts_prepare_server(t, &t->srv[i], 0);
    if (!tsr_packer_pending(t->geo))
        ts_snapshot(t);
}

void ts_GenerateMipmapEXT(void *self, GLenum target) { generate_mipmap(self, target); }
void ts_GenerateMipmap(void *self, GLenum target) { generate_mipmap(self, target); }

/* --- the draw and read buffers: the framebuffer's ------------------------- */

void ts_DrawBuffer(void *self, GLenum buf)
{
    tilesort *t = self;
    if (t->app_fb) {
        to_every_server_begin(t);
        tsr_call_DrawBuffer(&t->geo_table, buf);
        to_every_server_end(t);
        return;
    }
    ts_flush_before_state(t);
    tsr_call_DrawBuffer(&t->track_table, buf);
    if (!tsr_packer_pending(t->geo))
        ts_snapshot(t);
}

void ts_DrawBuffers(void *self, GLsizei n, const GLenum *bufs)
{
    tilesort *t = self;
    if (t->app_fb) {
        to_every_server_begin(t);
        tsr_call_DrawBuffers(&t->geo_table, n, bufs);
        to_every_server_end(t);
        return;
    }
    ts_flush_before_state(t);
    tsr_call_DrawBuffers(&t->track_table, n, bufs);
    if (!tsr_packer_pending(t->geo))
        ts_snapshot(t);
}

void ts_ReadBuffer(void *self, GLenum buf)
{
    tilesort *t = self;
    if (t->app_read_fb) {
        to_every_server_begin(t);
        tsr_call_ReadBuffer(&t->geo_table, buf);
        to_every_server_end(t);
        return;
    }
    ts_flush_before_state(t);
    tsr_call_ReadBuffer(&t->track_table, buf);
    if (!tsr_packer_pending(t->geo))
        ts_snapshot(t);
}

int ts_fbo_get_asks_server(const tilesort *t, GLenum pname)
{
    if (pname == GL_READ_BUFFER)
        return t->app_read_fb != 0;
    return t->app_fb && (pname == GL_DRAW_BUFFER || (pname >= GL_DRAW_BUFFER0 && pname <= GL_DRAW_BUFFER15));
}
