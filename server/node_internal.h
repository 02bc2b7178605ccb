/* server/node_internal.h — what node.c (listener, independent sessions,
 * statistics) and schedule.c (shared mode: one rendering thread, the
 * parallel API) share. Owns nothing; internal to server/. */
#ifndef TSR_NODE_INTERNAL_H
#define TSR_NODE_INTERNAL_H

#include <pthread.h>
#include <stdatomic.h>

#include "tessera/dev/net.h"
#include "node.h"
#include "tessera/chain.h"
#include "tessera/dev/unpack.h"

struct node_session;

/* Sizes of the last messages the node sent one client, newest last: with
 * netlib's count of messages whose credit has not come back, the reply
 * bytes the client has not taken yet. The client grants the credits
 * (net.h), so it could let more be in flight: a reply past the ring's
 * length of unreturned ones is refused (tsr_node_send_reply). */
#define TSR_NODE_SENT_RING 64
typedef struct tsr_node_sent {
    uint64_t sizes[TSR_NODE_SENT_RING];
    unsigned next;
} tsr_node_sent;

/* Records a message of `size` bytes sent to the client. */
void tsr_node_sent_add(tsr_node_sent *sent, uint64_t size);

/* One client's frame cost so far (the chain's thread CPU time since its
 * last swap, and the bytes it ran). */
typedef struct tsr_node_cost {
    double cpu_at_swap;  /* CLOCK_THREAD_CPUTIME_ID seconds at the last swap (or the start) */
    long faults_at_swap; /* the thread's minor page faults then */
    uint64_t bytes;      /* buffer bytes run since the last swap */
    uint32_t frame;      /* reports sent */
} tsr_node_cost;

struct tsr_node {
    char *chain_text;      /* the chain as text, or NULL and ... */
    tsr_chain_link *links; /* ... as links (owned copies) */
    size_t link_count;
    uint32_t timeout_ms;
    uint32_t test_stall_ms;  /* tsr_node_config.stall_first_frame_ms; 0 = none */
    atomic_int test_stalled; /* it did (sessions of independent mode race for it) */
    double test_cost_scale;  /* tsr_node_config.cost_scale; 1 = none */
    int test_cost_bytes;     /* tsr_node_config.cost_source BYTES */
    double fault_seconds;    /* thread CPU seconds of one minor page fault (under stats_lock) ... */
    int fault_measured;      /* ... measured at the first cost report with faults */
    unsigned clients;
    tsr_node_mode mode;
    tsr_unpack_limits limits; /* every client's unpacker's */
    uint64_t max_pending_reply_bytes;
    tsr_net *net;
    tsr_net_listener *listener;
    struct node_session *sessions; /* independent mode: `clients` entries */
    unsigned accepted;
    int ran;
    int stats_lock_ready;
    pthread_mutex_t stats_lock;
    tsr_node_stats stats;
    /* The first client dropped for silence, as tsr_node_run would name it
     * (under stats_lock): the agent reports it while other clients go on. */
    char silent_failure[512];
};

/* In a SwapBuffers that reaches the chain, before the chain's: sleeps
 * for the test stall on the node's first (tsr_node_config.stall_first_frame_ms). */
void tsr_node_test_stall(tsr_node *node);
/* The calling thread's CPU time in seconds (the chain runs on it). */
double tsr_node_thread_cpu(void);
/* The calling thread's minor page faults so far. */
long tsr_node_thread_faults(void);
/* Starts a frame's count (CPU time and faults) on the calling thread. */
void tsr_node_cost_start(tsr_node_cost *cost);
/* In a SwapBuffersTSR whose flags asked for it, after the chain's swap:
 * sends the frame's TSR_NODE_MSG_COST without waiting (no credit: dropped)
 * and starts the next frame's count. */
void tsr_node_report_cost(tsr_node *node, tsr_net_conn *conn, tsr_node_sent *sent, tsr_node_cost *cost);
/* Adds `delta` to the node's totals under its lock. */
void tsr_node_stats_add(tsr_node *node, const tsr_node_stats *delta);
/* A client ended (`conn` still open, or NULL): a failed one is counted
 * silent when it sent nothing for idle_timeout_ms (tsr_net_conn_went_silent)
 * and vanished when its end went away unclosed (tsr_net_conn_vanished);
 * `who` and `why` name a silent one for tsr_node_silent_failure (the first
 * such client is kept). */
void tsr_node_client_ended(tsr_node *node, int failed, tsr_net_conn *conn, const char *who, const char *why);
/* The chain for client `index` ("{client}" replaced); NULL with `err`. */
tsr_chain *tsr_node_create_chain(const tsr_node *node, unsigned index, tsr_error *err);
/* Sends a TSR_NODE_MSG_REPLY on `conn` through a growing buffer
 * (buf, cap); counts bytes_out. TSR_EPROTO (nothing sent) when the client
 * would then have more than max_pending_reply_bytes not taken. */
int tsr_node_send_reply(tsr_node *node, tsr_net_conn *conn, tsr_node_sent *sent, uint8_t **buf, size_t *cap,
                        uint32_t id, const uint8_t *data, size_t size, tsr_error *err);
/* A client's unpacker, with the node's limits. */
tsr_unpacker *tsr_node_unpacker(tsr_node *node, const tsr_dispatch *head, tsr_reply_fn reply, void *ctx,
                                tsr_error *err);
/* Accepts the next client; on failure fills `failure` (time-out and
 * refusals named) and returns NULL. */
tsr_net_conn *tsr_node_accept(tsr_node *node, int timeout_ms, tsr_error *failure);
/* Shared mode's tsr_node_run (schedule.c). */
int tsr_node_run_shared(tsr_node *node, tsr_error *err);

#endif
