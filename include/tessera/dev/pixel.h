/* tessera/dev/pixel.h — pixel-store state and the byte extent of images GL
 * reads or writes under it: the sizes of image payloads on the wire. For an
 * SPU that handles image commands itself (sizing a glTexImage2D's pixels,
 * copying a glReadPixels result into the application's memory) the same
 * way the packer and unpacker do. Part of libtessera (pkg-config tessera).
 *
 * Owns: tsr_pixel_store (pack and unpack modes; a small push stack lives in
 * the packer). Never: touches GL; pure arithmetic, overflow-checked.
 *
 * Use:
 *
 *   tsr_pixel_store ps;
 *   tsr_pixel_store_init(&ps);                    // GL's initial values
 *   tsr_pixel_store_set(&ps, GL_UNPACK_ALIGNMENT, 1);
 *   tsr_pixel_layout l;
 *   if (tsr_pixel_layout_of(&ps.unpack, 2, w, h, 1, GL_RGB, GL_UNSIGNED_BYTE, &l) == 0)
 *       ... l.extent bytes from the pointer are what glTexImage2D reads ...
 */
#ifndef TESSERA_DEV_PIXEL_H
#define TESSERA_DEV_PIXEL_H

#include <stddef.h>
#include <stdint.h>
#include <GL/gl.h>
#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct tsr_pixel_modes {
    int32_t row_length, image_height, skip_pixels, skip_rows, skip_images, alignment;
    uint8_t swap_bytes, lsb_first;
} tsr_pixel_modes;

typedef struct tsr_pixel_store {
    tsr_pixel_modes pack, unpack;
    /* GL_PIXEL_PACK_BUFFER and GL_PIXEL_UNPACK_BUFFER bindings, kept by a
     * packer's and an unpacker's mirrors (GL 2.1 puts them in the
     * pixel-store attribute group); 0 when none is bound. */
    uint32_t pack_buffer, unpack_buffer;
} tsr_pixel_store;

TSR_API void tsr_pixel_store_init(tsr_pixel_store *s);
/* Applies glPixelStore{i,f}(pname, value) as GL would; invalid values are
 * ignored like GL ignores them (it raises an error instead). Returns 1 when
 * pname is a pixel-store parameter. */
TSR_API int tsr_pixel_store_set(tsr_pixel_store *s, GLenum pname, double value);
/* Value of pname in `s` (for re-sending differences), 0 if not a pname. */
TSR_API int32_t tsr_pixel_store_get(const tsr_pixel_store *s, GLenum pname);

/* Bytes of one element of GL type `type` (GL_FLOAT 4, GL_2_BYTES 2, ...);
 * 0 when unknown. */
TSR_API size_t tsr_gl_type_size(GLenum type);

/* Image layout under `m`: `dims` is 1, 2 or 3 (SKIP_IMAGES and IMAGE_HEIGHT
 * apply to 3D only). */
typedef struct tsr_pixel_layout {
    uint64_t group_bytes; /* bytes of one pixel (0 for GL_BITMAP) */
    uint64_t row_bytes;   /* distance between rows */
    uint64_t image_bytes; /* distance between images */
    uint64_t first;       /* offset of the first byte read/written */
    uint64_t row_span;    /* bytes touched per row */
    uint64_t extent;      /* bytes from the pointer to the last byte touched + 1 (0: nothing) */
} tsr_pixel_layout;

/* Fills `out` for a w x h x d image of format/type. Returns 0, or -1 for an
 * unknown format/type, negative sizes, or sizes that overflow 64 bits. */
TSR_API int tsr_pixel_layout_of(const tsr_pixel_modes *m, int dims, int64_t w, int64_t h, int64_t d, GLenum format,
                                GLenum type, tsr_pixel_layout *out);
/* The GL error a pixel command with these sizes, format and type makes
 * before it reads or writes a pixel (GL 2.1 section 3.6.4, 4.3.2):
 * GL_INVALID_VALUE for a negative size, GL_INVALID_ENUM for a format or
 * type that is none (or that tessera does not know), GL_INVALID_OPERATION
 * for a packed type with a format it does not go with (GL_RGB for the
 * three-component ones, RGBA, BGRA or ABGR for the four-component ones);
 * GL_NO_ERROR otherwise. */
TSR_API GLenum tsr_pixel_image_error(int64_t w, int64_t h, int64_t d, GLenum format, GLenum type);
/* Copies only the pixel spans (what GL writes) of an image laid out as `l`
 * (h rows x d images) from src to dst, both addressed from the pointer. */
TSR_API void tsr_pixel_copy_spans(const tsr_pixel_layout *l, int64_t h, int64_t d, void *dst, const void *src);

#ifdef __cplusplus
}
#endif
#endif
