/* spus/render/plugin.c — the `render` plugin's class: its options
 * (render.h's and window output's, xwindow.h), create and destroy
 * (render.c), and the api it publishes for SPUs that inherit it
 * (tessera/dev/render.h, answered by frame.c). Owns nothing: the instance
 * is render.c's. */
#include "render.h"
#include "xwindow.h"

/* tessera/dev/render.h: what a subclass asks of its render super. */
static const tsr_render_api render_api = {.version = TSR_RENDER_API_VERSION,
                                          .window_size = render_spu_size,
                                          .tile_count = render_spu_tile_count,
                                          .end_frame = render_spu_end_frame,
                                          .read = render_spu_read};

static const tsr_option_spec render_options[] = {RENDER_OPTION_SPECS, RENDER_XWINDOW_OPTION_SPECS};

static const tsr_spu_class render_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "render",
    .summary = "draws with OSMesa offscreen and writes a PNG per swap; can show frames in an X window",
    .options = render_options,
    .option_count = sizeof render_options / sizeof render_options[0],
    .create = render_spu_create,
    .destroy = render_spu_destroy,
    /* Sends to no node; a server's own tiles: go to `tiles`. */
    .network = {.role = TSR_SPU_ROLE_NONE, .tiles = "tiles"},
    .api = &render_api,
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &render_class; }
