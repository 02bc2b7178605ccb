/* core/state/state_light.c — setters of the current attributes (glColor,
 * glNormal, glTexCoord, glEdgeFlag, glVertexAttrib, reached through the
 * generated entry points of state_gen.c), lights, the light model,
 * materials, glColorMaterial and glShadeModel. They share a file because
 * glColor is a lighting input: with GL_COLOR_MATERIAL on it writes the
 * material too.
 *
 * Owns: the CURRENT and LIGHTING groups of tsr_state_values, and the rule
 * of which material properties glColor drives (st_color_material_apply,
 * st_tracked_by_color), which the diff applies to shadows as well.
 *
 * Never: lets glMaterial change a property glColor currently drives (Mesa
 * ignores it), or transforms a light position or direction with anything
 * but the modelview matrix current at the call, as GL does. */
#include "state_internal.h"

#include <string.h>

/* --- glColor and the material ---------------------------------------------------- */
/* The color property pname of material m (NULL: not a color property). */
static GLfloat *material_color(tsr_state_material *m, GLenum pname)
{
    switch (pname) {
    case GL_AMBIENT: return m->ambient;
    case GL_DIFFUSE: return m->diffuse;
    case GL_SPECULAR: return m->specular;
    case GL_EMISSION: return m->emission;
    default: return NULL;
    }
}

/* Which material properties glColor currently drives (Mesa ignores
 * glMaterial for those while GL_COLOR_MATERIAL is enabled). */
int st_tracked_by_color(const tsr_state_values *v, int face, GLenum pname)
{
    if (!st_enabled(v, ST_EN_COLOR_MATERIAL))
        return 0;
    if ((face == 0 && v->color_material_face == GL_BACK) || (face == 1 && v->color_material_face == GL_FRONT))
        return 0;
    GLenum m = v->color_material_mode;
    return m == pname || (m == GL_AMBIENT_AND_DIFFUSE && (pname == GL_AMBIENT || pname == GL_DIFFUSE));
}

int st_color_material_apply(tsr_state_values *v)
{
    if (!st_enabled(v, ST_EN_COLOR_MATERIAL))
        return 0;
    static const GLenum props[4] = {GL_AMBIENT, GL_DIFFUSE, GL_SPECULAR, GL_EMISSION};
    for (int f = 0; f < 2; f++)
        for (int k = 0; k < 4; k++)
            if (st_tracked_by_color(v, f, props[k]))
                memcpy(material_color(&v->material[f], props[k]), v->color, 16);
    return 1;
}

void st_color_material_update(tsr_state_ctx *c)
{
    if (st_color_material_apply(&c->v))
        st_mark(c, TSR_SM_MATERIAL);
}

/* --- current attributes -------------------------------------------------------- */
void st_cur_color(void *self, GLfloat r, GLfloat g, GLfloat b, GLfloat a)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    st_set4(c->v.color, r, g, b, a);
    st_mark(c, TSR_SM_COLOR);
    st_color_material_update(c);
}

void st_cur_normal(void *self, GLfloat x, GLfloat y, GLfloat z)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.normal[0] = x;
    c->v.normal[1] = y;
    c->v.normal[2] = z;
    st_mark(c, TSR_SM_NORMAL);
}

void st_cur_texcoord(void *self, GLenum unit_enum, GLfloat s, GLfloat t, GLfloat r, GLfloat q)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLuint u = unit_enum - GL_TEXTURE0;
    if (u >= TSR_STATE_UNITS)
        return;
    st_set4(c->v.texcoord[u], s, t, r, q);
    st_mark(c, TSR_SM_TEXCOORD0 + (int)u);
}

void st_cur_edgeflag(void *self, GLboolean flag)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.edge_flag = flag ? GL_TRUE : GL_FALSE;
    st_mark(c, TSR_SM_EDGEFLAG);
}

/* Attribute 0 is the vertex position (it emits a vertex, sets no state). */
void st_cur_attrib(void *self, GLuint index, GLfloat x, GLfloat y, GLfloat z, GLfloat w)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (index == 0 || index >= TSR_STATE_ATTRIBS)
        return;
    st_set4(c->v.attrib[index], x, y, z, w);
    st_mark(c, TSR_SM_ATTRIBS);
}

/* --- lighting --------------------------------------------------------------------- */
static void light(tsr_state_ctx *c, GLenum which, GLenum pname, const GLfloat *p)
{
    if (which < GL_LIGHT0 || which >= GL_LIGHT0 + TSR_STATE_LIGHTS) {
        st_error(c, GL_INVALID_ENUM);
        return;
    }
    tsr_state_light *l = &c->v.light[which - GL_LIGHT0];
    const GLfloat *m = c->s.modelview[c->s.modelview_depth - 1];
    switch (pname) {
    case GL_AMBIENT: memcpy(l->ambient, p, 16); break;
    case GL_DIFFUSE: memcpy(l->diffuse, p, 16); break;
    case GL_SPECULAR: memcpy(l->specular, p, 16); break;
    case GL_POSITION:
        for (int i = 0; i < 4; i++)
            l->position[i] = m[i] * p[0] + m[4 + i] * p[1] + m[8 + i] * p[2] + m[12 + i] * p[3];
        break;
    case GL_SPOT_DIRECTION:
        for (int i = 0; i < 3; i++)
            l->spot_direction[i] = p[0] * m[i] + p[1] * m[4 + i] + p[2] * m[8 + i];
        break;
    case GL_SPOT_EXPONENT:
        if (p[0] < 0 || p[0] > 128)
            return;
        l->spot_exponent = p[0];
        break;
    case GL_SPOT_CUTOFF:
        if ((p[0] < 0 || p[0] > 90) && p[0] != 180)
            return;
        l->spot_cutoff = p[0];
        break;
    case GL_CONSTANT_ATTENUATION:
        if (p[0] < 0)
            return;
        l->attenuation[0] = p[0];
        break;
    case GL_LINEAR_ATTENUATION:
        if (p[0] < 0)
            return;
        l->attenuation[1] = p[0];
        break;
    case GL_QUADRATIC_ATTENUATION:
        if (p[0] < 0)
            return;
        l->attenuation[2] = p[0];
        break;
    default: st_error(c, GL_INVALID_ENUM); return;
    }
    st_mark(c, TSR_SM_LIGHT0 + (int)(which - GL_LIGHT0));
}

static int is_color_pname(GLenum p)
{
    return p == GL_AMBIENT || p == GL_DIFFUSE || p == GL_SPECULAR || p == GL_EMISSION || p == GL_AMBIENT_AND_DIFFUSE ||
           p == GL_LIGHT_MODEL_AMBIENT;
}

static void lighti(tsr_state_ctx *c, GLenum which, GLenum pname, const GLint *p)
{
    GLfloat f[4];
    int n = pname == GL_SPOT_DIRECTION ? 3 : (pname == GL_POSITION || is_color_pname(pname)) ? 4 : 1;
    st_ints_to_floats(f, p, n, is_color_pname(pname));
    light(c, which, pname, f);
}

static int scalar_light_pname(GLenum p)
{
    return p == GL_SPOT_EXPONENT || p == GL_SPOT_CUTOFF || p == GL_CONSTANT_ATTENUATION || p == GL_LINEAR_ATTENUATION ||
           p == GL_QUADRATIC_ATTENUATION;
}

static void st_Lightf(void *self, GLenum l, GLenum pname, GLfloat p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (scalar_light_pname(pname))
        light(c, l, pname, &p);
}

static void st_Lightfv(void *self, GLenum l, GLenum pname, const GLfloat *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    light(c, l, pname, p);
}

static void st_Lighti(void *self, GLenum l, GLenum pname, GLint p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (scalar_light_pname(pname))
        lighti(c, l, pname, &p);
}

static void st_Lightiv(void *self, GLenum l, GLenum pname, const GLint *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    lighti(c, l, pname, p);
}

static void light_model(tsr_state_ctx *c, GLenum pname, const GLfloat *p)
{
    tsr_state_values *v = &c->v;
    switch (pname) {
    case GL_LIGHT_MODEL_AMBIENT: memcpy(v->model_ambient, p, 16); break;
    case GL_LIGHT_MODEL_LOCAL_VIEWER: v->model_local_viewer = p[0] != 0.0f; break;
    case GL_LIGHT_MODEL_TWO_SIDE: v->model_two_side = p[0] != 0.0f; break;
    case GL_LIGHT_MODEL_COLOR_CONTROL:
        if ((GLenum)p[0] != GL_SINGLE_COLOR && (GLenum)p[0] != GL_SEPARATE_SPECULAR_COLOR)
            return;
        v->model_color_control = (GLenum)p[0];
        break;
    default: st_error(c, GL_INVALID_ENUM); return;
    }
    st_mark(c, TSR_SM_LIGHTMODEL);
}

static void light_modeli(tsr_state_ctx *c, GLenum pname, const GLint *p)
{
    GLfloat f[4];
    int color = pname == GL_LIGHT_MODEL_AMBIENT;
    st_ints_to_floats(f, p, color ? 4 : 1, color);
    light_model(c, pname, f);
}

static void st_LightModelf(void *self, GLenum pname, GLfloat p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (pname != GL_LIGHT_MODEL_AMBIENT)
        light_model(c, pname, &p);
}

static void st_LightModelfv(void *self, GLenum pname, const GLfloat *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    light_model(c, pname, p);
}

static void st_LightModeli(void *self, GLenum pname, GLint p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (pname != GL_LIGHT_MODEL_AMBIENT)
        light_modeli(c, pname, &p);
}

static void st_LightModeliv(void *self, GLenum pname, const GLint *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    light_modeli(c, pname, p);
}

static void material(tsr_state_ctx *c, GLenum face, GLenum pname, const GLfloat *p)
{
    int a, b;
    if (!st_faces(face, &a, &b))
        return;
    for (int f = a; f <= b; f++) {
        tsr_state_material *m = &c->v.material[f];
        GLenum props[2] = {pname, 0};
        if (pname == GL_AMBIENT_AND_DIFFUSE) {
            props[0] = GL_AMBIENT;
            props[1] = GL_DIFFUSE;
        }
        for (int k = 0; k < 2 && props[k]; k++) {
            if (st_tracked_by_color(&c->v, f, props[k]))
                continue;
            GLfloat *dst = material_color(m, props[k]);
            if (dst) {
                memcpy(dst, p, 16);
            } else if (props[k] == GL_SHININESS) {
                if (p[0] >= 0 && p[0] <= 128)
                    m->shininess = p[0];
                else
                    st_error(c, GL_INVALID_VALUE);
            } else if (props[k] != GL_COLOR_INDEXES) { /* colour-index lighting: not kept */
                st_error(c, GL_INVALID_ENUM);
                return;
            }
        }
    }
    st_mark(c, TSR_SM_MATERIAL);
}

static void materiali(tsr_state_ctx *c, GLenum face, GLenum pname, const GLint *p)
{
    GLfloat f[4];
    int color = pname != GL_SHININESS;
    st_ints_to_floats(f, p, color ? 4 : 1, color);
    if (pname != GL_COLOR_INDEXES)
        material(c, face, pname, f);
}

static void st_Materialf(void *self, GLenum face, GLenum pname, GLfloat p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (pname == GL_SHININESS)
        material(c, face, pname, &p);
}

static void st_Materialfv(void *self, GLenum face, GLenum pname, const GLfloat *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (pname != GL_COLOR_INDEXES)
        material(c, face, pname, p);
}

static void st_Materiali(void *self, GLenum face, GLenum pname, GLint p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (pname == GL_SHININESS)
        materiali(c, face, pname, &p);
}

static void st_Materialiv(void *self, GLenum face, GLenum pname, const GLint *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    materiali(c, face, pname, p);
}

static void st_ColorMaterial(void *self, GLenum face, GLenum mode)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    int a, b;
    if (!st_faces(face, &a, &b))
        return;
    if (mode != GL_EMISSION && mode != GL_AMBIENT && mode != GL_DIFFUSE && mode != GL_SPECULAR &&
        mode != GL_AMBIENT_AND_DIFFUSE)
        return;
    c->v.color_material_face = face;
    c->v.color_material_mode = mode;
    st_mark(c, TSR_SM_COLORMATERIAL);
    st_color_material_update(c);
}

static void st_ShadeModel(void *self, GLenum m)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (m != GL_FLAT && m != GL_SMOOTH)
        return;
    c->v.shade_model = m;
    st_mark(c, TSR_SM_SHADEMODEL);
}

void st_light_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d)
{
#define SET(name) tsr_set_##name(d, st_##name, c)
    SET(Lightf);
    SET(Lightfv);
    SET(Lighti);
    SET(Lightiv);
    SET(LightModelf);
    SET(LightModelfv);
    SET(LightModeli);
    SET(LightModeliv);
    SET(Materialf);
    SET(Materialfv);
    SET(Materiali);
    SET(Materialiv);
    SET(ColorMaterial);
    SET(ShadeModel);
#undef SET
}
