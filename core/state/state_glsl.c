/* core/state/state_glsl.c — shaders and programs in the state tracker (state.h
 * says what is kept and why). Setters follow GL 2.1: a call GL rejects for
 * a reason the client can see (unknown name, bad enum, negative count)
 * changes nothing. Names are allocated here (one namespace for shaders
 * and programs, max used + 1, never reused: a deleted shader a link still
 * refers to keeps its name on the renderers that got it), so glCreate*
 * need no round trip.
 *
 * Renderers get objects through CreateShaderTSR/CreateProgramTSR under
 * these names (tessera/glsl_names.h maps them to the driver's). What a
 * renderer holds is modelled per shadow (st_shadow_shader/_program: source
 * ids, link id, the last uniform call it got, its attachments), so
 * sending is idempotent and only the missing part is emitted. */
#include "state_internal.h"

#include <stdlib.h>
#include <string.h>

/* Uniform and UseProgram calls are compiled into lists (st_exec_ctx); the
 * object calls run at once even while compiling (GL 2.1 section 5.4). */

/* Mesa's GL_MAX_VERTEX_ATTRIBS. */
#define MAX_ATTRIBS 16

/* --- sources --------------------------------------------------------------- */
static st_source *src_make(tsr_state_ctx *c, GLsizei count, const GLchar *const *str, const GLint *len)
{
    size_t total = 0;
    for (GLsizei i = 0; i < count; i++)
        total += len && len[i] >= 0 ? (size_t)len[i] : strlen(str[i]);
    if (total > 0x7fffffff)
        return NULL;
    st_source *s = malloc(sizeof *s + total + 1);
    if (!s)
        return NULL;
    s->refs = 1;
    s->id = c->t->next_uid++;
    s->len = (GLint)total;
    size_t at = 0;
    for (GLsizei i = 0; i < count; i++) {
        size_t n = len && len[i] >= 0 ? (size_t)len[i] : strlen(str[i]);
        memcpy(s->text + at, str[i], n);
        at += n;
    }
    s->text[total] = 0;
    return s;
}

static st_source *src_ref(st_source *s)
{
    if (s)
        s->refs++;
    return s;
}

static void src_unref(st_source *s)
{
    if (s && --s->refs == 0)
        free(s);
}

/* --- objects --------------------------------------------------------------- */
static void mark(tsr_state_ctx *c) { st_mark(c, TSR_SM_PROGRAM); }

static GLuint new_name(const tsr_state_ctx *c)
{
    GLuint a = c->shaders.max_key, b = c->programs.max_key;
    return (a > b ? a : b) + 1;
}

static int name_used(const tsr_state_ctx *c, GLuint name)
{
    return tsr_name_map_get(&c->shaders, name) || tsr_name_map_get(&c->programs, name);
}

static st_shader *shader_new(tsr_state_ctx *c, GLuint name, GLenum type)
{
    if (!name || (type != GL_VERTEX_SHADER && type != GL_FRAGMENT_SHADER) || name_used(c, name))
        return NULL;
    st_shader *o = calloc(1, sizeof *o);
    if (!o)
        return NULL;
    o->name = name;
    o->type = type;
    if (tsr_name_map_put(&c->shaders, name, o) != 0) {
        free(o);
        return NULL;
    }
    mark(c);
    return o;
}

static void shader_free(st_shader *o)
{
    src_unref(o->source);
    src_unref(o->compiled);
    free(o);
}

static st_program *program_new(tsr_state_ctx *c, GLuint name)
{
    if (!name || name_used(c, name))
        return NULL;
    st_program *p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    p->name = name;
    p->uid = c->t->next_uid++;
    if (tsr_name_map_put(&c->programs, name, p) != 0) {
        free(p);
        return NULL;
    }
    mark(c);
    return p;
}

static void bindings_free(st_binding *b, size_t n)
{
    for (size_t i = 0; i < n; i++)
        free(b[i].name);
    free(b);
}

static void uniforms_clear(st_program *p)
{
    for (size_t i = 0; i < p->nuni; i++)
        free(p->uni[i].data);
    p->nuni = 0;
}

static void link_clear(st_program *p)
{
    for (size_t i = 0; i < p->nlink; i++)
        src_unref(p->link[i].src);
    free(p->link);
    p->link = NULL;
    p->nlink = 0;
    bindings_free(p->link_bind, p->nlink_bind);
    p->link_bind = NULL;
    p->nlink_bind = 0;
}

/* A shader loses one attachment; a deleted one goes with its last. */
static void shader_detached(tsr_state_ctx *c, GLuint name)
{
    st_shader *o = tsr_name_map_get(&c->shaders, name);
    if (o && o->attached && --o->attached == 0 && o->delete_pending)
        shader_free(tsr_name_map_del(&c->shaders, name));
}

/* The program object goes (GL detaches its shaders). */
static void program_destroy(tsr_state_ctx *c, st_program *p)
{
    tsr_name_map_del(&c->programs, p->name);
    for (size_t i = 0; i < p->nattached; i++)
        shader_detached(c, p->attached[i]);
    free(p->attached);
    bindings_free(p->bind, p->nbind);
    link_clear(p);
    uniforms_clear(p);
    free(p->uni);
    free(p);
}

void st_glsl_free(tsr_state_ctx *c)
{
    for (size_t i = 0; i < c->programs.cap; i++)
        if (c->programs.keys[i]) {
            st_program *p = c->programs.vals[i];
            free(p->attached);
            bindings_free(p->bind, p->nbind);
            link_clear(p);
            uniforms_clear(p);
            free(p->uni);
            free(p);
        }
    tsr_name_map_free(&c->programs);
    for (size_t i = 0; i < c->shaders.cap; i++)
        if (c->shaders.keys[i])
            shader_free(c->shaders.vals[i]);
    tsr_name_map_free(&c->shaders);
    c->program = 0;
}

void st_glsl_shadow_free(tsr_state_shadow *s)
{
    for (size_t i = 0; i < s->programs.cap; i++)
        if (s->programs.keys[i]) {
            st_shadow_program *p = s->programs.vals[i];
            free(p->attached);
            free(p);
        }
    tsr_name_map_free(&s->programs);
    for (size_t i = 0; i < s->shaders.cap; i++)
        if (s->shaders.keys[i])
            free(s->shaders.vals[i]);
    tsr_name_map_free(&s->shaders);
    s->program = 0;
}

/* --- the application's calls ------------------------------------------------ */
static GLuint st_CreateShader(void *self, GLenum type)
{
    tsr_state_ctx *c = self;
    GLuint name = new_name(c);
    return shader_new(c, name, type) ? name : 0;
}

static void st_CreateShaderTSR(void *self, GLuint name, GLenum type)
{
    tsr_state_ctx *c = self;
    shader_new(c, name, type);
}

static GLuint st_CreateProgram(void *self)
{
    tsr_state_ctx *c = self;
    GLuint name = new_name(c);
    return program_new(c, name) ? name : 0;
}

static void st_CreateProgramTSR(void *self, GLuint name)
{
    tsr_state_ctx *c = self;
    program_new(c, name);
}

static void st_ShaderSource(void *self, GLuint shader, GLsizei count, const GLchar *const *str, const GLint *len)
{
    tsr_state_ctx *c = self;
    st_shader *o = tsr_name_map_get(&c->shaders, shader);
    if (!o || count < 0 || !str) { /* GL's error; a program's name is the wrong kind of object */
        st_error(c, !o && tsr_name_map_get(&c->programs, shader) ? GL_INVALID_OPERATION : GL_INVALID_VALUE);
        return;
    }
    for (GLsizei i = 0; i < count; i++)
        if (!str[i])
            return;
    st_source *s = src_make(c, count, str, len);
    if (!s)
        return;
    src_unref(o->source);
    o->source = s;
    mark(c);
}

static void st_CompileShader(void *self, GLuint shader)
{
    tsr_state_ctx *c = self;
    st_shader *o = tsr_name_map_get(&c->shaders, shader);
    if (!o)
        return;
    st_source *s = o->source ? src_ref(o->source) : src_make(c, 0, NULL, NULL);
    if (!s)
        return;
    src_unref(o->compiled);
    o->compiled = s;
    mark(c);
}

static void st_DeleteShader(void *self, GLuint shader)
{
    tsr_state_ctx *c = self;
    st_shader *o = tsr_name_map_get(&c->shaders, shader);
    if (!o)
        return;
    if (o->attached)
        o->delete_pending = 1;
    else
        shader_free(tsr_name_map_del(&c->shaders, shader));
    mark(c);
}

static void st_AttachShader(void *self, GLuint program, GLuint shader)
{
    tsr_state_ctx *c = self;
    st_program *p = tsr_name_map_get(&c->programs, program);
    st_shader *o = tsr_name_map_get(&c->shaders, shader);
    if (!p || !o)
        return;
    for (size_t i = 0; i < p->nattached; i++)
        if (p->attached[i] == shader)
            return;
    if (p->nattached == p->capattached) {
        size_t cap = p->capattached ? 2 * p->capattached : 4;
        GLuint *n = realloc(p->attached, cap * sizeof *n);
        if (!n)
            return;
        p->attached = n;
        p->capattached = cap;
    }
    p->attached[p->nattached++] = shader;
    o->attached++;
    mark(c);
}

static void st_DetachShader(void *self, GLuint program, GLuint shader)
{
    tsr_state_ctx *c = self;
    st_program *p = tsr_name_map_get(&c->programs, program);
    if (!p)
        return;
    for (size_t i = 0; i < p->nattached; i++)
        if (p->attached[i] == shader) {
            p->attached[i] = p->attached[--p->nattached];
            shader_detached(c, shader);
            mark(c);
            return;
        }
}

static void st_BindAttribLocation(void *self, GLuint program, GLuint index, const GLchar *name)
{
    tsr_state_ctx *c = self;
    st_program *p = tsr_name_map_get(&c->programs, program);
    if (!p || !name || index >= MAX_ATTRIBS || !strncmp(name, "gl_", 3))
        return;
    size_t i = 0;
    while (i < p->nbind && strcmp(p->bind[i].name, name))
        i++;
    if (i == p->nbind) {
        char *copy = strdup(name);
        st_binding *n = copy ? realloc(p->bind, (p->nbind + 1) * sizeof *n) : NULL;
        if (!n) {
            free(copy);
            return;
        }
        p->bind = n;
        p->bind[p->nbind++] = (st_binding){copy, index};
    } else {
        p->bind[i].index = index;
    }
    p->bind_version = c->t->next_uid++;
    mark(c);
}

static void st_LinkProgram(void *self, GLuint program)
{
    tsr_state_ctx *c = self;
    st_program *p = tsr_name_map_get(&c->programs, program);
    if (!p)
        return;
    st_link_shader *l = calloc(p->nattached ? p->nattached : 1, sizeof *l);
    st_binding *b = calloc(p->nbind ? p->nbind : 1, sizeof *b);
    if (!l || !b) {
        free(l);
        free(b);
        return;
    }
    size_t nb = 0;
    for (; nb < p->nbind; nb++)
        if (!(b[nb].name = strdup(p->bind[nb].name)))
            break;
        else
            b[nb].index = p->bind[nb].index;
    if (nb != p->nbind) {
        free(l);
        bindings_free(b, nb);
        return;
    }
    link_clear(p);
    uniforms_clear(p); /* a link sets every uniform to 0 */
    for (size_t i = 0; i < p->nattached; i++) {
        st_shader *o = tsr_name_map_get(&c->shaders, p->attached[i]);
        l[i] = (st_link_shader){p->attached[i], o ? o->type : 0, o ? src_ref(o->compiled) : NULL};
    }
    p->link = l;
    p->nlink = p->nattached;
    p->link_bind = b;
    p->nlink_bind = nb;
    p->link_id = c->t->next_uid++;
    mark(c);
}

static void st_ValidateProgram(void *self, GLuint program)
{
    tsr_state_ctx *c = self;
    st_program *p = tsr_name_map_get(&c->programs, program);
    if (p) {
        p->validations++;
        mark(c);
    }
}

static void st_DeleteProgram(void *self, GLuint program)
{
    tsr_state_ctx *c = self;
    st_program *p = tsr_name_map_get(&c->programs, program);
    if (!p)
        return;
    if (c->program == program)
        p->delete_pending = 1;
    else
        program_destroy(c, p);
    mark(c);
}

static void st_UseProgram(void *self, GLuint program)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    st_program *p = program ? tsr_name_map_get(&c->programs, program) : NULL;
    if (program && (!p || !p->link_id))
        return; /* unknown or never linked: GL refuses */
    GLuint old = c->program;
    c->program = program;
    st_program *o = old != program && old ? tsr_name_map_get(&c->programs, old) : NULL;
    if (o && o->delete_pending)
        program_destroy(c, o);
    mark(c);
}

/* One uniform call on the current program: appended to its log after the
 * earlier calls of the same kind it covers are dropped. */
static void uniform(tsr_state_ctx *c, int base, int size, GLint loc, GLsizei count, GLboolean transpose,
                    const void *data)
{
    /* GL's errors in Mesa's order; location -1 is ignored, one the program
     * lacks is the renderer's error when the log is replayed into it */
    GLenum refused = !c->program ? GL_INVALID_OPERATION
                     : count < 0 ? GL_INVALID_VALUE
                     : loc < -1  ? GL_INVALID_OPERATION
                                 : GL_NO_ERROR;
    if (refused) {
        st_error(c, refused);
        return;
    }
    st_program *p = tsr_name_map_get(&c->programs, c->program);
    if (!p || loc < 0 || count == 0 || !data)
        return;
    size_t per = base == ST_U_M    ? (size_t)(size * size)
                 : base == ST_U_MX ? (size_t)((size >> 4) * (size & 15))
                                   : (size_t)size;
    size_t values = (size_t)count * per;
    void *copy = malloc(values ? values * 4 : 1);
    if (!copy)
        return;
    memcpy(copy, data, values * 4);
    size_t out = 0;
    for (size_t i = 0; i < p->nuni; i++) {
        st_uniform *u = &p->uni[i];
        if (u->base == base && u->size == size && u->loc >= loc && (int64_t)u->loc + u->count <= (int64_t)loc + count) {
            free(u->data);
            continue;
        }
        p->uni[out++] = *u;
    }
    p->nuni = out;
    if (p->nuni == p->capuni) {
        size_t cap = p->capuni ? 2 * p->capuni : 8;
        st_uniform *n = realloc(p->uni, cap * sizeof *n);
        if (!n) {
            free(copy);
            return;
        }
        p->uni = n;
        p->capuni = cap;
    }
    p->uni[p->nuni++] = (st_uniform){++p->next_seq, loc, count, (uint8_t)base, (uint8_t)size, transpose, copy};
    mark(c);
}

#define UF(n, ...)                                      \
    {                                                   \
        tsr_state_ctx *c = st_exec_ctx(self);           \
        const GLfloat v[] = {__VA_ARGS__};              \
        if (c)                                          \
            uniform(c, ST_U_F, n, loc, 1, GL_FALSE, v); \
    }
#define UI(n, ...)                                      \
    {                                                   \
        tsr_state_ctx *c = st_exec_ctx(self);           \
        const GLint v[] = {__VA_ARGS__};                \
        if (c)                                          \
            uniform(c, ST_U_I, n, loc, 1, GL_FALSE, v); \
    }
static void st_Uniform1f(void *self, GLint loc, GLfloat a)
    UF(1, a) static void st_Uniform2f(void *self, GLint loc, GLfloat a, GLfloat b)
        UF(2, a, b) static void st_Uniform3f(void *self, GLint loc, GLfloat a, GLfloat b, GLfloat d)
            UF(3, a, b, d) static void st_Uniform4f(void *self, GLint loc, GLfloat a, GLfloat b, GLfloat d, GLfloat e)
                UF(4, a, b, d, e) static void st_Uniform1i(void *self, GLint loc, GLint a)
                    UI(1, a) static void st_Uniform2i(void *self, GLint loc, GLint a, GLint b)
                        UI(2, a, b) static void st_Uniform3i(void *self, GLint loc, GLint a, GLint b, GLint d)
                            UI(3, a, b, d) static void st_Uniform4i(void *self, GLint loc, GLint a, GLint b, GLint d,
                                                                    GLint e) UI(4, a, b, d, e)
#undef UF
#undef UI
#define UV(name, base, n, T)                                                \
    static void st_##name(void *self, GLint loc, GLsizei count, const T *v) \
    {                                                                       \
        tsr_state_ctx *c = st_exec_ctx(self);                               \
        if (c)                                                              \
            uniform(c, base, n, loc, count, GL_FALSE, v);                   \
    }
                                UV(Uniform1fv, ST_U_F, 1, GLfloat) UV(Uniform2fv, ST_U_F, 2, GLfloat)
                                    UV(Uniform3fv, ST_U_F, 3, GLfloat) UV(Uniform4fv, ST_U_F, 4, GLfloat)
                                        UV(Uniform1iv, ST_U_I, 1, GLint) UV(Uniform2iv, ST_U_I, 2, GLint)
                                            UV(Uniform3iv, ST_U_I, 3, GLint) UV(Uniform4iv, ST_U_I, 4, GLint)
#undef UV
#define UM(name, n)                                                                                    \
    static void st_##name(void *self, GLint loc, GLsizei count, GLboolean transpose, const GLfloat *v) \
    {                                                                                                  \
        tsr_state_ctx *c = st_exec_ctx(self);                                                          \
        if (c)                                                                                         \
            uniform(c, ST_U_M, n, loc, count, transpose, v);                                           \
    }
                                                UM(UniformMatrix2fv, 2) UM(UniformMatrix3fv, 3) UM(UniformMatrix4fv, 4)
#undef UM
/* GL 2.1's non-square matrices: COLSxROWS, kept as columns << 4 | rows. */
#define UMX(name, cols, rows)                                                                          \
    static void st_##name(void *self, GLint loc, GLsizei count, GLboolean transpose, const GLfloat *v) \
    {                                                                                                  \
        tsr_state_ctx *c = st_exec_ctx(self);                                                          \
        if (c)                                                                                         \
            uniform(c, ST_U_MX, (cols) << 4 | (rows), loc, count, transpose, v);                       \
    }
                                                    UMX(UniformMatrix2x3fv, 2, 3) UMX(UniformMatrix3x2fv, 3, 2)
                                                        UMX(UniformMatrix2x4fv, 2, 4) UMX(UniformMatrix4x2fv, 4, 2)
                                                            UMX(UniformMatrix3x4fv, 3, 4) UMX(UniformMatrix4x3fv, 4, 3)
#undef UMX

                                                                void st_glsl_fill_dispatch(tsr_state_ctx *c,
                                                                                           tsr_dispatch *d)
{
#define SET(name) tsr_set_##name(d, st_##name, c)
    SET(CreateShader);
    SET(CreateShaderTSR);
    SET(CreateProgram);
    SET(CreateProgramTSR);
    SET(ShaderSource);
    SET(CompileShader);
    SET(DeleteShader);
    SET(AttachShader);
    SET(DetachShader);
    SET(BindAttribLocation);
    SET(LinkProgram);
    SET(ValidateProgram);
    SET(DeleteProgram);
    SET(UseProgram);
    SET(Uniform1f);
    SET(Uniform2f);
    SET(Uniform3f);
    SET(Uniform4f);
    SET(Uniform1i);
    SET(Uniform2i);
    SET(Uniform3i);
    SET(Uniform4i);
    SET(Uniform1fv);
    SET(Uniform2fv);
    SET(Uniform3fv);
    SET(Uniform4fv);
    SET(Uniform1iv);
    SET(Uniform2iv);
    SET(Uniform3iv);
    SET(Uniform4iv);
    SET(UniformMatrix2fv);
    SET(UniformMatrix3fv);
    SET(UniformMatrix4fv);
    SET(UniformMatrix2x3fv);
    SET(UniformMatrix3x2fv);
    SET(UniformMatrix2x4fv);
    SET(UniformMatrix4x2fv);
    SET(UniformMatrix3x4fv);
    SET(UniformMatrix4x3fv);
#undef SET
}

int tsr_state_program_has_vertex_shader(const tsr_state_ctx *c)
{
    const st_program *p = c->program ? tsr_name_map_get(&c->programs, c->program) : NULL;
    for (size_t i = 0; p && i < p->nlink; i++)
        if (p->link[i].type == GL_VERTEX_SHADER)
            return 1;
    return 0;
}

/* --- sending to a renderer ------------------------------------------------------ */
typedef struct gx {
    tsr_state_ctx *c;
    tsr_state_shadow *s;
    const tsr_dispatch *d;
    uint32_t n;
} gx;

static int attached_on(const st_shadow_program *sp, GLuint shader)
{
    for (size_t i = 0; i < sp->nattached; i++)
        if (sp->attached[i] == shader)
            return 1;
    return 0;
}

/* Whether some program on the renderer still has `shader` attached. */
static int attached_anywhere(const tsr_state_shadow *s, GLuint shader)
{
    for (size_t i = 0; i < s->programs.cap; i++)
        if (s->programs.keys[i] && attached_on(s->programs.vals[i], shader))
            return 1;
    return 0;
}

/* A deleted shader is gone on the renderer once nothing holds it. */
static void shadow_shader_check(gx *x, GLuint shader)
{
    st_shadow_shader *ss = tsr_name_map_get(&x->s->shaders, shader);
    if (ss && ss->deleted && !attached_anywhere(x->s, shader))
        free(tsr_name_map_del(&x->s->shaders, shader));
}

static void r_attach(gx *x, GLuint program, st_shadow_program *sp, GLuint shader)
{
    GLuint *n = realloc(sp->attached, (sp->nattached + 1) * sizeof *n);
    if (!n)
        return;
    sp->attached = n;
    sp->attached[sp->nattached++] = shader;
    tsr_call_AttachShader(x->d, program, shader);
    x->n++;
}

static void r_detach(gx *x, GLuint program, st_shadow_program *sp, GLuint shader)
{
    for (size_t i = 0; i < sp->nattached; i++)
        if (sp->attached[i] == shader) {
            sp->attached[i] = sp->attached[--sp->nattached];
            tsr_call_DetachShader(x->d, program, shader);
            x->n++;
            shadow_shader_check(x, shader);
            return;
        }
}

/* The program leaves the renderer (deleted there and not current). */
static void r_program_gone(gx *x, GLuint program)
{
    st_shadow_program *sp = tsr_name_map_del(&x->s->programs, program);
    if (!sp)
        return;
    for (size_t i = 0; i < sp->nattached; i++) {
        GLuint sh = sp->attached[i];
        sp->attached[i] = 0;
        shadow_shader_check(x, sh);
    }
    free(sp->attached);
    free(sp);
}

/* A logged non-square matrix uniform, sent again. */
static void replay_nonsquare(const tsr_dispatch *d, const st_uniform *u, const GLfloat *f)
{
    switch (u->size) {
    case 2 << 4 | 3: tsr_call_UniformMatrix2x3fv(d, u->loc, u->count, u->transpose, f); break;
    case 3 << 4 | 2: tsr_call_UniformMatrix3x2fv(d, u->loc, u->count, u->transpose, f); break;
    case 2 << 4 | 4: tsr_call_UniformMatrix2x4fv(d, u->loc, u->count, u->transpose, f); break;
    case 4 << 4 | 2: tsr_call_UniformMatrix4x2fv(d, u->loc, u->count, u->transpose, f); break;
    case 3 << 4 | 4: tsr_call_UniformMatrix3x4fv(d, u->loc, u->count, u->transpose, f); break;
    default: tsr_call_UniformMatrix4x3fv(d, u->loc, u->count, u->transpose, f); break;
    }
}

static void r_use(gx *x, GLuint program)
{
    GLuint old = x->s->program;
    if (old == program)
        return;
    tsr_call_UseProgram(x->d, program);
    x->n++;
    x->s->program = program;
    st_shadow_program *o = old ? tsr_name_map_get(&x->s->programs, old) : NULL;
    if (o && o->deleted)
        r_program_gone(x, old);
}

static st_shadow_shader *r_shader(gx *x, GLuint name, GLenum type)
{
    st_shadow_shader *ss = tsr_name_map_get(&x->s->shaders, name);
    if (ss)
        return ss;
    if (!(ss = calloc(1, sizeof *ss)) || tsr_name_map_put(&x->s->shaders, name, ss) != 0) {
        free(ss);
        return NULL;
    }
    ss->type = type;
    tsr_call_CreateShaderTSR(x->d, name, type);
    x->n++;
    return ss;
}

static void r_source(gx *x, GLuint name, st_shadow_shader *ss, const st_source *src)
{
    const GLchar *text = src->text;
    GLint len = src->len;
    tsr_call_ShaderSource(x->d, name, 1, &text, &len);
    x->n++;
    ss->source = src->id;
}

/* Shader `name` on the renderer compiled from `src`. */
static void r_compiled(gx *x, GLuint name, GLenum type, const st_source *src)
{
    st_shadow_shader *ss = r_shader(x, name, type);
    if (!ss || !src || ss->compiled == src->id)
        return;
    if (ss->source != src->id)
        r_source(x, name, ss, src);
    tsr_call_CompileShader(x->d, name);
    x->n++;
    ss->compiled = src->id;
}

/* Shader o as the client has it (sources and compile). */
static void sync_shader(gx *x, const st_shader *o)
{
    r_compiled(x, o->name, o->type, o->compiled);
    st_shadow_shader *ss = tsr_name_map_get(&x->s->shaders, o->name);
    if (ss && o->source && ss->source != o->source->id)
        r_source(x, o->name, ss, o->source);
}

static st_shadow_program *r_program(gx *x, const st_program *p)
{
    st_shadow_program *sp = tsr_name_map_get(&x->s->programs, p->name);
    if (sp && sp->uid == p->uid)
        return sp;
    if (sp) { /* another context's program under this name */
        tsr_call_DeleteProgram(x->d, p->name);
        x->n++;
        r_program_gone(x, p->name);
        if (x->s->program == p->name)
            x->s->program = ~0u; /* the old one stays in use there until a glUseProgram: force one */
    }
    if (!(sp = calloc(1, sizeof *sp)) || tsr_name_map_put(&x->s->programs, p->name, sp) != 0) {
        free(sp);
        return NULL;
    }
    sp->uid = p->uid;
    tsr_call_CreateProgramTSR(x->d, p->name);
    x->n++;
    return sp;
}

/* Program p linked from its last link's inputs, with every uniform call
 * since: what drawing with it needs. Leaves p current on the renderer
 * when it had to send uniforms. */
static st_shadow_program *sync_program_draw(gx *x, const st_program *p)
{
    st_shadow_program *sp = r_program(x, p);
    if (!sp)
        return NULL;
    if (p->link_id && sp->link_id != p->link_id) {
        for (size_t i = sp->nattached; i-- > 0;) {
            GLuint sh = sp->attached[i];
            int keep = 0;
            for (size_t k = 0; k < p->nlink && !keep; k++)
                keep = p->link[k].name == sh;
            if (!keep)
                r_detach(x, p->name, sp, sh);
        }
        for (size_t k = 0; k < p->nlink; k++) {
            r_compiled(x, p->link[k].name, p->link[k].type, p->link[k].src);
            if (!attached_on(sp, p->link[k].name))
                r_attach(x, p->name, sp, p->link[k].name);
        }
        for (size_t k = 0; k < p->nlink_bind; k++) {
            tsr_call_BindAttribLocation(x->d, p->name, p->link_bind[k].index, p->link_bind[k].name);
            x->n++;
        }
        tsr_call_LinkProgram(x->d, p->name);
        x->n++;
        sp->link_id = p->link_id;
        sp->uni_seq = 0;
        sp->bind_version = 0; /* the link's bindings: maybe older than the program's */
    }
    if (p->nuni && p->uni[p->nuni - 1].seq > sp->uni_seq) {
        r_use(x, p->name);
        for (size_t i = 0; i < p->nuni; i++) {
            const st_uniform *u = &p->uni[i];
            if (u->seq <= sp->uni_seq)
                continue;
            const GLfloat *f = u->data;
            const GLint *iv = u->data;
            if (u->base == ST_U_MX) {
                replay_nonsquare(x->d, u, f);
                x->n++;
                continue;
            }
            switch (u->base * 8 + u->size) {
            case ST_U_F * 8 + 1: tsr_call_Uniform1fv(x->d, u->loc, u->count, f); break;
            case ST_U_F * 8 + 2: tsr_call_Uniform2fv(x->d, u->loc, u->count, f); break;
            case ST_U_F * 8 + 3: tsr_call_Uniform3fv(x->d, u->loc, u->count, f); break;
            case ST_U_F * 8 + 4: tsr_call_Uniform4fv(x->d, u->loc, u->count, f); break;
            case ST_U_I * 8 + 1: tsr_call_Uniform1iv(x->d, u->loc, u->count, iv); break;
            case ST_U_I * 8 + 2: tsr_call_Uniform2iv(x->d, u->loc, u->count, iv); break;
            case ST_U_I * 8 + 3: tsr_call_Uniform3iv(x->d, u->loc, u->count, iv); break;
            case ST_U_I * 8 + 4: tsr_call_Uniform4iv(x->d, u->loc, u->count, iv); break;
            case ST_U_M * 8 + 2: tsr_call_UniformMatrix2fv(x->d, u->loc, u->count, u->transpose, f); break;
            case ST_U_M * 8 + 3: tsr_call_UniformMatrix3fv(x->d, u->loc, u->count, u->transpose, f); break;
            default: tsr_call_UniformMatrix4fv(x->d, u->loc, u->count, u->transpose, f); break;
            }
            x->n++;
        }
        sp->uni_seq = p->uni[p->nuni - 1].seq;
    }
    return sp;
}

/* Program p as the client has it: also its attachments (with their
 * shaders as the client has them), its bindings and validations. */
static void sync_program_full(gx *x, const st_program *p)
{
    st_shadow_program *sp = sync_program_draw(x, p);
    if (!sp)
        return;
    for (size_t i = 0; i < p->nattached; i++) {
        const st_shader *o = tsr_name_map_get(&x->c->shaders, p->attached[i]);
        if (o)
            sync_shader(x, o);
    }
    for (size_t i = sp->nattached; i-- > 0;) {
        int keep = 0;
        for (size_t k = 0; k < p->nattached && !keep; k++)
            keep = p->attached[k] == sp->attached[i];
        if (!keep)
            r_detach(x, p->name, sp, sp->attached[i]);
    }
    for (size_t k = 0; k < p->nattached; k++)
        if (!attached_on(sp, p->attached[k]))
            r_attach(x, p->name, sp, p->attached[k]);
    if (sp->bind_version != p->bind_version) {
        for (size_t k = 0; k < p->nbind; k++) {
            tsr_call_BindAttribLocation(x->d, p->name, p->bind[k].index, p->bind[k].name);
            x->n++;
        }
        sp->bind_version = p->bind_version;
    }
    if (sp->validations != p->validations) {
        tsr_call_ValidateProgram(x->d, p->name);
        x->n++;
        sp->validations = p->validations;
    }
}

/* Whether some context of the tracker still has the object (contexts that
 * meet on one renderer share its objects: only what none has goes). */
static int program_alive(const tsr_state_tracker *t, GLuint name, uint64_t uid)
{
    for (size_t i = 0; i < t->nctxs; i++) {
        const st_program *p = tsr_name_map_get(&t->ctxs[i]->programs, name);
        if (p && p->uid == uid)
            return 1;
    }
    return 0;
}

static int shader_alive(const tsr_state_tracker *t, GLuint name)
{
    for (size_t i = 0; i < t->nctxs; i++)
        if (tsr_name_map_get(&t->ctxs[i]->shaders, name))
            return 1;
    return 0;
}

/* Objects the client deleted leave the renderer too (a program still
 * current there, or a shader still attached, when GL lets it go). */
static void purge(gx *x)
{
    tsr_state_shadow *s = x->s;
    for (size_t i = 0; i < s->programs.cap; i++) {
        GLuint name = s->programs.keys[i];
        if (!name)
            continue;
        st_shadow_program *sp = s->programs.vals[i];
        if (sp->deleted || program_alive(x->c->t, name, sp->uid))
            continue;
        tsr_call_DeleteProgram(x->d, name);
        x->n++;
        if (s->program == name) {
            sp->deleted = 1;
        } else {
            r_program_gone(x, name);
            i = (size_t)-1; /* the map changed: start again */
        }
    }
    for (size_t i = 0; i < s->shaders.cap; i++) {
        GLuint name = s->shaders.keys[i];
        if (!name)
            continue;
        st_shadow_shader *ss = s->shaders.vals[i];
        if (ss->deleted || shader_alive(x->c->t, name))
            continue;
        tsr_call_DeleteShader(x->d, name);
        x->n++;
        ss->deleted = 1;
        if (!attached_anywhere(s, name)) {
            free(tsr_name_map_del(&s->shaders, name));
            i = (size_t)-1;
        }
    }
}

uint32_t st_glsl_diff(tsr_state_ctx *c, tsr_state_shadow *s, const tsr_dispatch *out)
{
    gx x = {c, s, out, 0};
    const st_program *p = c->program ? tsr_name_map_get(&c->programs, c->program) : NULL;
    if (p)
        sync_program_draw(&x, p);
    r_use(&x, c->program);
    purge(&x);
    return x.n;
}

/* After sending outside a diff: the renderer's current program as it was,
 * or (when that one is gone there) a diff to come puts it right. */
static void restore_current(gx *x, GLuint was)
{
    if (x->s->program == was)
        return;
    if (!was || tsr_name_map_get(&x->s->programs, was))
        r_use(x, was);
    else
        st_mark_one(x->c, TSR_SM_PROGRAM, x->s->id);
}

uint32_t tsr_state_send_shader(tsr_state_ctx *c, tsr_state_shadow *s, GLuint name, const tsr_dispatch *out)
{
    const st_shader *o = tsr_name_map_get(&c->shaders, name);
    if (!o)
        return 0;
    gx x = {c, s, out, 0};
    sync_shader(&x, o);
    return x.n;
}

uint32_t tsr_state_send_program(tsr_state_ctx *c, tsr_state_shadow *s, GLuint name, const tsr_dispatch *out)
{
    const st_program *p = tsr_name_map_get(&c->programs, name);
    if (!p)
        return 0;
    gx x = {c, s, out, 0};
    GLuint was = s->program;
    sync_program_full(&x, p);
    restore_current(&x, was);
    return x.n;
}

uint32_t tsr_state_send_glsl_all(tsr_state_ctx *c, tsr_state_shadow *s, const tsr_dispatch *out)
{
    gx x = {c, s, out, 0};
    GLuint was = s->program;
    /* programs first: a link may compile a shader from an older source
     * (its link's); the shaders are then put as the client has them */
    for (size_t i = 0; i < c->programs.cap; i++)
        if (c->programs.keys[i])
            sync_program_full(&x, c->programs.vals[i]);
    for (size_t i = 0; i < c->shaders.cap; i++)
        if (c->shaders.keys[i])
            sync_shader(&x, c->shaders.vals[i]);
    /* deletions GL holds back: a shader still attached, the current program */
    for (size_t i = 0; i < c->shaders.cap; i++) {
        const st_shader *o = c->shaders.keys[i] ? c->shaders.vals[i] : NULL;
        st_shadow_shader *ss = o && o->delete_pending ? tsr_name_map_get(&s->shaders, o->name) : NULL;
        if (ss && !ss->deleted) {
            tsr_call_DeleteShader(out, o->name);
            x.n++;
            ss->deleted = 1;
        }
    }
    const st_program *cur = c->program ? tsr_name_map_get(&c->programs, c->program) : NULL;
    if (cur && cur->delete_pending) {
        st_shadow_program *sp = tsr_name_map_get(&s->programs, cur->name);
        if (sp && !sp->deleted) {
            r_use(&x, cur->name);
            tsr_call_DeleteProgram(out, cur->name);
            x.n++;
            sp->deleted = 1;
        }
        return x.n;
    }
    restore_current(&x, was);
    return x.n;
}
