/* faker/refused.c — a library of glvnd's that the faker stands in for
 * without its contents, so that the system's copy is never mapped next to
 * the faker (tessera exec puts the faker's directory first in
 * LD_LIBRARY_PATH): built twice, as libGLdispatch.so.0 (FAKER_GLDISPATCH)
 * and libGLESv2.so.2 (FAKER_GLESV2). Its only code logs one line when the
 * library is loaded, saying what that means.
 *
 * libGLdispatch.so.0 is glvnd's internal dispatch, used only by glvnd's
 * other libraries, which the faker replaces: a system glvnd library loaded
 * by full path would need its symbols, finds none, and fails to load — a
 * clean refusal instead of a second GL stack. libGLESv2.so.2 (OpenGL ES 2
 * and 3): it depends on the faker's libGL.so.1, so the names ES shares
 * with OpenGL bind to the faker; ES contexts are refused by eglBindAPI
 * and glXCreateContextAttribsARB (ES is out of tessera's scope). */
#include "faker_gl.h"
#include "tessera/log.h"

#if defined(FAKER_GLDISPATCH)
#define FAKER_LIBRARY "libGLdispatch.so.0"
#define FAKER_LEVEL TSR_LOG_WARN
#define FAKER_REASON                                                                                             \
    "glvnd's internal dispatch is not used by the faker, which replaces glvnd's libraries: a system GL library " \
    "that needs it fails to load"
#elif defined(FAKER_GLESV2)
#define FAKER_LIBRARY "libGLESv2.so.2"
/* Info: replayers and loaders open it to probe; an ES context is refused
 * with its own error line. */
#define FAKER_LEVEL TSR_LOG_INFO
#define FAKER_REASON                                                                                            \
    "OpenGL ES is not supported by tessera: the names ES shares with OpenGL reach the faker's GL, ES contexts " \
    "are refused"
#else
#error "build refused.c with FAKER_GLDISPATCH or FAKER_GLESV2"
#endif

__attribute__((constructor)) static void tsr_faker_refused_loaded(void)
{
    tsr_faker_log(FAKER_LEVEL, "%s was loaded: %s", FAKER_LIBRARY, FAKER_REASON);
}
