/* node/node.h — a server node: accepts stream clients (the pack SPU) on one
 * listen address and feeds each client's buffers through that client's own
 * SPU chain, sending replies back. Used by `tessera node` (cli/cmd_node.c).
 * Owns: the listener, the client sessions and their chains. Never exits
 * the process: every failure is a returned or logged tsr_error.
 *
 * One client, one session: its own thread, its own chain instance built
 * from the node's chain text (so its own GL context: OSMesa contexts are
 * current per thread, and a session's thread is the only one that ever
 * calls its chain), its own unpacker. A client whose stream is malformed,
 * or whose connection fails, is dropped with one logged line naming it
 * (peer name and address) and sent a TSR_NODE_MSG_ERROR; other clients go
 * on unaffected.
 *
 * Limitation (issue 3 item 5 will change it): sessions run concurrently
 * and independently — no round-robin schedule, no barriers or semaphores
 * across clients, and every client's chain swaps on its own. With several
 * clients, write "{client}" in the chain text (e.g. render
 * output=out/c{client}-%04d.png): it becomes the client's number (0, 1, ...
 * in connection order), so their outputs do not overwrite each other. */
#ifndef TSR_NODE_NODE_H
#define TSR_NODE_NODE_H

#include <stdint.h>

#include "tessera/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct tsr_node tsr_node;

typedef struct tsr_node_config {
    const char *listen;     /* netlib address (netlib/net.h); tcp://...:0 picks a free port */
    const char *chain;      /* chain text, "{client}" replaced by the client's number */
    const char *token;      /* shared token clients must present; NULL/"" = none */
    const char *name;       /* this node's name in handshakes; NULL = "node" */
    unsigned clients;       /* serve this many clients, then tsr_node_run returns (>= 1) */
    uint32_t timeout_ms;    /* longest wait for the next client to connect, and longest
                               silence of a connected client; 0 = no limit */
} tsr_node_config;

/* Checks the chain text (builds and destroys client 0's chain once, so a
 * bad SPU, option or output directory fails here, not per client), then
 * listens. TSR_EINVAL for a bad configuration or chain, other codes for
 * runtime failures (address in use, ...). */
tsr_node *tsr_node_create(const tsr_node_config *config, tsr_error *err);
/* The address actually bound ("tcp://127.0.0.1:41234" for port 0). */
const char *tsr_node_address(const tsr_node *node);
/* Accepts `clients` clients, serves each until it ends, and returns once
 * all ended: TSR_OK when every client connected and ended cleanly (BYE),
 * else the first failure (a client dropped, or no client came in time).
 * Call once. */
int tsr_node_run(tsr_node *node, tsr_error *err);
void tsr_node_destroy(tsr_node *node);

/* Running totals over every client so far, for progress lines and the
 * mothership's statistics. Safe to call from any thread while
 * tsr_node_run runs. */
typedef struct tsr_node_stats {
    uint64_t frames;          /* SwapBuffers that reached the node's chain */
    uint64_t buffers;         /* wire buffers run */
    uint64_t commands;        /* commands decoded */
    uint64_t bytes_in;        /* payload bytes received from clients */
    uint64_t bytes_out;       /* reply bytes sent to clients */
    double busy_seconds;      /* time spent running buffers through the chain (render time) */
    unsigned clients_connected;
    unsigned clients_ended;   /* ended cleanly */
    unsigned clients_failed;  /* dropped */
} tsr_node_stats;
void tsr_node_get_stats(tsr_node *node, tsr_node_stats *out);

#ifdef __cplusplus
}
#endif
#endif
