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
    "the texels come from the renderer's own framebuffer, which the client never sees: one renderer gets the call; a sender whose renderers hold parts of the window gathers the source from them and gives the tracker a glTexImage/glTexSubImage of it instead"

#define NAMES \
    "the name stack only matters in GL_SELECT mode, which the renderers run; a sender forwards it to every renderer"
#define SELECT \
    "the selection and feedback buffers are the program's memory and the records come from the renderer that runs the pass (core/wire/select.c); the render mode is the renderer's answer, kept by the packer that asked (tsr_packer_render_mode)"
#define INDEX \
    "colour-index state: tessera's contexts are RGBA, where GL keeps it and ignores it; a sender forwards it to every renderer"
#define PIXELMAP "pixel maps are not tracked yet (rare); a sender forwards them to every renderer"
#define COMPRESSED "compressed texture images are not kept by the tracker yet; a sender forwards them to every renderer"
#define FBO \
    "the program's framebuffer objects (GL_EXT_framebuffer_object, and GL_ARB_framebuffer_object's core names for the same objects) live in the renderers: a tracking sender sends each such command to every renderer after its state diff, with the texture it attaches, and tracks glGenerateMipmapEXT as glGenerateMipmap"
#define QUERY "query objects live in the renderers, which count the samples; a sender forwards them to every renderer"

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
    {"RasterPos2dv", RASTER},
    {"RasterPos2s", RASTER},
    {"RasterPos2sv", RASTER},
    {"RasterPos3dv", RASTER},
    {"RasterPos3s", RASTER},
    {"RasterPos3sv", RASTER},
    {"RasterPos4d", RASTER},
    {"RasterPos4dv", RASTER},
    {"RasterPos4i", RASTER},
    {"RasterPos4iv", RASTER},
    {"RasterPos4s", RASTER},
    {"RasterPos4sv", RASTER},
    {"WindowPos2d", RASTER},
    {"WindowPos2dv", RASTER},
    {"WindowPos2fv", RASTER},
    {"WindowPos2iv", RASTER},
    {"WindowPos2s", RASTER},
    {"WindowPos2sv", RASTER},
    {"WindowPos3d", RASTER},
    {"WindowPos3dv", RASTER},
    {"WindowPos3f", RASTER},
    {"WindowPos3fv", RASTER},
    {"WindowPos3i", RASTER},
    {"WindowPos3iv", RASTER},
    {"WindowPos3s", RASTER},
    {"WindowPos3sv", RASTER},
    {"InitNames", NAMES},
    {"LoadName", NAMES},
    {"PassThrough", NAMES},
    {"PopName", NAMES},
    {"PushName", NAMES},
    {"SelectBuffer", SELECT},
    {"FeedbackBuffer", SELECT},
    {"RenderMode", SELECT},
    {"ClearIndex", INDEX},
    {"IndexMask", INDEX},
    {"PixelMapfv", PIXELMAP},
    {"PixelMapuiv", PIXELMAP},
    {"PixelMapusv", PIXELMAP},
    {"CopyTexSubImage3D", COPY},
    {"CompressedTexImage3D", COMPRESSED},
    {"CompressedTexImage2D", COMPRESSED},
    {"CompressedTexImage1D", COMPRESSED},
    {"CompressedTexSubImage3D", COMPRESSED},
    {"CompressedTexSubImage2D", COMPRESSED},
    {"CompressedTexSubImage1D", COMPRESSED},
    {"GenQueries", QUERY},
    {"DeleteQueries", QUERY},
    {"BeginQuery", QUERY},
    {"EndQuery", QUERY},
    {"GenRenderbuffersEXT", FBO},
    {"DeleteRenderbuffersEXT", FBO},
    {"BindRenderbufferEXT", FBO},
    {"RenderbufferStorageEXT", FBO},
    {"GenFramebuffersEXT", FBO},
    {"DeleteFramebuffersEXT", FBO},
    {"BindFramebufferEXT", FBO},
    {"FramebufferTexture1DEXT", FBO},
    {"FramebufferTexture2DEXT", FBO},
    {"FramebufferTexture3DEXT", FBO},
    {"FramebufferRenderbufferEXT", FBO},
    {"GenerateMipmapEXT", FBO},
    {"GenRenderbuffers", FBO},
    {"DeleteRenderbuffers", FBO},
    {"BindRenderbuffer", FBO},
    {"RenderbufferStorage", FBO},
    {"RenderbufferStorageMultisample", FBO},
    {"GenFramebuffers", FBO},
    {"DeleteFramebuffers", FBO},
    {"BindFramebuffer", FBO},
    {"FramebufferTexture1D", FBO},
    {"FramebufferTexture2D", FBO},
    {"FramebufferTexture3D", FBO},
    {"FramebufferTextureLayer", FBO},
    {"FramebufferRenderbuffer", FBO},
    {NULL, NULL},
};
