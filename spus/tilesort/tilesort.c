/* spus/tilesort/tilesort.c — the "tilesort" SPU: sort-first (DESIGN.md
 * section 3). One application stream, many tile servers; each server gets
 * only the geometry that touches its tiles, preceded by exactly the state
 * it lacks.
 *
 * Routing (set up once per instance from the spec's categories):
 *   - state and object commands the tracker (tessera/dev/state.h) implements go
 *     to the tracker only; before each one, pending geometry is flushed,
 *     because the diffs that precede geometry are taken from the tracker;
 *   - geometry is packed once into the geometry buffer while the packer
 *     keeps its object-space box; current attributes (glColor, ...) go to
 *     the buffer and to the tracker;
 *   - on flush (buffer full, state change, frame command) the box goes to
 *     window space (bucket.c) and every server it touches gets its tiles
 *     (TilesTSR, when they changed), the display lists the buffer calls
 *     that it lacks, its state diff, and then the buffer (copied once,
 *     shared by all those connections);
 *   - commands whose effect on the window is unknown (untracked state such
 *     as RasterPos, glRect, glBitmap, glDrawPixels, lists that change
 *     state, anything while a vertex shader is in use, boxes crossing the
 *     eye plane or holding NaN/Inf) make the buffer go to every server;
 *     frame commands (Clear, Finish, swap, barriers, semaphores, windows)
 *     go to every server and are flushed at once;
 *   - gets are answered by the tracker where the value is client-known,
 *     otherwise by the first live server (after its diff); glReadPixels is
 *     gathered from every server whose tiles meet the rectangle.
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
 * evaluator inside, strips under line stipple, lit quads, a program with
 * a vertex shader in use) go to every server whole, from the buffer holding their glBegin to
 * the one holding their glEnd (split_primitive).
 *
 * Array draws of independent primitives (glDrawArrays/glDrawElements of
 * points, lines, triangles, quads) are sorted primitive by primitive
 * instead: each primitive's own window box picks its servers, and each
 * server collects its primitives into compact draws of about batch_bytes
 * (batch.c: only the vertices they use, indices renumbered), sent to it
 * alone. Overlap then comes only from primitives that cross a tile edge,
 * and messages stay large. Draws that cannot be sorted (arrays in buffer
 * objects, a program with a vertex shader in use, broadcast) are cut into
 * boxed batches.
 *
 * Display lists are compiled here (their packed commands are kept, with
 * their object-space box) and sent lazily: a server gets a list the first
 * time a buffer it receives calls it. A list holding only geometry and
 * current attributes is placed by its box like any geometry. A list that
 * changes tracked state but draws only through the lists it calls (a
 * scene-graph node: transforms, materials, glCallList of meshes) is
 * expanded: its commands take the normal routes, so each mesh is placed by
 * its own box under the transform of that moment. Any other list that
 * changes state goes to every server, and its state calls are replayed
 * into the tracker.
 *
 * Owns, per instance: the stream client (tessera/dev/client.h, one connection per
 * server), the tracker with one context and one shadow per server, the
 * geometry packer, one small packer per server (diffs, tiles, lists,
 * requests), the tiling, the display lists. No globals. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tessera/dev/client.h"
#include "tessera/dev/pack.h"
#include "tessera/dev/state.h"
#include "tessera/image.h"
#include "tessera/log.h"
#include "tessera/spu.h"
#include "tilesort.h"
#include "tessera/dev/unpack.h"

/* What the routing does around a slot (see the header). */
enum {
    R_DEFAULT,      /* geometry buffer only */
    R_STATE,        /* tracker only, pending geometry flushed first */
    R_BROADCAST,    /* geometry buffer, and that buffer goes to every server */
    R_FRAME,        /* like R_BROADCAST, flushed at once */
    R_SERVER,       /* sent to the first live server (gets) */
};

/* ts_current (the current attributes): tilesort.h, shared with split.c */

typedef struct ts_chunk {
    uint8_t *data;
    size_t size;
} ts_chunk;

typedef struct ts_list {
    GLuint name;
    uint32_t version;       /* 0: slot free */
    ts_chunk *chunks;
    size_t nchunks, cap;
    float mn[3], mx[3];
    int boxed;              /* mn/mx hold the box of its vertices */
    int unknown;            /* holds commands a box cannot place: every server gets its calls */
    int has_state;          /* its calls change state: replayed into the tracker */
    int calls;              /* it calls lists */
    int geometry;           /* it draws itself (not only through the lists it calls) */
    int unexpandable;       /* holds commands a call cannot be expanded into (see expand_list) */
    tsr_pixel_modes unpack; /* unpack modes it was compiled under */
    struct {
        GLenum target;
        GLuint name;
    } *textures;            /* the textures it binds (sent before it runs) */
    size_t ntextures;
} ts_list;

typedef struct ts_server {
    struct tilesort *ts;
    size_t index;
    tsr_state_shadow *shadow;
    tsr_packer *packer;
    tsr_dispatch table;     /* the packer's functions */
    tsr_pack_sink inner;    /* the client's sink for this server */
    uint32_t tiles_version; /* of the tiling last sent (0: none) */
    uint32_t *lists;        /* per list slot: version the server has */
    size_t lists_cap;
    uint64_t frame_bytes, bytes;
    ts_batch sorted;        /* primitives of a sorted array draw waiting for this server */
} ts_server;

/* No single target: the geometry buffer goes where its box says. */
#define TS_ANY_TARGET SIZE_MAX

typedef struct tilesort {
    char name[96];
    tsr_stream_client *client;
    size_t nservers;
    ts_server *srv;
    ts_tiling tiling;
    uint32_t tiling_version;
    char *assemble;         /* PNG pattern of the gathered window, or NULL */
    size_t batch_bytes;     /* geometry is bucketed in batches of about this size */
    tsr_state_tracker *tracker;
    tsr_state_ctx *ctx;
    tsr_packer *geo;
    tsr_dispatch geo_table, track_table, normal, record;
    tsr_dispatch *live;
    unsigned char route[TSR_DISPATCH_COUNT];
    tsr_hook hooks[TSR_DISPATCH_COUNT];
    tsr_tee tees[TSR_DISPATCH_COUNT];
    tsr_hook rec_hooks[TSR_DISPATCH_COUNT];
    tsr_tee rec_tees[TSR_DISPATCH_COUNT];
    /* the geometry buffer */
    int in_begin, split_primitive, broadcast_next, program;
    ts_split *split;        /* split.c: a primitive cut across buffers */
    ts_current start;       /* current attributes when this buffer started */
    size_t *buffer_lists;   /* list slots called by this buffer */
    size_t nbuffer_lists, buffer_lists_cap;
    int buffer_calls_any;   /* glCallLists: every list may be called */
    uint8_t *hit;
    size_t *targets;
    size_t last_targets;    /* how many of targets[] the last flushed buffer went to */
    tsr_dispatch discard;   /* no-ops: diffs that only update a shadow */
    /* array draws sorted primitive by primitive */
    size_t only_target;     /* TS_ANY_TARGET, or the one server the buffer is for */
    ts_batch compact;       /* scratch: a sorted draw as one server would get it (statistics), or
                               one batch of a glDrawElements that is not sorted */
    uint8_t *gathered;      /* scratch: gathered arrays and 16-bit indices */
    size_t gathered_cap;
    /* display lists */
    ts_list *lists;
    size_t nlists;
    uint32_t list_versions;
    tsr_packer *list_packer;
    tsr_dispatch list_table;
    ts_list *recording;
    int recording_execute;
    tsr_unpacker *replay;
    int replay_depth;
    tsr_unpacker *expand;   /* runs an expanded list's commands through the normal routes */
    /* window and frames */
    int win_w, win_h;
    uint64_t frames;
    /* statistics: the stream packed once, and bytes per server per frame */
    uint64_t stream_bytes;
    /* what one server of a 1x1 configuration would get besides the stream:
     * its diffs, taken into a shadow of its own and counted, never sent */
    tsr_state_shadow *solo;
    tsr_packer *solo_packer;
    tsr_dispatch solo_table;
    uint64_t *frame_rows;   /* frames_kept rows of nservers counts */
    double *frame_seconds;  /* application time of each kept frame (swap to swap) */
    double last_swap;       /* monotonic seconds of the last swap (or of creation) */
    size_t frames_kept, frames_cap;
    tsr_error error;        /* first failure, reported once */
} tilesort;

static void report(tilesort *t, const tsr_error *e)
{
    if (!t->error.code && e->code) {
        t->error = *e;
        tsr_log(TSR_LOG_ERROR, "%s: %s", t->name, e->message);
    }
}

/* --- current attributes ------------------------------------------------------ */

static void snapshot(tilesort *t)
{
    ts_current_of(tsr_state_values_of(t->ctx), &t->start);
}

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

/* --- display lists ----------------------------------------------------------- */

static ts_list *find_list(tilesort *t, GLuint name)
{
    for (size_t i = 0; i < t->nlists; i++)
        if (t->lists[i].version && t->lists[i].name == name)
            return &t->lists[i];
    return NULL;
}

static void list_clear(ts_list *l)
{
    for (size_t i = 0; i < l->nchunks; i++)
        free(l->chunks[i].data);
    free(l->chunks);
    free(l->textures);
    memset(l, 0, sizeof *l);
}

static ts_list *new_list(tilesort *t, GLuint name)
{
    ts_list *l = find_list(t, name);
    if (l) {
        list_clear(l);
    } else {
        for (size_t i = 0; i < t->nlists && !l; i++)
            if (!t->lists[i].version)
                l = &t->lists[i];
        if (!l) {
            ts_list *n = realloc(t->lists, (t->nlists + 1) * sizeof *n);
            if (!n)
                return NULL;
            t->lists = n;
            l = &t->lists[t->nlists++];
            memset(l, 0, sizeof *l);
        }
    }
    l->name = name;
    l->version = ++t->list_versions;
    for (int i = 0; i < 3; i++) {
        l->mn[i] = INFINITY;
        l->mx[i] = -INFINITY;
    }
    return l;
}

static void list_union_box(tilesort *t, ts_list *l)
{
    float mn[3], mx[3];
    if (!tsr_packer_bbox(t->list_packer, mn, mx))
        return;
    for (int i = 0; i < 3; i++) {
        l->mn[i] = fminf(l->mn[i], mn[i]);
        l->mx[i] = fmaxf(l->mx[i], mx[i]);
    }
    l->boxed = 1;
    if (!isfinite(mn[0]) || !isfinite(mn[1]) || !isfinite(mn[2]) || !isfinite(mx[0]) || !isfinite(mx[1]) ||
        !isfinite(mx[2]))
        l->unknown = 1;
}

static int list_sink_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    tilesort *t = ctx;
    ts_list *l = t->recording;
    if (!l)
        return tsr_error_set(err, TSR_ESTATE, "%s: list buffer outside glNewList", t->name);
    ts_chunk c = {malloc(size), size};
    if (!c.data || (l->nchunks == l->cap && !(l->chunks = realloc(l->chunks, (l->cap = l->cap ? 2 * l->cap : 4) *
                                                                               sizeof *l->chunks)))) {
        free(c.data);
        return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory compiling list %u", t->name, l->name);
    }
    memcpy(c.data, buf, size);
    l->chunks[l->nchunks++] = c;
    t->stream_bytes += size;
    list_union_box(t, l);
    return TSR_OK;
}

/* The reply callback of the packers that only send (geometry, lists):
 * requests go to a server's own packer, never through these. */
static int no_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    (void)data;
    (void)size;
    tilesort *t = ctx;
    return tsr_error_set(err, TSR_ESTATE, "%s: request %u reached a packer that only sends", t->name, id);
}

static void send_pixel_modes(ts_server *s, const tsr_pixel_modes *m)
{
    static const GLenum names[] = {GL_UNPACK_ROW_LENGTH, GL_UNPACK_IMAGE_HEIGHT, GL_UNPACK_SKIP_PIXELS,
                                   GL_UNPACK_SKIP_ROWS,  GL_UNPACK_SKIP_IMAGES,  GL_UNPACK_ALIGNMENT,
                                   GL_UNPACK_SWAP_BYTES, GL_UNPACK_LSB_FIRST};
    const int32_t values[] = {m->row_length,  m->image_height, m->skip_pixels, m->skip_rows,
                              m->skip_images, m->alignment,    m->swap_bytes,  m->lsb_first};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        tsr_call_PixelStorei(&s->table, names[i], values[i]);
}

static int grow_server_lists(ts_server *s, size_t need)
{
    if (need <= s->lists_cap)
        return 0;
    uint32_t *n = realloc(s->lists, need * sizeof *n);
    if (!n)
        return -1;
    memset(n + s->lists_cap, 0, (need - s->lists_cap) * sizeof *n);
    s->lists = n;
    s->lists_cap = need;
    return 0;
}

static void ensure_list(tilesort *t, ts_server *s, size_t slot, int depth);

static void ensure_all_lists(tilesort *t, ts_server *s, int depth)
{
    for (size_t i = 0; i < t->nlists; i++)
        if (t->lists[i].version)
            ensure_list(t, s, i, depth);
}

/* Sends list `slot` to server s unless it has this version. The server's
 * state equals the tracker's here (its diff was just emitted), so the
 * unpack modes the list was compiled under are set around it and put
 * back. */
static void ensure_list(tilesort *t, ts_server *s, size_t slot, int depth)
{
    ts_list *l = &t->lists[slot];
    if (grow_server_lists(s, t->nlists) != 0) {
        tsr_error e;
        tsr_error_set(&e, TSR_ENOMEM, "out of memory");
        report(t, &e);
        return;
    }
    if (s->lists[slot] == l->version)
        return;
    s->lists[slot] = l->version;
    if (l->calls && depth < 64)
        ensure_all_lists(t, s, depth + 1);
    const tsr_pixel_modes *now = &tsr_state_values_of(t->ctx)->pixel_store.unpack;
    int modes = memcmp(now, &l->unpack, sizeof *now) != 0;
    if (modes)
        send_pixel_modes(s, &l->unpack);
    tsr_call_NewList(&s->table, l->name, GL_COMPILE);
    tsr_error err = {0};
    if (tsr_packer_flush(s->packer) != TSR_OK) {
        report(t, tsr_packer_error(s->packer));
        return;
    }
    for (size_t i = 0; i < l->nchunks; i++) {
        s->frame_bytes += l->chunks[i].size;
        if (tsr_stream_client_send(t->client, &s->index, 1, l->chunks[i].data, l->chunks[i].size, &err) != TSR_OK)
            report(t, &err);
    }
    tsr_call_EndList(&s->table);
    if (modes)
        send_pixel_modes(s, now);
}

/* The textures list l binds, as they are now, on server s (a list binds
 * by name: the object's current content is what it draws with). */
static void list_textures(tilesort *t, ts_server *s, const ts_list *l)
{
    for (size_t i = 0; i < l->ntextures; i++)
        tsr_state_send_texture(t->ctx, s->shadow, l->textures[i].target, l->textures[i].name, &s->table);
}

/* --- sending ------------------------------------------------------------------ */

/* Makes server s ready for what comes next: its tiles, the lists the
 * buffer calls, its state diff and (for a geometry buffer) the current
 * attributes the buffer starts with; flushes that to it. */
static void prepare_server(tilesort *t, ts_server *s, int geometry)
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
        if (t->buffer_calls_any)
            ensure_all_lists(t, s, 0);
        int nested = t->buffer_calls_any;
        for (size_t k = 0; k < t->nbuffer_lists; k++) {
            ensure_list(t, s, t->buffer_lists[k], 0);
            list_textures(t, s, &t->lists[t->buffer_lists[k]]);
            nested |= t->lists[t->buffer_lists[k]].calls;
        }
        for (size_t i = 0; nested && i < t->nlists; i++) /* lists called by lists */
            if (t->lists[i].version)
                list_textures(t, s, &t->lists[i]);
        send_start_current(t, s);
    }
    if (tsr_packer_flush(s->packer) != TSR_OK)
        report(t, tsr_packer_error(s->packer));
}

static size_t all_servers(tilesort *t)
{
    size_t n = 0;
    for (size_t i = 0; i < t->nservers; i++)
        if (!tsr_stream_client_server_failed(t->client, i))
            t->targets[n++] = i;
    return n;
}

static double box_margin(const tilesort *t)
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

/* The servers this buffer must reach, into t->targets. */
static size_t choose_targets(tilesort *t, size_t bytes)
{
    if (t->only_target != TS_ANY_TARGET) {
        if (tsr_stream_client_server_failed(t->client, t->only_target))
            return 0;
        t->targets[0] = t->only_target;
        return 1;
    }
    if (t->broadcast_next || t->split_primitive || t->program || t->tiling.mode == TS_BROADCAST ||
        t->win_w <= 0)
        return all_servers(t);
    float mn[3], mx[3];
    if (!tsr_packer_bbox(t->geo, mn, mx))
        return 0; /* no vertex: current attributes only (the tracker has them) */
    int x0, y0, x1, y1;
    const tsr_state_values *v = tsr_state_values_of(t->ctx);
    if (!ts_window_box(tsr_state_projection(t->ctx), tsr_state_modelview(t->ctx), v->viewport, mn, mx,
                       box_margin(t), t->win_w, t->win_h, &x0, &y0, &x1, &y1))
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
static void count_solo_diff(tilesort *t)
{
    tsr_state_diff(t->ctx, t->solo, &t->solo_table, NULL);
    if (tsr_packer_flush(t->solo_packer) != TSR_OK)
        tsr_packer_clear_error(t->solo_packer);
}

static int count_solo(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    tilesort *t = ctx;
    (void)buf;
    (void)err;
    t->stream_bytes += size;
    return TSR_OK;
}

static int geo_sink_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    tilesort *t = ctx;
    if (t->only_target == TS_ANY_TARGET) { /* sorted draws count their whole size themselves */
        t->stream_bytes += size;
        count_solo_diff(t);
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
        int may_cut = !t->program;
        tsr_error e = {0};
        piece = ts_split_piece(t->split, buf, size, &t->start, &end, t->in_begin, may_cut, state, t->geo, &buf,
                               &size, &e);
        if (piece < 0) {
            report(t, &e);
            piece = TS_SPLIT_WHOLE;
        }
    }
    if (t->in_begin && (piece == 0 || piece == TS_SPLIT_WHOLE))
        t->split_primitive = 1; /* not cut: the primitive goes whole to every server */
    size_t n = piece == TS_SPLIT_NOTHING ? 0 : choose_targets(t, size);
    t->last_targets = n;
    for (size_t k = 0; k < n; k++)
        prepare_server(t, &t->srv[t->targets[k]], 1);
    int rc = TSR_OK;
    if (n) {
        rc = tsr_stream_client_send(t->client, t->targets, n, buf, size, err);
        for (size_t k = 0; k < n; k++) {
            ts_server *s = &t->srv[t->targets[k]];
            s->frame_bytes += size;
            assume_current(t, s);
        }
    }
    t->broadcast_next = 0;
    t->nbuffer_lists = 0;
    t->buffer_calls_any = 0;
    if (!t->in_begin)
        t->split_primitive = 0;
    snapshot(t);
    return rc;
}

static int server_sink_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    ts_server *s = ctx;
    s->frame_bytes += size;
    return s->inner.flush(s->inner.ctx, buf, size, err);
}

static int server_sink_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    ts_server *s = ctx;
    return s->inner.reply(s->inner.ctx, id, data, size, err);
}

static void flush_geometry(tilesort *t)
{
    if (tsr_packer_pending(t->geo) && tsr_packer_flush(t->geo) != TSR_OK) {
        report(t, tsr_packer_error(t->geo));
        tsr_packer_clear_error(t->geo);
    }
}

/* Pending geometry goes before a state change, except inside glBegin
 * (then the primitive's buffers go to every server anyway). */
static void flush_before_state(tilesort *t)
{
    if (!t->in_begin)
        flush_geometry(t);
}

static ts_server *first_live(tilesort *t)
{
    for (size_t i = 0; i < t->nservers; i++)
        if (!tsr_stream_client_server_failed(t->client, i))
            return &t->srv[i];
    return &t->srv[0];
}

/* --- hooks ----------------------------------------------------------------- */

static void hook_before(void *ctx, int slot)
{
    tilesort *t = ctx;
    switch (t->route[slot]) {
    case R_STATE:
        flush_before_state(t);
        break;
    case R_BROADCAST:
    case R_FRAME:
        flush_before_state(t);
        t->broadcast_next = 1;
        break;
    case R_SERVER:
        flush_geometry(t);
        prepare_server(t, first_live(t), 0);
        break;
    default:
        break;
    }
}

static void hook_after(void *ctx, int slot)
{
    tilesort *t = ctx;
    if (t->route[slot] == R_FRAME && !t->in_begin)
        flush_geometry(t);
    if (t->route[slot] == R_STATE && !tsr_packer_pending(t->geo))
        snapshot(t);
}

/* A command inside glNewList that a box cannot place. */
static void rec_before(void *ctx, int slot)
{
    tilesort *t = ctx;
    if (t->recording) {
        t->recording->unknown = 1;
        t->recording->has_state = 1;
        /* pixel data was packed under the compile-time unpack modes */
        const char *name = tsr_dispatch_name(slot);
        if (t->route[slot] != R_STATE || strstr(name, "TexImage") || strstr(name, "TexSubImage") ||
            !strcmp(name, "PolygonStipple"))
            t->recording->unexpandable = 1;
    }
}

/* Geometry inside glNewList: the list draws by itself. */
static void rec_geometry_before(void *ctx, int slot)
{
    tilesort *t = ctx;
    (void)slot;
    if (t->recording)
        t->recording->geometry = 1;
}

/* A current attribute inside glNewList: the list's calls change the
 * current values, so they are replayed into the tracker (the box still
 * places the list). */
static void rec_current_before(void *ctx, int slot)
{
    tilesort *t = ctx;
    (void)slot;
    if (t->recording)
        t->recording->has_state = 1;
}

/* --- commands with their own code ------------------------------------------- */

static void ts_Begin(void *self, GLenum mode)
{
    tilesort *t = self;
    tsr_call_Begin(&t->geo_table, mode);
    t->in_begin = 1;
}

static void ts_End(void *self)
{
    tilesort *t = self;
    if (!t->split_primitive) {
        ts_current now;
        ts_current_of(tsr_state_values_of(t->ctx), &now);
        ts_split_end(t->split, &t->normal, &now); /* a line loop that was cut closes itself */
    }
    tsr_call_End(&t->geo_table);
    t->in_begin = 0;
}

static void frame_command_done(tilesort *t)
{
    flush_geometry(t);
}

static void window_size(tilesort *t, GLsizei w, GLsizei h)
{
    if (w == t->win_w && h == t->win_h)
        return;
    t->win_w = w;
    t->win_h = h;
    ts_tiling_window(&t->tiling, w, h);
    t->tiling_version++;
}

/* A window command goes to every server at once; the window's size then
 * places the tiles (and the load balancer's first split). */
static void window_command(tilesort *t, tsr_entry entry, GLint window, GLsizei w, GLsizei h)
{
    flush_before_state(t);
    t->broadcast_next = 1;
    ((tsr_fn_WindowSizeTSR)entry.fn)(entry.self, window, w, h);
    frame_command_done(t);
    window_size(t, w, h);
}

static void ts_WindowCreateTSR(void *self, GLint window, GLsizei w, GLsizei h)
{
    tilesort *t = self;
    window_command(t, t->geo_table.WindowCreateTSR, window, w, h);
}

static void ts_WindowSizeTSR(void *self, GLint window, GLsizei w, GLsizei h)
{
    tilesort *t = self;
    window_command(t, t->geo_table.WindowSizeTSR, window, w, h);
}

static void gather_pixels(tilesort *t, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type,
                          void *pixels);

static void assemble_frame(tilesort *t)
{
    if (!t->assemble || t->win_w <= 0)
        return;
    /* read as RGBA bytes under the application's pack modes (the servers
     * hold them), then take the rows out tightly */
    const tsr_pixel_modes *pack = &tsr_state_values_of(t->ctx)->pixel_store.pack;
    tsr_pixel_layout l;
    if (tsr_pixel_layout_of(pack, 2, t->win_w, t->win_h, 1, GL_RGBA, GL_UNSIGNED_BYTE, &l) != 0)
        return;
    uint8_t *raw = calloc(1, (size_t)l.extent), *img = malloc((size_t)t->win_w * (size_t)t->win_h * 4);
    if (raw && img) {
        gather_pixels(t, 0, 0, t->win_w, t->win_h, GL_RGBA, GL_UNSIGNED_BYTE, raw);
        for (int r = 0; r < t->win_h; r++)
            memcpy(img + (size_t)r * (size_t)t->win_w * 4, raw + l.first + (size_t)r * l.row_bytes,
                   (size_t)t->win_w * 4);
        char path[4096];
        snprintf(path, sizeof path, t->assemble, (int)t->frames);
        tsr_error err = {0};
        if (tsr_image_write_png_rgba(img, t->win_w, t->win_h, (size_t)t->win_w * 4, 1, path, &err) != TSR_OK)
            report(t, &err);
    }
    free(raw);
    free(img);
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* Per-frame bytes per server, for the statistics (the first
 * TS_STATS_FRAMES frames; totals cover every frame). */
#define TS_STATS_FRAMES 100000
static void keep_frame_row(tilesort *t)
{
    if (t->frames_kept == TS_STATS_FRAMES)
        return;
    if (t->frames_kept == t->frames_cap) {
        size_t cap = t->frames_cap ? 2 * t->frames_cap : 64;
        uint64_t *n = realloc(t->frame_rows, cap * t->nservers * sizeof *n);
        if (!n)
            return;
        t->frame_rows = n;
        double *secs = realloc(t->frame_seconds, cap * sizeof *secs);
        if (!secs)
            return;
        t->frame_seconds = secs;
        t->frames_cap = cap;
    }
    double now = now_seconds();
    t->frame_seconds[t->frames_kept] = now - t->last_swap;
    t->last_swap = now;
    for (size_t i = 0; i < t->nservers; i++)
        t->frame_rows[t->frames_kept * t->nservers + i] = t->srv[i].frame_bytes;
    t->frames_kept++;
}

static const char *bucket_name(ts_bucket_mode m)
{
    return m == TS_BROADCAST ? "broadcast" : m == TS_TILES ? "tiles" : m == TS_BALANCE ? "balance" : "grid";
}

/* The sort-first members of the statistics file (tessera/dev/client.h):
 *   "sort_first":{"bucket":"grid","servers":4,"stream_bytes":N,
 *     "bytes_out":N,"overlap":X,"imbalance":X,"server_bytes":[...],
 *     "frame_seconds":[...],"frames":[[bytes to server 0, 1, ...], ...]}
 * stream_bytes: the geometry buffers and display lists, packed once, and
 * the state diffs one server getting all of them would need (what
 * one server of a 1x1 configuration gets, without its state diffs);
 * overlap = bytes_out / stream_bytes; imbalance = max / mean of the
 * servers' bytes (1 is perfect); frame_seconds: the application's time
 * from one swap to the next (the first from the SPU's creation). */
static void write_sort_first_stats(void *ctx, FILE *f)
{
    tilesort *t = ctx;
    uint64_t total = 0, max = 0;
    for (size_t i = 0; i < t->nservers; i++) {
        uint64_t b = t->srv[i].bytes + t->srv[i].frame_bytes;
        total += b;
        max = b > max ? b : max;
    }
    double mean = (double)total / (double)t->nservers;
    fprintf(f, ",\"sort_first\":{\"bucket\":\"%s\",\"servers\":%zu,\"stream_bytes\":%llu,\"bytes_out\":%llu,"
               "\"overlap\":%.6f,\"imbalance\":%.6f,\"server_bytes\":[",
            bucket_name(t->tiling.mode), t->nservers, (unsigned long long)t->stream_bytes,
            (unsigned long long)total, t->stream_bytes ? (double)total / (double)t->stream_bytes : 0.0,
            mean > 0 ? (double)max / mean : 0.0);
    for (size_t i = 0; i < t->nservers; i++)
        fprintf(f, "%s%llu", i ? "," : "", (unsigned long long)(t->srv[i].bytes + t->srv[i].frame_bytes));
    fprintf(f, "],\"frame_seconds\":[");
    for (size_t r = 0; r < t->frames_kept; r++)
        fprintf(f, "%s%.6f", r ? "," : "", t->frame_seconds[r]);
    fprintf(f, "],\"frames\":[");
    for (size_t r = 0; r < t->frames_kept; r++) {
        fprintf(f, "%s[", r ? "," : "");
        for (size_t i = 0; i < t->nservers; i++)
            fprintf(f, "%s%llu", i ? "," : "", (unsigned long long)t->frame_rows[r * t->nservers + i]);
        fprintf(f, "]");
    }
    fprintf(f, "]}");
}

static void ts_SwapBuffersTSR(void *self, GLint window, GLbitfield flags)
{
    tilesort *t = self;
    flush_geometry(t);
    assemble_frame(t);
    t->broadcast_next = 1;
    tsr_call_SwapBuffersTSR(&t->geo_table, window, flags);
    flush_geometry(t);
    t->frames++;
    tsr_stream_client_count_frame(t->client);
    keep_frame_row(t);
    for (size_t i = 0; i < t->nservers; i++) {
        t->srv[i].bytes += t->srv[i].frame_bytes;
        t->srv[i].frame_bytes = 0;
    }
    if (ts_tiling_rebalance(&t->tiling))
        t->tiling_version++;
}

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
    tsr_client_array *all[4] = {&a->vertex, &a->normal, &a->color, &a->edge_flag};
    for (int i = 0; i < 4; i++)
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
    tsr_client_array *arrays[4 + TSR_PACK_TEXUNITS + TSR_PACK_ATTRIBS];
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
    tsr_client_array *arrays[4 + TSR_PACK_TEXUNITS + TSR_PACK_ATTRIBS];
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
    tsr_client_array saved[4 + TSR_PACK_TEXUNITS + TSR_PACK_ATTRIBS];
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
    GLenum mode, type;      /* type: of the indices; 0 for glDrawArrays */
    GLint first;
    const void *indices;
    int per;                /* vertices per primitive */
    size_t vertex_bytes;    /* wire bytes of one vertex's array elements */
    size_t overhead;        /* wire bytes of a draw command beyond its vertices and indices, at most */
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
        report(t, &e);
    }
    flush_geometry(t);
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
    ts_draw d = {.mode = mode, .type = type, .first = first, .indices = indices, .per = independent_vertices(mode),
                 .vertex_bytes = vertex_bytes(a)};
    float pos[4][4];
    if (!d.per || !d.vertex_bytes || count < 2 * d.per || (size_t)count * d.vertex_bytes < TS_SORT_MIN_BYTES ||
        t->in_begin || t->program || t->tiling.mode == TS_BROADCAST || t->win_w <= 0 || !a->vertex.enabled ||
        (type && (!indices || a->element_buffer)) || first < 0 ||
        !tsr_client_array_position(&a->vertex, source_vertex(&d, 0), pos[0]))
        return 0;
    flush_geometry(t);
    count_solo_diff(t);
    tsr_client_array *arrays[4 + TSR_PACK_TEXUNITS + TSR_PACK_ATTRIBS];
    d.overhead = (size_t)tsr_packer_draw_bytes(t->geo, 1, type ? GL_UNSIGNED_INT : 0, 1) +
                 8 * (enabled_arrays(a, arrays) + 1);
    const tsr_state_values *v = tsr_state_values_of(t->ctx);
    double pm[16];
    ts_clip_matrix(tsr_state_projection(t->ctx), tsr_state_modelview(t->ctx), pm);
    double margin = box_margin(t);
    double cost = (double)d.per * (double)(d.vertex_bytes + (type ? tsr_gl_type_size(type) : 0));
    size_t nprims = (size_t)count / (size_t)d.per;
    int failed = 0;
    for (size_t p = 0; p < nprims && !failed; p++) {
        uint32_t src[4];
        for (int k = 0; k < d.per; k++) {
            src[k] = source_vertex(&d, p * (size_t)d.per + (size_t)k);
            tsr_client_array_position(&a->vertex, src[k], pos[k]);
        }
        int x0, y0, x1, y1;
        if (ts_points_box(pm, v->viewport, (const float (*)[4])pos, d.per, margin, t->win_w, t->win_h, &x0, &y0, &x1,
                          &y1)) {
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
        tsr_error_set(&e, TSR_ENOMEM, "a draw of %d vertices could not be sorted (out of memory or index 0x%x)",
                      count, UINT32_MAX);
        report(t, &e);
    }
    return 1;
}

static void ts_DrawArrays(void *self, GLenum mode, GLint first, GLsizei count)
{
    tilesort *t = self;
    if (draw_sorted(t, mode, first, count, 0, NULL))
        return;
    GLsizei batch = batch_vertices(t, mode, count, 0);
    if (!batch) {
        tsr_call_DrawArrays(&t->geo_table, mode, first, count);
        return;
    }
    for (GLsizei k = 0; k < count; k += batch) {
        GLsizei n = count - k < batch ? count - k : batch;
        tsr_call_DrawArrays(&t->geo_table, mode, first + k, n);
        flush_geometry(t);
    }
}

static void ts_DrawElements(void *self, GLenum mode, GLsizei count, GLenum type, const void *indices)
{
    tilesort *t = self;
    size_t isize = tsr_gl_type_size(type);
    int listed = type == GL_UNSIGNED_BYTE || type == GL_UNSIGNED_SHORT || type == GL_UNSIGNED_INT;
    if (listed && draw_sorted(t, mode, 0, count, type, indices))
        return;
    GLsizei batch = t->geo->arrays.element_buffer || !indices || !listed ? 0 : batch_vertices(t, mode, count, isize);
    if (!batch) {
        tsr_call_DrawElements(&t->geo_table, mode, count, type, indices);
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
        flush_geometry(t);
    }
}

/* Programs are tracked (core/state/state_glsl.c) and reach each server in its
 * diff, the first time it draws with them. While the current program has
 * a vertex shader, positions are the shader's: buffers go to every server. */
static void ts_UseProgram(void *self, GLuint program)
{
    tilesort *t = self;
    flush_before_state(t);
    tsr_call_UseProgram(&t->track_table, program);
    t->program = tsr_state_program_has_vertex_shader(t->ctx);
    if (!tsr_packer_pending(t->geo))
        snapshot(t);
}

/* Shader and program gets: what the tracker knows, else the first live
 * server after it has been given the object (compile/link status, info
 * logs, locations: the same link inputs give the same answers on every
 * server, tests/state glsl_*). */
static ts_server *to_server(tilesort *t);

static ts_server *glsl_server(tilesort *t, GLuint name, int program)
{
    ts_server *s = to_server(t);
    if (program)
        tsr_state_send_program(t->ctx, s->shadow, name, &s->table);
    else
        tsr_state_send_shader(t->ctx, s->shadow, name, &s->table);
    return s;
}

static void ts_GetShaderiv(void *self, GLuint shader, GLenum pname, GLint *out)
{
    tilesort *t = self;
    if (!tsr_state_get_shaderiv(t->ctx, shader, pname, out))
        tsr_call_GetShaderiv(&glsl_server(t, shader, 0)->table, shader, pname, out);
}

static void ts_GetProgramiv(void *self, GLuint program, GLenum pname, GLint *out)
{
    tilesort *t = self;
    if (!tsr_state_get_programiv(t->ctx, program, pname, out))
        tsr_call_GetProgramiv(&glsl_server(t, program, 1)->table, program, pname, out);
}

static void ts_GetShaderInfoLog(void *self, GLuint shader, GLsizei size, GLsizei *length, GLchar *log)
{
    tsr_call_GetShaderInfoLog(&glsl_server(self, shader, 0)->table, shader, size, length, log);
}

static void ts_GetProgramInfoLog(void *self, GLuint program, GLsizei size, GLsizei *length, GLchar *log)
{
    tsr_call_GetProgramInfoLog(&glsl_server(self, program, 1)->table, program, size, length, log);
}

static GLint ts_GetUniformLocation(void *self, GLuint program, const GLchar *name)
{
    return tsr_call_GetUniformLocation(&glsl_server(self, program, 1)->table, program, name);
}

static GLint ts_GetAttribLocation(void *self, GLuint program, const GLchar *name)
{
    return tsr_call_GetAttribLocation(&glsl_server(self, program, 1)->table, program, name);
}

static void ts_PixelStorei(void *self, GLenum pname, GLint value)
{
    tilesort *t = self;
    flush_before_state(t);
    tsr_packer_mirror_PixelStore(t->geo, pname, value);
    tsr_call_PixelStorei(&t->track_table, pname, value);
}

static void ts_PixelStoref(void *self, GLenum pname, GLfloat value)
{
    tilesort *t = self;
    flush_before_state(t);
    tsr_packer_mirror_PixelStore(t->geo, pname, value);
    tsr_call_PixelStoref(&t->track_table, pname, value);
}

static void ts_BindBuffer(void *self, GLenum target, GLuint buffer)
{
    tilesort *t = self;
    flush_before_state(t);
    tsr_packer_mirror_BindBuffer(t->geo, target, buffer);
    tsr_call_BindBuffer(&t->track_table, target, buffer);
}

static void ts_DeleteBuffers(void *self, GLsizei n, const GLuint *buffers)
{
    tilesort *t = self;
    flush_before_state(t);
    tsr_packer_mirror_DeleteBuffers(t->geo, n, buffers);
    tsr_call_DeleteBuffers(&t->track_table, n, buffers);
}

/* Applies list l's state calls to the tracker (nested calls too). */
/* Runs list l's commands through unpacker u (the tracker's replay, or the
 * normal routes when a list is expanded), nested at most 64 deep. */
static void run_list(tilesort *t, tsr_unpacker *u, const ts_list *l)
{
    if (t->replay_depth >= 64)
        return;
    t->replay_depth++;
    u->pixels.unpack = l->unpack;
    for (size_t i = 0; i < l->nchunks; i++) {
        tsr_error err = {0};
        if (tsr_unpacker_run(u, l->chunks[i].data, l->chunks[i].size, &err) < 0)
            report(t, &err);
    }
    t->replay_depth--;
}

static void replay_list(tilesort *t, ts_list *l)
{
    run_list(t, t->replay, l);
}

static void replay_CallList(void *self, GLuint name)
{
    tilesort *t = self;
    ts_list *l = find_list(t, name);
    if (l && l->has_state) {
        replay_list(t, l);
        t->program = tsr_state_program_has_vertex_shader(t->ctx); /* a list may switch programs */
    }
}

static void replay_CallLists(void *self, GLsizei n, GLenum type, const GLvoid *lists);

/* The servers the last buffer went to ran the list: they hold the state
 * the tracker now has (after the replay), so their shadows are brought to
 * it without sending anything. (Without this, a value the list changed and
 * the application then set back would look unchanged to the diff.) */
static void list_ran_on_targets(tilesort *t)
{
    for (size_t k = 0; k < t->last_targets; k++)
        tsr_state_diff(t->ctx, t->srv[t->targets[k]].shadow, &t->discard, NULL);
    snapshot(t);
}

static void add_buffer_list(tilesort *t, size_t slot)
{
    for (size_t i = 0; i < t->nbuffer_lists; i++)
        if (t->buffer_lists[i] == slot)
            return;
    if (t->nbuffer_lists == t->buffer_lists_cap) {
        size_t cap = t->buffer_lists_cap ? 2 * t->buffer_lists_cap : 16;
        size_t *n = realloc(t->buffer_lists, cap * sizeof *n);
        if (!n) {
            t->buffer_calls_any = 1;
            return;
        }
        t->buffer_lists = n;
        t->buffer_lists_cap = cap;
    }
    t->buffer_lists[t->nbuffer_lists++] = slot;
}

/* A list that only changes tracked state and calls other lists (a
 * scene-graph node: transforms, materials, glCallList of meshes) would go
 * to every server, since its state changes are not boxed. Instead its
 * commands take the normal routes, as if the application had made them:
 * state to the tracker (and to each server with its next diff), and each
 * list it calls placed by its own box under the transform of that
 * moment. Only the small list itself is re-sent; the meshes stay lists. */
static int expand_list(tilesort *t, ts_list *l)
{
    if (l->geometry || l->unexpandable || t->in_begin || t->replay_depth >= 64)
        return 0;
    run_list(t, t->expand, l);
    return 1;
}

static void ts_CallList(void *self, GLuint name)
{
    tilesort *t = self;
    ts_list *l = find_list(t, name);
    if (!l)
        return; /* GL: calling an undefined list does nothing */
    if ((l->unknown || l->calls) && expand_list(t, l))
        return;
    if (l->unknown || l->calls) {
        flush_before_state(t);
        t->broadcast_next = 1;
    } else if (l->boxed) {
        tsr_packer_bbox3(t->geo, l->mn[0], l->mn[1], l->mn[2]);
        tsr_packer_bbox3(t->geo, l->mx[0], l->mx[1], l->mx[2]);
    }
    add_buffer_list(t, (size_t)(l - t->lists));
    tsr_call_CallList(&t->geo_table, name);
    if (l->has_state) {
        /* the diffs that precede this buffer must be the state before
         * the list ran: send it now, then let the tracker follow */
        if (!t->in_begin)
            flush_geometry(t);
        replay_list(t, l);
        list_ran_on_targets(t);
    }
}

static GLuint list_name_at(GLenum type, const GLvoid *lists, GLsizei i, int *ok)
{
    *ok = 1;
    switch (type) {
    case GL_BYTE: return (GLuint)(GLint)((const GLbyte *)lists)[i];
    case GL_UNSIGNED_BYTE: return ((const GLubyte *)lists)[i];
    case GL_SHORT: return (GLuint)(GLint)((const GLshort *)lists)[i];
    case GL_UNSIGNED_SHORT: return ((const GLushort *)lists)[i];
    case GL_INT: return (GLuint)((const GLint *)lists)[i];
    case GL_UNSIGNED_INT: return ((const GLuint *)lists)[i];
    case GL_FLOAT: return (GLuint)((const GLfloat *)lists)[i];
    case GL_2_BYTES: {
        const GLubyte *b = (const GLubyte *)lists + 2 * i;
        return (GLuint)(b[0] << 8 | b[1]);
    }
    case GL_3_BYTES: {
        const GLubyte *b = (const GLubyte *)lists + 3 * i;
        return (GLuint)(b[0] << 16 | b[1] << 8 | b[2]);
    }
    case GL_4_BYTES: {
        const GLubyte *b = (const GLubyte *)lists + 4 * i;
        return (GLuint)b[0] << 24 | (GLuint)(b[1] << 16 | b[2] << 8 | b[3]);
    }
    default: *ok = 0; return 0;
    }
}

static void replay_lists_array(tilesort *t, GLsizei n, GLenum type, const GLvoid *lists)
{
    GLuint base = tsr_state_values_of(t->ctx)->list_base;
    for (GLsizei i = 0; i < n && lists; i++) {
        int ok;
        GLuint name = list_name_at(type, lists, i, &ok);
        if (!ok)
            return;
        ts_list *l = find_list(t, base + name);
        if (l && l->has_state)
            replay_list(t, l);
    }
}

static void replay_CallLists(void *self, GLsizei n, GLenum type, const GLvoid *lists)
{
    replay_lists_array(self, n, type, lists);
}

static void ts_CallLists(void *self, GLsizei n, GLenum type, const GLvoid *lists)
{
    tilesort *t = self;
    flush_before_state(t);
    t->broadcast_next = 1;
    t->buffer_calls_any = 1;
    tsr_call_CallLists(&t->geo_table, n, type, lists);
    if (!t->in_begin)
        flush_geometry(t);
    replay_lists_array(t, n, type, lists);
    list_ran_on_targets(t);
}

static void ts_NewList(void *self, GLuint name, GLenum mode)
{
    tilesort *t = self;
    if (t->recording || name == 0 || (mode != GL_COMPILE && mode != GL_COMPILE_AND_EXECUTE))
        return; /* GL: an error, nothing compiled */
    flush_before_state(t);
    ts_list *l = new_list(t, name);
    if (!l) {
        tsr_error e;
        tsr_error_set(&e, TSR_ENOMEM, "out of memory compiling list %u", name);
        report(t, &e);
        return;
    }
    tsr_call_NewList(&t->track_table, name, mode);
    l->unpack = tsr_state_values_of(t->ctx)->pixel_store.unpack;
    /* the list packer reads client memory the way the geometry packer does */
    t->list_packer->pixels = t->geo->pixels;
    t->list_packer->arrays = t->geo->arrays;
    tsr_packer_bbox_reset(t->list_packer);
    t->recording = l;
    t->recording_execute = mode == GL_COMPILE_AND_EXECUTE;
    *t->live = t->record;
}

static void ts_EndList(void *self)
{
    tilesort *t = self;
    ts_list *l = t->recording;
    if (!l)
        return;
    if (tsr_packer_flush(t->list_packer) != TSR_OK) {
        report(t, tsr_packer_error(t->list_packer));
        tsr_packer_clear_error(t->list_packer);
    }
    t->recording = NULL;
    *t->live = t->normal;
    tsr_call_EndList(&t->track_table);
    if (t->recording_execute)
        ts_CallList(t, l->name);
}

/* glCallList / glCallLists while compiling: recorded, and the list is
 * marked as calling lists. */
static void rec_CallList(void *self, GLuint name)
{
    tilesort *t = self;
    t->recording->calls = 1;
    t->recording->unknown = 1;
    ts_list *inner = find_list(t, name);
    if (inner && inner->has_state)
        t->recording->has_state = 1;
    tsr_call_CallList(&t->list_table, name);
}

static void rec_BindTexture(void *self, GLenum target, GLuint name)
{
    tilesort *t = self;
    ts_list *l = t->recording;
    l->unknown = 1; /* a state change: every server runs its calls */
    l->has_state = 1;
    int known = 0;
    for (size_t i = 0; i < l->ntextures && !known; i++)
        known = l->textures[i].target == target && l->textures[i].name == name;
    if (!known && name) {
        void *n = realloc(l->textures, (l->ntextures + 1) * sizeof *l->textures);
        if (n) {
            l->textures = n;
            l->textures[l->ntextures].target = target;
            l->textures[l->ntextures].name = name;
            l->ntextures++;
        }
    }
    tsr_call_BindTexture(&t->list_table, target, name);
}

static void rec_CallLists(void *self, GLsizei n, GLenum type, const GLvoid *lists)
{
    tilesort *t = self;
    t->recording->calls = 1;
    t->recording->unknown = 1;
    t->recording->has_state = 1;
    tsr_call_CallLists(&t->list_table, n, type, lists);
}

static void ts_DeleteLists(void *self, GLuint first, GLsizei range)
{
    tilesort *t = self;
    flush_before_state(t);
    tsr_call_DeleteLists(&t->track_table, first, range);
    for (size_t i = 0; i < t->nlists; i++) {
        ts_list *l = &t->lists[i];
        if (l->version && l->name >= first && range > 0 && l->name - first < (GLuint)range)
            list_clear(l); /* servers keep their copy; a new list of that name replaces it */
    }
}

/* --- gets ------------------------------------------------------------------- */

static ts_server *to_server(tilesort *t)
{
    flush_geometry(t);
    ts_server *s = first_live(t);
    prepare_server(t, s, 0);
    return s;
}

#define ANSWER_OR_ASK(getter, call)                                                                                \
    do {                                                                                                           \
        tilesort *t = self;                                                                                        \
        if (getter)                                                                                                \
            return;                                                                                                \
        ts_server *s = to_server(t);                                                                               \
        call;                                                                                                      \
    } while (0)

static void ts_GetBooleanv(void *self, GLenum p, GLboolean *o)
{
    ANSWER_OR_ASK(tsr_state_get_booleanv(t->ctx, p, o), tsr_call_GetBooleanv(&s->table, p, o));
}
static void ts_GetIntegerv(void *self, GLenum p, GLint *o)
{
    ANSWER_OR_ASK(tsr_state_get_integerv(t->ctx, p, o), tsr_call_GetIntegerv(&s->table, p, o));
}
static void ts_GetFloatv(void *self, GLenum p, GLfloat *o)
{
    ANSWER_OR_ASK(tsr_state_get_floatv(t->ctx, p, o), tsr_call_GetFloatv(&s->table, p, o));
}
static void ts_GetDoublev(void *self, GLenum p, GLdouble *o)
{
    ANSWER_OR_ASK(tsr_state_get_doublev(t->ctx, p, o), tsr_call_GetDoublev(&s->table, p, o));
}
static void ts_GetLightfv(void *self, GLenum l, GLenum p, GLfloat *o)
{
    ANSWER_OR_ASK(tsr_state_get_lightfv(t->ctx, l, p, o), tsr_call_GetLightfv(&s->table, l, p, o));
}
static void ts_GetMaterialfv(void *self, GLenum f, GLenum p, GLfloat *o)
{
    ANSWER_OR_ASK(tsr_state_get_materialfv(t->ctx, f, p, o), tsr_call_GetMaterialfv(&s->table, f, p, o));
}
static void ts_GetTexEnvfv(void *self, GLenum tg, GLenum p, GLfloat *o)
{
    ANSWER_OR_ASK(tsr_state_get_tex_envfv(t->ctx, tg, p, o), tsr_call_GetTexEnvfv(&s->table, tg, p, o));
}
static void ts_GetTexGenfv(void *self, GLenum c, GLenum p, GLfloat *o)
{
    ANSWER_OR_ASK(tsr_state_get_tex_genfv(t->ctx, c, p, o), tsr_call_GetTexGenfv(&s->table, c, p, o));
}
static void ts_GetTexParameterfv(void *self, GLenum tg, GLenum p, GLfloat *o)
{
    ANSWER_OR_ASK(tsr_state_get_tex_parameterfv(t->ctx, tg, p, o), tsr_call_GetTexParameterfv(&s->table, tg, p, o));
}
static void ts_GetTexLevelParameteriv(void *self, GLenum tg, GLint lv, GLenum p, GLint *o)
{
    ANSWER_OR_ASK(tsr_state_get_tex_level_parameteriv(t->ctx, tg, lv, p, o),
                  tsr_call_GetTexLevelParameteriv(&s->table, tg, lv, p, o));
}
static void ts_GetClipPlane(void *self, GLenum p, GLdouble *o)
{
    ANSWER_OR_ASK(tsr_state_get_clip_plane(t->ctx, p, o), tsr_call_GetClipPlane(&s->table, p, o));
}
static void ts_GetPolygonStipple(void *self, GLubyte *o)
{
    ANSWER_OR_ASK(tsr_state_get_polygon_stipple(t->ctx, o), tsr_call_GetPolygonStipple(&s->table, o));
}
static void ts_GetBufferParameteriv(void *self, GLenum tg, GLenum p, GLint *o)
{
    ANSWER_OR_ASK(tsr_state_get_buffer_parameteriv(t->ctx, tg, p, o),
                  tsr_call_GetBufferParameteriv(&s->table, tg, p, o));
}
static GLboolean ts_IsEnabled(void *self, GLenum cap)
{
    tilesort *t = self;
    GLboolean b = GL_FALSE;
    if (tsr_state_is_enabled(t->ctx, cap, &b))
        return b;
    return tsr_call_IsEnabled(&to_server(t)->table, cap);
}

/* Each server answers for its own tiles; pixels outside every tile come
 * from the first server's answer. */
static void gather_pixels(tilesort *t, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type,
                          void *pixels)
{
    flush_geometry(t);
    const tsr_pixel_modes *pack = &tsr_state_values_of(t->ctx)->pixel_store.pack;
    tsr_pixel_layout l;
    if (w <= 0 || h <= 0 || !pixels ||
        tsr_pixel_layout_of(pack, 2, w, h, 1, format, type, &l) != 0 || l.group_bytes == 0) {
        ts_server *s = to_server(t);
        tsr_call_ReadPixels(&s->table, x, y, w, h, format, type, pixels);
        return;
    }
    uint8_t *tmp = malloc((size_t)l.extent);
    if (!tmp) {
        tsr_error e;
        tsr_error_set(&e, TSR_ENOMEM, "out of memory for glReadPixels (%d x %d)", (int)w, (int)h);
        report(t, &e);
        return;
    }
    int first = 1;
    for (size_t i = 0; i < t->nservers; i++) {
        ts_server *s = &t->srv[i];
        if (tsr_stream_client_server_failed(t->client, i))
            continue;
        int meets = first;
        for (size_t k = 0; k < t->tiling.ntiles[i] && !meets; k++) {
            const ts_rect *r = &t->tiling.tiles[i][k];
            meets = r->x < x + w && x < r->x + r->w && r->y < y + h && y < r->y + r->h;
        }
        if (!meets)
            continue;
        prepare_server(t, s, 0);
        tsr_call_ReadPixels(&s->table, x, y, w, h, format, type, tmp);
        if (first) {
            tsr_pixel_copy_spans(&l, h, 1, pixels, tmp);
            first = 0;
        }
        for (size_t k = 0; k < t->tiling.ntiles[i]; k++) {
            const ts_rect *r = &t->tiling.tiles[i][k];
            int cx0 = r->x > x ? r->x : x, cy0 = r->y > y ? r->y : y;
            int cx1 = r->x + r->w < x + w ? r->x + r->w : x + w, cy1 = r->y + r->h < y + h ? r->y + r->h : y + h;
            for (int row = cy0; row < cy1; row++) {
                size_t at = (size_t)(l.first + (uint64_t)(row - y) * l.row_bytes + (uint64_t)(cx0 - x) * l.group_bytes);
                memcpy((uint8_t *)pixels + at, tmp + at, (size_t)((uint64_t)(cx1 - cx0) * l.group_bytes));
            }
        }
    }
    free(tmp);
}

static void ts_ReadPixels(void *self, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type,
                          void *pixels)
{
    gather_pixels(self, x, y, w, h, format, type, pixels);
}

/* --- set-up -------------------------------------------------------------------- */

static int current_slots(uint8_t *is_current)
{
    const char *name, *category;
    for (size_t i = 0; tsr_state_spec_command(i, &name, &category); i++)
        if (!strcmp(category, "current")) {
            int slot = tsr_dispatch_slot(name);
            if (slot >= 0)
                is_current[slot] = 1;
        }
    return 0;
}

/* Commands GL executes at once instead of compiling into a list (GL 2.1
 * section 5.4), beyond gets and client state. */
static int immediate_in_list(const char *name)
{
    static const char *const names[] = {"PixelStorei", "PixelStoref", "Finish", "Flush", "GenLists",
                                        "DeleteLists", "GenTextures", "DeleteTextures", "GenBuffers",
                                        "DeleteBuffers", "BindBuffer", "BufferData", "BufferSubData",
                                        "RenderMode", "FeedbackBuffer", "SelectBuffer", "NewList", "EndList",
                                        "WindowCreateTSR", "WindowSizeTSR", "WindowDestroyTSR", "SwapBuffersTSR",
                                        "CreateShader", "CreateShaderTSR", "ShaderSource", "CompileShader",
                                        "DeleteShader", "CreateProgram", "CreateProgramTSR", "DeleteProgram",
                                        "AttachShader", "DetachShader", "BindAttribLocation", "LinkProgram",
                                        "ValidateProgram"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!strcmp(names[i], name))
            return 1;
    return 0;
}

static int is_boxed_geometry(const char *name, unsigned flags)
{
    return (flags & TSR_CMD_POSITION) || !strcmp(name, "Begin") || !strcmp(name, "End") ||
           !strcmp(name, "DrawArrays") || !strcmp(name, "DrawElements") || !strcmp(name, "MultiDrawArrays") ||
           !strcmp(name, "MultiDrawElements") || !strcmp(name, "DrawRangeElements");
}

#define SET(name) tsr_set_##name(&t->normal, ts_##name, t)

static void build_tables(tilesort *t)
{
    /* What the tracker implements: the slots it changes in a no-op table. */
    tsr_dispatch nops, tracked;
    tsr_dispatch_fill_nop(&nops);
    tracked = nops;
    tsr_state_fill_dispatch(t->ctx, &tracked);
    t->track_table = tracked;
    tsr_set_CallList(&t->track_table, replay_CallList, t);
    tsr_set_CallLists(&t->track_table, replay_CallLists, t);
    uint8_t is_current[TSR_DISPATCH_COUNT] = {0};
    current_slots(is_current);

    t->normal = t->geo_table;
    for (int slot = 0; slot < TSR_DISPATCH_COUNT; slot++) {
        const char *name = tsr_dispatch_name(slot);
        int cat = tsr_dispatch_category(slot);
        unsigned flags = tsr_dispatch_flags(slot);
        int by_tracker = tracked.slots[slot].fn != nops.slots[slot].fn;
        t->route[slot] = R_DEFAULT;
        if (is_current[slot] || (by_tracker && (cat == TSR_CAT_CLIENT || (flags & TSR_CMD_LOCAL)))) {
            /* geometry buffer (or the packer's mirrors) and tracker */
            t->tees[slot] = (tsr_tee){.first = t->geo_table.slots[slot], .second = tracked.slots[slot]};
            tsr_dispatch_tee(&t->normal, slot, &t->tees[slot]);
            continue;
        }
        if (by_tracker && cat != TSR_CAT_GET) {
            t->route[slot] = R_STATE;
            t->normal.slots[slot] = tracked.slots[slot];
        } else if (by_tracker) {
            t->normal.slots[slot] = tracked.slots[slot]; /* Is*, Gen* that always answer */
            continue;
        } else if (cat == TSR_CAT_FRAME) {
            t->route[slot] = R_FRAME;
        } else if (flags & TSR_CMD_OUTPUT) {
            /* the hook's before() readies the first live server: assumed
             * to be server 0 (with on_error=drop and server 0 gone, such
             * gets are answered by nobody) */
            t->route[slot] = R_SERVER;
            t->normal.slots[slot] = t->srv[0].table.slots[slot];
        } else if ((cat == TSR_CAT_GEOMETRY && is_boxed_geometry(name, flags)) || (flags & TSR_CMD_LOCAL)) {
            continue; /* packed with its box, or only the packer's mirrors */
        } else if (cat == TSR_CAT_SPECIAL) {
            t->route[slot] = R_FRAME;
        } else {
            t->route[slot] = R_BROADCAST;
        }
        t->hooks[slot] = (tsr_hook){.before = hook_before, .after = hook_after, .ctx = t};
        tsr_dispatch_hook(&t->normal, slot, &t->hooks[slot]);
    }
    /* own code (after the generic routes, which they replace) */
    SET(Begin); SET(End); SET(DrawArrays); SET(DrawElements); SET(WindowCreateTSR); SET(WindowSizeTSR); SET(SwapBuffersTSR); SET(UseProgram);
    SET(PixelStorei); SET(PixelStoref); SET(BindBuffer); SET(DeleteBuffers);
    SET(CallList); SET(CallLists); SET(NewList); SET(EndList); SET(DeleteLists);
    SET(GetBooleanv); SET(GetIntegerv); SET(GetFloatv); SET(GetDoublev); SET(GetLightfv); SET(GetMaterialfv);
    SET(GetTexEnvfv); SET(GetTexGenfv); SET(GetTexParameterfv); SET(GetTexLevelParameteriv); SET(GetClipPlane);
    SET(GetPolygonStipple); SET(GetBufferParameteriv); SET(IsEnabled); SET(ReadPixels);
    SET(GetShaderiv); SET(GetProgramiv); SET(GetShaderInfoLog); SET(GetProgramInfoLog);
    SET(GetUniformLocation); SET(GetAttribLocation);

    /* While compiling a list: compiled commands go to the list packer;
     * what GL runs at once takes the normal route (client state also
     * updates the list packer's mirrors). */
    t->record = t->list_table;
    for (int slot = 0; slot < TSR_DISPATCH_COUNT; slot++) {
        const char *name = tsr_dispatch_name(slot);
        int cat = tsr_dispatch_category(slot);
        unsigned flags = tsr_dispatch_flags(slot);
        if (cat == TSR_CAT_CLIENT || (flags & TSR_CMD_LOCAL)) {
            t->rec_tees[slot] = (tsr_tee){.first = t->list_table.slots[slot], .second = t->normal.slots[slot]};
            tsr_dispatch_tee(&t->record, slot, &t->rec_tees[slot]);
        } else if (cat == TSR_CAT_GET || (flags & TSR_CMD_OUTPUT) || immediate_in_list(name)) {
            t->record.slots[slot] = t->normal.slots[slot];
        } else if (!is_current[slot] && !(cat == TSR_CAT_GEOMETRY && is_boxed_geometry(name, flags))) {
            t->rec_hooks[slot] = (tsr_hook){.before = rec_before, .ctx = t};
            tsr_dispatch_hook(&t->record, slot, &t->rec_hooks[slot]);
        } else if (!is_current[slot]) {
            t->rec_hooks[slot] = (tsr_hook){.before = rec_geometry_before, .ctx = t};
            tsr_dispatch_hook(&t->record, slot, &t->rec_hooks[slot]);
        } else if (is_current[slot]) {
            t->rec_hooks[slot] = (tsr_hook){.before = rec_current_before, .ctx = t};
            tsr_dispatch_hook(&t->record, slot, &t->rec_hooks[slot]);
        }
    }
    tsr_set_CallList(&t->record, rec_CallList, t);
    tsr_set_CallLists(&t->record, rec_CallLists, t);
    tsr_set_BindTexture(&t->record, rec_BindTexture, t);
    tsr_set_EndList(&t->record, ts_EndList, t);
}

static void tilesort_destroy(void *instance)
{
    tilesort *t = instance;
    if (!t)
        return;
    if (t->geo)
        flush_geometry(t);
    if (t->client)
        tsr_stream_client_destroy(t->client);
    for (size_t i = 0; t->srv && i < t->nservers; i++) {
        tsr_packer_destroy(t->srv[i].packer);
        free(t->srv[i].lists);
        ts_batch_free(&t->srv[i].sorted);
    }
    for (size_t i = 0; i < t->nlists; i++)
        list_clear(&t->lists[i]);
    free(t->lists);
    tsr_unpacker_destroy(t->replay);
    tsr_unpacker_destroy(t->expand);
    tsr_packer_destroy(t->list_packer);
    tsr_packer_destroy(t->geo);
    tsr_packer_destroy(t->solo_packer);
    tsr_state_tracker_destroy(t->tracker); /* destroys the context and shadows */
    ts_split_destroy(t->split);
    ts_tiling_free(&t->tiling);
    free(t->srv);
    free(t->hit);
    free(t->targets);
    free(t->buffer_lists);
    ts_batch_free(&t->compact);
    free(t->gathered);
    free(t->frame_rows);
    free(t->frame_seconds);
    free(t->assemble);
    free(t);
}

static void *tilesort_create(const tsr_spu_init *init, tsr_error *err)
{
    size_t count = tsr_options_count(init->options, "servers");
    if (count == 0) {
        tsr_error_set(err, TSR_EINVAL,
                      "%s: option servers is required (e.g. servers=tcp://127.0.0.1:7000,tcp://127.0.0.1:7001)",
                      init->instance_name);
        return NULL;
    }
    tilesort *t = calloc(1, sizeof *t);
    if (!t) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    snprintf(t->name, sizeof t->name, "%s", init->instance_name);
    t->only_target = TS_ANY_TARGET;
    t->nservers = count;
    t->srv = calloc(count, sizeof *t->srv);
    t->hit = calloc(count, 1);
    t->targets = calloc(count, sizeof *t->targets);
    const char **servers = calloc(count, sizeof *servers);
    size_t ntiles = tsr_options_count(init->options, "tiles");
    const char **tiles = calloc(ntiles ? ntiles : 1, sizeof *tiles);
    if (!t->srv || !t->hit || !t->targets || !servers || !tiles) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", t->name);
        goto fail;
    }
    for (size_t i = 0; i < count; i++)
        servers[i] = tsr_options_string_at(init->options, "servers", i);
    for (size_t i = 0; i < ntiles; i++)
        tiles[i] = tsr_options_string_at(init->options, "tiles", i);
    const char *bucket = tsr_options_string(init->options, "bucket");
    ts_bucket_mode mode = !strcmp(bucket, "broadcast") ? TS_BROADCAST
                          : !strcmp(bucket, "tiles")   ? TS_TILES
                          : !strcmp(bucket, "balance") ? TS_BALANCE
                                                       : TS_GRID;
    if (ts_tiling_init(&t->tiling, mode, count, tiles, ntiles, t->name, err) != TSR_OK)
        goto fail;
    t->tiling.damping = tsr_options_float(init->options, "damping");
    t->batch_bytes = (size_t)tsr_options_int(init->options, "batch_bytes");
    const char *assemble = tsr_options_string(init->options, "assemble");
    if (assemble && assemble[0] && !(t->assemble = strdup(assemble))) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", t->name);
        goto fail;
    }
    tsr_stream_client_config cfg = {.spu = "tilesort", .name = t->name, .servers = servers, .server_count = count};
    tsr_stream_client_config_from_options(&cfg, init->options);
    t->client = tsr_stream_client_connect(&cfg, err);
    if (!t->client)
        goto fail;
    tsr_stream_client_set_stats_extra(t->client, write_sort_first_stats, t);
    if (!(t->tracker = tsr_state_tracker_create(err)) || !(t->ctx = tsr_state_ctx_create(t->tracker, err)) ||
        !(t->split = ts_split_create(err)))
        goto fail;
    for (size_t i = 0; i < count; i++) {
        ts_server *s = &t->srv[i];
        s->ts = t;
        s->index = i;
        if (!(s->shadow = tsr_state_shadow_create(t->tracker, err)))
            goto fail;
        tsr_stream_client_server_sink(t->client, i, &s->inner);
        tsr_pack_sink sink = {.flush = server_sink_flush, .reply = server_sink_reply, .ctx = s};
        /* diffs, lists and requests are small: a quarter of a buffer */
        size_t size = cfg.buffer_size / 4 > TSR_PACK_MIN_BUFFER ? cfg.buffer_size / 4 : TSR_PACK_MIN_BUFFER;
        if (!(s->packer = tsr_packer_create(size, &sink, err)))
            goto fail;
        tsr_dispatch_fill_nop(&s->table);
        tsr_packer_fill_dispatch(s->packer, &s->table);
    }
    tsr_pack_sink geo_sink = {.flush = geo_sink_flush, .reply = no_reply, .ctx = t};
    tsr_pack_sink solo_sink = {.flush = count_solo, .reply = no_reply, .ctx = t};
    if (!(t->solo = tsr_state_shadow_create(t->tracker, err)) ||
        !(t->solo_packer = tsr_packer_create(TSR_PACK_MIN_BUFFER, &solo_sink, err)))
        goto fail;
    tsr_dispatch_fill_nop(&t->solo_table);
    tsr_packer_fill_dispatch(t->solo_packer, &t->solo_table);
    tsr_pack_sink list_sink = {.flush = list_sink_flush, .reply = no_reply, .ctx = t};
    if (!(t->geo = tsr_packer_create(t->batch_bytes, &geo_sink, err)) ||
        !(t->list_packer = tsr_packer_create(cfg.buffer_size, &list_sink, err)))
        goto fail;
    tsr_dispatch_fill_nop(&t->geo_table);
    tsr_packer_fill_dispatch(t->geo, &t->geo_table);
    tsr_dispatch_fill_nop(&t->discard);
    tsr_dispatch_fill_nop(&t->list_table);
    tsr_packer_fill_dispatch(t->list_packer, &t->list_table);
    build_tables(t);
    if (!(t->replay = tsr_unpacker_create(&t->track_table, NULL, NULL, err)) ||
        !(t->expand = tsr_unpacker_create(&t->normal, NULL, NULL, err)))
        goto fail;
    /* tiles known from the options are sent with each server's first buffer */
    if (mode != TS_BALANCE && ntiles)
        t->tiling_version = 1;
    snapshot(t);
    t->last_swap = now_seconds();
    t->live = init->table;
    *t->live = t->normal;
    free(servers);
    free(tiles);
    return t;
fail:
    free(servers);
    free(tiles);
    tilesort_destroy(t);
    return NULL;
}

static const tsr_option_spec tilesort_options[] = {
    {.name = "servers", .type = TSR_OPT_STRING_LIST, .default_value = "", .min = 1, .max = 0,
     .help = "server node addresses in order, comma-separated: tcp://HOST:PORT or unix:PATH (required; "
             "tessera run fills it from the node's to: list)"},
    {.name = "tiles", .type = TSR_OPT_STRING_LIST, .default_value = "", .min = 1, .max = 0,
     .help = "the servers' tiles: SERVER:X:Y:WIDTH:HEIGHT,... (SERVER is the 0-based index in servers; "
             "window pixels, origin bottom-left; tessera run fills it from the servers' tiles:)"},
    {.name = "bucket", .type = TSR_OPT_ENUM, .default_value = "grid", .choices = "grid|tiles|broadcast|balance",
     .min = 1, .max = 0,
     .help = "how geometry finds its servers: grid (tiles form columns and rows; fastest), tiles (test "
             "every tile; any layout), broadcast (every server gets everything), balance (one region per "
             "server, re-split every frame from measured costs, damped)"},
    {.name = "batch_bytes", .type = TSR_OPT_INT, .default_value = "65536", .min = 256, .max = 67108864.0,
     .help = "geometry is bucketed in batches of about this many bytes (the geometry buffer's size): "
             "smaller batches reach fewer tiles, larger ones cost fewer messages; glDrawArrays/glDrawElements "
             "of points, lines, triangles and quads are sorted primitive by primitive and sent to each "
             "server in draws of about this size; a glBegin/glEnd primitive larger than a batch is cut "
             "into batches, each closed with glEnd and reopened in the next"},
    {.name = "damping", .type = TSR_OPT_FLOAT, .default_value = "0.5", .min = 0.0, .max = 1.0,
     .help = "bucket=balance: fraction of the way each split moves towards the measured balance per frame"},
    {.name = "assemble", .type = TSR_OPT_STRING, .default_value = "", .min = 1, .max = 0,
     .help = "also gather every frame from the servers and write the whole window as PNG files with "
             "this printf pattern (frame number), e.g. out/wall-%04d.png"},
    TSR_NODE_CLIENT_OPTION_SPECS,
};

static const tsr_spu_class tilesort_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "tilesort",
    .summary = "sort-first: sends each tile server only the geometry that touches its tiles, with the state "
               "it lacks",
    .options = tilesort_options,
    .option_count = sizeof tilesort_options / sizeof tilesort_options[0],
    .create = tilesort_create,
    .destroy = tilesort_destroy,
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void)
{
    return &tilesort_class;
}
