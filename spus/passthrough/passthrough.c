/* spus/passthrough — the trivial SPU: implements no command, so every call
 * falls through to the next SPU unchanged. Owns: one small instance per
 * chain link (its name and `verbose`). Never: touches or reorders calls. */
#include <stdio.h>
#include <stdlib.h>

#include "tessera/log.h"
#include "tessera/spu.h"

typedef struct passthrough {
    char name[96];
    bool verbose;
} passthrough;

static void *passthrough_create(const tsr_spu_init *init, tsr_error *err)
{
    passthrough *p = calloc(1, sizeof *p);
    if (!p) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    snprintf(p->name, sizeof p->name, "%s", init->instance_name);
    p->verbose = tsr_options_bool(init->options, "verbose");
    /* No slot is set: the loader fills every one from the child. The
     * verbose lines use the warn level because the user asked for them;
     * they must show without TESSERA_LOG. */
    if (p->verbose)
        tsr_log(TSR_LOG_WARN, "%s: created; every call goes straight to the next SPU", p->name);
    return p;
}

static void passthrough_destroy(void *self)
{
    passthrough *p = self;
    if (p->verbose)
        tsr_log(TSR_LOG_WARN, "%s: destroyed", p->name);
    free(p);
}

static const tsr_option_spec passthrough_options[] = {
    {.name = "verbose",
     .type = TSR_OPT_BOOL,
     .default_value = "false",
     .min = 1,
     .max = 0,
     .help = "log when the instance is created and destroyed"},
};

static const tsr_spu_class passthrough_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "passthrough",
    .summary = "passes every call to the next SPU unchanged",
    .options = passthrough_options,
    .option_count = sizeof passthrough_options / sizeof passthrough_options[0],
    .create = passthrough_create,
    .destroy = passthrough_destroy,
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &passthrough_class; }
