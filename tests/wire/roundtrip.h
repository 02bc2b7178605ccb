/* tests/wire/roundtrip.h — shared pieces of the wire tests: a packer whose
 * sink keeps a copy of every buffer and unpacks it at once into a
 * recording table (replies answered in-process), and a second recorder
 * that receives the same calls directly, so the two can be compared.
 * Owns nothing global; never hides a failure (every helper reports). */
#ifndef TSR_TESTS_WIRE_ROUNDTRIP_H
#define TSR_TESTS_WIRE_ROUNDTRIP_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/dev/pack.h"
#include "tessera/dev/unpack.h"
#include "wire_gen.h"
#include "wire_test_gen.h"

/* A failed check leaves the test function (later steps need what it made). */
#define HARNESS_ON_FAIL return 1
#include "harness.h"

typedef struct roundtrip {
    tsr_packer *packer;
    tsr_dispatch pack_table;     /* calls enter here and get packed */
    tsr_recorder expect, actual; /* direct calls / unpacked calls */
    tsr_dispatch expect_table, actual_table;
    tsr_unpacker *unpacker;
    uint8_t **bufs; /* copies of every flushed buffer (kept: */
    size_t *sizes;  /* unpacked pointers point into them) */
    size_t nbufs;
    int unpack_rc;
    tsr_error unpack_err;
    uint8_t *reply;
    size_t reply_len;
    uint32_t reply_id;
    int has_reply;
    int decode; /* unpack on flush (default 1) */
} roundtrip;

static int rt_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    roundtrip *rt = ctx;
    rt->bufs = realloc(rt->bufs, (rt->nbufs + 1) * sizeof *rt->bufs);
    rt->sizes = realloc(rt->sizes, (rt->nbufs + 1) * sizeof *rt->sizes);
    uint8_t *copy = malloc(size);
    if (!rt->bufs || !rt->sizes || !copy)
        return tsr_error_set(err, TSR_ENOMEM, "test sink: out of memory");
    memcpy(copy, buf, size);
    rt->bufs[rt->nbufs] = copy;
    rt->sizes[rt->nbufs] = size;
    rt->nbufs++;
    if (!rt->decode)
        return 0;
    int rc = tsr_unpacker_run(rt->unpacker, copy, size, &rt->unpack_err);
    if (rc && !rt->unpack_rc)
        rt->unpack_rc = rc;
    return rc;
}

static int rt_store_reply(void *ctx, uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    roundtrip *rt = ctx;
    free(rt->reply);
    rt->reply = malloc(size + 1);
    if (!rt->reply)
        return tsr_error_set(err, TSR_ENOMEM, "test reply: out of memory");
    memcpy(rt->reply, data, size);
    rt->reply_len = size;
    rt->reply_id = id;
    rt->has_reply = 1;
    return 0;
}

static int rt_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    roundtrip *rt = ctx;
    if (!rt->has_reply || rt->reply_id != id)
        return tsr_error_set(err, TSR_EPROTO, "test: no reply to request %u", id);
    rt->has_reply = 0;
    *data = rt->reply;
    *size = rt->reply_len;
    return 0;
}

static int rt_init(roundtrip *rt, size_t buffer_size)
{
    memset(rt, 0, sizeof *rt);
    rt->decode = 1;
    tsr_error err;
    tsr_pack_sink sink = {.flush = rt_flush, .reply = rt_reply, .ctx = rt};
    rt->packer = tsr_packer_create(buffer_size, &sink, &err);
    if (!rt->packer) {
        fprintf(stderr, "packer: %s\n", err.message);
        return -1;
    }
    tsr_packer_fill_dispatch(rt->packer, &rt->pack_table);
    tsr_recorder_init(&rt->expect);
    tsr_recorder_init(&rt->actual);
    tsr_recorder_fill(&rt->expect_table, &rt->expect);
    tsr_recorder_fill(&rt->actual_table, &rt->actual);
    rt->unpacker = tsr_unpacker_create(&rt->actual_table, rt_store_reply, rt, &err);
    return rt->unpacker ? 0 : -1;
}

static void rt_free(roundtrip *rt)
{
    tsr_packer_destroy(rt->packer);
    tsr_unpacker_destroy(rt->unpacker);
    tsr_recorder_clear(&rt->expect);
    tsr_recorder_clear(&rt->actual);
    for (size_t i = 0; i < rt->nbufs; i++)
        free(rt->bufs[i]);
    free(rt->bufs);
    free(rt->sizes);
    free(rt->reply);
}

/* Flushes and compares the recordings; 0 when equal. */
static int rt_check(roundtrip *rt, const char *what)
{
    tsr_packer_flush(rt->packer);
    if (rt->unpack_rc) {
        fprintf(stderr, "%s: unpack failed: %s\n", what, rt->unpack_err.message);
        return 1;
    }
    const tsr_error *pe = tsr_packer_error(rt->packer);
    if (pe->code) {
        fprintf(stderr, "%s: packer error: %s\n", what, pe->message);
        return 1;
    }
    char msg[512];
    if (tsr_recorder_compare(&rt->expect, &rt->actual, msg, sizeof msg) != 0) {
        fprintf(stderr, "%s: %s\n", what, msg);
        return 1;
    }
    return 0;
}

/* Header fields of a captured buffer. */
static inline uint32_t buf_nops(const uint8_t *b) { return tsr_wire_get_u32(b + 4); }
static inline uint64_t buf_len(const uint8_t *b) { return tsr_wire_get_u64(b + 8); }
static inline uint8_t *buf_data(uint8_t *b) { return b + TSR_WIRE_HEADER_SIZE + tsr_wire_align8(buf_nops(b)); }

#endif
