/* spus/render/drawpixels.h — render's fast glDrawPixels: RGBA8 rows
 * uploaded into a texture and blitted to the window, taken exactly when
 * the GL state makes the result identical to glDrawPixels (docs/render.md,
 * "DrawPixels"). llvmpipe draws pixel rectangles as a textured quad with a
 * JIT'd fragment shader per pixel (22-30 ms for a 1920x1080 frame); a
 * 1:1 blit flipped in y is a plain copy into its top-down colour buffer.
 *
 * Owns, per render instance: the resolved framebuffer-object entries, the
 * reversed-rows staging buffer, the clear colour's fill, the two textures
 * they are uploaded into (kept between calls: a new texture's storage is
 * zeroed by llvmpipe, as costly as the upload) and the counts of calls
 * taken fast / plain. The textures' names are in the client's share group
 * (the instance's contexts share one), which may bind any name without
 * generating it: render tells this module every name the client binds or
 * deletes (render_fastdraw_client_name), and a texture of ours whose name
 * the client takes is deleted first, so the client finds GL's default
 * object; a name a display list binds is never taken for ours; IsTexture
 * of ours answers false (render_fastdraw_owns).
 * Never: leaves any GL binding or pixel-store value it touched changed;
 * keeps a framebuffer object beyond one call; queries an enum the context
 * does not know (that would set the client's glGetError). */
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
/* Deletes the kept textures; a context of the instance's share group must
 * be current. (Destroying the group's last context frees them too.) */
void render_fastdraw_release(render_fastdraw *f, const tsr_gl_procs *gl);
/* The client binds or deletes texture `name` (compiling: into a display
 * list); called before the command reaches GL, in a context of the group. */
void render_fastdraw_client_name(render_fastdraw *f, const tsr_gl_procs *gl, GLuint name, bool compiling);
/* True when `name` is a texture this module keeps. */
bool render_fastdraw_owns(const render_fastdraw *f, GLuint name);

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
