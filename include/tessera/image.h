/* tessera/image.h — RGBA8 images: PNG read/write (libpng), pixel compare
 * (differing pixels, max channel error, PSNR) and row flipping.
 * Owns image memory it allocates; never exits or prints on bad input:
 * every failure is a tsr_error naming the file and the problem.
 *
 * Pixels are 8-bit RGBA, rows top to bottom, `stride` bytes apart (always
 * width * 4 for images made here). OpenGL reads framebuffers bottom row
 * first: flip with tsr_image_flip_rows, or write such a buffer straight to
 * PNG with tsr_image_write_png_pixels(..., bottom_up = true, ...). */
#ifndef TESSERA_IMAGE_H
#define TESSERA_IMAGE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "tessera/error.h"
#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest width or height accepted (reading and allocating). */
#define TSR_IMAGE_MAX_SIDE 32768

typedef struct tsr_image {
    int width;
    int height;
    size_t stride;   /* bytes from one row to the next: width * 4 */
    uint8_t *pixels; /* RGBA8, top row first; owned (tsr_image_free) */
} tsr_image;

/* Result of comparing two images of the same size. */
typedef struct tsr_image_diff {
    uint64_t differing_pixels; /* pixels with any channel off by more than the tolerance */
    int max_channel_error;     /* largest |a - b| over all channels (0..255) */
    double psnr_db;            /* over R, G, B and A; INFINITY when identical */
} tsr_image_diff;

/* Allocates a zeroed width x height image (1..TSR_IMAGE_MAX_SIDE each). */
TSR_API int tsr_image_alloc(tsr_image *img, int width, int height, tsr_error *err);
/* Frees the pixels and zeroes the struct; safe on a zeroed struct. */
TSR_API void tsr_image_free(tsr_image *img);

/* Reads a PNG file into `img` (allocated here; free with tsr_image_free).
 * Grey, grey+alpha, RGB, palette, 1/2/4/16-bit and interlaced files are
 * converted to RGBA8 (16-bit channels keep their high byte; missing alpha
 * becomes 255). On failure `img` is left zeroed. */
TSR_API int tsr_image_read_png(tsr_image *img, const char *path, tsr_error *err);
/* The same, refusing (TSR_EINVAL, naming the limit) before allocating or
 * decoding anything a file whose header claims more than `max_pixels`
 * (width x height) or more than TSR_IMAGE_MAX_SIDE per side. */
TSR_API int tsr_image_read_png_limited(tsr_image *img, const char *path, uint64_t max_pixels, tsr_error *err);
/* Reads only the signature and header: the size the file claims, under
 * the same limits. */
TSR_API int tsr_image_read_png_size(const char *path, uint64_t max_pixels, int *width, int *height, tsr_error *err);

/* Writes `img` as an 8-bit RGBA PNG, replacing `path` only when the file
 * is whole: it is written to a hidden temporary in the same directory
 * (".NAME.tmp-PID-N") and renamed, so a reader, a kill or a failure never
 * leaves a partial PNG under `path`. The temporary is removed on failure;
 * a signal that ends the process leaves it, unless the program listed it
 * (tsr_image_set_pending below). The directory must exist. */
TSR_API int tsr_image_write_png(const tsr_image *img, const char *path, tsr_error *err);

/* --- temporaries left by a signal ---------------------------------------
 * The library installs no signal handler of its own accord. A program
 * that wants no temporary left when SIGTERM, SIGINT or SIGHUP ends it
 * (the `tessera` program, the examples, the faker in the program it runs
 * in) opts in with one call at start-up:
 *
 *   tsr_image_pending_remove_on_signals(&err);
 *
 * A program with its own handlers instead owns a table, hands it to the
 * writer, and empties it from its handler:
 *
 *   static tsr_image_pending *pending;
 *   static void on_term(int sig) { tsr_image_pending_remove_all(pending); raise(sig); }  // SA_RESETHAND
 *   pending = tsr_image_pending_create(); tsr_image_set_pending(pending); sigaction(SIGTERM, ...);
 *
 * The table lists at most 32 PNGs being written at once (more are written
 * unlisted). */
typedef struct tsr_image_pending tsr_image_pending;
/* An empty table; NULL when out of memory. */
TSR_API tsr_image_pending *tsr_image_pending_create(void);
/* Frees it (and stops the writer using it, if it was the one set). No
 * PNG may be being written into it. */
TSR_API void tsr_image_pending_destroy(tsr_image_pending *pending);
/* Every PNG writer in the process lists its temporaries in `pending` from
 * now on (NULL: in none). The program's to set: the one process-wide hook
 * of this header. */
TSR_API void tsr_image_set_pending(tsr_image_pending *pending);
/* Removes every temporary listed by this process (not by a forked child
 * that inherited the table). Async-signal-safe: for a signal handler. */
TSR_API void tsr_image_pending_remove_all(tsr_image_pending *pending);

/* The program's opt-in: creates the process's table, sets it
 * (tsr_image_set_pending) and installs, over each of SIGTERM, SIGINT and
 * SIGHUP that still has its default action (a handler installed before is
 * left alone), a handler that removes the listed temporaries and lets the
 * signal end the process as before (SA_RESETHAND). Only the first call in
 * a process acts; any thread may call it. Returns 0, or TSR_ENOMEM with
 * nothing installed. */
TSR_API int tsr_image_pending_remove_on_signals(tsr_error *err);

/* Writes caller-owned RGBA8 pixels without copying them. `bottom_up`: the
 * first row in memory is the bottom row of the picture (glReadPixels,
 * OSMesa buffers); the file is written top row first either way.
 * `keep_alpha`: an RGBA PNG with each pixel's alpha; false: an RGB PNG of
 * the same colour bytes, each alpha dropped, so the file shows what a
 * window shows (an X window ignores the framebuffer's alpha); read back,
 * its alpha is 255 everywhere. */
TSR_API int tsr_image_write_png_pixels(const uint8_t *pixels, int width, int height, size_t stride, bool bottom_up,
                                       bool keep_alpha, const char *path, tsr_error *err);

/* Compares `a` and `b` channel by channel. A pixel differs when any of its
 * four channels differs by more than `tolerance` (0 = exact). Images of
 * different sizes are an error (TSR_EINVAL) naming both sizes. */
TSR_API int tsr_image_compare(const tsr_image *a, const tsr_image *b, int tolerance, tsr_image_diff *out,
                              tsr_error *err);

/* Formats a frame file name from a printf-style `pattern` holding at most
 * one integer conversion (%d or %i with optional flags 0-+ and a width up
 * to 2 digits, e.g. "out/frame-%04d.png"); "%%" is a literal '%'. Any
 * other '%' use is an error (TSR_EINVAL) naming the pattern, so a user's
 * pattern is never handed to printf unchecked. */
TSR_API int tsr_image_frame_path(char *out, size_t size, const char *pattern, int frame, tsr_error *err);

/* Checks an output option's frame `pattern` as tsr_image_frame_path will
 * use it, and that it holds a frame number unless `overwrite` (a pattern
 * without one writes every frame over the same file). Errors are one line
 * naming `who`, `option`=`pattern` and, for a missing frame number, the
 * option `overwrite_option` that allows it. */
TSR_API int tsr_image_check_frame_pattern(const char *who, const char *option, const char *pattern, bool overwrite,
                                          const char *overwrite_option, tsr_error *err);

/* Reverses the order of `height` rows of `stride` bytes in place. */
TSR_API void tsr_image_flip_rows(uint8_t *pixels, int height, size_t stride);

#ifdef __cplusplus
}
#endif
#endif
