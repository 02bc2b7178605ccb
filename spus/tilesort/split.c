/* spus/tilesort/split.c — a glBegin/glEnd primitive cut across geometry
 * buffers: each buffer is closed with glEnd, so its box places it only on
 * the servers it touches, and the next reopens the primitive.
 *
 * Why at flush time, and not per vertex: the geometry buffer fills inside
 * the packer (core/wire/pack.c), between two commands, so the SPU learns of a
 * cut only when a full buffer reaches its sink. Watching every glVertex
 * would tax every primitive; reading the buffer back taxes only the ones
 * that are cut. A cut buffer is
 *   1. scanned: its commands run into a scratch state tracker (the current
 *      attributes, converted as the tracker converts the application's)
 *      and into our Begin/End/Vertex functions, which count the
 *      primitive's vertices and keep its first and last four (position,
 *      current attributes, and where in the buffer each vertex command
 *      ends: the scan yields after each). Any other command inside the
 *      primitive (a display list, an evaluator, glVertexAttrib(0, ...))
 *      makes it opaque: it then goes whole to every server, as before;
 *   2. spliced, byte for byte (no command is re-encoded: draws and images
 *      in the buffer stay as packed): [glBegin, the vertices carried from
 *      the last piece each with its attributes, the attributes put back to
 *      the buffer's start] + [the buffer's commands, perhaps without its
 *      last vertex; a line loop's glBegin made GL_LINE_STRIP] + [the
 *      closing vertex, the attributes put back to the application's,
 *      glEnd]. The added parts are packed by a small packer of our own;
 *      data offsets keep their alignment because each added part starts
 *      and ends on 8 bytes, padded with glEdgeFlag commands (one byte each)
 *      that repeat the edge flag in force.
 * A server holds the buffer's start attributes before a piece (its diff
 * and send.c's send_start_current), and the application's at the end
 * of the buffer after it: the promise every geometry buffer keeps.
 *
 * Exactness (tests/tilesort: 0 differing pixels against one OSMesa
 * window), mode by mode; Mesa decomposes each mode by the GL rules, so the
 * pieces draw the same primitives with the same vertex order and
 * provoking vertex:
 *   points                 cut anywhere;
 *   lines, triangles,      the incomplete primitive's vertices are carried
 *   quads                  (GL ignores them at the piece's glEnd);
 *   line strip             the last vertex is carried;
 *   line loop              drawn as line strips; its glEnd re-sends the
 *                          first vertex (ts_split_end), which, as in a
 *                          loop, gives the closing segment its flat colour;
 *   triangle strip         the last two are carried after an even number
 *                          of vertices, so every triangle keeps its parity
 *                          (winding: culling, two-sided lighting); after an
 *                          odd number the last vertex is dropped from the
 *                          piece and three are carried;
 *   quad strip             from the first vertex of the incomplete quad;
 *   triangle fan           the first vertex and the last;
 *   polygon                the first vertex and the last; the last is
 *                          dropped from the piece and sent again with edge
 *                          flag false, and the first is re-sent with edge
 *                          flag false, so glPolygonMode(GL_LINE) draws no
 *                          internal closing edge; flat shading takes the
 *                          first vertex's colour in every piece.
 * Not cut, sent whole to every server: primitives while a program is in
 * use (the caller's may_cut), strips, loops, fans and
 * polygons under line stipple (GL restarts the pattern at each glBegin),
 * opaque ones (above), and quads and quad strips under lighting: lit quads
 * cut into pieces of a few vertices were lit slightly differently by Mesa
 * (tilescenes frame 14 with 256-byte batches: 39568 pixels, at most 14 of
 * 255 off; lit triangles, unlit quads and every other case were exact);
 * probably the cause found for engine (tests/render/quad_diagonal_test.c:
 * llvmpipe cuts a quad along 0-2 or 1-3 by what else its draw holds, and
 * the diagonals light differently), not re-measured on tilescenes.
 *
 * Owns: the scratch tracker, the scan table and unpacker, the small packer
 * and the piece's bytes. No globals. */
#include <stdlib.h>
#include <string.h>

#include "tessera/dev/pack.h"
#include "tessera/dev/state.h"
#include "tilesort.h"
#include "tessera/dev/unpack.h"
#include "tessera/dev/wire.h"

typedef struct ts_vertex {
    float pos[4];
    int size;       /* components the application gave (2, 3, 4): sent the same way */
    uint32_t cmd;   /* commands of the buffer up to and including this vertex */
    size_t pos_end; /* data offset where its command ends */
    ts_current attrs;
} ts_vertex;

/* Components of the application's last call setting each attribute (see
 * color() below). */
typedef struct ts_sizes {
    uint8_t color, tex[TSR_STATE_UNITS], attrib[TSR_STATE_ATTRIBS];
} ts_sizes;

typedef struct ts_bytes {
    uint8_t *b;
    size_t size, cap;
} ts_bytes;

struct ts_split {
    /* the primitive the current geometry buffer starts inside */
    int open;  /* the buffer starts inside a primitive cut before */
    int ended; /* that primitive's glEnd is in the buffer */
    GLenum mode;
    uint64_t count; /* its vertices so far */
    ts_vertex first;
    ts_vertex tail[3]; /* its last min(3, count) vertices, oldest first */
    int ntail;
    uint32_t mask;  /* the attributes set inside it (M_* bits) */
    ts_sizes sizes; /* the components of the last call setting each (see color()) */
    /* the scan */
    tsr_state_tracker *tracker;
    tsr_state_ctx *scratch;
    tsr_dispatch tracked; /* the scratch tracker's functions */
    tsr_dispatch scan;
    tsr_hook *hooks;
    uint8_t *kind;  /* per slot: the attribute a current-attribute command sets (K_*) */
    uint8_t *ncomp; /* per slot: its components */
    tsr_unpacker *scanner;
    int inside, opaque, began, tex_any, tex_any_size;
    uint32_t seen;
    ts_sizes ssizes;
    GLenum smode;
    uint64_t scount, new_vertices;
    ts_vertex sfirst, ring[4], begin; /* begin: where the last glBegin ends, the attributes there */
    ts_vertex *pending;               /* its position is known after the yield */
    /* the added parts */
    tsr_packer *packer;
    tsr_dispatch added;
    ts_bytes *sink_to, prefix, close, out;
    int sink_calls;
    uint8_t edge_opcode;
};

/* --- current attributes ---------------------------------------------------- */

void ts_current_of(const tsr_state_values *v, ts_current *out)
{
    memcpy(out->color, v->color, sizeof out->color);
    memcpy(out->normal, v->normal, sizeof out->normal);
    memcpy(out->texcoord, v->texcoord, sizeof out->texcoord);
    out->edge_flag = v->edge_flag;
    memcpy(out->attrib, v->attrib, sizeof out->attrib);
}

/* The attributes set inside a primitive, as mask bits. Mesa's immediate
 * mode builds a draw's vertex format from the attributes set inside
 * glBegin/glEnd (per-vertex inputs; the others are constants), so every
 * piece sets, right after its glBegin, each attribute the primitive has
 * set so far, even when the value did not change: its draw then has the
 * inputs the whole primitive's had. */
enum { M_COLOR = 1u, M_NORMAL = 2u, M_EDGE = 4u, M_TEX0 = 8u, M_ATTRIB0 = M_TEX0 << TSR_STATE_UNITS };
enum { K_NONE, K_COLOR, K_NORMAL, K_EDGE, K_TEX0, K_TEXANY };

/* Mesa stores an attribute with as many components as the call that set
 * it, and a primitive drawn with a 4-component colour or texture
 * coordinate does not always round like one drawn with 3 or 2 (measured:
 * tilescenes frames 12 and 14): so each is re-sent with the size of the
 * application's last call for it (4 when it made none). */
static void color(const tsr_dispatch *out, int n, const GLfloat *c)
{
    if (n == 3)
        tsr_call_Color3f(out, c[0], c[1], c[2]);
    else
        tsr_call_Color4f(out, c[0], c[1], c[2], c[3]);
}

static void texcoord(const tsr_dispatch *out, int n, GLenum unit, const GLfloat *t)
{
    switch (n) {
    case 1: tsr_call_MultiTexCoord1f(out, unit, t[0]); break;
    case 2: tsr_call_MultiTexCoord2f(out, unit, t[0], t[1]); break;
    case 3: tsr_call_MultiTexCoord3f(out, unit, t[0], t[1], t[2]); break;
    default: tsr_call_MultiTexCoord4f(out, unit, t[0], t[1], t[2], t[3]); break;
    }
}

static void attrib(const tsr_dispatch *out, int n, GLuint index, const GLfloat *a)
{
    switch (n) {
    case 1: tsr_call_VertexAttrib1f(out, index, a[0]); break;
    case 2: tsr_call_VertexAttrib2f(out, index, a[0], a[1]); break;
    case 3: tsr_call_VertexAttrib3f(out, index, a[0], a[1], a[2]); break;
    default: tsr_call_VertexAttrib4f(out, index, a[0], a[1], a[2], a[3]); break;
    }
}

static const ts_sizes four = {4, {4, 4, 4, 4, 4, 4, 4, 4}, {4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4}};

/* Emits the attributes of `to` that differ from `from`, and those in
 * `force`; all of them when from is NULL. Generic attribute 0 only then:
 * inside glBegin it would be a vertex (it aliases the position). */
static void emit_attrs_forced(const tsr_dispatch *out, const ts_current *from, const ts_current *to, uint32_t force,
                              const ts_sizes *z)
{
    if (!from || (force & M_COLOR) || memcmp(from->color, to->color, sizeof to->color))
        color(out, z->color, to->color);
    if (!from || (force & M_NORMAL) || memcmp(from->normal, to->normal, sizeof to->normal))
        tsr_call_Normal3f(out, to->normal[0], to->normal[1], to->normal[2]);
    for (int u = 0; u < TSR_STATE_UNITS; u++)
        if (!from || (force & (M_TEX0 << u)) || memcmp(from->texcoord[u], to->texcoord[u], sizeof to->texcoord[u]))
            texcoord(out, z->tex[u], GL_TEXTURE0 + (GLenum)u, to->texcoord[u]);
    if (!from || (force & M_EDGE) || from->edge_flag != to->edge_flag)
        tsr_call_EdgeFlag(out, to->edge_flag);
    for (int i = from ? 1 : 0; i < TSR_STATE_ATTRIBS; i++)
        if (!from || (force & (M_ATTRIB0 << i)) || memcmp(from->attrib[i], to->attrib[i], sizeof to->attrib[i]))
            attrib(out, z->attrib[i], (GLuint)i, to->attrib[i]);
}

static void emit_attrs(const tsr_dispatch *out, const ts_current *from, const ts_current *to, const ts_sizes *z)
{
    emit_attrs_forced(out, from, to, 0, z);
}

static void emit_vertex(const tsr_dispatch *out, const ts_vertex *v)
{
    if (v->size == 2)
        tsr_call_Vertex2f(out, v->pos[0], v->pos[1]);
    else if (v->size == 3)
        tsr_call_Vertex3f(out, v->pos[0], v->pos[1], v->pos[2]);
    else
        tsr_call_Vertex4f(out, v->pos[0], v->pos[1], v->pos[2], v->pos[3]);
}

/* --- what a piece starts with ------------------------------------------------ */

static int strip_like(GLenum mode)
{
    return mode == GL_LINE_STRIP || mode == GL_LINE_LOOP || mode == GL_TRIANGLE_STRIP || mode == GL_TRIANGLE_FAN ||
           mode == GL_QUAD_STRIP || mode == GL_POLYGON;
}

/* The vertices the next piece starts with (see the header), into out[];
 * returns how many. */
static int carried(const ts_split *sp, const ts_vertex **out)
{
    uint64_t k = sp->count;
    int last = 0;
    switch (sp->mode) {
    case GL_LINES: last = (int)(k % 2); break;
    case GL_TRIANGLES: last = (int)(k % 3); break;
    case GL_QUADS: last = (int)(k % 4); break;
    case GL_LINE_STRIP:
    case GL_LINE_LOOP: last = k ? 1 : 0; break;
    case GL_TRIANGLE_STRIP: last = k >= 3 && (k & 1) ? 3 : (int)(k < 2 ? k : 2); break;
    case GL_QUAD_STRIP: last = k < 2 ? (int)k : (k & 1) ? 3 : 2; break;
    case GL_TRIANGLE_FAN:
    case GL_POLYGON:
        if (!k)
            return 0;
        out[0] = &sp->first;
        if (k == 1)
            return 1;
        out[1] = &sp->tail[sp->ntail - 1];
        return 2;
    default: return 0; /* points */
    }
    for (int i = 0; i < last; i++)
        out[i] = &sp->tail[sp->ntail - last + i];
    return last;
}

/* glBegin and the carried vertices, then the attributes back to `start`. */
static void emit_prefix(const ts_split *sp, const tsr_dispatch *out, const ts_current *start)
{
    const ts_vertex *v[3];
    int n = carried(sp, v);
    tsr_call_Begin(out, sp->mode == GL_LINE_LOOP ? GL_LINE_STRIP : sp->mode);
    ts_current run = *start, a;
    uint32_t force = sp->mask & ~(uint32_t)M_ATTRIB0; /* never generic attribute 0 */
    for (int i = 0; i < n; i++) {
        a = v[i]->attrs;
        if (sp->mode == GL_POLYGON && i == 0 && sp->count >= 3)
            a.edge_flag = GL_FALSE; /* its edge to the carried last vertex is inside the polygon */
        emit_attrs_forced(out, &run, &a, force, &sp->sizes);
        force = 0;
        emit_vertex(out, v[i]);
        run = a;
    }
    emit_attrs_forced(out, &run, start, force, &sp->sizes);
}

/* --- the scan ----------------------------------------------------------------- */

static void scan_Begin(void *self, GLenum mode)
{
    ts_split *sp = self;
    sp->inside = 1;
    sp->began = 1;
    sp->opaque = 0;
    sp->smode = mode;
    sp->scount = 0;
    sp->new_vertices = 0;
    sp->seen = 0;
    sp->ssizes = four;
    ts_current_of(tsr_state_values_of(sp->scratch), &sp->begin.attrs);
    sp->pending = &sp->begin;
    tsr_unpacker_yield(sp->scanner);
}

static void scan_End(void *self)
{
    ts_split *sp = self;
    sp->inside = 0;
}

static void scan_current(void *ctx, int slot)
{
    ts_split *sp = ctx;
    if (!sp->inside)
        return;
    switch (sp->kind[slot]) {
    case K_COLOR:
        sp->seen |= M_COLOR;
        sp->ssizes.color = sp->ncomp[slot];
        break;
    case K_NORMAL: sp->seen |= M_NORMAL; break;
    case K_EDGE: sp->seen |= M_EDGE; break;
    case K_TEX0:
        sp->seen |= M_TEX0;
        sp->ssizes.tex[0] = sp->ncomp[slot];
        break;
    case K_TEXANY:
        sp->tex_any = 1;
        sp->tex_any_size = sp->ncomp[slot];
        break;
    default: break;
    }
}

static void scan_other(void *ctx, int slot)
{
    ts_split *sp = ctx;
    (void)slot;
    if (sp->inside)
        sp->opaque = 1; /* makes vertices we cannot see, or is not allowed here */
}

static void vertex(ts_split *sp, int size, float x, float y, float z, float w)
{
    if (!sp->inside)
        return;
    ts_vertex *v = &sp->ring[sp->scount & 3];
    v->pos[0] = x;
    v->pos[1] = y;
    v->pos[2] = z;
    v->pos[3] = w;
    v->size = size;
    ts_current_of(tsr_state_values_of(sp->scratch), &v->attrs);
    sp->pending = v; /* its place in the buffer is known after the yield (and sfirst copied then) */
    sp->scount++;
    sp->new_vertices++;
    tsr_unpacker_yield(sp->scanner);
}

#define V2(N, T) \
    static void w_##N(void *self, T x, T y) { vertex(self, 2, (float)x, (float)y, 0.0f, 1.0f); }
#define V3(N, T) \
    static void w_##N(void *self, T x, T y, T z) { vertex(self, 3, (float)x, (float)y, (float)z, 1.0f); }
#define V4(N, T) \
    static void w_##N(void *self, T x, T y, T z, T w) { vertex(self, 4, (float)x, (float)y, (float)z, (float)w); }
#define VV2(N, T) \
    static void w_##N(void *self, const T *v) { vertex(self, 2, (float)v[0], (float)v[1], 0.0f, 1.0f); }
#define VV3(N, T) \
    static void w_##N(void *self, const T *v) { vertex(self, 3, (float)v[0], (float)v[1], (float)v[2], 1.0f); }
#define VV4(N, T) \
    static void w_##N(void *self, const T *v) { vertex(self, 4, (float)v[0], (float)v[1], (float)v[2], (float)v[3]); }
/* A table of macro calls, laid out by hand: clang-format 14 rewraps it
 * differently on every run (it never settles). */
/* clang-format off */
#define VERTEX_TYPES(X2, X3, X4, XV2, XV3, XV4)                                                                    \
    X2(Vertex2f, GLfloat) X2(Vertex2d, GLdouble) X2(Vertex2i, GLint) X2(Vertex2s, GLshort)                         \
    X3(Vertex3f, GLfloat) X3(Vertex3d, GLdouble) X3(Vertex3i, GLint) X3(Vertex3s, GLshort)                         \
    X4(Vertex4f, GLfloat) X4(Vertex4d, GLdouble) X4(Vertex4i, GLint) X4(Vertex4s, GLshort)                         \
    XV2(Vertex2fv, GLfloat) XV2(Vertex2dv, GLdouble) XV2(Vertex2iv, GLint) XV2(Vertex2sv, GLshort)                 \
    XV3(Vertex3fv, GLfloat) XV3(Vertex3dv, GLdouble) XV3(Vertex3iv, GLint) XV3(Vertex3sv, GLshort)                 \
    XV4(Vertex4fv, GLfloat) XV4(Vertex4dv, GLdouble) XV4(Vertex4iv, GLint) XV4(Vertex4sv, GLshort)
/* clang-format on */

VERTEX_TYPES(V2, V3, V4, VV2, VV3, VV4)

#define SETW(N, T) tsr_set_##N(d, w_##N, sp);
static void set_vertices(tsr_dispatch *d, ts_split *sp){VERTEX_TYPES(SETW, SETW, SETW, SETW, SETW, SETW)}

/* glVertexAttrib*(0, ...) inside glBegin is a vertex: the primitive is
 * opaque. Other indices are current attributes (the scratch tracker). */
#define VA(N, K, PARAMS, ARGS)                         \
    static void a_##N PARAMS                           \
    {                                                  \
        ts_split *sp = self;                           \
        if (index == 0 && sp->inside)                  \
            sp->opaque = 1;                            \
        if (sp->inside && index < TSR_STATE_ATTRIBS) { \
            sp->seen |= M_ATTRIB0 << index;            \
            sp->ssizes.attrib[index] = K;              \
        }                                              \
        tsr_call_##N ARGS;                             \
    }
VA(VertexAttrib1f, 1, (void *self, GLuint index, GLfloat x), (&sp->tracked, index, x))
    VA(VertexAttrib2f, 2, (void *self, GLuint index, GLfloat x, GLfloat y), (&sp->tracked, index, x, y))
        VA(VertexAttrib3f, 3, (void *self, GLuint index, GLfloat x, GLfloat y, GLfloat z),
           (&sp->tracked, index, x, y, z)) VA(VertexAttrib4f, 4,
                                              (void *self, GLuint index, GLfloat x, GLfloat y, GLfloat z, GLfloat w),
                                              (&sp->tracked, index, x, y, z, w))
            VA(VertexAttrib1fv, 1, (void *self, GLuint index, const GLfloat *v), (&sp->tracked, index, v))
                VA(VertexAttrib2fv, 2, (void *self, GLuint index, const GLfloat *v), (&sp->tracked, index, v))
                    VA(VertexAttrib3fv, 3, (void *self, GLuint index, const GLfloat *v), (&sp->tracked, index, v))
                        VA(VertexAttrib4fv, 4, (void *self, GLuint index, const GLfloat *v), (&sp->tracked, index, v))

    /* Runs buf through the scan from the attributes `start`. */
    static int scan(ts_split *sp, const uint8_t *buf, size_t size, const ts_current *start,
                    const tsr_pixel_store *pixels, tsr_error *err)
{
    emit_attrs(&sp->tracked, NULL, start, &four);
    sp->inside = sp->open;
    sp->opaque = 0;
    sp->began = 0;
    sp->smode = sp->mode;
    sp->scount = sp->open ? sp->count : 0;
    sp->new_vertices = 0;
    sp->seen = sp->open ? sp->mask : 0;
    sp->ssizes = sp->open ? sp->sizes : four;
    sp->tex_any = 0;
    if (sp->open) {
        for (int i = 0; i < sp->ntail; i++)
            sp->ring[(sp->count - (uint64_t)sp->ntail + (uint64_t)i) & 3] = sp->tail[i];
        sp->sfirst = sp->first;
    }
    sp->scanner->pixels = *pixels; /* images in the buffer were packed under these */
    sp->pending = NULL;
    int rc = tsr_unpacker_run(sp->scanner, buf, size, err);
    while (rc == TSR_UNPACK_YIELDED) {
        ts_vertex *v = sp->pending;
        v->cmd = sp->scanner->resume_command;
        v->pos_end = sp->scanner->resume_pos;
        if (v != &sp->begin && sp->scount == 1)
            sp->sfirst = *v;
        rc = tsr_unpacker_resume(sp->scanner, err);
    }
    if (sp->tex_any) { /* glMultiTexCoord: the units that hold a coordinate now */
        const tsr_state_values *now = tsr_state_values_of(sp->scratch);
        for (int u = 0; u < TSR_STATE_UNITS; u++)
            if (now->texcoord[u][0] != 0 || now->texcoord[u][1] != 0 || now->texcoord[u][2] != 0 ||
                now->texcoord[u][3] != 1) {
                sp->seen |= M_TEX0 << u;
                sp->ssizes.tex[u] = (uint8_t)sp->tex_any_size;
            }
    }
    return rc;
}

/* --- the added parts ----------------------------------------------------------- */

static int bytes_put(ts_bytes *b, const uint8_t *src, size_t size)
{
    if (size > b->cap) {
        uint8_t *n = realloc(b->b, size);
        if (!n)
            return -1;
        b->b = n;
        b->cap = size;
    }
    memcpy(b->b, src, size);
    b->size = size;
    return 0;
}

static int added_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    ts_split *sp = ctx;
    sp->sink_calls++;
    if (bytes_put(sp->sink_to, buf, size) != 0)
        return tsr_error_set(err, TSR_ENOMEM, "out of memory for a primitive's piece");
    return TSR_OK;
}

static int added_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    (void)ctx;
    (void)data;
    (void)size;
    return tsr_error_set(err, TSR_ESTATE, "request %u in a primitive's piece", id);
}

/* Packs what `sp->added` received since the last call into `to` as one
 * wire buffer (empty when nothing). Its data is padded to 8 bytes with
 * glEdgeFlag(edge) when `pad`. */
static int take_added(ts_split *sp, ts_bytes *to, int pad, GLboolean edge, tsr_error *err)
{
    to->size = 0;
    if (pad)
        while ((size_t)(sp->packer->data - sp->packer->mid) & 7u)
            tsr_call_EdgeFlag(&sp->added, edge);
    sp->sink_to = to;
    sp->sink_calls = 0;
    if (tsr_packer_flush(sp->packer) != TSR_OK || sp->sink_calls > 1) {
        tsr_error_set(err, TSR_EPROTO, "a primitive's piece: %s",
                      sp->sink_calls > 1 ? "added commands do not fit one buffer"
                                         : tsr_packer_error(sp->packer)->message);
        tsr_packer_clear_error(sp->packer);
        return TSR_EPROTO;
    }
    return TSR_OK;
}

typedef struct wire_view {
    const uint8_t *data; /* opcodes end here (backwards), data start here */
    uint32_t nops;
    size_t len;
} wire_view;

static wire_view view_of(const uint8_t *b, size_t size)
{
    static const uint8_t none[8];
    wire_view v = {none, 0, 0};
    if (size >= TSR_WIRE_HEADER_SIZE) {
        v.nops = tsr_wire_get_u32(b + 4);
        v.len = (size_t)tsr_wire_get_u64(b + 8);
        v.data = b + TSR_WIRE_HEADER_SIZE + tsr_wire_align8(v.nops);
    }
    return v;
}

static void copy(uint8_t *to, const uint8_t *from, size_t n)
{
    if (n)
        memcpy(to, from, n);
}

/* out = prefix + the first `keep` commands of buf (data up to `keep_len`)
 * + `pads` glEdgeFlag(edge) + close. The prefix's data is a multiple of 8
 * long; `pads` brings keep_len to one; so every part's data keeps the
 * alignment it was packed with. */
static int splice(ts_split *sp, const wire_view *p, const wire_view *b, uint32_t keep, size_t keep_len,
                  const wire_view *c, GLboolean edge)
{
    uint32_t pads = c->nops ? (uint32_t)(tsr_wire_align8(keep_len) - keep_len) : 0;
    uint64_t nops = (uint64_t)p->nops + keep + pads + c->nops;
    size_t len = p->len + keep_len + pads + c->len;
    size_t oplen = (size_t)tsr_wire_align8(nops);
    size_t size = TSR_WIRE_HEADER_SIZE + oplen + len;
    if (size > sp->out.cap) {
        uint8_t *n = realloc(sp->out.b, size);
        if (!n)
            return -1;
        sp->out.b = n;
        sp->out.cap = size;
    }
    uint8_t *o = sp->out.b;
    tsr_wire_put_u32(o, TSR_WIRE_MAGIC);
    tsr_wire_put_u32(o + 4, (uint32_t)nops);
    tsr_wire_put_u64(o + 8, len);
    uint8_t *data = o + TSR_WIRE_HEADER_SIZE + oplen;
    memset(o + TSR_WIRE_HEADER_SIZE, 0, oplen - nops);
    /* opcodes, backwards from data: prefix, buffer, pads, close */
    uint8_t *op = data - p->nops;
    copy(op, p->data - p->nops, p->nops);
    op -= keep;
    copy(op, b->data - keep, keep);
    op -= pads;
    memset(op, sp->edge_opcode, pads);
    op -= c->nops;
    copy(op, c->data - c->nops, c->nops);
    /* data, forwards */
    uint8_t *d = data;
    copy(d, p->data, p->len);
    d += p->len;
    copy(d, b->data, keep_len);
    d += keep_len;
    memset(d, edge ? 1 : 0, pads);
    d += pads;
    copy(d, c->data, c->len);
    sp->out.size = size;
    return 0;
}

/* --- the API --------------------------------------------------------------------- */

ts_split *ts_split_create(tsr_error *err)
{
    ts_split *sp = calloc(1, sizeof *sp);
    uint8_t *current = calloc(TSR_DISPATCH_COUNT, 1);
    if (!sp || !current || !(sp->hooks = calloc(TSR_DISPATCH_COUNT, sizeof *sp->hooks))) {
        free(current);
        free(sp);
        tsr_error_set(err, TSR_ENOMEM, "out of memory");
        return NULL;
    }
    int edge = tsr_wire_slot_opcode(tsr_dispatch_slot("EdgeFlag"));
    sp->edge_opcode = (uint8_t)edge;
    if (edge <= 0 || edge >= (int)TSR_WIRE_EXTENDED) {
        tsr_error_set(err, TSR_ESTATE, "glEdgeFlag has no one-byte opcode");
        goto fail;
    }
    if (!(sp->tracker = tsr_state_tracker_create(err)) || !(sp->scratch = tsr_state_ctx_create(sp->tracker, err)))
        goto fail;
    tsr_dispatch_fill_nop(&sp->tracked);
    tsr_state_fill_dispatch(sp->scratch, &sp->tracked);
    /* The scan: current attributes to the scratch tracker; Begin, End and
     * vertices to us; any other command is a hook that marks the primitive
     * it is in as opaque. */
    tsr_dispatch_fill_nop(&sp->scan);
    const char *name, *category;
    for (size_t i = 0; tsr_state_spec_command(i, &name, &category); i++) {
        int slot = tsr_dispatch_slot(name);
        if (slot >= 0 && !strcmp(category, "current"))
            current[slot] = 1;
    }
    if (!(sp->kind = calloc(TSR_DISPATCH_COUNT, 1)) || !(sp->ncomp = calloc(TSR_DISPATCH_COUNT, 1))) {
        tsr_error_set(err, TSR_ENOMEM, "out of memory");
        goto fail;
    }
    for (int slot = 0; slot < TSR_DISPATCH_COUNT; slot++) {
        if (current[slot]) {
            const char *n = tsr_dispatch_name(slot);
            sp->kind[slot] = !strncmp(n, "Color", 5)            ? K_COLOR
                             : !strncmp(n, "Normal", 6)         ? K_NORMAL
                             : !strncmp(n, "EdgeFlag", 8)       ? K_EDGE
                             : !strncmp(n, "TexCoord", 8)       ? K_TEX0
                             : !strncmp(n, "MultiTexCoord", 13) ? K_TEXANY
                                                                : K_NONE;
            const char *digit = strpbrk(n, "1234");
            sp->ncomp[slot] = (uint8_t)(digit ? *digit - '0' : 4);
            sp->scan.slots[slot] = sp->tracked.slots[slot];
            sp->hooks[slot] = (tsr_hook){.before = scan_current, .ctx = sp};
            tsr_dispatch_hook(&sp->scan, slot, &sp->hooks[slot]);
        } else {
            sp->hooks[slot] = (tsr_hook){.before = scan_other, .ctx = sp};
            tsr_dispatch_hook(&sp->scan, slot, &sp->hooks[slot]);
        }
    }
    tsr_set_Begin(&sp->scan, scan_Begin, sp);
    tsr_set_End(&sp->scan, scan_End, sp);
    set_vertices(&sp->scan, sp);
    tsr_set_VertexAttrib1f(&sp->scan, a_VertexAttrib1f, sp);
    tsr_set_VertexAttrib2f(&sp->scan, a_VertexAttrib2f, sp);
    tsr_set_VertexAttrib3f(&sp->scan, a_VertexAttrib3f, sp);
    tsr_set_VertexAttrib4f(&sp->scan, a_VertexAttrib4f, sp);
    tsr_set_VertexAttrib1fv(&sp->scan, a_VertexAttrib1fv, sp);
    tsr_set_VertexAttrib2fv(&sp->scan, a_VertexAttrib2fv, sp);
    tsr_set_VertexAttrib3fv(&sp->scan, a_VertexAttrib3fv, sp);
    tsr_set_VertexAttrib4fv(&sp->scan, a_VertexAttrib4fv, sp);
    if (!(sp->scanner = tsr_unpacker_create(&sp->scan, NULL, NULL, err)))
        goto fail;
    /* the added parts: at most three carried vertices with all their
     * attributes, and the attributes put back, with room to spare */
    tsr_pack_sink sink = {.flush = added_flush, .reply = added_reply, .ctx = sp};
    if (!(sp->packer = tsr_packer_create(32768, &sink, err)))
        goto fail;
    tsr_dispatch_fill_nop(&sp->added);
    tsr_packer_fill_dispatch(sp->packer, &sp->added);
    free(current);
    return sp;
fail:
    free(current);
    ts_split_destroy(sp);
    return NULL;
}

void ts_split_destroy(ts_split *sp)
{
    if (!sp)
        return;
    tsr_unpacker_destroy(sp->scanner);
    tsr_packer_destroy(sp->packer);
    tsr_state_tracker_destroy(sp->tracker);
    free(sp->hooks);
    free(sp->kind);
    free(sp->ncomp);
    free(sp->prefix.b);
    free(sp->close.b);
    free(sp->out.b);
    free(sp);
}

int ts_split_open(const ts_split *sp) { return sp->open; }

void ts_split_end(ts_split *sp, const tsr_dispatch *route, const ts_current *now)
{
    if (!sp->open || sp->ended)
        return;
    if (sp->mode == GL_LINE_LOOP && sp->count) {
        /* the loop's closing segment: back to its first vertex (the
         * geometry buffer may be cut again while it is packed) */
        ts_vertex first = sp->first;
        ts_sizes sizes = sp->sizes;
        emit_attrs(route, now, &first.attrs, &sizes);
        emit_vertex(route, &first);
        emit_attrs(route, &first.attrs, now, &sizes);
    }
    sp->ended = 1; /* a primitive begun after it in this buffer is not it */
}

int ts_split_piece(ts_split *sp, const uint8_t *buf, size_t size, const ts_current *start, const ts_current *end,
                   int ends_inside, int may_cut, unsigned state, tsr_packer *box, const uint8_t **out, size_t *out_size,
                   tsr_error *err)
{
    *out = buf;
    *out_size = size;
    int rc = scan(sp, buf, size, start, &box->pixels, err);
    if (rc != TSR_OK) {
        sp->open = 0;
        return rc;
    }
    if (ends_inside && sp->open && !sp->began && !sp->new_vertices && !sp->opaque)
        return TS_SPLIT_NOTHING; /* attributes only: the next piece puts them back */
    int cut = ends_inside && sp->inside && may_cut && !sp->opaque &&
              !((state & TS_SPLIT_LINE_STIPPLE) && strip_like(sp->smode)) &&
              !((state & TS_SPLIT_LIGHTING) && (sp->smode == GL_QUADS || sp->smode == GL_QUAD_STRIP));
    if (!sp->open && !cut)
        return TS_SPLIT_WHOLE;
    uint64_t k = sp->scount;
    const wire_view b = view_of(buf, size);
    uint32_t keep = b.nops;
    size_t keep_len = b.len;
    ts_current run = *end; /* the attributes where the kept commands end */
    int drop = cut && k >= 3 && ((sp->smode == GL_TRIANGLE_STRIP && (k & 1)) || sp->smode == GL_POLYGON);
    if (drop) {
        /* cut after the primitive's vertex before the last, or its glBegin,
         * or (its first vertex here) at the buffer's start */
        const ts_vertex *at = sp->new_vertices >= 2 ? &sp->ring[(k - 2) & 3] : sp->began ? &sp->begin : NULL;
        keep = at ? at->cmd : 0;
        keep_len = at ? at->pos_end : 0;
        run = at ? at->attrs : *start;
    }
    /* the prefix: the last piece's carried vertices (in this piece's box) */
    if (sp->open) {
        emit_prefix(sp, &sp->added, start);
        const ts_vertex *v[3];
        int n = carried(sp, v);
        for (int i = 0; i < n; i++)
            tsr_packer_bbox4(box, v[i]->pos[0], v[i]->pos[1], v[i]->pos[2], v[i]->pos[3]);
    }
    if ((rc = take_added(sp, &sp->prefix, 1, start->edge_flag, err)) != TSR_OK)
        return rc;
    /* the close */
    if (cut) {
        if (drop && sp->smode == GL_POLYGON) {
            const ts_vertex *last = &sp->ring[(k - 1) & 3];
            ts_current a = last->attrs;
            a.edge_flag = GL_FALSE; /* its edge back to the first vertex is inside the polygon */
            emit_attrs(&sp->added, &run, &a, &sp->ssizes);
            emit_vertex(&sp->added, last);
            run = a;
        }
        emit_attrs(&sp->added, &run, end, &sp->ssizes);
        tsr_call_End(&sp->added);
    }
    if ((rc = take_added(sp, &sp->close, 0, GL_FALSE, err)) != TSR_OK)
        return rc;
    const wire_view p = view_of(sp->prefix.b, sp->prefix.size), c = view_of(sp->close.b, sp->close.size);
    if (splice(sp, &p, &b, keep, keep_len, &c, run.edge_flag) != 0) {
        sp->open = 0;
        return tsr_error_set(err, TSR_ENOMEM, "out of memory for a primitive's piece");
    }
    if (cut && sp->began && sp->smode == GL_LINE_LOOP) /* a loop that is cut is drawn as strips */
        tsr_wire_put_u32(sp->out.b + (size_t)(view_of(sp->out.b, sp->out.size).data - sp->out.b) + p.len +
                             sp->begin.pos_end - 4,
                         GL_LINE_STRIP);
    *out = sp->out.b;
    *out_size = sp->out.size;
    if (!cut) {
        sp->open = 0;
        return ends_inside ? TS_SPLIT_WHOLE : TS_SPLIT_PIECE;
    }
    /* what the next buffer starts inside */
    sp->open = 1;
    sp->ended = 0;
    sp->mode = sp->smode;
    sp->count = k;
    sp->first = sp->sfirst;
    sp->mask = sp->seen;
    sp->sizes = sp->ssizes;
    sp->ntail = k < 3 ? (int)k : 3;
    for (int i = 0; i < sp->ntail; i++)
        sp->tail[i] = sp->ring[(k - (uint64_t)sp->ntail + (uint64_t)i) & 3];
    return TS_SPLIT_PIECE;
}
