/* client/client.c — the stream client of tessera/dev/protocol.h (client.h): one
 * packer, one netlib instance, one connection per server; every flushed
 * buffer copied once and shared by all connections; replies from the first
 * live server; FINISH at the end; statistics to TESSERA_STATS_FILE. */
#include "tessera/dev/util.h"
#include "tessera/dev/client.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "join.h"
#include "tessera/dev/net.h"
#include "tessera/dev/pack.h"
#include "tessera/dev/protocol.h"
#include "tessera/log.h"
#include "tessera/dev/wire.h"

/* client.h cannot include pack.h (it is for SPUs too), so the option's
 * minimum there is a literal; keep them equal. */
_Static_assert(TSR_PACK_MIN_BUFFER == 256, "TSR_NODE_CLIENT_OPTION_SPECS buffer_size minimum");

/* One flushed buffer, shared by every connection it is sent on; the last
 * connection to release it returns it to its client's pool. Release runs
 * on netlib's I/O thread (or inside a netlib call), hence the atomic count
 * and the pool's own lock. */
typedef struct shared_buffer {
    atomic_uint refs;
    struct buffer_pool *pool;
    size_t capacity;
    struct shared_buffer *next_free;
    _Alignas(16) uint8_t data[];
} shared_buffer;

/* Buffers of buffer_size bytes, reused: a fresh megabyte comes from mmap
 * and costs a page fault per 4 KiB on first touch, which made the copy
 * into it dominate the sending thread. At most POOL_MAX are kept (the
 * credits bound how many are in flight anyway). */
#define POOL_MAX 16
typedef struct buffer_pool {
    pthread_mutex_t lock;
    shared_buffer *free_list;
    unsigned count;
    size_t capacity;
} buffer_pool;

typedef struct server {
    char address[TSR_NET_ADDRESS_MAX];
    tsr_net_conn *conn;
    int failed;
    tsr_net_stats final; /* the connection's counters when it was closed */
    int closed;
} server;

struct tsr_stream_client {
    char spu[32];
    char name[96];
    int exit_on_error;
    tsr_net *net;
    server *servers;
    size_t count;
    size_t live; /* servers not failed */
    tsr_packer *packer;
    tsr_net_msg reply; /* the reply handed to the packer, held until the next sink call */
    int holding_reply;
    size_t reply_server;             /* whose reply it is */
    tsr_entry swap;                  /* the packer's SwapBuffersTSR (frames are counted in front of it) */
    tsr_entry barrier, sem_p, sem_v; /* the packer's: flushed after (client_BarrierExecTSR) */
    buffer_pool pool;                /* flushed buffers' copies; outlives the I/O thread */
    uint64_t frames, buffers, stream_bytes;
    tsr_error first_error;
    tsr_node_join *join;                     /* late servers still expected (join.h); NULL: none, nothing tracked */
    struct server_sink *sinks;               /* per-server sink contexts (tsr_stream_client_server_sink) */
    int connected;                           /* every server reached: statistics are written at the end */
    void (*stats_extra)(void *ctx, FILE *f); /* the sending SPU's own members */
    void *stats_extra_ctx;
    tsr_stream_client_cost_fn cost_fn; /* TSR_NODE_MSG_COST reports go here */
    void *cost_ctx;
};

/* Context of a sink bound to one server. */
typedef struct server_sink {
    tsr_stream_client *client;
    size_t index;
} server_sink;

static void shared_release(void *data, void *ctx)
{
    (void)data;
    shared_buffer *b = ctx;
    if (atomic_fetch_sub_explicit(&b->refs, 1, memory_order_acq_rel) != 1)
        return;
    buffer_pool *pool = b->pool;
    pthread_mutex_lock(&pool->lock);
    if (b->capacity == pool->capacity && pool->count < POOL_MAX) {
        b->next_free = pool->free_list;
        pool->free_list = b;
        pool->count++;
        b = NULL;
    }
    pthread_mutex_unlock(&pool->lock);
    free(b);
}

/* A buffer of at least `size` bytes with one reference (the caller's). */
static shared_buffer *shared_get(buffer_pool *pool, size_t size)
{
    shared_buffer *b = NULL;
    if (size <= pool->capacity) {
        pthread_mutex_lock(&pool->lock);
        b = pool->free_list;
        if (b) {
            pool->free_list = b->next_free;
            pool->count--;
        }
        pthread_mutex_unlock(&pool->lock);
    }
    if (!b) {
        size_t capacity = size <= pool->capacity ? pool->capacity : size;
        b = malloc(sizeof *b + capacity);
        if (!b)
            return NULL;
        b->pool = pool;
        b->capacity = capacity;
    }
    atomic_init(&b->refs, 1);
    return b;
}

static void pool_drain(buffer_pool *pool)
{
    while (pool->free_list) {
        shared_buffer *b = pool->free_list;
        pool->free_list = b->next_free;
        free(b);
    }
    pool->count = 0;
}

void tsr_stream_client_config_from_options(tsr_stream_client_config *config, const tsr_options *options)
{
    config->token = tsr_options_string(options, TSR_NODE_CLIENT_TOKEN_OPTION);
    config->buffer_size = (size_t)tsr_options_int(options, "buffer_size");
    config->timeout_ms = (uint32_t)tsr_options_int(options, "timeout_ms");
    config->exit_on_error = !strcmp(tsr_options_string(options, "on_error"), "exit");
}

static void release_reply(tsr_stream_client *c)
{
    if (c->holding_reply) {
        tsr_net_msg_release(&c->reply);
        c->holding_reply = 0;
    }
}

/* "the server dropped this client: REASON" from a TSR_NODE_MSG_ERROR; the
 * reason is the server's text, so its control bytes are escaped. */
static void dropped_reason(tsr_error *why, const tsr_net_msg *m)
{
    char reason[400];
    tsr_text_sanitize(reason, sizeof reason, m->data, (size_t)(m->len < 400 ? m->len : 400));
    tsr_error_set(why, TSR_EPROTO, "the server dropped this client: %s", reason);
}

/* When a server dropped us it said why (TSR_NODE_MSG_ERROR) before
 * closing; that reason beats netlib's "peer closed". Takes queued messages
 * without waiting; returns 1 and fills `why` when one was the reason. */
static int server_reason(server *s, tsr_error *why)
{
    tsr_net_msg m;
    tsr_error ignored = {0};
    int found = 0;
    while (!found && tsr_net_recv(s->conn, &m, 0, &ignored) == 1) {
        if (m.kind == TSR_NODE_MSG_ERROR) {
            dropped_reason(why, &m);
            found = 1;
        }
        tsr_net_msg_release(&m);
    }
    return found;
}

static void write_stats_if_asked(tsr_stream_client *c)
{
    const char *path = getenv(TSR_NODE_CLIENT_STATS_ENV);
    if (!path || !path[0])
        return;
    tsr_error err = {0};
    if (tsr_stream_client_write_stats(c, path, &err) != TSR_OK)
        tsr_log(TSR_LOG_ERROR, "%s: %s", c->name, err.message);
}

void tsr_stream_client_exit(void)
{
    fflush(NULL);
    _exit(TSR_NODE_CLIENT_EXIT_STATUS);
}

/* Server `i` is unusable: one line naming it, then the on_error policy.
 * Returns the error code (fills `err`). */
static int server_failed(tsr_stream_client *c, size_t i, tsr_error *err, const char *what, const tsr_error *cause)
{
    server *s = &c->servers[i];
    if (!s->failed) {
        s->failed = 1;
        c->live--;
    }
    tsr_error reason = {0};
    if (cause->code != TSR_EPROTO && server_reason(s, &reason))
        cause = &reason;
    tsr_error_set(err, cause->code ? cause->code : TSR_EIO, "%s: server %s: %s: %s", c->name, s->address, what,
                  cause->message);
    tsr_log(TSR_LOG_ERROR, "%s", err->message);
    if (!c->first_error.code)
        c->first_error = *err;
    if (c->exit_on_error) {
        tsr_log(TSR_LOG_ERROR, "%s: ending the application (on_error=exit)", c->name);
        write_stats_if_asked(c);
        tsr_stream_client_exit();
    }
    if (c->live)
        tsr_log(TSR_LOG_ERROR, "%s: going on without server %s (on_error=drop)", c->name, s->address);
    else
        tsr_log(TSR_LOG_ERROR, "%s: no server left: dropping every further call (on_error=drop)", c->name);
    return err->code;
}

static int no_server_left(tsr_stream_client *c, tsr_error *err)
{
    return tsr_error_set(err, TSR_ESTATE, "%s: every server failed (first: %s)", c->name, c->first_error.message);
}

/* The packer's sink: one copy of the buffer, sent on every live connection. */
static int client_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    tsr_stream_client *c = ctx;
    release_reply(c);
    if (!c->live)
        return no_server_left(c, err);
    if (c->count == 1) {
        /* One server: tsr_net_send writes straight from the packer's buffer
         * when the connection's write side is idle, and copies it (into a
         * reused buffer) only when it must wait (tessera/dev/net.h SENDING). */
        c->buffers++;
        if (c->join)
            tsr_node_join_observe(c->join, buf, size);
        c->stream_bytes += size;
        tsr_error cause = {0}, ignored = {0};
        if (tsr_net_send(c->servers[0].conn, TSR_NODE_MSG_BUFFER, buf, size, TSR_NET_WAIT_FOREVER, &cause) != TSR_OK)
            server_failed(c, 0, &ignored, "sending a buffer failed", &cause);
        return c->live ? TSR_OK : no_server_left(c, err);
    }
    /* Its one reference is ours, dropped below: no connection can free it
     * while the loop still hands it out. */
    shared_buffer *b = shared_get(&c->pool, size);
    if (!b)
        return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory for a %zu-byte buffer", c->name, size);
    memcpy(b->data, buf, size);
    c->buffers++; /* counted before sending: a failure that ends the process writes them */
    if (c->join)
        tsr_node_join_observe(c->join, buf, size); /* the model follows what the servers get */
    c->stream_bytes += size;
    for (size_t i = 0; i < c->count; i++) {
        server *s = &c->servers[i];
        if (s->failed)
            continue;
        atomic_fetch_add_explicit(&b->refs, 1, memory_order_relaxed);
        tsr_error cause = {0};
        if (tsr_net_send_owned(s->conn, TSR_NODE_MSG_BUFFER, b->data, size, shared_release, b, TSR_NET_WAIT_FOREVER,
                               &cause) != TSR_OK) {
            shared_release(b->data, b); /* not taken */
            tsr_error ignored = {0};
            server_failed(c, i, &ignored, "sending a buffer failed", &cause);
        }
    }
    shared_release(b->data, b);
    return c->live ? TSR_OK : no_server_left(c, err);
}

int tsr_stream_client_send(tsr_stream_client *c, const size_t *targets, size_t n, const uint8_t *buf, size_t size,
                           tsr_error *err)
{
    release_reply(c);
    if (!c->live)
        return no_server_left(c, err);
    shared_buffer *b = shared_get(&c->pool, size);
    if (!b)
        return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory for a %zu-byte buffer", c->name, size);
    memcpy(b->data, buf, size);
    c->buffers++;
    c->stream_bytes += size;
    for (size_t k = 0; k < n; k++) {
        size_t i = targets[k];
        if (i >= c->count || c->servers[i].failed)
            continue;
        atomic_fetch_add_explicit(&b->refs, 1, memory_order_relaxed);
        tsr_error cause = {0};
        if (tsr_net_send_owned(c->servers[i].conn, TSR_NODE_MSG_BUFFER, b->data, size, shared_release, b,
                               TSR_NET_WAIT_FOREVER, &cause) != TSR_OK) {
            shared_release(b->data, b);
            tsr_error ignored = {0};
            server_failed(c, i, &ignored, "sending a buffer failed", &cause);
        }
    }
    shared_release(b->data, b);
    return c->live ? TSR_OK : no_server_left(c, err);
}

static int server_sink_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    server_sink *s = ctx;
    return tsr_stream_client_send(s->client, &s->index, 1, buf, size, err);
}

static int take_reply(tsr_stream_client *c, size_t i, uint32_t id, tsr_net_msg *m);

static int server_sink_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    server_sink *s = ctx;
    tsr_stream_client *c = s->client;
    release_reply(c);
    tsr_net_msg m;
    if (c->servers[s->index].failed || !take_reply(c, s->index, id, &m))
        return tsr_error_set(err, TSR_EIO, "%s: server %s failed before answering request %u", c->name,
                             c->servers[s->index].address, id);
    c->reply = m;
    c->holding_reply = 1;
    c->reply_server = s->index;
    *data = (const uint8_t *)c->reply.data + TSR_NODE_REPLY_HEADER;
    *size = (size_t)(c->reply.len - TSR_NODE_REPLY_HEADER);
    return TSR_OK;
}

/* The packer could not decode the reply it was handed (truncated, an item
 * of the wrong size): the server that sent it is failing, and the call it
 * answered returned zeros. on_error decides: exit, or go on without it. */
static void reply_failed(tsr_stream_client *c, const tsr_error *why)
{
    if (!c->holding_reply || c->servers[c->reply_server].failed)
        return;
    tsr_error ignored = {0};
    server_failed(c, c->reply_server, &ignored, "bad reply", why);
}

static void client_reply_failed(void *ctx, uint32_t id, const tsr_error *why)
{
    (void)id;
    reply_failed(ctx, why);
}

static void server_sink_reply_failed(void *ctx, uint32_t id, const tsr_error *why)
{
    (void)id;
    reply_failed(((server_sink *)ctx)->client, why);
}

void tsr_stream_client_server_sink(tsr_stream_client *c, size_t index, struct tsr_pack_sink *sink)
{
    *sink = (tsr_pack_sink){.flush = server_sink_flush,
                            .reply = server_sink_reply,
                            .ctx = &c->sinks[index],
                            .reply_failed = server_sink_reply_failed};
}

void tsr_stream_client_set_stats_extra(tsr_stream_client *c, void (*fn)(void *ctx, FILE *f), void *ctx)
{
    c->stats_extra = fn;
    c->stats_extra_ctx = ctx;
}

void tsr_stream_client_count_frame(tsr_stream_client *c) { c->frames++; }

int tsr_stream_client_server_failed(const tsr_stream_client *c, size_t index)
{
    return index >= c->count || c->servers[index].failed;
}

void tsr_stream_client_set_cost_sink(tsr_stream_client *c, tsr_stream_client_cost_fn fn, void *ctx)
{
    c->cost_fn = fn;
    c->cost_ctx = ctx;
}

/* A TSR_NODE_MSG_COST from server i goes to the cost sink and is released;
 * returns 1 when m was one. */
static int took_cost(tsr_stream_client *c, size_t i, tsr_net_msg *m)
{
    if (m->kind != TSR_NODE_MSG_COST)
        return 0;
    if (c->cost_fn && m->len >= TSR_NODE_COST_BYTES) {
        const uint8_t *d = m->data;
        tsr_frame_cost cost = {.frame = tsr_wire_get_u32(d),
                               .faults = tsr_wire_get_u32(d + 4),
                               .seconds = tsr_wire_get_f64(d + 8),
                               .fault_seconds = tsr_wire_get_f64(d + 16)};
        c->cost_fn(c->cost_ctx, i, &cost);
    }
    tsr_net_msg_release(m);
    return 1;
}

/* The next message of server s that is not a cost report. */
static int recv_not_cost(tsr_stream_client *c, size_t i, tsr_net_msg *m, int timeout_ms, tsr_error *cause)
{
    for (;;) {
        int got = tsr_net_recv(c->servers[i].conn, m, timeout_ms, cause);
        if (got != 1 || !took_cost(c, i, m))
            return got;
    }
}

void tsr_stream_client_take_costs(tsr_stream_client *c)
{
    for (size_t i = 0; i < c->count; i++) {
        tsr_net_msg m;
        tsr_error cause = {0}, ignored = {0};
        if (c->servers[i].failed || !c->servers[i].conn)
            continue;
        int got = recv_not_cost(c, i, &m, 0, &cause);
        if (got != 1)
            continue; /* nothing queued (a closed or failed connection shows at the next send) */
        if (m.kind == TSR_NODE_MSG_ERROR)
            dropped_reason(&cause, &m);
        else
            tsr_error_set(&cause, TSR_EPROTO, "unexpected message of kind 0x%02x, %llu bytes, between frames", m.kind,
                          (unsigned long long)m.len);
        tsr_net_msg_release(&m);
        server_failed(c, i, &ignored, "between frames", &cause);
    }
}

/* Takes server i's answer to request `id`: 1 with *m filled when it is the
 * reply, else reports the failure (0). */
static int take_reply(tsr_stream_client *c, size_t i, uint32_t id, tsr_net_msg *m)
{
    tsr_error cause = {0}, ignored = {0};
    int got = recv_not_cost(c, i, m, TSR_NET_WAIT_FOREVER, &cause);
    if (got == 0)
        tsr_error_set(&cause, TSR_EIO, "closed the connection instead of answering request %u", id);
    if (got <= 0) {
        server_failed(c, i, &ignored, "waiting for a reply", &cause);
        return 0;
    }
    if (m->kind == TSR_NODE_MSG_ERROR) {
        dropped_reason(&cause, m);
    } else if (m->kind != TSR_NODE_MSG_REPLY || m->len < TSR_NODE_REPLY_HEADER || tsr_wire_get_u32(m->data) != id) {
        tsr_error_set(&cause, TSR_EPROTO,
                      "expected the reply to request %u, got a message of kind 0x%02x, %llu bytes%s", id, m->kind,
                      (unsigned long long)m->len,
                      m->kind == TSR_NODE_MSG_REPLY && m->len >= TSR_NODE_REPLY_HEADER ? " (another request id)" : "");
    } else {
        return 1;
    }
    tsr_net_msg_release(m);
    server_failed(c, i, &ignored, "waiting for a reply", &cause);
    return 0;
}

/* Requests are answered in order, so each server's next message is its
 * reply to the request just flushed. The first live server's is kept; the
 * others' are checked and dropped (client.h says why). */
static int client_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    tsr_stream_client *c = ctx;
    release_reply(c);
    for (size_t i = 0; i < c->count; i++) {
        tsr_net_msg m;
        if (c->servers[i].failed || !take_reply(c, i, id, &m))
            continue;
        if (c->holding_reply) {
            tsr_net_msg_release(&m);
        } else {
            c->reply = m;
            c->holding_reply = 1;
            c->reply_server = i;
        }
    }
    if (!c->holding_reply)
        return no_server_left(c, err);
    *data = (const uint8_t *)c->reply.data + TSR_NODE_REPLY_HEADER;
    *size = (size_t)(c->reply.len - TSR_NODE_REPLY_HEADER);
    return TSR_OK;
}

/* A late server that caught up becomes server `count` (the arrays grow by
 * one; nothing outside keeps pointers into them while a packer client
 * runs, and late joiners exist only for those). */
static int add_server(tsr_stream_client *c, const char *address, tsr_net_conn *conn)
{
    server *v = realloc(c->servers, (c->count + 1) * sizeof *v);
    if (!v)
        return -1;
    c->servers = v;
    if (c->sinks) {
        server_sink *k = realloc(c->sinks, (c->count + 1) * sizeof *k);
        if (!k)
            return -1;
        c->sinks = k;
        c->sinks[c->count] = (server_sink){.client = c, .index = c->count};
    }
    memset(&v[c->count], 0, sizeof v[c->count]);
    snprintf(v[c->count].address, sizeof v[c->count].address, "%s", address);
    v[c->count].conn = conn;
    c->count++;
    c->live++;
    return 0;
}

/* At a frame boundary (the swap is packed): flush, so the model has seen
 * the whole frame and the joiner starts with the next one, then catch up
 * every connected late server and add it to the broadcast. */
static void admit_late_servers(tsr_stream_client *c)
{
    if (!tsr_node_join_ready(c->join) || tsr_packer_flush(c->packer) != TSR_OK)
        return;
    const char *address;
    tsr_net_conn *conn;
    while ((conn = tsr_node_join_take(c->join, &address))) {
        tsr_node_join_report r;
        tsr_error err = {0};
        if (tsr_node_join_catch_up(c->join, conn, &r, &err) != TSR_OK || add_server(c, address, conn) != 0) {
            tsr_log(TSR_LOG_ERROR, "%s: late server %s: catching up failed: %s", c->name, address,
                    err.code ? err.message : "out of memory");
            tsr_net_conn_close(conn);
            continue;
        }
        tsr_log(TSR_LOG_INFO,
                "%s: server %s joined at frame %llu (catch-up: %llu bytes, %u window%s, %u display list%s, "
                "%u texture%s, %u buffer%s, %u state call%s)",
                c->name, address, (unsigned long long)c->frames, (unsigned long long)r.bytes, r.windows,
                r.windows == 1 ? "" : "s", r.lists, r.lists == 1 ? "" : "s", r.textures, r.textures == 1 ? "" : "s",
                r.buffers, r.buffers == 1 ? "" : "s", r.state_calls, r.state_calls == 1 ? "" : "s");
    }
    if (!tsr_node_join_pending(c->join)) {
        tsr_node_join_destroy(c->join); /* every late server came: stop tracking */
        c->join = NULL;
    }
}

/* A server holds its other clients at a barrier or semaphore until this
 * one's exec / P / V arrives: sent now, not when the buffer fills. A
 * client that never swaps and sends little per frame (a readback tile
 * server with small tiles) would otherwise leave it unsent for ever. */
static void client_BarrierExecTSR(void *self, GLuint name)
{
    tsr_stream_client *c = self;
    ((tsr_fn_BarrierExecTSR)c->barrier.fn)(c->barrier.self, name);
    tsr_packer_flush(c->packer);
}

static void client_SemaphorePTSR(void *self, GLuint name)
{
    tsr_stream_client *c = self;
    ((tsr_fn_SemaphorePTSR)c->sem_p.fn)(c->sem_p.self, name);
    tsr_packer_flush(c->packer);
}

static void client_SemaphoreVTSR(void *self, GLuint name)
{
    tsr_stream_client *c = self;
    ((tsr_fn_SemaphoreVTSR)c->sem_v.fn)(c->sem_v.self, name);
    tsr_packer_flush(c->packer);
}

static void client_SwapBuffersTSR(void *self, GLint window, GLbitfield flags)
{
    tsr_stream_client *c = self;
    c->frames++;
    ((tsr_fn_SwapBuffersTSR)c->swap.fn)(c->swap.self, window, flags);
    if (c->join)
        admit_late_servers(c);
}

/* Sends what is left and FINISH to every live server, then waits until
 * each confirmed that every buffer ran (or says why not). */
static void finish_stream(tsr_stream_client *c)
{
    if ((c->packer && tsr_packer_flush(c->packer) != TSR_OK) || !c->live)
        return;
    release_reply(c);
    tsr_error ignored = {0};
    for (size_t i = 0; i < c->count; i++) {
        tsr_error cause = {0};
        if (!c->servers[i].failed &&
            tsr_net_send(c->servers[i].conn, TSR_NODE_MSG_FINISH, "", 0, TSR_NET_WAIT_FOREVER, &cause) != TSR_OK)
            server_failed(c, i, &ignored, "finishing the stream", &cause);
    }
    for (size_t i = 0; i < c->count; i++) {
        server *s = &c->servers[i];
        if (s->failed)
            continue;
        tsr_error cause = {0};
        tsr_net_msg m;
        int got = recv_not_cost(c, i, &m, TSR_NET_WAIT_FOREVER, &cause);
        if (got == 1 && m.kind == TSR_NODE_MSG_FINISH) {
            tsr_net_msg_release(&m);
            continue;
        }
        if (got == 1) {
            if (m.kind == TSR_NODE_MSG_ERROR)
                dropped_reason(&cause, &m);
            else
                tsr_error_set(&cause, TSR_EPROTO,
                              "expected the end of stream confirmation, got a message of kind 0x%02x", m.kind);
            tsr_net_msg_release(&m);
        } else if (got == 0) {
            tsr_error_set(&cause, TSR_EIO, "closed the connection before confirming the end of stream");
        }
        server_failed(c, i, &ignored, "finishing the stream", &cause);
    }
}

void tsr_stream_client_destroy(tsr_stream_client *c)
{
    if (!c)
        return;
    tsr_node_join_destroy(c->join); /* before the connections: it may hold one */
    c->join = NULL;
    if (c->connected && c->live)
        finish_stream(c);
    release_reply(c);
    for (size_t i = 0; i < c->count; i++) {
        server *s = &c->servers[i];
        if (!s->conn)
            continue;
        tsr_net_conn_stats(s->conn, &s->final);
        s->closed = 1;
        tsr_net_conn_close(s->conn); /* BYE: the server ends this client cleanly */
        s->conn = NULL;
    }
    tsr_net_destroy(c->net); /* waits (bounded) until everything was written */
    c->net = NULL;
    pool_drain(&c->pool); /* every buffer came back: the I/O thread is gone */
    pthread_mutex_destroy(&c->pool.lock);
    if (c->connected)
        write_stats_if_asked(c); /* only for a client that was created */
    tsr_packer_destroy(c->packer);
    free(c->sinks);
    free(c->servers);
    free(c);
}

tsr_stream_client *tsr_stream_client_connect(const tsr_stream_client_config *config, tsr_error *err)
{
    const char *name = config->name ? config->name : "client";
    tsr_stream_client *c = calloc(1, sizeof *c);
    if (c)
        c->servers = calloc(config->server_count ? config->server_count : 1, sizeof *c->servers);
    if (!c || !c->servers) {
        if (c)
            free(c);
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", name);
        return NULL;
    }
    pthread_mutex_init(&c->pool.lock, NULL);
    c->pool.capacity = config->buffer_size;
    snprintf(c->spu, sizeof c->spu, "%s", config->spu ? config->spu : "client");
    snprintf(c->name, sizeof c->name, "%s", name);
    c->exit_on_error = config->exit_on_error;
    c->count = config->server_count;
    if (!c->count) {
        tsr_error_set(err, TSR_EINVAL, "%s: no server given", c->name);
        goto fail;
    }
    for (size_t i = 0; i < c->count; i++) {
        const char *address = config->servers[i];
        if (!address || !address[0]) {
            tsr_error_set(err, TSR_EINVAL, "%s: server %zu of %zu is empty", c->name, i + 1, c->count);
            goto fail;
        }
        if (strlen(address) >= sizeof c->servers[i].address) {
            tsr_error_set(err, TSR_EINVAL, "%s: server address %.60s...: longer than %d bytes", c->name, address,
                          TSR_NET_ADDRESS_MAX - 1);
            goto fail;
        }
        for (size_t j = 0; j < i; j++)
            if (!strcmp(c->servers[j].address, address)) {
                tsr_error_set(err, TSR_EINVAL, "%s: server %s is listed twice", c->name, address);
                goto fail;
            }
        snprintf(c->servers[i].address, sizeof c->servers[i].address, "%s", address);
    }

    char node_name[TSR_NET_NAME_MAX + 1];
    snprintf(node_name, sizeof node_name, "%.40s-pid%ld", c->name, (long)getpid());
    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.node_name = node_name;
    cfg.token = config->token;
    cfg.idle_timeout_ms = config->timeout_ms;
    if (config->timeout_ms) {
        cfg.connect_timeout_ms = config->timeout_ms;
        cfg.handshake_timeout_ms = config->timeout_ms;
        cfg.close_timeout_ms = config->timeout_ms;
    }
    tsr_error cause = {0};
    c->net = tsr_net_create(&cfg, &cause);
    if (!c->net) {
        tsr_error_set(err, cause.code, "%s: %s", c->name, cause.message);
        goto fail;
    }
    for (size_t i = 0; i < c->count; i++) {
        server *s = &c->servers[i];
        s->conn = tsr_net_connect(c->net, s->address, &cause);
        if (!s->conn) {
            tsr_error_set(err, cause.code ? cause.code : TSR_EIO, "%s: cannot reach server %s: %s", c->name, s->address,
                          cause.message);
            goto fail;
        }
    }
    c->sinks = calloc(c->count, sizeof *c->sinks);
    if (!c->sinks) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", c->name);
        goto fail;
    }
    for (size_t i = 0; i < c->count; i++)
        c->sinks[i] = (server_sink){.client = c, .index = i};
    c->live = c->count;
    c->connected = 1;
    return c;
fail:
    c->live = 0; /* nothing was sent: no FINISH */
    tsr_stream_client_destroy(c);
    return NULL;
}

/* The late servers' model and connecting thread (join.h). */
static int start_late(tsr_stream_client *c, const tsr_stream_client_config *config, tsr_error *err)
{
    for (size_t i = 0; i < config->late_count; i++) {
        const char *a = config->late_servers[i];
        if (!a || !a[0] || strlen(a) >= TSR_NET_ADDRESS_MAX)
            return tsr_error_set(err, TSR_EINVAL, "%s: late server %zu of %zu is %s", c->name, i + 1,
                                 config->late_count, a && a[0] ? "too long" : "empty");
        for (size_t k = 0; k < c->count + i; k++)
            if (!strcmp(k < c->count ? c->servers[k].address : config->late_servers[k - c->count], a))
                return tsr_error_set(err, TSR_EINVAL, "%s: server %s is listed twice", c->name, a);
    }
    tsr_node_join_config jc = {.name = c->name,
                               .net = c->net,
                               .addresses = config->late_servers,
                               .count = config->late_count,
                               .retry_ms = config->late_retry_ms ? config->late_retry_ms : 200,
                               .give_up_ms = config->late_give_up_ms,
                               .buffer_size = config->buffer_size};
    c->join = tsr_node_join_create(&jc, err);
    return c->join ? TSR_OK : err->code;
}

tsr_stream_client *tsr_stream_client_create(const tsr_stream_client_config *config, tsr_dispatch *table, tsr_error *err)
{
    tsr_stream_client *c = tsr_stream_client_connect(config, err);
    if (!c)
        return NULL;
    tsr_pack_sink sink = {.flush = client_flush, .reply = client_reply, .ctx = c, .reply_failed = client_reply_failed};
    c->packer = tsr_packer_create(config->buffer_size, &sink, err);
    if (!c->packer) {
        c->live = 0;
        c->connected = 0;
        tsr_stream_client_destroy(c);
        return NULL;
    }
    tsr_packer_fill_dispatch(c->packer, table);
    c->swap = table->SwapBuffersTSR;
    tsr_set_SwapBuffersTSR(table, client_SwapBuffersTSR, c);
    c->barrier = table->BarrierExecTSR;
    c->sem_p = table->SemaphorePTSR;
    c->sem_v = table->SemaphoreVTSR;
    tsr_set_BarrierExecTSR(table, client_BarrierExecTSR, c);
    tsr_set_SemaphorePTSR(table, client_SemaphorePTSR, c);
    tsr_set_SemaphoreVTSR(table, client_SemaphoreVTSR, c);
    if (config->late_count && start_late(c, config, err) != TSR_OK) {
        tsr_stream_client_destroy(c);
        return NULL;
    }
    return c;
}

void tsr_stream_client_get_stats(tsr_stream_client *c, tsr_stream_client_stats *out,
                                 tsr_stream_client_server_stats *servers, size_t capacity)
{
    memset(out, 0, sizeof *out);
    out->stream_bytes = c->stream_bytes;
    out->buffers = c->buffers;
    out->frames = c->frames;
    out->server_count = c->count;
    for (size_t i = 0; i < c->count; i++) {
        server *s = &c->servers[i];
        tsr_net_stats st = s->final;
        if (!s->closed && s->conn)
            tsr_net_conn_stats(s->conn, &st);
        double blocked = (double)st.blocked_on_credits_ns * 1e-9;
        out->bytes_out += st.bytes_sent;
        out->blocked_seconds += blocked;
        if (servers && i < capacity)
            servers[i] = (tsr_stream_client_server_stats){.address = s->address,
                                                          .bytes_out = st.bytes_sent,
                                                          .messages = st.messages_sent,
                                                          .blocked_seconds = blocked,
                                                          .failed = s->failed};
    }
}

int tsr_stream_client_write_stats(tsr_stream_client *c, const char *path, tsr_error *err)
{
    tsr_stream_client_stats st;
    tsr_stream_client_server_stats *per = calloc(c->count, sizeof *per);
    if (!per)
        return tsr_error_set(err, TSR_ENOMEM, "out of memory writing statistics");
    tsr_stream_client_get_stats(c, &st, per, c->count);
    char tmp[4096];
    FILE *f = NULL;
    if ((size_t)snprintf(tmp, sizeof tmp, "%s.tmp%ld", path, (long)getpid()) < sizeof tmp)
        f = fopen(tmp, "w");
    if (!f) {
        free(per);
        return tsr_error_set(err, TSR_EIO, "cannot write statistics file %s", path);
    }
    fprintf(f, "{\"spu\":");
    tsr_json_string(f, c->spu);
    fprintf(f, ",\"name\":");
    tsr_json_string(f, c->name);
    fprintf(f,
            ",\"bytes_out\":%llu,\"stream_bytes\":%llu,\"buffers\":%llu,\"frames\":%llu,"
            "\"blocked_seconds\":%.6f,\"servers\":[",
            (unsigned long long)st.bytes_out, (unsigned long long)st.stream_bytes, (unsigned long long)st.buffers,
            (unsigned long long)st.frames, st.blocked_seconds);
    for (size_t i = 0; i < c->count; i++) {
        fprintf(f, "%s{\"address\":", i ? "," : "");
        tsr_json_string(f, per[i].address);
        fprintf(f, ",\"bytes_out\":%llu,\"messages\":%llu,\"blocked_seconds\":%.6f,\"failed\":%s}",
                (unsigned long long)per[i].bytes_out, (unsigned long long)per[i].messages, per[i].blocked_seconds,
                per[i].failed ? "true" : "false");
    }
    free(per);
    fprintf(f, "]");
    if (c->stats_extra)
        c->stats_extra(c->stats_extra_ctx, f);
    fprintf(f, ",\"error\":");
    if (c->first_error.code)
        tsr_json_string(f, c->first_error.message);
    else
        fprintf(f, "null");
    fprintf(f, "}\n");
    int bad = ferror(f);
    bad |= fclose(f) != 0;
    if (bad || rename(tmp, path) != 0) {
        unlink(tmp);
        return tsr_error_set(err, TSR_EIO, "cannot write statistics file %s", path);
    }
    return TSR_OK;
}
