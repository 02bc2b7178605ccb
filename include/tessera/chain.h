/* tessera/chain.h — a chain of SPU instances in one process.
 *
 * Text form (command lines, TESSERA_CHAIN): SPUs separated by '!', each a
 * name followed by key=value options; values may be quoted with "..." .
 *   "print file=trace.txt ! loopback ! render output=out/f-%04d.png"
 * Unknown SPUs, unknown options and bad values fail with a message naming
 * the SPU, the option and the value. */
#ifndef TESSERA_CHAIN_H
#define TESSERA_CHAIN_H

#include <stddef.h>
#include "tessera/dispatch.h"
#include "tessera/error.h"
#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct tsr_chain tsr_chain;

/* One SPU of a chain with its options in text form. */
typedef struct tsr_chain_link {
    const char *spu;
    const char *const *keys;
    const char *const *values;
    size_t option_count;
} tsr_chain_link;

TSR_API tsr_chain *tsr_chain_create(const char *text, tsr_error *err);
TSR_API tsr_chain *tsr_chain_create_links(const tsr_chain_link *links, size_t count, tsr_error *err);
/* The text form of `count` links, each value quoted (and '"' and '\'
 * escaped), so tsr_chain_create reads back exactly these links. Returns a
 * malloc'ed string to free(), or NULL with `err` filled (no links, out of
 * memory). */
TSR_API char *tsr_chain_links_text(const tsr_chain_link *links, size_t count, tsr_error *err);
/* The table calls enter through (the first SPU's resolved table). Valid
 * until tsr_chain_destroy. */
TSR_API const tsr_dispatch *tsr_chain_head(const tsr_chain *chain);
/* Destroys instances first to last. NULL is allowed. */
TSR_API void tsr_chain_destroy(tsr_chain *chain);

#ifdef __cplusplus
}
#endif
#endif
