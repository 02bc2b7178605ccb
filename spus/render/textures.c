/* spus/render/textures.c — the texture commands render implements: the
 * per-context texture budget (docs/render.md, "Budgets": a TexImage or
 * CopyTexImage that would take a context over max_texture_bytes is
 * refused) and the texture names the fast DrawPixels keeps
 * (drawpixels.h), which the client's names displace.
 *
 * Owns nothing: the table of texture bytes is budget.c's, kept in the
 * instance. Never: runs a refused command, guesses the bound texture (GL
 * is asked, so lists and attribute stacks are followed). */
#include "instance.h"

#include "tessera/dev/unpack.h"

/* The context whose budget a command is charged to. */
static GLint budget_owner(const render_spu *r) { return r->shared ? r->contexts[r->current].id : 0; }

/* The glGet enum of the texture bound for a TexImage target; 0 for proxy
 * targets (no storage) and targets GL refuses itself. */
static GLenum binding_of(GLenum target)
{
    switch (target) {
    case GL_TEXTURE_1D: return GL_TEXTURE_BINDING_1D;
    case GL_TEXTURE_2D: return GL_TEXTURE_BINDING_2D;
    case GL_TEXTURE_3D: return GL_TEXTURE_BINDING_3D;
    case GL_TEXTURE_RECTANGLE: return GL_TEXTURE_BINDING_RECTANGLE;
    case GL_TEXTURE_CUBE_MAP_POSITIVE_X:
    case GL_TEXTURE_CUBE_MAP_NEGATIVE_X:
    case GL_TEXTURE_CUBE_MAP_POSITIVE_Y:
    case GL_TEXTURE_CUBE_MAP_NEGATIVE_Y:
    case GL_TEXTURE_CUBE_MAP_POSITIVE_Z:
    case GL_TEXTURE_CUBE_MAP_NEGATIVE_Z: return GL_TEXTURE_BINDING_CUBE_MAP;
    default: return 0;
    }
}

/* Whether a texture image of width x height x depth may be specified now
 * (true: the caller runs it; the table then holds it). The texture bound
 * is asked of GL, so display lists and attribute stacks that bound it are
 * followed. Inside a list being compiled nothing is allocated yet: only
 * an image larger than the whole budget is refused there. */
/* Whether GL refuses an image of this size itself (GL_INVALID_VALUE),
 * allocating nothing: a side over its maximum, or a negative one. */
static bool size_refused_by_gl(render_spu *r, GLenum target, GLsizei width, GLsizei height, GLsizei depth)
{
    GLenum max_pname = target == GL_TEXTURE_3D                             ? GL_MAX_3D_TEXTURE_SIZE
                       : target == GL_TEXTURE_RECTANGLE                    ? GL_MAX_RECTANGLE_TEXTURE_SIZE
                       : binding_of(target) == GL_TEXTURE_BINDING_CUBE_MAP ? GL_MAX_CUBE_MAP_TEXTURE_SIZE
                                                                           : GL_MAX_TEXTURE_SIZE;
    GLint max = 0;
    r->gl.GetIntegerv(max_pname, &max);
    return width < 0 || height < 0 || depth < 0 ||
           (max > 0 && (width > max + 2 || height > max + 2 || depth > max + 2));
}

static bool texture_admit(render_spu *r, const char *command, GLenum target, GLint level, GLint internalformat,
                          GLsizei width, GLsizei height, GLsizei depth, GLint border)
{
    /* The budget protects a node from the streams it receives; in the
     * application's own process (also behind capture, which decodes the
     * program's stream there) the memory is the program's, and it gets
     * what its GL gives it, as natively (piglit's max-texture-size). */
    if (!tsr_unpacker_budgeted())
        return true;
    GLenum binding = binding_of(target);
    if (!binding || level < 0 || border < 0 || border > 1 || size_refused_by_gl(r, target, width, height, depth))
        return true; /* no storage, or GL's own error (it allocates nothing) */
    int64_t b2 = 2 * (int64_t)border;
    uint64_t bytes = render_tex_image_bytes(internalformat, width + b2, height + (height > 1 || border ? b2 : 0),
                                            depth + (depth > 1 || border ? b2 : 0));
    if (!bytes)
        return true;
    GLint owner = budget_owner(r);
    uint64_t max = r->max_texture_bytes;
    if (render_current_scissor(r)->list_mode) {
        if (max && bytes > max) {
            render_refuse(r,
                          "%s(target 0x%x, level %d, %dx%dx%d) in a display list: %llu bytes are over the texture "
                          "budget max_texture_bytes=%llu of context %d",
                          command, target, level, (int)width, (int)height, (int)depth, (unsigned long long)bytes,
                          (unsigned long long)max, (int)owner);
            return false;
        }
        return true;
    }
    GLint name = 0;
    r->gl.GetIntegerv(binding, &name);
    render_tex_image *old = render_tex_find(&r->textures, (GLuint)name, owner, target, level);
    uint64_t held = render_tex_held(&r->textures, owner) - (old && old->owner == owner ? old->bytes : 0);
    if (max && (bytes > max || held > max - bytes)) {
        render_refuse(r,
                      "%s(target 0x%x, level %d, %dx%dx%d, texture %d): %llu bytes are over the texture budget "
                      "max_texture_bytes=%llu of context %d (%llu bytes held)",
                      command, target, level, (int)width, (int)height, (int)depth, (int)name, (unsigned long long)bytes,
                      (unsigned long long)max, (int)owner, (unsigned long long)held);
        return false;
    }
    if (render_tex_set(&r->textures, (GLuint)name, owner, target, level, bytes) != 0) {
        render_refuse(r, "%s: out of memory for the texture table", command);
        return false;
    }
    return true;
}

static void render_TexImage1D(void *self, GLenum target, GLint level, GLint internalformat, GLsizei width, GLint border,
                              GLenum format, GLenum type, const void *pixels)
{
    render_spu *r = self;
    if (texture_admit(r, "TexImage1D", target, level, internalformat, width, 1, 1, border))
        r->gl.TexImage1D(target, level, internalformat, width, border, format, type, pixels);
}

static void render_TexImage2D(void *self, GLenum target, GLint level, GLint internalformat, GLsizei width,
                              GLsizei height, GLint border, GLenum format, GLenum type, const void *pixels)
{
    render_spu *r = self;
    if (texture_admit(r, "TexImage2D", target, level, internalformat, width, height, 1, border))
        r->gl.TexImage2D(target, level, internalformat, width, height, border, format, type, pixels);
}

static void render_TexImage3D(void *self, GLenum target, GLint level, GLint internalformat, GLsizei width,
                              GLsizei height, GLsizei depth, GLint border, GLenum format, GLenum type,
                              const void *pixels)
{
    render_spu *r = self;
    if (texture_admit(r, "TexImage3D", target, level, internalformat, width, height, depth, border))
        r->gl.TexImage3D(target, level, internalformat, width, height, depth, border, format, type, pixels);
}

static void render_CopyTexImage1D(void *self, GLenum target, GLint level, GLenum internalformat, GLint x, GLint y,
                                  GLsizei width, GLint border)
{
    render_spu *r = self;
    if (texture_admit(r, "CopyTexImage1D", target, level, (GLint)internalformat, width, 1, 1, border)) {
        bool began = render_ms_read_begin(r); /* a multisample window is read resolved */
        r->gl.CopyTexImage1D(target, level, internalformat, x, y, width, border);
        render_ms_read_end(r, began);
    }
}

static void render_CopyTexImage2D(void *self, GLenum target, GLint level, GLenum internalformat, GLint x, GLint y,
                                  GLsizei width, GLsizei height, GLint border)
{
    render_spu *r = self;
    if (texture_admit(r, "CopyTexImage2D", target, level, (GLint)internalformat, width, height, 1, border)) {
        bool began = render_ms_read_begin(r); /* a multisample window is read resolved */
        r->gl.CopyTexImage2D(target, level, internalformat, x, y, width, height, border);
        render_ms_read_end(r, began);
    }
}

/* Texture names the client binds or deletes may be ones the fast
 * DrawPixels keeps (drawpixels.h): it lets go of them first. */
static void render_BindTexture(void *self, GLenum target, GLuint texture)
{
    render_spu *r = self;
    render_fastdraw_client_name(r->fastdraw, &r->gl, texture, render_current_scissor(r)->list_mode != 0);
    r->gl.BindTexture(target, texture);
}

static GLboolean render_IsTexture(void *self, GLuint texture)
{
    render_spu *r = self;
    return render_fastdraw_owns(r->fastdraw, texture) ? GL_FALSE : r->gl.IsTexture(texture);
}

static void render_DeleteTextures(void *self, GLsizei n, const GLuint *textures)
{
    render_spu *r = self;
    for (GLsizei i = 0; i < n && textures; i++)
        render_fastdraw_client_name(r->fastdraw, &r->gl, textures[i], false);
    r->gl.DeleteTextures(n, textures);
    for (GLsizei i = 0; i < n && textures; i++)
        render_tex_forget(&r->textures, textures[i]);
}

void render_textures_install(render_spu *r, tsr_dispatch *table)
{
    tsr_set_TexImage1D(table, render_TexImage1D, r);
    tsr_set_TexImage2D(table, render_TexImage2D, r);
    tsr_set_TexImage3D(table, render_TexImage3D, r);
    tsr_set_CopyTexImage1D(table, render_CopyTexImage1D, r);
    tsr_set_CopyTexImage2D(table, render_CopyTexImage2D, r);
    tsr_set_DeleteTextures(table, render_DeleteTextures, r);
    tsr_set_BindTexture(table, render_BindTexture, r);
    tsr_set_IsTexture(table, render_IsTexture, r);
}
