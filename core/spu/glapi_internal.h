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

#endif
