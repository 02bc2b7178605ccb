/* cli/cmd_dot.c — `tessera dot GRAPH`: the graph as Graphviz DOT on stdout,
 * each node a record listing its role, SPU chain, tiles and host, each edge
 * labelled with its transport. Owns: DOT formatting and escaping. Never:
 * prints a graph that failed validation. */
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "tessera/graph.h"

#define APP_COLOR "#dbe8f7"
#define SERVER_COLOR "#e3f1dc"

static void print_usage(FILE *out)
{
    fprintf(out, "usage: tessera dot [--no-spu-check] GRAPH\n\n"
                 "Validates the graph file GRAPH like `tessera check`, then prints it as\n"
                 "Graphviz DOT on stdout: one box per node with its program or role, SPU\n"
                 "chain with options, tiles and host; one arrow per connection labelled with\n"
                 "its transport (and listen address). Make a picture with\n"
                 "  tessera dot GRAPH | dot -Tpng -o graph.png\n\n"
                 "  --no-spu-check  check the structure only; do not look SPUs up\n"
                 "  -h, --help      show this help\n\n"
                 "Exit codes: 0 ok, 1 runtime failure, 2 invalid graph or bad arguments.\n");
}

/* Text inside a record field: the record syntax characters and quotes
 * are escaped; `\l` ends a left-justified line. */
static void put_record_text(FILE *out, const char *s)
{
    for (; *s; s++) {
        if (strchr("{}|<>\"\\", *s))
            fputc('\\', out);
        fputc(*s, out);
    }
}

static void put_chain(FILE *out, const tsr_graph_node *node)
{
    for (size_t i = 0; i < node->chain_length; i++) {
        const tsr_chain_link *link = &node->chain[i];
        fputs("|", out);
        put_record_text(out, link->spu);
        for (size_t k = 0; k < link->option_count; k++) {
            fputs("\\n", out);
            put_record_text(out, link->keys[k]);
            fputc('=', out);
            put_record_text(out, link->values[k]);
        }
    }
}

static void put_node(FILE *out, const tsr_graph_node *node)
{
    fprintf(out, "  \"%s\" [fillcolor=\"%s\", label=\"{", node->name, node->exec ? APP_COLOR : SERVER_COLOR);
    put_record_text(out, node->name);
    if (node->exec) {
        fputs("\\nruns: ", out);
        for (size_t a = 0; a < node->exec_argc; a++) {
            /* Quote what the split would otherwise change. */
            const char *arg = node->exec[a];
            bool quote = !*arg || strpbrk(arg, " \t'\"\\");
            fputs(a ? (quote ? " '" : " ") : (quote ? "'" : ""), out);
            put_record_text(out, arg);
            if (quote)
                fputc('\'', out);
        }
    } else {
        fputs("\\nserver", out);
    }
    put_chain(out, node);
    if (node->tile_count) {
        fputs("|tiles", out);
        for (size_t t = 0; t < node->tile_count; t++) {
            const tsr_graph_tile *tile = &node->tiles[t];
            fprintf(out, "\\n%d,%d %dx%d", tile->x, tile->y, tile->width, tile->height);
        }
    }
    fputs("|host: ", out);
    put_record_text(out, node->host);
    fputs("}\"];\n", out);
}

/* Inside a quoted DOT string only '"' and '\' need escaping. */
static void put_escaped(FILE *out, const char *s)
{
    for (; *s; s++) {
        if (*s == '"' || *s == '\\')
            fputc('\\', out);
        fputc(*s, out);
    }
}

static void put_quoted(FILE *out, const char *s)
{
    fputc('"', out);
    put_escaped(out, s);
    fputc('"', out);
}

static void put_graph(FILE *out, const tsr_graph *graph)
{
    const char *file = tsr_graph_file(graph);
    const char *base = strrchr(file, '/');
    base = base ? base + 1 : file;
    fputs("digraph ", out);
    put_quoted(out, base);
    fputs(" {\n", out);
    char title[300];
    snprintf(title, sizeof title, "%s  (window %dx%d)", base, tsr_graph_width(graph), tsr_graph_height(graph));
    fputs("  graph [rankdir=TB, fontname=\"Helvetica\", fontsize=12, labelloc=t, nodesep=0.4, "
          "label=",
          out);
    put_quoted(out, title);
    fputs("];\n", out);
    fputs("  node [shape=Mrecord, style=filled, fontname=\"Helvetica\", fontsize=10];\n"
          "  edge [fontname=\"Helvetica\", fontsize=9];\n",
          out);
    for (size_t i = 0; i < tsr_graph_node_count(graph); i++)
        put_node(out, tsr_graph_node_at(graph, i));
    for (size_t i = 0; i < tsr_graph_node_count(graph); i++) {
        const tsr_graph_node *client = tsr_graph_node_at(graph, i);
        for (size_t e = 0; e < client->to_count; e++) {
            const tsr_graph_node *server = tsr_graph_node_at(graph, client->to[e]);
            fprintf(out, "  \"%s\" -> \"%s\" [label=\"%s", client->name, server->name,
                    tsr_transport_name(server->transport));
            if (server->listen) {
                fputs("\\n", out);
                put_escaped(out, server->listen);
            }
            fputs("\"];\n", out);
        }
    }
    fputs("}\n", out);
}

int cmd_dot(int argc, char **argv)
{
    tsr_graph *graph;
    unsigned flags;
    int rc = tsr_cli_load_graph(argc, argv, "dot", print_usage, &graph, &flags);
    if (!graph)
        return rc;
    (void)flags;
    put_graph(stdout, graph);
    tsr_graph_free(graph);
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "tessera dot: cannot write the output\n");
        return TSR_EXIT_FAIL;
    }
    return TSR_EXIT_OK;
}
