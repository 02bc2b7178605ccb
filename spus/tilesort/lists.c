/* spus/tilesort/lists.c — display lists: compiled here, sent lazily,
 * placed by their box, expanded or replayed.
 *
 * Compiled here: their packed commands are kept, with their object-space
 * box, and sent lazily: a server gets a list the first time a buffer it
 * receives calls it. A list holding only geometry and current attributes
 * is placed by its box like any geometry. A list that changes tracked
 * state but draws only through the lists it calls (a scene-graph node:
 * transforms, materials, glCallList of meshes) is expanded: its commands
 * take the normal routes, so each mesh is placed by its own box under the
 * transform of that moment. Any other list that changes state goes to
 * every server, and its state calls are replayed into the tracker.
 *
 * Owns the compiled lists and, per server, which version of each it holds
 * (a deleted list stays on the servers until a new one of that name
 * replaces it). Never sends a list to a server ahead of its diff (the
 * unpack modes set around the list are the tracker's), and never replays a
 * called list into the tracker before the buffer calling it is flushed
 * (outside glBegin): that buffer's diffs must be the state from before the
 * list ran. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "instance.h"

static ts_list *find_list(tilesort *t, GLuint name)
{
    for (size_t i = 0; i < t->nlists; i++)
        if (t->lists[i].version && t->lists[i].name == name)
            return &t->lists[i];
    return NULL;
}

void ts_list_clear(ts_list *l)
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
        ts_list_clear(l);
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

/* --- compiling ------------------------------------------------------------ */

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

int ts_list_sink_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    tilesort *t = ctx;
    ts_list *l = t->recording;
    if (!l)
        return tsr_error_set(err, TSR_ESTATE, "%s: list buffer outside glNewList", t->name);
    ts_chunk c = {malloc(size), size};
    if (!c.data || (l->nchunks == l->cap &&
                    !(l->chunks = realloc(l->chunks, (l->cap = l->cap ? 2 * l->cap : 4) * sizeof *l->chunks)))) {
        free(c.data);
        return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory compiling list %u", t->name, l->name);
    }
    memcpy(c.data, buf, size);
    l->chunks[l->nchunks++] = c;
    t->stream_bytes += size;
    list_union_box(t, l);
    return TSR_OK;
}

void ts_NewList(void *self, GLuint name, GLenum mode)
{
    tilesort *t = self;
    if (t->recording || name == 0 || (mode != GL_COMPILE && mode != GL_COMPILE_AND_EXECUTE)) {
        /* nothing compiled; the servers never see it, so the error is made here */
        ts_gl_error(t, t->recording ? GL_INVALID_OPERATION : name == 0 ? GL_INVALID_VALUE : GL_INVALID_ENUM);
        return;
    }
    ts_flush_before_state(t);
    ts_list *l = new_list(t, name);
    if (!l) {
        tsr_error e;
        tsr_error_set(&e, TSR_ENOMEM, "out of memory compiling list %u", name);
        ts_report(t, &e);
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

void ts_EndList(void *self)
{
    tilesort *t = self;
    ts_list *l = t->recording;
    if (!l) {
        ts_gl_error(t, GL_INVALID_OPERATION);
        return;
    }
    if (tsr_packer_flush(t->list_packer) != TSR_OK) {
        ts_report(t, tsr_packer_error(t->list_packer));
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
void ts_rec_CallList(void *self, GLuint name)
{
    tilesort *t = self;
    t->recording->calls = 1;
    t->recording->unknown = 1;
    ts_list *inner = find_list(t, name);
    if (inner && inner->has_state)
        t->recording->has_state = 1;
    tsr_call_CallList(&t->list_table, name);
}

void ts_rec_BindTexture(void *self, GLenum target, GLuint name)
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

void ts_rec_CallLists(void *self, GLsizei n, GLenum type, const GLvoid *lists)
{
    tilesort *t = self;
    t->recording->calls = 1;
    t->recording->unknown = 1;
    t->recording->has_state = 1;
    tsr_call_CallLists(&t->list_table, n, type, lists);
}

/* A deleted list goes from every server that holds it too: glCallLists
 * reaches the servers whole (ts_CallLists), and a server's copy would draw
 * where GL calls nothing (piglit's gl-1.0-dlist-bitmap). The buffers that
 * called it were flushed before, so each server deletes it after them. */
void ts_DeleteLists(void *self, GLuint first, GLsizei range)
{
    tilesort *t = self;
    ts_flush_before_state(t);
    tsr_call_DeleteLists(&t->track_table, first, range);
    for (size_t i = 0; i < t->nlists; i++) {
        ts_list *l = &t->lists[i];
        if (!l->version || range <= 0 || l->name < first || l->name - first >= (GLuint)range)
            continue;
        for (size_t k = 0; k < t->nservers; k++) {
            ts_server *s = &t->srv[k];
            if (i < s->lists_cap && s->lists[i] && !tsr_stream_client_server_failed(t->client, k)) {
                tsr_call_DeleteLists(&s->table, l->name, 1);
                s->lists[i] = 0;
            }
        }
        ts_list_clear(l);
    }
}

/* --- lazy sending --------------------------------------------------------- */

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
        ts_report(t, &e);
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
        ts_report(t, tsr_packer_error(s->packer));
        return;
    }
    for (size_t i = 0; i < l->nchunks; i++) {
        s->frame_bytes += l->chunks[i].size;
        t->frame_geometry[s->index] += l->chunks[i].size;
        if (tsr_stream_client_send(t->client, &s->index, 1, l->chunks[i].data, l->chunks[i].size, &err) != TSR_OK)
            ts_report(t, &err);
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

/* Right after server s's diff: the lists the buffer being flushed calls
 * (and the lists they call) that s lacks, and the textures they bind. */
void ts_send_buffer_lists(tilesort *t, ts_server *s)
{
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
}

/* --- calling -------------------------------------------------------------- */

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
            ts_report(t, &err);
    }
    t->replay_depth--;
}

/* Applies list l's state calls to the tracker (nested calls too). */
static void replay_list(tilesort *t, ts_list *l) { run_list(t, t->replay, l); }

void ts_replay_CallList(void *self, GLuint name)
{
    tilesort *t = self;
    ts_list *l = find_list(t, name);
    if (l && l->has_state) {
        replay_list(t, l);
        t->program = tsr_state_program_has_vertex_shader(t->ctx); /* a list may switch programs */
    }
}

/* The servers the last buffer went to ran the list: they hold the state
 * the tracker now has (after the replay), so their shadows are brought to
 * it without sending anything. (Without this, a value the list changed and
 * the application then set back would look unchanged to the diff.) */
static void list_ran_on_targets(tilesort *t)
{
    for (size_t k = 0; k < t->last_targets; k++)
        tsr_state_diff(t->ctx, t->srv[t->targets[k]].shadow, &t->discard, NULL);
    ts_snapshot(t);
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

void ts_CallList(void *self, GLuint name)
{
    tilesort *t = self;
    ts_list *l = find_list(t, name);
    if (!l)
        return; /* GL: calling an undefined list does nothing */
    if ((l->unknown || l->calls) && expand_list(t, l))
        return;
    if (l->unknown || l->calls) {
        ts_broadcast_next(t);
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
            ts_flush_geometry(t);
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

void ts_replay_CallLists(void *self, GLsizei n, GLenum type, const GLvoid *lists)
{
    replay_lists_array(self, n, type, lists);
}

void ts_CallLists(void *self, GLsizei n, GLenum type, const GLvoid *lists)
{
    tilesort *t = self;
    ts_broadcast_next(t);
    t->buffer_calls_any = 1;
    tsr_call_CallLists(&t->geo_table, n, type, lists);
    if (!t->in_begin)
        ts_flush_geometry(t);
    replay_lists_array(t, n, type, lists);
    list_ran_on_targets(t);
}
