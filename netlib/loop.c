/* netlib/loop.c — the tsr_net object: one libuv loop on its own I/O thread.
 * Owns: creating and joining the thread, the wake-up (uv_async), the queue
 * of operations application threads hand over, and the dirty-connection
 * list the I/O thread services. Never: runs application code on the I/O
 * thread, or lets a libuv handle be touched from another thread. */
#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <time.h>

#include "net_internal.h"
#include "tessera/log.h"

void tsr_net_config_defaults(tsr_net_config *config)
{
    memset(config, 0, sizeof *config);
    config->node_name = "node";
    config->credits = 8;
    config->max_message_bytes = 64u << 20;
    config->connect_timeout_ms = 5000;
    config->handshake_timeout_ms = 5000;
    config->idle_timeout_ms = 0;
    config->close_timeout_ms = 5000;
}

uint64_t net_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000u + (uint64_t)ts.tv_nsec / 1000000u;
}

int net_deadline(struct timespec *ts, int timeout_ms)
{
    if (timeout_ms < 0)
        return 0;
    clock_gettime(CLOCK_MONOTONIC, ts);
    ts->tv_sec += timeout_ms / 1000;
    ts->tv_nsec += (long)(timeout_ms % 1000) * 1000000L;
    if (ts->tv_nsec >= 1000000000L) {
        ts->tv_sec++;
        ts->tv_nsec -= 1000000000L;
    }
    return 1;
}

void net_wake(tsr_net *net) { uv_async_send(&net->wakeup); }

void net_mark_dirty(tsr_net_conn *conn)
{
    if (conn->transport == TSR_NET_INPROC || !conn->io_ref)
        return;
    if (!conn->dirty) {
        conn->dirty = true;
        conn->next_dirty = conn->net->dirty_head;
        conn->net->dirty_head = conn;
    }
    net_wake(conn->net);
}

int net_submit_op(tsr_net *net, net_op *op)
{
    op->done = false;
    op->next = NULL;
    if (net->ops_tail)
        net->ops_tail->next = op;
    else
        net->ops_head = op;
    net->ops_tail = op;
    net_wake(net);
    while (!op->done)
        pthread_cond_wait(&net->op_cond, &net->lock);
    return op->rc;
}

void net_io_maybe_finish(tsr_net *net)
{
    if (!net->stopping || uv_is_closing((uv_handle_t *)&net->wakeup))
        return;
    for (tsr_net_conn *c = net->conns; c; c = c->next_all)
        if (c->io_ref)
            return;
    for (tsr_net_listener *l = net->listeners; l; l = l->next)
        if (l->io_ref)
            return;
    uv_close((uv_handle_t *)&net->wakeup, NULL);
}

static void on_wakeup(uv_async_t *async)
{
    tsr_net *net = async->data;
    pthread_mutex_lock(&net->lock);
    while (net->ops_head) {
        net_op *op = net->ops_head;
        net->ops_head = op->next;
        if (!net->ops_head)
            net->ops_tail = NULL;
        switch (op->kind) {
        case NET_OP_LISTEN: net_io_listen(net, op); break;
        case NET_OP_CONNECT: net_io_connect(net, op); break;
        case NET_OP_CLOSE_LISTENER:
            net_io_close_listener(op->target);
            op->rc = TSR_OK;
            break;
        }
        op->done = true;
        pthread_cond_broadcast(&net->op_cond);
    }
    while (net->dirty_head) {
        tsr_net_conn *c = net->dirty_head;
        net->dirty_head = c->next_dirty;
        c->dirty = false;
        net_io_service(c); /* may free c */
    }
    if (net->stopping)
        net_io_stop(net);
    net_io_maybe_finish(net);
    pthread_mutex_unlock(&net->lock);
}

static void *io_thread_main(void *arg)
{
    tsr_net *net = arg;
    uv_run(&net->loop, UV_RUN_DEFAULT);
    return NULL;
}

static void init_monotonic_cond(pthread_cond_t *cond)
{
    pthread_condattr_t attr;
    pthread_condattr_init(&attr);
    pthread_condattr_setclock(&attr, CLOCK_MONOTONIC);
    pthread_cond_init(cond, &attr);
    pthread_condattr_destroy(&attr);
}

void net_cond_init(pthread_cond_t *cond) { init_monotonic_cond(cond); }

tsr_net *tsr_net_create(const tsr_net_config *config, tsr_error *err)
{
    tsr_net_config defaults;
    tsr_net_config_defaults(&defaults);
    if (!config)
        config = &defaults;
    const char *name = config->node_name && *config->node_name ? config->node_name : "node";
    if (strlen(name) > TSR_NET_NAME_MAX) {
        tsr_error_set(err, TSR_EINVAL, "net: node name '%s' is longer than %d bytes", name, TSR_NET_NAME_MAX);
        return NULL;
    }
    if (config->token && strlen(config->token) > TSR_NET_TOKEN_MAX) {
        tsr_error_set(err, TSR_EINVAL, "net: token is longer than %d bytes", TSR_NET_TOKEN_MAX);
        return NULL;
    }
    if (net_auth_init(err)) /* before any handshake may need a nonce */
        return NULL;
    if (config->credits == 0 || config->max_message_bytes == 0) {
        tsr_error_set(err, TSR_EINVAL, "net: credits and max_message_bytes must be above 0");
        return NULL;
    }
    uint64_t ring = config->shm_ring_bytes;
    if (ring && (ring < NET_SHM_RING_MIN || ring > NET_SHM_RING_MAX || ring % (uint64_t)sysconf(_SC_PAGESIZE))) {
        tsr_error_set(err, TSR_EINVAL, "net: shm_ring_bytes %llu is not 0 or a page multiple of 64 KiB..16 GiB",
                      (unsigned long long)ring);
        return NULL;
    }
    tsr_net *net = calloc(1, sizeof *net);
    if (!net) {
        tsr_error_set(err, TSR_ENOMEM, "net: out of memory");
        return NULL;
    }
    net->config = *config;
    strcpy(net->node_name, name);
    if (config->token)
        strcpy(net->token, config->token);
    net->config.node_name = net->node_name;
    net->config.token = net->token;
    if (!net->config.protocol_version)
        net->config.protocol_version = TSR_NET_PROTOCOL_VERSION;
#define DEFAULT_IF_ZERO(field) \
    if (!net->config.field)    \
        net->config.field = defaults.field;
    DEFAULT_IF_ZERO(connect_timeout_ms)
    DEFAULT_IF_ZERO(handshake_timeout_ms)
    DEFAULT_IF_ZERO(close_timeout_ms)
#undef DEFAULT_IF_ZERO
    pthread_mutex_init(&net->lock, NULL);
    init_monotonic_cond(&net->op_cond);
    init_monotonic_cond(&net->any_cond);
    int rc = uv_loop_init(&net->loop);
    if (rc == 0) {
        rc = uv_async_init(&net->loop, &net->wakeup, on_wakeup);
        if (rc)
            uv_loop_close(&net->loop);
    }
    if (rc) {
        tsr_error_set(err, TSR_EIO, "net: cannot start the I/O loop: %s", uv_strerror(rc));
        pthread_cond_destroy(&net->op_cond);
        pthread_cond_destroy(&net->any_cond);
        pthread_mutex_destroy(&net->lock);
        free(net);
        return NULL;
    }
    net->wakeup.data = net;
    /* The I/O thread takes no asynchronous signals (they belong to the
     * application), and SIGPIPE from writing to a vanished peer stays
     * blocked there, so the write fails with EPIPE instead of killing the
     * process — without changing the process-wide disposition. */
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &old);
    rc = pthread_create(&net->thread, NULL, io_thread_main, net);
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (rc) {
        tsr_error_set(err, TSR_EIO, "net: cannot start the I/O thread: %s", strerror(rc));
        uv_close((uv_handle_t *)&net->wakeup, NULL);
        uv_run(&net->loop, UV_RUN_DEFAULT);
        uv_loop_close(&net->loop);
        pthread_cond_destroy(&net->op_cond);
        pthread_cond_destroy(&net->any_cond);
        pthread_mutex_destroy(&net->lock);
        free(net);
        return NULL;
    }
    return net;
}

void tsr_net_destroy(tsr_net *net)
{
    if (!net)
        return;
    pthread_mutex_lock(&net->lock);
    net->stopping = true;
    /* In-process connections and listeners never touch the loop; they are
     * freed with everything else below once the I/O thread is done. */
    net_wake(net);
    pthread_mutex_unlock(&net->lock);
    pthread_join(net->thread, NULL);
    int rc = uv_loop_close(&net->loop);
    if (rc)
        tsr_log(TSR_LOG_ERROR, "net: I/O loop still had handles at shutdown: %s", uv_strerror(rc));
    /* Whatever the application did not close is freed now. */
    while (net->conns) {
        tsr_net_conn *c = net->conns;
        c->app_ref = false;
        c->io_ref = false;
        c->held = 0;
        net_conn_maybe_free(c);
    }
    while (net->listeners) {
        tsr_net_listener *l = net->listeners;
        l->app_ref = false;
        l->io_ref = false;
        net_listener_maybe_free(l);
    }
    pthread_cond_destroy(&net->op_cond);
    pthread_cond_destroy(&net->any_cond);
    pthread_mutex_destroy(&net->lock);
    free(net);
}
