/* netlib/conn_internal.h — what the files of the connection API share
 * (application threads): conn.c (messages' memory, connection life cycle,
 * waits, connecting, receiving, queries, close), conn_listen.c (listeners:
 * listen, accept, close), conn_send.c (the send path: credits, the ring,
 * owned and copied messages). Not for anything outside netlib. */
#ifndef TSR_NETLIB_CONN_INTERNAL_H
#define TSR_NETLIB_CONN_INTERNAL_H

#include <netdb.h>
#include <pthread.h>
#include <time.h>

#include "net_internal.h"

/* conn.c */
int conn_wait_until(pthread_cond_t *cond, pthread_mutex_t *lock, const struct timespec *dl);
int conn_unusable(const tsr_net_conn *c, const char *verb, tsr_error *err);

/* conn_listen.c */
int conn_resolve(const tsr_net_address *a, bool passive, struct addrinfo **out, const char *text, const char *verb,
                 tsr_error *err);

#endif
