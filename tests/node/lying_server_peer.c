/* tests/node/lying_server_peer.c — a server that completes netlib's handshake
 * over a real socket and then lies to its one client (issue 10, defects 9
 * and 10). It decodes the client's buffers with the real unpacker into a
 * real "render" chain, so every reply starts as the true one, then:
 *   wrong-size   sends each reply with its first item 2 bytes shorter
 *                (glGenLists gets a 2-byte return value)
 *   truncated    sends each reply cut to half of its bytes
 *   error-text   after the first buffer sends ERROR whose text holds
 *                ESC[2J (clear screen) and BEL, and closes
 * usage: lying_server MODE ADDRESS   (prints "listening on ADDR", serves
 * one client, exits 0 when it has gone; at most 30 s) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/dev/net.h"
#include "tessera/chain.h"
#include "tessera/dev/protocol.h"
#include "tessera/dev/unpack.h"
#include "tessera/dev/wire.h"

typedef struct liar {
    const char *mode;
    tsr_net_conn *conn;
    uint8_t out[1 << 16];
} liar;

static int lie(void *ctx, uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    liar *l = ctx;
    if (size + TSR_NODE_REPLY_HEADER > sizeof l->out)
        return tsr_error_set(err, TSR_ENOMEM, "reply too large for the liar");
    tsr_wire_put_u32(l->out, id);
    tsr_wire_put_u32(l->out + 4, 0);
    memcpy(l->out + TSR_NODE_REPLY_HEADER, data, size);
    if (!strcmp(l->mode, "wrong-size") && size >= 8) {
        uint64_t n = tsr_wire_get_u64(l->out + TSR_NODE_REPLY_HEADER);
        if (n >= 2)
            tsr_wire_put_u64(l->out + TSR_NODE_REPLY_HEADER, n - 2);
    } else if (!strcmp(l->mode, "truncated")) {
        size /= 2;
    }
    return tsr_net_send(l->conn, TSR_NODE_MSG_REPLY, l->out, TSR_NODE_REPLY_HEADER + size, 5000, err);
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: lying_server wrong-size|truncated|error-text ADDRESS\n");
        return 2;
    }
    static liar l;
    l.mode = argv[1];
    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.node_name = "liar";
    cfg.close_timeout_ms = 2000;
    tsr_error err = {0};
    tsr_net *net = tsr_net_create(&cfg, &err);
    tsr_net_listener *listener = net ? tsr_net_listen(net, argv[2], &err) : NULL;
    if (!listener) {
        fprintf(stderr, "lying_server: %s\n", err.message);
        return 1;
    }
    printf("listening on %s\n", tsr_net_listener_address(listener));
    fflush(stdout);
    l.conn = tsr_net_accept(listener, 30000, &err);
    tsr_chain *chain = l.conn ? tsr_chain_create("render", &err) : NULL;
    tsr_unpacker *u = chain ? tsr_unpacker_create(tsr_chain_head(chain), lie, &l, &err) : NULL;
    if (!u) {
        fprintf(stderr, "lying_server: %s\n", err.message);
        return 1;
    }
    for (;;) {
        tsr_net_msg m;
        int got = tsr_net_recv(l.conn, &m, 30000, &err);
        if (got != 1)
            break;
        if (m.kind == TSR_NODE_MSG_BUFFER && !strcmp(l.mode, "error-text")) {
            static const char text[] = "\x1b[2J\x07you have been pwned";
            tsr_net_send(l.conn, TSR_NODE_MSG_ERROR, text, sizeof text - 1, 2000, &err);
            tsr_net_msg_release(&m);
            break;
        }
        if (m.kind == TSR_NODE_MSG_BUFFER && tsr_unpacker_run(u, m.data, (size_t)m.len, &err) < 0)
            fprintf(stderr, "lying_server: %s\n", err.message);
        if (m.kind == TSR_NODE_MSG_FINISH)
            tsr_net_send(l.conn, TSR_NODE_MSG_FINISH, "", 0, 2000, &err);
        tsr_net_msg_release(&m);
    }
    tsr_unpacker_destroy(u);
    tsr_net_conn_close(l.conn);
    tsr_chain_destroy(chain);
    tsr_net_listener_close(listener);
    tsr_net_destroy(net);
    return 0;
}
