/* tessera/dev/wire.h — the tessera wire format: layout of a command buffer
 * and the little-endian field accessors the packer and unpacker share. For
 * an SPU that reads or writes wire bytes itself (a sorting SPU walking a
 * packed buffer, a custom command's payload, a reply). Header only.
 *
 * Owns: the format definition (this comment is its specification).
 * Never: host pointers, host byte order or host sizes on the wire; the
 * accessors never assume alignment.
 *
 * Use: read a buffer's header before trusting it
 *
 *   if (size < TSR_WIRE_HEADER_SIZE || tsr_wire_get_u32(buf) != TSR_WIRE_MAGIC) ...
 *   uint32_t n = tsr_wire_get_u32(buf + 4);               // opcode count
 *   uint64_t len = tsr_wire_get_u64(buf + 8);             // data length
 *   const uint8_t *data = buf + TSR_WIRE_HEADER_SIZE + tsr_wire_align8(n);
 *
 * (tsr_wire_buffer_size in tessera/dev/unpack.h does the whole check.)
 *
 * 1. A BUFFER (what a sink receives and an unpacker decodes) is one
 *    contiguous byte region:
 *
 *      [header: 16 bytes][opcodes: align8(N) bytes][data: L bytes]
 *
 *    header  = u32 magic "TSW1" (0x31575354), u32 N (opcode count),
 *              u64 L (data length).  Total size = 16 + align8(N) + L,
 *              exactly (a longer or shorter region is rejected).
 *    opcodes = one byte per command, stored BACKWARDS: the first command's
 *              opcode is the last byte before the data, the k-th command's
 *              opcode is at data[-1-k]; the align8(N)-N leading bytes are
 *              zero padding. (In the packer the opcodes grow backwards from
 *              the middle of its memory and the data forwards, so the
 *              region is sent without copying.)
 *    data    = the commands' arguments, in command order, growing forwards
 *              from the data start (which is 8-aligned in memory).
 *
 * 2. A COMMAND's data starts at the current data offset rounded up to the
 *    command's alignment (the largest natural alignment among its fixed
 *    fields; 8 for commands with variable-length parts); skipped bytes are
 *    padding. Its fields follow in parameter order, each naturally aligned
 *    relative to the data start: GLbyte/GLubyte/GLboolean/GLchar 1 byte,
 *    GLshort/GLushort/GLhalf 2, GLint/GLuint/GLsizei/GLenum/GLbitfield/
 *    GLfloat/GLclampf/GLfixed 4, GLdouble/GLclampd/GLint64/GLuint64 8,
 *    GLintptr/GLsizeiptr 8 (signed 64-bit on every host).
 *    Pointers with a constant element count (glVertex3fv's v[3]) travel
 *    inline as that many elements. So glVertex3f costs 13 bytes: one
 *    opcode byte and 12 data bytes (x, y, z at offsets 0, 4, 8).
 *    Commands with a reply (spec `wire: reply`) then carry a u32 request
 *    id (4-aligned), the only way replies are matched.
 *
 * 3. VARIABLE-LENGTH parts follow the fixed fields, one per input pointer
 *    whose count is not a constant, in parameter order: pad to 8, u64 byte
 *    length, then that many payload bytes. Length UINT64_MAX means a NULL
 *    pointer (only for `nullable` parameters). Length UINT64_MAX - 1
 *    (TSR_WIRE_OFFSET), only for {image: ...} and {bitmap: ...} inputs,
 *    means the client had a GL_PIXEL_UNPACK_BUFFER bound: the pointer was
 *    an offset into that buffer (GL 2.1 3.6.4), and a u64 offset follows
 *    instead of the pixels; the unpacker accepts it only while the stream
 *    has an unpack buffer bound (BindBuffer mirrored). The unpacker checks every
 *    length against what the arguments imply before dispatch:
 *      count n / n*k     n*k*elem bytes (negative or overflowing: error)
 *      {pname: P}        pname_counts[P]*elem (unknown P: error)
 *      {image: ...}      the bytes GL reads under the unpack pixel store
 *      {bitmap: ...}     (tessera/dev/pixel.h; PixelStore commands are sent and
 *                        both sides mirror them), from the pointer to the
 *                        last byte read, skips included
 *      {typed: [n, t]}   n * size of GL type t
 *      {bytes: s}        s bytes
 *      {string: true}    strlen+1 bytes, last byte NUL
 *      {map: ...}        ((order-1)*stride [+ (vorder-1)*vstride] + k)*elem,
 *                        k = pname_counts[target]
 *    Output pointers are not sent; the server sizes them itself.
 *
 * 4. EXTENDED OPCODES. Opcodes 1..254 are one byte. Opcode >= 255 is sent
 *    as the byte 255, and in the data, at the next 8-aligned offset, a u32
 *    opcode and a u32 length of the command data that follows (0xFFFFFFFF
 *    when it does not fit 32 bits); the command's data then starts right
 *    after (8-aligned). Opcode 0 is never valid.
 *
 * 5. REPLIES (server to client, matched by request id, delivered through
 *    the reply channel, not inside a buffer): a sequence of items, each
 *    8-aligned: u64 byte length + bytes. Item 0 is the return value when the
 *    command returns one (its wire-size scalar; for strings the bytes
 *    including the NUL); then one item per output pointer in parameter
 *    order, holding the bytes the server's GL wrote (images: the whole
 *    extent under the pack pixel store; the client copies only the pixel
 *    spans, so it never writes bytes GL would not have written).
 *
 * 6. CLIENT VERTEX ARRAYS (spec `wire: custom` DrawArrays/DrawElements):
 *    pointers and enables never travel (they are client state, spec
 *    `wire: local`); each draw carries one bulk payload. DrawRangeElements
 *    and MultiDrawArrays/MultiDrawElements travel as the DrawElements and
 *    DrawArrays GL defines them to be.
 *      DrawArrays:   u32 mode, i32 first, i32 count, u32 0,
 *                    u64 P, then P bytes of ARRAYS.
 *      DrawElements: u32 mode, i32 count, u32 type, u32 index_buffer,
 *                    u64 index_offset (index_buffer != 0), u64 I (inline
 *                    index bytes, 0 with a buffer), I bytes, pad to 8,
 *                    u64 P, then P bytes of ARRAYS.
 *      ARRAYS:       u32 array_buffer_binding, u32 element_buffer_binding
 *                    (the client's bindings, restored after the draw),
 *                    u32 client_active_texture (unit index, restored),
 *                    u32 array count A, then A records, each 8-aligned:
 *                    u32 kind (TSR_WIRE_ARRAY_*), u32 index (texture
 *                    unit / attribute), i32 size (1 for the fog coordinate
 *                    and index arrays), u32 type, i32 stride,
 *                    u32 normalized, u32 buffer, u32 0, u64 offset, u64 D,
 *                    D data bytes, pad to 8.
 *                    buffer != 0: the array lives in that buffer object
 *                    (it was bound to GL_ARRAY_BUFFER when the pointer was
 *                    set), offset = the pointer value, D = 0, stride as
 *                    given. buffer == 0: inline data compacted to the used
 *                    index range [offset, offset + D/elem): tightly packed
 *                    (stride sent as 0), offset = first index sent.
 *    The unpacker rebuilds the draw on its target table, in this order:
 *      for each array record: BindBuffer(GL_ARRAY_BUFFER, buffer);
 *        (texcoord: ClientActiveTexture(GL_TEXTURE0 + index));
 *        the ...Pointer call (inline data: pointer such that element
 *        `offset` is the first byte sent); EnableClientState(array) or
 *        EnableVertexAttribArray(index);
 *      DrawElements: BindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer),
 *        DrawElements(mode, count, type, inline indices or offset);
 *      DrawArrays: DrawArrays(mode, first, count);
 *      then restores: for each array record DisableClientState(array)
 *        (texcoord: after ClientActiveTexture(GL_TEXTURE0 + index)) or
 *        DisableVertexAttribArray(index); ClientActiveTexture(GL_TEXTURE0
 *        + client_active_texture) when a texcoord array was present;
 *        BindBuffer(GL_ARRAY_BUFFER, array_buffer_binding) when A > 0;
 *        DrawElements: BindBuffer(GL_ELEMENT_ARRAY_BUFFER,
 *        element_buffer_binding).
 *    ShaderSource (custom): u32 shader, i32 count, u64 P, then P bytes of
 *    `count` strings, each 8-aligned: u64 byte length S, S bytes (no NUL),
 *    then the length array as a variable part (NULL when the client passed
 *    NULL). GetTexImage (custom, reply): u32 target, i32 level, u32 format,
 *    u32 type, u32 request id; its reply holds item 0 = i32 width, height,
 *    depth of the level, item 1 = the image under the pack pixel store.
 *    GetMap{d,f,i}v, GetPixelMap{f,ui,us}v, GetUniform{f,i}v and
 *    GetCompressedTexImage (custom, reply): u32
 *    first argument (target, map, program), u32 second argument (query,
 *    location, level; 0 for GetPixelMap*), u32 request id, u32 0; the
 *    reply holds item 0 = the values the receiver's GL wrote, as many as
 *    its state says (the map's order, the pixel map's size, the uniform's
 *    type, the level's compressed size), which the sender copies into the
 *    program's buffer.
 *    SelectBuffer (custom): i32 size, u32 0; FeedbackBuffer (custom): i32
 *    size, u32 type (the program's buffer stays with the sender; the
 *    receiver gives its GL a buffer of `size` values of its own).
 *    RenderMode (custom, reply): u32 mode, u32 request id; its reply holds
 *    item 0 = i32 return value, item 1 = u32 mode left, u32 mode now (the
 *    receiver's GL_RENDER_MODE before and after), item 2 = the 4-byte
 *    values the receiver's GL wrote into the buffer of the mode left
 *    (GL_SELECT: the hit records, GL_FEEDBACK: the values counted by the
 *    return value; on overflow, return -1, the whole buffer; empty when
 *    the mode left is GL_RENDER), which the sender copies into the
 *    program's buffer.
 *
 * All multi-byte values are little-endian. Buffers are self-contained: no
 * state survives from one buffer to the next inside the decoder, so any
 * command boundary (also inside Begin/End) is a valid buffer boundary. */
#ifndef TESSERA_DEV_WIRE_H
#define TESSERA_DEV_WIRE_H

#include <stdint.h>
#include <string.h>

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "tessera's wire accessors assume a little-endian host"
#endif

#define TSR_WIRE_MAGIC 0x31575354u /* "TSW1" */
#define TSR_WIRE_HEADER_SIZE 16u
#define TSR_WIRE_EXTENDED 255u
#define TSR_WIRE_NULL UINT64_MAX
#define TSR_WIRE_OFFSET (UINT64_MAX - 1u)
#define TSR_WIRE_EXT_LEN_UNKNOWN 0xFFFFFFFFu

enum {
    TSR_WIRE_ARRAY_VERTEX = 1,
    TSR_WIRE_ARRAY_NORMAL = 2,
    TSR_WIRE_ARRAY_COLOR = 3,
    TSR_WIRE_ARRAY_EDGE_FLAG = 4,
    TSR_WIRE_ARRAY_TEXCOORD = 5,
    TSR_WIRE_ARRAY_ATTRIB = 6,
    TSR_WIRE_ARRAY_SECONDARY_COLOR = 7,
    TSR_WIRE_ARRAY_FOG_COORD = 8,
    TSR_WIRE_ARRAY_INDEX = 9,
};

#define TSR_LIKELY(x) __builtin_expect(!!(x), 1)
#define TSR_UNLIKELY(x) __builtin_expect(!!(x), 0)

static inline uint64_t tsr_wire_align8(uint64_t v) { return (v + 7u) & ~(uint64_t)7u; }

static inline void tsr_wire_put_u8(uint8_t *p, uint8_t v) { *p = v; }
static inline void tsr_wire_put_u16(uint8_t *p, uint16_t v) { memcpy(p, &v, 2); }
static inline void tsr_wire_put_u32(uint8_t *p, uint32_t v) { memcpy(p, &v, 4); }
static inline void tsr_wire_put_u64(uint8_t *p, uint64_t v) { memcpy(p, &v, 8); }
static inline void tsr_wire_put_f32(uint8_t *p, float v) { memcpy(p, &v, 4); }
static inline void tsr_wire_put_f64(uint8_t *p, double v) { memcpy(p, &v, 8); }
static inline uint8_t tsr_wire_get_u8(const uint8_t *p) { return *p; }
static inline uint16_t tsr_wire_get_u16(const uint8_t *p)
{
    uint16_t v;
    memcpy(&v, p, 2);
    return v;
}
static inline uint32_t tsr_wire_get_u32(const uint8_t *p)
{
    uint32_t v;
    memcpy(&v, p, 4);
    return v;
}
static inline uint64_t tsr_wire_get_u64(const uint8_t *p)
{
    uint64_t v;
    memcpy(&v, p, 8);
    return v;
}
static inline float tsr_wire_get_f32(const uint8_t *p)
{
    float v;
    memcpy(&v, p, 4);
    return v;
}
static inline double tsr_wire_get_f64(const uint8_t *p)
{
    double v;
    memcpy(&v, p, 8);
    return v;
}

#endif
