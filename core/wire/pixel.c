/* core/wire/pixel.c — pixel-store modes and image extents (GL 2.1 section 3.6.4
 * "Transfer of pixel rectangles" and 4.3.2 for packing). Owns only
 * arithmetic on caller-owned structs; never calls GL, never allocates. */
#include "tessera/dev/pixel.h"

#include <GL/glext.h>
#include <string.h>

void tsr_pixel_store_init(tsr_pixel_store *s)
{
    memset(s, 0, sizeof *s);
    s->pack.alignment = 4;
    s->unpack.alignment = 4;
}

static int32_t *int_field(tsr_pixel_store *s, GLenum pname, int *is_alignment, uint8_t **flag)
{
    *is_alignment = 0;
    *flag = NULL;
    switch (pname) {
    case GL_PACK_ROW_LENGTH: return &s->pack.row_length;
    case GL_PACK_IMAGE_HEIGHT: return &s->pack.image_height;
    case GL_PACK_SKIP_PIXELS: return &s->pack.skip_pixels;
    case GL_PACK_SKIP_ROWS: return &s->pack.skip_rows;
    case GL_PACK_SKIP_IMAGES: return &s->pack.skip_images;
    case GL_PACK_ALIGNMENT: *is_alignment = 1; return &s->pack.alignment;
    case GL_UNPACK_ROW_LENGTH: return &s->unpack.row_length;
    case GL_UNPACK_IMAGE_HEIGHT: return &s->unpack.image_height;
    case GL_UNPACK_SKIP_PIXELS: return &s->unpack.skip_pixels;
    case GL_UNPACK_SKIP_ROWS: return &s->unpack.skip_rows;
    case GL_UNPACK_SKIP_IMAGES: return &s->unpack.skip_images;
    case GL_UNPACK_ALIGNMENT: *is_alignment = 1; return &s->unpack.alignment;
    case GL_PACK_SWAP_BYTES: *flag = &s->pack.swap_bytes; return NULL;
    case GL_PACK_LSB_FIRST: *flag = &s->pack.lsb_first; return NULL;
    case GL_UNPACK_SWAP_BYTES: *flag = &s->unpack.swap_bytes; return NULL;
    case GL_UNPACK_LSB_FIRST: *flag = &s->unpack.lsb_first; return NULL;
    default: return NULL;
    }
}

int tsr_pixel_store_set(tsr_pixel_store *s, GLenum pname, double value)
{
    int is_alignment;
    uint8_t *flag;
    int32_t *field = int_field(s, pname, &is_alignment, &flag);
    if (flag) {
        *flag = value != 0.0;
        return 1;
    }
    if (!field)
        return 0;
    /* GL rounds float parameters to the nearest integer. */
    double r = value < 0 ? value - 0.5 : value + 0.5;
    if (!(r > -2147483648.0 && r < 2147483647.0))
        return 1;
    int32_t v = (int32_t)r;
    if (is_alignment) {
        if (v == 1 || v == 2 || v == 4 || v == 8)
            *field = v;
    } else if (v >= 0) {
        *field = v;
    }
    return 1;
}

int32_t tsr_pixel_store_get(const tsr_pixel_store *s, GLenum pname)
{
    int is_alignment;
    uint8_t *flag;
    int32_t *field = int_field((tsr_pixel_store *)s, pname, &is_alignment, &flag);
    if (flag)
        return *flag;
    return field ? *field : 0;
}

size_t tsr_gl_type_size(GLenum type)
{
    switch (type) {
    case GL_BYTE:
    case GL_UNSIGNED_BYTE: return 1;
    case GL_SHORT:
    case GL_UNSIGNED_SHORT:
    case GL_HALF_FLOAT:
    case GL_2_BYTES: return 2;
    case GL_3_BYTES: return 3;
    case GL_INT:
    case GL_UNSIGNED_INT:
    case GL_FLOAT:
    case GL_4_BYTES:
    case GL_FIXED: return 4;
    case GL_DOUBLE: return 8;
    default: return 0;
    }
}

/* Bytes of one packed pixel for packed types (0 for unpacked types). */
static uint64_t packed_type_bytes(GLenum type)
{
    switch (type) {
    case GL_UNSIGNED_BYTE_3_3_2:
    case GL_UNSIGNED_BYTE_2_3_3_REV: return 1;
    case GL_UNSIGNED_SHORT_5_6_5:
    case GL_UNSIGNED_SHORT_5_6_5_REV:
    case GL_UNSIGNED_SHORT_4_4_4_4:
    case GL_UNSIGNED_SHORT_4_4_4_4_REV:
    case GL_UNSIGNED_SHORT_5_5_5_1:
    case GL_UNSIGNED_SHORT_1_5_5_5_REV: return 2;
    case GL_UNSIGNED_INT_8_8_8_8:
    case GL_UNSIGNED_INT_8_8_8_8_REV:
    case GL_UNSIGNED_INT_10_10_10_2:
    case GL_UNSIGNED_INT_2_10_10_10_REV:
    case GL_UNSIGNED_INT_24_8:
    case GL_UNSIGNED_INT_10F_11F_11F_REV:
    case GL_UNSIGNED_INT_5_9_9_9_REV: return 4;
    case GL_FLOAT_32_UNSIGNED_INT_24_8_REV: return 8;
    default: return 0;
    }
}

static int components(GLenum format)
{
    switch (format) {
    case GL_COLOR_INDEX:
    case GL_STENCIL_INDEX:
    case GL_DEPTH_COMPONENT:
    case GL_DEPTH_STENCIL:
    case GL_RED:
    case GL_GREEN:
    case GL_BLUE:
    case GL_ALPHA:
    case GL_LUMINANCE:
    case GL_INTENSITY:
    case GL_RED_INTEGER:
    case GL_GREEN_INTEGER:
    case GL_BLUE_INTEGER:
    case GL_ALPHA_INTEGER:
    case GL_LUMINANCE_INTEGER_EXT: return 1;
    case GL_LUMINANCE_ALPHA:
    case GL_RG:
    case GL_RG_INTEGER:
    case GL_LUMINANCE_ALPHA_INTEGER_EXT: return 2;
    case GL_RGB:
    case GL_BGR:
    case GL_RGB_INTEGER:
    case GL_BGR_INTEGER: return 3;
    case GL_RGBA:
    case GL_BGRA:
    case GL_ABGR_EXT:
    case GL_RGBA_INTEGER:
    case GL_BGRA_INTEGER: return 4;
    default: return 0;
    }
}

GLenum tsr_pixel_image_error(int64_t w, int64_t h, int64_t d, GLenum format, GLenum type)
{
    if (w < 0 || h < 0 || d < 0)
        return GL_INVALID_VALUE;
    if (type == GL_BITMAP)
        return format == GL_COLOR_INDEX || format == GL_STENCIL_INDEX ? GL_NO_ERROR : GL_INVALID_ENUM;
    int n = components(format);
    if (!n || (!packed_type_bytes(type) && !tsr_gl_type_size(type)) || type == GL_2_BYTES || type == GL_3_BYTES ||
        type == GL_4_BYTES || type == GL_DOUBLE || type == GL_FIXED)
        return GL_INVALID_ENUM;
    switch (type) {
    case GL_UNSIGNED_BYTE_3_3_2:
    case GL_UNSIGNED_BYTE_2_3_3_REV:
    case GL_UNSIGNED_SHORT_5_6_5:
    case GL_UNSIGNED_SHORT_5_6_5_REV:
    case GL_UNSIGNED_INT_10F_11F_11F_REV:
    case GL_UNSIGNED_INT_5_9_9_9_REV:
        return format == GL_RGB || format == GL_RGB_INTEGER ? GL_NO_ERROR : GL_INVALID_OPERATION;
    case GL_UNSIGNED_SHORT_4_4_4_4:
    case GL_UNSIGNED_SHORT_4_4_4_4_REV:
    case GL_UNSIGNED_SHORT_5_5_5_1:
    case GL_UNSIGNED_SHORT_1_5_5_5_REV:
    case GL_UNSIGNED_INT_8_8_8_8:
    case GL_UNSIGNED_INT_8_8_8_8_REV:
    case GL_UNSIGNED_INT_10_10_10_2:
    case GL_UNSIGNED_INT_2_10_10_10_REV: return n == 4 ? GL_NO_ERROR : GL_INVALID_OPERATION;
    case GL_UNSIGNED_INT_24_8:
    case GL_FLOAT_32_UNSIGNED_INT_24_8_REV: return format == GL_DEPTH_STENCIL ? GL_NO_ERROR : GL_INVALID_OPERATION;
    default: return GL_NO_ERROR;
    }
}

#define MUL(a, b, r) __builtin_mul_overflow((a), (b), (r))
#define ADD(a, b, r) __builtin_add_overflow((a), (b), (r))

int tsr_pixel_layout_of(const tsr_pixel_modes *m, int dims, int64_t w, int64_t h, int64_t d, GLenum format, GLenum type,
                        tsr_pixel_layout *out)
{
    memset(out, 0, sizeof *out);
    if (w < 0 || h < 0 || d < 0 || w > INT32_MAX || h > INT32_MAX || d > INT32_MAX)
        return -1;
    uint64_t a = (uint64_t)m->alignment;
    uint64_t l = m->row_length > 0 ? (uint64_t)m->row_length : (uint64_t)w;
    uint64_t sp = (uint64_t)m->skip_pixels, sr = (uint64_t)m->skip_rows;
    uint64_t si = dims == 3 ? (uint64_t)m->skip_images : 0;
    uint64_t rows_per_image = dims == 3 && m->image_height > 0 ? (uint64_t)m->image_height : (uint64_t)h;
    uint64_t t;
    if (type == GL_BITMAP) {
        if (format != GL_COLOR_INDEX && format != GL_STENCIL_INDEX)
            return -1;
        /* Rows of bits, each padded to the alignment (in bytes). */
        out->row_bytes = a * ((l + 8 * a - 1) / (8 * a));
        if (MUL(sr, out->row_bytes, &out->first) || ADD(out->first, sp / 8, &out->first))
            return -1;
        if (w == 0 || h == 0 || d == 0)
            return 0;
        out->row_span = (sp + (uint64_t)w - 1) / 8 - sp / 8 + 1;
        if (MUL(sr + (uint64_t)h - 1, out->row_bytes, &t) || ADD(t, (sp + (uint64_t)w - 1) / 8 + 1, &t))
            return -1;
        out->image_bytes = out->extent = t;
        return 0;
    }
    uint64_t n, s;
    uint64_t packed = packed_type_bytes(type);
    if (packed) {
        if (!components(format))
            return -1;
        n = 1;
        s = packed;
    } else {
        n = (uint64_t)components(format);
        s = tsr_gl_type_size(type);
        if (!n || !s || type == GL_2_BYTES || type == GL_3_BYTES || type == GL_4_BYTES || type == GL_DOUBLE)
            return -1;
    }
    out->group_bytes = n * s;
    uint64_t row;
    if (MUL(out->group_bytes, l, &row))
        return -1;
    out->row_bytes = s >= a ? row : a * ((row + a - 1) / a);
    if (MUL(out->row_bytes, rows_per_image, &out->image_bytes))
        return -1;
    uint64_t f1, f2, f3;
    if (MUL(si, out->image_bytes, &f1) || MUL(sr, out->row_bytes, &f2) || MUL(sp, out->group_bytes, &f3) ||
        ADD(f1, f2, &t) || ADD(t, f3, &out->first))
        return -1;
    if (w == 0 || h == 0 || d == 0)
        return 0;
    if (MUL((uint64_t)w, out->group_bytes, &out->row_span))
        return -1;
    if (MUL(si + (uint64_t)d - 1, out->image_bytes, &f1) || MUL(sr + (uint64_t)h - 1, out->row_bytes, &f2) ||
        MUL(sp + (uint64_t)w, out->group_bytes, &f3) || ADD(f1, f2, &t) || ADD(t, f3, &out->extent))
        return -1;
    return 0;
}

void tsr_pixel_copy_spans(const tsr_pixel_layout *l, int64_t h, int64_t d, void *dst, const void *src)
{
    if (!l->extent)
        return;
    for (int64_t i = 0; i < d; i++)
        for (int64_t r = 0; r < h; r++) {
            uint64_t off = l->first + (uint64_t)i * l->image_bytes + (uint64_t)r * l->row_bytes;
            memcpy((uint8_t *)dst + off, (const uint8_t *)src + off, l->row_span);
        }
}
