/* core/state/state_diff_objects.c — the diff of objects: texture units
 * (bindings, environment, coordinate generation) and texture objects
 * (parameters and image uploads replayed, skipped when the renderer's copy
 * hashes the same), buffer objects (data sent once).
 * Owns nothing. Never: emits without applying to the shadow, leaves the
 * renderer's pixel-store state changed without marking it for restoring. */
#include "state_internal.h"

#include <stdlib.h>
#include <string.h>
#include "state_diff_internal.h"

/* --- textures --------------------------------------------------------------------- */
static const GLenum target_enum[TSR_TEX_TARGETS] = {GL_TEXTURE_1D, GL_TEXTURE_2D, GL_TEXTURE_3D, GL_TEXTURE_CUBE_MAP};

void diff_bind_tex(dctx *x, GLuint u, int ti, GLuint name)
{
    tsr_state_values *sv = &x->s->v;
    if (sv->image[u].binding[ti] == name)
        return;
    diff_sel_unit(x, u);
    tsr_call_BindTexture(x->d, target_enum[ti], name);
    sv->image[u].binding[ti] = name;
    if (u >= TSR_STATE_UNITS)
        sv->image_units_set[u >> 6] |= 1ull << (u & 63);
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
    if (!c->border_type && (s->border_type || NEQ(s->border_color, c->border_color))) {
        tsr_call_TexParameterfv(x->d, target, GL_TEXTURE_BORDER_COLOR, c->border_color);
        SYNC(s->border_color, c->border_color);
        s->border_type = 0;
        emitted(x);
    } else if (c->border_type && (s->border_type != c->border_type || NEQ(s->border_int, c->border_int))) {
        if (c->border_type == GL_INT)
            tsr_call_TexParameterIivEXT(x->d, target, GL_TEXTURE_BORDER_COLOR, (const GLint *)c->border_int);
        else
            tsr_call_TexParameterIuivEXT(x->d, target, GL_TEXTURE_BORDER_COLOR, c->border_int);
        SYNC(s->border_int, c->border_int);
        s->border_type = c->border_type;
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
    TPI(swizzle[0], GL_TEXTURE_SWIZZLE_R);
    TPI(swizzle[1], GL_TEXTURE_SWIZZLE_G);
    TPI(swizzle[2], GL_TEXTURE_SWIZZLE_B);
    TPI(swizzle[3], GL_TEXTURE_SWIZZLE_A);
#undef TPI
#undef TPF
}

void diff_replay(dctx *x, const st_texobj *o, const st_upload *u)
{
    if (u->kind == ST_UP_MIPMAP) {
        tsr_call_GenerateMipmap(x->d, target_enum[o->target]);
        emitted(x);
        return;
    }
    diff_sel_unpack_tight(x, u->swap_bytes, u->lsb_first);
    diff_sel_transfer(x, &u->transfer);
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
void diff_sync_texture(dctx *x, GLuint u, int ti, st_texobj *o)
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
        st_for_image_units (k, &s->v, NULL) {
            for (int t = 0; t < TSR_TEX_TARGETS; t++)
                if (s->v.image[k].binding[t] == name)
                    s->v.image[k].binding[t] = 0;
        }
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
    diff_bind_tex(x, u, ti, name);
    diff_sel_unit(x, u);
    /* Parameters first (they shape uploads and generation); each upload
     * is replayed with GL_GENERATE_MIPMAP as it was when it was made. */
    st_texparams want = o->params;
    for (size_t i = start; i < o->nup; i++) {
        want.generate_mipmap = o->up[i].kind == ST_UP_MIPMAP ? rec->params.generate_mipmap : o->up[i].gen_mipmap;
        texparams(x, target_enum[ti], &rec->params, &want);
        diff_replay(x, o, &o->up[i]);
    }
    texparams(x, target_enum[ti], &rec->params, &o->params);
    rec->version = o->version;
    rec->epoch = o->epoch;
    rec->nup = o->nup;
    rec->hash = tex_hash(o);
}

static void envi(dctx *x, GLuint u, GLenum target, GLenum pname, GLenum *dst, GLenum val)
{
    if (*dst == val)
        return;
    diff_sel_unit(x, u);
    tsr_call_TexEnvi(x->d, target, pname, (GLint)val);
    *dst = val;
    emitted(x);
}

static void envf(dctx *x, GLuint u, GLenum target, GLenum pname, GLfloat *dst, GLfloat val)
{
    if (!NEQ(*dst, val))
        return;
    diff_sel_unit(x, u);
    tsr_call_TexEnvf(x->d, target, pname, val);
    *dst = val;
    emitted(x);
}

void diff_texbind(dctx *x, GLuint u)
{
    for (int ti = 0; ti < TSR_TEX_TARGETS; ti++) {
        GLuint name = x->c->v.image[u].binding[ti];
        st_texobj *o = st_tex_lookup(x->c, name, ti);
        if (o)
            diff_sync_texture(x, u, ti, o);
        diff_bind_tex(x, u, ti, name);
    }
    tsr_state_imageunit *s = &x->s->v.image[u];
    envf(x, u, GL_TEXTURE_FILTER_CONTROL, GL_TEXTURE_LOD_BIAS, &s->lod_bias, x->c->v.image[u].lod_bias);
}

/* TSR_SM_TEXBIND_IMAGE: the image units past the coordinate units that
 * either side ever set (all others hold GL's initial state on both). */
void diff_texbind_image(dctx *x)
{
    const tsr_state_values *cv = &x->c->v;
    tsr_state_values *sv = &x->s->v;
    for (GLuint u = st_next_image_unit(cv, sv, TSR_STATE_UNITS); u < TSR_STATE_IMAGE_UNITS;
         u = st_next_image_unit(cv, sv, u + 1)) {
        sv->image_units_set[u >> 6] |= 1ull << (u & 63); /* the renderer may hold state there now */
        diff_texbind(x, u);
    }
}

void diff_texenv(dctx *x, GLuint u)
{
    tsr_state_texunit *c = &x->c->v.unit[u], *s = &x->s->v.unit[u];
    envi(x, u, GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, &s->env_mode, c->env_mode);
    if (NEQ(c->env_color, s->env_color)) {
        diff_sel_unit(x, u);
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
    if (c->coord_replace != s->coord_replace) {
        diff_sel_unit(x, u);
        tsr_call_TexEnvi(x->d, GL_POINT_SPRITE, GL_COORD_REPLACE, c->coord_replace);
        s->coord_replace = c->coord_replace;
        emitted(x);
    }
}

void diff_texgen(dctx *x, GLuint u)
{
    tsr_state_texunit *c = &x->c->v.unit[u], *s = &x->s->v.unit[u];
    int eye = 0;
    for (int g = 0; g < 4; g++) {
        GLenum coord = GL_S + (GLenum)g;
        if (c->gen[g].mode != s->gen[g].mode) {
            diff_sel_unit(x, u);
            tsr_call_TexGeni(x->d, coord, GL_TEXTURE_GEN_MODE, (GLint)c->gen[g].mode);
            s->gen[g].mode = c->gen[g].mode;
            emitted(x);
        }
        if (NEQ(c->gen[g].object_plane, s->gen[g].object_plane)) {
            diff_sel_unit(x, u);
            tsr_call_TexGenfv(x->d, coord, GL_OBJECT_PLANE, c->gen[g].object_plane);
            SYNC(s->gen[g].object_plane, c->gen[g].object_plane);
            emitted(x);
        }
        eye |= NEQ(c->gen[g].eye_plane, s->gen[g].eye_plane);
    }
    if (!eye)
        return;
    diff_sel_unit(x, u);
    diff_eye_begin(x);
    for (int g = 0; g < 4; g++)
        if (NEQ(c->gen[g].eye_plane, s->gen[g].eye_plane)) {
            tsr_call_TexGenfv(x->d, GL_S + (GLenum)g, GL_EYE_PLANE, c->gen[g].eye_plane);
            SYNC(s->gen[g].eye_plane, c->gen[g].eye_plane);
            emitted(x);
        }
    diff_eye_end(x);
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
void diff_buffers(dctx *x)
{
    const tsr_name_map *all = &x->c->buffers;
    for (size_t i = 0; i < all->cap; i++)
        if (all->keys[i])
            sync_buffer(x, all->keys[i]);
    bind_buf(x, GL_ARRAY_BUFFER, &x->s->v.array_buffer, x->c->v.array_buffer);
    bind_buf(x, GL_ELEMENT_ARRAY_BUFFER, &x->s->v.element_buffer, x->c->v.element_buffer);
    bind_buf(x, GL_PIXEL_PACK_BUFFER, &x->s->v.pixel_pack_buffer, x->c->v.pixel_pack_buffer);
    bind_buf(x, GL_PIXEL_UNPACK_BUFFER, &x->s->v.pixel_unpack_buffer, x->c->v.pixel_unpack_buffer);
}
