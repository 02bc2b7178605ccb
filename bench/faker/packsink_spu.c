/* bench/faker/packsink_spu.c — a benchmark-only SPU, "bench_packsink": the
 * pack SPU's packer (the generated packing functions, bounding box kept)
 * with a sink that only counts buffers instead of a socket, so a driver
 * can time glVertex3f from a program's call to the packed bytes without
 * the receiver's speed in the figure. Built into bench's own directory and
 * found through TESSERA_SPU_PATH; never installed, never in `tessera spus`.
 * Owns per instance: its packer and counters. Never: sends anything.
 * At each glFinish it flushes and prints "packsink: BUFFERS BYTES
 * BOX" to stderr (BOX: whether the packer still kept a box), so the
 * driver can check the stream and the box were really made. */
#include <stdio.h>
#include <stdlib.h>

#include "tessera/dev/pack.h"
#include "tessera/spu.h"

typedef struct packsink {
    tsr_packer *packer;
    unsigned long long buffers, bytes;
} packsink;

static int count_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    (void)buf;
    (void)err;
    packsink *s = ctx;
    s->buffers++;
    s->bytes += size;
    return 0;
}

static void packsink_finish(void *self)
{
    packsink *s = self;
    float lo[3], hi[3];
    bool box = tsr_packer_bbox(s->packer, lo, hi) && lo[0] <= hi[0];
    tsr_packer_flush(s->packer);
    fprintf(stderr, "packsink: %llu %llu %s\n", s->buffers, s->bytes, box ? "box" : "nobox");
}

static void *packsink_create(const tsr_spu_init *init, tsr_error *err)
{
    packsink *s = calloc(1, sizeof *s);
    if (!s) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    tsr_pack_sink sink = {.flush = count_flush, .ctx = s};
    s->packer = tsr_packer_create(1u << 20, &sink, err);
    if (!s->packer) {
        free(s);
        return NULL;
    }
    tsr_packer_fill_dispatch(s->packer, init->table);
    tsr_set_Finish(init->table, packsink_finish, s);
    return s;
}

static void packsink_destroy(void *instance)
{
    packsink *s = instance;
    tsr_packer_destroy(s->packer);
    free(s);
}

static const tsr_spu_class packsink_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "bench_packsink",
    .summary = "benchmark only: packs the stream into a sink that counts it",
    .create = packsink_create,
    .destroy = packsink_destroy,
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &packsink_class; }
