/* core/graph/graph_internal.h — what the graph loader's files share: the
 * model (struct tsr_graph), the loader and what it knows of each node's
 * source, and the helpers every step calls (memory, messages with
 * FILE:LINE:COL, typed values, names). The files: graph.c (the model's
 * memory, messages, typed values, loading, accessors), graph_events.c (the
 * pass over the YAML events that bounds the work), graph_keys.c (top-level
 * and node keys into the model), graph_rules.c (the rules between nodes).
 * Not for anything outside core/graph. */
#ifndef TSR_CORE_GRAPH_INTERNAL_H
#define TSR_CORE_GRAPH_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <yaml.h>

#include "tessera/dev/net.h"
#include "tessera/graph.h"
#include "tessera/spu.h"

/* execve refuses one argument of 32 pages or more (Linux's MAX_ARG_STRLEN). */
#define EXEC_ARG_LIMIT 131072

/* How netlib reads a node's listen place (tessera/dev/net.h): a unix
 * socket path for unix, else a tcp place. */
static inline tsr_net_transport graph_net_transport(tsr_transport t)
{
    return t == TSR_TRANSPORT_UNIX ? TSR_NET_UNIX : TSR_NET_TCP;
}

struct tsr_graph {
    char *file;
    int width, height;
    tsr_graph_node *nodes;
    size_t node_count;
    size_t edge_count;
    size_t *start_order; /* servers before their clients */
    size_t *by_name;     /* node indices sorted by name (tsr_graph_find) */
    void **allocations;  /* everything the model points to */
    size_t allocation_count, allocation_cap;
};

/* What the rules between nodes need to know about one node beyond the
 * model: where its keys were, and the names in `to:` before they resolve. */
typedef struct node_source {
    yaml_node_t *name;
    yaml_node_t *to_key;          /* NULL when the node has no `to:` */
    yaml_node_t **to_names;       /* scalars, to_count of them */
    yaml_node_t *network_spu;     /* first network SPU of the chain, or NULL */
    const tsr_spu_class *network; /* its class: its role (tessera/spu.h) */
    bool role_unknown;            /* TSR_GRAPH_NO_SPU_CHECK: an SPU of the chain is not
                                 installed here, so the node's role is unknown */
    yaml_node_t *grid_value;      /* the network SPU's declared grid option, when the
                                     graph gives it (tsr_spu_network.grid), or NULL */
    int grid_columns, grid_rows;  /* its value; -1, -1 when it is not two ints */
    yaml_node_t *tiles_key;       /* `tiles:` of the node, or NULL */
    yaml_node_t *server_key;      /* first of transport/listen/tiles set on the node */
    yaml_node_t *listen_value;
    yaml_node_t **tile_values; /* one sequence per tile */
} node_source;

typedef struct loader {
    const char *file;
    unsigned flags;
    yaml_document_t doc;
    tsr_graph *graph;
    tsr_error *err;
    const char *default_host;
    tsr_transport default_transport;
    node_source *sources; /* one per node */
} loader;

/* ---- names in n log n ------------------------------------------------------------ */

/* Duplicate keys and node lookups by sorting: a graph may have tens of
 * thousands of nodes, and an SPU entry any number of option keys. */
typedef struct named {
    const char *name;
    size_t index; /* position in the file */
} named;

/* graph.c */
const char *graph_network_spu_list(char *buf, size_t size);
void *graph_alloc(tsr_graph *g, size_t size);
char *graph_strdup(tsr_graph *g, const char *s);
tsr_graph_mark graph_mark_of(const yaml_node_t *n);
/* Every error goes through here so each names FILE:LINE:COL. */
int graph_fail_at(loader *l, const yaml_node_t *at, int code, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
int graph_out_of_memory(loader *l, const yaml_node_t *at);
yaml_node_t *graph_node_at(loader *l, int index);
bool graph_is_null(const yaml_node_t *n);
const char *graph_scalar_text(const yaml_node_t *n);
const char *graph_describe(const yaml_node_t *n, char *buf, size_t size);
const char *graph_expect_string(loader *l, const yaml_node_t *n, const char *what);
int graph_expect_int(loader *l, const yaml_node_t *n, const char *what, long min, long max, int *out);
int graph_expect_kind(loader *l, const yaml_node_t *n, yaml_node_type_t kind, const char *what);
int graph_check_keys(loader *l, const yaml_node_t *m, const char *where, const char *const *allowed, size_t count);
yaml_node_t *graph_lookup(loader *l, const yaml_node_t *m, const char *key, yaml_node_t **key_node);
bool graph_first_duplicate(named *v, size_t count, size_t *dup, size_t *first);
size_t graph_find_node(const tsr_graph *g, const char *name);
int graph_yaml_syntax_error(const yaml_parser_t *parser, const char *file_name, tsr_error *err);

/* graph_events.c */
int graph_check_events(const char *text, size_t length, const char *file_name, tsr_error *err);

/* graph_keys.c */
int graph_parse_version(loader *l, const yaml_node_t *root);
int graph_parse_window(loader *l, const yaml_node_t *root);
int graph_parse_defaults(loader *l, const yaml_node_t *root);
bool graph_find_overlap(const tsr_graph_tile *tiles, size_t count, int height, size_t *a, size_t *b, int *rc);
int graph_parse_tiles(loader *l, tsr_graph_node *node, node_source *src, const yaml_node_t *v);
int graph_check_listen(loader *l, const tsr_graph_node *node, const yaml_node_t *v);
int graph_parse_nodes(loader *l, const yaml_node_t *root);

/* graph_rules.c */
int graph_resolve_edges(loader *l);
int graph_check_roles(loader *l);
int graph_check_cycles(loader *l);
int graph_check_transports(loader *l);
int graph_compute_start_order(loader *l);

#endif
