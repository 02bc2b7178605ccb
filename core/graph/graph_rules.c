/* core/graph/graph_rules.c — the rules between nodes: edges resolved,
 * roles (who serves whom, displays, grids), cycles, listen addresses that
 * collide, transports, and the order servers start in; each in n log n
 * and without recursion.
 * Owns nothing. Never: recurses over the graph, accepts what the node or
 * `tessera run` would refuse for a reason visible in the file. */
#include <arpa/inet.h>
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <yaml.h>

#include "tessera/dev/util.h"
#include "tessera/graph.h"
#include "tessera/spu.h"

#include "graph_internal.h"
#include "groups.h"

/* ---- rules between nodes ----------------------------------------------------------- */

int graph_resolve_edges(loader *l)
{
    tsr_graph *g = l->graph;
    const char **names = malloc(g->node_count * sizeof *names);
    size_t *incoming = calloc(g->node_count, sizeof *incoming);
    size_t *listed_by = calloc(g->node_count, sizeof *listed_by); /* i + 1: node i's `to` has it */
    int rc = TSR_OK;
    if (!names || !incoming || !listed_by) {
        rc = graph_out_of_memory(l, NULL);
        goto done;
    }
    for (size_t i = 0; i < g->node_count; i++)
        names[i] = g->nodes[i].name;
    for (size_t i = 0; i < g->node_count && rc == TSR_OK; i++) {
        tsr_graph_node *node = &g->nodes[i];
        node_source *src = &l->sources[i];
        size_t *to = graph_alloc(g, (node->to_count ? node->to_count : 1) * sizeof *to);
        if (!to) {
            rc = graph_out_of_memory(l, src->name);
            break;
        }
        for (size_t e = 0; e < node->to_count && rc == TSR_OK; e++) {
            yaml_node_t *at = src->to_names[e];
            const char *target = graph_scalar_text(at);
            const tsr_graph_node *server = NULL;
            size_t j = graph_find_node(g, target);
            if (j != SIZE_MAX) {
                server = &g->nodes[j];
                to[e] = j;
            }
            if (!server) {
                const char *hint = tsr_closest_name(target, names, g->node_count);
                char suggestion[200] = "";
                if (hint)
                    snprintf(suggestion, sizeof suggestion, " (did you mean '%s'?)", hint);
                rc = graph_fail_at(l, at, TSR_EINVAL, "node '%s': 'to' names '%.80s', which is not a node%s",
                                   node->name, target, suggestion);
            } else if (server == node) {
                rc = graph_fail_at(l, at, TSR_EINVAL, "node '%s' sends to itself (a cycle)", node->name);
            } else if (server->exec) {
                rc = graph_fail_at(l, at, TSR_EINVAL,
                                   "node '%s': 'to' names '%s', an app node (it has 'exec'); only servers "
                                   "receive streams",
                                   node->name, target);
            }
            if (rc == TSR_OK && listed_by[to[e]] == i + 1)
                rc = graph_fail_at(l, at, TSR_EINVAL, "node '%s': 'to' lists '%s' twice", node->name, target);
            if (rc == TSR_OK) {
                listed_by[to[e]] = i + 1;
                incoming[to[e]]++;
            }
        }
        node->to = to;
        g->edge_count += node->to_count;
    }
    for (size_t i = 0; i < g->node_count && rc == TSR_OK; i++) {
        size_t *from = graph_alloc(g, (incoming[i] ? incoming[i] : 1) * sizeof *from);
        if (!from) {
            rc = graph_out_of_memory(l, l->sources[i].name);
            break;
        }
        g->nodes[i].from = from;
    }
    for (size_t i = 0; i < g->node_count && rc == TSR_OK; i++)
        for (size_t e = 0; e < g->nodes[i].to_count; e++) {
            tsr_graph_node *server = &g->nodes[g->nodes[i].to[e]];
            ((size_t *)server->from)[server->from_count++] = i;
        }
done:
    free(names);
    free(incoming);
    free(listed_by);
    return rc;
}

/* The role of node `i`'s network SPU; NONE without one. */
static tsr_spu_role role_of(const loader *l, size_t i)
{
    return l->sources[i].network ? l->sources[i].network->network.role : TSR_SPU_ROLE_NONE;
}

/* ROLE_DISPLAY: the node sends its tile images to ONE display node, and
 * the nodes whose images meet on one display own disjoint parts of the
 * window (a node without tiles sends all of it), or the assembled window
 * would depend on which image arrived last. */
static int check_display(loader *l, size_t i)
{
    tsr_graph *g = l->graph;
    const tsr_graph_node *node = &g->nodes[i];
    const node_source *src = &l->sources[i];
    if (node->to_count != 1)
        return graph_fail_at(l, src->to_key, TSR_EINVAL,
                             "node '%s': %s sends its tile images to one display node, but 'to' "
                             "names %zu",
                             node->name, graph_scalar_text(src->network_spu), node->to_count);
    const tsr_graph_node *display = &g->nodes[node->to[0]];
    /* Once, at the display's last sender of images: all of them in one
     * sweep, each node without tiles as the whole window. */
    size_t senders = 0, total = 0;
    for (size_t f = 0; f < display->from_count; f++) {
        size_t s = display->from[f];
        if (role_of(l, s) != TSR_SPU_ROLE_DISPLAY)
            continue;
        if (s > i)
            return TSR_OK;
        senders++;
        total += g->nodes[s].tile_count ? g->nodes[s].tile_count : 1;
    }
    if (senders < 2)
        return TSR_OK;
    tsr_graph_tile *tiles = malloc(total * sizeof *tiles);
    size_t *owner = malloc(total * sizeof *owner);
    int rc = tiles && owner ? TSR_OK : TSR_ENOMEM;
    size_t n = 0;
    for (size_t f = 0; f < display->from_count && rc == TSR_OK; f++) {
        size_t s = display->from[f];
        const tsr_graph_node *sender = &g->nodes[s];
        if (role_of(l, s) != TSR_SPU_ROLE_DISPLAY)
            continue;
        if (!sender->tile_count) {
            owner[n] = s;
            tiles[n++] = (tsr_graph_tile){0, 0, g->width, g->height};
        }
        for (size_t t = 0; t < sender->tile_count; t++) {
            owner[n] = s;
            tiles[n++] = sender->tiles[t];
        }
    }
    size_t a, b;
    /* A node's own tiles do not overlap (graph_parse_tiles): a and b are two nodes. */
    if (rc == TSR_OK && graph_find_overlap(tiles, n, g->height, &a, &b, &rc)) {
        if (owner[a] > owner[b]) {
            size_t swap = a;
            a = b;
            b = swap;
        }
        const tsr_graph_node *later = &g->nodes[owner[b]], *earlier = &g->nodes[owner[a]];
        const tsr_graph_tile *ta = &tiles[b], *tb = &tiles[a];
        rc = graph_fail_at(l, l->sources[owner[b]].to_names[0], TSR_EINVAL,
                           "node '%s': its %s [%d, %d, %d, %d] overlaps node '%s''s %s "
                           "[%d, %d, %d, %d], and both send images to display '%s'",
                           later->name, later->tile_count ? "tile" : "window", ta->x, ta->y, ta->width, ta->height,
                           earlier->name, earlier->tile_count ? "tile" : "window", tb->x, tb->y, tb->width, tb->height,
                           display->name);
    } else if (rc != TSR_OK) {
        rc = graph_out_of_memory(l, src->to_names[0]);
    }
    free(tiles);
    free(owner);
    return rc;
}

/* A grid of tiled servers (tsr_spu_network.grid): one server per cell,
 * and the grid, not `tiles:`, places them (the window it divides is the
 * program's, known only at run time, and re-divided at every resize). */
static int check_grid(loader *l, size_t i)
{
    tsr_graph *g = l->graph;
    const tsr_graph_node *node = &g->nodes[i];
    const node_source *src = &l->sources[i];
    const char *spu = graph_scalar_text(src->network_spu), *option = src->network->network.grid;
    int columns = src->grid_columns, rows = src->grid_rows;
    if (columns < 1 || rows < 1)
        return graph_fail_at(l, src->grid_value, TSR_EINVAL,
                             "node '%s': %s %s: expected [COLUMNS, ROWS], both at least 1 ([0, 0]: the servers' "
                             "tiles: as given)",
                             node->name, spu, option);
    if ((size_t)columns * (size_t)rows != node->to_count)
        return graph_fail_at(l, src->grid_value, TSR_EINVAL,
                             "node '%s': %s %s: [%d, %d] has %lld cells, but 'to' names %zu server%s (one server per "
                             "cell, in 'to' order)",
                             node->name, spu, option, columns, rows, (long long)columns * rows, node->to_count,
                             node->to_count == 1 ? "" : "s");
    for (size_t e = 0; e < node->to_count; e++) {
        const node_source *server = &l->sources[node->to[e]];
        if (server->tiles_key)
            return graph_fail_at(l, server->tiles_key, TSR_EINVAL,
                                 "node '%s': has 'tiles', but node '%s''s %s %s: [%d, %d] places it (column %zu, "
                                 "row %zu): give the grid or the tiles, not both",
                                 g->nodes[node->to[e]].name, node->name, spu, option, columns, rows,
                                 e % (size_t)columns, e / (size_t)columns);
    }
    return TSR_OK;
}

/* What `to:` must hold for the node's network SPU's role (tessera/spu.h). */
static int check_role(loader *l, size_t i)
{
    tsr_graph *g = l->graph;
    const tsr_graph_node *node = &g->nodes[i];
    const node_source *src = &l->sources[i];
    const char *spu = src->network_spu ? graph_scalar_text(src->network_spu) : NULL;
    switch (role_of(l, i)) {
    case TSR_SPU_ROLE_NONE:
    case TSR_SPU_ROLE_SERVERS: return TSR_OK;
    case TSR_SPU_ROLE_SERVER:
        /* The run fills in one server's address: more would fail there. */
        if (node->to_count != 1)
            return graph_fail_at(l, src->to_key, TSR_EINVAL, "node '%s': %s sends to one server, but 'to' names %zu",
                                 node->name, spu, node->to_count);
        return TSR_OK;
    case TSR_SPU_ROLE_TILED_SERVERS:
        if (src->grid_value && (src->grid_columns || src->grid_rows))
            return check_grid(l, i);
        /* Sort-first: every server draws its tiles. */
        for (size_t e = 0; e < node->to_count; e++)
            if (g->nodes[node->to[e]].tile_count == 0)
                return graph_fail_at(l, src->network_spu, TSR_EINVAL,
                                     "node '%s': %s sends to server '%s', which has no 'tiles' (give it "
                                     "tiles: [[x, y, width, height]])",
                                     node->name, spu, g->nodes[node->to[e]].name);
        return TSR_OK;
    case TSR_SPU_ROLE_DISPLAY: return check_display(l, i);
    case TSR_SPU_ROLE_PEERS:
        if (node->to_count != 1)
            return graph_fail_at(l, src->to_key, TSR_EINVAL,
                                 "node '%s': %s sends with its peers to one display node, but 'to' "
                                 "names %zu",
                                 node->name, spu, node->to_count);
        /* Servers or, in situ, applications: the group's rules are
         * tsr_graph_check_groups' (groups.c). */
        return TSR_OK;
    }
    return TSR_OK;
}

/* Roles: who may have `to:`, server-only keys, every server fed, and what
 * each network SPU's role asks of `to:` (check_role). A node whose role is
 * unknown (TSR_GRAPH_NO_SPU_CHECK, an SPU not installed here) is spared the
 * rules about `to:`. */
int graph_check_roles(loader *l)
{
    tsr_graph *g = l->graph;
    for (size_t i = 0; i < g->node_count; i++) {
        const tsr_graph_node *node = &g->nodes[i];
        const node_source *src = &l->sources[i];
        if (src->network_spu && node->to_count == 0)
            return graph_fail_at(l, src->network_spu, TSR_EINVAL,
                                 "node '%s': '%s' is a network SPU but the node has no servers ('to:' "
                                 "is missing or empty)",
                                 node->name, graph_scalar_text(src->network_spu));
        char list[200];
        if (!src->network_spu && src->to_key && !src->role_unknown)
            return graph_fail_at(l, src->to_key, TSR_EINVAL,
                                 "node '%s' has 'to' but no network SPU in its chain to send with (%s)", node->name,
                                 graph_network_spu_list(list, sizeof list));
        if (node->exec && src->server_key)
            return graph_fail_at(l, src->server_key, TSR_EINVAL,
                                 "node '%s': '%s' is for servers, but this is an app node (it has "
                                 "'exec')",
                                 node->name, graph_scalar_text(src->server_key));
        if (!node->exec && node->from_count == 0)
            return graph_fail_at(l, src->name, TSR_EINVAL,
                                 "server '%s' receives from no node: no 'to' names it (an app node "
                                 "needs 'exec')",
                                 node->name);
        int rc = check_role(l, i);
        if (rc != TSR_OK)
            return rc;
    }
    return TSR_OK;
}

/* Depth-first search from `root` without recursion (a chain of edges may
 * be as long as the graph has nodes); `state` 0 unvisited, 1 on the
 * current path, 2 done. `path` holds the nodes of the current path and
 * `next_edge` the edge each one goes on with. */
static int find_cycle(loader *l, size_t root, unsigned char *state, size_t *path, size_t *next_edge)
{
    tsr_graph *g = l->graph;
    size_t depth = 0;
    path[0] = root;
    next_edge[0] = 0;
    state[root] = 1;
    for (;;) {
        size_t at = path[depth];
        const tsr_graph_node *node = &g->nodes[at];
        if (next_edge[depth] == node->to_count) {
            state[at] = 2;
            if (depth == 0)
                return TSR_OK;
            depth--;
            continue;
        }
        size_t e = next_edge[depth]++;
        size_t next = node->to[e];
        if (state[next] == 1) {
            char cycle[400] = "";
            size_t used = 0;
            size_t start = depth;
            while (path[start] != next)
                start--;
            for (size_t i = start; i <= depth && used < sizeof cycle; i++)
                used += (size_t)snprintf(cycle + used, sizeof cycle - used, "%s -> ", g->nodes[path[i]].name);
            if (used < sizeof cycle)
                snprintf(cycle + used, sizeof cycle - used, "%s", g->nodes[next].name);
            return graph_fail_at(l, l->sources[at].to_names[e], TSR_EINVAL, "node '%s': 'to' closes a cycle: %s",
                                 node->name, cycle);
        }
        if (state[next] == 0) {
            state[next] = 1;
            path[++depth] = next;
            next_edge[depth] = 0;
        }
    }
}

int graph_check_cycles(loader *l)
{
    tsr_graph *g = l->graph;
    unsigned char *state = calloc(g->node_count, 1);
    size_t *path = calloc(g->node_count, sizeof *path);
    size_t *next_edge = calloc(g->node_count, sizeof *next_edge);
    int rc = state && path && next_edge ? TSR_OK : graph_out_of_memory(l, NULL);
    for (size_t i = 0; i < g->node_count && rc == TSR_OK; i++)
        if (state[i] == 0)
            rc = find_cycle(l, i, state, path, next_edge);
    free(state);
    free(path);
    free(next_edge);
    return rc;
}

/* A listen address as compared: host, transport, then the place (a unix
 * path, or a tcp port as digits) and the bind address ("" for "PORT" and
 * for unix, where the place alone decides). */
typedef struct listen_key {
    const char *host;
    tsr_transport transport;
    char place[TSR_NET_UNIX_PATH_MAX + 1];
    char bind[256];
    size_t index;
} listen_key;

static int compare_place(const listen_key *x, const listen_key *y)
{
    int c = strcmp(x->host, y->host);
    if (!c)
        c = (int)x->transport - (int)y->transport;
    return c ? c : strcmp(x->place, y->place);
}

static int compare_listen(const void *a, const void *b)
{
    const listen_key *x = a, *y = b;
    int c = compare_place(x, y);
    if (!c)
        c = strcmp(x->bind, y->bind);
    return c ? c : (x->index > y->index) - (x->index < y->index);
}

/* Two servers of one host and transport collide when their unix paths are
 * equal, or their tcp ports are equal and not 0 (any free port) and they
 * do not bind different addresses. Sorted, so tens of thousands of
 * servers cost n log n. The first node in file order that collides with
 * an earlier one is reported, with the first node it collides with. */
static int check_listen_collisions(loader *l)
{
    tsr_graph *g = l->graph;
    listen_key *keys = calloc(g->node_count ? g->node_count : 1, sizeof *keys);
    if (!keys)
        return graph_out_of_memory(l, NULL);
    size_t count = 0;
    for (size_t i = 0; i < g->node_count; i++) {
        const tsr_graph_node *node = &g->nodes[i];
        if (!node->listen)
            continue;
        listen_key *k = &keys[count];
        k->host = node->host;
        k->transport = node->transport;
        k->index = i;
        /* Checked already (graph_check_listen): netlib takes it apart. */
        tsr_net_address a;
        if (tsr_net_listen_spec_parse("listen", node->listen, graph_net_transport(node->transport), &a, NULL) != TSR_OK)
            continue;
        if (node->transport == TSR_TRANSPORT_UNIX) {
            snprintf(k->place, sizeof k->place, "%s", a.path);
        } else {
            if (a.port == 0)
                continue;
            snprintf(k->place, sizeof k->place, "%u", a.port);
            snprintf(k->bind, sizeof k->bind, "%s", a.host);
        }
        count++;
    }
    qsort(keys, count, sizeof *keys, compare_listen);
    size_t culprit = SIZE_MAX, with = SIZE_MAX;
    for (size_t s = 0, e; s < count; s = e) {
        /* One place: every bind address sorted, "" (all addresses) first. */
        size_t first = keys[s].index, first_any = SIZE_MAX;
        for (e = s + 1; e < count && !compare_place(&keys[e], &keys[s]); e++)
            first = keys[e].index < first ? keys[e].index : first;
        if (!keys[s].bind[0])
            first_any = keys[s].index;
        for (size_t k = s, same_bind = s; k < e; k++) {
            if (strcmp(keys[k].bind, keys[same_bind].bind))
                same_bind = k;
            size_t i = keys[k].index, j = SIZE_MAX;
            if (!keys[k].bind[0]) {
                j = first < i ? first : SIZE_MAX;
            } else {
                if (first_any < i)
                    j = first_any;
                if (keys[same_bind].index < i && keys[same_bind].index < j)
                    j = keys[same_bind].index;
            }
            if (j != SIZE_MAX && (culprit == SIZE_MAX || i < culprit)) {
                culprit = i;
                with = j;
            }
        }
    }
    free(keys);
    if (culprit == SIZE_MAX)
        return TSR_OK;
    const tsr_graph_node *node = &g->nodes[culprit], *other = &g->nodes[with];
    return graph_fail_at(l, l->sources[culprit].listen_value, TSR_EINVAL,
                         "node '%s': 'listen' address '%s' on host '%s' collides with node '%s' ('%s')", node->name,
                         node->listen, node->host, other->name, other->listen);
}

/* Transports that cannot leave a host, then listen addresses in use twice. */
int graph_check_transports(loader *l)
{
    tsr_graph *g = l->graph;
    for (size_t i = 0; i < g->node_count; i++) {
        const tsr_graph_node *node = &g->nodes[i];
        for (size_t e = 0; e < node->to_count; e++) {
            const tsr_graph_node *server = &g->nodes[node->to[e]];
            yaml_node_t *at = l->sources[i].to_names[e];
            if (server->transport != TSR_TRANSPORT_TCP && strcmp(server->host, node->host))
                return graph_fail_at(l, at, TSR_EINVAL,
                                     "node '%s' on host '%s' cannot reach '%s' on host '%s' over "
                                     "transport %s (same host only; use tcp)",
                                     node->name, node->host, server->name, server->host,
                                     tsr_transport_name(server->transport));
        }
    }
    return check_listen_collisions(l);
}

/* Post-order along `to`, without recursion: a node is placed after every
 * server it sends to. Runs after graph_check_cycles, so every path ends. */
int graph_compute_start_order(loader *l)
{
    tsr_graph *g = l->graph;
    bool *placed = calloc(g->node_count, sizeof *placed);
    size_t *path = calloc(g->node_count, sizeof *path);
    size_t *next_edge = calloc(g->node_count, sizeof *next_edge);
    g->start_order = graph_alloc(g, g->node_count * sizeof *g->start_order);
    int rc = placed && path && next_edge && g->start_order ? TSR_OK : graph_out_of_memory(l, NULL);
    size_t n = 0;
    for (size_t i = 0; i < g->node_count && rc == TSR_OK; i++) {
        if (placed[i])
            continue;
        size_t depth = 0;
        path[0] = i;
        next_edge[0] = 0;
        placed[i] = true;
        for (;;) {
            const tsr_graph_node *node = &g->nodes[path[depth]];
            if (next_edge[depth] == node->to_count) {
                g->start_order[n++] = path[depth];
                if (depth == 0)
                    break;
                depth--;
                continue;
            }
            size_t next = node->to[next_edge[depth]++];
            if (!placed[next]) {
                placed[next] = true;
                path[++depth] = next;
                next_edge[depth] = 0;
            }
        }
    }
    free(placed);
    free(path);
    free(next_edge);
    return rc;
}
