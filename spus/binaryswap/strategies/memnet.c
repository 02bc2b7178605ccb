/* spus/binaryswap/strategies/memnet.c — an in-process transport for the
 * executor: one FIFO per (from, to) pair of participants, for peers that
 * share a process (the display living with rank 0 in situ, the tests, the
 * benchmark's one-process runs). A send copies the message (as a socket
 * would); a receive blocks until the sender's message is there or the
 * time-out passes (then the error names the silent peer).
 *
 * Owns: the queued messages and the buffer each receiver holds. Never:
 * does I/O or keeps state outside the tsr_composite_memnet it is given. */
#include <errno.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "strategy.h"

typedef struct memnet_msg {
    struct memnet_msg *next;
    size_t size;
    uint8_t data[];
} memnet_msg;

typedef struct memnet_end {
    tsr_composite_memnet *net;
    int me;
} memnet_end;

struct tsr_composite_memnet {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int n, timeout_ms;
    memnet_msg **head, **tail; /* [from * n + to] */
    memnet_msg **held;         /* per receiver: the buffer its last recv returned */
    memnet_end *ends;
};

tsr_composite_memnet *tsr_composite_memnet_new(int participants, int timeout_ms, tsr_error *err)
{
    tsr_composite_memnet *m = calloc(1, sizeof *m);
    size_t n = participants > 0 ? (size_t)participants : 1;
    if (m) {
        m->head = calloc(n * n, sizeof *m->head);
        m->tail = calloc(n * n, sizeof *m->tail);
        m->held = calloc(n, sizeof *m->held);
        m->ends = calloc(n, sizeof *m->ends);
    }
    if (!m || !m->head || !m->tail || !m->held || !m->ends) {
        if (m) {
            free(m->head);
            free(m->tail);
            free(m->held);
            free(m->ends);
        }
        free(m);
        tsr_error_set(err, TSR_ENOMEM, "memnet: no memory for %d participants", participants);
        return NULL;
    }
    pthread_mutex_init(&m->mu, NULL);
    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    pthread_cond_init(&m->cv, &ca);
    pthread_condattr_destroy(&ca);
    m->n = (int)n;
    m->timeout_ms = timeout_ms;
    for (size_t i = 0; i < n; i++)
        m->ends[i] = (memnet_end){m, (int)i};
    return m;
}

int tsr_composite_memnet_drain(tsr_composite_memnet *m, int *from, int *to)
{
    int left = 0;
    pthread_mutex_lock(&m->mu);
    for (int q = 0; q < m->n * m->n; q++)
        while (m->head[q]) {
            memnet_msg *x = m->head[q];
            m->head[q] = x->next;
            free(x);
            if (!left++) {
                *from = q / m->n;
                *to = q % m->n;
            }
        }
    memset(m->tail, 0, (size_t)m->n * (size_t)m->n * sizeof *m->tail);
    pthread_mutex_unlock(&m->mu);
    return left;
}

void tsr_composite_memnet_free(tsr_composite_memnet *m)
{
    if (!m)
        return;
    int f, t;
    tsr_composite_memnet_drain(m, &f, &t);
    for (int i = 0; i < m->n; i++)
        free(m->held[i]);
    pthread_mutex_destroy(&m->mu);
    pthread_cond_destroy(&m->cv);
    free(m->head);
    free(m->tail);
    free(m->held);
    free(m->ends);
    free(m);
}

static int memnet_send(void *user, int to, const void *data, size_t size, tsr_error *err)
{
    memnet_end *e = user;
    tsr_composite_memnet *m = e->net;
    if (to < 0 || to >= m->n)
        return tsr_error_set(err, TSR_EINVAL, "memnet: participant %d sends to %d (0..%d)", e->me, to, m->n - 1);
    memnet_msg *x = malloc(sizeof *x + size);
    if (!x)
        return tsr_error_set(err, TSR_ENOMEM, "memnet: no memory for a %zu-byte message", size);
    x->next = NULL;
    x->size = size;
    memcpy(x->data, data, size);
    pthread_mutex_lock(&m->mu);
    int q = e->me * m->n + to;
    if (m->tail[q])
        m->tail[q]->next = x;
    else
        m->head[q] = x;
    m->tail[q] = x;
    pthread_cond_broadcast(&m->cv);
    pthread_mutex_unlock(&m->mu);
    return TSR_OK;
}

static int memnet_recv(void *user, int from, const void **data, size_t *size, tsr_error *err)
{
    memnet_end *e = user;
    tsr_composite_memnet *m = e->net;
    if (from < 0 || from >= m->n)
        return tsr_error_set(err, TSR_EINVAL, "memnet: participant %d receives from %d (0..%d)", e->me, from, m->n - 1);
    struct timespec until;
    clock_gettime(CLOCK_MONOTONIC, &until);
    until.tv_sec += m->timeout_ms / 1000;
    until.tv_nsec += (long)(m->timeout_ms % 1000) * 1000000L;
    if (until.tv_nsec >= 1000000000L) {
        until.tv_sec++;
        until.tv_nsec -= 1000000000L;
    }
    pthread_mutex_lock(&m->mu);
    int q = from * m->n + e->me;
    while (!m->head[q])
        if (pthread_cond_timedwait(&m->cv, &m->mu, &until) == ETIMEDOUT && !m->head[q]) {
            pthread_mutex_unlock(&m->mu);
            return tsr_error_set(err, TSR_ETIMEDOUT, "peer %d sent nothing to %d within %d ms", from, e->me,
                                 m->timeout_ms);
        }
    memnet_msg *x = m->head[q];
    m->head[q] = x->next;
    if (!m->head[q])
        m->tail[q] = NULL;
    pthread_mutex_unlock(&m->mu);
    free(m->held[e->me]);
    m->held[e->me] = x;
    *data = x->data;
    *size = x->size;
    return TSR_OK;
}

void tsr_composite_memnet_transport(tsr_composite_memnet *m, int me, tsr_composite_transport *out)
{
    out->user = &m->ends[me];
    out->send = memnet_send;
    out->recv = memnet_recv;
}
