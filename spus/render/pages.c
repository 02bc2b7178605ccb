/* spus/render/pages.c — zero pages of fresh renderbuffers back to the
 * kernel (pages.h says why). */
#define _DEFAULT_SOURCE
#include "pages.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

static bool add_span(render_page_map *map, size_t *cap, uintptr_t start, uintptr_t end)
{
    if (map->count == *cap) {
        size_t n = *cap ? *cap * 2 : 64;
        render_span *s = realloc(map->spans, n * sizeof *s);
        if (!s)
            return false;
        map->spans = s;
        *cap = n;
    }
    map->spans[map->count++] = (render_span){start, end};
    return true;
}

int render_pages_snapshot(render_page_map *map)
{
    map->spans = NULL;
    map->count = 0;
    FILE *f = fopen("/proc/self/maps", "r");
    if (!f)
        return -1;
    size_t cap = 0;
    char line[512];
    int rc = 0;
    while (fgets(line, sizeof line, f)) {
        unsigned long start, end, inode;
        char perms[8];
        int path_at = 0;
        if (sscanf(line, "%lx-%lx %7s %*s %*s %lu %n", &start, &end, perms, &inode, &path_at) < 4)
            continue;
        /* Anonymous (no inode, no name: not [heap], [stack], files, shared
         * memory), private and writable: what malloc'ed memory is. */
        const char *path = line + path_at;
        if (inode != 0 || (path[0] && path[0] != '\n') || strcmp(perms, "rw-p") != 0)
            continue;
        if (!add_span(map, &cap, start, end)) {
            rc = -1;
            break;
        }
    }
    fclose(f);
    if (rc)
        render_pages_free(map);
    return rc;
}

/* Reads whole pages of memory the program did not allocate itself (the
 * allocator's headers and padding around Mesa's buffer): not a bug under
 * AddressSanitizer, so not instrumented. */
#if defined(__has_attribute)
#if __has_attribute(no_sanitize)
#define PAGES_RAW_READ __attribute__((no_sanitize("address"), noinline))
#endif
#endif
#ifndef PAGES_RAW_READ
#define PAGES_RAW_READ
#endif

PAGES_RAW_READ static bool page_is_zero(const unsigned char *p, size_t size)
{
    const uint64_t *w = (const uint64_t *)(const void *)p;
    uint64_t any = 0;
    for (size_t i = 0; i < size / sizeof *w; i++)
        any |= w[i];
    return any == 0;
}

/* Drops the zero pages of [start, end) (page aligned). */
static size_t release_span(uintptr_t start, uintptr_t end, size_t page)
{
    size_t released = 0;
    uintptr_t run = 0; /* start of the current run of zero pages, 0: none */
    for (uintptr_t p = start; p <= end; p += page) {
        bool zero = p < end && page_is_zero((const unsigned char *)p, page);
        if (zero && !run)
            run = p;
        if (!zero && run) {
            if (madvise((void *)run, p - run, MADV_DONTNEED) == 0)
                released += p - run;
            run = 0;
        }
    }
    return released;
}

size_t render_pages_release(const render_page_map *before, size_t min_bytes)
{
    render_page_map now;
    if (!before->spans || render_pages_snapshot(&now) != 0)
        return 0;
    size_t page = (size_t)sysconf(_SC_PAGESIZE);
    size_t released = 0;
    for (size_t i = 0; i < now.count; i++) {
        /* The parts of this span no old span covered (the kernel merges a
         * new mapping into an adjacent one, so compare ranges, not lines). */
        uintptr_t at = now.spans[i].start, end = now.spans[i].end;
        while (at < end) {
            uintptr_t next_old = end;
            bool covered = false;
            for (size_t j = 0; j < before->count; j++) {
                const render_span *o = &before->spans[j];
                if (o->start <= at && at < o->end) {
                    at = o->end < end ? o->end : end;
                    covered = true;
                    break;
                }
                if (o->start > at && o->start < next_old)
                    next_old = o->start;
            }
            if (covered)
                continue;
            if (next_old - at >= min_bytes)
                released += release_span(at, next_old, page);
            at = next_old;
        }
    }
    render_pages_free(&now);
    return released;
}

void render_pages_free(render_page_map *map)
{
    free(map->spans);
    map->spans = NULL;
    map->count = 0;
}
