/* netlib/socket.c — TCP and Unix-domain connections on the I/O thread:
 * listening, connecting, the handshake, framing, credits and time-outs.
 * Owns: every libuv handle of connections and listeners, and the read
 * parser. Runs only on the I/O thread, always with net->lock held (each
 * libuv callback takes it first). Never: allocates a message before its
 * announced length passed the limit or its credit was granted, stops
 * reading an open socket because the application is busy (heartbeats are
 * answered here, whatever the credit window), or leaves a handle open at
 * shutdown.
 *
 * This file: the write path, closing, time-outs, the requests of
 * application threads, connecting. socket_read.c, socket_handshake.c and
 * socket_admit.c do the rest (socket_internal.h). */
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include "socket_internal.h"
#include "tessera/dev/util.h"
#include "tessera/log.h"


/* ---- writing -------------------------------------------------------------- */

bool net_write_met_closed_peer(tsr_net_conn *c, int uv_status)
{
    if (c->transport != TSR_NET_UNIX || (uv_status != UV_EPIPE && uv_status != UV_ECONNRESET) || c->saw_eof)
        return false;
    if (!c->peer_stopped_reading)
        tsr_log(TSR_LOG_DEBUG, "net: peer '%s' at %s closed its end: reading what it sent before", c->peer_name,
                c->address);
    c->peer_stopped_reading = true;
    return true;
}

static void on_write(uv_write_t *req, int status)
{
    net_msg *m = req->data;
    tsr_net_conn *c = m->conn;
    tsr_net *net = c->net;
    pthread_mutex_lock(&net->lock);
    c->writes_in_flight--;
    net_send_copy_done(c, m); /* its buffer may serve the next copy */
    if (c->flush_waiters)
        pthread_cond_broadcast(&c->cond);
    if (status < 0 && status != UV_ECANCELED && !c->handles_closing && !net_write_met_closed_peer(c, status)) {
        net_conn_fail(c, TSR_EIO, "net: writing to peer '%s' at %s failed: %s", c->peer_name, c->address,
                      uv_strerror(status));
        sock_close_handles(c);
    }
    pthread_mutex_unlock(&net->lock);
    net_msg_free(m); /* outside the lock: a caller's release() may take its own */
}

/* Hands one message (header + payload, less what a direct write already
 * put on the socket) to libuv. */
static void write_now(tsr_net_conn *c, net_msg *m)
{
    if (c->peer_stopped_reading) { /* it would only meet EPIPE again */
        net_send_copy_done(c, m);
        net_msg_free(m);
        return;
    }
    net_header_encode(m->header, net_version(c->net), m->type, m->flags, m->len);
    /* Set .len directly: uv_buf_init() takes an unsigned int, and a
     * message may be longer than 4 GiB (uv_buf_t.len is a size_t here). */
    uv_buf_t bufs[2];
    unsigned n = 0;
    if (m->written < TSR_NET_HEADER_BYTES)
        bufs[n++] = uv_buf_init((char *)m->header + m->written, (unsigned)(TSR_NET_HEADER_BYTES - m->written));
    uint64_t at = m->written > TSR_NET_HEADER_BYTES ? m->written - TSR_NET_HEADER_BYTES : 0;
    if (m->len > at) {
        bufs[n] = uv_buf_init((char *)m->data + at, 0);
        bufs[n++].len = (size_t)(m->len - at);
    }
    m->conn = c;
    m->write_req.data = m;
    /* uv_write writes what the socket takes at once: for a large message
     * that is a long kernel copy. Application threads must not wait for it
     * to queue their next message (the sender would stall on the lock while
     * its previous buffer is copied), so the lock is dropped around it.
     * Safe: only this thread touches libuv handles or frees `c` while it
     * holds io_ref, libuv never runs the write callback from inside
     * uv_write, and `m` is no longer in any list other threads see. The
     * write counts as in flight from here, so no application thread starts
     * a direct write meanwhile (direct.c). */
    bool unlock = m->len - at >= NET_STAGING_BYTES;
    c->writes_in_flight++;
    if (unlock)
        pthread_mutex_unlock(&c->net->lock);
    int rc = uv_write(&m->write_req, &c->h.stream, bufs, n, on_write);
    if (unlock)
        pthread_mutex_lock(&c->net->lock);
    if (rc) {
        c->writes_in_flight--;
        net_conn_fail(c, TSR_EIO, "net: writing to %s failed: %s", c->address, uv_strerror(rc));
        net_send_copy_done(c, m);
        net_msg_free(m);
        sock_close_handles(c);
        return;
    }
    c->last_written_ms = net_now_ms();
}

/* What an application thread's direct write left goes first. */
void sock_write_direct_rest(tsr_net_conn *c)
{
    net_direct_await(c);
    if (c->direct_rest && !c->handles_closing) {
        net_msg *r = c->direct_rest;
        c->direct_rest = NULL;
        write_now(c, r);
    }
}

void sock_write_msg(tsr_net_conn *c, net_msg *m)
{
    sock_write_direct_rest(c);
    if (c->handles_closing) {
        net_send_copy_done(c, m);
        net_msg_free(m);
        return;
    }
    write_now(c, m);
}

void sock_write_control(tsr_net_conn *c, uint8_t type, const void *payload, size_t len)
{
    net_msg *m = calloc(1, sizeof *m);
    uint8_t *data = len ? malloc(len) : NULL;
    if (!m || (len && !data)) {
        free(m);
        free(data);
        net_conn_fail(c, TSR_ENOMEM, "net: out of memory writing to %s", c->address);
        sock_close_handles(c);
        return;
    }
    if (len)
        memcpy(data, payload, len);
    m->type = type;
    m->data = data;
    m->len = len;
    sock_write_msg(c, m);
}

/* HELLO carries the client's nonce when it has a token, WELCOME the
 * server's proof when the client asked for one (net.h, HANDSHAKE). */
void sock_send_hello(tsr_net_conn *c, uint8_t type, const uint8_t *auth, uint8_t features)
{
    tsr_net *net = c->net;
    uint8_t payload[NET_CONTROL_MAX];
    size_t n =
        net_hello_encode(payload, net->config.credits, net->config.max_message_bytes, net->node_name, auth, features);
    sock_write_control(c, type, payload, n);
}

/* ---- closing -------------------------------------------------------------- */

static void on_handle_closed(uv_handle_t *h)
{
    tsr_net_conn *c = h->data;
    tsr_net *net = c->net;
    pthread_mutex_lock(&net->lock);
    if (--c->handles_open == 0) {
        c->io_ref = false;
        if (c->listener && !c->ready) {
            c->listener->pending--; /* never reached the ready queue */
            c->listener = NULL;
        }
        net_conn_signal(c);
        net_conn_maybe_free(c);
        net_io_maybe_finish(net);
    }
    pthread_mutex_unlock(&net->lock);
}

void sock_close_handles(tsr_net_conn *c)
{
    if (c->handles_closing)
        return;
    net_direct_await(c); /* an application thread may be writing on the descriptor */
    sock_half_open_remove(c);
    c->handles_closing = true;
    c->fd = -1;
    c->reading = false;
    if (c->state == NET_OPEN) /* nothing more can come or go */
        c->state = NET_ENDED;
    net_conn_signal(c);
    uv_close(&c->h.handle, on_handle_closed);
    uv_close((uv_handle_t *)&c->timer, on_handle_closed);
}

void sock_on_shutdown(uv_shutdown_t *req, int status)
{
    tsr_net_conn *c = req->data;
    pthread_mutex_lock(&c->net->lock);
    (void)status;
    c->write_side_shut = true;
    if (c->saw_eof || c->state == NET_FAILED)
        sock_close_handles(c);
    pthread_mutex_unlock(&c->net->lock);
}

/* Graceful end: what was sent is written, the write side shuts down, and
 * the handles close once the peer's end of stream arrives (or the close
 * time-out passes). Closing without this could make the peer's kernel
 * answer a late write with a reset that discards data still unread. */
void sock_begin_shutdown(tsr_net_conn *c)
{
    if (c->shutting_down || c->handles_closing)
        return;
    if (c->state != NET_OPEN && c->state != NET_ENDED) {
        sock_close_handles(c);
        return;
    }
    sock_flush_outbox(c);
    if (c->handles_closing)
        return;
    sock_write_control(c, NET_BYE, NULL, 0); /* tells a clean end from a crash */
    if (c->handles_closing)
        return;
    net_direct_await(c);
    c->shutting_down = true;
    c->shutdown_req.data = c;
    if (uv_shutdown(&c->shutdown_req, &c->h.stream, sock_on_shutdown)) {
        sock_close_handles(c);
        return;
    }
    if (!c->saw_eof)
        sock_start_reading(c); /* to see the peer's end of stream */
    sock_arm_timer(c);
}

/* ---- timers --------------------------------------------------------------- */

/* A client sends its HELLO as soon as its connect completes, so a
 * connection that said nothing for this long is not one: it is closed
 * before the full handshake time-out, and cannot hold a place for long. */
static uint32_t silent_ms(const tsr_net *net)
{
    uint32_t h = net->config.handshake_timeout_ms;
    return h < NET_SILENT_MS ? h : NET_SILENT_MS;
}

static void on_timer(uv_timer_t *t)
{
    tsr_net_conn *c = t->data;
    tsr_net *net = c->net;
    pthread_mutex_lock(&net->lock);
    uint64_t now = net_now_ms();
    if (c->handles_closing) {
        /* nothing */
    } else if (c->shutting_down) {
        sock_close_handles(c); /* the peer did not end its stream in time */
    } else if (c->state == NET_CONNECTING) {
        net_conn_fail(c, TSR_ETIMEDOUT, "net: cannot connect to %s: timed out after %u ms", c->address,
                      net->config.connect_timeout_ms);
        sock_close_handles(c);
    } else if (c->state == NET_HANDSHAKE && c->is_server && !c->heard_any) {
        net_conn_fail(c, TSR_ETIMEDOUT, "net: %s sent nothing within %u ms of connecting: closed", c->address,
                      silent_ms(net));
        sock_note_dropped(c, c->error.message);
        sock_close_handles(c);
    } else if (c->state == NET_HANDSHAKE) {
        net_conn_fail(c, TSR_ETIMEDOUT, "net: handshake with %s timed out after %u ms (is it a tessera node?)",
                      c->address, net->config.handshake_timeout_ms);
        if (c->is_server)
            sock_note_dropped(c, c->error.message);
        sock_close_handles(c);
    } else if (c->state == NET_OPEN && net->config.idle_timeout_ms) {
        int queued;
        if (c->rcvlowat > 1 && ioctl(c->fd, FIONREAD, &queued) == 0 && queued != c->lowat_queued) {
            /* Bytes below the low-water mark (update_lowat) still arrive:
             * a slow peer, not a silent one. */
            c->lowat_queued = queued;
            c->last_heard_ms = now;
        }
        if (now - c->last_heard_ms >= net->config.idle_timeout_ms) {
            /* TSR_EIO, not TSR_ETIMEDOUT: that one means only that a
             * caller's own wait ended with the connection still fine
             * (tsr_net_recv with a time-out), and a poll loop reading it
             * as "nothing yet" would poll a dead connection forever. */
            if (c->state != NET_FAILED)
                c->went_silent = true;
            net_conn_fail(c, TSR_EIO,
                          "net: peer '%s' at %s sent nothing for %u ms (idle_timeout_ms): "
                          "considered dead",
                          c->peer_name, c->address, net->config.idle_timeout_ms);
            sock_close_handles(c);
        } else if (now - c->last_written_ms >= net->config.idle_timeout_ms / 3 && c->writes_in_flight == 0) {
            /* (With writes still pending the peer is not reading; more
             * pings would only pile up.) */
            sock_write_control(c, NET_PING, NULL, 0);
        }
    }
    pthread_mutex_unlock(&net->lock);
}

void sock_arm_timer(tsr_net_conn *c)
{
    const tsr_net_config *cfg = &c->net->config;
    uv_timer_stop(&c->timer);
    if (c->handles_closing)
        return;
    if (c->shutting_down)
        uv_timer_start(&c->timer, on_timer, cfg->close_timeout_ms, 0);
    else if (c->state == NET_CONNECTING)
        uv_timer_start(&c->timer, on_timer, cfg->connect_timeout_ms, 0);
    else if (c->state == NET_HANDSHAKE && c->is_server && !c->heard_any)
        uv_timer_start(&c->timer, on_timer, silent_ms(c->net), 0);
    else if (c->state == NET_HANDSHAKE)
        uv_timer_start(&c->timer, on_timer, cfg->handshake_timeout_ms, 0);
    else if (c->state == NET_OPEN && cfg->idle_timeout_ms) {
        uint64_t tick = cfg->idle_timeout_ms / 6 ? cfg->idle_timeout_ms / 6 : 1;
        c->last_heard_ms = net_now_ms();
        uv_timer_start(&c->timer, on_timer, tick, tick);
    }
}

/* ---- servicing requests from application threads -------------------------- */

void net_io_service(tsr_net_conn *c)
{
    if (!c->io_ref || c->handles_closing) {
        net_conn_maybe_free(c);
        return;
    }
    if (c->state == NET_FAILED && !c->shutting_down) { /* failed on an application thread (direct.c) */
        sock_close_handles(c);
        return;
    }
    if (c->state == NET_OPEN && !c->shutting_down)
        sock_flush_outbox(c);
    if (c->credits_to_return && c->state == NET_OPEN && !c->handles_closing && !c->shutting_down) {
        uint8_t payload[12];
        size_t n = net_credit_encode(c, c->credits_to_return, payload);
        c->credits_to_return = 0;
        sock_write_control(c, NET_CREDIT, payload, n);
    }
    sock_update_reading(c);
    if (c->close_requested)
        sock_begin_shutdown(c);
}

void net_io_stop(tsr_net *net)
{
    for (tsr_net_listener *l = net->listeners; l; l = l->next)
        if (l->transport != TSR_NET_INPROC && l->io_ref && !uv_is_closing(&l->h.handle))
            net_io_close_listener(l);
    for (tsr_net_conn *c = net->conns; c; c = c->next_all)
        if (c->io_ref && !c->handles_closing) {
            c->close_requested = true;
            sock_begin_shutdown(c);
        }
}

/* ---- connecting ----------------------------------------------------------- */

static void on_connect(uv_connect_t *req, int status)
{
    tsr_net_conn *c = req->data;
    tsr_net *net = c->net;
    pthread_mutex_lock(&net->lock);
    if (c->handles_closing) {
        /* closed meanwhile (time-out or shutdown) */
    } else if (status < 0) {
        net_conn_fail(c, TSR_EIO, "net: cannot connect to %s: %s", c->address, uv_strerror(status));
        sock_close_handles(c);
    } else {
        c->socket_connected = true;
        c->state = NET_HANDSHAKE;
        sock_arm_timer(c);
        if (net->token[0])
            net_auth_nonce(c->client_nonce);
        sock_send_hello(c, NET_HELLO, net->token[0] ? c->client_nonce : NULL, sock_wanted_features(c));
        sock_start_reading(c);
    }
    pthread_mutex_unlock(&net->lock);
}

int sock_init_stream(tsr_net *net, tsr_net_conn *c)
{
    /* An IPC pipe when shared memory may be negotiated: libuv then reads
     * with recvmsg and keeps descriptors the peer passes (shm.c). */
    int ipc = net->config.shm_ring_bytes ? 1 : 0;
    int rc =
        c->transport == TSR_NET_TCP ? uv_tcp_init(&net->loop, &c->h.tcp) : uv_pipe_init(&net->loop, &c->h.pipe, ipc);
    if (rc)
        return rc;
    c->h.handle.data = c;
    uv_timer_init(&net->loop, &c->timer);
    c->timer.data = c;
    c->handles_open = 2;
    return 0;
}

void net_io_connect(tsr_net *net, net_op *op)
{
    tsr_net_conn *c = op->target;
    op->rc = TSR_OK;
    int rc = sock_init_stream(net, c);
    if (rc) {
        net_conn_fail(c, TSR_EIO, "net: cannot connect to %s: %s", c->address, uv_strerror(rc));
        c->io_ref = false;
        return;
    }
    sock_arm_timer(c);
    c->connect_req.data = c;
    if (c->transport == TSR_NET_TCP) {
        uv_tcp_nodelay(&c->h.tcp, 1);
        rc = uv_tcp_connect(&c->connect_req, &c->h.tcp, (const struct sockaddr *)&op->sockaddr, on_connect);
    } else {
        uv_pipe_connect(&c->connect_req, &c->h.pipe, op->address->path, on_connect);
    }
    if (rc) {
        net_conn_fail(c, TSR_EIO, "net: cannot connect to %s: %s", c->address, uv_strerror(rc));
        sock_close_handles(c);
    }
}
