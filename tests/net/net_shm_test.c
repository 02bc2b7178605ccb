/* tests/net/net_shm_test.c — netlib's shared memory between the two ends
 * of a Unix-socket connection (net.h, SHARED MEMORY), over real sockets,
 * real memfd rings and real threads: the bytes arrive whole through the
 * ring (tsr_net_send and the zero-copy reserve/commit), the statistics say
 * so, ring space is the credit (a held message stops the sender, its
 * release lets it go on), a new message takes the ring's start whenever
 * that is free (the pages in use are the messages in flight), it is negotiated only when both sides ask and
 * only on Unix sockets, and a peer that lies (descriptors outside the
 * ring, a ring that could be truncated, no segment, descriptors passed out
 * of place) fails its own connection with one line naming it, never the
 * process. One test per subcommand.
 * Never: mocks a netlib part; expected bytes come from the pattern. */
#include <fcntl.h>
#include <pthread.h>
#include <sys/mman.h>
#include <sys/un.h>

#include "net_test_util.h"

#define RING (1u << 20)

static char sock_path[108];
static int drop_released; /* make_net's shm_drop_released */

static tsr_net *make_net(const char *name, uint64_t ring)
{
    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.node_name = name;
    cfg.credits = 4;
    cfg.max_message_bytes = 4u << 20;
    cfg.connect_timeout_ms = 2000;
    cfg.handshake_timeout_ms = 2000;
    cfg.close_timeout_ms = 2000;
    cfg.shm_ring_bytes = ring;
    cfg.shm_drop_released = drop_released;
    tsr_error err = {0};
    tsr_net *net = tsr_net_create(&cfg, &err);
    CHECK(net, "tsr_net_create(%s): %s", name, err.message);
    return net;
}

typedef struct pair {
    tsr_net *server, *client;
    tsr_net_listener *l;
    tsr_net_conn *s, *c; /* server's and client's ends */
} pair;

static void open_pair(pair *p, const char *address, uint64_t server_ring, uint64_t client_ring)
{
    tsr_error err = {0};
    p->server = make_net("shm-server", server_ring);
    p->client = make_net("shm-client", client_ring);
    p->l = tsr_net_listen(p->server, address, &err);
    CHECK(p->l, "listen %s: %s", address, err.message);
    p->c = tsr_net_connect(p->client, tsr_net_listener_address(p->l), &err);
    CHECK(p->c, "connect: %s", err.message);
    p->s = tsr_net_accept(p->l, 2000, &err);
    CHECK(p->s, "accept: %s", err.message);
}

static void close_pair(pair *p)
{
    tsr_net_conn_close(p->c);
    tsr_net_conn_close(p->s);
    tsr_net_listener_close(p->l);
    tsr_net_destroy(p->client);
    tsr_net_destroy(p->server);
}

static const char *unix_address(void)
{
    static char a[128];
    snprintf(sock_path, sizeof sock_path, "/tmp/tsr-net-shm-%d.sock", (int)getpid());
    snprintf(a, sizeof a, "unix:%s", sock_path);
    return a;
}

/* Receives one message and checks it is `len` pattern bytes at stream
 * offset `at`; returns it held. */
static void recv_check(tsr_net_conn *c, uint64_t at, size_t len, tsr_net_msg *msg, const char *what)
{
    tsr_error err = {0};
    int rc = tsr_net_recv(c, msg, 5000, &err);
    CHECK(rc == 1, "%s: recv returned %d: %s", what, rc, err.message);
    CHECK(msg->len == len, "%s: %llu bytes, not %zu", what, (unsigned long long)msg->len, len);
    uint8_t *want = malloc(len ? len : 1);
    tsr_net_pattern_fill(want, at, len, 0);
    CHECK(!len || !memcmp(want, msg->data, len), "%s: bytes differ from the pattern", what);
    free(want);
}

/* ---- the bytes go through the ring, whole, and the statistics say so ---- */

static const size_t sizes[] = {0, 1, 63, 64, 65, 4095, 65536, 300001, RING / 2, RING + 5, 7, RING};

static int test_roundtrip(void)
{
    pair p;
    open_pair(&p, unix_address(), RING, RING);
    CHECK(!strcmp(tsr_net_conn_transport(p.c), "unix+shm"), "client transport %s", tsr_net_conn_transport(p.c));
    CHECK(!strcmp(tsr_net_conn_transport(p.s), "unix+shm"), "server transport %s", tsr_net_conn_transport(p.s));
    uint64_t at = 0, ring_msgs = 0, ring_bytes = 0, total = 0;
    size_t n = sizeof sizes / sizeof sizes[0];
    for (size_t i = 0; i < 2 * n; i++) {
        size_t len = sizes[i % n];
        tsr_error err = {0};
        uint8_t *src = malloc(len ? len : 1);
        tsr_net_pattern_fill(src, at, len, 0);
        if (i < n) { /* tsr_net_send: copied into the ring */
            CHECK(tsr_net_send(p.c, 0x20, src, len, 5000, &err) == TSR_OK, "send %zu: %s", len, err.message);
        } else { /* reserve/commit: built in place, a little over-reserved */
            void *buf;
            CHECK(tsr_net_send_reserve(p.c, len + 100, &buf, 5000, &err) == TSR_OK, "reserve %zu: %s", len,
                  err.message);
            memcpy(buf, src, len);
            CHECK(tsr_net_send_commit(p.c, 0x21, len, 5000, &err) == TSR_OK, "commit %zu: %s", len, err.message);
        }
        free(src);
        tsr_net_msg msg;
        recv_check(p.s, at, len, &msg, "round trip");
        CHECK(msg.kind == (i < n ? 0x20u : 0x21u), "kind %u", msg.kind);
        tsr_net_msg_release(&msg);
        /* What fits in the ring goes through it (a reservation too large
         * for it is a buffer, whose commit still goes through the ring
         * when the message itself fits). */
        if (len <= RING) {
            ring_msgs++;
            ring_bytes += len;
        }
        total += len;
        at += len;
    }
    tsr_net_stats cs, ss;
    tsr_net_conn_stats(p.c, &cs);
    tsr_net_conn_stats(p.s, &ss);
    printf("sent %llu messages (%llu bytes), %llu through the ring (%llu bytes); received %llu through it\n",
           (unsigned long long)cs.messages_sent, (unsigned long long)cs.bytes_sent,
           (unsigned long long)cs.messages_sent_shm, (unsigned long long)cs.bytes_sent_shm,
           (unsigned long long)ss.messages_received_shm);
    CHECK(cs.messages_sent == 2 * n && cs.bytes_sent == total, "sent %llu messages",
          (unsigned long long)cs.messages_sent);
    CHECK(cs.messages_sent_shm == ring_msgs && cs.bytes_sent_shm == ring_bytes, "ring: %llu messages %llu bytes",
          (unsigned long long)cs.messages_sent_shm, (unsigned long long)cs.bytes_sent_shm);
    CHECK(ss.messages_received_shm == ring_msgs && ss.bytes_received_shm == ring_bytes,
          "received through the ring: %llu", (unsigned long long)ss.messages_received_shm);
    CHECK(ss.messages_received == 2 * n, "received %llu", (unsigned long long)ss.messages_received);
    /* The other direction has its own ring. */
    uint8_t back[5000];
    tsr_net_pattern_fill(back, 0, sizeof back, 0);
    tsr_error err = {0};
    CHECK(tsr_net_send(p.s, 0x22, back, sizeof back, 5000, &err) == TSR_OK, "send back: %s", err.message);
    tsr_net_msg msg;
    recv_check(p.c, 0, sizeof back, &msg, "back");
    tsr_net_msg_release(&msg);
    tsr_net_conn_stats(p.c, &cs);
    CHECK(cs.messages_received_shm == 1, "the answer did not come through the server's ring");
    close_pair(&p);
    CHECK(access(sock_path, F_OK) != 0, "socket file left behind");
    printf("PASS\n");
    return 0;
}

/* ---- no copy: the receiver reads the very memory the sender wrote --------- */

static int test_zero_copy(void)
{
    pair p;
    open_pair(&p, unix_address(), RING, RING);
    tsr_error err = {0};
    void *buf;
    const size_t len = 100000;
    CHECK(tsr_net_send_reserve(p.c, len, &buf, 2000, &err) == TSR_OK, "reserve: %s", err.message);
    tsr_net_pattern_fill(buf, 0, len, 0);
    CHECK(tsr_net_send_commit(p.c, 0x20, len, 2000, &err) == TSR_OK, "commit: %s", err.message);
    tsr_net_msg m;
    recv_check(p.s, 0, len, &m, "zero copy");
    /* Two mappings of one memfd: what the sender writes now (it must not,
     * outside a test) shows in the message the receiver holds. */
    volatile uint8_t *mine = buf, *theirs = m.data;
    CHECK((void *)theirs != buf, "one address space? the receiver's pointer is the sender's");
    for (size_t i = 0; i < len; i += 4096) {
        mine[i] = (uint8_t)(theirs[i] ^ 0xff);
        CHECK(theirs[i] == mine[i], "byte %zu is a copy: the sender's write did not show", i);
    }
    printf("the received message is the sender's ring memory (%zu bytes, no copy)\n", len);
    tsr_net_msg_release(&m);
    close_pair(&p);
    printf("PASS\n");
    return 0;
}

/* ---- ring space is the credit ------------------------------------------------ */

static void send_pattern(tsr_net_conn *c, uint64_t at, size_t len, int timeout_ms, int want_rc, const char *want_text)
{
    uint8_t *src = malloc(len);
    tsr_net_pattern_fill(src, at, len, 0);
    tsr_error err = {0};
    int rc = tsr_net_send(c, 0x30, src, len, timeout_ms, &err);
    free(src);
    CHECK(rc == want_rc, "send of %zu at %llu returned %d, not %d: %s", len, (unsigned long long)at, rc, want_rc,
          err.message);
    if (want_text)
        CHECK(contains(err.message, want_text), "error '%s' does not say '%s'", err.message, want_text);
}

static int test_ring_is_the_credit(void)
{
    pair p;
    open_pair(&p, unix_address(), RING, RING);
    const size_t big = 300 * 1024; /* three fit in the ring, a fourth not */
    for (int i = 0; i < 3; i++)
        send_pattern(p.c, (uint64_t)i * big, big, 2000, TSR_OK, NULL);
    tsr_net_msg m0, m;
    recv_check(p.s, 0, big, &m0, "m0"); /* held: the ring cannot pass it */
    recv_check(p.s, big, big, &m, "m1");
    tsr_net_msg_release(&m);
    recv_check(p.s, 2 * big, big, &m, "m2");
    tsr_net_msg_release(&m);
    /* Credits are back (two of four released), ring space is not. */
    uint64_t t0 = test_now_ms();
    send_pattern(p.c, 3 * big, big, 300, TSR_ETIMEDOUT, "shared-memory ring");
    uint64_t waited = test_now_ms() - t0;
    printf("a fourth message waited %llu ms for ring space while the first was held\n", (unsigned long long)waited);
    /* send_pattern checked TSR_ETIMEDOUT naming the ring: the send waited for
     * ring space. A time-out never fires early (load only delays it), so
     * only the lower bound is checked. */
    CHECK(waited >= 250, "waited %llu ms, less than the 300 ms asked", (unsigned long long)waited);
    /* The data m0 points to is intact while held. */
    uint8_t *want = malloc(big);
    tsr_net_pattern_fill(want, 0, big, 0);
    CHECK(!memcmp(want, m0.data, big), "a held message changed under the receiver");
    free(want);
    tsr_net_msg_release(&m0);
    send_pattern(p.c, 3 * big, big, 2000, TSR_OK, NULL);
    recv_check(p.s, 3 * big, big, &m, "m3 after the release");
    tsr_net_msg_release(&m);
    /* Many more than the ring holds, streamed by a second thread's pace:
     * the ring is reused. */
    for (int i = 0; i < 40; i++) {
        send_pattern(p.c, (uint64_t)(4 + i) * big, big, 2000, TSR_OK, NULL);
        recv_check(p.s, (uint64_t)(4 + i) * big, big, &m, "stream");
        tsr_net_msg_release(&m);
    }
    tsr_net_stats st;
    tsr_net_conn_stats(p.c, &st);
    CHECK(st.messages_sent_shm == 44, "%llu of 44 through the ring", (unsigned long long)st.messages_sent_shm);
    close_pair(&p);
    printf("PASS\n");
    return 0;
}

/* ---- lowest offsets first: the pages in use are the messages in flight ---- */

/* Waits until the sender has every credit back but `held` (the receiver
 * released the others and its CREDIT, which carries the ring position,
 * has reached the sender's I/O thread). */
static void wait_credits(tsr_net_conn *c, uint64_t held)
{
    tsr_net_stats st;
    uint64_t t0 = test_now_ms();
    do {
        tsr_net_conn_stats(c, &st);
        if (st.messages_unreturned <= held)
            return;
        usleep(1000);
    } while (test_now_ms() - t0 < 20000); /* a hang guard, not a speed */
    CHECK(0, "%llu messages unreturned after 20 s, %llu held", (unsigned long long)st.messages_unreturned,
          (unsigned long long)held);
}

static int test_ring_reuses_its_start(void)
{
    pair p;
    open_pair(&p, unix_address(), RING, RING);
    const size_t big = 300 * 1024;
    tsr_net_msg held, m;
    send_pattern(p.c, 0, big, 2000, TSR_OK, NULL);
    recv_check(p.s, 0, big, &held, "m0");
    const uint8_t *start = held.data;
    /* The receiver holds one message while the next is written (a peer a
     * frame ahead): each new one goes to the ring's start whenever that
     * is free, so two places serve the whole stream. */
    const uint8_t *seen[4] = {start};
    int places = 1;
    for (int i = 1; i <= 30; i++) {
        send_pattern(p.c, (uint64_t)i * big, big, 2000, TSR_OK, NULL);
        recv_check(p.s, (uint64_t)i * big, big, &m, "stream");
        tsr_net_msg_release(&held);
        held = m;
        wait_credits(p.c, 1);
        int known = 0;
        for (int k = 0; k < places; k++)
            known |= seen[k] == (const uint8_t *)m.data;
        if (!known) {
            CHECK(places < 4, "message %d at ring offset %td: more than 2 places used", i,
                  (const uint8_t *)m.data - start);
            seen[places++] = m.data;
        }
    }
    tsr_net_msg_release(&held);
    printf("31 messages of %zu bytes, one always held, used %d places of the %u-byte ring\n", big, places, RING);
    CHECK(places == 2, "%d places, expected 2 (offset 0 and right after it)", places);
    CHECK((size_t)(seen[1] - start) == big, "the second place is at offset %td, not %zu", seen[1] - start, big);
    close_pair(&p);
    printf("PASS\n");
    return 0;
}

/* ---- a sender that waits for the releases writes at the ring's start ---- */

/* A sort-last peer knows (from its display's barrier) that its partner
 * released every image, but the CREDIT saying so may still be on its way:
 * without waiting for it the next message goes behind the released one, on
 * pages of its own, and over a run every ring comes to hold two messages'
 * pages in both processes. tsr_net_conn_wait_returned waits for it (and
 * times out naming the peer while a message is really held). */
static int test_wait_returned(void)
{
    pair p;
    open_pair(&p, unix_address(), RING, RING);
    const size_t big = 200 * 1024; /* the ring holds five */
    tsr_net_msg m;
    tsr_error err = {0};
    send_pattern(p.c, 0, big, 2000, TSR_OK, NULL);
    recv_check(p.s, 0, big, &m, "m0");
    const uint8_t *start = m.data;
    int rc = tsr_net_conn_wait_returned(p.c, 200, &err);
    CHECK(rc == TSR_ETIMEDOUT, "waiting while the receiver holds a message: %d (%s), not a time-out", rc, err.message);
    CHECK_CONTAINS(err.message, "shm-server");
    tsr_net_msg_release(&m);
    int behind = 0;
    const int n = 300;
    for (int i = 1; i <= n; i++) {
        rc = tsr_net_conn_wait_returned(p.c, 2000, &err);
        CHECK(rc == TSR_OK, "wait_returned after every release: %d (%s)", rc, err.message);
        send_pattern(p.c, (uint64_t)i * big, big, 2000, TSR_OK, NULL);
        recv_check(p.s, (uint64_t)i * big, big, &m, "stream");
        behind += (const uint8_t *)m.data != start;
        tsr_net_msg_release(&m);
    }
    printf("%d messages of %zu bytes, each sent right after the last one's release: %d behind the ring's start\n", n,
           big, behind);
    CHECK(behind == 0, "%d of %d messages went behind a released one (fresh pages)", behind, n);
    close_pair(&p);
    printf("PASS\n");
    return 0;
}

/* ---- shm_drop_released: a ring page resident in the sender only --------- */

/* Rss (kB) of this process's mapping that holds addr (/proc/self/smaps). */
static long mapping_rss_kb(const void *addr)
{
    FILE *f = fopen("/proc/self/smaps", "r");
    CHECK(f, "cannot open /proc/self/smaps");
    char line[512];
    int inside = 0;
    long kb = -1;
    uintptr_t a = (uintptr_t)addr;
    while (kb < 0 && fgets(line, sizeof line, f)) {
        unsigned long lo, hi;
        if (sscanf(line, "%lx-%lx ", &lo, &hi) == 2 && strchr(line, '-') < strchr(line, ' '))
            inside = a >= lo && a < hi;
        else if (inside && sscanf(line, "Rss: %ld kB", &kb) == 1)
            break;
    }
    fclose(f);
    CHECK(kb >= 0, "no mapping holds %p", addr);
    return kb;
}

static int drop_case(int drop, long *held_kb, long *released_kb)
{
    drop_released = drop;
    pair p;
    open_pair(&p, unix_address(), RING, RING);
    const size_t big = 768 * 1024;
    tsr_net_msg m;
    for (int i = 0; i < 3; i++) { /* the bytes survive the drop: read again through the same pages */
        send_pattern(p.c, (uint64_t)i * big, big, 2000, TSR_OK, NULL);
        recv_check(p.s, (uint64_t)i * big, big, &m, "message");
        const void *at = m.data;
        *held_kb = mapping_rss_kb(at);
        tsr_net_msg_release(&m);
        *released_kb = mapping_rss_kb(at);
        tsr_error err = {0};
        CHECK(tsr_net_conn_wait_returned(p.c, 2000, &err) == TSR_OK, "%s", err.message);
    }
    close_pair(&p);
    drop_released = 0;
    return 0;
}

static int test_drop_released(void)
{
    long held, released;
    drop_case(1, &held, &released);
    printf("shm_drop_released=1: the receiver's ring mapping %ld kB while held, %ld kB once released\n", held,
           released);
    CHECK(held >= 768, "the received message is not resident while read (%ld kB)", held);
    CHECK(released == 0, "%ld kB of the receiver's mapping stay resident after the release", released);
    drop_case(0, &held, &released);
    printf("shm_drop_released=0: %ld kB while held, %ld kB once released\n", held, released);
    CHECK(released >= 768, "without the option the pages stay mapped (%ld kB)", released);
    printf("PASS\n");
    return 0;
}

/* ---- negotiated only when both ask, only on Unix sockets ------------------- */

static void exchange_one(pair *p, const char *want_transport, int want_shm)
{
    CHECK(!strcmp(tsr_net_conn_transport(p->c), want_transport), "client transport %s, not %s",
          tsr_net_conn_transport(p->c), want_transport);
    CHECK(!strcmp(tsr_net_conn_transport(p->s), want_transport), "server transport %s, not %s",
          tsr_net_conn_transport(p->s), want_transport);
    send_pattern(p->c, 0, 100000, 2000, TSR_OK, NULL);
    tsr_net_msg m;
    recv_check(p->s, 0, 100000, &m, "negotiation");
    tsr_net_msg_release(&m);
    tsr_net_stats st;
    tsr_net_conn_stats(p->s, &st);
    CHECK((st.messages_received_shm == 1) == want_shm, "%llu messages through the ring",
          (unsigned long long)st.messages_received_shm);
    printf("%s: %s\n", tsr_net_conn_address(p->c), want_transport);
}

static int test_negotiation(void)
{
    pair p;
    open_pair(&p, unix_address(), 0, RING); /* the server does not ask */
    exchange_one(&p, "unix", 0);
    close_pair(&p);
    open_pair(&p, unix_address(), RING, 0); /* the client does not ask */
    exchange_one(&p, "unix", 0);
    close_pair(&p);
    open_pair(&p, "tcp://127.0.0.1:0", RING, RING); /* TCP: never */
    exchange_one(&p, "tcp", 0);
    close_pair(&p);
    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.shm_ring_bytes = 1000; /* not a page multiple, too small */
    tsr_error err = {0};
    CHECK(!tsr_net_create(&cfg, &err) && contains(err.message, "shm_ring_bytes 1000"), "bad ring size: %s",
          err.message);
    printf("PASS\n");
    return 0;
}

/* ---- a lying peer ----------------------------------------------------------- */

/* A raw client that handshakes asking for shared memory (features byte 1,
 * written by hand from net.h) and then does what `lie` says. */
static int raw_shm_client(void)
{
    int fd = socket(AF_UNIX, SOCK_STREAM, 0);
    CHECK(fd >= 0, "socket");
    struct sockaddr_un sa = {.sun_family = AF_UNIX};
    snprintf(sa.sun_path, sizeof sa.sun_path, "%s", sock_path);
    CHECK(connect(fd, (struct sockaddr *)&sa, sizeof sa) == 0, "connect %s: %s", sock_path, strerror(errno));
    uint8_t msg[600];
    size_t n = raw_hello(msg, "liar", 4, NULL);
    msg[n++] = 1; /* features: shared memory */
    put_le(msg + 8, n - 16, 8);
    raw_write_all(fd, msg, n);
    uint8_t buf[4096];
    size_t len;
    int type = raw_read_msg(fd, buf, &len);
    CHECK(type == 0x02, "answer type 0x%02x, not WELCOME", type);
    CHECK(len >= 1 && buf[len - 1] == 1, "WELCOME does not grant shared memory");
    return fd;
}

/* Sends header+payload with `pass_fd` attached (SCM_RIGHTS) when >= 0. */
static void send_with_fd(int fd, const uint8_t *data, size_t len, int pass_fd)
{
    struct iovec iov = {.iov_base = (void *)data, .iov_len = len};
    union {
        char buf[CMSG_SPACE(sizeof(int))];
        struct cmsghdr align;
    } u;
    struct msghdr mh = {.msg_iov = &iov, .msg_iovlen = 1};
    if (pass_fd >= 0) {
        memset(&u, 0, sizeof u);
        mh.msg_control = u.buf;
        mh.msg_controllen = sizeof u.buf;
        struct cmsghdr *cm = CMSG_FIRSTHDR(&mh);
        cm->cmsg_level = SOL_SOCKET;
        cm->cmsg_type = SCM_RIGHTS;
        cm->cmsg_len = CMSG_LEN(sizeof(int));
        memcpy(CMSG_DATA(cm), &pass_fd, sizeof(int));
    }
    CHECK(sendmsg(fd, &mh, MSG_NOSIGNAL) == (ssize_t)len, "sendmsg: %s", strerror(errno));
}

static int make_ring_fd(uint64_t size, int seal)
{
    int fd = memfd_create("liar-ring", MFD_CLOEXEC | MFD_ALLOW_SEALING);
    CHECK(fd >= 0 && ftruncate(fd, (off_t)size) == 0, "memfd: %s", strerror(errno));
    if (seal)
        CHECK(fcntl(fd, F_ADD_SEALS, F_SEAL_SHRINK | F_SEAL_GROW) == 0, "seal: %s", strerror(errno));
    return fd;
}

static void send_ring(int fd, uint64_t size, int pass_fd)
{
    uint8_t m[24];
    raw_header(m, TSR_NET_PROTOCOL_VERSION, 0x09, 8);
    put_le(m + 16, size, 8);
    send_with_fd(fd, m, sizeof m, pass_fd);
}

static void send_descriptor(int fd, uint64_t pos, uint64_t len)
{
    uint8_t m[32];
    raw_header(m, TSR_NET_PROTOCOL_VERSION, 0x20, 16);
    m[7] = 0x01;
    put_le(m + 16, pos, 8);
    put_le(m + 24, len, 8);
    raw_write_all(fd, m, sizeof m);
}

typedef enum { LIE_OUTSIDE, LIE_OVERLAP, LIE_PLACE, LIE_NO_FD, LIE_UNSEALED, LIE_SIZE, LIE_STRAY_FD, LIE_EARLY } lie;
static const struct {
    lie what;
    const char *name, *expect;
} lies[] = {
    {LIE_OUTSIDE, "descriptor past the end of the ring", "descriptor outside the ring"},
    {LIE_OVERLAP, "descriptor over a message not released", "over messages not yet released"},
    {LIE_PLACE, "descriptor not where the last message ended", "not where the previous message ended"},
    {LIE_NO_FD, "RING without a segment", "no memory segment came with it"},
    {LIE_UNSEALED, "RING with a memfd that could be truncated", "not a memfd sealed against resizing"},
    {LIE_SIZE, "RING announcing more than the segment has", "not a file of the"},
    {LIE_STRAY_FD, "a descriptor passed with a data message", "file descriptor out of place"},
    {LIE_EARLY, "a ring descriptor before any RING", "descriptor before its ring"},
};

static int test_lying_peer(void)
{
    tsr_net *server = make_net("honest", RING);
    tsr_error err = {0};
    tsr_net_listener *l = tsr_net_listen(server, unix_address(), &err);
    CHECK(l, "listen: %s", err.message);
    for (size_t i = 0; i < sizeof lies / sizeof lies[0]; i++) {
        int fd = raw_shm_client();
        tsr_net_conn *s = tsr_net_accept(l, 2000, &err);
        CHECK(s, "accept: %s", err.message);
        uint64_t size = RING;
        int ring = -1;
        switch (lies[i].what) {
        case LIE_NO_FD: send_ring(fd, size, -1); break;
        case LIE_UNSEALED: send_ring(fd, size, ring = make_ring_fd(size, 0)); break;
        case LIE_SIZE: send_ring(fd, 2 * size, ring = make_ring_fd(size, 1)); break;
        case LIE_EARLY: send_descriptor(fd, 0, 10); break;
        default: send_ring(fd, size, ring = make_ring_fd(size, 1)); break;
        }
        switch (lies[i].what) {
        case LIE_OUTSIDE: send_descriptor(fd, size - 64, 65); break;
        case LIE_OVERLAP:
            send_descriptor(fd, 0, size / 2); /* delivered, held below */
            send_descriptor(fd, size / 2, size / 4);
            send_descriptor(fd, size, 100); /* next lap: over the first, still held */
            break;
        case LIE_PLACE: send_descriptor(fd, 128, 10); break;
        case LIE_STRAY_FD: {
            uint8_t m[16 + 4];
            raw_header(m, TSR_NET_PROTOCOL_VERSION, 0x20, 4);
            int extra = make_ring_fd(size, 1);
            send_with_fd(fd, m, sizeof m, extra);
            close(extra);
            break;
        }
        default: break;
        }
        if (ring >= 0)
            close(ring);
        /* The honest side receives what was correct, then the failure. */
        tsr_net_msg held[4];
        int nheld = 0, rc;
        while ((rc = tsr_net_recv(s, &held[nheld], 3000, &err)) == 1 && nheld < 3)
            nheld++;
        printf("%s: %s\n", lies[i].name, err.message);
        CHECK(rc < 0 && rc != TSR_ETIMEDOUT, "%s: recv returned %d (%s), not the connection's failure", lies[i].name,
              rc, err.message);
        CHECK(contains(err.message, lies[i].expect), "%s: '%s' does not say '%s'", lies[i].name, err.message,
              lies[i].expect);
        CHECK(contains(err.message, "peer 'liar'"), "%s: '%s' does not name the peer", lies[i].name, err.message);
        CHECK(!strchr(err.message, '\n'), "more than one line");
        while (nheld > 0)
            tsr_net_msg_release(&held[--nheld]);
        tsr_net_conn_close(s);
        close(fd);
    }
    /* The node is unharmed: an honest client still gets through its ring. */
    tsr_net *client = make_net("shm-client", RING);
    tsr_net_conn *c = tsr_net_connect(client, tsr_net_listener_address(l), &err);
    CHECK(c, "connect after the lies: %s", err.message);
    tsr_net_conn *s = tsr_net_accept(l, 2000, &err);
    CHECK(s, "accept: %s", err.message);
    pair p = {.s = s, .c = c};
    exchange_one(&p, "unix+shm", 1);
    tsr_net_conn_close(c);
    tsr_net_conn_close(s);
    tsr_net_listener_close(l);
    tsr_net_destroy(client);
    tsr_net_destroy(server);
    printf("PASS\n");
    return 0;
}

int main(int argc, char **argv)
{
    static const struct {
        const char *name;
        int (*run)(void);
    } tests[] = {
        {"roundtrip", test_roundtrip},
        {"zero_copy", test_zero_copy},
        {"ring_is_the_credit", test_ring_is_the_credit},
        {"ring_reuses_its_start", test_ring_reuses_its_start},
        {"wait_returned", test_wait_returned},
        {"drop_released", test_drop_released},
        {"negotiation", test_negotiation},
        {"lying_peer", test_lying_peer},
    };
    setvbuf(stdout, NULL, _IOLBF, 0);
    for (size_t i = 0; argc == 2 && i < sizeof tests / sizeof tests[0]; i++)
        if (!strcmp(argv[1], tests[i].name))
            return tests[i].run();
    fprintf(stderr, "usage: net_shm_test TEST\n");
    return 2;
}
