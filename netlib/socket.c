/* netlib/socket.c — TCP and Unix-domain connections on the I/O thread:
 * listening, connecting, the handshake, framing, credits and time-outs.
 * Owns: every libuv handle of connections and listeners, and the read
 * parser. Runs only on the I/O thread, always with net->lock held (each
 * libuv callback takes it first). Never: allocates a message before its
 * announced length passed the limit or its credit was granted, stops
 * reading an open socket because the application is busy (heartbeats are
 * answered here, whatever the credit window), or leaves a handle open at
 * shutdown. */
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include "net_internal.h"
#include "tessera/dev/util.h"
#include "tessera/log.h"

#define NET_UNIX_SNDBUF (4 << 20) /* asked for a Unix socket's send buffer */

static void close_handles(tsr_net_conn *c);
static void arm_timer(tsr_net_conn *c);
static void start_reading(tsr_net_conn *c);
static void update_reading(tsr_net_conn *c);

/* ---- writing -------------------------------------------------------------- */

bool net_write_met_closed_peer(tsr_net_conn *c, int uv_status)
{
    if (c->transport != NET_UNIX || (uv_status != UV_EPIPE && uv_status != UV_ECONNRESET) || c->saw_eof)
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
        close_handles(c);
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
        close_handles(c);
        return;
    }
    c->last_written_ms = net_now_ms();
}

/* What an application thread's direct write left goes first. */
static void write_direct_rest(tsr_net_conn *c)
{
    net_direct_await(c);
    if (c->direct_rest && !c->handles_closing) {
        net_msg *r = c->direct_rest;
        c->direct_rest = NULL;
        write_now(c, r);
    }
}

static void write_msg(tsr_net_conn *c, net_msg *m)
{
    write_direct_rest(c);
    if (c->handles_closing) {
        net_send_copy_done(c, m);
        net_msg_free(m);
        return;
    }
    write_now(c, m);
}

static void write_control(tsr_net_conn *c, uint8_t type, const void *payload, size_t len)
{
    net_msg *m = calloc(1, sizeof *m);
    uint8_t *data = len ? malloc(len) : NULL;
    if (!m || (len && !data)) {
        free(m);
        free(data);
        net_conn_fail(c, TSR_ENOMEM, "net: out of memory writing to %s", c->address);
        close_handles(c);
        return;
    }
    if (len)
        memcpy(data, payload, len);
    m->type = type;
    m->data = data;
    m->len = len;
    write_msg(c, m);
}

/* HELLO carries the client's nonce when it has a token, WELCOME the
 * server's proof when the client asked for one (net.h, HANDSHAKE). */
static void send_hello(tsr_net_conn *c, uint8_t type, const uint8_t *auth, uint8_t features)
{
    tsr_net *net = c->net;
    uint8_t payload[NET_CONTROL_MAX];
    size_t n =
        net_hello_encode(payload, net->config.credits, net->config.max_message_bytes, net->node_name, auth, features);
    write_control(c, type, payload, n);
}

/* ---- connections in their handshake (server side) ------------------------ */

/* The peer's host: its address without the port (every Unix-domain peer
 * has the listener's address, so they count as one host). */
static size_t host_len(const tsr_net_conn *c)
{
    const char *colon = c->transport == NET_TCP ? strrchr(c->address, ':') : NULL;
    return colon ? (size_t)(colon - c->address) : strlen(c->address);
}

static bool same_host(const tsr_net_conn *a, const tsr_net_conn *b)
{
    size_t n = host_len(a);
    return n == host_len(b) && !memcmp(a->address, b->address, n);
}

static void half_open_add(tsr_net_listener *l, tsr_net_conn *c)
{
    c->half_listed = true;
    c->half_prev = l->half_tail;
    c->half_next = NULL;
    if (l->half_tail)
        l->half_tail->half_next = c;
    else
        l->half_head = c;
    l->half_tail = c;
    l->half_open++;
}

/* Leaves the list when the handshake is done, the connection closes or
 * its listener does. */
static void half_open_remove(tsr_net_conn *c)
{
    tsr_net_listener *l = c->listener;
    if (!c->half_listed || !l)
        return;
    if (c->half_prev)
        c->half_prev->half_next = c->half_next;
    else
        l->half_head = c->half_next;
    if (c->half_next)
        c->half_next->half_prev = c->half_prev;
    else
        l->half_tail = c->half_prev;
    c->half_prev = c->half_next = NULL;
    c->half_listed = false;
    l->half_open--;
}

/* Connections that never complete a handshake are closed in numbers under
 * a flood: the log says so at the 1st, 2nd, 4th, 8th... one, not for each. */
static void note_dropped(tsr_net_conn *c, const char *why)
{
    tsr_net_listener *l = c->listener;
    if (!l) {
        tsr_log(TSR_LOG_WARN, "%s", why);
        return;
    }
    unsigned n = ++l->dropped;
    if ((n & (n - 1)) == 0)
        tsr_log(TSR_LOG_WARN, "%s (%u connection%s without a handshake closed on %s so far)", why, n, n == 1 ? "" : "s",
                l->address);
}

static void flush_outbox(tsr_net_conn *c)
{
    write_direct_rest(c);
    while (c->outbox_head && !c->handles_closing) {
        net_msg *m = c->outbox_head;
        c->outbox_head = m->next;
        if (!c->outbox_head)
            c->outbox_tail = NULL;
        m->next = NULL;
        write_msg(c, m);
    }
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

static void close_handles(tsr_net_conn *c)
{
    if (c->handles_closing)
        return;
    net_direct_await(c); /* an application thread may be writing on the descriptor */
    half_open_remove(c);
    c->handles_closing = true;
    c->fd = -1;
    c->reading = false;
    if (c->state == NET_OPEN) /* nothing more can come or go */
        c->state = NET_ENDED;
    net_conn_signal(c);
    uv_close(&c->h.handle, on_handle_closed);
    uv_close((uv_handle_t *)&c->timer, on_handle_closed);
}

static void on_shutdown(uv_shutdown_t *req, int status)
{
    tsr_net_conn *c = req->data;
    pthread_mutex_lock(&c->net->lock);
    (void)status;
    c->write_side_shut = true;
    if (c->saw_eof || c->state == NET_FAILED)
        close_handles(c);
    pthread_mutex_unlock(&c->net->lock);
}

/* Graceful end: what was sent is written, the write side shuts down, and
 * the handles close once the peer's end of stream arrives (or the close
 * time-out passes). Closing without this could make the peer's kernel
 * answer a late write with a reset that discards data still unread. */
static void begin_shutdown(tsr_net_conn *c)
{
    if (c->shutting_down || c->handles_closing)
        return;
    if (c->state != NET_OPEN && c->state != NET_ENDED) {
        close_handles(c);
        return;
    }
    flush_outbox(c);
    if (c->handles_closing)
        return;
    write_control(c, NET_BYE, NULL, 0); /* tells a clean end from a crash */
    if (c->handles_closing)
        return;
    net_direct_await(c);
    c->shutting_down = true;
    c->shutdown_req.data = c;
    if (uv_shutdown(&c->shutdown_req, &c->h.stream, on_shutdown)) {
        close_handles(c);
        return;
    }
    if (!c->saw_eof)
        start_reading(c); /* to see the peer's end of stream */
    arm_timer(c);
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
        close_handles(c); /* the peer did not end its stream in time */
    } else if (c->state == NET_CONNECTING) {
        net_conn_fail(c, TSR_ETIMEDOUT, "net: cannot connect to %s: timed out after %u ms", c->address,
                      net->config.connect_timeout_ms);
        close_handles(c);
    } else if (c->state == NET_HANDSHAKE && c->is_server && !c->heard_any) {
        net_conn_fail(c, TSR_ETIMEDOUT, "net: %s sent nothing within %u ms of connecting: closed", c->address,
                      silent_ms(net));
        note_dropped(c, c->error.message);
        close_handles(c);
    } else if (c->state == NET_HANDSHAKE) {
        net_conn_fail(c, TSR_ETIMEDOUT, "net: handshake with %s timed out after %u ms (is it a tessera node?)",
                      c->address, net->config.handshake_timeout_ms);
        if (c->is_server)
            note_dropped(c, c->error.message);
        close_handles(c);
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
            close_handles(c);
        } else if (now - c->last_written_ms >= net->config.idle_timeout_ms / 3 && c->writes_in_flight == 0) {
            /* (With writes still pending the peer is not reading; more
             * pings would only pile up.) */
            write_control(c, NET_PING, NULL, 0);
        }
    }
    pthread_mutex_unlock(&net->lock);
}

static void arm_timer(tsr_net_conn *c)
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

/* ---- reading -------------------------------------------------------------- */

static void on_alloc(uv_handle_t *h, size_t suggested, uv_buf_t *buf)
{
    tsr_net_conn *c = h->data;
    (void)suggested;
    /* The rest of a large payload is read straight into the message. */
    if (c->partial && c->partial->len - c->partial_fill >= NET_STAGING_BYTES) {
        uint64_t left = c->partial->len - c->partial_fill;
        *buf =
            uv_buf_init((char *)c->partial->data + c->partial_fill, (unsigned)(left < (1u << 30) ? left : (1u << 30)));
        return;
    }
    if (!c->staging)
        c->staging = malloc(NET_STAGING_BYTES);
    *buf = uv_buf_init((char *)c->staging, c->staging ? NET_STAGING_BYTES : 0);
}

static uint32_t unreturned(const tsr_net_conn *c) { return c->inbox_count + c->held + c->credits_to_return; }

static void stop_reading(tsr_net_conn *c)
{
    if (c->reading) {
        uv_read_stop(&c->h.stream);
        c->reading = false;
    }
}

static void refuse(tsr_net_conn *c, const char *peer_name, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void refuse(tsr_net_conn *c, const char *peer_name, const char *fmt, ...)
{
    char reason[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    tsr_net_listener *l = c->listener;
    net_conn_fail(c, TSR_EPROTO, "net: refused peer '%s' from %s on %s: %s", peer_name, c->address,
                  l ? l->address : "?", reason);
    tsr_log(TSR_LOG_WARN, "%s", c->error.message);
    if (l) {
        l->refusals++;
        l->last_refusal = c->error;
    }
    write_control(c, NET_REFUSE, reason, strlen(reason));
    stop_reading(c);
    /* Let the reason reach the peer, then close (bounded by the close
     * time-out: shutting_down arms it). */
    net_direct_await(c);
    c->shutting_down = true;
    c->shutdown_req.data = c;
    if (c->handles_closing || uv_shutdown(&c->shutdown_req, &c->h.stream, on_shutdown))
        close_handles(c);
    else
        arm_timer(c);
}

static void handshake_done(tsr_net_conn *c, const net_hello *h)
{
    snprintf(c->peer_name, sizeof c->peer_name, "%s", h->name); /* escaped by net_hello_decode */
    /* The credits are the peer's window to grant; a message size it
     * announces is a ceiling, never a licence: this side builds none
     * larger than its own max_message_bytes either. */
    c->send_credits = h->credits;
    c->peer_window = h->credits;
    c->peer_max_message = h->max_message_bytes < c->net->config.max_message_bytes ? h->max_message_bytes
                                                                                  : c->net->config.max_message_bytes;
    c->state = NET_OPEN;
    c->handshaken = true;
    uv_os_fd_t fd;
    if (uv_fileno(&c->h.handle, &fd) == 0) {
        c->fd = fd; /* application threads may write on it now (direct.c) */
        if (c->transport == NET_UNIX) {
            /* A Unix socket queues only ~200 KiB by default (wmem_default),
             * so a large message never went out in one direct write; TCP
             * sizes its buffers itself (setting them would stop that). The
             * kernel caps the request at net.core.wmem_max. */
            int size = NET_UNIX_SNDBUF;
            setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &size, sizeof size);
        }
    }
    if (c->shm)
        net_shm_start(c); /* before any data: no application thread can send yet */
    arm_timer(c);
    net_conn_signal(c);
}

/* The features this side asks for in its HELLO: shared memory on a Unix
 * socket when configured (net.h, SHARED MEMORY). */
static uint8_t wanted_features(const tsr_net_conn *c)
{
    return c->transport == NET_UNIX && c->net->config.shm_ring_bytes ? NET_FEATURE_SHM : 0;
}

/* Server: the handshake succeeded (with the token proven, when this node
 * has one): answer WELCOME and queue the connection for accept. */
static void server_accept(tsr_net_conn *c, const net_hello *h, const uint8_t *proof)
{
    tsr_net_listener *l = c->listener;
    if (!l || l->closing) {
        net_conn_fail(c, TSR_ESTATE, "net: %s: listener closed during the handshake", c->address);
        close_handles(c);
        return;
    }
    unsigned waiting = 0;
    for (tsr_net_conn *r = l->ready_head; r; r = r->next_ready)
        waiting++;
    if (waiting >= NET_READY_MAX) {
        refuse(c, h->name, "%u connections already wait to be accepted on this node", waiting);
        return;
    }
    half_open_remove(c);
    uint8_t granted = h->features & wanted_features(c);
    send_hello(c, NET_WELCOME, proof, granted);
    c->shm = granted & NET_FEATURE_SHM;
    handshake_done(c, h);
    c->app_ref = true; /* held by the ready queue until accepted */
    c->ready = true;
    if (l->ready_tail)
        l->ready_tail->next_ready = c;
    else
        l->ready_head = c;
    l->ready_tail = c;
    pthread_cond_broadcast(&l->cond);
    tsr_log(TSR_LOG_INFO, "net: accepted peer '%s' from %s on %s", c->peer_name, c->address, l->address);
}

static void deliver_hello(tsr_net_conn *c, net_msg *m)
{
    tsr_net *net = c->net;
    net_hello h;
    tsr_error e;
    int bad = net_hello_decode(m->data, m->len, &h, &e);
    if (c->hello_version != net_version(net)) {
        refuse(c, bad ? "?" : h.name, "protocol version %u, this node speaks version %u", c->hello_version,
               net_version(net));
        return;
    }
    if (bad) {
        refuse(c, "?", "malformed handshake: %s", e.message);
        return;
    }
    if (!net->token[0]) {
        if (h.has_auth) /* the peer would refuse a WELCOME without proof */
            refuse(c, h.name, "this node has no token, the peer has one (give both the same token, or neither)");
        else
            server_accept(c, &h, NULL);
        return;
    }
    if (!h.has_auth) {
        refuse(c, h.name, "a token is required");
        return;
    }
    /* The client proves the token first, over both nonces; only then does
     * this side prove it (in WELCOME), so a stranger gets no proof at all. */
    c->peer_hello = h;
    memcpy(c->client_nonce, h.auth, NET_AUTH_BYTES);
    net_auth_nonce(c->server_nonce);
    c->auth_step = 1;
    write_control(c, NET_CHALLENGE, c->server_nonce, NET_AUTH_BYTES);
}

static void deliver_proof(tsr_net_conn *c, net_msg *m)
{
    tsr_net *net = c->net;
    uint8_t got[NET_AUTH_BYTES], want[NET_AUTH_BYTES];
    tsr_error e;
    if (net_auth_decode(m->data, m->len, got, "PROOF", &e)) {
        refuse(c, c->peer_hello.name, "malformed handshake: %s", e.message);
        return;
    }
    net_auth_proof(net->token, "client", c->client_nonce, c->server_nonce, want);
    if (!net_auth_equal(got, want)) {
        refuse(c, c->peer_hello.name, "token mismatch");
        return;
    }
    net_auth_proof(net->token, "server", c->client_nonce, c->server_nonce, want);
    server_accept(c, &c->peer_hello, want);
}

/* Client: the server sent its nonce; prove the token over both. */
static void deliver_challenge(tsr_net_conn *c, net_msg *m)
{
    tsr_net *net = c->net;
    tsr_error e;
    if (!net->token[0]) {
        net_conn_fail(c, TSR_EPROTO, "net: %s asks for a token (CHALLENGE), and this node ('%s') has none", c->address,
                      net->node_name);
        close_handles(c);
        return;
    }
    if (net_auth_decode(m->data, m->len, c->server_nonce, "CHALLENGE", &e)) {
        net_conn_fail(c, TSR_EPROTO, "net: %s sent a malformed handshake: %s", c->address, e.message);
        close_handles(c);
        return;
    }
    uint8_t proof[NET_AUTH_BYTES];
    net_auth_proof(net->token, "client", c->client_nonce, c->server_nonce, proof);
    c->auth_step = 1;
    write_control(c, NET_PROOF, proof, NET_AUTH_BYTES);
}

/* Client: WELCOME. With a token, it must carry the server's proof over
 * this connection's nonces: a server that does not know the token (or an
 * impostor on the port) cannot make one, and is refused. */
static void deliver_welcome(tsr_net_conn *c, net_msg *m)
{
    tsr_net *net = c->net;
    net_hello h;
    tsr_error e;
    if (net_hello_decode(m->data, m->len, &h, &e)) {
        net_conn_fail(c, TSR_EPROTO, "net: %s answered a malformed handshake: %s", c->address, e.message);
        close_handles(c);
        return;
    }
    if (net->token[0]) {
        uint8_t want[NET_AUTH_BYTES];
        net_auth_proof(net->token, "server", c->client_nonce, c->server_nonce, want);
        if (c->auth_step != 1 || !h.has_auth || !net_auth_equal(h.auth, want)) {
            net_conn_fail(c, TSR_EPROTO,
                          "net: refused the server at %s: it did not prove it knows the token (not the node "
                          "meant, or it has another token or none)",
                          c->address);
            close_handles(c);
            return;
        }
    } else if (h.has_auth) {
        net_conn_fail(c, TSR_EPROTO, "net: %s answered a malformed handshake: a proof nobody asked for", c->address);
        close_handles(c);
        return;
    }
    if (h.features & ~wanted_features(c)) {
        net_conn_fail(c, TSR_EPROTO, "net: %s answered a malformed handshake: features 0x%02x nobody asked for",
                      c->address, h.features);
        close_handles(c);
        return;
    }
    c->shm = h.features & NET_FEATURE_SHM;
    handshake_done(c, &h);
}

/* A complete message arrived. Takes ownership of m. */
static void deliver(tsr_net_conn *c, net_msg *m)
{
    tsr_net *net = c->net;
    switch (m->type) {
    case NET_HELLO:
        deliver_hello(c, m);
        net_msg_free(m);
        return;
    case NET_WELCOME:
        deliver_welcome(c, m);
        net_msg_free(m);
        return;
    case NET_CHALLENGE:
        deliver_challenge(c, m);
        net_msg_free(m);
        return;
    case NET_PROOF:
        deliver_proof(c, m);
        net_msg_free(m);
        return;
    case NET_REFUSE: {
        char reason[400];
        tsr_text_sanitize(reason, sizeof reason, m->data, (size_t)m->len);
        net_conn_fail(c, TSR_EPROTO, "net: %s refused this node ('%s'): %s", c->address, net->node_name, reason);
        close_handles(c);
        net_msg_free(m);
        return;
    }
    case NET_RING: {
        int bad = net_shm_ring_received(c, m);
        net_msg_free(m);
        if (bad)
            close_handles(c);
        return;
    }
    case NET_CREDIT: {
        uint32_t n = net_get_u32(m->data);
        uint64_t pos = c->shm ? net_get_u64(m->data + 4) : 0;
        net_msg_free(m);
        if ((uint64_t)c->send_credits + n > c->peer_window) {
            net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s returned more credits than it granted (%u)",
                          c->peer_name, c->address, c->peer_window);
            close_handles(c);
            return;
        }
        if (c->shm && net_shm_credit(c, pos)) {
            close_handles(c);
            return;
        }
        c->send_credits += n;
        net_conn_signal(c);
        update_reading(c);
        return;
    }
    case NET_PING:
        /* An empty PING asks for an answer (a PING of one byte, never
         * answered itself): a side whose idle_timeout_ms is shorter than
         * its peer's still hears from an idle peer in time. */
        /* Not while earlier writes are pending: the peer then hears
         * those, or is not reading, and answers would only pile up. */
        if (m->len == 0 && c->state == NET_OPEN && !c->shutting_down && !c->handles_closing &&
            c->writes_in_flight == 0 && !c->outbox_head && !c->direct_rest) {
            static const uint8_t answer = 1;
            write_control(c, NET_PING, &answer, 1);
        }
        net_msg_free(m);
        return;
    case NET_BYE:
        c->peer_said_bye = true;
        net_msg_free(m);
        return;
    default: break;
    }
    if (c->close_requested) { /* the application is gone: drop */
        net_msg_free(m);
        return;
    }
    if ((m->flags & NET_FLAG_SHM) && net_shm_take_descriptor(c, m)) {
        net_msg_free(m);
        close_handles(c);
        return;
    }
    m->conn = c;
    if (c->inbox_tail)
        c->inbox_tail->next = m;
    else
        c->inbox_head = m;
    c->inbox_tail = m;
    c->inbox_count++;
    c->stats.messages_received++;
    c->stats.bytes_received += m->len;
    net_conn_signal(c);
    update_reading(c);
}

/* Validates a complete header, then either starts reading its payload into
 * a new message, delivers a zero-length message at once, or fails the
 * connection (naming the peer) without allocating anything. */
static void handle_header(tsr_net_conn *c)
{
    tsr_net *net = c->net;
    net_header h;
    net_header_decode(c->hdr, &h);
    c->hdr_fill = 0;
    const char *who = c->peer_name;
    if (h.magic != TSR_NET_MAGIC) {
        net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s is not speaking the tessera protocol (magic 0x%08x)", who,
                      c->address, h.magic);
        if (c->is_server)
            tsr_log(TSR_LOG_WARN, "%s", c->error.message);
        close_handles(c);
        return;
    }
    bool handshaking = c->state == NET_HANDSHAKE;
    /* A HELLO of another version is still read (within the control limit),
     * so the refusal can name the peer when its payload parses; a REFUSE is
     * read whatever its version, so the reason reaches this side. */
    bool other_version_hello = handshaking && c->is_server && h.type == NET_HELLO && c->auth_step == 0;
    bool refusal = handshaking && !c->is_server && h.type == NET_REFUSE;
    if (other_version_hello)
        c->hello_version = h.version;
    if (h.version != net_version(net) && !refusal && !other_version_hello) {
        net_conn_fail(c, TSR_EPROTO,
                      "net: peer '%s' at %s speaks protocol version %u, this node speaks "
                      "version %u",
                      who, c->address, h.version, net_version(net));
        close_handles(c);
        return;
    }
    /* A ring descriptor (net.h, SHARED MEMORY): a data message on a
     * shared-memory connection whose peer's ring is mapped. */
    bool descriptor = h.flags == NET_FLAG_SHM && h.type >= TSR_NET_KIND_FIRST_USER && c->shm;
    if (descriptor && !c->rx.map) {
        net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s sent a shared-memory descriptor before its ring", who,
                      c->address);
        close_handles(c);
        return;
    }
    if (h.flags && !descriptor) {
        net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s sent unknown flags 0x%02x", who, c->address, h.flags);
        close_handles(c);
        return;
    }
    bool expected;
    uint64_t limit = NET_CONTROL_MAX;
    switch (h.type) {
    case NET_HELLO: expected = handshaking && c->is_server && c->auth_step == 0; break;
    case NET_PROOF:
        expected = handshaking && c->is_server && c->auth_step == 1;
        limit = NET_AUTH_BYTES;
        break;
    case NET_CHALLENGE:
        expected = handshaking && !c->is_server && c->auth_step == 0;
        limit = NET_AUTH_BYTES;
        break;
    case NET_WELCOME:
    case NET_REFUSE: expected = handshaking && !c->is_server; break;
    case NET_CREDIT:
        expected = c->state == NET_OPEN;
        limit = c->shm ? 12 : 4;
        break;
    case NET_RING:
        expected = c->state == NET_OPEN && c->shm && !c->rx.map;
        limit = 8;
        break;
    case NET_PING:
        expected = c->state == NET_OPEN;
        limit = 1;
        break;
    case NET_BYE:
        expected = c->state == NET_OPEN;
        limit = 0;
        break;
    default:
        expected = h.type >= TSR_NET_KIND_FIRST_USER && c->state == NET_OPEN && !c->peer_said_bye;
        limit = net->config.max_message_bytes;
        break;
    }
    if (!expected) {
        net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s sent message type 0x%02x %s", who, c->address, h.type,
                      handshaking ? "before completing the handshake" : "out of place");
        close_handles(c);
        return;
    }
    if ((h.type == NET_CREDIT || h.type == NET_RING || descriptor) && h.len != limit) {
        if (descriptor)
            limit = NET_SHM_DESC_BYTES;
        if (h.len != limit) {
            net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s sent a %s of %llu bytes (not %llu)", who, c->address,
                          h.type == NET_CREDIT ? "CREDIT"
                          : h.type == NET_RING ? "RING"
                                               : "shared-memory descriptor",
                          (unsigned long long)h.len, (unsigned long long)limit);
            close_handles(c);
            return;
        }
    }
    if (h.len > limit) {
        net_conn_fail(c, TSR_EPROTO,
                      "net: peer '%s' at %s announced a %llu-byte message (type 0x%02x), over "
                      "this node's limit of %llu bytes%s",
                      who, c->address, (unsigned long long)h.len, h.type, (unsigned long long)limit,
                      h.type >= TSR_NET_KIND_FIRST_USER ? " (max_message_bytes)" : "");
        close_handles(c);
        return;
    }
    if (h.type >= TSR_NET_KIND_FIRST_USER && !c->close_requested && unreturned(c) >= net->config.credits) {
        net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s sent more messages than the %u credits granted", who,
                      c->address, net->config.credits);
        close_handles(c);
        return;
    }
    net_msg *m = calloc(1, sizeof *m);
    uint64_t cap = 0;
    uint8_t *data = m ? net_payload_alloc(c, h.len, &cap) : NULL;
    if (!m || !data) {
        free(m);
        free(data);
        net_conn_fail(c, TSR_ENOMEM, "net: out of memory for a %llu-byte message from %s", (unsigned long long)h.len,
                      c->address);
        close_handles(c);
        return;
    }
    m->type = h.type;
    m->flags = h.flags;
    m->len = h.len;
    m->data = data;
    m->cap = cap;
    m->conn = c;
    if (h.len == 0) {
        deliver(c, m);
        return;
    }
    c->partial = m;
    c->partial_fill = 0;
}

static void parse_bytes(tsr_net_conn *c, const uint8_t *p, size_t n)
{
    while (n && !c->handles_closing && c->state != NET_FAILED) {
        if (c->partial) {
            uint64_t left = c->partial->len - c->partial_fill;
            size_t take = left < n ? (size_t)left : n;
            memcpy(c->partial->data + c->partial_fill, p, take);
            c->partial_fill += take;
            p += take;
            n -= take;
            if (c->partial_fill == c->partial->len) {
                net_msg *m = c->partial;
                c->partial = NULL;
                deliver(c, m);
            }
            continue;
        }
        size_t take = TSR_NET_HEADER_BYTES - c->hdr_fill;
        if (take > n)
            take = n;
        memcpy(c->hdr + c->hdr_fill, p, take);
        c->hdr_fill += take;
        p += take;
        n -= take;
        if (c->hdr_fill == TSR_NET_HEADER_BYTES)
            handle_header(c);
    }
}

static void on_peer_eof(tsr_net_conn *c)
{
    c->saw_eof = true;
    stop_reading(c);
    if (c->state == NET_CONNECTING || c->state == NET_HANDSHAKE) {
        net_conn_fail(c, TSR_EIO, "net: %s closed the connection during the handshake", c->address);
        close_handles(c);
        return;
    }
    if (c->partial || c->hdr_fill) {
        net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s ended its stream inside a message", c->peer_name,
                      c->address);
        close_handles(c);
        return;
    }
    if (c->state == NET_OPEN && !c->peer_said_bye) {
        c->vanished = true;
        net_conn_fail(c, TSR_EIO,
                      "net: peer '%s' at %s went away without closing the connection "
                      "(crashed, killed or cut off)",
                      c->peer_name, c->address);
        close_handles(c);
        return;
    }
    if (c->state == NET_OPEN) {
        c->state = NET_ENDED; /* queued messages stay readable */
        net_conn_signal(c);
    }
    if (c->write_side_shut || c->state == NET_FAILED)
        close_handles(c);
    else
        begin_shutdown(c); /* answer with our own end of stream */
}

/* TCP only: the kernel wakes this thread (and the sender's softirq pays
 * for the wake-up) each time a segment arrives, unless SO_RCVLOWAT says
 * how many bytes are worth waking for. Inside a large message that is what
 * is left of it, capped (the peer always finishes a message it started;
 * its end of stream or an error wakes the reader whatever the mark);
 * otherwise 1, so control messages and headers come through at once. The
 * idle timer looks at the bytes queued below the mark (FIONREAD), so a
 * slow peer is not taken for a silent one. */
#define NET_LOWAT_MAX (1u << 20)
static void update_lowat(tsr_net_conn *c)
{
    if (c->transport != NET_TCP || c->fd < 0 || c->handles_closing)
        return;
    uint64_t left = c->partial ? c->partial->len - c->partial_fill : 1;
    int want = (int)(left < NET_LOWAT_MAX ? left : NET_LOWAT_MAX);
    if (want != c->rcvlowat && !setsockopt(c->fd, SOL_SOCKET, SO_RCVLOWAT, &want, sizeof want))
        c->rcvlowat = want;
}

static void on_read(uv_stream_t *s, ssize_t nread, const uv_buf_t *buf)
{
    tsr_net_conn *c = s->data;
    tsr_net *net = c->net;
    pthread_mutex_lock(&net->lock);
    if (nread > 0 && !c->handles_closing) {
        c->last_heard_ms = net_now_ms();
        if (!c->heard_any) {
            c->heard_any = true;
            if (c->state == NET_HANDSHAKE && c->is_server)
                arm_timer(c); /* the full handshake time-out from here */
        }
        if (c->partial && buf->base == (char *)c->partial->data + c->partial_fill) {
            c->partial_fill += (uint64_t)nread;
            if (c->partial_fill == c->partial->len) {
                net_msg *m = c->partial;
                c->partial = NULL;
                deliver(c, m);
            }
        } else {
            parse_bytes(c, (const uint8_t *)buf->base, (size_t)nread);
        }
        if (!c->handles_closing && net_shm_check_stray_fds(c))
            close_handles(c);
        update_lowat(c);
    } else if (nread == UV_EOF) {
        on_peer_eof(c);
    } else if (nread < 0 && !c->handles_closing) {
        if (c->state == NET_CONNECTING || c->state == NET_HANDSHAKE)
            net_conn_fail(c, TSR_EIO, "net: %s closed the connection during the handshake (%s)", c->address,
                          uv_strerror((int)nread));
        else {
            c->vanished = nread == UV_ECONNRESET && c->state == NET_OPEN;
            net_conn_fail(c, TSR_EIO, "net: connection to peer '%s' at %s lost: %s", c->peer_name, c->address,
                          uv_strerror((int)nread));
        }
        close_handles(c);
    }
    pthread_mutex_unlock(&net->lock);
}

static void start_reading(tsr_net_conn *c)
{
    if (c->reading || c->handles_closing || c->saw_eof)
        return;
    int rc = uv_read_start(&c->h.stream, on_alloc, on_read);
    if (rc) {
        net_conn_fail(c, TSR_EIO, "net: cannot read from %s: %s", c->address, uv_strerror(rc));
        close_handles(c);
        return;
    }
    c->reading = true;
    c->last_heard_ms = net_now_ms();
}

/* An open socket is always read, also while the application holds a full
 * window of messages (inbox + held = credits) and is busy with them: the
 * peer has no credit left then, so only control messages can legally
 * arrive, and this thread must see them. A PING is answered and a CREDIT
 * taken whatever the application does, so a slow consumer is never taken
 * for a dead one (liveness is not flow control), and two peers that both
 * send cannot deadlock on CREDITs queued behind data. Memory stays
 * bounded: a data message beyond the credits fails the connection when
 * its header arrives, before any allocation. */
static void update_reading(tsr_net_conn *c)
{
    if (c->handles_closing || c->saw_eof)
        return;
    bool want = c->shutting_down || c->state == NET_HANDSHAKE || c->state == NET_OPEN;
    if (want)
        start_reading(c);
    else
        stop_reading(c);
}

/* ---- servicing requests from application threads -------------------------- */

void net_io_service(tsr_net_conn *c)
{
    if (!c->io_ref || c->handles_closing) {
        net_conn_maybe_free(c);
        return;
    }
    if (c->state == NET_FAILED && !c->shutting_down) { /* failed on an application thread (direct.c) */
        close_handles(c);
        return;
    }
    if (c->state == NET_OPEN && !c->shutting_down)
        flush_outbox(c);
    if (c->credits_to_return && c->state == NET_OPEN && !c->handles_closing && !c->shutting_down) {
        uint8_t payload[12];
        size_t n = net_credit_encode(c, c->credits_to_return, payload);
        c->credits_to_return = 0;
        write_control(c, NET_CREDIT, payload, n);
    }
    update_reading(c);
    if (c->close_requested)
        begin_shutdown(c);
}

void net_io_stop(tsr_net *net)
{
    for (tsr_net_listener *l = net->listeners; l; l = l->next)
        if (l->transport != NET_INPROC && l->io_ref && !uv_is_closing(&l->h.handle))
            net_io_close_listener(l);
    for (tsr_net_conn *c = net->conns; c; c = c->next_all)
        if (c->io_ref && !c->handles_closing) {
            c->close_requested = true;
            begin_shutdown(c);
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
        close_handles(c);
    } else {
        c->socket_connected = true;
        c->state = NET_HANDSHAKE;
        arm_timer(c);
        if (net->token[0])
            net_auth_nonce(c->client_nonce);
        send_hello(c, NET_HELLO, net->token[0] ? c->client_nonce : NULL, wanted_features(c));
        start_reading(c);
    }
    pthread_mutex_unlock(&net->lock);
}

static int init_stream(tsr_net *net, tsr_net_conn *c)
{
    /* An IPC pipe when shared memory may be negotiated: libuv then reads
     * with recvmsg and keeps descriptors the peer passes (shm.c). */
    int ipc = net->config.shm_ring_bytes ? 1 : 0;
    int rc = c->transport == NET_TCP ? uv_tcp_init(&net->loop, &c->h.tcp) : uv_pipe_init(&net->loop, &c->h.pipe, ipc);
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
    int rc = init_stream(net, c);
    if (rc) {
        net_conn_fail(c, TSR_EIO, "net: cannot connect to %s: %s", c->address, uv_strerror(rc));
        c->io_ref = false;
        return;
    }
    arm_timer(c);
    c->connect_req.data = c;
    if (c->transport == NET_TCP) {
        uv_tcp_nodelay(&c->h.tcp, 1);
        rc = uv_tcp_connect(&c->connect_req, &c->h.tcp, (const struct sockaddr *)&op->sockaddr, on_connect);
    } else {
        uv_pipe_connect(&c->connect_req, &c->h.pipe, op->address->path, on_connect);
    }
    if (rc) {
        net_conn_fail(c, TSR_EIO, "net: cannot connect to %s: %s", c->address, uv_strerror(rc));
        close_handles(c);
    }
}

/* ---- listening ------------------------------------------------------------ */

/* Before `c` joins the half-open list: connections still in their
 * handshake are capped per peer host and in all, and at a cap an OLD one
 * of them goes, not the newcomer: the oldest that has sent nothing, else
 * the oldest. So connections that never handshake (or are slow to) cannot
 * keep a client out: its connection has sent its HELLO, or is the newest,
 * and handshakes within a round trip. Only half-open connections count,
 * since every local client shares the loopback address: established ones
 * are never dropped here. */
static tsr_net_conn *pick_victim(tsr_net_listener *l, const tsr_net_conn *host)
{
    tsr_net_conn *oldest = NULL;
    for (tsr_net_conn *h = l->half_head; h; h = h->half_next)
        if (!host || same_host(h, host)) {
            if (!h->heard_any)
                return h;
            if (!oldest)
                oldest = h;
        }
    return oldest;
}

static void make_room(tsr_net_listener *l, tsr_net_conn *c)
{
    unsigned from_host = 0;
    for (tsr_net_conn *h = l->half_head; h; h = h->half_next)
        from_host += same_host(h, c);
    tsr_net_conn *victim = NULL;
    if (from_host >= NET_HALF_OPEN_PER_HOST)
        victim = pick_victim(l, c);
    else if (l->half_open >= NET_HALF_OPEN_MAX)
        victim = pick_victim(l, NULL);
    if (!victim)
        return;
    net_conn_fail(victim, TSR_EIO,
                  "net: dropped the connection from %s: its handshake was not done when newer connections "
                  "needed its place",
                  victim->address);
    note_dropped(victim, victim->error.message);
    close_handles(victim);
}

static void on_connection(uv_stream_t *server, int status)
{
    tsr_net_listener *l = server->data;
    tsr_net *net = l->net;
    pthread_mutex_lock(&net->lock);
    if (status < 0) {
        tsr_log(TSR_LOG_WARN, "net: accepting on %s failed: %s", l->address, uv_strerror(status));
        goto out;
    }
    tsr_net_conn *c = net_conn_new(net, l->transport, true, l->address);
    if (!c) {
        tsr_log(TSR_LOG_ERROR, "net: out of memory accepting on %s", l->address);
        goto out;
    }
    if (init_stream(net, c)) {
        c->io_ref = false;
        net_conn_maybe_free(c);
        goto out;
    }
    int rc = uv_accept(server, &c->h.stream);
    if (!rc && l->transport == NET_TCP) {
        struct sockaddr_storage peer;
        int len = sizeof peer;
        if (!uv_tcp_getpeername(&c->h.tcp, (struct sockaddr *)&peer, &len))
            net_address_format_sockaddr((struct sockaddr *)&peer, NET_TCP, c->address, sizeof c->address);
        uv_tcp_nodelay(&c->h.tcp, 1);
    } /* a Unix-domain peer has no address of its own: it keeps the listener's */
    c->listener = l;
    l->pending++;
    if (rc || l->closing) {
        net_conn_fail(c, TSR_EIO, "net: not accepted");
        close_handles(c);
        goto out;
    }
    make_room(l, c);
    half_open_add(l, c);
    arm_timer(c); /* handshake time-out */
    start_reading(c);
out:
    pthread_mutex_unlock(&net->lock);
}

static void on_listener_closed(uv_handle_t *h)
{
    tsr_net_listener *l = h->data;
    tsr_net *net = l->net;
    pthread_mutex_lock(&net->lock);
    /* Only the socket this listener bound: not a file that replaced it. */
    struct stat st;
    if (l->unix_path[0] && lstat(l->unix_path, &st) == 0 && S_ISSOCK(st.st_mode) && st.st_dev == l->unix_dev &&
        st.st_ino == l->unix_ino)
        unlink(l->unix_path);
    l->io_ref = false;
    net_listener_maybe_free(l);
    net_io_maybe_finish(net);
    pthread_mutex_unlock(&net->lock);
}

void net_io_close_listener(tsr_net_listener *l)
{
    l->closing = true;
    /* Connections still in their handshake (or refused and closing) lose
     * their listener, which may be freed before they close. */
    for (tsr_net_conn *c = l->net->conns; c; c = c->next_all)
        if (c->listener == l && !c->ready) {
            half_open_remove(c);
            c->listener = NULL;
            l->pending--;
        }
    if (!uv_is_closing(&l->h.handle))
        uv_close(&l->h.handle, on_listener_closed);
}

/* A socket file exists at `path`: is anyone listening on it? Only a
 * refused connection says no (ECONNREFUSED: nobody accepts on it). */
static bool unix_socket_is_live(const char *path)
{
    int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0)
        return true;
    struct sockaddr_un sa = {.sun_family = AF_UNIX};
    snprintf(sa.sun_path, sizeof sa.sun_path, "%s", path);
    bool live = connect(fd, (struct sockaddr *)&sa, sizeof sa) == 0 || errno != ECONNREFUSED;
    close(fd);
    return live;
}

/* Before binding a Unix socket at `path`: what is there must be nothing,
 * or a stale socket (a socket file nobody listens on, left by a process
 * that died), which is removed. Anything else is refused with one line
 * naming the path and left as it is: a regular file, a folder, a symbolic
 * link (never followed or removed), a live socket. A missing folder is
 * named as such (libuv would report EACCES for it). */
static int unix_path_prepare(const char *text, const char *path, tsr_error *err)
{
    struct stat st;
    if (lstat(path, &st) != 0) {
        if (errno != ENOENT)
            return tsr_error_set(err, TSR_EIO, "net: cannot listen on %s: cannot inspect %s: %s", text, path,
                                 strerror(errno));
        char dir[sizeof(((struct sockaddr_un *)0)->sun_path)];
        snprintf(dir, sizeof dir, "%s", path);
        char *slash = strrchr(dir, '/');
        if (!slash)
            return TSR_OK; /* in the working directory, which exists */
        if (slash == dir)
            slash[1] = '\0';
        else
            *slash = '\0';
        struct stat dst;
        if (stat(dir, &dst) != 0)
            return tsr_error_set(err, TSR_EINVAL, "net: cannot listen on %s: folder %s does not exist", text, dir);
        if (!S_ISDIR(dst.st_mode))
            return tsr_error_set(err, TSR_EINVAL, "net: cannot listen on %s: %s is not a folder", text, dir);
        return TSR_OK;
    }
    if (S_ISLNK(st.st_mode))
        return tsr_error_set(err, TSR_EINVAL,
                             "net: cannot listen on %s: %s is a symbolic link, not a socket "
                             "(left as it is)",
                             text, path);
    if (S_ISDIR(st.st_mode))
        return tsr_error_set(err, TSR_EINVAL, "net: cannot listen on %s: %s is a folder, not a socket", text, path);
    if (!S_ISSOCK(st.st_mode))
        return tsr_error_set(err, TSR_EINVAL,
                             "net: cannot listen on %s: %s exists and is not a socket (%s; left as "
                             "it is)",
                             text, path, S_ISREG(st.st_mode) ? "a regular file" : "a special file");
    if (unix_socket_is_live(path))
        return tsr_error_set(err, TSR_EINVAL,
                             "net: cannot listen on %s: address already in use (another listener "
                             "has %s)",
                             text, path);
    /* Stale. Removed only if it is still the same socket file. */
    struct stat again;
    if (lstat(path, &again) == 0 && S_ISSOCK(again.st_mode) && again.st_ino == st.st_ino && again.st_dev == st.st_dev &&
        unlink(path) != 0 && errno != ENOENT)
        return tsr_error_set(err, TSR_EIO, "net: cannot listen on %s: cannot remove the stale socket %s: %s", text,
                             path, strerror(errno));
    tsr_log(TSR_LOG_INFO, "net: replaced the stale socket %s (nobody listened on it)", path);
    return TSR_OK;
}

void net_io_listen(tsr_net *net, net_op *op)
{
    tsr_net_listener *l = op->target;
    const net_address *a = op->address;
    const char *text = l->address;
    int rc = l->transport == NET_TCP ? uv_tcp_init(&net->loop, &l->h.tcp) : uv_pipe_init(&net->loop, &l->h.pipe, 0);
    if (rc) {
        l->io_ref = false;
        op->rc = tsr_error_set(&op->err, TSR_EIO, "net: cannot listen on %s: %s", text, uv_strerror(rc));
        return;
    }
    l->h.handle.data = l;
    if (l->transport == NET_TCP) {
        rc = uv_tcp_bind(&l->h.tcp, (const struct sockaddr *)&op->sockaddr, 0);
    } else {
        op->rc = unix_path_prepare(text, a->path, &op->err);
        if (op->rc) {
            l->closing = true;
            uv_close(&l->h.handle, on_listener_closed);
            return;
        }
        rc = uv_pipe_bind(&l->h.pipe, a->path);
        struct stat st;
        if (!rc && lstat(a->path, &st) == 0) { /* ours: removed when the listener closes */
            snprintf(l->unix_path, sizeof l->unix_path, "%s", a->path);
            l->unix_dev = st.st_dev;
            l->unix_ino = st.st_ino;
        }
    }
    if (!rc)
        rc = uv_listen(&l->h.stream, 128, on_connection);
    if (rc) {
        /* (A Unix path that appeared since it was checked lands here too.) */
        op->rc = tsr_error_set(&op->err, rc == UV_EADDRINUSE ? TSR_EINVAL : TSR_EIO, "net: cannot listen on %s: %s%s",
                               text, uv_strerror(rc), rc == UV_EADDRINUSE ? " (another listener has it)" : "");
        l->closing = true;
        uv_close(&l->h.handle, on_listener_closed);
        return;
    }
    if (l->transport == NET_TCP) {
        struct sockaddr_storage sa;
        int len = sizeof sa;
        if (!uv_tcp_getsockname(&l->h.tcp, (struct sockaddr *)&sa, &len))
            net_address_format_sockaddr((struct sockaddr *)&sa, NET_TCP, l->address, sizeof l->address);
    } else {
        snprintf(l->address, sizeof l->address, "unix:%s", a->path);
    }
    op->rc = TSR_OK;
}
