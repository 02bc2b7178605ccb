/* spus/capture/capfile.c — the capture file's writer and its bounds-checked
 * reader (layout: capfile.h). */
#include "capfile.h"

#include <errno.h>
#include <fcntl.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tessera/dev/unpack.h"
#include "tessera/dev/wire.h"
#include "tessera/dispatch.h"

static const uint8_t zeros[8];

/* --- writing ------------------------------------------------------------ */

static void encode_header(uint8_t out[TSR_CAPFILE_HEADER_SIZE], const tsr_capfile_header *h)
{
    memset(out, 0, TSR_CAPFILE_HEADER_SIZE);
    memcpy(out, TSR_CAPFILE_MAGIC, 8);
    tsr_wire_put_u32(out + 8, h->version);
    tsr_wire_put_u32(out + 12, h->wire_magic);
    tsr_wire_put_u32(out + 16, h->width);
    tsr_wire_put_u32(out + 20, h->height);
    tsr_wire_put_u32(out + 24, h->frames);
    tsr_wire_put_u64(out + 32, h->buffers);
    tsr_wire_put_u64(out + 40, h->replies);
    tsr_wire_put_u64(out + 48, h->bytes);
}

int tsr_capfile_writer_open(tsr_capfile_writer *w, const char *path, tsr_error *err)
{
    static atomic_uint sequence;
    memset(w, 0, sizeof *w);
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    int dir_len = slash ? (int)(slash - path + 1) : 0;
    int n = snprintf(w->tmp, sizeof w->tmp, "%.*s.%.200s.tmp-%ld-%u", dir_len, path, base, (long)getpid(),
                     atomic_fetch_add(&sequence, 1));
    if (!base[0] || n < 0 || (size_t)n >= sizeof w->tmp || strlen(path) >= sizeof w->path)
        return tsr_error_set(err, TSR_EINVAL, "capture file '%s': not a usable file name", path);
    snprintf(w->path, sizeof w->path, "%s", path);
    int fd = open(w->tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    w->file = fd >= 0 ? fdopen(fd, "wb") : NULL;
    if (!w->file) {
        int e = errno;
        if (fd >= 0) {
            close(fd);
            unlink(w->tmp);
        }
        return tsr_error_set(err, e == ENOENT ? TSR_ENOENT : TSR_EIO, "cannot create %s: %s", path, strerror(e));
    }
    w->header.version = TSR_CAPFILE_VERSION;
    w->header.wire_magic = TSR_WIRE_MAGIC;
    uint8_t h[TSR_CAPFILE_HEADER_SIZE];
    encode_header(h, &w->header);
    if (fwrite(h, 1, sizeof h, w->file) != sizeof h) {
        int e = errno;
        tsr_capfile_writer_abandon(w);
        return tsr_error_set(err, TSR_EIO, "%s: write failed: %s", path, strerror(e));
    }
    return TSR_OK;
}

int tsr_capfile_write_record(tsr_capfile_writer *w, uint32_t kind, uint32_t id, const void *data, size_t size,
                             tsr_error *err)
{
    if (!w->file)
        return tsr_error_set(err, TSR_ESTATE, "%s: the capture is closed", w->path);
    uint8_t rh[TSR_CAPFILE_RECORD_HEADER];
    tsr_wire_put_u32(rh, kind);
    tsr_wire_put_u32(rh + 4, id);
    tsr_wire_put_u64(rh + 8, size);
    size_t pad = (size_t)(tsr_wire_align8(size) - size);
    if (fwrite(rh, 1, sizeof rh, w->file) != sizeof rh || (size && fwrite(data, 1, size, w->file) != size) ||
        (pad && fwrite(zeros, 1, pad, w->file) != pad))
        return tsr_error_set(err, TSR_EIO, "%s: write failed: %s", w->path, strerror(errno));
    w->header.bytes += sizeof rh + size + pad;
    if (kind == TSR_CAPFILE_BUFFER)
        w->header.buffers++;
    else
        w->header.replies++;
    return TSR_OK;
}

void tsr_capfile_writer_abandon(tsr_capfile_writer *w)
{
    if (!w->file)
        return;
    fclose(w->file);
    w->file = NULL;
    unlink(w->tmp);
}

int tsr_capfile_writer_close(tsr_capfile_writer *w, tsr_error *err)
{
    if (!w->file)
        return tsr_error_set(err, TSR_ESTATE, "%s: the capture is closed", w->path);
    uint8_t h[TSR_CAPFILE_HEADER_SIZE];
    encode_header(h, &w->header);
    int failed =
        fflush(w->file) != 0 || fseek(w->file, 0, SEEK_SET) != 0 || fwrite(h, 1, sizeof h, w->file) != sizeof h;
    int e = errno;
    failed |= fclose(w->file) != 0;
    w->file = NULL;
    if (failed || rename(w->tmp, w->path) != 0) {
        e = failed ? e : errno;
        unlink(w->tmp);
        return tsr_error_set(err, TSR_EIO, "%s: %s", w->path, strerror(e));
    }
    return TSR_OK;
}

/* --- reading ------------------------------------------------------------ */

int tsr_capfile_parse(tsr_capfile *f, const uint8_t *data, size_t size, const char *name, tsr_error *err)
{
    void *map = f->map;
    size_t map_size = f->map_size;
    memset(f, 0, sizeof *f);
    f->map = map;
    f->map_size = map_size;
    f->name = name;
    f->data = data;
    f->size = size;
    f->pos = TSR_CAPFILE_HEADER_SIZE;
    if (size < 8 || memcmp(data, TSR_CAPFILE_MAGIC, 8) != 0)
        return tsr_error_set(err, TSR_EPROTO, "%s: byte 0: not a tessera capture file (no \"TSRCAP\" magic)", name);
    if (size < TSR_CAPFILE_HEADER_SIZE)
        return tsr_error_set(err, TSR_EPROTO, "%s: byte %zu: truncated: the header is %u bytes", name, size,
                             TSR_CAPFILE_HEADER_SIZE);
    tsr_capfile_header *h = &f->header;
    h->version = tsr_wire_get_u32(data + 8);
    h->wire_magic = tsr_wire_get_u32(data + 12);
    h->width = tsr_wire_get_u32(data + 16);
    h->height = tsr_wire_get_u32(data + 20);
    h->frames = tsr_wire_get_u32(data + 24);
    h->buffers = tsr_wire_get_u64(data + 32);
    h->replies = tsr_wire_get_u64(data + 40);
    h->bytes = tsr_wire_get_u64(data + 48);
    if (h->version != TSR_CAPFILE_VERSION)
        return tsr_error_set(err, TSR_EPROTO, "%s: byte 8: capture format version %u, this tessera reads version %u",
                             name, h->version, TSR_CAPFILE_VERSION);
    if (h->wire_magic != TSR_WIRE_MAGIC)
        return tsr_error_set(err, TSR_EPROTO, "%s: byte 12: wire format 0x%08x, this tessera speaks 0x%08x (\"TSW1\")",
                             name, h->wire_magic, TSR_WIRE_MAGIC);
    if (tsr_wire_get_u32(data + 28) != 0 || tsr_wire_get_u64(data + 56) != 0)
        return tsr_error_set(err, TSR_EPROTO, "%s: byte %d: reserved header field is not 0", name,
                             tsr_wire_get_u32(data + 28) != 0 ? 28 : 56);
    if (h->width > 16384 || h->height > 16384)
        return tsr_error_set(err, TSR_EPROTO, "%s: byte 16: window %ux%u, larger than 16384 on a side", name, h->width,
                             h->height);
    if (h->bytes != size - TSR_CAPFILE_HEADER_SIZE)
        return tsr_error_set(err, TSR_EPROTO, "%s: byte %zu: the header says %llu bytes of records, the file has %zu%s",
                             name, size, (unsigned long long)h->bytes, size - TSR_CAPFILE_HEADER_SIZE,
                             h->bytes > size - TSR_CAPFILE_HEADER_SIZE ? " (truncated)" : "");
    return TSR_OK;
}

int tsr_capfile_open(tsr_capfile *f, const char *path, tsr_error *err)
{
    memset(f, 0, sizeof *f);
    f->name = path;
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return tsr_error_set(err, errno == ENOENT ? TSR_ENOENT : TSR_EIO, "%s: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        int e = errno;
        close(fd);
        return tsr_error_set(err, TSR_EINVAL, "%s: %s", path, S_ISREG(st.st_mode) ? strerror(e) : "not a file");
    }
    size_t size = (size_t)st.st_size;
    const uint8_t *data = (const uint8_t *)"";
    if (size) {
        void *m = mmap(NULL, size, PROT_READ, MAP_PRIVATE, fd, 0);
        if (m == MAP_FAILED) {
            int e = errno;
            close(fd);
            return tsr_error_set(err, TSR_EIO, "%s: cannot map it: %s", path, strerror(e));
        }
        f->map = m;
        f->map_size = size;
        data = m;
    }
    close(fd);
    int rc = tsr_capfile_parse(f, data, size, path, err);
    if (rc != TSR_OK)
        tsr_capfile_close(f);
    return rc;
}

void tsr_capfile_close(tsr_capfile *f)
{
    if (f->map)
        munmap(f->map, f->map_size);
    f->map = NULL;
    f->data = NULL;
    f->size = 0;
}

void tsr_capfile_rewind(tsr_capfile *f, uint64_t offset, uint64_t index)
{
    f->pos = offset >= TSR_CAPFILE_HEADER_SIZE && offset <= f->size ? (size_t)offset : TSR_CAPFILE_HEADER_SIZE;
    f->index = f->pos == TSR_CAPFILE_HEADER_SIZE ? 0 : index;
}

int tsr_capfile_next(tsr_capfile *f, tsr_capfile_record *rec, tsr_error *err)
{
    size_t left = f->size - f->pos;
    if (left == 0) {
        if (f->index != f->header.buffers + f->header.replies)
            return tsr_error_set(err, TSR_EPROTO,
                                 "%s: byte %zu: the header says %llu buffers and %llu replies, the file has %llu "
                                 "records",
                                 f->name, f->pos, (unsigned long long)f->header.buffers,
                                 (unsigned long long)f->header.replies, (unsigned long long)f->index);
        return 0;
    }
    const uint8_t *p = f->data + f->pos;
    if (left < TSR_CAPFILE_RECORD_HEADER)
        return tsr_error_set(err, TSR_EPROTO, "%s: byte %zu: truncated record header (%zu of %u bytes)", f->name,
                             f->pos, left, TSR_CAPFILE_RECORD_HEADER);
    uint32_t kind = tsr_wire_get_u32(p), id = tsr_wire_get_u32(p + 4);
    uint64_t len = tsr_wire_get_u64(p + 8);
    if (kind != TSR_CAPFILE_BUFFER && kind != TSR_CAPFILE_REPLY)
        return tsr_error_set(err, TSR_EPROTO, "%s: byte %zu: unknown record kind %u (1 buffer, 2 reply)", f->name,
                             f->pos, kind);
    if (kind == TSR_CAPFILE_BUFFER && id != 0)
        return tsr_error_set(err, TSR_EPROTO, "%s: byte %zu: buffer record with request id %u (must be 0)", f->name,
                             f->pos + 4, id);
    size_t room = left - TSR_CAPFILE_RECORD_HEADER;
    if (len > room || tsr_wire_align8(len) > room)
        return tsr_error_set(err, TSR_EPROTO, "%s: byte %zu: record of %llu bytes, only %zu left in the file", f->name,
                             f->pos + 8, (unsigned long long)len, room);
    const uint8_t *body = p + TSR_CAPFILE_RECORD_HEADER;
    for (uint64_t i = len; i < tsr_wire_align8(len); i++)
        if (body[i])
            return tsr_error_set(err, TSR_EPROTO, "%s: byte %zu: record padding is not zero", f->name,
                                 f->pos + TSR_CAPFILE_RECORD_HEADER + (size_t)i);
    if (kind == TSR_CAPFILE_BUFFER) {
        tsr_error why = {0};
        size_t want = tsr_wire_buffer_size(body, (size_t)len, &why);
        if (want == 0)
            return tsr_error_set(err, TSR_EPROTO, "%s: byte %zu: buffer record: %s", f->name,
                                 f->pos + TSR_CAPFILE_RECORD_HEADER, why.message);
        if (want != len)
            return tsr_error_set(err, TSR_EPROTO,
                                 "%s: byte %zu: buffer record of %llu bytes holds a wire buffer of %zu bytes", f->name,
                                 f->pos + 8, (unsigned long long)len, want);
    }
    rec->kind = kind;
    rec->id = id;
    rec->data = body;
    rec->size = (size_t)len;
    rec->offset = f->pos;
    rec->index = f->index++;
    f->pos += TSR_CAPFILE_RECORD_HEADER + (size_t)tsr_wire_align8(len);
    return 1;
}

/* --- scanning ------------------------------------------------------------- */

typedef struct scan_state {
    tsr_hook hooks[TSR_DISPATCH_COUNT];
    uint64_t *counts;
    uint64_t calls, frames;
    int last_slot; /* of the last call decoded: the request a reply answers */
} scan_state;

static void scan_count(void *ctx, int slot)
{
    scan_state *s = ctx;
    s->calls++;
    s->last_slot = slot;
    if (slot == TSR_SLOT_SwapBuffersTSR)
        s->frames++;
    if (s->counts)
        s->counts[slot]++;
}

int tsr_capfile_scan(tsr_capfile *f, tsr_capfile_stats *stats, uint64_t *counts, uint64_t *reply_counts, tsr_error *err)
{
    memset(stats, 0, sizeof *stats);
    scan_state *s = calloc(1, sizeof *s);
    tsr_dispatch *table = calloc(1, sizeof *table);
    if (!s || !table) {
        free(s);
        free(table);
        return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", f->name);
    }
    s->counts = counts;
    s->last_slot = -1;
    if (counts)
        memset(counts, 0, sizeof *counts * TSR_DISPATCH_COUNT);
    if (reply_counts)
        memset(reply_counts, 0, sizeof *reply_counts * TSR_DISPATCH_COUNT);
    tsr_dispatch_fill_nop(table);
    for (int i = 0; i < TSR_DISPATCH_COUNT; i++) {
        s->hooks[i] = (tsr_hook){.before = scan_count, .ctx = s};
        tsr_dispatch_hook(table, i, &s->hooks[i]);
    }
    int rc = TSR_OK;
    tsr_unpacker *u = tsr_unpacker_create(table, NULL, NULL, err);
    if (!u)
        rc = err->code ? err->code : TSR_ENOMEM;
    tsr_capfile_rewind(f, 0, 0);
    tsr_capfile_record rec;
    while (rc == TSR_OK) {
        int got = tsr_capfile_next(f, &rec, err);
        if (got <= 0) {
            rc = got;
            break;
        }
        if (rec.kind == TSR_CAPFILE_REPLY) {
            stats->replies++;
            stats->reply_bytes += rec.size;
            /* A buffer with a request ends with it, so the last call decoded
             * is the one this reply answers; a reply with no call before it
             * (only a malformed file has one) is counted apart. */
            if (s->last_slot < 0)
                stats->replies_unattributed++;
            else if (reply_counts)
                reply_counts[s->last_slot]++;
            s->last_slot = -1;
            continue;
        }
        stats->buffers++;
        stats->buffer_bytes += rec.size;
        tsr_error why = {0};
        if (tsr_unpacker_run(u, rec.data, rec.size, &why) < 0)
            rc = tsr_error_set(err, TSR_EPROTO, "%s: byte %llu: buffer %llu: %s", f->name,
                               (unsigned long long)rec.offset + TSR_CAPFILE_RECORD_HEADER,
                               (unsigned long long)stats->buffers - 1, why.message);
    }
    if (rc == TSR_OK && s->frames != f->header.frames)
        rc = tsr_error_set(err, TSR_EPROTO, "%s: byte 24: the header says %u frames, the stream has %llu", f->name,
                           f->header.frames, (unsigned long long)s->frames);
    stats->frames = s->frames;
    stats->calls = s->calls;
    stats->commands = u ? u->commands : 0;
    tsr_unpacker_destroy(u);
    tsr_capfile_rewind(f, 0, 0);
    free(s);
    free(table);
    return rc;
}
