/* spus/loopback/loopback.c — the "loopback" SPU: packs every call with the
 * real packer into wire buffers and, on each flush, unpacks the buffer into
 * its child in the same process (replies answered synchronously). It
 * exercises the whole wire path without a network. Owns its packer,
 * unpacker and reply copy; never calls the child except through the
 * unpacker. */
#include <stdlib.h>
#include <string.h>

#include "tessera/dev/pack.h"
#include "tessera/log.h"
#include "tessera/spu.h"
#include "tessera/dev/unpack.h"

typedef struct loopback_spu {
    const char *name;
    tsr_packer *packer;
    tsr_unpacker *unpacker;
    uint8_t *reply; /* the last reply the unpacker produced */
    size_t reply_len, reply_cap;
    uint32_t reply_id;
    int has_reply;
} loopback_spu;

static int loopback_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    loopback_spu *s = ctx;
    int rc = tsr_unpacker_run(s->unpacker, buf, size, err);
    if (rc)
        tsr_log(TSR_LOG_ERROR, "%s: %s", s->name, err->message);
    return rc;
}

static int loopback_store_reply(void *ctx, uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    loopback_spu *s = ctx;
    if (size > s->reply_cap) {
        uint8_t *r = realloc(s->reply, size);
        if (!r)
            return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory for a %zu-byte reply", s->name, size);
        s->reply = r;
        s->reply_cap = size;
    }
    if (size)
        memcpy(s->reply, data, size);
    s->reply_len = size;
    s->reply_id = id;
    s->has_reply = 1;
    return 0;
}

static int loopback_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    loopback_spu *s = ctx;
    if (!s->has_reply || s->reply_id != id)
        return tsr_error_set(err, TSR_EPROTO, "%s: no reply to request %u", s->name, id);
    s->has_reply = 0;
    /* A reply may be empty; still hand out a valid pointer. */
    *data = s->reply ? s->reply : (const uint8_t *)"";
    *size = s->reply_len;
    return 0;
}

static void loopback_destroy(void *instance)
{
    loopback_spu *s = instance;
    if (!s)
        return;
    if (s->packer)
        tsr_packer_flush(s->packer);
    tsr_packer_destroy(s->packer);
    tsr_unpacker_destroy(s->unpacker);
    free(s->reply);
    free(s);
}

static void *loopback_create(const tsr_spu_init *init, tsr_error *err)
{
    loopback_spu *s = calloc(1, sizeof *s);
    if (!s) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    s->name = init->instance_name;
    size_t size = (size_t)tsr_options_int(init->options, "buffer_size");
    tsr_pack_sink sink = {.flush = loopback_flush, .reply = loopback_reply, .ctx = s};
    s->packer = tsr_packer_create(size, &sink, err);
    if (s->packer)
        s->unpacker = tsr_unpacker_create(init->child, loopback_store_reply, s, err);
    if (!s->packer || !s->unpacker) {
        loopback_destroy(s);
        return NULL;
    }
    tsr_packer_fill_dispatch(s->packer, init->table);
    return s;
}

static const tsr_option_spec loopback_options[] = {
    {.name = "buffer_size",
     .type = TSR_OPT_INT,
     .default_value = "1048576",
     .min = TSR_PACK_MIN_BUFFER,
     .max = 1073741824.0,
     .help = "bytes of one wire buffer (header, opcodes and data)"},
};

static const tsr_spu_class loopback_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "loopback",
    .summary = "packs every call into wire buffers and unpacks them into its child in-process",
    .options = loopback_options,
    .option_count = sizeof loopback_options / sizeof loopback_options[0],
    .create = loopback_create,
    .destroy = loopback_destroy,
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &loopback_class; }
