/* mothership/agent.c — the node side of the control channel (`tessera node
 * --mothership`): joins, takes its CONFIG, runs a server (server/node.h on a
 * thread of its own) or an application (a child process with TESSERA_CHAIN
 * set), sends STATS as its heartbeat and DONE at the end.
 * Owns: its control connection, the server node or the application child
 * (which dies with this process: PR_SET_PDEATHSIG), and a private temporary
 * directory (unix socket, the application's statistics file).
 * Never: outlives a lost mothership — a STOP, or a control connection that
 * fails or stays silent, kills the application and ends the node. */
#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "tessera/chain.h"
#include "tessera/dev/util.h"
#include "mothership.h"
#include "tessera/dev/net.h"
#include "node.h"
#include "control.h"
#include "util.h"
#include "faker.h"
#include "tessera/log.h"

#define POLL_MS 20

typedef struct agent {
    const tsr_agent_config *cfg;
    tsr_net *net;
    tsr_net_conn *conn;
    char name[TSR_NET_NAME_MAX + 1];
    char tmpdir[128];
    uint32_t heartbeat_ms;
    double started;
    /* server */
    tsr_node *node;
    pthread_t thread;
    atomic_int node_done;
    int node_rc;
    tsr_error node_err;
    /* app */
    pid_t child;
    int app_exit_code; /* its exit status once it ended (DONE's exit_code) */
} agent;

static int send_ctl(agent *a, unsigned kind, tsr_ctl_out *out, tsr_error *err)
{
    if (out->failed)
        return tsr_error_set(err, TSR_ENOMEM, "control message: out of memory");
    return tsr_net_send(a->conn, kind, out->text ? out->text : "", out->len, 5000, err);
}

static void add_server_stats(agent *a, tsr_ctl_out *out)
{
    tsr_node_stats st;
    tsr_node_get_stats(a->node, &st);
    tsr_ctl_addf(out, "frames", "%llu", (unsigned long long)st.frames);
    tsr_ctl_addf(out, "buffers", "%llu", (unsigned long long)st.buffers);
    tsr_ctl_addf(out, "bytes_in", "%llu", (unsigned long long)st.bytes_in);
    tsr_ctl_addf(out, "bytes_out", "%llu", (unsigned long long)st.bytes_out);
    tsr_ctl_addf(out, "busy_seconds", "%.6f", st.busy_seconds);
    tsr_ctl_addf(out, "clients", "%u", st.clients_connected);
    tsr_ctl_addf(out, "clients_silent", "%u", st.clients_silent);
    tsr_ctl_addf(out, "clients_failed", "%u", st.clients_failed);
    tsr_ctl_addf(out, "clients_vanished", "%u", st.clients_vanished);
}

static const char *plain(const char *message) { return strncmp(message, "node: ", 6) ? message : message + 6; }

static int send_stats(agent *a, tsr_error *err)
{
    tsr_ctl_out out;
    tsr_ctl_out_init(&out);
    if (a->node) {
        add_server_stats(a, &out);
        /* A client dropped for silence while the others go on: the
         * mothership hears of it now, not when the last client ends (the
         * silent one's peers would by then have ended for it, and be
         * blamed). */
        char failure[512];
        if (tsr_node_silent_failure(a->node, failure, sizeof failure))
            tsr_ctl_add(&out, "failure", plain(failure));
    }
    tsr_ctl_addf(&out, "elapsed", "%.3f", tsr_now_seconds() - a->started);
    int rc = send_ctl(a, TSR_MS_MSG_STATS, &out, err);
    tsr_ctl_out_free(&out);
    return rc;
}

static void kill_child(agent *a)
{
    if (a->child > 0) {
        kill(a->child, SIGKILL);
        waitpid(a->child, NULL, 0);
        a->child = 0;
    }
}

static void remove_tmpdir(agent *a)
{
    if (!a->tmpdir[0])
        return;
    char path[320];
    snprintf(path, sizeof path, "%s/stats.json", a->tmpdir);
    unlink(path);
    snprintf(path, sizeof path, "%s/%s.sock", a->tmpdir, a->name);
    unlink(path);
    rmdir(a->tmpdir);
    a->tmpdir[0] = '\0';
}

static int make_tmpdir(agent *a, tsr_error *err)
{
    /* Under $TMPDIR: tessera run points it at a directory of the run that
     * it removes at the end, so even a killed node leaves nothing. */
    const char *base = getenv("TMPDIR");
    if (!base || !*base || strlen(base) > sizeof a->tmpdir - 24)
        base = "/tmp";
    snprintf(a->tmpdir, sizeof a->tmpdir, "%s/tessera-node-XXXXXX", base);
    if (!mkdtemp(a->tmpdir)) {
        a->tmpdir[0] = '\0';
        return tsr_error_set(err, TSR_EIO, "cannot create a temporary directory in %s: %s", base, strerror(errno));
    }
    return TSR_OK;
}

/* Waits up to `ms` for a control message and handles STOP / a lost
 * mothership. Returns 0 to go on, or the exit code (err filled). */
static int poll_control(agent *a, int ms, tsr_error *err)
{
    tsr_net_msg m;
    tsr_error e = {0};
    int rc = tsr_net_recv(a->conn, &m, ms, &e);
    if (rc == TSR_ETIMEDOUT)
        return 0;
    if (rc == 1) {
        int code = 0;
        if (m.kind == TSR_MS_MSG_STOP) {
            tsr_ctl msg;
            const char *reason = "no reason given";
            int parsed = tsr_ctl_parse(&msg, m.data, m.len, &e) == TSR_OK;
            if (parsed && tsr_ctl_get(&msg, "reason"))
                reason = tsr_ctl_get(&msg, "reason");
            tsr_error_set(err, TSR_ESTATE, "stopped by the mothership: %s", reason);
            if (parsed)
                tsr_ctl_free(&msg);
            code = 1;
        }
        tsr_net_msg_release(&m);
        return code;
    }
    if (rc == 0)
        tsr_error_set(err, TSR_ESTATE, "the mothership closed the control connection");
    else
        tsr_error_set(err, rc, "lost the mothership: %s", e.message);
    return 1;
}

/* links=later (control.h): heartbeats until the mothership sends LINKS,
 * parsed into `links` (its fields point into `msg`, freed by the caller).
 * Returns 0, or the exit code (err filled) on STOP or a lost mothership. */
static int wait_for_links(agent *a, tsr_ctl *msg, tsr_ctl_chain *links, tsr_error *err)
{
    double next_beat = tsr_now_seconds();
    for (;;) {
        if (tsr_now_seconds() >= next_beat) {
            if (send_stats(a, err) != TSR_OK)
                return 1;
            next_beat = tsr_now_seconds() + a->heartbeat_ms / 1000.0;
        }
        tsr_net_msg m;
        tsr_error e = {0};
        int rc = tsr_net_recv(a->conn, &m, POLL_MS, &e);
        if (rc == TSR_ETIMEDOUT)
            continue;
        if (rc != 1) {
            if (rc == 0)
                tsr_error_set(err, TSR_ESTATE, "the mothership closed the control connection");
            else
                tsr_error_set(err, rc, "lost the mothership: %s", e.message);
            return 1;
        }
        unsigned kind = m.kind;
        rc = kind == TSR_MS_MSG_LINKS || kind == TSR_MS_MSG_STOP ? tsr_ctl_parse(msg, m.data, m.len, err) : TSR_OK;
        tsr_net_msg_release(&m);
        if (rc != TSR_OK)
            return 1;
        if (kind == TSR_MS_MSG_STOP) {
            const char *reason = tsr_ctl_get(msg, "reason");
            tsr_error_set(err, TSR_ESTATE, "stopped by the mothership: %s", reason ? reason : "no reason given");
            tsr_ctl_free(msg);
            return 1;
        }
        if (kind != TSR_MS_MSG_LINKS)
            continue;
        if (tsr_ctl_chain_parse(msg, links, err) != TSR_OK) {
            tsr_ctl_free(msg);
            return 2;
        }
        return 0;
    }
}

static void *server_thread(void *arg)
{
    agent *a = arg;
    a->node_rc = tsr_node_run(a->node, &a->node_err);
    atomic_store(&a->node_done, 1);
    return NULL;
}

static int send_done(agent *a, int status, const char *message, int signal_number,
                     void (*extra)(agent *, tsr_ctl_out *), tsr_error *err)
{
    tsr_ctl_out out;
    tsr_ctl_out_init(&out);
    tsr_ctl_addf(&out, "status", "%d", status);
    tsr_ctl_add(&out, "message", message);
    tsr_ctl_addf(&out, "signal", "%d", signal_number);
    tsr_ctl_addf(&out, "elapsed", "%.3f", tsr_now_seconds() - a->started);
    if (a->node)
        add_server_stats(a, &out);
    if (extra)
        extra(a, &out);
    int rc = send_ctl(a, TSR_MS_MSG_DONE, &out, err);
    tsr_ctl_out_free(&out);
    return rc;
}

static int run_server(agent *a, const tsr_ctl *cfg, tsr_error *err)
{
    const char *listen = tsr_ctl_get(cfg, "listen");
    const char *port = tsr_ctl_get(cfg, "listen_port");
    char address[TSR_NET_ADDRESS_MAX];
    if (!listen || !*listen) {
        const char *host = a->cfg->bind && *a->cfg->bind ? a->cfg->bind : "127.0.0.1";
        if (tsr_net_address_tcp(host, port && *port ? port : "0", address, sizeof address, err) != TSR_OK) {
            send_done(a, 1, err->message, 0, NULL, &(tsr_error){0});
            return 2;
        }
        listen = address;
    }
    if (!strcmp(listen, "unix:")) {
        if (make_tmpdir(a, err) != TSR_OK) {
            send_done(a, 1, err->message, 0, NULL, &(tsr_error){0});
            return 1;
        }
        tsr_net_address place = {.transport = TSR_NET_UNIX};
        int n = snprintf(place.path, sizeof place.path, "%s/%s.sock", a->tmpdir, a->name);
        if (n < 0 || (size_t)n >= sizeof place.path ||
            tsr_net_address_format(&place, address, sizeof address, NULL) != TSR_OK) {
            tsr_error_set(err, TSR_EINVAL, "unix socket path %s/%s.sock is too long (a shorter TMPDIR helps)",
                          a->tmpdir, a->name);
            send_done(a, 1, err->message, 0, NULL, &(tsr_error){0});
            return 1;
        }
        listen = address;
    }
    /* links=later: the chain comes once the peers listen (control.h). */
    const char *later = tsr_ctl_get(cfg, "links");
    int chain_later = later && !strcmp(later, "later");
    tsr_ctl_chain chain = {0};
    if (!chain_later && tsr_ctl_chain_parse(cfg, &chain, err) != TSR_OK) {
        send_done(a, 1, err->message, 0, NULL, &(tsr_error){0});
        return 2;
    }
    tsr_node_config nc = {
        .listen = listen,
        .links = chain.links,
        .link_count = chain.count,
        .chain_later = chain_later,
        .token = tsr_ctl_get(cfg, "token"),
        .name = a->name,
        .clients = (unsigned)tsr_ctl_number(cfg, "clients", 1),
        .timeout_ms = (uint32_t)tsr_ctl_number(cfg, "timeout_ms", 60000),
        .idle_timeout_ms = (uint32_t)tsr_ctl_number(cfg, "idle_timeout_ms", 15000),
    };
    tsr_error e = {0};
    a->node = tsr_node_create(&nc, &e);
    tsr_ctl_chain_free(&chain); /* the node copied it */
    if (!a->node) {
        tsr_error_set(err, e.code, "%s", plain(e.message));
        send_done(a, 1, err->message, 0, NULL, &(tsr_error){0});
        return e.code == TSR_EINVAL ? 2 : 1;
    }
    tsr_ctl_out out;
    tsr_ctl_out_init(&out);
    tsr_ctl_add(&out, "address", tsr_node_address(a->node));
    int rc = send_ctl(a, TSR_MS_MSG_READY, &out, err);
    tsr_ctl_out_free(&out);
    if (rc != TSR_OK)
        return 1;
    if (chain_later) {
        tsr_ctl msg;
        int code = wait_for_links(a, &msg, &chain, err);
        if (code) {
            if (code == 2)
                send_done(a, 1, err->message, 0, NULL, &(tsr_error){0});
            tsr_node_destroy(a->node);
            a->node = NULL;
            return code;
        }
        rc = tsr_node_set_links(a->node, chain.links, chain.count, &e);
        tsr_ctl_chain_free(&chain);
        tsr_ctl_free(&msg);
        if (rc != TSR_OK) {
            tsr_error_set(err, e.code, "%s", plain(e.message));
            send_done(a, 1, err->message, 0, NULL, &(tsr_error){0});
            tsr_node_destroy(a->node);
            a->node = NULL;
            return e.code == TSR_EINVAL ? 2 : 1;
        }
    }
    if (pthread_create(&a->thread, NULL, server_thread, a)) {
        tsr_error_set(err, TSR_EIO, "cannot start the server thread");
        return 1;
    }
    double next_beat = tsr_now_seconds();
    int silent_reported = 0;
    while (!atomic_load(&a->node_done)) {
        if (!silent_reported && tsr_node_silent_failure(a->node, NULL, 0)) {
            silent_reported = 1;
            next_beat = 0; /* its STATS carries the failure: send it now */
        }
        if (tsr_now_seconds() >= next_beat) {
            if (send_stats(a, err) != TSR_OK)
                return 1; /* the node thread still runs: the caller ends the process */
            next_beat = tsr_now_seconds() + a->heartbeat_ms / 1000.0;
        }
        int code = poll_control(a, POLL_MS, err);
        if (code)
            return code;
    }
    pthread_join(a->thread, NULL);
    int status = a->node_rc == TSR_OK ? 0 : 1;
    if (status)
        tsr_error_set(err, a->node_rc, "%s", plain(a->node_err.message));
    send_done(a, status, status ? err->message : "", 0, NULL, &(tsr_error){0});
    tsr_node_destroy(a->node);
    a->node = NULL;
    return status;
}

/* Where a relative exec is found (see mothership.h). */
static int resolve_exec(const tsr_ctl *cfg, const char *prog, char *out, size_t size, tsr_error *err)
{
    char tried[1024] = "";
    size_t used = 0;
    if (prog[0] == '/') {
        snprintf(out, size, "%s", prog);
        if (access(out, X_OK) == 0)
            return TSR_OK;
        return tsr_error_set(err, TSR_ENOENT, "exec '%s': %s", prog, strerror(errno));
    }
    if (!strchr(prog, '/')) {
        const char *path = getenv("PATH");
        if (!path || !*path)
            path = "/usr/local/bin:/usr/bin:/bin";
        while (*path) {
            size_t n = strcspn(path, ":");
            snprintf(out, size, "%.*s/%s", (int)n, path, prog);
            if (n && access(out, X_OK) == 0)
                return TSR_OK;
            path += n + (path[n] == ':');
        }
        return tsr_error_set(err, TSR_ENOENT, "exec '%s': not found in PATH", prog);
    }
    /* Bases: the mothership's (graph directory), this program's prefix,
     * the working directory. */
    char self[PATH_MAX];
    char prefix[PATH_MAX] = "";
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n > 0) {
        self[n] = '\0';
        char *slash = strrchr(self, '/');
        if (slash) {
            *slash = '\0';
            slash = strrchr(self, '/');
            if (slash) {
                *slash = '\0';
                snprintf(prefix, sizeof prefix, "%s", self[0] ? self : "/");
            }
        }
    }
    for (size_t i = 0; i <= cfg->count + 1; i++) {
        const char *base;
        if (i < cfg->count) {
            if (strcmp(cfg->keys[i], "base"))
                continue;
            base = cfg->values[i];
        } else if (i == cfg->count) {
            base = prefix;
        } else {
            base = ".";
        }
        if (!base[0])
            continue;
        snprintf(out, size, "%s/%s", base, prog);
        if (access(out, F_OK) == 0) {
            if (access(out, X_OK) == 0)
                return TSR_OK;
            return tsr_error_set(err, TSR_EINVAL, "exec '%s': %s is not executable", prog, out);
        }
        used += (size_t)snprintf(tried + used, used < sizeof tried ? sizeof tried - used : 0, "%s%s", used ? ", " : "",
                                 strcmp(base, ".") ? base : "the working directory");
        if (used >= sizeof tried)
            used = sizeof tried - 1;
    }
    return tsr_error_set(err, TSR_ENOENT, "exec '%s': not found (looked in %s)", prog, tried);
}

static void add_app_stats(agent *a, tsr_ctl_out *out)
{
    tsr_ctl_addf(out, "exit_code", "%d", a->app_exit_code);
    char path[256];
    snprintf(path, sizeof path, "%s/stats.json", a->tmpdir);
    FILE *f = a->tmpdir[0] ? fopen(path, "r") : NULL;
    /* sort-first statistics hold bytes per server per frame: room for
     * thousands of frames of a 32-server wall */
    enum { STATS_MAX = 4 << 20 };
    char *text = f ? malloc(STATS_MAX) : NULL;
    size_t n = 0;
    if (f && text)
        n = fread(text, 1, STATS_MAX - 1, f);
    if (f)
        fclose(f);
    if (!text || !n) {
        free(text);
        tsr_ctl_add(out, "app_stats", "missing");
        return;
    }
    text[n] = '\0';
    tsr_ctl_add(out, "app_stats", "found");
    static const char *const keys[] = {"frames", "buffers", "bytes_out", "blocked_seconds"};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        double v;
        if (tsr_ms_json_number(text, keys[i], &v) == 0)
            tsr_ctl_addf(out, keys[i], "%.17g", v);
    }
    /* tilesort: its "sort_first" object goes to the mothership whole (it
     * is JSON the stats file then embeds) */
    const char *sf = strstr(text, "\"sort_first\":{");
    if (sf) {
        sf += strlen("\"sort_first\":");
        int depth = 0;
        const char *e = sf;
        for (; *e; e++) {
            depth += *e == '{' || *e == '[';
            depth -= *e == '}' || *e == ']';
            if (!depth)
                break;
        }
        if (*e) {
            char *obj = strndup(sf, (size_t)(e - sf + 1));
            if (obj)
                tsr_ctl_add(out, "sort_first", obj);
            free(obj);
        }
    }
    free(text);
}

static int run_app_args(agent *a, const tsr_ctl *cfg, const char **args, size_t argc, tsr_error *err);

/* The exec argv from the CONFIG's arg= fields, as many as it has. */
static int run_app(agent *a, const tsr_ctl *cfg, tsr_error *err)
{
    size_t argc = 0;
    const char **args = malloc((cfg->count + 1) * sizeof *args);
    if (!args) {
        tsr_error_set(err, TSR_ENOMEM, "out of memory for %zu arguments", cfg->count);
        send_done(a, 1, err->message, 0, NULL, &(tsr_error){0});
        return 1;
    }
    for (size_t i = 0; i < cfg->count; i++)
        if (!strcmp(cfg->keys[i], "arg"))
            args[argc++] = cfg->values[i];
    args[argc] = NULL;
    int rc = run_app_args(a, cfg, args, argc, err);
    free(args);
    return rc;
}

static int run_app_args(agent *a, const tsr_ctl *cfg, const char **args, size_t argc, tsr_error *err)
{
    char path[PATH_MAX];
    if (!argc) {
        tsr_error_set(err, TSR_EINVAL, "CONFIG for app node without arg=");
        send_done(a, 1, err->message, 0, NULL, &(tsr_error){0});
        return 2;
    }
    if (resolve_exec(cfg, args[0], path, sizeof path, err) != TSR_OK || make_tmpdir(a, err) != TSR_OK) {
        send_done(a, 1, err->message, 0, NULL, &(tsr_error){0});
        return 1;
    }
    char stats_path[256];
    snprintf(stats_path, sizeof stats_path, "%s/stats.json", a->tmpdir);
    /* The application reads its chain from TESSERA_CHAIN: the links in
     * text form. */
    tsr_ctl_chain links;
    if (tsr_ctl_chain_parse(cfg, &links, err) != TSR_OK) {
        send_done(a, 1, err->message, 0, NULL, &(tsr_error){0});
        return 2;
    }
    char *chain = tsr_chain_links_text(links.links, links.count, err);
    tsr_ctl_chain_free(&links);
    char *chain_var = chain ? malloc(strlen(chain) + sizeof "TESSERA_CHAIN=") : NULL;
    char stats_var[300];
    snprintf(stats_var, sizeof stats_var, "TESSERA_STATS_FILE=%s", stats_path);
    if (chain_var)
        sprintf(chain_var, "TESSERA_CHAIN=%s", chain);
    free(chain);
    /* An unmodified program (not linked to libtessera_gl) runs under the
     * faker as with `tessera exec` (faker.h). */
    char *ld_var = NULL;
    const char *faker = tsr_ms_links_tessera_gl(path) ? NULL : tsr_ms_faker_dir();
    if (faker) {
        const char *old = getenv("LD_LIBRARY_PATH");
        size_t len = sizeof "LD_LIBRARY_PATH=" + strlen(faker) + (old ? strlen(old) + 1 : 0);
        if ((ld_var = malloc(len)) != NULL)
            snprintf(ld_var, len, "LD_LIBRARY_PATH=%s%s%s", faker, old && old[0] ? ":" : "", old && old[0] ? old : "");
        tsr_log(TSR_LOG_INFO, "%s: %s is not linked to libtessera_gl: it runs under the faker (%s)", a->name, path,
                faker);
    }
    /* ld_var last: NULL ends the list there */
    const char *changes[] = {chain_var ? chain_var : "TESSERA_CHAIN", stats_var, "TESSERA_TOKEN", ld_var, NULL};
    char **env = chain_var ? tsr_ms_environ(changes) : NULL;
    char exec_failed[PATH_MAX + 160];
    snprintf(exec_failed, sizeof exec_failed, "tessera node: %s: cannot exec %s\n", a->name, path);
    pid_t parent = getpid();
    fflush(NULL);
    pid_t pid = env ? fork() : -1;
    if (pid < 0) {
        tsr_error_set(err, TSR_EIO, "cannot start the application: %s", env ? strerror(errno) : "out of memory");
        free(env);
        free(chain_var);
        free(ld_var);
        send_done(a, 1, err->message, 0, NULL, &(tsr_error){0});
        return 1;
    }
    if (pid == 0) {
        /* Only async-signal-safe calls here: the parent has threads. The
         * application must not outlive its node (kill -9 of the node). */
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (getppid() != parent)
            _exit(127);
        execve(path, (char *const *)args, env);
        ssize_t ignored = write(STDERR_FILENO, exec_failed, strlen(exec_failed));
        (void)ignored;
        _exit(127);
    }
    free(env);
    free(chain_var);
    free(ld_var);
    a->child = pid;
    tsr_ctl_out out;
    tsr_ctl_out_init(&out);
    tsr_ctl_addf(&out, "pid", "%ld", (long)pid);
    int rc = send_ctl(a, TSR_MS_MSG_READY, &out, err);
    tsr_ctl_out_free(&out);
    if (rc != TSR_OK) {
        kill_child(a);
        return 1;
    }
    double next_beat = tsr_now_seconds();
    int status = 0;
    for (;;) {
        pid_t w = waitpid(pid, &status, WNOHANG);
        if (w == pid)
            break;
        if (tsr_now_seconds() >= next_beat) {
            if (send_stats(a, err) != TSR_OK) {
                kill_child(a);
                return 1;
            }
            next_beat = tsr_now_seconds() + a->heartbeat_ms / 1000.0;
        }
        int code = poll_control(a, POLL_MS, err);
        if (code) {
            kill_child(a);
            return code;
        }
    }
    a->child = 0;
    int sig = 0, failed = 0;
    if (WIFSIGNALED(status)) {
        sig = WTERMSIG(status);
        failed = 1;
        tsr_error_set(err, TSR_EIO, "application %s killed by signal %d (%s)", args[0], sig, strsignal(sig));
    } else if (WEXITSTATUS(status) != 0) {
        failed = 1;
        tsr_error_set(err, TSR_EIO, "application %s exited with status %d", args[0], WEXITSTATUS(status));
    }
    /* The program's own status (`tessera exec --graph` passes it on). */
    a->app_exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 0;
    send_done(a, failed, failed ? err->message : "", sig, add_app_stats, &(tsr_error){0});
    return failed;
}

static int connect_mothership(agent *a, tsr_error *err)
{
    double deadline = tsr_now_seconds() + a->cfg->connect_timeout_ms / 1000.0;
    tsr_error e = {0};
    for (;;) {
        a->conn = tsr_net_connect(a->net, a->cfg->mothership, &e);
        if (a->conn)
            return TSR_OK;
        /* A refusal (wrong token, version) will not change by retrying. */
        if (strstr(e.message, "refused:") || tsr_now_seconds() + 0.1 >= deadline)
            break;
        struct timespec ts = {0, 100 * 1000000L};
        nanosleep(&ts, NULL);
    }
    return tsr_error_set(err, e.code ? e.code : TSR_EIO, "cannot reach the mothership at %s within %u ms: %s",
                         a->cfg->mothership, a->cfg->connect_timeout_ms, e.message);
}

static int join_and_run(agent *a, tsr_error *err)
{
    if (connect_mothership(a, err) != TSR_OK)
        return 1;
    char host[256] = "";
    gethostname(host, sizeof host - 1);
    tsr_ctl_out out;
    tsr_ctl_out_init(&out);
    if (a->cfg->name)
        tsr_ctl_add(&out, "name", a->cfg->name);
    else
        tsr_ctl_addf(&out, "rank", "%d", a->cfg->rank);
    tsr_ctl_addf(&out, "pid", "%ld", (long)getpid());
    tsr_ctl_add(&out, "host", host);
    int rc = send_ctl(a, TSR_MS_MSG_JOIN, &out, err);
    tsr_ctl_out_free(&out);
    if (rc != TSR_OK)
        return 1;

    tsr_net_msg m;
    tsr_error e = {0};
    rc = tsr_net_recv(a->conn, &m, TSR_NET_WAIT_FOREVER, &e);
    if (rc != 1) {
        if (rc == 0)
            tsr_error_set(err, TSR_ESTATE, "the mothership closed the control connection before configuring this node");
        else
            tsr_error_set(err, rc, "lost the mothership before configuration: %s", e.message);
        return 1;
    }
    tsr_ctl msg;
    if (tsr_ctl_parse(&msg, m.data, m.len, err) != TSR_OK) {
        tsr_net_msg_release(&m);
        return 1;
    }
    unsigned kind = m.kind;
    tsr_net_msg_release(&m);
    const char *reason = tsr_ctl_get(&msg, "reason");
    int code;
    if (kind == TSR_MS_MSG_REFUSE) {
        tsr_error_set(err, TSR_EINVAL, "the mothership refused this node: %s", reason ? reason : "?");
        code = 2;
    } else if (kind == TSR_MS_MSG_STOP) {
        tsr_error_set(err, TSR_ESTATE, "stopped by the mothership: %s", reason ? reason : "?");
        code = 1;
    } else if (kind != TSR_MS_MSG_CONFIG || !tsr_ctl_get(&msg, "role") ||
               (!tsr_ctl_get(&msg, "link") && !tsr_ctl_get(&msg, "links")) || !tsr_ctl_get(&msg, "name")) {
        tsr_error_set(err, TSR_EPROTO, "expected CONFIG with role, link and name from the mothership, got %s",
                      tsr_ctl_kind_name(kind));
        code = 1;
    } else {
        snprintf(a->name, sizeof a->name, "%s", tsr_ctl_get(&msg, "name"));
        a->heartbeat_ms = (uint32_t)tsr_ctl_number(&msg, "heartbeat_ms", 500);
        if (a->heartbeat_ms < 10)
            a->heartbeat_ms = 10;
        code = 0;
        for (size_t i = 0; i < msg.count && !code; i++) {
            if (!strcmp(msg.keys[i], "mkdir") && tsr_ms_mkdirs(msg.values[i])) {
                tsr_error_set(err, TSR_EIO, "cannot create output directory '%s': %s", msg.values[i], strerror(errno));
                send_done(a, 1, err->message, 0, NULL, &(tsr_error){0});
                code = 1;
            }
        }
        if (!code)
            code = !strcmp(tsr_ctl_get(&msg, "role"), "server") ? run_server(a, &msg, err) : run_app(a, &msg, err);
    }
    tsr_ctl_free(&msg);
    return code;
}

int tsr_agent_run(const tsr_agent_config *config, tsr_error *err)
{
    agent a;
    memset(&a, 0, sizeof a);
    a.cfg = config;
    a.started = tsr_now_seconds();
    if (config->name)
        snprintf(a.name, sizeof a.name, "%s", config->name);
    else
        snprintf(a.name, sizeof a.name, "rank-%d", config->rank);
    tsr_net_config nc;
    tsr_net_config_defaults(&nc);
    nc.node_name = a.name;
    nc.token = config->token;
    nc.connect_timeout_ms = config->connect_timeout_ms < 100 ? 100 : config->connect_timeout_ms;
    nc.handshake_timeout_ms = nc.connect_timeout_ms;
    /* The mothership pings every third of 2 x its time-out; three of ours
     * of silence means it stopped or died. */
    nc.idle_timeout_ms = config->timeout_ms ? 3 * config->timeout_ms : 0;
    nc.close_timeout_ms = 2000;
    a.net = tsr_net_create(&nc, err);
    if (!a.net)
        return 1;
    int code = join_and_run(&a, err);
    /* The reason may quote a peer (a STOP or REFUSE reason, a server's
     * error): made safe to print here, once for every path. */
    char raw[sizeof err->message];
    snprintf(raw, sizeof raw, "%s", err->message);
    tsr_text_sanitize(err->message, sizeof err->message, raw, strlen(raw));
    kill_child(&a);
    remove_tmpdir(&a);
    if (a.node && !atomic_load(&a.node_done))
        return code ? code : 1; /* node thread still running: the caller _exits */
    if (a.node)
        tsr_node_destroy(a.node);
    if (a.conn)
        tsr_net_conn_close(a.conn);
    tsr_net_destroy(a.net);
    return code;
}
