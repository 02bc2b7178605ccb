/* tests/fuzz/fuzz_graph.c — fuzz target for the graph YAML loader
 * (tessera/graph.h, core/graph): the input is a graph file, parsed with the
 * SPU checks on (the real SPU plugins of this build, found by the loader),
 * as `tessera check` and `tessera run` read it. Owns one graph per input.
 * Checked: a rejection is a one-line message naming the file; an accepted
 * graph is a consistent model (edges both ways, indices in range, names
 * found by tsr_graph_find, a start order that is a permutation placing
 * every server before its senders, chains that turn into chain text). */
#include "fuzz_target.h"

#include <stdbool.h>
#include <stdlib.h>

#include "tessera/chain.h"
#include "tessera/graph.h"

#define FILE_NAME "fuzz.yaml"

static void check_model(const tsr_graph *g)
{
    size_t n = tsr_graph_node_count(g), edges = 0;
    FUZZ_REQUIRE(n >= 1);
    FUZZ_REQUIRE(tsr_graph_width(g) >= 1 && tsr_graph_width(g) <= TSR_GRAPH_MAX_SIDE);
    FUZZ_REQUIRE(tsr_graph_height(g) >= 1 && tsr_graph_height(g) <= TSR_GRAPH_MAX_SIDE);
    for (size_t i = 0; i < n; i++) {
        const tsr_graph_node *node = tsr_graph_node_at(g, i);
        FUZZ_REQUIRE(node && node->name && node->host && node->chain_length >= 1);
        FUZZ_REQUIRE(tsr_graph_find(g, node->name) == node);
        for (size_t k = 0; node->exec && k < node->exec_argc; k++)
            FUZZ_REQUIRE(node->exec[k] != NULL);
        FUZZ_REQUIRE(!node->exec || node->exec[node->exec_argc] == NULL);
        for (size_t t = 0; t < node->to_count; t++) {
            size_t j = node->to[t];
            FUZZ_REQUIRE(j < n && j != i);
            const tsr_graph_node *server = tsr_graph_node_at(g, j);
            FUZZ_REQUIRE(server->exec == NULL);
            bool back = false;
            for (size_t f = 0; f < server->from_count; f++)
                back = back || server->from[f] == i;
            FUZZ_REQUIRE(back);
        }
        for (size_t f = 0; f < node->from_count; f++)
            FUZZ_REQUIRE(node->from[f] < n);
        for (size_t t = 0; t < node->tile_count; t++) {
            const tsr_graph_tile *tile = &node->tiles[t];
            FUZZ_REQUIRE(tile->width >= 1 && tile->height >= 1 && tile->x >= 0 && tile->y >= 0);
            FUZZ_REQUIRE(tile->x + tile->width <= tsr_graph_width(g) && tile->y + tile->height <= tsr_graph_height(g));
        }
        edges += node->to_count;
        tsr_error err = {0};
        char *text = tsr_chain_links_text(node->chain, node->chain_length, &err);
        FUZZ_REQUIRE(text != NULL);
        free(text);
        FUZZ_REQUIRE(strcmp(tsr_transport_name(node->transport), "unknown") != 0);
    }
    FUZZ_REQUIRE(edges == tsr_graph_edge_count(g));
    const size_t *order = tsr_graph_start_order(g);
    FUZZ_REQUIRE(order != NULL);
    bool *started = calloc(n, sizeof *started);
    FUZZ_REQUIRE(started != NULL);
    for (size_t k = 0; k < n; k++) {
        size_t i = order[k];
        FUZZ_REQUIRE(i < n && !started[i]);
        const tsr_graph_node *node = tsr_graph_node_at(g, i);
        for (size_t t = 0; t < node->to_count; t++)
            FUZZ_REQUIRE(started[node->to[t]]);
        started[i] = true;
    }
    free(started);
}

int fuzz_target_explain(const uint8_t *data, size_t size, char *why, size_t why_size)
{
    /* An exact-size copy without a terminator: the loader takes a length. */
    char *text = malloc(size ? size : 1);
    FUZZ_REQUIRE(text != NULL);
    memcpy(text, data, size);
    tsr_error err = {0};
    tsr_graph *g = tsr_graph_parse(text, size, FILE_NAME, 0, &err);
    free(text);
    if (!g) {
        FUZZ_REQUIRE(err.code != TSR_OK);
        FUZZ_REQUIRE(strncmp(err.message, FILE_NAME, strlen(FILE_NAME)) == 0);
        return fuzz_rejected(err.code, &err, why, why_size);
    }
    check_model(g);
    tsr_graph_free(g);
    return TSR_OK;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_target_explain(data, size, NULL, 0);
    return 0;
}
