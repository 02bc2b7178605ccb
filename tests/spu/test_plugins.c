/* tests/spu/test_plugins.c — plugin files the loader tests load for real,
 * one variant per build (TEST_PLUGIN_*): a second `passthrough` placed on
 * TESSERA_SPU_PATH, a library without the entry point, one built for
 * another ABI, one built as against the previous ABI's headers (ABI 1,
 * whose class had no `network`), and one whose class name does not match
 * its file name.
 * Owns nothing. Never: used outside tests. */
#include <stdlib.h>

#include "tessera/spu.h"

#ifdef TEST_PLUGIN_PREVIOUS_ABI
/* tsr_spu_class as ABI 1 laid it out: shorter than today's. The loader
 * must read no further than `abi` before refusing it. */
typedef struct abi1_class {
    uint32_t abi;
    uint32_t dispatch_count;
    const char *name, *super, *summary;
    const tsr_option_spec *options;
    size_t option_count;
    void *(*create)(const tsr_spu_init *init, tsr_error *err);
    void (*destroy)(void *instance);
} abi1_class;
#endif

#ifndef TEST_PLUGIN_NO_ENTRY
static void *plugin_create(const tsr_spu_init *init, tsr_error *err)
{
    (void)init;
    void *instance = malloc(1);
    if (!instance)
        tsr_error_set(err, TSR_ENOMEM, "out of memory");
    return instance;
}

static void plugin_destroy(void *instance) { free(instance); }

#ifdef TEST_PLUGIN_PREVIOUS_ABI
static const abi1_class plugin_class = {
    .abi = 1,
    .name = "prevabi",
#else
static const tsr_spu_class plugin_class = {
#endif
#ifdef TEST_PLUGIN_PREVIOUS_ABI
#elif defined TEST_PLUGIN_OLD_ABI
    .abi = TSR_SPU_ABI + 1000,
    .name = "oldabi",
#elif defined TEST_PLUGIN_MISNAMED
.abi = TSR_SPU_ABI, .name = "othername",
#else /* TEST_PLUGIN_SHADOW */
.abi = TSR_SPU_ABI, .name = "passthrough",
#endif
    .dispatch_count = TSR_DISPATCH_COUNT,
    .summary = "test copy found first on TESSERA_SPU_PATH",
    .create = plugin_create,
    .destroy = plugin_destroy,
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void)
{
    return (const tsr_spu_class *)(const void *)&plugin_class;
}
#else
/* Exports something, just not the entry point. */
TSR_SPU_EXPORT int tsr_spu_not_the_entry_point(void) { return 42; }
#endif
