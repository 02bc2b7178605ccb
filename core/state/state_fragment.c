/* core/state/state_fragment.c — setters of the per-fragment operations and
 * the framebuffer controls: blending, alpha test, logic op, color mask,
 * clear values, draw and read buffers, depth and stencil.
 *
 * Owns: the COLORBUF, DEPTH and STENCIL groups of tsr_state_values.
 *
 * Never: keeps a value other than the one the renderer keeps after the
 * same call (the alpha reference and the clear depth are clamped here
 * because GL clamps them): gets answer from these values, and diffs
 * compare them with what each renderer holds. */
#include "state_internal.h"

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
    c->v.clear_color_type = 0;
    st_mark(c, TSR_SM_CLEARCOLOR);
}

/* GL_EXT_texture_integer: the clear colour of integer colour buffers. GL
 * keeps one clear colour (Mesa a union of floats and integers), so an
 * integer one replaces glClearColor's. */
static void clear_color_int(tsr_state_ctx *c, GLenum type, GLuint r, GLuint g, GLuint b, GLuint a)
{
    c->v.clear_color_type = type;
    c->v.clear_color_int[0] = r;
    c->v.clear_color_int[1] = g;
    c->v.clear_color_int[2] = b;
    c->v.clear_color_int[3] = a;
    st_mark(c, TSR_SM_CLEARCOLOR);
}

static void st_ClearColorIiEXT(void *self, GLint r, GLint g, GLint b, GLint a)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (c)
        clear_color_int(c, GL_INT, (GLuint)r, (GLuint)g, (GLuint)b, (GLuint)a);
}

static void st_ClearColorIuiEXT(void *self, GLuint r, GLuint g, GLuint b, GLuint a)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (c)
        clear_color_int(c, GL_UNSIGNED_INT, r, g, b, a);
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
    c->v.draw_buffer = ST_BUFFER_TRACKED(buf);
    st_mark(c, TSR_SM_DRAWBUFFER);
}

static void st_DrawBuffers(void *self, GLsizei n, const GLenum *bufs)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (n >= 1) {
        c->v.draw_buffer = ST_BUFFER_TRACKED(bufs[0]);
        st_mark(c, TSR_SM_DRAWBUFFER);
    }
}

static void st_ReadBuffer(void *self, GLenum buf)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    c->v.read_buffer = ST_BUFFER_TRACKED(buf);
    st_mark(c, TSR_SM_DRAWBUFFER);
}

/* --- depth, stencil --------------------------------------------------------------- */
static void st_DepthFunc(void *self, GLenum f)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    if (!c)
        return;
    if (f < GL_NEVER || f > GL_ALWAYS) {
        st_error(c, GL_INVALID_ENUM);
        return;
    }
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

void st_fragment_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d)
{
#define SET(name) tsr_set_##name(d, st_##name, c)
    SET(BlendFunc);
    SET(BlendFuncSeparate);
    SET(BlendEquation);
    SET(BlendEquationSeparate);
    SET(BlendColor);
    SET(AlphaFunc);
    SET(LogicOp);
    SET(ColorMask);
    SET(ClearColor);
    SET(ClearColorIiEXT);
    SET(ClearColorIuiEXT);
    SET(ClearAccum);
    SET(DrawBuffer);
    SET(DrawBuffers);
    SET(ReadBuffer);
    SET(DepthFunc);
    SET(DepthMask);
    SET(ClearDepth);
    SET(ClearStencil);
    SET(StencilFunc);
    SET(StencilFuncSeparate);
    SET(StencilOp);
    SET(StencilOpSeparate);
    SET(StencilMask);
    SET(StencilMaskSeparate);
#undef SET
}
