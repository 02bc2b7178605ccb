/* netlib/conn_listen.c — listeners on the application side: listen on an
 * address (resolved here), accept with a time-out, the refusals counted,
 * close; and whether an address is local.
 * Owns the lifetime of listener objects. Never: touches a libuv handle
 * (the I/O thread does, socket_admit.c), waits without a time-out. */
#include <netdb.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "conn_internal.h"
#include "tessera/log.h"

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
int conn_resolve(const tsr_net_address *a, bool passive, struct addrinfo **out, const char *text, const char *verb,
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
    tsr_net_address a;
    if (tsr_net_address_parse(address, &a, err))
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
    if (a.transport == TSR_NET_TCP) {
        struct addrinfo *ai;
        if (conn_resolve(&a, true, &ai, address, "listen on", err)) {
            pthread_cond_destroy(&l->cond);
            free(l);
            return NULL;
        }
        memcpy(&op.sockaddr, ai->ai_addr, ai->ai_addrlen);
        freeaddrinfo(ai);
    }
    pthread_mutex_lock(&net->lock);
    int rc;
    if (a.transport == TSR_NET_INPROC) {
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
    tsr_net_address a;
    int rc = tsr_net_address_parse(address, &a, err);
    if (rc)
        return rc;
    if (a.transport != TSR_NET_TCP || !a.host[0])
        return 1;
    struct addrinfo *list;
    rc = conn_resolve(&a, true, &list, address, "listen on", err);
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
        if (conn_wait_until(&l->cond, &net->lock, dl))
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
        if (c->transport == TSR_NET_INPROC) {
            net_inproc_close(c);
        } else {
            c->app_ref = false;
            c->close_requested = true;
            net_mark_dirty(c);
        }
    }
    l->ready_tail = NULL;
    l->app_ref = false;
    if (l->transport == TSR_NET_INPROC) {
        net_listener_maybe_free(l);
    } else if (!net->stopping) {
        net_op op = {.kind = NET_OP_CLOSE_LISTENER, .target = l};
        net_submit_op(net, &op);
    }
    pthread_mutex_unlock(&net->lock);
}
