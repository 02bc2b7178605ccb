/* tessera/dev/util.h — small helpers that servers, coordinators and SPUs
 * share, so each exists once: a monotonic clock, a JSON string writer
 * (statistics files), peer text made safe to print, and "did you mean"
 * suggestions for error messages.
 * Part of libtessera (pkg-config tessera).
 *
 * Owns nothing: every function is pure or writes only where it is told.
 * Never: keeps state between calls or allocates.
 *
 *   double t0 = tsr_now_seconds();
 *   fprintf(f, "{\"name\":");
 *   tsr_json_string(f, name);                       // "pack#0", escaped
 *   fprintf(f, ",\"seconds\":%.3f}", tsr_now_seconds() - t0);
 *   const char *near = tsr_closest_name(word, names, count);
 *   if (near) ... "unknown option 'sever' (did you mean 'server'?)"
 */
#ifndef TESSERA_DEV_UTIL_H
#define TESSERA_DEV_UTIL_H

#include <stddef.h>
#include <stdio.h>

#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Seconds on CLOCK_MONOTONIC (for intervals; the origin is arbitrary). */
TSR_API double tsr_now_seconds(void);

/* Writes `s` to `f` as a JSON string: quoted, with quotes, backslashes and
 * control bytes escaped. */
TSR_API void tsr_json_string(FILE *f, const char *s);

/* Copies `len` bytes of text that came from a peer (a server's ERROR
 * reason, a node's DONE message, a name from a handshake) into `out`, made
 * safe for a terminal or a log: control bytes (C0, DEL, and C1 controls
 * U+0080..U+009F) and bytes that are not valid UTF-8 become "\xNN"; valid
 * UTF-8 is kept. Always NUL-terminates `out` (size > 0), cutting at a
 * whole character or escape when it is full. Returns the bytes written,
 * without the NUL. Use it on every peer's text before printing it. */
TSR_API size_t tsr_text_sanitize(char *out, size_t size, const void *in, size_t len);

/* Longest word the suggestions consider. */
#define TSR_SUGGEST_MAX_LEN 64
/* Edit distance (insert, delete, substitute, swap adjacent); (size_t)-1
 * for words over TSR_SUGGEST_MAX_LEN bytes. */
TSR_API size_t tsr_edit_distance(const char *a, const char *b);
/* The candidate closest to `word` if it is close enough to be a likely
 * typo (at most two edits, never the whole word), else NULL. */
TSR_API const char *tsr_closest_name(const char *word, const char *const *candidates, size_t count);

#ifdef __cplusplus
}
#endif
#endif
