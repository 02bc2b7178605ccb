/* mothership/plan.c — each node's configuration: its chain's links with
 * the options the graph leaves to the run filled in (peers' addresses,
 * tiles, groups), its listen address, and the CONFIG message sent.
 * Owns nothing past a call. Never: builds or re-parses chain text to learn
 * what an SPU is (the classes declare their roles), compares SPU names. */
#include <errno.h>
#include <ftw.h>
#include <limits.h>
#include <libgen.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "tessera/dev/util.h"
#include "ms_internal.h"
#include "tessera/dev/net.h"
#include "control.h"
#include "tessera/spu.h"
#include "util.h"

/* --- plan ------------------------------------------------------------- */

typedef struct strbuf {
    char *s;
    size_t len, cap;
    int failed;
} strbuf;

static void sb_add(strbuf *b, const char *s, size_t n)
{
    if (b->failed)
        return;
    if (b->len + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap * 2 : 256;
        while (cap < b->len + n + 1)
            cap *= 2;
        char *p = realloc(b->s, cap);
        if (!p) {
            b->failed = 1;
            return;
        }
        b->s = p;
        b->cap = cap;
    }
    memcpy(b->s + b->len, s, n);
    b->len += n;
    b->s[b->len] = '\0';
}

static void sb_str(strbuf *b, const char *s) { sb_add(b, s, strlen(s)); }

/* "X:Y:W:H" of a graph tile (tessera/tiles.h), after `prefix`. */
static void sb_tile(strbuf *b, const char *prefix, const tsr_graph_tile *t)
{
    char text[80];
    snprintf(text, sizeof text, "%s%d:%d:%d:%d", prefix, t->x, t->y, t->width, t->height);
    sb_str(b, text);
}

/* The node's own tiles, "X:Y:W:H,..." (its `tiles:`). */
static void own_tiles(const tsr_graph_node *g, strbuf *list)
{
    for (size_t t = 0; t < g->tile_count; t++)
        sb_tile(list, t ? "," : "", &g->tiles[t]);
}

/* Every server's tiles, "S:X:Y:W:H,..." (S = index in `to:`). */
static void server_tiles(const ms *m, const tsr_graph_node *g, strbuf *list)
{
    for (size_t s = 0; s < g->to_count; s++) {
        const tsr_graph_node *server = m->nodes[g->to[s]].g;
        for (size_t t = 0; t < server->tile_count; t++) {
            char prefix[24];
            snprintf(prefix, sizeof prefix, "%s%zu:", list->len ? "," : "", s);
            sb_tile(list, prefix, &server->tiles[t]);
        }
    }
}

/* The role of node `i`'s network SPU; NONE without one. */
tsr_spu_role ms_role_of(const ms *m, size_t i)
{
    return m->nodes[i].network ? m->nodes[i].network->network.role : TSR_SPU_ROLE_NONE;
}

/* The group of node `n`: the nodes sending to its first server with the
 * same role, in the graph's order (tessera/spu.h: rank, peers). Returns
 * n's place in it; `addresses` (may be NULL) gets the members' addresses. */
static int group_of(const ms *m, const ms_node *n, strbuf *addresses)
{
    const tsr_graph_node *server = m->nodes[n->g->to[0]].g;
    int rank = -1, members = 0;
    for (size_t f = 0; f < server->from_count; f++) {
        const ms_node *member = &m->nodes[server->from[f]];
        if (ms_role_of(m, member->index) != ms_role_of(m, n->index))
            continue;
        if (member == n)
            rank = members;
        if (addresses) {
            sb_str(addresses, members ? "," : "");
            sb_str(addresses, member->address);
        }
        members++;
    }
    return rank;
}

/* The addresses of the node's servers, in `to:` order. */
static void server_addresses(const ms *m, const tsr_graph_node *g, strbuf *list)
{
    for (size_t t = 0; t < g->to_count; t++) {
        sb_str(list, t ? "," : "");
        sb_str(list, m->nodes[g->to[t]].address);
    }
}

/* The values a graph run gives one link's options, as its class declares
 * them (tsr_spu_class.network): the node's own tiles for any SPU that takes
 * them; addresses, the token, server tiles, rank and peers for the node's
 * network SPU only. */
#define MAX_FILLED 8
typedef struct filled {
    const char *option[MAX_FILLED];
    strbuf value[MAX_FILLED];
    size_t count;
} filled;

static strbuf *fill(filled *f, const char *option)
{
    f->option[f->count] = option;
    return &f->value[f->count++];
}

static int fill_link(const ms *m, const ms_node *n, const tsr_spu_class *cls, int network, filled *f, tsr_error *err)
{
    const tsr_graph_node *g = n->g;
    const tsr_spu_network *role = &cls->network;
    if (role->tiles && g->tile_count)
        own_tiles(g, fill(f, role->tiles));
    if (!network)
        return TSR_OK;
    const char *one = role->server ? role->server : role->display;
    if (one && g->to_count != 1)
        return tsr_error_set(err, TSR_EINVAL, "node '%s': SPU %s sends to one server, but to: names %zu", g->name,
                             cls->name, g->to_count);
    if (one)
        server_addresses(m, g, fill(f, one));
    if (role->servers)
        server_addresses(m, g, fill(f, role->servers));
    if (role->token && m->cfg->token && m->cfg->token[0])
        sb_str(fill(f, role->token), m->cfg->token);
    if (role->server_tiles) {
        strbuf list = {0};
        server_tiles(m, g, &list);
        if (list.len)
            *fill(f, role->server_tiles) = list; /* none: the graph's value stays */
        else
            free(list.s);
    }
    if (role->rank) {
        char text[24];
        snprintf(text, sizeof text, "%d", group_of(m, n, NULL));
        sb_str(fill(f, role->rank), text);
    }
    if (role->peers)
        group_of(m, n, fill(f, role->peers));
    return TSR_OK;
}

/* The node's chain as structured links, one "link=SPU" field each followed
 * by its "option=KEY=VALUE" fields (control.h): the graph's options, then
 * the mothership's values (fill_link), which replace the graph's for the
 * same option. Each link is checked against its class as the node will
 * parse it, so a filled value that does not parse fails here. */
int ms_add_links(ms *m, const ms_node *n, tsr_ctl_out *out, tsr_error *err)
{
    const tsr_graph_node *g = n->g;
    int rc = TSR_OK;
    for (size_t i = 0; i < g->chain_length && rc == TSR_OK; i++) {
        const tsr_chain_link *l = &g->chain[i];
        tsr_error e = {0};
        const tsr_spu_class *cls = tsr_spu_find(l->spu, &e);
        if (!cls)
            return tsr_error_set(err, TSR_EINVAL, "node '%s': %s", g->name, e.message);
        filled f = {0};
        rc = fill_link(m, n, cls, i == n->network_link, &f, err);
        size_t total = l->option_count + f.count;
        const char **keys = calloc(total ? total : 1, sizeof *keys);
        const char **values = calloc(total ? total : 1, sizeof *values);
        if (rc == TSR_OK && (!keys || !values))
            rc = tsr_error_set(err, TSR_ENOMEM, "node '%s': out of memory", g->name);
        size_t count = 0;
        for (size_t k = 0; k < l->option_count && rc == TSR_OK; k++) {
            int replaced = 0;
            for (size_t j = 0; j < f.count; j++)
                replaced |= !strcmp(l->keys[k], f.option[j]);
            if (!replaced) {
                keys[count] = l->keys[k];
                values[count++] = l->values[k];
            }
        }
        for (size_t j = 0; j < f.count && rc == TSR_OK; j++) {
            if (f.value[j].failed)
                rc = tsr_error_set(err, TSR_ENOMEM, "node '%s': out of memory", g->name);
            keys[count] = f.option[j];
            values[count++] = f.value[j].s ? f.value[j].s : "";
        }
        if (rc == TSR_OK && tsr_spu_check_options(cls, keys, values, count, &e) != TSR_OK)
            rc = tsr_error_set(err, TSR_EINVAL, "node '%s': %s", g->name, e.message);
        if (rc == TSR_OK) {
            tsr_ctl_add(out, "link", l->spu);
            for (size_t k = 0; k < count; k++) {
                /* Values may be long (every server's tiles): no fixed buffer. */
                size_t size = strlen(keys[k]) + strlen(values[k]) + 2;
                char *field = malloc(size);
                if (field) {
                    snprintf(field, size, "%s=%s", keys[k], values[k]);
                    tsr_ctl_add(out, "option", field);
                } else {
                    out->failed = 1;
                }
                free(field);
            }
        }
        for (size_t j = 0; j < f.count; j++)
            free(f.value[j].s);
        free(keys);
        free(values);
    }
    return rc;
}

/* Where a server listens: listen=ADDR when the graph names a host (or a
 * unix path), else listen_port=PORT and the node picks the host
 * (loopback unless its --bind says otherwise). */
static void add_listen(tsr_ctl_out *out, const tsr_graph_node *g)
{
    tsr_net_transport transport = g->transport == TSR_TRANSPORT_UNIX ? TSR_NET_UNIX : TSR_NET_TCP;
    tsr_net_address place = {.transport = transport};
    char text[TSR_NET_ADDRESS_MAX];
    /* The graph was checked (netlib checked each place), so this parses. */
    if (g->listen && tsr_net_listen_spec_parse("listen", g->listen, transport, &place, NULL) != TSR_OK)
        return;
    if (transport == TSR_NET_TCP && !place.host[0])
        tsr_ctl_addf(out, "listen_port", "%u", place.port);
    else if (tsr_net_address_format(&place, text, sizeof text, NULL) == TSR_OK)
        tsr_ctl_add(out, "listen", text);
}

int ms_send_ctl(tsr_net_conn *conn, unsigned kind, tsr_ctl_out *out, tsr_error *err)
{
    if (out->failed)
        return tsr_error_set(err, TSR_ENOMEM, "control message: out of memory");
    return tsr_net_send(conn, kind, out->text ? out->text : "", out->len, 2000, err);
}

uint32_t ms_heartbeat_ms(const ms *m)
{
    uint32_t hb = m->cfg->timeout_ms / 5;
    return hb < 10 ? 10 : hb > 1000 ? 1000 : hb;
}

int ms_send_config(ms *m, ms_node *n, tsr_error *err)
{
    const tsr_graph_node *g = n->g;
    tsr_ctl_out out;
    tsr_ctl_out_init(&out);
    tsr_ctl_add(&out, "name", g->name);
    tsr_ctl_add(&out, "role", n->server ? "server" : "app");
    int rc = TSR_OK;
    if (n->links_later)
        tsr_ctl_add(&out, "links", "later");
    else
        rc = ms_add_links(m, n, &out, err);
    if (rc != TSR_OK) {
        tsr_ctl_out_free(&out);
        return rc == TSR_ENOMEM ? rc : TSR_EINVAL;
    }
    tsr_ctl_addf(&out, "heartbeat_ms", "%u", ms_heartbeat_ms(m));
    for (size_t i = 0; i < g->chain_length; i++) {
        const tsr_chain_link *l = &g->chain[i];
        for (size_t k = 0; k < l->option_count; k++) {
            if (strcmp(l->keys[k], "output") && strcmp(l->keys[k], "file"))
                continue;
            char dir[PATH_MAX];
            snprintf(dir, sizeof dir, "%s", l->values[k]);
            char *slash = strrchr(dir, '/');
            if (!slash || slash == dir)
                continue;
            *slash = '\0';
            tsr_ctl_add(&out, "mkdir", dir);
        }
    }
    tsr_ctl_add(&out, "base", m->graph_dir);
    if (m->cfg->token && m->cfg->token[0])
        tsr_ctl_add(&out, "token", m->cfg->token);
    if (n->server) {
        add_listen(&out, g);
        tsr_ctl_addf(&out, "clients", "%zu", g->from_count);
        uint32_t wait = m->cfg->join_timeout_ms > 60000 ? m->cfg->join_timeout_ms : 60000;
        tsr_ctl_addf(&out, "timeout_ms", "%u", wait);
        /* A client (the application's stream client) silent this long is
         * stopped or dead: the server drops it, which ends the run. */
        tsr_ctl_addf(&out, "idle_timeout_ms", "%u", m->cfg->timeout_ms);
    } else {
        const char *const *argv = m->cfg->app_exec ? m->cfg->app_exec : g->exec;
        if (m->cfg->exec_argv && m->cfg->exec_node && !strcmp(m->cfg->exec_node, g->name))
            argv = m->cfg->exec_argv;
        for (size_t i = 0; argv[i]; i++)
            tsr_ctl_add(&out, "arg", argv[i]);
    }
    rc = ms_send_ctl(n->conn, TSR_MS_MSG_CONFIG, &out, err);
    tsr_ctl_out_free(&out);
    return rc;
}
