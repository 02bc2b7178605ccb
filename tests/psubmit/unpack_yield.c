/* tests/psubmit/unpack_yield.c — the unpacker stops after a command whose
 * handler yields and resumes exactly after it (what a server node does
 * when a client blocks at a barrier mid-buffer): a buffer with vertices
 * around three BarrierExecTSR commands (one of them last) is packed, run
 * and resumed until finished; the calls seen must be the packed ones in
 * order, each once, with a yield right after every barrier; resume
 * without a paused buffer is TSR_ESTATE; a new run abandons a paused one. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/dev/pack.h"
#include "tessera/dispatch.h"
#include "tessera/dev/unpack.h"

#define MAX_CALLS 64

typedef struct recorder {
    tsr_unpacker *u;
    char calls[MAX_CALLS][32];
    int n;
} recorder;

typedef struct sink_state {
    uint8_t *buf;
    size_t size;
} sink_state;

static int keep(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    (void)err;
    sink_state *s = ctx;
    s->buf = malloc(size);
    memcpy(s->buf, buf, size);
    s->size = size;
    return 0;
}

static void rec_Vertex3f(void *self, GLfloat x, GLfloat y, GLfloat z)
{
    recorder *r = self;
    (void)y, (void)z;
    snprintf(r->calls[r->n++ % MAX_CALLS], 32, "V%d", (int)x);
}

static void rec_BarrierExecTSR(void *self, GLuint name)
{
    recorder *r = self;
    snprintf(r->calls[r->n++ % MAX_CALLS], 32, "B%u", name);
    tsr_unpacker_yield(r->u);
}

static int fail(const char *what)
{
    fprintf(stderr, "FAIL: %s\n", what);
    return 1;
}

int main(void)
{
    tsr_error err = {0};
    sink_state sink_buf = {0};
    tsr_pack_sink sink = {.flush = keep, .ctx = &sink_buf};
    tsr_packer *p = tsr_packer_create(4096, &sink, &err);
    tsr_dispatch *table = calloc(1, sizeof *table);
    tsr_dispatch *target = calloc(1, sizeof *target);
    if (!p || !table || !target)
        return fail("setup");
    tsr_packer_fill_dispatch(p, table);
    /* V0 V1 B1 V2 B2 V3 V4 B3 */
    tsr_call_Vertex3f(table, 0, 0, 0);
    tsr_call_Vertex3f(table, 1, 0, 0);
    tsr_call_BarrierExecTSR(table, 1);
    tsr_call_Vertex3f(table, 2, 0, 0);
    tsr_call_BarrierExecTSR(table, 2);
    tsr_call_Vertex3f(table, 3, 0, 0);
    tsr_call_Vertex3f(table, 4, 0, 0);
    tsr_call_BarrierExecTSR(table, 3);
    if (tsr_packer_flush(p) != 0 || !sink_buf.buf)
        return fail("packing");

    recorder r = {0};
    tsr_dispatch_fill_nop(target);
    tsr_set_Vertex3f(target, rec_Vertex3f, &r);
    tsr_set_BarrierExecTSR(target, rec_BarrierExecTSR, &r);
    r.u = tsr_unpacker_create(target, NULL, NULL, &err);
    if (!r.u)
        return fail("unpacker");
    if (tsr_unpacker_resume(r.u, &err) != TSR_ESTATE)
        return fail("resume with nothing paused is not TSR_ESTATE");

    static const char *const want[] = {"V0", "V1", "B1", "V2", "B2", "V3", "V4", "B3"};
    static const int stops[] = {3, 5, 8}; /* calls seen at each yield */
    int rc = tsr_unpacker_run(r.u, sink_buf.buf, sink_buf.size, &err);
    int yields = 0;
    while (rc == TSR_UNPACK_YIELDED) {
        if (yields >= 3 || r.n != stops[yields] || !tsr_unpacker_paused(r.u))
            return fail("yield at the wrong place");
        yields++;
        rc = tsr_unpacker_resume(r.u, &err);
    }
    if (rc != 0) {
        fprintf(stderr, "FAIL: unpack error %d: %s\n", rc, err.message);
        return 1;
    }
    /* The last barrier is the last command: its yield comes before the
     * buffer's end check, and resuming then finishes it. */
    if (yields != 3 || r.n != 8 || tsr_unpacker_paused(r.u))
        return fail("wrong number of yields or calls");
    for (int i = 0; i < 8; i++)
        if (strcmp(r.calls[i], want[i]) != 0)
            return fail("calls out of order");

    /* A new run abandons a paused buffer. */
    r.n = 0;
    if (tsr_unpacker_run(r.u, sink_buf.buf, sink_buf.size, &err) != TSR_UNPACK_YIELDED || r.n != 3)
        return fail("second run did not yield after B1");
    r.n = 0;
    rc = tsr_unpacker_run(r.u, sink_buf.buf, sink_buf.size, &err);
    if (rc != TSR_UNPACK_YIELDED || r.n != 3 || strcmp(r.calls[0], "V0") != 0)
        return fail("a new run did not start from the first command");

    printf("PASS: 8 calls in order, yields after each of 3 barriers, resume finishes the buffer\n");
    tsr_unpacker_destroy(r.u);
    tsr_packer_destroy(p);
    free(sink_buf.buf);
    free(table);
    free(target);
    return 0;
}
