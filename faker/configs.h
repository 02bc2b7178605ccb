/* faker/configs.h — the formats the faker offers and the X visuals they
 * are given (configs.c), shared by glx.c and egl.c. Never installed. */
#ifndef TSR_FAKER_CONFIGS_H
#define TSR_FAKER_CONFIGS_H

#include <X11/Xutil.h>
#include <stdbool.h>

#include "faker_gl.h"

/* RGB 8 8 8 always; the rest: */
typedef struct tsr_faker_format {
    int alpha, depth, stencil, accum; /* bits (accum: per channel) */
    bool doublebuffer;
    int samples; /* 0: single-sampled; else GLX/EGL_SAMPLES, with one sample buffer */
} tsr_faker_format;

#define TSR_FAKER_FORMATS 48

/* Format i (0..TSR_FAKER_FORMATS-1), in the order visuals are handed out;
 * NULL out of range. */
TSR_FAKER_API const tsr_faker_format *tsr_faker_format_at(int i);

/* The X visuals of `screen` that configs are given (TrueColor, depth 24
 * or 32, 8 bits a channel), the default visual first. *out is malloc'ed
 * (free it), NULL when there is none. Returns how many. */
TSR_FAKER_API int tsr_faker_visuals(Display *dpy, int screen, XVisualInfo **out);

#endif
