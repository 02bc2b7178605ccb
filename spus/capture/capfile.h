/* spus/capture/capfile.h — the capture file: a GL stream recorded by the
 * capture SPU in tessera's wire format, and read back by `tessera replay`
 * (cli/cmd_replay.c) and the fuzz target (tests/fuzz/fuzz_capture.c).
 * Static library tessera_capture_file, linked by both.
 *
 * Owns: the file layout (this comment is its specification), the writer
 * (temporary file renamed at close) and the bounds-checked reader.
 * Never: trusts a length or count from the file, reads outside the bytes
 * it was given, or exits; every refusal is one line naming the file and
 * the byte offset.
 *
 * Layout (all little-endian; every record starts 8-aligned):
 *
 *   offset  size  header (64 bytes)
 *   0       8     magic "TSRCAP\r\n"
 *   8       4     u32 capture format version (TSR_CAPFILE_VERSION)
 *   12      4     u32 wire magic of the buffers (TSR_WIRE_MAGIC, "TSW1":
 *                 tessera/dev/wire.h, the wire protocol's version)
 *   16      4     u32 window width  (the stream's first WindowCreateTSR /
 *   20      4     u32 window height  WindowSizeTSR; 0 x 0 when it had none)
 *   24      4     u32 frames (SwapBuffersTSR commands in the stream)
 *   28      4     u32 0
 *   32      8     u64 buffer records
 *   40      8     u64 reply records
 *   48      8     u64 bytes of records after the header (file size - 64)
 *   56      8     u64 0
 *
 *   record  u32 kind, u32 request id (replies; 0 for buffers),
 *           u64 length L, L bytes, zero padding to 8
 *     kind 1 BUFFER: one wire buffer exactly as the packer flushed it
 *            (header + opcodes + data, its own header giving L again)
 *     kind 2 REPLY:  the reply the program received for request `id`
 *            (tessera/dev/wire.h section 5), right after the buffer that
 *            ends with that request
 *
 * The header's counts are written when the capture ends: the file is
 * written under a hidden temporary name and renamed then, so a file that
 * exists is whole. The replies are what the program's downstream chain
 * answered (glGet*, glGenLists, ...); the commands after them already
 * carry what the program did with those answers, so a replay needs no
 * one to answer and can compare the answers it gets with these. */
#ifndef TSR_CAPFILE_H
#define TSR_CAPFILE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "tessera/error.h"

#define TSR_CAPFILE_MAGIC "TSRCAP\r\n"
#define TSR_CAPFILE_VERSION 1u
#define TSR_CAPFILE_HEADER_SIZE 64u
#define TSR_CAPFILE_RECORD_HEADER 16u
#define TSR_CAPFILE_BUFFER 1u
#define TSR_CAPFILE_REPLY 2u

typedef struct tsr_capfile_header {
    uint32_t version, wire_magic;
    uint32_t width, height, frames;
    uint64_t buffers, replies, bytes;
} tsr_capfile_header;

/* --- writing ------------------------------------------------------------ */

typedef struct tsr_capfile_writer {
    FILE *file;
    char path[4096], tmp[4096];
    tsr_capfile_header header;
} tsr_capfile_writer;

/* Creates the hidden temporary ".NAME.tmp-PID-N" next to `path`. */
int tsr_capfile_writer_open(tsr_capfile_writer *w, const char *path, tsr_error *err);
int tsr_capfile_write_record(tsr_capfile_writer *w, uint32_t kind, uint32_t id, const void *data, size_t size,
                             tsr_error *err);
/* Writes the header's counts (w->header) and renames the temporary to the
 * final name; on any failure the temporary is removed. */
int tsr_capfile_writer_close(tsr_capfile_writer *w, tsr_error *err);
/* Removes the temporary without writing a file. */
void tsr_capfile_writer_abandon(tsr_capfile_writer *w);

/* --- reading ------------------------------------------------------------ */

typedef struct tsr_capfile_record {
    uint32_t kind, id;
    const uint8_t *data;
    size_t size;
    uint64_t offset; /* of the record's header in the file */
    uint64_t index;  /* 0, 1, ... in file order */
} tsr_capfile_record;

typedef struct tsr_capfile {
    const char *name; /* the file, in every message */
    const uint8_t *data;
    size_t size;
    tsr_capfile_header header;
    size_t pos; /* the next record */
    uint64_t index;
    void *map; /* tsr_capfile_open's mapping, or NULL */
    size_t map_size;
} tsr_capfile;

/* Checks the header of `size` bytes at `data` (kept, not copied). Every
 * error: "NAME: byte OFFSET: what". */
int tsr_capfile_parse(tsr_capfile *f, const uint8_t *data, size_t size, const char *name, tsr_error *err);
/* Maps the file at `path` read-only and parses it. */
int tsr_capfile_open(tsr_capfile *f, const char *path, tsr_error *err);
void tsr_capfile_close(tsr_capfile *f);
/* The next record: 1 with *rec filled, 0 at the end (after checking the
 * header's counts against the records read), or an error. A BUFFER's
 * wire header is checked against its length here; its commands are
 * checked by the unpacker that runs it. */
int tsr_capfile_next(tsr_capfile *f, tsr_capfile_record *rec, tsr_error *err);
/* Back to the first record (or to the record at `offset`, one that
 * tsr_capfile_next returned before). */
void tsr_capfile_rewind(tsr_capfile *f, uint64_t offset, uint64_t index);

/* What `tessera replay --info` prints and the fuzz target checks: every
 * record read and every buffer decoded into a table that only counts the
 * calls a chain would receive (per dispatch slot, `counts` has
 * TSR_DISPATCH_COUNT entries, may be NULL), and the replies per request
 * they answer (`reply_counts`, per dispatch slot of the call that asked,
 * the last one decoded before the reply; may be NULL; a reply with no call
 * between it and the one before counts in replies_unattributed). Fails on
 * the first malformed record or buffer, naming the byte offset, and when
 * the frames found differ from the header's. */
typedef struct tsr_capfile_stats {
    uint64_t frames, buffers, replies, commands, calls, buffer_bytes, reply_bytes;
    uint64_t replies_unattributed;
} tsr_capfile_stats;
int tsr_capfile_scan(tsr_capfile *f, tsr_capfile_stats *stats, uint64_t *counts, uint64_t *reply_counts,
                     tsr_error *err);

#endif
