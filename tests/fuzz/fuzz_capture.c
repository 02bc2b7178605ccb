/* tests/fuzz/fuzz_capture.c — fuzz target for the capture file's reader
 * (spus/capture/capfile.c), as `tessera replay --info` runs it: the input
 * is a capture file, parsed from memory and scanned record by record,
 * every buffer decoded by the real unpacker into a counting table of
 * no-ops. Checked: a rejection is one line naming the file
 * ("fuzz.tsrcap: byte N: ...") with an offset inside the input; an
 * accepted file's records and frames are what its header says, and every
 * reply is counted once, against the request it answers or apart. */
#include "fuzz_target.h"

#include <stdlib.h>

#include "capfile.h"
#include "tessera/dispatch.h"

int fuzz_target_explain(const uint8_t *data, size_t size, char *why, size_t why_size)
{
    tsr_capfile f;
    memset(&f, 0, sizeof f);
    tsr_error err = {0};
    int rc = tsr_capfile_parse(&f, data, size, "fuzz.tsrcap", &err);
    tsr_capfile_stats st;
    uint64_t replies_by_request[TSR_DISPATCH_COUNT];
    if (rc == TSR_OK)
        rc = tsr_capfile_scan(&f, &st, NULL, replies_by_request, &err);
    if (rc != TSR_OK) {
        static const char prefix[] = "fuzz.tsrcap: byte ";
        FUZZ_REQUIRE(!strncmp(err.message, prefix, sizeof prefix - 1));
        char *end;
        unsigned long long at = strtoull(err.message + sizeof prefix - 1, &end, 10);
        FUZZ_REQUIRE(end != err.message + sizeof prefix - 1 && *end == ':' && at <= size);
        return fuzz_rejected(rc, &err, why, why_size);
    }
    FUZZ_REQUIRE(st.buffers == f.header.buffers && st.replies == f.header.replies);
    FUZZ_REQUIRE(st.frames == f.header.frames && st.calls >= st.frames);
    FUZZ_REQUIRE(st.buffer_bytes + st.reply_bytes <= f.header.bytes);
    uint64_t attributed = 0;
    for (int i = 0; i < TSR_DISPATCH_COUNT; i++)
        attributed += replies_by_request[i];
    FUZZ_REQUIRE(attributed + st.replies_unattributed == st.replies);
    return 0;
}

#ifndef TSR_FUZZ_TARGET
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_target_explain(data, size, NULL, 0);
    return 0;
}
#endif
