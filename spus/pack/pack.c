/* spus/pack/pack.c — the "pack" SPU: sends the stream, unchanged, to one
 * server node (`tessera node`); replies to gets, ReadPixels and the Gen and
 * Create calls come back, matched by request id.
 * Owns, per instance: one stream client (tessera/dev/client.h), which holds the
 * connection, the packer, the failure policy (on_error) and the
 * statistics (TESSERA_STATS_FILE). Never calls its child: the stream goes
 * to the server. replicate is the same client with several servers. */
#include <stdio.h>
#include <stdlib.h>

#include "tessera/dev/client.h"
#include "tessera/spu.h"

static void pack_destroy(void *instance) { tsr_stream_client_destroy(instance); }

static void *pack_create(const tsr_spu_init *init, tsr_error *err)
{
    const char *server = tsr_options_string(init->options, "server");
    if (!server || !server[0]) {
        tsr_error_set(err, TSR_EINVAL, "%s: option server is required (e.g. server=tcp://127.0.0.1:7000)",
                      init->instance_name);
        return NULL;
    }
    tsr_stream_client_config cfg = {.spu = "pack", .name = init->instance_name, .servers = &server, .server_count = 1};
    tsr_stream_client_config_from_options(&cfg, init->options);
    return tsr_stream_client_create(&cfg, init->table, err);
}

static const tsr_option_spec pack_options[] = {
    {.name = "server",
     .type = TSR_OPT_STRING,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "server node address: tcp://HOST:PORT or unix:PATH (required)"},
    TSR_NODE_CLIENT_OPTION_SPECS,
};

static const tsr_spu_class pack_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "pack",
    .summary = "sends the stream, unchanged, to one server node; replies come back",
    .options = pack_options,
    .option_count = sizeof pack_options / sizeof pack_options[0],
    .create = pack_create,
    .destroy = pack_destroy,
    /* One server: a graph run points `server` at the node's to: and gives
     * it the run's token. */
    .network = {.role = TSR_SPU_ROLE_SERVER, .server = "server", .token = TSR_NODE_CLIENT_TOKEN_OPTION},
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &pack_class; }
