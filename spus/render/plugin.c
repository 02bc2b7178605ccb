/* spus/render/plugin.c — the `render` plugin: render.c's implementation
 * (tessera_render_core, render.h) with no hooks. */
#include "render.h"

static void *render_plugin_create(const tsr_spu_init *init, tsr_error *err)
{
    return render_spu_create(init, NULL, err);
}

static const tsr_option_spec render_options[] = {RENDER_OPTION_SPECS};

static const tsr_spu_class render_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "render",
    .summary = "draws with OSMesa offscreen and writes a PNG per swap",
    .options = render_options,
    .option_count = sizeof render_options / sizeof render_options[0],
    .create = render_plugin_create,
    .destroy = render_spu_destroy,
    /* Sends to no node; a server's own tiles: go to `tiles`. */
    .network = {.role = TSR_SPU_ROLE_NONE, .tiles = "tiles"},
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &render_class; }
