/* netlib/socket_handshake.c — the handshake of a socket connection: HELLO,
 * CHALLENGE, PROOF and WELCOME delivered and answered, features agreed,
 * refusals named with the peer.
 * Owns nothing past the connection's handshake fields. Runs on the I/O
 * thread with net->lock held. Never: lets a connection carry application
 * messages before its handshake is done. */
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
    sock_write_control(c, NET_REFUSE, reason, strlen(reason));
    sock_stop_reading(c);
    /* Let the reason reach the peer, then close (bounded by the close
     * time-out: shutting_down arms it). */
    net_direct_await(c);
    c->shutting_down = true;
    c->shutdown_req.data = c;
    if (c->handles_closing || uv_shutdown(&c->shutdown_req, &c->h.stream, sock_on_shutdown))
        sock_close_handles(c);
    else
        sock_arm_timer(c);
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
        if (c->transport == TSR_NET_UNIX) {
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
    sock_arm_timer(c);
    net_conn_signal(c);
}

/* The features this side asks for in its HELLO: shared memory on a Unix
 * socket when configured (net.h, SHARED MEMORY). */
uint8_t sock_wanted_features(const tsr_net_conn *c)
{
    return c->transport == TSR_NET_UNIX && c->net->config.shm_ring_bytes ? NET_FEATURE_SHM : 0;
}

/* Server: the handshake succeeded (with the token proven, when this node
 * has one): answer WELCOME and queue the connection for accept. */
static void server_accept(tsr_net_conn *c, const net_hello *h, const uint8_t *proof)
{
    tsr_net_listener *l = c->listener;
    if (!l || l->closing) {
        net_conn_fail(c, TSR_ESTATE, "net: %s: listener closed during the handshake", c->address);
        sock_close_handles(c);
        return;
    }
    unsigned waiting = 0;
    for (tsr_net_conn *r = l->ready_head; r; r = r->next_ready)
        waiting++;
    if (waiting >= NET_READY_MAX) {
        refuse(c, h->name, "%u connections already wait to be accepted on this node", waiting);
        return;
    }
    sock_half_open_remove(c);
    uint8_t granted = h->features & sock_wanted_features(c);
    sock_send_hello(c, NET_WELCOME, proof, granted);
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

void sock_deliver_hello(tsr_net_conn *c, net_msg *m)
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
    sock_write_control(c, NET_CHALLENGE, c->server_nonce, NET_AUTH_BYTES);
}

void sock_deliver_proof(tsr_net_conn *c, net_msg *m)
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
void sock_deliver_challenge(tsr_net_conn *c, net_msg *m)
{
    tsr_net *net = c->net;
    tsr_error e;
    if (!net->token[0]) {
        net_conn_fail(c, TSR_EPROTO, "net: %s asks for a token (CHALLENGE), and this node ('%s') has none", c->address,
                      net->node_name);
        sock_close_handles(c);
        return;
    }
    if (net_auth_decode(m->data, m->len, c->server_nonce, "CHALLENGE", &e)) {
        net_conn_fail(c, TSR_EPROTO, "net: %s sent a malformed handshake: %s", c->address, e.message);
        sock_close_handles(c);
        return;
    }
    uint8_t proof[NET_AUTH_BYTES];
    net_auth_proof(net->token, "client", c->client_nonce, c->server_nonce, proof);
    c->auth_step = 1;
    sock_write_control(c, NET_PROOF, proof, NET_AUTH_BYTES);
}

/* Client: WELCOME. With a token, it must carry the server's proof over
 * this connection's nonces: a server that does not know the token (or an
 * impostor on the port) cannot make one, and is refused. */
void sock_deliver_welcome(tsr_net_conn *c, net_msg *m)
{
    tsr_net *net = c->net;
    net_hello h;
    tsr_error e;
    if (net_hello_decode(m->data, m->len, &h, &e)) {
        net_conn_fail(c, TSR_EPROTO, "net: %s answered a malformed handshake: %s", c->address, e.message);
        sock_close_handles(c);
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
            sock_close_handles(c);
            return;
        }
    } else if (h.has_auth) {
        net_conn_fail(c, TSR_EPROTO, "net: %s answered a malformed handshake: a proof nobody asked for", c->address);
        sock_close_handles(c);
        return;
    }
    if (h.features & ~sock_wanted_features(c)) {
        net_conn_fail(c, TSR_EPROTO, "net: %s answered a malformed handshake: features 0x%02x nobody asked for",
                      c->address, h.features);
        sock_close_handles(c);
        return;
    }
    c->shm = h.features & NET_FEATURE_SHM;
    handshake_done(c, &h);
}
