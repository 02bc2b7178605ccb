/* cli/cmd_mothership.c — `tessera mothership GRAPH --listen ADDR`: the
 * coordinator alone, for nodes started elsewhere (ssh, mpirun, srun) with
 * `tessera node --mothership`. Options, help and exit codes are shared
 * with `tessera run` (cli/cmd_run.c); the only differences are that
 * --listen is required and no node is launched. */
#include "commands.h"

int cmd_mothership(int argc, char **argv) { return tsr_cli_run_graph(argc, argv, 0); }
