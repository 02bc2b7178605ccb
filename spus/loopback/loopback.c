/* spus/loopback/loopback.c — the "loopback" SPU: packs every call with the
 * real packer into wire buffers and, on each flush, unpacks the buffer into
 * its child in the same process (replies answered synchronously). It
 * exercises the whole wire path without a network. Owns its wire loop
 * (tessera/dev/wireloop.h: packer, unpacker, reply); never calls the
 * child except through the unpacker. */
#include <stdlib.h>

#include "tessera/dev/pack.h"
#include "tessera/dev/wireloop.h"
#include "tessera/spu.h"

static void loopback_destroy(void *instance) { tsr_wire_loop_destroy(instance); }

static void *loopback_create(const tsr_spu_init *init, tsr_error *err)
{
    size_t size = (size_t)tsr_options_int(init->options, "buffer_size");
    tsr_wire_loop *loop = tsr_wire_loop_create(init->instance_name, size, init->child, NULL, err);
    if (loop)
        tsr_wire_loop_fill_dispatch(loop, init->table);
    return loop;
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
