/* spus/display_stream/display_stream.h — the stream on which an SPU that
 * renders and reads back (readback: its tile images; binaryswap: its final
 * piece) sends its frames to a display node, the one display path both
 * share: the internal static library tessera_display_stream, on the SPUs'
 * side because it builds a `pack` chain by name, which the core and
 * libtessera_client never do (test spu_core_knows_no_spu_by_name). The display is an ordinary shared-mode
 * `tessera node` (server/node.h); the stream is a `pack` chain of its own.
 *
 * Owns: the chain, created at first use (the first window command of the
 * followed window, image or swap), not with the instance: a node builds
 * its chain once at start-up only to check it, and that probe must not
 * count as one of the display's clients. Right after it is made, the
 * frame barrier is created on it for `barrier_clients` clients (0: every
 * client of the display node). Never: sends the display anything the
 * caller did not call besides that barrier, or decides what a failure
 * means (the caller's on_failure does: readback follows on_error, a
 * binaryswap peer ends). */
#ifndef TSR_SPUS_DISPLAY_STREAM_H
#define TSR_SPUS_DISPLAY_STREAM_H

#include <stdbool.h>

#include "tessera/chain.h"
#include "tessera/spu.h"

typedef struct display_stream {
    const char *name;           /* the instance's, first word of its lines */
    const tsr_options *options; /* address_option and TSR_NODE_CLIENT_OPTION_SPECS */
    const char *address_option; /* the option naming the display ("server", "display") */
    int window;                 /* the window whose commands the display gets */
    unsigned barrier, barrier_clients;
    const tsr_dispatch *child; /* where window commands go after the display */
    /* Called once when the display cannot be reached (err names it and
     * the address); if it returns, the stream stays without a display. */
    void (*on_failure)(void *ctx, const tsr_error *err);
    void *ctx;
    tsr_chain *chain;
    const tsr_dispatch *head;
    bool failed;
} display_stream;

/* The display's table, made at the first call; NULL once it failed. */
const tsr_dispatch *display_stream_get(display_stream *s);
/* Points `down`'s WindowCreateTSR and WindowSizeTSR at the stream: the
 * followed window's go to the display first, every one to s->child. */
void display_stream_follow_window(display_stream *s, tsr_dispatch *down);
/* Sends what is left and waits for the display to run it. */
void display_stream_close(display_stream *s);
/* on_failure for on_error (TSR_NODE_CLIENT_OPTION_SPECS): exit ends the
 * process after the line (tsr_stream_client_exit), drop logs that the
 * frames go nowhere and goes on. */
void display_stream_on_error(void *ctx, const tsr_error *err);

#endif
