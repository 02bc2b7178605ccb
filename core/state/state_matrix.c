/* core/state/state_matrix.c — the matrix stacks: glLoad/Mult/Translate/
 * Scale/Rotate/Frustum/Ortho, glMatrixMode, glPushMatrix/glPopMatrix,
 * glClipPlane, and each level's recipe (how it was built since its last
 * load, tsr_state_recipe).
 *
 * Owns: the stacks of tsr_state_stacks and their recipes, and how a fresh
 * stack starts. Mesa classifies a matrix by how it was built and lights
 * with different rounding per class, so a renderer must be given the same
 * history, not only the same values: that is what the recipes keep.
 *
 * Never: computes a matrix other than as Mesa does (same operation order,
 * same float/double conversions): the tracker's bits must be the bits a
 * renderer computes, or tilesort's bounding boxes and gets drift from
 * what the servers draw. */
#include "state_internal.h"

#include <math.h>
#include <string.h>

/* --- recipes ------------------------------------------------------------------- */
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

void st_recipe_copy(tsr_state_recipe *dst, const tsr_state_recipe *src)
{
    if (dst == src)
        return;
    memcpy(dst->base, src->base, sizeof dst->base);
    dst->base_is_identity = src->base_is_identity;
    dst->sticky = src->sticky;
    dst->count = src->count;
    memcpy(dst->kind, src->kind, src->count * sizeof dst->kind[0]);
    memcpy(dst->arg, src->arg, src->count * sizeof dst->arg[0]);
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

/* --- matrices -------------------------------------------------------------------- */
/* out = a * b, column-major, summed in the order Mesa's matmul4 uses. */
static void mat_mul(GLfloat out[16], const GLfloat a[16], const GLfloat b[16])
{
    GLfloat p[16];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            p[j * 4 + i] =
                a[i] * b[j * 4] + a[4 + i] * b[j * 4 + 1] + a[8 + i] * b[j * 4 + 2] + a[12 + i] * b[j * 4 + 3];
    memcpy(out, p, sizeof p);
}

static int mat_invert(GLfloat out[16], const GLfloat mf[16])
{
    double m[16], inv[16];
    for (int i = 0; i < 16; i++)
        m[i] = mf[i];
    inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] + m[9] * m[7] * m[14] +
             m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
    inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] - m[8] * m[7] * m[14] -
             m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
    inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] + m[8] * m[7] * m[13] +
             m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
    inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] - m[8] * m[6] * m[13] -
              m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
    inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] - m[9] * m[3] * m[14] -
             m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
    inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] + m[8] * m[3] * m[14] +
             m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
    inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] - m[8] * m[3] * m[13] -
             m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
    inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] + m[8] * m[2] * m[13] +
              m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
    inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] +
             m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
    inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] - m[4] * m[3] * m[14] -
             m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
    inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] + m[4] * m[3] * m[13] +
              m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
    inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] - m[4] * m[2] * m[13] -
              m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
    inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] - m[5] * m[3] * m[10] -
             m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
    inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] +
             m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
    inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] -
              m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
    inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] + m[8] * m[1] * m[6] -
              m[8] * m[2] * m[5];
    double det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
    if (det == 0.0) {
        identity(out);
        return -1;
    }
    for (int i = 0; i < 16; i++)
        out[i] = (GLfloat)(inv[i] / det);
    return 0;
}

/* The stack matrix mode selects (for GL_TEXTURE, the active unit's): its
 * levels, their recipes, its depth and limit, and its dirty-bit member. */
typedef struct mstack {
    GLfloat (*m)[16];
    tsr_state_recipe *r;
    uint32_t *depth, max;
    int member;
} mstack;

static mstack current_stack(tsr_state_ctx *c)
{
    tsr_state_stacks *s = &c->s;
    switch (c->v.matrix_mode) {
    case GL_PROJECTION:
        return (mstack){s->projection, s->projection_recipe, &s->projection_depth, TSR_STATE_PROJECTION_DEPTH,
                        TSR_SM_PROJECTION};
    case GL_TEXTURE: {
        GLuint u = c->v.active_texture;
        return (mstack){s->texture[u], s->texture_recipe[u], &s->texture_depth[u], TSR_STATE_TEXTURE_DEPTH,
                        TSR_SM_TEXMAT0 + (int)u};
    }
    default:
        return (mstack){s->modelview, s->modelview_recipe, &s->modelview_depth, TSR_STATE_MODELVIEW_DEPTH,
                        TSR_SM_MODELVIEW};
    }
}

static GLfloat *current_matrix(tsr_state_ctx *c, int *member)
{
    mstack k = current_stack(c);
    *member = k.member;
    return k.m[*k.depth - 1];
}

static tsr_state_recipe *current_recipe(tsr_state_ctx *c)
{
    mstack k = current_stack(c);
    return &k.r[*k.depth - 1];
}

/* The current matrix was loaded (or multiplied by an arbitrary matrix,
 * which Mesa also classifies from the values): it is the new base. */
static void recipe_rebase(tsr_state_ctx *c)
{
    int member;
    tsr_state_recipe *r = current_recipe(c);
    memcpy(r->base, current_matrix(c, &member), sizeof r->base);
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
    GLfloat *top = current_matrix(c, &member);
    mat_mul(top, top, m);
    st_mark(c, member);
}

static void st_LoadIdentity(void *self)
{
    tsr_state_ctx *c = st_matrix_ctx(self);
    if (!c)
        return;
    int member;
    identity(current_matrix(c, &member));
    recipe_identity(current_recipe(c));
    st_mark(c, member);
}

/* Mesa ignores a glLoadMatrix of the values the matrix already holds (it
 * keeps the matrix's classification too). */
static void load_matrix(tsr_state_ctx *c, const GLfloat m[16])
{
    int member;
    GLfloat *top = current_matrix(c, &member);
    if (!memcmp(top, m, 16 * sizeof *m))
        return;
    memcpy(top, m, 16 * sizeof *m);
    recipe_rebase(c);
    st_mark(c, member);
}

static void st_LoadMatrixf(void *self, const GLfloat *m)
{
    tsr_state_ctx *c = st_matrix_ctx(self);
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
    tsr_state_ctx *c = st_matrix_ctx(self);
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
    tsr_state_ctx *c = st_matrix_ctx(self);
    if (!c)
        return;
    GLfloat f[16];
    transpose(f, m);
    load_matrix(c, f);
}

/* Mesa returns from glMultMatrix at once when the matrix equals the
 * identity by value (== comparisons, so -0 counts as 0): neither the
 * values nor the classification change. */
static int is_identity_by_value(const GLfloat m[16])
{
    for (int i = 0; i < 16; i++)
        if (m[i] != (i % 5 == 0 ? 1.0f : 0.0f))
            return 0;
    return 1;
}

/* Mesa classifies the product of an arbitrary glMultMatrix from its
 * values, as it does a loaded matrix: the product is the new base. */
static void mult_matrix(tsr_state_ctx *c, const GLfloat m[16])
{
    if (is_identity_by_value(m))
        return;
    mat_apply(c, m);
    recipe_rebase(c);
}

static void st_MultMatrixf(void *self, const GLfloat *m)
{
    tsr_state_ctx *c = st_matrix_ctx(self);
    if (!c)
        return;
    mult_matrix(c, m);
}

static void st_MultMatrixd(void *self, const GLdouble *m)
{
    tsr_state_ctx *c = st_matrix_ctx(self);
    if (!c)
        return;
    GLfloat f[16];
    to_float16(f, m);
    mult_matrix(c, f);
}

static void st_MultTransposeMatrixf(void *self, const GLfloat *m)
{
    tsr_state_ctx *c = st_matrix_ctx(self);
    if (!c)
        return;
    GLfloat f[16];
    transpose(f, m);
    mult_matrix(c, f);
}

/* The double forms: Mesa converts to float first, then transposes. */
static void st_LoadTransposeMatrixd(void *self, const GLdouble *m)
{
    tsr_state_ctx *c = st_matrix_ctx(self);
    if (!c)
        return;
    GLfloat f[16], t[16];
    to_float16(f, m);
    transpose(t, f);
    load_matrix(c, t);
}

static void st_MultTransposeMatrixd(void *self, const GLdouble *m)
{
    tsr_state_ctx *c = st_matrix_ctx(self);
    if (!c)
        return;
    GLfloat f[16], t[16];
    to_float16(f, m);
    transpose(t, f);
    mult_matrix(c, t);
}

/* Mesa's _math_matrix_translate/scale: only the affected columns change. */
static void translate(tsr_state_ctx *c, GLfloat x, GLfloat y, GLfloat z)
{
    int member;
    GLfloat *m = current_matrix(c, &member);
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
    GLfloat *m = current_matrix(c, &member);
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
    tsr_state_ctx *c = st_matrix_ctx(self);
    if (!c)
        return;
    translate(c, x, y, z);
}

static void st_Translated(void *self, GLdouble x, GLdouble y, GLdouble z)
{
    tsr_state_ctx *c = st_matrix_ctx(self);
    if (!c)
        return;
    translate(c, (GLfloat)x, (GLfloat)y, (GLfloat)z);
}

static void st_Scalef(void *self, GLfloat x, GLfloat y, GLfloat z)
{
    tsr_state_ctx *c = st_matrix_ctx(self);
    if (!c)
        return;
    scale(c, x, y, z);
}

static void st_Scaled(void *self, GLdouble x, GLdouble y, GLdouble z)
{
    tsr_state_ctx *c = st_matrix_ctx(self);
    if (!c)
        return;
    scale(c, (GLfloat)x, (GLfloat)y, (GLfloat)z);
}

static void st_Rotatef(void *self, GLfloat a, GLfloat x, GLfloat y, GLfloat z)
{
    tsr_state_ctx *c = st_matrix_ctx(self);
    if (!c)
        return;
    rotate(c, a, x, y, z);
}

static void st_Rotated(void *self, GLdouble a, GLdouble x, GLdouble y, GLdouble z)
{
    tsr_state_ctx *c = st_matrix_ctx(self);
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
    tsr_state_ctx *c = st_matrix_ctx(self);
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
    tsr_state_ctx *c = st_matrix_ctx(self);
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
    if (mode != GL_MODELVIEW && mode != GL_PROJECTION && mode != GL_TEXTURE) {
        st_error(c, GL_INVALID_ENUM);
        return;
    }
    c->v.matrix_mode = mode;
    st_mark(c, TSR_SM_MODELVIEW); /* matrix mode travels with the stacks */
}

static void st_PushMatrix(void *self)
{
    tsr_state_ctx *c = st_matrix_ctx(self);
    if (!c)
        return;
    mstack k = current_stack(c);
    uint32_t d = *k.depth;
    if (d >= k.max) {
        st_error(c, GL_STACK_OVERFLOW);
        return;
    }
    memcpy(k.m[d], k.m[d - 1], sizeof k.m[0]);
    st_recipe_copy(&k.r[d], &k.r[d - 1]);
    *k.depth = d + 1;
    st_mark(c, k.member);
}

static void st_PopMatrix(void *self)
{
    tsr_state_ctx *c = st_matrix_ctx(self);
    if (!c)
        return;
    mstack k = current_stack(c);
    if (*k.depth <= 1) {
        st_error(c, GL_STACK_UNDERFLOW);
        return;
    }
    (*k.depth)--;
    st_mark(c, k.member);
}

/* GL transforms a plane by the inverse modelview (Mesa: row vector times
 * the inverse). */
void st_plane_to_eye(const tsr_state_ctx *c, GLfloat out[4], const GLfloat in[4])
{
    GLfloat inv[16];
    mat_invert(inv, c->s.modelview[c->s.modelview_depth - 1]);
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
    st_plane_to_eye(c, c->v.clip_plane[plane - GL_CLIP_PLANE0], f);
    st_mark(c, TSR_SM_CLIP);
}

void st_matrix_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d)
{
#define SET(name) tsr_set_##name(d, st_##name, c)
    SET(LoadIdentity);
    SET(LoadMatrixf);
    SET(LoadMatrixd);
    SET(LoadTransposeMatrixd);
    SET(MultTransposeMatrixd);
    SET(LoadTransposeMatrixf);
    SET(MultMatrixf);
    SET(MultMatrixd);
    SET(MultTransposeMatrixf);
    SET(Translatef);
    SET(Translated);
    SET(Scalef);
    SET(Scaled);
    SET(Rotatef);
    SET(Rotated);
    SET(Frustum);
    SET(Ortho);
    SET(MatrixMode);
    SET(PushMatrix);
    SET(PopMatrix);
    SET(ClipPlane);
#undef SET
}
