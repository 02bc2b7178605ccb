/* tessera/dev/wireloop.h — the wire path inside one process: a packer whose
 * every flushed buffer is unpacked at once into a child dispatch table, and
 * whose requests are answered from the child's reply. For SPUs that stand
 * where a network would be (loopback; capture, which also writes what
 * passes) and for anything that must see a stream exactly as a server
 * would. Part of libtessera (pkg-config tessera).
 *
 * Threads: a buffer flushed on another thread than the last one first makes
 * the child current again in the context the stream stands in, because
 * OSMesa (and GL generally) binds a current context to one thread; calls
 * from two threads must still be serialised by the caller.
 *
 * Owns: its packer, its unpacker and the one reply in flight.
 * Never: calls the child except through the unpacker, keeps globals (two
 * loops in one process are independent), or changes a buffer it hands to
 * the observer.
 *
 * Use:
 *
 *   tsr_wire_loop *l = tsr_wire_loop_create(name, 1 << 20, child, NULL, &err);
 *   tsr_wire_loop_fill_dispatch(l, table);   // the SPU's calls are packed
 *   ...
 *   tsr_wire_loop_destroy(l);                // flushes what is pending first
 */
#ifndef TESSERA_DEV_WIRELOOP_H
#define TESSERA_DEV_WIRELOOP_H

#include <stddef.h>
#include <stdint.h>
#include "tessera/dispatch.h"
#include "tessera/error.h"
#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One reply kept from when the unpacker produces it until the packer
 * takes it (zero-initialise; tsr_reply_slot_free releases it). */
typedef struct tsr_reply_slot {
    uint8_t *data;
    size_t size, capacity;
    uint32_t id;
    int full;
} tsr_reply_slot;

/* Copies the reply to request `id` into the slot (replacing an untaken one). */
TSR_API int tsr_reply_slot_store(tsr_reply_slot *slot, uint32_t id, const uint8_t *data, size_t size, tsr_error *err);
/* Hands out the stored reply to request `id` and empties the slot; TSR_EPROTO
 * when the slot holds no reply to `id`. The bytes stay valid until the next
 * store. `who` names the owner in the error. */
TSR_API int tsr_reply_slot_take(tsr_reply_slot *slot, const char *who, uint32_t id, const uint8_t **data, size_t *size,
                                tsr_error *err);
TSR_API void tsr_reply_slot_free(tsr_reply_slot *slot);

/* Sees what crosses the loop: each buffer before the child runs it, each
 * reply as the child produced it (bytes valid during the call). Either
 * may be NULL. */
typedef struct tsr_wire_loop_observer {
    void (*buffer)(void *ctx, const uint8_t *buf, size_t size);
    void (*reply)(void *ctx, uint32_t id, const uint8_t *data, size_t size);
    void *ctx;
} tsr_wire_loop_observer;

typedef struct tsr_wire_loop tsr_wire_loop;

/* name: used in log lines and errors (kept by pointer). buffer_size: bytes
 * of one wire buffer (at least TSR_PACK_MIN_BUFFER). observer: copied;
 * NULL for none. */
TSR_API tsr_wire_loop *tsr_wire_loop_create(const char *name, size_t buffer_size, const tsr_dispatch *child,
                                            const tsr_wire_loop_observer *observer, tsr_error *err);
/* Points every slot of `table` at the loop's packer. */
TSR_API void tsr_wire_loop_fill_dispatch(tsr_wire_loop *loop, tsr_dispatch *table);
/* Sends what is packed through the child now. Returns 0 or the error. */
TSR_API int tsr_wire_loop_flush(tsr_wire_loop *loop);
/* Flushes, then frees. NULL is a no-op. */
TSR_API void tsr_wire_loop_destroy(tsr_wire_loop *loop);

#ifdef __cplusplus
}
#endif
#endif
