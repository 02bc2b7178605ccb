/* tests/psubmit/unpack_yield_test.c — the unpacker stops after a command whose
 * handler yields and resumes exactly after it (what a server node does
 * when a client blocks at a barrier mid-buffer): a buffer with vertices
 * around three BarrierExecTSR commands (one of them last) is packed, run
 * and resumed until finished; the calls seen must be the packed ones in
 * order, each once, with a yield right after every barrier; resume
 * without a paused buffer is TSR_ESTATE; a new run abandons a paused one.
 * Every step needs the one before, so each check is a REQUIRE. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/dev/pack.h"
#include "tessera/dispatch.h"
#include "tessera/dev/unpack.h"
#include "tessera/error.h"

#include "harness.h"

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

int main(void)
{
    tsr_error err = {0};
    sink_state sink_buf = {0};
    tsr_pack_sink sink = {.flush = keep, .ctx = &sink_buf};
    tsr_packer *p = tsr_packer_create(4096, &sink, &err);
    tsr_dispatch *table = calloc(1, sizeof *table);
    tsr_dispatch *target = calloc(1, sizeof *target);
    REQUIRE(p && table && target, "setup: %s", p ? "out of memory" : err.message);
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
    int flushed = tsr_packer_flush(p);
    REQUIRE(flushed == 0 && sink_buf.buf, "packing: flush returned %d, %s", flushed,
            sink_buf.buf ? "a buffer was kept" : "no buffer reached the sink");

    recorder r = {0};
    tsr_dispatch_fill_nop(target);
    tsr_set_Vertex3f(target, rec_Vertex3f, &r);
    tsr_set_BarrierExecTSR(target, rec_BarrierExecTSR, &r);
    r.u = tsr_unpacker_create(target, NULL, NULL, &err);
    REQUIRE(r.u, "unpacker: %s", err.message);
    int resumed = tsr_unpacker_resume(r.u, &err);
    REQUIRE(resumed == TSR_ESTATE, "resume with nothing paused is not TSR_ESTATE but %d", resumed);

    static const char *const want[] = {"V0", "V1", "B1", "V2", "B2", "V3", "V4", "B3"};
    static const int stops[] = {3, 5, 8}; /* calls seen at each yield */
    int rc = tsr_unpacker_run(r.u, sink_buf.buf, sink_buf.size, &err);
    int yields = 0;
    while (rc == TSR_UNPACK_YIELDED) {
        REQUIRE(yields < 3 && r.n == stops[yields] && tsr_unpacker_paused(r.u),
                "yield at the wrong place: yield %d after %d calls (want %d), paused %d", yields + 1, r.n,
                yields < 3 ? stops[yields] : -1, tsr_unpacker_paused(r.u));
        yields++;
        rc = tsr_unpacker_resume(r.u, &err);
    }
    REQUIRE(rc == 0, "unpack error %d: %s", rc, err.message);
    /* The last barrier is the last command: its yield comes before the
     * buffer's end check, and resuming then finishes it. */
    REQUIRE(yields == 3 && r.n == 8 && !tsr_unpacker_paused(r.u),
            "wrong number of yields or calls: %d yields, %d calls, paused %d", yields, r.n, tsr_unpacker_paused(r.u));
    for (int i = 0; i < 8; i++)
        REQUIRE(strcmp(r.calls[i], want[i]) == 0, "calls out of order: call %d is %s, want %s", i, r.calls[i], want[i]);

    /* A new run abandons a paused buffer. */
    r.n = 0;
    rc = tsr_unpacker_run(r.u, sink_buf.buf, sink_buf.size, &err);
    REQUIRE(rc == TSR_UNPACK_YIELDED && r.n == 3, "second run did not yield after B1: rc %d after %d calls", rc, r.n);
    r.n = 0;
    rc = tsr_unpacker_run(r.u, sink_buf.buf, sink_buf.size, &err);
    REQUIRE(rc == TSR_UNPACK_YIELDED && r.n == 3 && strcmp(r.calls[0], "V0") == 0,
            "a new run did not start from the first command: rc %d after %d calls, first %s", rc, r.n,
            r.n ? r.calls[0] : "(none)");

    printf("PASS: 8 calls in order, yields after each of 3 barriers, resume finishes the buffer\n");
    tsr_unpacker_destroy(r.u);
    tsr_packer_destroy(p);
    free(sink_buf.buf);
    free(table);
    free(target);
    return 0;
}
