/* spus/tilesort/arrays.c — glDrawArrays and glDrawElements (and the
 * glDrawRangeElements and glMultiDraw* that stand for them): sorted
 * primitive by primitive, or cut into boxed batches.
 *
 * Array draws of independent primitives (points, lines, triangles, quads)
 * are sorted primitive by primitive instead of boxed whole: each
 * primitive's own window box picks its servers, and each server collects
 * its primitives into compact draws of about batch_bytes (batch.c: only
 * the vertices they use, indices renumbered), sent to it alone. Overlap
 * then comes only from primitives that cross a tile edge, and messages
 * stay large. Draws that cannot be sorted (arrays in buffer objects, a
 * program with a vertex shader in use, broadcast) are cut into boxed
 * batches.
 *
 * Owns the scratch of those draws: each server's batch, the compact batch,
 * the gathered arrays. Never reorders a server's primitives (GL draws them
 * in the application's order: blending, depth ties), and never leaves the
 * packer's array mirrors pointing at the gathered copies. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "instance.h"

/* Vertices per primitive of the modes that can be cut anywhere between
 * primitives (0: strips, fans, loops, polygons: drawn whole). */
static int independent_vertices(GLenum mode)
{
    switch (mode) {
    case GL_POINTS: return 1;
    case GL_LINES: return 2;
    case GL_TRIANGLES: return 3;
    case GL_QUADS: return 4;
    default: return 0;
    }
}

/* The client arrays the packer reads, as a list. */
static size_t enabled_arrays(tsr_client_arrays *a, tsr_client_array **out)
{
    size_t n = 0;
    tsr_client_array *all[7] = {&a->vertex,          &a->normal,    &a->color, &a->edge_flag,
                                &a->secondary_color, &a->fog_coord, &a->index};
    for (int i = 0; i < 7; i++)
        if (all[i]->enabled)
            out[n++] = all[i];
    for (int i = 0; i < TSR_PACK_TEXUNITS; i++)
        if (a->texcoord[i].enabled)
            out[n++] = &a->texcoord[i];
    for (int i = 0; i < TSR_PACK_ATTRIBS; i++)
        if (a->attrib[i].enabled)
            out[n++] = &a->attrib[i];
    return n;
}

/* Bytes of one element of a client array as the packer sends it. */
static size_t array_elem_bytes(const tsr_client_array *a)
{
    size_t comps = a->size == GL_BGRA ? 4 : a->size > 0 ? (size_t)a->size : 1;
    return comps * tsr_gl_type_size(a->type);
}

/* Bytes one vertex of the enabled client arrays takes on the wire (0 when
 * an array lives in a buffer object: the box is unknown anyway). */
static size_t vertex_bytes(tsr_client_arrays *a)
{
    tsr_client_array *arrays[TSR_PACK_ARRAYS];
    size_t n = enabled_arrays(a, arrays), bytes = 0;
    for (size_t i = 0; i < n; i++) {
        if (arrays[i]->buffer)
            return 0;
        bytes += array_elem_bytes(arrays[i]);
    }
    return bytes;
}

/* How many vertices of `mode` go in one batch of a large array draw that
 * is not sorted primitive by primitive (0: draw it whole). Each batch is
 * flushed on its own, so it is bucketed by its own box. */
static GLsizei batch_vertices(const tilesort *t, GLenum mode, GLsizei count, size_t index_bytes)
{
    int per = independent_vertices(mode);
    size_t vb = vertex_bytes(&t->geo->arrays) + index_bytes;
    if (!per || !vb || t->in_begin || (size_t)count * vb <= t->batch_bytes)
        return 0;
    size_t n = t->batch_bytes / vb / (size_t)per * (size_t)per;
    return (GLsizei)(n < (size_t)per ? (size_t)per : n);
}

static GLuint index_at(GLenum type, const void *indices, size_t i)
{
    switch (type) {
    case GL_UNSIGNED_BYTE: return ((const GLubyte *)indices)[i];
    case GL_UNSIGNED_SHORT: return ((const GLushort *)indices)[i];
    default: return ((const GLuint *)indices)[i];
    }
}

/* Draws a compact batch through the geometry buffer: the enabled arrays
 * gathered to the batch's vertices (the packer's array mirrors point at
 * the copies for the call and are put back after), with 16-bit indices
 * where they fit. */
static int draw_batch(tilesort *t, GLenum mode, const ts_batch *b, int indexed)
{
    tsr_client_array *arrays[TSR_PACK_ARRAYS];
    size_t narrays = enabled_arrays(&t->geo->arrays, arrays), need = 0;
    int short_index = indexed && b->nvert <= 65536;
    for (size_t k = 0; k < narrays; k++)
        need += (b->nvert * array_elem_bytes(arrays[k]) + 7) & ~(size_t)7;
    need += short_index ? b->nidx * sizeof(GLushort) : 0;
    if (need > t->gathered_cap) {
        uint8_t *g = realloc(t->gathered, need);
        if (!g)
            return -1;
        t->gathered = g;
        t->gathered_cap = need;
    }
    tsr_client_array saved[TSR_PACK_ARRAYS];
    uint8_t *q = t->gathered;
    for (size_t k = 0; k < narrays; k++) {
        tsr_client_array *a = arrays[k];
        size_t elem = array_elem_bytes(a), stride = a->stride ? (size_t)a->stride : elem;
        const uint8_t *src = a->pointer;
        saved[k] = *a;
        for (size_t u = 0; u < b->nvert; u++)
            memcpy(q + u * elem, src + (size_t)b->order[u] * stride, elem);
        a->pointer = q;
        a->stride = 0;
        q += (b->nvert * elem + 7) & ~(size_t)7;
    }
    if (!indexed) {
        tsr_call_DrawArrays(&t->geo_table, mode, 0, (GLsizei)b->nvert);
    } else if (short_index) {
        GLushort *ix = (GLushort *)(void *)q;
        for (size_t i = 0; i < b->nidx; i++)
            ix[i] = (GLushort)b->index[i];
        tsr_call_DrawElements(&t->geo_table, mode, (GLsizei)b->nidx, GL_UNSIGNED_SHORT, ix);
    } else {
        tsr_call_DrawElements(&t->geo_table, mode, (GLsizei)b->nidx, GL_UNSIGNED_INT, b->index);
    }
    for (size_t k = 0; k < narrays; k++)
        *arrays[k] = saved[k];
    return 0;
}

/* One array draw being sorted primitive by primitive. */
typedef struct ts_draw {
    GLenum mode, type; /* type: of the indices; 0 for glDrawArrays */
    GLint first;
    const void *indices;
    int per;             /* vertices per primitive */
    size_t vertex_bytes; /* wire bytes of one vertex's array elements */
    size_t overhead;     /* wire bytes of a draw command beyond its vertices and indices, at most */
} ts_draw;

static uint32_t source_vertex(const ts_draw *d, size_t i)
{
    return d->type ? index_at(d->type, d->indices, i) : (uint32_t)d->first + (uint32_t)i;
}

/* Wire bytes of batch b with one more primitive, at worst (all its
 * vertices new). */
static size_t bytes_with_one_more(const ts_draw *d, const ts_batch *b)
{
    size_t nvert = b->nvert + (size_t)d->per, nidx = d->type ? b->nidx + (size_t)d->per : 0;
    return d->overhead + nvert * d->vertex_bytes + nidx * (nvert <= 65536 ? 2 : 4);
}

/* Sends server `server` the primitives its batch collected, as one draw
 * through the geometry buffer to that server alone. */
static void send_sorted(tilesort *t, size_t server, const ts_draw *d)
{
    ts_batch *b = &t->srv[server].sorted;
    if (!b->nvert)
        return;
    t->only_target = server;
    if (draw_batch(t, d->mode, b, d->type != 0) != 0) {
        tsr_error e;
        tsr_error_set(&e, TSR_ENOMEM, "out of memory gathering arrays for server %zu", server);
        ts_report(t, &e);
    }
    ts_flush_geometry(t);
    t->only_target = TS_ANY_TARGET;
    ts_batch_clear(b);
}

/* The statistics' stream bytes: t->compact collects the draw exactly as a
 * single server would get it, batch by batch. */
static void count_whole(tilesort *t, const ts_draw *d)
{
    ts_batch *b = &t->compact;
    if (!b->nvert)
        return;
    GLenum itype = !d->type ? 0 : b->nvert <= 65536 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
    t->stream_bytes += tsr_packer_draw_bytes(t->geo, (GLsizei)(d->type ? b->nidx : b->nvert), itype, b->nvert);
    ts_batch_clear(b);
}

static int add_sorted(tilesort *t, size_t server, const ts_draw *d, const uint32_t *vertices)
{
    ts_batch *b = server == TS_ANY_TARGET ? &t->compact : &t->srv[server].sorted;
    if (b->nvert && bytes_with_one_more(d, b) > t->batch_bytes) {
        if (server == TS_ANY_TARGET)
            count_whole(t, d);
        else
            send_sorted(t, server, d);
    }
    return ts_batch_add(b, vertices, d->per, d->type != 0);
}

/* Draws below this size are boxed whole with the geometry around them. */
#define TS_SORT_MIN_BYTES 1024

/* An array draw of independent primitives (points, lines, triangles,
 * quads) sorted primitive by primitive: each primitive's own window box
 * picks its servers, and each server gets its primitives, in the
 * application's order, as compact draws of about batch_bytes. Overlap
 * then comes only from primitives that cross a tile edge, whatever the
 * batch size, and batches stay large. Returns 0 when the draw cannot be
 * sorted (the caller cuts it into boxed batches). */
static int draw_sorted(tilesort *t, GLenum mode, GLint first, GLsizei count, GLenum type, const void *indices)
{
    tsr_client_arrays *a = &t->geo->arrays;
    ts_draw d = {.mode = mode,
                 .type = type,
                 .first = first,
                 .indices = indices,
                 .per = independent_vertices(mode),
                 .vertex_bytes = vertex_bytes(a)};
    float pos[4][4];
    if (!d.per || !d.vertex_bytes || count < 2 * d.per || (size_t)count * d.vertex_bytes < TS_SORT_MIN_BYTES ||
        t->in_begin || t->program || t->app_fb || t->render_mode != GL_RENDER || t->tiling.mode == TS_BROADCAST ||
        t->win_w <= 0 || !a->vertex.enabled || (type && (!indices || a->element_buffer)) || first < 0 ||
        !tsr_client_array_position(&a->vertex, source_vertex(&d, 0), pos[0]))
        return 0;
    ts_flush_geometry(t);
    ts_count_solo_diff(t);
    tsr_client_array *arrays[TSR_PACK_ARRAYS];
    d.overhead =
        (size_t)tsr_packer_draw_bytes(t->geo, 1, type ? GL_UNSIGNED_INT : 0, 1) + 8 * (enabled_arrays(a, arrays) + 1);
    double pm[16];
    GLint vp[4];
    ts_clip_matrix(tsr_state_projection(t->ctx), tsr_state_modelview(t->ctx), pm);
    double margin = d.per >= 3 ? ts_polygon_margin(t) : ts_box_margin(t);
    /* A server gets each vertex its primitives use once (batch.c), so an
     * indexed primitive costs its indices and its share of the vertices:
     * the draw's distinct vertices (its index range) over its indices.
     * Charging every index a whole vertex made a mesh of shared vertices
     * (the isosurface's metaballs: about 6 triangles a vertex) look 3.5
     * times as costly as it is beside a flat triangle list, a spatial
     * error no per-server speed corrects before the split has moved. */
    double vertex_share = 1.0;
    if (type) {
        uint32_t lo = UINT32_MAX, hi = 0;
        for (GLsizei i = 0; i < count; i++) {
            uint32_t v = source_vertex(&d, (size_t)i);
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
        vertex_share = fmin(1.0, ((double)hi - (double)lo + 1.0) / (double)count);
    }
    double cost = (double)d.per * ((double)d.vertex_bytes * vertex_share + (type ? tsr_gl_type_size(type) : 0));
    size_t nprims = (size_t)count / (size_t)d.per;
    int failed = 0;
    for (size_t p = 0; p < nprims && !failed; p++) {
        uint32_t src[4];
        for (int k = 0; k < d.per; k++) {
            src[k] = source_vertex(&d, p * (size_t)d.per + (size_t)k);
            tsr_client_array_position(&a->vertex, src[k], pos[k]);
        }
        int x0, y0, x1, y1;
        if (ts_points_box(pm, ts_viewport(t, vp), (const float(*)[4])pos, d.per, margin, t->win_w, t->win_h, &x0, &y0,
                          &x1, &y1)) {
            ts_tiling_add_cost(&t->tiling, x0, y0, x1, y1, cost);
            ts_tiling_hit(&t->tiling, x0, y0, x1, y1, t->hit);
        } else {
            memset(t->hit, 1, t->nservers); /* crosses the eye plane, NaN: every server */
        }
        failed |= add_sorted(t, TS_ANY_TARGET, &d, src);
        for (size_t s = 0; s < t->nservers; s++)
            if (t->hit[s] && !tsr_stream_client_server_failed(t->client, s))
                failed |= add_sorted(t, s, &d, src);
    }
    for (size_t s = 0; s < t->nservers; s++)
        send_sorted(t, s, &d);
    count_whole(t, &d);
    if (failed) {
        tsr_error e;
        tsr_error_set(&e, TSR_ENOMEM, "a draw of %d vertices could not be sorted (out of memory or index 0x%x)", count,
                      UINT32_MAX);
        ts_report(t, &e);
    }
    return 1;
}

void ts_DrawArrays(void *self, GLenum mode, GLint first, GLsizei count)
{
    tilesort *t = self;
    if (first >= 0 && count >= 0 && draw_sorted(t, mode, first, count, 0, NULL))
        return;
    /* (the packer refuses a negative first or count with GL's error) */
    GLsizei batch = first < 0 || count < 0 ? 0 : batch_vertices(t, mode, count, 0);
    if (!batch) {
        tsr_call_DrawArrays(&t->geo_table, mode, first, count);
        return;
    }
    for (GLsizei k = 0; k < count; k += batch) {
        GLsizei n = count - k < batch ? count - k : batch;
        tsr_call_DrawArrays(&t->geo_table, mode, first + k, n);
        ts_flush_geometry(t);
    }
}

/* An unsorted glDrawElements into the geometry buffer. With indices in an
 * element array buffer, the tracker has that buffer's bytes: a draw whose
 * arrays are in client memory takes its indices from them (the geometry
 * packer has no receiver to ask, and sends the arrays' elements the
 * indices reach). */
static void draw_elements_unsorted(tilesort *t, GLenum mode, GLsizei count, GLenum type, const void *indices)
{
    if (!t->geo->arrays.element_buffer) {
        tsr_call_DrawElements(&t->geo_table, mode, count, type, indices);
        return;
    }
    GLsizeiptr size = 0;
    const void *bytes = tsr_state_buffer_bytes(t->ctx, GL_ELEMENT_ARRAY_BUFFER, &size);
    tsr_packer_draw_elements_known(t->geo, mode, count, type, indices, bytes, size);
}

void ts_DrawElements(void *self, GLenum mode, GLsizei count, GLenum type, const void *indices)
{
    tilesort *t = self;
    size_t isize = tsr_gl_type_size(type);
    int listed = type == GL_UNSIGNED_BYTE || type == GL_UNSIGNED_SHORT || type == GL_UNSIGNED_INT;
    if (listed && draw_sorted(t, mode, 0, count, type, indices))
        return;
    GLsizei batch =
        t->geo->arrays.element_buffer || !indices || !listed || count < 0 ? 0 : batch_vertices(t, mode, count, isize);
    if (!batch) {
        draw_elements_unsorted(t, mode, count, type, indices);
        return;
    }
    /* each batch made compact: only the vertices its indices use are sent
     * (and boxed), not every vertex between its smallest and largest index */
    ts_batch *b = &t->compact;
    for (GLsizei k = 0; k < count; k += batch) {
        GLsizei n = count - k < batch ? count - k : batch;
        const void *part = (const uint8_t *)indices + (size_t)k * isize;
        int ok = 1;
        for (GLsizei i = 0; i < n && ok; i++) {
            uint32_t v = index_at(type, part, (size_t)i);
            ok = ts_batch_add(b, &v, 1, 1) == 0;
        }
        if (!ok || draw_batch(t, mode, b, 1) != 0)
            tsr_call_DrawElements(&t->geo_table, mode, n, type, part);
        ts_batch_clear(b);
        ts_flush_geometry(t);
    }
}

/* glDrawRangeElements and glMultiDraw*: checked as GL checks them (the
 * geometry packer keeps the error for glGetError), then drawn as the
 * glDrawElements/glDrawArrays they stand for, each sorted or batched. */
void ts_DrawRangeElements(void *self, GLenum mode, GLuint start, GLuint end, GLsizei count, GLenum type,
                          const void *indices)
{
    tilesort *t = self;
    if (tsr_packer_check_DrawRangeElements(t->geo, mode, start, end, count, type) == 0)
        ts_DrawElements(self, mode, count, type, indices);
}

void ts_MultiDrawArrays(void *self, GLenum mode, const GLint *first, const GLsizei *count, GLsizei drawcount)
{
    tilesort *t = self;
    if (tsr_packer_check_MultiDraw(t->geo, mode, count, 0, drawcount) != 0)
        return;
    for (GLsizei i = 0; i < drawcount; i++)
        if (count[i] > 0)
            ts_DrawArrays(self, mode, first[i], count[i]);
}

void ts_MultiDrawElements(void *self, GLenum mode, const GLsizei *count, GLenum type, const void *const *indices,
                          GLsizei drawcount)
{
    tilesort *t = self;
    if (tsr_packer_check_MultiDraw(t->geo, mode, count, type, drawcount) != 0)
        return;
    for (GLsizei i = 0; i < drawcount; i++)
        if (count[i] > 0)
            ts_DrawElements(self, mode, count[i], type, indices[i]);
}
