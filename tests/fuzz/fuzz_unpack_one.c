/* tests/fuzz/fuzz_unpack_one.c — runs one fuzz input through a real
 * unpacker (see fuzz_unpack.h): splits it into wire buffers, decodes them
 * into the generated recording table (it stands in for GL: copies every
 * argument and every byte an input pointer addresses, sized the way GL
 * would read them, and writes a pattern into every output), reads every
 * reply, and checks the unpacker's error contract. Owns one unpacker and
 * recorder per input; never keeps state between inputs (a crash must
 * reproduce from its input file alone). */
#include "fuzz_unpack.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/dispatch.h"
#include "tessera/error.h"
#include "tessera/dev/unpack.h"
#include "wire_test_gen.h"

/* Outputs one command may request. The library default (1 GiB) is right for
 * a server, but a fuzzer would spend its time zeroing memory; the check
 * that matters (the bound is enforced without overflow) is the same. */
#define FUZZ_MAX_OUTPUT ((uint64_t)16 << 20)

typedef struct reply_reader {
    uint64_t replies;
    uint32_t checksum;
} reply_reader;

/* Reads every byte of every reply, so a reply whose size does not match
 * its bytes is an ASan error here, and checks the item framing
 * (tessera/dev/wire.h section 5: 8-aligned u64 length + bytes). */
static int read_reply(void *ctx, uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    (void)err;
    reply_reader *r = ctx;
    r->replies++;
    uint32_t sum = id;
    for (size_t i = 0; i < size; i++)
        sum = sum * 31u + data[i];
    r->checksum ^= sum;
    size_t pos = 0;
    while (pos < size) {
        if (size - pos < 8)
            __builtin_trap(); /* truncated item header: the unpacker built a bad reply */
        uint64_t len;
        memcpy(&len, data + pos, 8);
        if (len > size - pos - 8)
            __builtin_trap(); /* item longer than the reply */
        pos += 8 + (size_t)len;
        pos = (pos + 7u) & ~(size_t)7u;
    }
    return 0;
}

/* The error contract: a failure is one of the documented codes with a
 * message naming the culprit. Anything else is a bug worth a crash report. */
static void check_error(int rc, const tsr_error *err)
{
    if (rc == 0)
        return;
    if (rc != TSR_EPROTO && rc != TSR_ENOMEM)
        __builtin_trap();
    if (err->code != rc || memchr(err->message, '\0', sizeof err->message) == NULL || err->message[0] == '\0')
        __builtin_trap();
}

int fuzz_unpack_one(const uint8_t *data, size_t size) { return fuzz_unpack_explain(data, size, NULL, 0); }

int fuzz_unpack_explain(const uint8_t *data, size_t size, char *why, size_t why_size)
{
    tsr_dispatch *table = malloc(sizeof *table);
    tsr_recorder *recorder = malloc(sizeof *recorder);
    if (!table || !recorder) {
        free(table);
        free(recorder);
        return TSR_ENOMEM;
    }
    tsr_recorder_init(recorder);
    tsr_recorder_fill(table, recorder);

    reply_reader reader = {0};
    tsr_error err;
    tsr_error_clear(&err);
    tsr_unpacker *u = tsr_unpacker_create(table, read_reply, &reader, &err);
    if (!u) {
        free(table);
        free(recorder);
        return err.code ? err.code : TSR_ENOMEM;
    }
    u->max_output = FUZZ_MAX_OUTPUT;

    int first_error = 0;
    size_t pos = 0;
    do {
        /* Buffers after the first start at odd offsets of the input, which
         * also exercises the unpacker's copy of misaligned buffers. */
        size_t rest = size - pos;
        tsr_error header_err;
        size_t n = tsr_wire_buffer_size(data + pos, rest, &header_err);
        if (n == 0 || n > rest)
            n = rest;
        tsr_error_clear(&err);
        int rc = tsr_unpacker_run(u, data + pos, n, &err);
        check_error(rc, &err);
        if (rc != 0 && first_error == 0) {
            first_error = rc;
            if (why && why_size)
                snprintf(why, why_size, "%s", err.message);
        }
        pos += n;
    } while (pos < size);

    tsr_unpacker_destroy(u);
    tsr_recorder_clear(recorder);
    free(recorder);
    free(table);
    return first_error;
}
