/* examples/common/exapp.h — the tiny harness every example program shares.
 * Owns the command line (--frames, --size, --out, --detail, --chain), the GL context
 * and frame output; the example owns only its drawing, written as ordinary
 * GL 1.x code. Never draws anything itself.
 *
 * Every example is built twice from the same source:
 *   NAME-native  links libOSMesa: an OSMesa context (RGBA, depth 24,
 *                stencil 8, accum 0 — exactly what the render SPU creates)
 *                and PNG frames written by the harness. The reference.
 *   NAME         links libtessera_gl: GL calls enter the SPU chain given by
 *                --chain, else $TESSERA_CHAIN, else
 *                "render output=out/NAME-%04d.png" (--out changes that
 *                default's output). The harness sends WindowCreateTSR at
 *                start and SwapBuffersTSR after every frame.
 * Frames are numbered from 0 and written to the printf-style pattern
 * (one %d conversion) with the frame number. When the harness's own
 * default pattern is used it creates the out/ directory. */
#ifndef EXAPP_H
#define EXAPP_H

#include <stdbool.h>

typedef struct exapp_backend exapp_backend;

typedef struct exapp {
    const char *name;  /* example name, e.g. "spheres" */
    int width, height; /* window size (--size WxH) */
    int frames;        /* frames to draw (--frames N) */
    int frame;         /* number of the next frame to be swapped, from 0 */
    int detail;        /* --detail N (1..8): how finely examples that can vary it draw */
    int part, parts;   /* --part K/N (sort-last): draw only share K of N; 0/1 by default */
    int exit_code;     /* what main returns: 0, 1 runtime failure, 2 usage */
    exapp_backend *backend;
} exapp;

/* Parses the command line and makes a GL context current on this thread.
 * Returns true to go on drawing; false means main should return
 * app->exit_code now (0 after --help, 2 on bad arguments, 1 when the
 * context or chain could not be made; a one-line message was printed). */
bool exapp_init(exapp *app, const char *name, int argc, char **argv, int default_width, int default_height);

/* As exapp_init, with one example-specific flag (no value): `flag`
 * (e.g. "--overlap") sets *on, and `help` (one line, indented like the
 * others) is added to --help. */
bool exapp_init_flag(exapp *app, const char *name, int argc, char **argv, int default_width, int default_height,
                     const char *flag, const char *help, bool *on);

/* An example-specific option: `name` (e.g. "--orbit") takes a number in
 * [min, max] into *value, or, with value NULL, is a flag; *given says
 * whether it was on the command line. `help` is its --help text (lines
 * indented like the others, no final newline). */
typedef struct exapp_option {
    const char *name, *help;
    double min, max;
    double *value;
    bool *given;
} exapp_option;

/* As exapp_init, with `count` example-specific options (a bad value is a
 * usage error naming the option and the range). */
bool exapp_init_options(exapp *app, const char *name, int argc, char **argv, int default_width, int default_height,
                        const exapp_option *options, int count);

/* Ends the frame: the native build finishes and writes the PNG, the
 * tessera build sends SwapBuffersTSR(0, 0). Returns false (exit_code = 1,
 * message printed) when the frame could not be written. */
bool exapp_swap(exapp *app);

/* Sort-last parts (--part K/N): the example numbers its primitives
 * 0..total-1 in the order the whole scene draws them; share K is the
 * contiguous run [K*total/N, (K+1)*total/N), so the N shares are disjoint,
 * cover every primitive, and drawn in rank order give the whole scene's
 * draw order. Sets *first and returns how many of the `total` are this
 * process's (all of them without --part). */
long exapp_part_range(const exapp *app, long total, long *first);

/* Releases the context / chain; returns app->exit_code. */
int exapp_finish(exapp *app);

#endif
