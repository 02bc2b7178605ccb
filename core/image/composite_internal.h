/* core/image/composite_internal.h — what composite.c, sparse.c and
 * message.c share privately. Owns nothing. */
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

#endif
