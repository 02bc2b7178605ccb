/* netlib/inproc.c — the in-process transport ("inproc:NAME"): two
 * connection objects linked to each other inside one tsr_net.
 * Owns: moving a sent message straight into the peer's inbox and credits
 * straight back, with the same credit rules as the socket transports.
 * Never: uses the I/O thread or a socket, or copies a message twice. */
#include <stdio.h>
#include <string.h>

#include "net_internal.h"

static tsr_net_listener *find_listener(tsr_net *net, const char *name)
{
    for (tsr_net_listener *l = net->listeners; l; l = l->next)
        if (l->transport == TSR_NET_INPROC && !l->closing && !strcmp(l->inproc_name, name))
            return l;
    return NULL;
}

int net_inproc_listen(tsr_net *net, const tsr_net_address *a, tsr_net_listener *l, tsr_error *err)
{
    if (find_listener(net, a->name))
        return tsr_error_set(err, TSR_EINVAL, "net: cannot listen on inproc:%s: address already in use", a->name);
    snprintf(l->inproc_name, sizeof l->inproc_name, "%s", a->name);
    snprintf(l->address, sizeof l->address, "inproc:%s", a->name);
    l->next = net->listeners;
    net->listeners = l;
    return TSR_OK;
}

static void open_side(tsr_net_conn *c, tsr_net_conn *peer)
{
    tsr_net *net = c->net;
    c->state = NET_OPEN;
    c->app_ref = true;
    c->inproc_peer = peer;
    c->send_credits = net->config.credits;
    c->peer_window = net->config.credits;
    c->peer_max_message = net->config.max_message_bytes;
    snprintf(c->peer_name, sizeof c->peer_name, "%s", net->node_name);
}

tsr_net_conn *net_inproc_connect(tsr_net *net, const tsr_net_address *a, tsr_error *err)
{
    char address[TSR_NET_ADDRESS_MAX];
    snprintf(address, sizeof address, "inproc:%s", a->name);
    tsr_net_listener *l = find_listener(net, a->name);
    if (!l || net->stopping) {
        tsr_error_set(err, TSR_ENOENT, "net: cannot connect to %s: connection refused (nothing listens on it)",
                      address);
        return NULL;
    }
    if (l->pending >= NET_READY_MAX) { /* inproc peers are ready at once: pending counts ready ones */
        tsr_error_set(err, TSR_EIO, "net: cannot connect to %s: %u connections wait to be accepted", address,
                      l->pending);
        return NULL;
    }
    /* Both ends share this tsr_net's configuration, so the handshake's
     * version and token checks cannot fail here; credits and the message
     * limit still apply exactly as over a socket. */
    tsr_net_conn *client = net_conn_new(net, TSR_NET_INPROC, false, address);
    tsr_net_conn *server = client ? net_conn_new(net, TSR_NET_INPROC, true, address) : NULL;
    if (!server) {
        if (client)
            net_conn_maybe_free(client);
        tsr_error_set(err, TSR_ENOMEM, "net: out of memory");
        return NULL;
    }
    open_side(client, server);
    open_side(server, client);
    server->listener = l;
    server->ready = true;
    if (l->ready_tail)
        l->ready_tail->next_ready = server;
    else
        l->ready_head = server;
    l->ready_tail = server;
    l->pending++;
    pthread_cond_broadcast(&l->cond);
    return client;
}

void net_inproc_deliver(tsr_net_conn *from, net_msg *m)
{
    tsr_net_conn *to = from->inproc_peer;
    if (!to || to->close_requested) {
        net_msg_free(m); /* the peer is gone: like bytes sent into a closed socket */
        return;
    }
    m->conn = to;
    if (to->inbox_tail)
        to->inbox_tail->next = m;
    else
        to->inbox_head = m;
    to->inbox_tail = m;
    to->inbox_count++;
    to->stats.messages_received++;
    to->stats.bytes_received += m->len;
    net_conn_signal(to);
}

void net_inproc_return_credits(tsr_net_conn *c)
{
    tsr_net_conn *peer = c->inproc_peer;
    if (peer) {
        peer->send_credits += c->credits_to_return;
        net_conn_signal(peer);
    }
    c->credits_to_return = 0;
}

void net_inproc_close(tsr_net_conn *c)
{
    tsr_net_conn *peer = c->inproc_peer;
    if (peer) {
        peer->inproc_peer = NULL;
        if (peer->state == NET_OPEN)
            peer->state = NET_ENDED;
        net_conn_signal(peer);
    }
    c->inproc_peer = NULL;
    c->close_requested = true;
    c->app_ref = false;
    while (c->inbox_head) {
        net_msg *m = c->inbox_head;
        c->inbox_head = m->next;
        net_msg_free(m);
    }
    c->inbox_tail = NULL;
    c->inbox_count = 0;
    net_conn_signal(c);
    net_conn_maybe_free(c);
}
