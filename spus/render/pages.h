/* spus/render/pages.h — gives back to the kernel the zero pages that Mesa
 * writes when it allocates a renderbuffer, so a tile server pays only for
 * the pages its tiles touch (docs/render.md, "Memory").
 *
 * llvmpipe (Mesa 22.3, lp_texture.c llvmpipe_texture_layout) allocates
 * every texture/renderbuffer with align_malloc and then memsets all of it
 * to 0: a 4096x3072 RGBA8 + DEPTH24_STENCIL8 pair is 96 MiB resident at
 * once, although a tile server never draws outside its tiles. There is no
 * GL way to get the storage's address, so this module finds it: it
 * compares the process's anonymous private writable mappings
 * (/proc/self/maps) before and after the allocation, and in every span
 * that appeared (at least `min_bytes` long: large allocations are mmap'ed
 * on their own) drops the pages that are entirely zero with
 * madvise(MADV_DONTNEED). For private anonymous memory that is invisible
 * to the program: such a page reads as zeros again afterwards. Only pages
 * that are all zeros are dropped, so a wrongly chosen span loses nothing;
 * the caller must make sure no other thread writes those spans meanwhile
 * (render.c calls it with GL idle, right after allocating).
 * Linux only; elsewhere (or without /proc) it does nothing. */
#ifndef RENDER_PAGES_H
#define RENDER_PAGES_H

#include <stddef.h>
#include <stdint.h>

typedef struct render_span {
    uintptr_t start, end;
} render_span;

typedef struct render_page_map {
    render_span *spans;
    size_t count;
} render_page_map;

/* Records the current anonymous private writable mappings. Returns 0, or
 * -1 when /proc/self/maps cannot be read or memory runs out (the map is
 * then empty and render_pages_release does nothing). */
int render_pages_snapshot(render_page_map *map);

/* Drops the all-zero pages of the spans that are mapped now but were not
 * in `before` and are at least `min_bytes` long. Returns the bytes given
 * back. Frees nothing of `before` (see render_pages_free). */
size_t render_pages_release(const render_page_map *before, size_t min_bytes);

void render_pages_free(render_page_map *map);

#endif
