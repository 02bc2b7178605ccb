/* netlib/shm.c — shared memory between the two ends of a Unix-socket
 * connection (net.h, SHARED MEMORY): each side's ring, a sealed memfd it
 * maps and hands to its peer over the socket (SCM_RIGHTS), into which data
 * messages are written so that only a 16-byte descriptor crosses the socket.
 * Owns: creating, handing over, checking and mapping the rings; the
 * position arithmetic both sides must agree on; the receive side's record
 * of which ring messages are released, and (shm_drop_released) dropping
 * its mapping of the large ones once released (a ring page stays resident
 * in the sender's process only, not in both).
 * Never: maps a segment whose size could change under the mapping (a
 * memfd without F_SEAL_SHRINK and F_SEAL_GROW could be truncated and make
 * a read fault), trusts a descriptor or a returned position before
 * checking it against the ring (a lying peer fails its connection with one
 * line naming it), or keeps a passed file descriptor open.
 *
 * Why rings and not a segment per message: one mapping per direction,
 * made once, so a message costs no system call beyond the descriptor's
 * write, and its pages are reused (the sender rewinds to the start of the
 * ring whenever it is empty) instead of faulted in fresh. Why libuv's IPC
 * pipes: the descriptor must travel in order with the stream and be taken
 * off the receiving socket with recvmsg, which libuv does only in IPC
 * mode; the memfd is wrapped in a uv_pipe_t only for the hand-over. */
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "net_internal.h"
#include "tessera/log.h"

/* Messages from this size on have their pages dropped by the receiver
 * once released (drop_read_pages); small ones cost more to drop than
 * they hold. */
#define NET_SHM_DROP_MIN (256u << 10)

uint64_t net_shm_slot(uint64_t len)
{
    uint64_t s = (len + (NET_SHM_SLOT_ALIGN - 1)) & ~(uint64_t)(NET_SHM_SLOT_ALIGN - 1);
    return s ? s : NET_SHM_SLOT_ALIGN;
}

/* The start of the ring lap at or after pos. */
static uint64_t lap_start(uint64_t pos, uint64_t size)
{
    uint64_t r = pos % size;
    return r ? pos + (size - r) : pos;
}

bool net_shm_fits(const tsr_net_conn *c, uint64_t len, uint64_t *pos_out)
{
    const net_ring *r = &c->tx;
    if (!r->map || len > r->size)
        return false;
    uint64_t slot = net_shm_slot(len);
    if (slot > r->size)
        return false;
    uint64_t pos = r->head;
    /* Lowest offsets first: an empty ring starts over at offset 0, and so
     * does a message that fits between the start and the oldest one not
     * released. So the pages in use stay those of the messages in flight
     * (each one is resident in both processes), instead of creeping
     * through the whole ring when the peer holds one message while the
     * next is written; and a message never has to skip the end. */
    bool empty = r->head == r->tail;
    uint64_t next_lap = lap_start(pos, r->size);
    if (empty || pos % r->size > r->size - slot || (next_lap != pos && next_lap - r->tail <= r->size - slot))
        pos = next_lap;
    /* Unreleased messages lie in [tail, head): the new one must not reach
     * them a lap later. (An empty ring holds nothing to reach.) */
    if (!empty && pos - r->tail > r->size - slot)
        return false;
    *pos_out = pos;
    return true;
}

size_t net_credit_encode(const tsr_net_conn *c, uint32_t count, uint8_t out[12])
{
    net_put_u32(out, count);
    if (!c->shm)
        return 4;
    net_put_u64(out + 4, c->rx.tail);
    return 12;
}

int net_shm_credit(tsr_net_conn *c, uint64_t pos)
{
    net_ring *r = &c->tx;
    if (pos > r->head) {
        net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s returned ring position %llu, past the %llu sent to it",
                      c->peer_name, c->address, (unsigned long long)pos, (unsigned long long)r->head);
        return -1;
    }
    /* Lower: a CREDIT written before this side rewound its empty ring (or
     * for an inline message): nothing new, and it could only hold this
     * side back. */
    if (pos > r->tail)
        r->tail = pos;
    return 0;
}

/* ---- handing over this side's ring --------------------------------------- */

typedef struct ring_write {
    uv_write_t req;
    uv_pipe_t handle; /* the memfd, only to pass it (uv_write2) */
    tsr_net_conn *conn;
    uint8_t bytes[TSR_NET_HEADER_BYTES + 8];
} ring_write;

static void ring_write_free(uv_handle_t *h) { free(h->data); }

static void on_ring_written(uv_write_t *req, int status)
{
    ring_write *w = req->data;
    tsr_net_conn *c = w->conn;
    pthread_mutex_lock(&c->net->lock);
    c->writes_in_flight--;
    if (status < 0 && status != UV_ECANCELED && c->state == NET_OPEN && !net_write_met_closed_peer(c, status))
        net_conn_fail(c, TSR_EIO, "net: handing the shared-memory ring to peer '%s' at %s failed: %s", c->peer_name,
                      c->address, uv_strerror(status));
    net_conn_signal(c);
    pthread_mutex_unlock(&c->net->lock);
    uv_close((uv_handle_t *)&w->handle, ring_write_free); /* closes this process's memfd */
}

void net_shm_start(tsr_net_conn *c)
{
    tsr_net *net = c->net;
    uint64_t size = net->config.shm_ring_bytes;
    const char *why = NULL;
    int fd = memfd_create("tessera-net-ring", MFD_CLOEXEC | MFD_ALLOW_SEALING);
    void *map = MAP_FAILED;
    if (fd < 0)
        why = "memfd_create";
    else if (ftruncate(fd, (off_t)size) != 0)
        why = "ftruncate";
    else if (fcntl(fd, F_ADD_SEALS, F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_SEAL) != 0)
        why = "sealing";
    else if ((map = mmap(NULL, (size_t)size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0)) == MAP_FAILED)
        why = "mmap";
    ring_write *w = why ? NULL : calloc(1, sizeof *w);
    if (!why && !w)
        why = "out of memory";
    int err = 0;
    if (!why) {
        w->conn = c;
        w->req.data = w;
        w->handle.data = w;
        if ((err = uv_pipe_init(&net->loop, &w->handle, 0)) != 0) {
            why = "uv_pipe_init";
            free(w);
        } else if ((err = uv_pipe_open(&w->handle, fd)) != 0) {
            why = "uv_pipe_open"; /* the fd is still ours: closed below */
            uv_close((uv_handle_t *)&w->handle, ring_write_free);
        } else {
            fd = -1; /* the handle's now */
            net_header_encode(w->bytes, net_version(net), NET_RING, 0, 8);
            net_put_u64(w->bytes + TSR_NET_HEADER_BYTES, size);
            uv_buf_t buf = uv_buf_init((char *)w->bytes, sizeof w->bytes);
            /* Counted as in flight: no direct write (direct.c) overtakes it. */
            c->writes_in_flight++;
            if ((err = uv_write2(&w->req, &c->h.stream, &buf, 1, (uv_stream_t *)&w->handle, on_ring_written)) != 0) {
                c->writes_in_flight--;
                why = "uv_write2";
                munmap(map, (size_t)size); /* the peer never gets it */
                map = MAP_FAILED;
                uv_close((uv_handle_t *)&w->handle, ring_write_free);
            }
        }
    }
    if (why) {
        tsr_log(TSR_LOG_WARN, "net: no shared-memory ring to peer '%s' at %s (%s: %s): messages go through the socket",
                c->peer_name, c->address, why, err ? uv_strerror(err) : strerror(errno));
        if (map != MAP_FAILED)
            munmap(map, (size_t)size);
        if (fd >= 0)
            close(fd);
        return;
    }
    c->tx.map = map;
    c->tx.size = size;
}

/* ---- taking the peer's ring ------------------------------------------------ */

static void handle_free(uv_handle_t *h) { free(h); }

/* Takes the next descriptor the peer passed off the pipe; -1 if none. The
 * descriptor stays owned by *out (closed with it). */
static int take_fd(tsr_net_conn *c, uv_pipe_t **out)
{
    *out = NULL;
    if (c->transport != TSR_NET_UNIX || uv_pipe_pending_count(&c->h.pipe) < 1)
        return -1;
    uv_pipe_t *h = malloc(sizeof *h);
    if (!h || uv_pipe_init(&c->net->loop, h, 0) != 0) {
        free(h);
        return -1;
    }
    uv_os_fd_t fd = -1;
    if (uv_accept(&c->h.stream, (uv_stream_t *)h) != 0 || uv_fileno((uv_handle_t *)h, &fd) != 0)
        fd = -1;
    *out = h;
    return fd;
}

static int ring_refused(tsr_net_conn *c, uv_pipe_t *h, const char *why)
{
    net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s handed over a bad shared-memory ring: %s", c->peer_name,
                  c->address, why);
    if (h)
        uv_close((uv_handle_t *)h, handle_free);
    return -1;
}

int net_shm_ring_received(tsr_net_conn *c, const net_msg *m)
{
    uint64_t size = net_get_u64(m->data);
    char why[200];
    uv_pipe_t *h;
    int fd = take_fd(c, &h);
    if (fd < 0) {
        snprintf(why, sizeof why, "no memory segment came with it (%llu bytes announced)", (unsigned long long)size);
        return ring_refused(c, h, why);
    }
    if (size < NET_SHM_RING_MIN || size > NET_SHM_RING_MAX || size % (uint64_t)sysconf(_SC_PAGESIZE)) {
        snprintf(why, sizeof why, "%llu bytes (a page multiple of 64 KiB..%llu bytes expected)",
                 (unsigned long long)size, (unsigned long long)NET_SHM_RING_MAX);
        return ring_refused(c, h, why);
    }
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || (uint64_t)st.st_size != size) {
        snprintf(why, sizeof why, "the segment is not a file of the %llu bytes announced", (unsigned long long)size);
        return ring_refused(c, h, why);
    }
    int seals = fcntl(fd, F_GET_SEALS);
    int need = F_SEAL_SHRINK | F_SEAL_GROW;
    if (seals < 0 || (seals & need) != need) {
        snprintf(why, sizeof why, "the segment is not a memfd sealed against resizing (it could be truncated)");
        return ring_refused(c, h, why);
    }
    void *map = mmap(NULL, (size_t)size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (map == MAP_FAILED) {
        snprintf(why, sizeof why, "cannot map its %llu bytes: %s", (unsigned long long)size, strerror(errno));
        return ring_refused(c, h, why);
    }
    uv_close((uv_handle_t *)h, handle_free); /* the mapping outlives the descriptor */
    c->rx.map = map;
    c->rx.size = size;
    return 0;
}

int net_shm_check_stray_fds(tsr_net_conn *c)
{
    if (c->transport != TSR_NET_UNIX || c->handles_closing)
        return 0;
    int pending = uv_pipe_pending_count(&c->h.pipe);
    /* Only the peer's one ring may be on its way. */
    int allowed = c->shm && !c->rx.map ? 1 : 0;
    if (pending <= allowed)
        return 0;
    net_conn_fail(c, TSR_EPROTO, "net: peer '%s' at %s passed %d file descriptor%s out of place", c->peer_name,
                  c->address, pending - allowed, pending - allowed == 1 ? "" : "s");
    return -1; /* the caller closes the connection, and libuv the descriptors */
}

/* ---- ring messages ----------------------------------------------------------- */

static void release_nothing(void *data, void *ctx)
{
    (void)data;
    (void)ctx;
}

int net_shm_take_descriptor(tsr_net_conn *c, net_msg *m)
{
    net_ring *r = &c->rx;
    uint64_t pos = net_get_u64(m->data), len = net_get_u64(m->data + 8);
    uint64_t slot = net_shm_slot(len);
    bool in_place = pos == r->head;
    bool next_lap = pos > r->head && pos % r->size == 0 && pos - r->head < r->size;
    const char *why = NULL;
    if (len > c->net->config.max_message_bytes)
        why = "longer than this node's max_message_bytes";
    else if (len > r->size || slot > r->size || pos % r->size > r->size - slot)
        why = "outside the ring";
    else if (!in_place && !next_lap)
        why = "not where the previous message ended";
    else if (r->tail != r->head && pos - r->tail > r->size - slot)
        why = "over messages not yet released";
    if (why) {
        net_conn_fail(c, TSR_EPROTO,
                      "net: peer '%s' at %s sent a shared-memory descriptor %s (position %llu, length %llu, ring of "
                      "%llu bytes, next position %llu)",
                      c->peer_name, c->address, why, (unsigned long long)pos, (unsigned long long)len,
                      (unsigned long long)r->size, (unsigned long long)r->head);
        return -1;
    }
    net_ring_slot *s = malloc(sizeof *s);
    if (!s) {
        net_conn_fail(c, TSR_ENOMEM, "net: out of memory for a message from %s", c->address);
        return -1;
    }
    s->next = NULL;
    s->start = pos;
    s->end = pos + slot;
    s->released = false;
    if (r->slots_tail)
        r->slots_tail->next = s;
    else
        r->slots_head = s;
    r->slots_tail = s;
    if (r->tail == r->head) /* empty: the sender may have rewound; what it skipped is free */
        r->tail = pos;
    r->head = pos + slot;
    free(m->data);
    m->data = r->map + pos % r->size;
    m->len = len;
    m->cap = 0;
    m->release = release_nothing; /* the ring's memory */
    m->slot = s;
    c->stats.messages_received_shm++;
    c->stats.bytes_received_shm += len;
    return 0;
}

/* The receiver's mapping of a released message is dropped (its page table
 * entries only: the memfd keeps the data, and the sender, which wrote the
 * pages, still maps them). Each ring page is then resident in one process,
 * the sender's, instead of being counted in both; the next read of it
 * faults the pages back in, 16 at a time (the kernel's fault-around for
 * shared file pages). A page shared with a neighbouring message still held
 * is dropped too: its bytes are intact, the next touch maps it again. */
static void drop_read_pages(net_ring *r, const net_ring_slot *s)
{
    uintptr_t page = (uintptr_t)sysconf(_SC_PAGESIZE);
    uintptr_t a = (uintptr_t)(r->map + s->start % r->size), b = a + (uintptr_t)(s->end - s->start);
    a &= ~(page - 1);
    b = (b + page - 1) & ~(page - 1);
    if (b > a)
        madvise((void *)a, (size_t)(b - a), MADV_DONTNEED);
}

void net_shm_drop_read(tsr_net_conn *c, net_msg *m)
{
    /* Without the lock: the message is still held, so its slot and the
     * ring's mapping stay (a connection is freed only once nothing is
     * held), and the zap of its page table entries, with the TLB flush it
     * takes, holds up no other thread of this side. */
    if (m->slot && c->net->config.shm_drop_released && m->slot->end - m->slot->start >= NET_SHM_DROP_MIN)
        drop_read_pages(&c->rx, m->slot);
}

void net_shm_release(tsr_net_conn *c, net_msg *m)
{
    if (!m->slot)
        return;
    m->slot->released = true;
    m->slot = NULL;
    net_ring *r = &c->rx;
    while (r->slots_head && r->slots_head->released) {
        net_ring_slot *s = r->slots_head;
        r->tail = s->end;
        r->slots_head = s->next;
        if (!r->slots_head)
            r->slots_tail = NULL;
        free(s);
    }
}

void net_shm_free(tsr_net_conn *c)
{
    if (c->tx.map)
        munmap(c->tx.map, (size_t)c->tx.size);
    if (c->rx.map)
        munmap(c->rx.map, (size_t)c->rx.size);
    c->tx.map = c->rx.map = NULL;
    while (c->rx.slots_head) {
        net_ring_slot *s = c->rx.slots_head;
        c->rx.slots_head = s->next;
        free(s);
    }
    c->rx.slots_tail = NULL;
    free(c->reserve_buf);
    c->reserve_buf = NULL;
}
