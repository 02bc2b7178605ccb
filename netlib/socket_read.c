/* netlib/socket_read.c — the read path of a socket connection: buffers,
 * the frame parser (header, length and credit checks before any
 * allocation), delivery of each complete message, end of stream, and when
 * to read at all (credits, low-water mark).
 * Owns the read parser's state in each connection. Runs on the I/O thread
 * with net->lock held. Never: allocates a message before its announced
 * length passed the limit or its credit was granted, stops reading an open
 * socket because the application is busy. */
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

void sock_stop_reading(tsr_net_conn *c)
{
    if (c->reading) {
        uv_read_stop(&c->h.stream);
        c->reading = false;
    }
}

/* A complete message arrived. Takes ownership of m. */
static void deliver(tsr_net_conn *c, net_msg *m)
{
    tsr_net *net = c->net;
    switch (m->type) {
    case NET_HELLO:
        sock_deliver_hello(c, m);
        net_msg_free(m);
        return;
    case NET_WELCOME:
        sock_deliver_welcome(c, m);
        net_msg_free(m);
        return;
    case NET_CHALLENGE:
        sock_deliver_challenge(c, m);
        net_msg_free(m);
        return;
    case NET_PROOF:
        sock_deliver_proof(c, m);
        net_msg_free(m);
        return;
    case NET_REFUSE: {
        char reason[400];
        tsr_text_sanitize(reason, sizeof reason, m->data, (size_t)m->len);
        net_conn_fail(c, TSR_EPROTO, "net: %s refused this node ('%s'): %s", c->address, net->node_name, reason);
        sock_close_handles(c);
        net_msg_free(m);
        return;
    }
    case NET_RING: {
        int bad = net_shm_ring_received(c, m);
        net_msg_free(m);
        if (bad)
            sock_close_handles(c);
        return;
    }
    case NET_CREDIT: {
        uint32_t n = net_get_u32(m->data);
        uint64_t pos = c->shm ? net_get_u64(m->data + 4) : 0;
        net_msg_free(m);
        if ((uint64_t)c->send_credits + n > c->peer_window) {
            net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s returned more credits than it granted (%u)",
                          c->peer_name, c->address, c->peer_window);
            sock_close_handles(c);
            return;
        }
        if (c->shm && net_shm_credit(c, pos)) {
            sock_close_handles(c);
            return;
        }
        c->send_credits += n;
        net_conn_signal(c);
        sock_update_reading(c);
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
            sock_write_control(c, NET_PING, &answer, 1);
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
        sock_close_handles(c);
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
    sock_update_reading(c);
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
        sock_close_handles(c);
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
        sock_close_handles(c);
        return;
    }
    /* A ring descriptor (net.h, SHARED MEMORY): a data message on a
     * shared-memory connection whose peer's ring is mapped. */
    bool descriptor = h.flags == NET_FLAG_SHM && h.type >= TSR_NET_KIND_FIRST_USER && c->shm;
    if (descriptor && !c->rx.map) {
        net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s sent a shared-memory descriptor before its ring", who,
                      c->address);
        sock_close_handles(c);
        return;
    }
    if (h.flags && !descriptor) {
        net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s sent unknown flags 0x%02x", who, c->address, h.flags);
        sock_close_handles(c);
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
        sock_close_handles(c);
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
            sock_close_handles(c);
            return;
        }
    }
    if (h.len > limit) {
        net_conn_fail(c, TSR_EPROTO,
                      "net: peer '%s' at %s announced a %llu-byte message (type 0x%02x), over "
                      "this node's limit of %llu bytes%s",
                      who, c->address, (unsigned long long)h.len, h.type, (unsigned long long)limit,
                      h.type >= TSR_NET_KIND_FIRST_USER ? " (max_message_bytes)" : "");
        sock_close_handles(c);
        return;
    }
    if (h.type >= TSR_NET_KIND_FIRST_USER && !c->close_requested && unreturned(c) >= net->config.credits) {
        net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s sent more messages than the %u credits granted", who,
                      c->address, net->config.credits);
        sock_close_handles(c);
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
        sock_close_handles(c);
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
    sock_stop_reading(c);
    if (c->state == NET_CONNECTING || c->state == NET_HANDSHAKE) {
        net_conn_fail(c, TSR_EIO, "net: %s closed the connection during the handshake", c->address);
        sock_close_handles(c);
        return;
    }
    if (c->partial || c->hdr_fill) {
        net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s ended its stream inside a message", c->peer_name,
                      c->address);
        sock_close_handles(c);
        return;
    }
    if (c->state == NET_OPEN && !c->peer_said_bye) {
        c->vanished = true;
        net_conn_fail(c, TSR_EIO,
                      "net: peer '%s' at %s went away without closing the connection "
                      "(crashed, killed or cut off)",
                      c->peer_name, c->address);
        sock_close_handles(c);
        return;
    }
    if (c->state == NET_OPEN) {
        c->state = NET_ENDED; /* queued messages stay readable */
        net_conn_signal(c);
    }
    if (c->write_side_shut || c->state == NET_FAILED)
        sock_close_handles(c);
    else
        sock_begin_shutdown(c); /* answer with our own end of stream */
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
    if (c->transport != TSR_NET_TCP || c->fd < 0 || c->handles_closing)
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
                sock_arm_timer(c); /* the full handshake time-out from here */
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
            sock_close_handles(c);
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
        sock_close_handles(c);
    }
    pthread_mutex_unlock(&net->lock);
}

void sock_start_reading(tsr_net_conn *c)
{
    if (c->reading || c->handles_closing || c->saw_eof)
        return;
    int rc = uv_read_start(&c->h.stream, on_alloc, on_read);
    if (rc) {
        net_conn_fail(c, TSR_EIO, "net: cannot read from %s: %s", c->address, uv_strerror(rc));
        sock_close_handles(c);
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
void sock_update_reading(tsr_net_conn *c)
{
    if (c->handles_closing || c->saw_eof)
        return;
    bool want = c->shutting_down || c->state == NET_HANDSHAKE || c->state == NET_OPEN;
    if (want)
        sock_start_reading(c);
    else
        sock_stop_reading(c);
}
