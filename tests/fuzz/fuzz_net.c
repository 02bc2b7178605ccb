/* tests/fuzz/fuzz_net.c — fuzzing netlib's frame header and handshake
 * decoders through the real connection state machine: each input is the
 * byte stream one peer sends to a real netlib connection (a tsr_net with
 * its I/O thread, over a Unix-domain socket), so the bytes go through the
 * same read parser, header checks, HELLO/CHALLENGE/PROOF/WELCOME decoders
 * and credit rules as on a node. Built two ways (tests/fuzz.cmake):
 *   fuzz_net         libFuzzer target (-DTESSERA_FUZZ=ON, clang);
 *   fuzz_net_replay  DIR|FILE...: runs each input once, any compiler (the
 *                    ctest fuzz_net_corpus_replay); --write-seeds DIR
 *                    writes the seed corpus with netlib's own encoders.
 * Input: byte 0 picks who is fuzzed, the rest is what the peer sends:
 *   bit 0  0 = a netlib SERVER reads the bytes (from a raw client),
 *          1 = a netlib CLIENT reads them (from a raw fake server);
 *   bit 1  1 = first a correct handshake (this harness knows the token and
 *          computes the proofs), so the bytes arrive on an open
 *          connection: data, CREDIT, PING, BYE, lying lengths;
 *   bit 2  1 = neither side has a token (the auth=0 handshake);
 *   bit 3  1 = (server side only) a server with shared memory on (net.h,
 *          SHARED MEMORY; no token): with bit 1 the harness asks for it
 *          in its HELLO and hands over a real sealed memfd ring (RING,
 *          SCM_RIGHTS), so the bytes are ring descriptors, 12-byte
 *          CREDITs and the rest on a shared-memory connection.
 * Owns: two tsr_nets for the process, a private socket folder. Never:
 * filters inputs (refusing them is netlib's job); waits without a bound (a
 * connection that neither ends nor fails within 10 s aborts: a hang). */
#include <errno.h>
#include <poll.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include "net_internal.h"

#define FUZZ_TOKEN "fuzz-token"
#define FUZZ_BOUND_MS 10000

typedef struct fuzz_env {
    char dir[64];
    tsr_net *server[2], *client[2]; /* [0] with the token, [1] without */
    tsr_net_listener *listener[3];  /* [2]: the shared-memory server */
    tsr_net *shm_server;
    char server_path[3][sizeof(((struct sockaddr_un *)0)->sun_path)];
    char fake_path[sizeof(((struct sockaddr_un *)0)->sun_path)];
    char fake_address[TSR_NET_ADDRESS_MAX];
    int fake_fd;
} fuzz_env;

static fuzz_env env;

static void die(const char *what)
{
    fprintf(stderr, "fuzz_net: %s\n", what);
    abort();
}

static uint64_t now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000u + (uint64_t)ts.tv_nsec / 1000000u;
}

#define FUZZ_RING (64u << 10)

static tsr_net *make_net_ring(const char *name, const char *token, uint64_t ring)
{
    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.shm_ring_bytes = ring;
    cfg.node_name = name;
    cfg.token = token;
    cfg.credits = 4;
    cfg.max_message_bytes = 1 << 16;
    cfg.handshake_timeout_ms = 2000;
    cfg.close_timeout_ms = 2000;
    tsr_error err = {0};
    tsr_net *net = tsr_net_create(&cfg, &err);
    if (!net)
        die(err.message);
    return net;
}

static tsr_net *make_net(const char *name, const char *token) { return make_net_ring(name, token, 0); }

static int unix_socket_to(const char *path)
{
    int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    struct sockaddr_un sa = {.sun_family = AF_UNIX};
    snprintf(sa.sun_path, sizeof sa.sun_path, "%s", path);
    if (fd < 0 || connect(fd, (struct sockaddr *)&sa, sizeof sa))
        die("cannot connect to the netlib listener");
    return fd;
}

static void setup(void)
{
    setenv("TESSERA_LOG", "error", 0); /* refusals are the normal outcome here */
    snprintf(env.dir, sizeof env.dir, "/tmp/fuzz-net-XXXXXX");
    if (!mkdtemp(env.dir))
        die("mkdtemp");
    const char *tokens[2] = {FUZZ_TOKEN, NULL};
    for (int t = 0; t < 2; t++) {
        env.server[t] = make_net("fuzz-server", tokens[t]);
        env.client[t] = make_net("fuzz-client", tokens[t]);
        snprintf(env.server_path[t], sizeof env.server_path[t], "%s/server-%d", env.dir, t);
        char address[TSR_NET_ADDRESS_MAX];
        snprintf(address, sizeof address, "unix:%s", env.server_path[t]);
        tsr_error err = {0};
        env.listener[t] = tsr_net_listen(env.server[t], address, &err);
        if (!env.listener[t])
            die(err.message);
    }
    env.shm_server = make_net_ring("fuzz-shm-server", NULL, FUZZ_RING);
    snprintf(env.server_path[2], sizeof env.server_path[2], "%s/server-shm", env.dir);
    char address[TSR_NET_ADDRESS_MAX];
    snprintf(address, sizeof address, "unix:%s", env.server_path[2]);
    tsr_error err = {0};
    if (!(env.listener[2] = tsr_net_listen(env.shm_server, address, &err)))
        die(err.message);
    snprintf(env.fake_path, sizeof env.fake_path, "%s/fake", env.dir);
    snprintf(env.fake_address, sizeof env.fake_address, "unix:%s", env.fake_path);
    env.fake_fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    struct sockaddr_un sa = {.sun_family = AF_UNIX};
    snprintf(sa.sun_path, sizeof sa.sun_path, "%s", env.fake_path);
    if (env.fake_fd < 0 || bind(env.fake_fd, (struct sockaddr *)&sa, sizeof sa) || listen(env.fake_fd, 8))
        die("fake server socket");
}

static void teardown(void)
{
    for (int t = 0; t < 2; t++) {
        tsr_net_listener_close(env.listener[t]);
        tsr_net_destroy(env.server[t]);
        tsr_net_destroy(env.client[t]);
    }
    tsr_net_listener_close(env.listener[2]);
    tsr_net_destroy(env.shm_server);
    close(env.fake_fd);
    unlink(env.fake_path);
    rmdir(env.dir);
}

/* ---- raw socket helpers --------------------------------------------------- */

static void write_all(int fd, const uint8_t *p, size_t n)
{
    while (n) {
        ssize_t w = send(fd, p, n, MSG_NOSIGNAL);
        if (w <= 0)
            return; /* the peer gave up on us: that is its right */
        p += w;
        n -= (size_t)w;
    }
}

/* Reads exactly n bytes (bounded); 0 or -1. */
static int read_exact(int fd, uint8_t *p, size_t n)
{
    uint64_t end = now_ms() + FUZZ_BOUND_MS;
    while (n) {
        struct pollfd pfd = {.fd = fd, .events = POLLIN};
        uint64_t now = now_ms();
        if (now >= end || poll(&pfd, 1, (int)(end - now)) <= 0)
            return -1;
        ssize_t r = recv(fd, p, n, 0);
        if (r <= 0)
            return -1;
        p += r;
        n -= (size_t)r;
    }
    return 0;
}

/* One message from the netlib side: type, payload into buf (<= 4096). */
static int read_msg(int fd, uint8_t *buf, size_t *len)
{
    uint8_t h[TSR_NET_HEADER_BYTES];
    if (read_exact(fd, h, sizeof h))
        return -1;
    net_header hd;
    net_header_decode(h, &hd);
    if (hd.magic != TSR_NET_MAGIC || hd.len > 4096 || read_exact(fd, buf, (size_t)hd.len))
        return -1;
    *len = (size_t)hd.len;
    return hd.type;
}

/* Everything until the netlib side closes; a hang aborts. */
static void drain_until_closed(int fd)
{
    uint64_t end = now_ms() + FUZZ_BOUND_MS;
    for (;;) {
        struct pollfd pfd = {.fd = fd, .events = POLLIN};
        uint64_t now = now_ms();
        if (now >= end)
            die("netlib kept a connection open 10 s after its peer ended (hang)");
        if (poll(&pfd, 1, (int)(end - now)) <= 0)
            continue;
        uint8_t buf[4096];
        if (recv(fd, buf, sizeof buf, 0) <= 0)
            return;
    }
}

static void send_frame(int fd, uint8_t type, const uint8_t *payload, size_t len)
{
    uint8_t msg[TSR_NET_HEADER_BYTES + NET_CONTROL_MAX];
    net_header_encode(msg, TSR_NET_PROTOCOL_VERSION, type, 0, len);
    memcpy(msg + TSR_NET_HEADER_BYTES, payload, len);
    write_all(fd, msg, TSR_NET_HEADER_BYTES + len);
}

/* ---- the netlib side's application ---------------------------------------- */

/* What an application does with a connection: receive and release until
 * it ends or fails, then close. */
static void consume(tsr_net_conn *c)
{
    tsr_net_msg m;
    tsr_error err;
    uint64_t end = now_ms() + FUZZ_BOUND_MS;
    int got;
    while ((got = tsr_net_recv(c, &m, 2000, &err)) == 1 || got == TSR_ETIMEDOUT) {
        if (got == 1)
            tsr_net_msg_release(&m);
        if (now_ms() >= end)
            die("a connection neither ended nor failed 10 s after its peer ended (hang)");
    }
    tsr_net_conn_close(c);
}

/* Connections that completed a handshake wait in the listener's queue. */
static void accept_all(int t)
{
    tsr_error err;
    tsr_net_conn *c;
    while ((c = tsr_net_accept(env.listener[t], 0, &err)))
        consume(c);
}

/* ---- server side: a raw client sends the input ---------------------------- */

/* The correct client handshake (token t), leaving the connection open. */
static void client_handshake(int fd, int t)
{
    uint8_t payload[NET_CONTROL_MAX], nonce[NET_AUTH_BYTES], buf[4096];
    net_auth_nonce(nonce);
    size_t n = net_hello_encode(payload, 4, 1 << 16, "fuzz-peer", t == 0 ? nonce : NULL, 0);
    send_frame(fd, NET_HELLO, payload, n);
    size_t len;
    int type = read_msg(fd, buf, &len);
    if (t == 0) {
        if (type != NET_CHALLENGE || len != NET_AUTH_BYTES)
            die("no CHALLENGE for a correct HELLO");
        uint8_t proof[NET_AUTH_BYTES];
        net_auth_proof(FUZZ_TOKEN, "client", nonce, buf, proof);
        send_frame(fd, NET_PROOF, proof, sizeof proof);
        type = read_msg(fd, buf, &len);
    }
    if (type != NET_WELCOME)
        die("a correct handshake was not welcomed");
}

/* The correct shared-memory handshake with the shm server: HELLO asking
 * for it, WELCOME granting it, the server's RING, then this side's ring
 * (a sealed memfd, filled with a pattern) passed with SCM_RIGHTS. */
static void shm_handshake(int fd)
{
    uint8_t payload[NET_CONTROL_MAX], buf[4096];
    size_t n = net_hello_encode(payload, 4, 1 << 16, "fuzz-shm-peer", NULL, NET_FEATURE_SHM);
    send_frame(fd, NET_HELLO, payload, n);
    size_t len;
    if (read_msg(fd, buf, &len) != NET_WELCOME || !len || buf[len - 1] != NET_FEATURE_SHM)
        die("a correct shared-memory HELLO was not granted it");
    if (read_msg(fd, buf, &len) != NET_RING || len != 8) /* (its descriptor is dropped here) */
        die("the server handed over no ring");
    int ring = memfd_create("fuzz-ring", MFD_CLOEXEC | MFD_ALLOW_SEALING);
    if (ring < 0 || ftruncate(ring, FUZZ_RING) || fcntl(ring, F_ADD_SEALS, F_SEAL_SHRINK | F_SEAL_GROW))
        die("memfd");
    uint8_t msg[TSR_NET_HEADER_BYTES + 8];
    net_header_encode(msg, TSR_NET_PROTOCOL_VERSION, NET_RING, 0, 8);
    net_put_u64(msg + TSR_NET_HEADER_BYTES, FUZZ_RING);
    struct iovec iov = {.iov_base = msg, .iov_len = sizeof msg};
    union {
        char b[CMSG_SPACE(sizeof(int))];
        struct cmsghdr align;
    } u;
    memset(&u, 0, sizeof u);
    struct msghdr mh = {.msg_iov = &iov, .msg_iovlen = 1, .msg_control = u.b, .msg_controllen = sizeof u.b};
    struct cmsghdr *cm = CMSG_FIRSTHDR(&mh);
    cm->cmsg_level = SOL_SOCKET;
    cm->cmsg_type = SCM_RIGHTS;
    cm->cmsg_len = CMSG_LEN(sizeof(int));
    memcpy(CMSG_DATA(cm), &ring, sizeof(int));
    if (sendmsg(fd, &mh, MSG_NOSIGNAL) != (ssize_t)sizeof msg)
        die("sendmsg RING");
    close(ring);
}

static void fuzz_server(const uint8_t *data, size_t size, int proven, int t)
{
    int fd = unix_socket_to(env.server_path[t]);
    tsr_net_conn *c = NULL;
    if (proven && t == 2) {
        shm_handshake(fd);
        tsr_error err;
        if (!(c = tsr_net_accept(env.listener[t], FUZZ_BOUND_MS, &err)))
            die("a welcomed shared-memory connection did not reach accept");
    } else if (proven) {
        client_handshake(fd, t);
        tsr_error err;
        c = tsr_net_accept(env.listener[t], FUZZ_BOUND_MS, &err);
        if (!c)
            die("a welcomed connection did not reach accept");
    }
    write_all(fd, data, size);
    shutdown(fd, SHUT_WR);
    if (c)
        consume(c);
    drain_until_closed(fd);
    close(fd);
    accept_all(t);
}

/* ---- client side: a fake server sends the input --------------------------- */

typedef struct fake_job {
    const uint8_t *data;
    size_t size;
    int proven, t;
} fake_job;

static void *fake_server_main(void *arg)
{
    fake_job *j = arg;
    int fd = accept(env.fake_fd, NULL, NULL);
    if (fd < 0)
        return NULL;
    uint8_t hello[4096];
    size_t len;
    if (read_msg(fd, hello, &len) == NET_HELLO && j->proven) {
        net_hello h;
        tsr_error err;
        if (net_hello_decode(hello, len, &h, &err))
            die("netlib's client sent a HELLO its own decoder refuses");
        uint8_t payload[NET_CONTROL_MAX];
        size_t n;
        if (j->t == 0) {
            uint8_t nonce[NET_AUTH_BYTES], proof[NET_AUTH_BYTES], want[NET_AUTH_BYTES], buf[4096];
            net_auth_nonce(nonce);
            send_frame(fd, NET_CHALLENGE, nonce, sizeof nonce);
            if (read_msg(fd, buf, &len) != NET_PROOF || len != NET_AUTH_BYTES)
                die("netlib's client did not answer a CHALLENGE with a PROOF");
            net_auth_proof(FUZZ_TOKEN, "client", h.auth, nonce, want);
            if (!net_auth_equal(buf, want))
                die("netlib's client sent a wrong proof");
            net_auth_proof(FUZZ_TOKEN, "server", h.auth, nonce, proof);
            n = net_hello_encode(payload, 4, 1 << 16, "fuzz-fake", proof, 0);
        } else {
            n = net_hello_encode(payload, 4, 1 << 16, "fuzz-fake", NULL, 0);
        }
        send_frame(fd, NET_WELCOME, payload, n);
    }
    write_all(fd, j->data, j->size);
    shutdown(fd, SHUT_WR);
    drain_until_closed(fd);
    close(fd);
    return NULL;
}

static void fuzz_client(const uint8_t *data, size_t size, int proven, int t)
{
    fake_job j = {data, size, proven, t};
    pthread_t th;
    if (pthread_create(&th, NULL, fake_server_main, &j))
        die("pthread_create");
    tsr_error err;
    tsr_net_conn *c = tsr_net_connect(env.client[t], env.fake_address, &err);
    if (proven && !c)
        die("a correct handshake by the fake server was refused");
    if (c)
        consume(c);
    pthread_join(th, NULL);
}

static void run_one(const uint8_t *data, size_t size)
{
    if (!size)
        return;
    unsigned mode = data[0];
    int client = mode & 1, proven = (mode >> 1) & 1, t = (mode >> 2) & 1;
    if ((mode >> 3) & 1)
        t = 2; /* the shared-memory server (no token) */
    if (client && t < 2)
        fuzz_client(data + 1, size - 1, proven, t);
    else
        fuzz_server(data + 1, size - 1, proven, t);
}

#ifndef FUZZ_NET_REPLAY

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    setup();
    atexit(teardown);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    run_one(data, size);
    return 0;
}

#else /* the replay and seed-writer program */

#include <dirent.h>

static int replay_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "fuzz_net_replay: %s: %s\n", path, strerror(errno));
        return 1;
    }
    static uint8_t buf[1 << 20];
    size_t n = fread(buf, 1, sizeof buf, f);
    int bad = ferror(f);
    fclose(f);
    if (bad) {
        fprintf(stderr, "fuzz_net_replay: %s: read error\n", path);
        return 1;
    }
    run_one(buf, n);
    return 0;
}

static int replay(const char *path, unsigned *count)
{
    struct stat st;
    if (stat(path, &st)) {
        fprintf(stderr, "fuzz_net_replay: %s: %s\n", path, strerror(errno));
        return 1;
    }
    if (!S_ISDIR(st.st_mode)) {
        ++*count;
        return replay_file(path);
    }
    DIR *d = opendir(path);
    if (!d) {
        fprintf(stderr, "fuzz_net_replay: %s: %s\n", path, strerror(errno));
        return 1;
    }
    int failed = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (e->d_name[0] != '.') {
            char file[4096];
            snprintf(file, sizeof file, "%s/%s", path, e->d_name);
            failed |= replay(file, count);
        }
    closedir(d);
    return failed;
}

/* ---- seeds: real frames from netlib's encoders ---------------------------- */

typedef struct seed {
    uint8_t b[8192];
    size_t n;
} seed;

static void put(seed *s, const void *p, size_t n)
{
    if (s->n + n > sizeof s->b)
        die("seed too long");
    memcpy(s->b + s->n, p, n);
    s->n += n;
}

static void frame(seed *s, uint16_t version, uint8_t type, const void *payload, size_t len)
{
    uint8_t h[TSR_NET_HEADER_BYTES];
    net_header_encode(h, version, type, 0, len);
    put(s, h, sizeof h);
    put(s, payload, len);
}

static void hello(seed *s, uint8_t type, int with_auth)
{
    uint8_t payload[NET_CONTROL_MAX], nonce[NET_AUTH_BYTES];
    net_auth_nonce(nonce);
    size_t n = net_hello_encode(payload, 4, 1 << 16, "seed-peer", with_auth ? nonce : NULL, 0);
    frame(s, TSR_NET_PROTOCOL_VERSION, type, payload, n);
}

static void data_traffic(seed *s)
{
    static const uint8_t credit[4] = {1, 0, 0, 0}, one = 1;
    frame(s, TSR_NET_PROTOCOL_VERSION, 0x10, "hello", 5);
    frame(s, TSR_NET_PROTOCOL_VERSION, 0xff, "", 0);
    frame(s, TSR_NET_PROTOCOL_VERSION, NET_PING, NULL, 0);
    frame(s, TSR_NET_PROTOCOL_VERSION, NET_PING, &one, 1);
    frame(s, TSR_NET_PROTOCOL_VERSION, NET_CREDIT, credit, 4);
    uint8_t big[3000];
    memset(big, 0xa5, sizeof big);
    frame(s, TSR_NET_PROTOCOL_VERSION, 0x42, big, sizeof big);
    frame(s, TSR_NET_PROTOCOL_VERSION, NET_BYE, NULL, 0);
}

static void write_seed(const char *dir, const char *name, const seed *s)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.bin", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(s->b, 1, s->n, f) != s->n || fclose(f)) {
        fprintf(stderr, "fuzz_net_replay: cannot write %s: %s\n", path, strerror(errno));
        exit(1);
    }
    run_one(s->b, s->n); /* every seed must also run */
}

enum { M_SERVER = 0, M_CLIENT = 1, M_OPEN = 2, M_NO_TOKEN = 4, M_SHM = 8 };

/* A data message whose payload is a ring descriptor (net.h, SHARED MEMORY). */
static void descriptor(seed *s, uint64_t pos, uint64_t len)
{
    uint8_t h[TSR_NET_HEADER_BYTES], d[NET_SHM_DESC_BYTES];
    net_header_encode(h, TSR_NET_PROTOCOL_VERSION, 0x20, NET_FLAG_SHM, sizeof d);
    net_put_u64(d, pos);
    net_put_u64(d + 8, len);
    put(s, h, sizeof h);
    put(s, d, sizeof d);
}

static void shm_credit(seed *s, uint32_t count, uint64_t pos)
{
    uint8_t c[12];
    net_put_u32(c, count);
    net_put_u64(c + 4, pos);
    frame(s, TSR_NET_PROTOCOL_VERSION, NET_CREDIT, c, sizeof c);
}

static void write_seeds(const char *dir)
{
    seed s;
    uint8_t nonce[NET_AUTH_BYTES], reason[] = "token mismatch";
    net_auth_nonce(nonce);
#define SEED(name, mode, ...)      \
    do {                           \
        s.n = 0;                   \
        uint8_t m = (mode);        \
        put(&s, &m, 1);            \
        __VA_ARGS__;               \
        write_seed(dir, name, &s); \
    } while (0)
    /* a netlib server reads */
    SEED("server-hello-auth", M_SERVER, hello(&s, NET_HELLO, 1));
    SEED("server-hello-auth-guessed-proof", M_SERVER, hello(&s, NET_HELLO, 1);
         frame(&s, TSR_NET_PROTOCOL_VERSION, NET_PROOF, nonce, sizeof nonce));
    SEED("server-hello-no-auth", M_SERVER, hello(&s, NET_HELLO, 0));
    SEED("server-hello-old-version", M_SERVER, hello(&s, NET_HELLO, 1); s.b[1 + 4] = 1);
    SEED("server-no-token-hello-then-traffic", M_SERVER | M_NO_TOKEN, hello(&s, NET_HELLO, 0); data_traffic(&s));
    SEED("server-no-token-hello-auth", M_SERVER | M_NO_TOKEN, hello(&s, NET_HELLO, 1));
    SEED("server-open-traffic", M_SERVER | M_OPEN, data_traffic(&s));
    SEED("server-open-no-token-traffic", M_SERVER | M_OPEN | M_NO_TOKEN, data_traffic(&s));
    /* a netlib client reads (from a fake server) */
    SEED("client-challenge-then-guessed-welcome", M_CLIENT,
         frame(&s, TSR_NET_PROTOCOL_VERSION, NET_CHALLENGE, nonce, sizeof nonce);
         hello(&s, NET_WELCOME, 1));
    SEED("client-welcome-without-proof", M_CLIENT, hello(&s, NET_WELCOME, 0));
    SEED("client-refuse", M_CLIENT, frame(&s, TSR_NET_PROTOCOL_VERSION, NET_REFUSE, reason, sizeof reason - 1));
    SEED("client-no-token-welcome-then-traffic", M_CLIENT | M_NO_TOKEN, hello(&s, NET_WELCOME, 0); data_traffic(&s));
    SEED("client-no-token-challenge", M_CLIENT | M_NO_TOKEN,
         frame(&s, TSR_NET_PROTOCOL_VERSION, NET_CHALLENGE, nonce, sizeof nonce));
    SEED("client-open-traffic", M_CLIENT | M_OPEN, data_traffic(&s));
    SEED("client-open-no-token-traffic", M_CLIENT | M_OPEN | M_NO_TOKEN, data_traffic(&s));
    /* a shared-memory server reads */
    uint8_t hp[NET_CONTROL_MAX];
    size_t hn = net_hello_encode(hp, 4, 1 << 16, "seed-shm", NULL, NET_FEATURE_SHM);
    SEED("shm-hello-features", M_SERVER | M_SHM, frame(&s, TSR_NET_PROTOCOL_VERSION, NET_HELLO, hp, hn));
    SEED("shm-hello-unknown-feature", M_SERVER | M_SHM, hp[hn - 1] = 0x82;
         frame(&s, TSR_NET_PROTOCOL_VERSION, NET_HELLO, hp, hn); hp[hn - 1] = NET_FEATURE_SHM);
    SEED("shm-hello-then-descriptor-before-ring", M_SERVER | M_SHM,
         frame(&s, TSR_NET_PROTOCOL_VERSION, NET_HELLO, hp, hn);
         descriptor(&s, 0, 10));
    SEED("shm-open-descriptors", M_SERVER | M_SHM | M_OPEN, descriptor(&s, 0, 100); descriptor(&s, 128, 0);
         descriptor(&s, 192, 4000));
    SEED("shm-open-next-lap-and-rewind", M_SERVER | M_SHM | M_OPEN, descriptor(&s, 0, 40000);
         descriptor(&s, FUZZ_RING, 20000); descriptor(&s, 2 * FUZZ_RING, 64));
    SEED("shm-open-outside-ring", M_SERVER | M_SHM | M_OPEN, descriptor(&s, FUZZ_RING - 64, 65));
    SEED("shm-open-huge-length", M_SERVER | M_SHM | M_OPEN, descriptor(&s, 0, UINT64_MAX));
    SEED("shm-open-overlap", M_SERVER | M_SHM | M_OPEN, descriptor(&s, 0, FUZZ_RING / 2);
         descriptor(&s, FUZZ_RING / 2, FUZZ_RING / 4); descriptor(&s, FUZZ_RING, 64));
    SEED("shm-open-credits", M_SERVER | M_SHM | M_OPEN, shm_credit(&s, 1, 0); shm_credit(&s, 1, 1 << 20);
         frame(&s, TSR_NET_PROTOCOL_VERSION, NET_CREDIT, "\1\0\0\0", 4));
    SEED("shm-open-second-ring", M_SERVER | M_SHM | M_OPEN, shm_credit(&s, 0, 0);
         frame(&s, TSR_NET_PROTOCOL_VERSION, NET_RING, "\0\0\1\0\0\0\0\0", 8));
#undef SEED
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: fuzz_net_replay DIR|FILE... | --write-seeds DIR\n");
        return 2;
    }
    setup();
    int failed = 0;
    unsigned count = 0;
    if (!strcmp(argv[1], "--write-seeds") && argc == 3)
        write_seeds(argv[2]);
    else
        for (int i = 1; i < argc; i++)
            failed |= replay(argv[i], &count);
    teardown();
    if (!failed && count)
        printf("fuzz_net_replay: %u inputs ran through netlib connections\n", count);
    return failed;
}

#endif
