/* spus/binaryswap/mesh.c — the peer mesh of a binaryswap group and the
 * transport the strategies run over (send, send_buffer, recv: peers over
 * netlib, rank 0's own display participant as a local queue), the alpha
 * mode's box distances, and the end of a peer that fails. Owns, in the
 * instance: the netlib instance, listener and connections, the held
 * message, the local queue. Never composites or reads pixels.
 *
 * Group. `rank` (0..N-1) and `peers` (every peer's node address, rank
 * order) come from the graph (TSR_SPU_ROLE_PEERS); N is the number of
 * peers. Peers exchange images on their own listening sockets, one per
 * peer: `exchange` gives their addresses in rank order, else each is
 * derived from the peer's node address (unix:PATH -> unix:PATH.x;
 * tcp://HOST:PORT -> tcp://HOST:PORT+1) or, in situ (application peers
 * have no address: the graph run gives empty ones), from the display's
 * and the rank R (unix:PATH.peerR; tcp://HOST:PORT+1+R). The mesh is made at the first
 * swap: every peer listens, connects to every lower rank (retrying until
 * timeout_ms while that peer is not listening yet) and accepts the higher
 * ranks; the first message on a connection names the connecting rank.
 *
 * Failures: a peer that does not answer within timeout_ms, a connection
 * that breaks, a message whose frame, rank, window size or region is not
 * what it must be: one line naming the peer (rank and address), then the
 * process ends with status 1 (on_error=exit, the default, as readback
 * does: a frame that cannot be composited is a failed run). */
#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "instance.h"
#include "layers.h"
#include "tessera/dev/client.h"
#include "tessera/dev/util.h"
#include "tessera/log.h"

/* Ends the process after one line (tsr_stream_client_exit). */
void binaryswap_fatal(binaryswap_spu *b, const char *fmt, ...)
{
    char what[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(what, sizeof what, fmt, ap);
    va_end(ap);
    tsr_log(TSR_LOG_ERROR, "%s: %s", b->name, what);
    tsr_log(TSR_LOG_ERROR, "%s: ending (a frame that cannot be composited fails the run)", b->name);
    fflush(NULL);
    /* What this peer already sent (its HELLO, an image) and the line it
     * ends on reach the others before it goes, so they name the real
     * fault (a peer killed before this one), not its vanishing. */
    /* While the mesh forms, a peer reads a HELLO first from each link and
     * names a failure there itself: only a formed mesh hears last words. */
    tsr_error ignored = {0};
    for (int r = 0; b->meshed && r < b->nranks && r < BINARYSWAP_MAX_PEERS; r++)
        if (b->conns[r])
            tsr_net_send(b->conns[r], BINARYSWAP_KIND_ENDING, what, strlen(what), 100, &ignored);
    for (int r = 0; r < b->nranks && r < BINARYSWAP_MAX_PEERS; r++)
        if (b->conns[r])
            tsr_net_conn_flush(b->conns[r], 200);
    tsr_stream_client_exit();
}

static int64_t now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* The exchange address of a peer whose node listens at `node` (header). */
int binaryswap_derive_exchange(const char *node, char *out, size_t size, int display_rank, tsr_error *err)
{
    if (!strncmp(node, "unix:", 5)) {
        int n =
            display_rank ? snprintf(out, size, "%s.peer%d", node, display_rank - 1) : snprintf(out, size, "%s.x", node);
        if (n < 0 || (size_t)n >= size)
            return tsr_error_set(err, TSR_EINVAL, "address too long: %s", node);
        return TSR_OK;
    }
    const char *colon = strrchr(node, ':');
    if (!strncmp(node, "tcp://", 6) && colon && colon > node + 5) {
        char *end;
        long port = strtol(colon + 1, &end, 10);
        if (*end || port <= 0 || port >= 65535)
            return tsr_error_set(err, TSR_EINVAL, "cannot derive an exchange address from %s (give exchange=)", node);
        long to = display_rank ? port + display_rank : port + 1;
        if (to >= 65536)
            return tsr_error_set(err, TSR_EINVAL, "cannot derive an exchange address from %s (give exchange=)", node);
        if ((size_t)snprintf(out, size, "%.*s:%ld", (int)(colon - node), node, to) >= size)
            return tsr_error_set(err, TSR_EINVAL, "address too long: %s", node);
        return TSR_OK;
    }
    return tsr_error_set(err, TSR_EINVAL, "cannot derive an exchange address from %s (give exchange=)", node);
}

/* Each direction's shared-memory ring (unix: peers) holds what the
 * schedule sends on one connection in one frame, each message at its
 * largest (tsr_composite_message_max_size of its region), and no more: the
 * peers release every message of a frame before its barrier, and each
 * frame starts with the rings empty (await_releases), so the frame's
 * messages go at the ring's start, one after the other, and always fit
 * without waiting for a partner's progress. A bigger ring would only let
 * a sender that has not yet heard of its partner's release write the next
 * frame behind the last one: pages resident in both processes, in every
 * ring (direct send at 8 peers: 7 pieces out and 7 in). The participants
 * are positions in the compositing order (alpha mode may map them to any
 * ranks), so the ring takes the busiest pair of positions, and the
 * display's pieces (when the display composites, they travel to rank 0)
 * on top (tsr_composite_schedule_link_bytes). BINARYSWAP_RING_SPARE is room for the
 * small messages beside the images (the mesh's hello, alpha mode's box
 * distances) and for netlib rounding each ring message up to 64 bytes (a
 * link carries a few messages a frame: at most one per round and the
 * final piece). The rings are made at the first frame; after the window
 * grows, a message larger than its ring goes through the socket. */
#define BINARYSWAP_RING_SPARE ((uint64_t)64 << 10)

static uint64_t ring_bytes(const binaryswap_spu *b)
{
    int depth = b->mode == TSR_COMPOSITE_DEPTH ? TSR_COMPOSITE_DEPTH32F : TSR_COMPOSITE_NODEPTH;
    uint64_t page = (uint64_t)sysconf(_SC_PAGESIZE);
    uint64_t want = tsr_composite_schedule_link_bytes(&b->plan, b->colour, depth, b->codec) + BINARYSWAP_RING_SPARE;
    want = (want + page - 1) / page * page;
    return want > ((uint64_t)16 << 30) ? (uint64_t)16 << 30 : want;
}

void binaryswap_link_peers(binaryswap_spu *b, int W, int H)
{
    if (b->linked)
        return;
    b->linked = true;
    if (b->nranks == 1)
        return;
    tsr_error err = {0};
    char node_name[64];
    snprintf(node_name, sizeof node_name, "binaryswap-rank-%d", b->rank);
    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.node_name = node_name;
    cfg.token = tsr_options_string(b->options, "token");
    cfg.max_message_bytes = (uint64_t)1 << 31;
    binaryswap_plan(b, W, H); /* the rings are sized for what its schedule sends */
    cfg.shm_ring_bytes = tsr_options_bool(b->options, "shm") ? ring_bytes(b) : 0;
    cfg.shm_drop_released = tsr_options_bool(b->options, "shm_drop");
    if (b->timeout_ms > 0) {
        cfg.idle_timeout_ms = (uint32_t)b->timeout_ms;
        cfg.connect_timeout_ms = cfg.handshake_timeout_ms = (uint32_t)b->timeout_ms;
    }
    if (!(b->net = tsr_net_create(&cfg, &err)))
        binaryswap_fatal(b, "%s", err.message);
    if (!(b->listener = tsr_net_listen(b->net, binaryswap_peer_address(b, b->rank), &err))) {
        binaryswap_fatal(b, "rank %d cannot listen for its peers: %s", b->rank, err.message);
    }
    /* Peers reach their first frame at different times (start-up, their
     * share's first draw): the mesh has its own, longer limit. */
    int link_ms = (int)tsr_options_int(b->options, "link_timeout_ms");
    int64_t deadline = now_ms() + link_ms;
    for (int i = 0; i < b->rank; i++) {
        for (;;) {
            /* A Unix socket that is not there yet would be one more logged
             * refusal per try: wait for the file instead. */
            const char *a = binaryswap_peer_address(b, i);
            struct stat st;
            if (!strncmp(a, "unix:", 5) && stat(a + 5, &st) != 0 && now_ms() < deadline) {
                usleep(10000);
                continue;
            }
            b->conns[i] = tsr_net_connect(b->net, binaryswap_peer_address(b, i), &err);
            if (b->conns[i] || now_ms() >= deadline)
                break;
            usleep(20000); /* that peer does not listen yet */
        }
        if (!b->conns[i]) {
            binaryswap_fatal(b, "peer rank %d (%s) cannot be reached: %s", i, binaryswap_peer_address(b, i),
                             err.message);
        }
        int32_t me[3] = {b->rank, W, H};
        if (tsr_net_send(b->conns[i], BINARYSWAP_KIND_HELLO, me, sizeof me, b->timeout_ms, &err) != TSR_OK) {
            binaryswap_fatal(b, "peer rank %d (%s): %s", i, binaryswap_peer_address(b, i), err.message);
        }
    }
    for (int n = b->rank + 1; n < b->nranks; n++) {
        int64_t left = deadline - now_ms();
        tsr_net_conn *c = tsr_net_accept(b->listener, left > 0 ? (int)left : 1, &err);
        if (!c) {
            int missing = -1;
            for (int k = b->rank + 1; k < b->nranks && missing < 0; k++)
                if (!b->conns[k])
                    missing = k;
            binaryswap_fatal(b, "peer rank %d (%s) did not connect within %d ms (link_timeout_ms): %s", missing,
                             binaryswap_peer_address(b, missing), link_ms, err.message);
        }
        tsr_net_msg msg;
        int32_t hello[3] = {-1, 0, 0}, who = -1;
        int rc = tsr_net_recv(c, &msg, b->timeout_ms > 0 ? b->timeout_ms : TSR_NET_WAIT_FOREVER, &err);
        if (rc == 1) {
            if (msg.kind == BINARYSWAP_KIND_HELLO && msg.len == sizeof hello)
                memcpy(hello, msg.data, sizeof hello);
            tsr_net_msg_release(&msg);
        }
        who = hello[0];
        if (who <= b->rank || who >= b->nranks || b->conns[who]) {
            binaryswap_fatal(b, "a peer at %s did not say which rank it is (or said %d)", tsr_net_conn_address(c), who);
        }
        b->conns[who] = c;
        if (hello[1] != W || hello[2] != H)
            binaryswap_fatal(
                b, "frame 0: peer rank %d (%s) draws a %" PRId32 "x%" PRId32 " window, not %dx%d (window sizes differ)",
                who, binaryswap_peer_address(b, who), hello[1], hello[2], W, H);
    }
    tsr_log(TSR_LOG_DEBUG, "%s: rank %d of %d linked to its peers", b->name, b->rank, b->nranks);
    b->meshed = true;
    for (int i = 0; i < b->nranks; i++)
        if (b->conns[i])
            tsr_log(TSR_LOG_INFO, "%s: transport rank %d <-> rank %d (%s): %s", b->name, b->rank, i,
                    binaryswap_peer_address(b, i), tsr_net_conn_transport(b->conns[i]));
}

void binaryswap_release_held(binaryswap_spu *b)
{
    if (b->holding)
        tsr_net_msg_release(&b->held);
    b->holding = false;
    free(b->local_given);
    b->local_given = NULL;
}

/* The line a peer ended on (binaryswap_fatal sends it to every other peer),
 * from `msg`, or else from what `peer` sent before its link failed (looked
 * through without waiting); false when there is none. */
static bool last_word(binaryswap_spu *b, int peer, const tsr_net_msg *msg, char *out, size_t size)
{
    if (msg && msg->kind == BINARYSWAP_KIND_ENDING) {
        tsr_text_sanitize(out, size, msg->data, (size_t)msg->len);
        return true;
    }
    if (peer < 0 || peer >= b->nranks || !b->conns[peer])
        return false;
    tsr_net_msg m;
    tsr_error ignored = {0};
    while (tsr_net_recv(b->conns[peer], &m, 0, &ignored) == 1) {
        bool ending = m.kind == BINARYSWAP_KIND_ENDING;
        if (ending)
            tsr_text_sanitize(out, size, m.data, (size_t)m.len);
        tsr_net_msg_release(&m);
        if (ending)
            return true;
    }
    return false;
}

/* True with *err set when `peer` ended on a fault of its own and said
 * so (in `msg`, or before its link failed): the fault comes first, then
 * who passed it on. */
static bool peer_ended_on(binaryswap_spu *b, int peer, const tsr_net_msg *msg, tsr_error *err)
{
    char said[sizeof err->message / 2];
    if (!last_word(b, peer, msg, said, sizeof said))
        return false;
    /* its frame is this one's: the caller names it once */
    const char *fault = said;
    unsigned frame;
    int at = 0;
    if (sscanf(said, "frame %u: %n", &frame, &at) == 1 && at > 0)
        fault += at;
    tsr_error_set(err, TSR_EIO, "%s (said peer rank %d (%s), which ended on it)", fault, peer,
                  binaryswap_peer_address(b, peer));
    return true;
}

/* A failure on the link to `peer` (`what`: how it showed here), unless
 * `peer` ended on a fault of its own (peer_ended_on). */
static int peer_failed(binaryswap_spu *b, int peer, int code, const tsr_net_msg *msg, const char *what, tsr_error *err)
{
    if (peer_ended_on(b, peer, msg, err))
        return err->code;
    return tsr_error_set(err, code ? code : TSR_EIO, "peer rank %d (%s): %s", peer, binaryswap_peer_address(b, peer),
                         what);
}

/* Where the executor encodes its next message to `to`: shared memory the
 * peer maps (netlib's ring on unix: peers; elsewhere a buffer netlib
 * sends from), or the local message itself for rank 0's own display. */
void *binaryswap_transport_send_buffer(void *user, int to, size_t max_size, tsr_error *err)
{
    binaryswap_spu *b = user;
    if (to == b->nranks && b->rank == 0) {
        free(b->local_building);
        if (!(b->local_building = malloc(sizeof *b->local_building + max_size))) {
            tsr_error_set(err, TSR_ENOMEM, "out of memory for a %zu-byte image", max_size);
            return NULL;
        }
        return b->local_building->data;
    }
    /* `to` is a position in the compositing order, as in binaryswap_transport_send */
    int peer = to == b->nranks ? 0 : to >= 0 && to < b->nranks ? b->view[to] : -1;
    if (peer < 0 || peer >= b->nranks || !b->conns[peer]) {
        tsr_error_set(err, TSR_EINVAL, "no connection to participant %d", to);
        return NULL;
    }
    tsr_error e = {0};
    int rc = tsr_net_send_reserve(b->conns[peer], max_size, &b->reserved,
                                  b->timeout_ms > 0 ? b->timeout_ms : TSR_NET_WAIT_FOREVER, &e);
    if (rc != TSR_OK) {
        peer_failed(b, peer, rc, NULL, rc == TSR_ETIMEDOUT ? "took no image within timeout_ms" : e.message, err);
        return NULL;
    }
    return b->reserved;
}

/* Participant `to`: a peer rank over its connection, or the display
 * participant (nranks), which lives in rank 0's process. */
int binaryswap_transport_send(void *user, int to, const void *data, size_t size, tsr_error *err)
{
    binaryswap_spu *b = user;
    if (to == b->nranks && b->rank == 0) {
        local_msg *m = b->local_building;
        if (m && data == m->data) {
            b->local_building = NULL; /* encoded in place */
        } else if (!(m = malloc(sizeof *m + size))) {
            return tsr_error_set(err, TSR_ENOMEM, "out of memory for a %zu-byte image", size);
        } else {
            memcpy(m->data, data, size);
        }
        m->next = NULL;
        m->size = size;
        if (b->local_tail)
            b->local_tail->next = m;
        else
            b->local_head = m;
        b->local_tail = m;
        return TSR_OK;
    }
    int peer = to == b->nranks ? 0 : to >= 0 && to < b->nranks ? b->view[to] : -1;
    if (peer < 0 || peer >= b->nranks || !b->conns[peer])
        return tsr_error_set(err, TSR_EINVAL, "no connection to participant %d", to);
    tsr_error e = {0};
    int wait = b->timeout_ms > 0 ? b->timeout_ms : TSR_NET_WAIT_FOREVER;
    bool in_place = b->reserved && data == b->reserved;
    b->reserved = NULL;
    int rc = in_place ? tsr_net_send_commit(b->conns[peer], BINARYSWAP_KIND_IMAGE, size, wait, &e)
                      : tsr_net_send(b->conns[peer], BINARYSWAP_KIND_IMAGE, data, size, wait, &e);
    if (rc != TSR_OK)
        return peer_failed(b, peer, rc, NULL, rc == TSR_ETIMEDOUT ? "took no image within timeout_ms" : e.message, err);
    b->last_bytes += size;
    return TSR_OK;
}

int binaryswap_transport_recv(void *user, int from, const void **data, size_t *size, tsr_error *err)
{
    binaryswap_spu *b = user;
    binaryswap_release_held(b);
    if (from >= 0 && from < b->nranks)
        from = b->view[from]; /* a position in the compositing order: its rank */
    if (from == b->rank) {
        local_msg *m = b->local_head;
        if (!m)
            return tsr_error_set(err, TSR_EPROTO, "rank %d waits for an image from itself that was never sent",
                                 b->rank);
        b->local_head = m->next;
        if (!b->local_head)
            b->local_tail = NULL;
        b->local_given = m;
        *data = m->data;
        *size = m->size;
        return TSR_OK;
    }
    if (from < 0 || from >= b->nranks || !b->conns[from])
        return tsr_error_set(err, TSR_EINVAL, "no connection to participant %d", from);
    tsr_error e = {0};
    int rc = tsr_net_recv(b->conns[from], &b->held, b->timeout_ms > 0 ? b->timeout_ms : TSR_NET_WAIT_FOREVER, &e);
    if (rc != 1)
        return peer_failed(b, from, rc == 0 ? TSR_EIO : rc, NULL,
                           rc == 0               ? "ended before sending its image"
                           : rc == TSR_ETIMEDOUT ? "sent no image within timeout_ms"
                                                 : e.message,
                           err);
    b->holding = true;
    if (b->held.kind == BINARYSWAP_KIND_ENDING)
        return peer_failed(b, from, TSR_EIO, &b->held, "", err);
    if (b->held.kind != BINARYSWAP_KIND_IMAGE)
        return tsr_error_set(err, TSR_EPROTO, "peer rank %d (%s): a message of kind %u, not an image", from,
                             binaryswap_peer_address(b, from), b->held.kind);
    *data = b->held.data;
    *size = (size_t)b->held.len;
    return TSR_OK;
}

/* Every peer released the last frame's messages before the display's
 * barrier, so what a connection still counts as out is a CREDIT on its
 * way: waiting for it here (no peer's progress is needed) starts this
 * frame's messages at their rings' start (ring_bytes), on the pages the
 * last frame used. */
void binaryswap_await_releases(binaryswap_spu *b, uint32_t frame)
{
    if (!b->composited)
        return;
    for (int i = 0; i < b->nranks; i++) {
        tsr_error err = {0}, why = {0};
        if (i != b->rank && b->conns[i] &&
            tsr_net_conn_wait_returned(b->conns[i], b->timeout_ms > 0 ? b->timeout_ms : TSR_NET_WAIT_FOREVER, &err) !=
                TSR_OK) {
            peer_failed(b, i, err.code, NULL, err.message, &why);
            binaryswap_fatal(b, "frame %" PRIu32 ": %s", frame, why.message);
        }
    }
    b->composited = false;
}

/* Alpha mode with boxes: this frame's view order (layers.h). Every peer
 * sends every other its box's distance, then reads theirs: a few bytes
 * on each connection, before the frame's images. */
void binaryswap_exchange_order(binaryswap_spu *b, uint32_t frame)
{
    float mv[16], dist[BINARYSWAP_MAX_PEERS];
    tsr_call_GetFloatv(b->table, GL_MODELVIEW_MATRIX, mv);
    dist[b->rank] = binaryswap_box_distance(b->box, mv);
    uint32_t bits;
    memcpy(&bits, &dist[b->rank], 4);
    uint8_t msg8[8];
    for (int i = 0; i < 4; i++) {
        msg8[i] = (uint8_t)(frame >> (8 * i));
        msg8[4 + i] = (uint8_t)(bits >> (8 * i));
    }
    int wait = b->timeout_ms > 0 ? b->timeout_ms : TSR_NET_WAIT_FOREVER;
    tsr_error err = {0};
    for (int r = 0; r < b->nranks; r++)
        if (r != b->rank && tsr_net_send(b->conns[r], BINARYSWAP_KIND_ORDER, msg8, sizeof msg8, wait, &err) != TSR_OK) {
            tsr_error why = {0};
            peer_failed(b, r, err.code, NULL, err.message, &why);
            binaryswap_fatal(b, "frame %" PRIu32 ": %s", frame, why.message);
        }
    for (int r = 0; r < b->nranks; r++) {
        if (r == b->rank)
            continue;
        tsr_net_msg msg;
        int rc = tsr_net_recv(b->conns[r], &msg, wait, &err);
        bool ok = false;
        uint32_t their_frame = 0, their_bits = 0;
        tsr_error why = {0};
        if ((rc != 1 || msg.kind == BINARYSWAP_KIND_ENDING) && peer_ended_on(b, r, rc == 1 ? &msg : NULL, &why))
            binaryswap_fatal(b, "frame %" PRIu32 ": %s", frame, why.message);
        if (rc == 1) {
            if (msg.kind == BINARYSWAP_KIND_ORDER && msg.len == 8) {
                const uint8_t *m = msg.data;
                for (int i = 0; i < 4; i++) {
                    their_frame |= (uint32_t)m[i] << (8 * i);
                    their_bits |= (uint32_t)m[4 + i] << (8 * i);
                }
                memcpy(&dist[r], &their_bits, 4);
                ok = their_frame == frame && dist[r] == dist[r];
            }
            tsr_net_msg_release(&msg);
        }
        if (!ok)
            binaryswap_fatal(b, "frame %" PRIu32 ": peer rank %d (%s) %s", frame, r, binaryswap_peer_address(b, r),
                             rc == 1   ? "sent no box distance for this frame (does every peer have a box?)"
                             : rc == 0 ? "ended before sending its box distance"
                                       : "sent no box distance within timeout_ms");
    }
    binaryswap_order_by_distance(dist, b->nranks, b->view, b->pos);
    tsr_log(TSR_LOG_DEBUG, "%s: frame %" PRIu32 ": rank %d is at position %d of the view order (distance %g)", b->name,
            frame, b->rank, b->pos[b->rank], (double)dist[b->rank]);
}
