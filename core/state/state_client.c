/* core/state/state_client.c — client state: the pixel store, the client
 * arrays (pointers, enables, glInterleavedArrays) and the client attribute
 * stack (glPushClientAttrib/glPopClientAttrib).
 *
 * Owns: tsr_state_client and the client stack of a tracked context, and
 * the pixel store of tsr_state_values.
 *
 * Never: skips a call made inside glNewList(GL_COMPILE): GL executes client
 * state at once, so these setters take self as it is (no st_exec_ctx).
 * The arrays are tracked for gets and push/pop only: their contents travel
 * with each draw, never through a diff. */
#include "state_internal.h"

/* --- pixel store --------------------------------------------------------------------- */
/* GL's errors first: an unknown pname, an alignment other than 1, 2, 4 or
 * 8, a length or skip that rounds below 0 (piglit's roundmode-pixelstore);
 * the swap and LSB flags take any value. */
static void pixel_store(tsr_state_ctx *c, GLenum pname, double v)
{
    if (!tsr_pixel_store_set(&c->v.pixel_store, pname, v)) { /* a value GL refuses is left alone */
        st_error(c, GL_INVALID_ENUM);
        return;
    }
    int flag = pname == GL_PACK_SWAP_BYTES || pname == GL_UNPACK_SWAP_BYTES || pname == GL_PACK_LSB_FIRST ||
               pname == GL_UNPACK_LSB_FIRST;
    double rounded = v < 0 ? v - 0.5 : v + 0.5;
    int alignment = pname == GL_PACK_ALIGNMENT || pname == GL_UNPACK_ALIGNMENT;
    int aligned = rounded >= 1 && rounded < 9 && ((int)rounded & ((int)rounded - 1)) == 0;
    if (!flag && (alignment ? !aligned : rounded <= -1))
        st_error(c, GL_INVALID_VALUE);
    else
        st_mark(c, TSR_SM_PIXELSTORE);
}

static void st_PixelStorei(void *self, GLenum pname, GLint v) { pixel_store(self, pname, v); }

static void st_PixelStoref(void *self, GLenum pname, GLfloat v) { pixel_store(self, pname, v); }

/* --- client attribute stack ------------------------------------------------------ */
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

/* --- client arrays --------------------------------------------------------------- */
static void set_pointer(tsr_state_ctx *c, tsr_state_array *a, GLint size, GLenum type, GLsizei stride, const void *ptr)
{
    a->size = size;
    a->type = type;
    a->stride = stride;
    a->pointer = ptr;
    a->buffer = c->v.array_buffer;
}

static void st_VertexPointer(void *self, GLint size, GLenum type, GLsizei stride, const void *p)
{
    tsr_state_ctx *c = self;
    set_pointer(c, &c->client.vertex, size, type, stride, p);
}
static void st_NormalPointer(void *self, GLenum type, GLsizei stride, const void *p)
{
    tsr_state_ctx *c = self;
    set_pointer(c, &c->client.normal, 3, type, stride, p);
}
static void st_ColorPointer(void *self, GLint size, GLenum type, GLsizei stride, const void *p)
{
    tsr_state_ctx *c = self;
    set_pointer(c, &c->client.color, size, type, stride, p);
}
static void st_TexCoordPointer(void *self, GLint size, GLenum type, GLsizei stride, const void *p)
{
    tsr_state_ctx *c = self;
    set_pointer(c, &c->client.texcoord[c->client.client_active_texture], size, type, stride, p);
}
static void st_EdgeFlagPointer(void *self, GLsizei stride, const void *p)
{
    tsr_state_ctx *c = self;
    set_pointer(c, &c->client.edge_flag, 1, GL_BOOL, stride, p);
}

/* Pointers GL refuses (a size or type it does not take) leave the array
 * as it was; the packer raises their error. */
static void st_SecondaryColorPointer(void *self, GLint size, GLenum type, GLsizei stride, const void *p)
{
    tsr_state_ctx *c = self;
    if (size == 3 && stride >= 0 && ((type >= GL_BYTE && type <= GL_FLOAT) || type == GL_DOUBLE))
        set_pointer(c, &c->client.secondary_color, size, type, stride, p);
}
static void st_FogCoordPointer(void *self, GLenum type, GLsizei stride, const void *p)
{
    tsr_state_ctx *c = self;
    if (stride >= 0 && (type == GL_FLOAT || type == GL_DOUBLE))
        set_pointer(c, &c->client.fog_coord, 1, type, stride, p);
}
static void st_IndexPointer(void *self, GLenum type, GLsizei stride, const void *p)
{
    tsr_state_ctx *c = self;
    if (stride >= 0 &&
        (type == GL_UNSIGNED_BYTE || type == GL_SHORT || type == GL_INT || type == GL_FLOAT || type == GL_DOUBLE))
        set_pointer(c, &c->client.index, 1, type, stride, p);
}

static void st_VertexAttribPointer(void *self, GLuint index, GLint size, GLenum type, GLboolean normalized,
                                   GLsizei stride, const void *p)
{
    tsr_state_ctx *c = self;
    if (index >= TSR_STATE_ATTRIBS)
        return;
    set_pointer(c, &c->client.attrib[index], size, type, stride, p);
    c->client.attrib[index].normalized = normalized ? GL_TRUE : GL_FALSE;
}

static void st_EnableClientState(void *self, GLenum array)
{
    tsr_state_ctx *c = self;
    tsr_state_array *a = st_client_array(c, array);
    if (a)
        a->enabled = GL_TRUE;
}
static void st_DisableClientState(void *self, GLenum array)
{
    tsr_state_ctx *c = self;
    tsr_state_array *a = st_client_array(c, array);
    if (a)
        a->enabled = GL_FALSE;
}
static void st_EnableVertexAttribArray(void *self, GLuint i)
{
    tsr_state_ctx *c = self;
    if (i < TSR_STATE_ATTRIBS)
        c->client.attrib[i].enabled = GL_TRUE;
}
static void st_DisableVertexAttribArray(void *self, GLuint i)
{
    tsr_state_ctx *c = self;
    if (i < TSR_STATE_ATTRIBS)
        c->client.attrib[i].enabled = GL_FALSE;
}

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
    case GL_V2F:
        vs = 2;
        pv = 0;
        n = 2 * f;
        break;
    case GL_V3F:
        vs = 3;
        pv = 0;
        n = 3 * f;
        break;
    case GL_C4UB_V2F:
        cs = 4;
        ct = GL_UNSIGNED_BYTE;
        vs = 2;
        pc = 0;
        pv = 4;
        n = 4 + 2 * f;
        break;
    case GL_C4UB_V3F:
        cs = 4;
        ct = GL_UNSIGNED_BYTE;
        vs = 3;
        pc = 0;
        pv = 4;
        n = 4 + 3 * f;
        break;
    case GL_C3F_V3F:
        cs = 3;
        vs = 3;
        pc = 0;
        pv = 3 * f;
        n = 6 * f;
        break;
    case GL_N3F_V3F:
        pn = 1;
        vs = 3;
        pv = 3 * f;
        n = 6 * f;
        break;
    case GL_C4F_N3F_V3F:
        cs = 4;
        pc = 0;
        pn = 1;
        vs = 3;
        pv = 7 * f;
        n = 10 * f;
        break;
    case GL_T2F_V3F:
        tc = 2;
        vs = 3;
        pv = 2 * f;
        n = 5 * f;
        break;
    case GL_T4F_V4F:
        tc = 4;
        vs = 4;
        pv = 4 * f;
        n = 8 * f;
        break;
    case GL_T2F_C4UB_V3F:
        tc = 2;
        cs = 4;
        ct = GL_UNSIGNED_BYTE;
        pc = 2 * f;
        vs = 3;
        pv = 2 * f + 4;
        n = 2 * f + 4 + 3 * f;
        break;
    case GL_T2F_C3F_V3F:
        tc = 2;
        cs = 3;
        pc = 2 * f;
        vs = 3;
        pv = 5 * f;
        n = 8 * f;
        break;
    case GL_T2F_N3F_V3F:
        tc = 2;
        pn = 1;
        vs = 3;
        pv = 5 * f;
        n = 8 * f;
        break;
    case GL_T2F_C4F_N3F_V3F:
        tc = 2;
        cs = 4;
        pc = 2 * f;
        pn = 1;
        vs = 3;
        pv = 9 * f;
        n = 12 * f;
        break;
    case GL_T4F_C4F_N3F_V4F:
        tc = 4;
        cs = 4;
        pc = 4 * f;
        pn = 1;
        vs = 4;
        pv = 11 * f;
        n = 15 * f;
        break;
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

void st_client_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d)
{
#define SET(name) tsr_set_##name(d, st_##name, c)
    SET(PixelStorei);
    SET(PixelStoref);
    SET(PushClientAttrib);
    SET(PopClientAttrib);
    SET(VertexPointer);
    SET(NormalPointer);
    SET(ColorPointer);
    SET(TexCoordPointer);
    SET(EdgeFlagPointer);
    SET(VertexAttribPointer);
    SET(SecondaryColorPointer);
    SET(FogCoordPointer);
    SET(IndexPointer);
    SET(EnableClientState);
    SET(DisableClientState);
    SET(EnableVertexAttribArray);
    SET(DisableVertexAttribArray);
    SET(ClientActiveTexture);
    SET(InterleavedArrays);
#undef SET
}
