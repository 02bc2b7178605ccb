/* spus/capture/capture.c — the "capture" SPU: writes the stream passing
 * through it to a capture file (capfile.h: tessera's wire buffers plus the
 * replies the program received, under a header with the window size and
 * counts) and passes every call on to its child. `tessera replay` feeds
 * such a file into any chain or graph.
 *
 * It works as loopback does (tessera/dev/wireloop.h): every call is packed
 * by the real packer; each flushed buffer is written to the file, then
 * unpacked into the child, and
 * the child's answers to requests (glGet*, glGenLists, ReadPixels) are
 * written after it and returned to the program. So the child sees exactly
 * what the replay will later feed a chain, and the file holds exactly the
 * bytes a server would have received.
 *
 * Owns, per instance: its wire loop and the file writer. Never: keeps globals (two captures in one process write two
 * files), drops or changes a call, or leaves a half-written file under the
 * final name (it is renamed into place at the end). */
#include <stdlib.h>
#include <string.h>

#include "capfile.h"
#include "tessera/dev/pack.h"
#include "tessera/dev/wireloop.h"
#include "tessera/log.h"
#include "tessera/spu.h"

typedef struct capture_spu {
    const char *name;
    tsr_wire_loop *loop;
    tsr_capfile_writer writer;
    int writing;                                /* the file is open */
    long frames;                                /* frames=: finish the file after this many (0: at the end) */
    uint64_t max_bytes;                         /* max_bytes=: abandon the file past this size (0: no bound) */
    tsr_entry swap, window_create, window_size; /* the packer's own slots */
} capture_spu;

/* A write that fails ends the capture (the file is removed: a capture is
 * whole or absent); the program and its chain go on. */
static void capture_write(capture_spu *s, uint32_t kind, uint32_t id, const void *data, size_t size)
{
    if (!s->writing)
        return;
    uint64_t record = TSR_CAPFILE_RECORD_HEADER + ((uint64_t)size + 7) / 8 * 8;
    if (s->max_bytes && TSR_CAPFILE_HEADER_SIZE + s->writer.header.bytes + record > s->max_bytes) {
        tsr_log(TSR_LOG_ERROR, "%s: the capture would pass max_bytes=%llu; the capture is abandoned (no file)", s->name,
                (unsigned long long)s->max_bytes);
        tsr_capfile_writer_abandon(&s->writer);
        s->writing = 0;
        return;
    }
    tsr_error err = {0};
    if (tsr_capfile_write_record(&s->writer, kind, id, data, size, &err) != TSR_OK) {
        tsr_log(TSR_LOG_ERROR, "%s: %s; the capture is abandoned", s->name, err.message);
        tsr_capfile_writer_abandon(&s->writer);
        s->writing = 0;
    }
}

static void capture_finish(capture_spu *s)
{
    if (!s->writing)
        return;
    s->writing = 0;
    tsr_error err = {0};
    if (tsr_capfile_writer_close(&s->writer, &err) != TSR_OK)
        tsr_log(TSR_LOG_ERROR, "%s: %s", s->name, err.message);
    else
        tsr_log(TSR_LOG_INFO, "%s: wrote %s (%u frames, %llu buffers, %llu replies)", s->name, s->writer.path,
                s->writer.header.frames, (unsigned long long)s->writer.header.buffers,
                (unsigned long long)s->writer.header.replies);
}

static void capture_buffer(void *ctx, const uint8_t *buf, size_t size)
{
    capture_write(ctx, TSR_CAPFILE_BUFFER, 0, buf, size);
}

static void capture_reply(void *ctx, uint32_t id, const uint8_t *data, size_t size)
{
    capture_write(ctx, TSR_CAPFILE_REPLY, id, data, size);
}

/* The header's window: the stream's first size. */
static void note_window(capture_spu *s, GLsizei width, GLsizei height)
{
    if (s->writing && s->writer.header.width == 0 && s->writer.header.height == 0 && width > 0 && height > 0) {
        s->writer.header.width = (uint32_t)width;
        s->writer.header.height = (uint32_t)height;
    }
}

static void capture_WindowCreateTSR(void *self, GLint window, GLsizei width, GLsizei height)
{
    capture_spu *s = self;
    note_window(s, width, height);
    ((tsr_fn_WindowCreateTSR)s->window_create.fn)(s->window_create.self, window, width, height);
}

static void capture_WindowSizeTSR(void *self, GLint window, GLsizei width, GLsizei height)
{
    capture_spu *s = self;
    note_window(s, width, height);
    ((tsr_fn_WindowSizeTSR)s->window_size.fn)(s->window_size.self, window, width, height);
}

/* The packer flushes at every swap, so when it returns the frame is in the
 * file and the child has drawn it. */
static void capture_SwapBuffersTSR(void *self, GLint window, GLbitfield flags)
{
    capture_spu *s = self;
    ((tsr_fn_SwapBuffersTSR)s->swap.fn)(s->swap.self, window, flags);
    if (!s->writing)
        return;
    s->writer.header.frames++;
    if (s->frames > 0 && s->writer.header.frames >= (uint32_t)s->frames)
        capture_finish(s);
}

static void capture_destroy(void *instance)
{
    capture_spu *s = instance;
    if (!s)
        return;
    if (s->loop)
        tsr_wire_loop_flush(s->loop);
    capture_finish(s);
    tsr_wire_loop_destroy(s->loop);
    free(s);
}

static void *capture_create(const tsr_spu_init *init, tsr_error *err)
{
    const char *file = tsr_options_string(init->options, "file");
    if (!file || !file[0]) {
        tsr_error_set(err, TSR_EINVAL, "%s: option file is required (e.g. file=out/run.tsrcap)", init->instance_name);
        return NULL;
    }
    capture_spu *s = calloc(1, sizeof *s);
    if (!s) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    s->name = init->instance_name;
    s->frames = (long)tsr_options_int(init->options, "frames");
    s->max_bytes = (uint64_t)tsr_options_int(init->options, "max_bytes");
    size_t size = (size_t)tsr_options_int(init->options, "buffer_size");
    tsr_wire_loop_observer observer = {.buffer = capture_buffer, .reply = capture_reply, .ctx = s};
    s->loop = tsr_wire_loop_create(s->name, size, init->child, &observer, err);
    if (!s->loop) {
        capture_destroy(s);
        return NULL;
    }
    if (tsr_capfile_writer_open(&s->writer, file, err) != TSR_OK) {
        char why[sizeof err->message];
        snprintf(why, sizeof why, "%s", err->message);
        tsr_error_set(err, err->code, "%s: file=%s: %s", s->name, file, why);
        capture_destroy(s);
        return NULL;
    }
    s->writing = 1;
    tsr_wire_loop_fill_dispatch(s->loop, init->table);
    s->swap = init->table->SwapBuffersTSR;
    s->window_create = init->table->WindowCreateTSR;
    s->window_size = init->table->WindowSizeTSR;
    tsr_set_SwapBuffersTSR(init->table, capture_SwapBuffersTSR, s);
    tsr_set_WindowCreateTSR(init->table, capture_WindowCreateTSR, s);
    tsr_set_WindowSizeTSR(init->table, capture_WindowSizeTSR, s);
    return s;
}

static const tsr_option_spec capture_options[] = {
    {.name = "file",
     .type = TSR_OPT_STRING,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "the capture file (required); written under a hidden temporary name and renamed when the capture "
             "ends, so it exists only whole; one file per capture instance"},
    {.name = "frames",
     .type = TSR_OPT_INT,
     .default_value = "0",
     .min = 0,
     .max = 2147483647.0,
     .help = "finish the file after this many frames and pass the rest of the stream on uncaptured "
             "(0: capture until the chain ends; needed for programs that end only by a signal)"},
    {.name = "max_bytes",
     .type = TSR_OPT_INT,
     .default_value = "0",
     .min = 0,
     .max = 9007199254740992.0,
     .help = "abandon the capture (remove it, log one line, pass every call on) when the file would grow past this "
             "many bytes (0, the default: no bound); for programs that send gigabytes"},
    {.name = "buffer_size",
     .type = TSR_OPT_INT,
     .default_value = "1048576",
     .min = TSR_PACK_MIN_BUFFER,
     .max = 1073741824.0,
     .help = "bytes of one wire buffer (header, opcodes and data)"},
};

static const tsr_spu_class capture_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "capture",
    .summary = "writes the stream and the replies it gets to a capture file (tessera replay), passes every call on",
    .options = capture_options,
    .option_count = sizeof capture_options / sizeof capture_options[0],
    .create = capture_create,
    .destroy = capture_destroy,
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &capture_class; }
