/* tests/fault/fault_cell_test.c — one cell of the fault matrix (issue 10, item
 * 13): runs `tessera run GRAPH` as a child, waits until frames flow, applies
 * one fault to one process of the run, and checks what a user would see.
 *
 *   fault_cell TESSERA GRAPH OUT_DIR TARGET FAULT TIMEOUT_MS READY...
 *     TARGET   mothership (the `tessera run` process itself), application
 *              (the program an app node runs), or the name of a server node
 *     FAULT    sigkill | sigstop | sigterm | close
 *     READY    files (relative to OUT_DIR) that must exist before the fault
 *
 * `close` shuts down the target's stream connections (for the mothership:
 * its control connections) from outside, as a dead link or a peer's close
 * would: the driver copies each socket out of the target with
 * pidfd_getfd(2) and calls shutdown(2) on it, which ends the connection for
 * both of its ends; the target's code is not changed and nothing sits
 * between the two ends. A node's control connection is left alone when the
 * target is a node.
 *
 * Checks: the exit status of `tessera run`; that its message names the
 * node and what happened; that it ended (the time from the fault is
 * printed next to the expected time-out plus a margin, not judged; past
 * that plus HARD_EXTRA_MS, a hang guard, the run is killed); that no process of the run is left (every process of the run
 * carries TESSERA_FAULT_CELL=<unique> in its environment, found by a /proc
 * scan); that every PNG the run left is a whole PNG (read to its end with
 * libpng). A mothership that dies or stops cannot clean up: then its nodes
 * must end by themselves (they take a mothership silent for 3 x TIMEOUT_MS
 * as lost), and a stopped one, continued, must end its run with exit 1.
 *
 * Owns: the run it starts and every process carrying its marker (stopped
 * ones are continued and killed at the end). Never: signals a process
 * without its marker, waits without a bound. On success it removes
 * OUT_DIR/out (the frames) and keeps the logs. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <regex.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <netinet/in.h>
#include <arpa/inet.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "tessera/error.h"
#include "tessera/image.h"

#include "harness.h"

#define MARGIN_MS 6000      /* a failure's report: grace periods, a loaded machine */
#define READY_WAIT_MS 60000 /* frames must flow by then (the build may still be warm) */
#define HARD_EXTRA_MS 15000 /* past bound + this the driver stops waiting and kills */

enum fault { F_KILL, F_STOP, F_TERM, F_CLOSE };
/* How netlib names a connection cut under it: the far end's FIN or RST
 * seen by a read, or a write that finds it gone (EPIPE: seen once in 20
 * minutes of the suite, fault_wall_display_readback_close, when the
 * application's write to the cut tile server came before any read). */
#define CUT "went away without closing the connection|connection reset by peer|failed: broken pipe"
static const char *const fault_names[] = {"sigkill", "sigstop", "sigterm", "close"};

static char marker[512];  /* TESSERA_FAULT_CELL=... */
static char tmp_dir[128]; /* the run's TMPDIR, removed at exit */
static pid_t run_pid;
static int run_reaped, run_status;
static double run_exited_at;

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1000.0 + ts.tv_nsec / 1e6;
}

static void sleep_ms(int ms)
{
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

/* Reaps every child that ended: the run, and (we are their subreaper) the
 * nodes a dead mothership left behind. */
static void reap_all(void)
{
    int st;
    pid_t w;
    while ((w = waitpid(-1, &st, WNOHANG)) > 0)
        if (w == run_pid) {
            run_reaped = 1;
            run_status = st;
            run_exited_at = now_ms();
        }
}

static size_t read_file(const char *path, char *buf, size_t size)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return 0;
    size_t used = 0;
    ssize_t n;
    while (used + 1 < size && (n = read(fd, buf + used, size - 1 - used)) > 0)
        used += (size_t)n;
    close(fd);
    buf[used] = '\0';
    return used;
}

/* State letter and parent of a process; 0 when it is gone. */
static char proc_state(pid_t pid, pid_t *ppid)
{
    char path[64], buf[1024];
    snprintf(path, sizeof path, "/proc/%d/stat", (int)pid);
    if (!read_file(path, buf, sizeof buf))
        return 0;
    char *close_paren = strrchr(buf, ')');
    if (!close_paren || close_paren[1] != ' ')
        return 0;
    char state = close_paren[2];
    if (ppid)
        *ppid = (pid_t)strtol(close_paren + 4, NULL, 10);
    return state;
}

/* The command line with its NULs turned into blanks. */
static void proc_cmdline(pid_t pid, char *buf, size_t size)
{
    char path[64];
    snprintf(path, sizeof path, "/proc/%d/cmdline", (int)pid);
    size_t n = read_file(path, buf, size);
    for (size_t i = 0; i + 1 < n; i++)
        if (!buf[i])
            buf[i] = ' ';
}

static int has_marker(pid_t pid)
{
    static char env[1 << 17];
    char path[64];
    snprintf(path, sizeof path, "/proc/%d/environ", (int)pid);
    size_t n = read_file(path, env, sizeof env);
    size_t len = strlen(marker);
    for (size_t i = 0; i < n;) {
        if (!strncmp(env + i, marker, len) && env[i + len] == '\0')
            return 1;
        i += strlen(env + i) + 1;
    }
    return 0;
}

/* Every living (not zombie) process of the run, except `except`. */
static size_t run_processes(pid_t *out, size_t max, pid_t except)
{
    size_t count = 0;
    DIR *d = opendir("/proc");
    if (!d)
        return 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        char *end;
        long pid = strtol(e->d_name, &end, 10);
        if (*end || pid <= 0 || pid == getpid() || pid == except)
            continue;
        char state = proc_state((pid_t)pid, NULL);
        if (!state || state == 'Z' || !has_marker((pid_t)pid))
            continue;
        if (count < max)
            out[count] = (pid_t)pid;
        count++;
    }
    closedir(d);
    return count;
}

static void list_processes(const char *title, pid_t except)
{
    pid_t left[64];
    size_t n = run_processes(left, 64, except);
    for (size_t i = 0; i < n && i < 64; i++) {
        char cmd[512];
        pid_t ppid = 0;
        char state = proc_state(left[i], &ppid);
        proc_cmdline(left[i], cmd, sizeof cmd);
        fprintf(stderr, "  %s: pid %d (state %c, parent %d): %s\n", title, (int)left[i], state ? state : '?', (int)ppid,
                cmd);
    }
}

/* Continues and kills every process of the run still there, and reaps. */
static void kill_everything(void)
{
    for (int round = 0; round < 3; round++) {
        pid_t left[256];
        size_t n = run_processes(left, 256, 0);
        if (run_pid && !run_reaped) {
            kill(run_pid, SIGCONT);
            kill(run_pid, SIGKILL);
        }
        for (size_t i = 0; i < n && i < 256; i++) {
            kill(left[i], SIGCONT);
            kill(left[i], SIGKILL);
        }
        for (int i = 0; i < 100; i++) {
            reap_all();
            if (!run_processes(left, 1, 0) && (!run_pid || run_reaped))
                return;
            sleep_ms(10);
        }
    }
}

/* The pid of node `name`: the run's child `tessera node ... --name NAME`. */
static pid_t node_pid(const char *name)
{
    pid_t found = 0;
    DIR *d = opendir("/proc");
    if (!d)
        return 0;
    char want[256];
    snprintf(want, sizeof want, " --name %s ", name);
    struct dirent *e;
    while ((e = readdir(d)) != NULL && !found) {
        char *end;
        long pid = strtol(e->d_name, &end, 10);
        pid_t ppid = 0;
        if (*end || pid <= 0 || !proc_state((pid_t)pid, &ppid) || ppid != run_pid)
            continue;
        char cmd[1024];
        proc_cmdline((pid_t)pid, cmd, sizeof cmd - 1);
        strcat(cmd, " ");
        if (strstr(cmd, " node ") && strstr(cmd, want))
            found = (pid_t)pid;
    }
    closedir(d);
    return found;
}

/* The application: the one child of a node process (app nodes fork it;
 * server nodes run in-process). Its node's name goes to `node`. */
static pid_t application_pid(char *node, size_t size)
{
    pid_t found = 0;
    DIR *d = opendir("/proc");
    if (!d)
        return 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL && !found) {
        char *end;
        long pid = strtol(e->d_name, &end, 10);
        pid_t parent = 0, grandparent = 0;
        if (*end || pid <= 0 || !proc_state((pid_t)pid, &parent) || parent <= 1 || !proc_state(parent, &grandparent) ||
            grandparent != run_pid)
            continue;
        char cmd[1024];
        proc_cmdline(parent, cmd, sizeof cmd);
        const char *name = strstr(cmd, "--name ");
        if (!name)
            continue;
        snprintf(node, size, "%s", name + 7);
        node[strcspn(node, " ")] = '\0';
        found = (pid_t)pid;
    }
    closedir(d);
    return found;
}

/* --- close: the target's connections --------------------------------- */

/* The control port a node process was given (--mothership tcp://H:PORT). */
static unsigned control_port(pid_t pid)
{
    char cmd[1024];
    proc_cmdline(pid, cmd, sizeof cmd);
    const char *m = strstr(cmd, "--mothership ");
    if (!m)
        return 0;
    const char *end = m + 13 + strcspn(m + 13, " ");
    const char *colon = end;
    while (colon > m && *colon != ':')
        colon--;
    return *colon == ':' ? (unsigned)strtoul(colon + 1, NULL, 10) : 0;
}

/* Shuts down every connected socket of `pid` except its control
 * connection (`skip_port`: the mothership's port; 0 = none). Every socket
 * is copied out first (and asked, on the copy, whether it is connected and
 * to where) and only then shut down, all at once: the target reacts to the
 * first (closes the others, or exits) within milliseconds. Returns the
 * number shut down, or -1 with a message. */
static int close_connections(pid_t pid, unsigned skip_port, char *why, size_t why_size)
{
    int pidfd = (int)syscall(SYS_pidfd_open, pid, 0);
    if (pidfd < 0) {
        snprintf(why, why_size, "pidfd_open(%d): %s", (int)pid, strerror(errno));
        return -1;
    }
    char dir[64];
    snprintf(dir, sizeof dir, "/proc/%d/fd", (int)pid);
    DIR *d = opendir(dir);
    if (!d) {
        snprintf(why, why_size, "%s: %s", dir, strerror(errno));
        close(pidfd);
        return -1;
    }
    int copies[256];
    size_t count = 0, sockets = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL && count < sizeof copies / sizeof copies[0]) {
        char *end;
        long fd = strtol(e->d_name, &end, 10);
        if (*end || fd < 0)
            continue;
        char link[PATH_MAX], path[PATH_MAX];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        ssize_t n = readlink(path, link, sizeof link - 1);
        if (n <= 0)
            continue;
        link[n] = '\0';
        if (strncmp(link, "socket:", 7))
            continue;
        sockets++;
        int copy = (int)syscall(SYS_pidfd_getfd, pidfd, (int)fd, 0);
        if (copy < 0) {
            printf("  fd %ld of pid %d: pidfd_getfd: %s\n", fd, (int)pid, strerror(errno));
            continue;
        }
        int type = 0, listening = 0;
        socklen_t len = sizeof type;
        struct sockaddr_storage peer;
        socklen_t peer_len = sizeof peer;
        getsockopt(copy, SOL_SOCKET, SO_TYPE, &type, &len);
        len = sizeof listening;
        getsockopt(copy, SOL_SOCKET, SO_ACCEPTCONN, &listening, &len);
        int connected =
            type == SOCK_STREAM && !listening && getpeername(copy, (struct sockaddr *)&peer, &peer_len) == 0;
        unsigned port = 0;
        if (connected && peer.ss_family == AF_INET)
            port = ntohs(((struct sockaddr_in *)&peer)->sin_port);
        else if (connected && peer.ss_family == AF_INET6)
            port = ntohs(((struct sockaddr_in6 *)&peer)->sin6_port);
        if (connected && !(skip_port && port == skip_port))
            copies[count++] = copy;
        else
            close(copy);
    }
    closedir(d);
    close(pidfd);
    int closed = 0;
    for (size_t i = 0; i < count; i++) {
        if (shutdown(copies[i], SHUT_RDWR) == 0)
            closed++;
        close(copies[i]);
    }
    if (closed == 0)
        snprintf(why, why_size, "process %d: no connection could be shut down (%zu sockets)", (int)pid, sockets);
    return closed;
}

/* --- PNGs ------------------------------------------------------------- */

static int pngs_total, pngs_bad, others_left;

static int check_file(const char *path, const struct stat *st, int type, struct FTW *ftw)
{
    (void)st;
    (void)ftw;
    if (type != FTW_F)
        return 0;
    size_t len = strlen(path);
    if (len < 4 || strcmp(path + len - 4, ".png")) {
        if (others_left++ < 5)
            printf("  not a .png, left in the output: %s\n", path);
        return 0;
    }
    pngs_total++;
    tsr_image img;
    tsr_error err = {0};
    if (tsr_image_read_png(&img, path, &err) != TSR_OK) {
        pngs_bad++;
        fprintf(stderr, "  not a whole PNG: %s\n", err.message);
        return 0;
    }
    tsr_image_free(&img);
    return 0;
}

static int remove_entry(const char *path, const struct stat *st, int type, struct FTW *ftw)
{
    (void)st;
    (void)type;
    (void)ftw;
    remove(path);
    return 0;
}

static void remove_tmp_dir(void)
{
    if (tmp_dir[0])
        nftw(tmp_dir, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
}

static void show_file(const char *title, const char *path)
{
    static char text[1 << 16];
    size_t n = read_file(path, text, sizeof text);
    printf("--- %s (%s, %zu bytes)\n%s%s", title, path, n, text, n && text[n - 1] != '\n' ? "\n" : "");
}

/* The last line of the run's stderr that starts with "tessera run: ". */
static void run_verdict(const char *err_path, char *out, size_t size)
{
    static char text[1 << 16];
    read_file(err_path, text, sizeof text);
    out[0] = '\0';
    for (char *line = text; line && *line;) {
        char *nl = strchr(line, '\n');
        size_t n = nl ? (size_t)(nl - line) : strlen(line);
        if (!strncmp(line, "tessera run: ", 13))
            snprintf(out, size, "%.*s", (int)n, line);
        line = nl ? nl + 1 : NULL;
    }
}

static int matches(const char *text, const char *pattern)
{
    regex_t re;
    if (regcomp(&re, pattern, REG_EXTENDED | REG_NOSUB)) {
        fprintf(stderr, "fault_cell: bad pattern /%s/\n", pattern);
        return 0;
    }
    int ok = regexec(&re, text, 0, NULL, 0) == 0;
    regfree(&re);
    return ok;
}

/* Some line of the file matches `pattern`. */
static int file_matches(const char *path, const char *pattern)
{
    static char text[1 << 16];
    read_file(path, text, sizeof text);
    for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n"))
        if (matches(line, pattern))
            return 1;
    return 0;
}

static int file_contains(const char *path, const char *needle)
{
    static char text[1 << 16];
    read_file(path, text, sizeof text);
    return strstr(text, needle) != NULL;
}

static void describe(int st, char *out, size_t size)
{
    if (WIFSIGNALED(st))
        snprintf(out, size, "killed by signal %d", WTERMSIG(st));
    else
        snprintf(out, size, "exit %d", WEXITSTATUS(st));
}

/* Waits until `done()` or `deadline` (ms, monotonic); reaps meanwhile. */
static int wait_until(int (*done)(void), double deadline)
{
    for (;;) {
        reap_all();
        if (done())
            return 1;
        if (now_ms() >= deadline)
            return 0;
        sleep_ms(10);
    }
}

static int run_ended(void) { return run_reaped; }

static int nodes_ended(void)
{
    pid_t one;
    return run_processes(&one, 1, run_pid) == 0;
}

static int everything_ended(void) { return run_reaped && nodes_ended(); }

int main(int argc, char **argv)
{
    if (argc < 8) {
        fprintf(stderr, "usage: fault_cell TESSERA GRAPH OUT_DIR TARGET FAULT TIMEOUT_MS READY...\n");
        return 2;
    }
    const char *tessera = argv[1], *graph = argv[2], *out = argv[3], *target = argv[4];
    int fault = -1;
    for (int f = 0; f < 4; f++)
        if (!strcmp(argv[5], fault_names[f]))
            fault = f;
    long timeout_ms = strtol(argv[6], NULL, 10);
    REQUIRE(fault >= 0, "unknown fault '%s'", argv[5]);
    REQUIRE(timeout_ms > 0, "bad TIMEOUT_MS '%s'", argv[6]);
    int mothership = !strcmp(target, "mothership");
    int application = !strcmp(target, "application");

    setvbuf(stdout, NULL, _IONBF, 0); /* interleaved with stderr in ctest's log */
    nftw(out, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
    char err_path[PATH_MAX], out_path[PATH_MAX], frames[PATH_MAX];
    snprintf(err_path, sizeof err_path, "%s/run.err", out);
    snprintf(out_path, sizeof out_path, "%s/run.out", out);
    snprintf(frames, sizeof frames, "%s/out", out);
    char mk[PATH_MAX + 16];
    snprintf(mk, sizeof mk, "mkdir -p '%s'", out);
    REQUIRE(system(mk) == 0, "cannot create %s", out);
    /* The run's temporary files (a killed mothership cannot remove its
     * own): short, for the unix sockets under it (108 bytes at most). */
    snprintf(tmp_dir, sizeof tmp_dir, "/tmp/tessera-fault-XXXXXX");
    REQUIRE(mkdtemp(tmp_dir), "mkdtemp: %s", strerror(errno));
    atexit(remove_tmp_dir);
    snprintf(marker, sizeof marker, "TESSERA_FAULT_CELL=%s:%s:%s:%d", graph, target, fault_names[fault], (int)getpid());
    /* Orphans of a dead mothership come to us, not to init: reaped here,
     * and never mistaken for processes that are left. */
    prctl(PR_SET_CHILD_SUBREAPER, 1);

    char timeout_text[32];
    snprintf(timeout_text, sizeof timeout_text, "%ld", timeout_ms);
    fflush(NULL);
    run_pid = fork();
    REQUIRE(run_pid >= 0, "fork: %s", strerror(errno));
    if (run_pid == 0) {
        int o = open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        int e = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (o < 0 || e < 0)
            _exit(127);
        dup2(o, 1);
        dup2(e, 2);
        putenv(marker);
        setenv("TMPDIR", tmp_dir, 1);
        execl(tessera, tessera, "run", graph, "--out", out, "--timeout-ms", timeout_text, "--no-progress",
              (char *)NULL);
        _exit(127);
    }
    double started = now_ms();

    /* Frames flow: every READY file exists. */
    int ready = 0;
    while (!ready && now_ms() - started < READY_WAIT_MS) {
        reap_all();
        if (run_reaped)
            break;
        ready = 1;
        for (int i = 7; i < argc && ready; i++) {
            char path[PATH_MAX];
            snprintf(path, sizeof path, "%s/%s", out, argv[i]);
            ready = access(path, F_OK) == 0;
        }
        if (!ready)
            sleep_ms(10);
    }
    if (!ready) {
        fprintf(stderr, "FAIL: frames did not flow (%s) within %d ms\n", run_reaped ? "the run ended" : "time-out",
                READY_WAIT_MS);
        show_file("stderr of tessera run", err_path);
        kill_everything();
        return 1;
    }
    printf("frames flow %.0f ms after the start\n", now_ms() - started);

    /* The victim. */
    pid_t victim = 0;
    char app_node[128] = "";
    if (mothership)
        victim = run_pid;
    else if (application)
        victim = application_pid(app_node, sizeof app_node);
    else
        victim = node_pid(target);
    if (!victim) {
        fprintf(stderr, "FAIL: no process for target '%s'; the run's processes:\n", target);
        list_processes("run", 0);
        kill_everything();
        return 1;
    }
    printf("target %s: pid %d%s%s\n", target, (int)victim, app_node[0] ? ", of node " : "", app_node);

    /* The fault. */
    double t0 = now_ms();
    int sent = 0;
    char why[512] = "";
    switch (fault) {
    case F_KILL: sent = kill(victim, SIGKILL) == 0; break;
    case F_STOP: sent = kill(victim, SIGSTOP) == 0; break;
    case F_TERM: sent = kill(victim, SIGTERM) == 0; break;
    case F_CLOSE: {
        int n = close_connections(victim, mothership || application ? 0 : control_port(victim), why, sizeof why);
        sent = n > 0;
        if (sent)
            printf("shut down %d connection%s of pid %d\n", n, n == 1 ? "" : "s", (int)victim);
        break;
    }
    }
    if (!sent) {
        fprintf(stderr, "FAIL: could not apply %s to pid %d: %s\n", fault_names[fault], (int)victim,
                why[0] ? why : strerror(errno));
        kill_everything();
        return 1;
    }

    /* The expected time: a stop is found by silence (the run's time-out;
     * nodes take 3 x that of a silent mothership), everything else at once.
     * It is printed, not judged: the verdict is that the run ended (waits
     * bounded by it plus HARD_EXTRA_MS, a hang guard) and what it said. */
    double bound = MARGIN_MS + (fault == F_STOP ? (mothership ? 3 : 1) * (double)timeout_ms : 0);
    int status = 0;
    if (mothership && fault == F_STOP) {
        /* Its nodes must give up on it by themselves ... */
        int ended = wait_until(nodes_ended, t0 + bound + HARD_EXTRA_MS);
        double elapsed = now_ms() - t0;
        printf("nodes of the stopped mothership ended %.0f ms after the stop (expected within %.0f ms)\n", elapsed,
               bound);
        CHECK(ended, "the nodes outlived the stopped mothership by %.0f ms (hang guard %.0f ms)", elapsed,
              bound + HARD_EXTRA_MS);
        if (!ended)
            list_processes("still running", run_pid);
        /* ... and the mothership, continued, ends its run, naming its own
         * stop: it does so when it was stopped longer than its nodes wait
         * for it (3 x the time-out). The nodes' silence starts at the last
         * message they had, a little before the stop, so they may give up
         * a few ms short of that: the stop lasts at least that long. */
        double stopped_long_enough = t0 + 3.0 * timeout_ms + 250.0;
        while (now_ms() < stopped_long_enough)
            usleep(10 * 1000);
        double t1 = now_ms();
        kill(run_pid, SIGCONT);
        ended = wait_until(run_ended, t1 + MARGIN_MS + HARD_EXTRA_MS);
        elapsed = now_ms() - t1;
        printf("the continued mothership ended %.0f ms after SIGCONT (expected within %d ms)\n", elapsed, MARGIN_MS);
        CHECK(ended, "the continued mothership did not end within %.0f ms (hang guard)", elapsed);
    } else {
        int (*done)(void) = mothership ? everything_ended : run_ended;
        int ended = wait_until(done, t0 + bound + HARD_EXTRA_MS);
        double elapsed = (mothership ? now_ms() : run_exited_at) - t0;
        if (!ended)
            elapsed = now_ms() - t0;
        printf("%s ended %.0f ms after the fault (expected within %.0f ms)\n",
               mothership ? "every process of the run" : "tessera run", elapsed, bound);
        CHECK(ended, "not ended %.0f ms after the fault (hang guard %.0f ms)", elapsed, bound + HARD_EXTRA_MS);
        if (!ended)
            list_processes("still running", 0);
    }
    if (!run_reaped) {
        fprintf(stderr, "FAIL: tessera run did not end; killing it\n");
        status = 1;
        kill_everything();
    }

    /* Exit status and message. */
    char got[64] = "not ended", verdict[1024];
    if (run_reaped)
        describe(run_status, got, sizeof got);
    run_verdict(err_path, verdict, sizeof verdict);
    printf("tessera run: %s; its verdict: %s\n", got, verdict[0] ? verdict : "(none)");
    char want[640] = "", cause[640] = "";
    const char *want_status = "exit 1";
    switch (fault) {
    case F_KILL:
        if (mothership)
            want_status = "killed by signal 9";
        else if (application)
            snprintf(want, sizeof want, "^tessera run: node '%s': application [^ ]* killed by signal 9", app_node);
        else
            snprintf(want, sizeof want, "^tessera run: node '%s' \\(pid %d\\) killed by signal 9", target, (int)victim);
        break;
    case F_TERM:
        if (mothership) {
            want_status = "killed by signal 15";
            snprintf(want, sizeof want, "^tessera run: interrupted by signal 15");
        } else if (application)
            snprintf(want, sizeof want, "^tessera run: node '%s': application [^ ]* killed by signal 15", app_node);
        else
            snprintf(want, sizeof want, "^tessera run: node '%s' \\(pid %d\\) killed by signal 15", target,
                     (int)victim);
        break;
    case F_STOP:
        if (mothership)
            snprintf(want, sizeof want, "^tessera run: the mothership was stopped or starved for [0-9]+ ms");
        else if (application)
            /* its servers drop its silent stream, naming the client by pid */
            snprintf(want, sizeof want,
                     "^tessera run: node '[^']+': client [0-9]+ '[^']*-pid%d' .*dropped: .*sent nothing for %ld ms",
                     (int)victim, timeout_ms);
        else
            snprintf(want, sizeof want, "^tessera run: node '%s' sent no heartbeat for [0-9]+ ms", target);
        break;
    case F_CLOSE:
        /* Both ends of a cut stream report it; the verdict is the first
         * report (the application's exit, or any server's dropped client);
         * the line naming the cut end must be there. */
        if (mothership)
            snprintf(want, sizeof want, "^tessera run: node '[^']+'.*control connection (was )?lost");
        else
            snprintf(want, sizeof want, "^tessera run: node '[^']+'.*(exited with status 1|dropped)");
        if (application)
            snprintf(cause, sizeof cause, "client [0-9]+ '[^']*-pid%d' at [^ ]+ dropped: .*(%s)", (int)victim, CUT);
        else if (!mothership)
            snprintf(cause, sizeof cause, "peer '%s' at [^ ]+ .*(%s)", target, CUT);
        break;
    }
    CHECK(!strcmp(got, want_status), "tessera run: %s, expected %s", got, want_status);
    if (!(mothership && fault == F_KILL))
        CHECK(matches(verdict, want), "the verdict does not say /%s/", want);
    if (cause[0])
        CHECK(file_matches(err_path, cause), "no line of the run's stderr says /%s/", cause);
    if (mothership && fault != F_TERM)
        CHECK(file_contains(err_path, "mothership"), "no node said it lost the mothership");

    /* Nothing of the run is left. */
    wait_until(nodes_ended, now_ms() + 500);
    pid_t left[8];
    size_t n_left = run_processes(left, 8, 0);
    CHECK(n_left == 0, "%zu process(es) of the run are left", n_left);
    if (n_left)
        list_processes("left", 0);
    kill_everything();

    /* Every PNG is whole. */
    nftw(frames, check_file, 16, FTW_PHYS);
    printf("%d PNG file%s left, %d not whole\n", pngs_total, pngs_total == 1 ? "" : "s", pngs_bad);
    CHECK(pngs_total > 0, "no PNG at all in %s", frames);
    CHECK(pngs_bad == 0, "%d of %d PNG files are not whole", pngs_bad, pngs_total);

    show_file("stderr of tessera run", err_path);
    status |= harness_failures != 0;
    if (!status) {
        nftw(frames, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
        printf("PASS: %s %s %s\n", graph, target, fault_names[fault]);
    }
    return status;
}
