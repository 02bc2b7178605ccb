/* core/state/state_obj.c — objects in the state tracker: texture objects
 * (parameters and every image call, with a tight copy of the pixels so a
 * renderer can be given the texture later, lazily), buffer objects (size,
 * usage, a copy of the data) and display-list names. Names are generated
 * here (max used + 1, as Mesa does), so glGen* need no round trip. */
#include "state_internal.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

int st_tex_target_index(GLenum target)
{
    switch (target) {
    case GL_TEXTURE_1D: return TSR_TEX_1D;
    case GL_TEXTURE_2D: return TSR_TEX_2D;
    case GL_TEXTURE_3D: return TSR_TEX_3D;
    case GL_TEXTURE_CUBE_MAP:
    case GL_TEXTURE_CUBE_MAP_POSITIVE_X:
    case GL_TEXTURE_CUBE_MAP_NEGATIVE_X:
    case GL_TEXTURE_CUBE_MAP_POSITIVE_Y:
    case GL_TEXTURE_CUBE_MAP_NEGATIVE_Y:
    case GL_TEXTURE_CUBE_MAP_POSITIVE_Z:
    case GL_TEXTURE_CUBE_MAP_NEGATIVE_Z: return TSR_TEX_CUBE;
    default: return -1;
    }
}

void st_texparams_init(st_texparams *p, int target)
{
    (void)target;
    memset(p, 0, sizeof *p);
    p->min_filter = GL_NEAREST_MIPMAP_LINEAR;
    p->mag_filter = GL_LINEAR;
    p->wrap_s = p->wrap_t = p->wrap_r = GL_REPEAT;
    p->priority = 1.0f;
    p->min_lod = -1000.0f;
    p->max_lod = 1000.0f;
    p->max_level = 1000;
    p->compare_mode = GL_NONE;
    p->compare_func = GL_LEQUAL;
    p->depth_mode = GL_LUMINANCE;
    p->swizzle[0] = GL_RED;
    p->swizzle[1] = GL_GREEN;
    p->swizzle[2] = GL_BLUE;
    p->swizzle[3] = GL_ALPHA;
}

/* A value GL_TEXTURE_SWIZZLE_* takes. */
static bool swizzle_source(GLenum e)
{
    return e == GL_RED || e == GL_GREEN || e == GL_BLUE || e == GL_ALPHA || e == GL_ZERO || e == GL_ONE;
}

st_texobj *st_tex_lookup(tsr_state_ctx *c, GLuint name, int target)
{
    if (!name)
        return target >= 0 && target < TSR_TEX_TARGETS ? &c->default_tex[target] : NULL;
    return tsr_name_map_get(&c->textures, name);
}

st_bufobj *st_buf_lookup(const tsr_state_ctx *c, GLuint name) { return tsr_name_map_get(&c->buffers, name); }

static void uploads_free(st_texobj *o)
{
    for (size_t i = 0; i < o->nup; i++)
        free(o->up[i].data);
    free(o->up);
    o->up = NULL;
    o->nup = o->capup = 0;
}

static void tex_free(st_texobj *o)
{
    if (!o)
        return;
    uploads_free(o);
    free(o);
}

void st_objects_free(tsr_state_ctx *c)
{
    for (size_t i = 0; i < c->textures.cap; i++)
        if (c->textures.keys[i])
            tex_free(c->textures.vals[i]);
    tsr_name_map_free(&c->textures);
    for (int i = 0; i < TSR_TEX_TARGETS; i++)
        uploads_free(&c->default_tex[i]);
    for (size_t i = 0; i < c->buffers.cap; i++)
        if (c->buffers.keys[i]) {
            st_bufobj *b = c->buffers.vals[i];
            free(b->data);
            free(b);
        }
    tsr_name_map_free(&c->buffers);
    tsr_name_map_free(&c->lists);
    st_glsl_free(c);
}

void st_shadow_objects_free(tsr_state_shadow *s)
{
    for (size_t i = 0; i < s->textures.cap; i++)
        if (s->textures.keys[i])
            free(s->textures.vals[i]);
    tsr_name_map_free(&s->textures);
    for (size_t i = 0; i < s->buffers.cap; i++)
        if (s->buffers.keys[i])
            free(s->buffers.vals[i]);
    tsr_name_map_free(&s->buffers);
    st_glsl_shadow_free(s);
}

/* --- textures ------------------------------------------------------------------ */
static st_texobj *tex_new(tsr_state_ctx *c, GLuint name, int target)
{
    st_texobj *o = calloc(1, sizeof *o);
    if (!o)
        return NULL;
    o->name = name;
    o->target = target;
    o->uid = c->t->next_uid++;
    st_texparams_init(&o->params, target);
    if (tsr_name_map_put(&c->textures, name, o) != 0) {
        free(o);
        return NULL;
    }
    return o;
}

/* A changed object must be looked at by the next diff of every unit that
 * may have it bound. */
void st_tex_changed(tsr_state_ctx *c, st_texobj *o)
{
    o->version++;
    if (o->target < 0)
        return;
    st_for_image_units (u, &c->v, NULL) {
        if (c->v.image[u].binding[o->target] == o->name)
            st_mark(c, st_image_member(u));
    }
}

static void st_GenTextures(void *self, GLsizei n, GLuint *names)
{
    tsr_state_ctx *c = self;
    for (GLsizei i = 0; i < n; i++) {
        GLuint name = c->textures.max_key + 1;
        names[i] = tex_new(c, name, -1) ? name : 0;
    }
}

static void st_BindTexture(void *self, GLenum target, GLuint name)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    int ti = st_tex_target_index(target);
    if (ti < 0 || target != (ti == TSR_TEX_CUBE ? GL_TEXTURE_CUBE_MAP : target))
        return;
    if (name) {
        st_texobj *o = tsr_name_map_get(&c->textures, name);
        if (!o && !(o = tex_new(c, name, ti)))
            return;
        if (o->target < 0)
            o->target = ti;
        if (o->target != ti)
            return;
    }
    GLuint u = c->v.active_texture;
    if (c->v.image[u].binding[ti] == name)
        return;
    c->v.image[u].binding[ti] = name;
    st_image_changed(c, u);
}

static void st_DeleteTextures(void *self, GLsizei n, const GLuint *names)
{
    tsr_state_ctx *c = self;
    for (GLsizei i = 0; i < n; i++) {
        st_texobj *o = tsr_name_map_del(&c->textures, names[i]);
        if (!o)
            continue;
        st_for_image_units (u, &c->v, NULL) {
            for (int t = 0; t < TSR_TEX_TARGETS; t++)
                if (c->v.image[u].binding[t] == names[i]) {
                    c->v.image[u].binding[t] = 0;
                    st_mark(c, st_image_member(u));
                }
        }
        tex_free(o);
    }
}

static st_texobj *bound_tex(tsr_state_ctx *c, GLenum target)
{
    int ti = st_tex_target_index(target);
    if (ti < 0)
        return NULL;
    return st_tex_lookup(c, c->v.image[c->v.active_texture].binding[ti], ti);
}

static void tex_param(tsr_state_ctx *c, GLenum target, GLenum pname, const GLfloat *p)
{
    if (target != GL_TEXTURE_1D && target != GL_TEXTURE_2D && target != GL_TEXTURE_3D && target != GL_TEXTURE_CUBE_MAP)
        return;
    st_texobj *o = bound_tex(c, target);
    if (!o)
        return;
    st_texparams *t = &o->params;
    GLenum e = (GLenum)p[0];
    switch (pname) {
    case GL_TEXTURE_MIN_FILTER:
        if (e != GL_NEAREST && e != GL_LINEAR && e != GL_NEAREST_MIPMAP_NEAREST && e != GL_LINEAR_MIPMAP_NEAREST &&
            e != GL_NEAREST_MIPMAP_LINEAR && e != GL_LINEAR_MIPMAP_LINEAR)
            return;
        t->min_filter = e;
        break;
    case GL_TEXTURE_MAG_FILTER:
        if (e != GL_NEAREST && e != GL_LINEAR)
            return;
        t->mag_filter = e;
        break;
    case GL_TEXTURE_WRAP_S:
    case GL_TEXTURE_WRAP_T:
    case GL_TEXTURE_WRAP_R:
        if (e != GL_CLAMP && e != GL_CLAMP_TO_EDGE && e != GL_REPEAT && e != GL_CLAMP_TO_BORDER &&
            e != GL_MIRRORED_REPEAT)
            return;
        *(pname == GL_TEXTURE_WRAP_S ? &t->wrap_s : pname == GL_TEXTURE_WRAP_T ? &t->wrap_t : &t->wrap_r) = e;
        break;
    case GL_TEXTURE_BORDER_COLOR:
        memcpy(t->border_color, p, 16);
        t->border_type = 0;
        break;
    case GL_TEXTURE_PRIORITY: t->priority = p[0] < 0 ? 0 : p[0] > 1 ? 1 : p[0]; break;
    case GL_TEXTURE_MIN_LOD: t->min_lod = p[0]; break;
    case GL_TEXTURE_MAX_LOD: t->max_lod = p[0]; break;
    case GL_TEXTURE_LOD_BIAS: t->lod_bias = p[0]; break;
    case GL_TEXTURE_BASE_LEVEL:
        if (p[0] < 0)
            return;
        t->base_level = (GLint)p[0];
        break;
    case GL_TEXTURE_MAX_LEVEL:
        if (p[0] < 0)
            return;
        t->max_level = (GLint)p[0];
        break;
    case GL_GENERATE_MIPMAP: t->generate_mipmap = p[0] != 0.0f; break;
    case GL_TEXTURE_COMPARE_MODE:
        if (e != GL_NONE && e != GL_COMPARE_R_TO_TEXTURE)
            return;
        t->compare_mode = e;
        break;
    case GL_TEXTURE_COMPARE_FUNC:
        if (e < GL_NEVER || e > GL_ALWAYS)
            return;
        t->compare_func = e;
        break;
    case GL_DEPTH_TEXTURE_MODE:
        if (e != GL_LUMINANCE && e != GL_INTENSITY && e != GL_ALPHA && e != GL_RED)
            return;
        t->depth_mode = e;
        break;
    case GL_TEXTURE_SWIZZLE_R:
    case GL_TEXTURE_SWIZZLE_G:
    case GL_TEXTURE_SWIZZLE_B:
    case GL_TEXTURE_SWIZZLE_A:
        if (!swizzle_source(e)) {
            st_error(c, GL_INVALID_ENUM);
            return;
        }
        t->swizzle[pname - GL_TEXTURE_SWIZZLE_R] = e;
        break;
    case GL_TEXTURE_SWIZZLE_RGBA:
        for (int i = 0; i < 4; i++)
            if (!swizzle_source((GLenum)p[i])) {
                st_error(c, GL_INVALID_ENUM);
                return;
            }
        for (int i = 0; i < 4; i++)
            t->swizzle[i] = (GLenum)p[i];
        break;
    default: st_error(c, GL_INVALID_ENUM); return;
    }
    st_tex_changed(c, o);
}

/* As Mesa: names that are no texture object are skipped. */
static void st_PrioritizeTextures(void *self, GLsizei n, const GLuint *names, const GLfloat *priorities)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c || n < 0 || !names || !priorities)
        return;
    for (GLsizei i = 0; i < n; i++) {
        st_texobj *o = names[i] ? tsr_name_map_get(&c->textures, names[i]) : NULL;
        if (!o)
            continue;
        GLfloat p = priorities[i];
        o->params.priority = p < 0 ? 0 : p > 1 ? 1 : p;
        st_tex_changed(c, o);
    }
}

static void st_TexParameterf(void *self, GLenum target, GLenum pname, GLfloat p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (pname != GL_TEXTURE_BORDER_COLOR && pname != GL_TEXTURE_SWIZZLE_RGBA)
        tex_param(c, target, pname, &p);
}

static void st_TexParameterfv(void *self, GLenum target, GLenum pname, const GLfloat *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    tex_param(c, target, pname, p);
}

static void st_TexParameteri(void *self, GLenum target, GLenum pname, GLint p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLfloat f = (GLfloat)p;
    if (pname != GL_TEXTURE_BORDER_COLOR && pname != GL_TEXTURE_SWIZZLE_RGBA)
        tex_param(c, target, pname, &f);
}

static void st_TexParameteriv(void *self, GLenum target, GLenum pname, const GLint *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    GLfloat f[4] = {0, 0, 0, 0};
    int color = pname == GL_TEXTURE_BORDER_COLOR;
    st_ints_to_floats(f, p, color || pname == GL_TEXTURE_SWIZZLE_RGBA ? 4 : 1, color);
    tex_param(c, target, pname, f);
}

/* GL_EXT_texture_integer: a border colour of integers (GL keeps one border
 * colour, so it replaces the float one); any other pname as
 * glTexParameteriv, as Mesa does. */
static void tex_param_int(tsr_state_ctx *c, GLenum type, GLenum target, GLenum pname, const GLint *p)
{
    if (pname != GL_TEXTURE_BORDER_COLOR) {
        st_TexParameteriv(c, target, pname, p);
        return;
    }
    if (target != GL_TEXTURE_1D && target != GL_TEXTURE_2D && target != GL_TEXTURE_3D && target != GL_TEXTURE_CUBE_MAP)
        return;
    st_texobj *o = bound_tex(c, target);
    if (!o)
        return;
    o->params.border_type = type;
    memcpy(o->params.border_int, p, sizeof o->params.border_int);
    st_tex_changed(c, o);
}

static void st_TexParameterIivEXT(void *self, GLenum target, GLenum pname, const GLint *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (c)
        tex_param_int(c, GL_INT, target, pname, p);
}

static void st_TexParameterIuivEXT(void *self, GLenum target, GLenum pname, const GLuint *p)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (c)
        tex_param_int(c, GL_UNSIGNED_INT, target, pname, (const GLint *)p);
}

/* Where an image call's pixels are: client memory, or with a
 * GL_PIXEL_UNPACK_BUFFER bound (GL 2.1 section 3.6.4) the offset `pixels`
 * into that buffer, read from the tracker's copy of its data. NULL when
 * the tracker does not have those bytes (never a dereferenced offset).
 * The copy is what the stream put in the buffer: pixels a renderer wrote
 * into it (glReadPixels into a pack buffer) are not in it. */
const uint8_t *st_unpack_source(const tsr_state_ctx *c, const void *pixels, uint64_t extent)
{
    if (!c->v.pixel_unpack_buffer)
        return pixels;
    const st_bufobj *b = st_buf_lookup(c, c->v.pixel_unpack_buffer);
    uint64_t offset = (uint64_t)(uintptr_t)pixels;
    if (!b || !b->data || b->size < 0 || offset > (uint64_t)b->size || extent > (uint64_t)b->size - offset)
        return NULL;
    return b->data + offset;
}

/* The tight copy of an image given under the context's unpack store; NULL
 * when there is none (an image that reaches past the pixel unpack buffer's
 * end is GL_INVALID_OPERATION, GL 2.1 section 3.7.1). */
static uint8_t *copy_image(tsr_state_ctx *c, int dims, GLsizei w, GLsizei h, GLsizei d, GLenum format, GLenum type,
                           const void *pixels, size_t *size)
{
    const tsr_pixel_modes *m = &c->v.pixel_store.unpack;
    tsr_pixel_modes tight = {0, 0, 0, 0, 0, 1, m->swap_bytes, m->lsb_first};
    tsr_pixel_layout l, tl;
    if (tsr_pixel_layout_of(m, dims, w, h, d, format, type, &l) != 0 ||
        tsr_pixel_layout_of(&tight, dims, w, h, d, format, type, &tl) != 0 || tl.extent > SIZE_MAX)
        return NULL;
    const uint8_t *src = st_unpack_source(c, pixels, l.extent);
    if (!src) {
        if (c->v.pixel_unpack_buffer)
            st_error(c, GL_INVALID_OPERATION);
        return NULL;
    }
    uint8_t *out = malloc(tl.extent ? (size_t)tl.extent : 1);
    if (!out)
        return NULL;
    for (GLsizei z = 0; z < (dims == 3 ? d : 1); z++)
        for (GLsizei y = 0; y < (dims >= 2 ? h : 1); y++)
            memcpy(out + (uint64_t)z * tl.image_bytes + (uint64_t)y * tl.row_bytes,
                   src + l.first + (uint64_t)z * l.image_bytes + (uint64_t)y * l.row_bytes, (size_t)l.row_span);
    *size = (size_t)tl.extent;
    return out;
}

static void transfer_of(const tsr_state_values *v, st_transfer *t)
{
    memset(t, 0, sizeof *t);
    memcpy(t->scale, v->transfer_scale, sizeof t->scale);
    memcpy(t->bias, v->transfer_bias, sizeof t->bias);
    t->index_shift = v->index_shift;
    t->index_offset = v->index_offset;
    t->map_color = v->map_color;
    t->map_stencil = v->map_stencil;
}

static st_upload *push_upload(st_texobj *o)
{
    if (o->nup == o->capup) {
        size_t cap = o->capup ? o->capup * 2 : 4;
        st_upload *n = realloc(o->up, cap * sizeof *n);
        if (!n)
            return NULL;
        o->up = n;
        o->capup = cap;
    }
    st_upload *u = &o->up[o->nup++];
    memset(u, 0, sizeof *u);
    return u;
}

/* Appends `up` (which owns up.data) to o's upload log with the pixel
 * transfer and mipmap generation in force now; frees the data when out of
 * memory. */
static void record_upload(tsr_state_ctx *c, st_texobj *o, st_upload up)
{
    st_upload *u = push_upload(o);
    if (!u) {
        free(up.data);
        return;
    }
    *u = up;
    transfer_of(&c->v, &u->transfer);
    u->gen_mipmap = o->params.generate_mipmap;
    st_tex_changed(c, o);
}

/* The last full image of (face, level), or NULL. */
static st_upload *level_image(const st_texobj *o, GLenum face, GLint level)
{
    for (size_t i = o->nup; i-- > 0;)
        if (o->up[i].kind == ST_UP_IMAGE && o->up[i].target == face && o->up[i].level == level)
            return &o->up[i];
    return NULL;
}

static int is_proxy_target(GLenum target)
{
    return target == GL_PROXY_TEXTURE_1D || target == GL_PROXY_TEXTURE_2D || target == GL_PROXY_TEXTURE_3D ||
           target == GL_PROXY_TEXTURE_CUBE_MAP;
}

/* The GL error of a glTex(Sub)Image{dims}D target, before any other check
 * (GL 2.1 section 3.8.1): a tracked target of another dimension count, the
 * cube map itself (only its faces take images) and, for a sub-image, a
 * proxy are GL_INVALID_ENUM. A target the tracker does not know is none of
 * its business (0: the call is left alone, as before). */
static GLenum image_target_error(int dims, GLenum target, int sub)
{
    if (is_proxy_target(target))
        return sub ? GL_INVALID_ENUM : 0;
    int ti = st_tex_target_index(target);
    if (ti < 0)
        return 0;
    if (target == GL_TEXTURE_CUBE_MAP || (dims == 1) != (ti == TSR_TEX_1D) || (dims == 3) != (ti == TSR_TEX_3D))
        return GL_INVALID_ENUM;
    return 0;
}

/* A level or size past the renderers' limits, when known (GL 2.1 section
 * 3.8.1: a level past log2 of the largest size, an image wider than that
 * level's largest size plus its border). */
static int past_limits(const tsr_state_ctx *c, GLenum target, GLint level, GLsizei w, GLsizei h, GLsizei d,
                       GLint border)
{
    int ti = st_tex_target_index(target);
    GLint max = ti >= 0 ? c->t->max_tex_size[ti] : 0;
    if (max <= 0)
        return 0;
    GLint levels = 1;
    while ((max >> levels) > 0)
        levels++;
    if (level >= levels)
        return 1;
    GLsizei room = (max >> level) + 2 * border;
    return w > room || (ti != TSR_TEX_1D && h > room) || (ti == TSR_TEX_3D && d > room);
}

static void tex_image(tsr_state_ctx *c, int dims, GLenum target, GLint level, GLint ifmt, GLsizei w, GLsizei h,
                      GLsizei d, GLint border, GLenum format, GLenum type, const void *pixels)
{
    /* GL's errors the tracker can tell (the call is never sent when it
     * refuses it, so no server would raise them); a wall's glGetError
     * takes them (tsr_state_take_error) */
    GLenum error = image_target_error(dims, target, 0);
    if (!error && st_tex_target_index(target) >= 0 &&
        (level < 0 || w < 0 || h < 0 || d < 0 || border < 0 || border > 1 ||
         past_limits(c, target, level, w, h, d, border)))
        error = GL_INVALID_VALUE;
    if (error) {
        st_error(c, error);
        return;
    }
    int ti = st_tex_target_index(target);
    if (ti < 0)
        return;
    st_texobj *o = bound_tex(c, target);
    if (!o)
        return;
    size_t size = 0;
    uint8_t *copy = NULL;
    if ((pixels || c->v.pixel_unpack_buffer) && !(copy = copy_image(c, dims, w, h, d, format, type, pixels, &size)))
        return;
    /* A new image of a level replaces the earlier calls on that level, but
     * only after the last mipmap generation (explicit, or by an upload made
     * with GL_GENERATE_MIPMAP on), which read them: the list stays a
     * faithful log of what the renderer must replay, in order. */
    size_t keep = 0;
    for (size_t i = 0; i < o->nup; i++)
        if (o->up[i].kind == ST_UP_MIPMAP || o->up[i].gen_mipmap)
            keep = i + 1;
    size_t out = keep;
    for (size_t i = keep; i < o->nup; i++) {
        st_upload *u = &o->up[i];
        if (u->target == target && u->level == level) {
            free(u->data);
            continue;
        }
        o->up[out++] = *u;
    }
    if (out != o->nup)
        o->epoch++;
    o->nup = out;
    record_upload(c, o,
                  (st_upload){.kind = ST_UP_IMAGE,
                              .dims = dims,
                              .target = target,
                              .level = level,
                              .internalformat = ifmt,
                              .border = border,
                              .w = w,
                              .h = h,
                              .d = d,
                              .format = format,
                              .type = type,
                              .data = copy,
                              .size = size,
                              .swap_bytes = c->v.pixel_store.unpack.swap_bytes,
                              .lsb_first = c->v.pixel_store.unpack.lsb_first});
}

static void st_TexImage1D(void *self, GLenum target, GLint level, GLint ifmt, GLsizei w, GLint border, GLenum format,
                          GLenum type, const void *pixels)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    tex_image(c, 1, target, level, ifmt, w, 1, 1, border, format, type, pixels);
}

static void st_TexImage2D(void *self, GLenum target, GLint level, GLint ifmt, GLsizei w, GLsizei h, GLint border,
                          GLenum format, GLenum type, const void *pixels)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    tex_image(c, 2, target, level, ifmt, w, h, 1, border, format, type, pixels);
}

static void st_TexImage3D(void *self, GLenum target, GLint level, GLint ifmt, GLsizei w, GLsizei h, GLsizei d,
                          GLint border, GLenum format, GLenum type, const void *pixels)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    tex_image(c, 3, target, level, ifmt, w, h, d, border, format, type, pixels);
}

static void record_subimage(tsr_state_ctx *c, st_texobj *o, int dims, GLenum target, GLint level, GLint x, GLint y,
                            GLint z, GLsizei w, GLsizei h, GLsizei d, GLenum format, GLenum type, uint8_t *copy,
                            size_t size)
{
    record_upload(c, o,
                  (st_upload){.kind = ST_UP_SUBIMAGE,
                              .dims = dims,
                              .target = target,
                              .level = level,
                              .x = x,
                              .y = y,
                              .z = z,
                              .w = w,
                              .h = h,
                              .d = d,
                              .format = format,
                              .type = type,
                              .data = copy,
                              .size = size,
                              .swap_bytes = c->v.pixel_store.unpack.swap_bytes,
                              .lsb_first = c->v.pixel_store.unpack.lsb_first});
}

static void tex_subimage(tsr_state_ctx *c, int dims, GLenum target, GLint level, GLint x, GLint y, GLint z, GLsizei w,
                         GLsizei h, GLsizei d, GLenum format, GLenum type, const void *pixels)
{
    /* GL's errors in GL's order: target, level and sizes, a level with no
     * image, then the region (GL 2.1 section 3.8.2; the border widens
     * the range an offset may take) */
    GLenum error = image_target_error(dims, target, 1);
    if (!error && st_tex_target_index(target) >= 0 && (level < 0 || w < 0 || h < 0 || d < 0))
        error = GL_INVALID_VALUE;
    st_texobj *o = error ? NULL : bound_tex(c, target);
    st_upload *img = o ? level_image(o, target, level) : NULL;
    /* a level made by mipmap generation has no image of its own in the
     * log: the sub-image is logged and the renderer's GL judges it */
    int generated = 0;
    for (size_t i = 0; o && i < o->nup; i++)
        generated |= o->up[i].kind == ST_UP_MIPMAP || o->up[i].gen_mipmap;
    if (!error && o && !img && !generated)
        error = GL_INVALID_OPERATION;
    if (!error && img) {
        GLint b = img->border;
        if (x < -b || x + w > img->w - b || (dims > 1 && (y < -b || y + h > img->h - b)) ||
            (dims > 2 && (z < -b || z + d > img->d - b)))
            error = GL_INVALID_VALUE;
    }
    if (error) {
        st_error(c, error);
        return;
    }
    if (!o || (!pixels && !c->v.pixel_unpack_buffer))
        return; /* NULL pixels: GL reads nothing and changes nothing */
    size_t size;
    uint8_t *copy = copy_image(c, dims, w, h, d, format, type, pixels, &size);
    if (!copy)
        return;
    if (!img) {
        record_subimage(c, o, dims, target, level, x, y, z, w, h, d, format, type, copy, size);
        return;
    }
    /* A sub-image covering the whole level in the level's own format
     * replaces the image's pixels instead of growing the list (textures
     * streamed every frame stay one upload). */
    int logged_after = 0;
    for (const st_upload *u = img; u < o->up + o->nup; u++)
        logged_after |= u->kind == ST_UP_MIPMAP || u->gen_mipmap;
    if (!logged_after && !o->params.generate_mipmap && x == 0 && y == 0 && z == 0 && w == img->w && h == img->h &&
        d == img->d && format == img->format && type == img->type &&
        img->swap_bytes == c->v.pixel_store.unpack.swap_bytes && img->lsb_first == c->v.pixel_store.unpack.lsb_first) {
        size_t out = 0;
        for (size_t i = 0; i < o->nup; i++) {
            st_upload *u = &o->up[i];
            if (u->kind == ST_UP_SUBIMAGE && u->target == target && u->level == level) {
                free(u->data);
                continue;
            }
            o->up[out++] = *u;
        }
        o->nup = out;
        img = level_image(o, target, level);
        free(img->data);
        img->data = copy;
        img->size = size;
        transfer_of(&c->v, &img->transfer);
        o->epoch++;
        st_tex_changed(c, o);
        return;
    }
    record_subimage(c, o, dims, target, level, x, y, z, w, h, d, format, type, copy, size);
}

static void st_TexSubImage1D(void *self, GLenum target, GLint level, GLint x, GLsizei w, GLenum format, GLenum type,
                             const void *pixels)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    tex_subimage(c, 1, target, level, x, 0, 0, w, 1, 1, format, type, pixels);
}

static void st_TexSubImage2D(void *self, GLenum target, GLint level, GLint x, GLint y, GLsizei w, GLsizei h,
                             GLenum format, GLenum type, const void *pixels)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    tex_subimage(c, 2, target, level, x, y, 0, w, h, 1, format, type, pixels);
}

static void st_TexSubImage3D(void *self, GLenum target, GLint level, GLint x, GLint y, GLint z, GLsizei w, GLsizei h,
                             GLsizei d, GLenum format, GLenum type, const void *pixels)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    tex_subimage(c, 3, target, level, x, y, z, w, h, d, format, type, pixels);
}

static void st_GenerateMipmap(void *self, GLenum target)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    st_texobj *o = bound_tex(c, target);
    st_upload *u = o ? push_upload(o) : NULL;
    if (!u)
        return;
    u->kind = ST_UP_MIPMAP;
    u->target = target;
    u->level = -1;
    st_tex_changed(c, o);
}

/* --- buffers -------------------------------------------------------------------- */
static void st_GenBuffers(void *self, GLsizei n, GLuint *names)
{
    tsr_state_ctx *c = self;
    for (GLsizei i = 0; i < n; i++) {
        st_bufobj *b = calloc(1, sizeof *b);
        GLuint name = c->buffers.max_key + 1;
        if (!b || tsr_name_map_put(&c->buffers, name, b) != 0) {
            free(b);
            names[i] = 0;
            continue;
        }
        b->name = name;
        b->uid = c->t->next_uid++;
        b->usage = GL_STATIC_DRAW;
        names[i] = name;
    }
}

static GLuint *buffer_binding(tsr_state_ctx *c, GLenum target)
{
    if (target == GL_ARRAY_BUFFER)
        return &c->v.array_buffer;
    if (target == GL_ELEMENT_ARRAY_BUFFER)
        return &c->v.element_buffer;
    if (target == GL_PIXEL_PACK_BUFFER)
        return &c->v.pixel_pack_buffer;
    if (target == GL_PIXEL_UNPACK_BUFFER)
        return &c->v.pixel_unpack_buffer;
    return NULL;
}

static void st_BindBuffer(void *self, GLenum target, GLuint name)
{
    tsr_state_ctx *c = self;
    GLuint *binding = buffer_binding(c, target);
    if (!binding)
        return;
    if (name) {
        st_bufobj *b = tsr_name_map_get(&c->buffers, name);
        if (!b) {
            b = calloc(1, sizeof *b);
            if (!b || tsr_name_map_put(&c->buffers, name, b) != 0) {
                free(b);
                return;
            }
            b->name = name;
            b->uid = c->t->next_uid++;
            b->usage = GL_STATIC_DRAW;
        }
        b->bound = 1;
    }
    *binding = name;
    st_mark(c, TSR_SM_BUFBIND);
}

static void st_BufferData(void *self, GLenum target, GLsizeiptr size, const void *data, GLenum usage)
{
    tsr_state_ctx *c = self;
    GLuint *binding = buffer_binding(c, target);
    st_bufobj *b = binding ? tsr_name_map_get(&c->buffers, *binding) : NULL;
    if (!b || size < 0)
        return;
    uint8_t *copy = calloc(1, size ? (size_t)size : 1);
    if (!copy)
        return;
    if (data)
        memcpy(copy, data, (size_t)size);
    free(b->data);
    b->data = copy;
    b->mapped = 0; /* GL unmaps it (state_map.c) */
    b->size = size;
    b->usage = usage;
    b->version++;
    st_mark(c, TSR_SM_BUFBIND);
}

static void st_BufferSubData(void *self, GLenum target, GLintptr offset, GLsizeiptr size, const void *data)
{
    tsr_state_ctx *c = self;
    GLuint *binding = buffer_binding(c, target);
    st_bufobj *b = binding ? tsr_name_map_get(&c->buffers, *binding) : NULL;
    if (!b || !b->data || offset < 0 || size < 0 || offset + size > b->size)
        return;
    memcpy(b->data + offset, data, (size_t)size);
    b->version++;
    st_mark(c, TSR_SM_BUFBIND);
}

static void st_DeleteBuffers(void *self, GLsizei n, const GLuint *names)
{
    tsr_state_ctx *c = self;
    for (GLsizei i = 0; i < n; i++) {
        st_bufobj *b = tsr_name_map_del(&c->buffers, names[i]);
        if (!b)
            continue;
        if (c->v.array_buffer == names[i])
            c->v.array_buffer = 0;
        if (c->v.element_buffer == names[i])
            c->v.element_buffer = 0;
        if (c->v.pixel_pack_buffer == names[i])
            c->v.pixel_pack_buffer = 0;
        if (c->v.pixel_unpack_buffer == names[i])
            c->v.pixel_unpack_buffer = 0;
        /* GL also unbinds it from every array that sources it. */
        tsr_state_array *arrays[7 + TSR_STATE_UNITS + TSR_STATE_ATTRIBS];
        size_t na = 0;
        arrays[na++] = &c->client.vertex;
        arrays[na++] = &c->client.normal;
        arrays[na++] = &c->client.color;
        arrays[na++] = &c->client.edge_flag;
        arrays[na++] = &c->client.secondary_color;
        arrays[na++] = &c->client.fog_coord;
        arrays[na++] = &c->client.index;
        for (int u = 0; u < TSR_STATE_UNITS; u++)
            arrays[na++] = &c->client.texcoord[u];
        for (int a = 0; a < TSR_STATE_ATTRIBS; a++)
            arrays[na++] = &c->client.attrib[a];
        for (size_t k = 0; k < na; k++)
            if (arrays[k]->buffer == names[i])
                arrays[k]->buffer = 0;
        st_mark(c, TSR_SM_BUFBIND);
        free(b->data);
        free(b);
    }
}

/* --- display lists (names; their contents are the sender's business) ------------ */
static GLuint st_GenLists(void *self, GLsizei range)
{
    tsr_state_ctx *c = self;
    if (range <= 0)
        return 0;
    GLuint first = c->lists.max_key + 1;
    for (GLsizei i = 0; i < range; i++)
        if (tsr_name_map_put(&c->lists, first + (GLuint)i, (void *)1) != 0)
            return 0;
    return first;
}

static void st_NewList(void *self, GLuint list, GLenum mode)
{
    tsr_state_ctx *c = self;
    if (!list || (mode != GL_COMPILE && mode != GL_COMPILE_AND_EXECUTE) || c->list_mode)
        return;
    tsr_name_map_put(&c->lists, list, (void *)1);
    c->list_mode = mode;
    c->list_name = list;
}

static void st_EndList(void *self)
{
    tsr_state_ctx *c = self;
    c->list_mode = 0;
    c->list_name = 0;
}

static void st_DeleteLists(void *self, GLuint list, GLsizei range)
{
    tsr_state_ctx *c = self;
    for (GLsizei i = 0; i < range; i++)
        tsr_name_map_del(&c->lists, list + (GLuint)i);
}

void st_obj_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d)
{
#define SET(name) tsr_set_##name(d, st_##name, c)
    SET(GenTextures);
    SET(BindTexture);
    SET(DeleteTextures);
    SET(PrioritizeTextures);
    SET(TexParameterf);
    SET(TexParameterfv);
    SET(TexParameteri);
    SET(TexParameteriv);
    SET(TexParameterIivEXT);
    SET(TexParameterIuivEXT);
    SET(TexImage1D);
    SET(TexImage2D);
    SET(TexImage3D);
    SET(TexSubImage1D);
    SET(TexSubImage2D);
    SET(TexSubImage3D);
    SET(GenerateMipmap);
    SET(GenBuffers);
    SET(BindBuffer);
    SET(BufferData);
    SET(BufferSubData);
    SET(DeleteBuffers);
    SET(GenLists);
    SET(NewList);
    SET(EndList);
    SET(DeleteLists);
#undef SET
}
