/* tessera/dev/composite.h — sort-last compositing images, kernels and image
 * messages: what a compositing SPU (and the readback-to-display path) moves
 * between peers. Part of libtessera.
 *
 * Owns: the pixel memory of the images it allocates (64-byte aligned);
 * nothing else, and no process-wide state (the vector kernels are chosen by
 * the dynamic loader, per CPU, through ifunc clones). Never: does I/O,
 * touches GL, prints, exits or aborts; every failure is a tsr_error naming
 * the culprit (the peer rank and frame when a message is decoded).
 *
 * Coordinates. An image lives in a window of window_width x window_height
 * pixels, origin bottom left, rows bottom first (as glReadPixels and OSMesa
 * give them). A pixel's index is y * window_width + x. A dense image is a
 * rectangle of the window (its region of interest); a sparse image covers a
 * range of pixel indices [start, start + count) — whole rows make a
 * rectangle, a strip that starts or ends mid-row does not. Strategies split
 * the window by index ranges, so 1x1, 509x503 and 997x1 windows split into
 * any number of pieces (some possibly empty) without losing a pixel.
 *
 * Active pixels. Depth mode: depth < 1.0 (background is the cleared 1.0; a
 * NaN depth is never active and never wins). Alpha mode: any colour channel
 * non-zero (premultiplied: transparent black is background). Background
 * costs nothing: a sparse image stores only runs of (inactive, active)
 * counts and the active pixels' values, and merging two sparse images walks
 * the runs, never the background. The background colour is added once, when
 * the final frame is assembled (tsr_composite_sparse_to_dense).
 *
 * Order. Every merge takes a FRONT and a BACK image. Depth mode: the nearer
 * depth wins; on EQUAL depth the front wins. Alpha mode: front over back
 * (premultiplied; "under" is the same call with the accumulated image as
 * front). A strategy only ever merges images covering adjacent intervals of
 * the compositing order (rank order in depth mode, the view order in alpha
 * mode), the earlier interval as front. So equal depth goes to the lower
 * rank and every strategy, peer count and arrival order gives the same bits.
 *
 * Depth comparison: IEEE total order on the float's bits, with every NaN
 * greater than everything (NaN never wins, not even against background),
 * -0.0 < +0.0. OSMesa depth is in [0, 1], where this is ordinary "<".
 *
 * RGBA8 over: out = front + round(back * (255 - front_alpha) / 255), per
 * channel, saturated at 255. It is exact (and associative) whenever every
 * alpha is 0 or 255; otherwise rounding may differ by 1 between groupings.
 * RGBA32F over: out = front + back * (1 - front_alpha), in float (not
 * associative either). So alpha mode's frame is defined as the serial
 * back-to-front blend, (L0 over (L1 over (... over Ln-1))) over background;
 * the compositing executor folds in that grouping and accepts only
 * schedules that keep it (spus/binaryswap/strategies/strategy.h,
 * tsr_composite_schedule_keeps_order).
 *
 * Use (one peer, one round of a strategy, transport elided):
 *
 *   tsr_composite_image roi;          // filled from glReadPixels of the ROI
 *   tsr_composite_image_init(&roi, W, H, x, y, w, h, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, &err);
 *   tsr_composite_sparse mine = {0}, piece = {0}, theirs = {0}, out = {0};
 *   tsr_composite_sparse_compress(&roi, TSR_COMPOSITE_DEPTH, 0, W * H, &mine, &err);
 *   tsr_composite_sparse_split(&mine, half_start, half_count, &piece, &err);
 *   size_t cap = tsr_composite_message_max_size(half_count, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, codec);
 *   tsr_composite_message_encode(&piece, codec, buf, cap, &len, &err);   // send buf
 *   tsr_composite_message_decode(rbuf, rlen, &expect, &theirs, &err);    // received
 *   tsr_composite_sparse_merge(&front, &back, &out, &err);
 */
#ifndef TESSERA_DEV_COMPOSITE_H
#define TESSERA_DEV_COMPOSITE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "tessera/error.h"
#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest window side accepted (so pixel indices fit 32 bits). */
#define TSR_COMPOSITE_MAX_SIDE 32768

typedef enum tsr_composite_color_format {
    TSR_COMPOSITE_RGBA8 = 1,   /* 4 bytes per pixel, GL_RGBA/GL_UNSIGNED_BYTE */
    TSR_COMPOSITE_RGBA32F = 2, /* 16 bytes per pixel, GL_RGBA/GL_FLOAT (optional) */
} tsr_composite_color_format;

typedef enum tsr_composite_depth_format {
    TSR_COMPOSITE_NODEPTH = 0,  /* alpha mode only */
    TSR_COMPOSITE_DEPTH32F = 1, /* GL_DEPTH_COMPONENT/GL_FLOAT as OSMesa reads it */
} tsr_composite_depth_format;

typedef enum tsr_composite_mode {
    TSR_COMPOSITE_DEPTH = 0, /* nearest wins, equal depth: front (lower rank) */
    TSR_COMPOSITE_ALPHA = 1, /* premultiplied front over back */
} tsr_composite_mode;

/* Bytes per pixel of a colour / depth format (0 when unknown). */
TSR_API size_t tsr_composite_color_bytes(int color_format);
TSR_API size_t tsr_composite_depth_bytes(int depth_format);

/* ---- dense images (a region of interest as read back) ------------------ */

typedef struct tsr_composite_image {
    int window_width, window_height; /* the whole window */
    int x, y, width, height;         /* the region, inside the window; 0x0 = empty */
    int color_format, depth_format;
    int rank;       /* first position in the compositing order it covers */
    uint32_t frame; /* frame number */
    uint8_t *color; /* width*height pixels, rows bottom first, packed; owned */
    float *depth;   /* width*height floats, or NULL (NODEPTH); owned */
    size_t capacity_pixels;
} tsr_composite_image;

/* Sets the geometry and (re)allocates the planes to hold it, reusing memory
 * when it is big enough. Contents are undefined. A zero-sized region is an
 * empty image (no planes needed). Bad sizes or a region outside the window
 * are TSR_EINVAL naming them. */
TSR_API int tsr_composite_image_init(tsr_composite_image *img, int window_width, int window_height, int x, int y,
                                     int width, int height, int color_format, int depth_format, tsr_error *err);
TSR_API void tsr_composite_image_free(tsr_composite_image *img);

/* Dense merge of two images with the same geometry and formats into `out`
 * (which may alias either). The per-pixel kernels below, over the planes. */
TSR_API int tsr_composite_image_merge(int mode, const tsr_composite_image *front, const tsr_composite_image *back,
                                      tsr_composite_image *out, tsr_error *err);

/* ---- per-pixel kernels (vectorised; pointers need not be aligned) ------- */

/* Depth merge of n RGBA8+depth pixels. out_* may alias front_* or back_*. */
TSR_API void tsr_composite_depth_rgba8(size_t n, const uint8_t *front_color, const float *front_depth,
                                       const uint8_t *back_color, const float *back_depth, uint8_t *out_color,
                                       float *out_depth);
TSR_API void tsr_composite_depth_rgba32f(size_t n, const float *front_color, const float *front_depth,
                                         const float *back_color, const float *back_depth, float *out_color,
                                         float *out_depth);
/* Premultiplied front over back, n pixels. */
TSR_API void tsr_composite_over_rgba8(size_t n, const uint8_t *front, const uint8_t *back, uint8_t *out);
TSR_API void tsr_composite_over_rgba32f(size_t n, const float *front, const float *back, float *out);
/* Which implementation the loader picked for this CPU ("avx2", "sse2"...). */
TSR_API const char *tsr_composite_kernel_name(void);
/* memcpy for bytes going out in a message (no overlap): large copies use
 * streaming stores, so the destination is not read into the cache and
 * does not evict what this process still works on. Any alignment, any n
 * (0 with NULL pointers too). _using takes the kernel by name ("avx2",
 * "sse2", "c"; NULL: as the CPU allows; one the CPU lacks falls back) so
 * the tests reach every path. */
TSR_API void tsr_composite_copy(void *dst, const void *src, size_t n);
TSR_API void tsr_composite_copy_using(const char *kernel, void *dst, const void *src, size_t n);

/* ---- sparse images (active-pixel runs) ---------------------------------- */

/* Three planes: `runs` holds `nruns` pairs [inactive, active] of pixel
 * counts (adding up to `count`); `color` the active pixels' colours in
 * order, `depth` their depths (NULL for NODEPTH). Planar, so merging two
 * active spans is one kernel call over contiguous slices, and a message is
 * the planes back to back. */
typedef struct tsr_composite_sparse {
    int window_width, window_height;
    uint32_t start, count; /* pixel index range of the window */
    int mode;              /* tsr_composite_mode: which pixels are active */
    int color_format, depth_format;
    int rank;        /* first position of the compositing order it covers */
    int rank_count;  /* how many positions it covers (1 before any merge) */
    uint32_t frame;  /* frame number */
    uint32_t active; /* active pixels */
    uint32_t nruns;  /* run pairs in `runs` */
    uint32_t *runs;  /* owned; 2 * nruns entries */
    uint8_t *color;  /* owned; active * colour bytes */
    float *depth;    /* owned; active floats */
    size_t runs_capacity, pixel_capacity;
    int borrowed; /* 1: color/depth point into another image (a view) */
} tsr_composite_sparse;

/* An all-background image of the range (one run). */
TSR_API int tsr_composite_sparse_blank(tsr_composite_sparse *out, int window_width, int window_height, uint32_t start,
                                       uint32_t count, int mode, int color_format, int depth_format, int rank,
                                       uint32_t frame, tsr_error *err);
/* Sparse form of the pixels [start, start+count) of the window, taken from
 * the dense region `in` (pixels outside it are background). `out` takes
 * in's formats, rank and frame. `out`'s memory is reused. */
TSR_API int tsr_composite_sparse_compress(const tsr_composite_image *in, int mode, uint32_t start, uint32_t count,
                                          tsr_composite_sparse *out, tsr_error *err);
/* The same, but only the runs and `active`: the planes are left as they
 * were (for tsr_composite_message_encode_dense, which takes the pixels from
 * `in` itself). */
TSR_API int tsr_composite_sparse_compress_runs(const tsr_composite_image *in, int mode, uint32_t start, uint32_t count,
                                               tsr_composite_sparse *out, tsr_error *err);
/* The sub-range [start, start+count) of `in` (which must contain it), as
 * its own sparse image; background runs are cut, never expanded. */
TSR_API int tsr_composite_sparse_split(const tsr_composite_sparse *in, uint32_t start, uint32_t count,
                                       tsr_composite_sparse *out, tsr_error *err);
/* Like split, but without copying pixels: `out` gets its own runs and
 * points into in's colour and depth planes (out->borrowed), so it is valid
 * only while `in` is alive and unchanged. For pieces that are encoded or
 * merged at once (a strategy's sends and kept region). */
TSR_API int tsr_composite_sparse_view(const tsr_composite_sparse *in, uint32_t start, uint32_t count,
                                      tsr_composite_sparse *out, tsr_error *err);
/* Merges front and back (same window, range, mode and formats; adjacent
 * order intervals, front first) into `out` (must not alias either). */
TSR_API int tsr_composite_sparse_merge(const tsr_composite_sparse *front, const tsr_composite_sparse *back,
                                       tsr_composite_sparse *out, tsr_error *err);
/* A depth-mode fold of many pieces of one range: the running composite
 * keeps its pixels dense (pixel i of the range at index i) with its
 * active runs beside them, so merging a piece writes only the piece's
 * active pixels, not the whole union as a merge into a fresh image
 * would; one gather at the end gives the sparse image. The result is the
 * very image a chain of tsr_composite_sparse_merge calls with the same
 * grouping would give (same runs, same bits). Planes are reused from one
 * fold to the next. */
typedef struct tsr_composite_fold {
    tsr_composite_sparse acc;  /* header and union runs; planes dense over the range */
    tsr_composite_sparse next; /* the runs of the next step, built aside */
} tsr_composite_fold;
/* Starts a fold from `first` (depth mode, DEPTH32F). */
TSR_API int tsr_composite_fold_begin(tsr_composite_fold *f, const tsr_composite_sparse *first, tsr_error *err);
/* The same from a read-back itself: `runs` holds the runs of the range
 * (tsr_composite_sparse_compress_runs of `in`; its planes are not read) and
 * the active pixels are copied once, from `in`, to their places: no
 * sparse copy of the read-back is made first. */
TSR_API int tsr_composite_fold_begin_dense(tsr_composite_fold *f, const tsr_composite_image *in,
                                           const tsr_composite_sparse *runs, tsr_error *err);
/* Merges `piece` in front of (in_front) or behind the running composite;
 * the checks of tsr_composite_sparse_merge apply. */
TSR_API int tsr_composite_fold_add(tsr_composite_fold *f, const tsr_composite_sparse *piece, int in_front,
                                   tsr_error *err);
/* The running composite as a sparse image in `out`. */
TSR_API int tsr_composite_fold_end(tsr_composite_fold *f, tsr_composite_sparse *out, tsr_error *err);
/* Ends a fold where the composite is drawn as it is (a final piece): its
 * inactive pixels take `background` (as tsr_composite_sparse_to_dense writes
 * them, depth 1.0) and f->acc becomes a sparse image of one active run,
 * its planes dense, with no gather. Not for images merged further: their
 * background would count as pixels drawn at depth 1.0. */
TSR_API int tsr_composite_fold_fill(tsr_composite_fold *f, const void *background, tsr_error *err);
TSR_API void tsr_composite_fold_free(tsr_composite_fold *f);
/* Writes the image's range into `dst`, a dense image whose region covers
 * the range's pixels (the whole window for the final frame): inactive
 * pixels as `background` (RGBA8: 4 bytes; RGBA32F: 4 floats) with depth
 * 1.0; active ones as they are in depth mode, and blended over
 * `background` in alpha mode (so it is added once, not once per peer). Pixels of dst outside the range are left
 * alone, so the final pieces of a strategy assemble into one frame. */
TSR_API int tsr_composite_sparse_to_dense(const tsr_composite_sparse *in, const void *background,
                                          tsr_composite_image *dst, tsr_error *err);
TSR_API void tsr_composite_sparse_free(tsr_composite_sparse *img);

/* ---- codecs ------------------------------------------------------------- */

typedef enum tsr_composite_codec_color {
    TSR_COMPOSITE_CODEC_COLOR_RAW = 0,
    TSR_COMPOSITE_CODEC_COLOR_ERLE = 1,   /* bit-swizzled per-channel RLE, lossless */
    TSR_COMPOSITE_CODEC_COLOR_YUV420 = 2, /* lossy: Y per pixel, U V per 2x2 block, A kept */
} tsr_composite_codec_color;

typedef enum tsr_composite_codec_depth {
    TSR_COMPOSITE_CODEC_DEPTH_RAW = 0,
    TSR_COMPOSITE_CODEC_DEPTH_ERLE = 1, /* per-byte-plane RLE, lossless */
    TSR_COMPOSITE_CODEC_DEPTH_Q16 = 2,  /* lossy: depth in [0,1] quantised to 16 bits */
    TSR_COMPOSITE_CODEC_DEPTH_Q24 = 3,  /* lossy: 24 bits */
} tsr_composite_codec_depth;

typedef struct tsr_composite_codec {
    uint8_t runs;  /* 1: active-pixel runs (background free); 0: every pixel ("none") */
    uint8_t color; /* tsr_composite_codec_color */
    uint8_t depth; /* tsr_composite_codec_depth */
} tsr_composite_codec;

/* Parses a codec name: "none" (every pixel, raw), "rle" (runs, raw),
 * "erle" (runs, colour and depth per-channel RLE), "yuv420", "depth16",
 * "depth24", or '+'-joined combinations ("erle+depth16",
 * "yuv420+depth24"). Default for a group: "rle". Unknown names are
 * TSR_EINVAL listing the valid ones. */
TSR_API int tsr_composite_codec_parse(const char *text, tsr_composite_codec *out, tsr_error *err);
/* The canonical name of `c` ("rle", "yuv420+depth16", ...). */
TSR_API const char *tsr_composite_codec_name(tsr_composite_codec c, char *buf, size_t size);
TSR_API bool tsr_composite_codec_lossless(tsr_composite_codec c);

/* ---- image messages ----------------------------------------------------- */

/* Fixed little-endian header in front of every image message. */
#define TSR_COMPOSITE_MESSAGE_HEADER_SIZE 48

typedef struct tsr_composite_message_header {
    int window_width, window_height;
    uint32_t start, count;
    int mode, color_format, depth_format;
    int rank, rank_count;
    uint32_t frame;
    uint32_t active, runs;
    tsr_composite_codec codec;
    uint32_t payload_size;
} tsr_composite_message_header;

/* The largest message encoding any image of `count` pixels in these
 * formats with codec `c` can produce (header included). Never exceeded. */
TSR_API size_t tsr_composite_message_max_size(uint32_t count, int color_format, int depth_format,
                                              tsr_composite_codec c);
/* Encodes `img` into out[0..cap); *size is the message's length. cap below
 * tsr_composite_message_bound (<= tsr_composite_message_max_size) fails with
 * TSR_EINVAL, never overflows. A
 * lossy colour codec on float colour is TSR_EUNSUPPORTED. */
TSR_API int tsr_composite_message_encode(const tsr_composite_sparse *img, tsr_composite_codec c, uint8_t *out,
                                         size_t cap, size_t *size, tsr_error *err);
/* Reads and checks the header only (sizes, offsets, formats, payload size
 * against `size`). */
TSR_API int tsr_composite_message_header_read(const void *data, size_t size, tsr_composite_message_header *hdr,
                                              tsr_error *err);
/* Decodes a message into `out` (memory reused). Everything is bounds
 * checked: a bad magic, impossible sizes or offsets, runs that overflow the
 * range, a truncated or overlong payload is TSR_EPROTO with one line saying
 * what (never a crash, never a read past `size`). When `expect` is not
 * NULL, its window size, start, count, mode, formats, rank and frame must
 * match (a field < 0 / UINT32_MAX is not checked): a mismatch is
 * TSR_EPROTO naming the field, the expected and the received value. */
TSR_API int tsr_composite_message_decode(const void *data, size_t size, const tsr_composite_message_header *expect,
                                         tsr_composite_sparse *out, tsr_error *err);
/* Like decode, but without copying pixels when the codec leaves them raw
 * ("rle": runs, raw colour, raw depth) and `data` is 4-byte aligned: `out`
 * gets its own runs and points into the message's colour and depth
 * (out->borrowed), so it is valid only while the message is, and is never
 * written through. Every check of decode is made. Other codecs decode. */
TSR_API int tsr_composite_message_view(const void *data, size_t size, const tsr_composite_message_header *expect,
                                       tsr_composite_sparse *out, tsr_error *err);
/* A peer's read-back straight into a message: `runs` comes from
 * tsr_composite_sparse_compress_runs of `in`, and the message is the one
 * tsr_composite_sparse_compress followed by tsr_composite_message_encode would
 * give, bit for bit. With "rle" (raw planes) the active pixels go from
 * `in` into `out`, one copy and no sparse planes; other codecs gather them
 * into the planes of `runs` first. cap: tsr_composite_message_bound(runs). */
TSR_API int tsr_composite_message_encode_dense(const tsr_composite_image *in, tsr_composite_sparse *runs,
                                               tsr_composite_codec c, uint8_t *out, size_t cap, size_t *size,
                                               tsr_error *err);
/* The largest message encoding this very image (its runs and active
 * pixels) with codec `c` can produce, header included: at most
 * tsr_composite_message_max_size of its count, and what encode needs as cap.
 * A sender reserves this much, not the worst case of any image: in a
 * shared-memory ring the space reserved decides where the next message
 * goes, so the pages in use follow the bytes sent. */
TSR_API size_t tsr_composite_message_bound(const tsr_composite_sparse *img, tsr_composite_codec c);
/* An expectation with every field unchecked (fill in what you know). */
TSR_API void tsr_composite_message_expect_any(tsr_composite_message_header *expect);

#ifdef __cplusplus
}
#endif
#endif
