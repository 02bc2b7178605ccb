/* spus/tilesort/batch.c — compact draws built primitive by primitive.
 * When tilesort sorts an array draw primitive by primitive, each server
 * collects the primitives that touch its tiles into a ts_batch: the source
 * vertices they use, each once (a hash from source vertex to compact
 * vertex), and the primitives' indices renumbered to the compact vertices.
 * Sent as one glDrawElements (or glDrawArrays) over gathered arrays, a
 * server gets only the vertices its primitives use. Owns nothing but the
 * batch's own arrays. */
#include <stdlib.h>
#include <string.h>

#include "tilesort.h"

void ts_batch_free(ts_batch *b)
{
    free(b->order);
    free(b->index);
    free(b->keys);
    free(b->values);
    memset(b, 0, sizeof *b);
}

void ts_batch_clear(ts_batch *b)
{
    if (b->nvert && b->keys)
        memset(b->keys, 0, b->hcap * sizeof *b->keys);
    b->nvert = b->nidx = 0;
}

static int grow(uint32_t **v, size_t *cap, size_t need)
{
    if (need <= *cap)
        return 0;
    size_t n = *cap ? *cap : 256;
    while (n < need)
        n *= 2;
    uint32_t *p = realloc(*v, n * sizeof *p);
    if (!p)
        return -1;
    *v = p;
    *cap = n;
    return 0;
}

static size_t slot_of(const ts_batch *b, uint32_t key)
{
    size_t mask = b->hcap - 1, h = (size_t)(key * 2654435761u) & mask;
    while (b->keys[h] && b->keys[h] != key)
        h = (h + 1) & mask;
    return h;
}

/* Keeps the hash at most half full (keys are source vertex + 1; 0: empty). */
static int grow_hash(ts_batch *b, size_t need)
{
    if (2 * need <= b->hcap)
        return 0;
    size_t cap = b->hcap ? b->hcap : 1024;
    while (cap < 2 * need)
        cap *= 2;
    uint32_t *keys = calloc(cap, sizeof *keys), *values = malloc(cap * sizeof *values);
    if (!keys || !values) {
        free(keys);
        free(values);
        return -1;
    }
    uint32_t *old_keys = b->keys, *old_values = b->values;
    size_t old_cap = b->hcap;
    b->keys = keys;
    b->values = values;
    b->hcap = cap;
    for (size_t i = 0; i < old_cap; i++)
        if (old_keys[i]) {
            size_t h = slot_of(b, old_keys[i]);
            b->keys[h] = old_keys[i];
            b->values[h] = old_values[i];
        }
    free(old_keys);
    free(old_values);
    return 0;
}

int ts_batch_add(ts_batch *b, const uint32_t *vertices, int n, int indexed)
{
    if (grow(&b->order, &b->vcap, b->nvert + (size_t)n) != 0)
        return -1;
    if (!indexed) {
        for (int k = 0; k < n; k++)
            b->order[b->nvert++] = vertices[k];
        return 0;
    }
    if (grow(&b->index, &b->icap, b->nidx + (size_t)n) != 0 || grow_hash(b, b->nvert + (size_t)n) != 0)
        return -1;
    for (int k = 0; k < n; k++) {
        if (vertices[k] == UINT32_MAX)
            return -1; /* cannot be keyed; no client array is that long */
        uint32_t key = vertices[k] + 1;
        size_t h = slot_of(b, key);
        if (!b->keys[h]) {
            b->keys[h] = key;
            b->values[h] = (uint32_t)b->nvert;
            b->order[b->nvert++] = vertices[k];
        }
        b->index[b->nidx++] = b->values[h];
    }
    return 0;
}
