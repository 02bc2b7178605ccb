/* core/state/state_diff.c — the diff from a tracked context to one renderer's
 * shadow (state.h explains the bits). Each member has a function that
 * compares the context with the shadow field by field, emits a GL call for
 * each difference through the output table, and applies it to the shadow
 * exactly as the renderer will (including side effects such as
 * GL_COLOR_MATERIAL), so the shadow stays a faithful model.
 *
 * Order: enables first (so GL_COLOR_MATERIAL is right before colors and
 * materials are sent), the pixel store after textures and the polygon
 * stipple (their uploads switch the renderer to tightly packed pixels and
 * mark the pixel store for restoring), the matrix stacks last (lights,
 * clip planes and eye planes are sent in eye coordinates under a
 * temporary identity modelview, restored from the shadow). Selectors
 * (active texture, matrix mode) are restored at the very end.
 *
 * This file: the selectors and temporary state, the transform, misc and
 * pixel members, and the driver; state_diff_members.c and
 * state_diff_objects.c diff the other members (state_diff_internal.h).
 * Never: sends a call without applying it to the shadow. */
#include "state_internal.h"

#include <stdlib.h>
#include <string.h>
#include "state_diff_internal.h"

/* --- selectors and temporary state ------------------------------------------ */
void diff_sel_unit(dctx *x, GLuint u)
{
    if (x->s->v.active_texture == u)
        return;
    tsr_call_ActiveTexture(x->d, GL_TEXTURE0 + u);
    x->s->v.active_texture = u;
    x->n++;
}

static void sel_mode(dctx *x, GLenum mode)
{
    if (x->s->v.matrix_mode == mode)
        return;
    tsr_call_MatrixMode(x->d, mode);
    x->s->v.matrix_mode = mode;
    x->n++;
}

static const GLenum unpack_pnames[8] = {
    GL_UNPACK_SWAP_BYTES, GL_UNPACK_LSB_FIRST,   GL_UNPACK_ROW_LENGTH,  GL_UNPACK_IMAGE_HEIGHT,
    GL_UNPACK_SKIP_ROWS,  GL_UNPACK_SKIP_PIXELS, GL_UNPACK_SKIP_IMAGES, GL_UNPACK_ALIGNMENT,
};
static const GLenum pack_pnames[8] = {
    GL_PACK_SWAP_BYTES, GL_PACK_LSB_FIRST,   GL_PACK_ROW_LENGTH,  GL_PACK_IMAGE_HEIGHT,
    GL_PACK_SKIP_ROWS,  GL_PACK_SKIP_PIXELS, GL_PACK_SKIP_IMAGES, GL_PACK_ALIGNMENT,
};

/* Sets the renderer's unpack modes to tightly packed pixels (what the
 * tracker keeps) read from client memory: no GL_PIXEL_UNPACK_BUFFER, or
 * the renderer would take the tracker's pointer for an offset into it.
 * The PIXEL and BUFFER groups restore the application's later. */
void diff_sel_unpack_tight(dctx *x, uint8_t swap, uint8_t lsb)
{
    if (x->s->v.pixel_unpack_buffer) {
        tsr_call_BindBuffer(x->d, GL_PIXEL_UNPACK_BUFFER, 0);
        x->s->v.pixel_unpack_buffer = 0;
        x->n++;
        st_mark_one(x->c, TSR_SM_BUFBIND, x->s->id);
        x->changed[TSR_SM_BUFBIND >> 6] |= 1ull << (TSR_SM_BUFBIND & 63);
    }
    tsr_pixel_store want = x->s->v.pixel_store;
    want.unpack = (tsr_pixel_modes){0, 0, 0, 0, 0, 1, swap, lsb};
    for (int i = 0; i < 8; i++) {
        int32_t w = tsr_pixel_store_get(&want, unpack_pnames[i]);
        if (tsr_pixel_store_get(&x->s->v.pixel_store, unpack_pnames[i]) != w) {
            tsr_call_PixelStorei(x->d, unpack_pnames[i], w);
            x->n++;
        }
    }
    if (NEQ(x->s->v.pixel_store, want)) {
        x->s->v.pixel_store = want;
        st_mark_one(x->c, TSR_SM_PIXELSTORE, x->s->id);
        x->changed[TSR_SM_PIXELSTORE >> 6] |= 1ull << (TSR_SM_PIXELSTORE & 63);
    }
}

/* Sets the renderer's pixel-transfer modes to those an upload was made
 * under; the PIXEL group restores the application's later. */
void diff_sel_transfer(dctx *x, const st_transfer *t)
{
    tsr_state_values *s = &x->s->v;
    static const GLenum scale[5] = {GL_RED_SCALE, GL_GREEN_SCALE, GL_BLUE_SCALE, GL_ALPHA_SCALE, GL_DEPTH_SCALE};
    static const GLenum bias[5] = {GL_RED_BIAS, GL_GREEN_BIAS, GL_BLUE_BIAS, GL_ALPHA_BIAS, GL_DEPTH_BIAS};
    int changed = 0;
    for (int i = 0; i < 5; i++) {
        if (NEQ(s->transfer_scale[i], t->scale[i])) {
            tsr_call_PixelTransferf(x->d, scale[i], t->scale[i]);
            s->transfer_scale[i] = t->scale[i];
            x->n++, changed = 1;
        }
        if (NEQ(s->transfer_bias[i], t->bias[i])) {
            tsr_call_PixelTransferf(x->d, bias[i], t->bias[i]);
            s->transfer_bias[i] = t->bias[i];
            x->n++, changed = 1;
        }
    }
    const struct {
        GLenum p;
        GLint *sv;
        GLint want;
    } ints[2] = {{GL_INDEX_SHIFT, &s->index_shift, t->index_shift},
                 {GL_INDEX_OFFSET, &s->index_offset, t->index_offset}};
    for (int i = 0; i < 2; i++)
        if (*ints[i].sv != ints[i].want) {
            tsr_call_PixelTransferi(x->d, ints[i].p, ints[i].want);
            *ints[i].sv = ints[i].want;
            x->n++, changed = 1;
        }
    if (s->map_color != t->map_color) {
        tsr_call_PixelTransferi(x->d, GL_MAP_COLOR, t->map_color);
        s->map_color = t->map_color;
        x->n++, changed = 1;
    }
    if (s->map_stencil != t->map_stencil) {
        tsr_call_PixelTransferi(x->d, GL_MAP_STENCIL, t->map_stencil);
        s->map_stencil = t->map_stencil;
        x->n++, changed = 1;
    }
    if (changed) {
        st_mark_one(x->c, TSR_SM_PIXELMODE, x->s->id);
        x->changed[TSR_SM_PIXELMODE >> 6] |= 1ull << (TSR_SM_PIXELMODE & 63);
    }
}

/* Replays recipe r (tessera/dev/state.h) from operation `from` on: the renderer
 * then holds the matrix with the same bits and the same history. */
/* Operations whose only lasting effect, once glLoadIdentity follows, is
 * classification bit `bit` on the renderer's matrix. */
static void emit_sticky(dctx *x, unsigned bit)
{
    static const GLfloat general[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2};
    switch (bit) {
    case 1u << TSR_RECIPE_TRANSLATE: tsr_call_Translatef(x->d, 1, 0, 0); break;
    case 1u << TSR_RECIPE_SCALE: tsr_call_Scalef(x->d, 2, 2, 2); break;
    case 1u << TSR_RECIPE_ROTATE: tsr_call_Rotatef(x->d, 90, 0, 0, 1); break;
    case 1u << TSR_RECIPE_FRUSTUM: tsr_call_Frustum(x->d, -1, 1, -1, 1, 1, 2); break;
    case TSR_STICKY_GENERAL_SCALE: tsr_call_Scalef(x->d, 1, 2, 3); break;
    default: tsr_call_MultMatrixf(x->d, general); break;
    }
    x->n++;
}

/* Replays recipe r (tessera/dev/state.h) on the renderer, whose matrix was built
 * by recipe `had`, from operation `from` on (0: from the base); the
 * renderer then holds the same bits with the same classification. */
static void replay_recipe(dctx *x, const tsr_state_recipe *r, const tsr_state_recipe *had, unsigned from)
{
    if (from == 0 && r->base_is_identity) {
        /* glLoadIdentity keeps the classification the renderer's matrix
         * has: add the bits r's history has and it lacks. (Bits it has
         * and r lacks cannot be taken away without a glLoadMatrix.) */
        unsigned missing = r->sticky & ~st_recipe_bits(had);
        for (unsigned bit = 1; bit <= TSR_STICKY_GENERAL; bit <<= 1)
            if (missing & bit)
                emit_sticky(x, bit);
        tsr_call_LoadIdentity(x->d);
        x->n++;
    } else if (from == 0) {
        /* glLoadMatrix of the values the matrix holds does nothing in Mesa */
        tsr_call_Scalef(x->d, 2, 2, 2);
        tsr_call_LoadMatrixf(x->d, r->base);
        x->n += 2;
    }
    for (unsigned i = from; i < r->count; i++) {
        const GLfloat *a = r->arg[i];
        switch (r->kind[i]) {
        case TSR_RECIPE_TRANSLATE: tsr_call_Translatef(x->d, a[0], a[1], a[2]); break;
        case TSR_RECIPE_SCALE: tsr_call_Scalef(x->d, a[0], a[1], a[2]); break;
        case TSR_RECIPE_ROTATE: tsr_call_Rotatef(x->d, a[0], a[1], a[2], a[3]); break;
        case TSR_RECIPE_FRUSTUM: tsr_call_Frustum(x->d, a[0], a[1], a[2], a[3], a[4], a[5]); break;
        default: tsr_call_Ortho(x->d, a[0], a[1], a[2], a[3], a[4], a[5]); break;
        }
        x->n++;
    }
}

/* Operations the renderer's matrix (recipe s) lacks to become recipe c:
 * the index to replay from when s is a prefix of c, else 0 (replay all,
 * from the base). */
static unsigned recipe_from(const tsr_state_recipe *c, const tsr_state_recipe *s)
{
    if (s->count > c->count || s->base_is_identity != c->base_is_identity || s->sticky != c->sticky ||
        (!c->base_is_identity && memcmp(s->base, c->base, sizeof c->base)))
        return 0;
    for (unsigned i = 0; i < s->count; i++)
        if (s->kind[i] != c->kind[i] || memcmp(s->arg[i], c->arg[i], sizeof c->arg[i]))
            return 0;
    return s->count;
}

static int recipe_equal(const tsr_state_recipe *c, const tsr_state_recipe *s)
{
    return s->count == c->count && recipe_from(c, s) == c->count;
}

/* Eye-space values (light positions, spot directions, clip and eye planes)
 * are sent under an identity modelview, so the renderer stores exactly the
 * tracker's eye-space numbers. The renderer's matrix is saved with
 * glPushMatrix and restored with glPopMatrix (history included); with a
 * full stack it is rebuilt from its recipe. */
void diff_eye_begin(dctx *x)
{
    sel_mode(x, GL_MODELVIEW);
    x->eye_pushed = x->s->s.modelview_depth < TSR_STATE_MODELVIEW_DEPTH;
    if (x->eye_pushed) {
        tsr_call_PushMatrix(x->d);
        x->n++;
    }
    tsr_call_LoadIdentity(x->d);
    x->n++;
}

void diff_eye_end(dctx *x)
{
    if (x->eye_pushed) {
        tsr_call_PopMatrix(x->d);
        x->n++;
    } else {
        const tsr_state_recipe *r = &x->s->s.modelview_recipe[x->s->s.modelview_depth - 1];
        replay_recipe(x, r, r, 0);
    }
}

/* --- misc, pixel ------------------------------------------------------------------ */
static void d_misc(dctx *x, int m)
{
    tsr_state_values *c = &x->c->v, *s = &x->s->v;
    if (m == TSR_SM_LISTBASE && c->list_base != s->list_base) {
        tsr_call_ListBase(x->d, c->list_base);
        s->list_base = c->list_base;
        emitted(x);
    } else if (m == TSR_SM_MULTISAMPLE && (NEQ(c->sample_coverage_value, s->sample_coverage_value) ||
                                           c->sample_coverage_invert != s->sample_coverage_invert)) {
        tsr_call_SampleCoverage(x->d, c->sample_coverage_value, c->sample_coverage_invert);
        s->sample_coverage_value = c->sample_coverage_value;
        s->sample_coverage_invert = c->sample_coverage_invert;
        emitted(x);
    }
}

static void transferf(dctx *x, GLenum pname, GLfloat *dst, GLfloat val)
{
    if (!NEQ(*dst, val))
        return;
    tsr_call_PixelTransferf(x->d, pname, val);
    *dst = val;
    emitted(x);
}

static void d_pixel(dctx *x, int m)
{
    tsr_state_values *c = &x->c->v, *s = &x->s->v;
    if (m == TSR_SM_PIXELSTORE) {
        for (int i = 0; i < 16; i++) {
            GLenum p = i < 8 ? unpack_pnames[i] : pack_pnames[i - 8];
            int32_t want = tsr_pixel_store_get(&c->pixel_store, p);
            if (tsr_pixel_store_get(&s->pixel_store, p) != want) {
                tsr_call_PixelStorei(x->d, p, want);
                emitted(x);
            }
        }
        s->pixel_store = c->pixel_store;
        return;
    }
    if (NEQ(c->zoom, s->zoom)) {
        tsr_call_PixelZoom(x->d, c->zoom[0], c->zoom[1]);
        SYNC(s->zoom, c->zoom);
        emitted(x);
    }
    static const GLenum scale[5] = {GL_RED_SCALE, GL_GREEN_SCALE, GL_BLUE_SCALE, GL_ALPHA_SCALE, GL_DEPTH_SCALE};
    static const GLenum bias[5] = {GL_RED_BIAS, GL_GREEN_BIAS, GL_BLUE_BIAS, GL_ALPHA_BIAS, GL_DEPTH_BIAS};
    for (int i = 0; i < 5; i++) {
        transferf(x, scale[i], &s->transfer_scale[i], c->transfer_scale[i]);
        transferf(x, bias[i], &s->transfer_bias[i], c->transfer_bias[i]);
    }
    if (c->index_shift != s->index_shift) {
        tsr_call_PixelTransferi(x->d, GL_INDEX_SHIFT, c->index_shift);
        s->index_shift = c->index_shift;
        emitted(x);
    }
    if (c->index_offset != s->index_offset) {
        tsr_call_PixelTransferi(x->d, GL_INDEX_OFFSET, c->index_offset);
        s->index_offset = c->index_offset;
        emitted(x);
    }
    if (c->map_color != s->map_color) {
        tsr_call_PixelTransferi(x->d, GL_MAP_COLOR, c->map_color);
        s->map_color = c->map_color;
        emitted(x);
    }
    if (c->map_stencil != s->map_stencil) {
        tsr_call_PixelTransferi(x->d, GL_MAP_STENCIL, c->map_stencil);
        s->map_stencil = c->map_stencil;
        emitted(x);
    }
}

/* --- transform ---------------------------------------------------------------------- */
/* Makes the renderer's stack equal to the context's: pops down to the
 * longest common prefix (same bits, same recipe), then pushes and replays
 * what differs — only the operations the renderer's matrix lacks when its
 * recipe is a prefix of the context's. */
static void sync_stack(dctx *x, GLenum mode, GLuint unit, const GLfloat (*cm)[16], const tsr_state_recipe *cr,
                       uint32_t cd, GLfloat (*sm)[16], tsr_state_recipe *sr, uint32_t *sd)
{
    uint32_t k = 0, common = cd < *sd ? cd : *sd;
    while (k < common && memcmp(cm[k], sm[k], sizeof cm[k]) == 0 && recipe_equal(&cr[k], &sr[k]))
        k++;
    if (k == cd && k == *sd)
        return;
    if (mode == GL_TEXTURE)
        diff_sel_unit(x, unit);
    sel_mode(x, mode);
    uint32_t keep = k < 1 ? 1 : k;
    while (*sd > keep) {
        tsr_call_PopMatrix(x->d);
        (*sd)--;
        emitted(x);
    }
    if (k == 0) {
        replay_recipe(x, &cr[0], &sr[0], recipe_from(&cr[0], &sr[0]));
        memcpy(sm[0], cm[0], sizeof sm[0]);
        st_recipe_copy(&sr[0], &cr[0]);
        emitted(x);
    }
    while (*sd < cd) {
        uint32_t i = *sd;
        tsr_call_PushMatrix(x->d);
        memcpy(sm[i], sm[i - 1], sizeof sm[i]);
        st_recipe_copy(&sr[i], &sr[i - 1]);
        (*sd)++;
        emitted(x);
        if (memcmp(cm[i], sm[i], sizeof cm[i]) != 0 || !recipe_equal(&cr[i], &sr[i])) {
            replay_recipe(x, &cr[i], &sr[i], recipe_from(&cr[i], &sr[i]));
            memcpy(sm[i], cm[i], sizeof sm[i]);
            st_recipe_copy(&sr[i], &cr[i]);
            emitted(x);
        }
    }
}

static void d_transform(dctx *x, int m)
{
    tsr_state_stacks *c = &x->c->s, *s = &x->s->s;
    if (m == TSR_SM_MODELVIEW)
        sync_stack(x, GL_MODELVIEW, 0, (const GLfloat(*)[16])c->modelview, c->modelview_recipe, c->modelview_depth,
                   s->modelview, s->modelview_recipe, &s->modelview_depth);
    else if (m == TSR_SM_PROJECTION)
        sync_stack(x, GL_PROJECTION, 0, (const GLfloat(*)[16])c->projection, c->projection_recipe, c->projection_depth,
                   s->projection, s->projection_recipe, &s->projection_depth);
    else if (m >= TSR_SM_TEXMAT0 && m < TSR_SM_TEXMAT0 + TSR_STATE_UNITS) {
        GLuint u = (GLuint)(m - TSR_SM_TEXMAT0);
        sync_stack(x, GL_TEXTURE, u, (const GLfloat(*)[16])c->texture[u], c->texture_recipe[u], c->texture_depth[u],
                   s->texture[u], s->texture_recipe[u], &s->texture_depth[u]);
    } else if (m == TSR_SM_CLIP && NEQ(x->c->v.clip_plane, x->s->v.clip_plane)) {
        diff_eye_begin(x);
        for (int i = 0; i < TSR_STATE_CLIP_PLANES; i++)
            if (NEQ(x->c->v.clip_plane[i], x->s->v.clip_plane[i])) {
                const GLfloat *p = x->c->v.clip_plane[i];
                GLdouble eq[4] = {p[0], p[1], p[2], p[3]};
                tsr_call_ClipPlane(x->d, GL_CLIP_PLANE0 + (GLenum)i, eq);
                SYNC(x->s->v.clip_plane[i], x->c->v.clip_plane[i]);
                emitted(x);
            }
        diff_eye_end(x);
    }
}

/* --- the driver ------------------------------------------------------------------- */
static void diff_member(dctx *x, int m)
{
    x->member = m;
    switch (st_member_group[m]) {
    case TSR_SG_ENABLE: diff_enables(x, m - TSR_SM_ENABLE0); break;
    case TSR_SG_CURRENT: diff_current(x, m); break;
    case TSR_SG_VIEWPORT: diff_viewport(x, m); break;
    case TSR_SG_COLORBUF: diff_colorbuf(x, m); break;
    case TSR_SG_DEPTH: diff_depth(x); break;
    case TSR_SG_STENCIL: diff_stencil(x); break;
    case TSR_SG_FOG: diff_fog(x); break;
    case TSR_SG_LIGHTING: diff_lighting(x, m); break;
    case TSR_SG_RASTER: diff_raster(x, m); break;
    case TSR_SG_HINT: diff_hint(x); break;
    case TSR_SG_TEXTURE:
        if (m < TSR_SM_TEXBIND_IMAGE)
            diff_texbind(x, (GLuint)(m - TSR_SM_TEXBIND0));
        else if (m == TSR_SM_TEXBIND_IMAGE)
            diff_texbind_image(x);
        else if (m < TSR_SM_TEXGEN0)
            diff_texenv(x, (GLuint)(m - TSR_SM_TEXENV0));
        else
            diff_texgen(x, (GLuint)(m - TSR_SM_TEXGEN0));
        break;
    case TSR_SG_BUFFER: diff_buffers(x); break;
    case TSR_SG_MISC: d_misc(x, m); break;
    case TSR_SG_PIXEL: d_pixel(x, m); break;
    case TSR_SG_TRANSFORM: d_transform(x, m); break;
    case TSR_SG_PROGRAM:
        for (uint32_t k = st_glsl_diff(x->c, x->s, x->d); k; k--)
            emitted(x);
        break;
    default: break;
    }
}

int tsr_state_is_dirty(const tsr_state_ctx *c, const tsr_state_shadow *s)
{
    return (int)((c->dirty[(size_t)s->id >> 6] >> (s->id & 63)) & 1u);
}

uint32_t tsr_state_send_texture(tsr_state_ctx *c, tsr_state_shadow *s, GLenum target, GLuint name,
                                const tsr_dispatch *out)
{
    int ti = st_tex_target_index(target);
    st_texobj *o = ti < 0 || !name ? NULL : st_tex_lookup(c, name, ti);
    if (!o)
        return 0;
    dctx x = {.c = c, .s = s, .d = out};
    GLuint u = s->v.active_texture, was = s->v.image[u].binding[ti];
    diff_sync_texture(&x, u, ti, o);
    diff_bind_tex(&x, u, ti, was);
    return x.n;
}

uint32_t tsr_state_diff(tsr_state_ctx *c, tsr_state_shadow *s, const tsr_dispatch *out, tsr_state_diff_stats *stats)
{
    size_t w = c->t->words, word = (size_t)s->id >> 6;
    uint64_t bit = 1ull << (s->id & 63);
    if (stats)
        memset(stats, 0, sizeof *stats);
    if (__builtin_expect(!(c->dirty[word] & bit), 1))
        return 0;
    dctx x = {.c = c, .s = s, .d = out};
    c->dirty[word] &= ~bit;
    for (int g = 0; g < TSR_SG_COUNT; g++) {
        uint64_t *gb = &c->dirty[(size_t)(ST_NODE_GROUP0 + g) * w + word];
        if (!(*gb & bit))
            continue;
        *gb &= ~bit;
        uint32_t before = x.n;
        if (stats)
            stats->groups_visited++;
        for (int m = c->t->group_first[g]; m < c->t->group_first[g + 1]; m++) {
            uint64_t *mb = &c->dirty[(size_t)(ST_NODE_MEMBER0 + m) * w + word];
            if (!(*mb & bit))
                continue;
            *mb &= ~bit;
            if (stats)
                stats->members_visited++;
            diff_member(&x, m);
        }
        if (stats && x.n != before)
            stats->group_mask |= 1u << g;
    }
    /* Selectors last: every group above may have moved them. */
    if (s->v.active_texture != c->v.active_texture) {
        x.member = TSR_SM_TEXBIND0;
        tsr_call_ActiveTexture(out, GL_TEXTURE0 + c->v.active_texture);
        s->v.active_texture = c->v.active_texture;
        emitted(&x);
        if (stats)
            stats->group_mask |= 1u << TSR_SG_TEXTURE;
    }
    if (s->v.matrix_mode != c->v.matrix_mode) {
        x.member = TSR_SM_MODELVIEW;
        tsr_call_MatrixMode(out, c->v.matrix_mode);
        s->v.matrix_mode = c->v.matrix_mode;
        emitted(&x);
        if (stats)
            stats->group_mask |= 1u << TSR_SG_TRANSFORM;
    }
    /* Whatever changed on this renderer may now differ from every other
     * context's view of it. The diff itself may have re-marked members of
     * c that it already handled (side effects): they were handled later in
     * the same pass, so c is clean for s. */
    if (x.changed[0] | x.changed[1])
        for (size_t i = 0; i < c->t->nctxs; i++) {
            tsr_state_ctx *o = c->t->ctxs[i];
            if (o == c)
                continue;
            for (int k = 0; k < 2; k++)
                for (uint64_t b = x.changed[k]; b; b &= b - 1)
                    st_mark_one(o, k * 64 + __builtin_ctzll(b), s->id);
        }
    c->dirty[word] &= ~bit;
    if (stats)
        stats->commands = x.n;
    return x.n;
}

void tsr_state_shadow_assume(tsr_state_ctx *c, tsr_state_shadow *s, int member)
{
    tsr_state_values *cv = &c->v, *sv = &s->v;
    int m = member;
    if (m == TSR_SM_COLOR) {
        SYNC(sv->color, cv->color);
        st_color_material_apply(sv);
    } else if (m == TSR_SM_NORMAL)
        SYNC(sv->normal, cv->normal);
    else if (m >= TSR_SM_TEXCOORD0 && m < TSR_SM_TEXCOORD0 + TSR_STATE_UNITS)
        SYNC(sv->texcoord[m - TSR_SM_TEXCOORD0], cv->texcoord[m - TSR_SM_TEXCOORD0]);
    else if (m == TSR_SM_EDGEFLAG)
        sv->edge_flag = cv->edge_flag;
    else if (m == TSR_SM_ATTRIBS)
        SYNC(sv->attrib, cv->attrib);
    else if (m == TSR_SM_MATERIAL) {
        /* what the renderer's glColor drives stays its own */
        SYNC(sv->material, cv->material);
        st_color_material_apply(sv);
    } else
        return;
    for (size_t i = 0; i < c->t->nctxs; i++)
        if (c->t->ctxs[i] != c)
            st_mark_one(c->t->ctxs[i], m, s->id);
}
