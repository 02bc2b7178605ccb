/* tests/run/peers/peerprobe.c — a test SPU of the peers role
 * (TSR_SPU_ROLE_PEERS, tessera/spu.h), for tests/run/peers/peers.sh: it
 * writes what a graph run told it (its rank, every peer's address, the
 * display's address) to its `report` file, passes every call to its child,
 * and at its first swap connects to the display (the stream client) so the
 * display has its clients; destroying it ends that stream. Not a
 * compositor: only the roles' plumbing is under test. Owns, per instance:
 * its options' copies and the client. Never: connects from the node's
 * start-up probe of its chain (it swaps no frame). */
#include <stdio.h>
#include <stdlib.h>

#include "tessera/dev/client.h"
#include "tessera/spu.h"

typedef struct probe {
    char name[96];
    const tsr_dispatch *child;
    const tsr_options *options;
    tsr_stream_client *display; /* NULL until the first swap */
} probe;

static void probe_SwapBuffersTSR(void *self, GLint window, GLbitfield flags)
{
    probe *p = self;
    if (!p->display) {
        const char *address = tsr_options_string(p->options, "display");
        tsr_stream_client_config cfg = {.spu = "peerprobe", .name = p->name, .servers = &address, .server_count = 1};
        tsr_stream_client_config_from_options(&cfg, p->options);
        tsr_error err = {0};
        if (!(p->display = tsr_stream_client_connect(&cfg, &err)))
            fprintf(stderr, "%s: display %s: %s\n", p->name, address, err.message);
    }
    tsr_call_SwapBuffersTSR(p->child, window, flags);
}

static void *probe_create(const tsr_spu_init *init, tsr_error *err)
{
    probe *p = calloc(1, sizeof *p);
    if (!p) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    snprintf(p->name, sizeof p->name, "%s", init->instance_name);
    p->child = init->child;
    p->options = init->options;
    FILE *f = fopen(tsr_options_string(init->options, "report"), "w");
    if (!f) {
        free(p);
        tsr_error_set(err, TSR_EIO, "%s: cannot write the report", init->instance_name);
        return NULL;
    }
    fprintf(f, "rank=%lld display=%s peers=", (long long)tsr_options_int(init->options, "rank"),
            tsr_options_string(init->options, "display"));
    for (size_t i = 0; i < tsr_options_count(init->options, "peers"); i++)
        fprintf(f, "%s%s", i ? "," : "", tsr_options_string_at(init->options, "peers", i));
    fprintf(f, "\n");
    fclose(f);
    tsr_set_SwapBuffersTSR(init->table, probe_SwapBuffersTSR, p);
    return p;
}

static void probe_destroy(void *self)
{
    probe *p = self;
    tsr_stream_client_destroy(p->display);
    free(p);
}

static const tsr_option_spec probe_options[] = {
    {.name = "display",
     .type = TSR_OPT_STRING,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "the display node's address (a graph run fills it)"},
    {.name = "rank",
     .type = TSR_OPT_INT,
     .default_value = "-1",
     .min = -1,
     .max = 1e6,
     .help = "this node's rank among its peers (a graph run fills it)"},
    {.name = "peers",
     .type = TSR_OPT_STRING_LIST,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "every peer's address in rank order (a graph run fills it)"},
    {.name = "report",
     .type = TSR_OPT_STRING,
     .default_value = "peer.txt",
     .min = 1,
     .max = 0,
     .help = "where to write rank, display and peers"},
    TSR_NODE_CLIENT_OPTION_SPECS,
};

static const tsr_spu_class probe_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "peerprobe",
    .summary = "test: reports the rank, peers and display a graph run gives a peer",
    .options = probe_options,
    .option_count = sizeof probe_options / sizeof probe_options[0],
    .create = probe_create,
    .destroy = probe_destroy,
    .network = {.role = TSR_SPU_ROLE_PEERS,
                .display = "display",
                .rank = "rank",
                .peers = "peers",
                .token = TSR_NODE_CLIENT_TOKEN_OPTION},
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &probe_class; }
