/* core/wire/wireloop.c — a packer unpacked into a child in the same process
 * (tessera/dev/wireloop.h), and the one-reply slot such a loop needs. */
#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/dev/pack.h"
#include "tessera/dev/unpack.h"
#include "tessera/dev/wireloop.h"
#include "tessera/log.h"

int tsr_reply_slot_store(tsr_reply_slot *slot, uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    if (size > slot->capacity) {
        uint8_t *grown = realloc(slot->data, size);
        if (!grown)
            return tsr_error_set(err, TSR_ENOMEM, "out of memory for a %zu-byte reply", size);
        slot->data = grown;
        slot->capacity = size;
    }
    if (size)
        memcpy(slot->data, data, size);
    slot->size = size;
    slot->id = id;
    slot->full = 1;
    return TSR_OK;
}

int tsr_reply_slot_take(tsr_reply_slot *slot, const char *who, uint32_t id, const uint8_t **data, size_t *size,
                        tsr_error *err)
{
    if (!slot->full || slot->id != id)
        return tsr_error_set(err, TSR_EPROTO, "%s: no reply to request %u", who, id);
    slot->full = 0;
    /* An empty reply still gets a valid pointer. */
    *data = slot->data ? slot->data : (const uint8_t *)"";
    *size = slot->size;
    return TSR_OK;
}

void tsr_reply_slot_free(tsr_reply_slot *slot)
{
    free(slot->data);
    memset(slot, 0, sizeof *slot);
}

struct tsr_wire_loop {
    const char *name;
    const tsr_dispatch *child;
    tsr_packer *packer;
    tsr_unpacker *unpacker;
    tsr_reply_slot reply;
    tsr_wire_loop_observer observer;
    tsr_entry pack_make_current; /* the packer's own MakeCurrentTSR */
    /* The stream's current window and context: as packed so far, and as
     * of the start of the next buffer the child runs. */
    GLint packed_window, packed_context, run_window, run_context;
    bool packed_current, run_current;
    pthread_t run_thread; /* the thread that ran the last buffer */
    bool ran;
};

static void loop_MakeCurrentTSR(void *self, GLint window, GLint context)
{
    tsr_wire_loop *l = self;
    ((tsr_fn_MakeCurrentTSR)l->pack_make_current.fn)(l->pack_make_current.self, window, context);
    l->packed_window = window;
    l->packed_context = context;
    l->packed_current = true;
}

/* A buffer runs on the thread that flushed it. A child whose current
 * context is bound to a thread (OSMesa's is) is made current again on a
 * thread other than the last one to run a buffer, as of where the stream
 * stands: a program whose threads draw into one stream in turn (the
 * faker's share groups) would otherwise have another thread's calls run
 * in whatever context this thread last had. */
static int loop_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    tsr_wire_loop *l = ctx;
    if (l->observer.buffer)
        l->observer.buffer(l->observer.ctx, buf, size);
    pthread_t self = pthread_self();
    if (l->ran && !pthread_equal(self, l->run_thread) && l->run_current)
        tsr_call_MakeCurrentTSR(l->child, l->run_window, l->run_context);
    l->run_thread = self;
    l->ran = true;
    /* The packer has packed every call made so far into this buffer but
     * the one being packed, which a MakeCurrentTSR records only after. */
    l->run_window = l->packed_window;
    l->run_context = l->packed_context;
    l->run_current = l->packed_current;
    int rc = tsr_unpacker_run(l->unpacker, buf, size, err);
    if (rc)
        tsr_log(TSR_LOG_ERROR, "%s: %s", l->name, err->message);
    return rc;
}

static int loop_store_reply(void *ctx, uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    tsr_wire_loop *l = ctx;
    int rc = tsr_reply_slot_store(&l->reply, id, data, size, err);
    if (rc == TSR_OK && l->observer.reply)
        l->observer.reply(l->observer.ctx, id, data, size);
    return rc;
}

static int loop_take_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    tsr_wire_loop *l = ctx;
    return tsr_reply_slot_take(&l->reply, l->name, id, data, size, err);
}

tsr_wire_loop *tsr_wire_loop_create(const char *name, size_t buffer_size, const tsr_dispatch *child,
                                    const tsr_wire_loop_observer *observer, tsr_error *err)
{
    tsr_wire_loop *l = calloc(1, sizeof *l);
    if (!l) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", name);
        return NULL;
    }
    l->name = name;
    l->child = child;
    if (observer)
        l->observer = *observer;
    tsr_pack_sink sink = {.flush = loop_flush, .reply = loop_take_reply, .ctx = l};
    l->packer = tsr_packer_create(buffer_size, &sink, err);
    if (l->packer)
        l->unpacker = tsr_unpacker_create(child, loop_store_reply, l, err);
    if (!l->packer || !l->unpacker) {
        tsr_wire_loop_destroy(l);
        return NULL;
    }
    return l;
}

void tsr_wire_loop_fill_dispatch(tsr_wire_loop *loop, tsr_dispatch *table)
{
    tsr_packer_fill_dispatch(loop->packer, table);
    loop->pack_make_current = table->MakeCurrentTSR;
    tsr_set_MakeCurrentTSR(table, loop_MakeCurrentTSR, loop);
}

int tsr_wire_loop_flush(tsr_wire_loop *loop) { return tsr_packer_flush(loop->packer); }

void tsr_wire_loop_destroy(tsr_wire_loop *loop)
{
    if (!loop)
        return;
    if (loop->packer && loop->unpacker)
        tsr_packer_flush(loop->packer);
    tsr_packer_destroy(loop->packer);
    tsr_unpacker_destroy(loop->unpacker);
    tsr_reply_slot_free(&loop->reply);
    free(loop);
}
