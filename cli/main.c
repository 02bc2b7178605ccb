/* cli/main.c — `tessera`: one program, one subcommand per task. Owns
 * argument dispatch and the top-level --help/--version; each subcommand
 * parses its own options. Opts in to the removal of PNG temporaries on
 * fatal signals (tessera/image.h) for the whole program. */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "tessera/image.h"

static const tsr_cli_command commands[] = {
    {"spus", "list installed SPUs with their options, types, defaults and help", cmd_spus},
    {"check", "validate a graph file: keys, SPUs, options, edges, cycles, tiles", cmd_check},
    {"dot", "print a graph file as Graphviz DOT (tessera dot G | dot -Tpng)", cmd_dot},
    {"run", "run a graph: the mothership plus every local node as a child process", cmd_run},
    {"mothership", "coordinate a graph whose nodes are started elsewhere (ssh, mpirun, srun)", cmd_mothership},
    {"node", "run a server node: accept stream clients (network SPUs), run them through an SPU chain", cmd_node},
    {"imgdiff", "compare two PNG images: differing pixels, max channel error, PSNR", cmd_imgdiff},
    {"exec", "run an unmodified OpenGL program (glxgears, ...) under the faker libGL/libEGL", cmd_exec},
    {"replay", "feed a capture file (capture SPU) into a chain or graph; --info lists what it holds", cmd_replay},
};

static void print_usage(FILE *out)
{
    fprintf(out, "usage: tessera COMMAND [ARGS...]\n"
                 "       tessera --help | --version\n\n"
                 "Streams OpenGL command streams through chains of stream processing units.\n\n"
                 "commands:\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(out, "  %-10s %s\n", commands[i].name, commands[i].summary);
    fprintf(out, "\nRun `tessera COMMAND --help` for a command's options.\n"
                 "Exit codes: 0 ok, 1 runtime failure, 2 usage error or bad input.\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        print_usage(stderr);
        return TSR_EXIT_USAGE;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        print_usage(stdout);
        return TSR_EXIT_OK;
    }
    if (!strcmp(argv[1], "--version")) {
        printf("tessera %s\n", TESSERA_VERSION);
        return TSR_EXIT_OK;
    }
    /* Nodes of a graph run (this process or its children) start app
     * nodes' unmodified programs under the faker. */
    if (!strcmp(argv[1], "run") || !strcmp(argv[1], "node") || !strcmp(argv[1], "exec"))
        tsr_cli_export_faker_dir();
    /* The PNG temporaries are this program's to remove when SIGTERM,
     * SIGINT or SIGHUP end it (tessera/image.h); before a command installs
     * its own handlers (run, exec), which then replace these. Without
     * memory for the table, PNGs are still written whole or not at all. */
    tsr_image_pending_remove_on_signals(NULL);
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (!strcmp(argv[1], commands[i].name))
            return commands[i].run(argc - 1, argv + 1);
    fprintf(stderr, "tessera: unknown command '%s' (see tessera --help)\n", argv[1]);
    return TSR_EXIT_USAGE;
}
