/* tests/run/fake_node_peer.c — a hostile node of a graph run (issue 10, defect
 * 10): joins a real `tessera mothership` over a real netlib connection with
 * the real control codec (mothership/control.h), as node NAME from a host
 * whose name holds escape sequences, answers its CONFIG with READY, then
 * reports DONE status=1 with a message holding ESC[2J (clear screen), BEL
 * and a C1 CSI. The mothership must print that text escaped.
 * usage: fake_node ADDR NAME
 * Exit 0 once DONE is sent and the mothership ended the connection (STOP
 * or close), 1 on any other end. Owns only its connection. */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "control.h"
#include "tessera/dev/net.h"

static int send_ctl(tsr_net_conn *conn, unsigned kind, tsr_ctl_out *out, tsr_error *err)
{
    int rc = tsr_net_send(conn, kind, out->text, out->len, 5000, err);
    tsr_ctl_out_free(out);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: fake_node ADDR NAME\n");
        return 2;
    }
    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.node_name = "fake-node";
    tsr_error err = {0};
    tsr_net *net = tsr_net_create(&cfg, &err);
    tsr_net_conn *conn = net ? tsr_net_connect(net, argv[1], &err) : NULL;
    if (!conn) {
        fprintf(stderr, "fake_node: %s\n", err.message);
        tsr_net_destroy(net);
        return 1;
    }
    tsr_ctl_out out;
    tsr_ctl_out_init(&out);
    tsr_ctl_add(&out, "name", argv[2]);
    tsr_ctl_addf(&out, "pid", "%ld", (long)getpid());
    tsr_ctl_add(&out, "host", "host\x1b]0;owned\x07");
    int rc = send_ctl(conn, TSR_MS_MSG_JOIN, &out, &err);
    tsr_net_msg m;
    int got = rc ? rc : tsr_net_recv(conn, &m, 10000, &err);
    if (got != 1) {
        fprintf(stderr, "fake_node: no CONFIG: %s\n", got == 0 ? "the mothership closed" : err.message);
        return 1;
    }
    unsigned kind = m.kind;
    tsr_net_msg_release(&m);
    if (kind != TSR_MS_MSG_CONFIG) {
        fprintf(stderr, "fake_node: got %s, not CONFIG\n", tsr_ctl_kind_name(kind));
        return 1;
    }
    tsr_ctl_out_init(&out);
    tsr_ctl_add(&out, "address", "tcp://127.0.0.1:9");
    rc = send_ctl(conn, TSR_MS_MSG_READY, &out, &err);
    tsr_ctl_out_init(&out);
    tsr_ctl_add(&out, "status", "1");
    tsr_ctl_add(&out, "message",
                "render failed\x1b[2J\x07\xc2\x9b"
                "31mgotcha");
    tsr_ctl_add(&out, "signal", "0");
    rc = rc ? rc : send_ctl(conn, TSR_MS_MSG_DONE, &out, &err);
    if (rc) {
        fprintf(stderr, "fake_node: %s\n", err.message);
        return 1;
    }
    printf("fake_node: DONE sent\n");
    fflush(stdout);
    /* The mothership answers with STOP or closes; either ends this node. */
    for (int i = 0; i < 30; i++) {
        got = tsr_net_recv(conn, &m, 1000, &err);
        if (got == 1) {
            kind = m.kind;
            tsr_net_msg_release(&m);
            if (kind == TSR_MS_MSG_STOP)
                break;
        } else if (got != TSR_ETIMEDOUT) {
            break;
        }
    }
    tsr_net_conn_close(conn);
    tsr_net_destroy(net);
    return 0;
}
