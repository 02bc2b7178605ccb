/* mothership/messages.c — the control messages received: joins matched
 * to the graph's nodes (or refused), READY, DONE, statistics and failures
 * from each node, read from the control connections without blocking.
 * Owns the pending connections until they join. Never: puts stream data
 * on a control connection, blocks on a read. */
#include <errno.h>
#include <ftw.h>
#include <limits.h>
#include <libgen.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "tessera/dev/util.h"
#include "ms_internal.h"
#include "tessera/dev/net.h"
#include "control.h"
#include "tessera/spu.h"
#include "util.h"

/* --- messages --------------------------------------------------------- */

static void take_stats(ms_node *n, const tsr_ctl *msg)
{
    double t = tsr_now_seconds();
    n->frames = tsr_ctl_number(msg, "frames", n->frames);
    n->buffers = tsr_ctl_number(msg, "buffers", n->buffers);
    n->bytes_in = tsr_ctl_number(msg, "bytes_in", n->bytes_in);
    n->bytes_out = tsr_ctl_number(msg, "bytes_out", n->bytes_out);
    n->busy = tsr_ctl_number(msg, "busy_seconds", n->busy);
    n->blocked = tsr_ctl_number(msg, "blocked_seconds", n->blocked);
    n->elapsed = tsr_ctl_number(msg, "elapsed", n->elapsed);
    n->clients = (unsigned)tsr_ctl_number(msg, "clients", n->clients);
    const char *app = tsr_ctl_get(msg, "app_stats");
    if (app)
        n->app_stats = !strcmp(app, "found");
    const char *sf = tsr_ctl_get(msg, "sort_first");
    if (sf) {
        free(n->sort_first);
        n->sort_first = strdup(sf);
    }
    /* Rates over windows of at least half a second, for a steady line. */
    if (!n->rate_t) {
        n->rate_t = t;
    } else if (t - n->rate_t >= 0.5) {
        double bytes = n->bytes_in + n->bytes_out;
        n->fps = (n->frames - n->rate_frames) / (t - n->rate_t);
        n->mbps = (bytes - n->rate_bytes) / (t - n->rate_t) / 1e6;
        n->rate_t = t;
        n->rate_frames = n->frames;
        n->rate_bytes = bytes;
    }
}

static void refuse(tsr_net_conn *conn, const char *reason)
{
    tsr_ctl_out out;
    tsr_ctl_out_init(&out);
    tsr_ctl_add(&out, "reason", reason);
    tsr_error ignored = {0};
    ms_send_ctl(conn, TSR_MS_MSG_REFUSE, &out, &ignored);
    tsr_ctl_out_free(&out);
    tsr_net_conn_close(conn);
}

static void handle_join(ms *m, size_t p, const tsr_ctl *msg)
{
    tsr_net_conn *conn = m->pending[p].conn;
    m->pending[p] = m->pending[--m->pending_count];
    const char *name = tsr_ctl_get(msg, "name");
    const char *rank = tsr_ctl_get(msg, "rank");
    const char *host = tsr_ctl_get(msg, "host");
    char reason[400];
    ms_node *n = NULL;
    if (name) {
        for (size_t i = 0; i < m->count && !n; i++)
            if (!strcmp(m->nodes[i].g->name, name))
                n = &m->nodes[i];
        if (!n)
            snprintf(reason, sizeof reason, "a node joined as '%.64s', but %s has no such node", name,
                     tsr_graph_file(m->graph));
    } else if (rank) {
        char *end;
        long r = strtol(rank, &end, 10);
        if (*end || r < 0 || (size_t)r >= m->count)
            snprintf(reason, sizeof reason, "a node joined with rank %.20s, but %s has %zu nodes (ranks 0..%zu)", rank,
                     tsr_graph_file(m->graph), m->count, m->count - 1);
        else
            n = &m->nodes[r];
    } else {
        snprintf(reason, sizeof reason, "a node joined without a name or rank");
    }
    if (n && n->state != N_WAITING) {
        snprintf(reason, sizeof reason, "node '%s' joined twice (again from host %.64s)", n->g->name,
                 host ? host : "?");
        n = NULL;
    }
    if (!n) {
        char safe[sizeof reason];
        tsr_text_sanitize(safe, sizeof safe, reason, strlen(reason)); /* it quotes the peer's name and host */
        refuse(conn, safe);
        ms_fail(m, FAIL_OTHER, "%s", safe);
        return;
    }
    n->conn = conn;
    n->state = N_JOINED;
    n->last_heard = tsr_now_seconds();
    n->remote_pid = (long)tsr_ctl_number(msg, "pid", 0);
    tsr_text_sanitize(n->host, sizeof n->host, host ? host : "?", strlen(host ? host : "?"));
}

static void handle_message(ms *m, ms_node *n, unsigned kind, const tsr_ctl *msg)
{
    n->last_heard = tsr_now_seconds();
    switch (kind) {
    case TSR_MS_MSG_READY: {
        const char *addr = tsr_ctl_get(msg, "address");
        if (n->server) {
            if (!addr || !*addr) {
                ms_fail(m, FAIL_OTHER, "node '%s' reported READY without its address", n->g->name);
                return;
            }
            snprintf(n->address, sizeof n->address, "%s", addr);
        }
        n->state = N_READY;
        break;
    }
    case TSR_MS_MSG_STATS: {
        take_stats(n, msg);
        n->stats_at = tsr_now_seconds();
        /* A server dropped a client for silence and serves the others:
         * that client (a stopped or hung process) cannot finish its
         * frames, so the run fails now, named by the drop, before the
         * peers waiting for it time out and end (their exits are the
         * echo). Same class as the drop in a DONE. */
        const char *failure = tsr_ctl_get(msg, "failure");
        if (n->server && failure && *failure)
            ms_fail(m, FAIL_SILENT, "node '%s': %s", n->g->name, failure);
        break;
    }
    case TSR_MS_MSG_DONE: {
        take_stats(n, msg);
        n->state = N_DONE;
        n->done_at = tsr_now_seconds();
        n->done_status = (int)tsr_ctl_number(msg, "status", 1);
        /* An application that ended well, but whose stream client wrote no
         * statistics, may never have connected: its servers would wait
         * for it until their join time-out (check_unconnected). */
        n->check_connected = !n->server && !n->done_status && n->app_stats != 1 && n->network && n->g->to_count;
        const char *why = tsr_ctl_get(msg, "message");
        /* A server that dropped a client for silence found a stopped or
         * hung process, as a missed heartbeat does: that explains the
         * exits of the peers and applications that follow. */
        double failed = tsr_ctl_number(msg, "clients_failed", 0);
        int cls = tsr_ctl_number(msg, "signal", 0)                                                  ? FAIL_SIGNAL
                  : tsr_ctl_number(msg, "clients_silent", 0)                                        ? FAIL_SILENT
                  : n->server && failed > 0 && tsr_ctl_number(msg, "clients_vanished", 0) >= failed ? FAIL_ECHO
                                                                                                    : FAIL_EXIT;
        /* `tessera exec --graph`: the program's own end, for its caller. */
        int program = !n->server && m->cfg->exec_node && !strcmp(m->cfg->exec_node, n->g->name);
        if (program && m->cfg->program_end) {
            m->cfg->program_end->ended = true;
            m->cfg->program_end->exit_code = (int)tsr_ctl_number(msg, "exit_code", 0);
            m->cfg->program_end->signal = (int)tsr_ctl_number(msg, "signal", 0);
        }
        m->failing_program = program;
        if (n->done_status)
            ms_fail(m, cls, "node '%s': %s", n->g->name, why && *why ? why : "failed (no reason given)");
        m->failing_program = 0;
        break;
    }
    default: ms_fail(m, FAIL_OTHER, "node '%s' sent an unexpected %s message", n->g->name, tsr_ctl_kind_name(kind));
    }
}

/* One round of receiving: every message already queued, waiting at most
 * POLL_MS for the first. */
void ms_receive(ms *m)
{
    tsr_net_conn *conns[MAX_PENDING + 1024];
    ms_node *owners[MAX_PENDING + 1024];
    size_t count = 0;
    for (size_t i = 0; i < m->pending_count; i++) {
        owners[count] = NULL;
        conns[count++] = m->pending[i].conn;
    }
    for (size_t i = 0; i < m->count && count < sizeof conns / sizeof conns[0]; i++) {
        ms_node *n = &m->nodes[i];
        if (n->conn && !n->conn_ended) {
            owners[count] = n;
            conns[count++] = n->conn;
        }
    }
    if (!count) {
        struct timespec ts = {0, POLL_MS * 1000000L};
        nanosleep(&ts, NULL);
        return;
    }
    size_t which = count;
    int wait = POLL_MS;
    for (int round = 0; round < 64; round++) {
        tsr_net_msg msg;
        tsr_error e = {0};
        int rc = tsr_net_recv_any(conns, count, &which, &msg, wait, &e);
        wait = 0;
        if (rc == TSR_ETIMEDOUT)
            return;
        ms_node *n = owners[which];
        if (rc != 1) {
            if (!n) { /* a pending connection went away before joining */
                for (size_t p = 0; p < m->pending_count; p++)
                    if (m->pending[p].conn == conns[which]) {
                        tsr_net_conn_close(conns[which]);
                        m->pending[p] = m->pending[--m->pending_count];
                        break;
                    }
                return; /* arrays changed */
            }
            n->conn_ended = 1;
            if (n->state != N_DONE) { /* after DONE, its end was reported */
                if (!n->lost_at) {
                    n->lost_at = tsr_now_seconds();
                    n->lost_by_error = rc != 0;
                    snprintf(n->lost_why, sizeof n->lost_why, "%s",
                             rc == 0 ? "closed its control connection before reporting its end" : e.message);
                }
            }
            /* Every connection that ended is seen in this round, before
             * reap() judges the exits that follow from it. */
            conns[which] = conns[--count];
            owners[which] = owners[count];
            if (!count)
                return;
            continue;
        }
        tsr_ctl ctl;
        tsr_error perr = {0};
        int parsed = tsr_ctl_parse(&ctl, msg.data, msg.len, &perr) == TSR_OK;
        unsigned kind = msg.kind;
        tsr_net_msg_release(&msg);
        if (!parsed) {
            ms_fail(m, FAIL_OTHER, "node '%s': %s", n ? n->g->name : "(joining)", perr.message);
            continue;
        }
        if (!n) {
            if (kind == TSR_MS_MSG_JOIN) {
                for (size_t p = 0; p < m->pending_count; p++)
                    if (m->pending[p].conn == conns[which]) {
                        handle_join(m, p, &ctl);
                        break;
                    }
                tsr_ctl_free(&ctl);
                return; /* arrays changed */
            }
            ms_fail(m, FAIL_OTHER, "a connection sent %s before JOIN", tsr_ctl_kind_name(kind));
        } else {
            handle_message(m, n, kind, &ctl);
        }
        tsr_ctl_free(&ctl);
    }
}
