/* cli/cmd_check.c — `tessera check GRAPH`: loads and validates a graph file
 * and prints a one-line summary, or the FILE:LINE:COL error. Owns: the
 * command's arguments and output. Never: starts any node or SPU instance. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "tessera/graph.h"

static void print_usage(FILE *out)
{
    fprintf(out, "usage: tessera check [--no-spu-check] GRAPH\n\n"
                 "Validates the graph file GRAPH (YAML, see tessera/graph.h and\n"
                 "examples/graphs/README.md): keys and their types, node names, edges,\n"
                 "cycles, servers, tiles, transports, and every SPU and option against the\n"
                 "installed SPUs (see `tessera spus`). Prints\n"
                 "  ok: N nodes, E edges, window WxH\n"
                 "or one line FILE:LINE:COL: message naming the offending key or value.\n\n"
                 "  --no-spu-check  check the structure only; do not look SPUs up (for graphs\n"
                 "                  whose SPUs are not installed here)\n"
                 "  -h, --help      show this help\n\n"
                 "Exit codes: 0 valid, 1 runtime failure (out of memory), 2 invalid graph,\n"
                 "unreadable file or bad arguments.\n");
}

int cmd_check(int argc, char **argv)
{
    tsr_graph *graph;
    unsigned flags;
    int rc = tsr_cli_load_graph(argc, argv, "check", print_usage, &graph, &flags);
    if (!graph)
        return rc;
    size_t nodes = tsr_graph_node_count(graph), edges = tsr_graph_edge_count(graph);
    printf("ok: %zu node%s, %zu edge%s, window %dx%d%s\n", nodes, nodes == 1 ? "" : "s", edges, edges == 1 ? "" : "s",
           tsr_graph_width(graph), tsr_graph_height(graph),
           flags & TSR_GRAPH_NO_SPU_CHECK ? " (structure only: SPUs not checked)" : "");
    tsr_graph_free(graph);
    return TSR_EXIT_OK;
}
