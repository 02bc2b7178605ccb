/* faker/configs.c — the framebuffer formats the faker offers as GLX
 * FBConfigs and EGLConfigs, and the X visuals they are given. Owns a
 * constant table only; the per-display config tables are glx.c's and
 * egl.c's, which match and sort them by GLX 1.4's and EGL 1.5's rules.
 *
 * What render honours: its OSMesa contexts are RGBA8 with depth 24,
 * stencil 8 and 16-bit accumulation (spus/render/render.c), whatever the
 * program's config, and draw no pixel on the X server; so every format
 * below can be drawn, whatever the depth of the X visual it is given (a
 * format with alpha on a depth-24 visual, as Mesa's GLX offers on Xvfb).
 * A format smaller than render's buffers (no alpha, depth 0 or 16, no
 * stencil, no accumulation) is kept by having more (docs/faker.md says
 * what a program can tell). Multisample formats have 4 samples, the one
 * count llvmpipe has (GL_MAX_SAMPLES 4 in OSMesa, and Mesa's GLX on Xvfb
 * offers 4 and no other) and none has accumulation, as Mesa's: render
 * draws such a window into 4-sample renderbuffers (WindowSamplesTSR).
 * Formats render cannot draw are not offered: stereo, colour index, sRGB,
 * float, 10-bit colour — a program asking for them finds no config, as
 * on a driver without the feature. Never reads or writes GL state, never sends an X request
 * other than XGetVisualInfo's (which Xlib answers from the Display). */
#include <X11/Xutil.h>
#include <stdlib.h>

#include "configs.h"

/* In the order the visuals are handed out: the first format is what
 * Mesa's GLX gives the default visual (RGBA8, double-buffered, depth 24,
 * stencil 8, no accumulation), so a screen with one usable visual (an X
 * server without GLX) has it as that visual's own config. */
#define FORMAT(accum, depth, stencil, samples)                                             \
    {8, depth, stencil, accum, true, samples}, {8, depth, stencil, accum, false, samples}, \
        {0, depth, stencil, accum, true, samples},                                         \
    {                                                                                      \
        0, depth, stencil, accum, false, samples                                           \
    }
#define FORMATS_WITH(accum, samples)                                                             \
    FORMAT(accum, 24, 8, samples), FORMAT(accum, 24, 0, samples), FORMAT(accum, 16, 0, samples), \
        FORMAT(accum, 0, 0, samples)
/* The multisample ones last, so the single-sampled formats keep the
 * visuals they had before there were any. */
static const tsr_faker_format formats[TSR_FAKER_FORMATS] = {FORMATS_WITH(0, 0), FORMATS_WITH(16, 0),
                                                            FORMATS_WITH(0, 4)};

const tsr_faker_format *tsr_faker_format_at(int i) { return i >= 0 && i < TSR_FAKER_FORMATS ? &formats[i] : NULL; }

/* Usable: TrueColor, 8 bits a channel in the usual places. */
static bool usable(const XVisualInfo *v)
{
    return v->class == TrueColor && (v->depth == 24 || v->depth == 32) && v->bits_per_rgb == 8 &&
           v->red_mask == 0xff0000 && v->green_mask == 0xff00 && v->blue_mask == 0xff;
}

int tsr_faker_visuals(Display *dpy, int screen, XVisualInfo **out)
{
    *out = NULL;
    XVisualInfo tmpl = {.screen = screen};
    int n = 0;
    XVisualInfo *all = XGetVisualInfo(dpy, VisualScreenMask, &tmpl, &n);
    XVisualInfo *list = all ? malloc((size_t)n * sizeof *list) : NULL;
    int kept = 0;
    VisualID def = XVisualIDFromVisual(DefaultVisual(dpy, screen));
    /* The default visual first, then depth 24, then depth 32. */
    for (int pass = 0; list && pass < 3; pass++)
        for (int i = 0; i < n; i++) {
            if (!usable(&all[i]))
                continue;
            bool is_def = all[i].visualid == def;
            if ((pass == 0 && is_def) || (pass == 1 && !is_def && all[i].depth == 24) ||
                (pass == 2 && !is_def && all[i].depth == 32))
                list[kept++] = all[i];
        }
    if (all)
        XFree(all);
    if (!kept) {
        free(list);
        return 0;
    }
    *out = list;
    return kept;
}
