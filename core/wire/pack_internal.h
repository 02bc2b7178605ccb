/* core/wire/pack_internal.h — what the packer runtime's two files share:
 * pack.c (buffer memory and flushing, replies, client-array draws and the
 * other hand-written packers) and pack_mirror.c (the mirrors of client
 * state). Not for anything outside core/wire. */
#ifndef TSR_CORE_WIRE_PACK_INTERNAL_H
#define TSR_CORE_WIRE_PACK_INTERNAL_H

#include "tessera/dev/pack.h"

/* pack.c */
/* Records the packer's first error; later ones are dropped. */
void pack_record(tsr_packer *p, int code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

#endif
