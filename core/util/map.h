/* core/util/map.h — a map from 32-bit GL object names to pointers (open
 * addressing with linear probing; name 0 is never a key, as in GL). Used by
 * the state tracker, the display-list store and the GLSL name tables.
 * Owns its key and value arrays, never the values. Internal to libtessera. */
#ifndef TSR_CORE_UTIL_MAP_H
#define TSR_CORE_UTIL_MAP_H

#include <stddef.h>
#include <stdint.h>

typedef struct tsr_name_map {
    uint32_t *keys;
    void **vals;
    size_t cap, n;    /* cap: a power of two (or 0) */
    uint32_t max_key; /* largest key ever inserted: names are generated above it */
} tsr_name_map;

void *tsr_name_map_get(const tsr_name_map *m, uint32_t key);
/* 0 ok, -1 out of memory (or key 0). */
int tsr_name_map_put(tsr_name_map *m, uint32_t key, void *val);
/* Removes `key`; returns its value, or NULL. */
void *tsr_name_map_del(tsr_name_map *m, uint32_t key);
void tsr_name_map_free(tsr_name_map *m);
/* Iteration: for (size_t i = 0; i < m->cap; i++) if (m->keys[i]) ... */

#endif
