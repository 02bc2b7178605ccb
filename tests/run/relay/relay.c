/* tests/run/relay/relay.c — a third party's network SPU, built out of tree
 * against the installed developer API only (tessera/spu.h,
 * tessera/dev/pack.h, tessera/dev/client.h; pkg-config tessera). It packs
 * the stream with a packer of its own and relays every buffer to one
 * server through the stream client, counting frames, buffers and bytes,
 * and writes one report line when it ends.
 *
 * Nothing in tessera knows it: its class declares the role (one server)
 * and which of its options a graph run fills, under names of its own
 * choosing (`upstream`, `key`), so `to:` in a graph is enough. Owns, per
 * instance: the packer, the client, the counters. Never: uses globals. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <tessera/dev/client.h>
#include <tessera/dev/pack.h>
#include <tessera/spu.h>

typedef struct relay {
    char name[96];
    char upstream[256];
    int keyed;                 /* a token was given (a graph run always has one) */
    char *report;              /* file for the report line; "" = standard error */
    tsr_stream_client *client; /* connected to `upstream`, no packer of its own */
    tsr_pack_sink to_server;   /* the client's sink for server 0 (replies too) */
    tsr_packer *packer;        /* ours: every slot of the table packs into it */
    tsr_dispatch packed;       /* the packer's table, for the slots we wrap */
    uint64_t frames, buffers, bytes;
} relay;

/* Every full (or flushed) buffer goes to the server, counted. */
static int relay_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    relay *r = ctx;
    r->buffers++;
    r->bytes += size;
    return r->to_server.flush(r->to_server.ctx, buf, size, err);
}

static int relay_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    relay *r = ctx;
    return r->to_server.reply(r->to_server.ctx, id, data, size, err);
}

/* A frame ends: pack the swap, send the frame now (not when the buffer
 * fills), count it. */
static void relay_SwapBuffersTSR(void *self, GLint window, GLbitfield flags)
{
    relay *r = self;
    tsr_call_SwapBuffersTSR(&r->packed, window, flags);
    tsr_packer_flush(r->packer);
    tsr_stream_client_count_frame(r->client);
    r->frames++;
}

static void relay_destroy(void *self)
{
    relay *r = self;
    if (!r)
        return;
    if (r->packer)
        tsr_packer_flush(r->packer);
    tsr_stream_client_destroy(r->client); /* FINISH: waits until the server ran it all */
    tsr_packer_destroy(r->packer);
    FILE *out = r->report[0] ? fopen(r->report, "w") : stderr;
    if (out) {
        fprintf(out, "%s: upstream=%s key=%s frames=%llu buffers=%llu bytes=%llu\n", r->name, r->upstream,
                r->keyed ? "set" : "none", (unsigned long long)r->frames, (unsigned long long)r->buffers,
                (unsigned long long)r->bytes);
        if (out != stderr)
            fclose(out);
    }
    free(r->report);
    free(r);
}

static void *relay_create(const tsr_spu_init *init, tsr_error *err)
{
    const char *upstream = tsr_options_string(init->options, "upstream");
    if (!upstream[0]) {
        tsr_error_set(err, TSR_EINVAL, "%s: option upstream is required (a graph's to: fills it)", init->instance_name);
        return NULL;
    }
    relay *r = calloc(1, sizeof *r);
    const char *report = tsr_options_string(init->options, "report");
    if (!r || !(r->report = malloc(strlen(report) + 1))) {
        free(r);
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    strcpy(r->report, report);
    snprintf(r->name, sizeof r->name, "%s", init->instance_name);
    snprintf(r->upstream, sizeof r->upstream, "%s", upstream);
    r->keyed = tsr_options_string(init->options, "key")[0] != '\0';
    tsr_stream_client_config cfg = {
        .spu = "relay",
        .name = r->name,
        .servers = &upstream,
        .server_count = 1,
        .token = tsr_options_string(init->options, "key"),
        .timeout_ms = 10000,
        .buffer_size = (size_t)tsr_options_int(init->options, "buffer_size"),
        .exit_on_error = 1,
    };
    if (!(r->client = tsr_stream_client_connect(&cfg, err))) {
        relay_destroy(r);
        return NULL;
    }
    tsr_stream_client_server_sink(r->client, 0, &r->to_server);
    tsr_pack_sink sink = {.flush = relay_flush, .reply = relay_reply, .ctx = r};
    if (!(r->packer = tsr_packer_create(cfg.buffer_size, &sink, err))) {
        relay_destroy(r);
        return NULL;
    }
    tsr_packer_fill_dispatch(r->packer, init->table);
    r->packed = *init->table;
    tsr_set_SwapBuffersTSR(init->table, relay_SwapBuffersTSR, r);
    return r;
}

static const tsr_option_spec relay_options[] = {
    {.name = "upstream",
     .type = TSR_OPT_STRING,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "the server the stream goes to: tcp://HOST:PORT or unix:PATH (a graph's to:)"},
    {.name = "key",
     .type = TSR_OPT_STRING,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "the token the server requires (a graph run's token)"},
    {.name = "buffer_size",
     .type = TSR_OPT_INT,
     .default_value = "262144",
     .min = 4096,
     .max = 16777216.0,
     .help = "bytes of one wire buffer"},
    {.name = "report",
     .type = TSR_OPT_STRING,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "file for the report line written at the end (empty: standard error)"},
};

static const tsr_spu_class relay_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "relay",
    .summary = "packs the stream itself and relays every buffer to one server, counted",
    .options = relay_options,
    .option_count = sizeof relay_options / sizeof relay_options[0],
    .create = relay_create,
    .destroy = relay_destroy,
    .network = {.role = TSR_SPU_ROLE_SERVER, .server = "upstream", .token = "key"},
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &relay_class; }
