/* spus/tilesort/gets.c — gets: answered by the tracker where the value
 * is client-known, otherwise by the first live server. (Commands with
 * output the tracker does not implement reach that server through
 * tilesort.c's R_SERVER route; glReadPixels is gathered, frame.c.) Also
 * glGetError, gathered from every place an error is made, and proxy
 * texture images, which only change what that server answers.
 *
 * Owns nothing. Never asks a server before it has the tracker's state (its
 * diff, and the shader or program asked about): it would answer for state
 * the application has already left. */
#include "instance.h"

#define ANSWER_OR_ASK(getter, call)     \
    do {                                \
        tilesort *t = self;             \
        if (getter)                     \
            return;                     \
        ts_server *s = ts_to_server(t); \
        call;                           \
    } while (0)

void ts_GetBooleanv(void *self, GLenum p, GLboolean *o)
{
    ANSWER_OR_ASK(!ts_fbo_get_asks_server(t, p) && tsr_state_get_booleanv(t->ctx, p, o),
                  tsr_call_GetBooleanv(&s->table, p, o));
}
void ts_GetIntegerv(void *self, GLenum p, GLint *o)
{
    ANSWER_OR_ASK(!ts_fbo_get_asks_server(t, p) && tsr_state_get_integerv(t->ctx, p, o),
                  tsr_call_GetIntegerv(&s->table, p, o));
}
void ts_GetFloatv(void *self, GLenum p, GLfloat *o)
{
    ANSWER_OR_ASK(!ts_fbo_get_asks_server(t, p) && tsr_state_get_floatv(t->ctx, p, o),
                  tsr_call_GetFloatv(&s->table, p, o));
}
void ts_GetDoublev(void *self, GLenum p, GLdouble *o)
{
    ANSWER_OR_ASK(!ts_fbo_get_asks_server(t, p) && tsr_state_get_doublev(t->ctx, p, o),
                  tsr_call_GetDoublev(&s->table, p, o));
}
void ts_GetLightfv(void *self, GLenum l, GLenum p, GLfloat *o)
{
    ANSWER_OR_ASK(tsr_state_get_lightfv(t->ctx, l, p, o), tsr_call_GetLightfv(&s->table, l, p, o));
}
void ts_GetMaterialfv(void *self, GLenum f, GLenum p, GLfloat *o)
{
    tilesort *pending = self;
    /* materials still in the geometry buffer reach the tracker when it is
     * sent (send.c): send it first, as a state change would */
    if (!pending->in_begin && pending->nmaterials)
        ts_flush_before_state(pending);
    ANSWER_OR_ASK(tsr_state_get_materialfv(t->ctx, f, p, o), tsr_call_GetMaterialfv(&s->table, f, p, o));
}
void ts_GetTexEnvfv(void *self, GLenum tg, GLenum p, GLfloat *o)
{
    ANSWER_OR_ASK(tsr_state_get_tex_envfv(t->ctx, tg, p, o), tsr_call_GetTexEnvfv(&s->table, tg, p, o));
}
void ts_GetTexGenfv(void *self, GLenum c, GLenum p, GLfloat *o)
{
    ANSWER_OR_ASK(tsr_state_get_tex_genfv(t->ctx, c, p, o), tsr_call_GetTexGenfv(&s->table, c, p, o));
}
void ts_GetTexParameterfv(void *self, GLenum tg, GLenum p, GLfloat *o)
{
    ANSWER_OR_ASK(tsr_state_get_tex_parameterfv(t->ctx, tg, p, o), tsr_call_GetTexParameterfv(&s->table, tg, p, o));
}
void ts_GetTexParameterIivEXT(void *self, GLenum tg, GLenum p, GLint *o)
{
    ANSWER_OR_ASK(tsr_state_get_tex_parameter_int(t->ctx, tg, p, GL_INT, o),
                  tsr_call_GetTexParameterIivEXT(&s->table, tg, p, o));
}
void ts_GetTexParameterIuivEXT(void *self, GLenum tg, GLenum p, GLuint *o)
{
    ANSWER_OR_ASK(tsr_state_get_tex_parameter_int(t->ctx, tg, p, GL_UNSIGNED_INT, (GLint *)o),
                  tsr_call_GetTexParameterIuivEXT(&s->table, tg, p, o));
}
void ts_GetTexLevelParameteriv(void *self, GLenum tg, GLint lv, GLenum p, GLint *o)
{
    ANSWER_OR_ASK(tsr_state_get_tex_level_parameteriv(t->ctx, tg, lv, p, o),
                  tsr_call_GetTexLevelParameteriv(&s->table, tg, lv, p, o));
}
void ts_GetClipPlane(void *self, GLenum p, GLdouble *o)
{
    ANSWER_OR_ASK(tsr_state_get_clip_plane(t->ctx, p, o), tsr_call_GetClipPlane(&s->table, p, o));
}
void ts_GetPolygonStipple(void *self, GLubyte *o)
{
    if (ts_pack_buffer_stipple(self, o))
        return; /* `o` is an offset in the program's pack buffer */
    ANSWER_OR_ASK(tsr_state_get_polygon_stipple(t->ctx, o), tsr_call_GetPolygonStipple(&s->table, o));
}
void ts_GetBufferParameteriv(void *self, GLenum tg, GLenum p, GLint *o)
{
    ANSWER_OR_ASK(tsr_state_get_buffer_parameteriv(t->ctx, tg, p, o),
                  tsr_call_GetBufferParameteriv(&s->table, tg, p, o));
}
GLboolean ts_IsEnabled(void *self, GLenum cap)
{
    tilesort *t = self;
    GLboolean b = GL_FALSE;
    if (tsr_state_is_enabled(t->ctx, cap, &b))
        return b;
    return tsr_call_IsEnabled(&ts_to_server(t)->table, cap);
}

void ts_gl_error(tilesort *t, GLenum error)
{
    if (!t->gl_error)
        t->gl_error = error;
}

/* glGetError: what one GL would answer, from the errors held in many
 * places (docs/walls.md, "GL errors"). Inside glBegin/glEnd it is itself
 * GL_INVALID_OPERATION and answers 0 (GL 2.1 section 2.6.3; the servers
 * are not inside a primitive, the geometry buffer is). Otherwise the
 * first error of: those made here (a glEnd outside glBegin, a glNewList
 * GL refuses), the tracker's (a state call it refuses, never sent), the
 * geometry packer's (a pixel command GL refuses before reading a pixel,
 * tsr_pixel_image_error), then every live server's in server order (each
 * after its packer's own, an unknown pname); every one is taken, so the
 * next call starts clean as GL's one error flag does. A command sent to
 * every server raises its error on each; one sent to some (geometry
 * sorted by tile) on those, and the first of them answers. */
GLenum ts_GetError(void *self)
{
    tilesort *t = self;
    if (t->in_begin) {
        ts_gl_error(t, GL_INVALID_OPERATION);
        return GL_NO_ERROR;
    }
    GLenum e = t->gl_error;
    t->gl_error = GL_NO_ERROR;
    GLenum tracked = tsr_state_take_error(t->ctx);
    GLenum packed = tsr_packer_take_local_error(t->geo);
    if (!e)
        e = tracked ? tracked : packed;
    ts_flush_geometry(t);
    for (size_t i = 0; i < t->nservers; i++) {
        if (tsr_stream_client_server_failed(t->client, i))
            continue;
        ts_server *s = &t->srv[i];
        ts_prepare_server(t, s, 0);
        GLenum server = tsr_call_GetError(&s->table);
        if (!e)
            e = server;
    }
    return e;
}

/* Shader and program gets: what the tracker knows, else the first live
 * server after it has been given the object (compile/link status, info
 * logs, locations: the same link inputs give the same answers on every
 * server, tests/state glsl_*). */
static ts_server *glsl_server(tilesort *t, GLuint name, int program)
{
    ts_server *s = ts_to_server(t);
    if (program)
        tsr_state_send_program(t->ctx, s->shadow, name, &s->table);
    else
        tsr_state_send_shader(t->ctx, s->shadow, name, &s->table);
    return s;
}

void ts_GetShaderiv(void *self, GLuint shader, GLenum pname, GLint *out)
{
    tilesort *t = self;
    if (!tsr_state_get_shaderiv(t->ctx, shader, pname, out))
        tsr_call_GetShaderiv(&glsl_server(t, shader, 0)->table, shader, pname, out);
}

void ts_GetProgramiv(void *self, GLuint program, GLenum pname, GLint *out)
{
    tilesort *t = self;
    if (!tsr_state_get_programiv(t->ctx, program, pname, out))
        tsr_call_GetProgramiv(&glsl_server(t, program, 1)->table, program, pname, out);
}

void ts_GetShaderInfoLog(void *self, GLuint shader, GLsizei size, GLsizei *length, GLchar *log)
{
    tsr_call_GetShaderInfoLog(&glsl_server(self, shader, 0)->table, shader, size, length, log);
}

void ts_GetProgramInfoLog(void *self, GLuint program, GLsizei size, GLsizei *length, GLchar *log)
{
    tsr_call_GetProgramInfoLog(&glsl_server(self, program, 1)->table, program, size, length, log);
}

GLint ts_GetUniformLocation(void *self, GLuint program, const GLchar *name)
{
    return tsr_call_GetUniformLocation(&glsl_server(self, program, 1)->table, program, name);
}

void ts_GetUniformfv(void *self, GLuint program, GLint location, GLfloat *out)
{
    tsr_call_GetUniformfv(&glsl_server(self, program, 1)->table, program, location, out);
}

void ts_GetUniformiv(void *self, GLuint program, GLint location, GLint *out)
{
    tsr_call_GetUniformiv(&glsl_server(self, program, 1)->table, program, location, out);
}

GLint ts_GetAttribLocation(void *self, GLuint program, const GLchar *name)
{
    return tsr_call_GetAttribLocation(&glsl_server(self, program, 1)->table, program, name);
}

void ts_GetActiveAttrib(void *self, GLuint program, GLuint index, GLsizei size, GLsizei *length, GLint *n, GLenum *type,
                        GLchar *name)
{
    tsr_call_GetActiveAttrib(&glsl_server(self, program, 1)->table, program, index, size, length, n, type, name);
}

void ts_GetActiveUniform(void *self, GLuint program, GLuint index, GLsizei size, GLsizei *length, GLint *n,
                         GLenum *type, GLchar *name)
{
    tsr_call_GetActiveUniform(&glsl_server(self, program, 1)->table, program, index, size, length, n, type, name);
}

void ts_GetAttachedShaders(void *self, GLuint program, GLsizei max, GLsizei *count, GLuint *shaders)
{
    tsr_call_GetAttachedShaders(&glsl_server(self, program, 1)->table, program, max, count, shaders);
}

void ts_GetShaderSource(void *self, GLuint shader, GLsizei size, GLsizei *length, GLchar *source)
{
    tsr_call_GetShaderSource(&glsl_server(self, shader, 0)->table, shader, size, length, source);
}

/* A server that was never given the object would say GL_FALSE. */
GLboolean ts_IsShader(void *self, GLuint shader)
{
    return tsr_call_IsShader(&glsl_server(self, shader, 0)->table, shader);
}

GLboolean ts_IsProgram(void *self, GLuint program)
{
    return tsr_call_IsProgram(&glsl_server(self, program, 1)->table, program);
}

/* Proxy textures: glTexImage* of a proxy target changes only what
 * glGetTexLevelParameteriv of that target answers (GL 2.1 section 3.8.1),
 * and the first live server answers that (the tracker keeps no proxy), so
 * the call goes to it alone, with its GL errors (piglit's proxy-texture).
 * Other targets take the state route (the tracker). */
static int is_proxy(GLenum target)
{
    return target == GL_PROXY_TEXTURE_1D || target == GL_PROXY_TEXTURE_2D || target == GL_PROXY_TEXTURE_3D ||
           target == GL_PROXY_TEXTURE_CUBE_MAP || target == GL_PROXY_TEXTURE_RECTANGLE_ARB;
}

/* The tracker refuses a texture image past the servers' limits as GL does
 * (it would keep it and send it again with every later state), and
 * glActiveTexture of a unit past their image units: the first live server
 * tells them, once, at the first image or the first unit past the
 * coordinate units. */
static void learn_texture_limits(tilesort *t)
{
    if (t->texture_limits_known)
        return;
    const tsr_dispatch *to = &ts_to_server(t)->table;
    GLint max_size = 0, max_3d_size = 0, max_cube_size = 0, image_units = 0;
    tsr_call_GetIntegerv(to, GL_MAX_TEXTURE_SIZE, &max_size);
    tsr_call_GetIntegerv(to, GL_MAX_3D_TEXTURE_SIZE, &max_3d_size);
    tsr_call_GetIntegerv(to, GL_MAX_CUBE_MAP_TEXTURE_SIZE, &max_cube_size);
    tsr_call_GetIntegerv(to, GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &image_units);
    tsr_state_tracker_set_texture_limits(t->tracker, max_size, max_3d_size, max_cube_size);
    tsr_state_tracker_set_image_units(t->tracker, image_units);
    t->texture_limits_known = true;
}

/* glActiveTexture takes the state route (the tracker holds every image
 * unit: core/state), once the servers' count of units is known. */
void ts_ActiveTexture(void *self, GLenum texture)
{
    tilesort *t = self;
    if (texture - GL_TEXTURE0 >= TSR_STATE_UNITS)
        learn_texture_limits(t);
    ts_flush_before_state(t);
    tsr_call_ActiveTexture(&t->track_table, texture);
    if (!tsr_packer_pending(t->geo))
        ts_snapshot(t);
}

#define PROXY_OR_TRACKED(call)                                \
    do {                                                      \
        tilesort *t = self;                                   \
        if (is_proxy(target)) {                               \
            const tsr_dispatch *to = &ts_to_server(t)->table; \
            call;                                             \
            return;                                           \
        }                                                     \
        learn_texture_limits(t);                              \
        ts_flush_before_state(t);                             \
        const tsr_dispatch *to = &t->track_table;             \
        call;                                                 \
        if (!tsr_packer_pending(t->geo))                      \
            ts_snapshot(t);                                   \
    } while (0)

void ts_TexImage1D(void *self, GLenum target, GLint level, GLint internalformat, GLsizei width, GLint border,
                   GLenum format, GLenum type, const void *pixels)
{
    PROXY_OR_TRACKED(tsr_call_TexImage1D(to, target, level, internalformat, width, border, format, type, pixels));
}

void ts_TexImage2D(void *self, GLenum target, GLint level, GLint internalformat, GLsizei width, GLsizei height,
                   GLint border, GLenum format, GLenum type, const void *pixels)
{
    PROXY_OR_TRACKED(
        tsr_call_TexImage2D(to, target, level, internalformat, width, height, border, format, type, pixels));
}

void ts_TexImage3D(void *self, GLenum target, GLint level, GLint internalformat, GLsizei width, GLsizei height,
                   GLsizei depth, GLint border, GLenum format, GLenum type, const void *pixels)
{
    PROXY_OR_TRACKED(
        tsr_call_TexImage3D(to, target, level, internalformat, width, height, depth, border, format, type, pixels));
}

/* glRenderMode. Selection and feedback are not sorted: every server
 * renders with the program's whole-window viewport and projection and only
 * scissors its drawing to its tiles (TilesTSR), and neither selection nor
 * feedback depends on the scissor (hits and feedback vertices are taken
 * after clipping to the view volume, before any fragment). So the first
 * live server, which got glSelectBuffer/glFeedbackBuffer (R_SERVER), runs
 * the whole pass alone: every geometry buffer, list call and frame command
 * goes to it only, array draws are not sorted and primitives are not cut
 * (choose_targets, draw_sorted, ts_geo_sink_flush), and its records are
 * exactly GL's. Merging records from several servers instead would need
 * each hit record's name stack matched across servers (the same names may
 * be loaded twice) and feedback records put back in program order, and
 * the others would draw the pass's primitives as pixels: in selection and
 * feedback modes GL draws nothing. The mode is what the server reports
 * (a glRenderMode(GL_SELECT) GL refuses leaves GL_RENDER). The other
 * servers stay in GL_RENDER and get the state they lack in their next
 * diff; the name stack needs no tracking: GL empties it when a selection
 * pass ends and ignores it outside one. */
GLint ts_RenderMode(void *self, GLenum mode)
{
    tilesort *t = self;
    ts_server *s = ts_to_server(t);
    GLint r = tsr_call_RenderMode(&s->table, mode);
    t->render_mode = tsr_packer_render_mode(s->packer);
    t->render_server = s->index;
    return r;
}
