/* examples/common/exapp.c — the example harness: command line, GL context,
 * frame output. Compiled twice: with EXAPP_NATIVE (OSMesa context, PNGs
 * written here: the reference) and without (GL calls enter a tessera chain
 * through libtessera_gl). Owns the context/chain and opts the program in
 * to the removal of PNG temporaries on fatal signals; never draws. */
#include "exapp.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <GL/gl.h>

#include "tessera/error.h"
#include "tessera/image.h"

#ifdef EXAPP_NATIVE
#include <GL/osmesa.h>
#else
#include "tessera/chain.h"
#include "tessera/glapi.h"
#include "tessera/gltsr_gen.h" /* glWindowCreateTSR, glSwapBuffersTSR, ... */
#endif

#define EXAPP_DEFAULT_FRAMES 4

struct exapp_backend {
    char default_pattern[256]; /* "out/NAME-%04d.png" */
    const char *out_pattern;   /* --out, or default_pattern */
    bool out_alpha;            /* --out-alpha: PNGs keep the framebuffer's alpha */
#ifdef EXAPP_NATIVE
    OSMesaContext context;
    unsigned char *buffer; /* width * height RGBA, bottom row first */
#else
    const char *chain_text; /* --chain, $TESSERA_CHAIN or built default */
    char default_chain[400];
    tsr_chain *chain;
#endif
};

static void exapp_usage(const exapp *app, FILE *out, const char *flag_help)
{
    fprintf(out,
            "usage: %s [--frames N] [--size WxH] [--out PATTERN] [--out-alpha] [--detail N] [--part K/N]"
#ifndef EXAPP_NATIVE
            " [--chain \"SPU CHAIN\"]"
#endif
            "\n\n"
            "Tessera example '%s': draws N animated frames with OpenGL 1.x.\n\n"
            "options:\n"
            "  --frames N      frames to draw (default %d)\n"
            "  --size WxH      window size (default %dx%d)\n"
            "  --out PATTERN   frame files, one %%d for the frame number\n"
            "                  (default out/%s-%%04d.png; out/ is created)\n"
            "  --out-alpha     write the framebuffer's alpha too (RGBA PNGs); default:\n"
            "                  RGB, what a window shows\n"
            "  --detail N      scene detail, 1..8 (default 1): the isosurface's grids are\n"
            "                  N times finer (about N*N times the triangles)\n"
            "  --part K/N      sort-last: draw only share K (0..N-1) of N disjoint shares\n"
            "                  of the scene's primitives (contiguous runs in draw order;\n"
            "                  the union of all N equals the whole scene)\n"
#ifndef EXAPP_NATIVE
            "  --chain TEXT    SPU chain the GL calls enter (default: $TESSERA_CHAIN,\n"
            "                  else \"render output=PATTERN\")\n"
#else
            "                  This is the native build: OSMesa renders directly.\n"
#endif
            "%s%s"
            "  -h, --help      show this help\n",
            app->name, app->name, EXAPP_DEFAULT_FRAMES, app->width, app->height, app->name, flag_help ? flag_help : "",
            flag_help ? "\n" : "");
}

static bool parse_int(const char *text, int min, int max, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (errno || end == text || *end || v < min || v > max)
        return false;
    *out = (int)v;
    return true;
}

static bool parse_size(const char *text, int *w, int *h)
{
    char buf[64];
    const char *x = strchr(text, 'x');
    if (!x || (size_t)(x - text) >= sizeof buf)
        return false;
    memcpy(buf, text, (size_t)(x - text));
    buf[x - text] = '\0';
    return parse_int(buf, 1, 8192, w) && parse_int(x + 1, 1, 8192, h);
}

static bool parse_part(const char *text, int *part, int *parts)
{
    char buf[64];
    const char *slash = strchr(text, '/');
    if (!slash || (size_t)(slash - text) >= sizeof buf)
        return false;
    memcpy(buf, text, (size_t)(slash - text));
    buf[slash - text] = '\0';
    return parse_int(slash + 1, 1, 1048576, parts) && parse_int(buf, 0, *parts - 1, part);
}

long exapp_part_range(const exapp *app, long total, long *first)
{
    /* long long: total * parts must not overflow for big meshes. */
    long long lo = (long long)total * app->part / app->parts;
    long long hi = (long long)total * (app->part + 1) / app->parts;
    *first = (long)lo;
    return (long)(hi - lo);
}

static bool fail(exapp *app, int code, const char *msg, const char *detail)
{
    fprintf(stderr, "%s: %s%s%s\n", app->name, msg, detail ? ": " : "", detail ? detail : "");
    app->exit_code = code;
    return false;
}

static bool backend_start(exapp *app);

bool exapp_init(exapp *app, const char *name, int argc, char **argv, int default_width, int default_height)
{
    return exapp_init_flag(app, name, argc, argv, default_width, default_height, NULL, NULL, NULL);
}

bool exapp_init_flag(exapp *app, const char *name, int argc, char **argv, int default_width, int default_height,
                     const char *flag, const char *help, bool *on)
{
    exapp_option one = {flag, help, 0, 0, NULL, on};
    return exapp_init_options(app, name, argc, argv, default_width, default_height, &one, flag ? 1 : 0);
}

/* The options' help lines, one block (static: --help prints and exits). */
static const char *options_help(const exapp_option *options, int count)
{
    static char text[2048];
    size_t at = 0;
    text[0] = '\0';
    for (int k = 0; k < count; k++)
        if (options[k].help && at < sizeof text)
            at += (size_t)snprintf(text + at, sizeof text - at, "%s%s", k ? "\n" : "", options[k].help);
    return count ? text : NULL;
}

bool exapp_init_options(exapp *app, const char *name, int argc, char **argv, int default_width, int default_height,
                        const exapp_option *options, int count)
{
    for (int k = 0; k < count; k++)
        if (options[k].given)
            *options[k].given = false;
    /* The PNG temporaries are the program's to remove when SIGTERM, SIGINT
     * or SIGHUP end it (tessera/image.h); only the first call acts. */
    tsr_image_pending_remove_on_signals(NULL);
    memset(app, 0, sizeof *app);
    app->name = name;
    app->width = default_width;
    app->height = default_height;
    app->frames = EXAPP_DEFAULT_FRAMES;
    app->detail = 1;
    app->part = 0;
    app->parts = 1;
    app->backend = calloc(1, sizeof *app->backend);
    if (!app->backend)
        return fail(app, 1, "out of memory", NULL);
    exapp_backend *b = app->backend;
    snprintf(b->default_pattern, sizeof b->default_pattern, "out/%s-%%04d.png", name);
    b->out_pattern = b->default_pattern;
#ifndef EXAPP_NATIVE
    const char *chain_option = NULL;
#endif
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (!strcmp(arg, "-h") || !strcmp(arg, "--help")) {
            exapp_usage(app, stdout, options_help(options, count));
            app->exit_code = 0;
            return false;
        }
        const exapp_option *opt = NULL;
        for (int k = 0; k < count && !opt; k++)
            if (options[k].name && !strcmp(arg, options[k].name))
                opt = &options[k];
        if (opt) {
            if (opt->given)
                *opt->given = true;
            if (!opt->value)
                continue;
            char *end;
            if (i + 1 >= argc)
                return fail(app, 2, "option needs a value", arg);
            const char *value = argv[++i];
            errno = 0;
            double v = strtod(value, &end);
            if (errno || end == value || *end || !(v >= opt->min && v <= opt->max)) {
                char why[160];
                snprintf(why, sizeof why, "bad %s (expected a number in %g..%g)", arg, opt->min, opt->max);
                return fail(app, 2, why, value);
            }
            *opt->value = v;
            continue;
        }
        if (!strcmp(arg, "--out-alpha")) {
            b->out_alpha = true;
            continue;
        }
        bool known = !strcmp(arg, "--frames") || !strcmp(arg, "--size") || !strcmp(arg, "--out") ||
                     !strcmp(arg, "--detail") || !strcmp(arg, "--part");
#ifndef EXAPP_NATIVE
        known = known || !strcmp(arg, "--chain");
#endif
        if (!known)
            return fail(app, 2, "unknown option (see --help)", arg);
        if (i + 1 >= argc)
            return fail(app, 2, "option needs a value", arg);
        const char *value = argv[++i];
        if (!strcmp(arg, "--frames")) {
            if (!parse_int(value, 0, 1000000, &app->frames))
                return fail(app, 2, "bad --frames (expected 0..1000000)", value);
        } else if (!strcmp(arg, "--size")) {
            if (!parse_size(value, &app->width, &app->height))
                return fail(app, 2, "bad --size (expected WxH, 1..8192 each)", value);
        } else if (!strcmp(arg, "--out")) {
            b->out_pattern = value;
        } else if (!strcmp(arg, "--detail")) {
            if (!parse_int(value, 1, 8, &app->detail))
                return fail(app, 2, "bad --detail (expected 1..8)", value);
        } else if (!strcmp(arg, "--part")) {
            if (!parse_part(value, &app->part, &app->parts))
                return fail(app, 2, "bad --part (expected K/N, 0 <= K < N <= 1048576)", value);
        }
#ifndef EXAPP_NATIVE
        else {
            chain_option = value;
        }
#endif
    }
    char probe[PATH_MAX];
    tsr_error err = {0};
    if (b->out_pattern[0] && tsr_image_frame_path(probe, sizeof probe, b->out_pattern, 0, &err) != TSR_OK)
        return fail(app, 2, err.message, NULL);
    bool writes_default_output = b->out_pattern == b->default_pattern;
#ifndef EXAPP_NATIVE
    if (chain_option) {
        b->chain_text = chain_option;
        writes_default_output = false;
    } else if (getenv("TESSERA_CHAIN") && getenv("TESSERA_CHAIN")[0]) {
        b->chain_text = getenv("TESSERA_CHAIN");
        writes_default_output = false;
    } else {
        if (strchr(b->out_pattern, '"'))
            return fail(app, 2, "--out must not contain '\"'", b->out_pattern);
        snprintf(b->default_chain, sizeof b->default_chain, "render output=\"%s\"%s", b->out_pattern,
                 b->out_alpha ? " output_alpha=1" : "");
        b->chain_text = b->default_chain;
    }
#endif
    if (writes_default_output && mkdir("out", 0777) != 0 && errno != EEXIST)
        return fail(app, 1, "cannot create directory out", strerror(errno));
    return backend_start(app);
}

#ifdef EXAPP_NATIVE

static bool backend_start(exapp *app)
{
    exapp_backend *b = app->backend;
    /* Same attributes as spus/render: RGBA, depth 24, stencil 8, accum 16. */
    b->context = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 16, NULL);
    if (!b->context)
        return fail(app, 1, "OSMesaCreateContextExt failed", NULL);
    b->buffer = calloc((size_t)app->width * (size_t)app->height, 4);
    if (!b->buffer)
        return fail(app, 1, "out of memory for the framebuffer", NULL);
    if (!OSMesaMakeCurrent(b->context, b->buffer, GL_UNSIGNED_BYTE, app->width, app->height))
        return fail(app, 1, "OSMesaMakeCurrent failed", NULL);
    return true;
}

bool exapp_swap(exapp *app)
{
    exapp_backend *b = app->backend;
    glFinish();
    int frame = app->frame++;
    if (!b->out_pattern[0])
        return true;
    char path[PATH_MAX];
    tsr_error err = {0};
    if (tsr_image_frame_path(path, sizeof path, b->out_pattern, frame, &err) != TSR_OK)
        return fail(app, 1, err.message, NULL);
    size_t stride = (size_t)app->width * 4;
    int rc = tsr_image_write_png_pixels(b->buffer, app->width, app->height, stride, true, b->out_alpha, path, &err);
    if (rc != TSR_OK)
        return fail(app, 1, err.message, NULL);
    return true;
}

int exapp_finish(exapp *app)
{
    exapp_backend *b = app->backend;
    if (b) {
        if (b->context)
            OSMesaDestroyContext(b->context);
        free(b->buffer);
        free(b);
        app->backend = NULL;
    }
    return app->exit_code;
}

#else /* tessera build */

static bool backend_start(exapp *app)
{
    exapp_backend *b = app->backend;
    tsr_error err = {0};
    b->chain = tsr_chain_create(b->chain_text, &err);
    if (!b->chain)
        return fail(app, 1, err.message, NULL);
    tsr_gl_make_current(tsr_chain_head(b->chain));
    glWindowCreateTSR(0, app->width, app->height);
    return true;
}

bool exapp_swap(exapp *app)
{
    glSwapBuffersTSR(0, 0);
    app->frame++;
    return true;
}

int exapp_finish(exapp *app)
{
    exapp_backend *b = app->backend;
    if (b) {
        if (b->chain) {
            glWindowDestroyTSR(0);
            tsr_gl_make_current(NULL);
            tsr_chain_destroy(b->chain);
        }
        free(b);
        app->backend = NULL;
    }
    return app->exit_code;
}

#endif
