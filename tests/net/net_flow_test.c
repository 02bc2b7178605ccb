/* tests/net/net_flow_test.c — credit flow control against a stalled
 * receiver in another process (net_stall_server, fork/exec'd): the sender
 * must block while the receiver does not consume, both processes' VmRSS
 * must stay within credits x message size plus a fixed margin, and after
 * the stall every byte must arrive exactly.
 * Mode "kill": the stalled receiver is killed (SIGKILL) while the sender
 * is blocked on credits; the send must fail with TSR_EIO naming the peer
 * (not time out).
 * Never: passes on timing luck — the blocked send is located exactly. */
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <sys/wait.h>

#include "net_test_util.h"

#if defined(__SANITIZE_ADDRESS__)
/* Measure live memory, not ASan's quarantine of freed blocks. */
const char *__asan_default_options(void);
const char *__asan_default_options(void) { return "quarantine_size_mb=0"; }
#endif

enum {
    CREDITS = 8,
    MESSAGE_BYTES = 1 << 20,
    MESSAGES = 96, /* 96 MiB: far above the bound if anything buffered it */
    STALL_AFTER = 10,
    STALL_MS = 3000,
    MARGIN_KB = 8 * 1024,
};

typedef struct monitor {
    pid_t child;
    atomic_int stop;
    long peak_self_kb, peak_child_kb;
} monitor;

static void *monitor_main(void *arg)
{
    monitor *m = arg;
    while (!atomic_load(&m->stop)) {
        long self = rss_kb(0), child = rss_kb(m->child);
        if (self > m->peak_self_kb)
            m->peak_self_kb = self;
        if (child > m->peak_child_kb)
            m->peak_child_kb = child;
        usleep(20000);
    }
    return NULL;
}

static int read_line(FILE *f, char *line, size_t size, const char *want)
{
    while (fgets(line, (int)size, f)) {
        printf("server: %s", line);
        if (!strncmp(line, "error", 5))
            return -1;
        if (!strncmp(line, want, strlen(want)))
            return 0;
    }
    return -1;
}

static pid_t spawn_server(const char *helper, int stall_ms_value, FILE **from_child)
{
    int out[2];
    CHECK(pipe(out) == 0, "pipe: %s", strerror(errno));
    char credits[16], message_bytes[32], total[32], stall_after[16], stall_ms[16];
    snprintf(credits, sizeof credits, "%d", CREDITS);
    snprintf(message_bytes, sizeof message_bytes, "%d", MESSAGE_BYTES);
    snprintf(total, sizeof total, "%llu", (unsigned long long)MESSAGES * MESSAGE_BYTES);
    snprintf(stall_after, sizeof stall_after, "%d", STALL_AFTER);
    snprintf(stall_ms, sizeof stall_ms, "%d", stall_ms_value);
    pid_t child = fork();
    CHECK(child >= 0, "fork: %s", strerror(errno));
    if (child == 0) {
        dup2(out[1], 1);
        close(out[0]);
        close(out[1]);
        execl(helper, helper, credits, message_bytes, total, stall_after, stall_ms, (char *)NULL);
        _exit(127);
    }
    close(out[1]);
    *from_child = fdopen(out[0], "r");
    return child;
}

typedef struct blocked_sender {
    tsr_net_conn *conn;
    int rc;
    tsr_error err;
    uint64_t failed_at_ms;
    atomic_uint sent; /* sends that returned TSR_OK */
} blocked_sender;

static void *blocked_sender_main(void *arg)
{
    blocked_sender *b = arg;
    uint8_t *source = malloc(MESSAGE_BYTES);
    for (unsigned k = 0; k < MESSAGES && !b->rc; k++) {
        tsr_net_pattern_fill(source, (uint64_t)k * MESSAGE_BYTES, MESSAGE_BYTES, 0);
        b->rc = tsr_net_send(b->conn, TSR_NET_KIND_FIRST_USER, source, MESSAGE_BYTES, 15000, &b->err);
        if (!b->rc)
            atomic_fetch_add(&b->sent, 1);
    }
    b->failed_at_ms = test_now_ms();
    free(source);
    return NULL;
}

/* The receiver dies while the sender waits for credits. */
static int killed_receiver(const char *helper)
{
    FILE *from_child;
    pid_t child = spawn_server(helper, 20000, &from_child);
    char line[512], address[256];
    CHECK(read_line(from_child, line, sizeof line, "listening ") == 0, "server did not listen");
    CHECK(sscanf(line, "listening %255s", address) == 1, "bad line %s", line);
    tsr_error err = {0};
    tsr_net *net = tsr_net_create(NULL, &err);
    CHECK(net, "create: %s", err.message);
    blocked_sender b = {.conn = tsr_net_connect(net, address, &err)};
    CHECK(b.conn, "connect: %s", err.message);
    pthread_t thread;
    pthread_create(&thread, NULL, blocked_sender_main, &b);
    CHECK(read_line(from_child, line, sizeof line, "stalling") == 0, "server did not stall");
    /* The sender has used its credits once exactly STALL_AFTER + CREDITS
     * sends returned: the next one waits. Polled, bounded (20 s). */
    for (int i = 0; i < 2000 && atomic_load(&b.sent) < STALL_AFTER + CREDITS && !b.rc; i++)
        usleep(10000);
    CHECK(atomic_load(&b.sent) == STALL_AFTER + CREDITS, "%u sends returned before the kill; credits allow exactly %d",
          atomic_load(&b.sent), STALL_AFTER + CREDITS);
    uint64_t killed_at = test_now_ms();
    kill(child, SIGKILL);
    int status;
    waitpid(child, &status, 0);
    pthread_join(thread, NULL);
    uint64_t took = b.failed_at_ms - killed_at;
    printf("send failed %llu ms after SIGKILL: %s\n", (unsigned long long)took, b.err.message);
    CHECK(b.rc == TSR_EIO && contains(b.err.message, "stalling-server") && contains(b.err.message, address),
          "unclear error %s: %s", tsr_error_name(b.rc), b.err.message);
    /* TSR_EIO naming the peer, not the send's 15 s TSR_ETIMEDOUT: the
     * sender noticed the death; the time is printed, not judged. */
    tsr_net_conn_close(b.conn);
    tsr_net_destroy(net);
    fclose(from_child);
    return 0;
}

static int stalled_receiver(const char *helper)
{
    FILE *from_child;
    pid_t child = spawn_server(helper, STALL_MS, &from_child);
    char line[512], address[256];
    CHECK(read_line(from_child, line, sizeof line, "listening ") == 0, "server did not listen");
    CHECK(sscanf(line, "listening %255s", address) == 1, "bad line %s", line);

    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.node_name = "streaming-client";
    tsr_error err = {0};
    tsr_net *net = tsr_net_create(&cfg, &err);
    CHECK(net, "create: %s", err.message);
    tsr_net_conn *c = tsr_net_connect(net, address, &err);
    CHECK(c, "connect: %s", err.message);
    CHECK(read_line(from_child, line, sizeof line, "accepted") == 0, "server did not accept");

    uint8_t *source = malloc(MESSAGE_BYTES);
    tsr_net_pattern_fill(source, 0, MESSAGE_BYTES, 0); /* touch it before the baseline */
    usleep(100000);
    long base_self = rss_kb(0), base_child = rss_kb(child);
    monitor mon = {.child = child, .peak_self_kb = base_self, .peak_child_kb = base_child};
    pthread_t mon_thread;
    pthread_create(&mon_thread, NULL, monitor_main, &mon);

    uint64_t returned_ms[MESSAGES + 1];
    uint64_t fnv = TSR_NET_FNV_START;
    returned_ms[0] = test_now_ms();
    for (unsigned k = 0; k < MESSAGES; k++) {
        tsr_net_pattern_fill(source, (uint64_t)k * MESSAGE_BYTES, MESSAGE_BYTES, 0);
        fnv = tsr_net_fnv1a(fnv, source, MESSAGE_BYTES);
        CHECK_OK(tsr_net_send(c, TSR_NET_KIND_FIRST_USER, source, MESSAGE_BYTES, 10000, &err), err);
        returned_ms[k + 1] = test_now_ms();
    }
    tsr_net_stats st;
    tsr_net_conn_stats(c, &st);
    tsr_net_conn_close(c);
    CHECK(read_line(from_child, line, sizeof line, "done ") == 0, "server did not finish");
    unsigned long long got_bytes = 0, got_fnv = 0;
    unsigned got_messages = 0;
    CHECK(sscanf(line, "done bytes=%llu messages=%u fnv=%llx", &got_bytes, &got_messages, &got_fnv) == 3, "bad line %s",
          line);
    atomic_store(&mon.stop, 1);
    pthread_join(mon_thread, NULL);
    int status = 0;
    CHECK(waitpid(child, &status, 0) == child, "waitpid: %s", strerror(errno));
    tsr_net_destroy(net);
    fclose(from_child);
    free(source);

    /* The send that blocked: the longest wait between two returns. */
    unsigned blocked = 0;
    uint64_t longest = 0;
    for (unsigned k = 1; k <= MESSAGES; k++)
        if (returned_ms[k] - returned_ms[k - 1] > longest) {
            longest = returned_ms[k] - returned_ms[k - 1];
            blocked = k;
        }
    printf("send #%u blocked for %llu ms; %u sends returned before it (receiver consumed %d, "
           "granted %d credits); blocked on credits %.3f s in total\n",
           blocked, (unsigned long long)longest, blocked - 1, STALL_AFTER, CREDITS,
           (double)st.blocked_on_credits_ns / 1e9);
    long bound_kb = (long)(CREDITS + 2) * (MESSAGE_BYTES / 1024) + MARGIN_KB;
    printf("VmRSS client: baseline %ld KiB, peak %ld KiB, growth %ld KiB\n", base_self, mon.peak_self_kb,
           mon.peak_self_kb - base_self);
    printf("VmRSS server: baseline %ld KiB, peak %ld KiB, growth %ld KiB\n", base_child, mon.peak_child_kb,
           mon.peak_child_kb - base_child);
    printf("bound: (credits %d + 2) x %d KiB + %d KiB margin = %ld KiB; streamed %d MiB\n", CREDITS,
           MESSAGE_BYTES / 1024, MARGIN_KB, bound_kb, (int)((uint64_t)MESSAGES * MESSAGE_BYTES >> 20));
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0, "server exited with status %d", status);
    /* That the sender blocked is counted (credits wait time > 0 and the
     * exact send that waited, below), not timed: under load the sender may
     * reach the block late in the stall. */
    CHECK(st.blocked_on_credits_ns > 0, "no send blocked on credits during the %d ms stall (longest gap %llu ms)",
          STALL_MS, (unsigned long long)longest);
    CHECK(blocked - 1 == STALL_AFTER + CREDITS, "%u sends returned before the block; credits allow exactly %d",
          blocked - 1, STALL_AFTER + CREDITS);
#if defined(__SANITIZE_THREAD__)
    printf("memory bound not checked: ThreadSanitizer's allocator keeps freed memory\n");
#else
    CHECK(mon.peak_self_kb - base_self <= bound_kb, "client memory grew by %ld KiB > %ld KiB",
          mon.peak_self_kb - base_self, bound_kb);
    CHECK(mon.peak_child_kb - base_child <= bound_kb, "server memory grew by %ld KiB > %ld KiB",
          mon.peak_child_kb - base_child, bound_kb);
#endif
    CHECK(got_bytes == (unsigned long long)MESSAGES * MESSAGE_BYTES && got_messages == MESSAGES,
          "server received %llu bytes in %u messages", got_bytes, got_messages);
    CHECK(got_fnv == fnv, "checksum: sent %016llx, received %016llx", (unsigned long long)fnv, got_fnv);
    printf("all %d MiB arrived exactly (fnv1a %016llx)\n", (int)((uint64_t)MESSAGES * MESSAGE_BYTES >> 20), got_fnv);
    return 0;
}

int main(int argc, char **argv)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    if (argc == 3 && !strcmp(argv[1], "stall"))
        return stalled_receiver(argv[2]);
    if (argc == 3 && !strcmp(argv[1], "kill"))
        return killed_receiver(argv[2]);
    fprintf(stderr, "usage: net_flow_test stall|kill PATH/net_stall_server\n");
    return 2;
}
