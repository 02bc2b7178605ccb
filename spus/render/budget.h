/* spus/render/budget.h — the texture bytes each context of a render
 * instance holds, for its per-client budget (docs/render.md, "Budgets"):
 * a table of texture images (texture name, face, mipmap level) with the
 * bytes their storage takes and the context that specified them.
 * Owns only that table. Never calls GL (render.c asks GL which texture is
 * bound and passes names in) and never decides what to refuse: it answers
 * what an image would cost and what a context holds. */
#ifndef RENDER_BUDGET_H
#define RENDER_BUDGET_H

#include <stddef.h>
#include <stdint.h>

#include <GL/gl.h>

typedef struct render_tex_image {
    GLuint name; /* texture object; 0 = a context's default texture */
    GLint owner; /* context that specified it (render context id) */
    GLenum face; /* TexImage target: GL_TEXTURE_2D, a cube face, ... */
    GLint level; /* mipmap level */
    uint64_t bytes;
} render_tex_image;

typedef struct render_tex_table {
    render_tex_image *images;
    size_t count, cap;
} render_tex_table;

/* Storage bytes of a width x height x depth image (border included) of
 * `internalformat`, as an estimate of what the driver allocates: texels
 * of at least 4 bytes, 8 for 16-bit and 16 for 32-bit float formats, and
 * at least RENDER_TEX_MIN_BYTES per image (every image has a cost, so the
 * table stays small). */
#define RENDER_TEX_MIN_BYTES 256u
uint64_t render_tex_image_bytes(GLint internalformat, int64_t width, int64_t height, int64_t depth);

/* Bytes context `owner` holds. */
uint64_t render_tex_held(const render_tex_table *t, GLint owner);
/* The image (name, face, level; and owner for name 0) or NULL. */
render_tex_image *render_tex_find(render_tex_table *t, GLuint name, GLint owner, GLenum face, GLint level);
/* Records that the image now takes `bytes` for `owner` (replacing what it
 * took). Returns 0, or -1 when out of memory (nothing recorded). */
int render_tex_set(render_tex_table *t, GLuint name, GLint owner, GLenum face, GLint level, uint64_t bytes);
/* Forgets every image of texture `name` (glDeleteTextures). */
void render_tex_forget(render_tex_table *t, GLuint name);
/* Forgets the default-texture images of context `owner` (it is gone). */
void render_tex_forget_owner_defaults(render_tex_table *t, GLint owner);
void render_tex_free(render_tex_table *t);

#endif
