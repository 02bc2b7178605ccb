/* server/node.h — a server node: accepts stream clients (the pack SPU) on one
 * listen address and feeds their buffers through an SPU chain, sending
 * replies back. Used by `tessera node` (cli/cmd_node.c).
 * Owns: the listener, the client sessions and their chains. Never exits
 * the process: every failure is a returned or logged tsr_error.
 *
 * The chain comes as text (`tessera node --chain`) or as links (a graph
 * run's: the mothership sends each node its chain as structured links,
 * mothership/control.h).
 *
 * Two modes (tsr_node_config.mode):
 *
 * TSR_NODE_SHARED (the default; `tessera node` without --independent):
 * one chain, run by ONE thread (the one calling tsr_node_run), with a
 * separate GL context per client drawing into one shared window, as
 * Chromium's crserver did: N clients draw one picture. The node sends
 * ContextCreateTSR(client + 1) when a client connects, MakeCurrentTSR(0,
 * client + 1) before running that client's commands, ContextDestroyTSR
 * when it ends (spus/render implements them; other SPUs pass them on).
 * A client's own first context is that context; each further context the
 * client creates in its stream (ContextCreateTSR of another id: a program
 * whose threads draw into one share group, faker/core.c) gets a chain
 * context of its own (ids from 0x100000, at most 8 per client), which the
 * client's MakeCurrentTSR selects and its ContextDestroyTSR drops, so the
 * client's contexts keep their own state in one share group; windows
 * stay the node's.
 * Clients are scheduled round-robin, one received buffer per turn; a turn
 * also ends when the client blocks. Every connection is polled without
 * blocking, so a silent client never stalls the others.
 * The parallel API (Igehy, Stoll and Hanrahan, "The Design of a Parallel
 * Graphics Interface", SIGGRAPH 98) is obeyed here, never passed down the
 * chain:
 *   BarrierCreateTSR(name, count)  barrier `name` for `count` clients
 *       (0 = every client of the node). Every client may create it: a
 *       second create with the same count changes nothing; another count
 *       is an error for that client.
 *   BarrierExecTSR(name)  the client's stream stops until `count` clients
 *       reached the barrier; then all go on, and it can be used again.
 *   SemaphoreCreateTSR(name, value)  created once likewise; P waits while
 *       the value is 0, then decrements; V wakes the longest waiter (its P
 *       completes) or increments.
 *   Barrier/SemaphoreDestroyTSR  forget it (no-op when unknown, so every
 *       client may destroy it; an error while a client waits on it).
 *   Exec, P or V of an unknown name is an error for that client.
 * A blocked client's buffer is held (its credits with it) and its unpacker
 * paused right after the blocking command (tsr_unpacker_yield); it resumes
 * there when released. If every connected client is blocked once all
 * `clients` connected, nobody can release them: the node fails with one
 * line naming each barrier or semaphore, the clients waiting on it, and
 * the clients that already ended (e.g. one disconnected while the others
 * waited at a barrier counting it; a client dropped for silence, a
 * stopped process, is named first, as the cause); it sends that line to
 * every client and tsr_node_run returns TSR_ESTATE. After a client said
 * goodbye the node waits a second before failing that way: that client's
 * own failure, which its owner reports first, is usually the cause. Frames: the first client whose
 * SwapBuffersTSR arrives becomes the swapping client; only its swaps reach
 * the chain (and count as frames); other clients' swaps are dropped and
 * counted in swaps_ignored — a parallel program lets one rank swap, after
 * a barrier. "{client}" in the chain text is refused in this mode.
 *
 * TSR_NODE_INDEPENDENT (`--independent`): one session per client, each
 * with its own thread, its own chain instance built from the node's chain
 * text (so its own GL context and window: OSMesa contexts are current per
 * thread), its own unpacker; sessions run concurrently, swap on their own,
 * and do not obey the parallel API (the commands reach each chain). For
 * unrelated applications sharing a server: write "{client}" in the chain
 * text (e.g. render output=out/c{client}-%04d.png) and it becomes the
 * client's number (0, 1, ... in connection order), so their outputs do not
 * overwrite each other.
 *
 * In both modes a client whose stream is malformed, goes over its budget
 * (tsr_node_config.limits, max_pending_reply_bytes, and what the chain's
 * SPUs refuse: tsr_unpacker_refuse), or whose connection fails, is dropped with one logged line naming it (peer name and address)
 * and sent a TSR_NODE_MSG_ERROR; other clients go on. */
#ifndef TSR_NODE_NODE_H
#define TSR_NODE_NODE_H

#include <stdint.h>

#include "tessera/chain.h"
#include "tessera/dev/unpack.h"
#include "tessera/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct tsr_node tsr_node;

typedef enum tsr_node_mode {
    TSR_NODE_SHARED = 0,      /* one thread, one chain, a context per client, parallel API */
    TSR_NODE_INDEPENDENT = 1, /* a thread and a chain per client */
} tsr_node_mode;

typedef enum tsr_node_cost_source {
    TSR_NODE_COST_FROM_CPU = 0, /* the chain's thread CPU time (the default) */
    TSR_NODE_COST_FROM_BYTES,   /* 1 ns per byte received: independent of timing */
} tsr_node_cost_source;

typedef struct tsr_node_config {
    const char *listen; /* netlib address (tessera/dev/net.h); tcp://...:0 picks a free port */
    const char *chain;  /* chain text, "{client}" replaced by the client's number */
    /* Or the chain as links (a graph run's: mothership/control.h), used when
     * `chain` is NULL; "{client}" in a value is replaced likewise. Copied. */
    const tsr_chain_link *links;
    size_t link_count;
    /* Neither: the chain comes later (tsr_node_set_links), once the node
     * listens and its address is known: a graph run's peers learn each
     * other's addresses that way. */
    int chain_later;
    const char *token;        /* shared token clients must present; NULL/"" = none */
    const char *name;         /* this node's name in handshakes; NULL = "node" */
    unsigned clients;         /* serve this many clients, then tsr_node_run returns (>= 1) */
    uint32_t timeout_ms;      /* longest wait for the next client to connect; 0 = no limit */
    uint32_t idle_timeout_ms; /* longest silence of a connected client: then it is taken
                               for stopped or dead, dropped and named; 0 = no limit.
                               Silence is not being busy: a client's stream client
                               answers heartbeats from its I/O thread while the
                               application computes (tessera/dev/net.h, idle_timeout_ms). */
    tsr_node_mode mode;       /* TSR_NODE_SHARED (0, the default) or TSR_NODE_INDEPENDENT */
    /* Each client's budget (server/README.md, "Budgets"): what its stream
     * may make the node do, enforced by its unpacker (tessera/dev/unpack.h):
     * outputs of one request, vertices per buffer, buffer-object bytes.
     * NULL: the defaults. max_output is bounded by the node's own
     * max_message_bytes whatever is given (a reply must fit in a message
     * the node sends, and a client's announced limit does not raise it). */
    const tsr_unpack_limits *limits;
    /* Reply bytes a client may have sent to it and not yet taken (a client
     * that asks and never reads); a reply beyond it drops the client.
     * 0: TSR_NODE_DEFAULT_MAX_PENDING_REPLY_BYTES. */
    uint64_t max_pending_reply_bytes;
    /* Settings for testing a balancer (`tessera node --cost`, --cost-scale,
     * --stall-first-frame-ms; server/README.md, "Frame costs"), each logged
     * when set. The cost a swap reports (protocol.h TSR_NODE_MSG_COST) is
     * the chain's thread CPU time, or with cost_source BYTES the bytes the
     * frame brought at 1 ns per byte, so a balancer's test does not depend
     * on timing; it is multiplied by cost_scale (a server "twice as slow":
     * 2; 0: 1). The node's first frame takes stall_first_frame_ms longer
     * (the first SwapBuffers to reach the chain waits before it does): a
     * slow server without a huge window. */
    tsr_node_cost_source cost_source;
    double cost_scale;
    uint32_t stall_first_frame_ms;
} tsr_node_config;

#define TSR_NODE_DEFAULT_MAX_PENDING_REPLY_BYTES ((uint64_t)256 << 20)

/* Checks the chain (builds and destroys client 0's chain once, so a bad
 * SPU, option or output directory fails here, not per client), then
 * listens. The chain tsr_node_run uses is built on the thread that
 * calls it. TSR_EINVAL for a bad configuration or chain, other codes for
 * runtime failures (address in use, ...). */
tsr_node *tsr_node_create(const tsr_node_config *config, tsr_error *err);
/* With chain_later: the chain, as links (copied), checked like one given
 * to tsr_node_create. Once, before tsr_node_run. */
int tsr_node_set_links(tsr_node *node, const tsr_chain_link *links, size_t count, tsr_error *err);
/* The address actually bound ("tcp://127.0.0.1:41234" for port 0). */
const char *tsr_node_address(const tsr_node *node);
/* Accepts `clients` clients, serves each until it ends, and returns once
 * all ended: TSR_OK when every client connected and ended cleanly (BYE),
 * else the first failure (a client dropped, no client came in time, or,
 * in shared mode, a deadlock).
 * Call once. */
int tsr_node_run(tsr_node *node, tsr_error *err);
void tsr_node_destroy(tsr_node *node);

/* Running totals over every client so far, for progress lines and the
 * mothership's statistics. Safe to call from any thread while
 * tsr_node_run runs. */
typedef struct tsr_node_stats {
    uint64_t frames;     /* frames ended: SwapBuffers that reached the node's chain
                                 (shared mode: the swapping client's only) */
    uint64_t buffers;    /* wire buffers run */
    uint64_t commands;   /* commands decoded */
    uint64_t bytes_in;   /* payload bytes received from clients */
    uint64_t bytes_out;  /* reply bytes sent to clients */
    double busy_seconds; /* time spent running buffers through the chain (render time) */
    unsigned clients_connected;
    unsigned clients_ended;    /* ended cleanly */
    unsigned clients_failed;   /* dropped */
    unsigned clients_silent;   /* of those, dropped because they sent nothing for idle_timeout_ms */
    unsigned clients_vanished; /* of those, dropped because their end went away unclosed (the client's
                                  own end is the cause, reported by its node) */
    uint64_t swaps_ignored;    /* shared mode: swaps of clients other than the swapping one */
    uint64_t blocks;           /* shared mode: times a client blocked on a barrier or semaphore */
} tsr_node_stats;
void tsr_node_get_stats(tsr_node *node, tsr_node_stats *out);
/* 1 once a client was dropped because it sent nothing for
 * idle_timeout_ms (a stopped or hung process), with the first such drop
 * in `out` as tsr_node_run's failure would name it ("node: client N
 * 'NAME' at ADDRESS dropped: ..."); 0 while none was. The node goes on
 * serving its other clients; this lets its owner report the drop at once
 * (a peer that waits for the silent one would otherwise end first and
 * be blamed). Safe to call from any thread while tsr_node_run runs. */
int tsr_node_silent_failure(tsr_node *node, char *out, size_t size);

#ifdef __cplusplus
}
#endif
#endif
