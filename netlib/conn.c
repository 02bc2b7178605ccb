/* netlib/conn.c — the connection API application threads call: listen,
 * accept, connect, send, receive, release, close (net.h).
 * Owns: the blocking waits with their time-outs, credit accounting on the
 * application side, and the lifetime of connection and listener objects.
 * Never: touches a libuv handle (the I/O thread does, see socket.c) or
 * waits on anything without the caller's time-out or a failure to end it. */
#include <netdb.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "net_internal.h"
#include "tessera/log.h"

uint16_t net_version(const tsr_net *net) { return net->config.protocol_version; }

void net_msg_free(net_msg *m)
{
    if (!m)
        return;
    if (m->release)
        m->release(m->data, m->release_ctx);
    else
        free(m->data);
    free(m);
}

/* A kept buffer of at least `len` bytes and not more than twice that,
 * newest first (the likeliest to be in cache); NULL when none fits. */
static uint8_t *spares_take(net_spares *s, uint64_t len, uint64_t *cap)
{
    for (unsigned i = s->count; i-- > 0;)
        if (s->cap[i] >= len && s->cap[i] / 2 <= len) {
            uint8_t *p = s->buf[i];
            *cap = s->cap[i];
            s->count--;
            memmove(&s->buf[i], &s->buf[i + 1], (s->count - i) * sizeof s->buf[0]);
            memmove(&s->cap[i], &s->cap[i + 1], (s->count - i) * sizeof s->cap[0]);
            return p;
        }
    return NULL;
}

/* Keeps buf; when all places are taken it replaces the smallest (sizes
 * drift upwards), or is refused (0) when it is the smallest itself. */
static int spares_put(net_spares *s, uint8_t *buf, uint64_t cap)
{
    if (s->count == NET_SPARE_MAX) {
        unsigned small = 0;
        for (unsigned i = 1; i < s->count; i++)
            if (s->cap[i] < s->cap[small])
                small = i;
        if (s->cap[small] >= cap)
            return 0;
        free(s->buf[small]);
        s->count--;
        memmove(&s->buf[small], &s->buf[small + 1], (s->count - small) * sizeof s->buf[0]);
        memmove(&s->cap[small], &s->cap[small + 1], (s->count - small) * sizeof s->cap[0]);
    }
    s->buf[s->count] = buf;
    s->cap[s->count] = cap;
    s->count++;
    return 1;
}

static void spares_free(net_spares *s)
{
    while (s->count)
        free(s->buf[--s->count]);
}

uint8_t *net_payload_alloc(tsr_net_conn *c, uint64_t len, uint64_t *cap)
{
    uint8_t *p = len >= NET_STAGING_BYTES ? spares_take(&c->spares, len, cap) : NULL;
    if (p)
        return p;
    *cap = len ? len : 1;
    return malloc((size_t)*cap);
}

/* (L) Keeps the payload of a released large message for reuse; returns 1
 * when it took it. Spares plus messages in use stay within the credit
 * window, so the memory bound of net.h (credits x max_message_bytes per
 * connection and direction) still holds. */
static int keep_spare(tsr_net_conn *c, net_msg *m)
{
    if (m->release || m->cap < NET_STAGING_BYTES || c->close_requested || c->state != NET_OPEN)
        return 0;
    if (c->spares.count + c->inbox_count + c->held + (c->partial != NULL) >= c->net->config.credits)
        return 0;
    if (!spares_put(&c->spares, m->data, m->cap))
        return 0;
    m->data = NULL;
    return 1;
}

uint8_t *net_send_copy_alloc(tsr_net_conn *c, uint64_t len, uint64_t *cap)
{
    c->send_copies++;
    uint8_t *p = len >= NET_STAGING_BYTES ? spares_take(&c->send_spares, len, cap) : NULL;
    if (p)
        return p;
    *cap = len ? len : 1;
    return malloc((size_t)*cap);
}

void net_send_copy_done(tsr_net_conn *c, net_msg *m)
{
    if (!m->copy)
        return;
    m->copy = false;
    c->send_copies--;
    /* Copies queued plus kept stay within the peer's window: the sender's
     * side of the memory bound in net.h. */
    if (m->data && m->cap >= NET_STAGING_BYTES && !c->close_requested && c->state == NET_OPEN &&
        c->send_spares.count + c->send_copies < c->peer_window && spares_put(&c->send_spares, m->data, m->cap))
        m->data = NULL;
}

static void free_msg_list(net_msg **head, net_msg **tail)
{
    while (*head) {
        net_msg *m = *head;
        *head = m->next;
        net_msg_free(m);
    }
    if (tail)
        *tail = NULL;
}

tsr_net_conn *net_conn_new(tsr_net *net, enum net_transport t, bool is_server, const char *address)
{
    tsr_net_conn *c = calloc(1, sizeof *c);
    if (!c)
        return NULL;
    c->net = net;
    c->transport = t;
    c->is_server = is_server;
    snprintf(c->address, sizeof c->address, "%s", address);
    strcpy(c->peer_name, "?");
    net_cond_init(&c->cond);
    c->fd = -1;
    c->state = is_server ? NET_HANDSHAKE : NET_CONNECTING;
    c->io_ref = t != NET_INPROC;
    c->next_all = net->conns;
    if (net->conns)
        net->conns->prev_all = c;
    net->conns = c;
    return c;
}

void net_conn_maybe_free(tsr_net_conn *c)
{
    if (c->app_ref || c->io_ref || c->held)
        return;
    tsr_net *net = c->net;
    if (c->dirty) { /* still queued for the I/O thread: unqueue it */
        tsr_net_conn **p = &net->dirty_head;
        while (*p && *p != c)
            p = &(*p)->next_dirty;
        if (*p)
            *p = c->next_dirty;
        c->dirty = false;
    }
    if (c->prev_all)
        c->prev_all->next_all = c->next_all;
    else
        net->conns = c->next_all;
    if (c->next_all)
        c->next_all->prev_all = c->prev_all;
    free_msg_list(&c->inbox_head, &c->inbox_tail);
    free_msg_list(&c->outbox_head, &c->outbox_tail);
    net_msg_free(c->direct_rest);
    if (c->partial)
        net_msg_free(c->partial);
    spares_free(&c->spares);
    spares_free(&c->send_spares);
    net_shm_free(c);
    free(c->staging);
    pthread_cond_destroy(&c->cond);
    free(c);
}

void net_conn_signal(tsr_net_conn *c)
{
    pthread_cond_broadcast(&c->cond);
    if (c->net->any_waiters)
        pthread_cond_broadcast(&c->net->any_cond);
}

void net_conn_fail(tsr_net_conn *c, int code, const char *fmt, ...)
{
    if (c->state == NET_FAILED)
        return;
    c->state = NET_FAILED;
    c->error.code = code;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(c->error.message, sizeof c->error.message, fmt, ap);
    va_end(ap);
    net_conn_signal(c);
    tsr_log(TSR_LOG_INFO, "%s", c->error.message);
}

/* Waits on `cond` until `deadline` (NULL: no deadline). 1 = timed out. */
static int wait_until(pthread_cond_t *cond, pthread_mutex_t *lock, const struct timespec *dl)
{
    if (!dl) {
        pthread_cond_wait(cond, lock);
        return 0;
    }
    return pthread_cond_timedwait(cond, lock, dl) != 0;
}

static int conn_unusable(const tsr_net_conn *c, const char *verb, tsr_error *err)
{
    if (c->state == NET_FAILED)
        return tsr_error_set(err, c->error.code, "%s", c->error.message);
    if (c->state == NET_ENDED)
        return tsr_error_set(err, TSR_EIO, "net: cannot %s: peer '%s' at %s closed the connection", verb, c->peer_name,
                             c->address);
    return tsr_error_set(err, TSR_ESTATE, "net: cannot %s: connection to %s is not open", verb, c->address);
}

/* ---- listeners ------------------------------------------------------------ */

void net_listener_unlink(tsr_net_listener *l)
{
    tsr_net_listener **p = &l->net->listeners;
    while (*p && *p != l)
        p = &(*p)->next;
    if (*p)
        *p = l->next;
    l->next = NULL;
}

void net_listener_maybe_free(tsr_net_listener *l)
{
    if (l->app_ref || l->io_ref)
        return;
    net_listener_unlink(l);
    pthread_cond_destroy(&l->cond);
    free(l);
}

/* Resolves a tcp address in the calling thread (bounded by the system
 * resolver's own time-outs). An empty host means loopback. */
static int resolve(const net_address *a, bool passive, struct addrinfo **out, const char *text, const char *verb,
                   tsr_error *err)
{
    const char *host = a->host[0] ? a->host : "127.0.0.1";
    char port[8];
    snprintf(port, sizeof port, "%u", a->port);
    struct addrinfo hints = {0};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_NUMERICSERV | (passive ? AI_PASSIVE : 0);
    *out = NULL;
    int rc = getaddrinfo(host, port, &hints, out);
    if (rc || !*out)
        return tsr_error_set(err, TSR_ENOENT, "net: cannot %s %s: host '%s' not found (%s)", verb, text, host,
                             gai_strerror(rc));
    return TSR_OK;
}

tsr_net_listener *tsr_net_listen(tsr_net *net, const char *address, tsr_error *err)
{
    net_address a;
    if (net_address_parse(address, &a, err))
        return NULL;
    tsr_net_listener *l = calloc(1, sizeof *l);
    if (!l) {
        tsr_error_set(err, TSR_ENOMEM, "net: out of memory");
        return NULL;
    }
    l->net = net;
    l->transport = a.transport;
    l->app_ref = true;
    net_cond_init(&l->cond);
    snprintf(l->address, sizeof l->address, "%s", address);
    net_op op = {.kind = NET_OP_LISTEN, .target = l, .address = &a};
    if (a.transport == NET_TCP) {
        struct addrinfo *ai;
        if (resolve(&a, true, &ai, address, "listen on", err)) {
            pthread_cond_destroy(&l->cond);
            free(l);
            return NULL;
        }
        memcpy(&op.sockaddr, ai->ai_addr, ai->ai_addrlen);
        freeaddrinfo(ai);
    }
    pthread_mutex_lock(&net->lock);
    int rc;
    if (a.transport == NET_INPROC) {
        rc = net_inproc_listen(net, &a, l, err);
    } else {
        l->io_ref = true;
        l->next = net->listeners;
        net->listeners = l;
        rc = net_submit_op(net, &op);
        if (rc)
            tsr_error_set(err, op.err.code, "%s", op.err.message);
    }
    if (rc) {
        l->app_ref = false;
        net_listener_maybe_free(l);
        l = NULL;
    }
    pthread_mutex_unlock(&net->lock);
    return l;
}

int tsr_net_address_is_local(const char *address, tsr_error *err)
{
    net_address a;
    int rc = net_address_parse(address, &a, err);
    if (rc)
        return rc;
    if (a.transport != NET_TCP || !a.host[0])
        return 1;
    struct addrinfo *list;
    rc = resolve(&a, true, &list, address, "listen on", err);
    if (rc)
        return rc;
    int local = 1;
    for (struct addrinfo *ai = list; ai; ai = ai->ai_next) {
        if (ai->ai_family == AF_INET) {
            const struct sockaddr_in *in = (const struct sockaddr_in *)ai->ai_addr;
            if ((ntohl(in->sin_addr.s_addr) >> 24) != 127)
                local = 0;
        } else if (ai->ai_family == AF_INET6) {
            const struct sockaddr_in6 *in6 = (const struct sockaddr_in6 *)ai->ai_addr;
            if (!IN6_IS_ADDR_LOOPBACK(&in6->sin6_addr))
                local = 0;
        } else {
            local = 0;
        }
    }
    freeaddrinfo(list);
    return local;
}

const char *tsr_net_listener_address(const tsr_net_listener *l) { return l->address; }

tsr_net_conn *tsr_net_accept(tsr_net_listener *l, int timeout_ms, tsr_error *err)
{
    struct timespec ts;
    const struct timespec *dl = net_deadline(&ts, timeout_ms) ? &ts : NULL;
    tsr_net *net = l->net;
    pthread_mutex_lock(&net->lock);
    while (!l->ready_head && !l->closing && !net->stopping)
        if (wait_until(&l->cond, &net->lock, dl))
            break;
    tsr_net_conn *c = l->ready_head;
    if (c) {
        l->ready_head = c->next_ready;
        if (!l->ready_head)
            l->ready_tail = NULL;
        c->next_ready = NULL;
        c->listener = NULL;
        c->ready = false;
        l->pending--;
    } else if (l->closing || net->stopping) {
        tsr_error_set(err, TSR_ESTATE, "net: %s is closed", l->address);
    } else {
        tsr_error_set(err, TSR_ETIMEDOUT, "net: no connection on %s within %d ms", l->address, timeout_ms);
    }
    pthread_mutex_unlock(&net->lock);
    return c;
}

unsigned tsr_net_listener_refusals(tsr_net_listener *l, tsr_error *last)
{
    pthread_mutex_lock(&l->net->lock);
    unsigned n = l->refusals;
    if (last)
        *last = l->last_refusal;
    pthread_mutex_unlock(&l->net->lock);
    return n;
}

void tsr_net_listener_close(tsr_net_listener *l)
{
    if (!l)
        return;
    tsr_net *net = l->net;
    pthread_mutex_lock(&net->lock);
    l->closing = true;
    pthread_cond_broadcast(&l->cond);
    /* Connections nobody accepted are closed with it. */
    while (l->ready_head) {
        tsr_net_conn *c = l->ready_head;
        l->ready_head = c->next_ready;
        c->next_ready = NULL;
        c->listener = NULL;
        c->ready = false;
        l->pending--;
        if (c->transport == NET_INPROC) {
            net_inproc_close(c);
        } else {
            c->app_ref = false;
            c->close_requested = true;
            net_mark_dirty(c);
        }
    }
    l->ready_tail = NULL;
    l->app_ref = false;
    if (l->transport == NET_INPROC) {
        net_listener_maybe_free(l);
    } else if (!net->stopping) {
        net_op op = {.kind = NET_OP_CLOSE_LISTENER, .target = l};
        net_submit_op(net, &op);
    }
    pthread_mutex_unlock(&net->lock);
}

/* ---- connections ---------------------------------------------------------- */

/* One connection attempt to one resolved address (NULL for unix). Sets
 * *reached when the socket connected (so a later failure was the peer's
 * answer, not an unreachable address worth trying the next one for). */
static tsr_net_conn *connect_once(tsr_net *net, const net_address *a, const char *address, const struct addrinfo *ai,
                                  bool *reached, tsr_error *err)
{
    net_op op = {.kind = NET_OP_CONNECT, .address = a};
    if (ai)
        memcpy(&op.sockaddr, ai->ai_addr, ai->ai_addrlen);
    *reached = false;
    pthread_mutex_lock(&net->lock);
    if (net->stopping) {
        pthread_mutex_unlock(&net->lock);
        tsr_error_set(err, TSR_ESTATE, "net: cannot connect to %s: shutting down", address);
        return NULL;
    }
    tsr_net_conn *c = net_conn_new(net, a->transport, false, address);
    if (!c) {
        pthread_mutex_unlock(&net->lock);
        tsr_error_set(err, TSR_ENOMEM, "net: out of memory");
        return NULL;
    }
    c->app_ref = true;
    op.target = c;
    net_submit_op(net, &op);
    /* The I/O thread enforces both time-outs; this bound only guards it. */
    struct timespec ts;
    net_deadline(&ts, (int)(net->config.connect_timeout_ms + net->config.handshake_timeout_ms + 2000));
    bool guard_expired = false;
    while (c->state == NET_CONNECTING || c->state == NET_HANDSHAKE)
        if (wait_until(&c->cond, &net->lock, &ts)) {
            guard_expired = true;
            break;
        }
    *reached = c->socket_connected;
    /* A peer may answer WELCOME and at once say something and close (a
     * server dropping a client it cannot serve says why first). Once the
     * handshake succeeded the connection is the caller's even if it
     * already ended or failed: what the peer said stays receivable, and
     * the next send or receive reports the end. */
    if (c->state != NET_OPEN && !c->handshaken) {
        if (guard_expired)
            tsr_error_set(err, TSR_ETIMEDOUT, "net: connecting to %s timed out", address);
        else
            conn_unusable(c, "connect", err);
        c->app_ref = false;
        c->close_requested = true;
        net_mark_dirty(c);
        net_conn_maybe_free(c);
        c = NULL;
    }
    pthread_mutex_unlock(&net->lock);
    return c;
}

tsr_net_conn *tsr_net_connect(tsr_net *net, const char *address, tsr_error *err)
{
    net_address a;
    if (net_address_parse(address, &a, err))
        return NULL;
    if (a.transport == NET_INPROC) {
        pthread_mutex_lock(&net->lock);
        tsr_net_conn *c = net_inproc_connect(net, &a, err);
        pthread_mutex_unlock(&net->lock);
        return c;
    }
    bool reached;
    if (a.transport == NET_UNIX)
        return connect_once(net, &a, address, NULL, &reached, err);
    if (!a.host[0]) {
        tsr_error_set(err, TSR_EINVAL, "net: cannot connect to %s: no host given", address);
        return NULL;
    }
    struct addrinfo *list;
    if (resolve(&a, false, &list, address, "connect to", err))
        return NULL;
    /* A name may resolve to several addresses ("localhost": ::1 and
     * 127.0.0.1); try each until one answers. */
    tsr_net_conn *c = NULL;
    for (struct addrinfo *ai = list; ai && !c; ai = ai->ai_next) {
        c = connect_once(net, &a, address, ai, &reached, err);
        if (reached)
            break;
    }
    freeaddrinfo(list);
    return c;
}

static uint64_t elapsed_ns(const struct timespec *since)
{
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (uint64_t)(now.tv_sec - since->tv_sec) * 1000000000u + (uint64_t)(now.tv_nsec - since->tv_nsec);
}

static void release_nothing(void *data, void *ctx)
{
    (void)data;
    (void)ctx;
}

/* (L) Hands m (its credit taken) to the transport: the peer's inbox
 * (inproc), the socket from this thread (direct.c), or the I/O thread's
 * queue. Returns a message written whole, to free after unlocking. */
static net_msg *enqueue(tsr_net_conn *c, net_msg *m)
{
    if (c->transport == NET_INPROC) {
        net_inproc_deliver(c, m);
        return NULL;
    }
    if (net_direct_possible(c))
        return net_direct_write(c, m); /* no hand-over to the I/O thread */
    if (c->outbox_tail)
        c->outbox_tail->next = m;
    else
        c->outbox_head = m;
    c->outbox_tail = m;
    net_mark_dirty(c);
    return NULL;
}

/* (L) Waits until a credit is there and, with `pos` given, a ring message
 * of ring_len bytes fits (*pos: where it goes); takes nothing. Returns TSR_OK, TSR_ETIMEDOUT or the
 * connection's error. */
static int wait_to_send(tsr_net_conn *c, uint64_t ring_len, uint64_t *pos, const struct timespec *dl, int timeout_ms,
                        tsr_error *err)
{
    tsr_net *net = c->net;
    bool ready = c->send_credits > 0 && (!pos || net_shm_fits(c, ring_len, pos));
    if (ready)
        return TSR_OK;
    struct timespec started;
    clock_gettime(CLOCK_MONOTONIC, &started);
    c->send_waiters++;
    net_mark_dirty(c); /* the I/O thread must read, to see the peer's credits */
    while (c->state == NET_OPEN && !c->close_requested &&
           !(ready = c->send_credits > 0 && (!pos || net_shm_fits(c, ring_len, pos))))
        if (wait_until(&c->cond, &net->lock, dl))
            break;
    c->send_waiters--;
    c->stats.blocked_on_credits_ns += elapsed_ns(&started);
    if (c->state != NET_OPEN || c->close_requested)
        return conn_unusable(c, "send", err);
    if (!ready && c->send_credits == 0)
        return tsr_error_set(err, TSR_ETIMEDOUT, "net: peer '%s' at %s granted no credit within %d ms", c->peer_name,
                             c->address, timeout_ms);
    if (!ready)
        return tsr_error_set(err, TSR_ETIMEDOUT,
                             "net: peer '%s' at %s released no room for a %llu-byte message in the shared-memory "
                             "ring within %d ms",
                             c->peer_name, c->address, (unsigned long long)ring_len, timeout_ms);
    return TSR_OK;
}

/* (L) A reservation not committed is given up (tsr_net_send_reserve). */
static void drop_reservation(tsr_net_conn *c) { c->tx.reserved = false; }

/* (L) Sends the ring reservation's first len bytes: its descriptor goes
 * through the socket (flags NET_FLAG_SHM). *written as enqueue's. */
static int commit_ring(tsr_net_conn *c, unsigned kind, uint64_t len, net_msg **written, tsr_error *err)
{
    *written = NULL;
    c->tx.reserved = false;
    if (c->state != NET_OPEN || c->close_requested)
        return conn_unusable(c, "send", err);
    if (c->send_credits == 0) /* taken by nobody else: one sending thread */
        return tsr_error_set(err, TSR_ESTATE, "net: no credit for the reserved message to %s", c->address);
    net_msg *m = calloc(1, sizeof *m);
    uint8_t *desc = malloc(NET_SHM_DESC_BYTES);
    if (!m || !desc) {
        free(m);
        free(desc);
        return tsr_error_set(err, TSR_ENOMEM, "net: out of memory");
    }
    uint64_t pos = c->tx.reserved_pos;
    net_put_u64(desc, pos);
    net_put_u64(desc + 8, len);
    m->conn = c;
    m->type = (uint8_t)kind;
    m->flags = NET_FLAG_SHM;
    m->data = desc;
    m->len = NET_SHM_DESC_BYTES;
    if (c->tx.tail == c->tx.head) /* empty: rewound (net_shm_fits), the skipped end is free */
        c->tx.tail = pos;
    c->tx.head = pos + net_shm_slot(len);
    c->send_credits--;
    c->stats.messages_sent++;
    c->stats.bytes_sent += len;
    c->stats.messages_sent_shm++;
    c->stats.bytes_sent_shm += len;
    *written = enqueue(c, m);
    return TSR_OK;
}

int tsr_net_send_reserve(tsr_net_conn *c, uint64_t max_len, void **buf, int timeout_ms, tsr_error *err)
{
    *buf = NULL;
    tsr_net *net = c->net;
    struct timespec ts;
    const struct timespec *dl = net_deadline(&ts, timeout_ms) ? &ts : NULL;
    pthread_mutex_lock(&net->lock);
    drop_reservation(c);
    int rc = TSR_OK;
    if (c->state != NET_OPEN || c->close_requested) {
        rc = conn_unusable(c, "send", err);
    } else if (max_len > c->peer_max_message) {
        rc = tsr_error_set(err, TSR_EINVAL,
                           "net: a %llu-byte message is over the %llu-byte limit of peer '%s' at %s (its "
                           "max_message_bytes)",
                           (unsigned long long)max_len, (unsigned long long)c->peer_max_message, c->peer_name,
                           c->address);
    } else if (c->shm && net_shm_slot(max_len) <= c->tx.size) {
        uint64_t pos;
        if ((rc = wait_to_send(c, max_len, &pos, dl, timeout_ms, err)) == TSR_OK) {
            c->tx.reserved = c->tx.reserved_ring = true;
            c->tx.reserved_pos = pos;
            c->tx.reserved_len = max_len;
            *buf = c->tx.map + pos % c->tx.size;
        }
    } else {
        /* Not through a ring: a buffer kept for the connection, sent as
         * tsr_net_send sends (the socket copies it). */
        if (max_len > c->reserve_cap || !c->reserve_buf) {
            uint8_t *p = realloc(c->reserve_buf, max_len ? (size_t)max_len : 1);
            if (!p) {
                rc = tsr_error_set(err, TSR_ENOMEM, "net: out of memory for a %llu-byte message",
                                   (unsigned long long)max_len);
                goto out;
            }
            c->reserve_buf = p;
            c->reserve_cap = max_len;
        }
        c->tx.reserved = true;
        c->tx.reserved_ring = false;
        c->tx.reserved_len = max_len;
        *buf = c->reserve_buf;
    }
out:
    pthread_mutex_unlock(&net->lock);
    return rc;
}

static int send_msg(tsr_net_conn *c, unsigned kind, void *data, uint64_t len, void (*release)(void *, void *),
                    void *ctx, bool borrowed, int timeout_ms, tsr_error *err);

int tsr_net_send_commit(tsr_net_conn *c, unsigned kind, uint64_t len, int timeout_ms, tsr_error *err)
{
    if (kind < TSR_NET_KIND_FIRST_USER || kind > 255)
        return tsr_error_set(err, TSR_EINVAL, "net: message kind %u is outside the application range %d..255", kind,
                             TSR_NET_KIND_FIRST_USER);
    tsr_net *net = c->net;
    pthread_mutex_lock(&net->lock);
    if (!c->tx.reserved || len > c->tx.reserved_len) {
        bool had = c->tx.reserved;
        uint64_t cap = c->tx.reserved_len;
        c->tx.reserved = false;
        pthread_mutex_unlock(&net->lock);
        return had ? tsr_error_set(err, TSR_EINVAL, "net: committing %llu bytes of a %llu-byte reservation",
                                   (unsigned long long)len, (unsigned long long)cap)
                   : tsr_error_set(err, TSR_ESTATE, "net: nothing reserved to commit on %s", c->address);
    }
    if (!c->tx.reserved_ring) {
        c->tx.reserved = false;
        uint8_t *buf = c->reserve_buf;
        pthread_mutex_unlock(&net->lock);
        return send_msg(c, kind, buf, len, NULL, NULL, true, timeout_ms, err);
    }
    net_msg *written = NULL;
    int rc = commit_ring(c, kind, len, &written, err);
    pthread_mutex_unlock(&net->lock);
    net_msg_free(written);
    return rc;
}

/* tsr_net_send_owned, or with `borrowed` tsr_net_send: the caller's `data`
 * is written directly when the connection's write side is idle (no copy
 * at all), and copied only when it must wait in a queue. */
static int send_msg(tsr_net_conn *c, unsigned kind, void *data, uint64_t len, void (*release)(void *, void *),
                    void *ctx, bool borrowed, int timeout_ms, tsr_error *err)
{
    if (kind < TSR_NET_KIND_FIRST_USER || kind > 255)
        return tsr_error_set(err, TSR_EINVAL, "net: message kind %u is outside the application range %d..255", kind,
                             TSR_NET_KIND_FIRST_USER);
    if (!data && len)
        return tsr_error_set(err, TSR_EINVAL, "net: NULL data with length %llu", (unsigned long long)len);
    tsr_net *net = c->net;
    struct timespec ts;
    const struct timespec *dl = net_deadline(&ts, timeout_ms) ? &ts : NULL;
    net_msg *written = NULL;
    pthread_mutex_lock(&net->lock);
    int rc = TSR_OK;
    if (c->state != NET_OPEN || c->close_requested) {
        rc = conn_unusable(c, "send", err);
        goto out;
    }
    if (len > c->peer_max_message) {
        rc = tsr_error_set(err, TSR_EINVAL,
                           "net: a %llu-byte message is over the %llu-byte limit of peer '%s' "
                           "at %s (its max_message_bytes)",
                           (unsigned long long)len, (unsigned long long)c->peer_max_message, c->peer_name, c->address);
        goto out;
    }
    drop_reservation(c);
    if (c->shm && net_shm_slot(len) <= c->tx.size) {
        /* Through the ring: copied there (tsr_net_send_reserve spares even
         * that copy), and only a descriptor goes on the socket. */
        uint64_t pos;
        if ((rc = wait_to_send(c, len, &pos, dl, timeout_ms, err)))
            goto out;
        c->tx.reserved = c->tx.reserved_ring = true;
        c->tx.reserved_pos = pos;
        c->tx.reserved_len = len;
        pthread_mutex_unlock(&net->lock);
        if (len)
            memcpy(c->tx.map + pos % c->tx.size, data, (size_t)len);
        pthread_mutex_lock(&net->lock);
        rc = commit_ring(c, kind, len, &written, err);
        pthread_mutex_unlock(&net->lock);
        net_msg_free(written);
        if (rc == TSR_OK && !borrowed) { /* owned: the caller gave it to be released once sent */
            if (release)
                release(data, ctx);
            else
                free(data);
        }
        return rc;
    }
    if ((rc = wait_to_send(c, 0, NULL, dl, timeout_ms, err)))
        goto out;
    net_msg *m = calloc(1, sizeof *m);
    if (!m) {
        rc = tsr_error_set(err, TSR_ENOMEM, "net: out of memory");
        goto out;
    }
    m->conn = c;
    m->type = (uint8_t)kind;
    m->len = len;
    m->data = data;
    m->release = release;
    m->release_ctx = ctx;
    if (borrowed && !net_direct_possible(c)) {    /* it waits in a queue: copy it */
        bool pooled = c->transport != NET_INPROC; /* an inproc copy becomes the peer's */
        m->data = pooled ? net_send_copy_alloc(c, len, &m->cap) : malloc(len ? (size_t)len : 1);
        m->copy = pooled;
        m->release = NULL; /* free() */
        if (!m->data) {
            net_send_copy_done(c, m);
            free(m);
            rc = tsr_error_set(err, TSR_ENOMEM, "net: out of memory copying a %llu-byte message",
                               (unsigned long long)len);
            goto out;
        }
        pthread_mutex_unlock(&net->lock); /* the copy may be long: others go on */
        if (len)
            memcpy(m->data, data, (size_t)len);
        pthread_mutex_lock(&net->lock);
        if (c->state != NET_OPEN || c->close_requested) { /* changed while copying */
            net_send_copy_done(c, m);
            net_msg_free(m);
            rc = conn_unusable(c, "send", err);
            goto out;
        }
    } else if (borrowed) {
        m->release = release_nothing; /* the caller's memory; a rest is copied (direct.c) */
        m->borrowed = true;
    }
    c->send_credits--;
    c->stats.messages_sent++;
    c->stats.bytes_sent += len;
    written = enqueue(c, m);
out:
    pthread_mutex_unlock(&net->lock);
    net_msg_free(written); /* outside the lock: a caller's release() may take its own */
    return rc;
}

int tsr_net_send_owned(tsr_net_conn *c, unsigned kind, void *data, uint64_t len, void (*release)(void *, void *),
                       void *ctx, int timeout_ms, tsr_error *err)
{
    return send_msg(c, kind, data, len, release, ctx, false, timeout_ms, err);
}

int tsr_net_send(tsr_net_conn *c, unsigned kind, const void *data, uint64_t len, int timeout_ms, tsr_error *err)
{
    if (len >= SIZE_MAX)
        return tsr_error_set(err, TSR_EINVAL, "net: a %llu-byte message cannot be copied", (unsigned long long)len);
    return send_msg(c, kind, (void *)data, len, NULL, NULL, true, timeout_ms, err);
}

/* (L) Whether tsr_net_recv on c would return now. */
static bool recv_ready(const tsr_net_conn *c) { return c->inbox_head || c->state != NET_OPEN || c->close_requested; }

/* (L) What tsr_net_recv returns once recv_ready(c) (or on time-out). */
static int recv_take(tsr_net_conn *c, tsr_net_msg *msg, int timeout_ms, tsr_error *err)
{
    net_msg *m = c->inbox_head;
    if (m) {
        c->inbox_head = m->next;
        if (!c->inbox_head)
            c->inbox_tail = NULL;
        m->next = NULL;
        c->inbox_count--;
        c->held++;
        msg->kind = m->type;
        msg->data = m->data;
        msg->len = m->len;
        msg->internal = m;
        return 1;
    }
    if (c->state == NET_ENDED)
        return 0;
    if (c->state != NET_OPEN || c->close_requested)
        return conn_unusable(c, "receive", err);
    return tsr_error_set(err, TSR_ETIMEDOUT, "net: nothing from peer '%s' at %s within %d ms", c->peer_name, c->address,
                         timeout_ms);
}

int tsr_net_recv(tsr_net_conn *c, tsr_net_msg *msg, int timeout_ms, tsr_error *err)
{
    memset(msg, 0, sizeof *msg);
    tsr_net *net = c->net;
    struct timespec ts;
    const struct timespec *dl = net_deadline(&ts, timeout_ms) ? &ts : NULL;
    pthread_mutex_lock(&net->lock);
    while (!recv_ready(c))
        if (wait_until(&c->cond, &net->lock, dl))
            break;
    int rc = recv_take(c, msg, timeout_ms, err);
    pthread_mutex_unlock(&net->lock);
    return rc;
}

int tsr_net_recv_any(tsr_net_conn *const *conns, size_t count, size_t *which, tsr_net_msg *msg, int timeout_ms,
                     tsr_error *err)
{
    memset(msg, 0, sizeof *msg);
    if (count == 0 || !which)
        return tsr_error_set(err, TSR_EINVAL, "net: tsr_net_recv_any needs connections");
    tsr_net *net = conns[0]->net;
    for (size_t i = 1; i < count; i++)
        if (conns[i]->net != net)
            return tsr_error_set(err, TSR_EINVAL, "net: tsr_net_recv_any: %s belongs to another tsr_net",
                                 conns[i]->address);
    struct timespec ts;
    const struct timespec *dl = net_deadline(&ts, timeout_ms) ? &ts : NULL;
    size_t start = *which < count ? *which + 1 : 0; /* round-robin after the last one */
    pthread_mutex_lock(&net->lock);
    net->any_waiters++;
    size_t found = count;
    for (;;) {
        for (size_t k = 0; k < count && found == count; k++) {
            size_t i = (start + k) % count;
            if (recv_ready(conns[i]))
                found = i;
        }
        if (found < count || wait_until(&net->any_cond, &net->lock, dl))
            break;
    }
    net->any_waiters--;
    int rc;
    if (found < count) {
        *which = found;
        rc = recv_take(conns[found], msg, timeout_ms, err);
    } else {
        rc = tsr_error_set(err, TSR_ETIMEDOUT, "net: nothing from %zu connections within %d ms", count, timeout_ms);
    }
    pthread_mutex_unlock(&net->lock);
    return rc;
}

/* (L) Returns the released credits with a CREDIT the calling thread writes
 * itself (direct.c), sparing the I/O thread a wake-up per message; false
 * when the I/O thread must do it. *written gets the message to free after
 * unlocking. While the application held a full window the I/O thread
 * stopped reading; it is woken then to read again. */
static bool return_credits_direct(tsr_net_conn *c, net_msg **written)
{
    if (!net_direct_possible(c))
        return false;
    net_msg *m = calloc(1, sizeof *m);
    uint8_t *payload = malloc(12);
    if (!m || !payload) {
        free(m);
        free(payload);
        return false;
    }
    m->len = net_credit_encode(c, c->credits_to_return, payload);
    c->credits_to_return = 0;
    m->type = NET_CREDIT;
    m->data = payload;
    *written = net_direct_write(c, m);
    if (!c->reading)
        net_mark_dirty(c);
    return true;
}

void tsr_net_msg_release(tsr_net_msg *msg)
{
    net_msg *m = msg ? msg->internal : NULL;
    if (!m)
        return;
    msg->internal = NULL;
    msg->data = NULL;
    tsr_net_conn *c = m->conn;
    tsr_net *net = c->net;
    net_shm_drop_read(c, m);
    pthread_mutex_lock(&net->lock);
    c->held--;
    net_shm_release(c, m); /* before the credit, which tells the ring position */
    net_msg *credit = NULL;
    if (!c->close_requested && c->state == NET_OPEN) {
        c->credits_to_return++;
        if (c->transport == NET_INPROC)
            net_inproc_return_credits(c);
        else if (!return_credits_direct(c, &credit))
            net_mark_dirty(c);
    }
    if (c->transport != NET_INPROC)
        keep_spare(c, m); /* before maybe_free, which frees the spares with c */
    net_conn_maybe_free(c);
    pthread_mutex_unlock(&net->lock);
    net_msg_free(credit);
    net_msg_free(m);
}

const char *tsr_net_conn_peer_name(const tsr_net_conn *c) { return c->peer_name; }

const char *tsr_net_conn_transport(tsr_net_conn *c)
{
    pthread_mutex_lock(&c->net->lock);
    const char *t = c->transport == NET_TCP      ? "tcp"
                    : c->transport == NET_INPROC ? "inproc"
                    : c->tx.map                  ? "unix+shm"
                                                 : "unix";
    pthread_mutex_unlock(&c->net->lock);
    return t;
}
const char *tsr_net_conn_address(const tsr_net_conn *c) { return c->address; }

int tsr_net_conn_flush(tsr_net_conn *c, int timeout_ms)
{
    struct timespec ts;
    const struct timespec *dl = net_deadline(&ts, timeout_ms) ? &ts : NULL;
    pthread_mutex_lock(&c->net->lock);
    c->flush_waiters++;
    int timed_out = 0;
    while (c->state == NET_OPEN && !c->peer_stopped_reading && !timed_out &&
           (c->outbox_head || c->writes_in_flight || c->direct_rest || c->direct_writer))
        timed_out = wait_until(&c->cond, &c->net->lock, dl);
    c->flush_waiters--;
    int rc = c->state == NET_FAILED ? c->error.code : timed_out ? TSR_ETIMEDOUT : TSR_OK;
    pthread_mutex_unlock(&c->net->lock);
    return rc;
}

int tsr_net_conn_wait_returned(tsr_net_conn *c, int timeout_ms, tsr_error *err)
{
    tsr_net *net = c->net;
    struct timespec ts;
    const struct timespec *dl = net_deadline(&ts, timeout_ms) ? &ts : NULL;
    pthread_mutex_lock(&net->lock);
    bool returned = c->send_credits >= c->peer_window && c->tx.head == c->tx.tail;
    if (!returned) {
        c->send_waiters++;
        net_mark_dirty(c); /* the I/O thread must read, to see the peer's credits */
        while (c->state == NET_OPEN && !c->close_requested &&
               !(returned = c->send_credits >= c->peer_window && c->tx.head == c->tx.tail))
            if (wait_until(&c->cond, &net->lock, dl))
                break;
        c->send_waiters--;
    }
    int rc = TSR_OK;
    if (c->state != NET_OPEN || c->close_requested)
        rc = conn_unusable(c, "wait for the peer's releases", err);
    else if (!returned)
        rc = tsr_error_set(err, TSR_ETIMEDOUT, "net: peer '%s' at %s released not all of %u messages within %d ms",
                           c->peer_name, c->address, c->peer_window - c->send_credits, timeout_ms);
    pthread_mutex_unlock(&net->lock);
    return rc;
}

int tsr_net_conn_went_silent(tsr_net_conn *c)
{
    pthread_mutex_lock(&c->net->lock);
    int silent = c->went_silent;
    pthread_mutex_unlock(&c->net->lock);
    return silent;
}

int tsr_net_conn_vanished(tsr_net_conn *c)
{
    pthread_mutex_lock(&c->net->lock);
    int vanished = c->vanished;
    pthread_mutex_unlock(&c->net->lock);
    return vanished;
}

int tsr_net_conn_failure(tsr_net_conn *c, tsr_error *why)
{
    pthread_mutex_lock(&c->net->lock);
    int failed = c->state == NET_FAILED;
    if (failed)
        tsr_error_set(why, c->error.code, "%s", c->error.message);
    pthread_mutex_unlock(&c->net->lock);
    return failed;
}

void tsr_net_conn_stats(tsr_net_conn *c, tsr_net_stats *stats)
{
    pthread_mutex_lock(&c->net->lock);
    *stats = c->stats;
    stats->messages_unreturned = c->peer_window > c->send_credits ? c->peer_window - c->send_credits : 0;
    pthread_mutex_unlock(&c->net->lock);
}

void tsr_net_conn_close(tsr_net_conn *c)
{
    if (!c)
        return;
    tsr_net *net = c->net;
    pthread_mutex_lock(&net->lock);
    if (c->transport == NET_INPROC) {
        net_inproc_close(c);
    } else {
        c->close_requested = true;
        c->app_ref = false;
        /* Messages the application never received are dropped now. */
        while (c->inbox_head) {
            net_msg *m = c->inbox_head;
            c->inbox_head = m->next;
            net_msg_free(m);
        }
        c->inbox_tail = NULL;
        c->inbox_count = 0;
        net_conn_signal(c);
        net_mark_dirty(c);
        net_conn_maybe_free(c);
    }
    pthread_mutex_unlock(&net->lock);
}
