/* bench/bench_shm.c — how fast image-sized messages cross between two
 * threads of netlib connections on one host: through the shared-memory
 * ring of a Unix-socket connection (tessera/dev/net.h, SHARED MEMORY; the
 * sender builds each message in the ring with tsr_net_send_reserve/commit,
 * the receiver copies it out of its mapping), through the same Unix socket
 * without the ring (the sender builds it in its own buffer, tsr_net_send,
 * the kernel copies it in and out), and memcpy of the same bytes in the
 * same run, the bandwidth reference: a message has to be written once and
 * read once, which is at least one memcpy of it.
 * Figures (MB = 10^6 message bytes per second of wall time, best of the
 * repeats): shm_mbytes, unix_socket_mbytes, memcpy_mbytes, shm_vs_memcpy
 * (1 would be a message moved at the cost of one memcpy), shm_vs_unix.
 * Owns only its threads, connections and buffers; reports, never pass/fail. */
#include "bench_common.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "tessera/dev/net.h"

#define MESSAGE (8u << 20) /* about a 1920x1080 RGBA8 + depth strip pair */

static double wall_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

typedef struct receiver {
    tsr_net_conn *conn;
    uint8_t *dst;
    unsigned count;
    int failed;
    tsr_error err;
} receiver;

static void *receive_main(void *arg)
{
    receiver *r = arg;
    for (unsigned i = 0; i < r->count; i++) {
        tsr_net_msg m;
        if (tsr_net_recv(r->conn, &m, 10000, &r->err) != 1) {
            r->failed = 1;
            return NULL;
        }
        memcpy(r->dst, m.data, (size_t)m.len); /* the decoder's read */
        bench_keep(r->dst);
        tsr_net_msg_release(&m);
    }
    return NULL;
}

/* MB/s of `count` messages from one thread to another; -1 on failure. */
static double run(int shm, unsigned count, const uint8_t *src, uint8_t *dst)
{
    char path[96], address[128];
    snprintf(path, sizeof path, "/tmp/tsr-bench-shm-%ld.sock", (long)getpid());
    snprintf(address, sizeof address, "unix:%s", path);
    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.max_message_bytes = 2 * MESSAGE;
    cfg.shm_ring_bytes = shm ? 4 * (uint64_t)MESSAGE : 0;
    tsr_error err = {0};
    tsr_net *a = tsr_net_create(&cfg, &err), *b = tsr_net_create(&cfg, &err);
    tsr_net_listener *l = a ? tsr_net_listen(a, address, &err) : NULL;
    tsr_net_conn *c = l && b ? tsr_net_connect(b, tsr_net_listener_address(l), &err) : NULL;
    tsr_net_conn *s = c ? tsr_net_accept(l, 5000, &err) : NULL;
    double mbytes = -1;
    if (!s) {
        fprintf(stderr, "bench_shm: %s\n", err.message);
        goto out;
    }
    const char *want = shm ? "unix+shm" : "unix";
    if (strcmp(tsr_net_conn_transport(c), want)) {
        fprintf(stderr, "bench_shm: the connection is %s, not %s\n", tsr_net_conn_transport(c), want);
        goto out;
    }
    uint8_t *own = shm ? NULL : malloc(MESSAGE);
    receiver r = {.conn = s, .dst = dst, .count = count};
    pthread_t th;
    double t0 = wall_now();
    pthread_create(&th, NULL, receive_main, &r);
    int bad = 0;
    for (unsigned i = 0; i < count && !bad; i++) {
        if (shm) { /* built in the ring the peer maps */
            void *buf;
            bad = tsr_net_send_reserve(c, MESSAGE, &buf, 10000, &err) ||
                  (memcpy(buf, src, MESSAGE), tsr_net_send_commit(c, 0x20, MESSAGE, 10000, &err));
        } else { /* built in a buffer of its own, copied by the socket */
            memcpy(own, src, MESSAGE);
            bad = tsr_net_send(c, 0x20, own, MESSAGE, 10000, &err) != TSR_OK;
        }
    }
    pthread_join(th, NULL);
    double t = wall_now() - t0;
    free(own);
    if (bad || r.failed)
        fprintf(stderr, "bench_shm: %s\n", bad ? err.message : r.err.message);
    else
        mbytes = (double)count * MESSAGE / t / 1e6;
out:
    if (c)
        tsr_net_conn_close(c);
    if (s)
        tsr_net_conn_close(s);
    if (l)
        tsr_net_listener_close(l);
    if (b)
        tsr_net_destroy(b);
    if (a)
        tsr_net_destroy(a);
    return mbytes;
}

static double run_memcpy(unsigned count, const uint8_t *src, uint8_t *dst)
{
    double t0 = wall_now();
    for (unsigned i = 0; i < count; i++) {
        memcpy(dst, src, MESSAGE);
        bench_keep(dst);
    }
    return (double)count * MESSAGE / (wall_now() - t0) / 1e6;
}

int main(int argc, char **argv)
{
    bench_args args;
    if (bench_parse_args(argc, argv, &args, "") < 0)
        return 2;
    unsigned count = args.quick ? 4 : 120; /* 1 GB per run */
    uint8_t *src = malloc(MESSAGE), *dst = malloc(MESSAGE);
    if (!src || !dst)
        return 1;
    for (size_t i = 0; i < MESSAGE; i++)
        src[i] = (uint8_t)(i * 2654435761u >> 13);
    memset(dst, 0, MESSAGE);
    FILE *csv = bench_csv_open(args.csv_path, "repeat,shm_mbytes,unix_socket_mbytes,memcpy_mbytes");
    double best[3] = {0, 0, 0};
    for (int rep = 0; rep < args.repeats; rep++) {
        double v[3] = {run(1, count, src, dst), run(0, count, src, dst), run_memcpy(count, src, dst)};
        if (v[0] < 0 || v[1] < 0)
            return 1;
        for (int k = 0; k < 3; k++)
            if (v[k] > best[k])
                best[k] = v[k];
        if (csv)
            fprintf(csv, "%d,%.1f,%.1f,%.1f\n", rep, v[0], v[1], v[2]);
    }
    if (csv)
        fclose(csv);
    bench_figure("shm_mbytes", best[0], 1);
    bench_figure("unix_socket_mbytes", best[1], 1);
    bench_figure("memcpy_mbytes", best[2], 1);
    bench_figure("shm_vs_memcpy", best[0] / best[2], 3);
    bench_figure("shm_vs_unix", best[0] / best[1], 3);
    free(src);
    free(dst);
    return 0;
}
