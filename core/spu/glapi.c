/* core/spu/glapi.c — makes a dispatch table current for the calling thread
 * (libtessera_gl). Owns the thread-local current-table pointer; never owns
 * or frees the tables themselves (their creators do). */
#include "glapi_internal.h"
#include "tessera/glapi.h"

_Thread_local const tsr_dispatch *tsr_gl_current_table = NULL;

void tsr_gl_make_current(const tsr_dispatch *table) { tsr_gl_current_table = table; }

const tsr_dispatch *tsr_gl_current(void) { return tsr_gl_current_table; }
