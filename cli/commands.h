/* cli/commands.h — the subcommands of the `tessera` program. Each lives in
 * its own cli/cmd_NAME.c and returns the process exit code:
 * 0 ok, 1 runtime failure, 2 usage error or bad input. */
#ifndef TSR_CLI_COMMANDS_H
#define TSR_CLI_COMMANDS_H

#define TSR_EXIT_OK 0
#define TSR_EXIT_FAIL 1
#define TSR_EXIT_USAGE 2

typedef struct tsr_cli_command {
    const char *name;
    const char *summary;               /* one line for `tessera --help` */
    int (*run)(int argc, char **argv); /* argv[0] is the subcommand name */
} tsr_cli_command;

int cmd_imgdiff(int argc, char **argv);
int cmd_spus(int argc, char **argv);
int cmd_check(int argc, char **argv);
int cmd_dot(int argc, char **argv);
int cmd_node(int argc, char **argv);
int cmd_run(int argc, char **argv);
int cmd_mothership(int argc, char **argv);
int cmd_exec(int argc, char **argv);
/* `tessera run` (launch = 1) and `tessera mothership` (0): cli/cmd_run.c. */
int tsr_cli_run_graph(int argc, char **argv, int launch);
/* The same, every app node running `app_exec` (NULL-terminated) instead
 * of its graph exec when it is not NULL, messages prefixed with `as`
 * (NULL: the command's own name): `tessera replay --graph`. */
int tsr_cli_run_graph_as(int argc, char **argv, int launch, const char *const *app_exec, const char *as);
int cmd_replay(int argc, char **argv);
/* The same, with `program` (argv, NULL-terminated) as the exec of app node
 * `node` (NULL: the graph's single app node): `tessera exec --graph`. */
int tsr_cli_run_graph_exec(int argc, char **argv, int launch, const char *node, char **program);
/* The faker's directory (cli/cmd_exec.c): $TESSERA_FAKER_DIR, else the
 * build tree's, else the installed one; "" when none holds libGL.so.1.
 * tsr_cli_export_faker_dir sets $TESSERA_FAKER_DIR to it for the nodes a
 * run starts (mothership/faker.h). */
const char *tsr_cli_faker_dir(void);
void tsr_cli_export_faker_dir(void);


#include <stdio.h>
#include "tessera/graph.h"

/* For subcommands taking one GRAPH (check, dot): parses --help,
 * --no-spu-check and the path, loads the graph into *out (with the
 * TSR_GRAPH_* flags asked for in *flags). Returns the exit
 * code to use when *out is NULL (0 after --help, 2 for bad input). */
int tsr_cli_load_graph(int argc, char **argv, const char *command, void (*print_usage)(FILE *out), tsr_graph **out,
                       unsigned *flags);

#endif
