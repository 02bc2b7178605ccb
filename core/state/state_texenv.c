/* core/state/state_texenv.c — setters of the texture units: the active
 * unit, texture environments (combine modes, LOD bias, point sprite
 * coordinate replacement) and texture coordinate generation.
 *
 * Owns: the values of tsr_state_texunit (coordinate units) and the LOD
 * bias of tsr_state_imageunit (texture objects and bindings are
 * state_obj.c's).
 *
 * Never: keeps an eye plane as given: GL transforms it by the inverse
 * modelview at the call, and a get answers the transformed plane. */
#include "state_internal.h"

#include <string.h>

/* --- texture units ------------------------------------------------------------------ */
static void st_ActiveTexture(void *self, GLenum unit)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLuint u = unit - GL_TEXTURE0;
    if (u >= c->t->image_units) {
        st_error(c, GL_INVALID_ENUM);
        return;
    }
    c->v.active_texture = u;
    /* The selector travels with unit 0's bindings (restored last by the diff). */
    st_mark(c, TSR_SM_TEXBIND0);
}

static int env_enum_slot(tsr_state_texunit *t, GLenum pname, GLenum **slot)
{
    switch (pname) {
    case GL_TEXTURE_ENV_MODE: *slot = &t->env_mode; return 1;
    case GL_COMBINE_RGB: *slot = &t->combine_rgb; return 1;
    case GL_COMBINE_ALPHA: *slot = &t->combine_alpha; return 1;
    case GL_SRC0_RGB:
    case GL_SRC1_RGB:
    case GL_SRC2_RGB: *slot = &t->src_rgb[pname - GL_SRC0_RGB]; return 1;
    case GL_SRC0_ALPHA:
    case GL_SRC1_ALPHA:
    case GL_SRC2_ALPHA: *slot = &t->src_alpha[pname - GL_SRC0_ALPHA]; return 1;
    case GL_OPERAND0_RGB:
    case GL_OPERAND1_RGB:
    case GL_OPERAND2_RGB: *slot = &t->operand_rgb[pname - GL_OPERAND0_RGB]; return 1;
    case GL_OPERAND0_ALPHA:
    case GL_OPERAND1_ALPHA:
    case GL_OPERAND2_ALPHA: *slot = &t->operand_alpha[pname - GL_OPERAND0_ALPHA]; return 1;
    default: return 0;
    }
}

static void tex_env(tsr_state_ctx *c, GLenum target, GLenum pname, const GLfloat *p, int from_int)
{
    GLuint u = c->v.active_texture;
    if (target == GL_TEXTURE_FILTER_CONTROL && pname == GL_TEXTURE_LOD_BIAS) {
        c->v.image[u].lod_bias = p[0]; /* per image unit */
        st_image_changed(c, u);
        return;
    }
    if (u >= TSR_STATE_UNITS) {
        /* no fixed-function state there: Mesa refuses coordinate
         * replacement and ignores the environment */
        if (target == GL_POINT_SPRITE && pname == GL_COORD_REPLACE)
            st_error(c, GL_INVALID_OPERATION);
        else if (target != GL_TEXTURE_ENV && target != GL_POINT_SPRITE)
            st_error(c, GL_INVALID_ENUM);
        return;
    }
    tsr_state_texunit *t = &c->v.unit[u];
    GLenum *e;
    if (target == GL_POINT_SPRITE && pname == GL_COORD_REPLACE)
        t->coord_replace = p[0] != 0.0f;
    else if (target != GL_TEXTURE_ENV) {
        st_error(c, GL_INVALID_ENUM);
        return;
    } else if (pname == GL_TEXTURE_ENV_COLOR)
        for (int i = 0; i < 4; i++)
            t->env_color[i] = st_clampf(from_int ? st_int_to_float((GLint)p[i]) : p[i]);
    else if (pname == GL_RGB_SCALE || pname == GL_ALPHA_SCALE) {
        if (p[0] != 1.0f && p[0] != 2.0f && p[0] != 4.0f)
            return;
        *(pname == GL_RGB_SCALE ? &t->rgb_scale : &t->alpha_scale) = p[0];
    } else if (env_enum_slot(t, pname, &e)) {
        *e = (GLenum)p[0];
    } else {
        st_error(c, GL_INVALID_ENUM);
        return;
    }
    st_mark(c, TSR_SM_TEXENV0 + (int)u);
}

static void st_TexEnvf(void *self, GLenum target, GLenum pname, GLfloat p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (pname != GL_TEXTURE_ENV_COLOR)
        tex_env(c, target, pname, &p, 0);
}

static void st_TexEnvfv(void *self, GLenum target, GLenum pname, const GLfloat *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    tex_env(c, target, pname, p, 0);
}

static void st_TexEnvi(void *self, GLenum target, GLenum pname, GLint p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLfloat f = (GLfloat)p;
    if (pname != GL_TEXTURE_ENV_COLOR)
        tex_env(c, target, pname, &f, 0);
}
static void st_TexEnviv(void *self, GLenum target, GLenum pname, const GLint *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLfloat f[4] = {0, 0, 0, 0};
    int color = pname == GL_TEXTURE_ENV_COLOR;
    st_ints_to_floats(f, p, color ? 4 : 1, 0);
    tex_env(c, target, pname, f, color);
}

static void tex_gen(tsr_state_ctx *c, GLenum coord, GLenum pname, const GLfloat *p)
{
    if (coord < GL_S || coord > GL_Q)
        return;
    GLuint u = c->v.active_texture;
    if (u >= TSR_STATE_UNITS) {
        st_error(c, GL_INVALID_OPERATION); /* Mesa's: no coordinate generation past the coordinate units */
        return;
    }
    tsr_state_texgen *g = &c->v.unit[u].gen[coord - GL_S];
    switch (pname) {
    case GL_TEXTURE_GEN_MODE: {
        GLenum m = (GLenum)p[0];
        if (m != GL_OBJECT_LINEAR && m != GL_EYE_LINEAR && m != GL_SPHERE_MAP && m != GL_NORMAL_MAP &&
            m != GL_REFLECTION_MAP)
            return;
        if ((m == GL_SPHERE_MAP && coord >= GL_R) || ((m == GL_NORMAL_MAP || m == GL_REFLECTION_MAP) && coord == GL_Q))
            return;
        g->mode = m;
        break;
    }
    case GL_OBJECT_PLANE: memcpy(g->object_plane, p, 16); break;
    case GL_EYE_PLANE: st_plane_to_eye(c, g->eye_plane, p); break;
    default: st_error(c, GL_INVALID_ENUM); return;
    }
    st_mark(c, TSR_SM_TEXGEN0 + (int)u);
}

static void st_TexGenf(void *self, GLenum coord, GLenum pname, GLfloat p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (pname == GL_TEXTURE_GEN_MODE)
        tex_gen(c, coord, pname, &p);
}

static void st_TexGeni(void *self, GLenum coord, GLenum pname, GLint p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLfloat f = (GLfloat)p;
    if (pname == GL_TEXTURE_GEN_MODE)
        tex_gen(c, coord, pname, &f);
}

static void st_TexGend(void *self, GLenum coord, GLenum pname, GLdouble p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLfloat f = (GLfloat)p;
    if (pname == GL_TEXTURE_GEN_MODE)
        tex_gen(c, coord, pname, &f);
}

static void st_TexGenfv(void *self, GLenum coord, GLenum pname, const GLfloat *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    tex_gen(c, coord, pname, p);
}

static void st_TexGeniv(void *self, GLenum coord, GLenum pname, const GLint *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLfloat f[4] = {0, 0, 0, 0};
    st_ints_to_floats(f, p, pname == GL_TEXTURE_GEN_MODE ? 1 : 4, 0);
    tex_gen(c, coord, pname, f);
}

static void st_TexGendv(void *self, GLenum coord, GLenum pname, const GLdouble *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLfloat f[4] = {(GLfloat)p[0], 0, 0, 0};
    if (pname != GL_TEXTURE_GEN_MODE)
        for (int i = 1; i < 4; i++)
            f[i] = (GLfloat)p[i];
    tex_gen(c, coord, pname, f);
}

void st_texenv_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d)
{
#define SET(name) tsr_set_##name(d, st_##name, c)
    SET(ActiveTexture);
    SET(TexEnvf);
    SET(TexEnvfv);
    SET(TexEnvi);
    SET(TexEnviv);
    SET(TexGenf);
    SET(TexGeni);
    SET(TexGend);
    SET(TexGenfv);
    SET(TexGeniv);
    SET(TexGendv);
#undef SET
}
