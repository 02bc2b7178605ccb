/* bench/bench_state.c — context switches through the state tracker
 * (tessera/dev/state.h), the experiment of Buck, Humphreys and Hanrahan's 2000
 * state-tracking paper: two tracked contexts take turns on one renderer,
 * each turn a diff of the incoming context into the renderer's shadow,
 * packed by the real packer (buffers go to a sink that only counts them).
 *  ctx_switch_differ_per_s  the contexts differ in the current color and
 *                           the modelview matrix (each switch packs a
 *                           Color4f and a LoadMatrixf)
 *  ctx_switch_same_per_s    identical contexts (nothing to pack: the
 *                           hierarchical bits answer with one word test)
 * Both contexts carry a realistic state besides (projection, viewport,
 * lighting, material, a bound texture, blending, fog), which the "same"
 * case must not look at. Figures to beat (the paper): 200,000/s and
 * 5,000,000/s. Reports, never pass/fail. */
#include "bench_common.h"

#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>

#include "tessera/dev/pack.h"
#include "tessera/dev/state.h"
#include "tessera/dispatch.h"

typedef struct counter {
    uint64_t bytes, buffers;
} counter;

static int count_buffer(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    (void)buf, (void)err;
    counter *c = ctx;
    c->bytes += size;
    c->buffers++;
    return 0;
}

/* A scene's worth of state, the same in both contexts. */
static void common_state(const tsr_dispatch *d)
{
    static const GLfloat light_pos[4] = {1, 2, 3, 0}, diffuse[4] = {0.8f, 0.7f, 0.6f, 1};
    static GLubyte texels[8 * 8 * 4];
    tsr_call_WindowCreateTSR(d, 0, 1024, 768);
    tsr_call_Viewport(d, 0, 0, 1024, 768);
    tsr_call_MatrixMode(d, GL_PROJECTION);
    tsr_call_LoadIdentity(d);
    tsr_call_Frustum(d, -1, 1, -0.75, 0.75, 1, 100);
    tsr_call_MatrixMode(d, GL_MODELVIEW);
    tsr_call_LoadIdentity(d);
    tsr_call_Enable(d, GL_DEPTH_TEST);
    tsr_call_Enable(d, GL_LIGHTING);
    tsr_call_Enable(d, GL_LIGHT0);
    tsr_call_Lightfv(d, GL_LIGHT0, GL_POSITION, light_pos);
    tsr_call_Materialfv(d, GL_FRONT_AND_BACK, GL_DIFFUSE, diffuse);
    tsr_call_Enable(d, GL_BLEND);
    tsr_call_BlendFunc(d, GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    tsr_call_Fogi(d, GL_FOG_MODE, GL_LINEAR);
    tsr_call_BindTexture(d, GL_TEXTURE_2D, 1);
    tsr_call_TexImage2D(d, GL_TEXTURE_2D, 0, GL_RGBA, 8, 8, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    tsr_call_Enable(d, GL_TEXTURE_2D);
}

typedef struct run {
    double per_s;
    double bytes_per_switch;
} run;

/* Times `switches` diffs alternating between a and b on one renderer. */
static run time_switches(tsr_state_ctx *a, tsr_state_ctx *b, tsr_state_shadow *r, tsr_packer *p,
                         const tsr_dispatch *out, counter *cnt, long switches)
{
    /* Warm up: the renderer has met both contexts. */
    for (int i = 0; i < 4; i++) {
        tsr_state_diff(a, r, out, NULL);
        tsr_state_diff(b, r, out, NULL);
    }
    tsr_packer_flush(p);
    uint64_t bytes0 = cnt->bytes + tsr_packer_pending(p);
    double t0 = bench_now();
    for (long i = 0; i < switches / 2; i++) {
        tsr_state_diff(a, r, out, NULL);
        tsr_state_diff(b, r, out, NULL);
    }
    double t = bench_now() - t0;
    uint64_t bytes = cnt->bytes + tsr_packer_pending(p) - bytes0;
    tsr_packer_flush(p);
    run res = {(double)(switches / 2 * 2) / t, (double)bytes / (double)(switches / 2 * 2)};
    return res;
}

int main(int argc, char **argv)
{
    bench_args args;
    if (bench_parse_args(argc, argv, &args, NULL) != 0)
        return 2;
    tsr_error err = {0};
    counter cnt = {0, 0};
    tsr_pack_sink sink = {.flush = count_buffer, .ctx = &cnt};
    tsr_packer *p = tsr_packer_create(1u << 20, &sink, &err);
    tsr_state_tracker *t = tsr_state_tracker_create(&err);
    if (!p || !t) {
        fprintf(stderr, "bench_state: %s\n", err.message);
        return 1;
    }
    static tsr_dispatch out, da, db, dc, dd;
    tsr_dispatch_fill_nop(&out);
    tsr_packer_fill_dispatch(p, &out);
    tsr_state_ctx *a = tsr_state_ctx_create(t, &err), *b = tsr_state_ctx_create(t, &err);
    tsr_state_ctx *c = tsr_state_ctx_create(t, &err), *d = tsr_state_ctx_create(t, &err);
    tsr_state_shadow *r1 = tsr_state_shadow_create(t, &err), *r2 = tsr_state_shadow_create(t, &err);
    if (!a || !b || !c || !d || !r1 || !r2) {
        fprintf(stderr, "bench_state: %s\n", err.message);
        return 1;
    }
    tsr_state_ctx *ctxs[4] = {a, b, c, d};
    tsr_dispatch *tables[4] = {&da, &db, &dc, &dd};
    for (int i = 0; i < 4; i++) {
        tsr_dispatch_fill_nop(tables[i]);
        tsr_state_fill_dispatch(ctxs[i], tables[i]);
        common_state(tables[i]);
    }
    /* a and b differ in the current color and the modelview matrix. */
    tsr_call_Color4f(&da, 1, 0, 0, 1);
    tsr_call_Translatef(&da, 1, 0, -5);
    tsr_call_Color4f(&db, 0, 1, 0, 1);
    tsr_call_Translatef(&db, -1, 0, -5);
    /* c and d are identical. */
    for (int i = 2; i < 4; i++) {
        tsr_call_Color4f(tables[i], 0.5f, 0.5f, 1, 1);
        tsr_call_Translatef(tables[i], 0, 1, -5);
    }

    long n_differ = args.quick ? 2000 : 4000000;
    long n_same = args.quick ? 20000 : 200000000;
    FILE *csv = bench_csv_open(args.csv_path, "run,ctx_switch_differ_per_s,bytes_per_switch,ctx_switch_same_per_s");
    run best_differ = {0, 0}, best_same = {0, 0};
    for (int rep = 0; rep < args.repeats; rep++) {
        run dr = time_switches(a, b, r1, p, &out, &cnt, n_differ);
        run sr = time_switches(c, d, r2, p, &out, &cnt, n_same);
        if (csv)
            fprintf(csv, "%d,%.0f,%.1f,%.0f\n", rep, dr.per_s, dr.bytes_per_switch, sr.per_s);
        if (dr.per_s > best_differ.per_s)
            best_differ = dr;
        if (sr.per_s > best_same.per_s)
            best_same = sr;
    }
    if (csv)
        fclose(csv);
    bench_figure("ctx_switch_differ_per_s", best_differ.per_s, 0);
    bench_figure("ctx_switch_differ_bytes", best_differ.bytes_per_switch, 1);
    bench_figure("ctx_switch_same_per_s", best_same.per_s, 0);
    bench_figure("ctx_switch_same_bytes", best_same.bytes_per_switch, 1);
    tsr_state_tracker_destroy(t);
    tsr_packer_destroy(p);
    return 0;
}
