/* spus/render/drawpixels.h — render's fast glDrawPixels: RGBA8 rows
 * uploaded into a texture and blitted to the window, taken exactly when
 * the GL state makes the result identical to glDrawPixels (docs/render.md,
 * "DrawPixels"). llvmpipe draws pixel rectangles as a textured quad with a
 * JIT'd fragment shader per pixel (22-30 ms for a 1920x1080 frame); a
 * 1:1 blit flipped in y is a plain copy into its top-down colour buffer.
 *
 * Owns, per render instance: the resolved framebuffer-object entries, the
 * reversed-rows staging buffer, the clear colour's fill and the counts of
 * calls taken fast / plain.
 * Never: leaves any GL binding or pixel-store value it touched changed;
 * keeps a GL object beyond one call (texture and FBO names belong to the
 * client's share group, which may bind any name without generating it);
 * queries an enum the context does not know (that would set the client's
 * glGetError). */
#ifndef TSR_SPUS_RENDER_DRAWPIXELS_H
#define TSR_SPUS_RENDER_DRAWPIXELS_H

#include <stdbool.h>
#include <stdint.h>

#include "tessera/glprocs_gen.h"

typedef struct render_fastdraw render_fastdraw;

/* lookup resolves a gl* name in the instance's GL (OSMesaGetProcAddress).
 * enabled=false: every call takes the plain path (option fast_drawpixels). */
render_fastdraw *render_fastdraw_create(tsr_proc (*lookup)(const char *name, void *ctx), void *ctx, bool enabled);
void render_fastdraw_destroy(render_fastdraw *f, const char *instance_name);

/* Draws like gl->DrawPixels(width, height, format, type, pixels) in the
 * current context, whose draw framebuffer is window_width x window_height;
 * the fast path when the state allows it. */
void render_fastdraw_draw(render_fastdraw *f, const tsr_gl_procs *gl, int window_width, int window_height,
                          GLsizei width, GLsizei height, GLenum format, GLenum type, const void *pixels);

/* A glClear(GL_COLOR_BUFFER_BIT) under the scissor test (llvmpipe draws
 * that as a quad through its fragment shader, 5-6 times the time of the
 * blit per pixel) as the same upload and blit of the clear colour, when
 * the state makes it identical; true when it cleared, false when the
 * caller must call glClear. */
bool render_fastdraw_clear(render_fastdraw *f, const tsr_gl_procs *gl, int window_width, int window_height);

/* Calls so far that took the fast path, and all calls. */
void render_fastdraw_counts(const render_fastdraw *f, uint64_t *fast, uint64_t *total);
void render_fastdraw_clear_counts(const render_fastdraw *f, uint64_t *fast, uint64_t *total);

#endif
