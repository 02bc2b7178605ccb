/* spus/display_stream/display_stream.c — the display stream of
 * display_stream.h: the pack chain to the display node, the frame barrier,
 * and the window commands of the followed window. */
#include "display_stream.h"

#include <inttypes.h>
#include <stdio.h>
#include <string.h>

#include "tessera/dev/client.h"
#include "tessera/log.h"

/* The options passed through to the pack SPU that carries the frames. */
static const char *const pack_keys[] = {"server", "token", "buffer_size", "timeout_ms", "on_error"};
#define PACK_KEYS (sizeof pack_keys / sizeof pack_keys[0])

const tsr_dispatch *display_stream_get(display_stream *s)
{
    if (s->head || s->failed)
        return s->head;
    char numbers[2][24];
    snprintf(numbers[0], sizeof numbers[0], "%" PRId64, tsr_options_int(s->options, "buffer_size"));
    snprintf(numbers[1], sizeof numbers[1], "%" PRId64, tsr_options_int(s->options, "timeout_ms"));
    const char *values[PACK_KEYS] = {tsr_options_string(s->options, s->address_option),
                                     tsr_options_string(s->options, "token"), numbers[0], numbers[1],
                                     tsr_options_string(s->options, "on_error")};
    tsr_chain_link link = {.spu = "pack", .keys = pack_keys, .values = values, .option_count = PACK_KEYS};
    tsr_error err = {0};
    s->chain = tsr_chain_create_links(&link, 1, &err);
    if (!s->chain) {
        s->failed = true;
        tsr_error named = {0};
        tsr_error_set(&named, err.code, "display %s: %s", values[0], err.message);
        if (s->on_failure)
            s->on_failure(s->ctx, &named);
        return NULL;
    }
    s->head = tsr_chain_head(s->chain);
    tsr_call_BarrierCreateTSR(s->head, s->barrier, s->barrier_clients);
    return s->head;
}

static void stream_WindowCreateTSR(void *self, GLint window, GLsizei width, GLsizei height)
{
    display_stream *s = self;
    const tsr_dispatch *d = window == s->window ? display_stream_get(s) : NULL;
    if (d)
        tsr_call_WindowCreateTSR(d, window, width, height);
    tsr_call_WindowCreateTSR(s->child, window, width, height);
}

static void stream_WindowSizeTSR(void *self, GLint window, GLsizei width, GLsizei height)
{
    display_stream *s = self;
    const tsr_dispatch *d = window == s->window ? display_stream_get(s) : NULL;
    if (d)
        tsr_call_WindowSizeTSR(d, window, width, height);
    tsr_call_WindowSizeTSR(s->child, window, width, height);
}

void display_stream_follow_window(display_stream *s, tsr_dispatch *down)
{
    tsr_set_WindowCreateTSR(down, stream_WindowCreateTSR, s);
    tsr_set_WindowSizeTSR(down, stream_WindowSizeTSR, s);
}

void display_stream_close(display_stream *s)
{
    tsr_chain_destroy(s->chain);
    s->chain = NULL;
    s->head = NULL;
}

void display_stream_on_error(void *ctx, const tsr_error *err)
{
    display_stream *s = ctx;
    tsr_log(TSR_LOG_ERROR, "%s: %s", s->name, err->message);
    if (!strcmp(tsr_options_string(s->options, "on_error"), "exit")) {
        /* The failure policy of a display that fails later (pack's,
         * tessera/dev/client.h): frames that reach no display are a
         * failed run. */
        tsr_log(TSR_LOG_ERROR, "%s: ending the server (on_error=exit)", s->name);
        tsr_stream_client_exit();
    }
    tsr_log(TSR_LOG_ERROR, "%s: on_error=drop: tile images are not sent", s->name);
}
