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
 *   TSR_NODE_MSG_COST    the server's cost of one frame, sent after a
 *                        SwapBuffersTSR whose flags hold
 *                        TSR_NODE_SWAP_REPORT_COST (the bit is taken off
 *                        before the chain sees the swap): u32 frame (the
 *                        server's count of such swaps from this client,
 *                        from 0), u32 faults (the minor page faults of
 *                        the chain's thread in that frame), f64 seconds
 *                        (the thread CPU time of the server's chain from
 *                        the previous swap to the end of this one), f64
 *                        fault seconds (the part of those seconds the
 *                        faults cost: faults times the server's own
 *                        measured cost of one, so a balancer can tell a
 *                        region's steady cost from the one-time cost of
 *                        moving onto pixels the server had not drawn).
 *                        Unsolicited and never
 *                        waited for: the client takes it when it next looks
 *                        (a reply, its next swap, FINISH). A server with
 *                        no credit left for it drops it rather than block,
 *                        so it can never hold the stream up.
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
#define TSR_NODE_MSG_COST 0x14u

/* In SwapBuffersTSR's flags: "answer this swap with a TSR_NODE_MSG_COST"
 * (tilesort's load balancer asks; no other sender does). */
#define TSR_NODE_SWAP_REPORT_COST 0x1u
/* Bytes of a TSR_NODE_MSG_COST. */
#define TSR_NODE_COST_BYTES 24u

/* Bytes before the reply data in a TSR_NODE_MSG_REPLY (keeps the data
 * 8-aligned in the receiver's message memory). */
#define TSR_NODE_REPLY_HEADER 8u

#endif
