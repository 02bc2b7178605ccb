/* tessera/dev/native.h — the native window behind a tessera window id in
 * this process: set by whatever makes the stream's windows out of a
 * program's own windows (the faker, faker/, for an X drawable), read by an
 * SPU in the same process that draws frames back into that window (render's
 * window_output=app), as remote-rendering tools draw into the program's
 * window. Part of libtessera (pkg-config tessera).
 *
 * Owns: one table per process of (window id -> X display name, drawable),
 * behind a mutex. It is process-wide because the windows are: a program
 * has one set of X windows whatever chains run in it.
 * Never: opens a connection, knows who sets or reads it, or holds SPU
 * state.
 *
 *   tsr_native_window_set(0, ":5", 0x200002);      // faker, at WindowCreateTSR
 *   char dpy[256]; unsigned long xid;
 *   if (tsr_native_window_get(0, dpy, sizeof dpy, &xid)) ...  // SPU, at a swap
 */
#ifndef TESSERA_DEV_NATIVE_H
#define TESSERA_DEV_NATIVE_H

#include <stddef.h>

#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Records (or replaces) window `window`'s X drawable `xid` on the display
 * named `x_display` (XDisplayName's spelling; NULL or "" : $DISPLAY).
 * xid 0 forgets the window. 0: done; -1: out of memory. */
TSR_API int tsr_native_window_set(int window, const char *x_display, unsigned long xid);

/* 1 with the display name (truncated to n bytes, NUL-ended) and drawable
 * of `window`; 0 when none was set. */
TSR_API int tsr_native_window_get(int window, char *x_display, size_t n, unsigned long *xid);

#ifdef __cplusplus
}
#endif

#endif
