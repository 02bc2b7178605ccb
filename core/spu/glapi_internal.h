/* core/spu/glapi_internal.h — the calling thread's current dispatch table,
 * shared by core/spu/glapi.c (make current) and the generated gl* entry points
 * of libtessera_gl. Owns nothing else; never include it outside tessera_gl. */
#ifndef TSR_CORE_GLAPI_INTERNAL_H
#define TSR_CORE_GLAPI_INTERNAL_H

#include "tessera/dispatch.h"

/* initial-exec: one %fs-relative load per GL call (libtessera_gl is linked,
 * or dlopen'ed early like Mesa's libGL, which uses the same model). */
extern _Thread_local const tsr_dispatch *tsr_gl_current_table
    __attribute__((tls_model("initial-exec"), visibility("hidden")));

/* A gl* entry called with no current table (gl_entry_gen.c): GL's
 * behaviour is that nothing happens and queries return 0; the first such
 * call of each thread is logged, naming the function, so that a program
 * drawing without a tessera context (its context made by another GL
 * library, or never made current) is not silent. */
void tsr_gl_no_context(const char *name) __attribute__((visibility("hidden"), cold));

#endif
