/* core/spu/spu_loader.h — internal: checking SPU classes and walking their
 * super lineage (the public half is tessera/spu.h). Owns nothing.
 * Never: hands out a class that failed its checks. */
#ifndef TSR_CORE_SPU_LOADER_H
#define TSR_CORE_SPU_LOADER_H

#include <stddef.h>

#include "tessera/spu.h"

/* How many supers an SPU may have above it (readback -> render is one). */
#define TSR_SPU_MAX_SUPER_DEPTH 8

/* Checks what the loader relies on: ABI and dispatch size, a valid name,
 * create/destroy present, option declarations (defaults parse). `origin`
 * (a file path or "registered") goes into messages. */
int tsr_spu_class_check(const tsr_spu_class *cls, const char *origin, tsr_error *err);

/* Fills out[0] = cls, out[1] = its super, ... (finding each by name), at
 * most 1 + TSR_SPU_MAX_SUPER_DEPTH entries; a cycle, a deeper lineage or a
 * missing super is an error naming the SPUs involved. Returns the count, or
 * 0 with `err` filled. */
size_t tsr_spu_lineage(const tsr_spu_class *cls, const tsr_spu_class *out[TSR_SPU_MAX_SUPER_DEPTH + 1], tsr_error *err);

#endif
