/* core/image/composite_internal.h — what composite.c, composite_sparse.c and
 * composite_message.c share privately. Owns nothing. */
#ifndef TSR_CORE_IMAGE_COMPOSITE_INTERNAL_H
#define TSR_CORE_IMAGE_COMPOSITE_INTERNAL_H

#include <string.h>

/* memcpy that accepts n == 0 with NULL pointers (an empty image has no
 * planes; memcpy's arguments must never be NULL, even for 0 bytes). */
static inline void ci_copy(void *dst, const void *src, size_t n)
{
    if (n)
        memcpy(dst, src, n);
}

#include "tessera/dev/composite.h"

/* Outgoing message bytes (tsr_composite_copy): from this many bytes on,
 * a copy uses streaming stores. ci_copy_stream streams whatever its size
 * (for a message gathered in many small pieces: the threshold is the
 * message's), with no fence; ci_copy_fence after the last one. */
#define CI_STREAM_MIN ((size_t)64 * 1024)
void ci_copy_stream(void *dst, const void *src, size_t n);
void ci_copy_fence(void);

/* tsr_composite_sparse_compress; with runs_only, only the runs and the active
 * count are written (no planes reserved): the pixels stay in `in`, where
 * tsr_composite_message_encode_dense takes them straight into a message. */
int ci_sparse_compress(const tsr_composite_image *in, int mode, uint32_t start, uint32_t count,
                       tsr_composite_sparse *out, int runs_only, tsr_error *err);
/* The index in a dense region's planes of window pixel `pos`, which lies
 * in the region (a run of pixels from there stays in one of its rows, or,
 * in a region as wide as the window, runs on through its rows). */
static inline size_t ci_region_index(const tsr_composite_image *in, size_t pos)
{
    size_t w = (size_t)in->window_width;
    return (pos / w - (size_t)in->y) * (size_t)in->width + (pos % w - (size_t)in->x);
}

/* Planes of s for `pixels` active pixels of cb colour bytes. */
int ci_sparse_planes(tsr_composite_sparse *s, size_t pixels, size_t cb, tsr_error *err);

/* Image planes (colour, depth), 64-byte aligned. Large ones come straight
 * from mmap and go back with munmap: the resident memory of a compositing
 * peer is a measured figure (composite_peer_rss_mb), untouched parts of a
 * worst-case reservation are never backed, and a freed plane is not kept
 * in the heap for whatever is allocated next. ci_plane_bytes gives the
 * bytes a plane holds (0 for NULL), so capacity follows the format's real
 * size instead of the widest one. */
void *ci_plane_alloc(size_t bytes);
void ci_plane_free(void *plane);
size_t ci_plane_bytes(const void *plane);

#endif
