/* core/state/state_diff_members.c — the diff of the fixed-function
 * members, from the enables to the hints: current values, viewport,
 * colour buffer, depth, stencil, fog, lights and materials, raster and
 * points. Each d_* compares the context with the shadow, emits a call per
 * difference, and applies it to the shadow as the renderer will
 * (GL_COLOR_MATERIAL's side effects included).
 * Owns nothing. Never: emits without applying to the shadow, touches
 * texture or buffer objects (state_diff_objects.c). */
#include "state_internal.h"

#include <stdlib.h>
#include <string.h>
#include "state_diff_internal.h"

/* --- members -------------------------------------------------------------------- */
void diff_enables(dctx *x, int word)
{
    uint64_t diff = x->c->v.enables[word] ^ x->s->v.enables[word];
    while (diff) {
        int b = __builtin_ctzll(diff);
        diff &= diff - 1;
        int idx = word * 64 + b;
        GLenum cap = st_enable_caps[idx];
        if (!cap)
            continue;
        if (idx >= ST_EN_UNIT0)
            diff_sel_unit(x, (GLuint)(idx - ST_EN_UNIT0) / 8);
        int on = st_enabled(&x->c->v, idx);
        if (on)
            tsr_call_Enable(x->d, cap);
        else
            tsr_call_Disable(x->d, cap);
        x->s->v.enables[word] ^= 1ull << b;
        emitted(x);
        if (cap == GL_COLOR_MATERIAL && on && st_color_material_apply(&x->s->v)) {
            st_mark_one(x->c, TSR_SM_MATERIAL, x->s->id);
            x->changed[TSR_SM_MATERIAL >> 6] |= 1ull << (TSR_SM_MATERIAL & 63);
        }
    }
}

void diff_current(dctx *x, int m)
{
    tsr_state_values *c = &x->c->v, *s = &x->s->v;
    if (m == TSR_SM_COLOR && NEQ(c->color, s->color)) {
        tsr_call_Color4f(x->d, c->color[0], c->color[1], c->color[2], c->color[3]);
        SYNC(s->color, c->color);
        emitted(x);
        if (st_color_material_apply(s)) {
            st_mark_one(x->c, TSR_SM_MATERIAL, x->s->id);
            x->changed[TSR_SM_MATERIAL >> 6] |= 1ull << (TSR_SM_MATERIAL & 63);
        }
    } else if (m == TSR_SM_NORMAL && NEQ(c->normal, s->normal)) {
        tsr_call_Normal3f(x->d, c->normal[0], c->normal[1], c->normal[2]);
        SYNC(s->normal, c->normal);
        emitted(x);
    } else if (m >= TSR_SM_TEXCOORD0 && m < TSR_SM_TEXCOORD0 + TSR_STATE_UNITS) {
        int u = m - TSR_SM_TEXCOORD0;
        if (NEQ(c->texcoord[u], s->texcoord[u])) {
            const GLfloat *t = c->texcoord[u];
            tsr_call_MultiTexCoord4f(x->d, GL_TEXTURE0 + (GLenum)u, t[0], t[1], t[2], t[3]);
            SYNC(s->texcoord[u], c->texcoord[u]);
            emitted(x);
        }
    } else if (m == TSR_SM_EDGEFLAG && c->edge_flag != s->edge_flag) {
        tsr_call_EdgeFlag(x->d, c->edge_flag);
        s->edge_flag = c->edge_flag;
        emitted(x);
    } else if (m == TSR_SM_ATTRIBS) {
        for (GLuint i = 1; i < TSR_STATE_ATTRIBS; i++)
            if (NEQ(c->attrib[i], s->attrib[i])) {
                const GLfloat *a = c->attrib[i];
                tsr_call_VertexAttrib4f(x->d, i, a[0], a[1], a[2], a[3]);
                SYNC(s->attrib[i], c->attrib[i]);
                emitted(x);
            }
    }
}

void diff_viewport(dctx *x, int m)
{
    tsr_state_values *c = &x->c->v, *s = &x->s->v;
    if (m == TSR_SM_VIEWPORT && c->viewport[2] >= 0 && NEQ(c->viewport, s->viewport)) {
        tsr_call_Viewport(x->d, c->viewport[0], c->viewport[1], c->viewport[2], c->viewport[3]);
        SYNC(s->viewport, c->viewport);
        emitted(x);
    } else if (m == TSR_SM_DEPTHRANGE && NEQ(c->depth_range, s->depth_range)) {
        tsr_call_DepthRange(x->d, c->depth_range[0], c->depth_range[1]);
        SYNC(s->depth_range, c->depth_range);
        emitted(x);
    } else if (m == TSR_SM_SCISSOR && c->scissor[2] >= 0 && NEQ(c->scissor, s->scissor)) {
        tsr_call_Scissor(x->d, c->scissor[0], c->scissor[1], c->scissor[2], c->scissor[3]);
        SYNC(s->scissor, c->scissor);
        emitted(x);
    }
}

void diff_colorbuf(dctx *x, int m)
{
    tsr_state_values *c = &x->c->v, *s = &x->s->v;
    switch (m) {
    case TSR_SM_BLEND:
        if (c->blend_src_rgb != s->blend_src_rgb || c->blend_dst_rgb != s->blend_dst_rgb ||
            c->blend_src_alpha != s->blend_src_alpha || c->blend_dst_alpha != s->blend_dst_alpha) {
            if (c->blend_src_rgb == c->blend_src_alpha && c->blend_dst_rgb == c->blend_dst_alpha)
                tsr_call_BlendFunc(x->d, c->blend_src_rgb, c->blend_dst_rgb);
            else
                tsr_call_BlendFuncSeparate(x->d, c->blend_src_rgb, c->blend_dst_rgb, c->blend_src_alpha,
                                           c->blend_dst_alpha);
            s->blend_src_rgb = c->blend_src_rgb;
            s->blend_dst_rgb = c->blend_dst_rgb;
            s->blend_src_alpha = c->blend_src_alpha;
            s->blend_dst_alpha = c->blend_dst_alpha;
            emitted(x);
        }
        if (c->blend_eq_rgb != s->blend_eq_rgb || c->blend_eq_alpha != s->blend_eq_alpha) {
            if (c->blend_eq_rgb == c->blend_eq_alpha)
                tsr_call_BlendEquation(x->d, c->blend_eq_rgb);
            else
                tsr_call_BlendEquationSeparate(x->d, c->blend_eq_rgb, c->blend_eq_alpha);
            s->blend_eq_rgb = c->blend_eq_rgb;
            s->blend_eq_alpha = c->blend_eq_alpha;
            emitted(x);
        }
        if (NEQ(c->blend_color, s->blend_color)) {
            tsr_call_BlendColor(x->d, c->blend_color[0], c->blend_color[1], c->blend_color[2], c->blend_color[3]);
            SYNC(s->blend_color, c->blend_color);
            emitted(x);
        }
        break;
    case TSR_SM_ALPHAFUNC:
        if (c->alpha_func != s->alpha_func || NEQ(c->alpha_ref, s->alpha_ref)) {
            tsr_call_AlphaFunc(x->d, c->alpha_func, c->alpha_ref);
            s->alpha_func = c->alpha_func;
            s->alpha_ref = c->alpha_ref;
            emitted(x);
        }
        break;
    case TSR_SM_LOGICOP:
        if (c->logic_op != s->logic_op) {
            tsr_call_LogicOp(x->d, c->logic_op);
            s->logic_op = c->logic_op;
            emitted(x);
        }
        break;
    case TSR_SM_COLORMASK:
        if (NEQ(c->color_mask, s->color_mask)) {
            tsr_call_ColorMask(x->d, c->color_mask[0], c->color_mask[1], c->color_mask[2], c->color_mask[3]);
            SYNC(s->color_mask, c->color_mask);
            emitted(x);
        }
        break;
    case TSR_SM_CLEARCOLOR:
        if (!c->clear_color_type && (s->clear_color_type || NEQ(c->clear_color, s->clear_color))) {
            tsr_call_ClearColor(x->d, c->clear_color[0], c->clear_color[1], c->clear_color[2], c->clear_color[3]);
            SYNC(s->clear_color, c->clear_color);
            s->clear_color_type = 0;
            emitted(x);
        } else if (c->clear_color_type &&
                   (s->clear_color_type != c->clear_color_type || NEQ(c->clear_color_int, s->clear_color_int))) {
            const GLuint *v = c->clear_color_int;
            if (c->clear_color_type == GL_INT)
                tsr_call_ClearColorIiEXT(x->d, (GLint)v[0], (GLint)v[1], (GLint)v[2], (GLint)v[3]);
            else
                tsr_call_ClearColorIuiEXT(x->d, v[0], v[1], v[2], v[3]);
            SYNC(s->clear_color_int, c->clear_color_int);
            s->clear_color_type = c->clear_color_type;
            emitted(x);
        }
        break;
    case TSR_SM_DRAWBUFFER:
        if (c->draw_buffer && c->draw_buffer != s->draw_buffer) {
            tsr_call_DrawBuffer(x->d, ST_BUFFER_OF(c->draw_buffer));
            s->draw_buffer = c->draw_buffer;
            emitted(x);
        }
        if (c->read_buffer && c->read_buffer != s->read_buffer) {
            tsr_call_ReadBuffer(x->d, ST_BUFFER_OF(c->read_buffer));
            s->read_buffer = c->read_buffer;
            emitted(x);
        }
        break;
    case TSR_SM_CLEARACCUM:
        if (NEQ(c->clear_accum, s->clear_accum)) {
            tsr_call_ClearAccum(x->d, c->clear_accum[0], c->clear_accum[1], c->clear_accum[2], c->clear_accum[3]);
            SYNC(s->clear_accum, c->clear_accum);
            emitted(x);
        }
        break;
    default: break;
    }
}

void diff_depth(dctx *x)
{
    tsr_state_values *c = &x->c->v, *s = &x->s->v;
    if (c->depth_func != s->depth_func) {
        tsr_call_DepthFunc(x->d, c->depth_func);
        s->depth_func = c->depth_func;
        emitted(x);
    }
    if (c->depth_mask != s->depth_mask) {
        tsr_call_DepthMask(x->d, c->depth_mask);
        s->depth_mask = c->depth_mask;
        emitted(x);
    }
    if (NEQ(c->clear_depth, s->clear_depth)) {
        tsr_call_ClearDepth(x->d, c->clear_depth);
        s->clear_depth = c->clear_depth;
        emitted(x);
    }
}

void diff_stencil(dctx *x)
{
    tsr_state_values *c = &x->c->v, *s = &x->s->v;
    static const GLenum face_enum[2] = {GL_FRONT, GL_BACK};
    int fsame = c->stencil_func[0] == c->stencil_func[1] && c->stencil_ref[0] == c->stencil_ref[1] &&
                c->stencil_value_mask[0] == c->stencil_value_mask[1];
    for (int f = 0; f < 2; f++) {
        if (c->stencil_func[f] == s->stencil_func[f] && c->stencil_ref[f] == s->stencil_ref[f] &&
            c->stencil_value_mask[f] == s->stencil_value_mask[f])
            continue;
        if (fsame) {
            tsr_call_StencilFunc(x->d, c->stencil_func[0], c->stencil_ref[0], c->stencil_value_mask[0]);
            for (int g = 0; g < 2; g++) {
                s->stencil_func[g] = c->stencil_func[g];
                s->stencil_ref[g] = c->stencil_ref[g];
                s->stencil_value_mask[g] = c->stencil_value_mask[g];
            }
        } else {
            tsr_call_StencilFuncSeparate(x->d, face_enum[f], c->stencil_func[f], c->stencil_ref[f],
                                         c->stencil_value_mask[f]);
            s->stencil_func[f] = c->stencil_func[f];
            s->stencil_ref[f] = c->stencil_ref[f];
            s->stencil_value_mask[f] = c->stencil_value_mask[f];
        }
        emitted(x);
    }
    int osame = c->stencil_fail[0] == c->stencil_fail[1] && c->stencil_zfail[0] == c->stencil_zfail[1] &&
                c->stencil_zpass[0] == c->stencil_zpass[1];
    for (int f = 0; f < 2; f++) {
        if (c->stencil_fail[f] == s->stencil_fail[f] && c->stencil_zfail[f] == s->stencil_zfail[f] &&
            c->stencil_zpass[f] == s->stencil_zpass[f])
            continue;
        if (osame) {
            tsr_call_StencilOp(x->d, c->stencil_fail[0], c->stencil_zfail[0], c->stencil_zpass[0]);
            for (int g = 0; g < 2; g++) {
                s->stencil_fail[g] = c->stencil_fail[g];
                s->stencil_zfail[g] = c->stencil_zfail[g];
                s->stencil_zpass[g] = c->stencil_zpass[g];
            }
        } else {
            tsr_call_StencilOpSeparate(x->d, face_enum[f], c->stencil_fail[f], c->stencil_zfail[f],
                                       c->stencil_zpass[f]);
            s->stencil_fail[f] = c->stencil_fail[f];
            s->stencil_zfail[f] = c->stencil_zfail[f];
            s->stencil_zpass[f] = c->stencil_zpass[f];
        }
        emitted(x);
    }
    for (int f = 0; f < 2; f++) {
        if (c->stencil_writemask[f] == s->stencil_writemask[f])
            continue;
        if (c->stencil_writemask[0] == c->stencil_writemask[1]) {
            tsr_call_StencilMask(x->d, c->stencil_writemask[0]);
            s->stencil_writemask[0] = s->stencil_writemask[1] = c->stencil_writemask[0];
        } else {
            tsr_call_StencilMaskSeparate(x->d, face_enum[f], c->stencil_writemask[f]);
            s->stencil_writemask[f] = c->stencil_writemask[f];
        }
        emitted(x);
    }
    if (c->clear_stencil != s->clear_stencil) {
        tsr_call_ClearStencil(x->d, c->clear_stencil);
        s->clear_stencil = c->clear_stencil;
        emitted(x);
    }
}

static void fogf(dctx *x, GLenum pname, GLfloat *dst, GLfloat val)
{
    if (NEQ(*dst, val)) {
        tsr_call_Fogf(x->d, pname, val);
        *dst = val;
        emitted(x);
    }
}

static void fogi(dctx *x, GLenum pname, GLenum *dst, GLenum val)
{
    if (*dst != val) {
        tsr_call_Fogi(x->d, pname, (GLint)val);
        *dst = val;
        emitted(x);
    }
}

void diff_fog(dctx *x)
{
    tsr_state_values *c = &x->c->v, *s = &x->s->v;
    fogi(x, GL_FOG_MODE, &s->fog_mode, c->fog_mode);
    fogi(x, GL_FOG_COORD_SRC, &s->fog_coord_src, c->fog_coord_src);
    fogf(x, GL_FOG_DENSITY, &s->fog_density, c->fog_density);
    fogf(x, GL_FOG_START, &s->fog_start, c->fog_start);
    fogf(x, GL_FOG_END, &s->fog_end, c->fog_end);
    fogf(x, GL_FOG_INDEX, &s->fog_index, c->fog_index);
    if (NEQ(c->fog_color, s->fog_color)) {
        tsr_call_Fogfv(x->d, GL_FOG_COLOR, c->fog_color);
        SYNC(s->fog_color, c->fog_color);
        emitted(x);
    }
}

static void lightv(dctx *x, GLenum l, GLenum pname, GLfloat *dst, const GLfloat *src, size_t n)
{
    if (memcmp(dst, src, n * sizeof *src) == 0)
        return;
    tsr_call_Lightfv(x->d, l, pname, src);
    memcpy(dst, src, n * sizeof *src);
    emitted(x);
}

static void d_light(dctx *x, int i)
{
    tsr_state_light *c = &x->c->v.light[i], *s = &x->s->v.light[i];
    GLenum l = GL_LIGHT0 + (GLenum)i;
    lightv(x, l, GL_AMBIENT, s->ambient, c->ambient, 4);
    lightv(x, l, GL_DIFFUSE, s->diffuse, c->diffuse, 4);
    lightv(x, l, GL_SPECULAR, s->specular, c->specular, 4);
    if (NEQ(c->position, s->position) || NEQ(c->spot_direction, s->spot_direction)) {
        diff_eye_begin(x);
        lightv(x, l, GL_POSITION, s->position, c->position, 4);
        lightv(x, l, GL_SPOT_DIRECTION, s->spot_direction, c->spot_direction, 3);
        diff_eye_end(x);
    }
    lightv(x, l, GL_SPOT_EXPONENT, &s->spot_exponent, &c->spot_exponent, 1);
    lightv(x, l, GL_SPOT_CUTOFF, &s->spot_cutoff, &c->spot_cutoff, 1);
    lightv(x, l, GL_CONSTANT_ATTENUATION, &s->attenuation[0], &c->attenuation[0], 1);
    lightv(x, l, GL_LINEAR_ATTENUATION, &s->attenuation[1], &c->attenuation[1], 1);
    lightv(x, l, GL_QUADRATIC_ATTENUATION, &s->attenuation[2], &c->attenuation[2], 1);
}

void diff_lighting(dctx *x, int m)
{
    tsr_state_values *c = &x->c->v, *s = &x->s->v;
    if (m >= TSR_SM_LIGHT0 && m < TSR_SM_LIGHT0 + TSR_STATE_LIGHTS) {
        d_light(x, m - TSR_SM_LIGHT0);
    } else if (m == TSR_SM_LIGHTMODEL) {
        if (NEQ(c->model_ambient, s->model_ambient)) {
            tsr_call_LightModelfv(x->d, GL_LIGHT_MODEL_AMBIENT, c->model_ambient);
            SYNC(s->model_ambient, c->model_ambient);
            emitted(x);
        }
        if (c->model_local_viewer != s->model_local_viewer) {
            tsr_call_LightModeli(x->d, GL_LIGHT_MODEL_LOCAL_VIEWER, c->model_local_viewer);
            s->model_local_viewer = c->model_local_viewer;
            emitted(x);
        }
        if (c->model_two_side != s->model_two_side) {
            tsr_call_LightModeli(x->d, GL_LIGHT_MODEL_TWO_SIDE, c->model_two_side);
            s->model_two_side = c->model_two_side;
            emitted(x);
        }
        if (c->model_color_control != s->model_color_control) {
            tsr_call_LightModeli(x->d, GL_LIGHT_MODEL_COLOR_CONTROL, (GLint)c->model_color_control);
            s->model_color_control = c->model_color_control;
            emitted(x);
        }
    } else if (m == TSR_SM_COLORMATERIAL) {
        if (c->color_material_face != s->color_material_face || c->color_material_mode != s->color_material_mode) {
            tsr_call_ColorMaterial(x->d, c->color_material_face, c->color_material_mode);
            s->color_material_face = c->color_material_face;
            s->color_material_mode = c->color_material_mode;
            emitted(x);
            if (st_color_material_apply(s)) {
                st_mark_one(x->c, TSR_SM_MATERIAL, x->s->id);
                x->changed[TSR_SM_MATERIAL >> 6] |= 1ull << (TSR_SM_MATERIAL & 63);
            }
        }
    } else if (m == TSR_SM_MATERIAL) {
        static const GLenum props[5] = {GL_AMBIENT, GL_DIFFUSE, GL_SPECULAR, GL_EMISSION, GL_SHININESS};
        static const GLenum face_enum[2] = {GL_FRONT, GL_BACK};
        for (int p = 0; p < 5; p++) {
            size_t off = p == 0   ? offsetof(tsr_state_material, ambient)
                         : p == 1 ? offsetof(tsr_state_material, diffuse)
                         : p == 2 ? offsetof(tsr_state_material, specular)
                         : p == 3 ? offsetof(tsr_state_material, emission)
                                  : offsetof(tsr_state_material, shininess);
            size_t n = p == 4 ? sizeof(GLfloat) : 4 * sizeof(GLfloat);
            const GLfloat *cv[2], *sv[2];
            for (int f = 0; f < 2; f++) {
                cv[f] = (const GLfloat *)((const char *)&c->material[f] + off);
                sv[f] = (const GLfloat *)((const char *)&s->material[f] + off);
            }
            int differ0 = memcmp(cv[0], sv[0], n) != 0, differ1 = memcmp(cv[1], sv[1], n) != 0;
            if (!differ0 && !differ1)
                continue;
            if (differ0 && differ1 && memcmp(cv[0], cv[1], n) == 0) {
                tsr_call_Materialfv(x->d, GL_FRONT_AND_BACK, props[p], cv[0]);
                emitted(x);
            } else {
                for (int f = 0; f < 2; f++)
                    if (f == 0 ? differ0 : differ1) {
                        tsr_call_Materialfv(x->d, face_enum[f], props[p], cv[f]);
                        emitted(x);
                    }
            }
            /* The renderer ignores glMaterial for what glColor drives. */
            for (int f = 0; f < 2; f++)
                if (!st_tracked_by_color(s, f, props[p]))
                    memcpy((void *)sv[f], cv[f], n);
        }
    } else if (m == TSR_SM_SHADEMODEL && c->shade_model != s->shade_model) {
        tsr_call_ShadeModel(x->d, c->shade_model);
        s->shade_model = c->shade_model;
        emitted(x);
    }
}

static void pointf(dctx *x, GLenum pname, GLfloat *dst, GLfloat val)
{
    if (NEQ(*dst, val)) {
        tsr_call_PointParameterf(x->d, pname, val);
        *dst = val;
        emitted(x);
    }
}

void diff_raster(dctx *x, int m)
{
    tsr_state_values *c = &x->c->v, *s = &x->s->v;
    if (m == TSR_SM_POLYGON) {
        if (NEQ(c->polygon_mode, s->polygon_mode)) {
            if (c->polygon_mode[0] == c->polygon_mode[1]) {
                tsr_call_PolygonMode(x->d, GL_FRONT_AND_BACK, c->polygon_mode[0]);
                emitted(x);
            } else {
                for (int f = 0; f < 2; f++)
                    if (c->polygon_mode[f] != s->polygon_mode[f]) {
                        tsr_call_PolygonMode(x->d, f ? GL_BACK : GL_FRONT, c->polygon_mode[f]);
                        emitted(x);
                    }
            }
            SYNC(s->polygon_mode, c->polygon_mode);
        }
        if (c->cull_face_mode != s->cull_face_mode) {
            tsr_call_CullFace(x->d, c->cull_face_mode);
            s->cull_face_mode = c->cull_face_mode;
            emitted(x);
        }
        if (c->front_face != s->front_face) {
            tsr_call_FrontFace(x->d, c->front_face);
            s->front_face = c->front_face;
            emitted(x);
        }
        if (NEQ(c->offset_factor, s->offset_factor) || NEQ(c->offset_units, s->offset_units)) {
            tsr_call_PolygonOffset(x->d, c->offset_factor, c->offset_units);
            s->offset_factor = c->offset_factor;
            s->offset_units = c->offset_units;
            emitted(x);
        }
    } else if (m == TSR_SM_STIPPLE && NEQ(c->polygon_stipple, s->polygon_stipple)) {
        diff_sel_unpack_tight(x, 0, 0);
        tsr_call_PolygonStipple(x->d, c->polygon_stipple);
        SYNC(s->polygon_stipple, c->polygon_stipple);
        emitted(x);
    } else if (m == TSR_SM_LINE) {
        if (NEQ(c->line_width, s->line_width)) {
            tsr_call_LineWidth(x->d, c->line_width);
            s->line_width = c->line_width;
            emitted(x);
        }
        if (c->line_stipple_factor != s->line_stipple_factor || c->line_stipple_pattern != s->line_stipple_pattern) {
            tsr_call_LineStipple(x->d, c->line_stipple_factor, c->line_stipple_pattern);
            s->line_stipple_factor = c->line_stipple_factor;
            s->line_stipple_pattern = c->line_stipple_pattern;
            emitted(x);
        }
    } else if (m == TSR_SM_POINT) {
        if (NEQ(c->point_size, s->point_size)) {
            tsr_call_PointSize(x->d, c->point_size);
            s->point_size = c->point_size;
            emitted(x);
        }
        pointf(x, GL_POINT_SIZE_MIN, &s->point_min, c->point_min);
        if (c->point_max >= 0.0f)
            pointf(x, GL_POINT_SIZE_MAX, &s->point_max, c->point_max);
        pointf(x, GL_POINT_FADE_THRESHOLD_SIZE, &s->point_fade, c->point_fade);
        if (NEQ(c->point_attenuation, s->point_attenuation)) {
            tsr_call_PointParameterfv(x->d, GL_POINT_DISTANCE_ATTENUATION, c->point_attenuation);
            SYNC(s->point_attenuation, c->point_attenuation);
            emitted(x);
        }
        if (c->point_sprite_origin != s->point_sprite_origin) {
            tsr_call_PointParameteri(x->d, GL_POINT_SPRITE_COORD_ORIGIN, (GLint)c->point_sprite_origin);
            s->point_sprite_origin = c->point_sprite_origin;
            emitted(x);
        }
    }
}

void diff_hint(dctx *x)
{
    static const GLenum targets[8] = {
        GL_PERSPECTIVE_CORRECTION_HINT,
        GL_POINT_SMOOTH_HINT,
        GL_LINE_SMOOTH_HINT,
        GL_POLYGON_SMOOTH_HINT,
        GL_FOG_HINT,
        GL_GENERATE_MIPMAP_HINT,
        GL_TEXTURE_COMPRESSION_HINT,
        GL_FRAGMENT_SHADER_DERIVATIVE_HINT,
    };
    for (int i = 0; i < 8; i++)
        if (x->c->v.hint[i] != x->s->v.hint[i]) {
            tsr_call_Hint(x->d, targets[i], x->c->v.hint[i]);
            x->s->v.hint[i] = x->c->v.hint[i];
            emitted(x);
        }
}
