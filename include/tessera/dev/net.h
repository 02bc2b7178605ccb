/* tessera/dev/net.h — message connections over TCP, Unix-domain sockets
 * and an in-process transport, with a handshake and credit-based flow
 * control: libtessera_net (pkg-config tessera), the network under the
 * stream client (tessera/dev/client.h), the server node, the mothership
 * and SPUs that talk to their peers themselves (sort-last compositing).
 * Owns: the connection API, the netlib wire protocol (specified below) and
 * the I/O thread that runs one libuv loop per tsr_net; symbols are
 * tsr_net_*.
 * Never: exits or aborts on bad input or a bad peer, allocates what a peer
 * announces before checking it against the limit, or blocks without a bound
 * the caller chose.
 *
 * THREADS. tsr_net_create() starts one I/O thread running one libuv loop;
 * every socket lives on it. Any other thread may call the functions below
 * (one thread per connection at a time for send, one for receive); they
 * exchange messages with the I/O thread through bounded queues guarded by
 * one mutex and wake it with uv_async, or write to an idle socket
 * themselves (see SENDING). Blocking calls take a time-out in
 * milliseconds: 0 = poll, > 0 = at most that long, TSR_NET_WAIT_FOREVER =
 * until the call can complete or the connection fails (a dead or silent
 * peer is caught by idle_timeout_ms, so set it when waiting forever).
 * TSR_ETIMEDOUT from send, recv, recv_any or accept means only that the
 * caller's own time-out passed and the connection is as it was; a
 * connection that failed returns its error (a peer silent beyond
 * idle_timeout_ms: TSR_EIO), so a poll loop can tell "nothing yet" from
 * "dead".
 *
 * ADDRESSES are text:
 *   tcp://127.0.0.1:7000   tcp://[::1]:7000   tcp://host.example:7000
 *   tcp://:7000            (listen: loopback 127.0.0.1; port 0 = any free)
 *   tcp://0.0.0.0:7000     (listen on every IPv4 interface, only when asked)
 *   unix:/tmp/x.sock       (same host; only a stale socket file is replaced:
 *                          any other file there is refused, never removed)
 *   inproc:name            (same tsr_net; no sockets, same API)
 *
 * WIRE (every integer little-endian). Each message is a 16-byte header
 * followed by `length` payload bytes:
 *   offset 0  u32 magic   0x314E5354 ("TSN1" in memory order)
 *   offset 4  u16 version TSR_NET_PROTOCOL_VERSION
 *   offset 6  u8  type    0x01 HELLO, 0x02 WELCOME, 0x03 REFUSE, 0x04 CREDIT,
 *                         0x05 PING, 0x06 BYE, 0x07 CHALLENGE, 0x08 PROOF;
 *                         0x10..0xff application messages
 *   offset 7  u8  flags   0, or 0x01 on a data message of a shared-memory
 *                         connection (SHARED MEMORY below); receivers reject
 *                         anything else
 *   offset 8  u64 length  payload bytes; a data message longer than the
 *                         receiver's max_message_bytes (or a control
 *                         message longer than 4 KiB; CHALLENGE and PROOF
 *                         exactly 32) fails that connection before any
 *                         allocation.
 * HANDSHAKE. The connecting side sends HELLO; the accepting side answers
 * WELCOME or REFUSE, with a challenge-response between them when it has a
 * token. HELLO/WELCOME payload: u32 credits granted to the peer, u64
 * max_message_bytes accepted, u16 name length + node name bytes, u8 auth
 * (0 or 1), and when auth is 1 32 bytes: in HELLO the client's nonce (it
 * has a token), in WELCOME the server's proof. The token itself is never
 * sent. With a token on both sides:
 *   client -> HELLO auth=1, nonce Nc (32 fresh random bytes)
 *   server -> CHALLENGE  Ns (32 fresh random bytes)
 *   client -> PROOF      HMAC-SHA256(token, L "client\0" Nc Ns)
 *   server -> WELCOME auth=1, HMAC-SHA256(token, L "server\0" Nc Ns)
 *             (or REFUSE "token mismatch")
 * where L is "tessera-net-2 handshake proof ". Both nonces are in both
 * proofs, so a proof replayed on another connection fails (the other
 * side's nonce is new), and the role is, so a proof cannot be reflected
 * back as the other side's. The server proves only after the client did,
 * so a stranger connecting to a node gets no proof to attack offline. A client with a token
 * refuses a WELCOME without the right proof, naming the address (a server
 * without the token, or an impostor on the port); a server with a token
 * refuses a HELLO without auth ("a token is required"), a server without
 * one a HELLO with it. Without a token on either side: HELLO auth=0,
 * WELCOME auth=0, as before. This is authentication, not encryption:
 * everything after the handshake is clear text, and a relay in the path
 * sees and may alter it. A listener counts connections still in their
 * handshake per peer host (16) and in all (256): past a cap an old one of
 * them is closed (the oldest that sent nothing, else the oldest), never
 * the newcomer, and one that sent nothing within min(1 s,
 * handshake_timeout_ms) is closed, so idle connections cannot lock
 * clients out; established connections never count.
 * SHARED MEMORY (unix: only, when both sides set shm_ring_bytes). After
 * the auth fields, HELLO carries one more byte, features, when the client
 * asks for something: bit 0 = shared memory (other bits: malformed). The
 * server answers WELCOME with the features it grants (bit 0 only on a
 * Unix socket and when it set shm_ring_bytes too); a byte nobody asked for
 * is malformed. Without the byte, as before. On a shared-memory connection
 * each side, right after the handshake, creates a ring: a sealed memfd
 * (F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_SEAL: its size cannot change, so
 * a mapping never faults) of its shm_ring_bytes, which it maps and hands
 * to the peer with a RING message (type 0x09, payload u64 ring size),
 * the descriptor attached (SCM_RIGHTS). The receiver checks it is such a
 * memfd of that size (16 GiB at most) and maps it. Every data message
 * that fits is then written into the sender's ring and only a
 * descriptor crosses the socket: the data header with flags 0x01 and a
 * 16-byte payload u64 position, u64 length. Positions count ring bytes
 * from 0 and only grow; a message takes slot(length) = length rounded up
 * to 64 (at least 64) bytes at offset position mod size, never wrapping:
 * it starts where the previous ring message ended, or at the next
 * multiple of the size (the sender skips the end of the ring when the
 * message does not fit there or when it fits before the oldest message
 * not yet released, and rewinds to the start whenever the ring is empty:
 * lowest offsets first, so the pages in use are those of the messages in
 * flight, and they are reused). The receiver checks each descriptor
 * against that rule, against its max_message_bytes, and that the message
 * does not overlap one it has not released: a lying peer fails its
 * connection (one line naming it), nothing is read outside the mapping.
 * The receiving application gets a pointer into the mapping, valid until
 * it releases the message (with shm_drop_released the receiver then drops
 * its mapping of a message of 256 KiB or more, MADV_DONTNEED, so the
 * pages stay resident in the sender only). Ring space is returned with the credits: on a
 * shared-memory connection a CREDIT is 12 bytes, u32 count and u64 the
 * position up to which every ring message has been released (in arrival
 * order; past what was sent fails the connection, a lower one than
 * before is stale and ignored). A sender waits for ring space as for credits (tsr_net_send's
 * time-out). Messages larger than the ring, or sent before the ring
 * exists, travel inline as on any socket; order is kept either way.
 * CREDIT payload:
 * u32 count of credits returned. PING: empty asks the peer to answer with
 * a PING of one byte 0x01 (an answer is never answered), so a side hears
 * from an idle peer within its own idle_timeout_ms whatever the peer's
 * setting; BYE is empty. REFUSE payload:
 * a one-line reason (UTF-8, no terminator), after which the refusing side
 * closes. A version mismatch, a wrong or missing token, or a malformed
 * HELLO is refused; both sides report one line naming the other. Each
 * side sends messages of at most the smaller of the peer's and its own
 * max_message_bytes: a peer announcing a huge limit cannot make this side
 * build larger messages than its own configuration allows. Credits are the
 * receiver's to grant (its window); a sender that must bound what it queues
 * for a peer that never reads (a node's replies) does so with
 * tsr_net_stats.messages_unreturned (the node's pending-reply budget).
 *
 * FLOW CONTROL counts MESSAGES. Each side grants its peer `credits`
 * messages at the handshake. Sending a data message costs one credit; a
 * sender with none blocks in tsr_net_send(). A credit returns (CREDIT
 * message, u32 count, batched) when the receiving APPLICATION releases a
 * message with tsr_net_msg_release(), not when the socket reads it. A peer
 * that sends beyond its credits fails its connection when that message's
 * header arrives, before anything is allocated for it. Flow control is
 * not liveness: the I/O thread keeps reading every open socket while the
 * application holds `credits` unreceived or unreleased messages and is
 * busy with them (the peer has no credit then, so only control messages
 * can arrive): PINGs are answered and CREDITs taken whatever the
 * application does, so a peer whose consumer takes minutes over one
 * message stays alive to the other side's idle_timeout_ms, and two peers
 * that both send cannot deadlock. So per connection and direction, memory is
 * bounded by credits x max_message_bytes on each side (the sender's queue
 * and the receiver's window), plus a 64 KiB read buffer. Payload buffers
 * of released large messages are kept (within that window) and reused for
 * the next ones, so a stream does not fault in fresh pages per message;
 * so are tsr_net_send's copies (queued plus kept: at most the window).
 * Messages are delivered in order, exactly once, per connection.
 *
 * SENDING. A message goes to the I/O thread's queue, except when the
 * connection's write side is idle (nothing queued or being written): then
 * the sending thread writes it to the socket itself, without blocking and
 * without netlib's lock, which spares a hand-over to the I/O thread (a
 * wake-up) per message; the same goes for the CREDIT a release returns.
 * What the socket does not take at once is finished by the I/O thread
 * before anything else (for tsr_net_send, that rest is copied first, into
 * a reused buffer), so order, framing and every guarantee above hold
 * either way. The I/O thread writes, shuts down and closes nothing while a
 * thread writes directly.
 *
 * CLOSING. tsr_net_conn_close() hands the connection to the I/O thread,
 * which writes what was already sent, then BYE (empty), shuts down its
 * write side, waits (at most close_timeout_ms) for the peer's end of
 * stream, and closes. A peer's end of stream after BYE is a clean end
 * (tsr_net_recv returns 0 once the queue is empty); without BYE it is an
 * error naming the peer (it crashed, was killed, or was cut off).
 * tsr_net_destroy() closes everything left, then joins the I/O thread.
 */
#ifndef TESSERA_DEV_NET_H
#define TESSERA_DEV_NET_H

#include <stddef.h>
#include <stdint.h>

#include "tessera/error.h"
#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TSR_NET_PROTOCOL_VERSION 2 /* 2: challenge-response handshake */
#define TSR_NET_HEADER_BYTES 16
#define TSR_NET_MAGIC 0x314E5354u
#define TSR_NET_KIND_FIRST_USER 0x10 /* message kinds 0x10..0xff are the caller's */
#define TSR_NET_WAIT_FOREVER (-1)
#define TSR_NET_NAME_MAX 64 /* node name bytes */
/* A peer's name as this side keeps and prints it: made safe with
 * tsr_text_sanitize, where each byte may become "\xNN". */
#define TSR_NET_PEER_NAME_MAX (4 * TSR_NET_NAME_MAX)
#define TSR_NET_TOKEN_MAX 256 /* shared token bytes */
#define TSR_NET_ADDRESS_MAX 160

typedef struct tsr_net tsr_net;                   /* I/O thread + loop */
typedef struct tsr_net_conn tsr_net_conn;         /* one connection */
typedef struct tsr_net_listener tsr_net_listener; /* one listening address */

typedef struct tsr_net_config {
    const char *node_name;         /* sent in the handshake; default "node" */
    const char *token;             /* shared token, proven (never sent) in every handshake;
                                      NULL/"" = none (peers that have one are refused) */
    uint32_t credits;              /* messages a peer may have in flight; default 8 */
    uint64_t max_message_bytes;    /* largest message accepted; default 64 MiB */
    uint32_t connect_timeout_ms;   /* socket connect; default 5000 */
    uint32_t handshake_timeout_ms; /* HELLO..WELCOME; default 5000 */
    uint32_t idle_timeout_ms;      /* peer silent this long = dead; 0 = off (default).
                                      Each side pings every third of it. */
    uint32_t close_timeout_ms;     /* wait for the peer's end of stream; default 5000 */
    uint16_t protocol_version;     /* announced version; 0 = TSR_NET_PROTOCOL_VERSION.
                                      Only tests and compatibility shims set it. */
    uint64_t shm_ring_bytes;       /* 0 = off (default). Else unix: connections with a peer
                                      that sets it too carry data messages through a
                                      shared-memory ring of this many bytes per direction
                                      (see SHARED MEMORY; 64 KiB..16 GiB, a page multiple) */
    int shm_drop_released;         /* 0 (default) or 1: the receiving side drops its mapping of
                                      a released ring message of 256 KiB or more (its page table
                                      entries; the sender still maps the pages), so a ring page
                                      is resident in one process, not counted in both; the next
                                      read of it faults the pages back in */
} tsr_net_config;

/* A received message. `data` stays valid (and writable) until released. */
typedef struct tsr_net_msg {
    unsigned kind; /* TSR_NET_KIND_FIRST_USER..255 */
    void *data;
    uint64_t len;
    void *internal; /* netlib's; do not touch */
} tsr_net_msg;

typedef struct tsr_net_stats {
    uint64_t messages_sent, bytes_sent;         /* payload bytes */
    uint64_t messages_received, bytes_received; /* payload bytes */
    uint64_t blocked_on_credits_ns;             /* time tsr_net_send waited for credits (or ring space) */
    uint64_t messages_direct;                   /* data messages the sending thread wrote itself (see SENDING) */
    uint64_t messages_direct_rest;              /* ... of which the socket took only a part */
    uint32_t messages_unreturned;               /* data messages sent whose credit has not come back:
                                                   not yet taken by the peer's application */
    /* ... of the messages and payload bytes above, those that went through
     * the shared-memory ring (only a descriptor crossed the socket) */
    uint64_t messages_sent_shm, bytes_sent_shm;
    uint64_t messages_received_shm, bytes_received_shm;
} tsr_net_stats;

TSR_API void tsr_net_config_defaults(tsr_net_config *config);

/* Starts the I/O thread. `config` may be NULL (defaults); its strings are
 * copied. Returns NULL and fills `err` on failure. */
TSR_API tsr_net *tsr_net_create(const tsr_net_config *config, tsr_error *err);
/* Closes every listener and connection still open (see CLOSING), joins the
 * I/O thread and frees everything, including connections not yet closed. */
TSR_API void tsr_net_destroy(tsr_net *net);

/* Listens on `address`. Errors name the address ("address already in use"). */
TSR_API tsr_net_listener *tsr_net_listen(tsr_net *net, const char *address, tsr_error *err);
/* Whether a listen address can be reached from this host only: 1 for
 * loopback (tcp://:PORT, 127.0.0.0/8, ::1, a name resolving only to them),
 * unix: and inproc:; 0 when other hosts may reach it (0.0.0.0, another
 * interface's address); or an error (bad address, unknown host). */
TSR_API int tsr_net_address_is_local(const char *address, tsr_error *err);
/* The address actually bound, e.g. "tcp://127.0.0.1:41234" for port 0. */
TSR_API const char *tsr_net_listener_address(const tsr_net_listener *listener);
/* Waits for a connection whose handshake succeeded. Returns NULL with
 * TSR_ETIMEDOUT when none came in time. */
TSR_API tsr_net_conn *tsr_net_accept(tsr_net_listener *listener, int timeout_ms, tsr_error *err);
/* How many peers this listener refused, and the last reason (may be NULL). */
TSR_API unsigned tsr_net_listener_refusals(tsr_net_listener *listener, tsr_error *last);
/* Stops listening; connections not yet accepted are closed. */
TSR_API void tsr_net_listener_close(tsr_net_listener *listener);

/* Connects and handshakes, waiting at most connect + handshake time-outs
 * per address. A host name is resolved by the calling thread (bounded by
 * the system resolver's time-outs) and every address it resolves to is
 * tried until one answers. Errors name the address and, when the peer
 * refused, the peer's reason. Once the handshake succeeded the connection
 * is returned even if the peer closed (or it failed) right after: messages
 * the peer sent before stay receivable, then send/recv report the end. */
TSR_API tsr_net_conn *tsr_net_connect(tsr_net *net, const char *address, tsr_error *err);

/* Sends a copy of `data` (copied only when it cannot be written at once:
 * see SENDING; `data` is the caller's again on return). Blocks while the
 * peer grants no credit.
 * Returns TSR_OK, TSR_ETIMEDOUT (nothing sent), TSR_EINVAL (kind out of
 * range, or len above the peer's max_message_bytes: nothing allocated), or
 * the connection's error once it failed or closed. */
TSR_API int tsr_net_send(tsr_net_conn *conn, unsigned kind, const void *data, uint64_t len, int timeout_ms,
                         tsr_error *err);
/* Like tsr_net_send, but takes ownership of `data` instead of copying: it
 * calls release(data, ctx) once written or dropped (release NULL = free()).
 * release runs on the I/O thread or inside a netlib call, possibly with
 * netlib's lock held: it must not call netlib (return the buffer to a pool).
 * On an error return, `data` was not taken and is still the caller's. */
TSR_API int tsr_net_send_owned(tsr_net_conn *conn, unsigned kind, void *data, uint64_t len,
                               void (*release)(void *data, void *ctx), void *ctx, int timeout_ms, tsr_error *err);
/* Zero-copy sending: a buffer of at least max_len bytes in which the
 * caller builds its next message, then sends the first len <= max_len of
 * them with tsr_net_send_commit. On a shared-memory connection the buffer
 * is space in the ring the peer maps (reserve waits, within timeout_ms,
 * for a credit and that much ring space: the message is never copied);
 * otherwise (or when max_len does not fit in the ring) a buffer the
 * connection keeps, sent as tsr_net_send would. One reservation at a time
 * per connection, from its one sending thread; a new reserve or a
 * tsr_net_send drops one not committed. Errors as tsr_net_send. */
TSR_API int tsr_net_send_reserve(tsr_net_conn *conn, uint64_t max_len, void **buf, int timeout_ms, tsr_error *err);
TSR_API int tsr_net_send_commit(tsr_net_conn *conn, unsigned kind, uint64_t len, int timeout_ms, tsr_error *err);
/* Receives the next message. Returns 1 with *msg filled, 0 when the peer
 * closed cleanly and every message was received, TSR_ETIMEDOUT, or the
 * connection's error. Release every message (this returns its credit). */
TSR_API int tsr_net_recv(tsr_net_conn *conn, tsr_net_msg *msg, int timeout_ms, tsr_error *err);
/* Receives from whichever of `count` connections (all of one tsr_net) has
 * something first. Scanning starts after *which (the previous result; set
 * it to count the first time), so a busy connection cannot starve the
 * others: connections with messages waiting are served round-robin. Sets
 * *which to the connection the result is about and returns what
 * tsr_net_recv would for it — 1 (message), 0 (that peer closed cleanly) or
 * its error — so the caller can drop ended connections from its array; or
 * TSR_ETIMEDOUT (*which unchanged) when none had anything in time. */
TSR_API int tsr_net_recv_any(tsr_net_conn *const *conns, size_t count, size_t *which, tsr_net_msg *msg, int timeout_ms,
                             tsr_error *err);
TSR_API void tsr_net_msg_release(tsr_net_msg *msg);

/* The peer's node name (from its handshake, escaped by tsr_text_sanitize:
 * at most TSR_NET_PEER_NAME_MAX bytes) and address. */
TSR_API const char *tsr_net_conn_peer_name(const tsr_net_conn *conn);
TSR_API const char *tsr_net_conn_address(const tsr_net_conn *conn);
TSR_API void tsr_net_conn_stats(tsr_net_conn *conn, tsr_net_stats *stats);
/* How this side's data messages travel: "tcp", "unix", "unix+shm" (the
 * shared-memory ring, see SHARED MEMORY) or "inproc". */
TSR_API const char *tsr_net_conn_transport(tsr_net_conn *conn);
/* 1 when the connection failed because the peer sent nothing for
 * idle_timeout_ms (a stopped or hung peer, not one that went away). */
TSR_API int tsr_net_conn_went_silent(tsr_net_conn *conn);
/* 1 when the connection failed because the peer's end went away without
 * closing it (its process ended, was killed, or the connection was cut):
 * what the peer's own end reports is the cause, this is its echo. */
TSR_API int tsr_net_conn_vanished(tsr_net_conn *conn);
/* 1 with *why set when the connection has failed (the peer went away, was
 * cut or fell silent), even while messages it sent before are still
 * unread: a caller about to give up on a peer it is not reading (one
 * waiting at a barrier) names every end that is already gone. 0 while it
 * is open or ended cleanly. */
TSR_API int tsr_net_conn_failure(tsr_net_conn *conn, tsr_error *why);
/* Waits at most timeout_ms until everything tsr_net_send accepted on
 * `conn` has been handed to the kernel (a process about to _exit after a
 * fatal error flushes so its peers still read what it sent before). 0 when
 * written, TSR_ETIMEDOUT, or the connection's error. */
TSR_API int tsr_net_conn_flush(tsr_net_conn *conn, int timeout_ms);
/* Waits at most timeout_ms until the peer's application has released
 * every data message sent on `conn` and its credits (and, with shared
 * memory, the ring space) are back, so the next ring message goes at the
 * ring's start. A caller that knows the peer released everything (the
 * peer said so on another connection) uses it to stop racing the CREDIT
 * in flight. TSR_OK, TSR_ETIMEDOUT naming the peer, or the connection's
 * error. */
TSR_API int tsr_net_conn_wait_returned(tsr_net_conn *conn, int timeout_ms, tsr_error *err);
/* Closes gracefully (see CLOSING); `conn` must not be used afterwards.
 * Messages still held by the application may be released later. */
TSR_API void tsr_net_conn_close(tsr_net_conn *conn);

/* ---- addresses (address.c) ------------------------------------------------
 * Addresses are parsed, checked, printed and normalised here only: the
 * graph model, the mothership and the programs call these rather than
 * take text apart or build it themselves. */

/* Bytes of a unix: socket path: sockaddr_un.sun_path less its NUL. */
#define TSR_NET_UNIX_PATH_MAX 107

typedef enum tsr_net_transport { TSR_NET_TCP, TSR_NET_UNIX, TSR_NET_INPROC } tsr_net_transport;

/* An address taken apart. */
typedef struct tsr_net_address {
    tsr_net_transport transport;
    char host[TSR_NET_ADDRESS_MAX];       /* tcp: name, IPv4 or IPv6 (no brackets); "" for tcp://:PORT */
    unsigned port;                        /* tcp: 0..65535 */
    char path[TSR_NET_UNIX_PATH_MAX + 1]; /* unix */
    char name[TSR_NET_ADDRESS_MAX - 8];   /* inproc */
} tsr_net_address;

/* Parses `text` (ADDRESSES above; "unix:///p" is read as "unix:/p").
 * Never resolves a name. Errors name the address and what is wrong. */
TSR_API int tsr_net_address_parse(const char *text, tsr_net_address *out, tsr_error *err);
/* Writes `a` as text: tcp://HOST:PORT (an IPv6 host in brackets),
 * unix:PATH or inproc:NAME. TSR_EINVAL when it does not fit `size`. */
TSR_API int tsr_net_address_format(const tsr_net_address *a, char *out, size_t size, tsr_error *err);
/* tcp://HOST:PORT from a host (a name, IPv4, or IPv6 with or without
 * brackets) and a port as text, unchecked: the listener or connector
 * checks it. TSR_EINVAL when it does not fit `size`. */
TSR_API int tsr_net_address_tcp(const char *host, const char *port, char *out, size_t size, tsr_error *err);
/* An address as a user writes it on a command line: "HOST:PORT" becomes
 * "tcp://HOST:PORT"; tcp://, unix: and inproc: addresses pass unchanged.
 * TSR_EINVAL when it does not fit `size`. */
TSR_API int tsr_net_address_normalise(const char *text, char *out, size_t size, tsr_error *err);
/* A server's listen place as a graph file writes it: for tcp "PORT",
 * "HOST:PORT" or "[IPV6]:PORT" (out->host "" for a bare PORT: the node
 * picks the host), for unix a socket path. Checks what the node's
 * listener would refuse, so a checked graph is not refused at run time;
 * errors are one line beginning with `who`. */
TSR_API int tsr_net_listen_spec_parse(const char *who, const char *spec, tsr_net_transport transport,
                                      tsr_net_address *out, tsr_error *err);

/* Deterministic bytes for stream position [offset, offset+len) of `seed`. */
TSR_API void tsr_net_pattern_fill(void *dst, uint64_t offset, size_t len, uint64_t seed);
/* FNV-1a 64 over `len` bytes, continuing from `hash` (start: TSR_NET_FNV_START). */
#define TSR_NET_FNV_START 0xcbf29ce484222325ull
TSR_API uint64_t tsr_net_fnv1a(uint64_t hash, const void *data, size_t len);

#ifdef __cplusplus
}
#endif
#endif
