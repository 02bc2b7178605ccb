/* server/node.c — the server node (server/node.h): configuration, listener,
 * statistics, and independent mode (one session thread per client: chain
 * + unpacker + reply channel). Shared mode is in schedule.c.
 * Owns: the netlib instance, the listener, every session and its chain.
 * Never touches a session's chain from another thread (OSMesa contexts
 * are current per thread), never exits on a client's bad input. */
#include "tessera/dev/util.h"
#include "node.h"
#include "node_internal.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "tessera/dev/net.h"
#include "tessera/dev/protocol.h"
#include "tessera/chain.h"
#include "tessera/log.h"
#include "tessera/dev/unpack.h"
#include "tessera/dev/wire.h"

typedef struct node_session {
    struct tsr_node *node;
    unsigned index; /* client number, in connection order */
    tsr_net_conn *conn;
    char who[TSR_NET_NAME_MAX + TSR_NET_ADDRESS_MAX + 32]; /* "client 0 'pack-pid1' at tcp://..." */
    pthread_t thread;
    int started;
    uint8_t *reply; /* TSR_NODE_MSG_REPLY being sent */
    size_t reply_cap;
    tsr_node_sent sent;
    tsr_error error;      /* why this session failed; TSR_OK when it ended cleanly */
    tsr_dispatch head;    /* the chain's head with SwapBuffersTSR counted */
    tsr_entry chain_swap; /* the chain's own SwapBuffersTSR */
    tsr_node_cost cost;   /* this frame's, for TSR_NODE_SWAP_REPORT_COST */
} node_session;

/* Adds to the node's totals under its lock (sessions run on their own
 * threads; tsr_node_get_stats may be called from any). */
void tsr_node_stats_add(tsr_node *node, const tsr_node_stats *delta)
{
    pthread_mutex_lock(&node->stats_lock);
    tsr_node_stats *t = &node->stats;
    t->frames += delta->frames;
    t->buffers += delta->buffers;
    t->commands += delta->commands;
    t->bytes_in += delta->bytes_in;
    t->bytes_out += delta->bytes_out;
    t->busy_seconds += delta->busy_seconds;
    t->clients_connected += delta->clients_connected;
    t->clients_ended += delta->clients_ended;
    t->clients_failed += delta->clients_failed;
    t->clients_silent += delta->clients_silent;
    t->clients_vanished += delta->clients_vanished;
    t->swaps_ignored += delta->swaps_ignored;
    t->blocks += delta->blocks;
    pthread_mutex_unlock(&node->stats_lock);
}

void tsr_node_client_ended(tsr_node *node, int failed, tsr_net_conn *conn, const char *who, const char *why)
{
    int silent = failed && conn && tsr_net_conn_went_silent(conn);
    int vanished = failed && conn && !silent && tsr_net_conn_vanished(conn);
    pthread_mutex_lock(&node->stats_lock);
    tsr_node_stats *t = &node->stats;
    t->clients_ended += !failed;
    t->clients_failed += failed != 0;
    t->clients_silent += silent;
    t->clients_vanished += vanished;
    if (failed && silent && !node->silent_failure[0])
        snprintf(node->silent_failure, sizeof node->silent_failure, "node: %s dropped: %s", who, why);
    pthread_mutex_unlock(&node->stats_lock);
}

int tsr_node_silent_failure(tsr_node *node, char *out, size_t size)
{
    pthread_mutex_lock(&node->stats_lock);
    int found = node->silent_failure[0] != '\0';
    if (found && size)
        snprintf(out, size, "%s", node->silent_failure);
    pthread_mutex_unlock(&node->stats_lock);
    return found;
}

void tsr_node_get_stats(tsr_node *node, tsr_node_stats *out)
{
    pthread_mutex_lock(&node->stats_lock);
    *out = node->stats;
    pthread_mutex_unlock(&node->stats_lock);
}

static void count_swap(void *self, GLint window, GLbitfield flags)
{
    node_session *s = self;
    tsr_node_test_stall(s->node);
    ((tsr_fn_SwapBuffersTSR)s->chain_swap.fn)(s->chain_swap.self, window, flags & ~TSR_NODE_SWAP_REPORT_COST);
    if (flags & TSR_NODE_SWAP_REPORT_COST)
        tsr_node_report_cost(s->node, s->conn, &s->sent, &s->cost);
    tsr_node_stats delta = {.frames = 1};
    tsr_node_stats_add(s->node, &delta);
}

/* The chain text with every "{client}" replaced by `index`; NULL when out
 * of memory. */
static char *chain_text_for(const char *text, unsigned index)
{
    static const char marker[] = "{client}";
    char number[16];
    int digits = snprintf(number, sizeof number, "%u", index);
    size_t count = 0;
    for (const char *p = strstr(text, marker); p; p = strstr(p + 1, marker))
        count++;
    size_t size = strlen(text) + count * (size_t)digits + 1;
    char *out = malloc(size);
    if (!out)
        return NULL;
    char *o = out;
    for (const char *p = text;;) {
        const char *m = strstr(p, marker);
        size_t n = m ? (size_t)(m - p) : strlen(p);
        memcpy(o, p, n);
        o += n;
        if (!m)
            break;
        memcpy(o, number, (size_t)digits);
        o += digits;
        p = m + sizeof marker - 1;
    }
    *o = '\0';
    return out;
}

/* The node's links with "{client}" replaced in every value, built. */
static tsr_chain *create_chain_from_links(const tsr_node *node, unsigned index, tsr_error *err)
{
    size_t total = 0;
    for (size_t i = 0; i < node->link_count; i++)
        total += node->links[i].option_count;
    tsr_chain_link *links = calloc(node->link_count, sizeof *links);
    char **values = calloc(total ? total : 1, sizeof *values);
    int failed = !links || !values;
    size_t v = 0;
    for (size_t i = 0; i < node->link_count && !failed; i++) {
        links[i] = node->links[i];
        links[i].values = (const char *const *)values + v;
        for (size_t k = 0; k < node->links[i].option_count && !failed; k++)
            failed = !(values[v++] = chain_text_for(node->links[i].values[k], index));
    }
    tsr_chain *chain = NULL;
    if (failed)
        tsr_error_set(err, TSR_ENOMEM, "node: out of memory for the chain");
    else
        chain = tsr_chain_create_links(links, node->link_count, err);
    for (size_t i = 0; i < total && values; i++)
        free(values[i]);
    free(values);
    free(links);
    return chain;
}

/* Frees what copy_links made (also a partial copy: NULLs are skipped). */
static void free_links(tsr_chain_link *links, size_t count)
{
    for (size_t i = 0; links && i < count; i++) {
        for (size_t k = 0; k < links[i].option_count; k++) {
            free(links[i].keys ? (char *)links[i].keys[k] : NULL);
            free(links[i].values ? (char *)links[i].values[k] : NULL);
        }
        free((void *)links[i].keys);
        free((void *)links[i].values);
        free((char *)links[i].spu);
    }
    free(links);
}

/* Owned copies of `count` links, NULL when out of memory. */
static tsr_chain_link *copy_links(const tsr_chain_link *from, size_t count)
{
    tsr_chain_link *links = calloc(count ? count : 1, sizeof *links);
    int failed = !links;
    for (size_t i = 0; i < count && !failed; i++) {
        size_t n = from[i].option_count;
        const char **keys = calloc(n ? n : 1, sizeof *keys);
        const char **values = calloc(n ? n : 1, sizeof *values);
        links[i] = (tsr_chain_link){.spu = strdup(from[i].spu), .keys = keys, .values = values, .option_count = n};
        failed = !links[i].spu || !keys || !values;
        for (size_t k = 0; k < n && !failed; k++)
            failed = !(keys[k] = strdup(from[i].keys[k])) || !(values[k] = strdup(from[i].values[k]));
    }
    if (failed) {
        free_links(links, count);
        return NULL;
    }
    return links;
}

tsr_chain *tsr_node_create_chain(const tsr_node *node, unsigned index, tsr_error *err)
{
    if (!node->chain_text)
        return create_chain_from_links(node, index, err);
    char *text = chain_text_for(node->chain_text, index);
    if (!text) {
        tsr_error_set(err, TSR_ENOMEM, "node: out of memory for the chain text");
        return NULL;
    }
    tsr_chain *chain = tsr_chain_create(text, err);
    free(text);
    return chain;
}

void tsr_node_test_stall(tsr_node *node)
{
    if (!node->test_stall_ms || atomic_exchange(&node->test_stalled, 1))
        return;
    struct timespec ts = {node->test_stall_ms / 1000, (long)(node->test_stall_ms % 1000) * 1000000L};
    while (nanosleep(&ts, &ts) != 0)
        ;
}

double tsr_node_thread_cpu(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0)
        return 0;
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

long tsr_node_thread_faults(void)
{
    struct rusage ru;
    return getrusage(RUSAGE_THREAD, &ru) == 0 ? ru.ru_minflt : 0;
}

void tsr_node_cost_start(tsr_node_cost *cost)
{
    cost->cpu_at_swap = tsr_node_thread_cpu();
    cost->faults_at_swap = tsr_node_thread_faults();
}

/* Thread CPU seconds of one minor fault of fresh anonymous memory, the
 * kind a render server takes when its region moves onto pixels it has not
 * drawn (its buffers' pages outside its tiles are given back): the best of
 * a few rounds of touching fresh small pages, so a preempted round does
 * not count. The balancer takes these seconds off the frame it learns from
 * (tessera/dev/protocol.h TSR_NODE_MSG_COST). */
static double measure_fault_seconds(void)
{
    enum { PAGES = 256, ROUNDS = 5 };
    size_t page = (size_t)sysconf(_SC_PAGESIZE), size = PAGES * page;
    double best = 0;
    for (int round = 0; round < ROUNDS; round++) {
        unsigned char *p = mmap(NULL, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED)
            break;
#ifdef MADV_NOHUGEPAGE
        madvise(p, size, MADV_NOHUGEPAGE); /* one fault per small page, as a renderbuffer's */
#endif
        long f0 = tsr_node_thread_faults();
        double t0 = tsr_node_thread_cpu();
        for (size_t i = 0; i < size; i += page)
            ((volatile unsigned char *)p)[i] = 1;
        double t = tsr_node_thread_cpu() - t0;
        long faults = tsr_node_thread_faults() - f0;
        munmap(p, size);
        if (faults > 0 && (best == 0 || t / (double)faults < best))
            best = t / (double)faults;
    }
    return best;
}

/* The node's cost of one fault, measured at the first report that has
 * faults in it (a node nobody asks for costs never spends the 2-3 ms);
 * the sessions of independent mode share it, under the stats lock. */
static double fault_cost(tsr_node *node)
{
    pthread_mutex_lock(&node->stats_lock);
    if (!node->fault_measured) {
        node->fault_seconds = measure_fault_seconds();
        node->fault_measured = 1;
        tsr_log(TSR_LOG_DEBUG, "node: a minor page fault costs %.2f us of thread CPU here", node->fault_seconds * 1e6);
    }
    double seconds = node->fault_seconds;
    pthread_mutex_unlock(&node->stats_lock);
    return seconds;
}

void tsr_node_report_cost(tsr_node *node, tsr_net_conn *conn, tsr_node_sent *sent, tsr_node_cost *cost)
{
    double now = tsr_node_thread_cpu();
    long faults = tsr_node_thread_faults() - cost->faults_at_swap;
    faults = faults < 0 ? 0 : faults;
    double seconds = node->test_cost_bytes ? (double)cost->bytes * 1e-9 : now - cost->cpu_at_swap;
    /* deterministic test costs have no faults in them; the measurement
     * comes after the frame's count and before the next one starts */
    double fault_seconds = node->test_cost_bytes || !faults ? 0 : (double)faults * fault_cost(node);
    fault_seconds = fault_seconds < seconds ? fault_seconds : seconds;
    uint8_t msg[TSR_NODE_COST_BYTES];
    tsr_wire_put_u32(msg, cost->frame++);
    tsr_wire_put_u32(msg + 4, node->test_cost_bytes ? 0 : (uint32_t)(faults > (long)UINT32_MAX ? UINT32_MAX : faults));
    tsr_wire_put_f64(msg + 8, seconds * node->test_cost_scale);
    tsr_wire_put_f64(msg + 16, fault_seconds * node->test_cost_scale);
    tsr_error ignored = {0};
    /* never blocks the chain: without a credit the report is dropped (the
     * balancer keeps its last figure) and a broken connection shows at the
     * next receive */
    if (tsr_net_send(conn, TSR_NODE_MSG_COST, msg, sizeof msg, 0, &ignored) == TSR_OK) {
        tsr_node_sent_add(sent, sizeof msg);
        tsr_node_stats delta = {.bytes_out = sizeof msg};
        tsr_node_stats_add(node, &delta);
    }
    cost->bytes = 0;
    tsr_node_cost_start(cost); /* the report's own cost is not the frame's */
}

/* --- one client ---------------------------------------------------------- */

void tsr_node_sent_add(tsr_node_sent *sent, uint64_t size)
{
    sent->sizes[sent->next] = size;
    sent->next = (sent->next + 1) % TSR_NODE_SENT_RING;
}

/* Bytes of the newest `count` messages sent. */
static uint64_t sent_newest(const tsr_node_sent *sent, uint32_t count)
{
    uint64_t sum = 0;
    for (uint32_t k = 1; k <= count && k <= TSR_NODE_SENT_RING; k++)
        sum += sent->sizes[(sent->next + TSR_NODE_SENT_RING - k) % TSR_NODE_SENT_RING];
    return sum;
}

tsr_unpacker *tsr_node_unpacker(tsr_node *node, const tsr_dispatch *head, tsr_reply_fn reply, void *ctx, tsr_error *err)
{
    tsr_unpacker *u = tsr_unpacker_create(head, reply, ctx, err);
    if (u && tsr_unpacker_set_limits(u, &node->limits, err) != TSR_OK) {
        tsr_unpacker_destroy(u);
        return NULL;
    }
    return u;
}

int tsr_node_send_reply(tsr_node *node, tsr_net_conn *conn, tsr_node_sent *sent, uint8_t **buf, size_t *cap,
                        uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    size_t total = TSR_NODE_REPLY_HEADER + size;
    tsr_net_stats st;
    tsr_net_conn_stats(conn, &st);
    uint64_t pending = sent_newest(sent, st.messages_unreturned);
    uint64_t max = node->max_pending_reply_bytes;
    /* The credit window is the client's to grant (net.h), so it may let
     * far more replies be in flight than the ring has sizes of: past the
     * ring, the bytes pending could no longer be counted. */
    if (st.messages_unreturned >= TSR_NODE_SENT_RING)
        return tsr_error_set(err, TSR_EPROTO,
                             "the reply to request %u is over the reply budget max_pending_reply_bytes=%llu: "
                             "%u replies sent are not taken yet (at most %d may be)",
                             id, (unsigned long long)max, st.messages_unreturned, TSR_NODE_SENT_RING);
    if (total > max || pending > max - total)
        return tsr_error_set(err, TSR_EPROTO,
                             "the reply to request %u (%zu bytes) is over the reply budget "
                             "max_pending_reply_bytes=%llu: %llu bytes of replies sent are not taken yet",
                             id, total, (unsigned long long)max, (unsigned long long)pending);
    if (total > *cap) {
        uint8_t *r = realloc(*buf, total);
        if (!r)
            return tsr_error_set(err, TSR_ENOMEM, "node: out of memory for a %zu-byte reply", size);
        *buf = r;
        *cap = total;
    }
    tsr_wire_put_u32(*buf, id);
    tsr_wire_put_u32(*buf + 4, 0);
    if (size)
        memcpy(*buf + TSR_NODE_REPLY_HEADER, data, size);
    tsr_error cause = {0};
    if (tsr_net_send(conn, TSR_NODE_MSG_REPLY, *buf, total, TSR_NET_WAIT_FOREVER, &cause) != TSR_OK)
        return tsr_error_set(err, cause.code, "sending the reply to request %u failed: %s", id, cause.message);
    tsr_node_sent_add(sent, total);
    tsr_node_stats delta = {.bytes_out = total};
    tsr_node_stats_add(node, &delta);
    return TSR_OK;
}

static int send_reply(void *ctx, uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    node_session *s = ctx;
    int rc = tsr_node_send_reply(s->node, s->conn, &s->sent, &s->reply, &s->reply_cap, id, data, size, err);
    if (rc == TSR_ENOMEM)
        tsr_error_set(err, rc, "node: %s: out of memory for a %zu-byte reply", s->who, size);
    return rc;
}

/* Receives and runs buffers until the client ends. Returns TSR_OK on a
 * clean end, else the failure (in s->error). */
static int serve_client(node_session *s, tsr_unpacker *unpacker)
{
    for (;;) {
        tsr_net_msg m;
        tsr_error cause = {0};
        int got = tsr_net_recv(s->conn, &m, TSR_NET_WAIT_FOREVER, &cause);
        if (got == 0)
            return TSR_OK;
        if (got < 0)
            return tsr_error_set(&s->error, got, "%s", cause.message);
        int rc;
        if (m.kind == TSR_NODE_MSG_FINISH) {
            rc = tsr_net_send(s->conn, TSR_NODE_MSG_FINISH, "", 0, TSR_NET_WAIT_FOREVER, &cause);
            tsr_node_sent_add(&s->sent, 0);
        } else if (m.kind != TSR_NODE_MSG_BUFFER)
            rc = tsr_error_set(&cause, TSR_EPROTO, "unexpected message kind 0x%02x (%llu bytes)", m.kind,
                               (unsigned long long)m.len);
        else {
            uint64_t commands_before = unpacker->commands;
            double start = tsr_now_seconds();
            s->cost.bytes += m.len;
            rc = tsr_unpacker_run(unpacker, m.data, (size_t)m.len, &cause);
            tsr_node_stats delta = {.buffers = 1,
                                    .commands = unpacker->commands - commands_before,
                                    .bytes_in = m.len,
                                    .busy_seconds = tsr_now_seconds() - start};
            tsr_node_stats_add(s->node, &delta);
        }
        tsr_net_msg_release(&m);
        if (rc != TSR_OK) {
            tsr_error_set(&s->error, rc, "%s", cause.message);
            /* Tell the client why before closing; it may be gone already. */
            tsr_error ignored = {0};
            tsr_net_send(s->conn, TSR_NODE_MSG_ERROR, s->error.message, strlen(s->error.message), 1000, &ignored);
            return rc;
        }
    }
}

static void *session_main(void *arg)
{
    node_session *s = arg;
    tsr_error err = {0};
    /* The chain is created on this thread: its GL context is current here
     * and nowhere else. */
    tsr_chain *chain = tsr_node_create_chain(s->node, s->index, &err);
    tsr_unpacker *unpacker = NULL;
    if (chain) {
        s->head = *tsr_chain_head(chain);
        s->chain_swap = s->head.SwapBuffersTSR;
        tsr_set_SwapBuffersTSR(&s->head, count_swap, s);
        unpacker = tsr_node_unpacker(s->node, &s->head, send_reply, s, &err);
        tsr_node_cost_start(&s->cost);
    }
    if (!unpacker) {
        tsr_error_set(&s->error, err.code, "%s", err.message);
        tsr_error ignored = {0};
        tsr_net_send(s->conn, TSR_NODE_MSG_ERROR, s->error.message, strlen(s->error.message), 1000, &ignored);
    } else if (serve_client(s, unpacker) == TSR_OK) {
        tsr_log(TSR_LOG_INFO, "node: %s ended: %llu buffers, %llu commands", s->who,
                (unsigned long long)unpacker->buffers, (unsigned long long)unpacker->commands);
    }
    if (s->error.code)
        tsr_log(TSR_LOG_ERROR, "node: %s dropped: %s", s->who, s->error.message);
    tsr_node_client_ended(s->node, s->error.code != 0, s->conn, s->who, s->error.message);
    tsr_unpacker_destroy(unpacker);
    tsr_chain_destroy(chain);
    tsr_net_conn_close(s->conn);
    s->conn = NULL;
    free(s->reply);
    s->reply = NULL;
    return NULL;
}

/* --- the node ------------------------------------------------------------ */

/* Takes the chain (text, or else links: copied), refuses "{client}" in
 * shared mode, and builds and destroys client 0's chain once, so a bad SPU,
 * option or output directory fails now, not once per client. */
static int take_chain(tsr_node *node, const char *chain, const tsr_chain_link *links, size_t count, tsr_error *err)
{
    int text = chain && chain[0];
    if (!text && count == 0)
        return tsr_error_set(err, TSR_EINVAL, "node: no chain");
    int per_client = text && strstr(chain, "{client}");
    for (size_t i = 0; !text && i < count; i++)
        for (size_t k = 0; k < links[i].option_count; k++)
            per_client |= strstr(links[i].values[k], "{client}") != NULL;
    if (node->mode == TSR_NODE_SHARED && per_client)
        return tsr_error_set(err, TSR_EINVAL,
                             "node: chain: {client} needs independent mode (--independent): in shared mode "
                             "every client draws into the one chain");
    if (text) {
        if (!(node->chain_text = strdup(chain)))
            return tsr_error_set(err, TSR_ENOMEM, "node: out of memory");
    } else {
        if (!(node->links = copy_links(links, count)))
            return tsr_error_set(err, TSR_ENOMEM, "node: out of memory");
        node->link_count = count;
    }
    tsr_error chain_err = {0};
    tsr_chain *probe = tsr_node_create_chain(node, 0, &chain_err);
    if (!probe) {
        free(node->chain_text);
        free_links(node->links, node->link_count);
        node->chain_text = NULL;
        node->links = NULL;
        node->link_count = 0;
        return tsr_error_set(err, chain_err.code == TSR_ENOMEM ? TSR_ENOMEM : TSR_EINVAL, "node: chain: %s",
                             chain_err.message);
    }
    tsr_chain_destroy(probe);
    return TSR_OK;
}

int tsr_node_set_links(tsr_node *node, const tsr_chain_link *links, size_t count, tsr_error *err)
{
    if (node->chain_text || node->links)
        return tsr_error_set(err, TSR_ESTATE, "node: the chain is set already");
    if (node->ran)
        return tsr_error_set(err, TSR_ESTATE, "node: already ran");
    return take_chain(node, NULL, links, count, err);
}

tsr_node *tsr_node_create(const tsr_node_config *config, tsr_error *err)
{
    if (!config->listen || !config->listen[0])
        return tsr_error_set(err, TSR_EINVAL, "node: no listen address"), NULL;
    int has_chain = (config->chain && config->chain[0]) || config->link_count;
    if (!has_chain && !config->chain_later)
        return tsr_error_set(err, TSR_EINVAL, "node: no chain"), NULL;
    if (has_chain && config->chain_later)
        return tsr_error_set(err, TSR_EINVAL, "node: a chain and chain_later exclude each other"), NULL;
    if (config->clients < 1)
        return tsr_error_set(err, TSR_EINVAL, "node: clients must be at least 1"), NULL;
    if (config->mode != TSR_NODE_SHARED && config->mode != TSR_NODE_INDEPENDENT)
        return tsr_error_set(err, TSR_EINVAL, "node: unknown mode %d", (int)config->mode), NULL;
    tsr_node *node = calloc(1, sizeof *node);
    if (node)
        node->sessions = calloc(config->clients, sizeof *node->sessions);
    if (!node || !node->sessions) {
        tsr_error_set(err, TSR_ENOMEM, "node: out of memory");
        tsr_node_destroy(node);
        return NULL;
    }
    node->clients = config->clients;
    node->timeout_ms = config->timeout_ms;
    node->test_stall_ms = config->stall_first_frame_ms;
    if (node->test_stall_ms)
        tsr_log(TSR_LOG_WARN, "node: the first frame takes %u ms more (--stall-first-frame-ms, a test setting)",
                node->test_stall_ms);
    node->test_cost_scale = config->cost_scale > 0 ? config->cost_scale : 1.0;
    node->test_cost_bytes = config->cost_source == TSR_NODE_COST_FROM_BYTES;
    if (node->test_cost_scale != 1.0 || node->test_cost_bytes)
        tsr_log(TSR_LOG_WARN, "node: frame costs reported %s x %g (--cost, --cost-scale: a test setting)",
                node->test_cost_bytes ? "as 1 ns per byte received" : "as thread CPU time", node->test_cost_scale);
    node->mode = config->mode;
    if (config->limits)
        node->limits = *config->limits;
    else
        tsr_unpack_limits_defaults(&node->limits);
    node->max_pending_reply_bytes =
        config->max_pending_reply_bytes ? config->max_pending_reply_bytes : TSR_NODE_DEFAULT_MAX_PENDING_REPLY_BYTES;
    pthread_mutex_init(&node->stats_lock, NULL);
    node->stats_lock_ready = 1;
    if (has_chain && take_chain(node, config->chain, config->links, config->link_count, err) != TSR_OK) {
        tsr_node_destroy(node);
        return NULL;
    }

    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.node_name = config->name && config->name[0] ? config->name : "node";
    cfg.token = config->token;
    cfg.idle_timeout_ms = config->idle_timeout_ms;
    /* A reply must fit in one message the node may send (net.h: never
     * more than its own max_message_bytes): larger requests are refused
     * before anything is allocated for them. */
    uint64_t reply_room = cfg.max_message_bytes - TSR_NODE_REPLY_HEADER - 4096;
    if (!node->limits.max_output || node->limits.max_output > reply_room)
        node->limits.max_output = reply_room;
    node->net = tsr_net_create(&cfg, err);
    if (node->net)
        node->listener = tsr_net_listen(node->net, config->listen, err);
    if (!node->listener) {
        tsr_node_destroy(node);
        return NULL;
    }
    return node;
}

const char *tsr_node_address(const tsr_node *node) { return tsr_net_listener_address(node->listener); }

tsr_net_conn *tsr_node_accept(tsr_node *node, int timeout_ms, tsr_error *failure)
{
    tsr_error accept_err = {0};
    tsr_net_conn *conn = tsr_net_accept(node->listener, timeout_ms, &accept_err);
    if (conn)
        return conn;
    tsr_error last = {0};
    unsigned refused = tsr_net_listener_refusals(node->listener, &last);
    if (accept_err.code == TSR_ETIMEDOUT)
        tsr_error_set(failure, TSR_ETIMEDOUT, "node: %u of %u clients connected to %s within %u ms%s%s", node->accepted,
                      node->clients, tsr_node_address(node), node->timeout_ms, refused ? "; refused one: " : "",
                      refused ? last.message : "");
    else
        tsr_error_set(failure, accept_err.code, "node: accepting on %s: %s", tsr_node_address(node),
                      accept_err.message);
    return NULL;
}

int tsr_node_run(tsr_node *node, tsr_error *err)
{
    if (node->ran)
        return tsr_error_set(err, TSR_ESTATE, "node: already ran");
    if (!node->chain_text && !node->links)
        return tsr_error_set(err, TSR_ESTATE, "node: no chain yet (chain_later: tsr_node_set_links first)");
    node->ran = 1;
    if (node->mode == TSR_NODE_SHARED)
        return tsr_node_run_shared(node, err);
    tsr_error failure = {0};
    int timeout = node->timeout_ms ? (int)node->timeout_ms : TSR_NET_WAIT_FOREVER;
    while (node->accepted < node->clients) {
        tsr_net_conn *conn = tsr_node_accept(node, timeout, &failure);
        if (!conn)
            break;
        node_session *s = &node->sessions[node->accepted];
        s->node = node;
        s->index = node->accepted++;
        s->conn = conn;
        snprintf(s->who, sizeof s->who, "client %u '%s' at %s", s->index, tsr_net_conn_peer_name(conn),
                 tsr_net_conn_address(conn));
        tsr_log(TSR_LOG_INFO, "node: %s connected", s->who);
        tsr_node_stats connected = {.clients_connected = 1};
        tsr_node_stats_add(node, &connected);
        int rc = pthread_create(&s->thread, NULL, session_main, s);
        if (rc) {
            tsr_error_set(&failure, TSR_EIO, "node: cannot start a thread for %s: %s", s->who, strerror(rc));
            tsr_net_conn_close(conn);
            s->conn = NULL;
            break;
        }
        s->started = 1;
    }
    unsigned failed = 0;
    for (unsigned i = 0; i < node->accepted; i++) {
        node_session *s = &node->sessions[i];
        if (s->started)
            pthread_join(s->thread, NULL);
        s->started = 0;
        if (s->error.code) {
            failed++;
            if (!failure.code)
                tsr_error_set(&failure, s->error.code, "node: %s dropped: %s", s->who, s->error.message);
        }
    }
    if (!failure.code)
        return TSR_OK;
    if (failed > 1)
        return tsr_error_set(err, failure.code, "%s (and %u more clients failed)", failure.message, failed - 1);
    return tsr_error_set(err, failure.code, "%s", failure.message);
}

void tsr_node_destroy(tsr_node *node)
{
    if (!node)
        return;
    /* tsr_node_run joins every session; a node destroyed without running
     * has none. */
    if (node->listener)
        tsr_net_listener_close(node->listener);
    tsr_net_destroy(node->net);
    free(node->sessions);
    free(node->chain_text);
    free_links(node->links, node->link_count);
    if (node->stats_lock_ready)
        pthread_mutex_destroy(&node->stats_lock);
    free(node);
}
