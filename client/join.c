/* client/join.c — late joiners of a stream client (join.h): the model of
 * what the servers hold (tracker + list recorder + windows + object
 * names), the connecting thread, and the catch-up stream. */
#include "tessera/dev/util.h"
#include "join.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tessera/dev/dlist.h"
#include "tessera/dev/pack.h"
#include "tessera/dev/protocol.h"
#include "tessera/dev/state.h"
#include "tessera/log.h"
#include "tessera/dev/unpack.h"

enum { LATE_WAITING, LATE_READY, LATE_TAKEN, LATE_GAVE_UP };

typedef struct late {
    char address[TSR_NET_ADDRESS_MAX];
    int state;
    tsr_net_conn *conn; /* LATE_READY: connected, not yet admitted */
    unsigned attempts;
    tsr_error last; /* why the last attempt failed */
} late;

/* Object names the stream bound, with the target of their first binding
 * (sorted by name: binary search per BindTexture/BindBuffer). */
typedef struct named {
    GLuint name;
    GLenum target;
} named;
typedef struct name_set {
    named *v;
    size_t n, cap;
} name_set;

typedef struct window {
    GLint id;
    GLsizei width, height;
    GLint buffers; /* WindowBuffersTSR's; 0: never said (one) */
    GLint samples; /* WindowSamplesTSR's; 0: never said (single-sampled) */
} window;

struct tsr_node_join {
    char name[96];
    tsr_net *net;
    size_t buffer_size;
    uint32_t retry_ms, give_up_ms;
    /* the connecting thread and what it shares with the application thread */
    pthread_t thread;
    int thread_started;
    pthread_mutex_t lock;
    pthread_cond_t wake;
    int stop;
    late *lates;
    size_t late_count;
    atomic_uint ready; /* lates in LATE_READY */
    double start;
    /* the model (application thread only) */
    tsr_state_tracker *tracker;
    tsr_state_ctx *ctx;
    tsr_dispatch st;    /* the tracker's own slots (nop elsewhere) */
    tsr_dispatch track; /* st + our wrappers: the list recorder's `next` */
    tsr_dlist_store *lists;
    tsr_unpacker *unpacker; /* flushed buffers -> tsr_dlist_table(lists) */
    int broken;             /* a flushed buffer did not decode: no more joins */
    name_set textures, buffers;
    window *windows;
    size_t window_count, window_cap;
    GLint contexts[16];
    size_t context_count;
    GLint current_window, current_context;
    int has_current;
};

/* --- name sets --------------------------------------------------------------- */
static size_t set_lower(const name_set *s, GLuint name)
{
    size_t lo = 0, hi = s->n;
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        if (s->v[mid].name < name)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

static void set_add(name_set *s, GLuint name, GLenum target)
{
    size_t i = set_lower(s, name);
    if (i < s->n && s->v[i].name == name)
        return;
    if (s->n == s->cap) {
        size_t cap = s->cap ? s->cap * 2 : 16;
        named *v = realloc(s->v, cap * sizeof *v);
        if (!v)
            return; /* out of memory: that object is not caught up (the tracker still has it) */
        s->v = v;
        s->cap = cap;
    }
    memmove(&s->v[i + 1], &s->v[i], (s->n - i) * sizeof *s->v);
    s->v[i] = (named){name, target};
    s->n++;
}

static void set_del(name_set *s, GLuint name)
{
    size_t i = set_lower(s, name);
    if (i < s->n && s->v[i].name == name) {
        memmove(&s->v[i], &s->v[i + 1], (s->n - i - 1) * sizeof *s->v);
        s->n--;
    }
}

/* --- the model's wrappers (self = the join) ------------------------------------ */
static void tr_BindTexture(void *self, GLenum target, GLuint name)
{
    tsr_node_join *j = self;
    if (name)
        set_add(&j->textures, name, target);
    tsr_call_BindTexture(&j->st, target, name);
}

static void tr_DeleteTextures(void *self, GLsizei n, const GLuint *names)
{
    tsr_node_join *j = self;
    for (GLsizei i = 0; i < n; i++)
        set_del(&j->textures, names[i]);
    tsr_call_DeleteTextures(&j->st, n, names);
}

static void tr_BindBuffer(void *self, GLenum target, GLuint name)
{
    tsr_node_join *j = self;
    if (name)
        set_add(&j->buffers, name, target);
    tsr_call_BindBuffer(&j->st, target, name);
}

static void tr_DeleteBuffers(void *self, GLsizei n, const GLuint *names)
{
    tsr_node_join *j = self;
    for (GLsizei i = 0; i < n; i++)
        set_del(&j->buffers, names[i]);
    tsr_call_DeleteBuffers(&j->st, n, names);
}

/* glCallList: the list's state calls go into the tracker (nested calls
 * come back here through j->track). */
static void tr_CallList(void *self, GLuint list)
{
    tsr_node_join *j = self;
    tsr_error err = {0};
    if (tsr_dlist_call(j->lists, list, &j->track, &err) != TSR_OK && !j->broken) {
        j->broken = 1;
        tsr_log(TSR_LOG_ERROR, "%s: late joiners: display list %u does not replay: %s", j->name, list, err.message);
    }
}

/* Name i of glCallLists' array (GL 2.1 section 5.4), before the list base. */
static int list_name_at(GLenum type, const void *lists, GLsizei i, GLuint *out)
{
    const GLubyte *b = lists;
    switch (type) {
    case GL_BYTE: *out = (GLuint)(GLint)((const GLbyte *)lists)[i]; return 1;
    case GL_UNSIGNED_BYTE: *out = b[i]; return 1;
    case GL_SHORT: *out = (GLuint)(GLint)((const GLshort *)lists)[i]; return 1;
    case GL_UNSIGNED_SHORT: *out = ((const GLushort *)lists)[i]; return 1;
    case GL_INT: *out = (GLuint)((const GLint *)lists)[i]; return 1;
    case GL_UNSIGNED_INT: *out = ((const GLuint *)lists)[i]; return 1;
    case GL_FLOAT: {
        GLfloat f = ((const GLfloat *)lists)[i];
        if (!(f >= 0.0f && f < 4294967296.0f))
            return 0; /* not a list name (and no undefined conversion) */
        *out = (GLuint)f;
        return 1;
    }
    case GL_2_BYTES: *out = (GLuint)b[2 * i] << 8 | b[2 * i + 1]; return 1;
    case GL_3_BYTES: *out = (GLuint)b[3 * i] << 16 | (GLuint)b[3 * i + 1] << 8 | b[3 * i + 2]; return 1;
    case GL_4_BYTES:
        *out = (GLuint)b[4 * i] << 24 | (GLuint)b[4 * i + 1] << 16 | (GLuint)b[4 * i + 2] << 8 | b[4 * i + 3];
        return 1;
    default: return 0;
    }
}

static void tr_CallLists(void *self, GLsizei n, GLenum type, const void *lists)
{
    tsr_node_join *j = self;
    for (GLsizei i = 0; i < n; i++) {
        GLuint name;
        if (!list_name_at(type, lists, i, &name))
            return;
        /* The base is read per list: a list may change it (glListBase). */
        tr_CallList(self, tsr_state_values_of(j->ctx)->list_base + name);
    }
}

static window *find_window(tsr_node_join *j, GLint id)
{
    for (size_t i = 0; i < j->window_count; i++)
        if (j->windows[i].id == id)
            return &j->windows[i];
    return NULL;
}

static void tr_WindowCreateTSR(void *self, GLint id, GLsizei width, GLsizei height)
{
    tsr_node_join *j = self;
    window *w = find_window(j, id);
    if (!w && j->window_count == j->window_cap) {
        size_t cap = j->window_cap ? j->window_cap * 2 : 4;
        window *v = realloc(j->windows, cap * sizeof *v);
        if (!v)
            return;
        j->windows = v;
        j->window_cap = cap;
    }
    if (!w)
        w = &j->windows[j->window_count++];
    *w = (window){id, width, height, 0, 0};
}

static void tr_WindowBuffersTSR(void *self, GLint id, GLint buffers)
{
    window *w = find_window(self, id);
    if (w)
        w->buffers = buffers;
}

static void tr_WindowSamplesTSR(void *self, GLint id, GLint samples)
{
    window *w = find_window(self, id);
    if (w)
        w->samples = samples;
}

static void tr_WindowSizeTSR(void *self, GLint id, GLsizei width, GLsizei height)
{
    window *w = find_window(self, id);
    if (w) {
        w->width = width;
        w->height = height;
    }
}

static void tr_WindowDestroyTSR(void *self, GLint id)
{
    tsr_node_join *j = self;
    window *w = find_window(j, id);
    if (w)
        *w = j->windows[--j->window_count];
}

static void tr_ContextCreateTSR(void *self, GLint context)
{
    tsr_node_join *j = self;
    if (j->context_count < sizeof j->contexts / sizeof j->contexts[0])
        j->contexts[j->context_count++] = context;
}

static void tr_ContextDestroyTSR(void *self, GLint context)
{
    tsr_node_join *j = self;
    for (size_t i = 0; i < j->context_count; i++)
        if (j->contexts[i] == context) {
            j->contexts[i] = j->contexts[--j->context_count];
            break;
        }
}

static void tr_MakeCurrentTSR(void *self, GLint window_id, GLint context)
{
    tsr_node_join *j = self;
    j->current_window = window_id;
    j->current_context = context;
    j->has_current = 1;
}

/* --- the connecting thread ------------------------------------------------------ */
static void log_gave_up(const tsr_node_join *j, const late *l, const char *why)
{
    tsr_log(TSR_LOG_WARN, "%s: late server %s never joined (%s): %u connection attempt%s in %.1f s, last: %s", j->name,
            l->address, why, l->attempts, l->attempts == 1 ? "" : "s", tsr_now_seconds() - j->start,
            l->attempts ? l->last.message : "none made");
}

static void *connector(void *arg)
{
    tsr_node_join *j = arg;
    pthread_mutex_lock(&j->lock);
    while (!j->stop) {
        int waiting = 0;
        for (size_t i = 0; i < j->late_count && !j->stop; i++) {
            late *l = &j->lates[i];
            if (l->state != LATE_WAITING)
                continue;
            if (j->give_up_ms && (tsr_now_seconds() - j->start) * 1000.0 >= j->give_up_ms) {
                l->state = LATE_GAVE_UP;
                log_gave_up(j, l, "late_give_up_ms passed");
                continue;
            }
            waiting = 1;
            char address[TSR_NET_ADDRESS_MAX];
            memcpy(address, l->address, sizeof address);
            pthread_mutex_unlock(&j->lock);
            tsr_error err = {0};
            tsr_net_conn *conn = tsr_net_connect(j->net, address, &err);
            pthread_mutex_lock(&j->lock);
            l->attempts++;
            if (conn) {
                l->conn = conn;
                l->state = LATE_READY;
                atomic_fetch_add(&j->ready, 1);
            } else {
                l->last = err;
            }
        }
        if (!waiting)
            break;
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        uint64_t ns = (uint64_t)until.tv_nsec + (uint64_t)j->retry_ms * 1000000u;
        until.tv_sec += (time_t)(ns / 1000000000u);
        until.tv_nsec = (long)(ns % 1000000000u);
        while (!j->stop && pthread_cond_timedwait(&j->wake, &j->lock, &until) == 0) {
        }
    }
    pthread_mutex_unlock(&j->lock);
    return NULL;
}

/* --- life cycle -------------------------------------------------------------------- */
tsr_node_join *tsr_node_join_create(const tsr_node_join_config *config, tsr_error *err)
{
    const char *name = config->name ? config->name : "client";
    tsr_node_join *j = calloc(1, sizeof *j);
    if (j)
        j->lates = calloc(config->count ? config->count : 1, sizeof *j->lates);
    if (!j || !j->lates) {
        free(j);
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", name);
        return NULL;
    }
    snprintf(j->name, sizeof j->name, "%s", name);
    j->net = config->net;
    j->buffer_size = config->buffer_size;
    j->retry_ms = config->retry_ms ? config->retry_ms : 1;
    j->give_up_ms = config->give_up_ms;
    j->late_count = config->count;
    pthread_mutex_init(&j->lock, NULL);
    pthread_cond_init(&j->wake, NULL);
    atomic_init(&j->ready, 0);
    for (size_t i = 0; i < config->count; i++)
        snprintf(j->lates[i].address, sizeof j->lates[i].address, "%s", config->addresses[i]);

    j->tracker = tsr_state_tracker_create(err);
    j->ctx = j->tracker ? tsr_state_ctx_create(j->tracker, err) : NULL;
    if (!j->ctx)
        goto fail;
    tsr_dispatch_fill_nop(&j->st);
    tsr_state_fill_dispatch(j->ctx, &j->st);
    j->track = j->st;
    tsr_set_BindTexture(&j->track, tr_BindTexture, j);
    tsr_set_DeleteTextures(&j->track, tr_DeleteTextures, j);
    tsr_set_BindBuffer(&j->track, tr_BindBuffer, j);
    tsr_set_DeleteBuffers(&j->track, tr_DeleteBuffers, j);
    tsr_set_CallList(&j->track, tr_CallList, j);
    tsr_set_CallLists(&j->track, tr_CallLists, j);
    tsr_set_WindowCreateTSR(&j->track, tr_WindowCreateTSR, j);
    tsr_set_WindowSizeTSR(&j->track, tr_WindowSizeTSR, j);
    tsr_set_WindowBuffersTSR(&j->track, tr_WindowBuffersTSR, j);
    tsr_set_WindowSamplesTSR(&j->track, tr_WindowSamplesTSR, j);
    tsr_set_WindowDestroyTSR(&j->track, tr_WindowDestroyTSR, j);
    tsr_set_ContextCreateTSR(&j->track, tr_ContextCreateTSR, j);
    tsr_set_ContextDestroyTSR(&j->track, tr_ContextDestroyTSR, j);
    tsr_set_MakeCurrentTSR(&j->track, tr_MakeCurrentTSR, j);
    j->lists = tsr_dlist_create(&j->track, err);
    if (!j->lists)
        goto fail;
    j->unpacker = tsr_unpacker_create(tsr_dlist_table(j->lists), NULL, NULL, err);
    if (!j->unpacker)
        goto fail;
    j->start = tsr_now_seconds();
    if (pthread_create(&j->thread, NULL, connector, j) != 0) {
        tsr_error_set(err, TSR_EIO, "%s: cannot start the thread connecting to late servers", j->name);
        goto fail;
    }
    j->thread_started = 1;
    return j;
fail:
    if (err->code && !strstr(err->message, j->name)) {
        tsr_error cause = *err;
        tsr_error_set(err, cause.code, "%s: late joiners: %s", j->name, cause.message);
    }
    tsr_node_join_destroy(j);
    return NULL;
}

void tsr_node_join_destroy(tsr_node_join *j)
{
    if (!j)
        return;
    if (j->thread_started) {
        pthread_mutex_lock(&j->lock);
        j->stop = 1;
        pthread_cond_broadcast(&j->wake);
        pthread_mutex_unlock(&j->lock);
        pthread_join(j->thread, NULL);
        for (size_t i = 0; i < j->late_count; i++) {
            late *l = &j->lates[i];
            if (l->state == LATE_WAITING) {
                log_gave_up(j, l, "the stream ended first");
            } else if (l->state == LATE_READY) {
                tsr_log(TSR_LOG_WARN, "%s: late server %s connected after the last frame boundary: not admitted",
                        j->name, l->address);
                tsr_net_conn_close(l->conn);
            }
        }
    }
    tsr_unpacker_destroy(j->unpacker);
    tsr_dlist_destroy(j->lists);
    tsr_state_tracker_destroy(j->tracker); /* and its context */
    pthread_cond_destroy(&j->wake);
    pthread_mutex_destroy(&j->lock);
    free(j->textures.v);
    free(j->buffers.v);
    free(j->windows);
    free(j->lates);
    free(j);
}

void tsr_node_join_observe(tsr_node_join *j, const uint8_t *buf, size_t size)
{
    if (j->broken)
        return;
    tsr_error err = {0};
    int rc = tsr_unpacker_run(j->unpacker, buf, size, &err);
    if (rc != TSR_OK && rc != TSR_UNPACK_YIELDED) {
        j->broken = 1;
        tsr_log(TSR_LOG_ERROR, "%s: late joiners: cannot follow the stream (%s); no server will join", j->name,
                err.message);
    }
}

int tsr_node_join_ready(tsr_node_join *j)
{
    return atomic_load_explicit(&j->ready, memory_order_acquire) != 0 && !j->broken && !tsr_dlist_recording(j->lists);
}

tsr_net_conn *tsr_node_join_take(tsr_node_join *j, const char **address)
{
    tsr_net_conn *conn = NULL;
    pthread_mutex_lock(&j->lock);
    for (size_t i = 0; i < j->late_count && !conn; i++) {
        late *l = &j->lates[i];
        if (l->state == LATE_READY) {
            conn = l->conn;
            l->conn = NULL;
            l->state = LATE_TAKEN;
            atomic_fetch_sub(&j->ready, 1);
            *address = l->address;
        }
    }
    pthread_mutex_unlock(&j->lock);
    return conn;
}

int tsr_node_join_pending(tsr_node_join *j)
{
    int pending = 0;
    pthread_mutex_lock(&j->lock);
    for (size_t i = 0; i < j->late_count; i++)
        pending |= j->lates[i].state == LATE_WAITING || j->lates[i].state == LATE_READY;
    pthread_mutex_unlock(&j->lock);
    return pending && !j->broken;
}

/* --- catching up ----------------------------------------------------------------- */
typedef struct joiner_sink {
    tsr_net_conn *conn;
    uint64_t bytes;
} joiner_sink;

static int joiner_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    joiner_sink *s = ctx;
    s->bytes += size;
    return tsr_net_send(s->conn, TSR_NODE_MSG_BUFFER, buf, size, TSR_NET_WAIT_FOREVER, err);
}

static int joiner_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    (void)ctx, (void)data, (void)size;
    return tsr_error_set(err, TSR_ESTATE, "catch-up stream: request %u has no reply", id);
}

static int tex_index(GLenum target)
{
    switch (target) {
    case GL_TEXTURE_1D: return TSR_TEX_1D;
    case GL_TEXTURE_2D: return TSR_TEX_2D;
    case GL_TEXTURE_3D: return TSR_TEX_3D;
    case GL_TEXTURE_CUBE_MAP: return TSR_TEX_CUBE;
    default: return -1;
    }
}

/* Step 3 of join.h: each object bound in turn and diffed, then the
 * application's bindings put back (the final diff restores them on the
 * joiner too). */
static void send_objects(tsr_node_join *j, tsr_state_shadow *shadow, const tsr_dispatch *out, tsr_node_join_report *r)
{
    const tsr_state_values *v = tsr_state_values_of(j->ctx);
    for (size_t i = 0; i < j->textures.n; i++) {
        const named *t = &j->textures.v[i];
        int ti = tex_index(t->target);
        if (ti < 0)
            continue;
        GLuint saved = v->image[v->active_texture].binding[ti];
        tsr_call_BindTexture(&j->st, t->target, t->name);
        r->state_calls += tsr_state_diff(j->ctx, shadow, out, NULL);
        tsr_call_BindTexture(&j->st, t->target, saved);
        r->textures++;
    }
    for (size_t i = 0; i < j->buffers.n; i++) {
        const named *b = &j->buffers.v[i];
        GLuint saved;
        if (b->target == GL_ARRAY_BUFFER)
            saved = v->array_buffer;
        else if (b->target == GL_ELEMENT_ARRAY_BUFFER)
            saved = v->element_buffer;
        else
            continue;
        tsr_call_BindBuffer(&j->st, b->target, b->name);
        r->state_calls += tsr_state_diff(j->ctx, shadow, out, NULL);
        tsr_call_BindBuffer(&j->st, b->target, saved);
        r->buffers++;
    }
}

int tsr_node_join_catch_up(tsr_node_join *j, tsr_net_conn *conn, tsr_node_join_report *report, tsr_error *err)
{
    tsr_node_join_report r = {0};
    joiner_sink js = {.conn = conn};
    tsr_pack_sink sink = {.flush = joiner_flush, .reply = joiner_reply, .ctx = &js};
    tsr_packer *p = tsr_packer_create(j->buffer_size, &sink, err);
    if (!p)
        return err->code;
    tsr_dispatch out;
    tsr_packer_fill_dispatch(p, &out);
    /* 1. windows and contexts */
    for (size_t i = 0; i < j->window_count; i++) {
        tsr_call_WindowCreateTSR(&out, j->windows[i].id, j->windows[i].width, j->windows[i].height);
        if (j->windows[i].buffers)
            tsr_call_WindowBuffersTSR(&out, j->windows[i].id, j->windows[i].buffers);
        if (j->windows[i].samples)
            tsr_call_WindowSamplesTSR(&out, j->windows[i].id, j->windows[i].samples);
    }
    r.windows = (unsigned)j->window_count;
    for (size_t i = 0; i < j->context_count; i++)
        tsr_call_ContextCreateTSR(&out, j->contexts[i]);
    if (j->has_current)
        tsr_call_MakeCurrentTSR(&out, j->current_window, j->current_context);
    /* 2. display lists */
    long lists = tsr_dlist_define_all(j->lists, &out, err);
    tsr_state_shadow *shadow = NULL;
    if (lists >= 0) {
        r.lists = (unsigned)lists;
        shadow = tsr_state_shadow_create(j->tracker, err);
    }
    if (shadow) {
        /* 3. objects, 4. state */
        send_objects(j, shadow, &out, &r);
        r.state_calls += tsr_state_send_glsl_all(j->ctx, shadow, &out);
        tsr_state_diff_stats stats;
        r.state_calls += tsr_state_diff(j->ctx, shadow, &out, &stats);
        tsr_state_shadow_destroy(shadow);
        if (tsr_packer_flush(p) != TSR_OK || tsr_packer_error(p)->code)
            *err = *tsr_packer_error(p);
    }
    int rc = err->code;
    tsr_packer_destroy(p);
    r.bytes = js.bytes;
    if (report)
        *report = r;
    return rc;
}
