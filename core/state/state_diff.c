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
 * (active texture, matrix mode) are restored at the very end. */
#include "state_internal.h"

#include <stdlib.h>
#include <string.h>

_Static_assert(TSR_SM_COUNT <= 128, "changed-member bitmap holds 128 members");

typedef struct dctx {
    tsr_state_ctx *c;
    tsr_state_shadow *s;
    const tsr_dispatch *d;
    uint32_t n;
    uint64_t changed[2]; /* members this diff changed on the renderer */
    int member;          /* member being diffed */
    int eye_pushed;      /* eye_begin saved the modelview with glPushMatrix */
} dctx;

static inline void emitted(dctx *x)
{
    x->n++;
    x->changed[x->member >> 6] |= 1ull << (x->member & 63);
}

#define NEQ(a, b) (memcmp(&(a), &(b), sizeof(a)) != 0)
#define SYNC(a, b) memcpy(&(a), &(b), sizeof(a))

/* --- selectors and temporary state ------------------------------------------ */
static void sel_unit(dctx *x, GLuint u)
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
 * tracker keeps); the PIXEL group restores the application's later. */
static void sel_unpack_tight(dctx *x, uint8_t swap, uint8_t lsb)
{
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
static void sel_transfer(dctx *x, const st_transfer *t)
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
static void eye_begin(dctx *x)
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

static void eye_end(dctx *x)
{
    if (x->eye_pushed) {
        tsr_call_PopMatrix(x->d);
        x->n++;
    } else {
        const tsr_state_recipe *r = &x->s->s.modelview_recipe[x->s->s.modelview_depth - 1];
        replay_recipe(x, r, r, 0);
    }
}

/* --- members -------------------------------------------------------------------- */
static void d_enables(dctx *x, int word)
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
            sel_unit(x, (GLuint)(idx - ST_EN_UNIT0) / 8);
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

static void d_current(dctx *x, int m)
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

static void d_viewport(dctx *x, int m)
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

static void d_colorbuf(dctx *x, int m)
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
        if (NEQ(c->clear_color, s->clear_color)) {
            tsr_call_ClearColor(x->d, c->clear_color[0], c->clear_color[1], c->clear_color[2], c->clear_color[3]);
            SYNC(s->clear_color, c->clear_color);
            emitted(x);
        }
        break;
    case TSR_SM_DRAWBUFFER:
        if (c->draw_buffer && c->draw_buffer != s->draw_buffer) {
            tsr_call_DrawBuffer(x->d, c->draw_buffer);
            s->draw_buffer = c->draw_buffer;
            emitted(x);
        }
        if (c->read_buffer && c->read_buffer != s->read_buffer) {
            tsr_call_ReadBuffer(x->d, c->read_buffer);
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

static void d_depth(dctx *x)
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

static void d_stencil(dctx *x)
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

static void d_fog(dctx *x)
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
        eye_begin(x);
        lightv(x, l, GL_POSITION, s->position, c->position, 4);
        lightv(x, l, GL_SPOT_DIRECTION, s->spot_direction, c->spot_direction, 3);
        eye_end(x);
    }
    lightv(x, l, GL_SPOT_EXPONENT, &s->spot_exponent, &c->spot_exponent, 1);
    lightv(x, l, GL_SPOT_CUTOFF, &s->spot_cutoff, &c->spot_cutoff, 1);
    lightv(x, l, GL_CONSTANT_ATTENUATION, &s->attenuation[0], &c->attenuation[0], 1);
    lightv(x, l, GL_LINEAR_ATTENUATION, &s->attenuation[1], &c->attenuation[1], 1);
    lightv(x, l, GL_QUADRATIC_ATTENUATION, &s->attenuation[2], &c->attenuation[2], 1);
}

static void d_lighting(dctx *x, int m)
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

static void d_raster(dctx *x, int m)
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
        sel_unpack_tight(x, 0, 0);
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

static void d_hint(dctx *x)
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

/* --- textures --------------------------------------------------------------------- */
static const GLenum target_enum[TSR_TEX_TARGETS] = {GL_TEXTURE_1D, GL_TEXTURE_2D, GL_TEXTURE_3D, GL_TEXTURE_CUBE_MAP};

static void bind_tex(dctx *x, GLuint u, int ti, GLuint name)
{
    if (x->s->v.unit[u].binding[ti] == name)
        return;
    sel_unit(x, u);
    tsr_call_BindTexture(x->d, target_enum[ti], name);
    x->s->v.unit[u].binding[ti] = name;
    emitted(x);
}

static void texparams(dctx *x, GLenum target, st_texparams *s, const st_texparams *c)
{
#define TPI(field, pname)                                             \
    if (s->field != c->field) {                                       \
        tsr_call_TexParameteri(x->d, target, pname, (GLint)c->field); \
        s->field = c->field;                                          \
        emitted(x);                                                   \
    }
#define TPF(field, pname)                                      \
    if (NEQ(s->field, c->field)) {                             \
        tsr_call_TexParameterf(x->d, target, pname, c->field); \
        s->field = c->field;                                   \
        emitted(x);                                            \
    }
    TPI(min_filter, GL_TEXTURE_MIN_FILTER);
    TPI(mag_filter, GL_TEXTURE_MAG_FILTER);
    TPI(wrap_s, GL_TEXTURE_WRAP_S);
    TPI(wrap_t, GL_TEXTURE_WRAP_T);
    TPI(wrap_r, GL_TEXTURE_WRAP_R);
    if (NEQ(s->border_color, c->border_color)) {
        tsr_call_TexParameterfv(x->d, target, GL_TEXTURE_BORDER_COLOR, c->border_color);
        SYNC(s->border_color, c->border_color);
        emitted(x);
    }
    TPF(priority, GL_TEXTURE_PRIORITY);
    TPF(min_lod, GL_TEXTURE_MIN_LOD);
    TPF(max_lod, GL_TEXTURE_MAX_LOD);
    TPF(lod_bias, GL_TEXTURE_LOD_BIAS);
    TPI(base_level, GL_TEXTURE_BASE_LEVEL);
    TPI(max_level, GL_TEXTURE_MAX_LEVEL);
    TPI(generate_mipmap, GL_GENERATE_MIPMAP);
    TPI(compare_mode, GL_TEXTURE_COMPARE_MODE);
    TPI(compare_func, GL_TEXTURE_COMPARE_FUNC);
    TPI(depth_mode, GL_DEPTH_TEXTURE_MODE);
#undef TPI
#undef TPF
}

static void replay(dctx *x, const st_texobj *o, const st_upload *u)
{
    if (u->kind == ST_UP_MIPMAP) {
        tsr_call_GenerateMipmap(x->d, target_enum[o->target]);
        emitted(x);
        return;
    }
    sel_unpack_tight(x, u->swap_bytes, u->lsb_first);
    sel_transfer(x, &u->transfer);
    if (u->kind == ST_UP_IMAGE) {
        if (u->dims == 1)
            tsr_call_TexImage1D(x->d, u->target, u->level, u->internalformat, u->w, u->border, u->format, u->type,
                                u->data);
        else if (u->dims == 2)
            tsr_call_TexImage2D(x->d, u->target, u->level, u->internalformat, u->w, u->h, u->border, u->format, u->type,
                                u->data);
        else
            tsr_call_TexImage3D(x->d, u->target, u->level, u->internalformat, u->w, u->h, u->d, u->border, u->format,
                                u->type, u->data);
    } else {
        if (u->dims == 1)
            tsr_call_TexSubImage1D(x->d, u->target, u->level, u->x, u->w, u->format, u->type, u->data);
        else if (u->dims == 2)
            tsr_call_TexSubImage2D(x->d, u->target, u->level, u->x, u->y, u->w, u->h, u->format, u->type, u->data);
        else
            tsr_call_TexSubImage3D(x->d, u->target, u->level, u->x, u->y, u->z, u->w, u->h, u->d, u->format, u->type,
                                   u->data);
    }
    emitted(x);
}

/* Content hashes (FNV-1a, 64 bits): two contexts' objects with the same
 * name and the same content (identical contexts switched on one renderer)
 * are recognised without sending anything. */
static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const uint8_t *b = p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 0x100000001b3ull;
    return h;
}

static uint64_t tex_hash(const st_texobj *o)
{
    uint64_t h = fnv(0xcbf29ce484222325ull, &o->params, sizeof o->params);
    for (size_t i = 0; i < o->nup; i++) {
        const st_upload *u = &o->up[i];
        GLint f[17] = {(GLint)u->kind,
                       u->dims,
                       (GLint)u->target,
                       u->level,
                       u->internalformat,
                       u->border,
                       u->x,
                       u->y,
                       u->z,
                       u->w,
                       u->h,
                       u->d,
                       (GLint)u->format,
                       (GLint)u->type,
                       u->swap_bytes,
                       u->lsb_first,
                       u->gen_mipmap};
        h = fnv(h, f, sizeof f);
        h = fnv(h, &u->size, sizeof u->size);
        h = fnv(h, &u->transfer, sizeof u->transfer);
        if (u->data)
            h = fnv(h, u->data, u->size);
    }
    return h;
}

static uint64_t buf_hash(const st_bufobj *b)
{
    uint64_t h = fnv(0xcbf29ce484222325ull, &b->size, sizeof b->size);
    h = fnv(h, &b->usage, sizeof b->usage);
    return b->data ? fnv(h, b->data, (size_t)b->size) : h;
}

/* Gives the renderer texture object o (bound on unit u) as the tracker
 * has it: parameters that differ and the image calls it has not seen. */
static void sync_texture(dctx *x, GLuint u, int ti, st_texobj *o)
{
    tsr_state_shadow *s = x->s;
    GLuint name = o->name;
    st_shadow_tex *rec = name ? tsr_name_map_get(&s->textures, name) : &s->default_tex[ti];
    if (rec && rec->uid == o->uid && rec->version == o->version)
        return;
    if (rec && rec->uid != o->uid && rec->hash == tex_hash(o)) {
        /* Same content under the same name: adopt it. */
        rec->uid = o->uid;
        rec->version = o->version;
        rec->epoch = o->epoch;
        rec->nup = o->nup;
        return;
    }
    if (rec && rec->uid != o->uid && name) {
        /* Another object (another context's, or one deleted and made
         * again) has this name on the renderer: start from scratch. */
        tsr_call_DeleteTextures(x->d, 1, &name);
        emitted(x);
        for (int k = 0; k < TSR_STATE_UNITS; k++)
            for (int t = 0; t < TSR_TEX_TARGETS; t++)
                if (s->v.unit[k].binding[t] == name)
                    s->v.unit[k].binding[t] = 0;
        free(tsr_name_map_del(&s->textures, name));
        rec = NULL;
    }
    if (!rec) {
        rec = calloc(1, sizeof *rec);
        if (!rec || tsr_name_map_put(&s->textures, name, rec) != 0) {
            free(rec);
            return;
        }
        st_texparams_init(&rec->params, ti);
        rec->uid = o->uid;
    }
    size_t start = 0;
    if (rec->uid == o->uid && rec->epoch == o->epoch && rec->nup <= o->nup)
        start = rec->nup;
    rec->uid = o->uid;
    bind_tex(x, u, ti, name);
    sel_unit(x, u);
    /* Parameters first (they shape uploads and generation); each upload
     * is replayed with GL_GENERATE_MIPMAP as it was when it was made. */
    st_texparams want = o->params;
    for (size_t i = start; i < o->nup; i++) {
        want.generate_mipmap = o->up[i].kind == ST_UP_MIPMAP ? rec->params.generate_mipmap : o->up[i].gen_mipmap;
        texparams(x, target_enum[ti], &rec->params, &want);
        replay(x, o, &o->up[i]);
    }
    texparams(x, target_enum[ti], &rec->params, &o->params);
    rec->version = o->version;
    rec->epoch = o->epoch;
    rec->nup = o->nup;
    rec->hash = tex_hash(o);
}

static void d_texbind(dctx *x, GLuint u)
{
    for (int ti = 0; ti < TSR_TEX_TARGETS; ti++) {
        GLuint name = x->c->v.unit[u].binding[ti];
        st_texobj *o = st_tex_lookup(x->c, name, ti);
        if (o)
            sync_texture(x, u, ti, o);
        bind_tex(x, u, ti, name);
    }
}

static void envi(dctx *x, GLuint u, GLenum target, GLenum pname, GLenum *dst, GLenum val)
{
    if (*dst == val)
        return;
    sel_unit(x, u);
    tsr_call_TexEnvi(x->d, target, pname, (GLint)val);
    *dst = val;
    emitted(x);
}

static void envf(dctx *x, GLuint u, GLenum target, GLenum pname, GLfloat *dst, GLfloat val)
{
    if (!NEQ(*dst, val))
        return;
    sel_unit(x, u);
    tsr_call_TexEnvf(x->d, target, pname, val);
    *dst = val;
    emitted(x);
}

static void d_texenv(dctx *x, GLuint u)
{
    tsr_state_texunit *c = &x->c->v.unit[u], *s = &x->s->v.unit[u];
    envi(x, u, GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, &s->env_mode, c->env_mode);
    if (NEQ(c->env_color, s->env_color)) {
        sel_unit(x, u);
        tsr_call_TexEnvfv(x->d, GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, c->env_color);
        SYNC(s->env_color, c->env_color);
        emitted(x);
    }
    envi(x, u, GL_TEXTURE_ENV, GL_COMBINE_RGB, &s->combine_rgb, c->combine_rgb);
    envi(x, u, GL_TEXTURE_ENV, GL_COMBINE_ALPHA, &s->combine_alpha, c->combine_alpha);
    for (int i = 0; i < 3; i++) {
        envi(x, u, GL_TEXTURE_ENV, GL_SRC0_RGB + (GLenum)i, &s->src_rgb[i], c->src_rgb[i]);
        envi(x, u, GL_TEXTURE_ENV, GL_SRC0_ALPHA + (GLenum)i, &s->src_alpha[i], c->src_alpha[i]);
        envi(x, u, GL_TEXTURE_ENV, GL_OPERAND0_RGB + (GLenum)i, &s->operand_rgb[i], c->operand_rgb[i]);
        envi(x, u, GL_TEXTURE_ENV, GL_OPERAND0_ALPHA + (GLenum)i, &s->operand_alpha[i], c->operand_alpha[i]);
    }
    envf(x, u, GL_TEXTURE_ENV, GL_RGB_SCALE, &s->rgb_scale, c->rgb_scale);
    envf(x, u, GL_TEXTURE_ENV, GL_ALPHA_SCALE, &s->alpha_scale, c->alpha_scale);
    envf(x, u, GL_TEXTURE_FILTER_CONTROL, GL_TEXTURE_LOD_BIAS, &s->lod_bias, c->lod_bias);
    if (c->coord_replace != s->coord_replace) {
        sel_unit(x, u);
        tsr_call_TexEnvi(x->d, GL_POINT_SPRITE, GL_COORD_REPLACE, c->coord_replace);
        s->coord_replace = c->coord_replace;
        emitted(x);
    }
}

static void d_texgen(dctx *x, GLuint u)
{
    tsr_state_texunit *c = &x->c->v.unit[u], *s = &x->s->v.unit[u];
    int eye = 0;
    for (int g = 0; g < 4; g++) {
        GLenum coord = GL_S + (GLenum)g;
        if (c->gen[g].mode != s->gen[g].mode) {
            sel_unit(x, u);
            tsr_call_TexGeni(x->d, coord, GL_TEXTURE_GEN_MODE, (GLint)c->gen[g].mode);
            s->gen[g].mode = c->gen[g].mode;
            emitted(x);
        }
        if (NEQ(c->gen[g].object_plane, s->gen[g].object_plane)) {
            sel_unit(x, u);
            tsr_call_TexGenfv(x->d, coord, GL_OBJECT_PLANE, c->gen[g].object_plane);
            SYNC(s->gen[g].object_plane, c->gen[g].object_plane);
            emitted(x);
        }
        eye |= NEQ(c->gen[g].eye_plane, s->gen[g].eye_plane);
    }
    if (!eye)
        return;
    sel_unit(x, u);
    eye_begin(x);
    for (int g = 0; g < 4; g++)
        if (NEQ(c->gen[g].eye_plane, s->gen[g].eye_plane)) {
            tsr_call_TexGenfv(x->d, GL_S + (GLenum)g, GL_EYE_PLANE, c->gen[g].eye_plane);
            SYNC(s->gen[g].eye_plane, c->gen[g].eye_plane);
            emitted(x);
        }
    eye_end(x);
}

/* --- buffers ------------------------------------------------------------------------ */
static void bind_buf(dctx *x, GLenum target, GLuint *shadow_binding, GLuint name)
{
    if (*shadow_binding == name)
        return;
    tsr_call_BindBuffer(x->d, target, name);
    *shadow_binding = name;
    emitted(x);
}

static void sync_buffer(dctx *x, GLuint name)
{
    st_bufobj *b = name ? st_buf_lookup(x->c, name) : NULL;
    if (!b)
        return;
    st_shadow_buf *rec = tsr_name_map_get(&x->s->buffers, name);
    if (rec && rec->uid == b->uid && rec->version == b->version)
        return;
    uint64_t hash = buf_hash(b);
    if (rec && rec->hash == hash) {
        rec->uid = b->uid;
        rec->version = b->version;
        return;
    }
    if (!rec) {
        rec = calloc(1, sizeof *rec);
        if (!rec || tsr_name_map_put(&x->s->buffers, name, rec) != 0) {
            free(rec);
            return;
        }
    }
    bind_buf(x, GL_ARRAY_BUFFER, &x->s->v.array_buffer, name);
    if (b->data) {
        tsr_call_BufferData(x->d, GL_ARRAY_BUFFER, b->size, b->data, b->usage);
        emitted(x);
    }
    rec->uid = b->uid;
    rec->version = b->version;
    rec->hash = hash;
}

/* Every buffer the renderer lacks, not only the bound ones and those of
 * the arrays enabled now: a diff is taken at the END of what it precedes,
 * and that stream's draws carry their own arrays (buffer names and
 * offsets, core/wire/pack.c), so a buffer bound, pointed at, drawn from
 * and unbound again inside it is in no binding the diff sees (romanboy
 * binds its three buffers in turn around each glDrawElements: the first
 * never reached a tilesort server, which drew nothing). A buffer whose
 * data the renderer has costs a comparison. */
static void d_buffers(dctx *x)
{
    const tsr_name_map *all = &x->c->buffers;
    for (size_t i = 0; i < all->cap; i++)
        if (all->keys[i])
            sync_buffer(x, all->keys[i]);
    bind_buf(x, GL_ARRAY_BUFFER, &x->s->v.array_buffer, x->c->v.array_buffer);
    bind_buf(x, GL_ELEMENT_ARRAY_BUFFER, &x->s->v.element_buffer, x->c->v.element_buffer);
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
        sel_unit(x, unit);
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
        eye_begin(x);
        for (int i = 0; i < TSR_STATE_CLIP_PLANES; i++)
            if (NEQ(x->c->v.clip_plane[i], x->s->v.clip_plane[i])) {
                const GLfloat *p = x->c->v.clip_plane[i];
                GLdouble eq[4] = {p[0], p[1], p[2], p[3]};
                tsr_call_ClipPlane(x->d, GL_CLIP_PLANE0 + (GLenum)i, eq);
                SYNC(x->s->v.clip_plane[i], x->c->v.clip_plane[i]);
                emitted(x);
            }
        eye_end(x);
    }
}

/* --- the driver ------------------------------------------------------------------- */
static void diff_member(dctx *x, int m)
{
    x->member = m;
    switch (st_member_group[m]) {
    case TSR_SG_ENABLE: d_enables(x, m - TSR_SM_ENABLE0); break;
    case TSR_SG_CURRENT: d_current(x, m); break;
    case TSR_SG_VIEWPORT: d_viewport(x, m); break;
    case TSR_SG_COLORBUF: d_colorbuf(x, m); break;
    case TSR_SG_DEPTH: d_depth(x); break;
    case TSR_SG_STENCIL: d_stencil(x); break;
    case TSR_SG_FOG: d_fog(x); break;
    case TSR_SG_LIGHTING: d_lighting(x, m); break;
    case TSR_SG_RASTER: d_raster(x, m); break;
    case TSR_SG_HINT: d_hint(x); break;
    case TSR_SG_TEXTURE:
        if (m < TSR_SM_TEXENV0)
            d_texbind(x, (GLuint)(m - TSR_SM_TEXBIND0));
        else if (m < TSR_SM_TEXGEN0)
            d_texenv(x, (GLuint)(m - TSR_SM_TEXENV0));
        else
            d_texgen(x, (GLuint)(m - TSR_SM_TEXGEN0));
        break;
    case TSR_SG_BUFFER: d_buffers(x); break;
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
    GLuint u = s->v.active_texture, was = s->v.unit[u].binding[ti];
    sync_texture(&x, u, ti, o);
    bind_tex(&x, u, ti, was);
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
