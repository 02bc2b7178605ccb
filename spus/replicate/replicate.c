/* spus/replicate/replicate.c — the "replicate" SPU: sends the same stream,
 * unchanged, to every listed server node, so each renders the same frames.
 * The stream is packed once and each flushed buffer is copied once and
 * handed to every connection (no per-server packing or copying). Replies
 * come from the first live server; the others' replies are read, their
 * request ids checked, and dropped (tessera/dev/client.h says why).
 * Owns, per instance: one stream client (tessera/dev/client.h) with one
 * connection per server, the failure policy (on_error: exit, or go on
 * without the failed server) and the statistics (TESSERA_STATS_FILE).
 * Never calls its child.
 *
 * Late joiners (`late=ADDR,...`): servers that may join the running
 * stream. The client connects to them in the background (every
 * late_retry_ms, for late_give_up_ms or the whole run) and admits one
 * right after a SwapBuffersTSR, once it has been sent a catch-up stream of
 * its own (windows, display lists, texture and buffer objects, then a
 * state-tracker diff: client/join.h), so its frames from then on are the
 * application's. Without `late` nothing is tracked: the stream costs the
 * same as before. A late server that never comes is one warning line at
 * the end, not an error.
 *
 * Shaders and programs with `late`: glCreateShader/glCreateProgram are
 * answered here (names counted up from 1, one namespace, like the state
 * tracker's) and sent as CreateShaderTSR/CreateProgramTSR, so a joiner
 * that is given the objects later knows them under the names the stream
 * uses (every render server maps names to its driver's:
 * tessera/glsl_names.h). Without `late` they are round trips to the first
 * server, as before. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/dev/client.h"
#include "tessera/spu.h"

typedef struct replicate {
    tsr_stream_client *client;
    tsr_dispatch pack; /* the client's packer table */
    GLuint last_name;  /* shader/program names given out so far */
} replicate;

static GLuint rep_CreateShader(void *self, GLenum type)
{
    replicate *r = self;
    if (type != GL_VERTEX_SHADER && type != GL_FRAGMENT_SHADER)
        return 0; /* GL: INVALID_ENUM, no object */
    tsr_call_CreateShaderTSR(&r->pack, ++r->last_name, type);
    return r->last_name;
}

static GLuint rep_CreateProgram(void *self)
{
    replicate *r = self;
    tsr_call_CreateProgramTSR(&r->pack, ++r->last_name);
    return r->last_name;
}

static void replicate_destroy(void *instance)
{
    replicate *r = instance;
    if (!r)
        return;
    tsr_stream_client_destroy(r->client);
    free(r);
}

static void *replicate_create(const tsr_spu_init *init, tsr_error *err)
{
    size_t count = tsr_options_count(init->options, "servers");
    if (count == 0) {
        tsr_error_set(err, TSR_EINVAL,
                      "%s: option servers is required (e.g. servers=tcp://127.0.0.1:7000,unix:/tmp/s.sock)",
                      init->instance_name);
        return NULL;
    }
    const char **servers = calloc(count, sizeof *servers);
    if (!servers) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    for (size_t i = 0; i < count; i++)
        servers[i] = tsr_options_string_at(init->options, "servers", i);
    size_t late_count = tsr_options_count(init->options, "late");
    const char **late = calloc(late_count ? late_count : 1, sizeof *late);
    if (!late) {
        free(servers);
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    for (size_t i = 0; i < late_count; i++) {
        late[i] = tsr_options_string_at(init->options, "late", i);
        /* Checked before connecting: a server cannot be both. */
        for (size_t k = 0; k < count; k++)
            if (!strcmp(servers[k], late[i])) {
                tsr_error_set(err, TSR_EINVAL, "%s: server %s is listed twice (in servers and in late)",
                              init->instance_name, late[i]);
                free(servers);
                free(late);
                return NULL;
            }
    }
    tsr_stream_client_config cfg = {.spu = "replicate",
                                    .name = init->instance_name,
                                    .servers = servers,
                                    .server_count = count,
                                    .late_servers = late,
                                    .late_count = late_count,
                                    .late_retry_ms = (uint32_t)tsr_options_int(init->options, "late_retry_ms"),
                                    .late_give_up_ms = (uint32_t)tsr_options_int(init->options, "late_give_up_ms")};
    tsr_stream_client_config_from_options(&cfg, init->options);
    replicate *r = calloc(1, sizeof *r);
    if (!r) {
        free(servers);
        free(late);
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    r->client = tsr_stream_client_create(&cfg, init->table, err);
    free(servers); /* the client copied the addresses */
    free(late);
    if (!r->client) {
        free(r);
        return NULL;
    }
    if (late_count) {
        r->pack = *init->table;
        tsr_set_CreateShader(init->table, rep_CreateShader, r);
        tsr_set_CreateProgram(init->table, rep_CreateProgram, r);
    }
    return r;
}

static const tsr_option_spec replicate_options[] = {
    {.name = "servers",
     .type = TSR_OPT_STRING_LIST,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "server node addresses, comma-separated: tcp://HOST:PORT or unix:PATH (required; "
             "every one receives the whole stream, replies come from the first)"},
    {.name = "late",
     .type = TSR_OPT_STRING_LIST,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "servers that may join the running stream, comma-separated: not needed at start, "
             "connected in the background, caught up (state, textures, display lists, buffers, "
             "shaders and programs with their uniforms) "
             "and added at the next frame boundary"},
    {.name = "late_retry_ms",
     .type = TSR_OPT_INT,
     .default_value = "200",
     .min = 10,
     .max = 60000.0,
     .help = "pause between connection attempts to a late server"},
    {.name = "late_give_up_ms",
     .type = TSR_OPT_INT,
     .default_value = "0",
     .min = 0,
     .max = 86400000.0,
     .help = "stop trying late servers after this long (0: until the application ends)"},
    TSR_NODE_CLIENT_OPTION_SPECS,
};

static const tsr_spu_class replicate_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "replicate",
    .summary = "sends the same stream to every listed server node; replies come from the first",
    .options = replicate_options,
    .option_count = sizeof replicate_options / sizeof replicate_options[0],
    .create = replicate_create,
    .destroy = replicate_destroy,
    /* Every server of the node's to:, in order (late joiners are not the
     * graph's: `late` stays as written). */
    .network = {.role = TSR_SPU_ROLE_SERVERS, .servers = "servers", .token = TSR_NODE_CLIENT_TOKEN_OPTION},
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &replicate_class; }
