/* mothership/control.h — the control messages the mothership and its
 * nodes exchange over one netlib connection per node (tessera/dev/net.h: the
 * connection, handshake with the run's token, and flow control are
 * netlib's). Owns: the message kinds and their fields (this comment
 * specifies them) and the key=value codec (mothership/ctl.c). Never: puts
 * stream data on the control connection.
 *
 * Every payload is UTF-8 text: lines "key=value\n", keys [a-z_]+, values
 * without newlines; a key may repeat (lists, in order). Unknown keys are
 * ignored so later versions can add fields; missing required keys are a
 * protocol error naming the message and the key.
 *
 * Node to mothership:
 *   TSR_MS_MSG_JOIN     name=NODE or rank=N (rank i = the i-th node of the
 *                       graph in file order, from 0); pid=; host= (the
 *                       node machine's host name, for messages).
 *   TSR_MS_MSG_READY    a server listens: address= (the bound address,
 *                       the real port for port 0). App nodes send it once
 *                       their application process started.
 *   TSR_MS_MSG_STATS    the heartbeat, sent every heartbeat_ms from the
 *                       node's main thread: frames= buffers= bytes_in=
 *                       bytes_out= busy_seconds= (render time) clients=
 *                       (servers; running totals, with clients_failed=
 *                       and, of those, clients_vanished=: went away
 *                       unclosed) or elapsed= (apps).
 *                       A server that dropped a client for silence
 *                       (idle_timeout_ms) adds clients_silent= and
 *                       failure= (one line naming that client) and sends
 *                       it at once: the mothership fails the run with it.
 *   TSR_MS_MSG_DONE     the node ended: status=0|1, message= (one line
 *                       naming what failed; empty when status=0), signal=
 *                       (non-zero when the application was killed by a
 *                       signal), then its final STATS fields and, for app
 *                       nodes, exit_code= (the application's exit status;
 *                       0 when a signal ended it), app_stats=found|missing
 *                       plus the fields of
 *                       the application's TESSERA_STATS_FILE (frames,
 *                       buffers, bytes_out, blocked_seconds).
 * Mothership to node:
 *   TSR_MS_MSG_CONFIG   what to run: name=, role=server|app, the chain as
 *                       structured links: link=SPU (repeated, first SPU
 *                       first), each followed by its options as
 *                       option=KEY=VALUE (repeated; VALUE in the option's
 *                       text form, tessera/options.h), the graph's options
 *                       with the values the mothership fills already in
 *                       (what each SPU's class declares, tsr_spu_network:
 *                       server addresses, token, tiles, rank, peers), so a
 *                       node builds its chain from them
 *                       (tsr_chain_create_links) and parses no chain text;
 *                       heartbeat_ms=, mkdir= (repeated:
 *                       directories the chain writes into, relative to the
 *                       node's working directory), base= (repeated: where a
 *                       relative exec is looked for, in order).
 *                       Servers: listen= (netlib address; "unix:" alone =
 *                       a socket the node places itself) or listen_port=
 *                       (TCP on the node's --bind host, default
 *                       127.0.0.1: the graph named no host), clients=,
 *                       token= (clients must prove it), timeout_ms=
 *                       (longest wait for a client), idle_timeout_ms=
 *                       (longest silence of a connected client: the
 *                       run's timeout_ms).
 *                       Apps: arg= (repeated: the exec argv), token= (put
 *                       into the links by the mothership already); the
 *                       application gets the links as TESSERA_CHAIN text
 *                       (tsr_chain_links_text).
 *                       Servers get it at once; an app node only once every
 *                       server it sends to is READY (and has its links).
 *                       A server whose network SPU takes its peers'
 *                       addresses (tsr_spu_network.peers) gets links=later
 *                       instead of the links: it listens, answers READY,
 *                       and waits for LINKS.
 *   TSR_MS_MSG_LINKS    the links (link= and option= as in CONFIG) of a
 *                       node configured with links=later, sent once every
 *                       peer of its group is READY, so each one's address
 *                       is known. The node then builds its chain and runs.
 *   TSR_MS_MSG_STOP     the run is over for a failure elsewhere: reason=.
 *                       The node kills its application and exits 1.
 *   TSR_MS_MSG_REFUSE   the JOIN was wrong (unknown name, rank out of
 *                       range, node already joined): reason=. The node
 *                       prints it and exits 2.
 * A clean end: the node sends DONE status=0 and closes the connection
 * (netlib BYE). Any other end of a connection before DONE is a failure of
 * that node. */
#ifndef TSR_MOTHERSHIP_CONTROL_H
#define TSR_MOTHERSHIP_CONTROL_H

#include <stddef.h>

#include "tessera/chain.h"
#include "tessera/error.h"

#define TSR_MS_MSG_JOIN 0x20u
#define TSR_MS_MSG_READY 0x21u
#define TSR_MS_MSG_STATS 0x22u
#define TSR_MS_MSG_DONE 0x23u
#define TSR_MS_MSG_CONFIG 0x30u
#define TSR_MS_MSG_STOP 0x31u
#define TSR_MS_MSG_REFUSE 0x32u
#define TSR_MS_MSG_LINKS 0x33u

/* Defaults shared by `tessera run`, `tessera mothership` and `tessera node
 * --mothership`. */
#define TSR_MS_DEFAULT_TIMEOUT_MS 5000u       /* no heartbeat this long = node lost */
#define TSR_MS_DEFAULT_JOIN_TIMEOUT_MS 30000u /* every node joined within this */

/* A decoded message: key/value pairs pointing into one owned copy of the
 * text. As many fields as the message holds (a CONFIG has one per option
 * of every link and one per exec argument, so a fixed count would refuse
 * graphs that check accepts); the message size bounds them. */
typedef struct tsr_ctl {
    char *text;
    size_t count;
    const char **keys; /* count of each, owned */
    const char **values;
} tsr_ctl;

/* A message being built (text grows; never fails silently: an error is
 * remembered and returned by tsr_ctl_out_error). */
typedef struct tsr_ctl_out {
    char *text;
    size_t len, cap;
    int failed;
} tsr_ctl_out;

void tsr_ctl_out_init(tsr_ctl_out *out);
void tsr_ctl_out_free(tsr_ctl_out *out);
/* Adds key=value; a newline in value becomes a blank. */
void tsr_ctl_add(tsr_ctl_out *out, const char *key, const char *value);
void tsr_ctl_addf(tsr_ctl_out *out, const char *key, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Parses `len` bytes of payload. TSR_EPROTO when a line has no '='.
 * Free with tsr_ctl_free. */
int tsr_ctl_parse(tsr_ctl *msg, const void *data, size_t len, tsr_error *err);
void tsr_ctl_free(tsr_ctl *msg);
/* The first value of `key`, or NULL. */
const char *tsr_ctl_get(const tsr_ctl *msg, const char *key);
/* Numeric value of `key`; `fallback` when absent or not a number. */
double tsr_ctl_number(const tsr_ctl *msg, const char *key, double fallback);

/* The chain a CONFIG or LINKS carries as links ("link=SPU" fields, each
 * followed by its "option=KEY=VALUE" fields), ready for
 * tsr_chain_create_links. SPU names and values point into the message
 * (keep it until the chain is built); keys are copies. */
typedef struct tsr_ctl_chain {
    tsr_chain_link *links;
    size_t count;
    const char **keys, **values; /* every link's options, in order */
    size_t option_count;
} tsr_ctl_chain;

/* TSR_EPROTO naming the field when there is no link= or an option= is not
 * KEY=VALUE or comes before any link=. Free with tsr_ctl_chain_free. */
int tsr_ctl_chain_parse(const tsr_ctl *msg, tsr_ctl_chain *chain, tsr_error *err);
void tsr_ctl_chain_free(tsr_ctl_chain *chain);

/* Human names of the message kinds, for errors. */
const char *tsr_ctl_kind_name(unsigned kind);

#endif
