/* netlib/net_internal.h — structures shared by netlib's files.
 * Owns: the layout of tsr_net, connections, listeners and queued messages,
 * and the locking rule: every field marked (L) is read and written only
 * with net->lock held; fields marked (IO) only on the I/O thread.
 * Never: included outside netlib/. */
#ifndef TESSERA_NETLIB_NET_INTERNAL_H
#define TESSERA_NETLIB_NET_INTERNAL_H

#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>
#include <sys/socket.h>
#include <sys/types.h>
#include <sys/un.h>
#include <uv.h>

#include "tessera/dev/net.h"

#define NET_CONTROL_MAX 4096      /* largest control payload accepted */
#define NET_STAGING_BYTES 65536   /* per-connection socket read buffer */
#define NET_READY_MAX 64          /* handshaken, not yet accepted, per listener */
#define NET_HALF_OPEN_MAX 256     /* connections in their handshake, per listener */
#define NET_HALF_OPEN_PER_HOST 16 /* ... of them from one peer address */
#define NET_SILENT_MS 1000        /* a connection that sent nothing this long is closed */
#define NET_AUTH_BYTES 32         /* nonce and proof sizes */
#define NET_SPARE_MAX 8           /* released receive buffers kept per connection */

enum net_wire_type {
    NET_HELLO = 0x01,
    NET_WELCOME = 0x02,
    NET_REFUSE = 0x03,
    NET_CREDIT = 0x04,
    NET_PING = 0x05,
    NET_BYE = 0x06,
    NET_CHALLENGE = 0x07,
    NET_PROOF = 0x08,
    NET_RING = 0x09, /* shared-memory ring handed over (shm.c) */
};
#define NET_FLAG_SHM 0x01     /* header flag: the payload is a ring descriptor */
#define NET_FEATURE_SHM 0x01  /* HELLO/WELCOME features bit */
#define NET_SHM_DESC_BYTES 16 /* u64 position, u64 length */
#define NET_SHM_SLOT_ALIGN 64 /* ring messages start on cache lines */
#define NET_SHM_RING_MIN (64u << 10)
#define NET_SHM_RING_MAX ((uint64_t)16 << 30)


/* Payload buffers kept for reuse (newest last). */
typedef struct net_spares {
    uint8_t *buf[NET_SPARE_MAX];
    uint64_t cap[NET_SPARE_MAX];
    unsigned count;
} net_spares;

/* One message in an outbox (to write) or an inbox (received). */
typedef struct net_msg {
    struct net_msg *next;
    struct tsr_net_conn *conn; /* for release: whose credit it is */
    uint8_t type;
    uint8_t flags; /* header flags (NET_FLAG_SHM: data is a ring descriptor) */
    uint64_t len;
    uint8_t *data;
    uint64_t cap;                           /* bytes allocated at data (received messages) */
    void (*release)(void *data, void *ctx); /* NULL = free() */
    void *release_ctx;
    uint64_t written;           /* bytes of header + payload already on the socket (direct.c) */
    bool borrowed;              /* data is the sender's memory, valid only during tsr_net_send */
    bool copy;                  /* data is tsr_net_send's copy, counted in send_copies (cap set) */
    struct net_ring_slot *slot; /* received through the ring: its place there (shm.c) */
    uint8_t header[TSR_NET_HEADER_BYTES];
    uv_write_t write_req;
} net_msg;

typedef struct net_hello {
    uint32_t credits;
    uint64_t max_message_bytes;
    char name[TSR_NET_PEER_NAME_MAX + 1]; /* escaped: printed in every line naming the peer */
    bool has_auth;                        /* HELLO: the peer has a token; WELCOME: it proved it */
    uint8_t auth[NET_AUTH_BYTES];         /* HELLO: the client's nonce; WELCOME: the server's proof */
    uint8_t features;                     /* NET_FEATURE_*: asked for (HELLO), granted (WELCOME) */
} net_hello;

/* A message received through the peer's ring, oldest first: ring space
 * returns in arrival order, up to the oldest one not released. */
typedef struct net_ring_slot {
    struct net_ring_slot *next;
    uint64_t start, end; /* ring positions of it and after it */
    bool released;
} net_ring_slot;

/* One direction's ring (shm.c). Positions only grow; offset = pos % size. */
typedef struct net_ring {
    uint8_t *map;
    uint64_t size;
    uint64_t head;      /* send: end of the last committed message; receive: expected next */
    uint64_t tail;      /* send: released up to here (the peer's CREDIT); receive: the same, ours to tell */
    bool reserved;      /* send: a reservation not yet committed */
    bool reserved_ring; /* ... in the ring (else in reserve_buf) */
    uint64_t reserved_pos, reserved_len;
    net_ring_slot *slots_head, *slots_tail; /* receive */
} net_ring;

typedef enum net_conn_state {
    NET_CONNECTING, /* socket connect in progress (client) */
    NET_HANDSHAKE,  /* waiting for HELLO (server) or WELCOME (client) */
    NET_OPEN,
    NET_FAILED, /* error recorded; no more traffic */
    NET_ENDED,  /* peer closed cleanly */
} net_conn_state;

struct tsr_net_conn {
    tsr_net *net;
    tsr_net_transport transport;
    bool is_server;
    char address[TSR_NET_ADDRESS_MAX];         /* the peer's address, for messages */
    char peer_name[TSR_NET_PEER_NAME_MAX + 1]; /* escaped (net_hello.name) */
    pthread_cond_t cond;                       /* (L) any change an app thread may wait for */

    /* lifetime (L): freed when nobody holds it */
    bool app_ref;  /* the application (or a listener's queue) holds it */
    bool io_ref;   /* the I/O thread still has handles open */
    unsigned held; /* received messages not yet released */

    net_conn_state state;  /* (L) */
    tsr_error error;       /* (L) set once state is NET_FAILED */
    bool close_requested;  /* (L) app closed; I/O thread winds down */
    bool socket_connected; /* (L) the transport connected (handshake may still fail) */
    bool handshaken;       /* (L) the handshake succeeded (the state may have moved on) */
    bool went_silent;      /* (L) failed because the peer sent nothing for idle_timeout_ms */
    bool vanished;         /* (L) failed because the peer's end closed or reset without a goodbye */
    /* (L) A write to a Unix socket met EPIPE/ECONNRESET: the peer closed,
     * but what it sent before is still in our receive buffer. Nothing more
     * is written; the connection fails (or ends) when the reading side
     * reaches the peer's end of stream, after delivering all of it. */
    bool peer_stopped_reading;
    unsigned flush_waiters; /* (L) threads in tsr_net_conn_flush */

    /* send side (L) */
    uint32_t send_credits;
    uint32_t peer_window; /* credits the peer granted in its handshake */
    uint64_t peer_max_message;
    net_msg *outbox_head, *outbox_tail; /* accepted, not yet given to libuv */
    uint32_t writes_in_flight;          /* given to libuv (or being given), not completed */
    /* Direct writes (direct.c): an application thread may write a message
     * to the socket itself, without the lock, when nothing else is queued
     * or in libuv's hands. While direct_writer is set the I/O thread writes
     * nothing, shuts nothing down and closes nothing on this connection (it
     * waits on `cond`: the direct write never blocks). What the socket did
     * not take is left in direct_rest, which the I/O thread writes before
     * anything else. fd is the socket's descriptor while it is open, else -1. */
    bool direct_writer;
    bool direct_awaited; /* the I/O thread waits for the direct writer */
    net_msg *direct_rest;
    int fd;
    int rcvlowat;          /* (IO) SO_RCVLOWAT set on fd (0 = the kernel's default, 1) */
    int lowat_queued;      /* (IO) bytes queued below it when the idle timer last looked */
    uint32_t send_waiters; /* threads blocked for credits */

    /* receive side (L) */
    net_msg *inbox_head, *inbox_tail;
    uint32_t inbox_count;
    uint32_t credits_to_return; /* released by the app, not yet granted */
    /* Payload buffers of released large messages, reused for the next ones
     * (L): fresh multi-megabyte allocations come from mmap and cost a page
     * fault per 4 KiB on first touch, which halved stream throughput. At
     * most NET_SPARE_MAX, so memory stays within the credit bound. */
    net_spares spares;
    /* The same for the copies tsr_net_send makes of messages that must
     * wait in the queue (L): send_copies are queued or being written,
     * send_spares written and kept; together at most peer_window. */
    net_spares send_spares;
    unsigned send_copies;

    tsr_net_stats stats; /* (L) */

    /* I/O-thread bookkeeping (L: the dirty list links) */
    bool dirty;
    struct tsr_net_conn *next_dirty;
    struct tsr_net_conn *next_all, *prev_all;
    struct tsr_net_listener *listener; /* server side until accepted */
    struct tsr_net_conn *next_ready;
    bool ready;             /* (L) in listener->ready queue */
    uint16_t hello_version; /* (IO) version of the peer's HELLO header */
    /* (IO) the handshake's challenge-response (net.h, HANDSHAKE): step 0
     * before the CHALLENGE, 1 after it (client: PROOF sent; server: PROOF
     * awaited, the peer's HELLO kept in peer_hello) */
    unsigned auth_step;
    uint8_t client_nonce[NET_AUTH_BYTES], server_nonce[NET_AUTH_BYTES];
    struct net_hello peer_hello;
    bool heard_any; /* (IO) server: the peer sent at least one byte */
    /* (L) server side, while the handshake is not done: in its listener's
     * half-open list, oldest first (the one dropped when a newer one
     * needs its place) */
    bool half_listed;
    struct tsr_net_conn *half_prev, *half_next;
    struct tsr_net_conn *inproc_peer; /* (L) */

    /* shared memory (shm.c, L): negotiated in the handshake; tx is this
     * side's ring (mapped at the handshake), rx the peer's (mapped when its
     * RING arrives) */
    bool shm;
    net_ring tx, rx;
    uint8_t *reserve_buf; /* tsr_net_send_reserve's buffer when not in the ring */
    uint64_t reserve_cap;

    /* (IO) socket state */
    union {
        uv_handle_t handle;
        uv_stream_t stream;
        uv_tcp_t tcp;
        uv_pipe_t pipe;
    } h;
    uv_timer_t timer;      /* connect/handshake deadline, then idle pings */
    unsigned handles_open; /* handles whose close callback has not run */
    bool handles_closing, reading, shutting_down, write_side_shut, saw_eof, peer_said_bye;
    uv_connect_t connect_req;
    uv_shutdown_t shutdown_req;
    uint64_t last_heard_ms, last_written_ms;
    uint8_t hdr[TSR_NET_HEADER_BYTES];
    size_t hdr_fill;
    net_msg *partial; /* message whose payload is being read */
    uint64_t partial_fill;
    uint8_t *staging;
};

struct tsr_net_listener {
    tsr_net *net;
    tsr_net_transport transport;
    char address[TSR_NET_ADDRESS_MAX];
    char unix_path[sizeof(((struct sockaddr_un *)0)->sun_path)]; /* bound by this listener */
    dev_t unix_dev;                                              /* ... and its identity, so that only */
    ino_t unix_ino;                                              /*     that socket is removed */
    char inproc_name[TSR_NET_ADDRESS_MAX - 8];
    pthread_cond_t cond;                   /* (L) accept waits on it */
    tsr_net_conn *ready_head, *ready_tail; /* (L) handshaken, not accepted */
    unsigned pending;                      /* (L) handshaking + ready */
    tsr_net_conn *half_head, *half_tail;   /* (L) in their handshake, oldest first */
    unsigned half_open;                    /* (L) ... how many */
    unsigned dropped;                      /* (L) closed before completing a handshake */
    unsigned refusals;                     /* (L) */
    tsr_error last_refusal;                /* (L) */
    bool app_ref, io_ref, closing;         /* (L) */
    struct tsr_net_listener *next;         /* (L) net->listeners */
    union {
        uv_handle_t handle;
        uv_stream_t stream;
        uv_tcp_t tcp;
        uv_pipe_t pipe;
    } h; /* (IO) */
};

/* Work an application thread hands to the I/O thread and waits for. */
typedef enum net_op_kind { NET_OP_LISTEN, NET_OP_CONNECT, NET_OP_CLOSE_LISTENER } net_op_kind;
typedef struct net_op {
    net_op_kind kind;
    void *target;
    const tsr_net_address *address;
    struct sockaddr_storage sockaddr; /* resolved tcp address */
    bool done;
    int rc;
    tsr_error err;
    struct net_op *next;
} net_op;

struct tsr_net {
    tsr_net_config config;
    char node_name[TSR_NET_NAME_MAX + 1];
    char token[TSR_NET_TOKEN_MAX + 1];
    pthread_mutex_t lock;
    pthread_cond_t op_cond;  /* (L) op completion */
    pthread_cond_t any_cond; /* (L) some connection changed (tsr_net_recv_any) */
    unsigned any_waiters;    /* (L) threads in tsr_net_recv_any */
    uv_loop_t loop;
    uv_async_t wakeup;
    pthread_t thread;
    bool stopping;               /* (L) destroy called */
    net_op *ops_head, *ops_tail; /* (L) */
    tsr_net_conn *dirty_head;    /* (L) */
    tsr_net_conn *conns;         /* (L) every live connection */
    tsr_net_listener *listeners; /* (L) */
};

/* address.c */
void net_address_format_sockaddr(const struct sockaddr *sa, tsr_net_transport t, char *out, size_t size);

/* frame.c: header and handshake encoding */
void net_header_encode(uint8_t out[TSR_NET_HEADER_BYTES], uint16_t version, uint8_t type, uint8_t flags, uint64_t len);
typedef struct net_header {
    uint32_t magic;
    uint16_t version;
    uint8_t type, flags;
    uint64_t len;
} net_header;
void net_header_decode(const uint8_t in[TSR_NET_HEADER_BYTES], net_header *out);
/* Returns the payload size written into out (at most NET_CONTROL_MAX);
 * `auth` NULL = no authentication field (mode 0). */
size_t net_hello_encode(uint8_t *out, uint32_t credits, uint64_t max_message_bytes, const char *name,
                        const uint8_t *auth, uint8_t features);
int net_hello_decode(const uint8_t *in, uint64_t len, net_hello *out, tsr_error *err);
/* CHALLENGE (a nonce) and PROOF (an HMAC): exactly NET_AUTH_BYTES. `what`
 * names the message in the error. */
int net_auth_decode(const uint8_t *in, uint64_t len, uint8_t out[NET_AUTH_BYTES], const char *what, tsr_error *err);

/* auth.c: the challenge-response (libsodium) */
int net_auth_init(tsr_error *err);                /* once per process; thread-safe */
void net_auth_nonce(uint8_t out[NET_AUTH_BYTES]); /* fresh random bytes */
/* HMAC-SHA256 keyed with the token over the role ("client" or "server")
 * and both nonces, so a proof is valid for one connection and one
 * direction only. */
void net_auth_proof(const char *token, const char *role, const uint8_t client_nonce[NET_AUTH_BYTES],
                    const uint8_t server_nonce[NET_AUTH_BYTES], uint8_t out[NET_AUTH_BYTES]);
bool net_auth_equal(const uint8_t a[NET_AUTH_BYTES], const uint8_t b[NET_AUTH_BYTES]); /* constant time */
static inline void net_put_u16(uint8_t *p, uint16_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
}
static inline void net_put_u32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}
static inline void net_put_u64(uint8_t *p, uint64_t v)
{
    for (int i = 0; i < 8; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}
static inline uint16_t net_get_u16(const uint8_t *p) { return (uint16_t)(p[0] | p[1] << 8); }
static inline uint32_t net_get_u32(const uint8_t *p)
{
    uint32_t v = 0;
    for (int i = 3; i >= 0; i--)
        v = v << 8 | p[i];
    return v;
}
static inline uint64_t net_get_u64(const uint8_t *p)
{
    uint64_t v = 0;
    for (int i = 7; i >= 0; i--)
        v = v << 8 | p[i];
    return v;
}

/* loop.c */
void net_wake(tsr_net *net);                 /* (L) nudge the I/O thread */
void net_mark_dirty(tsr_net_conn *conn);     /* (L) + wake */
int net_submit_op(tsr_net *net, net_op *op); /* (L held) waits for completion */
uint64_t net_now_ms(void);
void net_cond_init(pthread_cond_t *cond);              /* waits use CLOCK_MONOTONIC */
void net_io_maybe_finish(tsr_net *net);                /* (IO, L) close the loop when idle */
int net_deadline(struct timespec *ts, int timeout_ms); /* 0 = no deadline */

/* conn.c */
tsr_net_conn *net_conn_new(tsr_net *net, tsr_net_transport t, bool is_server, const char *address);
void net_conn_maybe_free(tsr_net_conn *conn); /* (L) */
void net_conn_signal(tsr_net_conn *conn);     /* (L) wake its waiters */
/* (L) A failed write to a Unix socket whose peer has closed (EPIPE,
 * ECONNRESET): marks peer_stopped_reading and returns true, so the caller
 * does not fail the connection before its data is read. */
bool net_write_met_closed_peer(tsr_net_conn *c, int uv_status);
void net_conn_fail(tsr_net_conn *conn, int code, const char *fmt, ...) __attribute__((format(printf, 3, 4))); /* (L) */
void net_msg_free(net_msg *m);
/* (L) A payload buffer of at least `len` bytes for a message from `c`: a
 * spare one when it fits (and is not more than twice too big), else a new
 * one; sets *cap to its size. NULL when out of memory. */
uint8_t *net_payload_alloc(tsr_net_conn *c, uint64_t len, uint64_t *cap);
uint16_t net_version(const tsr_net *net);
/* (L) A payload buffer for a copy tsr_net_send queues (a send spare or a
 * new one); and, once written, keeps it for reuse within the bound. */
uint8_t *net_send_copy_alloc(tsr_net_conn *c, uint64_t len, uint64_t *cap);
void net_send_copy_done(tsr_net_conn *c, net_msg *m);

/* socket.c: runs on the I/O thread, net->lock held */
void net_io_listen(tsr_net *net, net_op *op);
void net_io_connect(tsr_net *net, net_op *op);
void net_io_close_listener(tsr_net_listener *l);
void net_io_service(tsr_net_conn *conn); /* act on dirty state */
void net_io_stop(tsr_net *net);          /* destroy: close everything */

/* direct.c: application threads, net->lock held on entry and on return */
bool net_direct_possible(const tsr_net_conn *conn);
/* Writes m (header encoded here) from the calling thread when
 * net_direct_possible(); the lock is dropped during the system call. Takes
 * m: returns it when it was written whole (free it after unlocking), or
 * NULL when the rest was left in direct_rest for the I/O thread. */
net_msg *net_direct_write(tsr_net_conn *conn, net_msg *m);
/* (I/O thread) Waits until no application thread writes on conn. */
void net_direct_await(tsr_net_conn *conn);

/* shm.c: the shared-memory rings (net.h, SHARED MEMORY); net->lock held */
uint64_t net_shm_slot(uint64_t len); /* ring bytes a message of len takes */
/* (IO) After the handshake of a shared-memory connection: create, map and
 * hand over this side's ring (a RING message with the memfd attached).
 * On failure the connection goes on without it (data inline), logged. */
void net_shm_start(tsr_net_conn *c);
/* (IO) A RING message arrived (its descriptor is pending on the pipe):
 * check and map the peer's ring. Fails the connection when it lies. */
int net_shm_ring_received(tsr_net_conn *c, const net_msg *m); /* 0, or -1: failed */
/* (IO) Fails the connection if the peer passed descriptors out of place;
 * called after each read. */
int net_shm_check_stray_fds(tsr_net_conn *c); /* 0, or -1: failed */
/* (IO) A data message whose payload is a ring descriptor: points m at the
 * ring data (0) or fails the connection naming the peer (-1). */
int net_shm_take_descriptor(tsr_net_conn *c, net_msg *m);
/* A ring message released by the application: its space returns once
 * every older one is released. */
/* Before a held ring message is released, without the lock: with
 * shm_drop_released, drops this side's mapping of its pages. */
void net_shm_drop_read(tsr_net_conn *c, net_msg *m);
void net_shm_release(tsr_net_conn *c, net_msg *m);
/* The CREDIT payload for `count` credits: 4 bytes, or 12 with the ring
 * position on a shared-memory connection. Returns its length. */
size_t net_credit_encode(const tsr_net_conn *c, uint32_t count, uint8_t out[12]);
/* (IO) A CREDIT's ring position: checked and taken (0) or fails (-1). */
int net_shm_credit(tsr_net_conn *c, uint64_t pos);
/* (send side) Whether a message of len bytes fits in this side's ring now
 * (credits aside); *pos gets where it goes (net.h's placement rule). */
bool net_shm_fits(const tsr_net_conn *c, uint64_t len, uint64_t *pos);
void net_shm_free(tsr_net_conn *c); /* unmaps both rings (conn free) */

/* inproc.c: application threads, net->lock held */
int net_inproc_listen(tsr_net *net, const tsr_net_address *a, tsr_net_listener *l, tsr_error *err);
tsr_net_conn *net_inproc_connect(tsr_net *net, const tsr_net_address *a, tsr_error *err);
void net_inproc_deliver(tsr_net_conn *from, net_msg *m); /* send: move to peer inbox */
void net_inproc_return_credits(tsr_net_conn *conn);
void net_inproc_close(tsr_net_conn *conn);
void net_listener_maybe_free(tsr_net_listener *l);
void net_listener_unlink(tsr_net_listener *l);

#endif
