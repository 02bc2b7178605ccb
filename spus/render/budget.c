/* spus/render/budget.c — the table of texture images behind render's
 * texture budget (budget.h). A flat array: images are specified rarely
 * (uploads, not draws) and every one costs at least RENDER_TEX_MIN_BYTES,
 * so a budget bounds the count. */
#include "budget.h"

#include <GL/glext.h>
#include <stdlib.h>

static uint64_t texel_bytes(GLint internalformat)
{
    switch (internalformat) {
    case GL_RGBA32F:
    case GL_RGB32F:
    case GL_RGBA32UI:
    case GL_RGBA32I:
    case GL_RGB32UI:
    case GL_RGB32I: return 16;
    case GL_RGBA16:
    case GL_RGB16:
    case GL_RGBA16F:
    case GL_RGB16F:
    case GL_RG32F:
    case GL_LUMINANCE_ALPHA32F_ARB:
    case GL_DEPTH32F_STENCIL8:
    case GL_RGBA16UI:
    case GL_RGBA16I: return 8;
    default: return 4;
    }
}

uint64_t render_tex_image_bytes(GLint internalformat, int64_t width, int64_t height, int64_t depth)
{
    if (width < 0 || height < 0 || depth < 0)
        return 0; /* GL refuses it and allocates nothing */
    /* At most 2^17 per side (GL's limits are far below): no overflow. */
    uint64_t w = width > (1 << 17) ? (1 << 17) : (uint64_t)width;
    uint64_t h = height > (1 << 17) ? (1 << 17) : (uint64_t)height;
    uint64_t d = depth > (1 << 17) ? (1 << 17) : (uint64_t)depth;
    uint64_t bytes = w * h * d * texel_bytes(internalformat);
    return bytes < RENDER_TEX_MIN_BYTES ? RENDER_TEX_MIN_BYTES : bytes;
}

uint64_t render_tex_held(const render_tex_table *t, GLint owner)
{
    uint64_t sum = 0;
    for (size_t i = 0; i < t->count; i++)
        if (t->images[i].owner == owner)
            sum += t->images[i].bytes;
    return sum;
}

render_tex_image *render_tex_find(render_tex_table *t, GLuint name, GLint owner, GLenum face, GLint level)
{
    for (size_t i = 0; i < t->count; i++) {
        render_tex_image *m = &t->images[i];
        if (m->name == name && m->face == face && m->level == level && (name != 0 || m->owner == owner))
            return m;
    }
    return NULL;
}

int render_tex_set(render_tex_table *t, GLuint name, GLint owner, GLenum face, GLint level, uint64_t bytes)
{
    render_tex_image *m = render_tex_find(t, name, owner, face, level);
    if (!m) {
        if (t->count == t->cap) {
            size_t cap = t->cap ? 2 * t->cap : 16;
            render_tex_image *grown = realloc(t->images, cap * sizeof *grown);
            if (!grown)
                return -1;
            t->images = grown;
            t->cap = cap;
        }
        m = &t->images[t->count++];
    }
    *m = (render_tex_image){.name = name, .owner = owner, .face = face, .level = level, .bytes = bytes};
    return 0;
}

static void forget_if(render_tex_table *t, GLuint name, GLint owner, int by_owner)
{
    for (size_t i = 0; i < t->count;) {
        const render_tex_image *m = &t->images[i];
        if (by_owner ? (m->name == 0 && m->owner == owner) : (m->name == name))
            t->images[i] = t->images[--t->count];
        else
            i++;
    }
}

void render_tex_forget(render_tex_table *t, GLuint name)
{
    if (name)
        forget_if(t, name, 0, 0);
}

void render_tex_forget_owner_defaults(render_tex_table *t, GLint owner) { forget_if(t, 0, owner, 1); }

void render_tex_free(render_tex_table *t)
{
    free(t->images);
    *t = (render_tex_table){0};
}
