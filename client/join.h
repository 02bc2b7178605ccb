/* client/join.h — late joiners of a stream client (tessera/dev/client.h): servers
 * that may connect while the stream runs (replicate's `late` option) and
 * are brought up to date before they draw their first frame.
 * Owns: the model of what the servers hold — a state tracker context
 * (tessera/dev/state.h) fed with exactly the bytes the servers received, the
 * display-list bodies (tessera/dev/dlist.h), the windows and contexts the stream
 * made, the texture and buffer names it bound — and one background thread
 * that connects to the late servers. Never blocks the application thread
 * on a connection: connecting happens on that thread; the application
 * thread only takes a ready connection at a frame boundary.
 *
 * How the model follows the stream: every buffer the client flushed to its
 * servers is decoded again (tessera/dev/unpack.h) into the tracker's table; calls
 * between glNewList and glEndList go into the list recorder, and a
 * glCallList/glCallLists replays the called list's state calls into the
 * tracker (nested lists followed), as tessera/dev/state.h asks of the sender.
 * This costs one decode of the stream on the application thread, and only
 * while a late server is still expected (the client drops the model once
 * every late server joined or was given up).
 *
 * Catching up (tsr_node_join_catch_up), sent to the joiner only, before it
 * is added to the broadcast:
 *   1. the windows (WindowCreateTSR at their latest size, WindowBuffersTSR
 *      and WindowSamplesTSR where they were said) and the
 *      contexts and current context the stream made (ContextCreateTSR,
 *      MakeCurrentTSR);
 *   2. every display list (tsr_dlist_define_all);
 *   3. every texture and buffer object the stream bound and did not delete
 *      (the tracker's diff sends only bound objects, but the application
 *      may bind any of them later without uploading again): each is bound
 *      in the tracker in turn and diffed into the joiner's shadow, then the
 *      application's bindings are put back;
 *   3b. every shader and program (tsr_state_send_glsl_all: sources,
 *      compiles, links from each program's last link inputs, uniform
 *      values, attachments, bindings, deletions GL holds back); names are
 *      the stream's own (replicate with `late` allocates them and sends
 *      CreateShaderTSR/CreateProgramTSR; renderers map them);
 *   4. tsr_state_diff of the whole state into that shadow.
 * The stream then continues on the joiner exactly as on the others.
 *
 * Not caught up (the tracker does not track them yet, tessera/dev/state.h):
 * the raster position, evaluators, CopyTex* images,
 * barriers and semaphores (a parallel-submission stream), and a stream
 * that switches between several application contexts (one tracked
 * context). A join is refused (deferred) while a list is being compiled. */
#ifndef TSR_NODE_JOIN_H
#define TSR_NODE_JOIN_H

#include <stddef.h>
#include <stdint.h>

#include "tessera/dev/net.h"
#include "tessera/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct tsr_node_join tsr_node_join;

typedef struct tsr_node_join_config {
    const char *name;             /* the client's instance name, first word of messages */
    tsr_net *net;                 /* the client's netlib instance (connections are made on it) */
    const char *const *addresses; /* the late servers */
    size_t count;
    uint32_t retry_ms;   /* pause between connection attempts to one server */
    uint32_t give_up_ms; /* stop trying after this long; 0 = until the client ends */
    size_t buffer_size;  /* wire buffer bytes of the catch-up stream */
} tsr_node_join_config;

/* Starts the connecting thread. Strings are copied. */
tsr_node_join *tsr_node_join_create(const tsr_node_join_config *config, tsr_error *err);
/* Stops the thread (waits at most one connection attempt), closes
 * connections that were never admitted, and logs one line per late server
 * that never joined (address, attempts, last reason). */
void tsr_node_join_destroy(tsr_node_join *j);

/* A buffer the client flushed to its servers (application thread). */
void tsr_node_join_observe(tsr_node_join *j, const uint8_t *buf, size_t size);

/* Whether a connected server waits to be admitted (one atomic load) and
 * the model allows it now (no list being compiled). */
int tsr_node_join_ready(tsr_node_join *j);
/* Takes the next connected server (NULL when none); *address is valid
 * while `j` lives. The caller then calls tsr_node_join_catch_up. */
tsr_net_conn *tsr_node_join_take(tsr_node_join *j, const char **address);
/* Whether some late server may still join (not joined, not given up). */
int tsr_node_join_pending(tsr_node_join *j);

typedef struct tsr_node_join_report {
    uint64_t bytes; /* catch-up stream bytes sent */
    unsigned windows, lists, textures, buffers;
    uint32_t state_calls; /* GL calls the diffs emitted (object uploads included) */
} tsr_node_join_report;

/* Sends the catch-up stream (above) to `conn` only, ending with a flushed
 * buffer; the caller then adds it to its broadcast. Returns TSR_OK or the
 * error that ended it (the caller closes the connection). */
int tsr_node_join_catch_up(tsr_node_join *j, tsr_net_conn *conn, tsr_node_join_report *report, tsr_error *err);

#ifdef __cplusplus
}
#endif
#endif
