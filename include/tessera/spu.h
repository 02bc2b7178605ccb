/* tessera/spu.h — writing a stream processing unit (SPU).
 *
 * An SPU is a shared library exporting one function, tsr_spu_describe(),
 * that returns a static tsr_spu_class: name, optional super SPU, typed
 * options, and create/destroy. Everything an instance needs arrives in
 * tsr_spu_init; the SPU keeps it in the instance it returns. No globals:
 * two instances of the same SPU in one process must work.
 *
 * An SPU that sends its stream to other nodes also declares its role in a
 * graph (tsr_spu_class.network, below): one server, several, tiled
 * servers, a display, or a group of peers, and which of its options a
 * graph run fills (addresses, token, tiles, rank, peers). Graphs and the
 * mothership know SPUs only by these declarations, never by name.
 *
 * Building a chain "a ! b ! c" (calls enter a, flow to c):
 *   c is created first; its child is a table of no-ops. Then b with child =
 *   c's resolved table, then a. An SPU with a super gets a super instance
 *   created first (same child, its own options from the same set). Slots
 *   the SPU leaves empty in `table` are taken from the super's table, else
 *   from the child's, so an SPU implements only what it changes.
 *
 * Inheriting: `.super = "render"` makes every GL call the SPU does not
 *   take go to a render instance of its own (its super instance). What the
 *   SPU takes, it may pass on through init->super (the super's resolved
 *   table). Beyond the table, a super may publish functions for its
 *   subclasses (tsr_spu_class.api, declared by a header of that SPU, e.g.
 *   tessera/dev/render.h); a subclass calls them with init->super_instance.
 *   readback and binaryswap inherit render this way.
 *
 * Minimal SPU:
 *
 *   static void my_Vertex3f(void *self, GLfloat x, GLfloat y, GLfloat z) {
 *       struct my *m = self; m->count++;
 *       tsr_call_Vertex3f(m->child, x, y, z);
 *   }
 *   static void *my_create(const tsr_spu_init *init, tsr_error *err) {
 *       struct my *m = calloc(1, sizeof *m);
 *       if (!m) { tsr_error_set(err, TSR_ENOMEM, "my: out of memory"); return NULL; }
 *       m->child = init->child;
 *       tsr_set_Vertex3f(init->table, my_Vertex3f, m);
 *       return m;
 *   }
 *   static void my_destroy(void *self) { free(self); }
 *   static const tsr_spu_class my_class = {
 *       .abi = TSR_SPU_ABI, .name = "my", .summary = "counts vertices",
 *       .create = my_create, .destroy = my_destroy };
 *   TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &my_class; }
 *
 * A network SPU adds its role, naming options it declares, e.g. one that
 * streams to one server (tessera/dev/client.h sends):
 *       .network = {.role = TSR_SPU_ROLE_SERVER, .server = "server",
 *                   .token = "token"},
 * and a graph node `{exec: ..., chain: [my], to: srv}` then gets
 * server=<srv's address> token=<the run's token> when it runs.
 */
#ifndef TESSERA_SPU_H
#define TESSERA_SPU_H

#include <stddef.h>
#include <stdint.h>
#include "tessera/dispatch.h"
#include "tessera/error.h"
#include "tessera/export.h"
#include "tessera/options.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Bumped whenever tsr_spu_class or tsr_spu_init change incompatibly or the
 * dispatch table layout changes (the spec's command list is part of the ABI:
 * the loader also compares TSR_DISPATCH_COUNT). `abi` stays the first member
 * of tsr_spu_class, so a plugin of any ABI is read that far and refused with
 * one line naming it and both versions.
 *   1  the first
 *   2  tsr_spu_class.network: roles instead of names known to the core
 *   3  tsr_spu_network.grid
 *   4  tsr_spu_init.native_windows
 *   5  tsr_spu_class.api, tsr_spu_init.super_instance and super_api */
#define TSR_SPU_ABI 5u

#define TSR_SPU_EXPORT __attribute__((visibility("default")))
#define TSR_SPU_ENTRY_NAME "tsr_spu_describe"

typedef struct tsr_spu_init {
    const char *instance_name;  /* "render#2": use it in messages */
    const tsr_options *options; /* validated; valid until destroy */
    const tsr_dispatch *child;  /* next SPU's resolved table (or no-ops) */
    const tsr_dispatch *super;  /* super instance's resolved table, or NULL */
    tsr_dispatch *table;        /* set the slots this SPU implements */
    /* The chain's native windows (tessera/dev/native.h): the program's
     * windows behind this chain's window ids; valid until destroy. */
    struct tsr_native_windows *native_windows;
    /* The super instance (what its class's create returned) and the
     * functions its class publishes for subclasses (its tsr_spu_class.api),
     * or NULL: valid until this instance is destroyed (a subclass is
     * destroyed before its super). */
    void *super_instance;
    const void *super_api;
} tsr_spu_init;

/* --- Network roles ---------------------------------------------------------
 * What a graph (tessera/graph.h) and the mothership need to know about an
 * SPU that talks to other nodes, declared by the SPU itself: nothing outside
 * spus/ knows an SPU by its name, so a third party's network SPU works in a
 * graph like the built-in ones.
 *
 * The role says what a node's `to:` means for the first SPU of its chain
 * that has a role other than NONE (the node's network SPU), and which graph
 * rules apply. */
typedef enum tsr_spu_role {
    /* Sends to no node (filters, renderers): a node whose chain has only
     * these may not have `to:`. The role of a zeroed class. */
    TSR_SPU_ROLE_NONE = 0,
    /* Streams to one server: `to:` names one node (`tessera check`
     * refuses more) (pack). */
    TSR_SPU_ROLE_SERVER,
    /* Streams to every server `to:` names, one or more (replicate). */
    TSR_SPU_ROLE_SERVERS,
    /* Sorts its stream among tiled servers: every node `to:` names has
     * `tiles:`, or none has and the SPU's declared `grid` option places
     * them (tilesort). */
    TSR_SPU_ROLE_TILED_SERVERS,
    /* Sends its node's own tile images to one display node, where the
     * final image goes: `to:` names exactly one node, and the nodes sending
     * to one display this way own disjoint tiles (readback). */
    TSR_SPU_ROLE_DISPLAY,
    /* One of a group of peers: the nodes whose network SPU sends to the
     * same display node with this role (`to:` names exactly that one).
     * Each is told every peer's address, in rank order, and its own rank;
     * peers are servers, so each has an address (sort-last compositing). */
    TSR_SPU_ROLE_PEERS,
} tsr_spu_role;

/* The role, and the options the mothership fills when a graph runs: each
 * member names an option of this class (declared by the class itself, of
 * the type given) or is NULL. A filled option replaces whatever the graph
 * file gave it. Only the node's network SPU gets addresses, the token and
 * a rank; every SPU of a node's chain that names `tiles` gets the node's
 * own tiles (when it has any). The loader checks this against `options`
 * (tsr_spu_class_check): a role's address option is required, a role of
 * NONE names only `tiles`. */
typedef struct tsr_spu_network {
    tsr_spu_role role;
    const char *server;       /* STRING: the one server's address (ROLE_SERVER) */
    const char *servers;      /* STRING_LIST: every server's address, in `to:` order
                                 (ROLE_SERVERS, ROLE_TILED_SERVERS) */
    const char *display;      /* STRING: the display node's address (ROLE_DISPLAY,
                                 ROLE_PEERS) */
    const char *token;        /* STRING: the run's token, when it has one */
    const char *tiles;        /* STRING or STRING_LIST: this node's own tiles,
                                 "X:Y:W:H,..." (tessera/tiles.h), when it has `tiles:` */
    const char *server_tiles; /* STRING or STRING_LIST: every server's tiles,
                                 "S:X:Y:W:H,..." with S the server's index in `to:`
                                 (required by ROLE_TILED_SERVERS) */
    const char *rank;         /* INT: this node's place, from 0, among the nodes that
                                 send to its display with the same role (in the
                                 graph's file order); rank 0 ends frames */
    const char *peers;        /* STRING_LIST: every peer's address in rank order,
                                 this node's own included (required by ROLE_PEERS) */
    const char *grid;         /* INT_LIST COLUMNS,ROWS, read, not filled
                                 (ROLE_TILED_SERVERS): when the graph gives it
                                 non-zero, the servers divide whatever window the
                                 program opens into that grid, in `to:` order, so
                                 they have no `tiles:`; `tessera check` wants
                                 COLUMNS x ROWS servers */
} tsr_spu_network;

typedef struct tsr_spu_class {
    uint32_t abi;                   /* TSR_SPU_ABI; always the first member */
    uint32_t dispatch_count;        /* TSR_DISPATCH_COUNT (0 = not checked) */
    const char *name;               /* [a-z0-9_]+ */
    const char *super;              /* name of the SPU inherited from, or NULL */
    const char *summary;            /* one line for `tessera spus` */
    const tsr_option_spec *options; /* may be NULL */
    size_t option_count;
    /* Returns the instance (passed as `self` to every slot it sets) or NULL
     * with `err` filled. */
    void *(*create)(const tsr_spu_init *init, tsr_error *err);
    void (*destroy)(void *instance);
    /* Its role in a graph and the options a graph run fills (above); all
     * zero for an SPU that sends to no node. */
    tsr_spu_network network;
    /* What a subclass may call on an instance of this class besides its
     * dispatch table, called with tsr_spu_init.super_instance: a struct of
     * functions that a header of this SPU declares (tessera/dev/render.h
     * for render), or NULL. */
    const void *api;
} tsr_spu_class;

typedef const tsr_spu_class *(*tsr_spu_describe_fn)(void);

/* --- Finding SPU classes -------------------------------------------------
 * Plugins are files named <name>_spu.so, looked up in this order:
 * TESSERA_SPU_PATH (colon-separated), the build tree's spus directory (for
 * uninstalled builds), then the install prefix's lib/tessera/spus. Classes
 * registered in-process win over files of the same name. */

/* Makes `cls` findable by name in this process (tests, embedded SPUs). The
 * class must outlive every chain that uses it. */
TSR_API int tsr_spu_register(const tsr_spu_class *cls, tsr_error *err);
/* Finds (loading if needed) the class called `name`. */
TSR_API const tsr_spu_class *tsr_spu_find(const char *name, tsr_error *err);
/* Lists every findable class (registered and on the search path) into
 * `out` (up to `max`); returns how many exist. Sorted by name. */
TSR_API size_t tsr_spu_list(const tsr_spu_class **out, size_t max);
/* The directories searched, in order, joined by ':' into `buf`. */
TSR_API const char *tsr_spu_search_path(char *buf, size_t size);

/* --- Roles ------------------------------------------------------------------ */

/* "none", "server", "servers", "tiled servers", "display", "peers"; "unknown"
 * outside the enum. */
TSR_API const char *tsr_spu_role_name(tsr_spu_role role);
/* What the role means in a graph, one phrase ("streams to the one server
 * its node's to: names"), for listings and messages. */
TSR_API const char *tsr_spu_role_summary(tsr_spu_role role);

/* --- Checking options without building a chain (graph checks) -------------
 * Both use the parser chains use, so options that check build a chain that
 * works. */

/* The declaration of option `key` of `cls` or of one of its supers; NULL
 * with `err` saying why (unknown option, with "did you mean"). */
TSR_API const tsr_option_spec *tsr_spu_find_option(const tsr_spu_class *cls, const char *key, tsr_error *err);
/* Parses the whole set of `count` key=value pairs as a chain link of `cls`
 * would (duplicates, defaults, every value): TSR_OK or `err` filled. */
TSR_API int tsr_spu_check_options(const tsr_spu_class *cls, const char *const *keys, const char *const *values,
                                  size_t count, tsr_error *err);

#ifdef __cplusplus
}
#endif
#endif
