/* core/image/composite_sparse.c — sparse compositing images (active-pixel runs,
 * tessera/dev/composite.h): compress a read-back region, split a range,
 * merge two images run by run, expand into a dense frame.
 *
 * Owns: the three planes of the tsr_composite_sparse values it fills. Never:
 * expands background while merging or splitting; keeps state. */
#include <stdlib.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include "composite_internal.h"
#include "tessera/dev/composite.h"

/* Room for `runs` run pairs and `pixels` active pixels of cb colour bytes
 * (planes reused while big enough; composite_internal.h). */
static int sparse_reserve(tsr_composite_sparse *s, size_t runs, size_t pixels, size_t cb, tsr_error *err)
{
    if (s->borrowed) {
        /* a view's planes are another image's: never freed or reused */
        s->color = NULL;
        s->depth = NULL;
        s->pixel_capacity = 0;
        s->borrowed = 0;
    }
    if (runs > s->runs_capacity) {
        uint32_t *r = realloc(s->runs, runs * 2 * sizeof *r);
        if (!r)
            return tsr_error_set(err, TSR_ENOMEM, "sparse image: no memory for %zu runs", runs);
        s->runs = r;
        s->runs_capacity = runs;
    }
    if (pixels > s->pixel_capacity || ci_plane_bytes(s->color) < pixels * cb || (!s->color && pixels)) {
        void *c = ci_plane_alloc(pixels * cb), *d = c ? ci_plane_alloc(pixels * 4) : NULL;
        if (!d) {
            ci_plane_free(c);
            return tsr_error_set(err, TSR_ENOMEM, "sparse image: no memory for %zu pixels", pixels);
        }
        ci_plane_free(s->color);
        ci_plane_free(s->depth);
        s->color = c;
        s->depth = d;
        s->pixel_capacity = pixels;
    }
    return TSR_OK;
}

void tsr_composite_sparse_free(tsr_composite_sparse *img)
{
    free(img->runs);
    if (!img->borrowed) {
        ci_plane_free(img->color);
        ci_plane_free(img->depth);
    }
    memset(img, 0, sizeof *img);
}

static void sparse_begin(tsr_composite_sparse *s, int ww, int wh, uint32_t start, uint32_t count, int mode, int cf,
                         int df, int rank, uint32_t frame)
{
    s->window_width = ww;
    s->window_height = wh;
    s->start = start;
    s->count = count;
    s->mode = mode;
    s->color_format = cf;
    s->depth_format = df;
    s->rank = rank;
    s->rank_count = 1;
    s->frame = frame;
    s->active = 0;
    s->nruns = 0;
}

/* Appends n inactive pixels (the runs stay canonical: no empty pairs). */
static inline void put_inactive(tsr_composite_sparse *s, uint32_t n)
{
    if (!n)
        return;
    if (s->nruns && s->runs[2 * s->nruns - 1] == 0) {
        s->runs[2 * s->nruns - 2] += n;
    } else {
        s->runs[2 * s->nruns] = n;
        s->runs[2 * s->nruns + 1] = 0;
        s->nruns++;
    }
}

/* Makes room for n active pixels at the end; returns their index. */
static inline uint32_t put_active(tsr_composite_sparse *s, uint32_t n)
{
    uint32_t at = s->active;
    if (!s->nruns) {
        s->runs[0] = 0;
        s->runs[1] = 0;
        s->nruns = 1;
    }
    s->runs[2 * s->nruns - 1] += n;
    s->active += n;
    return at;
}

static inline void copy_active(tsr_composite_sparse *s, const tsr_composite_sparse *from, uint32_t from_at, uint32_t n)
{
    size_t cb = tsr_composite_color_bytes(s->color_format);
    uint32_t at = put_active(s, n);
    ci_copy(s->color + at * cb, from->color + (size_t)from_at * cb, n * cb);
    if (s->depth_format)
        ci_copy(s->depth + at, from->depth + from_at, n * sizeof(float));
}

static int check_window(int ww, int wh, uint32_t start, uint32_t count, const char *what, tsr_error *err)
{
    if (ww < 1 || wh < 1 || ww > TSR_COMPOSITE_MAX_SIDE || wh > TSR_COMPOSITE_MAX_SIDE)
        return tsr_error_set(err, TSR_EINVAL, "%s: window %dx%d is outside 1..%d", what, ww, wh,
                             TSR_COMPOSITE_MAX_SIDE);
    if ((uint64_t)start + count > (uint64_t)ww * (uint64_t)wh)
        return tsr_error_set(err, TSR_EINVAL, "%s: pixels %u..%u are outside the %dx%d window", what, start,
                             (unsigned)((uint64_t)start + count), ww, wh);
    return TSR_OK;
}

int tsr_composite_sparse_blank(tsr_composite_sparse *out, int window_width, int window_height, uint32_t start,
                               uint32_t count, int mode, int color_format, int depth_format, int rank, uint32_t frame,
                               tsr_error *err)
{
    int rc = check_window(window_width, window_height, start, count, "sparse image", err);
    if (rc || (rc = sparse_reserve(out, 1, 0, 4, err)))
        return rc;
    sparse_begin(out, window_width, window_height, start, count, mode, color_format, depth_format, rank, frame);
    put_inactive(out, count);
    return TSR_OK;
}

/* Active-pixel test of one pixel (the definition in composite.h). */
static inline int pixel_active(int mode, int cf, const uint8_t *color, const float *depth)
{
    if (mode == TSR_COMPOSITE_DEPTH)
        return *depth < 1.0f;
    if (cf == TSR_COMPOSITE_RGBA8) {
        uint32_t v;
        ci_copy(&v, color, 4);
        return v != 0;
    }
    float c[4];
    ci_copy(c, color, sizeof c);
    return c[0] != 0.0f || c[1] != 0.0f || c[2] != 0.0f || c[3] != 0.0f;
}

/* The number of pixels from the first of n whose activity is `active`
 * (pixel_active), up to n. The scan of every layer's region runs through
 * here once per frame: the common cases (depth mode; RGBA8 colour) test
 * 16 pixels per step with SSE2 compares, which give the same answer as
 * pixel_active pixel by pixel (a NaN depth compares false: inactive). */
static inline uint32_t run_length(int mode, int cf, const uint8_t *color, const float *depth, uint32_t n, int active)
{
    uint32_t i = 0;
#if defined(__SSE2__)
    unsigned flip = active ? 0xffffu : 0u;
    if (mode == TSR_COMPOSITE_DEPTH) {
        const __m128 one = _mm_set1_ps(1.0f);
        for (; i + 16 <= n; i += 16) {
            unsigned m = (unsigned)_mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(depth + i), one)) |
                         (unsigned)_mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(depth + i + 4), one)) << 4 |
                         (unsigned)_mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(depth + i + 8), one)) << 8 |
                         (unsigned)_mm_movemask_ps(_mm_cmplt_ps(_mm_loadu_ps(depth + i + 12), one)) << 12;
            m ^= flip; /* set where active: now where the activity differs */
            if (m)
                return i + (uint32_t)__builtin_ctz(m);
        }
    } else if (cf == TSR_COMPOSITE_RGBA8) {
        const __m128i zero = _mm_setzero_si128();
        for (; i + 16 <= n; i += 16) {
            const __m128i *c = (const __m128i *)(const void *)(color + (size_t)i * 4);
            /* set where the pixel is 0 (inactive) */
            unsigned m =
                (unsigned)_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_loadu_si128(c), zero))) |
                (unsigned)_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_loadu_si128(c + 1), zero))) << 4 |
                (unsigned)_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_loadu_si128(c + 2), zero))) << 8 |
                (unsigned)_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_loadu_si128(c + 3), zero))) << 12;
            m ^= flip ^ 0xffffu; /* now set where the activity differs */
            if (m)
                return i + (uint32_t)__builtin_ctz(m);
        }
    }
#endif
    size_t cb = tsr_composite_color_bytes(cf);
    while (i < n && pixel_active(mode, cf, color + (size_t)i * cb, depth ? depth + i : NULL) == active)
        i++;
    return i;
}

int tsr_composite_sparse_compress(const tsr_composite_image *in, int mode, uint32_t start, uint32_t count,
                                  tsr_composite_sparse *out, tsr_error *err)
{
    return ci_sparse_compress(in, mode, start, count, out, 0, err);
}

int tsr_composite_sparse_compress_runs(const tsr_composite_image *in, int mode, uint32_t start, uint32_t count,
                                       tsr_composite_sparse *out, tsr_error *err)
{
    return ci_sparse_compress(in, mode, start, count, out, 1, err);
}

int ci_sparse_planes(tsr_composite_sparse *s, size_t pixels, size_t cb, tsr_error *err)
{
    return sparse_reserve(s, 0, pixels, cb, err);
}

int ci_sparse_compress(const tsr_composite_image *in, int mode, uint32_t start, uint32_t count,
                       tsr_composite_sparse *out, int runs_only, tsr_error *err)
{
    int rc = check_window(in->window_width, in->window_height, start, count, "sparse compress", err);
    if (rc)
        return rc;
    if (mode == TSR_COMPOSITE_DEPTH && in->depth_format != TSR_COMPOSITE_DEPTH32F)
        return tsr_error_set(err, TSR_EINVAL, "sparse compress: depth mode needs a depth plane");
    if (mode != TSR_COMPOSITE_DEPTH && mode != TSR_COMPOSITE_ALPHA)
        return tsr_error_set(err, TSR_EINVAL, "sparse compress: unknown mode %d", mode);
    uint32_t w = (uint32_t)in->window_width, end = start + count;
    size_t roi = (size_t)in->width * (size_t)in->height;
    /* Runs: at most one per two region pixels, plus the row edges. */
    size_t max_runs = roi / 2 + (size_t)in->height + 2;
    if ((rc = sparse_reserve(out, max_runs,
                             runs_only     ? 0
                             : roi < count ? roi
                                           : count,
                             tsr_composite_color_bytes(in->color_format), err)))
        return rc;
    sparse_begin(out, in->window_width, in->window_height, start, count, mode, in->color_format, in->depth_format,
                 in->rank, in->frame);
    size_t cb = tsr_composite_color_bytes(in->color_format);
    uint32_t pos = start;
    for (int row = 0; row < in->height && pos < end; row++) {
        uint32_t seg0 = (uint32_t)(in->y + row) * w + (uint32_t)in->x, seg1 = seg0 + (uint32_t)in->width;
        if (seg1 <= start)
            continue;
        if (seg0 < start)
            seg0 = start;
        if (seg1 > end)
            seg1 = end;
        if (seg0 >= seg1)
            break;
        put_inactive(out, seg0 - pos);
        size_t base = (size_t)row * (size_t)in->width - ((size_t)(in->y + row) * w + (size_t)in->x);
        const uint8_t *color = in->color + (base + seg0) * cb;
        const float *depth = in->depth ? in->depth + base + seg0 : NULL;
        uint32_t n = seg1 - seg0, i = 0;
        while (i < n) {
            uint32_t k = run_length(mode, in->color_format, color + (size_t)i * cb, depth ? depth + i : NULL, n - i, 0);
            put_inactive(out, k);
            i += k;
            k = run_length(mode, in->color_format, color + (size_t)i * cb, depth ? depth + i : NULL, n - i, 1);
            if (k) {
                uint32_t at = put_active(out, k);
                if (!runs_only) {
                    ci_copy(out->color + at * cb, color + (size_t)i * cb, (size_t)k * cb);
                    if (in->depth_format)
                        ci_copy(out->depth + at, depth + i, (size_t)k * sizeof(float));
                }
            }
            i += k;
        }
        pos = seg1;
    }
    put_inactive(out, end - pos);
    return TSR_OK;
}

/* The runs of in's pixels [start, start+count) into out (runs reserved
 * here; out's header set), without touching pixel values. *first gets the
 * index in `in` of the first active pixel inside the range; out->active
 * the active pixels inside (contiguous in in's planes from *first). */
static int clip_runs(const tsr_composite_sparse *in, uint32_t start, uint32_t count, tsr_composite_sparse *out,
                     size_t pixels, uint32_t *first_active, const char *what, tsr_error *err)
{
    if (start < in->start || (uint64_t)start + count > (uint64_t)in->start + in->count)
        return tsr_error_set(err, TSR_EINVAL, "%s: pixels %u+%u are outside the image's %u+%u", what, start, count,
                             in->start, in->count);
    if (out == in)
        return tsr_error_set(err, TSR_EINVAL, "%s: output aliases the input", what);
    uint32_t lo = start - in->start, hi = lo + count, pos = 0, aoff = 0, r = 0;
    /* skip the runs wholly before the range */
    while (r < in->nruns && pos + in->runs[2 * r] + in->runs[2 * r + 1] <= lo) {
        pos += in->runs[2 * r] + in->runs[2 * r + 1];
        aoff += in->runs[2 * r + 1];
        r++;
    }
    uint32_t first = r, nr = 0;
    for (uint32_t q = r, p = pos; q < in->nruns && p < hi; q++, nr++)
        p += in->runs[2 * q] + in->runs[2 * q + 1];
    int rc = sparse_reserve(out, (size_t)nr + 1, pixels, tsr_composite_color_bytes(in->color_format), err);
    if (rc)
        return rc;
    sparse_begin(out, in->window_width, in->window_height, start, count, in->mode, in->color_format, in->depth_format,
                 in->rank, in->frame);
    out->rank_count = in->rank_count;
    int have_first = 0;
    *first_active = aoff;
    for (r = first; r < in->nruns && pos < hi; r++) {
        uint32_t ni = in->runs[2 * r], na = in->runs[2 * r + 1];
        /* inactive [pos, pos+ni), active [pos+ni, pos+ni+na) clipped to [lo, hi) */
        uint32_t a0 = pos > lo ? pos : lo, a1 = pos + ni < hi ? pos + ni : hi;
        if (a1 > a0)
            put_inactive(out, a1 - a0);
        uint32_t b0 = pos + ni > lo ? pos + ni : lo, b1 = pos + ni + na < hi ? pos + ni + na : hi;
        if (b1 > b0) {
            if (!have_first) {
                *first_active = aoff + (b0 - (pos + ni));
                have_first = 1;
            }
            put_active(out, b1 - b0);
        }
        pos += ni + na;
        aoff += na;
    }
    return TSR_OK;
}

int tsr_composite_sparse_split(const tsr_composite_sparse *in, uint32_t start, uint32_t count,
                               tsr_composite_sparse *out, tsr_error *err)
{
    uint32_t first = 0;
    int rc = clip_runs(in, start, count, out, count < in->active ? count : in->active, &first, "sparse split", err);
    if (rc)
        return rc;
    size_t cb = tsr_composite_color_bytes(in->color_format);
    ci_copy(out->color, in->color + (size_t)first * cb, (size_t)out->active * cb);
    if (in->depth_format)
        ci_copy(out->depth, in->depth + first, (size_t)out->active * sizeof(float));
    return TSR_OK;
}

int tsr_composite_sparse_view(const tsr_composite_sparse *in, uint32_t start, uint32_t count, tsr_composite_sparse *out,
                              tsr_error *err)
{
    uint32_t first = 0;
    int rc = clip_runs(in, start, count, out, 0, &first, "sparse view", err);
    if (rc)
        return rc;
    if (!out->borrowed) {
        ci_plane_free(out->color);
        ci_plane_free(out->depth);
    }
    size_t cb = tsr_composite_color_bytes(in->color_format);
    out->color = in->color ? in->color + (size_t)first * cb : NULL;
    out->depth = in->depth ? in->depth + first : NULL;
    out->pixel_capacity = 0;
    out->borrowed = 1;
    return TSR_OK;
}

/* A reader over one image's runs: the current span is inactive or active
 * with `left` pixels remaining; `at` indexes the next active pixel. */
typedef struct run_cursor {
    const uint32_t *runs;
    uint32_t nruns, r, left, at;
    int active;
} run_cursor;

static inline void cursor_norm(run_cursor *c)
{
    while (!c->left && c->r < c->nruns) {
        if (!c->active) {
            c->active = 1;
            c->left = c->runs[2 * c->r + 1];
        } else {
            c->r++;
            c->active = 0;
            c->left = c->r < c->nruns ? c->runs[2 * c->r] : 0;
        }
    }
}

static void cursor_init(run_cursor *c, const tsr_composite_sparse *s)
{
    c->runs = s->runs;
    c->nruns = s->nruns;
    c->r = 0;
    c->at = 0;
    c->active = 0;
    c->left = s->nruns ? s->runs[0] : 0;
    cursor_norm(c);
}

static inline void cursor_take(run_cursor *c, uint32_t n)
{
    c->left -= n;
    if (c->active)
        c->at += n;
    cursor_norm(c);
}

/* The two images cover the same pixels of one window, in one mode and
 * format: what a merge or a fold of them needs. */
static int same_range(const tsr_composite_sparse *a, const tsr_composite_sparse *b, const char *what, tsr_error *err)
{
    if (a->window_width != b->window_width || a->window_height != b->window_height || a->start != b->start ||
        a->count != b->count || a->mode != b->mode || a->color_format != b->color_format ||
        a->depth_format != b->depth_format)
        return tsr_error_set(err, TSR_EINVAL, "%s: images differ (pixels %u+%u of %dx%d vs %u+%u of %dx%d, or formats)",
                             what, a->start, a->count, a->window_width, a->window_height, b->start, b->count,
                             b->window_width, b->window_height);
    return TSR_OK;
}

int tsr_composite_sparse_merge(const tsr_composite_sparse *front, const tsr_composite_sparse *back,
                               tsr_composite_sparse *out, tsr_error *err)
{
    if (same_range(front, back, "sparse merge", err))
        return err->code;
    if (out == front || out == back)
        return tsr_error_set(err, TSR_EINVAL, "sparse merge: output aliases an input");
    if (front->mode == TSR_COMPOSITE_DEPTH && front->depth_format != TSR_COMPOSITE_DEPTH32F)
        return tsr_error_set(err, TSR_EINVAL, "sparse merge: depth mode needs depth planes");
    size_t pixels = (size_t)front->active + back->active;
    if (pixels > front->count)
        pixels = front->count;
    int rc = sparse_reserve(out, (size_t)front->nruns + back->nruns + 1, pixels,
                            tsr_composite_color_bytes(front->color_format), err);
    if (rc)
        return rc;
    sparse_begin(out, front->window_width, front->window_height, front->start, front->count, front->mode,
                 front->color_format, front->depth_format, front->rank < back->rank ? front->rank : back->rank,
                 front->frame);
    out->rank_count = front->rank_count + back->rank_count;
    size_t cb = tsr_composite_color_bytes(front->color_format);
    int depth = front->mode == TSR_COMPOSITE_DEPTH, f32 = front->color_format == TSR_COMPOSITE_RGBA32F;
    run_cursor f, b;
    cursor_init(&f, front);
    cursor_init(&b, back);
    while (f.left && b.left) {
        uint32_t n = f.left < b.left ? f.left : b.left;
        if (!f.active && !b.active) {
            put_inactive(out, n);
        } else if (!b.active) {
            copy_active(out, front, f.at, n);
        } else if (!f.active) {
            copy_active(out, back, b.at, n);
        } else {
            uint32_t at = put_active(out, n);
            uint8_t *oc = out->color + at * cb;
            const uint8_t *fc = front->color + (size_t)f.at * cb, *bc = back->color + (size_t)b.at * cb;
            if (depth && !f32)
                tsr_composite_depth_rgba8(n, fc, front->depth + f.at, bc, back->depth + b.at, oc, out->depth + at);
            else if (depth)
                tsr_composite_depth_rgba32f(n, (const float *)(const void *)fc, front->depth + f.at,
                                            (const float *)(const void *)bc, back->depth + b.at, (float *)(void *)oc,
                                            out->depth + at);
            else if (!f32)
                tsr_composite_over_rgba8(n, fc, bc, oc);
            else
                tsr_composite_over_rgba32f(n, (const float *)(const void *)fc, (const float *)(const void *)bc,
                                           (float *)(void *)oc);
            if (!depth && out->depth_format)
                ci_copy(out->depth + at, front->depth + f.at, n * sizeof(float));
        }
        cursor_take(&f, n);
        cursor_take(&b, n);
    }
    if (f.left || b.left)
        return tsr_error_set(err, TSR_EPROTO, "sparse merge: the images' runs do not add up to %u pixels",
                             front->count);
    return TSR_OK;
}

static void fill_background(uint8_t *dst, const void *background, size_t cb, uint32_t n);

int tsr_composite_fold_begin(tsr_composite_fold *f, const tsr_composite_sparse *first, tsr_error *err)
{
    if (first->mode != TSR_COMPOSITE_DEPTH || first->depth_format != TSR_COMPOSITE_DEPTH32F)
        return tsr_error_set(err, TSR_EINVAL, "sparse fold: depth mode with depth planes only");
    size_t cb = tsr_composite_color_bytes(first->color_format);
    tsr_composite_sparse *a = &f->acc;
    int rc = sparse_reserve(a, (size_t)first->nruns + 1, first->count, cb, err);
    if (rc)
        return rc;
    sparse_begin(a, first->window_width, first->window_height, first->start, first->count, first->mode,
                 first->color_format, first->depth_format, first->rank, first->frame);
    a->rank_count = first->rank_count;
    uint32_t pos = 0, at = 0;
    for (uint32_t r = 0; r < first->nruns; r++) {
        uint32_t ni = first->runs[2 * r], na = first->runs[2 * r + 1];
        if ((uint64_t)pos + ni + na > first->count || (uint64_t)at + na > first->active)
            return tsr_error_set(err, TSR_EPROTO, "sparse fold: the image's runs do not add up to %u pixels",
                                 first->count);
        pos += ni;
        ci_copy(a->color + (size_t)pos * cb, first->color + (size_t)at * cb, (size_t)na * cb);
        ci_copy(a->depth + pos, first->depth + at, (size_t)na * sizeof(float));
        pos += na;
        at += na;
    }
    if (pos != first->count)
        return tsr_error_set(err, TSR_EPROTO, "sparse fold: the image's runs do not add up to %u pixels", first->count);
    ci_copy(a->runs, first->runs, (size_t)first->nruns * 2 * sizeof *a->runs);
    a->nruns = first->nruns;
    a->active = at;
    return TSR_OK;
}

int tsr_composite_fold_begin_dense(tsr_composite_fold *f, const tsr_composite_image *in,
                                   const tsr_composite_sparse *runs, tsr_error *err)
{
    if (runs->mode != TSR_COMPOSITE_DEPTH || in->depth_format != TSR_COMPOSITE_DEPTH32F ||
        runs->depth_format != TSR_COMPOSITE_DEPTH32F)
        return tsr_error_set(err, TSR_EINVAL, "sparse fold: depth mode with depth planes only");
    if (runs->window_width != in->window_width || runs->window_height != in->window_height ||
        runs->color_format != in->color_format)
        return tsr_error_set(err, TSR_EINVAL,
                             "sparse fold: runs of a %dx%d window for a %dx%d read-back (or formats differ)",
                             runs->window_width, runs->window_height, in->window_width, in->window_height);
    size_t cb = tsr_composite_color_bytes(in->color_format);
    tsr_composite_sparse *a = &f->acc;
    int rc = check_window(runs->window_width, runs->window_height, runs->start, runs->count, "sparse fold", err);
    if (rc || (rc = sparse_reserve(a, (size_t)runs->nruns + 1, runs->count, cb, err)))
        return rc;
    sparse_begin(a, runs->window_width, runs->window_height, runs->start, runs->count, runs->mode, runs->color_format,
                 runs->depth_format, runs->rank, runs->frame);
    a->rank_count = runs->rank_count;
    uint32_t w = (uint32_t)in->window_width, pos = 0, at = 0;
    for (uint32_t r = 0; r < runs->nruns; r++) {
        uint32_t ni = runs->runs[2 * r], na = runs->runs[2 * r + 1];
        if ((uint64_t)pos + ni + na > runs->count)
            return tsr_error_set(err, TSR_EPROTO, "sparse fold: the image's runs do not add up to %u pixels",
                                 runs->count);
        pos += ni;
        if (na) {
            /* an active run lies in one row of the read-back's region, or
             * in whole rows of a region as wide as the window */
            uint32_t p = runs->start + pos, y = p / w, x = p % w;
            int inside = in->x == 0 && in->width == in->window_width
                             ? (int)y >= in->y && (uint64_t)(p - (uint32_t)in->y * w) + na <=
                                                      (uint64_t)in->width * (uint64_t)in->height
                             : (int)y >= in->y && (int)y < in->y + in->height && (int)x >= in->x &&
                                   (uint64_t)x + na <= (uint64_t)in->x + (uint64_t)in->width;
            if (!inside)
                return tsr_error_set(err, TSR_EPROTO,
                                     "sparse fold: an active run at pixel %u lies outside the %dx%d region at %d,%d", p,
                                     in->width, in->height, in->x, in->y);
            size_t src = ci_region_index(in, p);
            ci_copy(a->color + (size_t)pos * cb, in->color + src * cb, (size_t)na * cb);
            ci_copy(a->depth + pos, in->depth + src, (size_t)na * sizeof(float));
        }
        pos += na;
        at += na;
    }
    if (pos != runs->count || at != runs->active)
        return tsr_error_set(err, TSR_EPROTO, "sparse fold: the image's runs do not add up to %u pixels", runs->count);
    ci_copy(a->runs, runs->runs, (size_t)runs->nruns * 2 * sizeof *a->runs);
    a->nruns = runs->nruns;
    a->active = at;
    return TSR_OK;
}

int tsr_composite_fold_add(tsr_composite_fold *f, const tsr_composite_sparse *piece, int in_front, tsr_error *err)
{
    tsr_composite_sparse *a = &f->acc, *nx = &f->next;
    int rc = same_range(a, piece, "sparse fold", err);
    if (rc || (rc = sparse_reserve(nx, (size_t)a->nruns + piece->nruns + 1, 0, 4, err)))
        return rc;
    sparse_begin(nx, a->window_width, a->window_height, a->start, a->count, a->mode, a->color_format, a->depth_format,
                 a->rank, a->frame);
    size_t cb = tsr_composite_color_bytes(a->color_format);
    int f32 = a->color_format == TSR_COMPOSITE_RGBA32F;
    run_cursor u, p;
    cursor_init(&u, a);
    cursor_init(&p, piece);
    uint32_t pos = 0;
    while (u.left && p.left) {
        uint32_t n = u.left < p.left ? u.left : p.left;
        if (!p.active) {
            if (u.active)
                put_active(nx, n);
            else
                put_inactive(nx, n);
        } else {
            uint8_t *dc = a->color + (size_t)pos * cb;
            float *dd = a->depth + pos;
            const uint8_t *pc = piece->color + (size_t)p.at * cb;
            const float *pd = piece->depth + p.at;
            if (!u.active) {
                ci_copy(dc, pc, (size_t)n * cb);
                ci_copy(dd, pd, (size_t)n * sizeof(float));
            } else if (!f32) {
                if (in_front)
                    tsr_composite_depth_rgba8(n, pc, pd, dc, dd, dc, dd);
                else
                    tsr_composite_depth_rgba8(n, dc, dd, pc, pd, dc, dd);
            } else {
                const float *pcf = (const float *)(const void *)pc;
                float *dcf = (float *)(void *)dc;
                if (in_front)
                    tsr_composite_depth_rgba32f(n, pcf, pd, dcf, dd, dcf, dd);
                else
                    tsr_composite_depth_rgba32f(n, dcf, dd, pcf, pd, dcf, dd);
            }
            put_active(nx, n);
        }
        pos += n;
        cursor_take(&u, n);
        cursor_take(&p, n);
    }
    if (u.left || p.left)
        return tsr_error_set(err, TSR_EPROTO, "sparse fold: the images' runs do not add up to %u pixels", a->count);
    /* the new runs become the composite's; the old array builds the next */
    uint32_t *r = a->runs;
    size_t rcap = a->runs_capacity;
    a->runs = nx->runs;
    a->runs_capacity = nx->runs_capacity;
    a->nruns = nx->nruns;
    a->active = nx->active;
    nx->runs = r;
    nx->runs_capacity = rcap;
    nx->nruns = 0;
    if (piece->rank < a->rank)
        a->rank = piece->rank;
    a->rank_count += piece->rank_count;
    if (in_front)
        a->frame = piece->frame;
    return TSR_OK;
}

int tsr_composite_fold_end(tsr_composite_fold *f, tsr_composite_sparse *out, tsr_error *err)
{
    const tsr_composite_sparse *a = &f->acc;
    size_t cb = tsr_composite_color_bytes(a->color_format);
    if (out == a || out == &f->next)
        return tsr_error_set(err, TSR_EINVAL, "sparse fold: output aliases the fold");
    int rc = sparse_reserve(out, (size_t)a->nruns + 1, a->active, cb, err);
    if (rc)
        return rc;
    sparse_begin(out, a->window_width, a->window_height, a->start, a->count, a->mode, a->color_format, a->depth_format,
                 a->rank, a->frame);
    out->rank_count = a->rank_count;
    ci_copy(out->runs, a->runs, (size_t)a->nruns * 2 * sizeof *a->runs);
    out->nruns = a->nruns;
    out->active = a->active;
    uint32_t pos = 0, at = 0;
    for (uint32_t r = 0; r < a->nruns; r++) {
        uint32_t ni = a->runs[2 * r], na = a->runs[2 * r + 1];
        pos += ni;
        ci_copy(out->color + (size_t)at * cb, a->color + (size_t)pos * cb, (size_t)na * cb);
        ci_copy(out->depth + at, a->depth + pos, (size_t)na * sizeof(float));
        pos += na;
        at += na;
    }
    return TSR_OK;
}

int tsr_composite_fold_fill(tsr_composite_fold *f, const void *background, tsr_error *err)
{
    tsr_composite_sparse *a = &f->acc;
    size_t cb = tsr_composite_color_bytes(a->color_format);
    if (a->count && !a->runs)
        return tsr_error_set(err, TSR_EINVAL, "sparse fold: fill before the fold began");
    uint32_t pos = 0;
    for (uint32_t r = 0; r < a->nruns; r++) {
        uint32_t ni = a->runs[2 * r], na = a->runs[2 * r + 1];
        fill_background(a->color + (size_t)pos * cb, background, cb, ni);
        for (uint32_t i = 0; i < ni; i++)
            a->depth[pos + i] = 1.0f;
        pos += ni + na;
    }
    a->nruns = a->count ? 1 : 0;
    if (a->count) {
        a->runs[0] = 0;
        a->runs[1] = a->count;
    }
    a->active = a->count;
    return TSR_OK;
}

void tsr_composite_fold_free(tsr_composite_fold *f)
{
    tsr_composite_sparse_free(&f->acc);
    tsr_composite_sparse_free(&f->next);
}

/* n pixels of the background colour: a copy of constant size per pixel,
 * which the compiler turns into plain (vector) stores; a copy of cb bytes
 * would be a library call per pixel, and background is most of a sparse
 * frame. */
static void fill_background(uint8_t *dst, const void *background, size_t cb, uint32_t n)
{
    if (cb == 4) {
        uint32_t v;
        memcpy(&v, background, 4);
        for (uint32_t i = 0; i < n; i++)
            memcpy(dst + 4 * (size_t)i, &v, 4);
    } else {
        float v[4];
        memcpy(v, background, sizeof v);
        for (uint32_t i = 0; i < n; i++)
            memcpy(dst + 16 * (size_t)i, v, sizeof v);
    }
}

int tsr_composite_sparse_to_dense(const tsr_composite_sparse *in, const void *background, tsr_composite_image *dst,
                                  tsr_error *err)
{
    if (dst->window_width != in->window_width || dst->window_height != in->window_height ||
        dst->color_format != in->color_format)
        return tsr_error_set(err, TSR_EINVAL, "sparse to dense: %dx%d image into a %dx%d frame (or formats differ)",
                             in->window_width, in->window_height, dst->window_width, dst->window_height);
    size_t cb = tsr_composite_color_bytes(in->color_format);
    uint32_t w = (uint32_t)in->window_width;
    uint32_t pos = in->start, at = 0;
    static const float far = 1.0f;
    for (uint32_t r = 0; r < in->nruns; r++) {
        for (int part = 0; part < 2; part++) {
            uint32_t n = in->runs[2 * r + part];
            while (n) {
                uint32_t y = pos / w, x = pos % w, len = w - x < n ? w - x : n;
                if ((int)y < dst->y || (int)y >= dst->y + dst->height || (int)x < dst->x ||
                    (int)(x + len) > dst->x + dst->width)
                    return tsr_error_set(
                        err, TSR_EINVAL,
                        "sparse to dense: pixels %u..%u of row %u lie outside the %dx%d region at %d,%d", x, x + len, y,
                        dst->width, dst->height, dst->x, dst->y);
                size_t o = (size_t)(y - (uint32_t)dst->y) * (size_t)dst->width + (x - (uint32_t)dst->x);
                if (part && in->mode == TSR_COMPOSITE_ALPHA) {
                    /* the background is added once, here: pixel over background */
                    if (in->color_format == TSR_COMPOSITE_RGBA8) {
                        for (uint32_t i = 0; i < len; i++)
                            tsr_composite_over_rgba8(1, in->color + ((size_t)at + i) * 4, background,
                                                     dst->color + (o + i) * 4);
                    } else {
                        for (uint32_t i = 0; i < len; i++)
                            tsr_composite_over_rgba32f(1,
                                                       (const float *)(const void *)(in->color + ((size_t)at + i) * 16),
                                                       background, (float *)(void *)(dst->color + (o + i) * 16));
                    }
                    if (dst->depth_format && in->depth_format)
                        ci_copy(dst->depth + o, in->depth + at, len * sizeof(float));
                    at += len;
                } else if (part) {
                    ci_copy(dst->color + o * cb, in->color + (size_t)at * cb, len * cb);
                    if (dst->depth_format && in->depth_format)
                        ci_copy(dst->depth + o, in->depth + at, len * sizeof(float));
                    at += len;
                } else {
                    fill_background(dst->color + o * cb, background, cb, len);
                    if (dst->depth_format)
                        for (uint32_t i = 0; i < len; i++)
                            dst->depth[o + i] = far;
                }
                pos += len;
                n -= len;
            }
        }
    }
    return TSR_OK;
}
