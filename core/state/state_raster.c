/* core/state/state_raster.c — setters of rasterization and the rest of the
 * fixed pipeline: glEnable/glDisable, viewport, scissor box, depth range and
 * the window's size, fog, polygons, lines and points, hints, the list base,
 * sample coverage, pixel zoom and pixel transfer.
 *
 * Owns: the ENABLE, VIEWPORT, FOG, RASTER, HINT and MISC groups of
 * tsr_state_values, and the PIXEL group's modes (the pixel store is client
 * state: state_client.c).
 *
 * Never: sets the viewport or scissor box from anything but the
 * application's calls or the window's real size (both start unknown). */
#include "state_internal.h"

#include <string.h>

/* --- enables ------------------------------------------------------------------------ */
static void set_enable(tsr_state_ctx *c, GLenum cap, int on)
{
    /* glEnable of a client array is glEnableClientState in Mesa (its
     * compatibility contexts take both; piglit's gl-1.1-color-material-array
     * enables its arrays so): the arrays a draw reads are the tracker's */
    tsr_state_array *a = st_client_array(c, cap);
    if (a) {
        a->enabled = on ? GL_TRUE : GL_FALSE;
        return;
    }
    int idx = st_enable_index(cap, c->v.active_texture);
    if (idx == -2) {
        /* a unit past the coordinate units has no fixed-function state:
         * Mesa ignores a texture target's enable there, refuses texgen's */
        if (cap >= GL_TEXTURE_GEN_S && cap <= GL_TEXTURE_GEN_Q)
            st_error(c, GL_INVALID_OPERATION);
        return;
    }
    if (idx < 0) {
        /* every cap of Mesa's GL 2.1 is in st_enable_caps but the
         * colour-index logic op, which does nothing in an RGBA context */
        if (cap != GL_INDEX_LOGIC_OP)
            st_error(c, GL_INVALID_ENUM);
        return;
    }
    uint64_t bit = 1ull << (idx & 63), *w = &c->v.enables[idx >> 6];
    if (((*w & bit) != 0) == (on != 0))
        return;
    *w = on ? (*w | bit) : (*w & ~bit);
    st_mark(c, TSR_SM_ENABLE0 + (idx >> 6));
    if (idx == ST_EN_COLOR_MATERIAL && on)
        st_color_material_update(c);
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
/* glViewport's and glScissor's box; GL ignores a negative size. */
static void set_box(tsr_state_ctx *c, GLint box[4], int member, GLint x, GLint y, GLsizei w, GLsizei h)
{
    if (w < 0 || h < 0)
        return;
    box[0] = x;
    box[1] = y;
    box[2] = w;
    box[3] = h;
    st_mark(c, member);
}

static void st_Viewport(void *self, GLint x, GLint y, GLsizei w, GLsizei h)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    set_box(c, c->v.viewport, TSR_SM_VIEWPORT, x, y, w, h);
}

static void st_Scissor(void *self, GLint x, GLint y, GLsizei w, GLsizei h)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    set_box(c, c->v.scissor, TSR_SM_SCISSOR, x, y, w, h);
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

/* glWindowSizeTSR, and glWindowCreateTSR (a new window has its size): the
 * window system sized the window. Like the render SPU (and a window system
 * making a context current the first time), an unknown viewport and
 * scissor box become the window. */
static void st_WindowSizeTSR(void *self, GLint window, GLsizei w, GLsizei h)
{
    (void)window;
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c || c->v.viewport[2] >= 0 || w <= 0 || h <= 0)
        return;
    set_box(c, c->v.viewport, TSR_SM_VIEWPORT, 0, 0, w, h);
    set_box(c, c->v.scissor, TSR_SM_SCISSOR, 0, 0, w, h);
}

/* --- fog ---------------------------------------------------------------------------- */
static void fog(tsr_state_ctx *c, GLenum pname, const GLfloat *p)
{
    tsr_state_values *v = &c->v;
    switch (pname) {
    case GL_FOG_MODE: v->fog_mode = (GLenum)p[0]; break;
    case GL_FOG_DENSITY:
        if (p[0] < 0)
            return;
        v->fog_density = p[0];
        break;
    case GL_FOG_START: v->fog_start = p[0]; break;
    case GL_FOG_END: v->fog_end = p[0]; break;
    case GL_FOG_INDEX: v->fog_index = p[0]; break;
    case GL_FOG_COLOR:
        for (int i = 0; i < 4; i++)
            v->fog_color[i] = st_clampf(p[i]);
        break;
    case GL_FOG_COORD_SRC: v->fog_coord_src = (GLenum)p[0]; break;
    default: st_error(c, GL_INVALID_ENUM); return;
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
    mask = st_unpack_source(c, mask, l.extent);
    if (!mask)
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
                *dst &= (GLubyte) ~(0x80u >> (x % 8));
        }
    }
    st_mark(c, TSR_SM_STIPPLE);
}

static void st_LineWidth(void *self, GLfloat w)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (w <= 0) {
        st_error(c, GL_INVALID_VALUE);
        return;
    }
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
    case GL_POINT_SIZE_MIN:
        if (p[0] < 0)
            return;
        v->point_min = p[0];
        break;
    case GL_POINT_SIZE_MAX:
        if (p[0] < 0)
            return;
        v->point_max = p[0];
        break;
    case GL_POINT_FADE_THRESHOLD_SIZE:
        if (p[0] < 0)
            return;
        v->point_fade = p[0];
        break;
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
    GL_PERSPECTIVE_CORRECTION_HINT,
    GL_POINT_SMOOTH_HINT,
    GL_LINE_SMOOTH_HINT,
    GL_POLYGON_SMOOTH_HINT,
    GL_FOG_HINT,
    GL_GENERATE_MIPMAP_HINT,
    GL_TEXTURE_COMPRESSION_HINT,
    GL_FRAGMENT_SHADER_DERIVATIVE_HINT,
};

static void st_Hint(void *self, GLenum target, GLenum mode)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (mode != GL_FASTEST && mode != GL_NICEST && mode != GL_DONT_CARE) {
        st_error(c, GL_INVALID_ENUM);
        return;
    }
    for (int i = 0; i < 8; i++)
        if (hint_targets[i] == target) {
            c->v.hint[i] = mode;
            st_mark(c, TSR_SM_HINT);
            return;
        }
    st_error(c, GL_INVALID_ENUM);
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

/* --- pixel modes ---------------------------------------------------------------- */
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

void st_raster_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d)
{
#define SET(name) tsr_set_##name(d, st_##name, c)
    SET(Enable);
    SET(Disable);
    SET(Viewport);
    SET(Scissor);
    SET(DepthRange);
    SET(WindowSizeTSR);
    SET(Fogf);
    SET(Fogfv);
    SET(Fogi);
    SET(Fogiv);
    SET(CullFace);
    SET(FrontFace);
    SET(PolygonMode);
    SET(PolygonOffset);
    SET(PolygonStipple);
    SET(LineWidth);
    SET(LineStipple);
    SET(PointSize);
    SET(PointParameterf);
    SET(PointParameterfv);
    SET(PointParameteri);
    SET(PointParameteriv);
    SET(Hint);
    SET(ListBase);
    SET(SampleCoverage);
    SET(PixelZoom);
    SET(PixelTransferf);
    SET(PixelTransferi);
#undef SET
    /* Creating a window gives it its size. */
    tsr_set_WindowCreateTSR(d, st_WindowSizeTSR, c);
}
