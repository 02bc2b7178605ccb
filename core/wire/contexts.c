/* core/wire/contexts.c — the client state a packer or an unpacker keeps for
 * the contexts of its stream other than the current one (wire_internal.h,
 * tsr_wire_contexts): records of one size, each starting with its context
 * number. Owns the records; never interprets what follows the number. */
#include <stdlib.h>
#include <string.h>

#include "wire_internal.h"

struct tsr_wire_contexts {
    unsigned char *records;
    size_t size, count, cap;
};

void *tsr_wire_contexts_find(tsr_wire_contexts *t, GLint context)
{
    for (size_t i = 0; t && i < t->count; i++) {
        unsigned char *r = t->records + i * t->size;
        GLint id;
        memcpy(&id, r, sizeof id);
        if (id == context)
            return r;
    }
    return NULL;
}

void *tsr_wire_contexts_add(tsr_wire_contexts **tp, GLint context, size_t size)
{
    if (!*tp) {
        *tp = calloc(1, sizeof **tp);
        if (!*tp)
            return NULL;
        (*tp)->size = size;
    }
    tsr_wire_contexts *t = *tp;
    if (t->count == t->cap) {
        size_t cap = t->cap ? 2 * t->cap : 4;
        unsigned char *r = realloc(t->records, cap * t->size);
        if (!r)
            return NULL;
        t->records = r;
        t->cap = cap;
    }
    unsigned char *r = t->records + t->count++ * t->size;
    memset(r, 0, t->size);
    memcpy(r, &context, sizeof context);
    return r;
}

void tsr_wire_contexts_remove(tsr_wire_contexts *t, GLint context)
{
    unsigned char *r = tsr_wire_contexts_find(t, context);
    if (r) {
        t->count--;
        memmove(r, t->records + t->count * t->size, t->size);
    }
}

void tsr_wire_contexts_free(tsr_wire_contexts *t)
{
    if (t)
        free(t->records);
    free(t);
}
