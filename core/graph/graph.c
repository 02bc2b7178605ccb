/* core/graph/graph.c — the graph file (tessera/graph.h): one pass over the
 * YAML events to bound the work (nesting, anchors, alias expansion), then
 * libyaml's document loader, every key checked and copied into the
 * immutable model, then the rules between nodes (edges, cycles, who serves
 * whom), each in n log n and without recursion. Owns: the model's memory
 * (one allocation list freed with the graph). Never: keeps a model that
 * failed a check, reports an error without FILE:LINE:COL, or reads a file
 * over the size limit.
 *
 * This file: the model's memory, messages, typed values, names, the
 * loading steps in order, the accessors. graph_events.c, graph_keys.c and
 * graph_rules.c do the steps (graph_internal.h). */
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
const char *graph_network_spu_list(char *buf, size_t size)
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

void *graph_alloc(tsr_graph *g, size_t size)
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

char *graph_strdup(tsr_graph *g, const char *s)
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

tsr_graph_mark graph_mark_of(const yaml_node_t *n)
{
    return (tsr_graph_mark){(int)n->start_mark.line + 1, (int)n->start_mark.column + 1};
}

/* Every error goes through here so each names FILE:LINE:COL. */
int graph_fail_at(loader *l, const yaml_node_t *at, int code, const char *fmt, ...)
{
    char message[sizeof l->err->message];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
    tsr_graph_mark m = at ? graph_mark_of(at) : (tsr_graph_mark){1, 1};
    return tsr_error_set(l->err, code, "%s:%d:%d: %s", l->file, m.line, m.column, message);
}

int graph_out_of_memory(loader *l, const yaml_node_t *at) { return graph_fail_at(l, at, TSR_ENOMEM, "out of memory"); }

yaml_node_t *graph_node_at(loader *l, int index) { return yaml_document_get_node(&l->doc, index); }

bool graph_is_null(const yaml_node_t *n)
{
    if (n->type != YAML_SCALAR_NODE || n->data.scalar.style != YAML_PLAIN_SCALAR_STYLE)
        return false;
    const char *v = (const char *)n->data.scalar.value;
    return !*v || !strcmp(v, "~") || !strcmp(v, "null");
}

const char *graph_scalar_text(const yaml_node_t *n)
{
    return n->type == YAML_SCALAR_NODE ? (const char *)n->data.scalar.value : NULL;
}

/* "a list", "a mapping", "nothing", "'abc'" — what the user wrote. */
const char *graph_describe(const yaml_node_t *n, char *buf, size_t size)
{
    if (n->type == YAML_SEQUENCE_NODE)
        return "a list";
    if (n->type == YAML_MAPPING_NODE)
        return "a mapping";
    if (graph_is_null(n))
        return "nothing";
    snprintf(buf, size, "'%.80s'", graph_scalar_text(n));
    return buf;
}

/* ---- typed values ----------------------------------------------------------- */

/* A non-empty scalar; `what` names the key for the message. */
const char *graph_expect_string(loader *l, const yaml_node_t *n, const char *what)
{
    char buf[100];
    if (n->type != YAML_SCALAR_NODE || graph_is_null(n)) {
        graph_fail_at(l, n, TSR_EINVAL, "%s: expected a string, got %s", what, graph_describe(n, buf, sizeof buf));
        return NULL;
    }
    return graph_scalar_text(n);
}

int graph_expect_int(loader *l, const yaml_node_t *n, const char *what, long min, long max, int *out)
{
    char buf[100];
    const char *text = graph_scalar_text(n);
    if (!text || graph_is_null(n))
        return graph_fail_at(l, n, TSR_EINVAL, "%s: expected an integer, got %s", what,
                             graph_describe(n, buf, sizeof buf));
    if (n->data.scalar.style != YAML_PLAIN_SCALAR_STYLE)
        return graph_fail_at(l, n, TSR_EINVAL, "%s: expected an integer, got the quoted string '%.80s'", what, text);
    errno = 0;
    char *end;
    long v = strtol(text, &end, 10);
    if (end == text || *end)
        return graph_fail_at(l, n, TSR_EINVAL, "%s: expected an integer, got '%.80s'", what, text);
    if (errno == ERANGE || v < min || v > max)
        return graph_fail_at(l, n, TSR_EINVAL, "%s: %.80s is out of range [%ld, %ld]", what, text, min, max);
    *out = (int)v;
    return TSR_OK;
}

int graph_expect_kind(loader *l, const yaml_node_t *n, yaml_node_type_t kind, const char *what)
{
    if (n->type == kind)
        return TSR_OK;
    char buf[100];
    return graph_fail_at(l, n, TSR_EINVAL, "%s: expected %s, got %s", what,
                         kind == YAML_MAPPING_NODE ? "a mapping" : "a list", graph_describe(n, buf, sizeof buf));
}

/* Checks that every key of mapping `m` is a scalar from `allowed`, given
 * once. `where` prefixes messages ("node 'app'"). */
int graph_check_keys(loader *l, const yaml_node_t *m, const char *where, const char *const *allowed, size_t count)
{
    for (yaml_node_pair_t *p = m->data.mapping.pairs.start; p < m->data.mapping.pairs.top; p++) {
        yaml_node_t *key = graph_node_at(l, p->key);
        const char *name = graph_scalar_text(key);
        if (!name) {
            char buf[100];
            return graph_fail_at(l, key, TSR_EINVAL, "%s: a key must be a name, got %s", where,
                                 graph_describe(key, buf, sizeof buf));
        }
        bool known = false;
        for (size_t i = 0; i < count; i++)
            known |= !strcmp(name, allowed[i]);
        if (!known) {
            const char *hint = tsr_closest_name(name, allowed, count);
            if (hint)
                return graph_fail_at(l, key, TSR_EINVAL, "%s: unknown key '%s' (did you mean '%s'?)", where, name,
                                     hint);
            char list[300] = "";
            size_t used = 0;
            for (size_t i = 0; i < count && used < sizeof list; i++)
                used += (size_t)snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", allowed[i]);
            return graph_fail_at(l, key, TSR_EINVAL, "%s: unknown key '%s' (keys: %s)", where, name, list);
        }
        for (yaml_node_pair_t *q = m->data.mapping.pairs.start; q < p; q++) {
            yaml_node_t *earlier = graph_node_at(l, q->key);
            const char *earlier_name = graph_scalar_text(earlier);
            if (earlier_name && !strcmp(earlier_name, name)) {
                tsr_graph_mark first = graph_mark_of(earlier);
                return graph_fail_at(l, key, TSR_EINVAL, "%s: key '%s' is given twice (first at %d:%d)", where, name,
                                     first.line, first.column);
            }
        }
    }
    return TSR_OK;
}

/* The value of `key` in mapping `m`, or NULL. Keys were checked to be
 * scalars by graph_check_keys. */
yaml_node_t *graph_lookup(loader *l, const yaml_node_t *m, const char *key, yaml_node_t **key_node)
{
    for (yaml_node_pair_t *p = m->data.mapping.pairs.start; p < m->data.mapping.pairs.top; p++) {
        yaml_node_t *k = graph_node_at(l, p->key);
        const char *name = graph_scalar_text(k);
        if (name && !strcmp(name, key)) {
            if (key_node)
                *key_node = k;
            return graph_node_at(l, p->value);
        }
    }
    return NULL;
}

static int compare_named(const void *a, const void *b)
{
    const named *x = a, *y = b;
    int c = strcmp(x->name, y->name);
    return c ? c : (x->index > y->index) - (x->index < y->index);
}

/* Sorts `v` by name and finds the first entry in file order whose name an
 * earlier entry has: *dup, and that earlier one, *first. False when every
 * name is unique. */
bool graph_first_duplicate(named *v, size_t count, size_t *dup, size_t *first)
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
size_t graph_find_node(const tsr_graph *g, const char *name)
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
    int rc = graph_expect_kind(l, root, YAML_MAPPING_NODE, "graph file");
    if (rc == TSR_OK)
        rc = graph_check_keys(l, root, "graph", top_keys, sizeof top_keys / sizeof top_keys[0]);
    if (rc == TSR_OK)
        rc = graph_parse_version(l, root);
    if (rc == TSR_OK)
        rc = graph_parse_window(l, root);
    if (rc == TSR_OK)
        rc = graph_parse_defaults(l, root);
    if (rc == TSR_OK)
        rc = graph_parse_nodes(l, root);
    if (rc == TSR_OK)
        rc = graph_resolve_edges(l);
    if (rc == TSR_OK)
        rc = graph_check_roles(l);
    if (rc == TSR_OK)
        rc = tsr_graph_check_groups(l->graph, l->flags, l->err);
    if (rc == TSR_OK)
        rc = graph_check_cycles(l);
    if (rc == TSR_OK)
        rc = graph_check_transports(l);
    if (rc == TSR_OK)
        rc = graph_compute_start_order(l);
    return rc;
}

/* libyaml's problem, where it was found, and where the construct it was
 * reading started ("while parsing a flow sequence (started at 6:12)"). */
int graph_yaml_syntax_error(const yaml_parser_t *parser, const char *file_name, tsr_error *err)
{
    char context[200] = "";
    if (parser->context)
        snprintf(context, sizeof context, " %s (started at %d:%d)", parser->context, (int)parser->context_mark.line + 1,
                 (int)parser->context_mark.column + 1);
    return tsr_error_set(err, TSR_EINVAL, "%s:%d:%d: YAML syntax: %s%s", file_name, (int)parser->problem_mark.line + 1,
                         (int)parser->problem_mark.column + 1, parser->problem ? parser->problem : "malformed document",
                         context);
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
    if (graph_check_events(text, length, file_name, err) != TSR_OK)
        return NULL;
    loader l = {.file = file_name, .flags = flags, .err = err};
    yaml_parser_t parser;
    if (!yaml_parser_initialize(&parser)) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory for the YAML parser", file_name);
        return NULL;
    }
    yaml_parser_set_input_string(&parser, (const unsigned char *)text, length);
    if (!yaml_parser_load(&parser, &l.doc)) {
        graph_yaml_syntax_error(&parser, file_name, err);
        yaml_parser_delete(&parser);
        return NULL;
    }
    /* One document per file: a second one is almost surely a mistake. */
    yaml_document_t extra;
    int rc = TSR_OK;
    if (yaml_document_get_root_node(&l.doc)) {
        if (!yaml_parser_load(&parser, &extra)) {
            rc = graph_yaml_syntax_error(&parser, file_name, err);
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
    size_t i = name ? graph_find_node(graph, name) : SIZE_MAX;
    return i == SIZE_MAX ? NULL : &graph->nodes[i];
}

const size_t *tsr_graph_start_order(const tsr_graph *graph) { return graph->start_order; }
