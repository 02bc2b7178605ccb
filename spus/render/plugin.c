/* spus/render/plugin.c — the `render` plugin: render.c's implementation
 * (tessera_render_core, render.h) with window output (xwindow.c) as its
 * hooks when window_output asks for it. */
#include <stdlib.h>

#include "render.h"
#include "xwindow.h"

typedef struct render_plugin {
    void *render;
    render_xwindow *xwindow;
} render_plugin;

static void render_plugin_destroy(void *self)
{
    render_plugin *p = self;
    render_spu_destroy(p->render);
    render_xwindow_destroy(p->xwindow);
    free(p);
}

static void *render_plugin_create(const tsr_spu_init *init, tsr_error *err)
{
    render_plugin *p = calloc(1, sizeof *p);
    if (!p) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    tsr_error xerr = {0};
    p->xwindow = render_xwindow_create(init, &xerr);
    if (!p->xwindow && xerr.code) {
        tsr_error_set(err, xerr.code, "%s", xerr.message);
        free(p);
        return NULL;
    }
    render_hooks hooks = {.image = render_xwindow_image, .done = render_xwindow_done, .ctx = p->xwindow};
    p->render = render_spu_create(init, p->xwindow ? &hooks : NULL, err);
    if (!p->render) {
        render_xwindow_destroy(p->xwindow);
        free(p);
        return NULL;
    }
    return p;
}

/* tessera/dev/render.h: what a subclass asks of its render super. */
static void api_window_size(const void *self, int *width, int *height)
{
    render_spu_size(((const render_plugin *)self)->render, width, height);
}
static size_t api_tile_count(const void *self) { return render_spu_tile_count(((const render_plugin *)self)->render); }
static int api_end_frame(void *self, tsr_render_tile_fn each, void *ctx)
{
    return render_spu_end_frame(((render_plugin *)self)->render, each, ctx);
}
static int api_read(void *self, int x, int y, int w, int h, unsigned format, unsigned type, void *pixels,
                    tsr_error *err)
{
    return render_spu_read(((render_plugin *)self)->render, x, y, w, h, format, type, pixels, err);
}
static const tsr_render_api render_api = {.version = TSR_RENDER_API_VERSION,
                                          .window_size = api_window_size,
                                          .tile_count = api_tile_count,
                                          .end_frame = api_end_frame,
                                          .read = api_read};

static const tsr_option_spec render_options[] = {RENDER_OPTION_SPECS, RENDER_XWINDOW_OPTION_SPECS};

static const tsr_spu_class render_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "render",
    .summary = "draws with OSMesa offscreen and writes a PNG per swap; can show frames in an X window",
    .options = render_options,
    .option_count = sizeof render_options / sizeof render_options[0],
    .create = render_plugin_create,
    .destroy = render_plugin_destroy,
    /* Sends to no node; a server's own tiles: go to `tiles`. */
    .network = {.role = TSR_SPU_ROLE_NONE, .tiles = "tiles"},
    .api = &render_api,
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &render_class; }
