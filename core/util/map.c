/* core/util/map.c — the name map of map.h: open addressing with linear
 * probing, a power-of-two capacity kept at least twice the count. Owns its
 * key and value arrays, never the values; never takes name 0 as a key. */
#include "map.h"

#include <stdlib.h>
#include <string.h>

static size_t slot_of(const tsr_name_map *m, uint32_t key)
{
    size_t mask = m->cap - 1, i = (key * 2654435761u) & mask;
    while (m->keys[i] && m->keys[i] != key)
        i = (i + 1) & mask;
    return i;
}

void *tsr_name_map_get(const tsr_name_map *m, uint32_t key)
{
    if (!m->cap || !key)
        return NULL;
    size_t i = slot_of(m, key);
    return m->keys[i] ? m->vals[i] : NULL;
}

static int grow(tsr_name_map *m)
{
    size_t cap = m->cap ? m->cap * 2 : 16;
    tsr_name_map n = {calloc(cap, sizeof *n.keys), calloc(cap, sizeof *n.vals), cap, 0, m->max_key};
    if (!n.keys || !n.vals) {
        free(n.keys);
        free(n.vals);
        return -1;
    }
    for (size_t i = 0; i < m->cap; i++)
        if (m->keys[i]) {
            size_t j = slot_of(&n, m->keys[i]);
            n.keys[j] = m->keys[i];
            n.vals[j] = m->vals[i];
            n.n++;
        }
    free(m->keys);
    free(m->vals);
    *m = n;
    return 0;
}

int tsr_name_map_put(tsr_name_map *m, uint32_t key, void *val)
{
    if (!key)
        return -1;
    if ((m->n + 1) * 2 > m->cap && grow(m) != 0)
        return -1;
    size_t i = slot_of(m, key);
    if (!m->keys[i]) {
        m->keys[i] = key;
        m->n++;
    }
    m->vals[i] = val;
    if (key > m->max_key)
        m->max_key = key;
    return 0;
}

void *tsr_name_map_del(tsr_name_map *m, uint32_t key)
{
    if (!m->cap || !key)
        return NULL;
    size_t mask = m->cap - 1, i = slot_of(m, key);
    if (!m->keys[i])
        return NULL;
    void *old = m->vals[i];
    m->keys[i] = 0;
    m->vals[i] = NULL;
    m->n--;
    /* Re-insert the rest of the cluster (linear probing deletion). */
    for (size_t j = (i + 1) & mask; m->keys[j]; j = (j + 1) & mask) {
        uint32_t k = m->keys[j];
        void *v = m->vals[j];
        m->keys[j] = 0;
        m->vals[j] = NULL;
        size_t s = slot_of(m, k);
        m->keys[s] = k;
        m->vals[s] = v;
    }
    return old;
}

void tsr_name_map_free(tsr_name_map *m)
{
    free(m->keys);
    free(m->vals);
    memset(m, 0, sizeof *m);
}
