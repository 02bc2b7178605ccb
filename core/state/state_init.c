/* core/state/state_init.c — life cycle: trackers, tracked contexts and
 * renderer shadows created and destroyed, the initial values GL gives a new
 * context, and the read-only accessors of tessera/dev/state.h.
 *
 * Owns: the allocations of a tracker (its context and shadow arrays, the
 * renderer ids and the width of the dirty-bit vectors, which grow with the
 * ids) and of each context (bits, attribute stacks).
 *
 * Never: guesses what only the window system knows (the initial viewport,
 * scissor box, draw buffer, maximum point size): those start unknown, so
 * gets go to a renderer and diffs send nothing until the application or
 * the window sets them. */
#include "state_internal.h"

#include <stdlib.h>
#include <string.h>

/* --- initial values ------------------------------------------------------------ */
static void values_init(tsr_state_values *v)
{
    memset(v, 0, sizeof *v);
    st_set4(v->color, 1, 1, 1, 1);
    v->normal[2] = 1.0f;
    for (int u = 0; u < TSR_STATE_UNITS; u++)
        v->texcoord[u][3] = 1.0f;
    for (int i = 0; i < TSR_STATE_ATTRIBS; i++)
        v->attrib[i][3] = 1.0f;
    v->edge_flag = GL_TRUE;
    v->enables[0] = (1ull << ST_EN_DITHER) | (1ull << ST_EN_MULTISAMPLE);
    /* The viewport and scissor box start at the window's size, which only
     * the window system knows: -1 width = unknown (gets go to the
     * renderer, diffs send nothing until the application sets them). */
    v->viewport[2] = v->viewport[3] = -1;
    v->scissor[2] = v->scissor[3] = -1;
    v->depth_range[1] = 1.0;
    v->blend_src_rgb = v->blend_src_alpha = GL_ONE;
    v->blend_dst_rgb = v->blend_dst_alpha = GL_ZERO;
    v->blend_eq_rgb = v->blend_eq_alpha = GL_FUNC_ADD;
    v->alpha_func = GL_ALWAYS;
    v->logic_op = GL_COPY;
    v->color_mask[0] = v->color_mask[1] = v->color_mask[2] = v->color_mask[3] = GL_TRUE;
    /* draw/read buffer 0: the window system's default (GL_BACK or GL_FRONT
     * depending on the visual), unknown here. */
    v->depth_func = GL_LESS;
    v->depth_mask = GL_TRUE;
    v->clear_depth = 1.0;
    for (int f = 0; f < 2; f++) {
        v->stencil_func[f] = GL_ALWAYS;
        v->stencil_value_mask[f] = v->stencil_writemask[f] = ~0u;
        v->stencil_fail[f] = v->stencil_zfail[f] = v->stencil_zpass[f] = GL_KEEP;
    }
    v->fog_mode = GL_EXP;
    v->fog_coord_src = GL_FRAGMENT_DEPTH;
    v->fog_density = 1.0f;
    v->fog_end = 1.0f;
    for (int i = 0; i < TSR_STATE_LIGHTS; i++) {
        tsr_state_light *l = &v->light[i];
        st_set4(l->ambient, 0, 0, 0, 1);
        if (i == 0) {
            st_set4(l->diffuse, 1, 1, 1, 1);
            st_set4(l->specular, 1, 1, 1, 1);
        } else {
            st_set4(l->diffuse, 0, 0, 0, 1);
            st_set4(l->specular, 0, 0, 0, 1);
        }
        st_set4(l->position, 0, 0, 1, 0);
        l->spot_direction[2] = -1.0f;
        l->spot_cutoff = 180.0f;
        l->attenuation[0] = 1.0f;
    }
    st_set4(v->model_ambient, 0.2f, 0.2f, 0.2f, 1.0f);
    v->model_color_control = GL_SINGLE_COLOR;
    for (int f = 0; f < 2; f++) {
        tsr_state_material *m = &v->material[f];
        st_set4(m->ambient, 0.2f, 0.2f, 0.2f, 1.0f);
        st_set4(m->diffuse, 0.8f, 0.8f, 0.8f, 1.0f);
        st_set4(m->specular, 0, 0, 0, 1);
        st_set4(m->emission, 0, 0, 0, 1);
    }
    v->color_material_face = GL_FRONT_AND_BACK;
    v->color_material_mode = GL_AMBIENT_AND_DIFFUSE;
    v->shade_model = GL_SMOOTH;
    v->polygon_mode[0] = v->polygon_mode[1] = GL_FILL;
    v->cull_face_mode = GL_BACK;
    v->front_face = GL_CCW;
    memset(v->polygon_stipple, 0xff, sizeof v->polygon_stipple);
    v->line_width = 1.0f;
    v->line_stipple_factor = 1;
    v->line_stipple_pattern = 0xffff;
    v->point_size = 1.0f;
    v->point_max = -1.0f; /* implementation's maximum: unknown here */
    v->point_fade = 1.0f;
    v->point_attenuation[0] = 1.0f;
    v->point_sprite_origin = GL_UPPER_LEFT;
    for (int i = 0; i < 8; i++)
        v->hint[i] = GL_DONT_CARE;
    tsr_pixel_store_init(&v->pixel_store);
    v->zoom[0] = v->zoom[1] = 1.0f;
    for (int i = 0; i < 5; i++)
        v->transfer_scale[i] = 1.0f;
    for (int u = 0; u < TSR_STATE_UNITS; u++) {
        tsr_state_texunit *t = &v->unit[u];
        t->env_mode = GL_MODULATE;
        t->combine_rgb = t->combine_alpha = GL_MODULATE;
        t->src_rgb[0] = t->src_alpha[0] = GL_TEXTURE;
        t->src_rgb[1] = t->src_alpha[1] = GL_PREVIOUS;
        t->src_rgb[2] = t->src_alpha[2] = GL_CONSTANT;
        t->operand_rgb[0] = t->operand_rgb[1] = GL_SRC_COLOR;
        t->operand_rgb[2] = GL_SRC_ALPHA;
        t->operand_alpha[0] = t->operand_alpha[1] = t->operand_alpha[2] = GL_SRC_ALPHA;
        t->rgb_scale = t->alpha_scale = 1.0f;
        for (int g = 0; g < 4; g++)
            t->gen[g].mode = GL_EYE_LINEAR;
        t->gen[0].object_plane[0] = t->gen[0].eye_plane[0] = 1.0f;
        t->gen[1].object_plane[1] = t->gen[1].eye_plane[1] = 1.0f;
    }
    v->sample_coverage_value = 1.0f;
    v->matrix_mode = GL_MODELVIEW;
}

static void client_init(tsr_state_client *c)
{
    memset(c, 0, sizeof *c);
    tsr_state_array *all[] = {&c->vertex,          &c->normal,    &c->color, &c->edge_flag,
                              &c->secondary_color, &c->fog_coord, &c->index};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        all[i]->type = GL_FLOAT;
    c->secondary_color.size = 3;
    c->fog_coord.size = 1;
    c->index.size = 1;
    c->vertex.size = 4;
    c->normal.size = 3;
    c->color.size = 4;
    c->edge_flag.size = 1;
    for (int u = 0; u < TSR_STATE_UNITS; u++) {
        c->texcoord[u].size = 4;
        c->texcoord[u].type = GL_FLOAT;
    }
    for (int i = 0; i < TSR_STATE_ATTRIBS; i++) {
        c->attrib[i].size = 4;
        c->attrib[i].type = GL_FLOAT;
    }
    tsr_pixel_store_init(&c->pixel_store);
}

/* Re-lays every context's bits out for `words` words per node. */
static int grow_words(tsr_state_tracker *t, size_t words)
{
    for (size_t i = 0; i < t->nctxs; i++) {
        tsr_state_ctx *c = t->ctxs[i];
        uint64_t *n = calloc((size_t)ST_NODES * words, sizeof *n);
        if (!n)
            return -1;
        for (size_t k = 0; k < ST_NODES; k++)
            memcpy(n + k * words, c->dirty + k * t->words, t->words * sizeof *n);
        free(c->dirty);
        c->dirty = n;
    }
    t->words = words;
    return 0;
}

/* --- life cycle ---------------------------------------------------------------- */
tsr_state_tracker *tsr_state_tracker_create(tsr_error *err)
{
    tsr_state_tracker *t = calloc(1, sizeof *t);
    if (!t) {
        tsr_error_set(err, TSR_ENOMEM, "state: out of memory");
        return NULL;
    }
    t->words = 1;
    t->next_uid = 1;
    t->image_units = TSR_STATE_IMAGE_UNITS;
    /* Members are declared group by group (state.h), so each group is a
     * contiguous range. */
    int m = 0;
    for (int g = 0; g <= TSR_SG_COUNT; g++) {
        while (m < TSR_SM_COUNT && st_member_group[m] < g)
            m++;
        t->group_first[g] = (uint8_t)m;
    }
    return t;
}

void tsr_state_tracker_destroy(tsr_state_tracker *t)
{
    if (!t)
        return;
    while (t->nctxs)
        tsr_state_ctx_destroy(t->ctxs[t->nctxs - 1]);
    for (size_t i = 0; i < t->nshadows; i++)
        if (t->shadows[i])
            tsr_state_shadow_destroy(t->shadows[i]);
    free(t->ctxs);
    free(t->shadows);
    free(t);
}

tsr_state_ctx *tsr_state_ctx_create(tsr_state_tracker *t, tsr_error *err)
{
    tsr_state_ctx *c = calloc(1, sizeof *c);
    if (c) {
        c->dirty = calloc((size_t)ST_NODES * t->words, sizeof *c->dirty);
        c->attrib_stack = calloc(TSR_STATE_ATTRIB_DEPTH, sizeof *c->attrib_stack);
        c->client_stack = calloc(TSR_STATE_ATTRIB_DEPTH, sizeof *c->client_stack);
    }
    if (c && t->nctxs == t->capctxs) {
        size_t cap = t->capctxs ? t->capctxs * 2 : 4;
        tsr_state_ctx **n = realloc(t->ctxs, cap * sizeof *n);
        if (n) {
            t->ctxs = n;
            t->capctxs = cap;
        }
    }
    if (!c || !c->dirty || !c->attrib_stack || !c->client_stack || t->nctxs == t->capctxs) {
        if (c) {
            free(c->dirty);
            free(c->attrib_stack);
            free(c->client_stack);
            free(c);
        }
        tsr_error_set(err, TSR_ENOMEM, "state: out of memory for a context");
        return NULL;
    }
    c->t = t;
    values_init(&c->v);
    st_stacks_init(&c->s);
    client_init(&c->client);
    for (int i = 0; i < TSR_TEX_TARGETS; i++) {
        c->default_tex[i].target = i;
        c->default_tex[i].uid = t->next_uid++;
        st_texparams_init(&c->default_tex[i].params, i);
    }
    t->ctxs[t->nctxs++] = c;
    st_mark_all(c);
    return c;
}

void tsr_state_ctx_destroy(tsr_state_ctx *c)
{
    if (!c)
        return;
    tsr_state_tracker *t = c->t;
    for (size_t i = 0; i < t->nctxs; i++)
        if (t->ctxs[i] == c) {
            t->ctxs[i] = t->ctxs[--t->nctxs];
            break;
        }
    st_objects_free(c);
    free(c->dirty);
    free(c->attrib_stack);
    free(c->client_stack);
    free(c);
}

/* Renderer s holds GL's initial state, and every context is dirty for it. */
static void shadow_start(tsr_state_shadow *s)
{
    values_init(&s->v);
    st_stacks_init(&s->s);
    /* A fresh renderer's viewport and scissor come from its window: mark
     * them as values no application can have, so the first diff sends the
     * application's. */
    s->v.viewport[2] = s->v.viewport[3] = -2;
    s->v.scissor[2] = s->v.scissor[3] = -2;
    s->v.point_max = -2.0f;
    for (int i = 0; i < TSR_TEX_TARGETS; i++) {
        memset(&s->default_tex[i], 0, sizeof s->default_tex[i]);
        st_texparams_init(&s->default_tex[i].params, i);
    }
    for (size_t i = 0; i < s->t->nctxs; i++)
        for (int m = 0; m < TSR_SM_COUNT; m++)
            st_mark_one(s->t->ctxs[i], m, s->id);
}

tsr_state_shadow *tsr_state_shadow_create(tsr_state_tracker *t, tsr_error *err)
{
    size_t id = 0;
    while (id < t->nshadows && t->shadows[id])
        id++;
    if (id == t->nshadows) {
        tsr_state_shadow **n = realloc(t->shadows, (t->nshadows + 1) * sizeof *n);
        if (!n)
            goto oom;
        t->shadows = n;
        t->shadows[t->nshadows++] = NULL;
    }
    if ((id >> 6) >= t->words && grow_words(t, t->words * 2) != 0)
        goto oom;
    tsr_state_shadow *s = calloc(1, sizeof *s);
    if (!s)
        goto oom;
    s->t = t;
    s->id = (int)id;
    shadow_start(s);
    t->shadows[id] = s;
    return s;
oom:
    tsr_error_set(err, TSR_ENOMEM, "state: out of memory for a renderer");
    return NULL;
}

void tsr_state_shadow_destroy(tsr_state_shadow *s)
{
    if (!s)
        return;
    s->t->shadows[s->id] = NULL;
    st_shadow_objects_free(s);
    free(s);
}

int tsr_state_shadow_id(const tsr_state_shadow *s) { return s->id; }

void tsr_state_shadow_reset(tsr_state_shadow *s)
{
    st_shadow_objects_free(s);
    shadow_start(s);
}

const tsr_state_values *tsr_state_values_of(const tsr_state_ctx *c) { return &c->v; }
const tsr_state_stacks *tsr_state_stacks_of(const tsr_state_ctx *c) { return &c->s; }
const tsr_state_client *tsr_state_client_of(const tsr_state_ctx *c) { return &c->client; }
const GLfloat *tsr_state_modelview(const tsr_state_ctx *c) { return c->s.modelview[c->s.modelview_depth - 1]; }
const GLfloat *tsr_state_projection(const tsr_state_ctx *c) { return c->s.projection[c->s.projection_depth - 1]; }

void tsr_state_tracker_set_texture_limits(tsr_state_tracker *t, GLint max_size, GLint max_3d_size, GLint max_cube_size)
{
    t->max_tex_size[TSR_TEX_1D] = max_size;
    t->max_tex_size[TSR_TEX_2D] = max_size;
    t->max_tex_size[TSR_TEX_3D] = max_3d_size;
    t->max_tex_size[TSR_TEX_CUBE] = max_cube_size;
}

void tsr_state_tracker_set_image_units(tsr_state_tracker *t, GLint units)
{
    t->image_units = units > 0 && units < TSR_STATE_IMAGE_UNITS ? (GLuint)units : TSR_STATE_IMAGE_UNITS;
}

GLenum tsr_state_take_error(tsr_state_ctx *c)
{
    GLenum e = c->gl_error;
    c->gl_error = GL_NO_ERROR;
    return e;
}
