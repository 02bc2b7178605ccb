/* tessera/glapi.h — the exported gl* entry points (library tessera_gl).
 * Every GL function of the spec is exported by libtessera_gl and jumps
 * through the calling thread's current dispatch table; programs written as
 * ordinary GL code link against it instead of libGL/libOSMesa and their
 * calls enter a tessera chain. (The faker adds GLX/EGL on top of this.) */
#ifndef TESSERA_GLAPI_H
#define TESSERA_GLAPI_H

#include "tessera/dispatch.h"
#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Makes `table` current for the calling thread (NULL: calls do nothing). */
TSR_API void tsr_gl_make_current(const tsr_dispatch *table);
TSR_API const tsr_dispatch *tsr_gl_current(void);

#ifdef __cplusplus
}
#endif
#endif
