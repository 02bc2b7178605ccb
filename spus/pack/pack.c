/* spus/pack/pack.c — the "pack" SPU: packs every call with the real packer
 * (core/pack.h) and sends each flushed buffer to one server node over
 * netlib (messages of node/protocol.h); replies to gets, ReadPixels and
 * the Gen and Create calls come back on the same connection, matched by
 * request id.
 * Owns, per instance: its netlib instance (I/O thread), the connection,
 * the packer and the reply message it is holding. Never calls its child:
 * the stream goes to the server, unchanged.
 *
 * Failure policy. GL calls cannot return errors to the application, so
 * when the connection fails mid-stream (server killed, stalled beyond
 * timeout_ms, dropped us) the SPU logs one line naming the server address
 * and then, with on_error=exit (the default), ends the process with exit
 * status 1 — the application cannot notice otherwise and would report
 * success for frames that were never drawn. on_error=drop keeps the
 * application running and drops every further call (the packer's error
 * stays recorded). Failing to connect at all is reported by create(),
 * so chain creation fails with the address in the message. destroy()
 * sends FINISH and waits for the server's confirmation that every buffer
 * ran, so an application that ends normally knows its stream was drawn
 * (a server that dropped it mid-way is caught there at the latest). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "net.h"
#include "pack.h"
#include "protocol.h"
#include "tessera/log.h"
#include "tessera/spu.h"
#include "wire.h"

#define PACK_EXIT_STATUS 1

typedef struct pack_spu {
    char name[96];
    char server[TSR_NET_ADDRESS_MAX];
    tsr_net *net;
    tsr_net_conn *conn;
    tsr_packer *packer;
    tsr_net_msg reply;       /* the reply handed to the packer, held until the next sink call */
    int holding_reply;
    int failed;              /* the connection is gone: drop everything */
    int exit_on_error;
} pack_spu;

static void release_reply(pack_spu *s)
{
    if (s->holding_reply) {
        tsr_net_msg_release(&s->reply);
        s->holding_reply = 0;
    }
}

/* When the server dropped us it said why (TSR_NODE_MSG_ERROR) before
 * closing; that reason beats netlib's "peer closed". Takes a queued
 * message without waiting; returns 1 and fills `why` when it was one. */
static int server_reason(pack_spu *s, tsr_error *why)
{
    tsr_net_msg m;
    tsr_error ignored = {0};
    int found = 0;
    while (!found && tsr_net_recv(s->conn, &m, 0, &ignored) == 1) {
        if (m.kind == TSR_NODE_MSG_ERROR) {
            tsr_error_set(why, TSR_EPROTO, "the server dropped this client: %.*s",
                          (int)(m.len < 400 ? m.len : 400), (const char *)m.data);
            found = 1;
        }
        tsr_net_msg_release(&m);
    }
    return found;
}

/* The connection is unusable: one line naming the server, then the
 * on_error policy. Returns the error code for the packer. */
static int connection_failed(pack_spu *s, tsr_error *err, const char *what, const tsr_error *cause)
{
    s->failed = 1;
    release_reply(s);
    tsr_error reason = {0};
    if (cause->code != TSR_EPROTO && server_reason(s, &reason))
        cause = &reason;
    tsr_error_set(err, cause->code ? cause->code : TSR_EIO, "%s: server %s: %s: %s", s->name,
                  s->server, what, cause->message);
    tsr_log(TSR_LOG_ERROR, "%s", err->message);
    if (s->exit_on_error) {
        tsr_log(TSR_LOG_ERROR, "%s: ending the application (on_error=exit)", s->name);
        fflush(NULL);
        /* _exit, not exit: other threads (the renderer's, netlib's) are
         * running and must not see library destructors run under them. */
        _exit(PACK_EXIT_STATUS);
    }
    return err->code;
}

static int pack_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    pack_spu *s = ctx;
    release_reply(s);
    if (s->failed)
        return tsr_error_set(err, TSR_ESTATE, "%s: server %s: connection already failed", s->name,
                             s->server);
    tsr_error cause = {0};
    if (tsr_net_send(s->conn, TSR_NODE_MSG_BUFFER, buf, size, TSR_NET_WAIT_FOREVER, &cause) != TSR_OK)
        return connection_failed(s, err, "sending a buffer failed", &cause);
    return TSR_OK;
}

/* Requests are answered in order, so the next message is the reply to the
 * request just flushed; its id says whether it really is. */
static int pack_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    pack_spu *s = ctx;
    release_reply(s);
    if (s->failed)
        return tsr_error_set(err, TSR_ESTATE, "%s: server %s: connection already failed", s->name,
                             s->server);
    tsr_error cause = {0};
    tsr_net_msg m;
    int got = tsr_net_recv(s->conn, &m, TSR_NET_WAIT_FOREVER, &cause);
    if (got == 0) {
        tsr_error_set(&cause, TSR_EIO, "closed the connection instead of answering request %u", id);
        return connection_failed(s, err, "waiting for a reply", &cause);
    }
    if (got < 0)
        return connection_failed(s, err, "waiting for a reply", &cause);
    if (m.kind == TSR_NODE_MSG_ERROR) {
        tsr_error_set(&cause, TSR_EPROTO, "the server dropped this client: %.*s",
                      (int)(m.len < 400 ? m.len : 400), (const char *)m.data);
        tsr_net_msg_release(&m);
        return connection_failed(s, err, "waiting for a reply", &cause);
    }
    if (m.kind != TSR_NODE_MSG_REPLY || m.len < TSR_NODE_REPLY_HEADER ||
        tsr_wire_get_u32(m.data) != id) {
        tsr_error_set(&cause, TSR_EPROTO,
                      "expected the reply to request %u, got a message of kind 0x%02x, %llu bytes%s",
                      id, m.kind, (unsigned long long)m.len,
                      m.kind == TSR_NODE_MSG_REPLY && m.len >= TSR_NODE_REPLY_HEADER
                          ? " (another request id)" : "");
        tsr_net_msg_release(&m);
        return connection_failed(s, err, "waiting for a reply", &cause);
    }
    s->reply = m;
    s->holding_reply = 1;
    *data = (const uint8_t *)m.data + TSR_NODE_REPLY_HEADER;
    *size = (size_t)(m.len - TSR_NODE_REPLY_HEADER);
    return TSR_OK;
}

/* Sends what is left and FINISH, and waits until the server confirmed that
 * every buffer ran (or says why not). */
static void finish_stream(pack_spu *s)
{
    tsr_error err = {0}, cause = {0};
    if (tsr_packer_flush(s->packer) != TSR_OK || s->failed)
        return;
    release_reply(s);
    if (tsr_net_send(s->conn, TSR_NODE_MSG_FINISH, "", 0, TSR_NET_WAIT_FOREVER, &cause) != TSR_OK) {
        connection_failed(s, &err, "finishing the stream", &cause);
        return;
    }
    tsr_net_msg m;
    int got = tsr_net_recv(s->conn, &m, TSR_NET_WAIT_FOREVER, &cause);
    if (got == 1 && m.kind == TSR_NODE_MSG_FINISH) {
        tsr_net_msg_release(&m);
        return;
    }
    if (got == 1) {
        if (m.kind == TSR_NODE_MSG_ERROR)
            tsr_error_set(&cause, TSR_EPROTO, "the server dropped this client: %.*s",
                          (int)(m.len < 400 ? m.len : 400), (const char *)m.data);
        else
            tsr_error_set(&cause, TSR_EPROTO, "expected the end of stream confirmation, got a message of "
                          "kind 0x%02x", m.kind);
        tsr_net_msg_release(&m);
    } else if (got == 0) {
        tsr_error_set(&cause, TSR_EIO, "closed the connection before confirming the end of stream");
    }
    connection_failed(s, &err, "finishing the stream", &cause);
}

static void pack_destroy(void *instance)
{
    pack_spu *s = instance;
    if (!s)
        return;
    if (s->packer && s->conn && !s->failed)
        finish_stream(s);
    release_reply(s);
    if (s->conn)
        tsr_net_conn_close(s->conn); /* BYE: the server ends this client cleanly */
    tsr_net_destroy(s->net);         /* waits (bounded) until everything was written */
    tsr_packer_destroy(s->packer);
    free(s);
}

static void *pack_create(const tsr_spu_init *init, tsr_error *err)
{
    pack_spu *s = calloc(1, sizeof *s);
    if (!s) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    snprintf(s->name, sizeof s->name, "%s", init->instance_name);
    const char *server = tsr_options_string(init->options, "server");
    if (!server || !server[0]) {
        tsr_error_set(err, TSR_EINVAL, "%s: option server is required (e.g. server=tcp://127.0.0.1:7000)",
                      s->name);
        goto fail;
    }
    if (strlen(server) >= sizeof s->server) {
        tsr_error_set(err, TSR_EINVAL, "%s: option server=%.60s...: longer than %d bytes", s->name,
                      server, TSR_NET_ADDRESS_MAX - 1);
        goto fail;
    }
    snprintf(s->server, sizeof s->server, "%s", server);
    s->exit_on_error = !strcmp(tsr_options_string(init->options, "on_error"), "exit");
    uint32_t timeout_ms = (uint32_t)tsr_options_int(init->options, "timeout_ms");

    char node_name[TSR_NET_NAME_MAX + 1];
    snprintf(node_name, sizeof node_name, "%.40s-pid%ld", s->name, (long)getpid());
    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.node_name = node_name;
    cfg.token = tsr_options_string(init->options, "token");
    cfg.idle_timeout_ms = timeout_ms;
    if (timeout_ms) {
        cfg.connect_timeout_ms = timeout_ms;
        cfg.handshake_timeout_ms = timeout_ms;
        cfg.close_timeout_ms = timeout_ms;
    }
    tsr_error cause = {0};
    s->net = tsr_net_create(&cfg, &cause);
    if (!s->net) {
        tsr_error_set(err, cause.code, "%s: %s", s->name, cause.message);
        goto fail;
    }
    s->conn = tsr_net_connect(s->net, s->server, &cause);
    if (!s->conn) {
        tsr_error_set(err, cause.code ? cause.code : TSR_EIO, "%s: cannot reach server %s: %s", s->name,
                      s->server, cause.message);
        goto fail;
    }
    size_t buffer_size = (size_t)tsr_options_int(init->options, "buffer_size");
    tsr_pack_sink sink = {.flush = pack_flush, .reply = pack_reply, .ctx = s};
    s->packer = tsr_packer_create(buffer_size, &sink, err);
    if (!s->packer)
        goto fail;
    tsr_packer_fill_dispatch(s->packer, init->table);
    return s;
fail:
    pack_destroy(s);
    return NULL;
}

static const tsr_option_spec pack_options[] = {
    {.name = "server", .type = TSR_OPT_STRING, .default_value = "", .min = 1, .max = 0,
     .help = "server node address: tcp://HOST:PORT or unix:PATH (required)"},
    {.name = "token", .type = TSR_OPT_STRING, .default_value = "", .min = 1, .max = 0,
     .help = "shared token the server requires (empty: none)"},
    {.name = "buffer_size", .type = TSR_OPT_INT, .default_value = "1048576", .min = TSR_PACK_MIN_BUFFER,
     .max = 67108864.0, .help = "bytes of one wire buffer (header, opcodes and data)"},
    {.name = "timeout_ms", .type = TSR_OPT_INT, .default_value = "10000", .min = 0, .max = 3600000.0,
     .help = "connect/handshake limit, and how long the server may stay silent before it counts "
             "as dead (0: netlib defaults, no silence limit)"},
    {.name = "on_error", .type = TSR_OPT_ENUM, .default_value = "exit", .choices = "exit|drop",
     .min = 1, .max = 0,
     .help = "when the connection fails mid-stream: exit ends the application with status 1, "
             "drop discards every further call"},
};

static const tsr_spu_class pack_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "pack",
    .summary = "sends the stream, unchanged, to one server node; replies come back",
    .options = pack_options,
    .option_count = sizeof pack_options / sizeof pack_options[0],
    .create = pack_create,
    .destroy = pack_destroy,
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void)
{
    return &pack_class;
}
