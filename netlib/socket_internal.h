/* netlib/socket_internal.h — what the files of the socket transport share
 * (all on the I/O thread, with net->lock held): socket.c (the write path,
 * closing, time-outs, servicing requests, connecting), socket_read.c (the
 * read parser and delivery), socket_handshake.c (HELLO, challenge, proof,
 * WELCOME), socket_admit.c (listeners, and which connections in their
 * handshake a listener admits). Not for anything outside netlib. */
#ifndef TSR_NETLIB_SOCKET_INTERNAL_H
#define TSR_NETLIB_SOCKET_INTERNAL_H

#include "net_internal.h"

#define NET_UNIX_SNDBUF (4 << 20) /* asked for a Unix socket's send buffer */

/* socket.c */
void sock_close_handles(tsr_net_conn *c);
void sock_arm_timer(tsr_net_conn *c);
void sock_write_direct_rest(tsr_net_conn *c);
void sock_write_msg(tsr_net_conn *c, net_msg *m);
void sock_write_control(tsr_net_conn *c, uint8_t type, const void *payload, size_t len);
void sock_send_hello(tsr_net_conn *c, uint8_t type, const uint8_t *auth, uint8_t features);
void sock_on_shutdown(uv_shutdown_t *req, int status);
void sock_begin_shutdown(tsr_net_conn *c);
int sock_init_stream(tsr_net *net, tsr_net_conn *c);

/* socket_read.c */
void sock_stop_reading(tsr_net_conn *c);
void sock_update_reading(tsr_net_conn *c);
void sock_start_reading(tsr_net_conn *c);

/* socket_handshake.c */
uint8_t sock_wanted_features(const tsr_net_conn *c);
void sock_deliver_hello(tsr_net_conn *c, net_msg *m);
void sock_deliver_proof(tsr_net_conn *c, net_msg *m);
void sock_deliver_challenge(tsr_net_conn *c, net_msg *m);
void sock_deliver_welcome(tsr_net_conn *c, net_msg *m);

/* socket_admit.c */
void sock_half_open_remove(tsr_net_conn *c);
void sock_note_dropped(tsr_net_conn *c, const char *why);
void sock_flush_outbox(tsr_net_conn *c);

#endif
