/* core/state/state_diff_internal.h — what the files of the diff share:
 * the diff's context (dctx), the selectors and temporary state every
 * member's diff uses (state_diff.c), and each member's diff function.
 * The diff is cut in three: state_diff.c (selectors, the transform, the
 * pixel and misc members, and the driver that walks the dirty members),
 * state_diff_members.c (the fixed-function members from enables to hints),
 * state_diff_objects.c (texture units and objects, buffer objects).
 * Not for anything outside core/state. */
#ifndef TSR_CORE_STATE_DIFF_INTERNAL_H
#define TSR_CORE_STATE_DIFF_INTERNAL_H

#include "state_internal.h"

#include <string.h>

_Static_assert(TSR_SM_COUNT <= 128, "changed-member bitmap holds 128 members");

typedef struct dctx {
    tsr_state_ctx *c;
    tsr_state_shadow *s;
    const tsr_dispatch *d;
    uint32_t n;
    uint64_t changed[2]; /* members this diff changed on the renderer */
    int member;          /* member being diffed */
    int eye_pushed;      /* diff_eye_begin saved the modelview with glPushMatrix */
} dctx;

static inline void emitted(dctx *x)
{
    x->n++;
    x->changed[x->member >> 6] |= 1ull << (x->member & 63);
}

#define NEQ(a, b) (memcmp(&(a), &(b), sizeof(a)) != 0)
#define SYNC(a, b) memcpy(&(a), &(b), sizeof(a))

/* state_diff.c */
void diff_sel_unit(dctx *x, GLuint u);
void diff_sel_unpack_tight(dctx *x, uint8_t swap, uint8_t lsb);
void diff_sel_transfer(dctx *x, const st_transfer *t);
void diff_eye_begin(dctx *x);
void diff_eye_end(dctx *x);

/* state_diff_members.c */
void diff_enables(dctx *x, int word);
void diff_current(dctx *x, int m);
void diff_viewport(dctx *x, int m);
void diff_colorbuf(dctx *x, int m);
void diff_depth(dctx *x);
void diff_stencil(dctx *x);
void diff_fog(dctx *x);
void diff_lighting(dctx *x, int m);
void diff_raster(dctx *x, int m);
void diff_hint(dctx *x);

/* state_diff_objects.c */
void diff_bind_tex(dctx *x, GLuint u, int ti, GLuint name);
void diff_replay(dctx *x, const st_texobj *o, const st_upload *u);
void diff_sync_texture(dctx *x, GLuint u, int ti, st_texobj *o);
void diff_texbind(dctx *x, GLuint u);
void diff_texbind_image(dctx *x);
void diff_texenv(dctx *x, GLuint u);
void diff_texgen(dctx *x, GLuint u);
void diff_buffers(dctx *x);

#endif
