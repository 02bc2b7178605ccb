/* core/state/state_spec.c — the spec commands (categories state, object,
 * client) the state tracker does not implement, each with the reason. The
 * test state_covers_spec holds every such command of spec/gl.yaml to be
 * either set by tsr_state_fill_dispatch or listed here, and nothing listed
 * here to be implemented as well. */
#include "tessera/dev/state.h"

#define RASTER \
    "the raster position is computed by the renderer from the transform and viewport at the time of the call (like a vertex); a sender forwards it in the stream with the geometry that uses it"
#define EVAL \
    "evaluator maps and grids are not tracked yet (rare in the programs tessera runs); a sender forwards them to every renderer"
#define COPY \
    "the texels come from the renderer's own framebuffer, which the client never sees; a sender must send the call to every renderer"

const tsr_state_untracked_cmd tsr_state_untracked[] = {
    {"RasterPos2f", RASTER},
    {"RasterPos2i", RASTER},
    {"RasterPos3f", RASTER},
    {"RasterPos2d", RASTER},
    {"RasterPos2fv", RASTER},
    {"RasterPos2iv", RASTER},
    {"RasterPos3d", RASTER},
    {"RasterPos3fv", RASTER},
    {"RasterPos3i", RASTER},
    {"RasterPos3iv", RASTER},
    {"RasterPos4f", RASTER},
    {"RasterPos4fv", RASTER},
    {"WindowPos2i", RASTER},
    {"WindowPos2f", RASTER},
    {"Map1f", EVAL},
    {"Map2f", EVAL},
    {"Map1d", EVAL},
    {"Map2d", EVAL},
    {"MapGrid1f", EVAL},
    {"MapGrid2f", EVAL},
    {"MapGrid1d", EVAL},
    {"MapGrid2d", EVAL},
    {"CopyTexImage1D", COPY},
    {"CopyTexImage2D", COPY},
    {"CopyTexSubImage1D", COPY},
    {"CopyTexSubImage2D", COPY},
    {NULL, NULL},
};
