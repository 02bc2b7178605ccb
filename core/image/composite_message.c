/* core/image/composite_message.c — image messages (tessera/dev/composite.h): a fixed
 * little-endian header and a codec payload (none, runs, bit-swizzled
 * per-channel RLE, lossy YUV 4:2:0 colour, 16/24-bit depth), the
 * worst-case size and a decoder that checks every count and offset.
 *
 * Owns: nothing beyond the images it fills. Never: reads past the buffer
 * it is given, trusts a count from the wire, keeps state.
 *
 * Payload of a runs codec: nruns pairs of uint32, then the colour section,
 * then the depth section. "none": every pixel of the range, colours then
 * depths. Byte-plane RLE (PackBits-like): a control byte c < 128 is
 * followed by c + 1 literal bytes, c >= 128 by one byte repeated c - 125
 * times (3..130); each plane is [uint32 length][bytes]. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "composite_internal.h"
#include "tessera/dev/composite.h"

#define MSG_MAGIC 0x4d495354u /* "TSIM" */
#define MSG_VERSION 1

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)v;
    p[1] = (uint8_t)(v >> 8);
    p[2] = (uint8_t)(v >> 16);
    p[3] = (uint8_t)(v >> 24);
}

static uint32_t get32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* ---- codec names -------------------------------------------------------- */

int tsr_composite_codec_parse(const char *text, tsr_composite_codec *out, tsr_error *err)
{
    tsr_composite_codec c = {1, TSR_COMPOSITE_CODEC_COLOR_RAW, TSR_COMPOSITE_CODEC_DEPTH_RAW};
    int none = 0, parts = 0;
    const char *p = text ? text : "";
    while (*p) {
        const char *e = strchr(p, '+');
        size_t n = e ? (size_t)(e - p) : strlen(p);
        parts++;
        if (n == 4 && !strncmp(p, "none", 4))
            none = 1;
        else if (n == 3 && !strncmp(p, "rle", 3))
            ;
        else if (n == 4 && !strncmp(p, "erle", 4)) {
            c.color = c.color == TSR_COMPOSITE_CODEC_COLOR_RAW ? TSR_COMPOSITE_CODEC_COLOR_ERLE : c.color;
            c.depth = c.depth == TSR_COMPOSITE_CODEC_DEPTH_RAW ? TSR_COMPOSITE_CODEC_DEPTH_ERLE : c.depth;
        } else if (n == 6 && !strncmp(p, "yuv420", 6))
            c.color = TSR_COMPOSITE_CODEC_COLOR_YUV420;
        else if (n == 7 && !strncmp(p, "depth16", 7))
            c.depth = TSR_COMPOSITE_CODEC_DEPTH_Q16;
        else if (n == 7 && !strncmp(p, "depth24", 7))
            c.depth = TSR_COMPOSITE_CODEC_DEPTH_Q24;
        else
            return tsr_error_set(err, TSR_EINVAL,
                                 "codec '%s': unknown part '%.*s' (valid: none, rle, erle, yuv420, depth16, depth24, "
                                 "joined with '+')",
                                 text ? text : "", (int)n, p);
        p += n;
        if (*p == '+')
            p++;
    }
    if (!parts)
        return tsr_error_set(err, TSR_EINVAL, "codec '': empty (valid: none, rle, erle, yuv420, depth16, depth24)");
    if (none && parts > 1)
        return tsr_error_set(err, TSR_EINVAL, "codec '%s': none sends every pixel raw and combines with nothing", text);
    if (none)
        c.runs = 0;
    *out = c;
    return TSR_OK;
}

const char *tsr_composite_codec_name(tsr_composite_codec c, char *buf, size_t size)
{
    if (!c.runs) {
        snprintf(buf, size, "none");
        return buf;
    }
    const char *col = c.color == TSR_COMPOSITE_CODEC_COLOR_ERLE     ? "erle"
                      : c.color == TSR_COMPOSITE_CODEC_COLOR_YUV420 ? "yuv420"
                                                                    : "";
    const char *dep = c.depth == TSR_COMPOSITE_CODEC_DEPTH_ERLE
                          ? (c.color == TSR_COMPOSITE_CODEC_COLOR_ERLE ? "" : "erle")
                      : c.depth == TSR_COMPOSITE_CODEC_DEPTH_Q16 ? "depth16"
                      : c.depth == TSR_COMPOSITE_CODEC_DEPTH_Q24 ? "depth24"
                                                                 : "";
    if (!*col && !*dep)
        snprintf(buf, size, "rle");
    else if (*col && *dep)
        snprintf(buf, size, "%s+%s", col, dep);
    else if (c.color == TSR_COMPOSITE_CODEC_COLOR_YUV420 && c.depth == TSR_COMPOSITE_CODEC_DEPTH_ERLE)
        snprintf(buf, size, "yuv420+erle");
    else
        snprintf(buf, size, "%s", *col ? col : dep);
    return buf;
}

bool tsr_composite_codec_lossless(tsr_composite_codec c)
{
    return c.color != TSR_COMPOSITE_CODEC_COLOR_YUV420 && c.depth != TSR_COMPOSITE_CODEC_DEPTH_Q16 &&
           c.depth != TSR_COMPOSITE_CODEC_DEPTH_Q24;
}

/* ---- byte-plane RLE ------------------------------------------------------ */

static size_t rle_bound(size_t n) { return 4 + n + (n + 127) / 128; }

/* First j >= i where three equal bytes start (n when none): eight bytes
 * at a time, a zero byte of (x ^ y) | (y ^ z) marks the spot. */
static size_t next_triple(const uint8_t *in, size_t i, size_t n)
{
    const uint64_t ones = 0x0101010101010101ull, highs = 0x8080808080808080ull;
    while (i + 10 <= n) {
        uint64_t x, y, z;
        ci_copy(&x, in + i, 8);
        ci_copy(&y, in + i + 1, 8);
        ci_copy(&z, in + i + 2, 8);
        uint64_t v = (x ^ y) | (y ^ z), t = (v - ones) & ~v & highs;
        if (t)
            return i + (size_t)(__builtin_ctzll(t) / 8);
        i += 8;
    }
    for (; i + 2 < n; i++)
        if (in[i] == in[i + 1] && in[i + 1] == in[i + 2])
            return i;
    return n;
}

/* Encodes the n bytes of a plane into out ([uint32 length][codes]);
 * returns the bytes written. */
static size_t rle_encode(const uint8_t *in, size_t n, uint8_t *out)
{
    size_t o = 4, i = 0;
    while (i < n) {
        size_t j = next_triple(in, i, n);
        while (i < j) {
            size_t k = j - i > 128 ? 128 : j - i;
            out[o++] = (uint8_t)(k - 1);
            ci_copy(out + o, in + i, k);
            o += k;
            i += k;
        }
        if (j < n) {
            size_t r = 3;
            while (j + r < n && r < 130 && in[j + r] == in[j])
                r++;
            out[o++] = (uint8_t)(r + 125);
            out[o++] = in[j];
            i = j + r;
        }
    }
    put32(out, (uint32_t)(o - 4));
    return o;
}

/* Decodes one plane of exactly n bytes into out; *used gets
 * the bytes consumed. Returns 0 or -1 with *why set. */
static int rle_decode(const uint8_t *in, size_t avail, size_t n, uint8_t *out, size_t *used, const char **why)
{
    if (avail < 4) {
        *why = "RLE plane header truncated";
        return -1;
    }
    size_t len = get32(in);
    if (len > avail - 4) {
        *why = "RLE plane longer than the payload";
        return -1;
    }
    const uint8_t *p = in + 4, *e = p + len;
    size_t o = 0;
    while (p < e) {
        unsigned c = *p++;
        if (c < 128) {
            size_t k = c + 1;
            if ((size_t)(e - p) < k || n - o < k) {
                *why = c + 1 > n - o ? "RLE literal overflows the plane" : "RLE literal truncated";
                return -1;
            }
            ci_copy(out + o, p, k);
            p += k;
            o += k;
        } else {
            size_t k = c - 125;
            if (p >= e || n - o < k) {
                *why = p >= e ? "RLE repeat truncated" : "RLE repeat overflows the plane";
                return -1;
            }
            memset(out + o, *p, k);
            p++;
            o += k;
        }
    }
    if (o != n) {
        *why = "RLE plane shorter than the active pixels";
        return -1;
    }
    *used = 4 + len;
    return 0;
}

/* Eilemann's bit swizzling of an RGBA8 word: output byte k holds bits
 * 7-2k and 6-2k of each channel (channel c at bits 2c, 2c+1), so the most
 * significant bits of all four channels share a byte and that plane
 * compresses best. A bijection, done with two 256-entry tables the caller
 * fills (no state kept between calls). spread[b]: byte b's bit pairs from
 * the top placed at bits 8k; gather[b]: byte b's four pairs placed at the
 * top pair of each byte. */
typedef struct swizzle_tables {
    uint32_t spread[256], gather[256];
} swizzle_tables;

static void swizzle_init(swizzle_tables *t)
{
    for (uint32_t b = 0; b < 256; b++) {
        uint32_t s = 0, g = 0;
        for (int k = 0; k < 4; k++) {
            s |= ((b >> (6 - 2 * k)) & 3u) << (8 * k);
            g |= ((b >> (2 * k)) & 3u) << (8 * k + 6);
        }
        t->spread[b] = s;
        t->gather[b] = g;
    }
}

static inline uint32_t swizzle(const swizzle_tables *t, uint32_t v)
{
    return t->spread[v & 255] | t->spread[(v >> 8) & 255] << 2 | t->spread[(v >> 16) & 255] << 4 |
           t->spread[v >> 24] << 6;
}

static inline uint32_t unswizzle(const swizzle_tables *t, uint32_t o)
{
    return t->gather[o & 255] | t->gather[(o >> 8) & 255] >> 2 | t->gather[(o >> 16) & 255] >> 4 |
           t->gather[o >> 24] >> 6;
}

/* ---- YUV 4:2:0 ---------------------------------------------------------- */

static inline uint8_t clamp8(int v) { return (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v); }

/* Visits the active pixels in order, grouped by 2x2-block row, assigning
 * each pixel a chroma slot: blocks numbered in order of first touch within
 * each block row, numbers running on across rows. Encoder and decoder
 * derive the same slots from the runs alone. slot[] gets one per pixel. */
static uint32_t yuv_slots(const tsr_composite_sparse *s, uint32_t *slot, uint32_t *stamp, uint32_t *stamp_slot)
{
    uint32_t w = (uint32_t)s->window_width, pos = s->start, at = 0, next = 0, cur_row = UINT32_MAX, gen = 0;
    memset(stamp, 0, ((w + 1) / 2) * sizeof *stamp);
    for (uint32_t r = 0; r < s->nruns; r++) {
        pos += s->runs[2 * r];
        for (uint32_t i = 0; i < s->runs[2 * r + 1]; i++, pos++, at++) {
            uint32_t by = pos / w / 2, bx = pos % w / 2;
            if (by != cur_row) {
                cur_row = by;
                gen++;
            }
            if (stamp[bx] != gen) {
                stamp[bx] = gen;
                stamp_slot[bx] = next++;
            }
            slot[at] = stamp_slot[bx];
        }
    }
    return next;
}

/* ---- sizes ----------------------------------------------------------------- */

static size_t color_section_bound(size_t n, int cf, int codec)
{
    size_t cb = tsr_composite_color_bytes(cf);
    if (codec == TSR_COMPOSITE_CODEC_COLOR_ERLE)
        return cb * rle_bound(n);
    if (codec == TSR_COMPOSITE_CODEC_COLOR_YUV420)
        return 4 * n; /* Y + A per pixel, U V per touched block (<= one per pixel) */
    return n * cb;
}

static size_t depth_section_bound(size_t n, int df, int codec)
{
    if (!df)
        return 0;
    if (codec == TSR_COMPOSITE_CODEC_DEPTH_ERLE)
        return 4 * rle_bound(n);
    if (codec == TSR_COMPOSITE_CODEC_DEPTH_Q16)
        return 2 * n;
    if (codec == TSR_COMPOSITE_CODEC_DEPTH_Q24)
        return 3 * n;
    return 4 * n;
}

size_t tsr_composite_message_max_size(uint32_t count, int color_format, int depth_format, tsr_composite_codec c)
{
    size_t n = count;
    if (!c.runs)
        return TSR_COMPOSITE_MESSAGE_HEADER_SIZE +
               n * (tsr_composite_color_bytes(color_format) + tsr_composite_depth_bytes(depth_format));
    /* Canonical runs: every pair but the first has an inactive pixel and
     * every pair but the last an active one, so pairs <= count / 2 + 1. */
    size_t pairs = n ? n / 2 + 1 : 0;
    return TSR_COMPOSITE_MESSAGE_HEADER_SIZE + 8 * pairs + color_section_bound(n, color_format, c.color) +
           depth_section_bound(n, depth_format, c.depth);
}

/* ---- encode ------------------------------------------------------------------ */

static void write_header(uint8_t *o, const tsr_composite_sparse *img, tsr_composite_codec c, uint32_t active,
                         uint32_t nruns, uint32_t payload)
{
    put32(o, MSG_MAGIC);
    o[4] = MSG_VERSION;
    o[5] = c.runs;
    o[6] = c.color;
    o[7] = c.depth;
    o[8] = (uint8_t)img->mode;
    o[9] = (uint8_t)img->color_format;
    o[10] = (uint8_t)img->depth_format;
    o[11] = 0;
    put32(o + 12, (uint32_t)img->window_width);
    put32(o + 16, (uint32_t)img->window_height);
    put32(o + 20, img->start);
    put32(o + 24, img->count);
    put32(o + 28, (uint32_t)img->rank | (uint32_t)img->rank_count << 16);
    put32(o + 32, img->frame);
    put32(o + 36, active);
    put32(o + 40, nruns);
    put32(o + 44, payload);
}

/* The runs section at o, re-canonicalised (a decoded image may carry empty
 * pairs); returns the pairs written. */
static uint32_t put_runs(const tsr_composite_sparse *img, uint8_t *o)
{
    uint32_t nr = 0;
    for (uint32_t r = 0; r < img->nruns; r++) {
        uint32_t ni = img->runs[2 * r], na = img->runs[2 * r + 1];
        if (nr && get32(o + 8 * (nr - 1) + 4) == 0) {
            put32(o + 8 * (nr - 1), get32(o + 8 * (nr - 1)) + ni);
            put32(o + 8 * (nr - 1) + 4, na);
        } else if (nr && ni == 0) {
            put32(o + 8 * (nr - 1) + 4, get32(o + 8 * (nr - 1) + 4) + na);
        } else if (ni || na) {
            put32(o + 8 * nr, ni);
            put32(o + 8 * nr + 4, na);
            nr++;
        }
    }
    return nr;
}

size_t tsr_composite_message_bound(const tsr_composite_sparse *img, tsr_composite_codec c)
{
    if (!c.runs)
        return tsr_composite_message_max_size(img->count, img->color_format, img->depth_format, c);
    /* encode writes canonical runs: never more pairs than max_size counts */
    size_t n = img->active, pairs = img->nruns, canonical = img->count ? (size_t)img->count / 2 + 1 : 0;
    pairs = pairs < canonical ? pairs : canonical;
    return TSR_COMPOSITE_MESSAGE_HEADER_SIZE + 8 * pairs + color_section_bound(n, img->color_format, c.color) +
           depth_section_bound(n, img->depth_format, c.depth);
}

static int check_encode(const tsr_composite_sparse *img, tsr_composite_codec c, size_t cap, tsr_error *err)
{
    size_t need = tsr_composite_message_bound(img, c);
    if (cap < need)
        return tsr_error_set(err, TSR_EINVAL, "image message: buffer of %zu bytes is below the worst case %zu", cap,
                             need);
    if (img->color_format != TSR_COMPOSITE_RGBA8 && c.color == TSR_COMPOSITE_CODEC_COLOR_YUV420)
        return tsr_error_set(err, TSR_EUNSUPPORTED, "image message: yuv420 needs RGBA8 colour");
    if (img->rank < 0 || img->rank > 0xffff || img->rank_count < 1 || img->rank_count > 0xffff)
        return tsr_error_set(err, TSR_EINVAL, "image message: rank %d+%d does not fit 16 bits", img->rank,
                             img->rank_count);
    return TSR_OK;
}

/* Copies the active pixels the runs of `runs` name (window indices from
 * runs->start) out of the dense region `in` into dst_color / dst_depth,
 * one copy per run and row. An active run lies inside the region (outside
 * it every pixel is background); it crosses rows only where the region
 * is as wide as the window, and there the region's rows are contiguous.
 * `out`: the destination is the message itself, which this process does
 * not read again: streamed when the message is large (CI_STREAM_MIN, the
 * pieces may be rows of a few KiB); else the planes a codec reads next,
 * which must stay in the cache. */
static void gather_active(const tsr_composite_image *in, const tsr_composite_sparse *runs, uint8_t *dst_color,
                          uint8_t *dst_depth, int out)
{
    size_t cb = tsr_composite_color_bytes(in->color_format), W = (size_t)in->window_width, at = 0;
    int stream = out && (size_t)runs->active * (cb + (dst_depth ? 4 : 0)) >= CI_STREAM_MIN;
    void (*copy)(void *, const void *, size_t) = stream ? ci_copy_stream : ci_copy;
    size_t pos = runs->start;
    int whole_rows = in->x == 0 && in->width == in->window_width;
    for (uint32_t r = 0; r < runs->nruns; r++) {
        pos += runs->runs[2 * r];
        size_t n = runs->runs[2 * r + 1];
        while (n) {
            size_t x = pos % W, len = whole_rows ? n : (W - x < n ? W - x : n);
            size_t src = ci_region_index(in, pos);
            copy(dst_color + at * cb, in->color + src * cb, len * cb);
            if (dst_depth)
                copy(dst_depth + at * 4, in->depth + src, len * 4);
            at += len;
            pos += len;
            n -= len;
        }
    }
    if (stream)
        ci_copy_fence();
}

int tsr_composite_message_encode_dense(const tsr_composite_image *in, tsr_composite_sparse *runs, tsr_composite_codec c,
                                       uint8_t *out, size_t cap, size_t *size, tsr_error *err)
{
    if (runs->window_width != in->window_width || runs->window_height != in->window_height ||
        runs->color_format != in->color_format || runs->depth_format != in->depth_format)
        return tsr_error_set(err, TSR_EINVAL, "image message: runs of a %dx%d image for a %dx%d read-back",
                             runs->window_width, runs->window_height, in->window_width, in->window_height);
    int rc;
    size_t n = runs->active, cb = tsr_composite_color_bytes(in->color_format);
    if (!(c.runs && c.color == TSR_COMPOSITE_CODEC_COLOR_RAW &&
          (c.depth == TSR_COMPOSITE_CODEC_DEPTH_RAW || !in->depth_format))) {
        /* the codec needs the pixels together: gather them into the runs'
         * own planes, then encode those */
        if ((rc = ci_sparse_planes(runs, n, cb, err)))
            return rc;
        gather_active(in, runs, runs->color, in->depth_format ? (uint8_t *)runs->depth : NULL, 0);
        return tsr_composite_message_encode(runs, c, out, cap, size, err);
    }
    if ((rc = check_encode(runs, c, cap, err)))
        return rc;
    uint8_t *o = out + TSR_COMPOSITE_MESSAGE_HEADER_SIZE;
    uint32_t nr = put_runs(runs, o);
    o += 8 * (size_t)nr;
    gather_active(in, runs, o, in->depth_format ? o + n * cb : NULL, 1);
    o += n * (cb + (in->depth_format ? 4 : 0));
    size_t payload = (size_t)(o - out) - TSR_COMPOSITE_MESSAGE_HEADER_SIZE;
    write_header(out, runs, c, (uint32_t)n, nr, (uint32_t)payload);
    *size = (size_t)(o - out);
    return TSR_OK;
}

int tsr_composite_message_encode(const tsr_composite_sparse *img, tsr_composite_codec c, uint8_t *out, size_t cap,
                                 size_t *size, tsr_error *err)
{
    int rc0 = check_encode(img, c, cap, err);
    if (rc0)
        return rc0;
    size_t cb = tsr_composite_color_bytes(img->color_format), n = img->active;
    uint8_t *o = out + TSR_COMPOSITE_MESSAGE_HEADER_SIZE;
    const uint8_t *color = img->color;
    const float *depth = img->depth;
    if (!c.runs) {
        /* Every pixel: expand the runs into the payload directly. */
        size_t db = img->depth_format ? 4 : 0;
        uint8_t *oc = o, *od = o + (size_t)img->count * cb;
        static const float far = 1.0f;
        size_t p = 0, at = 0;
        for (uint32_t r = 0; r < img->nruns; r++) {
            uint32_t ni = img->runs[2 * r], na = img->runs[2 * r + 1];
            memset(oc + p * cb, 0, (size_t)ni * cb);
            for (uint32_t i = 0; i < ni && db; i++)
                ci_copy(od + (p + i) * 4, &far, 4);
            p += ni;
            ci_copy(oc + p * cb, color + at * cb, (size_t)na * cb);
            if (db)
                ci_copy(od + p * 4, depth + at, (size_t)na * 4);
            p += na;
            at += na;
        }
        size_t payload = (size_t)img->count * (cb + db);
        write_header(out, img, c, img->count, 0, (uint32_t)payload);
        *size = TSR_COMPOSITE_MESSAGE_HEADER_SIZE + payload;
        return TSR_OK;
    }
    uint32_t nr = put_runs(img, o);
    o += 8 * (size_t)nr;
    if (c.color == TSR_COMPOSITE_CODEC_COLOR_RAW) {
        tsr_composite_copy(o, color, n * cb);
        o += n * cb;
    } else if (c.color == TSR_COMPOSITE_CODEC_COLOR_ERLE) {
        /* byte planes (swizzled for RGBA8), then each plane RLE-coded */
        uint8_t *planes = malloc(n ? n * cb : 1);
        swizzle_tables *tab = img->color_format == TSR_COMPOSITE_RGBA8 ? malloc(sizeof *tab) : NULL;
        if (!planes || (img->color_format == TSR_COMPOSITE_RGBA8 && !tab)) {
            free(planes);
            free(tab);
            return tsr_error_set(err, TSR_ENOMEM, "image message: no memory for %zu pixels", n);
        }
        if (tab) {
            swizzle_init(tab);
            for (size_t i = 0; i < n; i++) {
                uint32_t v;
                ci_copy(&v, color + 4 * i, 4);
                v = swizzle(tab, v);
                planes[i] = (uint8_t)v;
                planes[n + i] = (uint8_t)(v >> 8);
                planes[2 * n + i] = (uint8_t)(v >> 16);
                planes[3 * n + i] = (uint8_t)(v >> 24);
            }
        } else {
            for (size_t i = 0; i < n; i++)
                for (size_t k = 0; k < cb; k++)
                    planes[k * n + i] = color[i * cb + k];
        }
        for (size_t k = 0; k < cb; k++)
            o += rle_encode(planes + k * n, n, o);
        free(planes);
        free(tab);
    } else {
        uint32_t w = (uint32_t)img->window_width, half = (w + 1) / 2;
        uint32_t *slot = malloc((n ? n : 1) * sizeof *slot), *stamp = malloc(half * sizeof *stamp);
        uint32_t *stamp_slot = malloc(half * sizeof *stamp_slot);
        int32_t *acc = NULL;
        if (slot && stamp && stamp_slot) {
            uint32_t blocks = yuv_slots(img, slot, stamp, stamp_slot);
            acc = calloc((size_t)blocks * 3 + 1, sizeof *acc);
            if (acc) {
                for (size_t i = 0; i < n; i++) {
                    const uint8_t *px = color + 4 * i;
                    int R = px[0], G = px[1], B = px[2];
                    o[i] = clamp8((77 * R + 150 * G + 29 * B + 128) >> 8);
                    o[n + i] = px[3];
                    acc[3 * slot[i]] += (-43 * R - 85 * G + 128 * B);
                    acc[3 * slot[i] + 1] += (128 * R - 107 * G - 21 * B);
                    acc[3 * slot[i] + 2]++;
                }
                uint8_t *uv = o + 2 * n;
                for (uint32_t b = 0; b < blocks; b++) {
                    int cnt = acc[3 * b + 2];
                    uv[2 * b] = clamp8((int)lrint((double)acc[3 * b] / (256.0 * cnt)) + 128);
                    uv[2 * b + 1] = clamp8((int)lrint((double)acc[3 * b + 1] / (256.0 * cnt)) + 128);
                }
                o += 2 * n + 2 * (size_t)blocks;
            }
        }
        free(slot);
        free(stamp);
        free(stamp_slot);
        if (!acc)
            return tsr_error_set(err, TSR_ENOMEM, "image message: no memory for yuv420 of %zu pixels", n);
        free(acc);
    }
    if (img->depth_format) {
        if (c.depth == TSR_COMPOSITE_CODEC_DEPTH_RAW) {
            tsr_composite_copy(o, depth, n * 4);
            o += n * 4;
        } else if (c.depth == TSR_COMPOSITE_CODEC_DEPTH_ERLE) {
            uint8_t *planes = malloc(n ? 4 * n : 1);
            if (!planes)
                return tsr_error_set(err, TSR_ENOMEM, "image message: no memory for %zu depths", n);
            for (size_t i = 0; i < n; i++) {
                uint32_t v;
                ci_copy(&v, depth + i, 4);
                for (int k = 0; k < 4; k++) /* most significant byte first */
                    planes[(size_t)k * n + i] = (uint8_t)(v >> (24 - 8 * k));
            }
            for (int k = 0; k < 4; k++)
                o += rle_encode(planes + (size_t)k * n, n, o);
            free(planes);
        } else {
            int bits = c.depth == TSR_COMPOSITE_CODEC_DEPTH_Q16 ? 16 : 24;
            double scale = (double)(1u << bits);
            uint32_t maxq = (1u << bits) - 1;
            for (size_t i = 0; i < n; i++) {
                double d = depth[i];
                d = d > 0 ? d : 0; /* NaN and negatives to 0 */
                double q = floor(d * scale);
                uint32_t v = q > maxq ? maxq : (uint32_t)q;
                for (int b = 0; b < bits / 8; b++)
                    *o++ = (uint8_t)(v >> (8 * b));
            }
        }
    }
    size_t payload = (size_t)(o - out) - TSR_COMPOSITE_MESSAGE_HEADER_SIZE;
    write_header(out, img, c, (uint32_t)n, nr, (uint32_t)payload);
    *size = (size_t)(o - out);
    return TSR_OK;
}

/* ---- decode ----------------------------------------------------------------- */

void tsr_composite_message_expect_any(tsr_composite_message_header *e)
{
    memset(e, 0xff, sizeof *e);
    e->window_width = e->window_height = e->mode = e->color_format = e->depth_format = -1;
    e->rank = e->rank_count = -1;
}

int tsr_composite_message_header_read(const void *data, size_t size, tsr_composite_message_header *h, tsr_error *err)
{
    const uint8_t *p = data;
    if (size < TSR_COMPOSITE_MESSAGE_HEADER_SIZE)
        return tsr_error_set(err, TSR_EPROTO, "image message: %zu bytes, shorter than its %d-byte header", size,
                             TSR_COMPOSITE_MESSAGE_HEADER_SIZE);
    if (get32(p) != MSG_MAGIC || p[4] != MSG_VERSION)
        return tsr_error_set(err, TSR_EPROTO, "image message: bad magic or version (0x%08x v%u)", get32(p), p[4]);
    h->codec.runs = p[5];
    h->codec.color = p[6];
    h->codec.depth = p[7];
    h->mode = p[8];
    h->color_format = p[9];
    h->depth_format = p[10];
    h->window_width = (int)get32(p + 12);
    h->window_height = (int)get32(p + 16);
    h->start = get32(p + 20);
    h->count = get32(p + 24);
    h->rank = (int)(get32(p + 28) & 0xffff);
    h->rank_count = (int)(get32(p + 28) >> 16);
    h->frame = get32(p + 32);
    h->active = get32(p + 36);
    h->runs = get32(p + 40);
    h->payload_size = get32(p + 44);
    uint32_t ww = get32(p + 12), wh = get32(p + 16);
    if (h->codec.runs > 1 || h->codec.color > TSR_COMPOSITE_CODEC_COLOR_YUV420 ||
        h->codec.depth > TSR_COMPOSITE_CODEC_DEPTH_Q24 || (!h->codec.runs && (h->codec.color || h->codec.depth)) ||
        p[11])
        return tsr_error_set(err, TSR_EPROTO, "image message: unknown codec (%u/%u/%u)", p[5], p[6], p[7]);
    if (h->mode > TSR_COMPOSITE_ALPHA || !tsr_composite_color_bytes(h->color_format) ||
        h->depth_format > TSR_COMPOSITE_DEPTH32F || (h->mode == TSR_COMPOSITE_DEPTH && !h->depth_format) ||
        (h->codec.color == TSR_COMPOSITE_CODEC_COLOR_YUV420 && h->color_format != TSR_COMPOSITE_RGBA8))
        return tsr_error_set(err, TSR_EPROTO, "image message: impossible mode/format (mode %u, colour %u, depth %u)",
                             p[8], p[9], p[10]);
    if (ww < 1 || wh < 1 || ww > TSR_COMPOSITE_MAX_SIDE || wh > TSR_COMPOSITE_MAX_SIDE)
        return tsr_error_set(err, TSR_EPROTO, "image message: impossible window %ux%u", ww, wh);
    if ((uint64_t)h->start + h->count > (uint64_t)ww * wh)
        return tsr_error_set(err, TSR_EPROTO, "image message: pixels %u+%u lie outside the %ux%u window", h->start,
                             h->count, ww, wh);
    if (h->rank_count < 1)
        return tsr_error_set(err, TSR_EPROTO, "image message: covers %d ranks", h->rank_count);
    if (h->active > h->count || (h->codec.runs && h->runs > h->count / 2 + 1) || (!h->codec.runs && h->runs) ||
        (!h->codec.runs && h->active != h->count))
        return tsr_error_set(err, TSR_EPROTO, "image message: %u active pixels in %u runs cannot fit %u pixels",
                             h->active, h->runs, h->count);
    if ((uint64_t)h->payload_size != (uint64_t)size - TSR_COMPOSITE_MESSAGE_HEADER_SIZE)
        return tsr_error_set(err, TSR_EPROTO, "image message: payload of %u bytes in a %zu-byte message",
                             h->payload_size, size);
    return TSR_OK;
}

static int expect_field(const char *name, long long want, long long got, long long any, tsr_error *err)
{
    if (want != any && want != got)
        return tsr_error_set(err, TSR_EPROTO, "image message: %s is %lld, expected %lld", name, got, want);
    return TSR_OK;
}

/* Planes for n decoded pixels of cb colour bytes (reused while big
 * enough; composite_internal.h). */
static int reserve_planes(tsr_composite_sparse *s, size_t n, size_t cb, tsr_error *err)
{
    if (n <= s->pixel_capacity && ci_plane_bytes(s->color) >= n * cb && s->color)
        return TSR_OK;
    void *c = ci_plane_alloc(n * cb), *d = c ? ci_plane_alloc(n * 4) : NULL;
    if (!d) {
        ci_plane_free(c);
        return tsr_error_set(err, TSR_ENOMEM, "image message: no memory for %zu pixels", n);
    }
    ci_plane_free(s->color);
    ci_plane_free(s->depth);
    s->color = c;
    s->depth = d;
    s->pixel_capacity = n;
    return TSR_OK;
}

static int decode(const void *data, size_t size, const tsr_composite_message_header *e, tsr_composite_sparse *out,
                  int view, tsr_error *err);

int tsr_composite_message_decode(const void *data, size_t size, const tsr_composite_message_header *e,
                                 tsr_composite_sparse *out, tsr_error *err)
{
    return decode(data, size, e, out, 0, err);
}

int tsr_composite_message_view(const void *data, size_t size, const tsr_composite_message_header *e,
                               tsr_composite_sparse *out, tsr_error *err)
{
    return decode(data, size, e, out, 1, err);
}

static int decode(const void *data, size_t size, const tsr_composite_message_header *e, tsr_composite_sparse *out,
                  int view, tsr_error *err)
{
    tsr_composite_message_header h;
    int rc = tsr_composite_message_header_read(data, size, &h, err);
    if (rc)
        return rc;
    if (e && ((rc = expect_field("window width", e->window_width, h.window_width, -1, err)) ||
              (rc = expect_field("window height", e->window_height, h.window_height, -1, err)) ||
              (rc = expect_field("frame", e->frame, h.frame, UINT32_MAX, err)) ||
              (rc = expect_field("rank", e->rank, h.rank, -1, err)) ||
              (rc = expect_field("rank count", e->rank_count, h.rank_count, -1, err)) ||
              (rc = expect_field("start pixel", e->start, h.start, UINT32_MAX, err)) ||
              (rc = expect_field("pixel count", e->count, h.count, UINT32_MAX, err)) ||
              (rc = expect_field("mode", e->mode, h.mode, -1, err)) ||
              (rc = expect_field("colour format", e->color_format, h.color_format, -1, err)) ||
              (rc = expect_field("depth format", e->depth_format, h.depth_format, -1, err))))
        return rc;
    if (out->borrowed) {
        /* a view's planes belong to another image: decode into new ones */
        out->color = NULL;
        out->depth = NULL;
        out->pixel_capacity = 0;
        out->borrowed = 0;
    }
    const uint8_t *p = (const uint8_t *)data + TSR_COMPOSITE_MESSAGE_HEADER_SIZE, *end = p + h.payload_size;
    size_t cb = tsr_composite_color_bytes(h.color_format), db = h.depth_format ? 4 : 0;
    tsr_composite_sparse *s = out;
    s->window_width = h.window_width;
    s->window_height = h.window_height;
    s->start = h.start;
    s->count = h.count;
    s->mode = h.mode;
    s->color_format = h.color_format;
    s->depth_format = h.depth_format;
    s->rank = h.rank;
    s->rank_count = h.rank_count;
    s->frame = h.frame;
    s->active = 0;
    s->nruns = 0;
    if (!h.codec.runs) {
        if ((uint64_t)h.count * (cb + db) != h.payload_size)
            return tsr_error_set(err, TSR_EPROTO, "image message: %u raw pixels need %llu bytes, payload has %u",
                                 h.count, (unsigned long long)h.count * (cb + db), h.payload_size);
        /* Classify into canonical runs, as compressing a dense image does. */
        /* Sized for the worst case up front. */
        size_t maxr = h.count / 2 + 2;
        uint32_t *r = realloc(s->runs, maxr * 2 * sizeof *r);
        if (!r)
            return tsr_error_set(err, TSR_ENOMEM, "image message: no memory for runs");
        s->runs = r;
        s->runs_capacity = maxr;
        if ((rc = reserve_planes(s, h.count, cb, err)))
            return rc;
        for (uint32_t i = 0; i < h.count; i++) {
            const uint8_t *c = p + (size_t)i * cb;
            float d = 1.0f;
            if (db)
                ci_copy(&d, p + (size_t)h.count * cb + (size_t)i * 4, 4);
            int act;
            if (h.mode == TSR_COMPOSITE_DEPTH) {
                act = d < 1.0f;
            } else if (h.color_format == TSR_COMPOSITE_RGBA8) {
                act = (c[0] | c[1] | c[2] | c[3]) != 0;
            } else {
                float f[4];
                ci_copy(f, c, sizeof f);
                act = f[0] != 0.0f || f[1] != 0.0f || f[2] != 0.0f || f[3] != 0.0f;
            }
            if (act) {
                if (!s->nruns) {
                    s->runs[0] = s->runs[1] = 0;
                    s->nruns = 1;
                }
                s->runs[2 * s->nruns - 1]++;
                ci_copy(s->color + (size_t)s->active * cb, c, cb);
                if (db)
                    s->depth[s->active] = d;
                s->active++;
            } else if (s->nruns && s->runs[2 * s->nruns - 1] == 0) {
                s->runs[2 * s->nruns - 2]++;
            } else {
                s->runs[2 * s->nruns] = 1;
                s->runs[2 * s->nruns + 1] = 0;
                s->nruns++;
            }
        }
        return TSR_OK;
    }
    /* Runs. */
    if ((size_t)(end - p) < (size_t)h.runs * 8)
        return tsr_error_set(err, TSR_EPROTO, "image message: %u runs do not fit the %u-byte payload", h.runs,
                             h.payload_size);
    if (h.runs > s->runs_capacity || !s->runs) {
        uint32_t *r = realloc(s->runs, ((size_t)h.runs + 1) * 2 * sizeof *r);
        if (!r)
            return tsr_error_set(err, TSR_ENOMEM, "image message: no memory for %u runs", h.runs);
        s->runs = r;
        s->runs_capacity = h.runs + 1;
    }
    uint64_t pixels = 0, active = 0;
    for (uint32_t i = 0; i < h.runs; i++) {
        s->runs[2 * i] = get32(p + 8 * i);
        s->runs[2 * i + 1] = get32(p + 8 * i + 4);
        pixels += (uint64_t)s->runs[2 * i] + s->runs[2 * i + 1];
        active += s->runs[2 * i + 1];
        if (pixels > h.count)
            return tsr_error_set(err, TSR_EPROTO, "image message: run %u overflows the image's %u pixels", i, h.count);
    }
    if (pixels != h.count || active != h.active)
        return tsr_error_set(err, TSR_EPROTO,
                             "image message: runs cover %llu pixels (%llu active), header says %u (%u active)",
                             (unsigned long long)pixels, (unsigned long long)active, h.count, h.active);
    s->nruns = h.runs;
    p += (size_t)h.runs * 8;
    size_t n = h.active;
    if (view && h.codec.color == TSR_COMPOSITE_CODEC_COLOR_RAW &&
        (h.codec.depth == TSR_COMPOSITE_CODEC_DEPTH_RAW || !db) && (uintptr_t)p % 4 == 0) {
        /* The planes as they lie in the message (checked like a copy). */
        if ((size_t)(end - p) < n * cb)
            return tsr_error_set(err, TSR_EPROTO, "image message: colour of %zu pixels truncated", n);
        if ((size_t)(end - p) - n * cb < n * db)
            return tsr_error_set(err, TSR_EPROTO, "image message: depth of %zu pixels truncated", n);
        if ((size_t)(end - p) != n * (cb + db))
            return tsr_error_set(err, TSR_EPROTO, "image message: %zu bytes left over after the payload",
                                 (size_t)(end - p) - n * (cb + db));
        ci_plane_free(s->color);
        ci_plane_free(s->depth);
        s->color = (uint8_t *)(uintptr_t)p;
        s->depth = db ? (float *)(uintptr_t)(p + n * cb) : NULL;
        s->pixel_capacity = 0;
        s->borrowed = 1;
        s->active = (uint32_t)n;
        return TSR_OK;
    }
    if ((rc = reserve_planes(s, n, cb, err)))
        return rc;
    s->active = (uint32_t)n;
    const char *why = NULL;
    size_t used = 0;
    if (h.codec.color == TSR_COMPOSITE_CODEC_COLOR_RAW) {
        if ((size_t)(end - p) < n * cb)
            return tsr_error_set(err, TSR_EPROTO, "image message: colour of %zu pixels truncated", n);
        ci_copy(s->color, p, n * cb);
        p += n * cb;
    } else if (h.codec.color == TSR_COMPOSITE_CODEC_COLOR_ERLE) {
        uint8_t *planes = malloc(n ? n * cb : 1);
        swizzle_tables *tab = malloc(sizeof *tab);
        if (!planes || !tab) {
            free(planes);
            free(tab);
            return tsr_error_set(err, TSR_ENOMEM, "image message: no memory for %zu pixels", n);
        }
        for (size_t k = 0; k < cb; k++) {
            if (rle_decode(p, (size_t)(end - p), n, planes + k * n, &used, &why)) {
                free(planes);
                free(tab);
                return tsr_error_set(err, TSR_EPROTO, "image message: colour plane %zu: %s", k, why);
            }
            p += used;
        }
        if (h.color_format == TSR_COMPOSITE_RGBA8) {
            swizzle_init(tab);
            for (size_t i = 0; i < n; i++) {
                uint32_t v = (uint32_t)planes[i] | (uint32_t)planes[n + i] << 8 | (uint32_t)planes[2 * n + i] << 16 |
                             (uint32_t)planes[3 * n + i] << 24;
                v = unswizzle(tab, v);
                ci_copy(s->color + 4 * i, &v, 4);
            }
        } else {
            for (size_t i = 0; i < n; i++)
                for (size_t k = 0; k < cb; k++)
                    s->color[i * cb + k] = planes[k * n + i];
        }
        free(planes);
        free(tab);
    } else {
        uint32_t half = ((uint32_t)h.window_width + 1) / 2;
        uint32_t *slot = malloc((n ? n : 1) * sizeof *slot), *stamp = malloc(half * sizeof *stamp);
        uint32_t *stamp_slot = malloc(half * sizeof *stamp_slot);
        if (!slot || !stamp || !stamp_slot) {
            free(slot);
            free(stamp);
            free(stamp_slot);
            return tsr_error_set(err, TSR_ENOMEM, "image message: no memory for yuv420 of %zu pixels", n);
        }
        uint32_t blocks = yuv_slots(s, slot, stamp, stamp_slot);
        free(stamp);
        free(stamp_slot);
        if ((size_t)(end - p) < 2 * n + 2 * (size_t)blocks) {
            free(slot);
            return tsr_error_set(err, TSR_EPROTO, "image message: yuv420 colour of %zu pixels truncated", n);
        }
        const uint8_t *uv = p + 2 * n;
        for (size_t i = 0; i < n; i++) {
            int Y = p[i], U = uv[2 * slot[i]] - 128, V = uv[2 * slot[i] + 1] - 128;
            uint8_t *px = s->color + 4 * i;
            px[0] = clamp8(Y + ((359 * V + 128) >> 8));
            px[1] = clamp8(Y - ((88 * U + 183 * V + 128) >> 8));
            px[2] = clamp8(Y + ((454 * U + 128) >> 8));
            px[3] = p[n + i];
        }
        free(slot);
        p += 2 * n + 2 * (size_t)blocks;
    }
    if (h.depth_format) {
        if (h.codec.depth == TSR_COMPOSITE_CODEC_DEPTH_RAW) {
            if ((size_t)(end - p) < n * 4)
                return tsr_error_set(err, TSR_EPROTO, "image message: depth of %zu pixels truncated", n);
            ci_copy(s->depth, p, n * 4);
            p += n * 4;
        } else if (h.codec.depth == TSR_COMPOSITE_CODEC_DEPTH_ERLE) {
            uint8_t *planes = malloc(n ? 4 * n : 1);
            if (!planes)
                return tsr_error_set(err, TSR_ENOMEM, "image message: no memory for %zu depths", n);
            for (int k = 0; k < 4; k++) {
                if (rle_decode(p, (size_t)(end - p), n, planes + (size_t)k * n, &used, &why)) {
                    free(planes);
                    return tsr_error_set(err, TSR_EPROTO, "image message: depth plane %d: %s", k, why);
                }
                p += used;
            }
            for (size_t i = 0; i < n; i++) {
                uint32_t v = 0;
                for (int k = 0; k < 4; k++)
                    v |= (uint32_t)planes[(size_t)k * n + i] << (24 - 8 * k);
                ci_copy(s->depth + i, &v, 4);
            }
            free(planes);
        } else {
            int bytes = h.codec.depth == TSR_COMPOSITE_CODEC_DEPTH_Q16 ? 2 : 3;
            float scale = 1.0f / (float)(1u << (8 * bytes));
            if ((size_t)(end - p) < n * (size_t)bytes)
                return tsr_error_set(err, TSR_EPROTO, "image message: quantised depth of %zu pixels truncated", n);
            for (size_t i = 0; i < n; i++) {
                uint32_t v = 0;
                for (int b = 0; b < bytes; b++)
                    v |= (uint32_t)p[b] << (8 * b);
                p += bytes;
                s->depth[i] = (float)v * scale;
            }
        }
    }
    if (p != end)
        return tsr_error_set(err, TSR_EPROTO, "image message: %zu bytes left over after the payload",
                             (size_t)(end - p));
    return TSR_OK;
}
