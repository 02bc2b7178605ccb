/* cli/graph_args.c — argument handling shared by the subcommands that take
 * one GRAPH file (check, dot): --help, --no-spu-check, exactly one path,
 * and loading with the one-line FILE:LINE:COL error. Never prints to
 * stdout except the command's own --help. */
#include <stdio.h>
#include <string.h>

#include "commands.h"

int tsr_cli_load_graph(int argc, char **argv, const char *command, void (*print_usage)(FILE *out), tsr_graph **out,
                       unsigned *flags_out)
{
    unsigned flags = 0;
    const char *path = NULL;
    *out = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            print_usage(stdout);
            return TSR_EXIT_OK;
        }
        if (!strcmp(argv[i], "--no-spu-check")) {
            flags |= TSR_GRAPH_NO_SPU_CHECK;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            fprintf(stderr, "tessera %s: unknown option '%s' (see tessera %s --help)\n", command, argv[i], command);
            return TSR_EXIT_USAGE;
        } else if (path) {
            fprintf(stderr, "tessera %s: one GRAPH at a time ('%s' and '%s')\n", command, path, argv[i]);
            return TSR_EXIT_USAGE;
        } else {
            path = argv[i];
        }
    }
    if (!path) {
        print_usage(stderr);
        return TSR_EXIT_USAGE;
    }
    tsr_error err;
    tsr_error_clear(&err);
    *flags_out = flags;
    *out = tsr_graph_load(path, flags, &err);
    if (!*out) {
        fprintf(stderr, "%s\n", err.message);
        return err.code == TSR_ENOMEM ? TSR_EXIT_FAIL : TSR_EXIT_USAGE;
    }
    return TSR_EXIT_OK;
}
