/* tessera/graph.h — the graph file: which processes (nodes) run which SPU
 * chains, on which hosts, and who streams to whom. A YAML file is parsed
 * with libyaml into a validated, read-only model; every error names
 * FILE:LINE:COLUMN and the offending key or value, on one line.
 * Library libtessera_graph (pkg-config tessera-graph), the only one that
 * links libyaml: programs that read graphs use it, SPUs never need it.
 *
 * The file (version 1):
 *
 *   version: 1                        # required; the only version so far
 *   window: {width: 1024, height: 768}  # optional, default 1024x768; each
 *                                     # side an integer in [1, 16384]
 *   defaults:                         # optional: host and transport for
 *     host: localhost                 #   the nodes that do not set them
 *     transport: tcp
 *   nodes:                            # required, at least one node
 *     app:                            # node name: [A-Za-z0-9_.-]+, unique
 *       exec: bin/spheres --frames 20
 *       chain:
 *         - tilesort: {bucket: grid}
 *       to: [wall0, wall1]
 *     wall0:
 *       tiles: [[0, 0, 512, 768]]
 *       chain:
 *         - render: {output: "out/wall0-%04d.png"}
 *     ...
 *
 * Node keys:
 *   exec:      the application this node runs under the faker: a string
 *              (split at blanks; "..." and '...' quote, \ escapes, as in
 *              a shell, but nothing is expanded and no shell runs) or a
 *              list of arguments; each shorter than 128 KiB, together at
 *              most TSR_GRAPH_MAX_EXEC_BYTES (as execve will count them).
 *              A node with
 *              `exec` is an *app node*; a node without is a *server* that
 *              receives streams from the nodes whose `to:` names it.
 *   chain:     required, non-empty list of SPUs, calls flowing from the
 *              first to the last. Each entry is `spu`, `spu:` or
 *              `spu: {option: value, ...}`; values are scalars, or lists
 *              of scalars for list options (a list for another option is
 *              a type error). Unknown SPUs and options, and
 *              bad values, are errors (checked against the installed SPUs
 *              with the same parser chains use).
 *   to:        the servers this node's network SPU sends to: a node name or
 *              a list of names. Required (non-empty) when the chain holds a
 *              network SPU (one whose class declares a network role,
 *              tessera/spu.h; the first such SPU of the chain is the node's
 *              network SPU), forbidden otherwise.
 *   host:      where the node runs (default: defaults.host, else
 *              "localhost"). Compared as text: "localhost" and "127.0.0.1"
 *              are different hosts here.
 *   transport: how this node's clients reach it (servers only): tcp
 *              (default) or unix (Unix-domain socket, every client on the
 *              same host). inproc (the server's chain in its one client's
 *              process) is refused: `tessera run` starts every server as
 *              a process of its own.
 *   listen:    where a server listens (servers only). tcp: "PORT",
 *              "HOST:PORT" (HOST shorter than 160 bytes) or "[IPv6]:PORT",
 *              PORT in [0, 65535], 0 or no `listen` = a free port on
 *              loopback chosen at run time. unix: a socket path (shorter
 *              than 108 bytes); none = chosen at run time. Two servers on
 *              one host may not share an address.
 *   tiles:     list of [x, y, width, height] rectangles of the window this
 *              server draws (servers only); inside the window, positive
 *              sizes, not overlapping each other on one node.
 *
 * Keys are lower case; unknown keys are errors (with a "did you mean"),
 * and so is a key given twice. A value may be a YAML alias (*name) of an
 * anchor, but then errors point at the anchor.
 *
 * Graph rules besides the types of values: node names are unique, `to:`
 * names existing nodes other than app nodes, each at most once; the edges
 * have no cycle; every server is sent to by at least one node. The role
 * its network SPU's class declares (tsr_spu_network.role) asks more of a
 * node: tiled servers (TSR_SPU_ROLE_TILED_SERVERS, tilesort) — every server it
 * names has `tiles:`, or, when the graph gives the SPU's declared grid option
 * (tsr_spu_network.grid) non-zero, COLUMNS x ROWS servers none of which has
 * `tiles:` (the grid divides the program's window at run time); a display (TSR_SPU_ROLE_DISPLAY, readback: a tile
 * server streaming its tile images) — `to:` names exactly one node, and
 * the nodes sending to one display this way own disjoint tiles (no tiles:
 * the whole window); peers (TSR_SPU_ROLE_PEERS) — `to:` names exactly one
 * display, and the node is a server (peers reach each other at their
 * addresses). No rule knows an SPU by name.
 *
 * The model is immutable once loaded; strings and arrays live as long as
 * the graph. Nodes keep their position in the file so later errors (a node
 * that failed to start) can point at it. */
#ifndef TESSERA_GRAPH_H
#define TESSERA_GRAPH_H

#include <stdbool.h>
#include <stddef.h>

#include "tessera/chain.h"
#include "tessera/error.h"
#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TSR_GRAPH_VERSION 1
#define TSR_GRAPH_DEFAULT_WIDTH 1024
#define TSR_GRAPH_DEFAULT_HEIGHT 768
#define TSR_GRAPH_MAX_SIDE 16384
#define TSR_GRAPH_DEFAULT_HOST "localhost"
/* Limits that bound the work a graph file can ask for; each is refused
 * with an error naming the limit and its value. The file size is checked
 * before the file is read (tsr_graph_load) or parsed; nesting, anchors and
 * what aliases expand to (at most twice the file size limit, counted as
 * YAML nodes plus scalar bytes) while the YAML is read, before the
 * document is built. */
#define TSR_GRAPH_MAX_FILE_BYTES (4 << 20) /* 4 MiB */
#define TSR_GRAPH_MAX_DEPTH 64             /* nested lists and mappings */
#define TSR_GRAPH_MAX_NODES 65536
#define TSR_GRAPH_MAX_ANCHORS 256 /* YAML anchors (&name) in one file */
/* An exec's arguments, each counted with its NUL and pointer, as execve
 * will; a single argument is limited to 128 KiB - 1 as Linux limits it. */
#define TSR_GRAPH_MAX_EXEC_BYTES (1 << 20)

typedef enum tsr_transport {
    TSR_TRANSPORT_TCP,
    TSR_TRANSPORT_UNIX,
    TSR_TRANSPORT_INPROC,
} tsr_transport;

/* Flags for tsr_graph_load / tsr_graph_parse. */
enum {
    /* Check the structure only: SPU names must be well formed, and their
     * options are not checked. SPUs are looked up only for their network
     * roles; a node whose chain holds an SPU that is not installed here
     * has no known role, and the rules about `to:` skip it. For drawing or
     * checking graphs whose SPUs are not installed here. */
    TSR_GRAPH_NO_SPU_CHECK = 1u << 0,
};

/* A place in the graph file; line and column count from 1. */
typedef struct tsr_graph_mark {
    int line;
    int column;
} tsr_graph_mark;

typedef struct tsr_graph_tile {
    int x, y, width, height; /* window pixels, origin bottom-left as in GL */
} tsr_graph_tile;

typedef struct tsr_graph_node {
    const char *name;
    const char *host;        /* never NULL */
    const char *const *exec; /* argv, NULL-terminated; NULL for a server */
    size_t exec_argc;
    const tsr_chain_link *chain; /* ready for tsr_chain_create_links */
    size_t chain_length;         /* >= 1 */
    const size_t *to;            /* indices of the servers sent to */
    size_t to_count;
    const size_t *from; /* indices of the nodes sending here */
    size_t from_count;
    tsr_transport transport; /* how clients reach it (servers) */
    const char *listen;      /* NULL: chosen at run time */
    const tsr_graph_tile *tiles;
    size_t tile_count;
    tsr_graph_mark mark; /* where the node's name is in the file */
} tsr_graph_node;

typedef struct tsr_graph tsr_graph;

/* Reads and validates the graph file at `path`. Returns NULL with `err`
 * filled ("graph.yaml:7:9: unknown key 'chian' (did you mean 'chain'?)")
 * on any error. `flags`: TSR_GRAPH_* or 0. */
TSR_API tsr_graph *tsr_graph_load(const char *path, unsigned flags, tsr_error *err);
/* The same from memory; `file_name` is used in messages. */
TSR_API tsr_graph *tsr_graph_parse(const char *text, size_t length, const char *file_name, unsigned flags,
                                   tsr_error *err);
TSR_API void tsr_graph_free(tsr_graph *graph);

TSR_API const char *tsr_graph_file(const tsr_graph *graph);
TSR_API int tsr_graph_width(const tsr_graph *graph);
TSR_API int tsr_graph_height(const tsr_graph *graph);
/* Nodes in file order. */
TSR_API size_t tsr_graph_node_count(const tsr_graph *graph);
TSR_API const tsr_graph_node *tsr_graph_node_at(const tsr_graph *graph, size_t index);
/* NULL when no node has that name. */
TSR_API const tsr_graph_node *tsr_graph_find(const tsr_graph *graph, const char *name);
/* The number of client -> server connections (sum of to_count). */
TSR_API size_t tsr_graph_edge_count(const tsr_graph *graph);
/* tsr_graph_node_count node indices, ordered so every server comes before
 * the nodes that send to it (the order to start them in). */
TSR_API const size_t *tsr_graph_start_order(const tsr_graph *graph);

/* "tcp", "unix", "inproc". */
TSR_API const char *tsr_transport_name(tsr_transport transport);
/* True when the SPU called `spu_name` is found (tsr_spu_find) and its class
 * declares a network role (tsr_spu_network.role other than
 * TSR_SPU_ROLE_NONE): a chain holding one needs `to:`. False for NULL and
 * for SPUs that cannot be found. */
TSR_API bool tsr_spu_is_network(const char *spu_name);

#ifdef __cplusplus
}
#endif
#endif
