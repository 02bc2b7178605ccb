/* netlib/conn_send.c — the send path of application threads: credits
 * waited for, the shared-memory ring reserved and committed, owned and
 * copied messages queued for the I/O thread.
 * Owns the application side's credit accounting for sends. Never: touches
 * a libuv handle, waits on anything without the caller's time-out or a
 * failure to end it. */
#include <netdb.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "conn_internal.h"
#include "tessera/log.h"

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
    if (c->transport == TSR_NET_INPROC) {
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
        if (conn_wait_until(&c->cond, &net->lock, dl))
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
    if (borrowed && !net_direct_possible(c)) {        /* it waits in a queue: copy it */
        bool pooled = c->transport != TSR_NET_INPROC; /* an inproc copy becomes the peer's */
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
