/* tessera/dev/unpack.h — the unpacker: validates a received wire buffer
 * (tessera/dev/wire.h) command by command and calls a dispatch table with
 * the decoded arguments; produces replies through a callback. For whatever
 * receives a stream: a server node decoding into its chain, an SPU that
 * replays recorded buffers (display lists, tessera/dev/dlist.h).
 * Part of libtessera (pkg-config tessera).
 *
 * Owns: per-stream state (pixel-store mirror, output and reply scratch).
 * Never: reads outside the buffer, trusts a length, or aborts; malformed
 * input is TSR_EPROTO with the command and data offset named.
 *
 * Use (one unpacker per stream, buffers in the order they were packed):
 *
 *   static int my_reply(void *ctx, uint32_t id, const uint8_t *data, size_t size,
 *                       tsr_error *err) {
 *       return my_send_reply(ctx, id, data, size, err);  // tessera/dev/wire.h section 5
 *   }
 *   tsr_unpacker *u = tsr_unpacker_create(chain_head, my_reply, m, &err);
 *   while (next buffer buf of size n)
 *       if (tsr_unpacker_run(u, buf, n, &err) < 0) ...   // drop the sender: err says why
 *   tsr_unpacker_destroy(u);
 */
#ifndef TESSERA_DEV_UNPACK_H
#define TESSERA_DEV_UNPACK_H

#include <stddef.h>
#include <stdint.h>
#include "tessera/dispatch.h"
#include "tessera/error.h"
#include "tessera/export.h"
#include "tessera/dev/pixel.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Receives the reply to request `id` (bytes valid during the call only). */
typedef int (*tsr_reply_fn)(void *ctx, uint32_t id, const uint8_t *data, size_t size, tsr_error *err);

/* Default bound of the outputs one command may ask the server to produce
 * (a lying ReadPixels must not allocate gigabytes). */
#define TSR_UNPACK_MAX_OUTPUT ((uint64_t)1 << 30)

/* A stream's resource budget: what one sender (a server node's client)
 * may make its receiver do. Off until tsr_unpacker_set_limits: unpackers
 * that replay a process's own streams (display lists, tilesort) need none.
 * With limits on, the unpacker also follows the stream's buffer objects
 * (BindBuffer, BufferData, DeleteBuffers: sizes only, never contents) and
 * refuses a draw whose counts read past the arrays or buffers bound for
 * it, as GL's robustness rules allow; a draw with no arrays at all reads
 * nothing and is bounded by max_vertices alone. A refusal is TSR_EPROTO
 * naming the command, the budget, its value and the request. 0 in a field
 * means no limit. */
typedef struct tsr_unpack_limits {
    uint64_t max_output;       /* bytes of outputs (a reply) one command may ask for
                                  (max_reply_bytes in messages) */
    uint64_t max_vertices;     /* vertices the draws of one buffer may ask for */
    uint64_t max_buffer_bytes; /* bytes of the stream's buffer objects alive at once */
} tsr_unpack_limits;

/* The defaults a server node uses (server/README.md states them): room for
 * every example and benchmark. */
#define TSR_UNPACK_DEFAULT_MAX_VERTICES ((uint64_t)1 << 24)
#define TSR_UNPACK_DEFAULT_MAX_BUFFER_BYTES ((uint64_t)512 << 20)

struct tsr_unpack_buffers; /* the buffer objects followed (unpack.c) */

typedef struct tsr_unpacker {
    const tsr_dispatch *target;
    tsr_reply_fn reply;
    void *reply_ctx;
    tsr_pixel_store pixels; /* mirror of the PixelStore commands seen */
    uint64_t max_output;
    uint8_t *aligned; /* copy of a misaligned input buffer */
    size_t aligned_cap;
    uint8_t *out; /* outputs of the current command */
    size_t out_cap;
    uint8_t *rbuf; /* reply being built */
    size_t rcap;
    void **ptrs; /* pointer arrays of custom commands */
    size_t ptrs_cap;
    uint64_t commands, buffers;
    /* Yielding (see tsr_unpacker_yield): the paused buffer's commands and
     * where the next one starts. resume_* are 0 while no buffer is paused. */
    int yield;
    uint32_t resume_command;
    size_t resume_pos;
    const uint8_t *paused_data; /* NULL: nothing paused */
    uint32_t paused_nops;
    size_t paused_len;
    /* Budget (tsr_unpacker_set_limits); `limited` 0 = off. */
    int limited;
    tsr_unpack_limits limits;
    uint64_t buffer_vertices;           /* asked for by the current buffer's draws */
    struct tsr_unpack_buffers *objects; /* buffer objects of the stream */
    int refused;                        /* tsr_unpacker_refuse was called */
    char refusal[400];
    char outputs_why[160]; /* why the last command's outputs were refused */
    /* `pixels` and the buffer bindings are the current context's; other
     * contexts of the stream keep theirs here, swapped at MakeCurrentTSR. */
    int32_t context;
    int context_known;
    struct tsr_wire_contexts *contexts;
    /* the selection and feedback buffers given to GL, per context */
    struct tsr_wire_selection *selection;
} tsr_unpacker;

/* Returned (instead of 0) by tsr_unpacker_run and tsr_unpacker_resume when
 * a command handler asked to stop after its command. */
#define TSR_UNPACK_YIELDED 1

/* `target` receives every decoded call; `reply` may be NULL (replies are
 * then dropped after the call ran). */
TSR_API tsr_unpacker *tsr_unpacker_create(const tsr_dispatch *target, tsr_reply_fn reply, void *reply_ctx,
                                          tsr_error *err);
TSR_API void tsr_unpacker_destroy(tsr_unpacker *u);
/* Decodes one buffer (header + opcodes + data, any alignment) and
 * dispatches its commands in order. Commands before a malformed one have
 * been dispatched; the rest of the buffer is dropped. Returns 0,
 * TSR_UNPACK_YIELDED (a handler yielded: see below), or TSR_EPROTO /
 * TSR_ENOMEM with `err` filled. */
TSR_API int tsr_unpacker_run(tsr_unpacker *u, const void *buf, size_t size, tsr_error *err);
/* Called by a command handler (while run or resume dispatches it): the
 * unpacker stops right after this command and returns TSR_UNPACK_YIELDED;
 * tsr_unpacker_resume continues with the next command. The buffer handed
 * to run must stay valid and unchanged until the buffer is finished (a
 * server node uses this to block a client's stream at a barrier). Running
 * a new buffer abandons a paused one. */
static inline void tsr_unpacker_yield(tsr_unpacker *u) { u->yield = 1; }
/* True while a buffer is paused after a yield. */
static inline int tsr_unpacker_paused(const tsr_unpacker *u) { return u->paused_data != NULL; }
/* Continues the paused buffer: 0 when it is finished, TSR_UNPACK_YIELDED
 * when a handler yielded again, or an error as tsr_unpacker_run.
 * TSR_ESTATE when nothing is paused. */
TSR_API int tsr_unpacker_resume(tsr_unpacker *u, tsr_error *err);
/* Turns the budget on (or changes it). TSR_ENOMEM when the buffer-object
 * table cannot be made. */
TSR_API int tsr_unpacker_set_limits(tsr_unpacker *u, const tsr_unpack_limits *limits, tsr_error *err);
/* The defaults above, max_output TSR_UNPACK_MAX_OUTPUT. */
TSR_API void tsr_unpack_limits_defaults(tsr_unpack_limits *limits);
/* For an SPU that handles a command of a received stream and must not do
 * it (a budget of its own, e.g. render's texture bytes): when this thread
 * is decoding a stream, that stream fails after this command with
 * `fmt` as its error (a server node drops the sender with one line naming
 * it) and 1 is returned; otherwise (the SPU runs in the application's own
 * process) nothing happens and 0 is returned, and the SPU logs the line
 * itself. Either way the SPU skips the command. */
TSR_API int tsr_unpacker_refuse(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* 1 while this thread decodes a stream a node received from a client,
 * with the node's budgets set (tsr_unpacker_set_limits), where an SPU's
 * own budgets protect the node from its senders; 0 otherwise: in the
 * application's own process (also behind an SPU that decodes the
 * program's own stream there, as capture does) the memory is the
 * program's. */
TSR_API int tsr_unpacker_budgeted(void);

/* Checks a buffer's header: returns its total size, or 0 when `size` bytes
 * do not start a valid header (`err` filled). */
TSR_API size_t tsr_wire_buffer_size(const void *buf, size_t size, tsr_error *err);

/* Whether `data` decodes as one buffer: decodes it into a table of no-ops
 * (replies dropped). Returns 0 or the error code; never crashes. For
 * fuzzers and tests of a stream's producer. */
TSR_API int tsr_unpack_fuzz_one(const uint8_t *data, size_t size);

#ifdef __cplusplus
}
#endif
#endif
