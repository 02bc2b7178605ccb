/* tessera/dev/protocol.h — the messages a stream client (tessera/dev/client.h:
 * pack, replicate, tilesort) and a server node exchange over one
 * connection of the network library. For an SPU that talks to server nodes
 * without the stream client, or a program that serves streams. Header only.
 *
 * Owns: the message kinds and the reply layout (this comment specifies
 * them). Never: depends on the network library's internals; the
 * connection, handshake and flow control are the library's.
 *
 * Use (a receiver): decode each TSR_NODE_MSG_BUFFER with one unpacker
 * (tessera/dev/unpack.h) per client, send every reply its callback gets as
 * TSR_NODE_MSG_REPLY, and answer TSR_NODE_MSG_FINISH once every buffer
 * before it ran.
 *
 * Client to server:
 *   TSR_NODE_MSG_BUFFER  one complete wire buffer (tessera/dev/wire.h section 1),
 *                        exactly as the packer flushed it.
 *   TSR_NODE_MSG_FINISH  empty: "that was my last buffer; confirm". The
 *                        server answers TSR_NODE_MSG_FINISH (empty) once
 *                        every buffer before it ran, or ERROR. Only then
 *                        does the client know its stream was drawn.
 * Server to client:
 *   TSR_NODE_MSG_REPLY   u32 request id, u32 0, then the reply bytes
 *                        (tessera/dev/wire.h section 5). Requests are answered in
 *                        the order they were sent; the id is how the client
 *                        checks it.
 *   TSR_NODE_MSG_ERROR   one line (UTF-8, no terminator): why the server
 *                        dropped this client (malformed buffer, chain
 *                        failure, a wrong parallel-API command, or, in
 *                        shared mode, a deadlock that stopped the node).
 *                        The server closes right after it.
 * A clean end: FINISH both ways, then the connection's BYE (the client closes its
 * connection); the server then destroys that client's chain. */
#ifndef TESSERA_DEV_PROTOCOL_H
#define TESSERA_DEV_PROTOCOL_H

#define TSR_NODE_MSG_BUFFER 0x10u
#define TSR_NODE_MSG_REPLY 0x11u
#define TSR_NODE_MSG_ERROR 0x12u
#define TSR_NODE_MSG_FINISH 0x13u

/* Bytes before the reply data in a TSR_NODE_MSG_REPLY (keeps the data
 * 8-aligned in the receiver's message memory). */
#define TSR_NODE_REPLY_HEADER 8u

#endif
