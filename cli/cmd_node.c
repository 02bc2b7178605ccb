/* cli/cmd_node.c — `tessera node`: runs one server node (node/node.h) on a
 * listen address until the given number of clients connected and ended.
 * Owns only argument parsing and the exit code; the node does the work.
 * Prints "listening on ADDR" (the real port for tcp://...:0) on stdout once
 * clients may connect, so scripts can wait for that line. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "node.h"

static void node_usage(FILE *out)
{
    fprintf(out,
            "usage: tessera node --listen ADDR --chain \"SPU CHAIN\" [--token T] [--clients N]\n"
            "                    [--timeout-ms MS] [--name NAME]\n\n"
            "Runs a server node: accepts stream clients (the pack SPU) on ADDR and feeds\n"
            "each client's stream through its own instance of the SPU chain; replies go back.\n"
            "Ends when N clients have connected and disconnected.\n\n"
            "options:\n"
            "  --listen ADDR     tcp://127.0.0.1:PORT (port 0: any free port), tcp://[::1]:PORT,\n"
            "                    tcp://0.0.0.0:PORT (every interface, only when asked), unix:PATH\n"
            "  --chain TEXT      SPU chain per client, e.g. \"render output=out/f-%%04d.png\";\n"
            "                    {client} becomes the client's number (0, 1, ...)\n"
            "  --token T         shared token clients must present (default: none)\n"
            "  --clients N       clients to serve before ending (default 1)\n"
            "  --timeout-ms MS   longest wait for the next client, and longest silence of a\n"
            "                    connected one (default 60000; 0: no limit)\n"
            "  --name NAME       this node's name in handshakes (default \"node\")\n"
            "  -h, --help        show this help\n\n"
            "Prints \"listening on ADDR\" once ready. Exit codes: 0 every client ended cleanly,\n"
            "1 runtime failure (a client dropped, none came in time, address in use),\n"
            "2 usage error or bad chain.\n");
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

/* Node errors start with "node: "; after "tessera node: " that is noise. */
static const char *without_prefix(const char *message)
{
    return strncmp(message, "node: ", 6) ? message : message + 6;
}

int cmd_node(int argc, char **argv)
{
    tsr_node_config cfg = {.clients = 1, .timeout_ms = 60000};
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (!strcmp(arg, "-h") || !strcmp(arg, "--help")) {
            node_usage(stdout);
            return TSR_EXIT_OK;
        }
        int known = !strcmp(arg, "--listen") || !strcmp(arg, "--chain") || !strcmp(arg, "--token") ||
                    !strcmp(arg, "--clients") || !strcmp(arg, "--timeout-ms") || !strcmp(arg, "--name");
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
        else if (!strcmp(arg, "--clients")) {
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
        }
    }
    if (!cfg.listen || !cfg.chain) {
        fprintf(stderr, "tessera node: --listen and --chain are required (see tessera node --help)\n");
        return TSR_EXIT_USAGE;
    }
    tsr_error err = {0};
    tsr_node *node = tsr_node_create(&cfg, &err);
    if (!node) {
        fprintf(stderr, "tessera node: %s\n", without_prefix(err.message));
        return err.code == TSR_EINVAL ? TSR_EXIT_USAGE : TSR_EXIT_FAIL;
    }
    printf("listening on %s\n", tsr_node_address(node));
    fflush(stdout);
    int rc = tsr_node_run(node, &err);
    if (rc != TSR_OK)
        fprintf(stderr, "tessera node: %s\n", without_prefix(err.message));
    tsr_node_destroy(node);
    return rc == TSR_OK ? TSR_EXIT_OK : TSR_EXIT_FAIL;
}
