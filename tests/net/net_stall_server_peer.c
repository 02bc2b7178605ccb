/* tests/net/net_stall_server_peer.c — the receiving process of the flow-control
 * test: accepts one stream, consumes STALL_AFTER messages, stops consuming
 * for STALL_MS, then consumes the rest, verifying every byte and hashing it.
 * Reports on stdout, one line per event, for its parent to read.
 * Never: consumes while stalled, or exits 0 unless every byte was exact. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tessera/dev/net.h"

#if defined(__SANITIZE_ADDRESS__)
/* Measure live memory, not ASan's quarantine of freed blocks (which holds
 * up to 256 MiB on purpose): the test bounds what netlib keeps alive. */
const char *__asan_default_options(void);
const char *__asan_default_options(void) { return "quarantine_size_mb=0"; }
#endif

int main(int argc, char **argv)
{
    if (argc != 6) {
        fprintf(stderr, "usage: net_stall_server CREDITS MESSAGE_BYTES TOTAL_BYTES STALL_AFTER "
                        "STALL_MS\n");
        return 2;
    }
    unsigned credits = (unsigned)atoi(argv[1]);
    size_t message_bytes = (size_t)atoll(argv[2]);
    unsigned long long total = strtoull(argv[3], NULL, 10);
    unsigned stall_after = (unsigned)atoi(argv[4]);
    unsigned stall_ms = (unsigned)atoi(argv[5]);
    setvbuf(stdout, NULL, _IOLBF, 0);

    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.node_name = "stalling-server";
    cfg.credits = credits;
    cfg.max_message_bytes = message_bytes;
    tsr_error err = {0};
    tsr_net *net = tsr_net_create(&cfg, &err);
    tsr_net_listener *l = net ? tsr_net_listen(net, "tcp://127.0.0.1:0", &err) : NULL;
    if (!l) {
        printf("error %s\n", err.message);
        return 1;
    }
    printf("listening %s\n", tsr_net_listener_address(l));
    tsr_net_conn *c = tsr_net_accept(l, 10000, &err);
    if (!c) {
        printf("error %s\n", err.message);
        return 1;
    }
    printf("accepted %s\n", tsr_net_conn_peer_name(c));

    uint8_t *expect = malloc(message_bytes);
    uint64_t fnv = TSR_NET_FNV_START, at = 0;
    unsigned consumed = 0;
    int rc = 0;
    while (at < total) {
        if (consumed == stall_after) {
            printf("stalling after %u messages\n", consumed);
            usleep(stall_ms * 1000u);
            printf("resuming\n");
        }
        tsr_net_msg m;
        int got = tsr_net_recv(c, &m, 10000, &err);
        if (got <= 0) {
            printf("error stream ended after %llu of %llu bytes: %s\n", (unsigned long long)at, total,
                   got ? err.message : "peer closed");
            rc = 1;
            break;
        }
        tsr_net_pattern_fill(expect, at, (size_t)m.len, 0);
        if (m.len > message_bytes || memcmp(expect, m.data, (size_t)m.len)) {
            printf("error message %u (stream offset %llu) differs\n", consumed, (unsigned long long)at);
            rc = 1;
        }
        fnv = tsr_net_fnv1a(fnv, m.data, (size_t)m.len);
        at += m.len;
        consumed++;
        tsr_net_msg_release(&m);
    }
    if (!rc) {
        tsr_net_msg m;
        int got = tsr_net_recv(c, &m, 10000, &err);
        if (got != 0) {
            printf("error expected the end of the stream, got %d %s\n", got, err.message);
            if (got == 1)
                tsr_net_msg_release(&m);
            rc = 1;
        }
    }
    tsr_net_stats st;
    tsr_net_conn_stats(c, &st);
    printf("done bytes=%llu messages=%u fnv=%016llx\n", (unsigned long long)at, consumed, (unsigned long long)fnv);
    free(expect);
    tsr_net_conn_close(c);
    tsr_net_listener_close(l);
    tsr_net_destroy(net);
    return rc;
}
