/* mothership/mothership.c — the coordinator (mothership.h): plan, launch,
 * configure in start order, watch heartbeats and children, report, and
 * stop everything on the first failure.
 * Owns: the control tsr_net, every control connection, the launched
 * children (one process group each) and the run's statistics.
 * Never: blocks longer than POLL_MS in its loop, so a failure anywhere is
 * seen within timeout_ms + POLL_MS.
 *
 * This file: failure, the watch loop, configuring in start order, the
 * run. plan.c, processes.c, messages.c and stats.c do the rest
 * (ms_internal.h). */
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

void ms_fail(ms *m, int cls, const char *fmt, ...)
{
    if (m->fail_class == FAIL_NONE)
        m->fail_deadline = tsr_now_seconds() + (cls == FAIL_INTERRUPT ? 0 : FAIL_GRACE_S);
    if (cls >= m->fail_class)
        return;
    m->fail_class = cls;
    m->fail_is_program = m->failing_program;
    /* Failures quote peers (a node's DONE message, a JOIN's name, a
     * control message that did not parse): the whole line is made safe
     * to print, which leaves this file's own text as it is. */
    char raw[sizeof m->fail_message];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(raw, sizeof raw, fmt, ap);
    va_end(ap);
    tsr_text_sanitize(m->fail_message, sizeof m->fail_message, raw, strlen(raw));
}

static int is_local_host(const char *host)
{
    char self[256] = "";
    gethostname(self, sizeof self - 1);
    return !strcmp(host, "localhost") || !strcmp(host, "127.0.0.1") || !strcmp(host, "::1") || !strcmp(host, self);
}

/* --- watching --------------------------------------------------------- */

static void check(ms *m)
{
    double t = tsr_now_seconds();
    for (size_t i = 0; i < m->count; i++) {
        ms_node *n = &m->nodes[i];
        /* Heartbeats count once the node is READY: before, a server is
         * building its chain (loading OSMesa can take seconds on a loaded
         * machine) and cannot beat; that phase has the join time-out. */
        if (n->state == N_CONFIGURED && (t - n->configured_at) * 1000.0 > m->cfg->join_timeout_ms)
            ms_fail(m, FAIL_HEARTBEAT, "node '%s' was not ready within %u ms of its configuration", n->g->name,
                    m->cfg->join_timeout_ms);
        /* A silent node whose process is busy (running, starved or
         * exiting) gets one more time-out before it is named silent: a
         * node ended by SIGTERM on a machine at load 19 took longer than
         * the grace to be reaped, and its silence was named instead of
         * its signal (fault_wall_tileserver_sigterm in issue 28's flake
         * hunt). A stopped or sleeping one is named at once. */
        double silent_ms = (t - n->last_heard) * 1000.0;
        if (n->state == N_READY && !n->lost_at && silent_ms > m->cfg->timeout_ms &&
            !(n->pid && !n->reaped && silent_ms <= 2.0 * m->cfg->timeout_ms && ms_process_busy(n->pid)))
            ms_fail(m, FAIL_HEARTBEAT, "node '%s' sent no heartbeat for %.0f ms (stopped or hung; --timeout-ms %u)",
                    n->g->name, silent_ms, m->cfg->timeout_ms);
        if (n->exit_seen_at && n->state != N_DONE &&
            (n->conn_ended || !n->conn || t - n->exit_seen_at > LOST_GRACE_S)) {
            if (n->lost_by_error)
                ms_fail(m, FAIL_EXIT, "node '%s' (pid %ld) %s after its control connection was lost (%s)", n->g->name,
                        (long)n->pid, n->exit_what, n->lost_why);
            else
                ms_fail(m, FAIL_EXIT, "node '%s' (pid %ld) %s", n->g->name, (long)n->pid, n->exit_what);
        }
        if (n->lost_at && !n->reaped && (!n->pid || t - n->lost_at > LOST_GRACE_S))
            ms_fail(m, FAIL_LOST, "node '%s': control connection lost: %s", n->g->name, n->lost_why);
        if (n->state == N_WAITING && (t - m->start) * 1000.0 > m->cfg->join_timeout_ms)
            ms_fail(m, FAIL_OTHER, "node '%s' did not join within %u ms%s", n->g->name, m->cfg->join_timeout_ms,
                    n->local ? "" : " (start it with: tessera node --mothership ADDR --name NAME)");
    }
    for (size_t p = 0; p < m->pending_count; p++)
        if (t - m->pending[p].since > 10.0) {
            tsr_net_conn_close(m->pending[p].conn);
            m->pending[p--] = m->pending[--m->pending_count];
        }
}

/* An application that ended (status 0) without statistics from its
 * stream client: once each of its servers has sent a heartbeat made after
 * that end, a server still short of clients will never get this one.
 * Servers accept a client's connection before its application goes on, so
 * the count in such a heartbeat includes it if it ever connected. */
static void check_unconnected(ms *m)
{
    double beat = ms_heartbeat_ms(m) / 1000.0;
    for (size_t i = 0; i < m->count; i++) {
        ms_node *n = &m->nodes[i];
        if (!n->check_connected)
            continue;
        int pending = 0;
        for (size_t t = 0; t < n->g->to_count; t++) {
            const ms_node *server = &m->nodes[n->g->to[t]];
            if (server->state == N_DONE)
                continue;
            if (server->stats_at < n->done_at + beat) {
                pending = 1;
                continue;
            }
            if (server->clients < server->g->from_count) {
                ms_fail(m, FAIL_EXIT,
                        "node '%s': application %s exited with status 0 without connecting to node '%s' (%u of %zu "
                        "clients connected)",
                        n->g->name, n->g->exec_argc ? n->g->exec[0] : "?", server->g->name, server->clients,
                        server->g->from_count);
                n->check_connected = 0;
                return;
            }
        }
        n->check_connected = pending;
    }
}

/* A node whose CONFIG said links=later gets its chain once it and every
 * peer of its group listen (their addresses are in its links). */
static int send_links_when_peers_listen(ms *m, ms_node *n, tsr_error *err)
{
    const tsr_graph_node *display = m->nodes[n->g->to[0]].g;
    for (size_t f = 0; f < display->from_count; f++) {
        const ms_node *peer = &m->nodes[display->from[f]];
        if (ms_role_of(m, peer->index) == ms_role_of(m, n->index) && peer->state < N_READY)
            return TSR_OK;
    }
    tsr_ctl_out out;
    tsr_ctl_out_init(&out);
    tsr_error e = {0};
    int rc = ms_add_links(m, n, &out, &e);
    if (rc == TSR_OK)
        rc = ms_send_ctl(n->conn, TSR_MS_MSG_LINKS, &out, &e);
    tsr_ctl_out_free(&out);
    if (rc == TSR_EINVAL)
        return tsr_error_set(err, rc, "%s", e.message);
    if (rc != TSR_OK)
        ms_fail(m, FAIL_OTHER, "node '%s': cannot send its chain: %s", n->g->name, e.message);
    n->links_sent = 1;
    return TSR_OK;
}

/* Configures every joined node whose servers all listen (and, if they
 * take their chain later, have it), and sends the chain to nodes whose
 * peers all listen. */
static int configure(ms *m, tsr_error *err)
{
    for (size_t i = 0; i < m->count; i++) {
        ms_node *n = &m->nodes[i];
        if (n->links_later && !n->links_sent && n->state == N_READY &&
            send_links_when_peers_listen(m, n, err) != TSR_OK)
            return TSR_EINVAL;
        if (n->state != N_JOINED)
            continue;
        int ready = 1;
        for (size_t t = 0; t < n->g->to_count; t++) {
            const ms_node *server = &m->nodes[n->g->to[t]];
            ready &= server->state >= N_READY && (!server->links_later || server->links_sent);
        }
        if (!ready)
            continue;
        tsr_error e = {0};
        int rc = ms_send_config(m, n, &e);
        if (rc == TSR_EINVAL)
            return tsr_error_set(err, rc, "%s", e.message);
        if (rc != TSR_OK) {
            ms_fail(m, FAIL_OTHER, "node '%s': cannot send its configuration: %s", n->g->name, e.message);
            continue;
        }
        n->state = N_CONFIGURED;
        n->configured_at = n->last_heard = tsr_now_seconds();
    }
    return TSR_OK;
}

static void progress(ms *m, int final)
{
    if (!m->cfg->progress)
        return;
    double t = tsr_now_seconds();
    if (!final && t < m->next_progress)
        return;
    m->next_progress = t + 0.25;
    char line[1024];
    size_t used = (size_t)snprintf(line, sizeof line, "%.1fs", t - m->start);
    for (size_t i = 0; i < m->count && used < sizeof line; i++) {
        const ms_node *n = &m->nodes[i];
        const char *state = n->state == N_WAITING ? "waiting"
                            : n->state < N_READY  ? "starting"
                            : n->state == N_DONE  ? "done"
                                                  : NULL;
        if (n->server && !state)
            used += (size_t)snprintf(line + used, sizeof line - used, " | %s %.0f fr %.1f fr/s %.1f MB/s", n->g->name,
                                     n->frames, n->fps, n->mbps);
        else
            used +=
                (size_t)snprintf(line + used, sizeof line - used, " | %s %s", n->g->name, state ? state : "running");
    }
    fprintf(stderr, "\r\033[K%s", line);
    if (final)
        fputc('\n', stderr);
    fflush(stderr);
    m->progress_shown = 1;
}

/* --- the run ---------------------------------------------------------- */

static int prepare(ms *m, tsr_error *err)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s", tsr_graph_file(m->graph));
    char *dir = dirname(path);
    if (!realpath(dir, m->graph_dir))
        snprintf(m->graph_dir, sizeof m->graph_dir, "%s", dir);
    for (size_t i = 0; i < m->count; i++) {
        ms_node *n = &m->nodes[i];
        n->g = tsr_graph_node_at(m->graph, i);
        n->index = i;
        n->server = n->g->exec == NULL;
        n->app_stats = n->server ? -1 : 0;
        n->local = m->cfg->launch_local && is_local_host(n->g->host);
        /* The node's network SPU: the first whose class declares a role. */
        n->network_link = n->g->chain_length;
        for (size_t l = 0; l < n->g->chain_length && !n->network; l++) {
            tsr_error e = {0};
            const tsr_spu_class *cls = tsr_spu_find(n->g->chain[l].spu, &e);
            if (!cls)
                return tsr_error_set(err, TSR_EINVAL, "%s:%d:%d: node '%s': %s", tsr_graph_file(m->graph),
                                     n->g->mark.line, n->g->mark.column, n->g->name, e.message);
            if (cls->network.role != TSR_SPU_ROLE_NONE) {
                n->network = cls;
                n->network_link = l;
                /* An application peer (in situ) has no address to wait
                 * for: its peers' are derived from the display's. */
                n->links_later = cls->network.peers != NULL && n->server;
            }
        }
        if (n->server && n->g->transport == TSR_TRANSPORT_INPROC)
            return tsr_error_set(err, TSR_EINVAL,
                                 "%s:%d:%d: node '%s': transport inproc cannot be run as its own "
                                 "process yet; use tcp or unix",
                                 tsr_graph_file(m->graph), n->g->mark.line, n->g->mark.column, n->g->name);
        if (m->cfg->launch_local && !n->local && !m->cfg->listen)
            return tsr_error_set(err, TSR_EINVAL,
                                 "%s:%d:%d: node '%s' runs on host '%s': give --listen ADDR (an address "
                                 "that host reaches) and start it there with tessera node --mothership",
                                 tsr_graph_file(m->graph), n->g->mark.line, n->g->mark.column, n->g->name, n->g->host);
    }
    return TSR_OK;
}

static int run(ms *m, tsr_error *err)
{
    tsr_net_config nc;
    tsr_net_config_defaults(&nc);
    nc.node_name = "mothership";
    nc.token = m->cfg->token;
    nc.idle_timeout_ms = 2 * m->cfg->timeout_ms;
    nc.close_timeout_ms = 1000;
    m->net = tsr_net_create(&nc, err);
    if (!m->net)
        return TSR_EIO;
    tsr_error e = {0};
    m->listener = tsr_net_listen(m->net, m->cfg->listen ? m->cfg->listen : "tcp://127.0.0.1:0", &e);
    if (!m->listener)
        return tsr_error_set(err, e.code ? e.code : TSR_EIO, "control channel: %s", e.message);
    const char *control = tsr_net_listener_address(m->listener);
    if (m->cfg->on_listening)
        m->cfg->on_listening(control, m->cfg->ctx);
    m->start = tsr_now_seconds();
    /* An application whose node died is re-parented to us, not to init,
     * so we can reap it (and a container's init need not). */
    if (m->cfg->launch_local) {
        prctl(PR_SET_CHILD_SUBREAPER, 1);
        const char *base = getenv("TMPDIR");
        snprintf(m->run_tmp, sizeof m->run_tmp, "%s/tessera-run-XXXXXX", base && *base ? base : "/tmp");
        if (!mkdtemp(m->run_tmp))
            m->run_tmp[0] = '\0'; /* nodes then use /tmp themselves */
    }
    for (size_t i = 0; i < m->count; i++)
        if (m->nodes[i].local && ms_launch(m, &m->nodes[i], control, err) != TSR_OK)
            return TSR_EIO;

    int done = 0;
    double all_done_at = 0, last_round = tsr_now_seconds();
    while (!done) {
        if (m->cfg->interrupted && *m->cfg->interrupted)
            ms_fail(m, FAIL_INTERRUPT, "interrupted by signal %d", (int)*m->cfg->interrupted);
        /* A round takes about POLL_MS. One that took longer than the nodes
         * wait for a silent mothership (3 x timeout_ms, agent.c) means this
         * process was stopped (SIGSTOP) or starved: its nodes have given
         * up on it, and their ends are the echo, not the cause. */
        double round_start = tsr_now_seconds();
        if ((round_start - last_round) * 1000.0 > 3.0 * m->cfg->timeout_ms)
            ms_fail(m, FAIL_SIGNAL,
                    "the mothership was stopped or starved for %.0f ms (its nodes take %u ms of silence "
                    "for a lost mothership: 3 x --timeout-ms)",
                    (round_start - last_round) * 1000.0, 3 * m->cfg->timeout_ms);
        last_round = round_start;
        tsr_net_conn *c;
        while (m->pending_count < MAX_PENDING && (c = tsr_net_accept(m->listener, 0, &e)) != NULL) {
            m->pending[m->pending_count].conn = c;
            m->pending[m->pending_count++].since = tsr_now_seconds();
        }
        ms_receive(m);
        ms_reap(m);
        if (m->fail_class == FAIL_NONE) {
            check(m);
            check_unconnected(m);
            if (configure(m, err) != TSR_OK)
                ms_fail(m, FAIL_OTHER, "%s", err->message);
        } else if (m->fail_class > FAIL_HEARTBEAT) {
            /* Within FAIL_GRACE_S a more telling failure may still come:
             * the silent client may be a node whose missed heartbeat names
             * it, and a server killed outright loses its control
             * connection as its application's pack sees the data
             * connection go and exits 1, which its node may report first
             * (run_mothership_separate_nodes_server_killed_names_it
             * named the application once under ASan). */
            check(m);
        }
        if (m->fail_class != FAIL_NONE) {
            if (tsr_now_seconds() >= m->fail_deadline)
                break;
            continue;
        }
        progress(m, 0);
        int all = 1, children = 0;
        for (size_t i = 0; i < m->count; i++) {
            all &= m->nodes[i].state == N_DONE;
            children |= m->nodes[i].pid && !m->nodes[i].reaped;
        }
        if (all && !all_done_at)
            all_done_at = tsr_now_seconds();
        if (all && (!children || tsr_now_seconds() - all_done_at > END_GRACE_S))
            done = 1;
    }
    return TSR_OK;
}

int tsr_mothership_run(const tsr_graph *graph, const tsr_ms_config *config, tsr_error *err)
{
    ms m;
    memset(&m, 0, sizeof m);
    m.graph = graph;
    m.cfg = config;
    m.count = tsr_graph_node_count(graph);
    m.fail_class = FAIL_NONE;
    m.nodes = calloc(m.count, sizeof *m.nodes);
    if (!m.nodes)
        return tsr_error_set(err, TSR_ENOMEM, "out of memory");
    int rc = prepare(&m, err);
    if (rc == TSR_OK)
        rc = run(&m, err);
    int ok = rc == TSR_OK && m.fail_class == FAIL_NONE;
    if (m.progress_shown)
        progress(&m, 1);
    if (!ok && m.fail_class != FAIL_NONE)
        ms_stop_all(&m, m.fail_message);
    ms_kill_groups(&m);
    if (m.run_tmp[0])
        nftw(m.run_tmp, ms_remove_entry, 16, FTW_DEPTH | FTW_PHYS);
    double wall = m.start ? tsr_now_seconds() - m.start : 0;
    if (rc == TSR_OK && m.fail_class != FAIL_NONE)
        rc = tsr_error_set(err, TSR_EIO, "%s", m.fail_message);
    if (config->program_end)
        config->program_end->is_verdict = m.fail_class != FAIL_NONE && m.fail_is_program;
    if (m.start) {
        if (ok)
            ms_summary(&m, wall);
        if (config->stats_path) {
            tsr_error serr = {0};
            if (ms_write_stats(&m, ok, wall, &serr) != TSR_OK && rc == TSR_OK)
                rc = tsr_error_set(err, serr.code, "%s", serr.message);
        }
    }
    for (size_t i = 0; i < m.pending_count; i++)
        tsr_net_conn_close(m.pending[i].conn);
    for (size_t i = 0; i < m.count; i++)
        if (m.nodes[i].conn)
            tsr_net_conn_close(m.nodes[i].conn);
    if (m.listener)
        tsr_net_listener_close(m.listener);
    if (m.net)
        tsr_net_destroy(m.net);
    for (size_t i = 0; m.nodes && i < m.count; i++)
        free(m.nodes[i].sort_first);
    free(m.nodes);
    return rc;
}
