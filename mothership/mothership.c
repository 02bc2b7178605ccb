/* mothership/mothership.c — the coordinator (mothership.h): plan, launch,
 * configure in start order, watch heartbeats and children, report, and
 * stop everything on the first failure.
 * Owns: the control tsr_net, every control connection, the launched
 * children (one process group each) and the run's statistics.
 * Never: blocks longer than POLL_MS in its loop, so a failure anywhere is
 * seen within timeout_ms + POLL_MS. */
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
#include "mothership.h"
#include "net.h"
#include "control.h"
#include "tessera/spu.h"
#include "util.h"

#define POLL_MS 20
#define FAIL_GRACE_S \
    1.0                  /* collect related failures before naming one (a loaded
                              machine may see the root cause after its echo) */
#define LOST_GRACE_S 1.0 /* a launched node's lost connection: wait this long for its exit status */
#define STOP_GRACE_S 1.0 /* after STOP, before SIGKILL */
#define END_GRACE_S 5.0  /* after every DONE, for the processes to exit */
#define MAX_PENDING 64


/* Failure classes, most telling first: a killed or stalled process
 * explains the exits that follow it (an app whose server died exits 1). A
 * server's client dropped for silence is a stopped or hung process too,
 * but when that process is a node of the run its missed heartbeat, found
 * at about the same time (both wait the run's time-out), names it
 * directly; so the silent client ranks just after. A control connection
 * lost without an exit status to explain it (a node on another machine)
 * most likely means that node died. Last, a server whose only failures
 * are clients that went away unclosed: that is the echo of the client's
 * own end (an application that failed and exited), which its node reports
 * with the reason, usually just after the server saw the socket close. */
enum {
    FAIL_INTERRUPT,
    FAIL_SIGNAL,
    FAIL_HEARTBEAT,
    FAIL_SILENT,
    FAIL_LOST,
    FAIL_EXIT,
    FAIL_OTHER,
    FAIL_ECHO,
    FAIL_NONE
};

typedef enum { N_WAITING, N_JOINED, N_CONFIGURED, N_READY, N_DONE } node_state;

typedef struct ms_node {
    const tsr_graph_node *g;
    size_t index;
    int server;
    int local; /* launched by us */
    pid_t pid; /* launched child (process group leader); 0 = none */
    int reaped, wstatus;
    tsr_net_conn *conn;
    int conn_ended;
    double lost_at; /* control connection failed at; 0 = not */
    char lost_why[520];
    node_state state;
    double last_heard, configured_at, done_at;
    char address[TSR_NET_ADDRESS_MAX];
    char host[128];
    long remote_pid;
    /* statistics (running totals from STATS / DONE) */
    double frames, buffers, bytes_in, bytes_out, busy, blocked, elapsed;
    unsigned clients;
    int app_stats;                /* -1 not an app, 0 missing, 1 found */
    const tsr_spu_class *network; /* its network SPU's class (the first with a role), or NULL */
    size_t network_link;          /* that SPU's place in the chain (chain_length: none) */
    int links_later;              /* its network SPU takes its peers' addresses: CONFIG without
                                     the chain, LINKS once every peer is READY */
    int links_sent;
    char *sort_first; /* a tilesort app's "sort_first" statistics (JSON), or NULL */
    double rate_t, rate_frames, rate_bytes, fps, mbps;
    int done_status;
    double stats_at;     /* last STATS received */
    int check_connected; /* an app that ended well without statistics: did it reach its servers? */
} ms_node;

typedef struct pending_conn {
    tsr_net_conn *conn;
    double since;
} pending_conn;

typedef struct ms {
    const tsr_graph *graph;
    const tsr_ms_config *cfg;
    size_t count;
    ms_node *nodes;
    tsr_net *net;
    tsr_net_listener *listener;
    pending_conn pending[MAX_PENDING];
    size_t pending_count;
    char graph_dir[PATH_MAX];
    char run_tmp[PATH_MAX]; /* TMPDIR of launched nodes, removed at the end */
    double start;
    int fail_class;
    double fail_deadline;
    char fail_message[512];
    int failing_program; /* set around fail() for the exec program's own end */
    int fail_is_program; /* the verdict is that end */
    double next_progress;
    int progress_shown;
} ms;

static void fail(ms *m, int cls, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void fail(ms *m, int cls, const char *fmt, ...)
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

/* --- plan ------------------------------------------------------------- */

typedef struct strbuf {
    char *s;
    size_t len, cap;
    int failed;
} strbuf;

static void sb_add(strbuf *b, const char *s, size_t n)
{
    if (b->failed)
        return;
    if (b->len + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap * 2 : 256;
        while (cap < b->len + n + 1)
            cap *= 2;
        char *p = realloc(b->s, cap);
        if (!p) {
            b->failed = 1;
            return;
        }
        b->s = p;
        b->cap = cap;
    }
    memcpy(b->s + b->len, s, n);
    b->len += n;
    b->s[b->len] = '\0';
}

static void sb_str(strbuf *b, const char *s) { sb_add(b, s, strlen(s)); }

/* "X:Y:W:H" of a graph tile (tessera/tiles.h), after `prefix`. */
static void sb_tile(strbuf *b, const char *prefix, const tsr_graph_tile *t)
{
    char text[80];
    snprintf(text, sizeof text, "%s%d:%d:%d:%d", prefix, t->x, t->y, t->width, t->height);
    sb_str(b, text);
}

/* The node's own tiles, "X:Y:W:H,..." (its `tiles:`). */
static void own_tiles(const tsr_graph_node *g, strbuf *list)
{
    for (size_t t = 0; t < g->tile_count; t++)
        sb_tile(list, t ? "," : "", &g->tiles[t]);
}

/* Every server's tiles, "S:X:Y:W:H,..." (S = index in `to:`). */
static void server_tiles(const ms *m, const tsr_graph_node *g, strbuf *list)
{
    for (size_t s = 0; s < g->to_count; s++) {
        const tsr_graph_node *server = m->nodes[g->to[s]].g;
        for (size_t t = 0; t < server->tile_count; t++) {
            char prefix[24];
            snprintf(prefix, sizeof prefix, "%s%zu:", list->len ? "," : "", s);
            sb_tile(list, prefix, &server->tiles[t]);
        }
    }
}

/* The role of node `i`'s network SPU; NONE without one. */
static tsr_spu_role role_of(const ms *m, size_t i)
{
    return m->nodes[i].network ? m->nodes[i].network->network.role : TSR_SPU_ROLE_NONE;
}

/* The group of node `n`: the nodes sending to its first server with the
 * same role, in the graph's order (tessera/spu.h: rank, peers). Returns
 * n's place in it; `addresses` (may be NULL) gets the members' addresses. */
static int group_of(const ms *m, const ms_node *n, strbuf *addresses)
{
    const tsr_graph_node *server = m->nodes[n->g->to[0]].g;
    int rank = -1, members = 0;
    for (size_t f = 0; f < server->from_count; f++) {
        const ms_node *member = &m->nodes[server->from[f]];
        if (role_of(m, member->index) != role_of(m, n->index))
            continue;
        if (member == n)
            rank = members;
        if (addresses) {
            sb_str(addresses, members ? "," : "");
            sb_str(addresses, member->address);
        }
        members++;
    }
    return rank;
}

/* The addresses of the node's servers, in `to:` order. */
static void server_addresses(const ms *m, const tsr_graph_node *g, strbuf *list)
{
    for (size_t t = 0; t < g->to_count; t++) {
        sb_str(list, t ? "," : "");
        sb_str(list, m->nodes[g->to[t]].address);
    }
}

/* The values a graph run gives one link's options, as its class declares
 * them (tsr_spu_class.network): the node's own tiles for any SPU that takes
 * them; addresses, the token, server tiles, rank and peers for the node's
 * network SPU only. */
#define MAX_FILLED 8
typedef struct filled {
    const char *option[MAX_FILLED];
    strbuf value[MAX_FILLED];
    size_t count;
} filled;

static strbuf *fill(filled *f, const char *option)
{
    f->option[f->count] = option;
    return &f->value[f->count++];
}

static int fill_link(const ms *m, const ms_node *n, const tsr_spu_class *cls, int network, filled *f, tsr_error *err)
{
    const tsr_graph_node *g = n->g;
    const tsr_spu_network *role = &cls->network;
    if (role->tiles && g->tile_count)
        own_tiles(g, fill(f, role->tiles));
    if (!network)
        return TSR_OK;
    const char *one = role->server ? role->server : role->display;
    if (one && g->to_count != 1)
        return tsr_error_set(err, TSR_EINVAL, "node '%s': SPU %s sends to one server, but to: names %zu", g->name,
                             cls->name, g->to_count);
    if (one)
        server_addresses(m, g, fill(f, one));
    if (role->servers)
        server_addresses(m, g, fill(f, role->servers));
    if (role->token && m->cfg->token && m->cfg->token[0])
        sb_str(fill(f, role->token), m->cfg->token);
    if (role->server_tiles) {
        strbuf list = {0};
        server_tiles(m, g, &list);
        if (list.len)
            *fill(f, role->server_tiles) = list; /* none: the graph's value stays */
        else
            free(list.s);
    }
    if (role->rank) {
        char text[24];
        snprintf(text, sizeof text, "%d", group_of(m, n, NULL));
        sb_str(fill(f, role->rank), text);
    }
    if (role->peers)
        group_of(m, n, fill(f, role->peers));
    return TSR_OK;
}

/* The node's chain as structured links, one "link=SPU" field each followed
 * by its "option=KEY=VALUE" fields (control.h): the graph's options, then
 * the mothership's values (fill_link), which replace the graph's for the
 * same option. Each link is checked against its class as the node will
 * parse it, so a filled value that does not parse fails here. */
static int add_links(ms *m, const ms_node *n, tsr_ctl_out *out, tsr_error *err)
{
    const tsr_graph_node *g = n->g;
    int rc = TSR_OK;
    for (size_t i = 0; i < g->chain_length && rc == TSR_OK; i++) {
        const tsr_chain_link *l = &g->chain[i];
        tsr_error e = {0};
        const tsr_spu_class *cls = tsr_spu_find(l->spu, &e);
        if (!cls)
            return tsr_error_set(err, TSR_EINVAL, "node '%s': %s", g->name, e.message);
        filled f = {0};
        rc = fill_link(m, n, cls, i == n->network_link, &f, err);
        size_t total = l->option_count + f.count;
        const char **keys = calloc(total ? total : 1, sizeof *keys);
        const char **values = calloc(total ? total : 1, sizeof *values);
        if (rc == TSR_OK && (!keys || !values))
            rc = tsr_error_set(err, TSR_ENOMEM, "node '%s': out of memory", g->name);
        size_t count = 0;
        for (size_t k = 0; k < l->option_count && rc == TSR_OK; k++) {
            int replaced = 0;
            for (size_t j = 0; j < f.count; j++)
                replaced |= !strcmp(l->keys[k], f.option[j]);
            if (!replaced) {
                keys[count] = l->keys[k];
                values[count++] = l->values[k];
            }
        }
        for (size_t j = 0; j < f.count && rc == TSR_OK; j++) {
            if (f.value[j].failed)
                rc = tsr_error_set(err, TSR_ENOMEM, "node '%s': out of memory", g->name);
            keys[count] = f.option[j];
            values[count++] = f.value[j].s ? f.value[j].s : "";
        }
        if (rc == TSR_OK && tsr_spu_check_options(cls, keys, values, count, &e) != TSR_OK)
            rc = tsr_error_set(err, TSR_EINVAL, "node '%s': %s", g->name, e.message);
        if (rc == TSR_OK) {
            tsr_ctl_add(out, "link", l->spu);
            for (size_t k = 0; k < count; k++) {
                /* Values may be long (every server's tiles): no fixed buffer. */
                size_t size = strlen(keys[k]) + strlen(values[k]) + 2;
                char *field = malloc(size);
                if (field) {
                    snprintf(field, size, "%s=%s", keys[k], values[k]);
                    tsr_ctl_add(out, "option", field);
                } else {
                    out->failed = 1;
                }
                free(field);
            }
        }
        for (size_t j = 0; j < f.count; j++)
            free(f.value[j].s);
        free(keys);
        free(values);
    }
    return rc;
}

/* Where a server listens: listen=ADDR when the graph names a host (or a
 * unix path), else listen_port=PORT and the node picks the host
 * (loopback unless its --bind says otherwise). */
static void add_listen(tsr_ctl_out *out, const tsr_graph_node *g)
{
    if (g->transport == TSR_TRANSPORT_UNIX)
        tsr_ctl_addf(out, "listen", "unix:%s", g->listen ? g->listen : "");
    else if (!g->listen)
        tsr_ctl_add(out, "listen_port", "0");
    else if (!strchr(g->listen, ':'))
        tsr_ctl_add(out, "listen_port", g->listen);
    else
        tsr_ctl_addf(out, "listen", "tcp://%s", g->listen);
}

static int send_ctl(tsr_net_conn *conn, unsigned kind, tsr_ctl_out *out, tsr_error *err)
{
    if (out->failed)
        return tsr_error_set(err, TSR_ENOMEM, "control message: out of memory");
    return tsr_net_send(conn, kind, out->text ? out->text : "", out->len, 2000, err);
}

static uint32_t heartbeat_ms(const ms *m)
{
    uint32_t hb = m->cfg->timeout_ms / 5;
    return hb < 10 ? 10 : hb > 1000 ? 1000 : hb;
}

static int send_config(ms *m, ms_node *n, tsr_error *err)
{
    const tsr_graph_node *g = n->g;
    tsr_ctl_out out;
    tsr_ctl_out_init(&out);
    tsr_ctl_add(&out, "name", g->name);
    tsr_ctl_add(&out, "role", n->server ? "server" : "app");
    int rc = TSR_OK;
    if (n->links_later)
        tsr_ctl_add(&out, "links", "later");
    else
        rc = add_links(m, n, &out, err);
    if (rc != TSR_OK) {
        tsr_ctl_out_free(&out);
        return rc == TSR_ENOMEM ? rc : TSR_EINVAL;
    }
    tsr_ctl_addf(&out, "heartbeat_ms", "%u", heartbeat_ms(m));
    for (size_t i = 0; i < g->chain_length; i++) {
        const tsr_chain_link *l = &g->chain[i];
        for (size_t k = 0; k < l->option_count; k++) {
            if (strcmp(l->keys[k], "output") && strcmp(l->keys[k], "file"))
                continue;
            char dir[PATH_MAX];
            snprintf(dir, sizeof dir, "%s", l->values[k]);
            char *slash = strrchr(dir, '/');
            if (!slash || slash == dir)
                continue;
            *slash = '\0';
            tsr_ctl_add(&out, "mkdir", dir);
        }
    }
    tsr_ctl_add(&out, "base", m->graph_dir);
    if (m->cfg->token && m->cfg->token[0])
        tsr_ctl_add(&out, "token", m->cfg->token);
    if (n->server) {
        add_listen(&out, g);
        tsr_ctl_addf(&out, "clients", "%zu", g->from_count);
        uint32_t wait = m->cfg->join_timeout_ms > 60000 ? m->cfg->join_timeout_ms : 60000;
        tsr_ctl_addf(&out, "timeout_ms", "%u", wait);
        /* A client (the application's stream client) silent this long is
         * stopped or dead: the server drops it, which ends the run. */
        tsr_ctl_addf(&out, "idle_timeout_ms", "%u", m->cfg->timeout_ms);
    } else {
        const char *const *argv = m->cfg->app_exec ? m->cfg->app_exec : g->exec;
        if (m->cfg->exec_argv && m->cfg->exec_node && !strcmp(m->cfg->exec_node, g->name))
            argv = m->cfg->exec_argv;
        for (size_t i = 0; argv[i]; i++)
            tsr_ctl_add(&out, "arg", argv[i]);
    }
    rc = send_ctl(n->conn, TSR_MS_MSG_CONFIG, &out, err);
    tsr_ctl_out_free(&out);
    return rc;
}

/* --- launching -------------------------------------------------------- */

static int launch(ms *m, ms_node *n, const char *control, tsr_error *err)
{
    char timeout[32];
    snprintf(timeout, sizeof timeout, "%u", m->cfg->timeout_ms);
    const char *argv[] = {"tessera",  "node",         "--mothership", control, "--name",
                          n->g->name, "--timeout-ms", timeout,        NULL};
    /* Everything the child needs is made before fork: this process has
     * threads, so the child may only make async-signal-safe calls. */
    char token_var[TSR_NET_TOKEN_MAX + 32];
    snprintf(token_var, sizeof token_var, "TESSERA_TOKEN=%s", m->cfg->token ? m->cfg->token : "");
    char tmp_var[PATH_MAX + 8];
    snprintf(tmp_var, sizeof tmp_var, "TMPDIR=%s", m->run_tmp);
    const char *changes[] = {m->cfg->token && m->cfg->token[0] ? token_var : "TESSERA_TOKEN",
                             m->run_tmp[0] ? tmp_var : NULL, NULL};
    char **env = tsr_ms_environ(changes);
    char failed[PATH_MAX + 160];
    snprintf(failed, sizeof failed, "%s: node '%s': cannot start %s in %s\n", m->cfg->who, n->g->name, m->cfg->self_exe,
             m->cfg->out_dir ? m->cfg->out_dir : ".");
    if (!env)
        return tsr_error_set(err, TSR_ENOMEM, "node '%s': out of memory", n->g->name);
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) {
        free(env);
        return tsr_error_set(err, TSR_EIO, "node '%s': fork: %s", n->g->name, strerror(errno));
    }
    if (pid == 0) {
        setpgid(0, 0);
        signal(SIGINT, SIG_DFL);
        signal(SIGTERM, SIG_DFL);
        signal(SIGPIPE, SIG_DFL);
        if (!m->cfg->out_dir || chdir(m->cfg->out_dir) == 0)
            execve(m->cfg->self_exe, (char *const *)argv, env);
        ssize_t ignored = write(STDERR_FILENO, failed, strlen(failed));
        (void)ignored;
        _exit(127);
    }
    free(env);
    setpgid(pid, pid); /* both sides, so no signal can race the child's own call */
    n->pid = pid;
    return TSR_OK;
}

static void describe_status(int wstatus, char *out, size_t size)
{
    if (WIFSIGNALED(wstatus))
        snprintf(out, size, "killed by signal %d (%s)", WTERMSIG(wstatus), strsignal(WTERMSIG(wstatus)));
    else
        snprintf(out, size, "exited with status %d", WEXITSTATUS(wstatus));
}

static void receive(ms *m);

static void reap(ms *m)
{
    for (size_t i = 0; i < m->count; i++) {
        ms_node *n = &m->nodes[i];
        if (!n->pid || n->reaped)
            continue;
        int st;
        if (waitpid(n->pid, &st, WNOHANG) != n->pid)
            continue;
        n->reaped = 1;
        n->wstatus = st;
        char what[128];
        describe_status(st, what, sizeof what);
        if (WIFSIGNALED(st))
            fail(m, FAIL_SIGNAL, "node '%s' (pid %ld) %s", n->g->name, (long)n->pid, what);
        else if (n->state != N_DONE && WEXITSTATUS(st) && n->lost_at)
            /* No DONE could come: say what the node saw end first. */
            fail(m, FAIL_EXIT, "node '%s' (pid %ld) %s after its control connection was lost (%s)", n->g->name,
                 (long)n->pid, what, n->lost_why);
        else if (n->state != N_DONE && WEXITSTATUS(st))
            fail(m, FAIL_EXIT, "node '%s' (pid %ld) %s%s", n->g->name, (long)n->pid, what,
                 n->state == N_WAITING ? " before joining" : "");
        else if (n->state != N_DONE) {
            /* A node sends DONE and exits at once: its DONE may still be
             * queued here when the exit is seen (many nodes ending
             * together, e.g. a sort-last group). Read what is queued first. */
            receive(m);
            if (n->state != N_DONE)
                fail(m, FAIL_OTHER, "node '%s' (pid %ld) ended without reporting its end", n->g->name, (long)n->pid);
        }
    }
}

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
    send_ctl(conn, TSR_MS_MSG_REFUSE, &out, &ignored);
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
        fail(m, FAIL_OTHER, "%s", safe);
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
                fail(m, FAIL_OTHER, "node '%s' reported READY without its address", n->g->name);
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
            fail(m, FAIL_SILENT, "node '%s': %s", n->g->name, failure);
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
            fail(m, cls, "node '%s': %s", n->g->name, why && *why ? why : "failed (no reason given)");
        m->failing_program = 0;
        break;
    }
    default: fail(m, FAIL_OTHER, "node '%s' sent an unexpected %s message", n->g->name, tsr_ctl_kind_name(kind));
    }
}

/* One round of receiving: every message already queued, waiting at most
 * POLL_MS for the first. */
static void receive(ms *m)
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
            fail(m, FAIL_OTHER, "node '%s': %s", n ? n->g->name : "(joining)", perr.message);
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
            fail(m, FAIL_OTHER, "a connection sent %s before JOIN", tsr_ctl_kind_name(kind));
        } else {
            handle_message(m, n, kind, &ctl);
        }
        tsr_ctl_free(&ctl);
    }
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
            fail(m, FAIL_HEARTBEAT, "node '%s' was not ready within %u ms of its configuration", n->g->name,
                 m->cfg->join_timeout_ms);
        if (n->state == N_READY && !n->lost_at && (t - n->last_heard) * 1000.0 > m->cfg->timeout_ms)
            fail(m, FAIL_HEARTBEAT, "node '%s' sent no heartbeat for %.0f ms (stopped or hung; --timeout-ms %u)",
                 n->g->name, (t - n->last_heard) * 1000.0, m->cfg->timeout_ms);
        if (n->lost_at && !n->reaped && (!n->pid || t - n->lost_at > LOST_GRACE_S))
            fail(m, FAIL_LOST, "node '%s': control connection lost: %s", n->g->name, n->lost_why);
        if (n->state == N_WAITING && (t - m->start) * 1000.0 > m->cfg->join_timeout_ms)
            fail(m, FAIL_OTHER, "node '%s' did not join within %u ms%s", n->g->name, m->cfg->join_timeout_ms,
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
    double beat = heartbeat_ms(m) / 1000.0;
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
                fail(m, FAIL_EXIT,
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
        if (role_of(m, peer->index) == role_of(m, n->index) && peer->state < N_READY)
            return TSR_OK;
    }
    tsr_ctl_out out;
    tsr_ctl_out_init(&out);
    tsr_error e = {0};
    int rc = add_links(m, n, &out, &e);
    if (rc == TSR_OK)
        rc = send_ctl(n->conn, TSR_MS_MSG_LINKS, &out, &e);
    tsr_ctl_out_free(&out);
    if (rc == TSR_EINVAL)
        return tsr_error_set(err, rc, "%s", e.message);
    if (rc != TSR_OK)
        fail(m, FAIL_OTHER, "node '%s': cannot send its chain: %s", n->g->name, e.message);
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
        int rc = send_config(m, n, &e);
        if (rc == TSR_EINVAL)
            return tsr_error_set(err, rc, "%s", e.message);
        if (rc != TSR_OK) {
            fail(m, FAIL_OTHER, "node '%s': cannot send its configuration: %s", n->g->name, e.message);
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

/* --- ending ----------------------------------------------------------- */

static void stop_all(ms *m, const char *reason)
{
    tsr_ctl_out out;
    tsr_ctl_out_init(&out);
    tsr_ctl_add(&out, "reason", reason);
    for (size_t i = 0; i < m->count; i++) {
        ms_node *n = &m->nodes[i];
        if (n->conn && !n->conn_ended && n->state != N_DONE) {
            tsr_error ignored = {0};
            if (!out.failed)
                tsr_net_send(n->conn, TSR_MS_MSG_STOP, out.text, out.len, 200, &ignored);
        }
    }
    tsr_ctl_out_free(&out);
    double until = tsr_now_seconds() + STOP_GRACE_S;
    for (;;) {
        int running = 0;
        for (size_t i = 0; i < m->count; i++)
            running |= m->nodes[i].pid && !m->nodes[i].reaped;
        if (!running || tsr_now_seconds() >= until)
            break;
        struct timespec ts = {0, 10 * 1000000L};
        nanosleep(&ts, NULL);
        for (size_t i = 0; i < m->count; i++) {
            ms_node *n = &m->nodes[i];
            if (n->pid && !n->reaped && waitpid(n->pid, &n->wstatus, WNOHANG) == n->pid)
                n->reaped = 1;
        }
    }
}

/* Every process group we started is killed, whatever its leader did: an
 * application whose node died is still in its node's group. */
static void kill_groups(ms *m)
{
    for (size_t i = 0; i < m->count; i++) {
        ms_node *n = &m->nodes[i];
        if (!n->pid)
            continue;
        killpg(n->pid, SIGKILL);
        if (!n->reaped && waitpid(n->pid, &n->wstatus, 0) == n->pid)
            n->reaped = 1;
    }
    /* Orphans re-parented to us (we are their subreaper): reap them, so
     * not even a zombie of the run is left. Bounded: they were killed. */
    if (!m->cfg->launch_local)
        return;
    double until = tsr_now_seconds() + 1.0;
    while (tsr_now_seconds() < until) {
        pid_t w = waitpid(-1, NULL, WNOHANG);
        if (w < 0)
            break; /* ECHILD: none left */
        if (w == 0) {
            struct timespec ts = {0, 5 * 1000000L};
            nanosleep(&ts, NULL);
        }
    }
}

static int remove_entry(const char *path, const struct stat *st, int type, struct FTW *ftw)
{
    (void)st;
    (void)type;
    (void)ftw;
    remove(path);
    return 0;
}

/* Load imbalance of the servers' render time: max / mean of their busy
 * seconds (1: even; 0 without servers). */
static double render_imbalance(const ms *m)
{
    double max = 0, sum = 0;
    size_t n = 0;
    for (size_t i = 0; i < m->count; i++)
        if (m->nodes[i].server) {
            max = m->nodes[i].busy > max ? m->nodes[i].busy : max;
            sum += m->nodes[i].busy;
            n++;
        }
    return n && sum > 0 ? max / (sum / (double)n) : 0.0;
}

static int write_stats(ms *m, int ok, double wall, tsr_error *err)
{
    FILE *f = fopen(m->cfg->stats_path, "w");
    if (!f)
        return tsr_error_set(err, TSR_EIO, "--stats %s: %s", m->cfg->stats_path, strerror(errno));
    fprintf(f, "{\n  \"graph\": ");
    tsr_json_string(f, tsr_graph_file(m->graph));
    fprintf(f, ",\n  \"status\": \"%s\",\n  \"failure\": ", ok ? "ok" : "failed");
    if (ok)
        fprintf(f, "null");
    else
        tsr_json_string(f, m->fail_message);
    fprintf(f, ",\n  \"wall_seconds\": %.3f,\n  \"nodes\": [\n", wall);
    for (size_t i = 0; i < m->count; i++) {
        const ms_node *n = &m->nodes[i];
        fprintf(f, "    {\"name\": ");
        tsr_json_string(f, n->g->name);
        fprintf(f, ", \"role\": \"%s\", \"host\": ", n->server ? "server" : "app");
        tsr_json_string(f, n->host[0] ? n->host : n->g->host);
        fprintf(f, ", \"state\": \"%s\", \"seconds\": %.3f",
                n->state == N_DONE ? (n->done_status ? "failed" : "done") : "unfinished", n->elapsed);
        if (n->server || n->app_stats == 1) {
            fprintf(f, ", \"frames\": %.0f, \"buffers\": %.0f, \"bytes_in\": %.0f, \"bytes_out\": %.0f", n->frames,
                    n->buffers, n->bytes_in, n->bytes_out);
        } else {
            /* The application's network SPU wrote no TESSERA_STATS_FILE
             * (not every chain has one): unknown, not zero. */
            fprintf(f, ", \"frames\": null, \"buffers\": null, \"bytes_in\": null, \"bytes_out\": null");
        }
        if (n->server) {
            fprintf(f, ", \"address\": ");
            tsr_json_string(f, n->address);
            fprintf(f, ", \"render_seconds\": %.6f, \"blocked_seconds\": null, \"clients\": %u}", n->busy, n->clients);
        } else if (n->app_stats == 1)
            fprintf(f, ", \"render_seconds\": null, \"blocked_seconds\": %.6f, \"app_stats\": \"found\"%s%s}",
                    n->blocked, n->sort_first ? ", \"sort_first\": " : "", n->sort_first ? n->sort_first : "");
        else
            fprintf(f, ", \"render_seconds\": null, \"blocked_seconds\": null, \"app_stats\": \"missing\"}");
        fprintf(f, "%s\n", i + 1 < m->count ? "," : "");
    }
    fprintf(f, "  ],\n  \"server_render_imbalance\": %.6f\n}\n", render_imbalance(m));
    if (fclose(f))
        return tsr_error_set(err, TSR_EIO, "--stats %s: %s", m->cfg->stats_path, strerror(errno));
    return TSR_OK;
}

static void summary(ms *m, double wall)
{
    FILE *f = m->cfg->summary;
    if (!f)
        return;
    fprintf(f, "%s: %s in %.2f s\n", m->cfg->who, tsr_graph_file(m->graph), wall);
    for (size_t i = 0; i < m->count; i++) {
        const ms_node *n = &m->nodes[i];
        double secs = n->elapsed > 0 ? n->elapsed : wall;
        if (n->server)
            fprintf(f,
                    "  %-12s server: %.0f frames, %.1f frames/s, %.2f MB in (%.1f MB/s), render %.3f s, %u client%s\n",
                    n->g->name, n->frames, n->frames / secs, n->bytes_in / 1e6, n->bytes_in / 1e6 / secs, n->busy,
                    n->clients, n->clients == 1 ? "" : "s");
        else if (n->app_stats == 1)
            fprintf(f,
                    "  %-12s app:    %.0f frames, %.1f frames/s, %.2f MB out (%.1f MB/s), blocked on credits %.3f s\n",
                    n->g->name, n->frames, n->frames / secs, n->bytes_out / 1e6, n->bytes_out / 1e6 / secs, n->blocked);
        else
            fprintf(f, "  %-12s app:    ran %.2f s (no network statistics from its chain)\n", n->g->name, secs);
        double overlap, imbalance;
        if (n->sort_first && tsr_ms_json_number(n->sort_first, "overlap", &overlap) == 0 &&
            tsr_ms_json_number(n->sort_first, "imbalance", &imbalance) == 0)
            fprintf(f,
                    "  %-12s sort-first: overlap %.3f (bytes sent / stream), imbalance %.3f (max / mean "
                    "server bytes), server render time imbalance %.3f\n",
                    "", overlap, imbalance, render_imbalance(m));
    }
    fflush(f);
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
        if (m->nodes[i].local && launch(m, &m->nodes[i], control, err) != TSR_OK)
            return TSR_EIO;

    int done = 0;
    double all_done_at = 0, last_round = tsr_now_seconds();
    while (!done) {
        if (m->cfg->interrupted && *m->cfg->interrupted)
            fail(m, FAIL_INTERRUPT, "interrupted by signal %d", (int)*m->cfg->interrupted);
        /* A round takes about POLL_MS. One that took longer than the nodes
         * wait for a silent mothership (3 x timeout_ms, agent.c) means this
         * process was stopped (SIGSTOP) or starved: its nodes have given
         * up on it, and their ends are the echo, not the cause. */
        double round_start = tsr_now_seconds();
        if ((round_start - last_round) * 1000.0 > 3.0 * m->cfg->timeout_ms)
            fail(m, FAIL_SIGNAL,
                 "the mothership was stopped or starved for %.0f ms (its nodes take %u ms of silence "
                 "for a lost mothership: 3 x --timeout-ms)",
                 (round_start - last_round) * 1000.0, 3 * m->cfg->timeout_ms);
        last_round = round_start;
        tsr_net_conn *c;
        while (m->pending_count < MAX_PENDING && (c = tsr_net_accept(m->listener, 0, &e)) != NULL) {
            m->pending[m->pending_count].conn = c;
            m->pending[m->pending_count++].since = tsr_now_seconds();
        }
        receive(m);
        reap(m);
        if (m->fail_class == FAIL_NONE) {
            check(m);
            check_unconnected(m);
            if (configure(m, err) != TSR_OK)
                fail(m, FAIL_OTHER, "%s", err->message);
        } else if (m->fail_class == FAIL_SILENT) {
            check(m); /* the silent client may be a node: its missed heartbeat names it (FAIL_GRACE_S) */
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
        stop_all(&m, m.fail_message);
    kill_groups(&m);
    if (m.run_tmp[0])
        nftw(m.run_tmp, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
    double wall = m.start ? tsr_now_seconds() - m.start : 0;
    if (rc == TSR_OK && m.fail_class != FAIL_NONE)
        rc = tsr_error_set(err, TSR_EIO, "%s", m.fail_message);
    if (config->program_end)
        config->program_end->is_verdict = m.fail_class != FAIL_NONE && m.fail_is_program;
    if (m.start) {
        if (ok)
            summary(&m, wall);
        if (config->stats_path) {
            tsr_error serr = {0};
            if (write_stats(&m, ok, wall, &serr) != TSR_OK && rc == TSR_OK)
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
