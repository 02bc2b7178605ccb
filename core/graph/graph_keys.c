/* core/graph/graph_keys.c — every key of the graph file checked and
 * copied into the model: the top-level keys (version, window, defaults)
 * and each node's (exec, chain, to, host, transport, listen, tiles), with
 * the tiles' overlap found in n log n.
 * Owns nothing: what it copies lives in the model's allocation list.
 * Never: looks at another node (graph_rules.c does), names an SPU by
 * name (roles come from the SPU classes). */
#include <ctype.h>
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

/* ---- top-level keys ----------------------------------------------------------- */

static const char *transport_names[] = {"tcp", "unix", "inproc"};

const char *tsr_transport_name(tsr_transport transport)
{
    if ((unsigned)transport < sizeof transport_names / sizeof transport_names[0])
        return transport_names[transport];
    return "unknown";
}

static int parse_transport(loader *l, const yaml_node_t *n, const char *where, tsr_transport *out)
{
    char what[160];
    snprintf(what, sizeof what, "%s: 'transport'", where);
    const char *text = graph_expect_string(l, n, what);
    if (!text)
        return l->err->code;
    size_t count = TSR_TRANSPORT_INPROC; /* the transports a graph may use */
    /* `tessera run` starts every server as a process of its own, which
     * an inproc server cannot be: refused here, so check and run agree. */
    if (!strcmp(text, "inproc"))
        return graph_fail_at(l, n, TSR_EUNSUPPORTED,
                             "%s: transport inproc cannot be run as its own process yet; use tcp or unix", where);
    for (size_t i = 0; i < count; i++)
        if (!strcmp(text, transport_names[i])) {
            *out = (tsr_transport)i;
            return TSR_OK;
        }
    const char *hint = tsr_closest_name(text, transport_names, count);
    char suggestion[64] = "";
    if (hint)
        snprintf(suggestion, sizeof suggestion, "did you mean '%s'? ", hint);
    return graph_fail_at(l, n, TSR_EINVAL, "%s: unknown transport '%.80s' (%stransports: tcp, unix)", where, text,
                         suggestion);
}

int graph_parse_version(loader *l, const yaml_node_t *root)
{
    yaml_node_t *v = graph_lookup(l, root, "version", NULL);
    if (!v)
        return graph_fail_at(l, root, TSR_EINVAL, "missing key 'version' (write 'version: %d' first)",
                             TSR_GRAPH_VERSION);
    int version;
    int rc = graph_expect_int(l, v, "'version'", INT_MIN, INT_MAX, &version);
    if (rc != TSR_OK)
        return rc;
    if (version != TSR_GRAPH_VERSION)
        return graph_fail_at(l, v, TSR_EUNSUPPORTED, "'version': %d is not supported (this tessera reads version %d)",
                             version, TSR_GRAPH_VERSION);
    return TSR_OK;
}

int graph_parse_window(loader *l, const yaml_node_t *root)
{
    l->graph->width = TSR_GRAPH_DEFAULT_WIDTH;
    l->graph->height = TSR_GRAPH_DEFAULT_HEIGHT;
    yaml_node_t *w = graph_lookup(l, root, "window", NULL);
    if (!w)
        return TSR_OK;
    static const char *const keys[] = {"width", "height"};
    int rc = graph_expect_kind(l, w, YAML_MAPPING_NODE, "'window'");
    if (rc == TSR_OK)
        rc = graph_check_keys(l, w, "'window'", keys, 2);
    for (size_t i = 0; i < 2 && rc == TSR_OK; i++) {
        yaml_node_t *v = graph_lookup(l, w, keys[i], NULL);
        if (!v)
            return graph_fail_at(l, w, TSR_EINVAL, "'window': missing '%s'", keys[i]);
        char what[32];
        snprintf(what, sizeof what, "window '%s'", keys[i]);
        rc = graph_expect_int(l, v, what, 1, TSR_GRAPH_MAX_SIDE, i == 0 ? &l->graph->width : &l->graph->height);
    }
    return rc;
}

int graph_parse_defaults(loader *l, const yaml_node_t *root)
{
    l->default_host = TSR_GRAPH_DEFAULT_HOST;
    l->default_transport = TSR_TRANSPORT_TCP;
    yaml_node_t *d = graph_lookup(l, root, "defaults", NULL);
    if (!d)
        return TSR_OK;
    static const char *const keys[] = {"host", "transport"};
    int rc = graph_expect_kind(l, d, YAML_MAPPING_NODE, "'defaults'");
    if (rc == TSR_OK)
        rc = graph_check_keys(l, d, "'defaults'", keys, 2);
    yaml_node_t *host = rc == TSR_OK ? graph_lookup(l, d, "host", NULL) : NULL;
    if (host) {
        /* Nodes point at it after the document is gone: copy it. */
        const char *text = graph_expect_string(l, host, "'defaults': 'host'");
        if (!text)
            return l->err->code;
        if (!(l->default_host = graph_strdup(l->graph, text)))
            return graph_out_of_memory(l, host);
    }
    yaml_node_t *transport = rc == TSR_OK ? graph_lookup(l, d, "transport", NULL) : NULL;
    if (transport)
        rc = parse_transport(l, transport, "'defaults'", &l->default_transport);
    return rc;
}

/* ---- node keys ------------------------------------------------------------------ */

/* Splits `text` at blanks; "..." and '...' group, backslash escapes the
 * next character outside single quotes. No expansions: no shell runs. */
static int split_exec(loader *l, tsr_graph_node *node, const yaml_node_t *at, const char *text)
{
    tsr_graph *g = l->graph;
    size_t len = strlen(text);
    char *buf = graph_alloc(g, len + 1);
    /* At most one word per two characters, plus the terminating NULL. */
    const char **argv = graph_alloc(g, (len / 2 + 2) * sizeof *argv);
    if (!buf || !argv)
        return graph_out_of_memory(l, at);
    size_t argc = 0, n = 0;
    const char *p = text;
    for (;;) {
        while (isspace((unsigned char)*p))
            p++;
        if (!*p)
            break;
        argv[argc++] = buf + n;
        char quote = 0;
        for (; *p && (quote || !isspace((unsigned char)*p)); p++) {
            if (quote && *p == quote) {
                quote = 0;
            } else if (!quote && (*p == '"' || *p == '\'')) {
                quote = *p;
            } else if (*p == '\\' && quote != '\'' && p[1]) {
                buf[n++] = *++p;
            } else {
                buf[n++] = *p;
            }
        }
        if (quote)
            return graph_fail_at(l, at, TSR_EINVAL, "node '%s': 'exec': unterminated %c quote in '%.80s'", node->name,
                                 quote, text);
        buf[n++] = '\0';
    }
    if (argc == 0)
        return graph_fail_at(l, at, TSR_EINVAL, "node '%s': 'exec' names no program", node->name);
    node->exec = argv;
    node->exec_argc = argc;
    return TSR_OK;
}

/* What execve would refuse, refused here: one argument too long, or all
 * of them more than TSR_GRAPH_MAX_EXEC_BYTES (the kernel's limit for
 * arguments and environment together is usually 2 MiB). `items`: the
 * list's items, or NULL when the exec was one string `v`. */
static int check_exec_size(loader *l, const tsr_graph_node *node, const yaml_node_t *v, const yaml_node_item_t *items)
{
    size_t total = sizeof(char *); /* the terminating NULL */
    for (size_t i = 0; i < node->exec_argc; i++) {
        size_t len = strlen(node->exec[i]);
        const yaml_node_t *at = items ? graph_node_at(l, items[i]) : v;
        if (len >= EXEC_ARG_LIMIT)
            return graph_fail_at(l, at, TSR_EINVAL, "node '%s': 'exec': argument %zu is %zu bytes, the limit is %d",
                                 node->name, i + 1, len, EXEC_ARG_LIMIT - 1);
        total += len + 1 + sizeof(char *);
    }
    if (total > TSR_GRAPH_MAX_EXEC_BYTES)
        return graph_fail_at(l, v, TSR_EINVAL, "node '%s': 'exec': %zu bytes of arguments, more than the limit of %d",
                             node->name, total, TSR_GRAPH_MAX_EXEC_BYTES);
    return TSR_OK;
}

static int parse_exec(loader *l, tsr_graph_node *node, const yaml_node_t *v)
{
    char what[160];
    snprintf(what, sizeof what, "node '%s': 'exec'", node->name);
    if (v->type != YAML_SEQUENCE_NODE) {
        const char *text = graph_expect_string(l, v, what);
        int rc = text ? split_exec(l, node, v, text) : l->err->code;
        return rc == TSR_OK ? check_exec_size(l, node, v, NULL) : rc;
    }
    size_t count = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
    if (count == 0)
        return graph_fail_at(l, v, TSR_EINVAL, "%s names no program", what);
    const char **argv = graph_alloc(l->graph, (count + 1) * sizeof *argv);
    if (!argv)
        return graph_out_of_memory(l, v);
    for (size_t i = 0; i < count; i++) {
        yaml_node_t *item = graph_node_at(l, v->data.sequence.items.start[i]);
        const char *arg = graph_expect_string(l, item, what);
        if (!arg || !(argv[i] = graph_strdup(l->graph, arg)))
            return arg ? graph_out_of_memory(l, item) : l->err->code;
    }
    node->exec = argv;
    node->exec_argc = count;
    return check_exec_size(l, node, v, v->data.sequence.items.start);
}

/* An option value in the chain's text form: a scalar as written, a list
 * of scalars joined by ',' (how list options are written in chain text). */
static const char *option_text(loader *l, const yaml_node_t *v, const char *where, const char *key)
{
    char buf[100];
    if (v->type == YAML_SCALAR_NODE)
        return graph_strdup(l->graph, graph_is_null(v) ? "" : graph_scalar_text(v));
    if (v->type == YAML_MAPPING_NODE) {
        graph_fail_at(l, v, TSR_EINVAL, "%s: option '%s': expected a value or a list, got %s", where, key,
                      graph_describe(v, buf, sizeof buf));
        return NULL;
    }
    size_t total = 1;
    for (yaml_node_item_t *i = v->data.sequence.items.start; i < v->data.sequence.items.top; i++) {
        yaml_node_t *item = graph_node_at(l, *i);
        const char *text = graph_scalar_text(item);
        if (!text) {
            graph_fail_at(l, item, TSR_EINVAL, "%s: option '%s': list elements must be values, got %s", where, key,
                          graph_describe(item, buf, sizeof buf));
            return NULL;
        }
        if (strchr(text, ',')) {
            graph_fail_at(l, item, TSR_EINVAL,
                          "%s: option '%s': list element '%.80s' contains ',', which separates elements", where, key,
                          text);
            return NULL;
        }
        total += strlen(text) + 1;
    }
    char *joined = graph_alloc(l->graph, total);
    if (!joined) {
        graph_out_of_memory(l, v);
        return NULL;
    }
    for (yaml_node_item_t *i = v->data.sequence.items.start; i < v->data.sequence.items.top; i++) {
        if (i != v->data.sequence.items.start)
            strcat(joined, ",");
        strcat(joined, graph_scalar_text(graph_node_at(l, *i)));
    }
    return joined;
}

static bool is_spu_name(const char *name)
{
    if (!*name)
        return false;
    for (const char *p = name; *p; p++)
        if (!islower((unsigned char)*p) && !isdigit((unsigned char)*p) && *p != '_')
            return false;
    return true;
}

/* Checks one link against the installed SPU: the class exists, every key
 * is an option of it or its supers, every value parses. Uses the option
 * parser chains use, so a graph that checks builds a chain that works. */
static int check_link_options(loader *l, const tsr_graph_node *node, const tsr_chain_link *link, yaml_node_t *spu_node,
                              yaml_node_t **key_nodes, yaml_node_t **value_nodes, const tsr_spu_class **found)
{
    /* The loader's and option parser's messages name the SPU already. */
    char where[120];
    snprintf(where, sizeof where, "node '%s'", node->name);
    tsr_error e;
    tsr_error_clear(&e);
    const tsr_spu_class *cls = tsr_spu_find(link->spu, &e);
    if (!cls)
        return graph_fail_at(l, spu_node, e.code, "%s: %s", where, e.message);
    *found = cls;
    /* The class itself first (its supers, its defaults). */
    if (tsr_spu_check_options(cls, NULL, NULL, 0, &e) != TSR_OK)
        return graph_fail_at(l, spu_node, e.code, "%s: %s", where, e.message);
    for (size_t k = 0; k < link->option_count; k++) {
        const tsr_option_spec *spec = tsr_spu_find_option(cls, link->keys[k], &e);
        if (!spec)
            return graph_fail_at(l, key_nodes[k], e.code ? e.code : TSR_EINVAL, "%s: %s", where, e.message);
        /* The value's text joins a list with ',' (option_text), which a
         * string option would take as one value: the YAML type decides. */
        bool is_list =
            spec->type == TSR_OPT_INT_LIST || spec->type == TSR_OPT_FLOAT_LIST || spec->type == TSR_OPT_STRING_LIST;
        if (value_nodes[k]->type == YAML_SEQUENCE_NODE && !is_list)
            return graph_fail_at(
                l, value_nodes[k], TSR_EINVAL,
                "%s: %s: option '%s': expected one %s value, got a list (only list options take lists)", where,
                link->spu, link->keys[k], tsr_option_type_name(spec->type));
        if (tsr_option_check_value(link->spu, spec, link->values[k], &e) != TSR_OK)
            return graph_fail_at(l, value_nodes[k], e.code, "%s: %s", where, e.message);
    }
    /* The whole set once more, as the chain will parse it. */
    if (tsr_spu_check_options(cls, link->keys, link->values, link->option_count, &e) != TSR_OK)
        return graph_fail_at(l, spu_node, e.code, "%s: %s", where, e.message);
    return TSR_OK;
}

/* The link's class, checked (checks on) or only looked up for its role
 * (TSR_GRAPH_NO_SPU_CHECK: an SPU that is not installed here leaves the
 * node's role unknown); the first with a network role is the node's
 * network SPU. */
static int link_class(loader *l, const tsr_graph_node *node, node_source *src, const tsr_chain_link *link,
                      yaml_node_t *spu_node, yaml_node_t **key_nodes, yaml_node_t **value_nodes)
{
    const tsr_spu_class *cls = NULL;
    if (!(l->flags & TSR_GRAPH_NO_SPU_CHECK)) {
        int rc = check_link_options(l, node, link, spu_node, key_nodes, value_nodes, &cls);
        if (rc != TSR_OK)
            return rc;
    } else {
        tsr_error ignored;
        tsr_error_clear(&ignored);
        cls = tsr_spu_find(link->spu, &ignored);
        src->role_unknown |= !cls;
    }
    if (cls && cls->network.role != TSR_SPU_ROLE_NONE && !src->network_spu) {
        src->network_spu = spu_node;
        src->network = cls;
        for (size_t k = 0; cls->network.grid && value_nodes && k < link->option_count; k++) {
            if (strcmp(link->keys[k], cls->network.grid))
                continue;
            /* The option's text form: "C,R" (option_text). */
            int columns, rows, end = 0;
            src->grid_value = value_nodes[k];
            src->grid_columns = src->grid_rows = -1;
            if (sscanf(link->values[k], "%d,%d%n", &columns, &rows, &end) == 2 && !link->values[k][end]) {
                src->grid_columns = columns;
                src->grid_rows = rows;
            }
        }
    }
    return TSR_OK;
}

/* One chain entry: `spu`, `spu:` or `spu: {key: value, ...}`. */
static int parse_link(loader *l, tsr_graph_node *node, node_source *src, const yaml_node_t *entry, tsr_chain_link *link)
{
    char where[160], buf[100];
    snprintf(where, sizeof where, "node '%s': chain", node->name);
    yaml_node_t *spu_node = (yaml_node_t *)entry, *options = NULL;
    if (entry->type == YAML_MAPPING_NODE) {
        size_t pairs = (size_t)(entry->data.mapping.pairs.top - entry->data.mapping.pairs.start);
        if (pairs != 1)
            return graph_fail_at(l, entry, TSR_EINVAL,
                                 "%s: an entry names one SPU, this one has %zu keys (start each SPU "
                                 "with '- ')",
                                 where, pairs);
        spu_node = graph_node_at(l, entry->data.mapping.pairs.start->key);
        options = graph_node_at(l, entry->data.mapping.pairs.start->value);
        if (graph_is_null(options))
            options = NULL;
    }
    const char *name = graph_scalar_text(spu_node);
    if (!name || graph_is_null(spu_node))
        return graph_fail_at(l, spu_node, TSR_EINVAL, "%s: expected an SPU name, got %s", where,
                             graph_describe(spu_node, buf, sizeof buf));
    if (!is_spu_name(name))
        return graph_fail_at(l, spu_node, TSR_EINVAL, "%s: '%.80s' is not an SPU name ([a-z0-9_]+)", where, name);
    snprintf(where, sizeof where, "node '%s': SPU '%s'", node->name, name);
    if (!(link->spu = graph_strdup(l->graph, name)))
        return graph_out_of_memory(l, spu_node);
    if (options) {
        int rc = graph_expect_kind(l, options, YAML_MAPPING_NODE, where);
        if (rc != TSR_OK)
            return rc;
        size_t count = (size_t)(options->data.mapping.pairs.top - options->data.mapping.pairs.start);
        const char **keys = graph_alloc(l->graph, count * sizeof *keys);
        const char **values = graph_alloc(l->graph, count * sizeof *values);
        yaml_node_t **key_nodes = calloc(count ? count : 1, sizeof *key_nodes);
        yaml_node_t **value_nodes = calloc(count ? count : 1, sizeof *value_nodes);
        named *names = calloc(count ? count : 1, sizeof *names);
        if (!keys || !values || !key_nodes || !value_nodes || !names) {
            free(key_nodes);
            free(value_nodes);
            free(names);
            return graph_out_of_memory(l, options);
        }
        size_t named_count = 0, dup = SIZE_MAX, first = 0;
        for (size_t k = 0; k < count; k++) {
            yaml_node_t *key = graph_node_at(l, options->data.mapping.pairs.start[k].key);
            if (graph_scalar_text(key) && !graph_is_null(key))
                names[named_count++] = (named){graph_scalar_text(key), k};
        }
        if (!graph_first_duplicate(names, named_count, &dup, &first))
            dup = SIZE_MAX;
        free(names);
        for (size_t k = 0; k < count && rc == TSR_OK; k++) {
            yaml_node_pair_t *p = &options->data.mapping.pairs.start[k];
            key_nodes[k] = graph_node_at(l, p->key);
            value_nodes[k] = graph_node_at(l, p->value);
            const char *key = graph_scalar_text(key_nodes[k]);
            if (!key || graph_is_null(key_nodes[k])) {
                rc = graph_fail_at(l, key_nodes[k], TSR_EINVAL, "%s: an option name must be a name, got %s", where,
                                   graph_describe(key_nodes[k], buf, sizeof buf));
                break;
            }
            if (k == dup) {
                tsr_graph_mark at = graph_mark_of(key_nodes[first]);
                rc = graph_fail_at(l, key_nodes[k], TSR_EINVAL, "%s: option '%s' is given twice (first at %d:%d)",
                                   where, key, at.line, at.column);
                break;
            }
            if (!(keys[k] = graph_strdup(l->graph, key)))
                rc = graph_out_of_memory(l, key_nodes[k]);
            else if (!(values[k] = option_text(l, value_nodes[k], where, key)))
                rc = l->err->code;
        }
        link->keys = keys;
        link->values = values;
        link->option_count = rc == TSR_OK ? count : 0;
        if (rc == TSR_OK)
            rc = link_class(l, node, src, link, spu_node, key_nodes, value_nodes);
        free(key_nodes);
        free(value_nodes);
        return rc;
    }
    return link_class(l, node, src, link, spu_node, NULL, NULL);
}

static int parse_chain(loader *l, tsr_graph_node *node, node_source *src, const yaml_node_t *v)
{
    char where[160];
    snprintf(where, sizeof where, "node '%s': 'chain'", node->name);
    int rc = graph_expect_kind(l, v, YAML_SEQUENCE_NODE, where);
    if (rc != TSR_OK)
        return rc;
    size_t count = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
    if (count == 0)
        return graph_fail_at(l, v, TSR_EINVAL, "%s is empty: name at least one SPU", where);
    tsr_chain_link *links = graph_alloc(l->graph, count * sizeof *links);
    if (!links)
        return graph_out_of_memory(l, v);
    for (size_t i = 0; i < count && rc == TSR_OK; i++)
        rc = parse_link(l, node, src, graph_node_at(l, v->data.sequence.items.start[i]), &links[i]);
    node->chain = links;
    node->chain_length = count;
    return rc;
}

static int parse_to(loader *l, tsr_graph_node *node, node_source *src, yaml_node_t *v)
{
    char where[160];
    snprintf(where, sizeof where, "node '%s': 'to'", node->name);
    size_t count =
        v->type == YAML_SEQUENCE_NODE ? (size_t)(v->data.sequence.items.top - v->data.sequence.items.start) : 1;
    src->to_names = calloc(count ? count : 1, sizeof *src->to_names);
    if (!src->to_names)
        return graph_out_of_memory(l, v);
    for (size_t i = 0; i < count; i++) {
        yaml_node_t *item = v->type == YAML_SEQUENCE_NODE ? graph_node_at(l, v->data.sequence.items.start[i]) : v;
        if (!graph_expect_string(l, item, where))
            return l->err->code;
        src->to_names[i] = item;
    }
    node->to_count = count;
    return TSR_OK;
}

/* ---- overlapping tiles in n log n ------------------------------------------------- */

/* A sweep along x over tiles inside a window `height` rows high: the
 * y-intervals of the tiles the sweep line crosses are disjoint while no
 * overlap has been found, so a new tile overlaps one of them exactly when
 * the active interval that starts last below its top reaches above its
 * bottom. Rows of active starts are kept in a count tree over the rows. */
typedef struct sweep_event {
    int x;
    int open; /* 0: the tile ends at x (ends sort first: tiles are half-open) */
    size_t tile;
} sweep_event;

static int compare_events(const void *a, const void *b)
{
    const sweep_event *p = a, *q = b;
    if (p->x != q->x)
        return p->x < q->x ? -1 : 1;
    if (p->open != q->open)
        return p->open - q->open;
    return (p->tile > q->tile) - (p->tile < q->tile);
}

static void count_tree_add(unsigned *tree, size_t leaves, size_t row, int delta)
{
    for (size_t i = leaves + row; i >= 1; i >>= 1)
        tree[i] += (unsigned)delta;
}

/* The highest row below `row` that holds an active start, or SIZE_MAX. */
static size_t count_tree_below(const unsigned *tree, size_t leaves, size_t row)
{
    if (row == 0)
        return SIZE_MAX;
    size_t i = leaves + row - 1;
    if (tree[i])
        return row - 1;
    /* Up until a left sibling holds a start, then down its right edge. */
    for (;; i >>= 1) {
        if (i <= 1)
            return SIZE_MAX;
        if ((i & 1) && tree[i - 1]) {
            i--;
            break;
        }
    }
    while (i < leaves)
        i = tree[2 * i + 1] ? 2 * i + 1 : 2 * i;
    return i - leaves;
}

/* Finds two overlapping tiles among `count` (each inside a window of
 * `height` rows): true with *a < *b. *rc is TSR_ENOMEM on failure. */
bool graph_find_overlap(const tsr_graph_tile *tiles, size_t count, int height, size_t *a, size_t *b, int *rc)
{
    size_t leaves = 1;
    while (leaves < (size_t)height)
        leaves *= 2;
    sweep_event *events = malloc(2 * count * sizeof *events);
    unsigned *tree = calloc(2 * leaves, sizeof *tree);
    size_t *starts = malloc((size_t)height * sizeof *starts); /* row -> tile starting there */
    bool found = false;
    *rc = events && tree && starts ? TSR_OK : TSR_ENOMEM;
    for (size_t i = 0; i < count && *rc == TSR_OK; i++) {
        events[2 * i] = (sweep_event){tiles[i].x, 1, i};
        events[2 * i + 1] = (sweep_event){tiles[i].x + tiles[i].width, 0, i};
    }
    if (*rc == TSR_OK)
        qsort(events, 2 * count, sizeof *events, compare_events);
    for (size_t e = 0; e < 2 * count && *rc == TSR_OK && !found; e++) {
        const tsr_graph_tile *t = &tiles[events[e].tile];
        if (!events[e].open) {
            count_tree_add(tree, leaves, (size_t)t->y, -1);
            continue;
        }
        size_t row = count_tree_below(tree, leaves, (size_t)(t->y + t->height));
        if (row != SIZE_MAX && (int)row + tiles[starts[row]].height > t->y) {
            size_t other = starts[row], self = events[e].tile;
            *a = other < self ? other : self;
            *b = other < self ? self : other;
            found = true;
            break;
        }
        starts[t->y] = events[e].tile;
        count_tree_add(tree, leaves, (size_t)t->y, 1);
    }
    free(events);
    free(tree);
    free(starts);
    return found;
}

int graph_parse_tiles(loader *l, tsr_graph_node *node, node_source *src, const yaml_node_t *v)
{
    char where[160];
    snprintf(where, sizeof where, "node '%s': 'tiles'", node->name);
    int rc = graph_expect_kind(l, v, YAML_SEQUENCE_NODE, where);
    if (rc != TSR_OK)
        return rc;
    size_t count = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
    if (count == 0)
        return graph_fail_at(l, v, TSR_EINVAL, "%s is empty: leave it out, or list [x, y, width, height]", where);
    tsr_graph_tile *tiles = graph_alloc(l->graph, count * sizeof *tiles);
    src->tile_values = calloc(count, sizeof *src->tile_values);
    if (!tiles || !src->tile_values)
        return graph_out_of_memory(l, v);
    int w = l->graph->width, h = l->graph->height;
    for (size_t i = 0; i < count; i++) {
        yaml_node_t *t = graph_node_at(l, v->data.sequence.items.start[i]);
        src->tile_values[i] = t;
        size_t n =
            t->type == YAML_SEQUENCE_NODE ? (size_t)(t->data.sequence.items.top - t->data.sequence.items.start) : 0;
        if (n != 4) {
            char buf[100];
            return graph_fail_at(l, t, TSR_EINVAL, "%s: a tile is [x, y, width, height], got %s", where,
                                 t->type == YAML_SEQUENCE_NODE ? (snprintf(buf, sizeof buf, "a list of %zu", n), buf)
                                                               : graph_describe(t, buf, sizeof buf));
        }
        static const char *const field[] = {"x", "y", "width", "height"};
        int value[4];
        for (size_t f = 0; f < 4; f++) {
            char what[200];
            snprintf(what, sizeof what, "%s: tile %zu %s", where, i + 1, field[f]);
            rc = graph_expect_int(l, graph_node_at(l, t->data.sequence.items.start[f]), what, f < 2 ? 0 : 1,
                                  TSR_GRAPH_MAX_SIDE, &value[f]);
            if (rc != TSR_OK)
                return rc;
        }
        tiles[i] = (tsr_graph_tile){value[0], value[1], value[2], value[3]};
        if (value[0] + value[2] > w || value[1] + value[3] > h)
            return graph_fail_at(
                l, t, TSR_EINVAL, "%s: tile [%d, %d, %d, %d] reaches (%d, %d), outside the %dx%d window", where,
                value[0], value[1], value[2], value[3], value[0] + value[2], value[1] + value[3], w, h);
    }
    size_t first, second;
    if (graph_find_overlap(tiles, count, h, &first, &second, &rc)) {
        const tsr_graph_tile *a = &tiles[first], *b = &tiles[second];
        return graph_fail_at(l, src->tile_values[second], TSR_EINVAL,
                             "%s: tile %zu [%d, %d, %d, %d] overlaps tile %zu [%d, %d, %d, %d]", where, second + 1,
                             b->x, b->y, b->width, b->height, first + 1, a->x, a->y, a->width, a->height);
    }
    if (rc != TSR_OK)
        return graph_out_of_memory(l, v);
    node->tiles = tiles;
    node->tile_count = count;
    return TSR_OK;
}

/* "PORT", "HOST:PORT" or "[V6]:PORT" for tcp; a path for unix: netlib
 * checks it as the node's listener will (tessera/dev/net.h). */
int graph_check_listen(loader *l, const tsr_graph_node *node, const yaml_node_t *v)
{
    tsr_error err;
    tsr_error_clear(&err);
    char who[sizeof err.message];
    snprintf(who, sizeof who, "node '%s': 'listen'", node->name);
    tsr_net_address place;
    if (tsr_net_listen_spec_parse(who, node->listen, graph_net_transport(node->transport), &place, &err) != TSR_OK)
        return graph_fail_at(l, v, err.code, "%s", err.message);
    return TSR_OK;
}

static const char *const node_keys[] = {"exec", "chain", "to", "host", "transport", "listen", "tiles"};

static int parse_node(loader *l, yaml_node_t *name_node, yaml_node_t *v, tsr_graph_node *node, node_source *src)
{
    char where[160], buf[100];
    const char *name = graph_scalar_text(name_node);
    if (!name || graph_is_null(name_node) || !*name)
        return graph_fail_at(l, name_node, TSR_EINVAL, "'nodes': a node name must be a name, got %s",
                             graph_describe(name_node, buf, sizeof buf));
    for (const char *p = name; *p; p++)
        if (!isalnum((unsigned char)*p) && *p != '_' && *p != '-' && *p != '.')
            return graph_fail_at(l, name_node, TSR_EINVAL,
                                 "node name '%.80s' has '%c': use letters, digits, '_', '-' and '.'", name, *p);
    if (!(node->name = graph_strdup(l->graph, name)))
        return graph_out_of_memory(l, name_node);
    node->mark = graph_mark_of(name_node);
    src->name = name_node;
    snprintf(where, sizeof where, "node '%s'", name);
    if (v->type != YAML_MAPPING_NODE)
        return graph_fail_at(l, v, TSR_EINVAL, "%s: expected a mapping of node keys (chain, exec, to, ...), got %s",
                             where, graph_describe(v, buf, sizeof buf));
    int rc = graph_check_keys(l, v, where, node_keys, sizeof node_keys / sizeof node_keys[0]);
    if (rc != TSR_OK)
        return rc;
    /* In file order, so the first mistake on the page is the one reported. */
    yaml_node_t *listen = NULL;
    for (yaml_node_pair_t *p = v->data.mapping.pairs.start; p < v->data.mapping.pairs.top && rc == TSR_OK; p++) {
        yaml_node_t *key = graph_node_at(l, p->key), *value = graph_node_at(l, p->value);
        const char *k = graph_scalar_text(key);
        if (!k) /* graph_check_keys() accepted only scalar keys */
            return graph_fail_at(l, key, TSR_EINVAL, "%s: keys must be plain names", where);
        char what[200];
        snprintf(what, sizeof what, "%s: '%s'", where, k);
        if (!strcmp(k, "exec")) {
            rc = parse_exec(l, node, value);
        } else if (!strcmp(k, "chain")) {
            rc = parse_chain(l, node, src, value);
        } else if (!strcmp(k, "to")) {
            src->to_key = key;
            rc = parse_to(l, node, src, value);
        } else if (!strcmp(k, "host")) {
            const char *host = graph_expect_string(l, value, what);
            if (!host)
                rc = l->err->code;
            else if (!(node->host = graph_strdup(l->graph, host)))
                rc = graph_out_of_memory(l, value);
        } else if (!strcmp(k, "transport")) {
            src->server_key = src->server_key ? src->server_key : key;
            rc = parse_transport(l, value, where, &node->transport);
        } else if (!strcmp(k, "listen")) {
            src->server_key = src->server_key ? src->server_key : key;
            const char *text = graph_expect_string(l, value, what);
            if (!text)
                rc = l->err->code;
            else if (!(node->listen = graph_strdup(l->graph, text)))
                rc = graph_out_of_memory(l, value);
            listen = value;
        } else if (!strcmp(k, "tiles")) {
            src->server_key = src->server_key ? src->server_key : key;
            src->tiles_key = key;
            rc = graph_parse_tiles(l, node, src, value);
        }
    }
    if (rc != TSR_OK)
        return rc;
    if (!node->chain)
        return graph_fail_at(l, name_node, TSR_EINVAL, "%s: missing key 'chain' (the SPUs it runs)", where);
    if (!node->host)
        node->host = l->default_host;
    src->listen_value = listen;
    if (listen)
        return graph_check_listen(l, node, listen);
    return TSR_OK;
}

/* Every node starts from the default transport; parse_node overrides it
 * when the node sets its own. */
int graph_parse_nodes(loader *l, const yaml_node_t *root)
{
    yaml_node_t *key;
    yaml_node_t *nodes = graph_lookup(l, root, "nodes", &key);
    if (!nodes)
        return graph_fail_at(l, root, TSR_EINVAL, "missing key 'nodes' (the processes of the graph)");
    int rc = graph_expect_kind(l, nodes, YAML_MAPPING_NODE, "'nodes'");
    if (rc != TSR_OK)
        return rc;
    size_t count = (size_t)(nodes->data.mapping.pairs.top - nodes->data.mapping.pairs.start);
    if (count == 0)
        return graph_fail_at(l, nodes, TSR_EINVAL, "'nodes' is empty: a graph needs at least one node");
    if (count > TSR_GRAPH_MAX_NODES)
        return graph_fail_at(l, key, TSR_EINVAL, "'nodes': %zu nodes, more than the limit of %d", count,
                             TSR_GRAPH_MAX_NODES);
    l->graph->nodes = graph_alloc(l->graph, count * sizeof *l->graph->nodes);
    l->graph->by_name = graph_alloc(l->graph, count * sizeof *l->graph->by_name);
    l->sources = calloc(count, sizeof *l->sources);
    named *names = calloc(count, sizeof *names);
    if (!l->graph->nodes || !l->graph->by_name || !l->sources || !names) {
        free(names);
        return graph_out_of_memory(l, nodes);
    }
    /* Duplicates are found first (YAML itself lets a later key win
     * silently), and reported where the node is reached, so the first
     * mistake on the page is the one reported. */
    size_t named_count = 0, dup = SIZE_MAX, first = 0;
    for (size_t i = 0; i < count; i++) {
        yaml_node_t *name = graph_node_at(l, nodes->data.mapping.pairs.start[i].key);
        if (name->type == YAML_SCALAR_NODE)
            names[named_count++] = (named){graph_scalar_text(name), i};
    }
    if (!graph_first_duplicate(names, named_count, &dup, &first))
        dup = SIZE_MAX;
    for (size_t i = 0; i < count && rc == TSR_OK; i++) {
        yaml_node_pair_t *p = &nodes->data.mapping.pairs.start[i];
        yaml_node_t *name = graph_node_at(l, p->key);
        if (i == dup) {
            tsr_graph_mark at = graph_mark_of(graph_node_at(l, nodes->data.mapping.pairs.start[first].key));
            rc = graph_fail_at(l, name, TSR_EINVAL, "duplicate node name '%s' (first defined at %d:%d)",
                               graph_scalar_text(name), at.line, at.column);
            break;
        }
        tsr_graph_node *node = &l->graph->nodes[i];
        node->transport = l->default_transport;
        l->graph->node_count = i + 1;
        rc = parse_node(l, name, graph_node_at(l, p->value), node, &l->sources[i]);
    }
    /* Every key was a valid, unique name: `names` is the lookup order. */
    for (size_t i = 0; i < count && rc == TSR_OK; i++)
        l->graph->by_name[i] = names[i].index;
    free(names);
    return rc;
}
