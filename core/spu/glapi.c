/* core/spu/glapi.c — makes a dispatch table current for the calling thread
 * (libtessera_gl, and the faker's libGL.so.1). Owns the thread-local
 * current-table pointer and whether this thread was told it called GL with
 * none; never owns or frees the tables themselves (their creators do). */
#include <stdbool.h>

#include "glapi_internal.h"
#include "tessera/glapi.h"
#include "tessera/log.h"

_Thread_local const tsr_dispatch *tsr_gl_current_table = NULL;

void tsr_gl_make_current(const tsr_dispatch *table) { tsr_gl_current_table = table; }

const tsr_dispatch *tsr_gl_current(void) { return tsr_gl_current_table; }

static _Thread_local bool told_no_context;

void tsr_gl_no_context(const char *name)
{
    if (told_no_context)
        return;
    told_no_context = true;
    tsr_log(TSR_LOG_WARN,
            "%s called with no current tessera context: ignored (GL's behaviour: no effect, queries return 0); "
            "logged once a thread",
            name);
}
