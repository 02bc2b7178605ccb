/* tests/composite/composite_test.c — sort-last compositing: the kernels
 * of tessera/dev/composite.h against plain reference loops written here,
 * sparse against dense, the codecs and the message decoder, and every
 * strategy of spus/binaryswap/strategies for 1..64 peers run in one process
 * (a thread per peer, in-memory queues as the transport) against a serial
 * reference composite. `composite_test NAME` runs one test. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <dirent.h>
#include "fuzz_composite_message.h"
#include "harness.h"
#include "strategy.h"
#include "tessera/dev/composite.h"

static uint64_t rng_state = 88172645463325252ull;
static uint32_t rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (uint32_t)(rng_state >> 11);
}
static float rndf(void) { return (float)(rnd() % 1000000) / 1000000.0f; }

/* ---- references ----------------------------------------------------------- */

/* "back wins": the rule composite.h states, written out plainly. */
static int ref_back_wins(float f, float b)
{
    if (isnan(b))
        return 0;
    if (isnan(f))
        return 1;
    if (b < f)
        return 1;
    return b == f && signbit(b) && !signbit(f);
}

static uint8_t ref_over8(uint8_t f, uint8_t b, uint8_t fa)
{
    double exact = (double)b * (255 - fa) / 255.0;
    int v = f + (int)floor(exact + 0.5);
    return (uint8_t)(v > 255 ? 255 : v);
}

static const uint8_t BG[4] = {10, 20, 30, 40};

typedef enum { FILL_RANDOM, FILL_BACKGROUND, FILL_EQUAL, FILL_EXTREMES, FILL_SINGLE, FILL_NAN, FILL_OPAQUE } fill_kind;

/* A peer's read-back image: region x,y,w,h of a W x H window. */
static void make_image(tsr_composite_image *img, int W, int H, int x, int y, int w, int h, int rank, fill_kind kind)
{
    tsr_error err;
    REQUIRE(tsr_composite_image_init(img, W, H, x, y, w, h, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, &err) ==
                TSR_OK,
            "%s", err.message);
    img->rank = rank;
    img->frame = 7;
    size_t n = (size_t)w * h;
    size_t single = n ? rnd() % n : 0;
    for (size_t i = 0; i < n; i++) {
        uint8_t *c = img->color + 4 * i;
        for (int k = 0; k < 4; k++)
            c[k] = (uint8_t)rnd();
        float d;
        switch (kind) {
        case FILL_BACKGROUND: d = 1.0f; break;
        case FILL_EQUAL: d = 0.5f; break;
        case FILL_EXTREMES: d = (rnd() & 1) ? 0.0f : 1.0f; break;
        case FILL_SINGLE: d = i == single ? 0.25f : 1.0f; break;
        case FILL_NAN: d = (rnd() % 3 == 0) ? NAN : (rnd() % 2 ? 1.0f : rndf()); break;
        case FILL_OPAQUE:
        default:
            /* runs of background and of depth, coarse so ties happen */
            d = (i / 5 + (size_t)rank) % 3 == 0 ? 1.0f : (float)(rnd() % 8) / 8.0f;
            break;
        }
        if (kind == FILL_OPAQUE)
            c[3] = (rnd() & 1) ? 255 : 0;
        img->depth[i] = d;
    }
}

/* The serial reference: the whole window, peers drawn in rank order with
 * GL_LESS over a cleared frame (background colour, depth 1). */
static void reference_depth(tsr_composite_image *imgs, int n, int W, int H, uint8_t *color, float *depth)
{
    for (int p = 0; p < W * H; p++) {
        memcpy(color + 4 * p, BG, 4);
        depth[p] = 1.0f;
    }
    for (int r = 0; r < n; r++) {
        tsr_composite_image *im = &imgs[r];
        for (int yy = 0; yy < im->height; yy++)
            for (int xx = 0; xx < im->width; xx++) {
                size_t i = (size_t)yy * im->width + xx, p = (size_t)(im->y + yy) * W + im->x + xx;
                float d = im->depth[i];
                if (d < depth[p]) {
                    depth[p] = d;
                    memcpy(color + 4 * p, im->color + 4 * i, 4);
                }
            }
    }
}

/* Alpha reference: the serial back-to-front blend, written out pixel by
 * pixel: acc = transparent black; acc = layer over acc from the last rank
 * to rank 0; then acc over the background, added once. */
static void reference_alpha(tsr_composite_image *imgs, int n, int W, int H, uint8_t *color)
{
    memset(color, 0, (size_t)W * H * 4);
    for (int r = n - 1; r >= 0; r--) {
        tsr_composite_image *im = &imgs[r];
        for (int yy = 0; yy < im->height; yy++)
            for (int xx = 0; xx < im->width; xx++) {
                size_t i = (size_t)yy * im->width + xx, p = (size_t)(im->y + yy) * W + im->x + xx;
                uint8_t *a = color + 4 * p, *f = im->color + 4 * i;
                uint8_t fa = f[3];
                for (int k = 0; k < 4; k++)
                    a[k] = ref_over8(f[k], a[k], fa);
            }
    }
    for (int p = 0; p < W * H; p++) {
        uint8_t *a = color + 4 * p, fa = a[3];
        for (int k = 0; k < 4; k++)
            a[k] = ref_over8(a[k], BG[k], fa);
    }
}

/* ---- kernels ----------------------------------------------------------------- */

static float adversarial_depth(void)
{
    static const float v[] = {0.0f, -0.0f, 1.0f, 0.5f, 0.5f, 1e-38f, 1e-45f, INFINITY, -INFINITY, NAN, -NAN, 2.0f};
    return rnd() % 3 ? v[rnd() % (sizeof v / sizeof v[0])] : rndf();
}

static int test_depth_kernel_matches_reference(void)
{
    for (int iter = 0; iter < 400; iter++) {
        size_t n = rnd() % 70, off = rnd() % 4;
        uint8_t fc[300], bc[300], oc[300], rc[300];
        float fd[80], bd[80], od[80], rd[80];
        for (size_t i = 0; i < n + off; i++) {
            for (int k = 0; k < 4; k++) {
                fc[4 * i + k] = (uint8_t)rnd();
                bc[4 * i + k] = (uint8_t)rnd();
            }
            fd[i] = adversarial_depth();
            bd[i] = iter % 5 == 0 ? fd[i] : adversarial_depth();
        }
        for (size_t i = off; i < n + off; i++) {
            int back = ref_back_wins(fd[i], bd[i]);
            memcpy(rc + 4 * i, back ? bc + 4 * i : fc + 4 * i, 4);
            memcpy(rd + i, back ? bd + i : fd + i, 4);
        }
        int alias = iter % 3;
        if (alias == 0) {
            tsr_composite_depth_rgba8(n, fc + 4 * off, fd + off, bc + 4 * off, bd + off, oc + 4 * off, od + off);
        } else if (alias == 1) {
            tsr_composite_depth_rgba8(n, fc + 4 * off, fd + off, bc + 4 * off, bd + off, bc + 4 * off, bd + off);
            memcpy(oc, bc, sizeof oc);
            memcpy(od, bd, sizeof od);
        } else {
            tsr_composite_depth_rgba8(n, fc + 4 * off, fd + off, bc + 4 * off, bd + off, fc + 4 * off, fd + off);
            memcpy(oc, fc, sizeof oc);
            memcpy(od, fd, sizeof od);
        }
        CHECK(!memcmp(oc + 4 * off, rc + 4 * off, 4 * n), "colour differs (n %zu, alias %d)", n, alias);
        CHECK(!memcmp(od + off, rd + off, 4 * n), "depth differs (n %zu, alias %d)", n, alias);
    }
    printf("kernel: %s\n", tsr_composite_kernel_name());
    return harness_failures;
}

/* One copy through `kernel` into dst (cap bytes, all 0xa5 outside what
 * earlier copies wrote): the bytes equal memcpy's, the 64 before and after
 * are untouched. */
static int copy_matches(const char *kernel, uint8_t *dst, size_t cap, const uint8_t *src, size_t dof, size_t n)
{
    size_t guard_end = dof + n + 64 < cap ? dof + n + 64 : cap;
    memset(dst, 0xa5, dof);
    memset(dst + dof + n, 0xa5, guard_end - dof - n);
    tsr_composite_copy_using(kernel, dst + dof, src, n);
    if (n && memcmp(dst + dof, src, n))
        return 0;
    for (size_t i = 0; i < dof; i++)
        if (dst[i] != 0xa5)
            return 0;
    for (size_t i = dof + n; i < guard_end; i++)
        if (dst[i] != 0xa5)
            return 0;
    return 1;
}

/* The message copy's streaming path starts at 64 KiB: every destination
 * start and end alignment within a cache line (sizes from just below to
 * just above that), the source's alignment varied with them, then a few
 * sizes far from it; through each kernel, against memcpy. */
static int test_large_messages_any_alignment(void)
{
    static const char *kernels[] = {"avx2", "sse2", "c", NULL};
    size_t cap = (1u << 20) + 256;
    uint8_t *src = malloc(cap), *dst = malloc(cap);
    REQUIRE(src && dst, "no memory");
    for (size_t i = 0; i < cap; i++)
        src[i] = (uint8_t)rnd();
    for (size_t k = 0; k < sizeof kernels / sizeof *kernels; k++) {
        const char *name = kernels[k] ? kernels[k] : "auto";
        for (size_t dof = 0; dof < 64; dof++)
            for (size_t end = 0; end < 64; end++) {
                size_t n = 65536 - dof + end, so = (dof * 5 + end * 3 + k) % 64;
                if (!copy_matches(kernels[k], dst, cap, src + so, dof, n)) {
                    CHECK(0, "kernel %s: %zu bytes from offset %zu to offset %zu differ from memcpy", name, n, so, dof);
                    goto out;
                }
            }
        static const size_t sizes[] = {0, 1, 63, 64, 4095, 65535, 65536, 65537, 200003, 1u << 20};
        static const size_t offs[] = {0, 1, 15, 16, 31, 32, 63};
        for (size_t z = 0; z < sizeof sizes / sizeof *sizes; z++)
            for (size_t a = 0; a < sizeof offs / sizeof *offs; a++)
                for (size_t b = 0; b < sizeof offs / sizeof *offs; b++)
                    if (!copy_matches(kernels[k], dst, cap, src + offs[a], offs[b], sizes[z])) {
                        CHECK(0, "kernel %s: %zu bytes from offset %zu to offset %zu differ from memcpy", name,
                              sizes[z], offs[a], offs[b]);
                        goto out;
                    }
    }
    tsr_composite_copy(NULL, NULL, 0); /* an empty image has no planes */
out:
    free(src);
    free(dst);
    printf("kernel: %s\n", tsr_composite_kernel_name());
    return harness_failures;
}

static int test_over_kernel_matches_reference(void)
{
    for (int iter = 0; iter < 400; iter++) {
        size_t n = rnd() % 70;
        uint8_t f[280], b[280], o[280], r[280];
        for (size_t i = 0; i < n; i++) {
            uint8_t fa = (uint8_t)rnd(), ba = (uint8_t)rnd();
            if (iter % 4 == 0)
                fa = (rnd() & 1) ? 255 : 0;
            for (int k = 0; k < 3; k++) {
                f[4 * i + k] = iter % 2 ? (uint8_t)(rnd() % (fa + 1u)) : (uint8_t)rnd();
                b[4 * i + k] = (uint8_t)(rnd() % (ba + 1u));
            }
            f[4 * i + 3] = fa;
            b[4 * i + 3] = ba;
            for (int k = 0; k < 4; k++)
                r[4 * i + k] = ref_over8(f[4 * i + k], b[4 * i + k], fa);
        }
        tsr_composite_over_rgba8(n, f, b, o);
        CHECK(!memcmp(o, r, 4 * n), "over differs from round(b*(255-fa)/255) (n %zu)", n);
        tsr_composite_over_rgba8(n, f, b, b); /* in place into back */
        CHECK(!memcmp(b, r, 4 * n), "in-place over differs (n %zu)", n);
    }
    /* associative where it must be: every alpha 0 or 255 */
    for (int iter = 0; iter < 200; iter++) {
        uint8_t L[3][64 * 4], ab[256], abc1[256], bc[256], abc2[256];
        for (int l = 0; l < 3; l++)
            for (int i = 0; i < 64; i++) {
                uint8_t a = (rnd() & 1) ? 255 : 0;
                for (int k = 0; k < 3; k++)
                    L[l][4 * i + k] = a ? (uint8_t)rnd() : 0;
                L[l][4 * i + 3] = a;
            }
        tsr_composite_over_rgba8(64, L[0], L[1], ab);
        tsr_composite_over_rgba8(64, ab, L[2], abc1);
        tsr_composite_over_rgba8(64, L[1], L[2], bc);
        tsr_composite_over_rgba8(64, L[0], bc, abc2);
        CHECK(!memcmp(abc1, abc2, sizeof abc1), "(a over b) over c != a over (b over c) with binary alpha");
    }
    return harness_failures;
}

static int test_nan_depth_never_wins(void)
{
    uint8_t fc[4] = {1, 1, 1, 1}, bc[4] = {2, 2, 2, 2}, oc[4];
    float fd, bd, od;
    fd = NAN, bd = 0.5f;
    tsr_composite_depth_rgba8(1, fc, &fd, bc, &bd, oc, &od);
    CHECK(oc[0] == 2 && od == 0.5f, "NaN front beat 0.5");
    fd = 0.5f, bd = NAN;
    tsr_composite_depth_rgba8(1, fc, &fd, bc, &bd, oc, &od);
    CHECK(oc[0] == 1 && od == 0.5f, "NaN back beat 0.5");
    fd = 1.0f, bd = -NAN;
    tsr_composite_depth_rgba8(1, fc, &fd, bc, &bd, oc, &od);
    CHECK(oc[0] == 1, "negative NaN beat the background depth 1.0");
    fd = 0.5f, bd = 0.5f;
    tsr_composite_depth_rgba8(1, fc, &fd, bc, &bd, oc, &od);
    CHECK(oc[0] == 1, "equal depth did not go to the front (lower rank)");
    /* a NaN pixel is background in the sparse form */
    tsr_composite_image img = {0};
    tsr_error err;
    make_image(&img, 4, 4, 0, 0, 4, 4, 0, FILL_NAN);
    tsr_composite_sparse s = {0};
    CHECK_OK(tsr_composite_sparse_compress(&img, TSR_COMPOSITE_DEPTH, 0, 16, &s, &err), err);
    for (uint32_t i = 0; i < s.active; i++)
        CHECK(!isnan(s.depth[i]) && s.depth[i] < 1.0f, "active pixel with depth %g", s.depth[i]);
    tsr_composite_sparse_free(&s);
    tsr_composite_image_free(&img);
    return harness_failures;
}

/* The runs compress finds, against a pixel-by-pixel reading of the
 * active-pixel rule (composite.h): runs of every length around the
 * kernel's 16-pixel steps, depth values at the edge of the rule (1.0, the
 * largest float below it, -0, NaN, infinities), RGBA8 pixels with one byte
 * set, float colours with one -0 or NaN channel, regions that start and end
 * anywhere in a row. */
static int ref_active(int mode, int cf, const tsr_composite_image *img, size_t i)
{
    if (mode == TSR_COMPOSITE_DEPTH)
        return img->depth[i] < 1.0f;
    if (cf == TSR_COMPOSITE_RGBA8)
        return img->color[4 * i] || img->color[4 * i + 1] || img->color[4 * i + 2] || img->color[4 * i + 3];
    const float *c = (const float *)(const void *)img->color + 4 * i;
    return c[0] != 0.0f || c[1] != 0.0f || c[2] != 0.0f || c[3] != 0.0f;
}

static int test_compress_runs_match_pixel_rule(void)
{
    tsr_error err;
    static const float depths_on[] = {0.0f, -0.0f, 0.5f, 0.99999994f, -INFINITY, -1.0f};
    static const float depths_off[] = {1.0f, 2.0f, INFINITY, NAN, -NAN};
    for (int iter = 0; iter < 400; iter++) {
        int mode = iter % 3 == 2 ? TSR_COMPOSITE_ALPHA : TSR_COMPOSITE_DEPTH;
        int cf = mode == TSR_COMPOSITE_ALPHA && iter % 2 ? TSR_COMPOSITE_RGBA32F : TSR_COMPOSITE_RGBA8;
        int W = 1 + rnd() % 90, H = 1 + rnd() % 6;
        int x = rnd() % W, y = rnd() % H, w = 1 + rnd() % (W - x), h = 1 + rnd() % (H - y);
        tsr_composite_image img = {0};
        CHECK_OK(tsr_composite_image_init(&img, W, H, x, y, w, h, cf, TSR_COMPOSITE_DEPTH32F, &err), err);
        size_t n = (size_t)w * h, cb = tsr_composite_color_bytes(cf);
        memset(img.color, 0, n * cb);
        /* runs of 1..40 pixels, alternating activity */
        int on = rnd() % 2;
        for (size_t i = 0; i < n;) {
            size_t len = 1 + rnd() % (iter % 4 ? 40 : 3);
            for (size_t j = i; j < n && j < i + len; j++) {
                img.depth[j] = on ? depths_on[rnd() % 6] : depths_off[rnd() % 5];
                if (cf == TSR_COMPOSITE_RGBA8) {
                    memset(img.color + 4 * j, 0, 4);
                    if (on)
                        img.color[4 * j + rnd() % 4] = (uint8_t)(1 + rnd() % 255);
                } else {
                    float *c = (float *)(void *)(img.color + 16 * j);
                    c[0] = c[1] = c[2] = c[3] = rnd() % 2 ? 0.0f : -0.0f;
                    if (on)
                        c[rnd() % 4] = rnd() % 2 ? NAN : rndf() + 0.001f;
                }
            }
            i += len;
            on = !on;
        }
        uint32_t all = (uint32_t)W * H, start = rnd() % all, count = rnd() % (all - start + 1);
        tsr_composite_sparse s = {0};
        CHECK_OK(tsr_composite_sparse_compress(&img, mode, start, count, &s, &err), err);
        /* walk the runs against the rule, pixel by pixel */
        uint32_t p = start, a = 0;
        for (uint32_t r = 0; r < s.nruns && !harness_failures; r++)
            for (int act = 0; act < 2; act++)
                for (uint32_t k = 0; k < s.runs[2 * r + act]; k++, p++) {
                    int px = (int)(p % (uint32_t)W), py = (int)(p / (uint32_t)W);
                    int inside = px >= x && px < x + w && py >= y && py < y + h;
                    size_t i = inside ? (size_t)(py - y) * w + (size_t)(px - x) : 0;
                    int want = inside && ref_active(mode, cf, &img, i);
                    CHECK(want == act, "iter %d: pixel %u is %s in the runs, %s by the rule", iter, p,
                          act ? "active" : "inactive", want ? "active" : "inactive");
                    if (act && want) {
                        CHECK(!memcmp(s.color + (size_t)a * cb, img.color + i * cb, cb), "iter %d: colour of pixel %u",
                              iter, p);
                        CHECK(!memcmp(&s.depth[a], &img.depth[i], 4), "iter %d: depth of pixel %u", iter, p);
                    }
                    a += act;
                    if (harness_failures)
                        break;
                }
        CHECK(p == start + count, "iter %d: runs cover %u pixels of %u", iter, p - start, count);
        CHECK(a == s.active, "iter %d: %u active pixels in the runs, %u counted", iter, a, s.active);
        tsr_composite_sparse_free(&s);
        tsr_composite_image_free(&img);
        if (harness_failures)
            break;
    }
    return harness_failures;
}

static const uint8_t ZERO[4] = {0, 0, 0, 0};

static void expand_bg(const tsr_composite_sparse *s, tsr_composite_image *frame, const void *bg)
{
    tsr_error err;
    REQUIRE(tsr_composite_image_init(frame, s->window_width, s->window_height, 0, 0, s->window_width, s->window_height,
                                     s->color_format, s->depth_format, &err) == TSR_OK);
    /* pixels outside the image's range: a fixed fill, so frames compare */
    size_t all = (size_t)s->window_width * s->window_height;
    memset(frame->color, 0x5a, all * tsr_composite_color_bytes(s->color_format));
    for (size_t i = 0; i < all && s->depth_format; i++)
        frame->depth[i] = 2.0f;
    REQUIRE(tsr_composite_sparse_to_dense(s, bg, frame, &err) == TSR_OK, "%s", err.message);
}

static void expand(const tsr_composite_sparse *s, tsr_composite_image *frame) { expand_bg(s, frame, BG); }

static int test_sparse_merge_equals_dense(void)
{
    tsr_error err;
    for (int iter = 0; iter < 300; iter++) {
        int W = 1 + rnd() % 40, H = 1 + rnd() % 20;
        fill_kind kinds[] = {FILL_RANDOM, FILL_BACKGROUND, FILL_EQUAL, FILL_EXTREMES, FILL_SINGLE, FILL_NAN};
        tsr_composite_image a = {0}, b = {0}, da = {0}, db = {0}, dm = {0}, ds = {0};
        int x = rnd() % W, y = rnd() % H;
        make_image(&a, W, H, x, y, rnd() % (W - x + 1), rnd() % (H - y + 1), 0, kinds[rnd() % 6]);
        x = rnd() % W, y = rnd() % H;
        make_image(&b, W, H, x, y, rnd() % (W - x + 1), rnd() % (H - y + 1), 1, kinds[rnd() % 6]);
        int mode = iter % 4 == 3 ? TSR_COMPOSITE_ALPHA : TSR_COMPOSITE_DEPTH;
        uint32_t all = (uint32_t)W * H;
        tsr_composite_sparse sa = {0}, sb = {0}, sm = {0}, norm = {0};
        CHECK_OK(tsr_composite_sparse_compress(&a, mode, 0, all, &sa, &err), err);
        CHECK_OK(tsr_composite_sparse_compress(&b, mode, 0, all, &sb, &err), err);
        CHECK_OK(tsr_composite_sparse_merge(&sa, &sb, &sm, &err), err);
        /* dense: both as whole-window frames (inactive = background:
         * transparent black for over), the dense kernel, then inactive
         * pixels shown as background again */
        const uint8_t *bg = mode == TSR_COMPOSITE_ALPHA ? ZERO : BG;
        expand_bg(&sm, &ds, bg);
        expand_bg(&sa, &da, bg);
        expand_bg(&sb, &db, bg);
        CHECK_OK(tsr_composite_image_init(&dm, W, H, 0, 0, W, H, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, &err),
                 err);
        CHECK_OK(tsr_composite_image_merge(mode, &da, &db, &dm, &err), err);
        CHECK_OK(tsr_composite_sparse_compress(&dm, mode, 0, all, &norm, &err), err);
        tsr_composite_image dn = {0};
        expand_bg(&norm, &dn, bg);
        CHECK(!memcmp(dn.color, ds.color, all * 4), "sparse merge colour != dense merge (%dx%d, iter %d)", W, H, iter);
        if (mode == TSR_COMPOSITE_DEPTH)
            CHECK(!memcmp(dn.depth, ds.depth, all * 4), "sparse merge depth != dense merge (iter %d)", iter);
        CHECK(sm.active <= sa.active + sb.active, "merge grew the active pixels");
        tsr_composite_image *imgs[] = {&a, &b, &da, &db, &dm, &ds, &dn};
        for (size_t i = 0; i < sizeof imgs / sizeof *imgs; i++)
            tsr_composite_image_free(imgs[i]);
        tsr_composite_sparse *ss[] = {&sa, &sb, &sm, &norm};
        for (size_t i = 0; i < 4; i++)
            tsr_composite_sparse_free(ss[i]);
        if (harness_failures)
            break;
    }
    return harness_failures;
}

/* The dense-strip fold against the chain of merges it replaces, grouped
 * the same way (out from one piece, in front then behind): runs, header
 * and every byte equal. Pieces are cut from whole-window images at random
 * split lines (so runs end there), of every fill (all background, a single
 * pixel, equal depths, NaN), some with adversarial depths written into
 * their active pixels (NaN, infinities, 1.0, ties), as a message could
 * carry; one fold is reused across sizes, as an executor's is. */
static int test_sparse_fold_equals_merges(void)
{
    tsr_error err;
    tsr_composite_fold fold = {0}, dfold = {0};
    for (int iter = 0; iter < 400 && !harness_failures; iter++) {
        enum { MAXN = 7 };
        int W = 1 + rnd() % 60, H = 1 + rnd() % 12, n = 1 + rnd() % MAXN;
        uint32_t all = (uint32_t)W * H, start = rnd() % all, count = rnd() % (all - start + 1);
        int cf = iter % 5 == 4 ? TSR_COMPOSITE_RGBA32F : TSR_COMPOSITE_RGBA8;
        size_t cb = tsr_composite_color_bytes(cf);
        fill_kind kinds[] = {FILL_RANDOM, FILL_BACKGROUND, FILL_EQUAL, FILL_EXTREMES, FILL_SINGLE, FILL_NAN};
        tsr_composite_sparse p[MAXN] = {{0}}, whole = {0}, ref = {0}, tmp = {0}, got = {0}, runs = {0}, dgot = {0};
        /* the fold from `at` also begins from its read-back itself
         * (tsr_composite_fold_begin_dense) when that piece is as read back */
        int at = rnd() % n, dense_at = rnd() % 2;
        tsr_composite_image at_img = {0}, at_wide = {0};
        for (int r = 0; r < n; r++) {
            tsr_composite_image img = {0}, wide = {0};
            int x = rnd() % W, y = rnd() % H;
            make_image(&img, W, H, x, y, rnd() % (W - x + 1), rnd() % (H - y + 1), r, kinds[rnd() % 6]);
            const tsr_composite_image *src = &img;
            if (cf == TSR_COMPOSITE_RGBA32F) {
                CHECK_OK(tsr_composite_image_init(&wide, W, H, img.x, img.y, img.width, img.height, cf,
                                                  TSR_COMPOSITE_DEPTH32F, &err),
                         err);
                wide.rank = img.rank;
                wide.frame = img.frame;
                size_t np = (size_t)img.width * img.height;
                for (size_t i = 0; i < np; i++) {
                    float v[4];
                    for (int k = 0; k < 4; k++)
                        v[k] = (float)img.color[4 * i + k] / 255.0f;
                    memcpy(wide.color + 16 * i, v, sizeof v);
                    wide.depth[i] = img.depth[i];
                }
                src = &wide;
            }
            CHECK_OK(tsr_composite_sparse_compress(src, TSR_COMPOSITE_DEPTH, 0, all, &whole, &err), err);
            CHECK_OK(tsr_composite_sparse_split(&whole, start, count, &p[r], &err), err);
            if (r == at && dense_at) {
                CHECK_OK(tsr_composite_sparse_compress_runs(src, TSR_COMPOSITE_DEPTH, start, count, &runs, &err), err);
                at_img = img;
                at_wide = wide;
                continue;
            }
            if (rnd() % 3 == 0)
                for (uint32_t i = 0; i < p[r].active; i++)
                    if (rnd() % 2)
                        p[r].depth[i] = adversarial_depth();
            tsr_composite_image_free(&img);
            tsr_composite_image_free(&wide);
        }
        /* the reference: merges into fresh images, alternating buffers */
        tsr_composite_sparse *acc = &p[at], *bufs[2] = {&ref, &tmp};
        int b = 0;
        for (int i = at - 1; i >= 0; i--, b ^= 1) {
            CHECK_OK(tsr_composite_sparse_merge(&p[i], acc, bufs[b], &err), err);
            acc = bufs[b];
        }
        for (int i = at + 1; i < n; i++, b ^= 1) {
            CHECK_OK(tsr_composite_sparse_merge(acc, &p[i], bufs[b], &err), err);
            acc = bufs[b];
        }
        CHECK_OK(tsr_composite_fold_begin(&fold, &p[at], &err), err);
        for (int i = at - 1; i >= 0; i--)
            CHECK_OK(tsr_composite_fold_add(&fold, &p[i], 1, &err), err);
        for (int i = at + 1; i < n; i++)
            CHECK_OK(tsr_composite_fold_add(&fold, &p[i], 0, &err), err);
        CHECK_OK(tsr_composite_fold_end(&fold, &got, &err), err);
        if (dense_at) {
            CHECK_OK(
                tsr_composite_fold_begin_dense(&dfold, cf == TSR_COMPOSITE_RGBA32F ? &at_wide : &at_img, &runs, &err),
                err);
            for (int i = at - 1; i >= 0; i--)
                CHECK_OK(tsr_composite_fold_add(&dfold, &p[i], 1, &err), err);
            for (int i = at + 1; i < n; i++)
                CHECK_OK(tsr_composite_fold_add(&dfold, &p[i], 0, &err), err);
            CHECK_OK(tsr_composite_fold_end(&dfold, &dgot, &err), err);
            CHECK(dgot.nruns == got.nruns && dgot.active == got.active && dgot.rank == got.rank &&
                      dgot.rank_count == got.rank_count && dgot.frame == got.frame &&
                      (!got.nruns || !memcmp(dgot.runs, got.runs, (size_t)got.nruns * 8)) &&
                      (!got.active || (!memcmp(dgot.color, got.color, (size_t)got.active * cb) &&
                                       !memcmp(dgot.depth, got.depth, (size_t)got.active * 4))),
                  "a fold begun from the read-back differs from one begun from its sparse copy (iter %d)", iter);
            tsr_composite_image_free(&at_img);
            tsr_composite_image_free(&at_wide);
        }
        CHECK(got.start == acc->start && got.count == acc->count && got.rank == acc->rank &&
                  got.rank_count == acc->rank_count && got.frame == acc->frame && got.color_format == acc->color_format,
              "fold header differs (iter %d)", iter);
        CHECK(got.nruns == acc->nruns && got.active == acc->active, "fold runs %u/%u active %u/%u (iter %d)", got.nruns,
              acc->nruns, got.active, acc->active, iter);
        if (got.nruns == acc->nruns && got.active == acc->active) {
            CHECK(!got.nruns || !memcmp(got.runs, acc->runs, (size_t)got.nruns * 8), "fold runs differ (iter %d)",
                  iter);
            CHECK(!got.active || !memcmp(got.color, acc->color, (size_t)got.active * cb),
                  "fold colour differs (iter %d)", iter);
            CHECK(!got.active || !memcmp(got.depth, acc->depth, (size_t)got.active * 4), "fold depth differs (iter %d)",
                  iter);
        }
        /* a piece of another range is refused, as merge refuses it */
        if (count && start) {
            tsr_composite_sparse other = {0};
            CHECK_OK(tsr_composite_sparse_split(&whole, start - 1, count, &other, &err), err);
            CHECK(tsr_composite_fold_add(&fold, &other, 0, &err) == TSR_EINVAL, "fold took a piece of another range");
            tsr_composite_sparse_free(&other);
        }
        for (int r = 0; r < n; r++)
            tsr_composite_sparse_free(&p[r]);
        tsr_composite_sparse *ss[] = {&whole, &ref, &tmp, &got, &runs, &dgot};
        for (size_t i = 0; i < sizeof ss / sizeof *ss; i++)
            tsr_composite_sparse_free(ss[i]);
    }
    tsr_composite_fold_free(&fold);
    tsr_composite_fold_free(&dfold);
    return harness_failures;
}

static int test_split_at_run_edges(void)
{
    tsr_error err;
    for (int iter = 0; iter < 200; iter++) {
        int W = 1 + rnd() % 50, H = 1 + rnd() % 10;
        tsr_composite_image a = {0}, whole = {0}, parts = {0};
        make_image(&a, W, H, 0, 0, W, H, 0, iter % 2 ? FILL_RANDOM : FILL_SINGLE);
        uint32_t all = (uint32_t)W * H;
        tsr_composite_sparse s = {0}, p = {0}, v = {0};
        CHECK_OK(tsr_composite_sparse_compress(&a, TSR_COMPOSITE_DEPTH, 0, all, &s, &err), err);
        expand(&s, &whole);
        CHECK_OK(tsr_composite_image_init(&parts, W, H, 0, 0, W, H, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, &err),
                 err);
        memset(parts.color, 0xee, all * 4);
        /* cut at every run edge (inactive/active boundary) and at random */
        uint32_t cuts[1024], nc = 0, pos = 0;
        cuts[nc++] = 0;
        for (uint32_t r = 0; r < s.nruns && nc < 1000; r++) {
            pos += s.runs[2 * r];
            cuts[nc++] = pos;
            pos += s.runs[2 * r + 1];
            cuts[nc++] = pos;
        }
        cuts[nc++] = all;
        uint32_t prev = 0, active = 0;
        for (uint32_t c = 1; c < nc; c++) {
            uint32_t at = cuts[c] < prev ? prev : cuts[c];
            CHECK_OK(tsr_composite_sparse_split(&s, prev, at - prev, &p, &err), err);
            CHECK_OK(tsr_composite_sparse_view(&s, prev, at - prev, &v, &err), err);
            CHECK(v.active == p.active && v.nruns == p.nruns &&
                      (!p.nruns || !memcmp(v.runs, p.runs, 8 * (size_t)p.nruns)) &&
                      (!p.active || (!memcmp(v.color, p.color, 4 * (size_t)p.active) &&
                                     !memcmp(v.depth, p.depth, 4 * (size_t)p.active))),
                  "view of %u+%u differs from the split", prev, at - prev);
            CHECK_OK(tsr_composite_sparse_to_dense(&p, BG, &parts, &err), err);
            active += p.active;
            prev = at;
        }
        CHECK(prev == all && active == s.active, "pieces hold %u of %u active pixels", active, s.active);
        CHECK(!memcmp(parts.color, whole.color, all * 4), "pieces cut at run edges do not reassemble (%dx%d)", W, H);
        tsr_composite_image_free(&a);
        tsr_composite_image_free(&whole);
        tsr_composite_image_free(&parts);
        tsr_composite_sparse_free(&s);
        tsr_composite_sparse_free(&p);
        tsr_composite_sparse_free(&v);
    }
    return harness_failures;
}

/* ---- codecs ----------------------------------------------------------------- */

static const char *CODECS[] = {"none", "rle", "erle", "yuv420", "depth16", "depth24", "erle+depth16", "yuv420+depth24"};

static double psnr8(const uint8_t *a, const uint8_t *b, size_t n)
{
    double se = 0;
    for (size_t i = 0; i < n; i++)
        se += ((double)a[i] - b[i]) * ((double)a[i] - b[i]);
    return se == 0 ? INFINITY : 10 * log10(255.0 * 255.0 * n / se);
}

/* A smooth scene: a shaded disc per peer over background. */
static void make_smooth(tsr_composite_image *img, int W, int H, int rank)
{
    tsr_error err;
    REQUIRE(tsr_composite_image_init(img, W, H, 0, 0, W, H, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, &err) ==
            TSR_OK);
    img->rank = rank;
    img->frame = 3;
    double cx = W * (0.3 + 0.1 * rank), cy = H * 0.5, rad = W * 0.25;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            double dx = (x - cx) / rad, dy = (y - cy) / rad, r2 = dx * dx + dy * dy;
            uint8_t *c = img->color + 4 * i;
            if (r2 < 1) {
                double z = sqrt(1 - r2);
                c[0] = (uint8_t)(40 + 200 * z);
                c[1] = (uint8_t)(30 + 150 * z * (x % 7 == 0 ? 0.9 : 1));
                c[2] = (uint8_t)(100 + 50 * dx * dx);
                c[3] = 255;
                img->depth[i] = (float)(0.5 - 0.3 * z);
            } else {
                memcpy(c, BG, 4);
                img->depth[i] = 1.0f;
            }
        }
}

static int test_codecs_roundtrip(void)
{
    tsr_error err;
    int sizes[][2] = {{1, 1}, {997, 1}, {61, 37}, {256, 192}};
    for (size_t si = 0; si < sizeof sizes / sizeof *sizes; si++) {
        int W = sizes[si][0], H = sizes[si][1];
        tsr_composite_image img = {0}, a = {0}, b = {0};
        make_smooth(&img, W, H, 0);
        uint32_t all = (uint32_t)W * H;
        tsr_composite_sparse s = {0}, d = {0}, piece = {0};
        CHECK_OK(tsr_composite_sparse_compress(&img, TSR_COMPOSITE_DEPTH, 0, all, &s, &err), err);
        /* also a piece that starts and ends mid-row */
        uint32_t ps = all / 3, pc = all / 2;
        CHECK_OK(tsr_composite_sparse_split(&s, ps, pc, &piece, &err), err);
        for (size_t ci = 0; ci < sizeof CODECS / sizeof *CODECS; ci++) {
            tsr_composite_codec c;
            CHECK_OK(tsr_composite_codec_parse(CODECS[ci], &c, &err), err);
            char name[64];
            CHECK_STR(tsr_composite_codec_name(c, name, sizeof name), CODECS[ci]);
            for (int which = 0; which < 2; which++) {
                tsr_composite_sparse *src = which ? &piece : &s;
                size_t cap = tsr_composite_message_max_size(src->count, src->color_format, src->depth_format, c), len;
                uint8_t *buf = malloc(cap);
                CHECK_OK(tsr_composite_message_encode(src, c, buf, cap, &len, &err), err);
                CHECK(len <= cap, "%s: %zu bytes over the bound %zu", CODECS[ci], len, cap);
                CHECK_OK(tsr_composite_message_decode(buf, len, NULL, &d, &err), err);
                CHECK(d.start == src->start && d.count == src->count && d.active == src->active, "%s: geometry changed",
                      CODECS[ci]);
                tsr_composite_image_free(&a);
                tsr_composite_image_free(&b);
                expand(src, &a);
                expand(&d, &b);
                if (tsr_composite_codec_lossless(c)) {
                    CHECK(!memcmp(a.color, b.color, all * 4) && !memcmp(a.depth, b.depth, all * 4),
                          "%s (%dx%d): lossless round trip differs", CODECS[ci], W, H);
                } else {
                    double p = psnr8(a.color, b.color, all * 4), maxdz = 0;
                    for (uint32_t i = 0; i < all; i++)
                        maxdz = fmax(maxdz, fabs((double)a.depth[i] - b.depth[i]));
                    if (!which && si == 3)
                        printf("%s %dx%d: colour PSNR %.1f dB, max depth error %.2g, %zu bytes\n", CODECS[ci], W, H, p,
                               maxdz, len);
                    CHECK(p > 30.0, "%s: PSNR %.1f dB", CODECS[ci], p);
                    CHECK(maxdz <= 1.0 / 65536, "%s: depth error %g", CODECS[ci], maxdz);
                }
                if (!which && si == 3 && tsr_composite_codec_lossless(c))
                    printf("%s %dx%d: lossless, %zu bytes\n", CODECS[ci], W, H, len);
                free(buf);
            }
        }
        tsr_composite_codec def;
        CHECK_OK(tsr_composite_codec_parse("rle", &def, &err), err);
        CHECK(tsr_composite_codec_lossless(def), "the default codec is lossy");
        CHECK(tsr_composite_codec_parse("jpeg", &def, &err) == TSR_EINVAL);
        CHECK_CONTAINS(err.message, "unknown part 'jpeg'");
        CHECK(tsr_composite_codec_parse("none+erle", &def, &err) == TSR_EINVAL);
        tsr_composite_image_free(&img);
        tsr_composite_image_free(&a);
        tsr_composite_image_free(&b);
        tsr_composite_sparse_free(&s);
        tsr_composite_sparse_free(&d);
        tsr_composite_sparse_free(&piece);
    }
    return harness_failures;
}

static int test_codec_worst_case_size(void)
{
    tsr_error err;
    /* alternating active/inactive (the most runs) with noise (RLE expands
     * every plane), and all active noise; odd and even counts */
    for (int pattern = 0; pattern < 3; pattern++)
        for (int W = 1; W <= 130; W += 43) {
            int H = 3;
            tsr_composite_image img = {0};
            REQUIRE(tsr_composite_image_init(&img, W, H, 0, 0, W, H, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F,
                                             &err) == TSR_OK);
            for (int i = 0; i < W * H; i++) {
                for (int k = 0; k < 4; k++)
                    img.color[4 * i + k] = (uint8_t)rnd();
                img.depth[i] = pattern == 2 || i % 2 == pattern ? (float)(rnd() % 1000) / 1001.0f : 1.0f;
            }
            tsr_composite_sparse s = {0};
            CHECK_OK(tsr_composite_sparse_compress(&img, TSR_COMPOSITE_DEPTH, 0, (uint32_t)(W * H), &s, &err), err);
            for (size_t ci = 0; ci < sizeof CODECS / sizeof *CODECS; ci++) {
                tsr_composite_codec c;
                tsr_composite_codec_parse(CODECS[ci], &c, &err);
                size_t cap = tsr_composite_message_max_size(s.count, s.color_format, s.depth_format, c), len = 0;
                uint8_t *buf = malloc(cap);
                CHECK_OK(tsr_composite_message_encode(&s, c, buf, cap, &len, &err), err);
                CHECK(len <= cap, "%s: %zu bytes over the advertised %zu (pattern %d, %d px)", CODECS[ci], len, cap,
                      pattern, W * H);
                size_t bound = tsr_composite_message_bound(&s, c);
                CHECK(len <= bound && bound <= cap, "%s: %zu bytes, the image's bound %zu, the worst case %zu",
                      CODECS[ci], len, bound, cap);
                CHECK(tsr_composite_message_encode(&s, c, buf, bound - 1, &len, &err) == TSR_EINVAL,
                      "a buffer below the image's bound is accepted");
                free(buf);
            }
            tsr_composite_sparse_free(&s);
            tsr_composite_image_free(&img);
        }
    return harness_failures;
}

static int test_message_decoder_rejects_bad_input(void)
{
    tsr_error err;
    tsr_composite_image img = {0};
    make_image(&img, 16, 4, 0, 0, 16, 4, 2, FILL_RANDOM);
    tsr_composite_sparse s = {0}, d = {0};
    CHECK_OK(tsr_composite_sparse_compress(&img, TSR_COMPOSITE_DEPTH, 0, 64, &s, &err), err);
    tsr_composite_codec c;
    tsr_composite_codec_parse("erle", &c, &err);
    size_t cap = tsr_composite_message_max_size(64, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, c), len;
    uint8_t *buf = malloc(cap), *bad = malloc(cap);
    CHECK_OK(tsr_composite_message_encode(&s, c, buf, cap, &len, &err), err);
    struct {
        size_t off;
        uint32_t value;
        const char *want;
    } cases[] = {
        {0, 0x12345678, "bad magic"}, {12, 0, "impossible window"},      {12, 40000, "impossible window"},
        {20, 60, "outside the"},      {24, 0xffffffff, "outside the"},   {36, 65, "cannot fit"},
        {44, 5, "payload of"},        {48, 1000, "overflows the image"}, {52, 0, "runs cover"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        memcpy(bad, buf, len);
        uint32_t v = cases[i].value;
        for (int b = 0; b < 4; b++)
            bad[cases[i].off + b] = (uint8_t)(v >> (8 * b));
        CHECK(tsr_composite_message_decode(bad, len, NULL, &d, &err) == TSR_EPROTO, "case %zu accepted", i);
        CHECK_CONTAINS(err.message, cases[i].want);
    }
    CHECK(tsr_composite_message_decode(buf, len - 1, NULL, &d, &err) == TSR_EPROTO);
    CHECK(tsr_composite_message_decode(buf, 10, NULL, &d, &err) == TSR_EPROTO);
    CHECK_CONTAINS(err.message, "shorter than its");
    tsr_composite_message_header e;
    tsr_composite_message_expect_any(&e);
    e.frame = 8;
    CHECK(tsr_composite_message_decode(buf, len, &e, &d, &err) == TSR_EPROTO);
    CHECK_CONTAINS(err.message, "frame is 7, expected 8");
    tsr_composite_message_expect_any(&e);
    e.rank = 2;
    e.window_width = 16;
    CHECK_OK(tsr_composite_message_decode(buf, len, &e, &d, &err), err);
    /* random corruption of the payload: an error or a valid image, never a crash */
    for (int iter = 0; iter < 3000; iter++) {
        memcpy(bad, buf, len);
        int flips = 1 + rnd() % 4;
        for (int f = 0; f < flips; f++)
            bad[48 + rnd() % (len - 48)] ^= (uint8_t)(1u << (rnd() % 8));
        size_t cut = iter % 7 == 0 ? rnd() % len : len;
        if (cut != len)
            bad[44] = (uint8_t)(cut - 48);
        if (tsr_composite_message_decode(bad, cut, NULL, &d, &err) == TSR_OK)
            CHECK(d.active <= d.count);
    }
    free(buf);
    free(bad);
    tsr_composite_sparse_free(&s);
    tsr_composite_sparse_free(&d);
    tsr_composite_image_free(&img);
    return harness_failures;
}

/* ---- straight from the read-back, straight out of the message ------------------ */

/* encode_dense (the peer's sends, no sparse copy) gives the very bytes of
 * compress + encode, for every codec, region and range shape: whole
 * window, a box inside it, a full-width band, an empty region, ranges
 * starting and ending mid-row, all background, a single pixel, NaN. */
/* Small windows, then one whose messages pass the streaming threshold
 * (CI_STREAM_MIN) gathered from rows far below it (a box narrower than
 * the window: one copy per row and run). */
static int test_encode_dense_equals_compress_encode(void)
{
    tsr_error err;
    tsr_composite_sparse sp = {0}, scratch = {0};
    int compared = 0;
    for (int geo = 0; geo < 2; geo++) {
        const int W = geo ? 509 : 61, H = geo ? 203 : 37;
        const int small_boxes[][4] = {{0, 0, 61, 37}, {7, 5, 30, 20}, {0, 9, 61, 11}, {0, 0, 0, 0}, {60, 36, 1, 1}};
        const int large_boxes[][4] = {
            {0, 0, 509, 203}, {13, 7, 301, 190}, {0, 50, 509, 100}, {1, 1, 507, 201}, {3, 2, 1, 1}};
        const int(*boxes)[4] = geo ? large_boxes : small_boxes;
        const fill_kind fills[] = {FILL_RANDOM, FILL_BACKGROUND, FILL_SINGLE, FILL_NAN, FILL_OPAQUE};
        uint32_t all = (uint32_t)W * H;
        const uint32_t ranges[][2] = {{0, all}, {all / 3, all / 2}, {100, 1}, {all - 5, 5}, {0, 0}};
        for (size_t bi = 0; bi < 5; bi++)
            for (size_t fi = 0; fi < sizeof fills / sizeof *fills; fi++) {
                tsr_composite_image img = {0};
                make_image(&img, W, H, boxes[bi][0], boxes[bi][1], boxes[bi][2], boxes[bi][3], 3, fills[fi]);
                for (int mode = TSR_COMPOSITE_DEPTH; mode <= TSR_COMPOSITE_ALPHA; mode++)
                    for (size_t ri = 0; ri < sizeof ranges / sizeof *ranges; ri++)
                        for (size_t ci = 0; ci < sizeof CODECS / sizeof *CODECS; ci++) {
                            tsr_composite_codec c;
                            CHECK_OK(tsr_composite_codec_parse(CODECS[ci], &c, &err), err);
                            uint32_t st = ranges[ri][0], n = ranges[ri][1];
                            size_t cap = tsr_composite_message_max_size(n, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F,
                                                                        c),
                                   la = 0, lb = 0;
                            uint8_t *a = malloc(cap), *b = malloc(cap);
                            CHECK_OK(tsr_composite_sparse_compress(&img, mode, st, n, &sp, &err), err);
                            CHECK_OK(tsr_composite_message_encode(&sp, c, a, cap, &la, &err), err);
                            CHECK_OK(tsr_composite_sparse_compress_runs(&img, mode, st, n, &scratch, &err), err);
                            size_t bound = tsr_composite_message_bound(&scratch, c);
                            CHECK(bound <= cap && bound == tsr_composite_message_bound(&sp, c),
                                  "%s: the image's bound %zu is over the worst case %zu or differs from its copy's",
                                  CODECS[ci], bound, cap);
                            CHECK_OK(tsr_composite_message_encode_dense(&img, &scratch, c, b, bound, &lb, &err), err);
                            CHECK(la <= bound, "%s: %zu bytes over the image's bound %zu", CODECS[ci], la, bound);
                            CHECK(la == lb && !memcmp(a, b, la),
                                  "%s, box %zu, fill %zu, mode %d, range %u+%u: %zu bytes vs %zu, or they differ",
                                  CODECS[ci], bi, fi, mode, st, n, la, lb);
                            compared++;
                            free(a);
                            free(b);
                        }
                tsr_composite_image_free(&img);
            }
    }
    printf("%d messages encoded from the read-back equal compress + encode byte for byte\n", compared);
    tsr_composite_sparse_free(&sp);
    tsr_composite_sparse_free(&scratch);
    return harness_failures;
}

/* The zero-copy view of a received message equals its decoded copy
 * (same header, runs, pixels), points into the message for "rle", and
 * rejects every corrupted message with decode's code and words. */
static int test_message_view_equals_decode(void)
{
    tsr_error err, err2;
    tsr_composite_image img = {0};
    make_image(&img, 64, 16, 3, 2, 50, 12, 2, FILL_RANDOM);
    tsr_composite_sparse s = {0}, d = {0}, v = {0};
    CHECK_OK(tsr_composite_sparse_compress(&img, TSR_COMPOSITE_DEPTH, 64 * 3 + 5, 64 * 9, &s, &err), err);
    for (size_t ci = 0; ci < sizeof CODECS / sizeof *CODECS; ci++) {
        tsr_composite_codec c;
        CHECK_OK(tsr_composite_codec_parse(CODECS[ci], &c, &err), err);
        size_t cap = tsr_composite_message_max_size(s.count, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, c), len;
        uint8_t *buf = malloc(cap), *bad = malloc(cap);
        CHECK_OK(tsr_composite_message_encode(&s, c, buf, cap, &len, &err), err);
        CHECK_OK(tsr_composite_message_decode(buf, len, NULL, &d, &err), err);
        CHECK_OK(tsr_composite_message_view(buf, len, NULL, &v, &err), err);
        CHECK(d.start == v.start && d.count == v.count && d.active == v.active && d.nruns == v.nruns &&
                  d.rank == v.rank && d.frame == v.frame,
              "%s: the view's header differs from the copy's", CODECS[ci]);
        CHECK(!memcmp(d.runs, v.runs, 8 * (size_t)d.nruns) && !memcmp(d.color, v.color, 4 * (size_t)d.active) &&
                  !memcmp(d.depth, v.depth, 4 * (size_t)d.active),
              "%s: the view's runs or pixels differ from the copy's", CODECS[ci]);
        int inside = v.color >= buf && v.color < buf + len;
        CHECK(inside == !strcmp(CODECS[ci], "rle"), "%s: the view's colour %s the message", CODECS[ci],
              inside ? "points into" : "does not point into");
        for (int iter = 0; iter < 1500; iter++) {
            memcpy(bad, buf, len);
            int flips = 1 + rnd() % 4;
            for (int f = 0; f < flips; f++)
                bad[rnd() % len] ^= (uint8_t)(1u << (rnd() % 8));
            size_t cut = iter % 5 == 0 ? rnd() % (len + 1) : len;
            int ra = tsr_composite_message_decode(bad, cut, NULL, &d, &err);
            int rb = tsr_composite_message_view(bad, cut, NULL, &v, &err2);
            CHECK(ra == rb, "%s, corruption %d: decode says %d, view %d (%s)", CODECS[ci], iter, ra, rb,
                  rb ? err2.message : err.message);
            if (ra && rb)
                CHECK(!strcmp(err.message, err2.message), "%s: decode says '%s', view '%s'", CODECS[ci], err.message,
                      err2.message);
            if (!ra && !rb)
                CHECK(d.active == v.active && !memcmp(d.color, v.color, 4 * (size_t)d.active),
                      "%s: a corrupted message decodes and views differently", CODECS[ci]);
        }
        free(buf);
        free(bad);
    }
    printf("view = decode for %zu codecs, 1500 corrupted messages each (same verdict, same words)\n",
           sizeof CODECS / sizeof *CODECS);
    tsr_composite_sparse_free(&s);
    tsr_composite_sparse_free(&d);
    tsr_composite_sparse_free(&v);
    tsr_composite_image_free(&img);
    return harness_failures;
}

/* ---- schedules ------------------------------------------------------------------ */

typedef struct {
    int kind, k;
} strat;
static const strat STRATS[] = {{TSR_COMPOSITE_BSWAP, 0},  {TSR_COMPOSITE_DIRECT, 0}, {TSR_COMPOSITE_RADIXK, 2},
                               {TSR_COMPOSITE_RADIXK, 3}, {TSR_COMPOSITE_RADIXK, 4}, {TSR_COMPOSITE_RADIXK, 8},
                               {TSR_COMPOSITE_GATHER, 0}, {TSR_COMPOSITE_AUTO, 0}};
#define NSTRATS (sizeof STRATS / sizeof *STRATS)

static int test_schedules_hold_invariants(void)
{
    tsr_error err;
    int wins[][2] = {{1, 1}, {7, 5}, {997, 1}, {509, 503}};
    for (size_t w = 0; w < 4; w++)
        for (size_t si = 0; si < NSTRATS; si++)
            for (int n = 1; n <= 64; n++) {
                tsr_composite_schedule s;
                CHECK_OK(tsr_composite_plan(STRATS[si].kind, n, wins[w][0], wins[w][1], STRATS[si].k, NULL, &s, &err),
                         err);
                if (tsr_composite_schedule_check(&s, &err) != TSR_OK) {
                    CHECK(0, "%s n=%d %dx%d: %s", s.name, n, wins[w][0], wins[w][1], err.message);
                    tsr_composite_schedule_free(&s);
                    return harness_failures;
                }
                CHECK(s.reason[0] != 0);
                tsr_composite_schedule_free(&s);
            }
    int kind, k;
    CHECK_OK(tsr_composite_kind_parse("radixk-5", &kind, &k, &err), err);
    CHECK(kind == TSR_COMPOSITE_RADIXK && k == 5);
    CHECK(tsr_composite_kind_parse("tree", &kind, &k, &err) == TSR_EINVAL);
    CHECK_CONTAINS(err.message, "unknown (valid: auto");
    tsr_composite_schedule s;
    CHECK(tsr_composite_plan(TSR_COMPOSITE_BSWAP, 65, 4, 4, 0, NULL, &s, &err) == TSR_EINVAL);
    CHECK_OK(tsr_composite_plan(TSR_COMPOSITE_AUTO, 16, 1920, 1080, 0, NULL, &s, &err), err);
    printf("auto 16 x 1920x1080: %s (%s)\n", s.name, s.reason);
    tsr_composite_schedule_free(&s);
    return harness_failures;
}

/* A message's ring slot: its largest encoding rounded to 64 bytes. */
static uint64_t slot_of(uint32_t count, tsr_composite_codec c)
{
    return tsr_composite_message_max_size(count, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, c);
}

/* tsr_composite_schedule_link_bytes, which sizes binaryswap's shared-memory
 * rings: every pair's messages of a frame fit (so no sender waits for its
 * partner within a frame), and no more than that, so a frame's messages
 * cannot be written behind the last frame's on fresh pages: direct send
 * of 8 peers at 1920x1080 gets one piece (1/8 frame), where the rings
 * used to take four whole frames (66 MB). */
static int test_link_bytes_hold_one_frame(void)
{
    tsr_error err;
    tsr_composite_codec rle;
    CHECK_OK(tsr_composite_codec_parse("rle", &rle, &err), err);
    int wins[][2] = {{7, 5}, {509, 503}};
    for (size_t w = 0; w < 2; w++)
        for (size_t si = 0; si < NSTRATS; si++)
            for (int n = 1; n <= 64; n++) {
                tsr_composite_schedule s;
                CHECK_OK(tsr_composite_plan(STRATS[si].kind, n, wins[w][0], wins[w][1], STRATS[si].k, NULL, &s, &err),
                         err);
                uint64_t link = tsr_composite_schedule_link_bytes(&s, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, rle),
                         most = 0;
                int display = tsr_composite_schedule_display_composites(&s);
                for (int p = 0; p < n; p++) {
                    uint64_t to[TSR_COMPOSITE_MAX_PEERS + 1] = {0};
                    const tsr_composite_rank *R = &s.ranks[p];
                    for (int i = 0; i < R->nrounds; i++)
                        for (int j = 0; j < R->rounds[i].nsend; j++)
                            to[R->rounds[i].send[j].peer] += slot_of(R->rounds[i].send[j].region.count, rle);
                    uint64_t fin = display && R->final.count ? slot_of(R->final.count, rle) : 0;
                    for (int q = 0; q < n; q++)
                        if (to[q] + fin > most)
                            most = to[q] + fin;
                }
                CHECK(link == most, "%s n=%d %dx%d: link bytes %llu, the busiest pair sends up to %llu", s.name, n,
                      wins[w][0], wins[w][1], (unsigned long long)link, (unsigned long long)most);
                tsr_composite_schedule_free(&s);
            }
    tsr_composite_schedule s;
    CHECK_OK(tsr_composite_plan(TSR_COMPOSITE_DIRECT, 8, 1920, 1080, 0, NULL, &s, &err), err);
    uint64_t link = tsr_composite_schedule_link_bytes(&s, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, rle);
    uint64_t piece = slot_of(1920 * 1080 / 8, rle), smallest = UINT64_MAX;
    /* a full layer's pieces (every pixel active), as bench/binaryswap.sh sends */
    tsr_composite_image full = {0};
    CHECK_OK(tsr_composite_image_init(&full, 1920, 1080, 0, 0, 1920, 1080, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F,
                                      &err),
             err);
    for (size_t i = 0; i < (size_t)1920 * 1080; i++)
        full.depth[i] = 0.5f;
    tsr_composite_sparse sp = {0};
    for (int p = 0; p < 8; p++)
        for (int j = 0; j < s.ranks[p].rounds[0].nsend; j++) {
            tsr_composite_region r = s.ranks[p].rounds[0].send[j].region;
            CHECK_OK(tsr_composite_sparse_compress(&full, TSR_COMPOSITE_DEPTH, r.start, r.count, &sp, &err), err);
            uint64_t b = tsr_composite_message_bound(&sp, rle);
            if (b < smallest)
                smallest = b;
        }
    tsr_composite_sparse_free(&sp);
    tsr_composite_image_free(&full);
    printf("direct 8 x 1920x1080: link %llu bytes, one piece at its largest %llu, a full piece %llu\n",
           (unsigned long long)link, (unsigned long long)piece, (unsigned long long)smallest);
    CHECK(link == piece, "direct 8 x 1920x1080: link bytes %llu, not one piece (%llu)", (unsigned long long)link,
          (unsigned long long)piece);
    CHECK(link < 2 * smallest, "direct 8 x 1920x1080: %llu link bytes hold two full pieces of %llu",
          (unsigned long long)link, (unsigned long long)smallest);
    tsr_composite_schedule_free(&s);
    CHECK_OK(tsr_composite_plan(TSR_COMPOSITE_GATHER, 4, 640, 480, 0, NULL, &s, &err), err);
    CHECK(tsr_composite_schedule_link_bytes(&s, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, rle) ==
              slot_of(640 * 480, rle),
          "gather: a whole frame to the display");
    tsr_composite_schedule_free(&s);
    return harness_failures;
}

typedef struct peer_job {
    const tsr_composite_schedule *s;
    tsr_composite_codec codec;
    tsr_composite_image *img;
    int rank, mode, rc;
    tsr_composite_transport t;
    tsr_error err;
} peer_job;

static void *peer_main(void *arg)
{
    peer_job *j = arg;
    tsr_composite_executor *ex = tsr_composite_executor_new(j->s, j->codec, &j->err);
    j->rc = ex ? tsr_composite_run_peer(ex, j->rank, j->img, j->mode, &j->t, &j->err) : TSR_ENOMEM;
    tsr_composite_executor_free(ex);
    return NULL;
}

/* Runs a whole group in this process (a thread per peer, the display on
 * this thread, memnet between them); the display's frame goes to out. */
static int run_group(const tsr_composite_schedule *s, tsr_composite_image *imgs, int mode, const char *codec_name,
                     tsr_composite_image *out, char *why, size_t why_size)
{
    int n = s->nranks;
    tsr_error err;
    tsr_composite_memnet *net = tsr_composite_memnet_new(n + 1, 60000, &err);
    REQUIRE(net != NULL, "%s", err.message);
    tsr_composite_codec codec;
    tsr_composite_codec_parse(codec_name, &codec, &err);
    peer_job *jobs = calloc((size_t)n, sizeof *jobs);
    pthread_t *th = calloc((size_t)n, sizeof *th);
    for (int r = 0; r < n; r++) {
        jobs[r] = (peer_job){.s = s, .codec = codec, .img = &imgs[r], .rank = r, .mode = mode};
        tsr_composite_memnet_transport(net, r, &jobs[r].t);
        pthread_create(&th[r], NULL, peer_main, &jobs[r]);
    }
    tsr_composite_transport t;
    tsr_composite_memnet_transport(net, TSR_COMPOSITE_DISPLAY(n), &t);
    tsr_composite_executor *ex = tsr_composite_executor_new(s, codec, &err);
    int rc = tsr_composite_run_display(ex, imgs[0].frame, mode, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, BG, out,
                                       &t, &err);
    if (rc)
        snprintf(why, why_size, "display: %s", err.message);
    tsr_composite_executor_free(ex);
    for (int r = 0; r < n; r++) {
        pthread_join(th[r], NULL);
        if (jobs[r].rc && !rc) {
            rc = jobs[r].rc;
            snprintf(why, why_size, "rank %d: %s", r, jobs[r].err.message);
        }
    }
    int from, to;
    if (tsr_composite_memnet_drain(net, &from, &to) && !rc) {
        rc = TSR_EPROTO;
        snprintf(why, why_size, "a message from %d to %d was never received", from, to);
    }
    tsr_composite_memnet_free(net);
    free(jobs);
    free(th);
    return rc;
}

typedef struct frames_job {
    const tsr_composite_schedule *s;
    tsr_composite_codec codec;
    tsr_composite_image *img;
    int rank, frames, rc;
    size_t pixel_bytes;          /* the executor's planes after the last frame */
    const void *fill;            /* tsr_composite_run_peer_rounds' fill background, or NULL */
    tsr_composite_image *placed; /* the last frame's final piece is drawn into it (to_dense over BG), or NULL */
    int filled;                  /* that piece came back filled: one active run */
    tsr_composite_transport t;
    tsr_error err;
} frames_job;

static void *frames_main(void *arg)
{
    frames_job *j = arg;
    tsr_composite_executor *ex = tsr_composite_executor_new(j->s, j->codec, &j->err);
    j->rc = ex ? TSR_OK : TSR_ENOMEM;
    for (int f = 0; f < j->frames && !j->rc; f++) {
        const tsr_composite_sparse *final = NULL;
        j->img->frame = (uint32_t)f;
        j->rc =
            tsr_composite_run_peer_rounds(ex, j->rank, j->img, TSR_COMPOSITE_DEPTH, &j->t, j->fill, &final, &j->err);
        if (!j->rc && final && f == j->frames - 1 && j->placed) {
            j->filled = final->active == final->count && final->nruns == 1;
            j->rc = tsr_composite_sparse_to_dense(final, BG, j->placed, &j->err);
        }
    }
    j->pixel_bytes = ex ? tsr_composite_executor_pixel_bytes(ex) : 0;
    tsr_composite_executor_free(ex);
    return NULL;
}

/* A peer's executor keeps one piece of pixels from frame to frame, not
 * three (bench/README.md, "Peer memory"): with full layers (every pixel
 * active) the kept part is a view of the read-back and the merges write
 * into the executor's one image. Direct send, 8 peers, 3 frames. */
static int test_executor_keeps_one_piece(void)
{
    enum { N = 8, W = 64, H = 48 };
    tsr_error err;
    tsr_composite_schedule s;
    CHECK_OK(tsr_composite_plan(TSR_COMPOSITE_DIRECT, N, W, H, 0, NULL, &s, &err), err);
    tsr_composite_codec rle;
    CHECK_OK(tsr_composite_codec_parse("rle", &rle, &err), err);
    tsr_composite_memnet *net = tsr_composite_memnet_new(N + 1, 60000, &err);
    CHECK(net != NULL, "%s", err.message);
    tsr_composite_image imgs[N] = {{0}};
    frames_job jobs[N];
    pthread_t th[N];
    for (int r = 0; r < N; r++) {
        CHECK_OK(
            tsr_composite_image_init(&imgs[r], W, H, 0, 0, W, H, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, &err),
            err);
        imgs[r].rank = r;
        for (int p = 0; p < W * H; p++) {
            memset(imgs[r].color + 4 * p, 16 * r + 1, 4);
            imgs[r].depth[p] = (float)((rnd() % 1000) + 1) / 1002.0f;
        }
        jobs[r] = (frames_job){.s = &s, .codec = rle, .img = &imgs[r], .rank = r, .frames = 3};
        tsr_composite_memnet_transport(net, r, &jobs[r].t);
        pthread_create(&th[r], NULL, frames_main, &jobs[r]);
    }
    size_t most = 0;
    for (int r = 0; r < N; r++) {
        pthread_join(th[r], NULL);
        CHECK(jobs[r].rc == TSR_OK, "rank %d: %s", r, jobs[r].err.message);
        if (jobs[r].pixel_bytes > most)
            most = jobs[r].pixel_bytes;
    }
    size_t piece = (size_t)s.ranks[0].final.count * 8;
    printf("direct %d x %dx%d, 3 frames: the largest executor owns %zu bytes of planes, one piece is %zu\n", N, W, H,
           most, piece);
    CHECK(most <= piece + piece / 4, "an executor keeps %zu bytes of planes, more than one piece (%zu)", most, piece);
    int from, to;
    CHECK(tsr_composite_memnet_drain(net, &from, &to) == 0, "a message from %d to %d was never received", from, to);
    tsr_composite_memnet_free(net);
    for (int r = 0; r < N; r++)
        tsr_composite_image_free(&imgs[r]);
    tsr_composite_schedule_free(&s);
    return harness_failures;
}

/* One group of frames_job peers (memnet, a thread each); the last
 * frame's final pieces drawn into `placed`. Returns how many came back
 * without a background pixel (filled, or covered). */
static int run_frames(const tsr_composite_schedule *s, tsr_composite_image *imgs, const void *fill,
                      tsr_composite_image *placed)
{
    int n = s->nranks, filled = 0;
    tsr_error err;
    tsr_composite_codec rle;
    REQUIRE(tsr_composite_codec_parse("rle", &rle, &err) == TSR_OK, "%s", err.message);
    tsr_composite_memnet *net = tsr_composite_memnet_new(n + 1, 60000, &err);
    REQUIRE(net != NULL, "%s", err.message);
    frames_job jobs[TSR_COMPOSITE_MAX_PEERS];
    pthread_t th[TSR_COMPOSITE_MAX_PEERS];
    for (int r = 0; r < n; r++) {
        jobs[r] =
            (frames_job){.s = s, .codec = rle, .img = &imgs[r], .rank = r, .frames = 2, .fill = fill, .placed = placed};
        tsr_composite_memnet_transport(net, r, &jobs[r].t);
        pthread_create(&th[r], NULL, frames_main, &jobs[r]);
    }
    for (int r = 0; r < n; r++) {
        pthread_join(th[r], NULL);
        CHECK(jobs[r].rc == TSR_OK, "rank %d: %s", r, jobs[r].err.message);
        filled += jobs[r].filled;
    }
    int from, to;
    CHECK(tsr_composite_memnet_drain(net, &from, &to) == 0, "a message from %d to %d was never received", from, to);
    tsr_composite_memnet_free(net);
    return filled;
}

/* A final piece that a dense strip composited may come back with its
 * background filled in (tsr_composite_run_peer_rounds' fill) instead of gathered:
 * drawn, it gives the very pixels (colour, and depth 1.0 where nothing was
 * drawn) the gathered piece gives, for direct send and radix-k, full-window
 * and region-of-interest layers, mostly covered (filled) and sparse
 * (gathered: more than 1/8 of the strip is background). */
static int test_filled_final_pieces_equal_gathered(void)
{
    enum { W = 67, H = 29 };
    tsr_error err;
    const strat which[] = {{TSR_COMPOSITE_DIRECT, 0}, {TSR_COMPOSITE_RADIXK, 4}};
    const char *names[] = {"direct", "radixk-4"};
    int holes_filled = 0;
    for (size_t si = 0; si < sizeof which / sizeof *which; si++)
        for (int n = 3; n <= 8; n++)
            for (int dense = 0; dense < 2; dense++) {
                tsr_composite_schedule s;
                CHECK_OK(tsr_composite_plan(which[si].kind, n, W, H, which[si].k, NULL, &s, &err), err);
                tsr_composite_image imgs[8] = {{0}}, placed[2] = {{0}};
                for (int r = 0; r < n; r++) {
                    /* odd ranks: a region of interest, not the window */
                    int x = r % 2 ? 3 : 0, y = r % 2 ? 2 : 0;
                    CHECK_OK(tsr_composite_image_init(&imgs[r], W, H, x, y, W - x, H - y, TSR_COMPOSITE_RGBA8,
                                                      TSR_COMPOSITE_DEPTH32F, &err),
                             err);
                    imgs[r].rank = r;
                    for (int p = 0; p < (W - x) * (H - y); p++) {
                        int active = (int)(rnd() % 100) < (dense ? 80 : 30);
                        for (int c = 0; c < 4; c++)
                            imgs[r].color[4 * p + c] = active ? (uint8_t)(rnd() % 255 + 1) : 0;
                        imgs[r].depth[p] = active ? (float)(rnd() % 4000) / 4001.0f : 1.0f;
                    }
                }
                for (int v = 0; v < 2; v++) {
                    CHECK_OK(tsr_composite_image_init(&placed[v], W, H, 0, 0, W, H, TSR_COMPOSITE_RGBA8,
                                                      TSR_COMPOSITE_DEPTH32F, &err),
                             err);
                    memset(placed[v].color, 0x5a, (size_t)W * H * 4);
                    for (int p = 0; p < W * H; p++)
                        placed[v].depth[p] = 2.0f;
                }
                int filled = run_frames(&s, imgs, BG, &placed[0]);
                int covered = run_frames(&s, imgs, NULL, &placed[1]);
                /* direct send: every rank's one round folds n pieces */
                if (which[si].kind == TSR_COMPOSITE_DIRECT && dense) {
                    CHECK(filled == n, "direct n=%d, mostly covered: %d of %d final pieces filled", n, filled, n);
                    holes_filled += filled - covered;
                }
                if (which[si].kind == TSR_COMPOSITE_DIRECT && !dense && n == 3)
                    CHECK(filled == covered, "direct n=3, sparse: %d final pieces filled, none expected",
                          filled - covered);
                CHECK(!memcmp(placed[0].color, placed[1].color, (size_t)W * H * 4),
                      "%s n=%d %s: filled pieces draw other colours than gathered ones", names[si], n,
                      dense ? "dense" : "sparse");
                CHECK(!memcmp(placed[0].depth, placed[1].depth, (size_t)W * H * 4),
                      "%s n=%d %s: filled pieces draw other depths than gathered ones", names[si], n,
                      dense ? "dense" : "sparse");
                for (int r = 0; r < n; r++)
                    tsr_composite_image_free(&imgs[r]);
                tsr_composite_image_free(&placed[0]);
                tsr_composite_image_free(&placed[1]);
                tsr_composite_schedule_free(&s);
                if (harness_failures)
                    return harness_failures;
            }
    CHECK(holes_filled > 0, "no final piece with background pixels came back filled");
    printf("final pieces with background filled in: %d\n", holes_filled);
    return harness_failures;
}

/* Every strategy in `which` for every peer count in [n0, n1] on W x H
 * windows: the display's frame equals the serial reference, bit for bit. */
static int check_strategies(const strat *which, size_t nwhich, int n0, int n1, int W, int H, fill_kind kind, int mode,
                            const char *codec)
{
    tsr_error err;
    uint8_t *rc = malloc((size_t)W * H * 4);
    float *rd = malloc((size_t)W * H * 4);
    for (int n = n0; n <= n1; n++) {
        tsr_composite_image *imgs = calloc((size_t)n, sizeof *imgs);
        for (int r = 0; r < n; r++) {
            int x = rnd() % W, y = rnd() % H;
            int w = r % 4 == 0 ? W - x : (int)(rnd() % (uint32_t)(W - x + 1));
            int h = r % 4 == 0 ? H - y : (int)(rnd() % (uint32_t)(H - y + 1));
            fill_kind k = kind;
            if (kind == FILL_RANDOM && r % 5 == 4)
                k = FILL_BACKGROUND;
            make_image(&imgs[r], W, H, x, y, w, h, r, k);
        }
        if (mode == TSR_COMPOSITE_DEPTH)
            reference_depth(imgs, n, W, H, rc, rd);
        else
            reference_alpha(imgs, n, W, H, rc);
        for (size_t si = 0; si < nwhich; si++) {
            tsr_composite_schedule s;
            if (tsr_composite_plan(which[si].kind, n, W, H, which[si].k, NULL, &s, &err) != TSR_OK) {
                CHECK(0, "plan: %s", err.message);
                continue;
            }
            CHECK_OK(tsr_composite_schedule_check(&s, &err), err);
            tsr_composite_image out = {0};
            char why[600] = "";
            int r = run_group(&s, imgs, mode, codec, &out, why, sizeof why);
            CHECK(r == TSR_OK, "%s n=%d %dx%d: %s", s.name, n, W, H, why);
            if (r == TSR_OK) {
                size_t bad = 0;
                for (int p = 0; p < W * H; p++)
                    bad += memcmp(out.color + 4 * p, rc + 4 * p, 4) != 0;
                CHECK(bad == 0, "%s n=%d %dx%d %s: %zu pixels differ from the serial reference", s.name, n, W, H, codec,
                      bad);
            }
            tsr_composite_image_free(&out);
            tsr_composite_schedule_free(&s);
        }
        for (int r = 0; r < n; r++)
            tsr_composite_image_free(&imgs[r]);
        free(imgs);
        if (harness_failures)
            break;
    }
    free(rc);
    free(rd);
    return harness_failures;
}

static int test_binaryswap_odd_peer_counts(void)
{
    static const strat bs[] = {{TSR_COMPOSITE_BSWAP, 0}, {TSR_COMPOSITE_RADIXK, 2}};
    return check_strategies(bs, 2, 1, 64, 13, 7, FILL_RANDOM, TSR_COMPOSITE_DEPTH, "rle");
}

static int test_all_strategies_agree(void)
{
    check_strategies(STRATS, NSTRATS, 1, 64, 9, 5, FILL_RANDOM, TSR_COMPOSITE_DEPTH, "rle");
    check_strategies(STRATS, NSTRATS, 1, 12, 9, 5, FILL_EQUAL, TSR_COMPOSITE_DEPTH, "erle");
    check_strategies(STRATS, NSTRATS, 1, 9, 9, 5, FILL_EXTREMES, TSR_COMPOSITE_DEPTH, "none");
    check_strategies(STRATS, NSTRATS, 1, 9, 9, 5, FILL_NAN, TSR_COMPOSITE_DEPTH, "rle");
    return harness_failures;
}

static int test_odd_image_sizes(void)
{
    check_strategies(STRATS, NSTRATS, 1, 64, 1, 1, FILL_RANDOM, TSR_COMPOSITE_DEPTH, "rle");
    check_strategies(STRATS, NSTRATS, 1, 64, 997, 1, FILL_RANDOM, TSR_COMPOSITE_DEPTH, "rle");
    for (int n = 1; n <= 8; n += (n < 3 ? 1 : 2))
        check_strategies(STRATS, NSTRATS, n, n, 509, 503, FILL_RANDOM, TSR_COMPOSITE_DEPTH, "erle");
    return harness_failures;
}

static int test_blank_peers(void)
{
    check_strategies(STRATS, NSTRATS, 1, 17, 11, 3, FILL_BACKGROUND, TSR_COMPOSITE_DEPTH, "rle");
    check_strategies(STRATS, NSTRATS, 1, 17, 11, 3, FILL_SINGLE, TSR_COMPOSITE_DEPTH, "rle");
    return harness_failures;
}

/* Alpha: with every alpha 0 or 255 over is exact, so every strategy equals
 * the serial back-to-front blend; with any alpha, the schedules that blend
 * each pixel's layers in one place, back to front (gather, direct send,
 * one round of radix-k, bswap of two), still do, bit for bit. */
static int test_alpha_strategies_agree(void)
{
    static const strat chain[] = {{TSR_COMPOSITE_GATHER, 0}, {TSR_COMPOSITE_DIRECT, 0}};
    static const strat one_round[] = {{TSR_COMPOSITE_RADIXK, 3}, {TSR_COMPOSITE_BSWAP, 0}};
    check_strategies(STRATS, NSTRATS, 1, 24, 9, 5, FILL_OPAQUE, TSR_COMPOSITE_ALPHA, "erle");
    check_strategies(chain, 2, 1, 16, 9, 5, FILL_RANDOM, TSR_COMPOSITE_ALPHA, "rle");
    check_strategies(&one_round[0], 1, 3, 3, 9, 5, FILL_RANDOM, TSR_COMPOSITE_ALPHA, "rle");
    check_strategies(&one_round[1], 1, 2, 2, 9, 5, FILL_RANDOM, TSR_COMPOSITE_ALPHA, "rle");
    return harness_failures;
}


/* Which schedules alpha mode may use (tsr_composite_schedule_keeps_order): those
 * that blend every pixel's layers back to front in one place. The claim is
 * also checked by running them: alpha_strategies_agree above. */
static int test_alpha_schedules_keep_order(void)
{
    tsr_error err;
    char why[160];
    for (int n = 1; n <= 64; n++) {
        int prime = n > 1;
        for (int d = 2; d * d <= n; d++)
            prime = prime && n % d;
        /* radix-k of a prime peer count is one round of all (radixk.c) */
        struct {
            int kind, k, keeps;
        } cases[] = {{TSR_COMPOSITE_GATHER, 0, 1},
                     {TSR_COMPOSITE_DIRECT, 0, 1},
                     {TSR_COMPOSITE_BSWAP, 0, n <= 2},
                     {TSR_COMPOSITE_RADIXK, n, 1},
                     {TSR_COMPOSITE_RADIXK, 2, n <= 2 || prime}};
        for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
            if (cases[c].kind == TSR_COMPOSITE_RADIXK && cases[c].k < 2)
                continue;
            tsr_composite_schedule s;
            CHECK_OK(tsr_composite_plan(cases[c].kind, n, 13, 7, cases[c].k, NULL, &s, &err), err);
            int keeps = tsr_composite_schedule_keeps_order(&s, why, sizeof why);
            CHECK(keeps == cases[c].keeps, "%s for %d peers: keeps_order says %d (%s), expected %d", s.name, n, keeps,
                  why, cases[c].keeps);
            tsr_composite_schedule_free(&s);
        }
    }
    return harness_failures;
}

/* Float over against a plain loop: random, all transparent, all opaque,
 * a single pixel; bit for bit (the same expression, in float). */
static int test_over_float_kernel_matches_reference(void)
{
    uint32_t seed = 7;
    for (int pattern = 0; pattern < 4; pattern++) {
        size_t n = pattern == 3 ? 1 : 257;
        float *f = malloc(n * 16), *b = malloc(n * 16), *o = malloc(n * 16), *r = malloc(n * 16);
        for (size_t i = 0; i < 4 * n; i++) {
            seed = seed * 1664525u + 1013904223u;
            float v = (float)(seed >> 8) / 16777216.0f;
            f[i] = pattern == 1 ? 0.0f : v;
            b[i] = v * 0.5f;
        }
        for (size_t i = 0; i < n; i++) {
            if (pattern == 2)
                f[4 * i + 3] = 1.0f;
            for (int k = 0; k < 3 && pattern != 1; k++)
                f[4 * i + k] *= f[4 * i + 3]; /* premultiplied */
            for (int k = 0; k < 4; k++) {
                float keep = 1.0f - f[4 * i + 3];
                r[4 * i + k] = f[4 * i + k] + b[4 * i + k] * keep;
            }
        }
        tsr_composite_over_rgba32f(n, f, b, o);
        CHECK(!memcmp(o, r, n * 16), "float over differs from the plain loop (pattern %d)", pattern);
        if (pattern == 1)
            CHECK(!memcmp(o, b, n * 16), "transparent over back is not back");
        if (pattern == 2)
            for (size_t i = 0; i < 4 * n; i++)
                CHECK(o[i] == f[i], "opaque over back is not front (float %zu)", i);
        free(f);
        free(b);
        free(o);
        free(r);
    }
    return harness_failures;
}

/* A peer that never sends, a frame number that does not match (ahead,
 * or gone backwards: a stale image), a peer whose window differs: each is
 * one error naming the peer, within the transport's time-out. */
static int test_faults_name_the_peer(void)
{
    tsr_error err;
    int n = 4, W = 8, H = 4;
    tsr_composite_image imgs[4] = {{0}};
    for (int r = 0; r < n; r++)
        make_image(&imgs[r], W, H, 0, 0, W, H, r, FILL_RANDOM);
    for (int fault = 0; fault < 4; fault++) {
        tsr_composite_schedule s;
        CHECK_OK(
            tsr_composite_plan(fault == 2 ? TSR_COMPOSITE_GATHER : TSR_COMPOSITE_BSWAP, n, W, H, 0, NULL, &s, &err),
            err);
        tsr_composite_memnet *net = tsr_composite_memnet_new(n + 1, 300, &err);
        tsr_composite_codec codec;
        tsr_composite_codec_parse("rle", &codec, &err);
        peer_job jobs[4];
        pthread_t th[4];
        tsr_composite_image odd = {0};
        if (fault == 2)
            make_image(&odd, W + 1, H, 0, 0, W + 1, H, 1, FILL_RANDOM);
        for (int r = 0; r < n; r++) {
            jobs[r] = (peer_job){.s = &s, .codec = codec, .img = &imgs[r], .rank = r, .mode = TSR_COMPOSITE_DEPTH};
            if (fault == 2 && r == 1)
                jobs[r].img = &odd;
            tsr_composite_memnet_transport(net, r, &jobs[r].t);
        }
        if (fault == 1)
            imgs[2].frame = 8;
        if (fault == 3)
            imgs[2].frame = 6; /* the frame number went backwards */
        struct timespec t0, t1;
        clock_gettime(CLOCK_MONOTONIC, &t0);
        for (int r = 0; r < n; r++)
            if (!(fault == 0 && r == 3)) /* rank 3 stays silent */
                pthread_create(&th[r], NULL, peer_main, &jobs[r]);
        tsr_composite_transport t;
        tsr_composite_memnet_transport(net, n, &t);
        tsr_composite_executor *ex = tsr_composite_executor_new(&s, codec, &err);
        tsr_composite_image out = {0};
        int rc = tsr_composite_run_display(ex, 7, TSR_COMPOSITE_DEPTH, TSR_COMPOSITE_RGBA8, TSR_COMPOSITE_DEPTH32F, BG,
                                           &out, &t, &err);
        for (int r = 0; r < n; r++)
            if (!(fault == 0 && r == 3))
                pthread_join(th[r], NULL);
        clock_gettime(CLOCK_MONOTONIC, &t1);
        double secs = (double)(t1.tv_sec - t0.tv_sec) + (double)(t1.tv_nsec - t0.tv_nsec) / 1e9;
        CHECK(rc != TSR_OK, "fault %d: the display assembled a frame", fault);
        CHECK(secs < 10, "fault %d took %.1f s", fault, secs);
        if (fault == 0) {
            CHECK(jobs[2].rc == TSR_ETIMEDOUT, "rank 2 (rank 3's partner) did not time out");
            CHECK_CONTAINS(jobs[2].err.message, "peer 3 sent nothing");
        } else if (fault == 1 || fault == 3) {
            const char *want = fault == 1 ? "from peer 2: image message: frame is 8, expected 7"
                                          : "from peer 2: image message: frame is 6, expected 7";
            int named = 0;
            for (int r = 0; r < n; r++)
                named += jobs[r].rc && strstr(jobs[r].err.message, want);
            CHECK(named == 1, "no rank named peer 2's frame %d (display: %s)", fault == 1 ? 8 : 6, err.message);
        } else {
            CHECK(jobs[1].rc == TSR_EINVAL);
            CHECK_CONTAINS(jobs[1].err.message, "rank 1's window is 9x4, the group's 8x4");
            CHECK_CONTAINS(err.message, "peer 1 sent nothing");
        }
        imgs[2].frame = 7;
        int from, to;
        tsr_composite_memnet_drain(net, &from, &to);
        tsr_composite_memnet_free(net);
        tsr_composite_executor_free(ex);
        tsr_composite_image_free(&out);
        tsr_composite_image_free(&odd);
        tsr_composite_schedule_free(&s);
    }
    for (int r = 0; r < n; r++)
        tsr_composite_image_free(&imgs[r]);
    return harness_failures;
}

/* ---- fuzz corpus ------------------------------------------------------------ */

static int write_file(const char *dir, const char *name, const uint8_t *data, size_t size)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(data, 1, size, f) != size || fclose(f) != 0) {
        fprintf(stderr, "composite_test: cannot write %s\n", path);
        return 1;
    }
    return 0;
}

/* Seeds: valid messages of every codec and format (ok-*), and the known
 * malformations (bad-*), each checked through the fuzz entry point first. */
static int fuzz_seeds(const char *dir)
{
    tsr_error err;
    int fails = 0;
    for (int variant = 0; variant < 3; variant++) {
        tsr_composite_image img = {0};
        make_image(&img, 23, 5, 2, 1, 17, 3, 1, FILL_RANDOM);
        int mode = variant == 1 ? TSR_COMPOSITE_ALPHA : TSR_COMPOSITE_DEPTH;
        if (variant == 2) {
            /* float colour */
            tsr_composite_image f = {0};
            REQUIRE(tsr_composite_image_init(&f, 23, 5, 2, 1, 17, 3, TSR_COMPOSITE_RGBA32F, TSR_COMPOSITE_DEPTH32F,
                                             &err) == TSR_OK);
            for (int i = 0; i < 17 * 3; i++) {
                float c[4] = {img.color[4 * i] / 255.0f, 0.5f, 0.25f, 1.0f};
                memcpy(f.color + 16 * i, c, sizeof c);
                f.depth[i] = img.depth[i];
            }
            tsr_composite_image_free(&img);
            img = f;
        }
        tsr_composite_sparse s = {0};
        CHECK_OK(tsr_composite_sparse_compress(&img, mode, 7, 100, &s, &err), err);
        for (size_t ci = 0; ci < sizeof CODECS / sizeof *CODECS; ci++) {
            tsr_composite_codec c;
            tsr_composite_codec_parse(CODECS[ci], &c, &err);
            size_t cap = tsr_composite_message_max_size(s.count, s.color_format, s.depth_format, c), len;
            uint8_t *buf = malloc(cap);
            if (tsr_composite_message_encode(&s, c, buf, cap, &len, &err) == TSR_OK) {
                char name[96];
                snprintf(name, sizeof name, "ok-%s-%s",
                         variant == 0   ? "depth"
                         : variant == 1 ? "alpha"
                                        : "float",
                         CODECS[ci]);
                for (char *q = name; *q; q++)
                    if (*q == '+')
                        *q = '_';
                CHECK(fuzz_composite_message_one(buf, len) == 0, "seed %s does not decode", name);
                fails += write_file(dir, name, buf, len);
                if (variant == 0 && ci == 2) {
                    /* malformations of the erle message */
                    static const struct {
                        const char *name;
                        size_t off;
                        uint32_t v;
                    } bad[] = {{"bad-magic", 0, 1},          {"bad-window", 12, 0},
                               {"bad-range", 24, 1u << 30},  {"bad-active", 36, 101},
                               {"bad-payload-size", 44, 3},  {"bad-run-overflow", 48, 0x10000},
                               {"bad-codec", 4, 0x05050501}, {"bad-rle-plane-length", 48 + 8 * 0, 0}};
                    for (size_t b = 0; b < sizeof bad / sizeof *bad; b++) {
                        uint8_t *m = malloc(len);
                        memcpy(m, buf, len);
                        size_t off = bad[b].off;
                        if (b == sizeof bad / sizeof *bad - 1)
                            off = 48 + 8 * (size_t)s.nruns; /* first colour plane's length */
                        for (int k = 0; k < 4; k++)
                            m[off + k] = (uint8_t)(bad[b].v >> (8 * k));
                        if (b == sizeof bad / sizeof *bad - 1)
                            m[off] = 0xff, m[off + 1] = 0xff;
                        CHECK(fuzz_composite_message_one(m, len) == 1, "seed %s is accepted", bad[b].name);
                        fails += write_file(dir, bad[b].name, m, len);
                        free(m);
                    }
                    CHECK(fuzz_composite_message_one(buf, len - 1) == 1);
                    fails += write_file(dir, "bad-truncated", buf, len - 1);
                }
            }
            free(buf);
        }
        tsr_composite_sparse_free(&s);
        tsr_composite_image_free(&img);
    }
    return fails + harness_failures;
}

/* Replays every file of `dir`: ok-* must decode, bad-* must be rejected,
 * anything else (inputs libFuzzer found) must only return. */
static int fuzz_replay(const char *dir)
{
    DIR *d = opendir(dir);
    REQUIRE(d != NULL, "cannot open %s", dir);
    struct dirent *e;
    int files = 0;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.')
            continue;
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        FILE *f = fopen(path, "rb");
        REQUIRE(f != NULL, "cannot read %s", path);
        static uint8_t buf[1 << 20];
        size_t n = fread(buf, 1, sizeof buf, f);
        fclose(f);
        uint8_t *copy = malloc(n ? n : 1); /* exact size, so ASan sees overreads */
        memcpy(copy, buf, n);
        int rc = fuzz_composite_message_one(copy, n);
        free(copy);
        if (!strncmp(e->d_name, "ok-", 3))
            CHECK(rc == 0, "%s does not decode", e->d_name);
        if (!strncmp(e->d_name, "bad-", 4))
            CHECK(rc == 1, "%s is accepted", e->d_name);
        files++;
    }
    closedir(d);
    CHECK(files > 10, "only %d corpus files in %s", files, dir);
    printf("replayed %d files\n", files);
    return harness_failures;
}

int main(int argc, char **argv)
{
    static const struct {
        const char *name;
        int (*fn)(void);
    } tests[] = {
        {"depth_kernel_matches_reference", test_depth_kernel_matches_reference},
        {"over_kernel_matches_reference", test_over_kernel_matches_reference},
        {"large_messages_any_alignment", test_large_messages_any_alignment},
        {"nan_depth_never_wins", test_nan_depth_never_wins},
        {"compress_runs_match_pixel_rule", test_compress_runs_match_pixel_rule},
        {"sparse_merge_equals_dense", test_sparse_merge_equals_dense},
        {"sparse_fold_equals_merges", test_sparse_fold_equals_merges},
        {"split_at_run_edges", test_split_at_run_edges},
        {"codecs_roundtrip", test_codecs_roundtrip},
        {"codec_worst_case_size", test_codec_worst_case_size},
        {"message_decoder_rejects_bad_input", test_message_decoder_rejects_bad_input},
        {"encode_dense_equals_compress_encode", test_encode_dense_equals_compress_encode},
        {"message_view_equals_decode", test_message_view_equals_decode},
        {"schedules_hold_invariants", test_schedules_hold_invariants},
        {"link_bytes_hold_one_frame", test_link_bytes_hold_one_frame},
        {"executor_keeps_one_piece", test_executor_keeps_one_piece},
        {"filled_final_pieces_equal_gathered", test_filled_final_pieces_equal_gathered},
        {"binaryswap_odd_peer_counts", test_binaryswap_odd_peer_counts},
        {"all_strategies_agree", test_all_strategies_agree},
        {"odd_image_sizes", test_odd_image_sizes},
        {"blank_peers", test_blank_peers},
        {"alpha_strategies_agree", test_alpha_strategies_agree},
        {"faults_name_the_peer", test_faults_name_the_peer},
        {"alpha_schedules_keep_order", test_alpha_schedules_keep_order},
        {"over_float_kernel_matches_reference", test_over_float_kernel_matches_reference},
    };
    if (argc == 3 && !strcmp(argv[1], "fuzz_seeds"))
        return fuzz_seeds(argv[2]) ? 1 : 0;
    if (argc == 3 && !strcmp(argv[1], "fuzz_replay"))
        return fuzz_replay(argv[2]) ? 1 : 0;
    if (argc != 2) {
        fprintf(stderr, "usage: composite_test NAME | fuzz_seeds DIR | fuzz_replay DIR\n");
        return 2;
    }
    for (size_t i = 0; i < sizeof tests / sizeof *tests; i++)
        if (!strcmp(argv[1], tests[i].name)) {
            int f = tests[i].fn();
            return f ? 1 : 0;
        }
    fprintf(stderr, "composite_test: unknown test '%s'\n", argv[1]);
    return 2;
}
