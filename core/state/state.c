/* core/state/state.c — the state tracker's life cycle, dirty bits and setters
 * (the tracker functions tsr_state_fill_dispatch puts in a table). Objects
 * are in state_obj.c, the diff in state_diff.c, gets in state_get.c.
 * Setters follow GL (and Mesa where GL leaves room): an invalid enum or a
 * value out of range changes nothing, as GL ignores it with an error. */
#include "state_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* --- groups and members ---------------------------------------------------- */
static const char *const group_names[TSR_SG_COUNT] = {
    "enable", "current", "viewport", "colorbuf", "depth", "stencil", "fog", "lighting",
    "raster", "hint", "texture", "buffer", "misc", "pixel", "transform", "program",
};

const char *tsr_state_group_name(int group)
{
    return group >= 0 && group < TSR_SG_COUNT ? group_names[group] : "?";
}

#define U8 TSR_STATE_UNITS
const uint8_t st_member_group[TSR_SM_COUNT] = {
    [TSR_SM_ENABLE0] = TSR_SG_ENABLE, [TSR_SM_ENABLE1] = TSR_SG_ENABLE,
    [TSR_SM_COLOR] = TSR_SG_CURRENT, [TSR_SM_NORMAL] = TSR_SG_CURRENT,
    [TSR_SM_TEXCOORD0 ... TSR_SM_TEXCOORD0 + U8 - 1] = TSR_SG_CURRENT,
    [TSR_SM_EDGEFLAG] = TSR_SG_CURRENT, [TSR_SM_ATTRIBS] = TSR_SG_CURRENT,
    [TSR_SM_VIEWPORT] = TSR_SG_VIEWPORT, [TSR_SM_DEPTHRANGE] = TSR_SG_VIEWPORT,
    [TSR_SM_SCISSOR] = TSR_SG_VIEWPORT,
    [TSR_SM_BLEND] = TSR_SG_COLORBUF, [TSR_SM_ALPHAFUNC] = TSR_SG_COLORBUF,
    [TSR_SM_LOGICOP] = TSR_SG_COLORBUF, [TSR_SM_COLORMASK] = TSR_SG_COLORBUF,
    [TSR_SM_CLEARCOLOR] = TSR_SG_COLORBUF, [TSR_SM_DRAWBUFFER] = TSR_SG_COLORBUF,
    [TSR_SM_CLEARACCUM] = TSR_SG_COLORBUF,
    [TSR_SM_DEPTH] = TSR_SG_DEPTH, [TSR_SM_STENCIL] = TSR_SG_STENCIL, [TSR_SM_FOG] = TSR_SG_FOG,
    [TSR_SM_LIGHT0 ... TSR_SM_LIGHT0 + TSR_STATE_LIGHTS - 1] = TSR_SG_LIGHTING,
    [TSR_SM_LIGHTMODEL] = TSR_SG_LIGHTING, [TSR_SM_MATERIAL] = TSR_SG_LIGHTING,
    [TSR_SM_COLORMATERIAL] = TSR_SG_LIGHTING, [TSR_SM_SHADEMODEL] = TSR_SG_LIGHTING,
    [TSR_SM_POLYGON] = TSR_SG_RASTER, [TSR_SM_STIPPLE] = TSR_SG_RASTER,
    [TSR_SM_LINE] = TSR_SG_RASTER, [TSR_SM_POINT] = TSR_SG_RASTER,
    [TSR_SM_HINT] = TSR_SG_HINT,
    [TSR_SM_TEXBIND0 ... TSR_SM_TEXBIND0 + U8 - 1] = TSR_SG_TEXTURE,
    [TSR_SM_TEXENV0 ... TSR_SM_TEXENV0 + U8 - 1] = TSR_SG_TEXTURE,
    [TSR_SM_TEXGEN0 ... TSR_SM_TEXGEN0 + U8 - 1] = TSR_SG_TEXTURE,
    [TSR_SM_BUFBIND] = TSR_SG_BUFFER,
    [TSR_SM_LISTBASE] = TSR_SG_MISC, [TSR_SM_MULTISAMPLE] = TSR_SG_MISC,
    [TSR_SM_PIXELSTORE] = TSR_SG_PIXEL, [TSR_SM_PIXELMODE] = TSR_SG_PIXEL,
    [TSR_SM_MODELVIEW] = TSR_SG_TRANSFORM, [TSR_SM_PROJECTION] = TSR_SG_TRANSFORM,
    [TSR_SM_TEXMAT0 ... TSR_SM_TEXMAT0 + U8 - 1] = TSR_SG_TRANSFORM,
    [TSR_SM_CLIP] = TSR_SG_TRANSFORM,
    [TSR_SM_PROGRAM] = TSR_SG_PROGRAM,
};

int tsr_state_member_group(int member)
{
    return member >= 0 && member < TSR_SM_COUNT ? st_member_group[member] : -1;
}

/* --- enables ---------------------------------------------------------------- */
#define EN_UNIT(u, k) [ST_EN_UNIT0 + (u)*8 + 0] = GL_TEXTURE_1D, [ST_EN_UNIT0 + (u)*8 + 1] = GL_TEXTURE_2D, \
    [ST_EN_UNIT0 + (u)*8 + 2] = GL_TEXTURE_3D, [ST_EN_UNIT0 + (u)*8 + 3] = GL_TEXTURE_CUBE_MAP, \
    [ST_EN_UNIT0 + (u)*8 + 4] = GL_TEXTURE_GEN_S, [ST_EN_UNIT0 + (u)*8 + 5] = GL_TEXTURE_GEN_T, \
    [ST_EN_UNIT0 + (u)*8 + 6] = GL_TEXTURE_GEN_R, [ST_EN_UNIT0 + (u)*8 + 7] = GL_TEXTURE_GEN_Q
const GLenum st_enable_caps[128] = {
    GL_ALPHA_TEST, GL_AUTO_NORMAL, GL_BLEND, GL_CLIP_PLANE0, GL_CLIP_PLANE1, GL_CLIP_PLANE2,
    GL_CLIP_PLANE3, GL_CLIP_PLANE4, GL_CLIP_PLANE5, GL_COLOR_LOGIC_OP, GL_COLOR_MATERIAL,
    GL_CULL_FACE, GL_DEPTH_TEST, GL_DITHER, GL_FOG, GL_LIGHT0, GL_LIGHT1, GL_LIGHT2, GL_LIGHT3,
    GL_LIGHT4, GL_LIGHT5, GL_LIGHT6, GL_LIGHT7, GL_LIGHTING, GL_LINE_SMOOTH, GL_LINE_STIPPLE,
    GL_NORMALIZE, GL_POINT_SMOOTH, GL_POLYGON_OFFSET_FILL, GL_POLYGON_OFFSET_LINE,
    GL_POLYGON_OFFSET_POINT, GL_POLYGON_SMOOTH, GL_POLYGON_STIPPLE, GL_RESCALE_NORMAL,
    GL_SCISSOR_TEST, GL_STENCIL_TEST, GL_MULTISAMPLE, GL_SAMPLE_ALPHA_TO_COVERAGE,
    GL_SAMPLE_ALPHA_TO_ONE, GL_SAMPLE_COVERAGE, GL_POINT_SPRITE, GL_VERTEX_PROGRAM_POINT_SIZE,
    GL_VERTEX_PROGRAM_TWO_SIDE, GL_COLOR_SUM,
    GL_MAP1_COLOR_4, GL_MAP1_INDEX, GL_MAP1_NORMAL, GL_MAP1_TEXTURE_COORD_1,
    GL_MAP1_TEXTURE_COORD_2, GL_MAP1_TEXTURE_COORD_3, GL_MAP1_TEXTURE_COORD_4, GL_MAP1_VERTEX_3,
    GL_MAP1_VERTEX_4, GL_MAP2_COLOR_4, GL_MAP2_INDEX, GL_MAP2_NORMAL, GL_MAP2_TEXTURE_COORD_1,
    GL_MAP2_TEXTURE_COORD_2, GL_MAP2_TEXTURE_COORD_3, GL_MAP2_TEXTURE_COORD_4, GL_MAP2_VERTEX_3,
    GL_MAP2_VERTEX_4,
    EN_UNIT(0, 0), EN_UNIT(1, 0), EN_UNIT(2, 0), EN_UNIT(3, 0),
    EN_UNIT(4, 0), EN_UNIT(5, 0), EN_UNIT(6, 0), EN_UNIT(7, 0),
};
enum { EN_COLOR_MATERIAL = 10, EN_DITHER = 13, EN_MULTISAMPLE = 36, EN_COLOR_SUM = 43 };

int st_enable_index(GLenum cap, GLuint unit)
{
    switch (cap) {
    case GL_TEXTURE_1D: return ST_EN_UNIT0 + (int)unit * 8 + 0;
    case GL_TEXTURE_2D: return ST_EN_UNIT0 + (int)unit * 8 + 1;
    case GL_TEXTURE_3D: return ST_EN_UNIT0 + (int)unit * 8 + 2;
    case GL_TEXTURE_CUBE_MAP: return ST_EN_UNIT0 + (int)unit * 8 + 3;
    case GL_TEXTURE_GEN_S: return ST_EN_UNIT0 + (int)unit * 8 + 4;
    case GL_TEXTURE_GEN_T: return ST_EN_UNIT0 + (int)unit * 8 + 5;
    case GL_TEXTURE_GEN_R: return ST_EN_UNIT0 + (int)unit * 8 + 6;
    case GL_TEXTURE_GEN_Q: return ST_EN_UNIT0 + (int)unit * 8 + 7;
    default: break;
    }
    for (int i = 0; i < ST_EN_UNIT0; i++)
        if (st_enable_caps[i] == cap)
            return i;
    return -1;
}

/* --- initial values -------------------------------------------------------------- */
static void identity(GLfloat m[16])
{
    memset(m, 0, 16 * sizeof *m);
    m[0] = m[5] = m[10] = m[15] = 1.0f;
}

/* The classification bits recipe r gives a matrix (Mesa's flags: glScale
 * is a uniform or a general scale, glOrtho a translation and a general
 * scale, a loaded matrix general). */
unsigned st_recipe_bits(const tsr_state_recipe *r)
{
    unsigned k = r->sticky | (r->base_is_identity ? 0u : TSR_STICKY_GENERAL);
    for (unsigned i = 0; i < r->count; i++) {
        const GLfloat *a = r->arg[i];
        if (r->kind[i] == TSR_RECIPE_SCALE)
            k |= fabsf(a[0] - a[1]) < 1e-8f && fabsf(a[0] - a[2]) < 1e-8f ? 1u << TSR_RECIPE_SCALE
                                                                          : TSR_STICKY_GENERAL_SCALE;
        else if (r->kind[i] == TSR_RECIPE_ORTHO)
            k |= TSR_STICKY_GENERAL_SCALE | 1u << TSR_RECIPE_TRANSLATE;
        else
            k |= 1u << r->kind[i];
    }
    return k;
}

/* A fresh matrix level: identity, no history. */
static void recipe_init(tsr_state_recipe *r)
{
    identity(r->base);
    r->base_is_identity = 1;
    r->sticky = 0;
    r->count = 0;
}

/* glLoadIdentity: the values go, the classification stays. */
static void recipe_identity(tsr_state_recipe *r)
{
    uint8_t kinds = (uint8_t)st_recipe_bits(r);
    recipe_init(r);
    r->sticky = kinds;
}

void st_values_init(tsr_state_values *v)
{
    memset(v, 0, sizeof *v);
    st_set4(v->color, 1, 1, 1, 1);
    v->normal[2] = 1.0f;
    for (int u = 0; u < TSR_STATE_UNITS; u++)
        v->texcoord[u][3] = 1.0f;
    for (int i = 0; i < TSR_STATE_ATTRIBS; i++)
        v->attrib[i][3] = 1.0f;
    v->edge_flag = GL_TRUE;
    v->enables[0] = (1ull << EN_DITHER) | (1ull << EN_MULTISAMPLE);
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
    v->point_max = -1.0f;   /* implementation's maximum: unknown here */
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

void st_stacks_init(tsr_state_stacks *s)
{
    identity(s->modelview[0]);
    identity(s->projection[0]);
    recipe_init(&s->modelview_recipe[0]);
    recipe_init(&s->projection_recipe[0]);
    s->modelview_depth = s->projection_depth = 1;
    for (int u = 0; u < TSR_STATE_UNITS; u++) {
        identity(s->texture[u][0]), recipe_init(&s->texture_recipe[u][0]);
        s->texture_depth[u] = 1;
    }
}

static void client_init(tsr_state_client *c)
{
    memset(c, 0, sizeof *c);
    tsr_state_array *all[] = {&c->vertex, &c->normal, &c->color, &c->edge_flag};
    for (size_t i = 0; i < 4; i++)
        all[i]->type = GL_FLOAT;
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

/* --- bits ------------------------------------------------------------------------ */
void st_mark_all(tsr_state_ctx *c)
{
    memset(c->dirty, 0xff, (size_t)ST_NODES * c->t->words * sizeof *c->dirty);
}

void st_mark_one(tsr_state_ctx *c, int member, int id)
{
    size_t w = c->t->words, word = (size_t)id >> 6;
    uint64_t bit = 1ull << (id & 63);
    c->dirty[(size_t)(ST_NODE_MEMBER0 + member) * w + word] |= bit;
    c->dirty[(size_t)(ST_NODE_GROUP0 + st_member_group[member]) * w + word] |= bit;
    c->dirty[word] |= bit;
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
    st_values_init(&c->v);
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

static void shadow_init(tsr_state_shadow *s)
{
    st_values_init(&s->v);
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
    shadow_init(s);
    t->shadows[id] = s;
    for (size_t i = 0; i < t->nctxs; i++)
        for (int m = 0; m < TSR_SM_COUNT; m++)
            st_mark_one(t->ctxs[i], m, s->id);
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

int tsr_state_shadow_id(const tsr_state_shadow *s)
{
    return s->id;
}

void tsr_state_shadow_reset(tsr_state_shadow *s)
{
    st_shadow_objects_free(s);
    shadow_init(s);
    for (size_t i = 0; i < s->t->nctxs; i++)
        for (int m = 0; m < TSR_SM_COUNT; m++)
            st_mark_one(s->t->ctxs[i], m, s->id);
}

const tsr_state_values *tsr_state_values_of(const tsr_state_ctx *c) { return &c->v; }
const tsr_state_stacks *tsr_state_stacks_of(const tsr_state_ctx *c) { return &c->s; }
const tsr_state_client *tsr_state_client_of(const tsr_state_ctx *c) { return &c->client; }
const GLfloat *tsr_state_modelview(const tsr_state_ctx *c) { return c->s.modelview[c->s.modelview_depth - 1]; }
const GLfloat *tsr_state_projection(const tsr_state_ctx *c) { return c->s.projection[c->s.projection_depth - 1]; }

/* --- matrices -------------------------------------------------------------------- */
/* out = a * b, column-major, summed in the order Mesa's matmul4 uses. */
void st_mat_mul(GLfloat out[16], const GLfloat a[16], const GLfloat b[16])
{
    GLfloat p[16];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            p[j * 4 + i] = a[i] * b[j * 4] + a[4 + i] * b[j * 4 + 1] + a[8 + i] * b[j * 4 + 2] +
                           a[12 + i] * b[j * 4 + 3];
    memcpy(out, p, sizeof p);
}

int st_mat_invert(GLfloat out[16], const GLfloat mf[16])
{
    double m[16], inv[16];
    for (int i = 0; i < 16; i++)
        m[i] = mf[i];
    inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] + m[9] * m[7] * m[14] + m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
    inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] - m[8] * m[7] * m[14] - m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
    inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] + m[8] * m[7] * m[13] + m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
    inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] - m[8] * m[6] * m[13] - m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
    inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] - m[9] * m[3] * m[14] - m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
    inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] + m[8] * m[3] * m[14] + m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
    inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] - m[8] * m[3] * m[13] - m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
    inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] + m[8] * m[2] * m[13] + m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
    inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] + m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
    inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] - m[4] * m[3] * m[14] - m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
    inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] + m[4] * m[3] * m[13] + m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
    inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] - m[4] * m[2] * m[13] - m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
    inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] - m[5] * m[3] * m[10] - m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
    inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] + m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
    inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] - m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
    inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] + m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
    double det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
    if (det == 0.0) {
        identity(out);
        return -1;
    }
    for (int i = 0; i < 16; i++)
        out[i] = (GLfloat)(inv[i] / det);
    return 0;
}

GLfloat *st_current_matrix(tsr_state_ctx *c, int *member)
{
    switch (c->v.matrix_mode) {
    case GL_PROJECTION:
        *member = TSR_SM_PROJECTION;
        return c->s.projection[c->s.projection_depth - 1];
    case GL_TEXTURE: {
        GLuint u = c->v.active_texture;
        *member = TSR_SM_TEXMAT0 + (int)u;
        return c->s.texture[u][c->s.texture_depth[u] - 1];
    }
    default:
        *member = TSR_SM_MODELVIEW;
        return c->s.modelview[c->s.modelview_depth - 1];
    }
}

static tsr_state_recipe *current_recipe(tsr_state_ctx *c)
{
    switch (c->v.matrix_mode) {
    case GL_PROJECTION:
        return &c->s.projection_recipe[c->s.projection_depth - 1];
    case GL_TEXTURE: {
        GLuint u = c->v.active_texture;
        return &c->s.texture_recipe[u][c->s.texture_depth[u] - 1];
    }
    default:
        return &c->s.modelview_recipe[c->s.modelview_depth - 1];
    }
}

/* The current matrix was loaded (or multiplied by an arbitrary matrix,
 * which Mesa also classifies from the values): it is the new base. */
static void recipe_rebase(tsr_state_ctx *c)
{
    int member;
    tsr_state_recipe *r = current_recipe(c);
    memcpy(r->base, st_current_matrix(c, &member), sizeof r->base);
    r->base_is_identity = 0;
    r->sticky = 0;
    r->count = 0;
}

/* Called after the operation was applied to the matrix. */
static void recipe_add(tsr_state_ctx *c, int kind, const GLfloat *args, int nargs)
{
    tsr_state_recipe *r = current_recipe(c);
    if (r->count == TSR_STATE_RECIPE_OPS) {
        recipe_rebase(c);
        return;
    }
    r->kind[r->count] = (uint8_t)kind;
    memset(r->arg[r->count], 0, sizeof r->arg[r->count]);
    memcpy(r->arg[r->count], args, (size_t)nargs * sizeof *args);
    r->count++;
}

/* --- setters ------------------------------------------------------------------- */
static void mat_apply(tsr_state_ctx *c, const GLfloat m[16])
{
    int member;
    GLfloat *top = st_current_matrix(c, &member);
    st_mat_mul(top, top, m);
    st_mark(c, member);
}

static void st_LoadIdentity(void *self)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    int member;
    identity(st_current_matrix(c, &member));
    recipe_identity(current_recipe(c));
    st_mark(c, member);
}

/* Mesa ignores a glLoadMatrix of the values the matrix already holds (it
 * keeps the matrix's classification too). */
static void load_matrix(tsr_state_ctx *c, const GLfloat m[16])
{
    int member;
    GLfloat *top = st_current_matrix(c, &member);
    if (!memcmp(top, m, 16 * sizeof *m))
        return;
    memcpy(top, m, 16 * sizeof *m);
    recipe_rebase(c);
    st_mark(c, member);
}

static void st_LoadMatrixf(void *self, const GLfloat *m)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    load_matrix(c, m);
}

/* A double matrix as GL stores it (Mesa converts each element to float). */
static void to_float16(GLfloat f[16], const GLdouble *m)
{
    for (int i = 0; i < 16; i++)
        f[i] = (GLfloat)m[i];
}

static void st_LoadMatrixd(void *self, const GLdouble *m)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLfloat f[16];
    to_float16(f, m);
    load_matrix(c, f);
}

static void transpose(GLfloat o[16], const GLfloat m[16])
{
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            o[i * 4 + j] = m[j * 4 + i];
}

static void st_LoadTransposeMatrixf(void *self, const GLfloat *m)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLfloat f[16];
    transpose(f, m);
    load_matrix(c, f);
}

/* Mesa classifies the product of an arbitrary glMultMatrix from its
 * values, as it does a loaded matrix: the product is the new base. */
static void mult_matrix(tsr_state_ctx *c, const GLfloat m[16])
{
    mat_apply(c, m);
    recipe_rebase(c);
}

static void st_MultMatrixf(void *self, const GLfloat *m)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    mult_matrix(c, m);
}

static void st_MultMatrixd(void *self, const GLdouble *m)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLfloat f[16];
    to_float16(f, m);
    mult_matrix(c, f);
}

static void st_MultTransposeMatrixf(void *self, const GLfloat *m)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLfloat f[16];
    transpose(f, m);
    mult_matrix(c, f);
}

/* Mesa's _math_matrix_translate/scale: only the affected columns change. */
static void translate(tsr_state_ctx *c, GLfloat x, GLfloat y, GLfloat z)
{
    int member;
    GLfloat *m = st_current_matrix(c, &member);
    m[12] = m[0] * x + m[4] * y + m[8] * z + m[12];
    m[13] = m[1] * x + m[5] * y + m[9] * z + m[13];
    m[14] = m[2] * x + m[6] * y + m[10] * z + m[14];
    m[15] = m[3] * x + m[7] * y + m[11] * z + m[15];
    recipe_add(c, TSR_RECIPE_TRANSLATE, (const GLfloat[]){x, y, z}, 3);
    st_mark(c, member);
}

static void scale(tsr_state_ctx *c, GLfloat x, GLfloat y, GLfloat z)
{
    int member;
    GLfloat *m = st_current_matrix(c, &member);
    for (int i = 0; i < 4; i++) {
        m[i] *= x;
        m[4 + i] *= y;
        m[8 + i] *= z;
    }
    recipe_add(c, TSR_RECIPE_SCALE, (const GLfloat[]){x, y, z}, 3);
    st_mark(c, member);
}

/* As Mesa's _math_matrix_rotate computes it, so a renderer given the
 * tracker's matrix holds the very bits it would have computed: sine and
 * cosine of the angle converted in double, rotations about one axis built
 * from them directly (no normalising, no 1 - cos terms), a near-zero axis
 * ignored. */
static void rotate(tsr_state_ctx *c, GLfloat angle, GLfloat x, GLfloat y, GLfloat z)
{
    if (angle == 0.0f)
        return; /* Mesa's glRotate leaves the matrix (and its class) alone */
    const GLfloat args[4] = {angle, x, y, z};
    GLfloat r[16];
    identity(r);
    GLfloat s = sinf((GLfloat)(angle * M_PI / 180.0)), co = cosf((GLfloat)(angle * M_PI / 180.0));
    if (x == 0.0f && y == 0.0f && z != 0.0f) {
        r[0] = co;
        r[5] = co;
        r[4] = z < 0.0f ? s : -s;
        r[1] = z < 0.0f ? -s : s;
    } else if (x == 0.0f && z == 0.0f && y != 0.0f) {
        r[0] = co;
        r[10] = co;
        r[8] = y < 0.0f ? -s : s;
        r[2] = y < 0.0f ? s : -s;
    } else if (y == 0.0f && z == 0.0f && x != 0.0f) {
        r[5] = co;
        r[10] = co;
        r[9] = x < 0.0f ? s : -s;
        r[6] = x < 0.0f ? -s : s;
    } else {
        GLfloat len = sqrtf(x * x + y * y + z * z);
        if (len <= 1.0e-4f)
            return;
        x /= len;
        y /= len;
        z /= len;
        GLfloat one_c = 1.0f - co;
        r[0] = x * x * one_c + co;
        r[4] = x * y * one_c - z * s;
        r[8] = z * x * one_c + y * s;
        r[1] = x * y * one_c + z * s;
        r[5] = y * y * one_c + co;
        r[9] = y * z * one_c - x * s;
        r[2] = z * x * one_c - y * s;
        r[6] = y * z * one_c + x * s;
        r[10] = z * z * one_c + co;
    }
    mat_apply(c, r);
    recipe_add(c, TSR_RECIPE_ROTATE, args, 4);
}

static void st_Translatef(void *self, GLfloat x, GLfloat y, GLfloat z)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    translate(c, x, y, z);
}

static void st_Translated(void *self, GLdouble x, GLdouble y, GLdouble z)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    translate(c, (GLfloat)x, (GLfloat)y, (GLfloat)z);
}

static void st_Scalef(void *self, GLfloat x, GLfloat y, GLfloat z)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    scale(c, x, y, z);
}

static void st_Scaled(void *self, GLdouble x, GLdouble y, GLdouble z)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    scale(c, (GLfloat)x, (GLfloat)y, (GLfloat)z);
}

static void st_Rotatef(void *self, GLfloat a, GLfloat x, GLfloat y, GLfloat z)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    rotate(c, a, x, y, z);
}

static void st_Rotated(void *self, GLdouble a, GLdouble x, GLdouble y, GLdouble z)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    rotate(c, (GLfloat)a, (GLfloat)x, (GLfloat)y, (GLfloat)z);
}

/* Frustum and Ortho as Mesa builds them: the double arguments converted to
 * float first and the matrix computed in float (_math_matrix_frustum /
 * _math_float_ortho), so the tracker holds the renderer's very bits (in
 * double, 2 / (r - l) can round the other way). */
static void st_Frustum(void *self, GLdouble ld, GLdouble rd, GLdouble bd, GLdouble td, GLdouble nd, GLdouble fd)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (nd <= 0 || fd <= 0 || nd == fd || ld == rd || bd == td)
        return;
    GLfloat l = (GLfloat)ld, r = (GLfloat)rd, b = (GLfloat)bd, t = (GLfloat)td, n = (GLfloat)nd, f = (GLfloat)fd;
    GLfloat m[16] = {0};
    m[0] = (2.0f * n) / (r - l);
    m[5] = (2.0f * n) / (t - b);
    m[8] = (r + l) / (r - l);
    m[9] = (t + b) / (t - b);
    m[10] = -(f + n) / (f - n);
    m[11] = -1.0f;
    m[14] = -(2.0f * f * n) / (f - n);
    mat_apply(c, m);
    recipe_add(c, TSR_RECIPE_FRUSTUM, (const GLfloat[]){l, r, b, t, n, f}, 6);
}

static void st_Ortho(void *self, GLdouble ld, GLdouble rd, GLdouble bd, GLdouble td, GLdouble nd, GLdouble fd)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (ld == rd || bd == td || nd == fd)
        return;
    GLfloat l = (GLfloat)ld, r = (GLfloat)rd, b = (GLfloat)bd, t = (GLfloat)td, n = (GLfloat)nd, f = (GLfloat)fd;
    GLfloat m[16] = {0};
    m[0] = 2.0f / (r - l);
    m[5] = 2.0f / (t - b);
    m[10] = -2.0f / (f - n);
    m[12] = -(r + l) / (r - l);
    m[13] = -(t + b) / (t - b);
    m[14] = -(f + n) / (f - n);
    m[15] = 1.0f;
    mat_apply(c, m);
    recipe_add(c, TSR_RECIPE_ORTHO, (const GLfloat[]){l, r, b, t, n, f}, 6);
}

static void st_MatrixMode(void *self, GLenum mode)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (mode != GL_MODELVIEW && mode != GL_PROJECTION && mode != GL_TEXTURE)
        return;
    c->v.matrix_mode = mode;
    st_mark(c, TSR_SM_MODELVIEW);   /* matrix mode travels with the stacks */
}

static void st_PushMatrix(void *self)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    int member;
    st_current_matrix(c, &member);
    uint32_t *depth, max;
    GLfloat(*stack)[16];
    if (member == TSR_SM_MODELVIEW) {
        depth = &c->s.modelview_depth, max = TSR_STATE_MODELVIEW_DEPTH, stack = c->s.modelview;
    } else if (member == TSR_SM_PROJECTION) {
        depth = &c->s.projection_depth, max = TSR_STATE_PROJECTION_DEPTH, stack = c->s.projection;
    } else {
        GLuint u = c->v.active_texture;
        depth = &c->s.texture_depth[u], max = TSR_STATE_TEXTURE_DEPTH, stack = c->s.texture[u];
    }
    if (*depth >= max)
        return;
    memcpy(stack[*depth], stack[*depth - 1], sizeof stack[0]);
    tsr_state_recipe *below = current_recipe(c);
    (*depth)++;
    *current_recipe(c) = *below;
    st_mark(c, member);
}

static void st_PopMatrix(void *self)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    int member;
    st_current_matrix(c, &member);
    uint32_t *depth = member == TSR_SM_MODELVIEW    ? &c->s.modelview_depth
                      : member == TSR_SM_PROJECTION ? &c->s.projection_depth
                                                    : &c->s.texture_depth[c->v.active_texture];
    if (*depth <= 1)
        return;
    (*depth)--;
    st_mark(c, member);
}

/* GL transforms a plane by the inverse modelview (Mesa: row vector times
 * the inverse). */
static void plane_to_eye(const tsr_state_ctx *c, GLfloat out[4], const GLfloat in[4])
{
    GLfloat inv[16];
    st_mat_invert(inv, c->s.modelview[c->s.modelview_depth - 1]);
    for (int j = 0; j < 4; j++)
        out[j] = in[0] * inv[4 * j] + in[1] * inv[4 * j + 1] + in[2] * inv[4 * j + 2] + in[3] * inv[4 * j + 3];
}

static void st_ClipPlane(void *self, GLenum plane, const GLdouble *eq)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (plane < GL_CLIP_PLANE0 || plane >= GL_CLIP_PLANE0 + TSR_STATE_CLIP_PLANES)
        return;
    GLfloat f[4] = {(GLfloat)eq[0], (GLfloat)eq[1], (GLfloat)eq[2], (GLfloat)eq[3]};
    plane_to_eye(c, c->v.clip_plane[plane - GL_CLIP_PLANE0], f);
    st_mark(c, TSR_SM_CLIP);
}

/* --- current attributes -------------------------------------------------------- */
static void color_material_update(tsr_state_ctx *c)
{
    if (st_color_material_apply(&c->v))
        st_mark(c, TSR_SM_MATERIAL);
}

int st_color_material_apply(tsr_state_values *v)
{
    if (!st_enabled(v, EN_COLOR_MATERIAL))
        return 0;
    for (int f = 0; f < 2; f++) {
        if ((f == 0 && v->color_material_face == GL_BACK) || (f == 1 && v->color_material_face == GL_FRONT))
            continue;
        tsr_state_material *m = &v->material[f];
        switch (v->color_material_mode) {
        case GL_AMBIENT: memcpy(m->ambient, v->color, 16); break;
        case GL_DIFFUSE: memcpy(m->diffuse, v->color, 16); break;
        case GL_SPECULAR: memcpy(m->specular, v->color, 16); break;
        case GL_EMISSION: memcpy(m->emission, v->color, 16); break;
        case GL_AMBIENT_AND_DIFFUSE:
            memcpy(m->ambient, v->color, 16);
            memcpy(m->diffuse, v->color, 16);
            break;
        default: break;
        }
    }
    return 1;
}

void st_cur_color(void *self, GLfloat r, GLfloat g, GLfloat b, GLfloat a)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    st_set4(c->v.color, r, g, b, a);
    st_mark(c, TSR_SM_COLOR);
    color_material_update(c);
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

/* --- enables ------------------------------------------------------------------------ */
static void set_enable(tsr_state_ctx *c, GLenum cap, int on)
{
    int idx = st_enable_index(cap, c->v.active_texture);
    if (idx < 0)
        return;
    uint64_t bit = 1ull << (idx & 63), *w = &c->v.enables[idx >> 6];
    if (((*w & bit) != 0) == (on != 0))
        return;
    *w = on ? (*w | bit) : (*w & ~bit);
    st_mark(c, TSR_SM_ENABLE0 + (idx >> 6));
    if (idx == EN_COLOR_MATERIAL && on)
        color_material_update(c);
}

static void st_Enable(void *self, GLenum cap)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    set_enable(c, cap, 1);
}

static void st_Disable(void *self, GLenum cap)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    set_enable(c, cap, 0);
}

/* --- viewport ---------------------------------------------------------------------- */
static void st_Viewport(void *self, GLint x, GLint y, GLsizei w, GLsizei h)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (w < 0 || h < 0)
        return;
    GLint v[4] = {x, y, w, h};
    memcpy(c->v.viewport, v, sizeof v);
    st_mark(c, TSR_SM_VIEWPORT);
}

static void st_Scissor(void *self, GLint x, GLint y, GLsizei w, GLsizei h)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (w < 0 || h < 0)
        return;
    GLint v[4] = {x, y, w, h};
    memcpy(c->v.scissor, v, sizeof v);
    st_mark(c, TSR_SM_SCISSOR);
}

static void st_DepthRange(void *self, GLdouble n, GLdouble f)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.depth_range[0] = st_clampd(n);
    c->v.depth_range[1] = st_clampd(f);
    st_mark(c, TSR_SM_DEPTHRANGE);
}

/* The window system sized the window: like the render SPU (and a window
 * system making a context current the first time), an unknown viewport and
 * scissor box become the window. */
static void window_size(tsr_state_ctx *c, GLsizei w, GLsizei h)
{
    if (c->v.viewport[2] < 0 && w > 0 && h > 0) {
        GLint v[4] = {0, 0, w, h};
        memcpy(c->v.viewport, v, sizeof v);
        memcpy(c->v.scissor, v, sizeof v);
        st_mark(c, TSR_SM_VIEWPORT);
        st_mark(c, TSR_SM_SCISSOR);
    }
}

/* Also glWindowCreateTSR's: a new window has its size. */
static void st_WindowSizeTSR(void *self, GLint window, GLsizei w, GLsizei h)
{
    (void)window;
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    window_size(c, w, h);
}

/* --- color buffer ------------------------------------------------------------------- */
static void st_BlendFunc(void *self, GLenum s, GLenum d)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.blend_src_rgb = c->v.blend_src_alpha = s;
    c->v.blend_dst_rgb = c->v.blend_dst_alpha = d;
    st_mark(c, TSR_SM_BLEND);
}

static void st_BlendFuncSeparate(void *self, GLenum sr, GLenum dr, GLenum sa, GLenum da)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.blend_src_rgb = sr;
    c->v.blend_dst_rgb = dr;
    c->v.blend_src_alpha = sa;
    c->v.blend_dst_alpha = da;
    st_mark(c, TSR_SM_BLEND);
}

static void st_BlendEquation(void *self, GLenum mode)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.blend_eq_rgb = c->v.blend_eq_alpha = mode;
    st_mark(c, TSR_SM_BLEND);
}

static void st_BlendEquationSeparate(void *self, GLenum rgb, GLenum alpha)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.blend_eq_rgb = rgb;
    c->v.blend_eq_alpha = alpha;
    st_mark(c, TSR_SM_BLEND);
}

static void st_BlendColor(void *self, GLfloat r, GLfloat g, GLfloat b, GLfloat a)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    st_set4(c->v.blend_color, r, g, b, a);
    st_mark(c, TSR_SM_BLEND);
}

static void st_AlphaFunc(void *self, GLenum func, GLfloat ref)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.alpha_func = func;
    c->v.alpha_ref = st_clampf(ref);
    st_mark(c, TSR_SM_ALPHAFUNC);
}

static void st_LogicOp(void *self, GLenum op)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.logic_op = op;
    st_mark(c, TSR_SM_LOGICOP);
}

static void st_ColorMask(void *self, GLboolean r, GLboolean g, GLboolean b, GLboolean a)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.color_mask[0] = r ? GL_TRUE : GL_FALSE;
    c->v.color_mask[1] = g ? GL_TRUE : GL_FALSE;
    c->v.color_mask[2] = b ? GL_TRUE : GL_FALSE;
    c->v.color_mask[3] = a ? GL_TRUE : GL_FALSE;
    st_mark(c, TSR_SM_COLORMASK);
}

static void st_ClearColor(void *self, GLfloat r, GLfloat g, GLfloat b, GLfloat a)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    st_set4(c->v.clear_color, r, g, b, a);
    st_mark(c, TSR_SM_CLEARCOLOR);
}

static void st_ClearAccum(void *self, GLfloat r, GLfloat g, GLfloat b, GLfloat a)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    st_set4(c->v.clear_accum, r, g, b, a);
    st_mark(c, TSR_SM_CLEARACCUM);
}

static void st_DrawBuffer(void *self, GLenum buf)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.draw_buffer = buf;
    st_mark(c, TSR_SM_DRAWBUFFER);
}

static void st_DrawBuffers(void *self, GLsizei n, const GLenum *bufs)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (n >= 1) {
        c->v.draw_buffer = bufs[0];
        st_mark(c, TSR_SM_DRAWBUFFER);
    }
}

static void st_ReadBuffer(void *self, GLenum buf)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.read_buffer = buf;
    st_mark(c, TSR_SM_DRAWBUFFER);
}

/* --- depth, stencil --------------------------------------------------------------- */
static void st_DepthFunc(void *self, GLenum f)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.depth_func = f;
    st_mark(c, TSR_SM_DEPTH);
}

static void st_DepthMask(void *self, GLboolean m)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.depth_mask = m ? GL_TRUE : GL_FALSE;
    st_mark(c, TSR_SM_DEPTH);
}

static void st_ClearDepth(void *self, GLdouble d)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.clear_depth = st_clampd(d);
    st_mark(c, TSR_SM_DEPTH);
}

static void st_ClearStencil(void *self, GLint s)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.clear_stencil = s;
    st_mark(c, TSR_SM_STENCIL);
}

static void stencil_func(tsr_state_ctx *c, GLenum face, GLenum func, GLint ref, GLuint mask)
{
    int a, b;
    if (!st_faces(face, &a, &b))
        return;
    for (int f = a; f <= b; f++) {
        c->v.stencil_func[f] = func;
        c->v.stencil_ref[f] = ref;
        c->v.stencil_value_mask[f] = mask;
    }
    st_mark(c, TSR_SM_STENCIL);
}

static void stencil_op(tsr_state_ctx *c, GLenum face, GLenum fail, GLenum zfail, GLenum zpass)
{
    int a, b;
    if (!st_faces(face, &a, &b))
        return;
    for (int f = a; f <= b; f++) {
        c->v.stencil_fail[f] = fail;
        c->v.stencil_zfail[f] = zfail;
        c->v.stencil_zpass[f] = zpass;
    }
    st_mark(c, TSR_SM_STENCIL);
}

static void stencil_mask(tsr_state_ctx *c, GLenum face, GLuint mask)
{
    int a, b;
    if (!st_faces(face, &a, &b))
        return;
    for (int f = a; f <= b; f++)
        c->v.stencil_writemask[f] = mask;
    st_mark(c, TSR_SM_STENCIL);
}

static void st_StencilFunc(void *self, GLenum func, GLint ref, GLuint mask)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    stencil_func(c, GL_FRONT_AND_BACK, func, ref, mask);
}

static void st_StencilFuncSeparate(void *self, GLenum face, GLenum func, GLint ref, GLuint mask)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    stencil_func(c, face, func, ref, mask);
}

static void st_StencilOp(void *self, GLenum f, GLenum zf, GLenum zp)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    stencil_op(c, GL_FRONT_AND_BACK, f, zf, zp);
}

static void st_StencilOpSeparate(void *self, GLenum face, GLenum f, GLenum zf, GLenum zp)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    stencil_op(c, face, f, zf, zp);
}

static void st_StencilMask(void *self, GLuint m)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    stencil_mask(c, GL_FRONT_AND_BACK, m);
}

static void st_StencilMaskSeparate(void *self, GLenum face, GLuint m)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    stencil_mask(c, face, m);
}

/* --- fog ---------------------------------------------------------------------------- */
static void fog(tsr_state_ctx *c, GLenum pname, const GLfloat *p)
{
    tsr_state_values *v = &c->v;
    switch (pname) {
    case GL_FOG_MODE: v->fog_mode = (GLenum)p[0]; break;
    case GL_FOG_DENSITY: if (p[0] < 0) return; v->fog_density = p[0]; break;
    case GL_FOG_START: v->fog_start = p[0]; break;
    case GL_FOG_END: v->fog_end = p[0]; break;
    case GL_FOG_INDEX: v->fog_index = p[0]; break;
    case GL_FOG_COLOR: for (int i = 0; i < 4; i++) v->fog_color[i] = st_clampf(p[i]); break;
    case GL_FOG_COORD_SRC: v->fog_coord_src = (GLenum)p[0]; break;
    default: return;
    }
    st_mark(c, TSR_SM_FOG);
}

static void fogi(tsr_state_ctx *c, GLenum pname, const GLint *p)
{
    GLfloat f[4];
    int color = pname == GL_FOG_COLOR;
    st_ints_to_floats(f, p, color ? 4 : 1, color);
    fog(c, pname, f);
}

static void st_Fogf(void *self, GLenum pname, GLfloat p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (pname != GL_FOG_COLOR)
        fog(c, pname, &p);
}

static void st_Fogfv(void *self, GLenum pname, const GLfloat *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    fog(c, pname, p);
}

static void st_Fogi(void *self, GLenum pname, GLint p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (pname != GL_FOG_COLOR)
        fogi(c, pname, &p);
}

static void st_Fogiv(void *self, GLenum pname, const GLint *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    fogi(c, pname, p);
}

/* --- lighting --------------------------------------------------------------------- */
static void light(tsr_state_ctx *c, GLenum which, GLenum pname, const GLfloat *p)
{
    if (which < GL_LIGHT0 || which >= GL_LIGHT0 + TSR_STATE_LIGHTS)
        return;
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
    case GL_SPOT_EXPONENT: if (p[0] < 0 || p[0] > 128) return; l->spot_exponent = p[0]; break;
    case GL_SPOT_CUTOFF: if ((p[0] < 0 || p[0] > 90) && p[0] != 180) return; l->spot_cutoff = p[0]; break;
    case GL_CONSTANT_ATTENUATION: if (p[0] < 0) return; l->attenuation[0] = p[0]; break;
    case GL_LINEAR_ATTENUATION: if (p[0] < 0) return; l->attenuation[1] = p[0]; break;
    case GL_QUADRATIC_ATTENUATION: if (p[0] < 0) return; l->attenuation[2] = p[0]; break;
    default: return;
    }
    st_mark(c, TSR_SM_LIGHT0 + (int)(which - GL_LIGHT0));
}

static int is_color_pname(GLenum p)
{
    return p == GL_AMBIENT || p == GL_DIFFUSE || p == GL_SPECULAR || p == GL_EMISSION ||
           p == GL_AMBIENT_AND_DIFFUSE || p == GL_LIGHT_MODEL_AMBIENT;
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
    return p == GL_SPOT_EXPONENT || p == GL_SPOT_CUTOFF || p == GL_CONSTANT_ATTENUATION ||
           p == GL_LINEAR_ATTENUATION || p == GL_QUADRATIC_ATTENUATION;
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
    default: return;
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

/* Which material properties glColor currently drives (Mesa ignores
 * glMaterial for those while GL_COLOR_MATERIAL is enabled). */
int st_tracked_by_color(const tsr_state_values *v, int face, GLenum pname)
{
    if (!st_enabled(v, EN_COLOR_MATERIAL))
        return 0;
    if ((face == 0 && v->color_material_face == GL_BACK) || (face == 1 && v->color_material_face == GL_FRONT))
        return 0;
    GLenum m = v->color_material_mode;
    return m == pname || (m == GL_AMBIENT_AND_DIFFUSE && (pname == GL_AMBIENT || pname == GL_DIFFUSE));
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
            switch (props[k]) {
            case GL_AMBIENT: memcpy(m->ambient, p, 16); break;
            case GL_DIFFUSE: memcpy(m->diffuse, p, 16); break;
            case GL_SPECULAR: memcpy(m->specular, p, 16); break;
            case GL_EMISSION: memcpy(m->emission, p, 16); break;
            case GL_SHININESS: if (p[0] < 0 || p[0] > 128) break; m->shininess = p[0]; break;
            default: return;
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
    color_material_update(c);
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

/* --- polygon, line, point ------------------------------------------------------ */
static void st_CullFace(void *self, GLenum m)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.cull_face_mode = m;
    st_mark(c, TSR_SM_POLYGON);
}

static void st_FrontFace(void *self, GLenum m)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.front_face = m;
    st_mark(c, TSR_SM_POLYGON);
}

static void st_PolygonMode(void *self, GLenum face, GLenum mode)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    int a, b;
    if (!st_faces(face, &a, &b) || (mode != GL_POINT && mode != GL_LINE && mode != GL_FILL))
        return;
    for (int f = a; f <= b; f++)
        c->v.polygon_mode[f] = mode;
    st_mark(c, TSR_SM_POLYGON);
}

static void st_PolygonOffset(void *self, GLfloat factor, GLfloat units)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.offset_factor = factor;
    c->v.offset_units = units;
    st_mark(c, TSR_SM_POLYGON);
}

/* The stipple is read under the unpack pixel store, like any bitmap:
 * bit by bit, since SKIP_PIXELS need not be a multiple of 8. Kept
 * MSB-first and tightly packed, as GL returns it by default. */
static void st_PolygonStipple(void *self, const GLubyte *mask)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    const tsr_pixel_modes *m = &c->v.pixel_store.unpack;
    tsr_pixel_layout l;
    if (tsr_pixel_layout_of(m, 2, 32, 32, 1, GL_COLOR_INDEX, GL_BITMAP, &l) != 0)
        return;
    uint64_t sp = (uint64_t)m->skip_pixels, sr = (uint64_t)m->skip_rows;
    for (int row = 0; row < 32; row++) {
        const GLubyte *src = mask + (sr + (uint64_t)row) * l.row_bytes;
        for (int x = 0; x < 32; x++) {
            uint64_t b = sp + (uint64_t)x;
            int bit = m->lsb_first ? (src[b / 8] >> (b % 8)) & 1 : (src[b / 8] >> (7 - b % 8)) & 1;
            GLubyte *dst = &c->v.polygon_stipple[row * 4 + x / 8];
            if (bit)
                *dst |= (GLubyte)(0x80u >> (x % 8));
            else
                *dst &= (GLubyte)~(0x80u >> (x % 8));
        }
    }
    st_mark(c, TSR_SM_STIPPLE);
}

static void st_LineWidth(void *self, GLfloat w)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (w <= 0)
        return;
    c->v.line_width = w;
    st_mark(c, TSR_SM_LINE);
}

static void st_LineStipple(void *self, GLint factor, GLushort pattern)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.line_stipple_factor = factor < 1 ? 1 : factor > 256 ? 256 : factor;
    c->v.line_stipple_pattern = pattern;
    st_mark(c, TSR_SM_LINE);
}

static void st_PointSize(void *self, GLfloat s)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (s <= 0)
        return;
    c->v.point_size = s;
    st_mark(c, TSR_SM_POINT);
}

static void point_param(tsr_state_ctx *c, GLenum pname, const GLfloat *p)
{
    tsr_state_values *v = &c->v;
    switch (pname) {
    case GL_POINT_SIZE_MIN: if (p[0] < 0) return; v->point_min = p[0]; break;
    case GL_POINT_SIZE_MAX: if (p[0] < 0) return; v->point_max = p[0]; break;
    case GL_POINT_FADE_THRESHOLD_SIZE: if (p[0] < 0) return; v->point_fade = p[0]; break;
    case GL_POINT_DISTANCE_ATTENUATION: memcpy(v->point_attenuation, p, 12); break;
    case GL_POINT_SPRITE_COORD_ORIGIN:
        if ((GLenum)p[0] != GL_LOWER_LEFT && (GLenum)p[0] != GL_UPPER_LEFT)
            return;
        v->point_sprite_origin = (GLenum)p[0];
        break;
    default: return;
    }
    st_mark(c, TSR_SM_POINT);
}

static void point_parami(tsr_state_ctx *c, GLenum pname, const GLint *p)
{
    GLfloat f[3] = {0, 0, 0};
    st_ints_to_floats(f, p, pname == GL_POINT_DISTANCE_ATTENUATION ? 3 : 1, 0);
    point_param(c, pname, f);
}

static void st_PointParameterf(void *self, GLenum pname, GLfloat p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (pname != GL_POINT_DISTANCE_ATTENUATION)
        point_param(c, pname, &p);
}

static void st_PointParameterfv(void *self, GLenum pname, const GLfloat *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    point_param(c, pname, p);
}

static void st_PointParameteri(void *self, GLenum pname, GLint p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (pname != GL_POINT_DISTANCE_ATTENUATION)
        point_parami(c, pname, &p);
}

static void st_PointParameteriv(void *self, GLenum pname, const GLint *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    point_parami(c, pname, p);
}

/* --- hints, misc ------------------------------------------------------------------- */
static const GLenum hint_targets[8] = {
    GL_PERSPECTIVE_CORRECTION_HINT, GL_POINT_SMOOTH_HINT, GL_LINE_SMOOTH_HINT,
    GL_POLYGON_SMOOTH_HINT, GL_FOG_HINT, GL_GENERATE_MIPMAP_HINT, GL_TEXTURE_COMPRESSION_HINT,
    GL_FRAGMENT_SHADER_DERIVATIVE_HINT,
};

static void st_Hint(void *self, GLenum target, GLenum mode)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (mode != GL_FASTEST && mode != GL_NICEST && mode != GL_DONT_CARE)
        return;
    for (int i = 0; i < 8; i++)
        if (hint_targets[i] == target) {
            c->v.hint[i] = mode;
            st_mark(c, TSR_SM_HINT);
        }
}

static void st_ListBase(void *self, GLuint base)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.list_base = base;
    st_mark(c, TSR_SM_LISTBASE);
}

static void st_SampleCoverage(void *self, GLfloat value, GLboolean invert)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.sample_coverage_value = st_clampf(value);
    c->v.sample_coverage_invert = invert ? GL_TRUE : GL_FALSE;
    st_mark(c, TSR_SM_MULTISAMPLE);
}

/* --- pixel ------------------------------------------------------------------------- */
static void st_PixelStorei(void *self, GLenum pname, GLint v)
{
    tsr_state_ctx *c = self;
    if (tsr_pixel_store_set(&c->v.pixel_store, pname, v))
        st_mark(c, TSR_SM_PIXELSTORE);
}

static void st_PixelStoref(void *self, GLenum pname, GLfloat v)
{
    tsr_state_ctx *c = self;
    if (tsr_pixel_store_set(&c->v.pixel_store, pname, v))
        st_mark(c, TSR_SM_PIXELSTORE);
}

static void st_PixelZoom(void *self, GLfloat x, GLfloat y)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.zoom[0] = x;
    c->v.zoom[1] = y;
    st_mark(c, TSR_SM_PIXELMODE);
}

static void pixel_transfer(tsr_state_ctx *c, GLenum pname, GLfloat p)
{
    tsr_state_values *v = &c->v;
    switch (pname) {
    case GL_RED_SCALE: v->transfer_scale[0] = p; break;
    case GL_GREEN_SCALE: v->transfer_scale[1] = p; break;
    case GL_BLUE_SCALE: v->transfer_scale[2] = p; break;
    case GL_ALPHA_SCALE: v->transfer_scale[3] = p; break;
    case GL_DEPTH_SCALE: v->transfer_scale[4] = p; break;
    case GL_RED_BIAS: v->transfer_bias[0] = p; break;
    case GL_GREEN_BIAS: v->transfer_bias[1] = p; break;
    case GL_BLUE_BIAS: v->transfer_bias[2] = p; break;
    case GL_ALPHA_BIAS: v->transfer_bias[3] = p; break;
    case GL_DEPTH_BIAS: v->transfer_bias[4] = p; break;
    case GL_INDEX_SHIFT: v->index_shift = (GLint)p; break;
    case GL_INDEX_OFFSET: v->index_offset = (GLint)p; break;
    case GL_MAP_COLOR: v->map_color = p != 0.0f; break;
    case GL_MAP_STENCIL: v->map_stencil = p != 0.0f; break;
    default: return;
    }
    st_mark(c, TSR_SM_PIXELMODE);
}

static void st_PixelTransferf(void *self, GLenum pname, GLfloat p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    pixel_transfer(c, pname, p);
}

static void st_PixelTransferi(void *self, GLenum pname, GLint p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    pixel_transfer(c, pname, (GLfloat)p);
}

/* --- texture units ------------------------------------------------------------------ */
static void st_ActiveTexture(void *self, GLenum unit)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLuint u = unit - GL_TEXTURE0;
    if (u >= TSR_STATE_UNITS)
        return;
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
    case GL_SRC0_RGB: case GL_SRC1_RGB: case GL_SRC2_RGB: *slot = &t->src_rgb[pname - GL_SRC0_RGB]; return 1;
    case GL_SRC0_ALPHA: case GL_SRC1_ALPHA: case GL_SRC2_ALPHA: *slot = &t->src_alpha[pname - GL_SRC0_ALPHA]; return 1;
    case GL_OPERAND0_RGB: case GL_OPERAND1_RGB: case GL_OPERAND2_RGB: *slot = &t->operand_rgb[pname - GL_OPERAND0_RGB]; return 1;
    case GL_OPERAND0_ALPHA: case GL_OPERAND1_ALPHA: case GL_OPERAND2_ALPHA: *slot = &t->operand_alpha[pname - GL_OPERAND0_ALPHA]; return 1;
    default: return 0;
    }
}

static void tex_env(tsr_state_ctx *c, GLenum target, GLenum pname, const GLfloat *p, int from_int)
{
    GLuint u = c->v.active_texture;
    tsr_state_texunit *t = &c->v.unit[u];
    GLenum *e;
    if (target == GL_TEXTURE_FILTER_CONTROL && pname == GL_TEXTURE_LOD_BIAS)
        t->lod_bias = p[0];
    else if (target == GL_POINT_SPRITE && pname == GL_COORD_REPLACE)
        t->coord_replace = p[0] != 0.0f;
    else if (target != GL_TEXTURE_ENV)
        return;
    else if (pname == GL_TEXTURE_ENV_COLOR)
        for (int i = 0; i < 4; i++)
            t->env_color[i] = st_clampf(from_int ? st_int_to_float((GLint)p[i]) : p[i]);
    else if (pname == GL_RGB_SCALE || pname == GL_ALPHA_SCALE) {
        if (p[0] != 1.0f && p[0] != 2.0f && p[0] != 4.0f)
            return;
        *(pname == GL_RGB_SCALE ? &t->rgb_scale : &t->alpha_scale) = p[0];
    } else if (env_enum_slot(t, pname, &e))
        *e = (GLenum)p[0];
    else
        return;
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
    case GL_EYE_PLANE: plane_to_eye(c, g->eye_plane, p); break;
    default: return;
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
#define ENABLES(...)                                         \
    do {                                                     \
        static const GLenum caps_[] = {__VA_ARGS__};         \
        uint64_t m_[2] = {0, 0};                             \
        enable_mask(m_, caps_, sizeof caps_ / sizeof *caps_); \
        copy_enables(d, s, m_);                              \
    } while (0)

/* Restores the groups of `mask` from s into d (glPopAttrib). */
static void attrib_restore(tsr_state_values *d, const tsr_state_values *s, GLbitfield mask)
{
    if (mask & GL_CURRENT_BIT) {
        COPY(color); COPY(normal); COPY(texcoord); COPY(edge_flag); COPY(attrib);
    }
    if (mask & GL_POINT_BIT) {
        COPY(point_size); COPY(point_min); COPY(point_max); COPY(point_fade); COPY(point_attenuation);
        COPY(point_sprite_origin);
        ENABLES(GL_POINT_SMOOTH, GL_POINT_SPRITE);
        for (int u = 0; u < TSR_STATE_UNITS; u++)
            d->unit[u].coord_replace = s->unit[u].coord_replace;
    }
    if (mask & GL_LINE_BIT) {
        COPY(line_width); COPY(line_stipple_factor); COPY(line_stipple_pattern);
        ENABLES(GL_LINE_SMOOTH, GL_LINE_STIPPLE);
    }
    if (mask & GL_POLYGON_BIT) {
        COPY(polygon_mode); COPY(cull_face_mode); COPY(front_face); COPY(offset_factor); COPY(offset_units);
        ENABLES(GL_CULL_FACE, GL_POLYGON_SMOOTH, GL_POLYGON_STIPPLE, GL_POLYGON_OFFSET_FILL,
                GL_POLYGON_OFFSET_LINE, GL_POLYGON_OFFSET_POINT);
    }
    if (mask & GL_POLYGON_STIPPLE_BIT)
        COPY(polygon_stipple);
    if (mask & GL_PIXEL_MODE_BIT) {
        COPY(zoom); COPY(transfer_scale); COPY(transfer_bias); COPY(index_shift); COPY(index_offset);
        COPY(map_color); COPY(map_stencil); COPY(read_buffer);
    }
    if (mask & GL_LIGHTING_BIT) {
        COPY(light); COPY(model_ambient); COPY(model_local_viewer); COPY(model_two_side);
        COPY(model_color_control); COPY(material); COPY(color_material_face);
        COPY(color_material_mode); COPY(shade_model);
        ENABLES(GL_LIGHTING, GL_COLOR_MATERIAL, GL_LIGHT0, GL_LIGHT1, GL_LIGHT2, GL_LIGHT3, GL_LIGHT4,
                GL_LIGHT5, GL_LIGHT6, GL_LIGHT7);
    }
    if (mask & GL_FOG_BIT) {
        COPY(fog_mode); COPY(fog_coord_src); COPY(fog_density); COPY(fog_start); COPY(fog_end);
        COPY(fog_index); COPY(fog_color);
        ENABLES(GL_FOG);
    }
    if (mask & GL_DEPTH_BUFFER_BIT) {
        COPY(depth_func); COPY(depth_mask); COPY(clear_depth);
        ENABLES(GL_DEPTH_TEST);
    }
    if (mask & GL_ACCUM_BUFFER_BIT)
        COPY(clear_accum);
    if (mask & GL_STENCIL_BUFFER_BIT) {
        COPY(stencil_func); COPY(stencil_ref); COPY(stencil_value_mask); COPY(stencil_writemask);
        COPY(stencil_fail); COPY(stencil_zfail); COPY(stencil_zpass); COPY(clear_stencil);
        ENABLES(GL_STENCIL_TEST);
    }
    if (mask & GL_VIEWPORT_BIT) {
        COPY(viewport); COPY(depth_range);
    }
    if (mask & GL_TRANSFORM_BIT) {
        COPY(matrix_mode); COPY(clip_plane);
        ENABLES(GL_NORMALIZE, GL_RESCALE_NORMAL, GL_CLIP_PLANE0, GL_CLIP_PLANE1, GL_CLIP_PLANE2,
                GL_CLIP_PLANE3, GL_CLIP_PLANE4, GL_CLIP_PLANE5);
    }
    if (mask & GL_ENABLE_BIT) {
        /* All but GL_COLOR_SUM, which Mesa (the renderer) does not save. */
        uint64_t keep = d->enables[0] & (1ull << EN_COLOR_SUM);
        COPY(enables);
        d->enables[0] = (d->enables[0] & ~(1ull << EN_COLOR_SUM)) | keep;
    }
    if (mask & GL_COLOR_BUFFER_BIT) {
        COPY(alpha_func); COPY(alpha_ref); COPY(blend_src_rgb); COPY(blend_dst_rgb);
        COPY(blend_src_alpha); COPY(blend_dst_alpha); COPY(blend_eq_rgb); COPY(blend_eq_alpha);
        COPY(blend_color); COPY(logic_op); COPY(color_mask); COPY(clear_color); COPY(draw_buffer);
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
                GL_MAP1_TEXTURE_COORD_2, GL_MAP1_TEXTURE_COORD_3, GL_MAP1_TEXTURE_COORD_4,
                GL_MAP1_VERTEX_3, GL_MAP1_VERTEX_4, GL_MAP2_COLOR_4, GL_MAP2_INDEX, GL_MAP2_NORMAL,
                GL_MAP2_TEXTURE_COORD_1, GL_MAP2_TEXTURE_COORD_2, GL_MAP2_TEXTURE_COORD_3,
                GL_MAP2_TEXTURE_COORD_4, GL_MAP2_VERTEX_3, GL_MAP2_VERTEX_4);
    if (mask & GL_LIST_BIT)
        COPY(list_base);
    if (mask & GL_TEXTURE_BIT) {
        COPY(active_texture);
        for (int u = 0; u < TSR_STATE_UNITS; u++) {
            GLboolean keep = d->unit[u].coord_replace;  /* POINT_BIT's */
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
        COPY(sample_coverage_value); COPY(sample_coverage_invert);
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
    if (c->attrib_depth >= TSR_STATE_ATTRIB_DEPTH)
        return;
    st_attrib_entry *e = &c->attrib_stack[c->attrib_depth++];
    e->mask = mask;
    e->v = c->v;
    if (mask & GL_TEXTURE_BIT)
        for (int u = 0; u < TSR_STATE_UNITS; u++)
            for (int t = 0; t < TSR_TEX_TARGETS; t++) {
                st_texobj *o = st_tex_lookup(c, c->v.unit[u].binding[t], t);
                if (o)
                    e->tex_params[u][t] = o->params;
            }
}

static void st_PopAttrib(void *self)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (!c->attrib_depth)
        return;
    st_attrib_entry *e = &c->attrib_stack[--c->attrib_depth];
    attrib_restore(&c->v, &e->v, e->mask);
    if (e->mask & GL_TEXTURE_BIT)
        for (int u = 0; u < TSR_STATE_UNITS; u++)
            for (int t = 0; t < TSR_TEX_TARGETS; t++) {
                st_texobj *o = st_tex_lookup(c, c->v.unit[u].binding[t], t);
                if (o && memcmp(&o->params, &e->tex_params[u][t], sizeof o->params) != 0) {
                    o->params = e->tex_params[u][t];
                    st_tex_changed(c, o);
                }
            }
    /* Rare: let the diff compare everything rather than track which
     * members the mask covered. */
    st_mark_all(c);
}

static void st_PushClientAttrib(void *self, GLbitfield mask)
{
    tsr_state_ctx *c = self;
    if (c->client_depth >= TSR_STATE_ATTRIB_DEPTH)
        return;
    st_client_entry *e = &c->client_stack[c->client_depth++];
    e->mask = mask;
    e->c = c->client;
    e->c.pixel_store = c->v.pixel_store;
    e->array_buffer = c->v.array_buffer;
    e->element_buffer = c->v.element_buffer;
}

static void st_PopClientAttrib(void *self)
{
    tsr_state_ctx *c = self;
    if (!c->client_depth)
        return;
    st_client_entry *e = &c->client_stack[--c->client_depth];
    if (e->mask & GL_CLIENT_PIXEL_STORE_BIT) {
        c->v.pixel_store = e->c.pixel_store;
        st_mark(c, TSR_SM_PIXELSTORE);
    }
    if (e->mask & GL_CLIENT_VERTEX_ARRAY_BIT) {
        tsr_pixel_store keep = c->client.pixel_store;
        c->client = e->c;
        c->client.pixel_store = keep;
        /* The buffer bindings are vertex-array state too. */
        c->v.array_buffer = e->array_buffer;
        c->v.element_buffer = e->element_buffer;
        st_mark(c, TSR_SM_BUFBIND);
    }
}

/* --- client arrays (client state: tracked for gets and push/pop) ---------------- */

static void set_pointer(tsr_state_ctx *c, tsr_state_array *a, GLint size, GLenum type, GLsizei stride,
                        const void *ptr)
{
    a->size = size;
    a->type = type;
    a->stride = stride;
    a->pointer = ptr;
    a->buffer = c->v.array_buffer;
}

static void st_VertexPointer(void *self, GLint size, GLenum type, GLsizei stride, const void *p) { tsr_state_ctx *c = self; set_pointer(c, &c->client.vertex, size, type, stride, p); }
static void st_NormalPointer(void *self, GLenum type, GLsizei stride, const void *p) { tsr_state_ctx *c = self; set_pointer(c, &c->client.normal, 3, type, stride, p); }
static void st_ColorPointer(void *self, GLint size, GLenum type, GLsizei stride, const void *p) { tsr_state_ctx *c = self; set_pointer(c, &c->client.color, size, type, stride, p); }
static void st_TexCoordPointer(void *self, GLint size, GLenum type, GLsizei stride, const void *p) { tsr_state_ctx *c = self; set_pointer(c, &c->client.texcoord[c->client.client_active_texture], size, type, stride, p); }
static void st_EdgeFlagPointer(void *self, GLsizei stride, const void *p) { tsr_state_ctx *c = self; set_pointer(c, &c->client.edge_flag, 1, GL_BOOL, stride, p); }

static void st_VertexAttribPointer(void *self, GLuint index, GLint size, GLenum type, GLboolean normalized,
                                   GLsizei stride, const void *p)
{
    tsr_state_ctx *c = self;
    if (index >= TSR_STATE_ATTRIBS)
        return;
    set_pointer(c, &c->client.attrib[index], size, type, stride, p);
    c->client.attrib[index].normalized = normalized ? GL_TRUE : GL_FALSE;
}

static void st_EnableClientState(void *self, GLenum array) { tsr_state_ctx *c = self; tsr_state_array *a = st_client_array(c, array); if (a) a->enabled = GL_TRUE; }
static void st_DisableClientState(void *self, GLenum array) { tsr_state_ctx *c = self; tsr_state_array *a = st_client_array(c, array); if (a) a->enabled = GL_FALSE; }
static void st_EnableVertexAttribArray(void *self, GLuint i) { tsr_state_ctx *c = self; if (i < TSR_STATE_ATTRIBS) c->client.attrib[i].enabled = GL_TRUE; }
static void st_DisableVertexAttribArray(void *self, GLuint i) { tsr_state_ctx *c = self; if (i < TSR_STATE_ATTRIBS) c->client.attrib[i].enabled = GL_FALSE; }

static void st_ClientActiveTexture(void *self, GLenum unit)
{
    tsr_state_ctx *c = self;
    if (unit - GL_TEXTURE0 < TSR_STATE_UNITS)
        c->client.client_active_texture = unit - GL_TEXTURE0;
}

/* glInterleavedArrays: sets the pointers, enables and disables it implies
 * (GL 2.1 table 2.5). */
static void st_InterleavedArrays(void *self, GLenum format, GLsizei stride, const void *pointer)
{
    tsr_state_ctx *c = self;
    int tc = 0, cs = 0, vs = 0, n = 0;
    GLenum ct = GL_FLOAT;
    int pc = 0, pn = 0, pv = 0;
    const int f = (int)sizeof(GLfloat);
    switch (format) {
    case GL_V2F: vs = 2; pv = 0; n = 2 * f; break;
    case GL_V3F: vs = 3; pv = 0; n = 3 * f; break;
    case GL_C4UB_V2F: cs = 4; ct = GL_UNSIGNED_BYTE; vs = 2; pc = 0; pv = 4; n = 4 + 2 * f; break;
    case GL_C4UB_V3F: cs = 4; ct = GL_UNSIGNED_BYTE; vs = 3; pc = 0; pv = 4; n = 4 + 3 * f; break;
    case GL_C3F_V3F: cs = 3; vs = 3; pc = 0; pv = 3 * f; n = 6 * f; break;
    case GL_N3F_V3F: pn = 1; vs = 3; pv = 3 * f; n = 6 * f; break;
    case GL_C4F_N3F_V3F: cs = 4; pc = 0; pn = 1; vs = 3; pv = 7 * f; n = 10 * f; break;
    case GL_T2F_V3F: tc = 2; vs = 3; pv = 2 * f; n = 5 * f; break;
    case GL_T4F_V4F: tc = 4; vs = 4; pv = 4 * f; n = 8 * f; break;
    case GL_T2F_C4UB_V3F: tc = 2; cs = 4; ct = GL_UNSIGNED_BYTE; pc = 2 * f; vs = 3; pv = 2 * f + 4; n = 2 * f + 4 + 3 * f; break;
    case GL_T2F_C3F_V3F: tc = 2; cs = 3; pc = 2 * f; vs = 3; pv = 5 * f; n = 8 * f; break;
    case GL_T2F_N3F_V3F: tc = 2; pn = 1; vs = 3; pv = 5 * f; n = 8 * f; break;
    case GL_T2F_C4F_N3F_V3F: tc = 2; cs = 4; pc = 2 * f; pn = 1; vs = 3; pv = 9 * f; n = 12 * f; break;
    case GL_T4F_C4F_N3F_V4F: tc = 4; cs = 4; pc = 4 * f; pn = 1; vs = 4; pv = 11 * f; n = 15 * f; break;
    default: return;
    }
    if (stride == 0)
        stride = n;
    const char *p = pointer;
    tsr_state_array *t = &c->client.texcoord[c->client.client_active_texture];
    t->enabled = tc != 0;
    if (tc)
        set_pointer(c, t, tc, GL_FLOAT, stride, p);
    c->client.color.enabled = cs != 0;
    if (cs)
        set_pointer(c, &c->client.color, cs, ct, stride, p + pc);
    c->client.normal.enabled = pn != 0;
    if (pn)
        set_pointer(c, &c->client.normal, 3, GL_FLOAT, stride, p + (pv - 3 * f));
    c->client.edge_flag.enabled = GL_FALSE;
    c->client.vertex.enabled = GL_TRUE;
    set_pointer(c, &c->client.vertex, vs, GL_FLOAT, stride, p + pv);
}

/* --- the table --------------------------------------------------------------------- */
void st_gen_fill_current(tsr_state_ctx *c, tsr_dispatch *d);   /* state_gen.c (generated) */

void tsr_state_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d)
{
#define SET(name) tsr_set_##name(d, st_##name, c)
    SET(LoadIdentity); SET(LoadMatrixf); SET(LoadMatrixd); SET(LoadTransposeMatrixf);
    SET(MultMatrixf); SET(MultMatrixd); SET(MultTransposeMatrixf);
    SET(Translatef); SET(Translated); SET(Scalef); SET(Scaled); SET(Rotatef); SET(Rotated);
    SET(Frustum); SET(Ortho); SET(MatrixMode); SET(PushMatrix); SET(PopMatrix); SET(ClipPlane);
    SET(Enable); SET(Disable);
    SET(Viewport); SET(Scissor); SET(DepthRange); SET(WindowSizeTSR);
    tsr_set_WindowCreateTSR(d, st_WindowSizeTSR, c);
    SET(BlendFunc); SET(BlendFuncSeparate); SET(BlendEquation); SET(BlendEquationSeparate);
    SET(BlendColor); SET(AlphaFunc); SET(LogicOp); SET(ColorMask); SET(ClearColor);
    SET(ClearAccum); SET(DrawBuffer); SET(DrawBuffers); SET(ReadBuffer);
    SET(DepthFunc); SET(DepthMask); SET(ClearDepth); SET(ClearStencil);
    SET(StencilFunc); SET(StencilFuncSeparate); SET(StencilOp); SET(StencilOpSeparate);
    SET(StencilMask); SET(StencilMaskSeparate);
    SET(Fogf); SET(Fogfv); SET(Fogi); SET(Fogiv);
    SET(Lightf); SET(Lightfv); SET(Lighti); SET(Lightiv);
    SET(LightModelf); SET(LightModelfv); SET(LightModeli); SET(LightModeliv);
    SET(Materialf); SET(Materialfv); SET(Materiali); SET(Materialiv);
    SET(ColorMaterial); SET(ShadeModel);
    SET(CullFace); SET(FrontFace); SET(PolygonMode); SET(PolygonOffset); SET(PolygonStipple);
    SET(LineWidth); SET(LineStipple); SET(PointSize);
    SET(PointParameterf); SET(PointParameterfv); SET(PointParameteri); SET(PointParameteriv);
    SET(Hint); SET(ListBase); SET(SampleCoverage);
    SET(PixelStorei); SET(PixelStoref); SET(PixelZoom); SET(PixelTransferf); SET(PixelTransferi);
    SET(ActiveTexture); SET(TexEnvf); SET(TexEnvfv); SET(TexEnvi); SET(TexEnviv);
    SET(TexGenf); SET(TexGeni); SET(TexGend); SET(TexGenfv); SET(TexGeniv); SET(TexGendv);
    SET(PushAttrib); SET(PopAttrib); SET(PushClientAttrib); SET(PopClientAttrib);
    SET(VertexPointer); SET(NormalPointer); SET(ColorPointer); SET(TexCoordPointer);
    SET(EdgeFlagPointer); SET(VertexAttribPointer); SET(EnableClientState);
    SET(DisableClientState); SET(EnableVertexAttribArray); SET(DisableVertexAttribArray);
    SET(ClientActiveTexture); SET(InterleavedArrays);
#undef SET
    st_gen_fill_current(c, d);
    st_obj_fill_dispatch(c, d);
    st_glsl_fill_dispatch(c, d);
    st_get_fill_dispatch(c, d);
}
