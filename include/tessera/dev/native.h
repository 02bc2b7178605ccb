/* tessera/dev/native.h — the native windows behind a chain's tessera
 * window ids: set by whatever makes the stream's windows out of a
 * program's own windows (the faker, faker/, for an X drawable), read by an
 * SPU of that chain that draws frames back into that window (render's
 * window_output=app), as remote-rendering tools draw into the program's
 * window. Part of libtessera (pkg-config tessera).
 *
 * Owns: one table per chain (tsr_chain_native_windows; an SPU gets its
 * chain's in tsr_spu_init.native_windows) of (window id -> X display name,
 * drawable), behind a mutex: two chains in one process keep two tables.
 * Never: opens a connection, knows who sets or reads it, holds SPU state
 * or anything process-wide.
 *
 *   tsr_native_window_set(tsr_chain_native_windows(chain), 0, ":5", 0x200002); // faker
 *   char dpy[256]; unsigned long xid;
 *   if (tsr_native_window_get(init->native_windows, 0, dpy, sizeof dpy, &xid)) ... // SPU
 */
#ifndef TESSERA_DEV_NATIVE_H
#define TESSERA_DEV_NATIVE_H

#include <stddef.h>

#include "tessera/chain.h"
#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct tsr_native_windows tsr_native_windows;

/* An empty table; NULL when out of memory. A chain makes its own; this is
 * for a program or test that keeps one outside a chain. */
TSR_API tsr_native_windows *tsr_native_windows_create(void);
/* Frees the table and its entries; NULL is allowed. */
TSR_API void tsr_native_windows_destroy(tsr_native_windows *windows);

/* The table `chain` owns and hands its SPUs; valid until tsr_chain_destroy. */
TSR_API tsr_native_windows *tsr_chain_native_windows(const tsr_chain *chain);

/* Records (or replaces) window `window`'s X drawable `xid` on the display
 * named `x_display` (XDisplayName's spelling; NULL or "" : $DISPLAY).
 * xid 0 forgets the window. 0: done; -1: out of memory or no table. */
TSR_API int tsr_native_window_set(tsr_native_windows *windows, int window, const char *x_display, unsigned long xid);

/* 1 with the display name (truncated to n bytes, NUL-ended) and drawable
 * of `window`; 0 when none was set or `windows` is NULL. */
TSR_API int tsr_native_window_get(tsr_native_windows *windows, int window, char *x_display, size_t n,
                                  unsigned long *xid);

#ifdef __cplusplus
}
#endif

#endif
