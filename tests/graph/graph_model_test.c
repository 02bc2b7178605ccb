/* tests/graph/graph_model_test.c — the graph model as a program using
 * tessera/graph.h sees it: fields, defaults, edges both ways, start order,
 * exec splitting, option text, chains built from the model, and that every
 * truncation of a valid file fails cleanly. Owns nothing shared.
 * Never: checks error wording (tests/graph/bad/ does, through the CLI). */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/chain.h"
#include "tessera/graph.h"
#include "tessera/spu.h"

#include "harness.h"

static tsr_graph *parse(const char *text, unsigned flags)
{
    tsr_error err;
    tsr_error_clear(&err);
    tsr_graph *g = tsr_graph_parse(text, strlen(text), "test.yaml", flags, &err);
    if (!g)
        fprintf(stderr, "unexpected error: %s\n", err.message);
    return g;
}

static const char *option(const tsr_chain_link *link, const char *key)
{
    for (size_t i = 0; i < link->option_count; i++)
        if (!strcmp(link->keys[i], key))
            return link->values[i];
    return NULL;
}

static void reads_nodes_chain_options_edges(void)
{
    tsr_graph *g = parse("version: 1\n"
                         "window: {width: 640, height: 480}\n"
                         "nodes:\n"
                         "  app:\n"
                         "    exec: [bin/spheres, --frames, '3']\n"
                         "    chain:\n"
                         "      - passthrough: {verbose: yes}\n"
                         "      - render: {output: out/f-%04d.png, width: 64}\n",
                         0);
    CHECK(g);
    if (!g)
        return;
    CHECK(tsr_graph_width(g) == 640 && tsr_graph_height(g) == 480);
    CHECK(!strcmp(tsr_graph_file(g), "test.yaml"));
    CHECK(tsr_graph_node_count(g) == 1 && tsr_graph_edge_count(g) == 0);
    const tsr_graph_node *app = tsr_graph_find(g, "app");
    CHECK(app && app == tsr_graph_node_at(g, 0));
    CHECK(tsr_graph_node_at(g, 1) == NULL && tsr_graph_find(g, "nobody") == NULL);
    if (app) {
        CHECK(app->exec_argc == 3 && !strcmp(app->exec[0], "bin/spheres") && !strcmp(app->exec[2], "3") &&
              app->exec[3] == NULL);
        CHECK(app->chain_length == 2);
        CHECK(!strcmp(app->chain[0].spu, "passthrough") && !strcmp(app->chain[1].spu, "render"));
        CHECK(option(&app->chain[0], "verbose") && !strcmp(option(&app->chain[0], "verbose"), "yes"));
        CHECK(option(&app->chain[1], "output") && !strcmp(option(&app->chain[1], "output"), "out/f-%04d.png"));
        CHECK(option(&app->chain[1], "width") && !strcmp(option(&app->chain[1], "width"), "64"));
        CHECK(!strcmp(app->host, TSR_GRAPH_DEFAULT_HOST));
        CHECK(app->mark.line == 4 && app->mark.column == 3);
        CHECK(app->to_count == 0 && app->from_count == 0 && app->tile_count == 0);
    }
    tsr_graph_free(g);
}

static void defaults_apply_and_nodes_override(void)
{
    tsr_graph *g = parse("version: 1\n"
                         "defaults: {host: alpha, transport: unix}\n"
                         "nodes:\n"
                         "  app: {exec: x, chain: [replicate], to: [near, far]}\n"
                         "  near: {chain: [render], listen: /tmp/near.sock}\n"
                         "  far: {chain: [render], host: beta, transport: tcp, listen: '7000',\n"
                         "        tiles: [[0, 0, 10, 20], [10, 0, 5, 5]]}\n",
                         TSR_GRAPH_NO_SPU_CHECK);
    CHECK(g);
    if (!g)
        return;
    CHECK(tsr_graph_width(g) == TSR_GRAPH_DEFAULT_WIDTH && tsr_graph_height(g) == TSR_GRAPH_DEFAULT_HEIGHT);
    const tsr_graph_node *app = tsr_graph_find(g, "app"), *near = tsr_graph_find(g, "near"),
                         *far = tsr_graph_find(g, "far");
    CHECK(app && near && far);
    if (app && near && far) {
        CHECK(!strcmp(app->host, "alpha") && !strcmp(near->host, "alpha"));
        CHECK(!strcmp(far->host, "beta"));
        CHECK(near->transport == TSR_TRANSPORT_UNIX && far->transport == TSR_TRANSPORT_TCP);
        CHECK(!strcmp(near->listen, "/tmp/near.sock") && !strcmp(far->listen, "7000"));
        CHECK(far->tile_count == 2 && far->tiles[1].x == 10 && far->tiles[1].width == 5 && far->tiles[0].height == 20);
        CHECK(app->exec_argc == 1 && !strcmp(app->exec[0], "x"));
        CHECK(near->exec == NULL);
        CHECK(!strcmp(tsr_transport_name(near->transport), "unix"));
    }
    tsr_graph_free(g);
}

/* Every edge appears as `to` on its client and `from` on its server, and
 * the start order puts each server before its clients. */
static void edges_both_ways_and_start_order(void)
{
    tsr_graph *g = parse("version: 1\n"
                         "nodes:\n"
                         "  app0: {exec: x, chain: [replicate], to: [relay, s1]}\n"
                         "  app1: {exec: x, chain: [pack], to: relay}\n"
                         "  relay: {chain: [passthrough, pack], to: [s2]}\n"
                         "  s1: {chain: [render]}\n"
                         "  s2: {chain: [render]}\n",
                         TSR_GRAPH_NO_SPU_CHECK);
    CHECK(g);
    if (!g)
        return;
    size_t n = tsr_graph_node_count(g), edges = 0, from_total = 0;
    const size_t *order = tsr_graph_start_order(g);
    size_t *position = calloc(n, sizeof *position);
    size_t *seen = calloc(n, sizeof *seen);
    CHECK(order && position && seen);
    for (size_t i = 0; order && position && seen && i < n; i++) {
        CHECK(order[i] < n);
        if (order[i] < n) {
            position[order[i]] = i;
            seen[order[i]]++;
        }
    }
    for (size_t i = 0; position && seen && i < n; i++) {
        const tsr_graph_node *node = tsr_graph_node_at(g, i);
        CHECK(seen[i] == 1);
        edges += node->to_count;
        from_total += node->from_count;
        for (size_t e = 0; e < node->to_count; e++) {
            const tsr_graph_node *server = tsr_graph_node_at(g, node->to[e]);
            bool listed = false;
            for (size_t f = 0; f < server->from_count; f++)
                listed |= server->from[f] == i;
            CHECK(listed);
            CHECK(position[node->to[e]] < position[i]);
        }
    }
    CHECK(edges == tsr_graph_edge_count(g) && from_total == edges && edges == 4);
    const tsr_graph_node *relay = tsr_graph_find(g, "relay");
    CHECK(relay && relay->from_count == 2 && relay->to_count == 1);
    free(position);
    free(seen);
    tsr_graph_free(g);
}

static void exec_string_is_split_like_a_shell(void)
{
    tsr_graph *g = parse("version: 1\n"
                         "nodes:\n"
                         "  app:\n"
                         "    exec: >-\n"
                         "      bin/x --out 'a b' \"c d\" e\\ f g\"h i\"\n"
                         "    chain: [render]\n",
                         0);
    CHECK(g);
    if (!g)
        return;
    const tsr_graph_node *app = tsr_graph_node_at(g, 0);
    const char *want[] = {"bin/x", "--out", "a b", "c d", "e f", "gh i"};
    CHECK(app->exec_argc == 6);
    for (size_t i = 0; i < 6 && i < app->exec_argc; i++)
        CHECK(!strcmp(app->exec[i], want[i]));
    CHECK(app->exec[app->exec_argc] == NULL);
    tsr_graph_free(g);
}

static void list_option_values_use_chain_text(void)
{
    tsr_graph *g = parse("version: 1\n"
                         "nodes:\n"
                         "  app: {exec: x, chain: [{someday: {sizes: [1, 2, 3], name: '', on: }}]}\n",
                         TSR_GRAPH_NO_SPU_CHECK);
    CHECK(g);
    if (!g)
        return;
    const tsr_chain_link *link = &tsr_graph_node_at(g, 0)->chain[0];
    CHECK(!strcmp(link->spu, "someday") && link->option_count == 3);
    CHECK(option(link, "sizes") && !strcmp(option(link, "sizes"), "1,2,3"));
    CHECK(option(link, "name") && !strcmp(option(link, "name"), ""));
    CHECK(option(link, "on") && !strcmp(option(link, "on"), ""));
    tsr_graph_free(g);
}

/* The model's links are what tsr_chain_create_links takes. */
static void chain_builds_from_the_model(void)
{
    tsr_graph *g = parse("version: 1\n"
                         "nodes:\n"
                         "  app:\n"
                         "    exec: x\n"
                         "    chain: [passthrough, {passthrough: {verbose: false}}]\n",
                         0);
    CHECK(g);
    if (!g)
        return;
    const tsr_graph_node *app = tsr_graph_node_at(g, 0);
    tsr_error err;
    tsr_error_clear(&err);
    tsr_chain *chain = tsr_chain_create_links(app->chain, app->chain_length, &err);
    if (!chain)
        fprintf(stderr, "chain: %s\n", err.message);
    CHECK(chain && tsr_chain_head(chain));
    tsr_chain_destroy(chain);
    tsr_graph_free(g);
}

/* Cutting a valid file anywhere gives a graph or an error that starts with
 * the file name and a position — never a crash or an unplaced message. */
static void every_truncation_fails_cleanly(void)
{
    static const char text[] = "version: 1\n"
                               "window: {width: 1024, height: 768}\n"
                               "defaults: {host: localhost, transport: tcp}\n"
                               "nodes:\n"
                               "  app:\n"
                               "    exec: \"bin/spheres --frames 2\"\n"
                               "    chain:\n"
                               "      - tilesort: {bucket: grid}\n"
                               "    to: [left, right]\n"
                               "  left:\n"
                               "    tiles: [[0, 0, 512, 768]]\n"
                               "    listen: 127.0.0.1:0\n"
                               "    chain: [render]\n"
                               "  right:\n"
                               "    tiles: [[512, 0, 512, 768]]\n"
                               "    chain: [{render: {output: 'out/r-%04d.png'}}]\n";
    size_t ok = 0;
    for (size_t len = 0; len <= sizeof text - 1; len++) {
        tsr_error err;
        tsr_error_clear(&err);
        tsr_graph *g = tsr_graph_parse(text, len, "cut.yaml", TSR_GRAPH_NO_SPU_CHECK, &err);
        if (g) {
            ok++;
            tsr_graph_free(g);
            continue;
        }
        int line = 0, column = 0;
        CHECK(sscanf(err.message, "cut.yaml:%d:%d: ", &line, &column) == 2 && line >= 1 && column >= 1);
        CHECK(err.code != TSR_OK && !strchr(err.message, '\n'));
    }
    CHECK(ok >= 1); /* at least the whole text */
}

/* Classes registered in-process, one per network role, none of them known
 * to the core by name: what a third party's network SPU declares. */
static void *role_create(const tsr_spu_init *init, tsr_error *err)
{
    (void)init;
    void *self = malloc(1);
    if (!self)
        tsr_error_set(err, TSR_ENOMEM, "out of memory");
    return self;
}
static void role_destroy(void *self) { free(self); }

static const tsr_option_spec role_options[] = {
    {.name = "to_one", .type = TSR_OPT_STRING, .default_value = "", .min = 1, .max = 0},
    {.name = "to_all", .type = TSR_OPT_STRING_LIST, .default_value = "", .min = 1, .max = 0},
    {.name = "own", .type = TSR_OPT_STRING, .default_value = "", .min = 1, .max = 0},
    {.name = "theirs", .type = TSR_OPT_STRING_LIST, .default_value = "", .min = 1, .max = 0},
    {.name = "place", .type = TSR_OPT_INT, .default_value = "0", .min = 0, .max = 1000},
    {.name = "group", .type = TSR_OPT_STRING_LIST, .default_value = "", .min = 1, .max = 0},
};
#define ROLE_CLASS(id, ...)                                                                                           \
    {                                                                                                                 \
        .abi = TSR_SPU_ABI, .name = id, .summary = "test role", .options = role_options,                              \
        .option_count = sizeof role_options / sizeof role_options[0], .create = role_create, .destroy = role_destroy, \
        .network = __VA_ARGS__                                                                                        \
    }
static const tsr_spu_class role_classes[] = {
    ROLE_CLASS("t_one", {.role = TSR_SPU_ROLE_SERVER, .server = "to_one"}),
    ROLE_CLASS("t_all", {.role = TSR_SPU_ROLE_SERVERS, .servers = "to_all"}),
    ROLE_CLASS("t_tiled", {.role = TSR_SPU_ROLE_TILED_SERVERS, .servers = "to_all", .server_tiles = "theirs"}),
    ROLE_CLASS("t_display", {.role = TSR_SPU_ROLE_DISPLAY, .display = "to_one", .tiles = "own", .rank = "place"}),
    ROLE_CLASS("t_peers", {.role = TSR_SPU_ROLE_PEERS, .display = "to_one", .rank = "place", .peers = "group"}),
    ROLE_CLASS("t_filter", {.role = TSR_SPU_ROLE_NONE, .tiles = "own"}),
    /* the coming sort-last SPU, under its name */
    ROLE_CLASS("binaryswap", {.role = TSR_SPU_ROLE_PEERS, .display = "to_one", .rank = "place", .peers = "group"}),
};

static void register_role_classes(void)
{
    for (size_t i = 0; i < sizeof role_classes / sizeof role_classes[0]; i++) {
        tsr_error err;
        tsr_error_clear(&err);
        int rc = tsr_spu_register(&role_classes[i], &err);
        if (rc != TSR_OK)
            fprintf(stderr, "register %s: %s\n", role_classes[i].name, err.message);
        CHECK(rc == TSR_OK);
    }
}

/* A graph around one app node whose chain is `spu`, sending to the nodes
 * of `to` (YAML), with `servers` (YAML node entries) after it. */
static int graph_checks(const char *spu, const char *to, const char *servers)
{
    char text[2048];
    snprintf(text, sizeof text,
             "version: 1\n"
             "window: {width: 64, height: 32}\n"
             "nodes:\n"
             "  app:\n"
             "    exec: bin/spheres\n"
             "    chain: [%s]\n"
             "    to: %s\n"
             "%s",
             spu, to, servers);
    tsr_error err;
    tsr_error_clear(&err);
    tsr_graph *g = tsr_graph_parse(text, strlen(text), "roles.yaml", 0, &err);
    tsr_graph_free(g);
    return g ? TSR_OK : err.code;
}

#define SERVER(name, tiles) "  " name ":\n    chain: [t_filter]\n" tiles
#define TILE(x) "    tiles: [[" #x ", 0, 32, 32]]\n"

/* The graph's rules follow each class's declared role, whatever its name:
 * one server, every server, tiled servers, a display, a group of peers. */
static void roles_decide_the_graph_rules(void)
{
    register_role_classes();
    const char *two = SERVER("a", TILE(0)) SERVER("b", TILE(32));
    /* one server */
    CHECK(graph_checks("t_one", "a", SERVER("a", "")) == TSR_OK);
    /* every server: any number */
    CHECK(graph_checks("t_all", "[a, b]", two) == TSR_OK);
    /* tiled servers: every one has tiles */
    CHECK(graph_checks("t_tiled", "[a, b]", two) == TSR_OK);
    CHECK(graph_checks("t_tiled", "[a, b]", SERVER("a", TILE(0)) SERVER("b", "")) == TSR_EINVAL);
    /* no role: no to: */
    CHECK(graph_checks("t_filter", "[a]", SERVER("a", "")) == TSR_EINVAL);
    /* display: tile servers sending to one display, disjoint tiles */
    const char *wall = "  a:\n    chain: [t_display]\n    to: d\n" TILE(
        0) "  b:\n    chain: [t_display]\n    to: d\n" TILE(32) "  d:\n    chain: [t_filter]\n";
    CHECK(graph_checks("t_all", "[a, b]", wall) == TSR_OK);
    const char *overlap = "  a:\n    chain: [t_display]\n    to: d\n" TILE(
        0) "  b:\n    chain: [t_display]\n    to: d\n" TILE(16) "  d:\n    chain: [t_filter]\n";
    CHECK(graph_checks("t_all", "[a, b]", overlap) == TSR_EINVAL);
    const char *two_displays = "  a:\n    chain: [t_display]\n    to: [d, e]\n"
                               "  d:\n    chain: [t_filter]\n  e:\n    chain: [t_filter]\n";
    CHECK(graph_checks("t_one", "a", two_displays) == TSR_EINVAL);
    /* peers: servers sending to one display (overlap is theirs to sort out) */
    const char *peers = "  a:\n    chain: [t_peers]\n    to: d\n"
                        "  b:\n    chain: [t_peers]\n    to: d\n"
                        "  d:\n    chain: [t_filter]\n";
    CHECK(graph_checks("t_all", "[a, b]", peers) == TSR_OK);
    const char *peers_two = "  a:\n    chain: [t_peers]\n    to: [d, e]\n"
                            "  d:\n    chain: [t_filter]\n  e:\n    chain: [t_filter]\n";
    CHECK(graph_checks("t_one", "a", peers_two) == TSR_EINVAL);
    /* an app node may be a peer (in situ: sort-last, issue 11); its
     * group's rules are core/graph/groups.c's (tests/binaryswap) */
    CHECK(graph_checks("t_peers", "d", "  d:\n    chain: [t_filter]\n") == TSR_OK);
    /* Structure only: an SPU not installed here has no known role, so its
     * node's to: is neither required nor refused. */
    static const char unknown[] = "version: 1\n"
                                  "nodes:\n"
                                  "  app: {exec: bin/spheres, chain: [not_installed_here], to: s}\n"
                                  "  s: {chain: [render]}\n";
    tsr_error err;
    tsr_error_clear(&err);
    tsr_graph *g = tsr_graph_parse(unknown, strlen(unknown), "unknown.yaml", TSR_GRAPH_NO_SPU_CHECK, &err);
    CHECK(g != NULL);
    tsr_graph_free(g);
    CHECK(!tsr_graph_parse(unknown, strlen(unknown), "unknown.yaml", 0, &err));
}

static void network_spus_are_known(void)
{
    register_role_classes(); /* binaryswap: the coming sort-last SPU's role */
    const char *network[] = {"pack", "replicate", "tilesort", "binaryswap", "readback"};
    for (size_t i = 0; i < 5; i++)
        CHECK(tsr_spu_is_network(network[i]));
    CHECK(!tsr_spu_is_network("render") && !tsr_spu_is_network("passthrough") && !tsr_spu_is_network(NULL));
}

static bool rects_overlap(const int *a, const int *b)
{
    return a[0] < b[0] + b[2] && b[0] < a[0] + a[2] && a[1] < b[1] + b[3] && b[1] < a[1] + a[3];
}

/* The overlap search (a sweep) against every pair, on random tiles of one
 * server: it finds an overlap exactly when a pair overlaps, and the two
 * tiles it names do. Then the same for the tiles of display senders. */
static void tile_overlaps_match_every_pair(void)
{
    static char text[65536];
    int tiles[40][4];
    unsigned seed = 12345;
    int overlapping = 0;
    for (int round = 0; round < 600; round++) {
        int n = 2 + (int)((seed = seed * 1103515245u + 12345u) >> 16) % 12;
        size_t used = (size_t)snprintf(text, sizeof text,
                                       "version: 1\nwindow: {width: 64, height: 48}\nnodes:\n"
                                       "  app: {exec: a, chain: [tilesort], to: wall}\n"
                                       "  wall:\n    chain: [render]\n    tiles:\n");
        for (int i = 0; i < n; i++) {
            int *t = tiles[i];
            for (int f = 0; f < 4; f++)
                t[f] = (int)((seed = seed * 1103515245u + 12345u) >> 16);
            t[2] = 1 + t[2] % 12;
            t[3] = 1 + t[3] % 12;
            t[0] %= 64 - t[2] + 1;
            t[1] %= 48 - t[3] + 1;
            used +=
                (size_t)snprintf(text + used, sizeof text - used, "      - [%d, %d, %d, %d]\n", t[0], t[1], t[2], t[3]);
        }
        bool any = false;
        for (int i = 0; i < n; i++)
            for (int j = 0; j < i; j++)
                any |= rects_overlap(tiles[i], tiles[j]);
        overlapping += any;
        tsr_error err;
        tsr_error_clear(&err);
        tsr_graph *g = tsr_graph_parse(text, used, "tiles.yaml", 0, &err);
        CHECK(!g == any, "round %d: overlap %d, parse: %s", round, any, g ? "ok" : err.message);
        int a = 0, b = 0;
        const char *at = strstr(err.message, "'tiles': tile ");
        if (!g && at && sscanf(at, "'tiles': tile %d [%*d, %*d, %*d, %*d] overlaps tile %d", &a, &b) == 2)
            CHECK(a > b && b >= 1 && a <= n && rects_overlap(tiles[a - 1], tiles[b - 1]), "round %d: %s", round,
                  err.message);
        else
            CHECK(g, "round %d: %s", round, err.message);
        tsr_graph_free(g);
    }
    CHECK(overlapping > 100 && overlapping < 500, "%d of 600 rounds overlap", overlapping);
}

/* Listen addresses on one host: equal ports collide unless the bind
 * addresses differ; port 0 never; unix paths when equal; the first node in
 * file order that collides is named, with the first one it collides with. */
static void listen_collisions_follow_bind_addresses(void)
{
    static const struct {
        const char *a, *b, *c; /* listen: of three servers ("" = none) */
        const char *collision; /* "node 'X' ... collides with node 'Y'", or NULL */
    } cases[] = {
        {"7000", "127.0.0.1:7000", "",
         "node 's2': 'listen' address '127.0.0.1:7000' on host 'localhost' collides "
         "with node 's1' ('7000')"},
        {"127.0.0.1:7000", "127.0.0.2:7000", "", NULL},
        {"127.0.0.1:7000", "127.0.0.2:7000", "7000",
         "node 's3': 'listen' address '7000' on host 'localhost' "
         "collides with node 's1'"},
        {"127.0.0.2:7000", "127.0.0.1:7000", "127.0.0.1:7000",
         "node 's3': 'listen' address '127.0.0.1:7000' on "
         "host 'localhost' collides with node 's2'"},
        {"0", "0", "127.0.0.1:0", NULL},
        {"7000", "7001", "[::1]:7000",
         "node 's3': 'listen' address '[::1]:7000' on host 'localhost' collides with "
         "node 's1'"},
        {"[::1]:7000", "127.0.0.1:7000", "", NULL},
        {"07000", "7000", "", "node 's2': 'listen' address '7000' on host 'localhost' collides with node 's1'"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[1024];
        const char *listen[3] = {cases[i].a, cases[i].b, cases[i].c};
        size_t used = (size_t)snprintf(text, sizeof text,
                                       "version: 1\nnodes:\n  app: {exec: a, chain: [replicate], to: [s1, s2, s3]}\n");
        for (int s = 0; s < 3; s++)
            used += (size_t)snprintf(text + used, sizeof text - used, "  s%d: {chain: [render]%s%s%s}\n", s + 1,
                                     listen[s][0] ? ", listen: '" : "", listen[s], listen[s][0] ? "'" : "");
        tsr_error err;
        tsr_error_clear(&err);
        tsr_graph *g = tsr_graph_parse(text, used, "listen.yaml", TSR_GRAPH_NO_SPU_CHECK, &err);
        if (cases[i].collision) {
            CHECK(!g, "case %zu accepted", i);
            CHECK_CONTAINS(err.message, cases[i].collision);
        } else {
            CHECK(g, "case %zu: %s", i, err.message);
        }
        tsr_graph_free(g);
    }
    /* The same ports on two hosts, and a unix path used twice. */
    const char *hosts = "version: 1\nnodes:\n  app: {exec: a, chain: [replicate], to: [s1, s2]}\n"
                        "  s1: {chain: [render], listen: '7000', host: a}\n"
                        "  s2: {chain: [render], listen: '7000', host: b}\n";
    tsr_error err;
    tsr_error_clear(&err);
    tsr_graph *g = tsr_graph_parse(hosts, strlen(hosts), "hosts.yaml", TSR_GRAPH_NO_SPU_CHECK, &err);
    CHECK(g, "%s", err.message);
    tsr_graph_free(g);
    const char *unix_paths = "version: 1\nnodes:\n  app: {exec: a, chain: [replicate], to: [s1, s2]}\n"
                             "  s1: {chain: [render], transport: unix, listen: /tmp/x.sock}\n"
                             "  s2: {chain: [render], transport: unix, listen: /tmp/x.sock}\n";
    g = tsr_graph_parse(unix_paths, strlen(unix_paths), "unix.yaml", TSR_GRAPH_NO_SPU_CHECK, &err);
    CHECK(!g);
    CHECK_CONTAINS(err.message, "unix.yaml:5:50: node 's2': 'listen' address '/tmp/x.sock'");
    tsr_graph_free(g);
}

int main(int argc, char **argv)
{
    static const struct {
        const char *name;
        void (*run)(void);
    } tests[] = {
        {"reads_nodes_chain_options_edges", reads_nodes_chain_options_edges},
        {"defaults_apply_and_nodes_override", defaults_apply_and_nodes_override},
        {"edges_both_ways_and_start_order", edges_both_ways_and_start_order},
        {"exec_string_is_split_like_a_shell", exec_string_is_split_like_a_shell},
        {"list_option_values_use_chain_text", list_option_values_use_chain_text},
        {"chain_builds_from_the_model", chain_builds_from_the_model},
        {"every_truncation_fails_cleanly", every_truncation_fails_cleanly},
        {"network_spus_are_known", network_spus_are_known},
        {"roles_decide_the_graph_rules", roles_decide_the_graph_rules},
        {"tile_overlaps_match_every_pair", tile_overlaps_match_every_pair},
        {"listen_collisions_follow_bind_addresses", listen_collisions_follow_bind_addresses},
    };
    if (argc != 2) {
        fprintf(stderr, "usage: %s TEST\n", argv[0]);
        return 2;
    }
    for (size_t i = 0; i < sizeof tests / sizeof tests[0]; i++)
        if (!strcmp(argv[1], tests[i].name)) {
            tests[i].run();
            if (harness_failures)
                fprintf(stderr, "%s: %d checks failed\n", argv[1], harness_failures);
            return harness_failures ? 1 : 0;
        }
    fprintf(stderr, "unknown test '%s'\n", argv[1]);
    return 2;
}
