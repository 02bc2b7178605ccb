/* mothership/mothership.h — the coordinator of a graph run and the node
 * side of its control channel. Used by `tessera run`, `tessera mothership`
 * (cli/cmd_run.c, cli/cmd_mothership.c) and `tessera node --mothership`
 * (cli/cmd_node.c).
 * Owns: the control listener, one control connection per node, the run's
 * plan (which node gets which chain and addresses), the processes it
 * launched (each in its own process group), statistics and the failure
 * verdict. Never: leaves a process it started running after it returns,
 * or waits on a node without a time-out.
 *
 * A run, in order (messages: mothership/control.h):
 *  1. The mothership listens for control connections (tessera run: on
 *     tcp://127.0.0.1:0) and, in launch mode, starts every local node as
 *     `tessera node --mothership ADDR --name NAME` in its own process
 *     group, working directory = the output directory. It becomes their
 *     child subreaper (PR_SET_CHILD_SUBREAPER), so an application whose
 *     node died is still its to kill and reap.
 *  2. Each node JOINs by name or rank (rank i = the i-th node of the graph
 *     in file order). A node gets its CONFIG once every server it sends to
 *     is READY, so servers listen before their clients connect; a server
 *     answers READY with its bound address (port 0 → the real port).
 *  3. Each node's CONFIG holds its chain as structured links (control.h):
 *     the graph's options plus what the mothership fills in, as each SPU's
 *     class declares (tsr_spu_network, tessera/spu.h): its servers' READY
 *     addresses, the run's token, tiles, rank and peers. An app node runs
 *     the graph's exec with TESSERA_CHAIN = those links as chain text and
 *     TESSERA_STATS_FILE = a file the network SPU writes its statistics to.
 *  4. Every node sends STATS as its heartbeat; the mothership prints a
 *     progress line (on a terminal) and, at the end, a summary and the
 *     statistics JSON.
 *  5. Failure: a node that exits non-zero, dies by a signal, sends no
 *     heartbeat for timeout_ms once READY, or is not READY within
 *     join_timeout_ms of its CONFIG, ends the run: the mothership waits a short
 *     moment for related failures (so the cause, not its consequence, is
 *     named), tells every node to STOP, kills the process groups it
 *     started, and returns TSR_EIO with one line naming the node and what
 *     happened.
 *
 * Paths: a relative exec[0] containing '/' is looked for relative to the
 * graph file's directory, then to the directory above the `tessera`
 * program's bin/ (the build or install prefix: `bin/spheres`), then the
 * node's working directory; a bare name is looked up in PATH. Output
 * files (render output=, print file=) are relative to the node's working
 * directory (tessera run: --out DIR, default the current directory); their
 * directories are created. */
#ifndef TSR_MOTHERSHIP_H
#define TSR_MOTHERSHIP_H

#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "tessera/error.h"
#include "tessera/graph.h"

typedef struct tsr_ms_config {
    const char *listen;       /* control address; NULL = tcp://127.0.0.1:0 */
    const char *token;        /* control and stream token; NULL/"" = none */
    bool launch_local;        /* start local nodes as children (tessera run) */
    const char *self_exe;     /* the tessera program to launch nodes with */
    const char *out_dir;      /* working directory of launched nodes; NULL = "." */
    const char *stats_path;   /* statistics JSON; NULL = none */
    uint32_t timeout_ms;      /* no heartbeat this long = node lost */
    uint32_t join_timeout_ms; /* every node must have joined within this */
    bool progress;            /* live progress line on stderr */
    FILE *summary;            /* end-of-run summary; NULL = none */
    const char *who;          /* prefix of messages: "tessera run" */
    /* Set (to the signal number) by the caller's SIGINT/SIGTERM handler:
     * the run stops as on a failure. May be NULL. */
    volatile sig_atomic_t *interrupted;
    /* Called once listening, with the control address (tessera mothership
     * prints it for launchers). May be NULL. */
    void (*on_listening)(const char *address, void *ctx);
    void *ctx;
    /* NULL-terminated argv every app node runs instead of its graph exec,
     * or NULL (`tessera replay --graph`: the replay is the application). */
    const char *const *app_exec;
    /* `tessera exec --graph`: app node `exec_node` runs exec_argv (NULL-
     * terminated) instead of the graph's exec. NULL: the graph's. */
    const char *exec_node;
    const char *const *exec_argv;
    /* Filled when the run ended and exec_node's program ended by itself
     * (its DONE came): its exit status and the signal that ended it (0:
     * none), and whether that end is the run's failure (the verdict
     * names the program, not a node whose failure it followed). May be
     * NULL. */
    struct tsr_ms_program_end {
        bool ended, is_verdict;
        int exit_code, signal;
    } * program_end;
} tsr_ms_config;

/* Runs the graph to its end. TSR_OK when every node ended cleanly; else
 * `err` names the node and what happened (TSR_EINVAL: the graph cannot be
 * run as given, e.g. an inproc server or a remote node without --listen). */
int tsr_mothership_run(const tsr_graph *graph, const tsr_ms_config *config, tsr_error *err);

/* The node side (`tessera node --mothership`). */
typedef struct tsr_agent_config {
    const char *mothership;      /* netlib address of the mothership */
    const char *name;            /* join by name, or NULL and ... */
    int rank;                    /* ... by rank (>= 0) */
    const char *token;           /* NULL/"" = none */
    uint32_t connect_timeout_ms; /* keep trying to reach the mothership this long */
    uint32_t timeout_ms;         /* the mothership silent this long = lost */
    const char *bind;            /* host a server listens on when the graph names
                                     none; NULL = 127.0.0.1 (loopback) */
} tsr_agent_config;

/* Joins, runs what the mothership configures, reports, and returns the
 * process exit code: 0 ok, 1 failure (err says what), 2 refused or bad
 * configuration. */
int tsr_agent_run(const tsr_agent_config *config, tsr_error *err);

#endif
