/* tessera/dev/client.h — the stream client of tessera/dev/protocol.h: what
 * every SPU that sends its GL stream to server nodes shares (pack: one
 * server, replicate: several, tilesort: a buffer to the servers it
 * chooses). Library libtessera_client (pkg-config tessera).
 *
 * Owns: one network instance (one I/O thread) with one connection per
 * server, the packer whose buffers go to all of them, the reply the packer
 * is holding, the failure policy and the statistics.
 * Never: packs a call twice or copies a buffer once per server (each
 * flushed buffer is copied once and that copy is handed to every
 * connection), or waits on a server without a bound its silence can end
 * (timeout_ms).
 *
 * Use (an SPU sending its whole stream; declare its options with
 * TSR_NODE_CLIENT_OPTION_SPECS next to its own `server` option):
 *
 *   tsr_stream_client_config cfg = {.spu = "my", .name = init->instance_name,
 *                                   .servers = &server, .server_count = 1};
 *   tsr_stream_client_config_from_options(&cfg, init->options);
 *   m->client = tsr_stream_client_create(&cfg, init->table, err);  // every slot sends
 *   ...
 *   tsr_stream_client_destroy(m->client);   // FINISH, confirmation, statistics
 *
 * Addresses are the network library's: "tcp://host:port", "unix:/path",
 * "inproc:name" (a server node in the same process).
 *
 * Replies (gets, ReadPixels, the Gen and Create calls) come from the FIRST
 * live server. Every other live server answers the same request too; its
 * reply is read (so the stream stays in step and its credit returns) and
 * its request id checked, and its bytes are dropped, not compared: servers
 * on different hosts may legitimately answer differently (GL_RENDERER,
 * GL_VERSION), while their drawing is what the tests compare.
 *
 * Failure policy (GL calls cannot return errors). A server that fails
 * mid-stream (killed, silent beyond timeout_ms, dropped us) is reported in
 * one line naming its address; with exit_on_error the process then ends
 * with status 1 (the application would otherwise report success for frames
 * that were never drawn); otherwise that server is dropped and the stream
 * goes on to the others (replies from the next live one); with no server
 * left every further call is dropped. Failing to connect to any server is
 * an error of tsr_stream_client_create(), naming that server. Destroying the
 * client sends FINISH to every server and waits for each one's
 * confirmation that every buffer ran.
 *
 * Late joiners (config.late_servers). A late server is not
 * needed at start: a background thread connects to it; right after the
 * next SwapBuffersTSR the packer is flushed, the server gets a catch-up
 * stream of its own (windows, display lists, texture and buffer objects,
 * state diff) and then joins the broadcast, drawing from the next frame
 * on; one info line says "server ADDR joined at frame N". A late server
 * that never comes costs the stream nothing but one warning line when the
 * client ends (or gives up); the application's exit status is not
 * affected. Once joined it is a server like the others (failure policy,
 * replies, FINISH, statistics).
 *
 * Statistics. The client counts wire buffers and their bytes (the stream,
 * packed once), frames (SwapBuffersTSR calls), and per server the payload
 * bytes and messages sent and the time the application thread was blocked
 * waiting for that server's send credits. When the environment variable
 * TESSERA_STATS_FILE names a file, destroy (or a failure that ends the
 * process) replaces that file with one JSON object:
 *   {"spu":"pack","name":"pack#0","bytes_out":N,"stream_bytes":N,
 *    "buffers":N,"frames":N,"blocked_seconds":X,
 *    "servers":[{"address":"tcp://...","bytes_out":N,"messages":N,
 *                "blocked_seconds":X,"failed":false}],
 *    "error":null}
 * bytes_out is what left this process (the sum over servers: replicate to
 * three servers sends the stream three times); stream_bytes is the stream
 * once; blocked_seconds sums the servers' (sends are sequential on the
 * application thread, so it is wall time); error is the first failure's
 * message or null. One file per process: a second client in the same
 * process replaces the first one's file (the mothership gives each node its
 * own). The file is written whole to a temporary name and renamed, so a
 * reader never sees half of it. */
#ifndef TESSERA_DEV_CLIENT_H
#define TESSERA_DEV_CLIENT_H

#include <stddef.h>
#include <stdio.h>
#include <stdint.h>

#include "tessera/dispatch.h"
#include "tessera/error.h"
#include "tessera/export.h"
#include "tessera/options.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TSR_NODE_CLIENT_STATS_ENV "TESSERA_STATS_FILE"
#define TSR_NODE_CLIENT_EXIT_STATUS 1

typedef struct tsr_stream_client tsr_stream_client;

typedef struct tsr_stream_client_config {
    const char *spu;            /* the SPU's class name, for the statistics ("pack") */
    const char *name;           /* instance name, first word of every message ("pack#0") */
    const char *const *servers; /* addresses ("tcp://host:port", above) */
    size_t server_count;        /* >= 1 */
    const char *token;          /* shared token; NULL/"" = none */
    uint32_t timeout_ms;        /* connect/handshake limit and longest silence of a
                                        server; 0 = the network library's defaults, no
                                        silence limit */
    size_t buffer_size;         /* bytes of one wire buffer */
    int exit_on_error;          /* see the failure policy above */
    /* Late joiners (replicate's `late` option): servers not
     * required at start, connected to in the background and admitted at a
     * frame boundary once caught up. None: nothing is tracked (no cost).
     * tsr_stream_client_create only (the client's own packer is followed). */
    const char *const *late_servers;
    size_t late_count;
    uint32_t late_retry_ms;   /* pause between attempts per server (0: 200) */
    uint32_t late_give_up_ms; /* stop trying after this long; 0 = until the end */
} tsr_stream_client_config;

/* The options every stream client SPU shares, as tsr_option_spec
 * initialisers to put in the SPU's own option array (after its own way of
 * naming servers), and the call that reads them into a config. The token
 * option's name is the one to give tsr_spu_network.token (tessera/spu.h):
 * a graph run fills it with the run's token. */
#define TSR_NODE_CLIENT_TOKEN_OPTION "token"
#define TSR_NODE_CLIENT_OPTION_SPECS                                                                                   \
    {.name = TSR_NODE_CLIENT_TOKEN_OPTION,                                                                             \
     .type = TSR_OPT_STRING,                                                                                           \
     .default_value = "",                                                                                              \
     .min = 1,                                                                                                         \
     .max = 0,                                                                                                         \
     .help = "shared token the servers require (empty: none)"},                                                        \
        {.name = "buffer_size",                                                                                        \
         .type = TSR_OPT_INT,                                                                                          \
         .default_value = "1048576",                                                                                   \
         .min = 256,                                                                                                   \
         .max = 67108864.0,                                                                                            \
         .help = "bytes of one wire buffer (header, opcodes and data)"},                                               \
        {.name = "timeout_ms",                                                                                         \
         .type = TSR_OPT_INT,                                                                                          \
         .default_value = "10000",                                                                                     \
         .min = 0,                                                                                                     \
         .max = 3600000.0,                                                                                             \
         .help = "connect/handshake limit, and how long a server may stay silent before it counts "                    \
                 "as dead (0: netlib defaults, no silence limit)"},                                                    \
    {                                                                                                                  \
        .name = "on_error", .type = TSR_OPT_ENUM, .default_value = "exit", .choices = "exit|drop", .min = 1, .max = 0, \
        .help = "when a server fails mid-stream: exit ends the application with status 1, drop "                       \
                "goes on without that server (every call is dropped once none is left)"                                \
    }

/* The end of a process under on_error=exit, the one place it is written
 * (the stream client, and every SPU that ends a run it cannot serve:
 * tilesort's wall, readback's and binaryswap's display): flushes stdio and
 * ends with TSR_NODE_CLIENT_EXIT_STATUS. _exit, not exit: other threads
 * (the renderer's, netlib's) are running and must not see library
 * destructors run under them. The caller has logged its line. */
TSR_API void tsr_stream_client_exit(void) __attribute__((noreturn));

/* Fills token, timeout_ms, buffer_size and exit_on_error from options
 * declared with TSR_NODE_CLIENT_OPTION_SPECS. */
TSR_API void tsr_stream_client_config_from_options(tsr_stream_client_config *config, const tsr_options *options);

/* Connects to every server (in order; the first that cannot be reached or
 * refuses fails the call, naming it), creates the packer and points every
 * slot of `table` at it (SwapBuffersTSR also counts the frame). Strings of
 * `config` are copied. */
TSR_API tsr_stream_client *tsr_stream_client_create(const tsr_stream_client_config *config, tsr_dispatch *table,
                                                    tsr_error *err);
/* Sends what is packed and FINISH, waits for every server's confirmation,
 * closes, writes the statistics file (TESSERA_STATS_FILE) and frees. */
TSR_API void tsr_stream_client_destroy(tsr_stream_client *client);

/* Sorting clients (tilesort) decide per buffer which servers get it: they
 * connect without a packer of the client's own and send through these.
 * tsr_stream_client_connect: as tsr_stream_client_create, but no packer and no
 * table; the statistics count what tsr_stream_client_send sent. */
TSR_API tsr_stream_client *tsr_stream_client_connect(const tsr_stream_client_config *config, tsr_error *err);
/* Sends one wire buffer to servers[0..n) (indexes into config.servers;
 * failed ones are skipped), copying it once. TSR_OK unless no server is
 * left (the failure policy above applies to each failed server). */
TSR_API int tsr_stream_client_send(tsr_stream_client *client, const size_t *servers, size_t n, const uint8_t *buf,
                                   size_t size, tsr_error *err);
/* A packer sink that sends to server `index` only and takes replies from
 * it alone (the request went to it alone). */
struct tsr_pack_sink;
TSR_API void tsr_stream_client_server_sink(tsr_stream_client *client, size_t index, struct tsr_pack_sink *sink);
/* The sending SPU's own statistics: fn writes members (",\"name\":value")
 * into the JSON object after "servers" (fn runs while the client is
 * destroyed or fails, so ctx must still be valid then). */
TSR_API void tsr_stream_client_set_stats_extra(tsr_stream_client *client, void (*fn)(void *ctx, FILE *f), void *ctx);
/* Frame costs the servers report (tessera/dev/protocol.h TSR_NODE_MSG_COST,
 * asked for with TSR_NODE_SWAP_REPORT_COST in a swap's flags): fn gets
 * the server's index and its report, on the SPU's thread, whenever the
 * client takes that server's messages (waiting for a reply,
 * tsr_stream_client_take_costs, the end of the stream). Without a sink,
 * reports are dropped. */
typedef struct tsr_frame_cost {
    uint32_t frame;       /* the server's count of reporting swaps from this client, from 0 */
    uint32_t faults;      /* minor page faults of the server's chain in that frame */
    double seconds;       /* thread CPU time of the server's chain in that frame */
    double fault_seconds; /* the part of `seconds` those faults cost, at the server's measured cost of one */
} tsr_frame_cost;
typedef void (*tsr_stream_client_cost_fn)(void *ctx, size_t server, const tsr_frame_cost *cost);
TSR_API void tsr_stream_client_set_cost_sink(tsr_stream_client *client, tsr_stream_client_cost_fn fn, void *ctx);
/* Takes every report already received from every live server, without
 * waiting (a server's ERROR found there fails that server). */
TSR_API void tsr_stream_client_take_costs(tsr_stream_client *client);
/* Counts one frame (a SwapBuffersTSR the sorting SPU sent). */
TSR_API void tsr_stream_client_count_frame(tsr_stream_client *client);
/* Whether server `index` failed (its buffers are dropped). */
TSR_API int tsr_stream_client_server_failed(const tsr_stream_client *client, size_t index);

typedef struct tsr_stream_client_server_stats {
    const char *address;    /* valid while the client lives */
    uint64_t bytes_out;     /* payload bytes sent */
    uint64_t messages;      /* messages sent (buffers + FINISH) */
    double blocked_seconds; /* waiting for this server's send credits */
    int failed;
} tsr_stream_client_server_stats;

typedef struct tsr_stream_client_stats {
    uint64_t bytes_out;     /* sum over servers */
    uint64_t stream_bytes;  /* wire buffer bytes, counted once */
    uint64_t buffers;       /* wire buffers flushed */
    uint64_t frames;        /* SwapBuffersTSR calls */
    double blocked_seconds; /* sum over servers */
    size_t server_count;
} tsr_stream_client_stats;

/* Running totals (the application thread's view); `servers` may be NULL,
 * else it receives min(capacity, server count) entries. */
TSR_API void tsr_stream_client_get_stats(tsr_stream_client *client, tsr_stream_client_stats *out,
                                         tsr_stream_client_server_stats *servers, size_t capacity);
/* Writes the statistics JSON object (above) to `path` (temporary file +
 * rename). */
TSR_API int tsr_stream_client_write_stats(tsr_stream_client *client, const char *path, tsr_error *err);

#ifdef __cplusplus
}
#endif
#endif
