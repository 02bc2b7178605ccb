/* core/graph/graph.c — the graph file (tessera/graph.h): one pass over the
 * YAML events to bound the work (nesting, anchors, alias expansion), then
 * libyaml's document loader, every key checked and copied into the
 * immutable model, then the rules between nodes (edges, cycles, who serves
 * whom), each in n log n and without recursion. Owns: the model's memory
 * (one allocation list freed with the graph). Never: keeps a model that
 * failed a check, reports an error without FILE:LINE:COL, or reads a file
 * over the size limit. */
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

#include "groups.h"

/* Unix-domain socket paths must fit sockaddr_un.sun_path (108 on Linux). */
#define UNIX_PATH_LIMIT 108
/* A tcp listen HOST must fit netlib's parsed address (TSR_NET_ADDRESS_MAX,
 * netlib/net.h), or the node refuses what check accepted. */
#define LISTEN_HOST_LIMIT 160
/* execve refuses one argument of 32 pages or more (Linux's MAX_ARG_STRLEN). */
#define EXEC_ARG_LIMIT 131072

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

/* Whether an SPU sends to other nodes is its class's to say (its network
 * role, tessera/spu.h): no SPU is known here by name. */
bool tsr_spu_is_network(const char *spu_name)
{
    if (!spu_name)
        return false;
    tsr_error ignored;
    tsr_error_clear(&ignored);
    const tsr_spu_class *cls = tsr_spu_find(spu_name, &ignored);
    return cls && cls->network.role != TSR_SPU_ROLE_NONE;
}

/* The installed network SPUs, "pack, replicate, ..." (sorted), for
 * messages; "none installed" when there are none. */
static const char *network_spu_list(char *buf, size_t size)
{
    const tsr_spu_class *classes[256];
    size_t count = tsr_spu_list(classes, sizeof classes / sizeof classes[0]);
    if (count > sizeof classes / sizeof classes[0])
        count = sizeof classes / sizeof classes[0];
    size_t used = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < count && used < size; i++)
        if (classes[i]->network.role != TSR_SPU_ROLE_NONE)
            used += (size_t)snprintf(buf + used, size - used, "%s%s", used ? ", " : "", classes[i]->name);
    if (!buf[0])
        snprintf(buf, size, "none installed");
    return buf;
}

/* ---- the model's memory ------------------------------------------------ */

static void *graph_alloc(tsr_graph *g, size_t size)
{
    if (g->allocation_count == g->allocation_cap) {
        size_t cap = g->allocation_cap ? 2 * g->allocation_cap : 64;
        void **grown = realloc(g->allocations, cap * sizeof *grown);
        if (!grown)
            return NULL;
        g->allocations = grown;
        g->allocation_cap = cap;
    }
    void *p = calloc(1, size ? size : 1);
    if (p)
        g->allocations[g->allocation_count++] = p;
    return p;
}

static char *graph_strdup(tsr_graph *g, const char *s)
{
    size_t len = strlen(s);
    char *d = graph_alloc(g, len + 1);
    if (d)
        memcpy(d, s, len + 1);
    return d;
}

void tsr_graph_free(tsr_graph *graph)
{
    if (!graph)
        return;
    for (size_t i = 0; i < graph->allocation_count; i++)
        free(graph->allocations[i]);
    free(graph->allocations);
    free(graph);
}

/* ---- messages ------------------------------------------------------------- */

static tsr_graph_mark mark_of(const yaml_node_t *n)
{
    return (tsr_graph_mark){(int)n->start_mark.line + 1, (int)n->start_mark.column + 1};
}

/* Every error goes through here so each names FILE:LINE:COL. */
static int fail_at(loader *l, const yaml_node_t *at, int code, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static int fail_at(loader *l, const yaml_node_t *at, int code, const char *fmt, ...)
{
    char message[sizeof l->err->message];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
    tsr_graph_mark m = at ? mark_of(at) : (tsr_graph_mark){1, 1};
    return tsr_error_set(l->err, code, "%s:%d:%d: %s", l->file, m.line, m.column, message);
}

static int out_of_memory(loader *l, const yaml_node_t *at) { return fail_at(l, at, TSR_ENOMEM, "out of memory"); }

static yaml_node_t *node_at(loader *l, int index) { return yaml_document_get_node(&l->doc, index); }

static bool is_null(const yaml_node_t *n)
{
    if (n->type != YAML_SCALAR_NODE || n->data.scalar.style != YAML_PLAIN_SCALAR_STYLE)
        return false;
    const char *v = (const char *)n->data.scalar.value;
    return !*v || !strcmp(v, "~") || !strcmp(v, "null");
}

static const char *scalar_text(const yaml_node_t *n)
{
    return n->type == YAML_SCALAR_NODE ? (const char *)n->data.scalar.value : NULL;
}

/* "a list", "a mapping", "nothing", "'abc'" — what the user wrote. */
static const char *describe(const yaml_node_t *n, char *buf, size_t size)
{
    if (n->type == YAML_SEQUENCE_NODE)
        return "a list";
    if (n->type == YAML_MAPPING_NODE)
        return "a mapping";
    if (is_null(n))
        return "nothing";
    snprintf(buf, size, "'%.80s'", scalar_text(n));
    return buf;
}

/* ---- typed values ----------------------------------------------------------- */

/* A non-empty scalar; `what` names the key for the message. */
static const char *expect_string(loader *l, const yaml_node_t *n, const char *what)
{
    char buf[100];
    if (n->type != YAML_SCALAR_NODE || is_null(n)) {
        fail_at(l, n, TSR_EINVAL, "%s: expected a string, got %s", what, describe(n, buf, sizeof buf));
        return NULL;
    }
    return scalar_text(n);
}

static int expect_int(loader *l, const yaml_node_t *n, const char *what, long min, long max, int *out)
{
    char buf[100];
    const char *text = scalar_text(n);
    if (!text || is_null(n))
        return fail_at(l, n, TSR_EINVAL, "%s: expected an integer, got %s", what, describe(n, buf, sizeof buf));
    if (n->data.scalar.style != YAML_PLAIN_SCALAR_STYLE)
        return fail_at(l, n, TSR_EINVAL, "%s: expected an integer, got the quoted string '%.80s'", what, text);
    errno = 0;
    char *end;
    long v = strtol(text, &end, 10);
    if (end == text || *end)
        return fail_at(l, n, TSR_EINVAL, "%s: expected an integer, got '%.80s'", what, text);
    if (errno == ERANGE || v < min || v > max)
        return fail_at(l, n, TSR_EINVAL, "%s: %.80s is out of range [%ld, %ld]", what, text, min, max);
    *out = (int)v;
    return TSR_OK;
}

static int expect_kind(loader *l, const yaml_node_t *n, yaml_node_type_t kind, const char *what)
{
    if (n->type == kind)
        return TSR_OK;
    char buf[100];
    return fail_at(l, n, TSR_EINVAL, "%s: expected %s, got %s", what,
                   kind == YAML_MAPPING_NODE ? "a mapping" : "a list", describe(n, buf, sizeof buf));
}

/* Checks that every key of mapping `m` is a scalar from `allowed`, given
 * once. `where` prefixes messages ("node 'app'"). */
static int check_keys(loader *l, const yaml_node_t *m, const char *where, const char *const *allowed, size_t count)
{
    for (yaml_node_pair_t *p = m->data.mapping.pairs.start; p < m->data.mapping.pairs.top; p++) {
        yaml_node_t *key = node_at(l, p->key);
        const char *name = scalar_text(key);
        if (!name) {
            char buf[100];
            return fail_at(l, key, TSR_EINVAL, "%s: a key must be a name, got %s", where,
                           describe(key, buf, sizeof buf));
        }
        bool known = false;
        for (size_t i = 0; i < count; i++)
            known |= !strcmp(name, allowed[i]);
        if (!known) {
            const char *hint = tsr_closest_name(name, allowed, count);
            if (hint)
                return fail_at(l, key, TSR_EINVAL, "%s: unknown key '%s' (did you mean '%s'?)", where, name, hint);
            char list[300] = "";
            size_t used = 0;
            for (size_t i = 0; i < count && used < sizeof list; i++)
                used += (size_t)snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", allowed[i]);
            return fail_at(l, key, TSR_EINVAL, "%s: unknown key '%s' (keys: %s)", where, name, list);
        }
        for (yaml_node_pair_t *q = m->data.mapping.pairs.start; q < p; q++) {
            yaml_node_t *earlier = node_at(l, q->key);
            const char *earlier_name = scalar_text(earlier);
            if (earlier_name && !strcmp(earlier_name, name)) {
                tsr_graph_mark first = mark_of(earlier);
                return fail_at(l, key, TSR_EINVAL, "%s: key '%s' is given twice (first at %d:%d)", where, name,
                               first.line, first.column);
            }
        }
    }
    return TSR_OK;
}

/* The value of `key` in mapping `m`, or NULL. Keys were checked to be
 * scalars by check_keys. */
static yaml_node_t *lookup(loader *l, const yaml_node_t *m, const char *key, yaml_node_t **key_node)
{
    for (yaml_node_pair_t *p = m->data.mapping.pairs.start; p < m->data.mapping.pairs.top; p++) {
        yaml_node_t *k = node_at(l, p->key);
        const char *name = scalar_text(k);
        if (name && !strcmp(name, key)) {
            if (key_node)
                *key_node = k;
            return node_at(l, p->value);
        }
    }
    return NULL;
}

/* ---- names in n log n ------------------------------------------------------------ */

/* Duplicate keys and node lookups by sorting: a graph may have tens of
 * thousands of nodes, and an SPU entry any number of option keys. */
typedef struct named {
    const char *name;
    size_t index; /* position in the file */
} named;

static int compare_named(const void *a, const void *b)
{
    const named *x = a, *y = b;
    int c = strcmp(x->name, y->name);
    return c ? c : (x->index > y->index) - (x->index < y->index);
}

/* Sorts `v` by name and finds the first entry in file order whose name an
 * earlier entry has: *dup, and that earlier one, *first. False when every
 * name is unique. */
static bool first_duplicate(named *v, size_t count, size_t *dup, size_t *first)
{
    qsort(v, count, sizeof *v, compare_named);
    bool found = false;
    for (size_t s = 0, e; s < count; s = e) {
        for (e = s + 1; e < count && !strcmp(v[e].name, v[s].name);)
            e++;
        if (e - s > 1 && (!found || v[s + 1].index < *dup)) {
            found = true;
            *dup = v[s + 1].index;
            *first = v[s].index;
        }
    }
    return found;
}

/* The index of the node called `name` (graph->by_name is sorted), or
 * SIZE_MAX. */
static size_t find_node(const tsr_graph *g, const char *name)
{
    size_t lo = 0, hi = g->node_count;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        int c = strcmp(g->nodes[g->by_name[mid]].name, name);
        if (c == 0)
            return g->by_name[mid];
        if (c < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return SIZE_MAX;
}

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
    const char *text = expect_string(l, n, what);
    if (!text)
        return l->err->code;
    size_t count = TSR_TRANSPORT_INPROC; /* the transports a graph may use */
    /* `tessera run` starts every server as a process of its own, which
     * an inproc server cannot be: refused here, so check and run agree. */
    if (!strcmp(text, "inproc"))
        return fail_at(l, n, TSR_EUNSUPPORTED,
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
    return fail_at(l, n, TSR_EINVAL, "%s: unknown transport '%.80s' (%stransports: tcp, unix)", where, text,
                   suggestion);
}

static int parse_version(loader *l, const yaml_node_t *root)
{
    yaml_node_t *v = lookup(l, root, "version", NULL);
    if (!v)
        return fail_at(l, root, TSR_EINVAL, "missing key 'version' (write 'version: %d' first)", TSR_GRAPH_VERSION);
    int version;
    int rc = expect_int(l, v, "'version'", INT_MIN, INT_MAX, &version);
    if (rc != TSR_OK)
        return rc;
    if (version != TSR_GRAPH_VERSION)
        return fail_at(l, v, TSR_EUNSUPPORTED, "'version': %d is not supported (this tessera reads version %d)",
                       version, TSR_GRAPH_VERSION);
    return TSR_OK;
}

static int parse_window(loader *l, const yaml_node_t *root)
{
    l->graph->width = TSR_GRAPH_DEFAULT_WIDTH;
    l->graph->height = TSR_GRAPH_DEFAULT_HEIGHT;
    yaml_node_t *w = lookup(l, root, "window", NULL);
    if (!w)
        return TSR_OK;
    static const char *const keys[] = {"width", "height"};
    int rc = expect_kind(l, w, YAML_MAPPING_NODE, "'window'");
    if (rc == TSR_OK)
        rc = check_keys(l, w, "'window'", keys, 2);
    for (size_t i = 0; i < 2 && rc == TSR_OK; i++) {
        yaml_node_t *v = lookup(l, w, keys[i], NULL);
        if (!v)
            return fail_at(l, w, TSR_EINVAL, "'window': missing '%s'", keys[i]);
        char what[32];
        snprintf(what, sizeof what, "window '%s'", keys[i]);
        rc = expect_int(l, v, what, 1, TSR_GRAPH_MAX_SIDE, i == 0 ? &l->graph->width : &l->graph->height);
    }
    return rc;
}

static int parse_defaults(loader *l, const yaml_node_t *root)
{
    l->default_host = TSR_GRAPH_DEFAULT_HOST;
    l->default_transport = TSR_TRANSPORT_TCP;
    yaml_node_t *d = lookup(l, root, "defaults", NULL);
    if (!d)
        return TSR_OK;
    static const char *const keys[] = {"host", "transport"};
    int rc = expect_kind(l, d, YAML_MAPPING_NODE, "'defaults'");
    if (rc == TSR_OK)
        rc = check_keys(l, d, "'defaults'", keys, 2);
    yaml_node_t *host = rc == TSR_OK ? lookup(l, d, "host", NULL) : NULL;
    if (host) {
        /* Nodes point at it after the document is gone: copy it. */
        const char *text = expect_string(l, host, "'defaults': 'host'");
        if (!text)
            return l->err->code;
        if (!(l->default_host = graph_strdup(l->graph, text)))
            return out_of_memory(l, host);
    }
    yaml_node_t *transport = rc == TSR_OK ? lookup(l, d, "transport", NULL) : NULL;
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
        return out_of_memory(l, at);
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
            return fail_at(l, at, TSR_EINVAL, "node '%s': 'exec': unterminated %c quote in '%.80s'", node->name, quote,
                           text);
        buf[n++] = '\0';
    }
    if (argc == 0)
        return fail_at(l, at, TSR_EINVAL, "node '%s': 'exec' names no program", node->name);
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
        const yaml_node_t *at = items ? node_at(l, items[i]) : v;
        if (len >= EXEC_ARG_LIMIT)
            return fail_at(l, at, TSR_EINVAL, "node '%s': 'exec': argument %zu is %zu bytes, the limit is %d",
                           node->name, i + 1, len, EXEC_ARG_LIMIT - 1);
        total += len + 1 + sizeof(char *);
    }
    if (total > TSR_GRAPH_MAX_EXEC_BYTES)
        return fail_at(l, v, TSR_EINVAL, "node '%s': 'exec': %zu bytes of arguments, more than the limit of %d",
                       node->name, total, TSR_GRAPH_MAX_EXEC_BYTES);
    return TSR_OK;
}

static int parse_exec(loader *l, tsr_graph_node *node, const yaml_node_t *v)
{
    char what[160];
    snprintf(what, sizeof what, "node '%s': 'exec'", node->name);
    if (v->type != YAML_SEQUENCE_NODE) {
        const char *text = expect_string(l, v, what);
        int rc = text ? split_exec(l, node, v, text) : l->err->code;
        return rc == TSR_OK ? check_exec_size(l, node, v, NULL) : rc;
    }
    size_t count = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
    if (count == 0)
        return fail_at(l, v, TSR_EINVAL, "%s names no program", what);
    const char **argv = graph_alloc(l->graph, (count + 1) * sizeof *argv);
    if (!argv)
        return out_of_memory(l, v);
    for (size_t i = 0; i < count; i++) {
        yaml_node_t *item = node_at(l, v->data.sequence.items.start[i]);
        const char *arg = expect_string(l, item, what);
        if (!arg || !(argv[i] = graph_strdup(l->graph, arg)))
            return arg ? out_of_memory(l, item) : l->err->code;
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
        return graph_strdup(l->graph, is_null(v) ? "" : scalar_text(v));
    if (v->type == YAML_MAPPING_NODE) {
        fail_at(l, v, TSR_EINVAL, "%s: option '%s': expected a value or a list, got %s", where, key,
                describe(v, buf, sizeof buf));
        return NULL;
    }
    size_t total = 1;
    for (yaml_node_item_t *i = v->data.sequence.items.start; i < v->data.sequence.items.top; i++) {
        yaml_node_t *item = node_at(l, *i);
        const char *text = scalar_text(item);
        if (!text) {
            fail_at(l, item, TSR_EINVAL, "%s: option '%s': list elements must be values, got %s", where, key,
                    describe(item, buf, sizeof buf));
            return NULL;
        }
        if (strchr(text, ',')) {
            fail_at(l, item, TSR_EINVAL, "%s: option '%s': list element '%.80s' contains ',', which separates elements",
                    where, key, text);
            return NULL;
        }
        total += strlen(text) + 1;
    }
    char *joined = graph_alloc(l->graph, total);
    if (!joined) {
        out_of_memory(l, v);
        return NULL;
    }
    for (yaml_node_item_t *i = v->data.sequence.items.start; i < v->data.sequence.items.top; i++) {
        if (i != v->data.sequence.items.start)
            strcat(joined, ",");
        strcat(joined, scalar_text(node_at(l, *i)));
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
        return fail_at(l, spu_node, e.code, "%s: %s", where, e.message);
    *found = cls;
    /* The class itself first (its supers, its defaults). */
    if (tsr_spu_check_options(cls, NULL, NULL, 0, &e) != TSR_OK)
        return fail_at(l, spu_node, e.code, "%s: %s", where, e.message);
    for (size_t k = 0; k < link->option_count; k++) {
        const tsr_option_spec *spec = tsr_spu_find_option(cls, link->keys[k], &e);
        if (!spec)
            return fail_at(l, key_nodes[k], e.code ? e.code : TSR_EINVAL, "%s: %s", where, e.message);
        /* The value's text joins a list with ',' (option_text), which a
         * string option would take as one value: the YAML type decides. */
        bool is_list =
            spec->type == TSR_OPT_INT_LIST || spec->type == TSR_OPT_FLOAT_LIST || spec->type == TSR_OPT_STRING_LIST;
        if (value_nodes[k]->type == YAML_SEQUENCE_NODE && !is_list)
            return fail_at(l, value_nodes[k], TSR_EINVAL,
                           "%s: %s: option '%s': expected one %s value, got a list (only list options take lists)",
                           where, link->spu, link->keys[k], tsr_option_type_name(spec->type));
        if (tsr_option_check_value(link->spu, spec, link->values[k], &e) != TSR_OK)
            return fail_at(l, value_nodes[k], e.code, "%s: %s", where, e.message);
    }
    /* The whole set once more, as the chain will parse it. */
    if (tsr_spu_check_options(cls, link->keys, link->values, link->option_count, &e) != TSR_OK)
        return fail_at(l, spu_node, e.code, "%s: %s", where, e.message);
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
            return fail_at(l, entry, TSR_EINVAL,
                           "%s: an entry names one SPU, this one has %zu keys (start each SPU "
                           "with '- ')",
                           where, pairs);
        spu_node = node_at(l, entry->data.mapping.pairs.start->key);
        options = node_at(l, entry->data.mapping.pairs.start->value);
        if (is_null(options))
            options = NULL;
    }
    const char *name = scalar_text(spu_node);
    if (!name || is_null(spu_node))
        return fail_at(l, spu_node, TSR_EINVAL, "%s: expected an SPU name, got %s", where,
                       describe(spu_node, buf, sizeof buf));
    if (!is_spu_name(name))
        return fail_at(l, spu_node, TSR_EINVAL, "%s: '%.80s' is not an SPU name ([a-z0-9_]+)", where, name);
    snprintf(where, sizeof where, "node '%s': SPU '%s'", node->name, name);
    if (!(link->spu = graph_strdup(l->graph, name)))
        return out_of_memory(l, spu_node);
    if (options) {
        int rc = expect_kind(l, options, YAML_MAPPING_NODE, where);
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
            return out_of_memory(l, options);
        }
        size_t named_count = 0, dup = SIZE_MAX, first = 0;
        for (size_t k = 0; k < count; k++) {
            yaml_node_t *key = node_at(l, options->data.mapping.pairs.start[k].key);
            if (scalar_text(key) && !is_null(key))
                names[named_count++] = (named){scalar_text(key), k};
        }
        if (!first_duplicate(names, named_count, &dup, &first))
            dup = SIZE_MAX;
        free(names);
        for (size_t k = 0; k < count && rc == TSR_OK; k++) {
            yaml_node_pair_t *p = &options->data.mapping.pairs.start[k];
            key_nodes[k] = node_at(l, p->key);
            value_nodes[k] = node_at(l, p->value);
            const char *key = scalar_text(key_nodes[k]);
            if (!key || is_null(key_nodes[k])) {
                rc = fail_at(l, key_nodes[k], TSR_EINVAL, "%s: an option name must be a name, got %s", where,
                             describe(key_nodes[k], buf, sizeof buf));
                break;
            }
            if (k == dup) {
                tsr_graph_mark at = mark_of(key_nodes[first]);
                rc = fail_at(l, key_nodes[k], TSR_EINVAL, "%s: option '%s' is given twice (first at %d:%d)", where, key,
                             at.line, at.column);
                break;
            }
            if (!(keys[k] = graph_strdup(l->graph, key)))
                rc = out_of_memory(l, key_nodes[k]);
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
    int rc = expect_kind(l, v, YAML_SEQUENCE_NODE, where);
    if (rc != TSR_OK)
        return rc;
    size_t count = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
    if (count == 0)
        return fail_at(l, v, TSR_EINVAL, "%s is empty: name at least one SPU", where);
    tsr_chain_link *links = graph_alloc(l->graph, count * sizeof *links);
    if (!links)
        return out_of_memory(l, v);
    for (size_t i = 0; i < count && rc == TSR_OK; i++)
        rc = parse_link(l, node, src, node_at(l, v->data.sequence.items.start[i]), &links[i]);
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
        return out_of_memory(l, v);
    for (size_t i = 0; i < count; i++) {
        yaml_node_t *item = v->type == YAML_SEQUENCE_NODE ? node_at(l, v->data.sequence.items.start[i]) : v;
        if (!expect_string(l, item, where))
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
static bool find_overlap(const tsr_graph_tile *tiles, size_t count, int height, size_t *a, size_t *b, int *rc)
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

static int parse_tiles(loader *l, tsr_graph_node *node, node_source *src, const yaml_node_t *v)
{
    char where[160];
    snprintf(where, sizeof where, "node '%s': 'tiles'", node->name);
    int rc = expect_kind(l, v, YAML_SEQUENCE_NODE, where);
    if (rc != TSR_OK)
        return rc;
    size_t count = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
    if (count == 0)
        return fail_at(l, v, TSR_EINVAL, "%s is empty: leave it out, or list [x, y, width, height]", where);
    tsr_graph_tile *tiles = graph_alloc(l->graph, count * sizeof *tiles);
    src->tile_values = calloc(count, sizeof *src->tile_values);
    if (!tiles || !src->tile_values)
        return out_of_memory(l, v);
    int w = l->graph->width, h = l->graph->height;
    for (size_t i = 0; i < count; i++) {
        yaml_node_t *t = node_at(l, v->data.sequence.items.start[i]);
        src->tile_values[i] = t;
        size_t n =
            t->type == YAML_SEQUENCE_NODE ? (size_t)(t->data.sequence.items.top - t->data.sequence.items.start) : 0;
        if (n != 4) {
            char buf[100];
            return fail_at(l, t, TSR_EINVAL, "%s: a tile is [x, y, width, height], got %s", where,
                           t->type == YAML_SEQUENCE_NODE ? (snprintf(buf, sizeof buf, "a list of %zu", n), buf)
                                                         : describe(t, buf, sizeof buf));
        }
        static const char *const field[] = {"x", "y", "width", "height"};
        int value[4];
        for (size_t f = 0; f < 4; f++) {
            char what[200];
            snprintf(what, sizeof what, "%s: tile %zu %s", where, i + 1, field[f]);
            rc = expect_int(l, node_at(l, t->data.sequence.items.start[f]), what, f < 2 ? 0 : 1, TSR_GRAPH_MAX_SIDE,
                            &value[f]);
            if (rc != TSR_OK)
                return rc;
        }
        tiles[i] = (tsr_graph_tile){value[0], value[1], value[2], value[3]};
        if (value[0] + value[2] > w || value[1] + value[3] > h)
            return fail_at(l, t, TSR_EINVAL, "%s: tile [%d, %d, %d, %d] reaches (%d, %d), outside the %dx%d window",
                           where, value[0], value[1], value[2], value[3], value[0] + value[2], value[1] + value[3], w,
                           h);
    }
    size_t first, second;
    if (find_overlap(tiles, count, h, &first, &second, &rc)) {
        const tsr_graph_tile *a = &tiles[first], *b = &tiles[second];
        return fail_at(l, src->tile_values[second], TSR_EINVAL,
                       "%s: tile %zu [%d, %d, %d, %d] overlaps tile %zu [%d, %d, %d, %d]", where, second + 1, b->x,
                       b->y, b->width, b->height, first + 1, a->x, a->y, a->width, a->height);
    }
    if (rc != TSR_OK)
        return out_of_memory(l, v);
    node->tiles = tiles;
    node->tile_count = count;
    return TSR_OK;
}

/* "PORT", "HOST:PORT" or "[V6]:PORT" for tcp; a path for unix. */
static int check_listen(loader *l, const tsr_graph_node *node, const yaml_node_t *v)
{
    const char *text = node->listen;
    if (node->transport == TSR_TRANSPORT_UNIX) {
        if (strlen(text) >= UNIX_PATH_LIMIT)
            return fail_at(l, v, TSR_EINVAL, "node '%s': 'listen': unix socket path is %zu bytes, the limit is %d",
                           node->name, strlen(text), UNIX_PATH_LIMIT - 1);
        return TSR_OK;
    }
    const char *port = text;
    const char *colon = strrchr(text, ':');
    if (text[0] == '[') {
        const char *close = strchr(text, ']');
        char v6[INET6_ADDRSTRLEN];
        struct in6_addr probe;
        if (!close || close[1] != ':' || close == text + 1 || (size_t)(close - text - 1) >= sizeof v6 ||
            (snprintf(v6, sizeof v6, "%.*s", (int)(close - text - 1), text + 1), inet_pton(AF_INET6, v6, &probe) != 1))
            return fail_at(l, v, TSR_EINVAL, "node '%s': 'listen': '%.80s' is not [IPv6]:PORT", node->name, text);
        port = close + 2;
    } else if (colon) {
        if (colon == text || memchr(text, ':', (size_t)(colon - text)))
            return fail_at(l, v, TSR_EINVAL,
                           "node '%s': 'listen': '%.80s' is not HOST:PORT (write IPv6 as "
                           "[ADDR]:PORT)",
                           node->name, text);
        if ((size_t)(colon - text) >= LISTEN_HOST_LIMIT)
            return fail_at(l, v, TSR_EINVAL, "node '%s': 'listen': the host is %zu bytes, the limit is %d", node->name,
                           (size_t)(colon - text), LISTEN_HOST_LIMIT - 1);
        port = colon + 1;
    }
    char *end;
    errno = 0;
    long p = strtol(port, &end, 10);
    if (!*port || *end || !isdigit((unsigned char)*port) || errno == ERANGE || p > 65535)
        return fail_at(l, v, TSR_EINVAL, "node '%s': 'listen': port '%.20s' in '%.80s' is not a number in [0, 65535]",
                       node->name, port, text);
    return TSR_OK;
}

static const char *const node_keys[] = {"exec", "chain", "to", "host", "transport", "listen", "tiles"};

static int parse_node(loader *l, yaml_node_t *name_node, yaml_node_t *v, tsr_graph_node *node, node_source *src)
{
    char where[160], buf[100];
    const char *name = scalar_text(name_node);
    if (!name || is_null(name_node) || !*name)
        return fail_at(l, name_node, TSR_EINVAL, "'nodes': a node name must be a name, got %s",
                       describe(name_node, buf, sizeof buf));
    for (const char *p = name; *p; p++)
        if (!isalnum((unsigned char)*p) && *p != '_' && *p != '-' && *p != '.')
            return fail_at(l, name_node, TSR_EINVAL,
                           "node name '%.80s' has '%c': use letters, digits, '_', '-' and '.'", name, *p);
    if (!(node->name = graph_strdup(l->graph, name)))
        return out_of_memory(l, name_node);
    node->mark = mark_of(name_node);
    src->name = name_node;
    snprintf(where, sizeof where, "node '%s'", name);
    if (v->type != YAML_MAPPING_NODE)
        return fail_at(l, v, TSR_EINVAL, "%s: expected a mapping of node keys (chain, exec, to, ...), got %s", where,
                       describe(v, buf, sizeof buf));
    int rc = check_keys(l, v, where, node_keys, sizeof node_keys / sizeof node_keys[0]);
    if (rc != TSR_OK)
        return rc;
    /* In file order, so the first mistake on the page is the one reported. */
    yaml_node_t *listen = NULL;
    for (yaml_node_pair_t *p = v->data.mapping.pairs.start; p < v->data.mapping.pairs.top && rc == TSR_OK; p++) {
        yaml_node_t *key = node_at(l, p->key), *value = node_at(l, p->value);
        const char *k = scalar_text(key);
        if (!k) /* check_keys() accepted only scalar keys */
            return fail_at(l, key, TSR_EINVAL, "%s: keys must be plain names", where);
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
            const char *host = expect_string(l, value, what);
            if (!host)
                rc = l->err->code;
            else if (!(node->host = graph_strdup(l->graph, host)))
                rc = out_of_memory(l, value);
        } else if (!strcmp(k, "transport")) {
            src->server_key = src->server_key ? src->server_key : key;
            rc = parse_transport(l, value, where, &node->transport);
        } else if (!strcmp(k, "listen")) {
            src->server_key = src->server_key ? src->server_key : key;
            const char *text = expect_string(l, value, what);
            if (!text)
                rc = l->err->code;
            else if (!(node->listen = graph_strdup(l->graph, text)))
                rc = out_of_memory(l, value);
            listen = value;
        } else if (!strcmp(k, "tiles")) {
            src->server_key = src->server_key ? src->server_key : key;
            src->tiles_key = key;
            rc = parse_tiles(l, node, src, value);
        }
    }
    if (rc != TSR_OK)
        return rc;
    if (!node->chain)
        return fail_at(l, name_node, TSR_EINVAL, "%s: missing key 'chain' (the SPUs it runs)", where);
    if (!node->host)
        node->host = l->default_host;
    src->listen_value = listen;
    if (listen)
        return check_listen(l, node, listen);
    return TSR_OK;
}

/* Every node starts from the default transport; parse_node overrides it
 * when the node sets its own. */
static int parse_nodes(loader *l, const yaml_node_t *root)
{
    yaml_node_t *key;
    yaml_node_t *nodes = lookup(l, root, "nodes", &key);
    if (!nodes)
        return fail_at(l, root, TSR_EINVAL, "missing key 'nodes' (the processes of the graph)");
    int rc = expect_kind(l, nodes, YAML_MAPPING_NODE, "'nodes'");
    if (rc != TSR_OK)
        return rc;
    size_t count = (size_t)(nodes->data.mapping.pairs.top - nodes->data.mapping.pairs.start);
    if (count == 0)
        return fail_at(l, nodes, TSR_EINVAL, "'nodes' is empty: a graph needs at least one node");
    if (count > TSR_GRAPH_MAX_NODES)
        return fail_at(l, key, TSR_EINVAL, "'nodes': %zu nodes, more than the limit of %d", count, TSR_GRAPH_MAX_NODES);
    l->graph->nodes = graph_alloc(l->graph, count * sizeof *l->graph->nodes);
    l->graph->by_name = graph_alloc(l->graph, count * sizeof *l->graph->by_name);
    l->sources = calloc(count, sizeof *l->sources);
    named *names = calloc(count, sizeof *names);
    if (!l->graph->nodes || !l->graph->by_name || !l->sources || !names) {
        free(names);
        return out_of_memory(l, nodes);
    }
    /* Duplicates are found first (YAML itself lets a later key win
     * silently), and reported where the node is reached, so the first
     * mistake on the page is the one reported. */
    size_t named_count = 0, dup = SIZE_MAX, first = 0;
    for (size_t i = 0; i < count; i++) {
        yaml_node_t *name = node_at(l, nodes->data.mapping.pairs.start[i].key);
        if (name->type == YAML_SCALAR_NODE)
            names[named_count++] = (named){scalar_text(name), i};
    }
    if (!first_duplicate(names, named_count, &dup, &first))
        dup = SIZE_MAX;
    for (size_t i = 0; i < count && rc == TSR_OK; i++) {
        yaml_node_pair_t *p = &nodes->data.mapping.pairs.start[i];
        yaml_node_t *name = node_at(l, p->key);
        if (i == dup) {
            tsr_graph_mark at = mark_of(node_at(l, nodes->data.mapping.pairs.start[first].key));
            rc = fail_at(l, name, TSR_EINVAL, "duplicate node name '%s' (first defined at %d:%d)", scalar_text(name),
                         at.line, at.column);
            break;
        }
        tsr_graph_node *node = &l->graph->nodes[i];
        node->transport = l->default_transport;
        l->graph->node_count = i + 1;
        rc = parse_node(l, name, node_at(l, p->value), node, &l->sources[i]);
    }
    /* Every key was a valid, unique name: `names` is the lookup order. */
    for (size_t i = 0; i < count && rc == TSR_OK; i++)
        l->graph->by_name[i] = names[i].index;
    free(names);
    return rc;
}

/* ---- rules between nodes ----------------------------------------------------------- */

static int resolve_edges(loader *l)
{
    tsr_graph *g = l->graph;
    const char **names = malloc(g->node_count * sizeof *names);
    size_t *incoming = calloc(g->node_count, sizeof *incoming);
    size_t *listed_by = calloc(g->node_count, sizeof *listed_by); /* i + 1: node i's `to` has it */
    int rc = TSR_OK;
    if (!names || !incoming || !listed_by) {
        rc = out_of_memory(l, NULL);
        goto done;
    }
    for (size_t i = 0; i < g->node_count; i++)
        names[i] = g->nodes[i].name;
    for (size_t i = 0; i < g->node_count && rc == TSR_OK; i++) {
        tsr_graph_node *node = &g->nodes[i];
        node_source *src = &l->sources[i];
        size_t *to = graph_alloc(g, (node->to_count ? node->to_count : 1) * sizeof *to);
        if (!to) {
            rc = out_of_memory(l, src->name);
            break;
        }
        for (size_t e = 0; e < node->to_count && rc == TSR_OK; e++) {
            yaml_node_t *at = src->to_names[e];
            const char *target = scalar_text(at);
            const tsr_graph_node *server = NULL;
            size_t j = find_node(g, target);
            if (j != SIZE_MAX) {
                server = &g->nodes[j];
                to[e] = j;
            }
            if (!server) {
                const char *hint = tsr_closest_name(target, names, g->node_count);
                char suggestion[200] = "";
                if (hint)
                    snprintf(suggestion, sizeof suggestion, " (did you mean '%s'?)", hint);
                rc = fail_at(l, at, TSR_EINVAL, "node '%s': 'to' names '%.80s', which is not a node%s", node->name,
                             target, suggestion);
            } else if (server == node) {
                rc = fail_at(l, at, TSR_EINVAL, "node '%s' sends to itself (a cycle)", node->name);
            } else if (server->exec) {
                rc = fail_at(l, at, TSR_EINVAL,
                             "node '%s': 'to' names '%s', an app node (it has 'exec'); only servers "
                             "receive streams",
                             node->name, target);
            }
            if (rc == TSR_OK && listed_by[to[e]] == i + 1)
                rc = fail_at(l, at, TSR_EINVAL, "node '%s': 'to' lists '%s' twice", node->name, target);
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
            rc = out_of_memory(l, l->sources[i].name);
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
        return fail_at(l, src->to_key, TSR_EINVAL,
                       "node '%s': %s sends its tile images to one display node, but 'to' "
                       "names %zu",
                       node->name, scalar_text(src->network_spu), node->to_count);
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
    /* A node's own tiles do not overlap (parse_tiles): a and b are two nodes. */
    if (rc == TSR_OK && find_overlap(tiles, n, g->height, &a, &b, &rc)) {
        if (owner[a] > owner[b]) {
            size_t swap = a;
            a = b;
            b = swap;
        }
        const tsr_graph_node *later = &g->nodes[owner[b]], *earlier = &g->nodes[owner[a]];
        const tsr_graph_tile *ta = &tiles[b], *tb = &tiles[a];
        rc = fail_at(l, l->sources[owner[b]].to_names[0], TSR_EINVAL,
                     "node '%s': its %s [%d, %d, %d, %d] overlaps node '%s''s %s "
                     "[%d, %d, %d, %d], and both send images to display '%s'",
                     later->name, later->tile_count ? "tile" : "window", ta->x, ta->y, ta->width, ta->height,
                     earlier->name, earlier->tile_count ? "tile" : "window", tb->x, tb->y, tb->width, tb->height,
                     display->name);
    } else if (rc != TSR_OK) {
        rc = out_of_memory(l, src->to_names[0]);
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
    const char *spu = scalar_text(src->network_spu), *option = src->network->network.grid;
    int columns = src->grid_columns, rows = src->grid_rows;
    if (columns < 1 || rows < 1)
        return fail_at(l, src->grid_value, TSR_EINVAL,
                       "node '%s': %s %s: expected [COLUMNS, ROWS], both at least 1 ([0, 0]: the servers' "
                       "tiles: as given)",
                       node->name, spu, option);
    if ((size_t)columns * (size_t)rows != node->to_count)
        return fail_at(l, src->grid_value, TSR_EINVAL,
                       "node '%s': %s %s: [%d, %d] has %lld cells, but 'to' names %zu server%s (one server per "
                       "cell, in 'to' order)",
                       node->name, spu, option, columns, rows, (long long)columns * rows, node->to_count,
                       node->to_count == 1 ? "" : "s");
    for (size_t e = 0; e < node->to_count; e++) {
        const node_source *server = &l->sources[node->to[e]];
        if (server->tiles_key)
            return fail_at(l, server->tiles_key, TSR_EINVAL,
                           "node '%s': has 'tiles', but node '%s''s %s %s: [%d, %d] places it (column %zu, "
                           "row %zu): give the grid or the tiles, not both",
                           g->nodes[node->to[e]].name, node->name, spu, option, columns, rows, e % (size_t)columns,
                           e / (size_t)columns);
    }
    return TSR_OK;
}

/* What `to:` must hold for the node's network SPU's role (tessera/spu.h). */
static int check_role(loader *l, size_t i)
{
    tsr_graph *g = l->graph;
    const tsr_graph_node *node = &g->nodes[i];
    const node_source *src = &l->sources[i];
    const char *spu = src->network_spu ? scalar_text(src->network_spu) : NULL;
    switch (role_of(l, i)) {
    case TSR_SPU_ROLE_NONE:
    case TSR_SPU_ROLE_SERVERS: return TSR_OK;
    case TSR_SPU_ROLE_SERVER:
        /* The run fills in one server's address: more would fail there. */
        if (node->to_count != 1)
            return fail_at(l, src->to_key, TSR_EINVAL, "node '%s': %s sends to one server, but 'to' names %zu",
                           node->name, spu, node->to_count);
        return TSR_OK;
    case TSR_SPU_ROLE_TILED_SERVERS:
        if (src->grid_value && (src->grid_columns || src->grid_rows))
            return check_grid(l, i);
        /* Sort-first: every server draws its tiles. */
        for (size_t e = 0; e < node->to_count; e++)
            if (g->nodes[node->to[e]].tile_count == 0)
                return fail_at(l, src->network_spu, TSR_EINVAL,
                               "node '%s': %s sends to server '%s', which has no 'tiles' (give it "
                               "tiles: [[x, y, width, height]])",
                               node->name, spu, g->nodes[node->to[e]].name);
        return TSR_OK;
    case TSR_SPU_ROLE_DISPLAY: return check_display(l, i);
    case TSR_SPU_ROLE_PEERS:
        if (node->to_count != 1)
            return fail_at(l, src->to_key, TSR_EINVAL,
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
static int check_roles(loader *l)
{
    tsr_graph *g = l->graph;
    for (size_t i = 0; i < g->node_count; i++) {
        const tsr_graph_node *node = &g->nodes[i];
        const node_source *src = &l->sources[i];
        if (src->network_spu && node->to_count == 0)
            return fail_at(l, src->network_spu, TSR_EINVAL,
                           "node '%s': '%s' is a network SPU but the node has no servers ('to:' "
                           "is missing or empty)",
                           node->name, scalar_text(src->network_spu));
        char list[200];
        if (!src->network_spu && src->to_key && !src->role_unknown)
            return fail_at(l, src->to_key, TSR_EINVAL,
                           "node '%s' has 'to' but no network SPU in its chain to send with (%s)", node->name,
                           network_spu_list(list, sizeof list));
        if (node->exec && src->server_key)
            return fail_at(l, src->server_key, TSR_EINVAL,
                           "node '%s': '%s' is for servers, but this is an app node (it has "
                           "'exec')",
                           node->name, scalar_text(src->server_key));
        if (!node->exec && node->from_count == 0)
            return fail_at(l, src->name, TSR_EINVAL,
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
            return fail_at(l, l->sources[at].to_names[e], TSR_EINVAL, "node '%s': 'to' closes a cycle: %s", node->name,
                           cycle);
        }
        if (state[next] == 0) {
            state[next] = 1;
            path[++depth] = next;
            next_edge[depth] = 0;
        }
    }
}

static int check_cycles(loader *l)
{
    tsr_graph *g = l->graph;
    unsigned char *state = calloc(g->node_count, 1);
    size_t *path = calloc(g->node_count, sizeof *path);
    size_t *next_edge = calloc(g->node_count, sizeof *next_edge);
    int rc = state && path && next_edge ? TSR_OK : out_of_memory(l, NULL);
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
    char place[UNIX_PATH_LIMIT];
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
        return out_of_memory(l, NULL);
    size_t count = 0;
    for (size_t i = 0; i < g->node_count; i++) {
        const tsr_graph_node *node = &g->nodes[i];
        if (!node->listen)
            continue;
        listen_key *k = &keys[count];
        k->host = node->host;
        k->transport = node->transport;
        k->index = i;
        if (node->transport == TSR_TRANSPORT_UNIX) {
            snprintf(k->place, sizeof k->place, "%s", node->listen); /* < UNIX_PATH_LIMIT: check_listen */
        } else {
            const char *colon = strrchr(node->listen, ':');
            long port = strtol(colon ? colon + 1 : node->listen, NULL, 10);
            if (port == 0)
                continue;
            snprintf(k->place, sizeof k->place, "%ld", port);
            snprintf(k->bind, sizeof k->bind, "%.*s", colon ? (int)(colon - node->listen) : 0, node->listen);
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
    return fail_at(l, l->sources[culprit].listen_value, TSR_EINVAL,
                   "node '%s': 'listen' address '%s' on host '%s' collides with node '%s' ('%s')", node->name,
                   node->listen, node->host, other->name, other->listen);
}

/* Transports that cannot leave a host, then listen addresses in use twice. */
static int check_transports(loader *l)
{
    tsr_graph *g = l->graph;
    for (size_t i = 0; i < g->node_count; i++) {
        const tsr_graph_node *node = &g->nodes[i];
        for (size_t e = 0; e < node->to_count; e++) {
            const tsr_graph_node *server = &g->nodes[node->to[e]];
            yaml_node_t *at = l->sources[i].to_names[e];
            if (server->transport != TSR_TRANSPORT_TCP && strcmp(server->host, node->host))
                return fail_at(l, at, TSR_EINVAL,
                               "node '%s' on host '%s' cannot reach '%s' on host '%s' over "
                               "transport %s (same host only; use tcp)",
                               node->name, node->host, server->name, server->host,
                               tsr_transport_name(server->transport));
        }
    }
    return check_listen_collisions(l);
}

/* Post-order along `to`, without recursion: a node is placed after every
 * server it sends to. Runs after check_cycles, so every path ends. */
static int compute_start_order(loader *l)
{
    tsr_graph *g = l->graph;
    bool *placed = calloc(g->node_count, sizeof *placed);
    size_t *path = calloc(g->node_count, sizeof *path);
    size_t *next_edge = calloc(g->node_count, sizeof *next_edge);
    g->start_order = graph_alloc(g, g->node_count * sizeof *g->start_order);
    int rc = placed && path && next_edge && g->start_order ? TSR_OK : out_of_memory(l, NULL);
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

/* ---- loading ----------------------------------------------------------------------- */

static const char *const top_keys[] = {"version", "window", "defaults", "nodes"};

static int load_document(loader *l)
{
    yaml_node_t *root = yaml_document_get_root_node(&l->doc);
    if (!root)
        return tsr_error_set(l->err, TSR_EINVAL,
                             "%s:1:1: empty graph file (expected 'version: %d' "
                             "and 'nodes:')",
                             l->file, TSR_GRAPH_VERSION);
    int rc = expect_kind(l, root, YAML_MAPPING_NODE, "graph file");
    if (rc == TSR_OK)
        rc = check_keys(l, root, "graph", top_keys, sizeof top_keys / sizeof top_keys[0]);
    if (rc == TSR_OK)
        rc = parse_version(l, root);
    if (rc == TSR_OK)
        rc = parse_window(l, root);
    if (rc == TSR_OK)
        rc = parse_defaults(l, root);
    if (rc == TSR_OK)
        rc = parse_nodes(l, root);
    if (rc == TSR_OK)
        rc = resolve_edges(l);
    if (rc == TSR_OK)
        rc = check_roles(l);
    if (rc == TSR_OK)
        rc = tsr_graph_check_groups(l->graph, l->flags, l->err);
    if (rc == TSR_OK)
        rc = check_cycles(l);
    if (rc == TSR_OK)
        rc = check_transports(l);
    if (rc == TSR_OK)
        rc = compute_start_order(l);
    return rc;
}

/* libyaml's problem, where it was found, and where the construct it was
 * reading started ("while parsing a flow sequence (started at 6:12)"). */
static int yaml_syntax_error(const yaml_parser_t *parser, const char *file_name, tsr_error *err)
{
    char context[200] = "";
    if (parser->context)
        snprintf(context, sizeof context, " %s (started at %d:%d)", parser->context, (int)parser->context_mark.line + 1,
                 (int)parser->context_mark.column + 1);
    return tsr_error_set(err, TSR_EINVAL, "%s:%d:%d: YAML syntax: %s%s", file_name, (int)parser->problem_mark.line + 1,
                         (int)parser->problem_mark.column + 1, parser->problem ? parser->problem : "malformed document",
                         context);
}

/* What one pass over the YAML events keeps to bound the work: the open
 * collections (where each began in the expanded size, and its anchor), and
 * the anchors so far with the size they expand to. */
typedef struct event_pass {
    const char *file;
    tsr_error *err;
    int depth;
    size_t open_start[TSR_GRAPH_MAX_DEPTH + 1];
    char *open_anchor[TSR_GRAPH_MAX_DEPTH + 1]; /* owned copies */
    size_t expanded;                            /* YAML nodes plus scalar bytes, aliases expanded */
    char *anchor_name[TSR_GRAPH_MAX_ANCHORS];
    size_t anchor_size[TSR_GRAPH_MAX_ANCHORS];
    size_t anchor_count;
} event_pass;

static int event_fail(event_pass *p, const yaml_event_t *e, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int event_fail(event_pass *p, const yaml_event_t *e, const char *fmt, ...)
{
    char message[sizeof p->err->message];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
    return tsr_error_set(p->err, TSR_EINVAL, "%s:%d:%d: %s", p->file, (int)e->start_mark.line + 1,
                         (int)e->start_mark.column + 1, message);
}

/* A node that ended, with its anchor (or NULL; owned by the pass from
 * here) and where it began. */
static int node_ended(event_pass *p, const yaml_event_t *e, char *anchor, size_t start)
{
    if (!anchor)
        return TSR_OK;
    if (p->anchor_count == TSR_GRAPH_MAX_ANCHORS) {
        free(anchor);
        return event_fail(p, e, "more than %d anchors (&name), the limit", TSR_GRAPH_MAX_ANCHORS);
    }
    p->anchor_name[p->anchor_count] = anchor;
    p->anchor_size[p->anchor_count++] = p->expanded - start;
    return TSR_OK;
}

static int copy_anchor(event_pass *p, const yaml_char_t *anchor, char **out)
{
    *out = NULL;
    if (anchor && !(*out = strdup((const char *)anchor)))
        return tsr_error_set(p->err, TSR_ENOMEM, "%s: out of memory", p->file);
    return TSR_OK;
}

static int count_expanded(event_pass *p, const yaml_event_t *e, size_t units)
{
    p->expanded += units;
    if (p->expanded > 2 * (size_t)TSR_GRAPH_MAX_FILE_BYTES)
        return event_fail(p, e,
                          "aliases expand the graph past %zu YAML nodes and scalar bytes (the limit, twice the "
                          "file size limit)",
                          2 * (size_t)TSR_GRAPH_MAX_FILE_BYTES);
    return TSR_OK;
}

static int on_event(event_pass *p, const yaml_event_t *e)
{
    int rc = TSR_OK;
    switch (e->type) {
    case YAML_SEQUENCE_START_EVENT:
    case YAML_MAPPING_START_EVENT:
        if (p->depth == TSR_GRAPH_MAX_DEPTH)
            return event_fail(p, e, "lists and mappings nested more than %d deep (the limit)", TSR_GRAPH_MAX_DEPTH);
        rc = copy_anchor(
            p, e->type == YAML_SEQUENCE_START_EVENT ? e->data.sequence_start.anchor : e->data.mapping_start.anchor,
            &p->open_anchor[p->depth]);
        if (rc != TSR_OK)
            return rc;
        p->open_start[p->depth++] = p->expanded;
        return count_expanded(p, e, 1);
    case YAML_SEQUENCE_END_EVENT:
    case YAML_MAPPING_END_EVENT: p->depth--; return node_ended(p, e, p->open_anchor[p->depth], p->open_start[p->depth]);
    case YAML_SCALAR_EVENT: {
        size_t start = p->expanded;
        char *anchor;
        rc = count_expanded(p, e, 1 + e->data.scalar.length);
        if (rc == TSR_OK)
            rc = copy_anchor(p, e->data.scalar.anchor, &anchor);
        return rc == TSR_OK ? node_ended(p, e, anchor, start) : rc;
    }
    case YAML_ALIAS_EVENT: {
        const char *name = (const char *)e->data.alias.anchor;
        for (int d = 0; d < p->depth; d++)
            if (p->open_anchor[d] && !strcmp(p->open_anchor[d], name))
                return event_fail(p, e, "alias *%s is inside its own anchor", name);
        /* The latest anchor of that name; an unknown one is the loader's to report. */
        for (size_t i = p->anchor_count; i-- > 0;)
            if (!strcmp(p->anchor_name[i], name))
                return count_expanded(p, e, p->anchor_size[i]);
        return TSR_OK;
    }
    default: return TSR_OK;
    }
}

/* Reads the YAML events once before the document is built, to bound the
 * work the rest can take: nesting deeper than TSR_GRAPH_MAX_DEPTH (the
 * scanner's work per token grows with the open flow collections, so
 * unbounded nesting costs quadratic time), more than
 * TSR_GRAPH_MAX_ANCHORS anchors (the loader looks each anchor and alias up
 * among all of them), and aliases that expand the document to more than
 * twice the file size limit (every check walks the expanded values). A
 * syntax error is reported here as the loader would report it. */
static int check_events(const char *text, size_t length, const char *file_name, tsr_error *err)
{
    event_pass *p = calloc(1, sizeof *p);
    yaml_parser_t parser;
    if (!p || !yaml_parser_initialize(&parser)) {
        free(p);
        return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory for the YAML parser", file_name);
    }
    p->file = file_name;
    p->err = err;
    yaml_parser_set_input_string(&parser, (const unsigned char *)text, length);
    int rc = TSR_OK;
    for (bool end = false; !end && rc == TSR_OK;) {
        yaml_event_t event;
        if (!yaml_parser_parse(&parser, &event)) {
            rc = yaml_syntax_error(&parser, file_name, err);
            break;
        }
        end = event.type == YAML_STREAM_END_EVENT;
        rc = on_event(p, &event);
        yaml_event_delete(&event);
    }
    yaml_parser_delete(&parser);
    for (size_t i = 0; i < p->anchor_count; i++)
        free(p->anchor_name[i]);
    for (int d = 0; d < p->depth; d++)
        free(p->open_anchor[d]);
    free(p);
    return rc;
}

tsr_graph *tsr_graph_parse(const char *text, size_t length, const char *file_name, unsigned flags, tsr_error *err)
{
    tsr_error local;
    if (!err) {
        err = &local;
    }
    tsr_error_clear(err);
    if (!file_name)
        file_name = "(graph)";
    if (!text) {
        tsr_error_set(err, TSR_EINVAL, "%s: no graph text", file_name);
        return NULL;
    }
    if (length > TSR_GRAPH_MAX_FILE_BYTES) {
        tsr_error_set(err, TSR_EINVAL, "%s: %zu bytes, more than the limit of %d bytes (%d MiB) for a graph file",
                      file_name, length, TSR_GRAPH_MAX_FILE_BYTES, TSR_GRAPH_MAX_FILE_BYTES >> 20);
        return NULL;
    }
    if (check_events(text, length, file_name, err) != TSR_OK)
        return NULL;
    loader l = {.file = file_name, .flags = flags, .err = err};
    yaml_parser_t parser;
    if (!yaml_parser_initialize(&parser)) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory for the YAML parser", file_name);
        return NULL;
    }
    yaml_parser_set_input_string(&parser, (const unsigned char *)text, length);
    if (!yaml_parser_load(&parser, &l.doc)) {
        yaml_syntax_error(&parser, file_name, err);
        yaml_parser_delete(&parser);
        return NULL;
    }
    /* One document per file: a second one is almost surely a mistake. */
    yaml_document_t extra;
    int rc = TSR_OK;
    if (yaml_document_get_root_node(&l.doc)) {
        if (!yaml_parser_load(&parser, &extra)) {
            rc = yaml_syntax_error(&parser, file_name, err);
        } else {
            yaml_node_t *second = yaml_document_get_root_node(&extra);
            if (second)
                rc = tsr_error_set(err, TSR_EINVAL,
                                   "%s:%d:%d: a second YAML document ('---'); a graph file holds "
                                   "one",
                                   file_name, (int)extra.start_mark.line + 1, (int)extra.start_mark.column + 1);
            yaml_document_delete(&extra);
        }
    }
    yaml_parser_delete(&parser);

    l.graph = calloc(1, sizeof *l.graph);
    if (rc == TSR_OK && !l.graph)
        rc = tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", file_name);
    if (rc == TSR_OK && !(l.graph->file = graph_strdup(l.graph, file_name)))
        rc = tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", file_name);
    if (rc == TSR_OK)
        rc = load_document(&l);
    if (l.sources && l.graph) {
        for (size_t i = 0; i < l.graph->node_count; i++) {
            free(l.sources[i].to_names);
            free(l.sources[i].tile_values);
        }
    }
    free(l.sources);
    yaml_document_delete(&l.doc);
    if (rc != TSR_OK) {
        tsr_graph_free(l.graph);
        return NULL;
    }
    return l.graph;
}

/* The size is known (stat) before anything is read, so an oversized file
 * costs nothing; a file whose size stat cannot tell (a pipe, a file that
 * grows) is read up to one byte past the limit. */
tsr_graph *tsr_graph_load(const char *path, unsigned flags, tsr_error *err)
{
    if (!path) {
        tsr_error_set(err, TSR_EINVAL, "graph: no file name");
        return NULL;
    }
    FILE *f = fopen(path, "rb");
    if (!f) {
        tsr_error_set(err, errno == ENOENT ? TSR_ENOENT : TSR_EIO, "%s: cannot open: %s", path, strerror(errno));
        return NULL;
    }
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
        fclose(f);
        tsr_error_set(err, TSR_EINVAL, "%s: is a directory, not a graph file", path);
        return NULL;
    }
    if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode) && st.st_size > TSR_GRAPH_MAX_FILE_BYTES) {
        fclose(f);
        tsr_error_set(err, TSR_EINVAL, "%s: %lld bytes, more than the limit of %d bytes (%d MiB) for a graph file",
                      path, (long long)st.st_size, TSR_GRAPH_MAX_FILE_BYTES, TSR_GRAPH_MAX_FILE_BYTES >> 20);
        return NULL;
    }
    size_t cap = (size_t)TSR_GRAPH_MAX_FILE_BYTES + 1; /* one byte past: too long */
    char *text = malloc(cap);
    if (!text) {
        fclose(f);
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory for %zu bytes", path, cap);
        return NULL;
    }
    size_t size = 0;
    for (size_t got; size < cap && (got = fread(text + size, 1, cap - size, f)) > 0;)
        size += got;
    int failed = ferror(f);
    int read_errno = errno;
    fclose(f);
    if (failed) {
        free(text);
        tsr_error_set(err, TSR_EIO, "%s: read error: %s", path, strerror(read_errno));
        return NULL;
    }
    tsr_graph *g = tsr_graph_parse(text, size, path, flags, err);
    free(text);
    return g;
}

/* ---- accessors ---------------------------------------------------------------------- */

const char *tsr_graph_file(const tsr_graph *graph) { return graph->file; }
int tsr_graph_width(const tsr_graph *graph) { return graph->width; }
int tsr_graph_height(const tsr_graph *graph) { return graph->height; }
size_t tsr_graph_node_count(const tsr_graph *graph) { return graph->node_count; }
size_t tsr_graph_edge_count(const tsr_graph *graph) { return graph->edge_count; }

const tsr_graph_node *tsr_graph_node_at(const tsr_graph *graph, size_t index)
{
    return index < graph->node_count ? &graph->nodes[index] : NULL;
}

const tsr_graph_node *tsr_graph_find(const tsr_graph *graph, const char *name)
{
    size_t i = name ? find_node(graph, name) : SIZE_MAX;
    return i == SIZE_MAX ? NULL : &graph->nodes[i];
}

const size_t *tsr_graph_start_order(const tsr_graph *graph) { return graph->start_order; }
