/* spus/binaryswap/stats.c — the per-frame timing lines of stats.h, and
 * the instance's figures: its stats= line per frame, its transport
 * statistics at the end. Owns nothing; never decides from the figures. */
#include "stats.h"
#include "instance.h"
#include "tessera/log.h"

#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

int64_t binaryswap_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

int64_t binaryswap_cpu_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

int binaryswap_stats_open(const char *path, tsr_error *err)
{
    int fd = open(path, O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (fd < 0)
        tsr_error_set(err, TSR_EIO, "stats=%s: %s", path, strerror(errno));
    return fd;
}

/* VmHWM and VmRSS of this process in KiB (0 when /proc is not there). */
static void memory_kb(long *hwm, long *rss)
{
    *hwm = *rss = 0;
    FILE *f = fopen("/proc/self/status", "r");
    if (!f)
        return;
    char line[256];
    while (fgets(line, sizeof line, f)) {
        if (!strncmp(line, "VmHWM:", 6))
            sscanf(line + 6, "%ld", hwm);
        else if (!strncmp(line, "VmRSS:", 6))
            sscanf(line + 6, "%ld", rss);
    }
    fclose(f);
}

void binaryswap_stats_write(int fd, const binaryswap_frame_stats *s)
{
    long hwm, rss;
    memory_kb(&hwm, &rss);
    char line[512];
    int n =
        snprintf(line, sizeof line,
                 "frame %" PRIu32 " rank %d nranks %d swap_ns %" PRId64 " ready_ns %" PRId64 " composited_ns %" PRId64
                 " assembled_ns %" PRId64 " sent_ns %" PRId64 " displayed_ns %" PRId64 " bytes_sent %" PRIu64
                 " vmhwm_kb %ld vmrss_kb %ld cpu_ns %" PRId64 " hook_cpu_ns %" PRId64 " final_filled %" PRIu64 "\n",
                 s->frame, s->rank, s->nranks, s->swap_ns, s->ready_ns, s->composited_ns, s->assembled_ns, s->sent_ns,
                 s->displayed_ns, s->bytes_sent, hwm, rss, binaryswap_cpu_ns(), s->hook_cpu_ns, s->final_filled);
    if (n > 0 && (size_t)n < sizeof line && write(fd, line, (size_t)n) != n) {
        /* A full disk loses a timing line, never the frame. */
    }
}

void binaryswap_stats_frame(binaryswap_spu *b, uint32_t frame)
{
    if (b->stats_fd < 0)
        return;
    b->st.frame = frame;
    b->st.rank = b->rank;
    b->st.nranks = b->nranks;
    b->st.bytes_sent = b->last_bytes;
    binaryswap_stats_write(b->stats_fd, &b->st);
}

/* One line per peer pair at the end of the run: which transport carried
 * this peer's images to each peer and back, and how much of it. */
void binaryswap_log_transport_stats(const binaryswap_spu *b)
{
    for (int i = 0; i < b->nranks; i++) {
        if (!b->conns[i])
            continue;
        tsr_net_stats st;
        tsr_net_conn_stats(b->conns[i], &st);
        tsr_log(TSR_LOG_INFO,
                "%s: transport stats rank %d -> rank %d: %s; sent %" PRIu64 " messages %" PRIu64 " bytes (%" PRIu64
                " messages %" PRIu64 " bytes through shared memory); received %" PRIu64 " messages %" PRIu64
                " bytes (%" PRIu64 " messages %" PRIu64 " bytes through shared memory)",
                b->name, b->rank, i, tsr_net_conn_transport(b->conns[i]), st.messages_sent, st.bytes_sent,
                st.messages_sent_shm, st.bytes_sent_shm, st.messages_received, st.bytes_received,
                st.messages_received_shm, st.bytes_received_shm);
    }
}
