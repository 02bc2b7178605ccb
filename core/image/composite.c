/* core/image/composite.c — dense compositing images and the per-pixel
 * kernels (tessera/dev/composite.h): depth merge and premultiplied over.
 *
 * Owns: the planes of the tsr_composite_image values it allocates. Never: keeps
 * state between calls. The x86-64 kernels use SSE2 (always there) or AVX2
 * when the CPU has it (asked per call: __builtin_cpu_supports reads the
 * CPU model libgcc records at start-up, no state of ours); other machines
 * run the plain loops, which are also the definition the tests check. */
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include "composite_internal.h"
#include "tessera/dev/composite.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define TSR_COMPOSITE_X86 1
#endif

size_t tsr_composite_color_bytes(int color_format)
{
    return color_format == TSR_COMPOSITE_RGBA8 ? 4 : color_format == TSR_COMPOSITE_RGBA32F ? 16 : 0;
}

size_t tsr_composite_depth_bytes(int depth_format) { return depth_format == TSR_COMPOSITE_DEPTH32F ? 4 : 0; }

/* ---- planes (composite_internal.h) -------------------------------------- */

#define CI_PLANE_HEADER 64             /* keeps the plane 64-byte aligned */
#define CI_PLANE_MMAP_MIN (256u << 10) /* below: the heap (small images, tests) */

typedef struct ci_plane_header {
    size_t bytes, mapped; /* mapped: the mmap length, 0 when from the heap */
} ci_plane_header;

void *ci_plane_alloc(size_t bytes)
{
    if (bytes > SIZE_MAX - CI_PLANE_HEADER - 4096)
        return NULL;
    size_t total = bytes + CI_PLANE_HEADER;
    uint8_t *base = NULL;
    size_t mapped = 0;
    if (total >= CI_PLANE_MMAP_MIN) {
        void *m = mmap(NULL, total, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (m == MAP_FAILED)
            return NULL;
        base = m;
        mapped = total;
        /* whole frames are streamed through: huge pages, where the
         * system gives them (transparent_hugepage=madvise), spare the TLB */
        if (total >= (size_t)4 << 20)
            madvise(m, total, MADV_HUGEPAGE);
    } else {
        void *p = NULL;
        if (posix_memalign(&p, 64, total) != 0)
            return NULL;
        base = p;
    }
    ci_plane_header h = {.bytes = bytes, .mapped = mapped};
    memcpy(base, &h, sizeof h);
    return base + CI_PLANE_HEADER;
}

void ci_plane_free(void *plane)
{
    if (!plane)
        return;
    uint8_t *base = (uint8_t *)plane - CI_PLANE_HEADER;
    ci_plane_header h;
    memcpy(&h, base, sizeof h);
    if (h.mapped)
        munmap(base, h.mapped);
    else
        free(base);
}

size_t ci_plane_bytes(const void *plane)
{
    if (!plane)
        return 0;
    ci_plane_header h;
    memcpy(&h, (const uint8_t *)plane - CI_PLANE_HEADER, sizeof h);
    return h.bytes;
}

int tsr_composite_image_init(tsr_composite_image *img, int window_width, int window_height, int x, int y, int width,
                             int height, int color_format, int depth_format, tsr_error *err)
{
    if (window_width < 1 || window_height < 1 || window_width > TSR_COMPOSITE_MAX_SIDE ||
        window_height > TSR_COMPOSITE_MAX_SIDE)
        return tsr_error_set(err, TSR_EINVAL, "composite image: window %dx%d is outside 1..%d", window_width,
                             window_height, TSR_COMPOSITE_MAX_SIDE);
    if (width < 0 || height < 0 || x < 0 || y < 0 || x > window_width - width || y > window_height - height)
        return tsr_error_set(err, TSR_EINVAL, "composite image: region %dx%d at %d,%d is outside the %dx%d window",
                             width, height, x, y, window_width, window_height);
    if (!tsr_composite_color_bytes(color_format) ||
        (depth_format != TSR_COMPOSITE_NODEPTH && depth_format != TSR_COMPOSITE_DEPTH32F))
        return tsr_error_set(err, TSR_EINVAL, "composite image: unknown format (colour %d, depth %d)", color_format,
                             depth_format);
    size_t n = (size_t)width * (size_t)height, cb = tsr_composite_color_bytes(color_format);
    if (n > img->capacity_pixels || ci_plane_bytes(img->color) < n * cb || (depth_format && !img->depth && n) ||
        (!img->color && n)) {
        ci_plane_free(img->color);
        ci_plane_free(img->depth);
        img->color = ci_plane_alloc(n * cb);
        img->depth = ci_plane_alloc(n * 4);
        img->capacity_pixels = n;
        if (!img->color || !img->depth) {
            tsr_composite_image_free(img);
            return tsr_error_set(err, TSR_ENOMEM, "composite image: no memory for %dx%d pixels", width, height);
        }
    }
    img->window_width = window_width;
    img->window_height = window_height;
    img->x = x;
    img->y = y;
    img->width = width;
    img->height = height;
    img->color_format = color_format;
    img->depth_format = depth_format;
    return TSR_OK;
}

void tsr_composite_image_free(tsr_composite_image *img)
{
    ci_plane_free(img->color);
    ci_plane_free(img->depth);
    memset(img, 0, sizeof *img);
}

/* ---- plain kernels: the definition ----------------------------------- */

/* Total order on depth bits as a signed integer; every NaN is the largest. */
static inline int32_t depth_key(float d)
{
    uint32_t b;
    memcpy(&b, &d, 4);
    int32_t s = (int32_t)b;
    int32_t k = s ^ ((s >> 31) & INT32_MAX);
    return (b & 0x7fffffffu) > 0x7f800000u ? INT32_MAX : k;
}

static void depth_rgba8_c(size_t n, const uint8_t *fc, const float *fd, const uint8_t *bc, const float *bd, uint8_t *oc,
                          float *od)
{
    for (size_t i = 0; i < n; i++) {
        uint32_t cf, cb, df, db;
        memcpy(&cf, fc + 4 * i, 4);
        memcpy(&cb, bc + 4 * i, 4);
        memcpy(&df, fd + i, 4);
        memcpy(&db, bd + i, 4);
        uint32_t back = 0u - (uint32_t)(depth_key(fd[i]) > depth_key(bd[i]));
        uint32_t c = (cf & ~back) | (cb & back), d = (df & ~back) | (db & back);
        memcpy(oc + 4 * i, &c, 4);
        memcpy(od + i, &d, 4);
    }
}

static inline uint8_t over8(uint8_t f, uint8_t b, uint8_t fa)
{
    unsigned t = (unsigned)b * (255u - fa) + 128u;
    t = (t + (t >> 8)) >> 8;
    t += f;
    return (uint8_t)(t > 255u ? 255u : t);
}

static void over_rgba8_c(size_t n, const uint8_t *f, const uint8_t *b, uint8_t *o)
{
    for (size_t i = 0; i < n; i++) {
        uint8_t fa = f[4 * i + 3];
        uint8_t r = over8(f[4 * i], b[4 * i], fa), g = over8(f[4 * i + 1], b[4 * i + 1], fa);
        uint8_t bl = over8(f[4 * i + 2], b[4 * i + 2], fa), a = over8(fa, b[4 * i + 3], fa);
        o[4 * i] = r;
        o[4 * i + 1] = g;
        o[4 * i + 2] = bl;
        o[4 * i + 3] = a;
    }
}

/* ---- x86 kernels ------------------------------------------------------- */

#ifdef TSR_COMPOSITE_X86
static inline __m128i key_sse2(__m128i x)
{
    const __m128i abs = _mm_set1_epi32(INT32_MAX), inf = _mm_set1_epi32(0x7f800000);
    __m128i k = _mm_xor_si128(x, _mm_and_si128(_mm_srai_epi32(x, 31), abs));
    __m128i nan = _mm_cmpgt_epi32(_mm_and_si128(x, abs), inf);
    return _mm_or_si128(_mm_andnot_si128(nan, k), _mm_and_si128(nan, abs));
}

static inline __m128i sel_sse2(__m128i m, __m128i a, __m128i b)
{
    return _mm_or_si128(_mm_andnot_si128(m, a), _mm_and_si128(m, b));
}

static void depth_rgba8_sse2(size_t n, const uint8_t *fc, const float *fd, const uint8_t *bc, const float *bd,
                             uint8_t *oc, float *od)
{
    size_t i = 0;
    int into_back = oc == bc && od == bd;
    for (; i + 4 <= n; i += 4) {
        __m128i f = _mm_loadu_si128((const __m128i *)(fd + i)), b = _mm_loadu_si128((const __m128i *)(bd + i));
        __m128i back = _mm_cmpgt_epi32(key_sse2(f), key_sse2(b));
        /* Merging into back: spans the back wins wholly stay clean in cache. */
        if (into_back && _mm_movemask_epi8(back) == 0xffff)
            continue;
        __m128i cf = _mm_loadu_si128((const __m128i *)(fc + 4 * i)),
                cb = _mm_loadu_si128((const __m128i *)(bc + 4 * i));
        _mm_storeu_si128((__m128i *)(oc + 4 * i), sel_sse2(back, cf, cb));
        _mm_storeu_si128((__m128i *)(od + i), sel_sse2(back, f, b));
    }
    depth_rgba8_c(n - i, fc + 4 * i, fd + i, bc + 4 * i, bd + i, oc + 4 * i, od + i);
}

__attribute__((target("avx2"))) static inline __m256i key_avx2(__m256i x)
{
    const __m256i abs = _mm256_set1_epi32(INT32_MAX), inf = _mm256_set1_epi32(0x7f800000);
    __m256i k = _mm256_xor_si256(x, _mm256_and_si256(_mm256_srai_epi32(x, 31), abs));
    __m256i nan = _mm256_cmpgt_epi32(_mm256_and_si256(x, abs), inf);
    return _mm256_blendv_epi8(k, abs, nan);
}

__attribute__((target("avx2"))) static void depth_rgba8_avx2(size_t n, const uint8_t *fc, const float *fd,
                                                             const uint8_t *bc, const float *bd, uint8_t *oc, float *od)
{
    size_t i = 0;
    int into_back = oc == bc && od == bd;
    for (; i + 8 <= n; i += 8) {
        __m256i f = _mm256_loadu_si256((const __m256i *)(fd + i));
        __m256i b = _mm256_loadu_si256((const __m256i *)(bd + i));
        __m256i back = _mm256_cmpgt_epi32(key_avx2(f), key_avx2(b));
        if (into_back && _mm256_movemask_epi8(back) == -1)
            continue;
        __m256i cf = _mm256_loadu_si256((const __m256i *)(fc + 4 * i));
        __m256i cb = _mm256_loadu_si256((const __m256i *)(bc + 4 * i));
        _mm256_storeu_si256((__m256i *)(oc + 4 * i), _mm256_blendv_epi8(cf, cb, back));
        _mm256_storeu_si256((__m256i *)(od + i), _mm256_blendv_epi8(f, b, back));
    }
    depth_rgba8_c(n - i, fc + 4 * i, fd + i, bc + 4 * i, bd + i, oc + 4 * i, od + i);
}

/* 16-bit lanes: round(x / 255) for x in 0..65025, as over8 computes it. */
static inline __m128i div255_sse2(__m128i x)
{
    x = _mm_add_epi16(x, _mm_set1_epi16(128));
    return _mm_srli_epi16(_mm_add_epi16(x, _mm_srli_epi16(x, 8)), 8);
}

static void over_rgba8_sse2(size_t n, const uint8_t *f, const uint8_t *b, uint8_t *o)
{
    size_t i = 0;
    const __m128i zero = _mm_setzero_si128(), c255 = _mm_set1_epi16(255);
    for (; i + 4 <= n; i += 4) {
        __m128i vf = _mm_loadu_si128((const __m128i *)(f + 4 * i)), vb = _mm_loadu_si128((const __m128i *)(b + 4 * i));
        /* front alpha replicated over each pixel's four bytes */
        __m128i a = _mm_srli_epi32(vf, 24);
        a = _mm_or_si128(a, _mm_slli_epi32(a, 8));
        a = _mm_or_si128(a, _mm_slli_epi32(a, 16));
        __m128i alo = _mm_sub_epi16(c255, _mm_unpacklo_epi8(a, zero)),
                ahi = _mm_sub_epi16(c255, _mm_unpackhi_epi8(a, zero));
        __m128i lo = div255_sse2(_mm_mullo_epi16(_mm_unpacklo_epi8(vb, zero), alo));
        __m128i hi = div255_sse2(_mm_mullo_epi16(_mm_unpackhi_epi8(vb, zero), ahi));
        _mm_storeu_si128((__m128i *)(o + 4 * i), _mm_adds_epu8(vf, _mm_packus_epi16(lo, hi)));
    }
    over_rgba8_c(n - i, f + 4 * i, b + 4 * i, o + 4 * i);
}
#endif

/* ---- public kernels ----------------------------------------------------- */

void tsr_composite_depth_rgba8(size_t n, const uint8_t *front_color, const float *front_depth,
                               const uint8_t *back_color, const float *back_depth, uint8_t *out_color, float *out_depth)
{
#ifdef TSR_COMPOSITE_X86
    if (__builtin_cpu_supports("avx2"))
        depth_rgba8_avx2(n, front_color, front_depth, back_color, back_depth, out_color, out_depth);
    else
        depth_rgba8_sse2(n, front_color, front_depth, back_color, back_depth, out_color, out_depth);
#else
    depth_rgba8_c(n, front_color, front_depth, back_color, back_depth, out_color, out_depth);
#endif
}

void tsr_composite_depth_rgba32f(size_t n, const float *front_color, const float *front_depth, const float *back_color,
                                 const float *back_depth, float *out_color, float *out_depth)
{
    for (size_t i = 0; i < n; i++) {
        int back = depth_key(front_depth[i]) > depth_key(back_depth[i]);
        const float *c = back ? back_color + 4 * i : front_color + 4 * i;
        float d = back ? back_depth[i] : front_depth[i];
        float v[4] = {c[0], c[1], c[2], c[3]};
        memcpy(out_color + 4 * i, v, sizeof v);
        out_depth[i] = d;
    }
}

void tsr_composite_over_rgba8(size_t n, const uint8_t *front, const uint8_t *back, uint8_t *out)
{
#ifdef TSR_COMPOSITE_X86
    over_rgba8_sse2(n, front, back, out);
#else
    over_rgba8_c(n, front, back, out);
#endif
}

void tsr_composite_over_rgba32f(size_t n, const float *front, const float *back, float *out)
{
    for (size_t i = 0; i < n; i++) {
        float k = 1.0f - front[4 * i + 3];
        float v[4];
        for (int c = 0; c < 4; c++)
            v[c] = front[4 * i + c] + back[4 * i + c] * k;
        memcpy(out + 4 * i, v, sizeof v);
    }
}

/* ---- outgoing message copies -------------------------------------------- */

/* A message is written once here and read by another process (or the
 * display) later, never by this one: ordinary stores would first read
 * every destination line into the cache (the read-for-ownership) and then
 * push this peer's working set (the layer, the pieces it still merges) out
 * of it. Streaming stores skip both. Below the threshold the fence and the
 * unaligned edges cost more than they save, and the lines are likely still
 * cached by the reader when it comes, so memcpy stays (the threshold is
 * CI_STREAM_MIN, composite_internal.h). */

#ifdef TSR_COMPOSITE_X86
/* dst is advanced to a 16-byte boundary with memcpy first: the streaming
 * stores need aligned destinations, the loads take any source. No fence:
 * the caller fences once after its last streamed copy. */
static void copy_stream_sse2(uint8_t *dst, const uint8_t *src, size_t n)
{
    size_t head = (16 - ((uintptr_t)dst & 15)) & 15;
    head = head < n ? head : n;
    memcpy(dst, src, head);
    dst += head, src += head, n -= head;
    for (; n >= 64; n -= 64, dst += 64, src += 64) {
        __m128i a = _mm_loadu_si128((const __m128i *)src), b = _mm_loadu_si128((const __m128i *)(src + 16));
        __m128i c = _mm_loadu_si128((const __m128i *)(src + 32)), d = _mm_loadu_si128((const __m128i *)(src + 48));
        _mm_stream_si128((__m128i *)dst, a);
        _mm_stream_si128((__m128i *)(dst + 16), b);
        _mm_stream_si128((__m128i *)(dst + 32), c);
        _mm_stream_si128((__m128i *)(dst + 48), d);
    }
    memcpy(dst, src, n);
}

__attribute__((target("avx2"))) static void copy_stream_avx2(uint8_t *dst, const uint8_t *src, size_t n)
{
    size_t head = (32 - ((uintptr_t)dst & 31)) & 31;
    head = head < n ? head : n;
    memcpy(dst, src, head);
    dst += head, src += head, n -= head;
    for (; n >= 128; n -= 128, dst += 128, src += 128) {
        __m256i a = _mm256_loadu_si256((const __m256i *)src), b = _mm256_loadu_si256((const __m256i *)(src + 32));
        __m256i c = _mm256_loadu_si256((const __m256i *)(src + 64));
        __m256i d = _mm256_loadu_si256((const __m256i *)(src + 96));
        _mm256_stream_si256((__m256i *)dst, a);
        _mm256_stream_si256((__m256i *)(dst + 32), b);
        _mm256_stream_si256((__m256i *)(dst + 64), c);
        _mm256_stream_si256((__m256i *)(dst + 96), d);
    }
    memcpy(dst, src, n);
}
#endif

static void copy_streamed(const char *kernel, void *dst, const void *src, size_t n)
{
    if (kernel && !strcmp(kernel, "c")) {
        ci_copy(dst, src, n);
        return;
    }
#ifdef TSR_COMPOSITE_X86
    if (__builtin_cpu_supports("avx2") && (!kernel || !strcmp(kernel, "avx2")))
        copy_stream_avx2(dst, src, n);
    else
        copy_stream_sse2(dst, src, n);
#else
    memcpy(dst, src, n);
#endif
}

void ci_copy_stream(void *dst, const void *src, size_t n)
{
    if (n)
        copy_streamed(NULL, dst, src, n);
}

void ci_copy_fence(void)
{
#ifdef TSR_COMPOSITE_X86
    /* streamed stores are weakly ordered: the fence makes them visible
     * before whatever tells the reader the message is complete */
    _mm_sfence();
#endif
}

void tsr_composite_copy_using(const char *kernel, void *dst, const void *src, size_t n)
{
    if (n < CI_STREAM_MIN) {
        ci_copy(dst, src, n);
        return;
    }
    copy_streamed(kernel, dst, src, n);
    ci_copy_fence();
}

void tsr_composite_copy(void *dst, const void *src, size_t n) { tsr_composite_copy_using(NULL, dst, src, n); }

const char *tsr_composite_kernel_name(void)
{
#ifdef TSR_COMPOSITE_X86
    return __builtin_cpu_supports("avx2") ? "avx2" : "sse2";
#else
    return "c";
#endif
}

int tsr_composite_image_merge(int mode, const tsr_composite_image *front, const tsr_composite_image *back,
                              tsr_composite_image *out, tsr_error *err)
{
    if (front->width != back->width || front->height != back->height || front->x != back->x || front->y != back->y ||
        front->color_format != back->color_format || front->depth_format != back->depth_format ||
        out->width != front->width || out->height != front->height || out->color_format != front->color_format ||
        out->depth_format != front->depth_format)
        return tsr_error_set(err, TSR_EINVAL, "composite merge: images differ in region or format (%dx%d vs %dx%d)",
                             front->width, front->height, back->width, back->height);
    size_t n = (size_t)front->width * (size_t)front->height;
    if (mode == TSR_COMPOSITE_DEPTH) {
        if (front->depth_format != TSR_COMPOSITE_DEPTH32F)
            return tsr_error_set(err, TSR_EINVAL, "composite merge: depth mode needs depth planes");
        if (front->color_format == TSR_COMPOSITE_RGBA8)
            tsr_composite_depth_rgba8(n, front->color, front->depth, back->color, back->depth, out->color, out->depth);
        else
            tsr_composite_depth_rgba32f(n, (const float *)(void *)front->color, front->depth,
                                        (const float *)(void *)back->color, back->depth, (float *)(void *)out->color,
                                        out->depth);
    } else if (mode == TSR_COMPOSITE_ALPHA) {
        if (front->color_format == TSR_COMPOSITE_RGBA8)
            tsr_composite_over_rgba8(n, front->color, back->color, out->color);
        else
            tsr_composite_over_rgba32f(n, (const float *)(void *)front->color, (const float *)(void *)back->color,
                                       (float *)(void *)out->color);
    } else {
        return tsr_error_set(err, TSR_EINVAL, "composite merge: unknown mode %d", mode);
    }
    return TSR_OK;
}
