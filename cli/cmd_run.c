/* cli/cmd_run.c — `tessera run GRAPH` (the mothership plus every local node
 * as a child process) and the shared option handling of `tessera
 * mothership` (cli/cmd_mothership.c). Owns argument parsing, the run's
 * token, signal handling and the exit code; mothership/ does the work. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "commands.h"
#include "mothership.h"
#include "control.h"
#include "util.h"
#include "tessera/dev/net.h"


static void run_usage(FILE *out)
{
    fprintf(out,
            "usage: tessera run GRAPH [--out DIR] [--stats FILE] [--timeout-ms MS] [--listen ADDR]\n"
            "                   [--token T] [--join-timeout-ms MS] [--progress | --no-progress]\n\n"
            "Runs a graph file: starts the mothership and every node on this host as a child\n"
            "process (`tessera node --mothership ...`, each in its own process group), servers\n"
            "first; app nodes run their `exec` with TESSERA_CHAIN set to their chain, network\n"
            "SPUs pointed at the servers' real addresses. Nodes on other hosts join over\n"
            "--listen (see tessera mothership --help).\n\n"
            "Paths: a relative exec is looked for next to the graph file, then in the build or\n"
            "install prefix of this program (bin/spheres), then in DIR; outputs (render\n"
            "output=, print file=) are relative to DIR, their directories are created.\n\n"
            "options:\n"
            "  --out DIR            working directory of the nodes, created if missing\n"
            "                       (default: the current one)\n"
            "  --stats FILE         write per-node statistics (frames, bytes in/out, time\n"
            "                       blocked on credits, render time) as JSON; checked to be\n"
            "                       writable before the run starts\n"
            "  --timeout-ms MS      a node silent this long (no heartbeat) fails the run, and\n"
            "                       so does an application whose stream is silent this long\n"
            "                       (stopped or dead; its servers drop it) (default %u)\n"
            "  --join-timeout-ms MS every node must have joined within this (default %u)\n"
            "  --listen ADDR        control address (default tcp://127.0.0.1:0, loopback)\n"
            "  --token T            shared token for control and stream connections\n"
            "                       (default: a random one per run)\n"
            "  --progress           live progress line on stderr even when not a terminal\n"
            "  --no-progress        no progress line (default: only on a terminal)\n"
            "  -h, --help           show this help\n\n"
            "Ends when every node ended. On a failure (a node exits non-zero, is killed, or\n"
            "stops answering) it stops every node, kills every process it started, and prints\n"
            "one line naming the node and what happened.\n"
            "Exit codes: 0 ok, 1 a node failed, 2 usage error or bad graph (FILE:LINE:COL).\n"
            "SIGINT or SIGTERM stops every node, then the run ends by that same signal\n"
            "(130 or 143 in a shell's $?).\n",
            TSR_MS_DEFAULT_TIMEOUT_MS, TSR_MS_DEFAULT_JOIN_TIMEOUT_MS);
}

static void mothership_usage(FILE *out)
{
    fprintf(out,
            "usage: tessera mothership GRAPH --listen ADDR [--token T] [--stats FILE]\n"
            "                          [--timeout-ms MS] [--join-timeout-ms MS] [--no-progress]\n\n"
            "Coordinates a graph whose nodes are started by someone else, e.g. on several\n"
            "machines. Prints \"mothership listening on ADDR\", waits for every node to join,\n"
            "configures servers first, then the app nodes, and reports like tessera run.\n"
            "Start each node with\n"
            "  tessera node --mothership HOST:PORT --name NODE      (by name), or\n"
            "  tessera node --mothership HOST:PORT --rank N         (rank N = the N-th node of\n"
            "                                                       the graph, from 0)\n"
            "  tessera node --mothership HOST:PORT                  (rank from OMPI_COMM_WORLD_RANK,\n"
            "                                                       PMI_RANK or SLURM_PROCID)\n"
            "e.g.  ssh hostB tessera node --mothership hostA:7000 --name server\n"
            "      mpirun -np 3 tessera node --mothership hostA:7000\n"
            "      srun -n 3 tessera node --mothership hostA:7000\n\n"
            "options:\n"
            "  --listen ADDR        control address: HOST:PORT, tcp://HOST:PORT (port 0: any\n"
            "                       free port; tcp://0.0.0.0:PORT for every interface), unix:PATH\n"
            "  --token T            shared token (also TESSERA_TOKEN) every node proves it\n"
            "                       knows by HMAC challenge-response, never sending it;\n"
            "                       servers then require the same proof from their clients\n"
            "  --stats FILE         write per-node statistics as JSON\n"
            "  --timeout-ms MS      no heartbeat this long fails the run (default %u; give\n"
            "                       nodes the same --timeout-ms)\n"
            "  --join-timeout-ms MS every node must have joined within this (default %u)\n"
            "  --progress, --no-progress   as for tessera run\n"
            "  -h, --help           show this help\n\n"
            "Servers listen on loopback unless the graph's listen: says otherwise: give remote\n"
            "servers a listen address their clients reach. Exit codes as for tessera run.\n",
            TSR_MS_DEFAULT_TIMEOUT_MS, TSR_MS_DEFAULT_JOIN_TIMEOUT_MS);
}

static volatile sig_atomic_t interrupted;

static void on_signal(int sig) { interrupted = sig; }

static void print_listening(const char *address, void *ctx)
{
    (void)ctx;
    printf("mothership listening on %s\n", address);
    fflush(stdout);
}

static int parse_ms(const char *text, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (errno || end == text || *end || v < 1 || v > 86400000)
        return -1;
    *out = v;
    return 0;
}

static int random_token(char *out, size_t size)
{
    unsigned char bytes[16];
    int fd = open("/dev/urandom", O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return -1;
    ssize_t n = read(fd, bytes, sizeof bytes);
    close(fd);
    if (n != (ssize_t)sizeof bytes || size < 2 * sizeof bytes + 1)
        return -1;
    for (size_t i = 0; i < sizeof bytes; i++)
        snprintf(out + 2 * i, 3, "%02x", bytes[i]);
    return 0;
}

/* --out: created when missing, then it must be a directory the nodes can
 * work in; said in one line before anything starts. */
static int check_out_dir(const char *who, const char *dir, char *abs)
{
    struct stat st;
    if (tsr_ms_mkdirs(dir) != 0) {
        fprintf(stderr, "%s: --out %s: cannot create the directory: %s\n", who, dir, strerror(errno));
        return -1;
    }
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        fprintf(stderr, "%s: --out %s: not a directory\n", who, dir);
        return -1;
    }
    if (access(dir, W_OK | X_OK) != 0 || !realpath(dir, abs)) {
        fprintf(stderr, "%s: --out %s: cannot work in it: %s\n", who, dir, strerror(errno));
        return -1;
    }
    return 0;
}

/* --stats is written when the run is over: a path that cannot be written
 * is found before the run starts (opened for writing, nothing truncated;
 * a file made for the test is removed again). */
static int check_stats_path(const char *who, const char *path)
{
    int fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_NONBLOCK | O_CLOEXEC, 0666);
    if (fd >= 0) {
        close(fd);
        unlink(path);
        return 0;
    }
    if (errno == EEXIST)
        fd = open(path, O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd >= 0) {
        close(fd);
        return 0;
    }
    fprintf(stderr, "%s: --stats %s: cannot write it: %s\n", who, path, strerror(errno));
    return -1;
}

int tsr_cli_run_graph(int argc, char **argv, int launch)
{
    return tsr_cli_run_graph_as(argc, argv, launch, NULL, NULL);
}

static int run_graph(int argc, char **argv, int launch, const char *const *app_exec, const char *as, const char *node,
                     char **program);

int tsr_cli_run_graph_as(int argc, char **argv, int launch, const char *const *app_exec, const char *as)
{
    return run_graph(argc, argv, launch, app_exec, as, NULL, NULL);
}

int tsr_cli_run_graph_exec(int argc, char **argv, int launch, const char *node, char **program)
{
    return run_graph(argc, argv, launch, NULL, "tessera exec", node, program);
}

/* The app node `tessera exec --graph` runs its program as: `name`, else
 * the single app node. NULL with one line said when there is none. */
static const tsr_graph_node *exec_node(const char *who, const tsr_graph *graph, const char *name)
{
    if (name) {
        const tsr_graph_node *n = tsr_graph_find(graph, name);
        if (!n)
            fprintf(stderr, "%s: --node %s: %s has no node of that name\n", who, name, tsr_graph_file(graph));
        else if (!n->exec)
            fprintf(stderr, "%s: --node %s: in %s it is a server, not an app node (no exec:)\n", who, name,
                    tsr_graph_file(graph));
        return n && n->exec ? n : NULL;
    }
    const tsr_graph_node *app = NULL;
    size_t apps = 0;
    for (size_t i = 0; i < tsr_graph_node_count(graph); i++)
        if (tsr_graph_node_at(graph, i)->exec && apps++ == 0)
            app = tsr_graph_node_at(graph, i);
    if (apps != 1) {
        fprintf(stderr, "%s: %s has %zu app nodes: name the program's with --node NAME\n", who, tsr_graph_file(graph),
                apps);
        return NULL;
    }
    return app;
}

/* `tessera exec --graph`: the run failed because the program itself
 * ended badly, so this process ends as the program did, as `tessera exec
 * --chain` (which becomes the program) would: its exit status, or death by
 * the same signal (re-raised with the default action; no core file of
 * this process, which did not crash), else 128 + N as a shell reports it. */
static int die_by_signal(int sig)
{
    fflush(NULL);
    struct rlimit no_core = {0, 0};
    setrlimit(RLIMIT_CORE, &no_core);
    signal(sig, SIG_DFL);
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, sig);
    sigprocmask(SIG_UNBLOCK, &set, NULL);
    raise(sig);
    return 128 + sig; /* a signal that does not end a process (SIGCHLD, SIGCONT...) */
}

static int pass_through(const struct tsr_ms_program_end *end)
{
    if (!end->signal)
        return end->exit_code;
    return die_by_signal(end->signal);
}

static int run_graph(int argc, char **argv, int launch, const char *const *app_exec, const char *as, const char *node,
                     char **program)
{
    const char *who = as ? as : launch ? "tessera run" : "tessera mothership";
    void (*usage)(FILE *) = launch ? run_usage : mothership_usage;
    const char *graph_path = NULL, *out_dir = NULL, *stats = NULL, *listen = NULL, *token = NULL;
    long timeout = TSR_MS_DEFAULT_TIMEOUT_MS, join_timeout = TSR_MS_DEFAULT_JOIN_TIMEOUT_MS;
    int progress = -1;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (!strcmp(arg, "-h") || !strcmp(arg, "--help")) {
            usage(stdout);
            return TSR_EXIT_OK;
        }
        if (!strcmp(arg, "--progress") || !strcmp(arg, "--no-progress")) {
            progress = !strcmp(arg, "--progress");
            continue;
        }
        if (arg[0] != '-' || !arg[1]) {
            if (graph_path) {
                fprintf(stderr, "%s: one GRAPH at a time ('%s' and '%s')\n", who, graph_path, arg);
                return TSR_EXIT_USAGE;
            }
            graph_path = arg;
            continue;
        }
        int known = !strcmp(arg, "--stats") || !strcmp(arg, "--timeout-ms") || !strcmp(arg, "--join-timeout-ms") ||
                    !strcmp(arg, "--listen") || !strcmp(arg, "--token") || (launch && !strcmp(arg, "--out"));
        if (!known) {
            fprintf(stderr, "%s: unknown option '%s' (see %s --help)\n", who, arg, who);
            return TSR_EXIT_USAGE;
        }
        if (i + 1 >= argc) {
            fprintf(stderr, "%s: option %s needs a value\n", who, arg);
            return TSR_EXIT_USAGE;
        }
        const char *value = argv[++i];
        if (!strcmp(arg, "--stats"))
            stats = value;
        else if (!strcmp(arg, "--listen"))
            listen = value;
        else if (!strcmp(arg, "--token"))
            token = value;
        else if (!strcmp(arg, "--out"))
            out_dir = value;
        else if (parse_ms(value, !strcmp(arg, "--timeout-ms") ? &timeout : &join_timeout)) {
            fprintf(stderr, "%s: bad %s '%s' (expected 1..86400000)\n", who, arg, value);
            return TSR_EXIT_USAGE;
        }
    }
    if (!graph_path) {
        usage(stderr);
        return TSR_EXIT_USAGE;
    }
    if (!launch && !listen) {
        fprintf(stderr, "%s: --listen ADDR is required (see %s --help)\n", who, who);
        return TSR_EXIT_USAGE;
    }
    tsr_error err = {0};
    tsr_graph *graph = tsr_graph_load(graph_path, 0, &err);
    if (!graph) {
        fprintf(stderr, "%s\n", err.message);
        return err.code == TSR_ENOMEM ? TSR_EXIT_FAIL : TSR_EXIT_USAGE;
    }
    const tsr_graph_node *app = NULL;
    if (program && !(app = exec_node(who, graph, node))) {
        tsr_graph_free(graph);
        return TSR_EXIT_USAGE;
    }
    char self[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n <= 0) {
        fprintf(stderr, "%s: cannot find this program (/proc/self/exe): %s\n", who, strerror(errno));
        tsr_graph_free(graph);
        return TSR_EXIT_FAIL;
    }
    self[n] = '\0';
    char out_abs[PATH_MAX];
    if ((out_dir && check_out_dir(who, out_dir, out_abs)) || (stats && check_stats_path(who, stats))) {
        tsr_graph_free(graph);
        return TSR_EXIT_USAGE;
    }
    if (out_dir)
        out_dir = out_abs;
    char run_token[40];
    char listen_buf[256];
    if (!token || !*token)
        token = getenv("TESSERA_TOKEN");
    if ((!token || !*token) && launch) {
        if (random_token(run_token, sizeof run_token)) {
            fprintf(stderr, "%s: cannot read /dev/urandom for the run's token\n", who);
            tsr_graph_free(graph);
            return TSR_EXIT_FAIL;
        }
        token = run_token;
    }
    if (listen) {
        tsr_error err;
        if (tsr_net_address_normalise(listen, listen_buf, sizeof listen_buf, &err) != TSR_OK) {
            fprintf(stderr, "%s: --listen: %s\n", who, err.message);
            tsr_graph_free(graph);
            return TSR_EXIT_USAGE;
        }
        listen = listen_buf;
    }
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    signal(SIGPIPE, SIG_IGN);

    tsr_ms_config cfg = {
        .listen = listen,
        .token = token,
        .launch_local = launch,
        .self_exe = self,
        .out_dir = out_dir,
        .stats_path = stats,
        .timeout_ms = (uint32_t)timeout,
        .join_timeout_ms = (uint32_t)join_timeout,
        .progress = progress == -1 ? isatty(STDERR_FILENO) : progress,
        .summary = stdout,
        .who = who,
        .on_listening = launch ? NULL : print_listening,
        .interrupted = &interrupted,
        .app_exec = app_exec,
        .exec_node = app ? app->name : NULL,
        .exec_argv = (const char *const *)program,
    };
    struct tsr_ms_program_end end = {0};
    if (program)
        cfg.program_end = &end;
    int rc = tsr_mothership_run(graph, &cfg, &err);
    tsr_graph_free(graph);
    if (rc != TSR_OK) {
        fprintf(stderr, "%s: %s\n", who, err.message);
        if (end.is_verdict)
            return pass_through(&end);
        /* Every node is stopped by now: end by the signal that asked us
         * to, so a shell or a batch system sees what ended the run (an
         * interrupted script loop stops; 128+N in $?), not a failure. */
        if (interrupted)
            return die_by_signal((int)interrupted);
        return rc == TSR_EINVAL ? TSR_EXIT_USAGE : TSR_EXIT_FAIL;
    }
    return TSR_EXIT_OK;
}

int cmd_run(int argc, char **argv) { return tsr_cli_run_graph(argc, argv, 1); }
