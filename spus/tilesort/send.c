/* spus/tilesort/send.c — where a geometry buffer goes, and what each of
 * its servers is sent before it.
 *
 * On flush (buffer full, state change, frame command) the buffer's box
 * goes to window space (bucket.c) and every server it touches gets its
 * tiles (TilesTSR, when they changed), its state diff, the display lists
 * the buffer calls that it lacks (lists.c), the attributes the buffer
 * starts with, and then the buffer (copied once, shared by all those
 * connections). The buffer goes to every server
 * instead when its effect on the window is unknown: a command routed so
 * (tilesort.c), a program with a vertex shader in use, broadcast, no
 * window size yet, a box crossing the eye plane or holding NaN/Inf
 * (bucket.c).
 *
 * The current attributes a buffer starts with: the tracker follows the
 * application, so when a buffer is flushed it holds the values at the
 * buffer's END. Each buffer therefore remembers the values it started
 * with; after a server's diff, the attributes whose start value differs
 * from the end value are sent as they were at the start.
 *
 * A primitive (glBegin ... glEnd) that does not fit one buffer is cut
 * (split.c): each buffer that ends inside it is closed with glEnd and
 * placed by its own box; the next reopens it with glBegin and the vertices
 * the primitive still needs (a strip's last two, a fan's or polygon's
 * first and last, ...), each with the attributes it had, so every tile is
 * still exact. Primitives split.c cannot cut exactly (a display list or an
 * evaluator inside, strips under line stipple, lit quads, a program with a
 * vertex shader in use) go to every server whole, from the buffer holding
 * their glBegin to the one holding their glEnd (split_primitive).
 *
 * glMaterial inside glBegin/glEnd (moebius sets a diffuse colour before
 * each vertex of its wire mesh) is a state change the tracker cannot hold
 * for the buffer it is in: a diff goes before its buffer and is taken at
 * the buffer's end, so tracked at once each server would get the
 * primitive's last material before its first vertex. It goes into the
 * geometry buffer instead (split.c then sends the primitive whole to
 * every server), and reaches the tracker only once that buffer has been
 * sent, its servers' shadows told they hold it.
 *
 * Owns the geometry buffer's sending: its targets, its start attributes,
 * each server's tiles version. Never sends a server a buffer before its
 * tiles, lists and diff: the buffer's commands assume the state the
 * application drew them in. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "instance.h"

/* --- current attributes ------------------------------------------------------ */

void ts_snapshot(tilesort *t) { ts_current_of(tsr_state_values_of(t->ctx), &t->start); }

/* After server s's diff it holds the end values: send the start values
 * where they differ. */
static void send_start_current(tilesort *t, ts_server *s)
{
    ts_current end;
    ts_current_of(tsr_state_values_of(t->ctx), &end);
    const ts_current *a = &t->start;
    if (memcmp(a->color, end.color, sizeof end.color))
        tsr_call_Color4f(&s->table, a->color[0], a->color[1], a->color[2], a->color[3]);
    if (memcmp(a->normal, end.normal, sizeof end.normal))
        tsr_call_Normal3f(&s->table, a->normal[0], a->normal[1], a->normal[2]);
    for (int u = 0; u < TSR_STATE_UNITS; u++)
        if (memcmp(a->texcoord[u], end.texcoord[u], sizeof end.texcoord[u]))
            tsr_call_MultiTexCoord4f(&s->table, GL_TEXTURE0 + u, a->texcoord[u][0], a->texcoord[u][1],
                                     a->texcoord[u][2], a->texcoord[u][3]);
    if (a->edge_flag != end.edge_flag)
        tsr_call_EdgeFlag(&s->table, a->edge_flag);
    for (int i = 0; i < TSR_STATE_ATTRIBS; i++)
        if (memcmp(a->attrib[i], end.attrib[i], sizeof end.attrib[i]))
            tsr_call_VertexAttrib4f(&s->table, (GLuint)i, a->attrib[i][0], a->attrib[i][1], a->attrib[i][2],
                                    a->attrib[i][3]);
}

static void assume_current(tilesort *t, ts_server *s)
{
    tsr_state_shadow_assume(t->ctx, s->shadow, TSR_SM_COLOR);
    tsr_state_shadow_assume(t->ctx, s->shadow, TSR_SM_NORMAL);
    for (int u = 0; u < TSR_STATE_UNITS; u++)
        tsr_state_shadow_assume(t->ctx, s->shadow, TSR_SM_TEXCOORD0 + u);
    tsr_state_shadow_assume(t->ctx, s->shadow, TSR_SM_EDGEFLAG);
    tsr_state_shadow_assume(t->ctx, s->shadow, TSR_SM_ATTRIBS);
}

/* --- glMaterial inside glBegin/glEnd ---------------------------------------- */

static void track_material(tilesort *t, const ts_material *m)
{
    switch (m->slot) {
    case 0: tsr_call_Materialf(&t->track_table, m->face, m->pname, m->v.f[0]); break;
    case 1: tsr_call_Materialfv(&t->track_table, m->face, m->pname, m->v.f); break;
    case 2: tsr_call_Materiali(&t->track_table, m->face, m->pname, m->v.i[0]); break;
    default: tsr_call_Materialiv(&t->track_table, m->face, m->pname, m->v.i); break;
    }
}

/* The materials of the buffer just sent to targets[0..n) reach the
 * tracker, and those servers' shadows. */
static void materials_sent(tilesort *t, size_t n)
{
    if (!t->nmaterials)
        return;
    for (size_t i = 0; i < t->nmaterials; i++)
        track_material(t, &t->materials[i]);
    t->nmaterials = 0;
    for (size_t k = 0; k < n; k++)
        tsr_state_shadow_assume(t->ctx, t->srv[t->targets[k]].shadow, TSR_SM_MATERIAL);
}

/* Inside glBegin and outside alike: packed, and kept for materials_sent.
 * Outside, too, a glMaterial is a vertex attribute to Mesa, not only state:
 * called while vertices of earlier pairs are pending, it joins the vertex
 * format, and the pairs after it are lit with a material per vertex (the
 * material times the light in the shader) instead of the premultiplied
 * one a material set as state gives, which rounds differently. As a state
 * change, a repeated one vanished from the servers' streams (the tracker
 * sends differences), and geodesic, which sets the same material before
 * each glBegin, differed from the 1x1 render by a pixel, on a 1x1
 * tilesort too. In the buffer, each server of its pairs gets the calls as
 * the program made them; the others get the value by a diff once it is
 * tracked. The packer may flush the buffer before the command goes in, so
 * it is kept after packing. */
/* Whether GL takes glMaterial(face, pname, first value) without an
 * error: one it refuses outside glBegin is tracked at once, so that
 * glGetError, which the tracker answers, has it. */
static bool material_valid(int slot, GLenum face, GLenum pname, const ts_material *m)
{
    if (face != GL_FRONT && face != GL_BACK && face != GL_FRONT_AND_BACK)
        return false;
    switch (pname) {
    case GL_AMBIENT:
    case GL_DIFFUSE:
    case GL_SPECULAR:
    case GL_EMISSION:
    case GL_AMBIENT_AND_DIFFUSE:
    case GL_COLOR_INDEXES: return true;
    case GL_SHININESS: {
        float s = slot < 2 ? m->v.f[0] : (float)m->v.i[0];
        return s >= 0 && s <= 128;
    }
    default: return false;
    }
}

static void material(tilesort *t, int slot, GLenum face, GLenum pname, const void *v, size_t bytes)
{
    ts_material m = {.slot = slot, .face = face, .pname = pname};
    memcpy(&m.v, v, bytes < sizeof m.v ? bytes : sizeof m.v);
    if (!t->in_begin && !material_valid(slot, face, pname, &m)) {
        ts_flush_before_state(t);
        track_material(t, &m);
        if (!tsr_packer_pending(t->geo))
            ts_snapshot(t);
        return;
    }
    switch (slot) {
    case 0: tsr_call_Materialf(&t->geo_table, face, pname, m.v.f[0]); break;
    case 1: tsr_call_Materialfv(&t->geo_table, face, pname, m.v.f); break;
    case 2: tsr_call_Materiali(&t->geo_table, face, pname, m.v.i[0]); break;
    default: tsr_call_Materialiv(&t->geo_table, face, pname, m.v.i); break;
    }
    if (t->nmaterials == t->materials_cap) {
        size_t cap = t->materials_cap ? 2 * t->materials_cap : 64;
        ts_material *p = realloc(t->materials, cap * sizeof *p);
        if (!p) {
            tsr_error e;
            tsr_error_set(&e, TSR_ENOMEM, "out of memory keeping a glMaterial inside glBegin");
            ts_report(t, &e);
            return;
        }
        t->materials = p;
        t->materials_cap = cap;
    }
    t->materials[t->nmaterials++] = m;
}

static size_t material_values(GLenum pname) { return pname == GL_SHININESS ? 1 : pname == GL_COLOR_INDEXES ? 3 : 4; }

void ts_Materialf(void *self, GLenum face, GLenum pname, GLfloat param)
{
    material(self, 0, face, pname, &param, sizeof param);
}
void ts_Materialfv(void *self, GLenum face, GLenum pname, const GLfloat *params)
{
    material(self, 1, face, pname, params, material_values(pname) * sizeof *params);
}
void ts_Materiali(void *self, GLenum face, GLenum pname, GLint param)
{
    material(self, 2, face, pname, &param, sizeof param);
}
void ts_Materialiv(void *self, GLenum face, GLenum pname, const GLint *params)
{
    material(self, 3, face, pname, params, material_values(pname) * sizeof *params);
}

/* --- sending ------------------------------------------------------------------ */

/* Makes server s ready for what comes next: its tiles, its state diff
 * and (for a geometry buffer) the lists the buffer calls and the current
 * attributes the buffer starts with; flushes that to it. */
void ts_prepare_server(tilesort *t, ts_server *s, int geometry)
{
    if (s->tiles_version != t->tiling_version && t->tiling_version) {
        size_t i = s->index, n = t->tiling.ntiles[i];
        GLint *rects = malloc((n ? n : 1) * 4 * sizeof *rects);
        if (rects) {
            for (size_t k = 0; k < n; k++) {
                const ts_rect *r = &t->tiling.tiles[i][k];
                rects[4 * k] = r->x;
                rects[4 * k + 1] = r->y;
                rects[4 * k + 2] = r->w;
                rects[4 * k + 3] = r->h;
            }
            tsr_call_TilesTSR(&s->table, 0, (GLsizei)n, rects);
            free(rects);
            s->tiles_version = t->tiling_version;
        }
    }
    tsr_state_diff(t->ctx, s->shadow, &s->table, NULL);
    if (geometry) {
        ts_send_buffer_lists(t, s);
        send_start_current(t, s);
    }
    if (tsr_packer_flush(s->packer) != TSR_OK)
        ts_report(t, tsr_packer_error(s->packer));
}

static size_t all_servers(tilesort *t)
{
    size_t n = 0;
    for (size_t i = 0; i < t->nservers; i++)
        if (!tsr_stream_client_server_failed(t->client, i))
            t->targets[n++] = i;
    return n;
}

double ts_box_margin(const tilesort *t)
{
    const tsr_state_values *v = tsr_state_values_of(t->ctx);
    double size = v->line_width > v->point_size ? v->line_width : v->point_size;
    if (v->point_attenuation[0] != 1.0f || v->point_attenuation[1] != 0.0f || v->point_attenuation[2] != 0.0f)
        size = fmax(size, v->point_max);
    if (!isfinite(size) || size > 1e6)
        size = 1e6;
    /* half the width, plus antialiasing's extra pixel and rounding */
    return size / 2.0 + 2.0;
}

/* The margin of a filled polygon's box. GL fills a pixel only where the
 * polygon covers its centre (multisampled: one of its samples; smooth:
 * some of its area), all inside the pixel's square, so a box grown by
 * half a pixel holds every pixel it can touch with half a pixel to spare
 * for rounding (the renderer's float transform and subpixel snap are
 * well under 1/100 of a pixel). The line width and point size matter
 * only when polygons are drawn as lines or points. The general margin's
 * 2.5 pixels around the isosurface's small triangles sent 6 % more bytes
 * on a 32-server kd split (overlap 1.147 -> 1.080). */
double ts_polygon_margin(const tilesort *t)
{
    const tsr_state_values *v = tsr_state_values_of(t->ctx);
    if (v->polygon_mode[0] != GL_FILL || v->polygon_mode[1] != GL_FILL)
        return ts_box_margin(t);
    return 0.5;
}

const GLint *ts_viewport(const tilesort *t, GLint out[4])
{
    const GLint *vp = tsr_state_values_of(t->ctx)->viewport;
    if (vp[2] >= 0 && vp[3] >= 0)
        return vp;
    /* never set: GL's is the window's, from the first MakeCurrent (the
     * tracker does not know the window) */
    out[0] = out[1] = 0;
    out[2] = t->win_w;
    out[3] = t->win_h;
    return out;
}

/* The servers this buffer must reach, into t->targets. */
static size_t choose_targets(tilesort *t, size_t bytes)
{
    if (t->render_mode != GL_RENDER) { /* a selection or feedback pass: one server runs it all (gets.c) */
        if (tsr_stream_client_server_failed(t->client, t->render_server))
            return 0;
        t->targets[0] = t->render_server;
        return 1;
    }
    if (t->only_target != TS_ANY_TARGET) {
        if (tsr_stream_client_server_failed(t->client, t->only_target))
            return 0;
        t->targets[0] = t->only_target;
        return 1;
    }
    /* a program FBO is drawn whole on every server (fbo.c) */
    if (t->broadcast_next || t->split_primitive || t->program || t->app_fb || t->tiling.mode == TS_BROADCAST ||
        t->win_w <= 0)
        return all_servers(t);
    float mn[3], mx[3];
    if (!tsr_packer_bbox(t->geo, mn, mx))
        return 0; /* no vertex: current attributes only (the tracker has them) */
    int x0, y0, x1, y1;
    GLint vp[4];
    if (!ts_window_box(tsr_state_projection(t->ctx), tsr_state_modelview(t->ctx), ts_viewport(t, vp), mn, mx,
                       ts_box_margin(t), t->win_w, t->win_h, &x0, &y0, &x1, &y1))
        return all_servers(t);
    ts_tiling_add_cost(&t->tiling, x0, y0, x1, y1, (double)bytes);
    ts_tiling_hit(&t->tiling, x0, y0, x1, y1, t->hit);
    size_t n = 0;
    for (size_t i = 0; i < t->nservers; i++)
        if (t->hit[i] && !tsr_stream_client_server_failed(t->client, i))
            t->targets[n++] = i;
    return n;
}

/* The diff a single server getting every buffer would need now. */
void ts_count_solo_diff(tilesort *t)
{
    tsr_state_diff(t->ctx, t->solo, &t->solo_table, NULL);
    if (tsr_packer_flush(t->solo_packer) != TSR_OK)
        tsr_packer_clear_error(t->solo_packer);
}

int ts_geo_sink_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    tilesort *t = ctx;
    if (t->only_target == TS_ANY_TARGET) { /* sorted draws count their whole size themselves */
        t->stream_bytes += size;
        ts_count_solo_diff(t);
    }
    int piece = 0;
    if (!t->split_primitive && (t->in_begin || ts_split_open(t->split))) {
        /* a primitive cut here, or reopened (split.c): this buffer becomes
         * its piece, closed and reopened */
        ts_current end;
        ts_current_of(tsr_state_values_of(t->ctx), &end);
        GLboolean stipple = GL_FALSE, lighting = GL_FALSE;
        tsr_state_is_enabled(t->ctx, GL_LINE_STIPPLE, &stipple);
        tsr_state_is_enabled(t->ctx, GL_LIGHTING, &lighting);
        unsigned state = (stipple ? TS_SPLIT_LINE_STIPPLE : 0u) | (lighting ? TS_SPLIT_LIGHTING : 0u);
        /* feedback records show where a primitive starts (a strip's first
         * line is GL_LINE_RESET_TOKEN): a selection or feedback pass gets
         * its primitives whole */
        int may_cut = !t->program && t->render_mode == GL_RENDER;
        tsr_error e = {0};
        piece =
            ts_split_piece(t->split, buf, size, &t->start, &end, t->in_begin, may_cut, state, t->geo, &buf, &size, &e);
        if (piece < 0) {
            ts_report(t, &e);
            piece = TS_SPLIT_WHOLE;
        }
    }
    if (t->in_begin && (piece == 0 || piece == TS_SPLIT_WHOLE))
        t->split_primitive = 1; /* not cut: the primitive goes whole to every server */
    size_t n = piece == TS_SPLIT_NOTHING ? 0 : choose_targets(t, size);
    t->last_targets = n;
    for (size_t k = 0; k < n; k++)
        ts_prepare_server(t, &t->srv[t->targets[k]], 1);
    int rc = TSR_OK;
    if (n) {
        rc = tsr_stream_client_send(t->client, t->targets, n, buf, size, err);
        for (size_t k = 0; k < n; k++) {
            ts_server *s = &t->srv[t->targets[k]];
            s->frame_bytes += size;
            if (!t->broadcast_next) /* window and frame commands ride the geometry buffer to all */
                t->frame_geometry[s->index] += size;
            assume_current(t, s);
        }
    }
    materials_sent(t, n);
    t->broadcast_next = 0;
    t->nbuffer_lists = 0;
    t->buffer_calls_any = 0;
    if (!t->in_begin)
        t->split_primitive = 0;
    ts_snapshot(t);
    return rc;
}

int ts_server_sink_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    ts_server *s = ctx;
    s->frame_bytes += size;
    return s->inner.flush(s->inner.ctx, buf, size, err);
}

int ts_server_sink_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    ts_server *s = ctx;
    return s->inner.reply(s->inner.ctx, id, data, size, err);
}

void ts_flush_geometry(tilesort *t)
{
    if (tsr_packer_pending(t->geo) && tsr_packer_flush(t->geo) != TSR_OK) {
        ts_report(t, tsr_packer_error(t->geo));
        tsr_packer_clear_error(t->geo);
    }
}

/* Pending geometry goes before a state change, except inside glBegin
 * (then the primitive's buffers go to every server anyway). */
void ts_flush_before_state(tilesort *t)
{
    if (!t->in_begin)
        ts_flush_geometry(t);
}

/* What comes next goes to every server; the geometry before it is placed
 * by its box as usual. */
void ts_broadcast_next(tilesort *t)
{
    ts_flush_before_state(t);
    t->broadcast_next = 1;
}

static ts_server *first_live(tilesort *t)
{
    for (size_t i = 0; i < t->nservers; i++)
        if (!tsr_stream_client_server_failed(t->client, i))
            return &t->srv[i];
    return &t->srv[0];
}

/* The server that answers requests, with everything it lacks. */
ts_server *ts_to_server(tilesort *t)
{
    ts_flush_geometry(t);
    ts_server *s = first_live(t);
    ts_prepare_server(t, s, 0);
    return s;
}

/* --- glBegin / glEnd -------------------------------------------------------- */

void ts_Begin(void *self, GLenum mode)
{
    tilesort *t = self;
    /* GL refuses these (glBegin inside glBegin, a mode that is none) and
     * stays as it was: sent, the error would be raised only by the servers
     * the buffer's box reaches, perhaps none */
    if (t->in_begin || mode > GL_POLYGON) {
        ts_gl_error(t, t->in_begin ? GL_INVALID_OPERATION : GL_INVALID_ENUM);
        return;
    }
    tsr_call_Begin(&t->geo_table, mode);
    t->in_begin = 1;
}

void ts_End(void *self)
{
    tilesort *t = self;
    if (!t->in_begin) { /* GL refuses it: sent, it would reach only the servers of the next buffer */
        ts_gl_error(t, GL_INVALID_OPERATION);
        return;
    }
    if (!t->split_primitive) {
        ts_current now;
        ts_current_of(tsr_state_values_of(t->ctx), &now);
        ts_split_end(t->split, &t->normal, &now); /* a line loop that was cut closes itself */
    }
    tsr_call_End(&t->geo_table);
    t->in_begin = 0;
}
