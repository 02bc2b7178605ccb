/* core/graph/graph_events.c — the pass over the YAML events before the
 * document is built: bounds nesting, anchors and the size alias expansion
 * would reach, so that libyaml's loader never does unbounded work.
 * Owns nothing past the call. Never: builds the document, reports an
 * error without FILE:LINE:COL. */
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
int graph_check_events(const char *text, size_t length, const char *file_name, tsr_error *err)
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
            rc = graph_yaml_syntax_error(&parser, file_name, err);
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
