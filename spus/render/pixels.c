/* spus/render/pixels.c — the commands that write pixels outside the
 * vertex pipeline: Clear, CopyPixels and DrawPixels. They keep the record
 * of whether the stream ever wrote a stencil value (so a depth clear can
 * clear the stencil too, in one fill) and send DrawPixels and colour
 * clears to the fast paths (drawpixels.h).
 *
 * Owns: nothing beyond the instance's stencil_written flag.
 * Never: changes a pixel GL would not (the stencil is cleared only while
 * every stencil value is still 0), rewrites a clear compiled into a list. */
#include "instance.h"

/* A depth clear that keeps the stencil (no GL_STENCIL_BUFFER_BIT) makes
 * llvmpipe rewrite every packed 24/8 depth-stencil word through a mask,
 * about 1.6 times a clear of both (git show 56d9c59:bench/results/sortlast/README.md).
 * The stencil changes only through the stencil test, a stencil clear, or
 * stencil DrawPixels/CopyPixels (the commands tessera carries); while the
 * stream has done none of them with another value than 0, every stencil
 * value is 0 (or undefined, never yet written), so clearing it to 0 too
 * changes no pixel, and the clear is one fill. A clear compiled into a
 * display list is left as it is: the list may run after the stencil was
 * used. */
static void render_Clear(void *self, GLbitfield mask)
{
    render_spu *r = self;
    bool compiling = render_current_scissor(r)->list_mode != 0;
    if (mask & GL_STENCIL_BUFFER_BIT) {
        GLint value = 0;
        if (!compiling && !r->stencil_written)
            r->gl.GetIntegerv(GL_STENCIL_CLEAR_VALUE, &value);
        if (compiling || value != 0)
            r->stencil_written = true;
    } else if ((mask & GL_DEPTH_BUFFER_BIT) && !compiling && !r->stencil_written) {
        GLint value = -1;
        r->gl.GetIntegerv(GL_STENCIL_CLEAR_VALUE, &value);
        if (value == 0)
            mask |= GL_STENCIL_BUFFER_BIT;
    }
    if (mask == GL_COLOR_BUFFER_BIT && !compiling && render_fastdraw_clear(r->fastdraw, &r->gl, r->width, r->height))
        return;
    r->gl.Clear(mask);
}

static void render_CopyPixels(void *self, GLint x, GLint y, GLsizei width, GLsizei height, GLenum type)
{
    render_spu *r = self;
    if (type != GL_COLOR && type != GL_DEPTH)
        r->stencil_written = true;
    r->gl.CopyPixels(x, y, width, height, type);
}

static void render_DrawPixels(void *self, GLsizei width, GLsizei height, GLenum format, GLenum type, const void *pixels)
{
    render_spu *r = self;
    if (format == GL_STENCIL_INDEX || format == GL_DEPTH_STENCIL)
        r->stencil_written = true;
    render_fastdraw_draw(r->fastdraw, &r->gl, r->width, r->height, width, height, format, type, pixels);
}

void render_pixels_install(render_spu *r, tsr_dispatch *table)
{
    tsr_set_Clear(table, render_Clear, r);
    tsr_set_CopyPixels(table, render_CopyPixels, r);
    tsr_set_DrawPixels(table, render_DrawPixels, r);
}
