/* core/wire/pack_mirror.c — the packer's mirrors of client state, per
 * context: pixel store, vertex arrays and their enables, buffer bindings,
 * the client attribute stack, GetPointerv and GetVertexAttribPointerv;
 * swapped at the stream's MakeCurrentTSR and dropped at ContextDestroyTSR.
 * Per stream (a share group's objects): the shader and program names the
 * receiver created. Owns the mirrors' records in the packer. Never: sends a host pointer,
 * aborts (problems are recorded in the packer's error). */
#include "pack_internal.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/map.h"
#include "wire_gen.h"
#include "wire_internal.h"

/* --- mirrors of client state ------------------------------------------------ */

/* The mirrors of the stream's contexts other than the current one. */
typedef struct pack_context_state {
    GLint context;
    tsr_pixel_store pixels;
    tsr_client_arrays arrays;
    uint32_t stack_depth;
    unsigned char stack[sizeof(((tsr_packer *)0)->stack)];
} pack_context_state;

static void pack_mirrors_reset(tsr_packer *p)
{
    tsr_pixel_store_init(&p->pixels);
    memset(&p->arrays, 0, sizeof p->arrays);
    p->stack_depth = 0;
}

void tsr_packer_mirror_MakeCurrent(tsr_packer *p, GLint context)
{
    if (p->context_known && context == p->context)
        return;
    if (p->context_known) {
        pack_context_state *s = tsr_wire_contexts_find(p->contexts, p->context);
        if (!s)
            s = tsr_wire_contexts_add(&p->contexts, p->context, sizeof *s);
        if (!s) {
            pack_record(p, TSR_ENOMEM, "out of memory for context %d's client state", (int)p->context);
            return;
        }
        s->pixels = p->pixels;
        s->arrays = p->arrays;
        s->stack_depth = p->stack_depth;
        memcpy(s->stack, p->stack, sizeof s->stack);
    }
    const pack_context_state *s = tsr_wire_contexts_find(p->contexts, context);
    if (s) {
        p->pixels = s->pixels;
        p->arrays = s->arrays;
        p->stack_depth = s->stack_depth;
        memcpy(p->stack, s->stack, sizeof p->stack);
    } else if (p->context_known) {
        pack_mirrors_reset(p);
    }
    p->context = context;
    p->context_known = 1;
}

void tsr_packer_mirror_ContextDestroy(tsr_packer *p, GLint context)
{
    tsr_wire_contexts_remove(p->contexts, context);
    tsr_wire_selection_forget(p->selection, context);
    if (p->context_known && context == p->context) {
        /* Whatever is made current next starts from GL's initial values
         * or its own saved state. */
        pack_mirrors_reset(p);
        p->context_known = 0;
    }
}

void tsr_packer_mirror_PixelStore(tsr_packer *p, GLenum pname, double value)
{
    tsr_pixel_store_set(&p->pixels, pname, value);
}

void tsr_packer_mirror_BindBuffer(tsr_packer *p, GLenum target, GLuint buffer)
{
    if (target == GL_ARRAY_BUFFER)
        p->arrays.array_buffer = buffer;
    else if (target == GL_ELEMENT_ARRAY_BUFFER)
        p->arrays.element_buffer = buffer;
    else if (target == GL_PIXEL_PACK_BUFFER)
        p->pixels.pack_buffer = buffer;
    else if (target == GL_PIXEL_UNPACK_BUFFER)
        p->pixels.unpack_buffer = buffer;
}

void tsr_packer_mirror_DeleteBuffers(tsr_packer *p, GLsizei n, const GLuint *buffers)
{
    for (GLsizei i = 0; buffers && i < n; i++) {
        if (!buffers[i])
            continue;
        if (buffers[i] == p->arrays.array_buffer)
            p->arrays.array_buffer = 0;
        if (buffers[i] == p->arrays.element_buffer)
            p->arrays.element_buffer = 0;
        if (buffers[i] == p->pixels.pack_buffer)
            p->pixels.pack_buffer = 0;
        if (buffers[i] == p->pixels.unpack_buffer)
            p->pixels.unpack_buffer = 0;
    }
    tsr_packer_forget_mappings(p, n, buffers);
}

static void set_array(tsr_packer *p, tsr_client_array *a, GLint size, GLenum type, GLsizei stride, GLboolean normalized,
                      const void *pointer)
{
    a->size = size;
    a->type = type;
    a->stride = stride;
    a->normalized = normalized != 0;
    a->buffer = p->arrays.array_buffer;
    a->pointer = pointer;
}

void tsr_packer_local_VertexPointer(tsr_packer *p, GLint size, GLenum type, GLsizei stride, const void *pointer)
{
    set_array(p, &p->arrays.vertex, size, type, stride, 0, pointer);
}

void tsr_packer_local_NormalPointer(tsr_packer *p, GLenum type, GLsizei stride, const void *pointer)
{
    set_array(p, &p->arrays.normal, 3, type, stride, 0, pointer);
}

void tsr_packer_local_ColorPointer(tsr_packer *p, GLint size, GLenum type, GLsizei stride, const void *pointer)
{
    set_array(p, &p->arrays.color, size, type, stride, 0, pointer);
}

void tsr_packer_local_TexCoordPointer(tsr_packer *p, GLint size, GLenum type, GLsizei stride, const void *pointer)
{
    if (p->arrays.active_texture < TSR_PACK_TEXUNITS)
        set_array(p, &p->arrays.texcoord[p->arrays.active_texture], size, type, stride, 0, pointer);
}

void tsr_packer_local_EdgeFlagPointer(tsr_packer *p, GLsizei stride, const void *pointer)
{
    set_array(p, &p->arrays.edge_flag, 1, GL_UNSIGNED_BYTE, stride, 0, pointer);
}

void tsr_packer_local_VertexAttribPointer(tsr_packer *p, GLuint index, GLint size, GLenum type, GLboolean normalized,
                                          GLsizei stride, const void *pointer)
{
    if (index < TSR_PACK_ATTRIBS)
        set_array(p, &p->arrays.attrib[index], size, type, stride, normalized, pointer);
}

/* Whether `type` is one GL takes for the array (GL 2.1 table 2.4); a
 * pointer GL refuses raises the error and leaves the array as it was. */
static int pointer_ok(tsr_packer *p, GLenum type, const GLenum *types, size_t ntypes, int size_ok, GLsizei stride)
{
    int known = 0;
    for (size_t i = 0; i < ntypes; i++)
        known |= types[i] == type;
    if (!known) {
        tsr_packer_local_error(p, GL_INVALID_ENUM);
        return 0;
    }
    if (!size_ok || stride < 0) {
        tsr_packer_local_error(p, GL_INVALID_VALUE);
        return 0;
    }
    return 1;
}

void tsr_packer_local_SecondaryColorPointer(tsr_packer *p, GLint size, GLenum type, GLsizei stride, const void *pointer)
{
    static const GLenum types[] = {GL_BYTE, GL_UNSIGNED_BYTE, GL_SHORT, GL_UNSIGNED_SHORT,
                                   GL_INT,  GL_UNSIGNED_INT,  GL_FLOAT, GL_DOUBLE};
    if (pointer_ok(p, type, types, sizeof types / sizeof types[0], size == 3, stride))
        set_array(p, &p->arrays.secondary_color, size, type, stride, 0, pointer);
}

void tsr_packer_local_FogCoordPointer(tsr_packer *p, GLenum type, GLsizei stride, const void *pointer)
{
    static const GLenum types[] = {GL_FLOAT, GL_DOUBLE};
    if (pointer_ok(p, type, types, sizeof types / sizeof types[0], 1, stride))
        set_array(p, &p->arrays.fog_coord, 1, type, stride, 0, pointer);
}

void tsr_packer_local_IndexPointer(tsr_packer *p, GLenum type, GLsizei stride, const void *pointer)
{
    static const GLenum types[] = {GL_UNSIGNED_BYTE, GL_SHORT, GL_INT, GL_FLOAT, GL_DOUBLE};
    if (pointer_ok(p, type, types, sizeof types / sizeof types[0], 1, stride))
        set_array(p, &p->arrays.index, 1, type, stride, 0, pointer);
}

static tsr_client_array *array_of(tsr_packer *p, GLenum array)
{
    switch (array) {
    case GL_VERTEX_ARRAY: return &p->arrays.vertex;
    case GL_NORMAL_ARRAY: return &p->arrays.normal;
    case GL_COLOR_ARRAY: return &p->arrays.color;
    case GL_EDGE_FLAG_ARRAY: return &p->arrays.edge_flag;
    case GL_SECONDARY_COLOR_ARRAY: return &p->arrays.secondary_color;
    case GL_FOG_COORD_ARRAY: return &p->arrays.fog_coord;
    case GL_INDEX_ARRAY: return &p->arrays.index;
    case GL_TEXTURE_COORD_ARRAY:
        return p->arrays.active_texture < TSR_PACK_TEXUNITS ? &p->arrays.texcoord[p->arrays.active_texture] : NULL;
    default: return NULL;
    }
}

int tsr_packer_answer_IsEnabled(tsr_packer *p, GLenum cap, GLboolean *out)
{
    const tsr_client_array *a = array_of(p, cap);
    if (!a && cap != GL_TEXTURE_COORD_ARRAY)
        return 0;
    *out = a && a->enabled ? GL_TRUE : GL_FALSE;
    return 1;
}

/* Which attribute of which array a client-array pname asks for. */
enum { ASK_SIZE, ASK_TYPE, ASK_STRIDE, ASK_BUFFER, ASK_ENABLED };

static const struct {
    GLenum pname, array;
    int ask;
} client_gets[] = {
    {GL_VERTEX_ARRAY_SIZE, GL_VERTEX_ARRAY, ASK_SIZE},
    {GL_VERTEX_ARRAY_TYPE, GL_VERTEX_ARRAY, ASK_TYPE},
    {GL_VERTEX_ARRAY_STRIDE, GL_VERTEX_ARRAY, ASK_STRIDE},
    {GL_VERTEX_ARRAY_BUFFER_BINDING, GL_VERTEX_ARRAY, ASK_BUFFER},
    {GL_NORMAL_ARRAY_TYPE, GL_NORMAL_ARRAY, ASK_TYPE},
    {GL_NORMAL_ARRAY_STRIDE, GL_NORMAL_ARRAY, ASK_STRIDE},
    {GL_NORMAL_ARRAY_BUFFER_BINDING, GL_NORMAL_ARRAY, ASK_BUFFER},
    {GL_COLOR_ARRAY_SIZE, GL_COLOR_ARRAY, ASK_SIZE},
    {GL_COLOR_ARRAY_TYPE, GL_COLOR_ARRAY, ASK_TYPE},
    {GL_COLOR_ARRAY_STRIDE, GL_COLOR_ARRAY, ASK_STRIDE},
    {GL_COLOR_ARRAY_BUFFER_BINDING, GL_COLOR_ARRAY, ASK_BUFFER},
    {GL_EDGE_FLAG_ARRAY_STRIDE, GL_EDGE_FLAG_ARRAY, ASK_STRIDE},
    {GL_EDGE_FLAG_ARRAY_BUFFER_BINDING, GL_EDGE_FLAG_ARRAY, ASK_BUFFER},
    {GL_SECONDARY_COLOR_ARRAY_SIZE, GL_SECONDARY_COLOR_ARRAY, ASK_SIZE},
    {GL_SECONDARY_COLOR_ARRAY_TYPE, GL_SECONDARY_COLOR_ARRAY, ASK_TYPE},
    {GL_SECONDARY_COLOR_ARRAY_STRIDE, GL_SECONDARY_COLOR_ARRAY, ASK_STRIDE},
    {GL_SECONDARY_COLOR_ARRAY_BUFFER_BINDING, GL_SECONDARY_COLOR_ARRAY, ASK_BUFFER},
    {GL_FOG_COORD_ARRAY_TYPE, GL_FOG_COORD_ARRAY, ASK_TYPE},
    {GL_FOG_COORD_ARRAY_STRIDE, GL_FOG_COORD_ARRAY, ASK_STRIDE},
    {GL_FOG_COORD_ARRAY_BUFFER_BINDING, GL_FOG_COORD_ARRAY, ASK_BUFFER},
    {GL_INDEX_ARRAY_TYPE, GL_INDEX_ARRAY, ASK_TYPE},
    {GL_INDEX_ARRAY_STRIDE, GL_INDEX_ARRAY, ASK_STRIDE},
    {GL_INDEX_ARRAY_BUFFER_BINDING, GL_INDEX_ARRAY, ASK_BUFFER},
    {GL_TEXTURE_COORD_ARRAY_SIZE, GL_TEXTURE_COORD_ARRAY, ASK_SIZE},
    {GL_TEXTURE_COORD_ARRAY_TYPE, GL_TEXTURE_COORD_ARRAY, ASK_TYPE},
    {GL_TEXTURE_COORD_ARRAY_STRIDE, GL_TEXTURE_COORD_ARRAY, ASK_STRIDE},
    {GL_TEXTURE_COORD_ARRAY_BUFFER_BINDING, GL_TEXTURE_COORD_ARRAY, ASK_BUFFER},
    {GL_VERTEX_ARRAY, GL_VERTEX_ARRAY, ASK_ENABLED},
    {GL_NORMAL_ARRAY, GL_NORMAL_ARRAY, ASK_ENABLED},
    {GL_COLOR_ARRAY, GL_COLOR_ARRAY, ASK_ENABLED},
    {GL_EDGE_FLAG_ARRAY, GL_EDGE_FLAG_ARRAY, ASK_ENABLED},
    {GL_SECONDARY_COLOR_ARRAY, GL_SECONDARY_COLOR_ARRAY, ASK_ENABLED},
    {GL_FOG_COORD_ARRAY, GL_FOG_COORD_ARRAY, ASK_ENABLED},
    {GL_INDEX_ARRAY, GL_INDEX_ARRAY, ASK_ENABLED},
    {GL_TEXTURE_COORD_ARRAY, GL_TEXTURE_COORD_ARRAY, ASK_ENABLED},
};

/* GL's initial size of an array never given a pointer (GL 2.1 table 6.8). */
static GLint initial_size(GLenum array)
{
    switch (array) {
    case GL_SECONDARY_COLOR_ARRAY: return 3;
    case GL_VERTEX_ARRAY:
    case GL_COLOR_ARRAY:
    case GL_TEXTURE_COORD_ARRAY: return 4;
    default: return 1;
    }
}

int tsr_packer_answer_client_get(tsr_packer *p, GLenum pname, GLenum as, void *data)
{
    double v;
    if (pname == GL_CLIENT_ACTIVE_TEXTURE) {
        v = GL_TEXTURE0 + p->arrays.active_texture;
    } else {
        size_t i = 0, n = sizeof client_gets / sizeof client_gets[0];
        while (i < n && client_gets[i].pname != pname)
            i++;
        if (i == n)
            return 0;
        const tsr_client_array *a = array_of(p, client_gets[i].array);
        /* a mirror never written holds zeros: GL's initial values then */
        int set = a && a->type != 0;
        switch (client_gets[i].ask) {
        case ASK_SIZE: v = set ? a->size : initial_size(client_gets[i].array); break;
        case ASK_TYPE: v = set ? a->type : GL_FLOAT; break;
        case ASK_STRIDE: v = set ? a->stride : 0; break;
        case ASK_BUFFER: v = set ? a->buffer : 0; break;
        default: v = a && a->enabled; break;
        }
    }
    if (!data)
        return 1;
    switch (as) {
    case GL_BOOL: *(GLboolean *)data = v != 0 ? GL_TRUE : GL_FALSE; break;
    case GL_INT: *(GLint *)data = (GLint)v; break;
    case GL_FLOAT: *(GLfloat *)data = (GLfloat)v; break;
    default: *(GLdouble *)data = v; break;
    }
    return 1;
}

void tsr_packer_local_error(tsr_packer *p, GLenum error)
{
    if (!p->local_error)
        p->local_error = error;
}

/* --- the stream's GLSL object names ------------------------------------------- */

struct tsr_packer_glsl_names {
    tsr_name_map kinds; /* name -> (void *)1 shader, (void *)2 program */
    int incomplete;     /* a name was lost to a failed allocation */
};

void tsr_packer_note_glsl_name(tsr_packer *p, GLuint name, int is_program)
{
    if (!name)
        return; /* the receiver refused to create it */
    if (!p->glsl_names)
        p->glsl_names = calloc(1, sizeof *p->glsl_names);
    if (!p->glsl_names)
        return; /* no record at all: the packer cannot tell, and never refuses */
    if (tsr_name_map_put(&p->glsl_names->kinds, name, (void *)(uintptr_t)(is_program ? 2 : 1)) != 0)
        p->glsl_names->incomplete = 1;
}

GLenum tsr_packer_shader_name_error(const tsr_packer *p, GLuint name)
{
    const struct tsr_packer_glsl_names *n = p->glsl_names;
    if (!n || n->incomplete)
        return 0;
    uintptr_t kind = (uintptr_t)tsr_name_map_get(&n->kinds, name);
    return kind == 1 ? 0 : kind == 2 ? GL_INVALID_OPERATION : GL_INVALID_VALUE;
}

void tsr_packer_glsl_names_free(struct tsr_packer_glsl_names *n)
{
    if (!n)
        return;
    tsr_name_map_free(&n->kinds);
    free(n);
}

GLenum tsr_packer_take_local_error(tsr_packer *p)
{
    GLenum e = p->local_error;
    p->local_error = 0;
    return e;
}

int tsr_packer_local_enable_array(tsr_packer *p, GLenum cap, int on)
{
    if (!tsr_wire_is_client_array(cap))
        return 0;
    tsr_client_array *a = array_of(p, cap);
    if (a)
        a->enabled = on != 0;
    return 1;
}

void tsr_packer_local_EnableClientState(tsr_packer *p, GLenum array)
{
    tsr_client_array *a = array_of(p, array);
    if (a)
        a->enabled = 1;
}

void tsr_packer_local_DisableClientState(tsr_packer *p, GLenum array)
{
    tsr_client_array *a = array_of(p, array);
    if (a)
        a->enabled = 0;
}

void tsr_packer_local_EnableVertexAttribArray(tsr_packer *p, GLuint index)
{
    if (index < TSR_PACK_ATTRIBS)
        p->arrays.attrib[index].enabled = 1;
}

void tsr_packer_local_DisableVertexAttribArray(tsr_packer *p, GLuint index)
{
    if (index < TSR_PACK_ATTRIBS)
        p->arrays.attrib[index].enabled = 0;
}

void tsr_packer_local_ClientActiveTexture(tsr_packer *p, GLenum texture)
{
    if (texture >= GL_TEXTURE0 && texture < GL_TEXTURE0 + TSR_PACK_TEXUNITS)
        p->arrays.active_texture = texture - GL_TEXTURE0;
    else /* past GL_MAX_TEXTURE_COORDS (the mirror's units, Mesa's 8): GL's error */
        tsr_packer_local_error(p, GL_INVALID_ENUM);
}

/* glInterleavedArrays (GL 2.1 table 2.5): which arrays a format enables,
 * their sizes and offsets in floats (c = 4 unsigned bytes of color). */
typedef struct interleaved {
    GLenum format;
    int st, sc, sv; /* texcoord, color, vertex sizes (0: absent) */
    GLenum ctype;
    int normal;        /* has a normal */
    int pc, pn, pv, s; /* offsets and stride, in bytes */
} interleaved;

#define F 4
#define C 4
static const interleaved interleaved_formats[] = {
    {GL_V2F, 0, 0, 2, 0, 0, 0, 0, 0, 2 * F},
    {GL_V3F, 0, 0, 3, 0, 0, 0, 0, 0, 3 * F},
    {GL_C4UB_V2F, 0, 4, 2, GL_UNSIGNED_BYTE, 0, 0, 0, C, C + 2 * F},
    {GL_C4UB_V3F, 0, 4, 3, GL_UNSIGNED_BYTE, 0, 0, 0, C, C + 3 * F},
    {GL_C3F_V3F, 0, 3, 3, GL_FLOAT, 0, 0, 0, 3 * F, 6 * F},
    {GL_N3F_V3F, 0, 0, 3, 0, 1, 0, 0, 3 * F, 6 * F},
    {GL_C4F_N3F_V3F, 0, 4, 3, GL_FLOAT, 1, 0, 4 * F, 7 * F, 10 * F},
    {GL_T2F_V3F, 2, 0, 3, 0, 0, 0, 0, 2 * F, 5 * F},
    {GL_T4F_V4F, 4, 0, 4, 0, 0, 0, 0, 4 * F, 8 * F},
    {GL_T2F_C4UB_V3F, 2, 4, 3, GL_UNSIGNED_BYTE, 0, 2 * F, 0, C + 2 * F, C + 5 * F},
    {GL_T2F_C3F_V3F, 2, 3, 3, GL_FLOAT, 0, 2 * F, 0, 5 * F, 8 * F},
    {GL_T2F_N3F_V3F, 2, 0, 3, 0, 1, 0, 2 * F, 5 * F, 8 * F},
    {GL_T2F_C4F_N3F_V3F, 2, 4, 3, GL_FLOAT, 1, 2 * F, 6 * F, 9 * F, 12 * F},
    {GL_T4F_C4F_N3F_V4F, 4, 4, 4, GL_FLOAT, 1, 4 * F, 8 * F, 11 * F, 15 * F},
};
#undef F
#undef C

void tsr_packer_local_InterleavedArrays(tsr_packer *p, GLenum format, GLsizei stride, const void *pointer)
{
    const interleaved *f = NULL;
    for (size_t i = 0; i < sizeof interleaved_formats / sizeof interleaved_formats[0]; i++)
        if (interleaved_formats[i].format == format)
            f = &interleaved_formats[i];
    if (!f || stride < 0) {
        tsr_packer_drop(p, "InterleavedArrays", "unknown format or negative stride");
        return;
    }
    GLsizei s = stride ? stride : f->s;
    const char *base = pointer;
    /* Integer arithmetic: with a bound buffer the pointer is an offset. */
#define AT(off) ((const void *)((uintptr_t)base + (uintptr_t)(off)))
    p->arrays.edge_flag.enabled = 0;
    tsr_client_array *tc = array_of(p, GL_TEXTURE_COORD_ARRAY);
    if (tc) {
        tc->enabled = f->st != 0;
        if (f->st)
            set_array(p, tc, f->st, GL_FLOAT, s, 0, AT(0));
    }
    p->arrays.color.enabled = f->sc != 0;
    if (f->sc)
        set_array(p, &p->arrays.color, f->sc, f->ctype, s, 0, AT(f->pc));
    p->arrays.normal.enabled = f->normal != 0;
    if (f->normal)
        set_array(p, &p->arrays.normal, 3, GL_FLOAT, s, 0, AT(f->pn));
    p->arrays.vertex.enabled = 1;
    set_array(p, &p->arrays.vertex, f->sv, GL_FLOAT, s, 0, AT(f->pv));
#undef AT
}

static const GLenum pixel_pnames[] = {
    GL_PACK_ROW_LENGTH,    GL_PACK_IMAGE_HEIGHT,   GL_PACK_SKIP_PIXELS,   GL_PACK_SKIP_ROWS,
    GL_PACK_SKIP_IMAGES,   GL_PACK_ALIGNMENT,      GL_PACK_SWAP_BYTES,    GL_PACK_LSB_FIRST,
    GL_UNPACK_ROW_LENGTH,  GL_UNPACK_IMAGE_HEIGHT, GL_UNPACK_SKIP_PIXELS, GL_UNPACK_SKIP_ROWS,
    GL_UNPACK_SKIP_IMAGES, GL_UNPACK_ALIGNMENT,    GL_UNPACK_SWAP_BYTES,  GL_UNPACK_LSB_FIRST,
};

void tsr_packer_local_PushClientAttrib(tsr_packer *p, GLbitfield mask)
{
    if (p->stack_depth >= TSR_PACK_STACK) {
        pack_record(p, TSR_ESTATE, "glPushClientAttrib: stack overflow (depth %d)", TSR_PACK_STACK);
        return;
    }
    p->stack[p->stack_depth].mask = mask;
    p->stack[p->stack_depth].pixels = p->pixels;
    p->stack[p->stack_depth].arrays = p->arrays;
    p->stack_depth++;
}

void tsr_packer_local_PopClientAttrib(tsr_packer *p)
{
    if (!p->stack_depth) {
        pack_record(p, TSR_ESTATE, "glPopClientAttrib: stack underflow");
        return;
    }
    p->stack_depth--;
    uint32_t mask = p->stack[p->stack_depth].mask;
    /* The server never sees Push/PopClientAttrib: send what the pop changes
     * in state it does see (pixel store, buffer bindings). */
    if (mask & GL_CLIENT_PIXEL_STORE_BIT) {
        tsr_pixel_store old = p->pixels;
        const tsr_pixel_store *saved = &p->stack[p->stack_depth].pixels;
        for (size_t i = 0; i < sizeof pixel_pnames / sizeof pixel_pnames[0]; i++) {
            int32_t v = tsr_pixel_store_get(saved, pixel_pnames[i]);
            if (v != tsr_pixel_store_get(&old, pixel_pnames[i]))
                tsr_pack_PixelStorei(p, pixel_pnames[i], v);
        }
        p->pixels = *saved;
    }
    if (mask & GL_CLIENT_VERTEX_ARRAY_BIT) {
        tsr_client_arrays *saved = &p->stack[p->stack_depth].arrays;
        if (saved->array_buffer != p->arrays.array_buffer)
            tsr_pack_BindBuffer(p, GL_ARRAY_BUFFER, saved->array_buffer);
        if (saved->element_buffer != p->arrays.element_buffer)
            tsr_pack_BindBuffer(p, GL_ELEMENT_ARRAY_BUFFER, saved->element_buffer);
        p->arrays = *saved;
    }
}

void tsr_packer_local_GetPointerv(tsr_packer *p, GLenum pname, void **params)
{
    if (tsr_packer_answer_GetPointerv(p, pname, params))
        return;
    const tsr_client_array *a = NULL;
    switch (pname) {
    case GL_VERTEX_ARRAY_POINTER: a = &p->arrays.vertex; break;
    case GL_NORMAL_ARRAY_POINTER: a = &p->arrays.normal; break;
    case GL_COLOR_ARRAY_POINTER: a = &p->arrays.color; break;
    case GL_EDGE_FLAG_ARRAY_POINTER: a = &p->arrays.edge_flag; break;
    case GL_SECONDARY_COLOR_ARRAY_POINTER: a = &p->arrays.secondary_color; break;
    case GL_FOG_COORD_ARRAY_POINTER: a = &p->arrays.fog_coord; break;
    case GL_INDEX_ARRAY_POINTER: a = &p->arrays.index; break;
    case GL_TEXTURE_COORD_ARRAY_POINTER: a = array_of(p, GL_TEXTURE_COORD_ARRAY); break;
    default: break;
    }
    if (params)
        *params = a ? (void *)a->pointer : NULL;
}

/* The program's own pointer (or buffer offset) as it gave it: the
 * receiver never saw it. Errors as Mesa raises them. */
void tsr_packer_local_GetVertexAttribPointerv(tsr_packer *p, GLuint index, GLenum pname, void **pointer)
{
    if (index >= TSR_PACK_ATTRIBS) {
        tsr_packer_local_error(p, GL_INVALID_VALUE);
        return;
    }
    if (pname != GL_VERTEX_ATTRIB_ARRAY_POINTER) {
        tsr_packer_local_error(p, GL_INVALID_ENUM);
        return;
    }
    if (pointer)
        *pointer = (void *)p->arrays.attrib[index].pointer;
}
