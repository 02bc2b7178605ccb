/* netlib/socket_admit.c — listeners and admission: listening on TCP and
 * Unix-domain addresses (a stale socket file replaced, a live one left
 * alone), accepting connections, and the half-open list that caps
 * connections still in their handshake per peer host and in all.
 * Owns the listeners' libuv handles. Runs on the I/O thread with
 * net->lock held. Never: drops an established connection to make room,
 * removes a socket file another process still listens on. */
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

/* ---- connections in their handshake (server side) ------------------------ */

/* The peer's host: its address without the port (every Unix-domain peer
 * has the listener's address, so they count as one host). */
static size_t host_len(const tsr_net_conn *c)
{
    const char *colon = c->transport == TSR_NET_TCP ? strrchr(c->address, ':') : NULL;
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
void sock_half_open_remove(tsr_net_conn *c)
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
void sock_note_dropped(tsr_net_conn *c, const char *why)
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

void sock_flush_outbox(tsr_net_conn *c)
{
    sock_write_direct_rest(c);
    while (c->outbox_head && !c->handles_closing) {
        net_msg *m = c->outbox_head;
        c->outbox_head = m->next;
        if (!c->outbox_head)
            c->outbox_tail = NULL;
        m->next = NULL;
        sock_write_msg(c, m);
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
    sock_note_dropped(victim, victim->error.message);
    sock_close_handles(victim);
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
    if (sock_init_stream(net, c)) {
        c->io_ref = false;
        net_conn_maybe_free(c);
        goto out;
    }
    int rc = uv_accept(server, &c->h.stream);
    if (!rc && l->transport == TSR_NET_TCP) {
        struct sockaddr_storage peer;
        int len = sizeof peer;
        if (!uv_tcp_getpeername(&c->h.tcp, (struct sockaddr *)&peer, &len))
            net_address_format_sockaddr((struct sockaddr *)&peer, TSR_NET_TCP, c->address, sizeof c->address);
        uv_tcp_nodelay(&c->h.tcp, 1);
    } /* a Unix-domain peer has no address of its own: it keeps the listener's */
    c->listener = l;
    l->pending++;
    if (rc || l->closing) {
        net_conn_fail(c, TSR_EIO, "net: not accepted");
        sock_close_handles(c);
        goto out;
    }
    make_room(l, c);
    half_open_add(l, c);
    sock_arm_timer(c); /* handshake time-out */
    sock_start_reading(c);
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
            sock_half_open_remove(c);
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
    const tsr_net_address *a = op->address;
    const char *text = l->address;
    int rc = l->transport == TSR_NET_TCP ? uv_tcp_init(&net->loop, &l->h.tcp) : uv_pipe_init(&net->loop, &l->h.pipe, 0);
    if (rc) {
        l->io_ref = false;
        op->rc = tsr_error_set(&op->err, TSR_EIO, "net: cannot listen on %s: %s", text, uv_strerror(rc));
        return;
    }
    l->h.handle.data = l;
    if (l->transport == TSR_NET_TCP) {
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
    if (l->transport == TSR_NET_TCP) {
        struct sockaddr_storage sa;
        int len = sizeof sa;
        if (!uv_tcp_getsockname(&l->h.tcp, (struct sockaddr *)&sa, &len))
            net_address_format_sockaddr((struct sockaddr *)&sa, TSR_NET_TCP, l->address, sizeof l->address);
    } else {
        snprintf(l->address, sizeof l->address, "unix:%s", a->path);
    }
    op->rc = TSR_OK;
}
