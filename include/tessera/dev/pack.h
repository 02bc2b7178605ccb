/* tessera/dev/pack.h — the packer: turns GL calls into wire buffers
 * (tessera/dev/wire.h) and hands full buffers to a sink. For an SPU that
 * sends a GL stream anywhere (a socket, a file, a display-list body): pack,
 * replicate and tilesort pack through it, and the stream client
 * (tessera/dev/client.h) is a packer whose sink is the network.
 * Part of libtessera (pkg-config tessera).
 *
 * Owns: its buffer memory, the object-space bounding box of the vertices
 * packed since the last flush, and mirrors of the client state (pixel
 * store, vertex arrays, buffer bindings) needed to size payloads. No
 * globals: every packer is a caller-owned object, used by one thread.
 * Never: sends a host pointer, splits one command across buffers, or
 * blocks except inside the sink.
 *
 * Typical use (an SPU that sends):
 *
 *   static int my_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err) {
 *       return my_send(ctx, buf, size, err);   // copy: buf is valid during the call only
 *   }
 *   tsr_pack_sink sink = {.flush = my_flush, .ctx = m};
 *   tsr_packer *p = tsr_packer_create(1 << 20, &sink, &err);
 *   tsr_packer_fill_dispatch(p, init->table);  // every slot packs (self = p)
 *   ... GL calls arrive through the table ...
 *   tsr_packer_flush(p);                       // also done when a buffer fills
 *   if (tsr_packer_error(p)->code) ...         // dropped commands, failed flushes
 *   tsr_packer_destroy(p);
 *
 * The packing function of each command is generated from the spec and
 * reached through the table; the functions under "for generated code"
 * below are what the inline fast paths of this header call. */
#ifndef TESSERA_DEV_PACK_H
#define TESSERA_DEV_PACK_H

#include <stddef.h>
#include <stdint.h>
#include <GL/gl.h>
#include "tessera/dispatch.h"
#include "tessera/error.h"
#include "tessera/export.h"
#include "tessera/dev/pixel.h"
#include "tessera/dev/wire.h"
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Where buffers go. flush: one complete buffer [buf, buf+size) (valid only
 * during the call; copy it to keep it). reply: after a request was flushed,
 * return the reply bytes of request `id` (tessera/dev/wire.h section 5), valid
 * until the next call into the sink; NULL when the sink cannot answer.
 * reply_failed (optional): the reply `reply` returned for request `id` did
 * not decode (truncated, an item of the wrong size): whoever answered sent
 * a malformed reply, and the call it answered returned zeros. */
typedef struct tsr_pack_sink {
    int (*flush)(void *ctx, const uint8_t *buf, size_t size, tsr_error *err);
    int (*reply)(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err);
    void *ctx;
    void (*reply_failed)(void *ctx, uint32_t id, const tsr_error *why);
} tsr_pack_sink;

#define TSR_PACK_MIN_BUFFER 256u
#define TSR_PACK_MAX_FIXED 256u /* largest fixed-size command (generator checks) */
#define TSR_PACK_TEXUNITS 8
#define TSR_PACK_ATTRIBS 16
#define TSR_PACK_STACK 16
/* every client array a draw may read: the seven of the fixed function,
 * a texture coordinate array per unit, a generic attribute array each */
#define TSR_PACK_ARRAYS (7 + TSR_PACK_TEXUNITS + TSR_PACK_ATTRIBS)

typedef struct tsr_client_array {
    uint8_t enabled, normalized;
    int32_t size;
    GLenum type;
    int32_t stride;
    GLuint buffer;       /* GL_ARRAY_BUFFER binding when the pointer was set */
    const void *pointer; /* client address, or offset into `buffer` */
} tsr_client_array;

typedef struct tsr_client_arrays {
    tsr_client_array vertex, normal, color, edge_flag;
    tsr_client_array secondary_color, fog_coord, index; /* GL 1.4, 1.4, 1.1 */
    tsr_client_array texcoord[TSR_PACK_TEXUNITS];
    tsr_client_array attrib[TSR_PACK_ATTRIBS];
    uint32_t active_texture; /* unit index of ClientActiveTexture */
    GLuint array_buffer, element_buffer;
} tsr_client_arrays;

typedef struct tsr_packer {
    /* Hot fields first: one cache line for the Vertex3f path. */
    uint8_t *op;       /* the next opcode goes to op[-1] */
    uint8_t *op_limit; /* lowest opcode address of this buffer */
    uint8_t *data;     /* next data byte */
    uint8_t *data_end; /* end of the data area (8-aligned) */
    float bbox_min[4] __attribute__((aligned(16)));
    float bbox_max[4] __attribute__((aligned(16)));
    uint32_t bbox_nan; /* non-zero once a NaN coordinate was boxed */
    uint8_t *mid;      /* data start (8-aligned) */
    uint8_t *mem;      /* normal buffer memory */
    size_t mem_size;
    uint8_t *big; /* an oversized single-command buffer, or NULL */
    size_t op_room, data_room;
    tsr_pack_sink sink;
    tsr_pixel_store pixels;
    tsr_client_arrays arrays;
    struct {
        uint32_t mask;
        tsr_pixel_store pixels;
        tsr_client_arrays arrays;
    } stack[TSR_PACK_STACK];
    uint32_t stack_depth;
    uint32_t next_request;
    uint32_t reply_id; /* the request whose reply is being decoded */
    char **strings;    /* GetString results, owned; freed on destroy */
    size_t nstrings;
    tsr_error error; /* first error (sticky until tsr_packer_clear_error) */
    uint64_t buffers_sent, bytes_sent, commands_dropped;
    uint8_t discard[TSR_PACK_MAX_FIXED] __attribute__((aligned(16)));
    /* The mirrors above are the current context's: a share group's
     * contexts travel in one stream, and each keeps its own pixel store
     * and client arrays, swapped at MakeCurrentTSR (pack.c). */
    int32_t context;   /* the stream's current context, once context_known */
    int context_known; /* a MakeCurrentTSR was packed */
    struct tsr_wire_contexts *contexts;
    /* glMapBuffer's and glMapBufferRange's client copies, one per mapped
     * buffer object (pack_map.c) */
    struct tsr_packer_mapping {
        GLbitfield access; /* GL_MAP_*_BIT (glMapBuffer's access as Mesa turns it into bits) */
        GLuint buffer;     /* the buffer object mapped (GL maps an object, not a target) */
        GLintptr offset;   /* the range mapped: `length` bytes from `offset` */
        GLsizeiptr length;
        void *data; /* the copy of that range; NULL: the slot is free */
    } mapped[4];
    GLenum local_error; /* an error found here, for the next glGetError (pack.c) */
    /* the program's selection and feedback buffers and the render mode,
     * per context */
    struct tsr_wire_selection *selection;
    /* the shader and program names the stream's receiver gave or was
     * given (glCreateShader, glCreateProgram, their TSR forms): a call on
     * a name that is neither is GL's error before its pointers are read
     * (pack_mirror.c) */
    struct tsr_packer_glsl_names *glsl_names;
} tsr_packer;

/* Whether cap names a client array (GL_VERTEX_ARRAY, ...). glEnable and
 * glDisable of one are glEnableClientState/glDisableClientState (Mesa's
 * compatibility contexts take both): the packer keeps them in its mirror,
 * the unpacker drops one that comes from the wire (arrays come inline with
 * each draw), and an SPU that routes glEnable as state routes these as
 * client state. */
static inline int tsr_wire_is_client_array(GLenum cap)
{
    switch (cap) {
    case GL_VERTEX_ARRAY:
    case GL_NORMAL_ARRAY:
    case GL_COLOR_ARRAY:
    case GL_INDEX_ARRAY:
    case GL_TEXTURE_COORD_ARRAY:
    case GL_EDGE_FLAG_ARRAY:
    case GL_FOG_COORD_ARRAY:
    case GL_SECONDARY_COLOR_ARRAY: return 1;
    default: return 0;
    }
}

/* buffer_size: bytes of a buffer including header and opcodes (at least
 * TSR_PACK_MIN_BUFFER). The sink is copied. */
TSR_API tsr_packer *tsr_packer_create(size_t buffer_size, const tsr_pack_sink *sink, tsr_error *err);
TSR_API void tsr_packer_destroy(tsr_packer *p);
/* Sends what is packed (nothing when empty). Returns 0 or the sink's error. */
TSR_API int tsr_packer_flush(tsr_packer *p);
/* Bytes of commands currently packed (opcodes + data, no header). */
TSR_API size_t tsr_packer_pending(const tsr_packer *p);
/* The GL error the packer found itself without the receiver (a query
 * whose pname the wire cannot size, a pixel command GL refuses before it
 * reads a pixel), once, then 0: the packer's glGetError answers it before
 * asking; an SPU that routes glGetError elsewhere (tilesort) takes it
 * from its own packers. */
TSR_API GLenum tsr_packer_take_local_error(tsr_packer *p);
/* The GL error glMapBufferRange makes for its range and access bits
 * before it looks at the buffer's size (Mesa's checks, in its order):
 * GL_INVALID_VALUE for a negative offset or length or an unknown bit,
 * GL_INVALID_OPERATION for a length of 0, neither read nor write, read
 * with an invalidate or the unsynchronized bit, or flush-explicit without
 * write; 0 otherwise. The packer's mappings and the state tracker's
 * both ask it. */
TSR_API GLenum tsr_map_range_error(GLintptr offset, GLsizeiptr length, GLbitfield access);
/* The access enum GL answers for GL_BUFFER_ACCESS of a mapping made with
 * `access` (GL_MAP_*_BIT): GL_READ_ONLY or GL_WRITE_ONLY for one of the
 * two, GL_READ_WRITE for both (and for no mapping, access 0). */
TSR_API GLenum tsr_map_access_enum(GLbitfield access);
/* Sets every slot of `d` to this packer (self = p): commands sent on the
 * wire are packed (those with a reply flush and wait for it), client-state
 * commands update the mirrors and draws with client arrays carry their
 * data (tessera/dev/wire.h section 6). */
TSR_API void tsr_packer_fill_dispatch(tsr_packer *p, tsr_dispatch *d);
/* Object-space box of the vertex positions packed since the last flush (or
 * reset); returns 0 when no vertex was packed. The box is reset after each
 * flush, once the sink returned (so a sink may read it). Fed by the spec's
 * `vertex: position` commands and by DrawArrays/DrawElements with client
 * vertex arrays (all elements of the index range sent). A homogeneous
 * vertex with w <= 0, or vertex data the packer never sees (arrays or
 * indices in buffer objects), makes the box infinite. Other geometry
 * (Rect*, Eval*, CallList*, Bitmap, ...) does not touch it: a box-keeping
 * SPU treats those as unknown itself. A NaN coordinate makes the box
 * infinite too (where such a vertex lands is up to the renderer). */
TSR_API int tsr_packer_bbox(const tsr_packer *p, float min[3], float max[3]);
TSR_API void tsr_packer_bbox_reset(tsr_packer *p);
/* The window-space box of geometry: an object-space box
 * [mn, mx] (e.g. the packer's) or n homogeneous object-space points, under
 * projection * modelview (column-major; pm = their product in double, from
 * tsr_box_clip_matrix) and the viewport [x, y, w, h], grown by `margin`
 * pixels and clamped to the win_w x win_h window. Returns 1 with the box
 * [box[0], box[2]) x [box[1], box[3]) in whole pixels (possibly empty: all
 * of it off screen), or 0 when it is unknown (a non-finite value; or a
 * point at w <= 0 when `clip` is 0). With `clip`, points behind the eye
 * are handled: the hull of the (at most 8) points is clipped against the
 * near and far planes in homogeneous space, as GL clips what it draws,
 * and the box is that of what is left. */
TSR_API void tsr_box_clip_matrix(const GLfloat *projection, const GLfloat *modelview, double pm[16]);
TSR_API int tsr_box_window(const GLfloat *projection, const GLfloat *modelview, const GLint *viewport,
                           const float mn[3], const float mx[3], double margin, int clip, int win_w, int win_h,
                           int box[4]);
TSR_API int tsr_box_points_window(const double pm[16], const GLint *viewport, const float (*pts)[4], int n,
                                  double margin, int clip, int win_w, int win_h, int box[4]);
/* Element i's position from a client vertex array (GL_FLOAT, GL_DOUBLE,
 * GL_INT or GL_SHORT, 1 to 4 components; missing ones are 0, 0, 1) into
 * out; returns 0 for other types and arrays in buffer objects. */
TSR_API int tsr_client_array_position(const tsr_client_array *a, uint64_t i, float out[4]);
/* Bytes (opcode + data, before alignment padding) that glDrawArrays
 * (index_type 0) or glDrawElements of `count` vertices or indices of
 * index_type with client arrays of `vertices` elements would take with the
 * arrays enabled now: a box-keeping SPU uses it to account for a draw it
 * sends in other pieces. 0 when the arrays cannot be packed. */
TSR_API uint64_t tsr_packer_draw_bytes(tsr_packer *p, GLsizei count, GLenum index_type, uint64_t vertices);
/* The GL errors of glDrawRangeElements and of glMultiDrawArrays (type 0)
 * or glMultiDrawElements, checked as Mesa checks them: a refused call
 * becomes the packer's local error (-1), else 0 and the call stands for
 * its glDrawElements, or its glDrawArrays/glDrawElements of count[i] > 0
 * in order; a box-keeping SPU that draws those itself checks first. */
TSR_API int tsr_packer_check_DrawRangeElements(tsr_packer *p, GLenum mode, GLuint start, GLuint end, GLsizei count,
                                               GLenum type);
TSR_API int tsr_packer_check_MultiDraw(tsr_packer *p, GLenum mode, const GLsizei *count, GLenum type,
                                       GLsizei drawcount);
/* First error since creation/clear (TSR_OK when none), e.g. a failed flush,
 * a dropped command (invalid size, unknown enum), a missing reply. */
TSR_API const tsr_error *tsr_packer_error(const tsr_packer *p);
TSR_API void tsr_packer_clear_error(tsr_packer *p);

/* --- spec tables (generated from spec/gl.yaml) ------------------------------ */

/* Element count of an enum-dependent vector (spec pname_counts: glLightfv's
 * params for GL_POSITION is 4); -1 when the enum is unknown. */
TSR_API int tsr_wire_pname_count(GLenum pname);
/* Values per control point of an evaluator target (spec map_components);
 * -1 when unknown. */
TSR_API int tsr_wire_map_components(GLenum target);
/* Opcode of a dispatch slot (TSR_SLOT_*), -1 when out of range. */
TSR_API int tsr_wire_slot_opcode(int slot);
/* Name of an opcode ("Vertex3f"), NULL when unknown (messages). */
TSR_API const char *tsr_wire_opcode_name(uint32_t opcode);

/* --- for generated code: the inline fast paths ------------------------------ */

/* Slow path of tsr_packer_cmd (fixed-size commands, at most
 * TSR_PACK_MAX_FIXED bytes): flushes and places the command. Never NULL:
 * if memory runs out the command goes to a discard area (error recorded). */
TSR_API uint8_t *tsr_packer_cmd_slow(tsr_packer *p, uint32_t opcode, uint64_t size, size_t align) __attribute__((cold));

/* Reserves `size` data bytes (aligned to `align`, a power of two) for a
 * one-byte opcode and records the opcode; the caller fills the bytes. */
static inline uint8_t *tsr_packer_cmd(tsr_packer *p, uint8_t opcode, size_t size, size_t align)
{
    uint8_t *d = (uint8_t *)(((uintptr_t)p->data + (align - 1)) & ~(uintptr_t)(align - 1));
    if (TSR_UNLIKELY((size_t)(p->data_end - d) < size || p->op == p->op_limit))
        return tsr_packer_cmd_slow(p, opcode, size, align);
    *--p->op = opcode;
    p->data = d + size;
    return d;
}

/* Grow the box by one vertex position (the packers of the spec's
 * `vertex: position` commands call these; an SPU that accounts for
 * geometry it sends in other pieces may too). tsr_packer_bbox4 divides
 * by w; w <= 0 or NaN makes the box infinite. */
#if defined(__SSE__)
/* One min and one max on 4 lanes (x, y, z, z). A NaN component is ignored
 * (minps returns the second operand). */
static inline void tsr_packer_bbox3(tsr_packer *p, float x, float y, float z)
{
    __m128 v = _mm_setr_ps(x, y, z, z);
    p->bbox_nan |= (uint32_t)_mm_movemask_ps(_mm_cmpunord_ps(v, v));
    _mm_store_ps(p->bbox_min, _mm_min_ps(v, _mm_load_ps(p->bbox_min)));
    _mm_store_ps(p->bbox_max, _mm_max_ps(v, _mm_load_ps(p->bbox_max)));
}
#else
static inline void tsr_packer_bbox3(tsr_packer *p, float x, float y, float z)
{
    p->bbox_nan |= (x != x) | (y != y) | (z != z);
    p->bbox_min[0] = x < p->bbox_min[0] ? x : p->bbox_min[0];
    p->bbox_min[1] = y < p->bbox_min[1] ? y : p->bbox_min[1];
    p->bbox_min[2] = z < p->bbox_min[2] ? z : p->bbox_min[2];
    p->bbox_max[0] = x > p->bbox_max[0] ? x : p->bbox_max[0];
    p->bbox_max[1] = y > p->bbox_max[1] ? y : p->bbox_max[1];
    p->bbox_max[2] = z > p->bbox_max[2] ? z : p->bbox_max[2];
}
#endif

/* Makes the box infinite (a vertex whose place is unknown). */
TSR_API void tsr_packer_bbox_infinite(tsr_packer *p);

static inline void tsr_packer_bbox4(tsr_packer *p, float x, float y, float z, float w)
{
    if (TSR_LIKELY(w == 1.0f))
        tsr_packer_bbox3(p, x, y, z);
    else if (w > 0.0f)
        tsr_packer_bbox3(p, x / w, y / w, z / w);
    else
        tsr_packer_bbox_infinite(p); /* also w NaN */
}

/* glDrawElements(mode, count, type, indices) with an element array buffer
 * bound whose bytes the caller has (buffer_bytes, buffer_size: tilesort's
 * tracker keeps buffer contents; NULL when the buffer has no data store or
 * is mapped): a draw whose arrays are in client memory then carries its
 * indices inline, read from those bytes, without the round trip the packer
 * would make to ask the receiver for them (nothing is drawn when they lie
 * past the buffer's end); the receiver's element array buffer binding
 * stays. A draw from buffers only is packed as glDrawElements. */
TSR_API void tsr_packer_draw_elements_known(tsr_packer *p, GLenum mode, GLsizei count, GLenum type, const void *indices,
                                            const void *buffer_bytes, GLsizeiptr buffer_size);

/* --- the client-state mirrors ------------------------------------------------
 * An SPU that sends the stream in pieces through several packers (tilesort:
 * state to one, geometry to another) keeps each packer's mirrors right by
 * telling it about the calls it did not pack itself. */
TSR_API void tsr_packer_mirror_PixelStore(tsr_packer *p, GLenum pname, double value);
TSR_API void tsr_packer_mirror_BindBuffer(tsr_packer *p, GLenum target, GLuint buffer);
TSR_API void tsr_packer_mirror_DeleteBuffers(tsr_packer *p, GLsizei n, const GLuint *buffers);
/* The stream's current context became `context`: the mirrors become that
 * context's (GL's initial values for one not seen before; the first
 * context of a stream keeps what was mirrored before it). */
TSR_API void tsr_packer_mirror_MakeCurrent(tsr_packer *p, GLint context);
/* `context` is gone: its mirrors are dropped. */
TSR_API void tsr_packer_mirror_ContextDestroy(tsr_packer *p, GLint context);
/* The render mode (GL_RENDER, GL_SELECT, GL_FEEDBACK) of the stream's
 * current context as the receiver reported it at the last glRenderMode
 * this packer sent (GL_RENDER before any): the receiver's answer, so a
 * mode GL refused to enter is not taken for on. */
TSR_API GLenum tsr_packer_render_mode(tsr_packer *p);

#ifdef __cplusplus
}
#endif
#endif
