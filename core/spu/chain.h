/* core/spu/chain.h — internal: the text form of a chain ("a k=v ! b") parsed
 * into links (tessera/chain.h builds and runs chains). Owns: the parsed
 * strings. Never: looks SPUs up or creates anything. */
#ifndef TSR_CORE_CHAIN_H
#define TSR_CORE_CHAIN_H

#include <stddef.h>

#include "tessera/chain.h"

typedef struct tsr_chain_text {
    tsr_chain_link *links;
    size_t count;
} tsr_chain_text;

/* Splits `text` into links; errors quote the offending token and its
 * column ("chain: 'k' after 'render' (column 8) is not key=value"). */
int tsr_chain_text_parse(const char *text, tsr_chain_text *out, tsr_error *err);
void tsr_chain_text_free(tsr_chain_text *parsed);

#endif
