/* mothership/processes.c — the children: launched in a process group
 * each, reaped with their exit status described, stopped with STOP, then
 * killed after a grace period.
 * Owns the launched processes. Never: leaves a process it started running
 * after the run returns, waits on one without a time-out. */
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

/* --- launching -------------------------------------------------------- */

int ms_launch(ms *m, ms_node *n, const char *control, tsr_error *err)
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


void ms_reap(ms *m)
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
            ms_fail(m, FAIL_SIGNAL, "node '%s' (pid %ld) %s", n->g->name, (long)n->pid, what);
        else if (n->state != N_DONE && WEXITSTATUS(st) && n->lost_at && n->lost_by_error)
            /* No DONE could come: say what the node saw break first. */
            ms_fail(m, FAIL_EXIT, "node '%s' (pid %ld) %s after its control connection was lost (%s)", n->g->name,
                    (long)n->pid, what, n->lost_why);
        else if (n->state != N_DONE && WEXITSTATUS(st)) {
            /* A node that fails sends DONE with its reason, then exits:
             * the DONE may not have been read yet (the mothership's
             * network thread reads it, later on a loaded machine). Read
             * what is queued; if it is not there, check() names the exit
             * once the connection has ended or LOST_GRACE_S has passed
             * (faker_tessera_exec_passes_status_* named the exit instead
             * of the node's reason under load), and names a broken
             * connection there too, whichever of the two was seen first
             * (fault_wall_mothership_close got the bare exit when the
             * exit was reaped before the cut was read). */
            ms_receive(m);
            if (n->state != N_DONE && !n->exit_seen_at) {
                n->exit_seen_at = tsr_now_seconds();
                snprintf(n->exit_what, sizeof n->exit_what, "%s%s", what,
                         n->state == N_WAITING ? " before joining" : "");
            }
        } else if (n->state != N_DONE) {
            /* A node sends DONE and exits at once: its DONE may still be
             * queued here when the exit is seen (many nodes ending
             * together, e.g. a sort-last group). Read what is queued first. */
            ms_receive(m);
            if (n->state != N_DONE)
                ms_fail(m, FAIL_OTHER, "node '%s' (pid %ld) ended without reporting its end", n->g->name, (long)n->pid);
        }
    }
}

/* Whether a launched node's process is on a processor or waiting for one
 * (/proc state R, D, Z or X): not silent of its own accord, but busy,
 * starved or already exiting; a stopped (T, t) or sleeping (S) one is
 * not. Unknown (no /proc entry): false. */
bool ms_process_busy(pid_t pid)
{
    char path[64], line[512];
    snprintf(path, sizeof path, "/proc/%ld/stat", (long)pid);
    FILE *f = fopen(path, "r");
    if (!f)
        return false;
    size_t n = fread(line, 1, sizeof line - 1, f);
    fclose(f);
    line[n] = '\0';
    /* "pid (comm) S ...": comm may hold spaces and parentheses; the state
     * follows the last ')' */
    const char *close = strrchr(line, ')');
    if (!close || close[1] != ' ')
        return false;
    char state = close[2];
    return state == 'R' || state == 'D' || state == 'Z' || state == 'X';
}

/* --- ending ----------------------------------------------------------- */

void ms_stop_all(ms *m, const char *reason)
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
void ms_kill_groups(ms *m)
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

int ms_remove_entry(const char *path, const struct stat *st, int type, struct FTW *ftw)
{
    (void)st;
    (void)type;
    (void)ftw;
    remove(path);
    return 0;
}
