/* core/state/state_attrib.c — glPushAttrib/glPopAttrib: which values each
 * attribute bit saves and restores, with the texture parameters of the
 * bound textures for GL_TEXTURE_BIT.
 *
 * Owns: the server attribute stack of a tracked context.
 *
 * Never: sends a push or pop to a renderer: the tracker resolves the stack
 * itself and the diff sends the values that result. So it must restore
 * exactly what Mesa restores, including what Mesa leaves out (GL_COLOR_SUM
 * under GL_ENABLE_BIT, GL_GENERATE_MIPMAP_HINT under GL_HINT_BIT). */
#include "state_internal.h"

#include <string.h>

/* --- attribute stacks ----------------------------------------------------------- */
static void copy_enables(tsr_state_values *d, const tsr_state_values *s, const uint64_t mask[2])
{
    for (int i = 0; i < 2; i++)
        d->enables[i] = (d->enables[i] & ~mask[i]) | (s->enables[i] & mask[i]);
}

static void enable_mask(uint64_t m[2], const GLenum *caps, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        int idx = st_enable_index(caps[i], 0);
        if (idx >= 0)
            m[idx >> 6] |= 1ull << (idx & 63);
    }
}

#define COPY(f) memcpy(&d->f, &s->f, sizeof d->f)
#define ENABLES(...)                                          \
    do {                                                      \
        static const GLenum caps_[] = {__VA_ARGS__};          \
        uint64_t m_[2] = {0, 0};                              \
        enable_mask(m_, caps_, sizeof caps_ / sizeof *caps_); \
        copy_enables(d, s, m_);                               \
    } while (0)

/* Restores the groups of `mask` from s into d (glPopAttrib). */
static void attrib_restore(tsr_state_values *d, const tsr_state_values *s, GLbitfield mask)
{
    if (mask & GL_CURRENT_BIT) {
        COPY(color);
        COPY(normal);
        COPY(texcoord);
        COPY(edge_flag);
        COPY(attrib);
    }
    if (mask & GL_POINT_BIT) {
        COPY(point_size);
        COPY(point_min);
        COPY(point_max);
        COPY(point_fade);
        COPY(point_attenuation);
        COPY(point_sprite_origin);
        ENABLES(GL_POINT_SMOOTH, GL_POINT_SPRITE);
        for (int u = 0; u < TSR_STATE_UNITS; u++)
            d->unit[u].coord_replace = s->unit[u].coord_replace;
    }
    if (mask & GL_LINE_BIT) {
        COPY(line_width);
        COPY(line_stipple_factor);
        COPY(line_stipple_pattern);
        ENABLES(GL_LINE_SMOOTH, GL_LINE_STIPPLE);
    }
    if (mask & GL_POLYGON_BIT) {
        COPY(polygon_mode);
        COPY(cull_face_mode);
        COPY(front_face);
        COPY(offset_factor);
        COPY(offset_units);
        ENABLES(GL_CULL_FACE, GL_POLYGON_SMOOTH, GL_POLYGON_STIPPLE, GL_POLYGON_OFFSET_FILL, GL_POLYGON_OFFSET_LINE,
                GL_POLYGON_OFFSET_POINT);
    }
    if (mask & GL_POLYGON_STIPPLE_BIT)
        COPY(polygon_stipple);
    if (mask & GL_PIXEL_MODE_BIT) {
        COPY(zoom);
        COPY(transfer_scale);
        COPY(transfer_bias);
        COPY(index_shift);
        COPY(index_offset);
        COPY(map_color);
        COPY(map_stencil);
        COPY(read_buffer);
    }
    if (mask & GL_LIGHTING_BIT) {
        COPY(light);
        COPY(model_ambient);
        COPY(model_local_viewer);
        COPY(model_two_side);
        COPY(model_color_control);
        COPY(material);
        COPY(color_material_face);
        COPY(color_material_mode);
        COPY(shade_model);
        ENABLES(GL_LIGHTING, GL_COLOR_MATERIAL, GL_LIGHT0, GL_LIGHT1, GL_LIGHT2, GL_LIGHT3, GL_LIGHT4, GL_LIGHT5,
                GL_LIGHT6, GL_LIGHT7);
    }
    if (mask & GL_FOG_BIT) {
        COPY(fog_mode);
        COPY(fog_coord_src);
        COPY(fog_density);
        COPY(fog_start);
        COPY(fog_end);
        COPY(fog_index);
        COPY(fog_color);
        ENABLES(GL_FOG);
    }
    if (mask & GL_DEPTH_BUFFER_BIT) {
        COPY(depth_func);
        COPY(depth_mask);
        COPY(clear_depth);
        ENABLES(GL_DEPTH_TEST);
    }
    if (mask & GL_ACCUM_BUFFER_BIT)
        COPY(clear_accum);
    if (mask & GL_STENCIL_BUFFER_BIT) {
        COPY(stencil_func);
        COPY(stencil_ref);
        COPY(stencil_value_mask);
        COPY(stencil_writemask);
        COPY(stencil_fail);
        COPY(stencil_zfail);
        COPY(stencil_zpass);
        COPY(clear_stencil);
        ENABLES(GL_STENCIL_TEST);
    }
    if (mask & GL_VIEWPORT_BIT) {
        COPY(viewport);
        COPY(depth_range);
    }
    if (mask & GL_TRANSFORM_BIT) {
        COPY(matrix_mode);
        COPY(clip_plane);
        ENABLES(GL_NORMALIZE, GL_RESCALE_NORMAL, GL_CLIP_PLANE0, GL_CLIP_PLANE1, GL_CLIP_PLANE2, GL_CLIP_PLANE3,
                GL_CLIP_PLANE4, GL_CLIP_PLANE5);
    }
    if (mask & GL_ENABLE_BIT) {
        /* All but GL_COLOR_SUM, which Mesa (the renderer) does not save. */
        uint64_t keep = d->enables[0] & (1ull << ST_EN_COLOR_SUM);
        COPY(enables);
        d->enables[0] = (d->enables[0] & ~(1ull << ST_EN_COLOR_SUM)) | keep;
    }
    if (mask & GL_COLOR_BUFFER_BIT) {
        COPY(alpha_func);
        COPY(alpha_ref);
        COPY(blend_src_rgb);
        COPY(blend_dst_rgb);
        COPY(blend_src_alpha);
        COPY(blend_dst_alpha);
        COPY(blend_eq_rgb);
        COPY(blend_eq_alpha);
        COPY(blend_color);
        COPY(logic_op);
        COPY(color_mask);
        COPY(clear_color);
        COPY(clear_color_type);
        COPY(clear_color_int);
        COPY(draw_buffer);
        ENABLES(GL_ALPHA_TEST, GL_BLEND, GL_COLOR_LOGIC_OP, GL_DITHER);
    }
    if (mask & GL_HINT_BIT) {
        /* Not GL_GENERATE_MIPMAP_HINT: Mesa (the renderer) does not save it. */
        GLenum keep = d->hint[5];
        COPY(hint);
        d->hint[5] = keep;
    }
    if (mask & GL_EVAL_BIT)
        ENABLES(GL_AUTO_NORMAL, GL_MAP1_COLOR_4, GL_MAP1_INDEX, GL_MAP1_NORMAL, GL_MAP1_TEXTURE_COORD_1,
                GL_MAP1_TEXTURE_COORD_2, GL_MAP1_TEXTURE_COORD_3, GL_MAP1_TEXTURE_COORD_4, GL_MAP1_VERTEX_3,
                GL_MAP1_VERTEX_4, GL_MAP2_COLOR_4, GL_MAP2_INDEX, GL_MAP2_NORMAL, GL_MAP2_TEXTURE_COORD_1,
                GL_MAP2_TEXTURE_COORD_2, GL_MAP2_TEXTURE_COORD_3, GL_MAP2_TEXTURE_COORD_4, GL_MAP2_VERTEX_3,
                GL_MAP2_VERTEX_4);
    if (mask & GL_LIST_BIT)
        COPY(list_base);
    if (mask & GL_TEXTURE_BIT) {
        COPY(active_texture);
        /* Mesa saves every image unit's bindings, the LOD bias of the
         * coordinate units only; d's units_set holds s's (it only grows) */
        st_for_image_units (u, d, NULL) {
            memcpy(d->image[u].binding, s->image[u].binding, sizeof d->image[u].binding);
            if (u < TSR_STATE_UNITS)
                d->image[u].lod_bias = s->image[u].lod_bias;
        }
        for (int u = 0; u < TSR_STATE_UNITS; u++) {
            GLboolean keep = d->unit[u].coord_replace; /* POINT_BIT's */
            d->unit[u] = s->unit[u];
            d->unit[u].coord_replace = keep;
        }
        uint64_t m[2] = {0, ~0ull};
        copy_enables(d, s, m);
    }
    if (mask & GL_SCISSOR_BIT) {
        COPY(scissor);
        ENABLES(GL_SCISSOR_TEST);
    }
    if (mask & GL_MULTISAMPLE_BIT) {
        COPY(sample_coverage_value);
        COPY(sample_coverage_invert);
        ENABLES(GL_MULTISAMPLE, GL_SAMPLE_ALPHA_TO_COVERAGE, GL_SAMPLE_ALPHA_TO_ONE, GL_SAMPLE_COVERAGE);
    }
}
#undef COPY
#undef ENABLES

static void st_PushAttrib(void *self, GLbitfield mask)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (c->attrib_depth >= TSR_STATE_ATTRIB_DEPTH) {
        st_error(c, GL_STACK_OVERFLOW);
        return;
    }
    st_attrib_entry *e = &c->attrib_stack[c->attrib_depth++];
    e->mask = mask;
    e->v = c->v;
    if (mask & GL_TEXTURE_BIT)
        st_for_image_units (u, &c->v, NULL) {
            for (int t = 0; t < TSR_TEX_TARGETS; t++) {
                st_texobj *o = st_tex_lookup(c, c->v.image[u].binding[t], t);
                if (o)
                    e->tex_params[u][t] = o->params;
            }
        }
}

static void st_PopAttrib(void *self)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (!c->attrib_depth) {
        st_error(c, GL_STACK_UNDERFLOW);
        return;
    }
    st_attrib_entry *e = &c->attrib_stack[--c->attrib_depth];
    attrib_restore(&c->v, &e->v, e->mask);
    if (e->mask & GL_TEXTURE_BIT) /* the units whose parameters the push saved */
        st_for_image_units (u, &e->v, NULL) {
            for (int t = 0; t < TSR_TEX_TARGETS; t++) {
                st_texobj *o = st_tex_lookup(c, c->v.image[u].binding[t], t);
                if (o && memcmp(&o->params, &e->tex_params[u][t], sizeof o->params) != 0) {
                    o->params = e->tex_params[u][t];
                    st_tex_changed(c, o);
                }
            }
        }
    /* Rare: let the diff compare everything rather than track which
     * members the mask covered. */
    st_mark_all(c);
}

void st_attrib_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d)
{
#define SET(name) tsr_set_##name(d, st_##name, c)
    SET(PushAttrib);
    SET(PopAttrib);
#undef SET
}
