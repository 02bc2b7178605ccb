/* netlib/direct.c — writing a message from the application thread that
 * sends it (or releases what it received: the CREDIT), straight to the
 * socket, when the connection's write side is idle: nothing queued, nothing
 * in libuv's hands, no other direct write.
 * Owns: the hand-over of the write side between an application thread and
 * the I/O thread (direct_writer, direct_rest in net_internal.h).
 * Never: touches a libuv handle, blocks in the kernel (the socket is
 * non-blocking and MSG_DONTWAIT is passed), raises SIGPIPE in the caller's
 * thread (MSG_NOSIGNAL), or writes while the I/O thread may.
 *
 * Why: handing each message to the I/O thread costs a wake-up of that
 * thread (uv_async), and each wake-up costs tens of microseconds in a VM;
 * with 1 MiB messages the sender's hand-over and the receiver's credit
 * hand-over were a good part of the stream's time (bench/README.md). The
 * kernel copy is the same work on either thread. What the socket does not
 * take at once (its buffer is full: the peer reads slower) is left to the
 * I/O thread, which writes it before anything else when the socket drains,
 * exactly as if the message had been queued.
 *
 * Tried and measured worse (bench/README.md, third pass): writing only the
 * first half of a large message here and leaving the rest to the I/O
 * thread, to share the kernel's send work between the two cores. The I/O
 * thread then seldom finished before the next buffer came, so most buffers
 * were copied and queued whole, and the receiving side, which shares the
 * other core with the I/O thread, fell behind (the packer waited for
 * credits 2-4 times longer). */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/uio.h>

#include "net_internal.h"

bool net_direct_possible(const tsr_net_conn *c)
{
    return c->transport != TSR_NET_INPROC && c->fd >= 0 && c->io_ref && c->state == NET_OPEN && !c->close_requested &&
           !c->handles_closing && !c->shutting_down && !c->direct_writer && !c->direct_awaited && !c->direct_rest &&
           !c->outbox_head && c->writes_in_flight == 0;
}

/* Writes what the socket takes of m without blocking. */
static void write_some(int fd, net_msg *m)
{
    const uint64_t total = TSR_NET_HEADER_BYTES + m->len;
    while (m->written < total) {
        struct iovec iov[2];
        int n = 0;
        if (m->written < TSR_NET_HEADER_BYTES) {
            iov[n].iov_base = m->header + m->written;
            iov[n].iov_len = TSR_NET_HEADER_BYTES - (size_t)m->written;
            n++;
        }
        uint64_t at = m->written > TSR_NET_HEADER_BYTES ? m->written - TSR_NET_HEADER_BYTES : 0;
        if (m->len > at) {
            uint64_t left = m->len - at;
            iov[n].iov_base = m->data + at;
            iov[n].iov_len = (size_t)(left < (1u << 30) ? left : (1u << 30));
            n++;
        }
        struct msghdr mh = {.msg_iov = iov, .msg_iovlen = (size_t)n};
        ssize_t w = sendmsg(fd, &mh, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (w > 0)
            m->written += (uint64_t)w;
        else if (w < 0 && errno == EINTR)
            continue;
        else
            return; /* full (EAGAIN), or an error libuv meets again and reports */
    }
}

net_msg *net_direct_write(tsr_net_conn *c, net_msg *m)
{
    tsr_net *net = c->net;
    net_header_encode(m->header, net_version(net), m->type, m->flags, m->len);
    m->conn = c;
    m->written = 0;
    m->next = NULL;
    c->direct_writer = true;
    int fd = c->fd;
    /* Unlocked: the I/O thread leaves the write side, the descriptor and
     * the handles alone while direct_writer is set (net_direct_await), and
     * the caller is the connection's only sending thread. */
    pthread_mutex_unlock(&net->lock);
    write_some(fd, m);
    uint8_t *copy = NULL;
    uint64_t copy_cap = 0;
    bool partial = m->written < TSR_NET_HEADER_BYTES + m->len;
    if (partial && m->borrowed) {
        /* The caller's memory is the caller's again on return: copy what
         * is not written yet into a reused buffer (at the same offsets, so
         * the message stays one payload for the I/O thread). The lock is
         * taken only to pick the buffer: direct_writer stays set, so the
         * I/O thread leaves the rest alone until it is copied. */
        pthread_mutex_lock(&net->lock);
        copy = net_send_copy_alloc(c, m->len, &copy_cap);
        if (!copy)
            c->send_copies--; /* nothing to count */
        pthread_mutex_unlock(&net->lock);
        uint64_t at = m->written > TSR_NET_HEADER_BYTES ? m->written - TSR_NET_HEADER_BYTES : 0;
        if (copy && m->len > at)
            memcpy(copy + at, m->data + at, (size_t)(m->len - at));
    }
    pthread_mutex_lock(&net->lock);
    c->direct_writer = false;
    if (c->direct_awaited)
        pthread_cond_broadcast(&c->cond);
    if (m->written)
        c->last_written_ms = net_now_ms();
    if (m->type >= TSR_NET_KIND_FIRST_USER)
        c->stats.messages_direct++;
    if (m->written == TSR_NET_HEADER_BYTES + m->len) {
        net_send_copy_done(c, m); /* a queued copy: its buffer may serve the next one */
        return m;
    }
    if (m->type >= TSR_NET_KIND_FIRST_USER)
        c->stats.messages_direct_rest++;
    if (m->borrowed) {
        if (!copy) {
            /* Half a message is on the wire: the stream cannot go on. */
            net_conn_fail(c, TSR_ENOMEM, "net: out of memory for a %llu-byte message to %s", (unsigned long long)m->len,
                          c->address);
            net_mark_dirty(c); /* the I/O thread closes it */
            return m;
        }
        m->data = copy;
        m->cap = copy_cap;
        m->copy = true;    /* counted in send_copies; recycled once written */
        m->release = NULL; /* free() */
        m->borrowed = false;
    }
    /* The rest goes before anything else the I/O thread writes, so the
     * stream stays whole; it also meets a write error again and fails the
     * connection with the usual message. */
    c->direct_rest = m;
    net_mark_dirty(c);
    return NULL;
}

void net_direct_await(tsr_net_conn *c)
{
    if (!c->direct_writer)
        return;
    /* No new direct write starts until this thread has the lock back
     * (net_direct_possible), so a busy sender cannot starve the loop. */
    c->direct_awaited = true;
    while (c->direct_writer)
        pthread_cond_wait(&c->cond, &c->net->lock);
    c->direct_awaited = false;
}
