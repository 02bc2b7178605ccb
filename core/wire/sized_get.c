/* core/wire/sized_get.c — the gets whose answer has a size only the
 * receiver's GL state decides (format in tessera/dev/wire.h):
 * glGetMap{d,f,i}v (the evaluator map's order), glGetPixelMap{f,ui,us}v
 * (the pixel map's size), glGetUniform{f,i}v (the uniform's type) and
 * glGetCompressedTexImage (the level's compressed size).
 *
 * The program's buffer is as large as its GL says, which the sender cannot
 * know, so the receiver works the size out from its own GL with queries
 * that cannot raise an error of their own (each is asked only when its
 * arguments are valid, so the error the program sees is the one its call
 * raises), makes the call into a buffer of that size and answers with the
 * values its GL wrote; the packer copies them into the program's buffer.
 *
 * Owns nothing. Never writes a program's buffer with a reply whose length
 * is not a whole number of the command's values; never asks the receiving
 * GL a question that could leave an error flag the program did not cause;
 * never sends a host pointer (a pack buffer bound to GL_PIXEL_PACK_BUFFER
 * makes glGetPixelMap* and glGetCompressedTexImage write into the
 * receiver's buffer, which no request carries: refused as the other
 * read-backs are). */
#include <stdio.h>
#include <string.h>

#include "pack_internal.h"
#include "tessera/dev/wire.h"
#include "wire_gen.h"
#include "wire_internal.h"

#define BAD(...) return tsr_error_set(err, TSR_EPROTO, __VA_ARGS__)

/* Every sized get carries the same 16 bytes: two u32 arguments (the second
 * 0 for glGetPixelMap*), the request id and 0. */
enum { SIZED_GET_BYTES = 16 };

/* The largest answer a uniform has: a mat4 (or dmat4) is 16 values. */
enum { UNIFORM_MAX_VALUES = 16 };

/* --- packer ------------------------------------------------------------------ */

/* Sends the request and copies the receiver's values (each `value_size`
 * bytes, at most `max_values` of them when that is not 0) into `out`. */
static void sized_get(tsr_packer *p, uint32_t opcode, const char *name, uint32_t a, uint32_t b, void *out,
                      size_t value_size, uint64_t max_values)
{
    uint32_t id = p->next_request++;
    uint8_t *d = tsr_packer_cmd_var(p, opcode, SIZED_GET_BYTES, 8);
    if (!d)
        return;
    tsr_wire_put_u32(d, a);
    tsr_wire_put_u32(d + 4, b);
    tsr_wire_put_u32(d + 8, id);
    tsr_wire_put_u32(d + 12, 0);
    size_t rsize = 0, pos = 0;
    uint64_t len;
    const uint8_t *r = tsr_packer_request(p, id, &rsize);
    if (!r)
        return;
    const uint8_t *values = tsr_packer_reply_item(p, r, rsize, &pos, &len, name);
    if (!values)
        return;
    if (len % value_size || (max_values && len / value_size > max_values)) {
        char why[96];
        snprintf(why, sizeof why, "%llu bytes are not a whole number of %zu-byte values (at most %llu)",
                 (unsigned long long)len, value_size, (unsigned long long)max_values);
        tsr_packer_reply_bad(p, name, why);
        return;
    }
    if (out && len)
        memcpy(out, values, (size_t)len);
}

void tsr_packer_custom_GetMapdv(tsr_packer *p, GLenum target, GLenum query, GLdouble *v)
{
    sized_get(p, TSR_OP_GetMapdv, "GetMapdv", target, query, v, sizeof *v, 0);
}

void tsr_packer_custom_GetMapfv(tsr_packer *p, GLenum target, GLenum query, GLfloat *v)
{
    sized_get(p, TSR_OP_GetMapfv, "GetMapfv", target, query, v, sizeof *v, 0);
}

void tsr_packer_custom_GetMapiv(tsr_packer *p, GLenum target, GLenum query, GLint *v)
{
    sized_get(p, TSR_OP_GetMapiv, "GetMapiv", target, query, v, sizeof *v, 0);
}

void tsr_packer_custom_GetPixelMapfv(tsr_packer *p, GLenum map, GLfloat *values)
{
    if (!tsr_packer_get_into_pack_buffer(p, TSR_OP_GetPixelMapfv, (const GLint[]){(GLint)map}, 1, values))
        sized_get(p, TSR_OP_GetPixelMapfv, "GetPixelMapfv", map, 0, values, sizeof *values, 0);
}

void tsr_packer_custom_GetPixelMapuiv(tsr_packer *p, GLenum map, GLuint *values)
{
    if (!tsr_packer_get_into_pack_buffer(p, TSR_OP_GetPixelMapuiv, (const GLint[]){(GLint)map}, 1, values))
        sized_get(p, TSR_OP_GetPixelMapuiv, "GetPixelMapuiv", map, 0, values, sizeof *values, 0);
}

void tsr_packer_custom_GetPixelMapusv(tsr_packer *p, GLenum map, GLushort *values)
{
    if (!tsr_packer_get_into_pack_buffer(p, TSR_OP_GetPixelMapusv, (const GLint[]){(GLint)map}, 1, values))
        sized_get(p, TSR_OP_GetPixelMapusv, "GetPixelMapusv", map, 0, values, sizeof *values, 0);
}

void tsr_packer_custom_GetUniformfv(tsr_packer *p, GLuint program, GLint location, GLfloat *params)
{
    sized_get(p, TSR_OP_GetUniformfv, "GetUniformfv", program, (uint32_t)location, params, sizeof *params,
              UNIFORM_MAX_VALUES);
}

void tsr_packer_custom_GetUniformiv(tsr_packer *p, GLuint program, GLint location, GLint *params)
{
    sized_get(p, TSR_OP_GetUniformiv, "GetUniformiv", program, (uint32_t)location, params, sizeof *params,
              UNIFORM_MAX_VALUES);
}

void tsr_packer_custom_GetCompressedTexImage(tsr_packer *p, GLenum target, GLint level, void *img)
{
    if (!tsr_packer_get_into_pack_buffer(p, TSR_OP_GetCompressedTexImage, (const GLint[]){(GLint)target, level}, 2,
                                         img))
        sized_get(p, TSR_OP_GetCompressedTexImage, "GetCompressedTexImage", target, (uint32_t)level, img, 1, 0);
}

/* --- the receiver's sizes ------------------------------------------------------ */

/* How many values an evaluator map `target` has per control point, and
 * whether it is two-dimensional; 0 for a name that is no map. */
static int map_components(GLenum target, int *dims)
{
    static const int components[9] = {4, 1, 3, 1, 2, 3, 4, 3, 4}; /* COLOR_4 .. VERTEX_4 */
    if (target >= GL_MAP1_COLOR_4 && target <= GL_MAP1_VERTEX_4) {
        *dims = 1;
        return components[target - GL_MAP1_COLOR_4];
    }
    if (target >= GL_MAP2_COLOR_4 && target <= GL_MAP2_VERTEX_4) {
        *dims = 2;
        return components[target - GL_MAP2_COLOR_4];
    }
    return 0;
}

static uint64_t map_values(const tsr_dispatch *d, GLenum target, GLenum query)
{
    int dims = 0;
    int k = map_components(target, &dims);
    if (!k)
        return 0;
    switch (query) {
    case GL_ORDER: return (uint64_t)dims;
    case GL_DOMAIN: return 2u * (uint64_t)dims;
    case GL_COEFF: {
        GLint order[2] = {0, 1};
        tsr_call_GetMapiv(d, target, GL_ORDER, order);
        if (order[0] < 0 || order[1] < 0)
            return 0;
        return (uint64_t)order[0] * (uint64_t)(dims == 2 ? order[1] : 1) * (uint64_t)k;
    }
    default: return 0;
    }
}

static uint64_t pixel_map_values(const tsr_dispatch *d, GLenum map)
{
    if (map < GL_PIXEL_MAP_I_TO_I || map > GL_PIXEL_MAP_A_TO_A)
        return 0;
    /* Each map's size query is the map's name plus 0x40 (GL_PIXEL_MAP_I_TO_I_SIZE ...). */
    GLint size = 0;
    tsr_call_GetIntegerv(d, map + (GL_PIXEL_MAP_I_TO_I_SIZE - GL_PIXEL_MAP_I_TO_I), &size);
    return size > 0 ? (uint64_t)size : 0;
}

/* Values of one uniform of GL type `type`: every type the list does not
 * name (samplers, images) is one value. */
static uint64_t uniform_type_values(GLenum type)
{
    switch (type) {
    case GL_FLOAT_VEC2:
    case GL_INT_VEC2:
    case GL_BOOL_VEC2:
    case GL_UNSIGNED_INT_VEC2:
    case GL_DOUBLE_VEC2: return 2;
    case GL_FLOAT_VEC3:
    case GL_INT_VEC3:
    case GL_BOOL_VEC3:
    case GL_UNSIGNED_INT_VEC3:
    case GL_DOUBLE_VEC3: return 3;
    case GL_FLOAT_VEC4:
    case GL_INT_VEC4:
    case GL_BOOL_VEC4:
    case GL_UNSIGNED_INT_VEC4:
    case GL_DOUBLE_VEC4:
    case GL_FLOAT_MAT2:
    case GL_DOUBLE_MAT2: return 4;
    case GL_FLOAT_MAT2x3:
    case GL_FLOAT_MAT3x2:
    case GL_DOUBLE_MAT2x3:
    case GL_DOUBLE_MAT3x2: return 6;
    case GL_FLOAT_MAT2x4:
    case GL_FLOAT_MAT4x2:
    case GL_DOUBLE_MAT2x4:
    case GL_DOUBLE_MAT4x2: return 8;
    case GL_FLOAT_MAT3:
    case GL_DOUBLE_MAT3: return 9;
    case GL_FLOAT_MAT3x4:
    case GL_FLOAT_MAT4x3:
    case GL_DOUBLE_MAT3x4:
    case GL_DOUBLE_MAT4x3: return 12;
    case GL_FLOAT_MAT4:
    case GL_DOUBLE_MAT4: return 16;
    default: return 1;
    }
}

/* The values of the uniform at `location` of a linked `program`: the
 * active uniform (or array element) whose location it is. 0 when the
 * program is none or not linked, or no uniform has that location: GL then
 * raises the call's error itself and writes nothing. */
static uint64_t uniform_values(const tsr_dispatch *d, GLuint program, GLint location)
{
    if (location < 0 || !tsr_call_IsProgram(d, program))
        return 0;
    GLint linked = 0, count = 0, longest = 0;
    tsr_call_GetProgramiv(d, program, GL_LINK_STATUS, &linked);
    if (!linked)
        return 0;
    tsr_call_GetProgramiv(d, program, GL_ACTIVE_UNIFORMS, &count);
    tsr_call_GetProgramiv(d, program, GL_ACTIVE_UNIFORM_MAX_LENGTH, &longest);
    char name[512], element[540];
    if (longest <= 0 || longest > (GLint)sizeof name)
        longest = (GLint)sizeof name;
    for (GLint i = 0; i < count; i++) {
        GLsizei length = 0;
        GLint size = 0;
        GLenum type = 0;
        tsr_call_GetActiveUniform(d, program, (GLuint)i, longest, &length, &size, &type, name);
        name[length >= 0 && length < longest ? length : longest - 1] = '\0';
        char *bracket = strstr(name, "[0]"); /* an array's name ends in [0] */
        if (bracket && bracket[3] == '\0')
            *bracket = '\0';
        for (GLint e = 0; e < size; e++) {
            if (size > 1 || bracket)
                snprintf(element, sizeof element, "%s[%d]", name, e);
            else
                snprintf(element, sizeof element, "%s", name);
            if (tsr_call_GetUniformLocation(d, program, element) == location)
                return uniform_type_values(type);
        }
    }
    return 0;
}

static int is_texture_image_target(GLenum target)
{
    return target == GL_TEXTURE_1D || target == GL_TEXTURE_2D || target == GL_TEXTURE_3D ||
           (target >= GL_TEXTURE_CUBE_MAP_POSITIVE_X && target <= GL_TEXTURE_CUBE_MAP_NEGATIVE_Z);
}

static uint64_t compressed_image_bytes(const tsr_dispatch *d, GLenum target, GLint level)
{
    if (!is_texture_image_target(target) || level < 0 || level > 31)
        return 0;
    GLint compressed = 0, size = 0;
    tsr_call_GetTexLevelParameteriv(d, target, level, GL_TEXTURE_COMPRESSED, &compressed);
    if (!compressed)
        return 0;
    tsr_call_GetTexLevelParameteriv(d, target, level, GL_TEXTURE_COMPRESSED_IMAGE_SIZE, &size);
    return size > 0 ? (uint64_t)size : 0;
}

/* --- unpacker ---------------------------------------------------------------- */

typedef struct sized_request {
    uint32_t a, b, id;
    size_t at;
} sized_request;

static int read_request(const uint8_t *b, size_t len, size_t *pos, const char *name, sized_request *q, tsr_error *err)
{
    size_t at = (size_t)tsr_wire_align8(*pos);
    if (at > len || len - at < SIZED_GET_BYTES)
        BAD("command %s at data offset %zu: truncated", name, *pos);
    q->a = tsr_wire_get_u32(b + at);
    q->b = tsr_wire_get_u32(b + at + 4);
    q->id = tsr_wire_get_u32(b + at + 8);
    q->at = at;
    *pos = at + SIZED_GET_BYTES;
    return 0;
}

/* Space for `values` values of `value_size` bytes, never less than 16 of
 * them, so that a GL that writes where the receiver counted none (a name
 * tessera does not know yet) writes into its own memory. */
static uint8_t *answer_space(tsr_unpacker *u, const char *name, const sized_request *q, uint64_t values,
                             size_t value_size, tsr_error *err)
{
    uint64_t sizes[1] = {(values < 16 ? 16 : values) * value_size};
    uint8_t *ptrs[1];
    if (values > UINT64_MAX / 8 / value_size || tsr_unpacker_outputs(u, 1, sizes, ptrs) != 0) {
        tsr_error_set(err, TSR_EPROTO, "command %s at data offset %zu: an answer of %llu values is too large", name,
                      q->at, (unsigned long long)values);
        return NULL;
    }
    return ptrs[0];
}

static int answer(tsr_unpacker *u, const sized_request *q, uint64_t bytes, uint8_t *space, tsr_error *err)
{
    if (!u->reply)
        return 0;
    uint64_t sizes[1] = {bytes};
    uint8_t *ptrs[1] = {space};
    return tsr_unpacker_reply(u, q->id, NULL, TSR_WIRE_NULL, 1, sizes, ptrs, err);
}

/* One unpacker per command: read the request, size the answer from the
 * receiver's state, make the call, answer. */
#define SIZED_UNPACK(Name, Type, count_expr, call_expr)                                                       \
    int tsr_unpack_custom_##Name(struct tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len, \
                                 size_t *pos, tsr_error *err)                                                 \
    {                                                                                                         \
        sized_request q;                                                                                      \
        if (read_request(b, len, pos, #Name, &q, err) != 0)                                                   \
            return TSR_EPROTO;                                                                                \
        uint64_t values = (count_expr);                                                                       \
        uint8_t *space = answer_space(u, #Name, &q, values, sizeof(Type), err);                               \
        if (!space)                                                                                           \
            return TSR_EPROTO;                                                                                \
        call_expr;                                                                                            \
        return answer(u, &q, values * sizeof(Type), space, err);                                              \
    }

SIZED_UNPACK(GetMapdv, GLdouble, map_values(d, q.a, q.b), tsr_call_GetMapdv(d, q.a, q.b, (GLdouble *)space))
SIZED_UNPACK(GetMapfv, GLfloat, map_values(d, q.a, q.b), tsr_call_GetMapfv(d, q.a, q.b, (GLfloat *)space))
SIZED_UNPACK(GetMapiv, GLint, map_values(d, q.a, q.b), tsr_call_GetMapiv(d, q.a, q.b, (GLint *)space))
SIZED_UNPACK(GetPixelMapfv, GLfloat, pixel_map_values(d, q.a), tsr_call_GetPixelMapfv(d, q.a, (GLfloat *)space))
SIZED_UNPACK(GetPixelMapuiv, GLuint, pixel_map_values(d, q.a), tsr_call_GetPixelMapuiv(d, q.a, (GLuint *)space))
SIZED_UNPACK(GetPixelMapusv, GLushort, pixel_map_values(d, q.a), tsr_call_GetPixelMapusv(d, q.a, (GLushort *)space))
SIZED_UNPACK(GetUniformfv, GLfloat, uniform_values(d, q.a, (GLint)q.b),
             tsr_call_GetUniformfv(d, q.a, (GLint)q.b, (GLfloat *)space))
SIZED_UNPACK(GetUniformiv, GLint, uniform_values(d, q.a, (GLint)q.b),
             tsr_call_GetUniformiv(d, q.a, (GLint)q.b, (GLint *)space))
SIZED_UNPACK(GetCompressedTexImage, GLubyte, compressed_image_bytes(d, q.a, (GLint)q.b),
             tsr_call_GetCompressedTexImage(d, q.a, (GLint)q.b, space))
