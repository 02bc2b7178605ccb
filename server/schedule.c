/* server/schedule.c — shared mode of the server node (server/node.h): one
 * thread runs one chain for every client, each client in its own GL
 * context of that chain, scheduled round-robin one buffer per turn, with
 * barriers and semaphores across clients and deadlock detection.
 * Owns: the chain, every client's connection, unpacker and held message,
 * the barriers and semaphores. Never blocks on one connection while
 * another could run, never waits for a client that nobody can release. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tessera/dev/util.h"
#include "node_internal.h"
#include "tessera/dev/protocol.h"
#include "tessera/log.h"
#include "tessera/dev/unpack.h"
#include "tessera/dev/wire.h"

/* How long the scheduler sleeps in one wait for input when nothing can
 * run (it then also looks for new connections). */
#define SCHED_POLL_MS 20
/* A client that says goodbye while others wait at a barrier counting it
 * has usually ended because of a failure of its own, which its owner
 * reports: the node waits this long before failing on the barrier, so
 * the report naming the cause comes first (a parallel program whose
 * ranks end one by one at the last frame is not a failure either way). */
#define SCHED_GOODBYE_GRACE_MS 1000

typedef enum client_state {
    CLIENT_READY,   /* runs when it has a buffer */
    CLIENT_BLOCKED, /* waits at a barrier or on a semaphore */
    CLIENT_ENDED,   /* said goodbye */
    CLIENT_FAILED,  /* dropped */
} client_state;

typedef enum sync_kind { SYNC_BARRIER, SYNC_SEMAPHORE } sync_kind;

typedef struct sync_object {
    sync_kind kind;
    GLuint name;
    GLuint count;   /* barrier: clients it waits for; semaphore: initial value */
    GLuint arrived; /* barrier: clients waiting now */
    GLuint value;   /* semaphore */
} sync_object;

typedef struct sched sched;

#define SCHED_CLIENT_CONTEXTS 8         /* a client's contexts beyond its first */
#define SCHED_SUB_CONTEXT_BASE 0x100000 /* their chain ids: above every client's own */

typedef struct sched_client {
    sched *sched;
    unsigned index;
    GLint context; /* index + 1 */
    /* A client with several contexts of its own (a program whose threads
     * draw into one share group, faker/core.c): its first context id is
     * `context`; each other id it creates gets a chain context of its
     * own, so their state (bindings, an open display list) stays apart. */
    GLint first_own; /* the client's first context id; 0: none seen */
    GLint active;    /* the chain context its commands go to */
    struct {
        GLint own, chain;
    } subs[SCHED_CLIENT_CONTEXTS];
    int nsubs;
    char who[TSR_NET_NAME_MAX + TSR_NET_ADDRESS_MAX + 32];
    tsr_net_conn *conn;
    tsr_unpacker *unpacker;
    client_state state;
    tsr_net_msg msg; /* received, not finished */
    int has_msg;
    int started;         /* msg is a buffer paused mid-way */
    sync_kind wait_kind; /* while BLOCKED */
    GLuint wait_name;
    uint64_t wait_ticket; /* FIFO order of semaphore waiters */
    tsr_error error;      /* why it was dropped */
    uint8_t *reply;
    size_t reply_cap;
    tsr_node_sent sent;
} sched_client;

struct sched {
    tsr_node *node;
    tsr_chain *chain;
    tsr_dispatch head;        /* the chain's head with the node's commands */
    const tsr_dispatch *down; /* the chain's own table */
    sched_client *clients;    /* node->clients entries, `accepted` used */
    tsr_net_conn **conns;     /* scratch for waiting on every ready client */
    sched_client **owners;
    unsigned accepted;
    sched_client *current; /* whose commands run now */
    GLint current_context; /* context current in the chain; 0 = none yet */
    GLint next_sub;        /* the next chain id of a client's further context */
    int swapper;           /* client whose swaps end frames; -1 = none yet */
    sync_object *syncs;
    size_t nsyncs, syncs_cap;
    uint64_t tickets;
    tsr_error failure;  /* first client failure */
    tsr_node_cost cost; /* the chain's (all clients') since the swapper's last swap */
    double goodbye;     /* when the last client said goodbye (tsr_now_seconds), or 0 */
};

/* --- client errors inside command handlers -------------------------------- */

/* Marks the running client's stream as bad: the unpacker stops after this
 * command and the scheduler drops the client. */
__attribute__((format(printf, 2, 3))) static void client_error(sched *s, const char *fmt, ...)
{
    sched_client *c = s->current;
    if (c->error.code)
        return;
    va_list ap;
    va_start(ap, fmt);
    char text[sizeof c->error.message];
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    tsr_error_set(&c->error, TSR_EPROTO, "%s", text);
    tsr_unpacker_yield(c->unpacker);
}

static sync_object *find_sync(sched *s, sync_kind kind, GLuint name)
{
    for (size_t i = 0; i < s->nsyncs; i++)
        if (s->syncs[i].kind == kind && s->syncs[i].name == name)
            return &s->syncs[i];
    return NULL;
}

static const char *kind_name(sync_kind kind) { return kind == SYNC_BARRIER ? "barrier" : "semaphore"; }

static unsigned count_waiters(const sched *s, sync_kind kind, GLuint name)
{
    unsigned n = 0;
    for (unsigned i = 0; i < s->accepted; i++)
        n +=
            s->clients[i].state == CLIENT_BLOCKED && s->clients[i].wait_kind == kind && s->clients[i].wait_name == name;
    return n;
}

static void create_sync(sched *s, sync_kind kind, GLuint name, GLuint count, const char *command)
{
    sync_object *o = find_sync(s, kind, name);
    if (o) {
        /* Every client of a parallel program may create it; the first wins. */
        if (o->count != count)
            client_error(s, "%s(%u, %u): %s %u exists with count %u", command, name, count, kind_name(kind), name,
                         o->count);
        return;
    }
    if (s->nsyncs == s->syncs_cap) {
        size_t cap = s->syncs_cap ? 2 * s->syncs_cap : 8;
        sync_object *grown = realloc(s->syncs, cap * sizeof *grown);
        if (!grown) {
            client_error(s, "%s(%u, %u): out of memory", command, name, count);
            return;
        }
        s->syncs = grown;
        s->syncs_cap = cap;
    }
    s->syncs[s->nsyncs++] = (sync_object){.kind = kind, .name = name, .count = count, .value = count};
}

static void destroy_sync(sched *s, sync_kind kind, GLuint name, const char *command)
{
    sync_object *o = find_sync(s, kind, name);
    if (!o)
        return; /* every client may destroy it */
    unsigned waiting = count_waiters(s, kind, name);
    if (waiting) {
        client_error(s, "%s(%u): %u client(s) wait on it", command, name, waiting);
        return;
    }
    *o = s->syncs[--s->nsyncs];
}

static void block_current(sched *s, sync_kind kind, GLuint name)
{
    sched_client *c = s->current;
    c->state = CLIENT_BLOCKED;
    c->wait_kind = kind;
    c->wait_name = name;
    c->wait_ticket = s->tickets++;
    tsr_unpacker_yield(c->unpacker);
    /* Tests wait for this line rather than guess when a client is blocked. */
    tsr_log(TSR_LOG_DEBUG, "node: %s waits %s %u", c->who, kind == SYNC_BARRIER ? "at barrier" : "on semaphore", name);
    tsr_node_stats delta = {.blocks = 1};
    tsr_node_stats_add(s->node, &delta);
}

/* --- the node's commands (self = sched) ------------------------------------ */

static void node_BarrierCreateTSR(void *self, GLuint name, GLuint count)
{
    sched *s = self;
    create_sync(s, SYNC_BARRIER, name, count ? count : s->node->clients, "BarrierCreateTSR");
}

static void node_BarrierDestroyTSR(void *self, GLuint name)
{
    destroy_sync(self, SYNC_BARRIER, name, "BarrierDestroyTSR");
}

static void node_BarrierExecTSR(void *self, GLuint name)
{
    sched *s = self;
    sync_object *b = find_sync(s, SYNC_BARRIER, name);
    if (!b) {
        client_error(s, "BarrierExecTSR(%u): no such barrier", name);
        return;
    }
    if (b->arrived + 1 < b->count) {
        b->arrived++;
        block_current(s, SYNC_BARRIER, name);
        return;
    }
    /* The last one: everybody waiting goes on, and so does this client. */
    b->arrived = 0;
    for (unsigned i = 0; i < s->accepted; i++) {
        sched_client *w = &s->clients[i];
        if (w->state == CLIENT_BLOCKED && w->wait_kind == SYNC_BARRIER && w->wait_name == name)
            w->state = CLIENT_READY;
    }
}

static void node_SemaphoreCreateTSR(void *self, GLuint name, GLuint count)
{
    create_sync(self, SYNC_SEMAPHORE, name, count, "SemaphoreCreateTSR");
}

static void node_SemaphoreDestroyTSR(void *self, GLuint name)
{
    destroy_sync(self, SYNC_SEMAPHORE, name, "SemaphoreDestroyTSR");
}

static void node_SemaphorePTSR(void *self, GLuint name)
{
    sched *s = self;
    sync_object *o = find_sync(s, SYNC_SEMAPHORE, name);
    if (!o)
        client_error(s, "SemaphorePTSR(%u): no such semaphore", name);
    else if (o->value > 0)
        o->value--;
    else
        block_current(s, SYNC_SEMAPHORE, name);
}

static void node_SemaphoreVTSR(void *self, GLuint name)
{
    sched *s = self;
    sync_object *o = find_sync(s, SYNC_SEMAPHORE, name);
    if (!o) {
        client_error(s, "SemaphoreVTSR(%u): no such semaphore", name);
        return;
    }
    sched_client *first = NULL;
    for (unsigned i = 0; i < s->accepted; i++) {
        sched_client *w = &s->clients[i];
        if (w->state == CLIENT_BLOCKED && w->wait_kind == SYNC_SEMAPHORE && w->wait_name == name &&
            (!first || w->wait_ticket < first->wait_ticket))
            first = w;
    }
    if (first)
        first->state = CLIENT_READY; /* its P completes: the value stays 0 */
    else
        o->value++;
}

static void node_SwapBuffersTSR(void *self, GLint window, GLbitfield flags)
{
    sched *s = self;
    if (s->swapper < 0) {
        s->swapper = (int)s->current->index;
        tsr_log(TSR_LOG_INFO, "node: %s swaps: its SwapBuffers end frames", s->current->who);
    }
    tsr_node_stats delta = {0};
    if (s->swapper == (int)s->current->index) {
        tsr_node_test_stall(s->node);
        tsr_call_SwapBuffersTSR(s->down, window, flags & ~TSR_NODE_SWAP_REPORT_COST);
        if (flags & TSR_NODE_SWAP_REPORT_COST)
            tsr_node_report_cost(s->node, s->current->conn, &s->current->sent, &s->cost);
        delta.frames = 1;
    } else {
        delta.swaps_ignored = 1;
    }
    tsr_node_stats_add(s->node, &delta);
}

/* Contexts are the node's to manage: a client's first context is the
 * node's context of that client; further ones (several contexts in one
 * stream) get chain contexts of their own; windows are the node's. */
static int sub_index(const sched_client *c, GLint own)
{
    for (int i = 0; i < c->nsubs; i++)
        if (c->subs[i].own == own)
            return i;
    return -1;
}

static void node_ContextCreateTSR(void *self, GLint context)
{
    sched *s = self;
    sched_client *c = s->current;
    if (!c->first_own) {
        c->first_own = context;
        return;
    }
    if (context == c->first_own || sub_index(c, context) >= 0)
        return;
    if (c->nsubs == SCHED_CLIENT_CONTEXTS) {
        tsr_log(TSR_LOG_ERROR,
                "node: %s: ContextCreateTSR(%d): more than %d contexts of one client; its commands "
                "go to the client's first context",
                c->who, (int)context, SCHED_CLIENT_CONTEXTS + 1);
        return;
    }
    GLint id = s->next_sub++;
    c->subs[c->nsubs].own = context;
    c->subs[c->nsubs].chain = id;
    c->nsubs++;
    tsr_call_ContextCreateTSR(s->down, id);
}

static void node_MakeCurrentTSR(void *self, GLint window, GLint context)
{
    (void)window;
    sched *s = self;
    sched_client *c = s->current;
    int i = sub_index(c, context);
    c->active = i >= 0 ? c->subs[i].chain : c->context;
    if (s->current_context != c->active) {
        tsr_call_MakeCurrentTSR(s->down, 0, c->active);
        s->current_context = c->active;
    }
}

static void sub_destroy(sched *s, sched_client *c, int i)
{
    GLint id = c->subs[i].chain;
    if (c->active == id)
        c->active = c->context;
    if (s->current_context == id)
        s->current_context = 0;
    tsr_call_ContextDestroyTSR(s->down, id);
    c->subs[i] = c->subs[--c->nsubs];
}

static void node_ContextDestroyTSR(void *self, GLint context)
{
    sched *s = self;
    sched_client *c = s->current;
    int i = sub_index(c, context);
    if (i >= 0)
        sub_destroy(s, c, i);
}

static int client_reply(void *ctx, uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    sched_client *c = ctx;
    return tsr_node_send_reply(c->sched->node, c->conn, &c->sent, &c->reply, &c->reply_cap, id, data, size, err);
}

/* --- clients ----------------------------------------------------------------- */

static void make_current(sched *s, sched_client *c)
{
    s->current = c;
    if (s->current_context != c->active) {
        tsr_call_MakeCurrentTSR(s->down, 0, c->active);
        s->current_context = c->active;
    }
}

static void release_msg(sched_client *c)
{
    if (c->has_msg)
        tsr_net_msg_release(&c->msg);
    c->has_msg = 0;
    c->started = 0;
}

/* Ends a client: its context goes, its connection closes. */
static void retire(sched *s, sched_client *c, client_state state)
{
    tsr_node_client_ended(s->node, state == CLIENT_FAILED, c->conn, c->who, c->error.message);
    release_msg(c);
    c->state = state;
    while (c->nsubs)
        sub_destroy(s, c, c->nsubs - 1);
    if (s->current_context == c->context) {
        s->current_context = 0;
    }
    tsr_call_ContextDestroyTSR(s->down, c->context);
    tsr_unpacker_destroy(c->unpacker);
    c->unpacker = NULL;
    tsr_net_conn_close(c->conn);
    c->conn = NULL;
    free(c->reply);
    c->reply = NULL;
    if (state == CLIENT_ENDED)
        s->goodbye = tsr_now_seconds();
}

static void drop(sched *s, sched_client *c)
{
    tsr_log(TSR_LOG_ERROR, "node: %s dropped: %s", c->who, c->error.message);
    tsr_error ignored = {0};
    tsr_net_send(c->conn, TSR_NODE_MSG_ERROR, c->error.message, strlen(c->error.message), 1000, &ignored);
    if (!s->failure.code)
        tsr_error_set(&s->failure, c->error.code, "node: %s dropped: %s", c->who, c->error.message);
    retire(s, c, CLIENT_FAILED);
}

static int add_client(sched *s, tsr_net_conn *conn)
{
    sched_client *c = &s->clients[s->accepted];
    memset(c, 0, sizeof *c);
    c->sched = s;
    c->index = s->accepted++;
    c->context = (GLint)c->index + 1;
    c->active = c->context;
    c->conn = conn;
    c->state = CLIENT_READY;
    snprintf(c->who, sizeof c->who, "client %u '%s' at %s", c->index, tsr_net_conn_peer_name(conn),
             tsr_net_conn_address(conn));
    tsr_log(TSR_LOG_INFO, "node: %s connected", c->who);
    tsr_node_stats connected = {.clients_connected = 1};
    tsr_node_stats_add(s->node, &connected);
    tsr_call_ContextCreateTSR(s->down, c->context);
    tsr_error err = {0};
    c->unpacker = tsr_node_unpacker(s->node, &s->head, client_reply, c, &err);
    if (!c->unpacker) {
        tsr_error_set(&c->error, err.code, "%s", err.message);
        drop(s, c);
        return err.code;
    }
    return TSR_OK;
}

/* Takes the client's next message into its hand without waiting. Returns
 * 1 when it holds one, 0 when none is there yet; a client that ended or
 * failed is retired. */
static int take_message(sched *s, sched_client *c, int got, tsr_error *cause)
{
    if (got == 1) {
        c->has_msg = 1;
        c->started = 0;
        return 1;
    }
    if (got == TSR_ETIMEDOUT)
        return 0;
    if (got == 0) {
        tsr_log(TSR_LOG_INFO, "node: %s ended: %llu buffers, %llu commands", c->who,
                (unsigned long long)c->unpacker->buffers, (unsigned long long)c->unpacker->commands);
        retire(s, c, CLIENT_ENDED);
    } else {
        tsr_error_set(&c->error, got, "%s", cause->message);
        drop(s, c);
    }
    return 0;
}

static int poll_client(sched *s, sched_client *c)
{
    if (c->state != CLIENT_READY)
        return 0;
    if (c->has_msg)
        return 1;
    tsr_error cause = {0};
    return take_message(s, c, tsr_net_recv(c->conn, &c->msg, 0, &cause), &cause);
}

/* Runs the message in the client's hand until it is finished or the
 * client blocks. */
static void run_turn(sched *s, sched_client *c)
{
    tsr_error cause = {0};
    if (c->msg.kind == TSR_NODE_MSG_FINISH) {
        /* Every buffer before it ran: confirm. */
        int rc = tsr_net_send(c->conn, TSR_NODE_MSG_FINISH, "", 0, TSR_NET_WAIT_FOREVER, &cause);
        tsr_node_sent_add(&c->sent, 0);
        release_msg(c);
        if (rc != TSR_OK) {
            tsr_error_set(&c->error, rc, "%s", cause.message);
            drop(s, c);
        }
        return;
    }
    if (c->msg.kind != TSR_NODE_MSG_BUFFER) {
        tsr_error_set(&c->error, TSR_EPROTO, "unexpected message kind 0x%02x (%llu bytes)", c->msg.kind,
                      (unsigned long long)c->msg.len);
        drop(s, c);
        return;
    }
    make_current(s, c);
    uint64_t commands_before = c->unpacker->commands;
    int first = !c->started;
    double start = tsr_now_seconds();
    int rc = first ? tsr_unpacker_run(c->unpacker, c->msg.data, (size_t)c->msg.len, &cause)
                   : tsr_unpacker_resume(c->unpacker, &cause);
    c->started = 1;
    if (first)
        s->cost.bytes += c->msg.len;
    tsr_node_stats delta = {.buffers = first,
                            .commands = c->unpacker->commands - commands_before,
                            .bytes_in = first ? c->msg.len : 0,
                            .busy_seconds = tsr_now_seconds() - start};
    tsr_node_stats_add(s->node, &delta);
    if (c->error.code) { /* a parallel-API command was wrong */
        drop(s, c);
        return;
    }
    if (rc == TSR_UNPACK_YIELDED)
        return; /* blocked: the buffer stays in hand, paused */
    if (rc != TSR_OK) {
        tsr_error_set(&c->error, rc, "%s", cause.message);
        drop(s, c);
        return;
    }
    release_msg(c);
}

/* --- deadlock ------------------------------------------------------------------ */

static void append(char *buf, size_t size, size_t *len, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static void append(char *buf, size_t size, size_t *len, const char *fmt, ...)
{
    if (*len >= size - 1)
        return;
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(buf + *len, size - *len, fmt, ap);
    va_end(ap);
    if (n > 0)
        *len = *len + (size_t)n < size ? *len + (size_t)n : size - 1;
}

/* Every live client is blocked and nobody else can come: names what each
 * waits for, and the clients that are gone. */
static void report_deadlock(sched *s, tsr_error *err)
{
    char text[sizeof err->message];
    size_t len = 0;
    append(text, sizeof text, &len, "node: deadlock, every client is blocked:");
    for (size_t i = 0; i < s->nsyncs; i++) {
        const sync_object *o = &s->syncs[i];
        unsigned waiting = count_waiters(s, o->kind, o->name);
        if (!waiting)
            continue;
        if (o->kind == SYNC_BARRIER)
            append(text, sizeof text, &len, " barrier %u (count %u, %u arrived) holds", o->name, o->count, o->arrived);
        else
            append(text, sizeof text, &len, " semaphore %u (value %u) holds", o->name, o->value);
        const char *sep = " ";
        for (unsigned k = 0; k < s->accepted; k++) {
            const sched_client *c = &s->clients[k];
            if (c->state == CLIENT_BLOCKED && c->wait_kind == o->kind && c->wait_name == o->name) {
                append(text, sizeof text, &len, "%sclient %u '%s'", sep, c->index, tsr_net_conn_peer_name(c->conn));
                sep = ", ";
            }
        }
        append(text, sizeof text, &len, ";");
    }
    /* Clients that are gone can never arrive at a barrier counting them. */
    const char *sep = " already ended, so barriers counting them cannot be reached:";
    for (unsigned k = 0; k < s->accepted; k++) {
        const sched_client *c = &s->clients[k];
        if (c->state == CLIENT_ENDED || c->state == CLIENT_FAILED) {
            append(text, sizeof text, &len, "%s %s (%s)", sep, c->who,
                   c->state == CLIENT_ENDED ? "disconnected" : "dropped");
            sep = ",";
        }
    }
    if (len && text[len - 1] == ';')
        text[--len] = '\0';
    tsr_error_set(err, TSR_ESTATE, "%s", text);
}

/* A barrier with waiters that counts more clients than are left (live or
 * still to connect) can never release them: fails with a line naming it,
 * its waiters and the clients that left. Returns 0 when there is none. */
static int check_unreachable(sched *s, unsigned live, tsr_error *err)
{
    unsigned left = live + (s->node->clients - s->accepted);
    for (size_t i = 0; i < s->nsyncs; i++) {
        const sync_object *o = &s->syncs[i];
        if (o->kind != SYNC_BARRIER || !o->arrived || o->count <= left)
            continue;
        /* A waiter's stream is not read, so its end may be gone unnoticed:
         * a cut that ended others (peers of one compositing group) often
         * reaches this node through them first. Each gone end gets its
         * own line, naming the cause, before the node gives up. */
        for (unsigned k = 0; k < s->accepted; k++) {
            sched_client *c = &s->clients[k];
            if (c->state == CLIENT_BLOCKED && tsr_net_conn_failure(c->conn, &c->error)) {
                drop(s, c);
                left--;
            }
        }
        char text[sizeof err->message];
        size_t len = 0;
        /* A client dropped for silence (a stopped process) is the cause:
         * the line names it first, as its owner would have reported it. */
        char silent[sizeof err->message];
        if (tsr_node_silent_failure(s->node, silent, sizeof silent))
            append(text, sizeof text, &len, "%s; so ", silent);
        else
            append(text, sizeof text, &len, "node: ");
        append(text, sizeof text, &len, "barrier %u can never be reached: it counts %u clients, %u left", o->name,
               o->count, left);
        const char *sep = "; waiting:";
        for (unsigned k = 0; k < s->accepted; k++) {
            const sched_client *c = &s->clients[k];
            if (c->state == CLIENT_BLOCKED && c->wait_kind == SYNC_BARRIER && c->wait_name == o->name) {
                append(text, sizeof text, &len, "%s client %u '%s'", sep, c->index, tsr_net_conn_peer_name(c->conn));
                sep = ",";
            }
        }
        sep = "; gone:";
        for (unsigned k = 0; k < s->accepted; k++) {
            const sched_client *c = &s->clients[k];
            if (c->state == CLIENT_ENDED || c->state == CLIENT_FAILED) {
                append(text, sizeof text, &len, "%s %s (%s)", sep, c->who,
                       c->state == CLIENT_ENDED ? "disconnected" : "dropped");
                sep = ",";
            }
        }
        return tsr_error_set(err, TSR_ESTATE, "%s", text);
    }
    return 0;
}

/* --- the loop ---------------------------------------------------------------- */

static int scheduler_loop(sched *s, tsr_error *err)
{
    tsr_node *node = s->node;
    unsigned next = 0; /* round-robin position */
    double last_accept = tsr_now_seconds();
    for (;;) {
        /* New clients, without waiting. */
        while (s->accepted < node->clients) {
            tsr_error ignored = {0};
            tsr_net_conn *conn = tsr_net_accept(node->listener, 0, &ignored);
            if (!conn)
                break;
            add_client(s, conn);
            last_accept = tsr_now_seconds();
        }
        /* One turn: the next client (round-robin) with work. */
        int ran = 0;
        for (unsigned k = 0; k < s->accepted && !ran; k++) {
            sched_client *c = &s->clients[(next + k) % s->accepted];
            if (poll_client(s, c)) {
                run_turn(s, c);
                next = (c->index + 1) % s->accepted;
                ran = 1;
            }
        }
        if (ran)
            continue;

        unsigned live = 0, ready = 0, blocked = 0;
        for (unsigned i = 0; i < s->accepted; i++) {
            live += s->clients[i].state == CLIENT_READY || s->clients[i].state == CLIENT_BLOCKED;
            ready += s->clients[i].state == CLIENT_READY;
            blocked += s->clients[i].state == CLIENT_BLOCKED;
        }
        int all_came = s->accepted == node->clients;
        if (all_came && live == 0)
            return s->failure.code ? tsr_error_set(err, s->failure.code, "%s", s->failure.message) : TSR_OK;
        int settling = s->goodbye > 0 && (tsr_now_seconds() - s->goodbye) * 1000.0 < SCHED_GOODBYE_GRACE_MS;
        if (blocked && !settling && check_unreachable(s, live, err) != 0)
            return err->code;
        if (all_came && ready == 0 && blocked > 0 && !settling) {
            report_deadlock(s, err);
            return err->code;
        }
        if (!all_came && node->timeout_ms && (tsr_now_seconds() - last_accept) * 1000.0 > node->timeout_ms) {
            tsr_error last = {0};
            unsigned refused = tsr_net_listener_refusals(node->listener, &last);
            return tsr_error_set(err, TSR_ETIMEDOUT, "node: %u of %u clients connected to %s within %u ms%s%s",
                                 s->accepted, node->clients, tsr_node_address(node), node->timeout_ms,
                                 refused ? "; refused one: " : "", refused ? last.message : "");
        }
        /* Nothing to run: wait a little for input from any ready client
         * (or, with none, for a connection). */
        if (ready) {
            size_t n = 0;
            for (unsigned i = 0; i < s->accepted; i++)
                if (s->clients[i].state == CLIENT_READY) {
                    s->owners[n] = &s->clients[i];
                    s->conns[n++] = s->clients[i].conn;
                }
            size_t which = n;
            tsr_net_msg m;
            tsr_error cause = {0};
            int got = tsr_net_recv_any(s->conns, n, &which, &m, SCHED_POLL_MS, &cause);
            if (got != TSR_ETIMEDOUT && which < n) {
                s->owners[which]->msg = m;
                take_message(s, s->owners[which], got, &cause);
            }
        } else {
            tsr_error ignored = {0};
            tsr_net_conn *conn = tsr_net_accept(node->listener, SCHED_POLL_MS, &ignored);
            if (conn) {
                add_client(s, conn);
                last_accept = tsr_now_seconds();
            }
        }
    }
}

int tsr_node_run_shared(tsr_node *node, tsr_error *err)
{
    sched s = {.node = node, .swapper = -1, .next_sub = SCHED_SUB_CONTEXT_BASE};
    tsr_node_cost_start(&s.cost);
    s.clients = calloc(node->clients, sizeof *s.clients);
    s.conns = calloc(node->clients, sizeof *s.conns);
    s.owners = calloc(node->clients, sizeof *s.owners);
    if (!s.clients || !s.conns || !s.owners) {
        free(s.clients), free(s.conns), free(s.owners);
        return tsr_error_set(err, TSR_ENOMEM, "node: out of memory");
    }
    /* Built here: its contexts are made current on this thread only. */
    tsr_error chain_err = {0};
    s.chain = tsr_node_create_chain(node, 0, &chain_err);
    if (!s.chain) {
        free(s.clients), free(s.conns), free(s.owners);
        return tsr_error_set(err, chain_err.code, "node: chain: %s", chain_err.message);
    }
    s.down = tsr_chain_head(s.chain);
    s.head = *s.down;
    tsr_set_BarrierCreateTSR(&s.head, node_BarrierCreateTSR, &s);
    tsr_set_BarrierDestroyTSR(&s.head, node_BarrierDestroyTSR, &s);
    tsr_set_BarrierExecTSR(&s.head, node_BarrierExecTSR, &s);
    tsr_set_SemaphoreCreateTSR(&s.head, node_SemaphoreCreateTSR, &s);
    tsr_set_SemaphoreDestroyTSR(&s.head, node_SemaphoreDestroyTSR, &s);
    tsr_set_SemaphorePTSR(&s.head, node_SemaphorePTSR, &s);
    tsr_set_SemaphoreVTSR(&s.head, node_SemaphoreVTSR, &s);
    tsr_set_SwapBuffersTSR(&s.head, node_SwapBuffersTSR, &s);
    tsr_set_ContextCreateTSR(&s.head, node_ContextCreateTSR, &s);
    tsr_set_ContextDestroyTSR(&s.head, node_ContextDestroyTSR, &s);
    tsr_set_MakeCurrentTSR(&s.head, node_MakeCurrentTSR, &s);

    int rc = scheduler_loop(&s, err);
    tsr_node_stats totals;
    tsr_node_get_stats(node, &totals);
    tsr_log(TSR_LOG_INFO, "node: %llu frames; %llu swaps of other clients ignored; %llu blocks",
            (unsigned long long)totals.frames, (unsigned long long)totals.swaps_ignored,
            (unsigned long long)totals.blocks);
    if (rc != TSR_OK) {
        /* Tell every client still there why, then let them go. */
        for (unsigned i = 0; i < s.accepted; i++) {
            sched_client *c = &s.clients[i];
            if (c->state != CLIENT_READY && c->state != CLIENT_BLOCKED)
                continue;
            tsr_error ignored = {0};
            tsr_net_send(c->conn, TSR_NODE_MSG_ERROR, err->message, strlen(err->message), 1000, &ignored);
            retire(&s, c, CLIENT_FAILED);
        }
    }
    tsr_chain_destroy(s.chain);
    free(s.syncs);
    free(s.clients), free(s.conns), free(s.owners);
    return rc;
}
