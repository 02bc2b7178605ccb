/* core/state/glsl_names.c — stream <-> driver names of shaders and programs
 * (tessera/glsl_names.h). */
#include "tessera/glsl_names.h"

#include <stdint.h>
#include <stdlib.h>

#include "util/map.h"

/* Never handed out by a driver in practice: an unknown stream name becomes
 * this, so GL answers as for any unknown name. */
#define UNKNOWN_NAME 0xFFFFFFFFu

struct tsr_glsl_names {
    tsr_dispatch drv;       /* the slots as they were (the driver, or whatever was there) */
    tsr_name_map to_drv;    /* stream name -> (void *)driver name */
    tsr_name_map to_stream; /* driver name -> (void *)stream name */
};

static GLuint drv_of(const tsr_glsl_names *m, GLuint name)
{
    if (!name)
        return 0;
    void *d = tsr_name_map_get(&m->to_drv, name);
    return d ? (GLuint)(uintptr_t)d : UNKNOWN_NAME;
}

GLuint tsr_glsl_names_driver(const tsr_glsl_names *m, GLuint name) { return drv_of(m, name); }

/* Stream name `name` is driver name `d` from now on. A stale stream name
 * still pointing at `d` (its object is gone: the driver gave `d` out
 * again) and an old object under `name` are forgotten. */
static void bind_names(tsr_glsl_names *m, GLuint name, GLuint d)
{
    void *old = tsr_name_map_del(&m->to_stream, d);
    if (old)
        tsr_name_map_del(&m->to_drv, (GLuint)(uintptr_t)old);
    void *was = tsr_name_map_del(&m->to_drv, name);
    if (was)
        tsr_name_map_del(&m->to_stream, (GLuint)(uintptr_t)was);
    if (tsr_name_map_put(&m->to_drv, name, (void *)(uintptr_t)d) != 0 ||
        tsr_name_map_put(&m->to_stream, d, (void *)(uintptr_t)name) != 0)
        tsr_name_map_del(&m->to_drv, name); /* out of memory: the name stays unknown */
}

/* A driver-made object's stream name: the driver's own when free. */
static GLuint adopt(tsr_glsl_names *m, GLuint d)
{
    if (!d)
        return 0;
    GLuint name = d;
    void *v = tsr_name_map_get(&m->to_drv, d);
    if (v && (GLuint)(uintptr_t)v != d) { /* the stream already uses d for another object */
        name = m->to_drv.max_key + 1;
        while (!name || tsr_name_map_get(&m->to_drv, name))
            name++;
    }
    bind_names(m, name, d);
    return name;
}

static GLuint n_CreateShader(void *self, GLenum type)
{
    tsr_glsl_names *m = self;
    return adopt(m, tsr_call_CreateShader(&m->drv, type));
}

static GLuint n_CreateProgram(void *self)
{
    tsr_glsl_names *m = self;
    return adopt(m, tsr_call_CreateProgram(&m->drv));
}

static void n_CreateShaderTSR(void *self, GLuint shader, GLenum type)
{
    tsr_glsl_names *m = self;
    GLuint d = tsr_call_CreateShader(&m->drv, type);
    if (shader && d)
        bind_names(m, shader, d);
}

static void n_CreateProgramTSR(void *self, GLuint program)
{
    tsr_glsl_names *m = self;
    GLuint d = tsr_call_CreateProgram(&m->drv);
    if (program && d)
        bind_names(m, program, d);
}

#define M tsr_glsl_names *m = self
static void n_DeleteShader(void *self, GLuint s)
{
    M;
    tsr_call_DeleteShader(&m->drv, drv_of(m, s));
}
static void n_ShaderSource(void *self, GLuint s, GLsizei n, const GLchar *const *str, const GLint *len)
{
    M;
    tsr_call_ShaderSource(&m->drv, drv_of(m, s), n, str, len);
}
static void n_CompileShader(void *self, GLuint s)
{
    M;
    tsr_call_CompileShader(&m->drv, drv_of(m, s));
}
static void n_DeleteProgram(void *self, GLuint p)
{
    M;
    tsr_call_DeleteProgram(&m->drv, drv_of(m, p));
}
static void n_AttachShader(void *self, GLuint p, GLuint s)
{
    M;
    tsr_call_AttachShader(&m->drv, drv_of(m, p), drv_of(m, s));
}
static void n_DetachShader(void *self, GLuint p, GLuint s)
{
    M;
    tsr_call_DetachShader(&m->drv, drv_of(m, p), drv_of(m, s));
}
static void n_LinkProgram(void *self, GLuint p)
{
    M;
    tsr_call_LinkProgram(&m->drv, drv_of(m, p));
}
static void n_BindAttribLocation(void *self, GLuint p, GLuint i, const GLchar *name)
{
    M;
    tsr_call_BindAttribLocation(&m->drv, drv_of(m, p), i, name);
}
static void n_ValidateProgram(void *self, GLuint p)
{
    M;
    tsr_call_ValidateProgram(&m->drv, drv_of(m, p));
}
static void n_UseProgram(void *self, GLuint p)
{
    M;
    tsr_call_UseProgram(&m->drv, drv_of(m, p));
}
static void n_GetShaderiv(void *self, GLuint s, GLenum pname, GLint *out)
{
    M;
    tsr_call_GetShaderiv(&m->drv, drv_of(m, s), pname, out);
}
static void n_GetProgramiv(void *self, GLuint p, GLenum pname, GLint *out)
{
    M;
    tsr_call_GetProgramiv(&m->drv, drv_of(m, p), pname, out);
}
static void n_GetShaderInfoLog(void *self, GLuint s, GLsizei size, GLsizei *len, GLchar *log)
{
    M;
    tsr_call_GetShaderInfoLog(&m->drv, drv_of(m, s), size, len, log);
}
static void n_GetProgramInfoLog(void *self, GLuint p, GLsizei size, GLsizei *len, GLchar *log)
{
    M;
    tsr_call_GetProgramInfoLog(&m->drv, drv_of(m, p), size, len, log);
}
static GLint n_GetUniformLocation(void *self, GLuint p, const GLchar *name)
{
    M;
    return tsr_call_GetUniformLocation(&m->drv, drv_of(m, p), name);
}
static void n_GetUniformfv(void *self, GLuint p, GLint location, GLfloat *out)
{
    M;
    tsr_call_GetUniformfv(&m->drv, drv_of(m, p), location, out);
}
static void n_GetUniformiv(void *self, GLuint p, GLint location, GLint *out)
{
    M;
    tsr_call_GetUniformiv(&m->drv, drv_of(m, p), location, out);
}
static GLint n_GetAttribLocation(void *self, GLuint p, const GLchar *name)
{
    M;
    return tsr_call_GetAttribLocation(&m->drv, drv_of(m, p), name);
}

/* glGet of GL_CURRENT_PROGRAM answers with the stream's name. */
static GLuint stream_of(const tsr_glsl_names *m, GLuint d)
{
    void *s = d ? tsr_name_map_get(&m->to_stream, d) : NULL;
    return s ? (GLuint)(uintptr_t)s : d;
}
static void n_GetIntegerv(void *self, GLenum pname, GLint *out)
{
    M;
    tsr_call_GetIntegerv(&m->drv, pname, out);
    if (pname == GL_CURRENT_PROGRAM)
        out[0] = (GLint)stream_of(m, (GLuint)out[0]);
}
static void n_GetFloatv(void *self, GLenum pname, GLfloat *out)
{
    M;
    tsr_call_GetFloatv(&m->drv, pname, out);
    if (pname == GL_CURRENT_PROGRAM)
        out[0] = (GLfloat)stream_of(m, (GLuint)out[0]);
}
static void n_GetDoublev(void *self, GLenum pname, GLdouble *out)
{
    M;
    tsr_call_GetDoublev(&m->drv, pname, out);
    if (pname == GL_CURRENT_PROGRAM)
        out[0] = (GLdouble)stream_of(m, (GLuint)out[0]);
}
static void n_GetActiveAttrib(void *self, GLuint p, GLuint i, GLsizei size, GLsizei *len, GLint *n, GLenum *type,
                              GLchar *name)
{
    M;
    tsr_call_GetActiveAttrib(&m->drv, drv_of(m, p), i, size, len, n, type, name);
}
static void n_GetActiveUniform(void *self, GLuint p, GLuint i, GLsizei size, GLsizei *len, GLint *n, GLenum *type,
                               GLchar *name)
{
    M;
    tsr_call_GetActiveUniform(&m->drv, drv_of(m, p), i, size, len, n, type, name);
}
static void n_GetShaderSource(void *self, GLuint s, GLsizei size, GLsizei *len, GLchar *src)
{
    M;
    tsr_call_GetShaderSource(&m->drv, drv_of(m, s), size, len, src);
}
static GLboolean n_IsShader(void *self, GLuint s)
{
    M;
    return s ? tsr_call_IsShader(&m->drv, drv_of(m, s)) : GL_FALSE;
}
static GLboolean n_IsProgram(void *self, GLuint p)
{
    M;
    return p ? tsr_call_IsProgram(&m->drv, drv_of(m, p)) : GL_FALSE;
}
/* The driver's names of the attached shaders go back as the stream's. */
static void n_GetAttachedShaders(void *self, GLuint p, GLsizei max, GLsizei *count, GLuint *shaders)
{
    M;
    GLsizei n = 0;
    tsr_call_GetAttachedShaders(&m->drv, drv_of(m, p), max, &n, shaders);
    for (GLsizei i = 0; shaders && i < n && i < max; i++)
        shaders[i] = stream_of(m, shaders[i]);
    if (count)
        *count = n;
}
#undef M

tsr_glsl_names *tsr_glsl_names_create(tsr_dispatch *table, tsr_error *err)
{
    tsr_glsl_names *m = calloc(1, sizeof *m);
    if (!m) {
        tsr_error_set(err, TSR_ENOMEM, "out of memory (shader name map)");
        return NULL;
    }
    m->drv = *table;
#define SET(name) tsr_set_##name(table, n_##name, m)
    SET(CreateShader);
    SET(CreateProgram);
    SET(CreateShaderTSR);
    SET(CreateProgramTSR);
    SET(DeleteShader);
    SET(ShaderSource);
    SET(CompileShader);
    SET(DeleteProgram);
    SET(AttachShader);
    SET(DetachShader);
    SET(LinkProgram);
    SET(BindAttribLocation);
    SET(ValidateProgram);
    SET(UseProgram);
    SET(GetShaderiv);
    SET(GetProgramiv);
    SET(GetShaderInfoLog);
    SET(GetProgramInfoLog);
    SET(GetUniformLocation);
    SET(GetUniformfv);
    SET(GetUniformiv);
    SET(GetAttribLocation);
    SET(GetIntegerv);
    SET(GetFloatv);
    SET(GetDoublev);
    SET(GetActiveAttrib);
    SET(GetActiveUniform);
    SET(GetShaderSource);
    SET(IsShader);
    SET(IsProgram);
    SET(GetAttachedShaders);
#undef SET
    return m;
}

void tsr_glsl_names_destroy(tsr_glsl_names *m)
{
    if (!m)
        return;
    tsr_name_map_free(&m->to_drv);
    tsr_name_map_free(&m->to_stream);
    free(m);
}
