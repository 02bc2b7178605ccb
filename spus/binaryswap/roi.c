/* spus/binaryswap/roi.c — the region of interest of a peer's frame from
 * the geometry its chain sees (issue 11, item 2): the window-space box of
 * everything drawn since the last swap, so that only that box's colour and
 * depth are read back. binaryswap sees the GL calls itself in both forms
 * (in situ they come from the application, with servers from the
 * unpacked stream), so the same code serves both.
 *
 * How. A packer of the core (tessera/dev/pack.h, whose box code pack and
 * tilesort use too) is fed every call that carries vertex positions
 * (glVertex*, Begin/End, DrawArrays/DrawElements) and every client-state
 * call its mirrors need (arrays, buffer bindings), before render draws
 * them; its sink throws the packed bytes away, it is kept only for its
 * object-space box. Before any other call (a matrix, the viewport, a
 * context switch, the swap) that box is folded: transformed with the
 * current projection, modelview and viewport (asked of render's GL
 * context) into window space by tsr_box_window, which clips a box partly
 * behind the eye in homogeneous space (never dropped), grown by the line
 * width / point size, clamped to the window, and united with the frame's
 * box. BoundsInfoTSR boxes are united the same way. A box that cannot be
 * placed (a non-finite value, a vertex with w <= 0, arrays in buffer
 * objects: the packer makes those infinite) counts as the whole window.
 *
 * Unknown extent: a command that draws where no box says (CallList, Rect,
 * Eval, Bitmap, DrawPixels, CopyPixels, Accum, generic vertex attributes,
 * any draw while a GLSL program is bound or generic array 0 is enabled, a
 * Clear of depth to a value other than 1.0 or under a scissor, a frame
 * without a Clear of the whole colour and depth buffers) makes the
 * frame's box unknown: binaryswap then finds the region from the depth
 * buffer instead (layer.c, binaryswap_read_layer).
 *
 * Owns: its packer, the saved render table and the hook/tee records (they
 * are the slots' `self`). Never: changes what render draws or any GL state
 * (it only reads state, never inside Begin/End), keeps state outside its
 * instance. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "roi.h"
#include "tessera/dev/pack.h"
#include "tessera/log.h"

struct binaryswap_roi {
    tsr_dispatch render; /* render's own table, for the queries */
    tsr_dispatch next;   /* the table as built below, for the wrapped calls */
    tsr_packer *box;     /* kept for its object-space box */
    tsr_tee tees[TSR_DISPATCH_COUNT];
    tsr_hook hooks[TSR_DISPATCH_COUNT];
    tsr_hook inner[TSR_DISPATCH_COUNT]; /* Begin/End: after their tee */
    void (*window_size)(void *ctx, int *w, int *h);
    void *ctx;

    int in_begin;
    /* this frame's object-space box from the packer's flushes (the packer
     * resets its own at every flush; the matrices cannot have changed) */
    float flushed_mn[3], flushed_mx[3];
    int flushed;
    int frame_box[4]; /* x0, y0, x1, y1; x0 >= x1: empty */
    int unknown;      /* the frame drew something no box covers */
    int cleared;      /* the frame cleared colour and depth, whole window */
    unsigned program; /* bound GLSL program (vertex positions are its) */
    int attrib0;      /* generic array 0 enabled (it may be the position) */
};

static int discard(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    (void)buf;
    (void)size;
    (void)err;
    binaryswap_roi *r = ctx;
    float mn[3], mx[3];
    if (!tsr_packer_bbox(r->box, mn, mx))
        return TSR_OK;
    for (int a = 0; a < 3; a++) {
        r->flushed_mn[a] = r->flushed ? fminf(r->flushed_mn[a], mn[a]) : mn[a];
        r->flushed_mx[a] = r->flushed ? fmaxf(r->flushed_mx[a], mx[a]) : mx[a];
        /* fminf drops a NaN: keep what the packer's box said (infinite) */
    }
    r->flushed = 1;
    return TSR_OK;
}

static void unite(binaryswap_roi *r, const int b[4])
{
    if (b[0] >= b[2] || b[1] >= b[3])
        return;
    int *f = r->frame_box;
    if (f[0] >= f[2] || f[1] >= f[3]) {
        memcpy(f, b, sizeof r->frame_box);
        return;
    }
    f[0] = b[0] < f[0] ? b[0] : f[0];
    f[1] = b[1] < f[1] ? b[1] : f[1];
    f[2] = b[2] > f[2] ? b[2] : f[2];
    f[3] = b[3] > f[3] ? b[3] : f[3];
}

/* Places the object-space box [mn, mx] with the current matrices. */
static void place(binaryswap_roi *r, const float mn[3], const float mx[3])
{
    int W = 0, H = 0;
    r->window_size(r->ctx, &W, &H);
    GLfloat p[16], m[16], lw = 1, ps = 1, att[3] = {1, 0, 0};
    GLint vp[4] = {0, 0, W, H};
    tsr_call_GetFloatv(&r->render, GL_PROJECTION_MATRIX, p);
    tsr_call_GetFloatv(&r->render, GL_MODELVIEW_MATRIX, m);
    tsr_call_GetIntegerv(&r->render, GL_VIEWPORT, vp);
    tsr_call_GetFloatv(&r->render, GL_LINE_WIDTH, &lw);
    tsr_call_GetFloatv(&r->render, GL_POINT_SIZE, &ps);
    tsr_call_GetFloatv(&r->render, GL_POINT_DISTANCE_ATTENUATION, att);
    double size = lw > ps ? lw : ps;
    if (att[0] != 1.0f || att[1] != 0.0f || att[2] != 0.0f) {
        GLfloat most = 1;
        tsr_call_GetFloatv(&r->render, GL_POINT_SIZE_MAX, &most);
        size = fmax(size, most);
    }
    if (!isfinite(size) || size > 1e6)
        size = 1e6;
    /* half the width, plus antialiasing's extra pixel and rounding */
    double margin = size / 2.0 + 2.0;
    int b[4];
    if (!tsr_box_window(p, m, vp, mn, mx, margin, 1, W, H, b)) {
        b[0] = b[1] = 0; /* cannot be placed: the whole window */
        b[2] = W;
        b[3] = H;
    }
    unite(r, b);
}

/* The geometry since the last fold, placed with the matrices it had. */
static void fold(binaryswap_roi *r)
{
    if (r->in_begin)
        return;
    float mn[3], mx[3];
    int have = tsr_packer_bbox(r->box, mn, mx);
    if (r->flushed) {
        for (int a = 0; a < 3 && have; a++) {
            mn[a] = fminf(mn[a], r->flushed_mn[a]);
            mx[a] = fmaxf(mx[a], r->flushed_mx[a]);
        }
        if (!have) {
            memcpy(mn, r->flushed_mn, sizeof mn);
            memcpy(mx, r->flushed_mx, sizeof mx);
        }
        have = 1;
    }
    if (!have)
        return;
    for (int a = 0; a < 3; a++)
        if (mn[a] != mn[a] || mx[a] != mx[a]) {
            mn[a] = -INFINITY; /* a NaN vertex: anywhere */
            mx[a] = INFINITY;
        }
    tsr_packer_bbox_reset(r->box);
    r->flushed = 0;
    place(r, mn, mx);
}

static void before_fold(void *ctx, int slot)
{
    (void)slot;
    fold(ctx);
}

static void before_unknown(void *ctx, int slot)
{
    binaryswap_roi *r = ctx;
    if (!r->unknown)
        tsr_log(TSR_LOG_DEBUG, "binaryswap: %s has no box: this frame's region comes from the depth buffer",
                tsr_dispatch_name(slot));
    r->unknown = 1;
}

static void before_begin(void *ctx, int slot)
{
    (void)slot;
    binaryswap_roi *r = ctx;
    fold(r);
    if (r->program || r->attrib0)
        r->unknown = 1;
    r->in_begin = 1;
}

static void after_end(void *ctx, int slot)
{
    (void)slot;
    ((binaryswap_roi *)ctx)->in_begin = 0;
}

static void before_draw(void *ctx, int slot)
{
    (void)slot;
    binaryswap_roi *r = ctx;
    fold(r);
    if (r->program || r->attrib0)
        r->unknown = 1;
}

/* --- the commands it looks into ------------------------------------------ */

static void roi_Clear(void *self, GLbitfield mask)
{
    binaryswap_roi *r = self;
    fold(r);
    GLboolean scissor = GL_FALSE, colors[4] = {0}, depths = GL_FALSE;
    GLfloat depth = 1.0f;
    tsr_call_GetBooleanv(&r->render, GL_SCISSOR_TEST, &scissor);
    tsr_call_GetBooleanv(&r->render, GL_COLOR_WRITEMASK, colors);
    tsr_call_GetBooleanv(&r->render, GL_DEPTH_WRITEMASK, &depths);
    tsr_call_GetFloatv(&r->render, GL_DEPTH_CLEAR_VALUE, &depth);
    /* A clear of the whole window to depth 1.0 is background: no box. A
     * partial one leaves last frame's pixels, another depth draws. */
    if (scissor || ((mask & GL_DEPTH_BUFFER_BIT) && depth != 1.0f))
        before_unknown(r, TSR_SLOT_Clear);
    else if ((mask & GL_COLOR_BUFFER_BIT) && (mask & GL_DEPTH_BUFFER_BIT) && colors[0] && colors[1] && colors[2] &&
             colors[3] && depths)
        r->cleared = 1;
    tsr_call_Clear(&r->next, mask);
}

static void roi_UseProgram(void *self, GLuint program)
{
    binaryswap_roi *r = self;
    fold(r);
    r->program = program;
    tsr_call_UseProgram(&r->next, program);
}

static void roi_EnableVertexAttribArray(void *self, GLuint index)
{
    binaryswap_roi *r = self;
    if (index == 0)
        r->attrib0 = 1;
    tsr_call_EnableVertexAttribArray(&r->next, index);
}

static void roi_DisableVertexAttribArray(void *self, GLuint index)
{
    binaryswap_roi *r = self;
    if (index == 0)
        r->attrib0 = 0;
    tsr_call_DisableVertexAttribArray(&r->next, index);
}

static void roi_BoundsInfoTSR(void *self, const GLfloat *bounds)
{
    binaryswap_roi *r = self;
    fold(r);
    if (bounds && !r->in_begin)
        place(r, bounds, bounds + 3);
    if (r->next.slots[TSR_SLOT_BoundsInfoTSR].fn)
        tsr_call_BoundsInfoTSR(&r->next, bounds); /* a hint: it ends here otherwise */
}

/* --- the table ------------------------------------------------------------ */

/* The draws from client arrays: the packer boxes what they read. */
static int is_array_draw(const char *name)
{
    return !strcmp(name, "DrawArrays") || !strcmp(name, "DrawElements") || !strcmp(name, "DrawRangeElements") ||
           !strcmp(name, "MultiDrawArrays") || !strcmp(name, "MultiDrawElements");
}

static int is_boxed(int slot)
{
    return (tsr_dispatch_flags(slot) & TSR_CMD_POSITION) || slot == TSR_SLOT_Begin || slot == TSR_SLOT_End ||
           is_array_draw(tsr_dispatch_name(slot));
}

/* Draws whose extent no box gives (GEOMETRY commands other than positions
 * and current attributes, and Accum). */
static int is_unknown(int slot)
{
    static const char *const prefixes[] = {"Eval",       "CallList",   "Rect",  "Bitmap",
                                           "DrawPixels", "CopyPixels", "Accum", "VertexAttrib"};
    const char *name = tsr_dispatch_name(slot);
    if (!strncmp(name, "VertexAttribPointer", 19))
        return 0;
    for (size_t i = 0; i < sizeof prefixes / sizeof prefixes[0]; i++)
        if (!strncmp(name, prefixes[i], strlen(prefixes[i])))
            return 1;
    return 0;
}

binaryswap_roi *binaryswap_roi_create(tsr_dispatch *table, void (*window_size)(void *ctx, int *w, int *h), void *ctx,
                                      tsr_error *err)
{
    binaryswap_roi *r = calloc(1, sizeof *r);
    if (!r) {
        tsr_error_set(err, TSR_ENOMEM, "out of memory for the region of interest");
        return NULL;
    }
    r->window_size = window_size;
    r->ctx = ctx;
    r->render = *table;
    tsr_pack_sink sink = {.flush = discard, .ctx = r};
    if (!(r->box = tsr_packer_create(1 << 20, &sink, err))) {
        free(r);
        return NULL;
    }
    tsr_dispatch packs;
    tsr_packer_fill_dispatch(r->box, &packs);
    for (int slot = 0; slot < TSR_DISPATCH_COUNT; slot++) {
        int cat = tsr_dispatch_category(slot);
        unsigned flags = tsr_dispatch_flags(slot);
        const char *name = tsr_dispatch_name(slot);
        if (!table->slots[slot].fn)
            continue; /* not render's: the chain fills it (towards the child) */
        if (is_boxed(slot) || cat == TSR_CAT_CLIENT || (flags & TSR_CMD_LOCAL) || !strncmp(name, "BindBuffer", 10)) {
            /* the packer first (its box, its mirrors), then render */
            r->tees[slot] = (tsr_tee){.first = packs.slots[slot], .second = r->render.slots[slot]};
            tsr_dispatch_tee(table, slot, &r->tees[slot]);
            if (slot == TSR_SLOT_Begin || slot == TSR_SLOT_End || is_array_draw(name)) {
                r->hooks[slot] = (tsr_hook){.before = slot == TSR_SLOT_End     ? NULL
                                                      : slot == TSR_SLOT_Begin ? before_begin
                                                                               : before_draw,
                                            .after = slot == TSR_SLOT_End ? after_end : NULL,
                                            .ctx = r};
                tsr_dispatch_hook(table, slot, &r->hooks[slot]);
            }
        } else if (is_unknown(slot)) {
            r->hooks[slot] = (tsr_hook){.before = before_unknown, .ctx = r};
            tsr_dispatch_hook(table, slot, &r->hooks[slot]);
        } else if (cat != TSR_CAT_GEOMETRY) {
            r->hooks[slot] = (tsr_hook){.before = before_fold, .ctx = r};
            tsr_dispatch_hook(table, slot, &r->hooks[slot]);
        }
    }
    r->next = *table;
#define ROI_WRAP(name)                     \
    if (r->next.slots[TSR_SLOT_##name].fn) \
    tsr_set_##name(table, roi_##name, r)
    ROI_WRAP(Clear);
    ROI_WRAP(UseProgram);
    ROI_WRAP(EnableVertexAttribArray);
    ROI_WRAP(DisableVertexAttribArray);
#undef ROI_WRAP
    tsr_set_BoundsInfoTSR(table, roi_BoundsInfoTSR, r);
    return r;
}

void binaryswap_roi_destroy(binaryswap_roi *r)
{
    if (!r)
        return;
    tsr_packer_destroy(r->box);
    free(r);
}

int binaryswap_roi_frame(binaryswap_roi *r, int box[4])
{
    r->in_begin = 0;
    fold(r);
    /* without a clear, what is outside the box is last frame's */
    int known = !r->unknown && !r->program && !r->attrib0 && r->cleared;
    memcpy(box, r->frame_box, sizeof r->frame_box);
    if (box[0] >= box[2] || box[1] >= box[3])
        box[0] = box[1] = box[2] = box[3] = 0;
    r->frame_box[0] = r->frame_box[1] = r->frame_box[2] = r->frame_box[3] = 0;
    r->unknown = 0;
    r->cleared = 0;
    return known;
}
