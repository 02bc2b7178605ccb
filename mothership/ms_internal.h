/* mothership/ms_internal.h — what the coordinator's files share: the run
 * (ms), its nodes and pending connections, the time limits, and the steps
 * each file does for the others. The files: mothership.c (failure, the
 * watch loop, configuring in start order, the run), plan.c (each node's
 * configuration: chains with their peers' addresses and tiles),
 * processes.c (launching, reaping, stopping and killing the children),
 * messages.c (joins and control messages), stats.c (the statistics file
 * and the summary). Not for anything outside mothership/. */
#ifndef TSR_MOTHERSHIP_MS_INTERNAL_H
#define TSR_MOTHERSHIP_MS_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/types.h>

#include "control.h"
#include "mothership.h"
#include "tessera/dev/net.h"
#include "tessera/spu.h"

#define POLL_MS 20
#define FAIL_GRACE_S \
    1.0                  /* collect related failures before naming one (a loaded
                              machine may see the root cause after its echo) */
#define LOST_GRACE_S 1.0 /* a launched node's lost connection: wait this long for its exit status */
#define STOP_GRACE_S 1.0 /* after STOP, before SIGKILL */
#define END_GRACE_S 5.0  /* after every DONE, for the processes to exit */
#define MAX_PENDING 64


/* Failure classes, most telling first: a killed or stalled process
 * explains the exits that follow it (an app whose server died exits 1). A
 * server's client dropped for silence is a stopped or hung process too,
 * but when that process is a node of the run its missed heartbeat, found
 * at about the same time (both wait the run's time-out), names it
 * directly; so the silent client ranks just after. A control connection
 * lost without an exit status to explain it (a node on another machine)
 * most likely means that node died. Last, a server whose only failures
 * are clients that went away unclosed: that is the echo of the client's
 * own end (an application that failed and exited), which its node reports
 * with the reason, usually just after the server saw the socket close. */
enum {
    FAIL_INTERRUPT,
    FAIL_SIGNAL,
    FAIL_HEARTBEAT,
    FAIL_SILENT,
    FAIL_LOST,
    FAIL_EXIT,
    FAIL_OTHER,
    FAIL_ECHO,
    FAIL_NONE
};

typedef enum { N_WAITING, N_JOINED, N_CONFIGURED, N_READY, N_DONE } node_state;

typedef struct ms_node {
    const tsr_graph_node *g;
    size_t index;
    int server;
    int local; /* launched by us */
    pid_t pid; /* launched child (process group leader); 0 = none */
    int reaped, wstatus;
    tsr_net_conn *conn;
    int conn_ended;
    double lost_at; /* control connection ended before DONE at; 0 = not */
    /* It ended by an error (cut, reset, no goodbye), not by the orderly
     * end a node's own exit sends: only then did the node outlive it. */
    int lost_by_error;
    /* Exited with a non-zero status before its DONE was read, at (0 =
     * not): its DONE names the cause and may still be on its way. */
    double exit_seen_at;
    char exit_what[160];
    char lost_why[520];
    node_state state;
    double last_heard, configured_at, done_at;
    char address[TSR_NET_ADDRESS_MAX];
    char host[128];
    long remote_pid;
    /* statistics (running totals from STATS / DONE) */
    double frames, buffers, bytes_in, bytes_out, busy, blocked, elapsed;
    unsigned clients;
    int app_stats;                /* -1 not an app, 0 missing, 1 found */
    const tsr_spu_class *network; /* its network SPU's class (the first with a role), or NULL */
    size_t network_link;          /* that SPU's place in the chain (chain_length: none) */
    int links_later;              /* its network SPU takes its peers' addresses: CONFIG without
                                     the chain, LINKS once every peer is READY */
    int links_sent;
    char *sort_first; /* a tilesort app's "sort_first" statistics (JSON), or NULL */
    double rate_t, rate_frames, rate_bytes, fps, mbps;
    int done_status;
    double stats_at;     /* last STATS received */
    int check_connected; /* an app that ended well without statistics: did it reach its servers? */
} ms_node;

typedef struct pending_conn {
    tsr_net_conn *conn;
    double since;
} pending_conn;

typedef struct ms {
    const tsr_graph *graph;
    const tsr_ms_config *cfg;
    size_t count;
    ms_node *nodes;
    tsr_net *net;
    tsr_net_listener *listener;
    pending_conn pending[MAX_PENDING];
    size_t pending_count;
    char graph_dir[PATH_MAX];
    char run_tmp[PATH_MAX]; /* TMPDIR of launched nodes, removed at the end */
    double start;
    int fail_class;
    double fail_deadline;
    char fail_message[512];
    int failing_program; /* set around fail() for the exec program's own end */
    int fail_is_program; /* the verdict is that end */
    double next_progress;
    int progress_shown;
} ms;

/* mothership.c */
void ms_fail(ms *m, int cls, const char *fmt, ...);

/* plan.c */
tsr_spu_role ms_role_of(const ms *m, size_t i);
int ms_add_links(ms *m, const ms_node *n, tsr_ctl_out *out, tsr_error *err);
int ms_send_ctl(tsr_net_conn *conn, unsigned kind, tsr_ctl_out *out, tsr_error *err);
uint32_t ms_heartbeat_ms(const ms *m);
int ms_send_config(ms *m, ms_node *n, tsr_error *err);

/* processes.c */
int ms_launch(ms *m, ms_node *n, const char *control, tsr_error *err);
void ms_reap(ms *m);
bool ms_process_busy(pid_t pid);
void ms_stop_all(ms *m, const char *reason);
void ms_kill_groups(ms *m);
int ms_remove_entry(const char *path, const struct stat *st, int type, struct FTW *ftw);

/* messages.c */
void ms_receive(ms *m);

/* stats.c */
int ms_write_stats(ms *m, int ok, double wall, tsr_error *err);
void ms_summary(ms *m, double wall);

#endif
