/* core/graph/groups.c — sort-last compositing groups (issue 11): the
 * peers of a display node, i.e. the nodes whose network SPU declares
 * TSR_SPU_ROLE_PEERS and whose `to:` names that display. Their ranks are
 * their places in the file; the mothership tells each its rank and every
 * peer's address (tessera/spu.h). Owns nothing; knows no SPU by name (only
 * the role and the option names the class declares). Never changes the
 * graph.
 *
 * Rules (each a TSR_EINVAL at the node at fault, file:line:column):
 *   - a group is all servers (render servers) or all applications (in
 *     situ), never a mix: the peers of one kind find each other one way;
 *   - a peer's network SPU drawing a window of its own size (options
 *     `width`/`height` set, not 0) draws the graph's window: peers whose
 *     windows differ cannot be composited pixel for pixel;
 *   - a graph may spell a group out: the peers option of a member's
 *     network SPU (the name its class declares) listing node names in rank
 *     order. Then every name is a node (else a missing peer), none is
 *     listed twice, each sends to this member's display (not to a second
 *     display node), the list is in the file's order (which gives the
 *     ranks), and every peer of the display is in it (else it is missing). */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "groups.h"
#include "tessera/spu.h"

/* More names than any group has peers: further ones are not compared. */
#define GROUP_MAX_LISTED 256

/* The node's network link (the first whose class declares a role) and its
 * class; false when it has none or a class is not installed. */
static bool network_link(const tsr_graph_node *n, size_t *link, const tsr_spu_class **cls)
{
    for (size_t i = 0; i < n->chain_length; i++) {
        tsr_error ignored;
        tsr_error_clear(&ignored);
        const tsr_spu_class *c = tsr_spu_find(n->chain[i].spu, &ignored);
        if (!c)
            return false;
        if (c->network.role != TSR_SPU_ROLE_NONE) {
            *link = i;
            *cls = c;
            return true;
        }
    }
    return false;
}

static bool is_peer(const tsr_graph_node *n, size_t *link, const tsr_spu_class **cls)
{
    return network_link(n, link, cls) && (*cls)->network.role == TSR_SPU_ROLE_PEERS && n->to_count == 1;
}

static const char *option_value(const tsr_chain_link *l, const char *key)
{
    for (size_t k = 0; key && k < l->option_count; k++)
        if (!strcmp(l->keys[k], key))
            return l->values[k];
    return NULL;
}

static int fail_at(const tsr_graph *g, const tsr_graph_node *n, tsr_error *err, const char *fmt, const char *a,
                   const char *b, const char *c)
{
    char message[400];
    snprintf(message, sizeof message, fmt, a, b, c);
    return tsr_error_set(err, TSR_EINVAL, "%s:%d:%d: node '%s': %s", tsr_graph_file(g), n->mark.line, n->mark.column,
                         n->name, message);
}

/* The place of `peer` among the display's peers, or -1. */
static int rank_in(const tsr_graph *g, const tsr_graph_node *display, const tsr_graph_node *peer)
{
    int rank = 0;
    for (size_t f = 0; f < display->from_count; f++) {
        const tsr_graph_node *m = tsr_graph_node_at(g, display->from[f]);
        size_t link;
        const tsr_spu_class *cls;
        if (!is_peer(m, &link, &cls))
            continue;
        if (m == peer)
            return rank;
        rank++;
    }
    return -1;
}

/* The explicit peers list of `member` (rules in the header comment). */
static int check_list(const tsr_graph *g, const tsr_graph_node *display, const tsr_graph_node *member, const char *list,
                      const char *option, tsr_error *err)
{
    char *copy = strdup(list);
    if (!copy)
        return tsr_error_set(err, TSR_ENOMEM, "out of memory");
    int rc = TSR_OK, expected = 0;
    const char *seen[GROUP_MAX_LISTED];
    size_t nseen = 0;
    for (char *save = NULL, *name = strtok_r(copy, ",", &save); name && rc == TSR_OK;
         name = strtok_r(NULL, ",", &save)) {
        while (*name == ' ')
            name++;
        const tsr_graph_node *p = tsr_graph_find(g, name);
        size_t link;
        const tsr_spu_class *cls;
        for (size_t i = 0; i < nseen && rc == TSR_OK; i++)
            if (!strcmp(seen[i], name))
                rc = fail_at(g, member, err, "%s lists peer '%s' twice", option, name, "");
        if (rc != TSR_OK)
            break;
        if (nseen < GROUP_MAX_LISTED)
            seen[nseen++] = name;
        if (!p) {
            rc = fail_at(g, member, err, "%s names peer '%s', but no node has that name (a missing peer)", option, name,
                         "");
        } else if (!is_peer(p, &link, &cls)) {
            rc = fail_at(g, member, err, "%s names '%s', which is not a peer (its network SPU has not the peers role)",
                         option, name, "");
        } else if (tsr_graph_node_at(g, p->to[0]) != display) {
            rc = fail_at(g, member, err, "%s names '%s', which sends to display '%s': one group has one display node",
                         option, name, tsr_graph_node_at(g, p->to[0])->name);
        } else if (rank_in(g, display, p) != expected) {
            char at[24];
            snprintf(at, sizeof at, "%d", expected);
            rc = fail_at(g, member, err,
                         "%s lists '%s' at rank %s: list the peers in the graph's order (which gives "
                         "their ranks)",
                         option, name, at);
        }
        expected++;
    }
    /* Every peer of the display must be listed (seen[] points into copy). */
    for (size_t f = 0; f < display->from_count && rc == TSR_OK; f++) {
        const tsr_graph_node *m = tsr_graph_node_at(g, display->from[f]);
        size_t link;
        const tsr_spu_class *cls;
        if (!is_peer(m, &link, &cls))
            continue;
        bool listed = false;
        for (size_t i = 0; i < nseen; i++)
            listed = listed || !strcmp(seen[i], m->name);
        if (!listed && nseen < GROUP_MAX_LISTED)
            rc = fail_at(g, member, err, "%s misses peer '%s', which also sends to display '%s'", option, m->name,
                         display->name);
    }
    free(copy);
    return rc;
}

static int check_group(const tsr_graph *g, const tsr_graph_node *display, tsr_error *err)
{
    const tsr_graph_node *first = NULL;
    for (size_t f = 0; f < display->from_count; f++) {
        const tsr_graph_node *m = tsr_graph_node_at(g, display->from[f]);
        size_t link;
        const tsr_spu_class *cls;
        if (!is_peer(m, &link, &cls))
            continue;
        if (!first)
            first = m;
        if ((first->exec == NULL) != (m->exec == NULL))
            return fail_at(g, m, err,
                           "it and '%s' are peers of display '%s', but one is a server and the other an "
                           "application: a group's peers are all render servers or all applications%s",
                           first->name, display->name, "");
        const tsr_chain_link *l = &m->chain[link];
        const char *w = option_value(l, "width"), *h = option_value(l, "height");
        int gw = tsr_graph_width(g), gh = tsr_graph_height(g);
        if ((w && atoi(w) && atoi(w) != gw) || (h && atoi(h) && atoi(h) != gh)) {
            char size[64], window[64];
            snprintf(size, sizeof size, "%sx%s", w && atoi(w) ? w : "(window)", h && atoi(h) ? h : "(window)");
            snprintf(window, sizeof window, "%dx%d", gw, gh);
            return fail_at(g, m, err,
                           "its %s draws %s, but the group's window is %s: the peers' window sizes must "
                           "match",
                           l->spu, size, window);
        }
        const char *list = option_value(l, cls->network.peers);
        if (list && list[0]) {
            int rc = check_list(g, display, m, list, cls->network.peers, err);
            if (rc != TSR_OK)
                return rc;
        }
    }
    return TSR_OK;
}

int tsr_graph_check_groups(const tsr_graph *graph, unsigned flags, tsr_error *err)
{
    (void)flags; /* uninstalled SPUs: network_link is false, the node is no peer */
    for (size_t i = 0; i < tsr_graph_node_count(graph); i++) {
        const tsr_graph_node *n = tsr_graph_node_at(graph, i);
        int rc = check_group(graph, n, err);
        if (rc != TSR_OK)
            return rc;
    }
    return TSR_OK;
}
