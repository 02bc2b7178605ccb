/* netlib/conn.c — the connection API application threads call: listen,
 * accept, connect, send, receive, release, close (net.h).
 * Owns: the blocking waits with their time-outs, credit accounting on the
 * application side, and the lifetime of connection and listener objects.
 * Never: touches a libuv handle (the I/O thread does, see socket.c) or
 * waits on anything without the caller's time-out or a failure to end it.
 *
 * This file: messages' memory, the connection's life cycle and waits,
 * connecting, receiving, queries and close. conn_listen.c and conn_send.c
 * do the rest (conn_internal.h). */
#include <netdb.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "conn_internal.h"
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

tsr_net_conn *net_conn_new(tsr_net *net, tsr_net_transport t, bool is_server, const char *address)
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
    c->io_ref = t != TSR_NET_INPROC;
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
int conn_wait_until(pthread_cond_t *cond, pthread_mutex_t *lock, const struct timespec *dl)
{
    if (!dl) {
        pthread_cond_wait(cond, lock);
        return 0;
    }
    return pthread_cond_timedwait(cond, lock, dl) != 0;
}

int conn_unusable(const tsr_net_conn *c, const char *verb, tsr_error *err)
{
    if (c->state == NET_FAILED)
        return tsr_error_set(err, c->error.code, "%s", c->error.message);
    if (c->state == NET_ENDED)
        return tsr_error_set(err, TSR_EIO, "net: cannot %s: peer '%s' at %s closed the connection", verb, c->peer_name,
                             c->address);
    return tsr_error_set(err, TSR_ESTATE, "net: cannot %s: connection to %s is not open", verb, c->address);
}

/* ---- connections ---------------------------------------------------------- */

/* One connection attempt to one resolved address (NULL for unix). Sets
 * *reached when the socket connected (so a later failure was the peer's
 * answer, not an unreachable address worth trying the next one for). */
static tsr_net_conn *connect_once(tsr_net *net, const tsr_net_address *a, const char *address,
                                  const struct addrinfo *ai, bool *reached, tsr_error *err)
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
        if (conn_wait_until(&c->cond, &net->lock, &ts)) {
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
    tsr_net_address a;
    if (tsr_net_address_parse(address, &a, err))
        return NULL;
    if (a.transport == TSR_NET_INPROC) {
        pthread_mutex_lock(&net->lock);
        tsr_net_conn *c = net_inproc_connect(net, &a, err);
        pthread_mutex_unlock(&net->lock);
        return c;
    }
    bool reached;
    if (a.transport == TSR_NET_UNIX)
        return connect_once(net, &a, address, NULL, &reached, err);
    if (!a.host[0]) {
        tsr_error_set(err, TSR_EINVAL, "net: cannot connect to %s: no host given", address);
        return NULL;
    }
    struct addrinfo *list;
    if (conn_resolve(&a, false, &list, address, "connect to", err))
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
        if (conn_wait_until(&c->cond, &net->lock, dl))
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
        if (found < count || conn_wait_until(&net->any_cond, &net->lock, dl))
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
        if (c->transport == TSR_NET_INPROC)
            net_inproc_return_credits(c);
        else if (!return_credits_direct(c, &credit))
            net_mark_dirty(c);
    }
    if (c->transport != TSR_NET_INPROC)
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
    const char *t = c->transport == TSR_NET_TCP      ? "tcp"
                    : c->transport == TSR_NET_INPROC ? "inproc"
                    : c->tx.map                      ? "unix+shm"
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
        timed_out = conn_wait_until(&c->cond, &c->net->lock, dl);
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
            if (conn_wait_until(&c->cond, &net->lock, dl))
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
    if (c->transport == TSR_NET_INPROC) {
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
