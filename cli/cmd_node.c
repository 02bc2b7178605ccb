/* cli/cmd_node.c — `tessera node`: either a standalone server node
 * (server/node.h) on a listen address until the given number of clients
 * connected and ended, or, with --mothership, a node of a graph run that
 * takes its role from the mothership (mothership/mothership.h).
 * Owns only argument parsing and the exit code; the node does the work.
 * Standalone, prints "listening on ADDR" (the real port for tcp://...:0) on
 * stdout once clients may connect, so scripts can wait for that line. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "mothership.h"
#include "control.h"
#include "tessera/dev/net.h"
#include "node.h"
#include "tessera/dev/unpack.h"

static void node_usage(FILE *out)
{
    fprintf(out,
            "usage: tessera node --listen ADDR --chain \"SPU CHAIN\" [--token T | --insecure]\n"
            "                    [--clients N] [--timeout-ms MS] [--idle-timeout-ms MS]\n"
            "                    [--name NAME] [--independent] [--max-vertices N]\n"
            "                    [--max-buffer-bytes N] [--max-reply-bytes N]\n"
            "                    [--max-pending-reply-bytes N] [--cost cpu|bytes]\n"
            "                    [--cost-scale X] [--stall-first-frame-ms MS]\n"
            "       tessera node --mothership HOST:PORT [--name NAME | --rank N] [--token T]\n"
            "                    [--bind HOST] [--timeout-ms MS] [--connect-timeout-ms MS]\n\n"
            "Runs a server node: accepts stream clients (the pack SPU) on ADDR and feeds\n"
            "their streams through the SPU chain; replies go back. Ends when N clients have\n"
            "connected and disconnected.\n\n"
            "By default the N clients draw ONE picture, like the processes of a parallel\n"
            "program: one thread runs one chain with a GL context per client (render: one\n"
            "shared window), scheduling clients round-robin a buffer at a time. Barriers\n"
            "and semaphores (glBarrierCreateTSR/ExecTSR, glSemaphoreCreateTSR/PTSR/VTSR)\n"
            "block and release clients' streams; the first client to swap is the one whose\n"
            "swaps end frames (the others' are ignored). If every client is blocked, the\n"
            "node fails naming the barrier or semaphore and the clients waiting (exit 1).\n\n"
            "options:\n"
            "  --listen ADDR     tcp://127.0.0.1:PORT (port 0: any free port), tcp://[::1]:PORT,\n"
            "                    tcp://0.0.0.0:PORT (every interface, only when asked), unix:PATH\n"
            "  --chain TEXT      SPU chain, e.g. \"render output=out/f-%%04d.png\"\n"
            "  --independent     one chain and thread per client instead: unrelated apps, each\n"
            "                    swapping on its own; {client} in the chain text becomes the\n"
            "                    client's number (0, 1, ...), e.g. output=out/c{client}-%%04d.png\n"
            "  --token T         shared token clients must prove they know (default: none);\n"
            "                    never sent: each side proves it to the other (HMAC of the\n"
            "                    other's nonce). Authentication only: traffic is not encrypted\n"
            "  --insecure        listen on an address other hosts reach (not loopback)\n"
            "                    without --token: anyone reaching it can use the node.\n"
            "                    Without it, such a node refuses to start\n"
            "  --clients N       clients to serve before ending (default 1)\n"
            "  --timeout-ms MS   longest wait for the next client (default 60000; 0: no limit)\n"
            "  --idle-timeout-ms MS  longest silence of a connected client, which is then taken\n"
            "                    for stopped or dead, dropped and named (default 15000; 0: no\n"
            "                    limit); a client busy computing still answers heartbeats\n"
            "  --name NAME       this node's name in handshakes (default \"node\")\n"
            "  Each client's budget (a client over it is dropped and named; the others go on;\n"
            "  0: no limit; render's own: its options max_texture_bytes, max_window_pixels):\n"
            "  --max-vertices N  vertices the draws of one received buffer may ask for\n"
            "                    (default 16777216); draws reading past their arrays or\n"
            "                    buffers are refused whatever the budget\n"
            "  --max-buffer-bytes N  bytes of buffer objects a client may hold (default 536870912)\n"
            "  --max-reply-bytes N   bytes one request may ask the node to send back (default\n"
            "                    and at most 67104760: the node's message limit, whatever\n"
            "                    limit the client announces)\n"
            "  --max-pending-reply-bytes N  reply bytes a client may leave unread (default\n"
            "                    268435456)\n"
            "  Settings for testing a load balancer (an SPU that splits by frame cost; each is logged):\n"
            "  --cost cpu|bytes  the frame cost a swap reports: the chain's thread CPU time\n"
            "                    (cpu, the default) or 1 ns per byte received (bytes: the\n"
            "                    same on any machine and load)\n"
            "  --cost-scale X    multiply the reported cost by X (2: a server twice as slow;\n"
            "                    default 1)\n"
            "  --stall-first-frame-ms MS  the node's first frame takes MS longer (a slow\n"
            "                    server without a huge window; default 0)\n"
            "  -h, --help        show this help\n\n"
            "Prints \"listening on ADDR\" once ready. Exit codes: 0 every client ended cleanly,\n"
            "1 runtime failure (a client dropped, none came in time, address in use),\n"
            "2 usage error or bad chain.\n\n"
            "With --mothership, the node joins a graph run instead (tessera mothership --help):\n"
            "the mothership says whether it is a server or runs an application, and with which\n"
            "chain. It joins by --name, or by --rank N (the N-th node of the graph in file\n"
            "order, from 0); without either, the rank comes from OMPI_COMM_WORLD_RANK,\n"
            "PMI_RANK or SLURM_PROCID (mpirun, srun).\n"
            "  --mothership ADDR       HOST:PORT, tcp://HOST:PORT or unix:PATH\n"
            "  --rank N                join as the N-th node of the graph\n"
            "  --token T               the run's token (default: $TESSERA_TOKEN)\n"
            "  --bind HOST             as a server whose graph entry names no listen host,\n"
            "                          listen on HOST (an address its clients reach; default\n"
            "                          127.0.0.1, loopback only)\n"
            "  --timeout-ms MS         give the mothership's --timeout-ms (default %u); a\n"
            "                          mothership silent for 3 x MS counts as lost\n"
            "  --connect-timeout-ms MS keep trying to reach the mothership this long\n"
            "                          (default 10000)\n"
            "Exit codes: 0 ok, 1 failure (the line says why; also when the mothership stops\n"
            "the run or is lost), 2 usage error or refused by the mothership.\n",
            TSR_MS_DEFAULT_TIMEOUT_MS);
}

static int parse_count(const char *text, long min, long max, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (errno || end == text || *end || v < min || v > max)
        return -1;
    *out = v;
    return 0;
}

/* --cost, --cost-scale or --stall-first-frame-ms `value` into `cfg`; 0, or
 * -1 after one line naming the option and value. */
static int parse_cost_setting(tsr_node_config *cfg, const char *option, const char *value)
{
    long n;
    if (!strcmp(option, "--cost")) {
        if (!strcmp(value, "cpu") || !strcmp(value, "bytes")) {
            cfg->cost_source = !strcmp(value, "bytes") ? TSR_NODE_COST_FROM_BYTES : TSR_NODE_COST_FROM_CPU;
            return 0;
        }
        fprintf(stderr, "tessera node: bad --cost '%s' (expected cpu or bytes)\n", value);
        return -1;
    }
    if (!strcmp(option, "--cost-scale")) {
        char *end;
        errno = 0;
        double x = strtod(value, &end);
        if (!errno && end != value && !*end && x > 0 && x <= 1e6) {
            cfg->cost_scale = x;
            return 0;
        }
        fprintf(stderr, "tessera node: bad --cost-scale '%s' (expected a number over 0, at most 1e6)\n", value);
        return -1;
    }
    if (parse_count(value, 0, 3600000, &n) == 0) {
        cfg->stall_first_frame_ms = (uint32_t)n;
        return 0;
    }
    fprintf(stderr, "tessera node: bad --stall-first-frame-ms '%s' (expected 0..3600000)\n", value);
    return -1;
}

/* Node errors start with "node: "; after "tessera node: " that is noise. */
static const char *without_prefix(const char *message) { return strncmp(message, "node: ", 6) ? message : message + 6; }

/* The launcher's rank: mpirun (Open MPI, MPICH/PMI) or srun. */
static const char *rank_from_env(const char **var)
{
    static const char *const vars[] = {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "SLURM_PROCID"};
    for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++) {
        const char *v = getenv(vars[i]);
        if (v && *v) {
            *var = vars[i];
            return v;
        }
    }
    return NULL;
}

static int node_with_mothership(const char *mothership, const char *name, const char *rank_text, const char *token,
                                long timeout_ms, long connect_timeout_ms, const char *bind)
{
    tsr_agent_config cfg = {.name = name, .rank = -1, .token = token, .bind = bind};
    char address[256];
    tsr_error bad;
    if (tsr_net_address_normalise(mothership, address, sizeof address, &bad) != TSR_OK) {
        fprintf(stderr, "tessera node: --mothership: %s\n", bad.message);
        return TSR_EXIT_USAGE;
    }
    cfg.mothership = address;
    if (name && rank_text) {
        fprintf(stderr, "tessera node: --name and --rank exclude each other\n");
        return TSR_EXIT_USAGE;
    }
    const char *source = "--rank";
    if (!name && !rank_text)
        rank_text = rank_from_env(&source);
    if (!name) {
        long r;
        if (!rank_text) {
            fprintf(stderr, "tessera node: --mothership needs --name NAME or --rank N (or one of "
                            "OMPI_COMM_WORLD_RANK, PMI_RANK, SLURM_PROCID)\n");
            return TSR_EXIT_USAGE;
        }
        if (parse_count(rank_text, 0, 1000000, &r)) {
            fprintf(stderr, "tessera node: bad rank '%s' from %s (expected 0, 1, ...)\n", rank_text, source);
            return TSR_EXIT_USAGE;
        }
        cfg.rank = (int)r;
    }
    if (!cfg.token || !*cfg.token)
        cfg.token = getenv("TESSERA_TOKEN");
    cfg.timeout_ms = timeout_ms < 0 ? TSR_MS_DEFAULT_TIMEOUT_MS : (uint32_t)timeout_ms;
    cfg.connect_timeout_ms = connect_timeout_ms < 0 ? 10000 : (uint32_t)connect_timeout_ms;
    tsr_error err = {0};
    int code = tsr_agent_run(&cfg, &err);
    if (code)
        fprintf(stderr, "tessera node: %s%s%s: %s\n", name ? "" : "rank ", name ? name : rank_text, "", err.message);
    /* A server thread or the I/O thread may still run after a STOP: end
     * here, without running exit handlers under their feet. */
    fflush(NULL);
    _exit(code);
}

int cmd_node(int argc, char **argv)
{
    tsr_node_config cfg = {.clients = 1, .timeout_ms = 60000, .idle_timeout_ms = 15000};
    const char *mothership = NULL, *rank = NULL, *bind = NULL;
    int insecure = 0;
    long timeout_given = -1, connect_timeout = -1, idle_given = -1;
    int cost_given = 0;
    tsr_unpack_limits limits;
    tsr_unpack_limits_defaults(&limits);
    cfg.limits = &limits;
    uint64_t *budgets[] = {&limits.max_vertices, &limits.max_buffer_bytes, &limits.max_output,
                           &cfg.max_pending_reply_bytes};
    static const char *const budget_flags[] = {"--max-vertices", "--max-buffer-bytes", "--max-reply-bytes",
                                               "--max-pending-reply-bytes"};
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (!strcmp(arg, "-h") || !strcmp(arg, "--help")) {
            node_usage(stdout);
            return TSR_EXIT_OK;
        }
        if (!strcmp(arg, "--independent")) {
            cfg.mode = TSR_NODE_INDEPENDENT;
            continue;
        }
        if (!strcmp(arg, "--insecure")) {
            insecure = 1;
            continue;
        }
        int budget = -1;
        for (int k = 0; k < 4; k++)
            if (!strcmp(arg, budget_flags[k]))
                budget = k;
        if (budget >= 0) {
            char *end;
            errno = 0;
            unsigned long long v = i + 1 < argc ? strtoull(argv[i + 1], &end, 10) : 0;
            if (i + 1 >= argc || errno || end == argv[i + 1] || *end || argv[i + 1][0] == '-') {
                fprintf(stderr, "tessera node: bad %s '%s' (expected a count of 0 or more)\n", arg,
                        i + 1 < argc ? argv[i + 1] : "");
                return TSR_EXIT_USAGE;
            }
            /* 0 is no limit; pending replies have no "off" (0 = the default). */
            *budgets[budget] = v ? v : budget == 3 ? UINT64_MAX : 0;
            i++;
            continue;
        }
        if (!strcmp(arg, "--cost") || !strcmp(arg, "--cost-scale") || !strcmp(arg, "--stall-first-frame-ms")) {
            const char *value = i + 1 < argc ? argv[++i] : "";
            if (parse_cost_setting(&cfg, arg, value) != 0)
                return TSR_EXIT_USAGE;
            cost_given = 1;
            continue;
        }
        int known = !strcmp(arg, "--listen") || !strcmp(arg, "--chain") || !strcmp(arg, "--token") ||
                    !strcmp(arg, "--clients") || !strcmp(arg, "--timeout-ms") || !strcmp(arg, "--name") ||
                    !strcmp(arg, "--mothership") || !strcmp(arg, "--rank") || !strcmp(arg, "--bind") ||
                    !strcmp(arg, "--connect-timeout-ms") || !strcmp(arg, "--idle-timeout-ms");
        if (!known) {
            fprintf(stderr, "tessera node: unknown option '%s' (see tessera node --help)\n", arg);
            return TSR_EXIT_USAGE;
        }
        if (i + 1 >= argc) {
            fprintf(stderr, "tessera node: option %s needs a value\n", arg);
            return TSR_EXIT_USAGE;
        }
        const char *value = argv[++i];
        long n;
        if (!strcmp(arg, "--listen"))
            cfg.listen = value;
        else if (!strcmp(arg, "--chain"))
            cfg.chain = value;
        else if (!strcmp(arg, "--token"))
            cfg.token = value;
        else if (!strcmp(arg, "--name"))
            cfg.name = value;
        else if (!strcmp(arg, "--mothership"))
            mothership = value;
        else if (!strcmp(arg, "--rank"))
            rank = value;
        else if (!strcmp(arg, "--bind"))
            bind = value;
        else if (!strcmp(arg, "--connect-timeout-ms")) {
            if (parse_count(value, 0, 86400000, &n)) {
                fprintf(stderr, "tessera node: bad --connect-timeout-ms '%s' (expected 0..86400000)\n", value);
                return TSR_EXIT_USAGE;
            }
            connect_timeout = n;
        } else if (!strcmp(arg, "--idle-timeout-ms")) {
            if (parse_count(value, 0, 86400000, &n)) {
                fprintf(stderr, "tessera node: bad --idle-timeout-ms '%s' (expected 0..86400000)\n", value);
                return TSR_EXIT_USAGE;
            }
            cfg.idle_timeout_ms = (uint32_t)n;
            idle_given = n;
        } else if (!strcmp(arg, "--clients")) {
            if (parse_count(value, 1, 100000, &n)) {
                fprintf(stderr, "tessera node: bad --clients '%s' (expected 1..100000)\n", value);
                return TSR_EXIT_USAGE;
            }
            cfg.clients = (unsigned)n;
        } else {
            if (parse_count(value, 0, 86400000, &n)) {
                fprintf(stderr, "tessera node: bad --timeout-ms '%s' (expected 0..86400000)\n", value);
                return TSR_EXIT_USAGE;
            }
            cfg.timeout_ms = (uint32_t)n;
            timeout_given = n;
        }
    }
    if (mothership) {
        if (cfg.listen || cfg.chain) {
            fprintf(stderr, "tessera node: --mothership gives the node its role: no --listen or --chain\n");
            return TSR_EXIT_USAGE;
        }
        if (insecure) {
            fprintf(stderr, "tessera node: --insecure is for a standalone node (with --mothership, the run's "
                            "token decides)\n");
            return TSR_EXIT_USAGE;
        }
        if (idle_given >= 0) {
            fprintf(stderr, "tessera node: with --mothership, the run's --timeout-ms is the servers' "
                            "--idle-timeout-ms\n");
            return TSR_EXIT_USAGE;
        }
        if (cost_given) {
            fprintf(stderr, "tessera node: --cost, --cost-scale and --stall-first-frame-ms are for a standalone "
                            "node (not with --mothership)\n");
            return TSR_EXIT_USAGE;
        }
        return node_with_mothership(mothership, cfg.name, rank, cfg.token, timeout_given, connect_timeout, bind);
    }
    if (rank || bind || connect_timeout >= 0) {
        fprintf(stderr, "tessera node: --rank, --bind and --connect-timeout-ms need --mothership\n");
        return TSR_EXIT_USAGE;
    }
    if (!cfg.listen || !cfg.chain) {
        fprintf(stderr, "tessera node: --listen and --chain are required (see tessera node --help)\n");
        return TSR_EXIT_USAGE;
    }
    tsr_error err = {0};
    const char *warning = NULL;
    if (!cfg.token || !*cfg.token) {
        /* (An address that does not parse or resolve is reported below.) */
        int local = tsr_net_address_is_local(cfg.listen, &err);
        if (local == 0 && !insecure) {
            fprintf(stderr,
                    "tessera node: refusing to listen on %s without --token: other hosts reach it and could "
                    "drive this node (give --token T, listen on 127.0.0.1, or pass --insecure)\n",
                    cfg.listen);
            return TSR_EXIT_USAGE;
        }
        /* Warned once the node listens (a bad address is one line). A
         * unix: socket is guarded by its file's permissions instead. */
        if (local == 0)
            warning = "--insecure: anyone who reaches it can use this node";
        else if (local == 1 && !strncmp(cfg.listen, "tcp://", 6))
            warning = "no --token: any local user can connect to it";
    }
    tsr_node *node = tsr_node_create(&cfg, &err);
    if (!node) {
        fprintf(stderr, "tessera node: %s\n", without_prefix(err.message));
        return err.code == TSR_EINVAL ? TSR_EXIT_USAGE : TSR_EXIT_FAIL;
    }
    if (warning)
        fprintf(stderr, "tessera node: warning: %s (%s)\n", warning, tsr_node_address(node));
    printf("listening on %s\n", tsr_node_address(node));
    fflush(stdout);
    int rc = tsr_node_run(node, &err);
    if (rc != TSR_OK)
        fprintf(stderr, "tessera node: %s\n", without_prefix(err.message));
    tsr_node_destroy(node);
    return rc == TSR_OK ? TSR_EXIT_OK : TSR_EXIT_FAIL;
}
