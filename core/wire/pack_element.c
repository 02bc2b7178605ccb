/* core/wire/pack_element.c — glArrayElement for a packer: the element of
 * every enabled client array is read at the call and packed as the
 * immediate-mode command of the array's size and type (glColor4ubv for a
 * GL_UNSIGNED_BYTE colour array of size 4, glFogCoordfv, glIndexsv, ...),
 * the vertex last, as GL defines glArrayElement (GL 2.1 section 2.8) and
 * as Mesa runs it. So the receiver needs no arrays, a box-keeping SPU
 * boxes the vertex, and a display list being compiled keeps the values of
 * the time of the call.
 * The opcode ArrayElement never travels (unpack.c refuses it).
 *
 * Owns nothing. Never reads an array that lives in a buffer object (the
 * receiver has it): such a call is dropped with one message naming it. */
#include <string.h>

#include "tessera/dev/pack.h"
#include "wire_gen.h"
#include "wire_internal.h"

static size_t type_bytes(GLenum type)
{
    switch (type) {
    case GL_BYTE:
    case GL_UNSIGNED_BYTE: return 1;
    case GL_SHORT:
    case GL_UNSIGNED_SHORT: return 2;
    case GL_INT:
    case GL_UNSIGNED_INT:
    case GL_FLOAT: return 4;
    case GL_DOUBLE: return 8;
    default: return 0;
    }
}

/* The element's address, or NULL (disabled, unknown type, no pointer). */
static const void *element(const tsr_client_array *a, GLint i)
{
    size_t tb = type_bytes(a->type);
    if (!a->enabled || !a->pointer || !tb || a->size < 1 || i < 0)
        return NULL;
    size_t stride = a->stride ? (size_t)a->stride : tb * (size_t)a->size;
    return (const uint8_t *)a->pointer + (size_t)i * stride;
}

/* Copies one element into aligned storage (client arrays need not be). */
static const void *aligned(const tsr_client_array *a, const void *e, GLdouble buf[4])
{
    memcpy(buf, e, type_bytes(a->type) * (size_t)(a->size > 4 ? 4 : a->size));
    return buf;
}

static void colour(tsr_packer *p, const tsr_client_array *a, const void *v)
{
    int four = a->size == 4;
    switch (a->type) {
    case GL_BYTE: four ? tsr_pack_Color4bv(p, v) : tsr_pack_Color3bv(p, v); break;
    case GL_UNSIGNED_BYTE: four ? tsr_pack_Color4ubv(p, v) : tsr_pack_Color3ubv(p, v); break;
    case GL_SHORT: four ? tsr_pack_Color4sv(p, v) : tsr_pack_Color3sv(p, v); break;
    case GL_UNSIGNED_SHORT: four ? tsr_pack_Color4usv(p, v) : tsr_pack_Color3usv(p, v); break;
    case GL_INT: four ? tsr_pack_Color4iv(p, v) : tsr_pack_Color3iv(p, v); break;
    case GL_UNSIGNED_INT: four ? tsr_pack_Color4uiv(p, v) : tsr_pack_Color3uiv(p, v); break;
    case GL_FLOAT: four ? tsr_pack_Color4fv(p, v) : tsr_pack_Color3fv(p, v); break;
    default: four ? tsr_pack_Color4dv(p, v) : tsr_pack_Color3dv(p, v); break;
    }
}

static void secondary_colour(tsr_packer *p, const tsr_client_array *a, const void *v)
{
    switch (a->type) {
    case GL_BYTE: tsr_pack_SecondaryColor3bv(p, v); break;
    case GL_UNSIGNED_BYTE: tsr_pack_SecondaryColor3ubv(p, v); break;
    case GL_SHORT: tsr_pack_SecondaryColor3sv(p, v); break;
    case GL_UNSIGNED_SHORT: tsr_pack_SecondaryColor3usv(p, v); break;
    case GL_INT: tsr_pack_SecondaryColor3iv(p, v); break;
    case GL_UNSIGNED_INT: tsr_pack_SecondaryColor3uiv(p, v); break;
    case GL_FLOAT: tsr_pack_SecondaryColor3fv(p, v); break;
    default: tsr_pack_SecondaryColor3dv(p, v); break;
    }
}

static void fog_coord(tsr_packer *p, const tsr_client_array *a, const void *v)
{
    if (a->type == GL_FLOAT)
        tsr_pack_FogCoordfv(p, v);
    else
        tsr_pack_FogCoorddv(p, v);
}

static void colour_index(tsr_packer *p, const tsr_client_array *a, const void *v)
{
    switch (a->type) {
    case GL_UNSIGNED_BYTE: tsr_pack_Indexubv(p, v); break;
    case GL_SHORT: tsr_pack_Indexsv(p, v); break;
    case GL_INT: tsr_pack_Indexiv(p, v); break;
    case GL_FLOAT: tsr_pack_Indexfv(p, v); break;
    default: tsr_pack_Indexdv(p, v); break;
    }
}

static void normal(tsr_packer *p, const tsr_client_array *a, const void *v)
{
    switch (a->type) {
    case GL_BYTE: tsr_pack_Normal3bv(p, v); break;
    case GL_SHORT: tsr_pack_Normal3sv(p, v); break;
    case GL_INT: tsr_pack_Normal3iv(p, v); break;
    case GL_FLOAT: tsr_pack_Normal3fv(p, v); break;
    case GL_DOUBLE: tsr_pack_Normal3dv(p, v); break;
    default: break;
    }
}

#define BY_SIZE(prefix, sfx, ...)                           \
    switch (a->size) {                                      \
    case 1: tsr_pack_##prefix##1##sfx(__VA_ARGS__); break;  \
    case 2: tsr_pack_##prefix##2##sfx(__VA_ARGS__); break;  \
    case 3: tsr_pack_##prefix##3##sfx(__VA_ARGS__); break;  \
    default: tsr_pack_##prefix##4##sfx(__VA_ARGS__); break; \
    }

static void texcoord(tsr_packer *p, const tsr_client_array *a, GLenum unit, const void *v)
{
    switch (a->type) {
    case GL_SHORT: BY_SIZE(MultiTexCoord, sv, p, unit, v) break;
    case GL_INT: BY_SIZE(MultiTexCoord, iv, p, unit, v) break;
    case GL_FLOAT: BY_SIZE(MultiTexCoord, fv, p, unit, v) break;
    case GL_DOUBLE: BY_SIZE(MultiTexCoord, dv, p, unit, v) break;
    default: break;
    }
}

#define VERTEX_BY_SIZE(sfx)                      \
    switch (a->size) {                           \
    case 2: tsr_pack_Vertex2##sfx(p, v); break;  \
    case 3: tsr_pack_Vertex3##sfx(p, v); break;  \
    default: tsr_pack_Vertex4##sfx(p, v); break; \
    }

static void vertex(tsr_packer *p, const tsr_client_array *a, const void *v)
{
    if (a->size < 2)
        return;
    switch (a->type) {
    case GL_SHORT: VERTEX_BY_SIZE(sv) break;
    case GL_INT: VERTEX_BY_SIZE(iv) break;
    case GL_FLOAT: VERTEX_BY_SIZE(fv) break;
    case GL_DOUBLE: VERTEX_BY_SIZE(dv) break;
    default: break;
    }
}

/* A generic attribute as floats: integers normalised the way Mesa's
 * glVertexAttrib4N* does when the array is normalised, else converted. */
static void attrib(tsr_packer *p, const tsr_client_array *a, GLuint index, const void *v)
{
    GLfloat f[4] = {0, 0, 0, 1};
    for (int k = 0; k < a->size && k < 4; k++) {
        double x;
        switch (a->type) {
        case GL_BYTE:
            x = ((const GLbyte *)v)[k];
            x = a->normalized ? (2.0 * x + 1.0) / 255.0 : x;
            break;
        case GL_UNSIGNED_BYTE:
            x = ((const GLubyte *)v)[k];
            x = a->normalized ? x / 255.0 : x;
            break;
        case GL_SHORT:
            x = ((const GLshort *)v)[k];
            x = a->normalized ? (2.0 * x + 1.0) / 65535.0 : x;
            break;
        case GL_UNSIGNED_SHORT:
            x = ((const GLushort *)v)[k];
            x = a->normalized ? x / 65535.0 : x;
            break;
        case GL_INT:
            x = ((const GLint *)v)[k];
            x = a->normalized ? (2.0 * x + 1.0) / 4294967295.0 : x;
            break;
        case GL_UNSIGNED_INT:
            x = ((const GLuint *)v)[k];
            x = a->normalized ? x / 4294967295.0 : x;
            break;
        case GL_FLOAT: x = ((const GLfloat *)v)[k]; break;
        default: x = ((const GLdouble *)v)[k]; break;
        }
        f[k] = (GLfloat)x;
    }
    BY_SIZE(VertexAttrib, fv, p, index, f)
}

static int in_buffer(const tsr_client_array *a) { return a->enabled && a->buffer != 0; }

void tsr_packer_custom_ArrayElement(tsr_packer *p, GLint i)
{
    tsr_client_arrays *arr = &p->arrays;
    int buffered = in_buffer(&arr->vertex) || in_buffer(&arr->normal) || in_buffer(&arr->color) ||
                   in_buffer(&arr->edge_flag) || in_buffer(&arr->secondary_color) || in_buffer(&arr->fog_coord) ||
                   in_buffer(&arr->index);
    for (int u = 0; u < TSR_PACK_TEXUNITS; u++)
        buffered |= in_buffer(&arr->texcoord[u]);
    for (int k = 0; k < TSR_PACK_ATTRIBS; k++)
        buffered |= in_buffer(&arr->attrib[k]);
    if (buffered) {
        tsr_packer_drop(p, "ArrayElement", "an enabled array is in a buffer object (not supported yet)");
        return;
    }
    GLdouble buf[4];
    const void *e;
    if ((e = element(&arr->edge_flag, i)))
        tsr_pack_EdgeFlagv(p, e);
    if ((e = element(&arr->normal, i)))
        normal(p, &arr->normal, aligned(&arr->normal, e, buf));
    if ((e = element(&arr->color, i)))
        colour(p, &arr->color, aligned(&arr->color, e, buf));
    if ((e = element(&arr->secondary_color, i)))
        secondary_colour(p, &arr->secondary_color, aligned(&arr->secondary_color, e, buf));
    if ((e = element(&arr->fog_coord, i)))
        fog_coord(p, &arr->fog_coord, aligned(&arr->fog_coord, e, buf));
    if ((e = element(&arr->index, i)))
        colour_index(p, &arr->index, aligned(&arr->index, e, buf));
    for (int u = 0; u < TSR_PACK_TEXUNITS; u++)
        if ((e = element(&arr->texcoord[u], i)))
            texcoord(p, &arr->texcoord[u], GL_TEXTURE0 + (GLenum)u, aligned(&arr->texcoord[u], e, buf));
    for (int k = 1; k < TSR_PACK_ATTRIBS; k++)
        if ((e = element(&arr->attrib[k], i)))
            attrib(p, &arr->attrib[k], (GLuint)k, aligned(&arr->attrib[k], e, buf));
    /* generic attribute 0 provokes the vertex in place of the vertex array */
    if ((e = element(&arr->attrib[0], i)))
        attrib(p, &arr->attrib[0], 0, aligned(&arr->attrib[0], e, buf));
    else if ((e = element(&arr->vertex, i)))
        vertex(p, &arr->vertex, aligned(&arr->vertex, e, buf));
}
