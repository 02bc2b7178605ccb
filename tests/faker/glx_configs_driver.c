/* tests/faker/glx_configs_driver.c — the faker's GLX configs held next to Mesa's.
 *
 *   faker_glx_configs ask LIBGL          answers of the libGL.so.1 at path
 *                                        LIBGL on $DISPLAY, one line each
 *   faker_glx_configs compare MESA FAKER holds FAKER's answers to MESA's
 *
 * `ask` dlopens the library (the system's Mesa, or the faker's) in its own
 * process, sends it the attribute lists below — what real programs send,
 * written from reading their sources — and prints for each the first
 * config's (or the visual's) sizes: "name: r g b a depth stencil
 * doublebuffer accum sample_buffers samples", "name: none", or "name: BAD
 * ..." when a returned
 * config does not meet the request (GLX 1.4: every returned config meets
 * every attribute, sizes as minimums).
 *
 * `compare`'s rule: whenever Mesa returns a config, the faker returns one
 * with the same red, green, blue, alpha, depth, stencil, double-buffer and
 * sample sizes (GLX_SAMPLE_BUFFERS, GLX_SAMPLES), except where `allowed`
 * below says why not. No answer may be BAD.
 * Run on the same default Xvfb, MESA is Mesa's answers there; on an X
 * server without GLX (no Mesa to ask), MESA is the default Xvfb's answers
 * kept from the first run: the sizes a program gets must not depend on
 * the X server's visuals. */
#define GLX_GLXEXT_PROTOTYPES 1
#include <GL/glx.h>
#include <GL/glxext.h>
#include <X11/Xlib.h>
#include <dlfcn.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define END None

typedef struct request {
    const char *name; /* program_what */
    bool visual;      /* glXChooseVisual (GLX 1.2 list), else glXChooseFBConfig */
    int attrs[48];
} request;

/* The list waffle builds for piglit (the requests below say more). */
#define WAFFLE_PIGLIT(depth, stencil, doublebuffer, accum)                                                            \
    {                                                                                                                 \
        GLX_BUFFER_SIZE, 4, GLX_RED_SIZE, 1, GLX_GREEN_SIZE, 1, GLX_BLUE_SIZE, 1, GLX_ALPHA_SIZE, 1, GLX_DEPTH_SIZE,  \
            depth, GLX_STENCIL_SIZE, stencil, GLX_SAMPLE_BUFFERS, 0, GLX_SAMPLES, 0, GLX_DOUBLEBUFFER, doublebuffer,  \
            GLX_ACCUM_RED_SIZE, accum, GLX_ACCUM_GREEN_SIZE, accum, GLX_ACCUM_BLUE_SIZE, accum, GLX_ACCUM_ALPHA_SIZE, \
            accum, GLX_DRAWABLE_TYPE, GLX_WINDOW_BIT, END                                                             \
    }

/* What programs send (the list each program builds for its usual case,
 * and the variants it falls back to). */
static const request requests[] = {
    /* glxgears: glXChooseVisual, RGB 1 1 1, double, depth 1. */
    {"glxgears",
     true,
     {GLX_RGBA, GLX_RED_SIZE, 1, GLX_GREEN_SIZE, 1, GLX_BLUE_SIZE, 1, GLX_DOUBLEBUFFER, GLX_DEPTH_SIZE, 1, END}},
    {"glxgears_stereo",
     true,
     {GLX_RGBA, GLX_RED_SIZE, 1, GLX_GREEN_SIZE, 1, GLX_BLUE_SIZE, 1, GLX_DOUBLEBUFFER, GLX_DEPTH_SIZE, 1, GLX_STEREO,
      END}},
    /* glxinfo: the visual of its test window, single then double. */
    {"glxinfo_single", true, {GLX_RGBA, GLX_RED_SIZE, 1, GLX_GREEN_SIZE, 1, GLX_BLUE_SIZE, 1, END}},
    {"glxinfo_double", true, {GLX_RGBA, GLX_RED_SIZE, 1, GLX_GREEN_SIZE, 1, GLX_BLUE_SIZE, 1, GLX_DOUBLEBUFFER, END}},
    /* waffle (piglit): sizes 1 for what the test asks, GLX_BUFFER_SIZE the
     * sum, no multisample, GLX_WINDOW_BIT; double, single, with depth and
     * stencil or without, with accumulation. */
    {"waffle_piglit_rgba_depth_stencil_double", false, WAFFLE_PIGLIT(1, 1, True, 0)},
    {"waffle_piglit_rgba_single", false, WAFFLE_PIGLIT(0, 0, False, 0)},
    {"waffle_piglit_rgba_depth_double", false, WAFFLE_PIGLIT(1, 0, True, 0)},
    {"waffle_piglit_accum", false, WAFFLE_PIGLIT(0, 0, True, 1)},
    {"waffle_rgba8",
     false,
     {GLX_BUFFER_SIZE, 32, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8, GLX_BLUE_SIZE, 8, GLX_ALPHA_SIZE, 8, GLX_DOUBLEBUFFER,
      True, GLX_DRAWABLE_TYPE, GLX_WINDOW_BIT, END}},
    /* apitrace's glretrace: RGBA8, double or single, depth and stencil 1;
     * its pbuffers the same with GLX_PBUFFER_BIT. */
    {"apitrace_double",
     false,
     {GLX_DRAWABLE_TYPE, GLX_WINDOW_BIT, GLX_RENDER_TYPE, GLX_RGBA_BIT, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8,
      GLX_BLUE_SIZE, 8, GLX_ALPHA_SIZE, 8, GLX_DOUBLEBUFFER, True, GLX_DEPTH_SIZE, 1, GLX_STENCIL_SIZE, 1, END}},
    {"apitrace_single",
     false,
     {GLX_DRAWABLE_TYPE, GLX_WINDOW_BIT, GLX_RENDER_TYPE, GLX_RGBA_BIT, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8,
      GLX_BLUE_SIZE, 8, GLX_ALPHA_SIZE, 8, GLX_DOUBLEBUFFER, False, GLX_DEPTH_SIZE, 1, GLX_STENCIL_SIZE, 1, END}},
    {"apitrace_pbuffer",
     false,
     {GLX_DRAWABLE_TYPE, GLX_PBUFFER_BIT, GLX_RENDER_TYPE, GLX_RGBA_BIT, GLX_RED_SIZE, 1, GLX_GREEN_SIZE, 1,
      GLX_BLUE_SIZE, 1, GLX_ALPHA_SIZE, 1, GLX_DOUBLEBUFFER, True, GLX_DEPTH_SIZE, 1, GLX_STENCIL_SIZE, 1, END}},
    {"apitrace_multisample",
     false,
     {GLX_DRAWABLE_TYPE,
      GLX_WINDOW_BIT,
      GLX_RENDER_TYPE,
      GLX_RGBA_BIT,
      GLX_RED_SIZE,
      8,
      GLX_GREEN_SIZE,
      8,
      GLX_BLUE_SIZE,
      8,
      GLX_ALPHA_SIZE,
      8,
      GLX_DOUBLEBUFFER,
      True,
      GLX_DEPTH_SIZE,
      1,
      GLX_STENCIL_SIZE,
      1,
      GLX_SAMPLE_BUFFERS,
      1,
      GLX_SAMPLES,
      4,
      END}},
    /* GLFW 3: window and RGBA-bit configs; its default hints RGBA8, depth
     * 24, stencil 8, double buffered, no sRGB (it then picks the closest
     * itself, which these minimums stand for). */
    {"glfw_default",
     false,
     {GLX_RENDER_TYPE, GLX_RGBA_BIT, GLX_DRAWABLE_TYPE, GLX_WINDOW_BIT, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8,
      GLX_BLUE_SIZE, 8, GLX_ALPHA_SIZE, 8, GLX_DEPTH_SIZE, 24, GLX_STENCIL_SIZE, 8, GLX_DOUBLEBUFFER, True, END}},
    {"glfw_srgb",
     false,
     {GLX_RENDER_TYPE, GLX_RGBA_BIT, GLX_DRAWABLE_TYPE, GLX_WINDOW_BIT, GLX_RED_SIZE, 8, GLX_GREEN_SIZE, 8,
      GLX_BLUE_SIZE, 8, GLX_DOUBLEBUFFER, True, GLX_FRAMEBUFFER_SRGB_CAPABLE_ARB, True, END}},
    /* SDL2: its defaults (red 3, green 3, blue 2, depth 16, double), first
     * asking a DirectColor visual (for gamma ramps), then any. */
    {"sdl2_directcolor",
     true,
     {GLX_RGBA, GLX_RED_SIZE, 3, GLX_GREEN_SIZE, 3, GLX_BLUE_SIZE, 2, GLX_DOUBLEBUFFER, GLX_DEPTH_SIZE, 16,
      GLX_X_VISUAL_TYPE, GLX_DIRECT_COLOR, END}},
    {"sdl2_default",
     true,
     {GLX_RGBA, GLX_RED_SIZE, 3, GLX_GREEN_SIZE, 3, GLX_BLUE_SIZE, 2, GLX_DOUBLEBUFFER, GLX_DEPTH_SIZE, 16, END}},
    {"sdl2_fbconfig",
     false,
     {GLX_RENDER_TYPE, GLX_RGBA_BIT, GLX_RED_SIZE, 3, GLX_GREEN_SIZE, 3, GLX_BLUE_SIZE, 2, GLX_DOUBLEBUFFER, True,
      GLX_DEPTH_SIZE, 16, END}},
    /* freeglut: GLUT_RGBA | GLUT_DOUBLE | GLUT_DEPTH, then with
     * GLUT_ALPHA | GLUT_STENCIL | GLUT_ACCUM, then GLUT_INDEX. */
    {"freeglut_double_depth",
     false,
     {GLX_RENDER_TYPE, GLX_RGBA_BIT, GLX_RED_SIZE, 1, GLX_GREEN_SIZE, 1, GLX_BLUE_SIZE, 1, GLX_DOUBLEBUFFER, True,
      GLX_DEPTH_SIZE, 1, END}},
    {"freeglut_alpha_stencil_accum",
     false,
     {GLX_RENDER_TYPE,
      GLX_RGBA_BIT,
      GLX_RED_SIZE,
      1,
      GLX_GREEN_SIZE,
      1,
      GLX_BLUE_SIZE,
      1,
      GLX_ALPHA_SIZE,
      1,
      GLX_DOUBLEBUFFER,
      True,
      GLX_DEPTH_SIZE,
      1,
      GLX_STENCIL_SIZE,
      1,
      GLX_ACCUM_RED_SIZE,
      1,
      GLX_ACCUM_GREEN_SIZE,
      1,
      GLX_ACCUM_BLUE_SIZE,
      1,
      GLX_ACCUM_ALPHA_SIZE,
      1,
      END}},
    {"freeglut_single",
     false,
     {GLX_RENDER_TYPE, GLX_RGBA_BIT, GLX_RED_SIZE, 1, GLX_GREEN_SIZE, 1, GLX_BLUE_SIZE, 1, GLX_DOUBLEBUFFER, False,
      END}},
    {"freeglut_index", false, {GLX_RENDER_TYPE, GLX_COLOR_INDEX_BIT, GLX_BUFFER_SIZE, 8, END}},
    /* VTK 9: window and RGBA bits, RGB 1, depth 1, double, alpha 1 when
     * asked, stereo when asked; it retries without alpha. */
    {"vtk_alpha",
     false,
     {GLX_DRAWABLE_TYPE, GLX_WINDOW_BIT, GLX_RENDER_TYPE, GLX_RGBA_BIT, GLX_RED_SIZE, 1, GLX_GREEN_SIZE, 1,
      GLX_BLUE_SIZE, 1, GLX_DEPTH_SIZE, 1, GLX_DOUBLEBUFFER, True, GLX_ALPHA_SIZE, 1, END}},
    {"vtk_no_alpha",
     false,
     {GLX_DRAWABLE_TYPE, GLX_WINDOW_BIT, GLX_RENDER_TYPE, GLX_RGBA_BIT, GLX_RED_SIZE, 1, GLX_GREEN_SIZE, 1,
      GLX_BLUE_SIZE, 1, GLX_DEPTH_SIZE, 1, GLX_DOUBLEBUFFER, True, END}},
    {"vtk_stereo",
     false,
     {GLX_DRAWABLE_TYPE, GLX_WINDOW_BIT, GLX_RENDER_TYPE, GLX_RGBA_BIT, GLX_RED_SIZE, 1, GLX_GREEN_SIZE, 1,
      GLX_BLUE_SIZE, 1, GLX_DEPTH_SIZE, 1, GLX_DOUBLEBUFFER, True, GLX_STEREO, True, END}},
    /* Qt 5/6 (xcb GLX): level 0, window bit, RGB at least 1, alpha 0,
     * double, no stereo, QOpenGLWidget's depth 24 and stencil 8, no
     * multisample. */
    {"qt_default",
     false,
     {GLX_LEVEL,
      0,
      GLX_DRAWABLE_TYPE,
      GLX_WINDOW_BIT,
      GLX_RENDER_TYPE,
      GLX_RGBA_BIT,
      GLX_RED_SIZE,
      1,
      GLX_GREEN_SIZE,
      1,
      GLX_BLUE_SIZE,
      1,
      GLX_ALPHA_SIZE,
      0,
      GLX_DOUBLEBUFFER,
      True,
      GLX_STEREO,
      False,
      GLX_DEPTH_SIZE,
      24,
      GLX_STENCIL_SIZE,
      8,
      GLX_SAMPLE_BUFFERS_ARB,
      0,
      GLX_SAMPLES_ARB,
      0,
      END}},
    {"qt_alpha_pbuffer",
     false,
     {GLX_LEVEL,
      0,
      GLX_DRAWABLE_TYPE,
      GLX_PBUFFER_BIT,
      GLX_RENDER_TYPE,
      GLX_RGBA_BIT,
      GLX_RED_SIZE,
      8,
      GLX_GREEN_SIZE,
      8,
      GLX_BLUE_SIZE,
      8,
      GLX_ALPHA_SIZE,
      8,
      GLX_DOUBLEBUFFER,
      False,
      GLX_STEREO,
      False,
      GLX_DEPTH_SIZE,
      24,
      GLX_STENCIL_SIZE,
      8,
      END}},
    /* xscreensaver-gl (GLX builds): its visual-finding walks glXChooseVisual
     * from depth 24 down with and without stencil. */
    {"xscreensaver_depth_stencil",
     true,
     {GLX_RGBA, GLX_RED_SIZE, 1, GLX_GREEN_SIZE, 1, GLX_BLUE_SIZE, 1, GLX_DEPTH_SIZE, 1, GLX_STENCIL_SIZE, 1,
      GLX_DOUBLEBUFFER, END}},
    /* piglit's samples=N tests (waffle: WAFFLE_SAMPLE_BUFFERS 1 and
     * WAFFLE_SAMPLES N in the list above), and N past what the driver has. */
    {"waffle_piglit_samples_2",
     false,
     {GLX_RED_SIZE,
      1,
      GLX_GREEN_SIZE,
      1,
      GLX_BLUE_SIZE,
      1,
      GLX_ALPHA_SIZE,
      1,
      GLX_DEPTH_SIZE,
      1,
      GLX_STENCIL_SIZE,
      1,
      GLX_SAMPLE_BUFFERS,
      1,
      GLX_SAMPLES,
      2,
      GLX_DOUBLEBUFFER,
      True,
      GLX_DRAWABLE_TYPE,
      GLX_WINDOW_BIT,
      END}},
    {"waffle_piglit_samples_4",
     false,
     {GLX_RED_SIZE,
      1,
      GLX_GREEN_SIZE,
      1,
      GLX_BLUE_SIZE,
      1,
      GLX_ALPHA_SIZE,
      1,
      GLX_DEPTH_SIZE,
      1,
      GLX_STENCIL_SIZE,
      1,
      GLX_SAMPLE_BUFFERS,
      1,
      GLX_SAMPLES,
      4,
      GLX_DOUBLEBUFFER,
      True,
      GLX_DRAWABLE_TYPE,
      GLX_WINDOW_BIT,
      END}},
    {"waffle_piglit_samples_8",
     false,
     {GLX_RED_SIZE,
      1,
      GLX_GREEN_SIZE,
      1,
      GLX_BLUE_SIZE,
      1,
      GLX_ALPHA_SIZE,
      1,
      GLX_DEPTH_SIZE,
      1,
      GLX_STENCIL_SIZE,
      1,
      GLX_SAMPLE_BUFFERS,
      1,
      GLX_SAMPLES,
      8,
      GLX_DOUBLEBUFFER,
      True,
      GLX_DRAWABLE_TYPE,
      GLX_WINDOW_BIT,
      END}},
    /* freeglut GLUT_MULTISAMPLE (4 samples unless glutSetOption says) and
     * GLFW's GLFW_SAMPLES 4 hint, single-buffered and with accumulation
     * (which no multisample config of Mesa's has). */
    {"freeglut_multisample",
     false,
     {GLX_RENDER_TYPE, GLX_RGBA_BIT, GLX_RED_SIZE, 1, GLX_GREEN_SIZE, 1, GLX_BLUE_SIZE, 1, GLX_DOUBLEBUFFER, True,
      GLX_DEPTH_SIZE, 1, GLX_SAMPLE_BUFFERS, 1, GLX_SAMPLES, 4, END}},
    {"glfw_samples_single",
     false,
     {GLX_RENDER_TYPE,
      GLX_RGBA_BIT,
      GLX_DRAWABLE_TYPE,
      GLX_WINDOW_BIT,
      GLX_RED_SIZE,
      8,
      GLX_GREEN_SIZE,
      8,
      GLX_BLUE_SIZE,
      8,
      GLX_ALPHA_SIZE,
      8,
      GLX_DEPTH_SIZE,
      24,
      GLX_STENCIL_SIZE,
      8,
      GLX_DOUBLEBUFFER,
      False,
      GLX_SAMPLE_BUFFERS,
      1,
      GLX_SAMPLES,
      4,
      END}},
    {"multisample_accum",
     false,
     {GLX_RENDER_TYPE, GLX_RGBA_BIT, GLX_DOUBLEBUFFER, True, GLX_ACCUM_RED_SIZE, 1, GLX_SAMPLE_BUFFERS, 1, GLX_SAMPLES,
      2, END}},
    /* glXChooseVisual with GLX 1.2's list and GLX_SAMPLES_ARB (SDL2's
     * SDL_GL_MULTISAMPLESAMPLES 4). */
    {"sdl2_multisample_visual",
     true,
     {GLX_RGBA, GLX_RED_SIZE, 3, GLX_GREEN_SIZE, 3, GLX_BLUE_SIZE, 2, GLX_DOUBLEBUFFER, GLX_DEPTH_SIZE, 16,
      GLX_SAMPLE_BUFFERS_ARB, 1, GLX_SAMPLES_ARB, 4, END}},
    /* A GLX 1.2 list without GLX_RGBA (colour index): Mesa has no
     * colour-index visual and answers with an RGBA one. */
    {"colour_index_visual", true, {GLX_BUFFER_SIZE, 8, GLX_DOUBLEBUFFER, END}},
};
#define NREQUESTS (sizeof requests / sizeof requests[0])

/* Where the faker may answer otherwise than Mesa, and why. */
typedef struct allowance {
    const char *name;
    const char *why;
} allowance;
static const allowance allowed[] = {
    {"glfw_srgb", "no sRGB-capable config: render's default framebuffer is not sRGB (GL_FRAMEBUFFER_SRGB would "
                  "not encode), so none is offered"},
    {"sdl2_directcolor", "no DirectColor visual: the faker's configs are on TrueColor visuals only (it draws no "
                         "pixel on the X server, so gamma ramps would not apply); SDL2 retries without"},
};

typedef struct answer {
    bool any, bad;
    int r, g, b, a, depth, stencil, db, accum, sample_buffers, samples;
    char detail[160];
} answer;

static const int asked_sizes[] = {GLX_RED_SIZE,         GLX_GREEN_SIZE,      GLX_BLUE_SIZE,        GLX_ALPHA_SIZE,
                                  GLX_DEPTH_SIZE,       GLX_STENCIL_SIZE,    GLX_BUFFER_SIZE,      GLX_ACCUM_RED_SIZE,
                                  GLX_ACCUM_GREEN_SIZE, GLX_ACCUM_BLUE_SIZE, GLX_ACCUM_ALPHA_SIZE, GLX_SAMPLE_BUFFERS,
                                  GLX_SAMPLES};

static bool is_size(int attribute)
{
    for (size_t i = 0; i < sizeof asked_sizes / sizeof asked_sizes[0]; i++)
        if (asked_sizes[i] == attribute)
            return true;
    return false;
}

static int run_ask(const char *libgl)
{
    void *gl = dlopen(libgl, RTLD_NOW | RTLD_LOCAL);
    if (!gl) {
        fprintf(stderr, "glx_configs: %s\n", dlerror());
        return 2;
    }
    GLXFBConfig *(*choose_fb)(Display *, int, const int *, int *) =
        (GLXFBConfig * (*)(Display *, int, const int *, int *)) dlsym(gl, "glXChooseFBConfig");
    int (*fb_attrib)(Display *, GLXFBConfig, int, int *) =
        (int (*)(Display *, GLXFBConfig, int, int *))dlsym(gl, "glXGetFBConfigAttrib");
    XVisualInfo *(*choose_vis)(Display *, int, int *) =
        (XVisualInfo * (*)(Display *, int, int *)) dlsym(gl, "glXChooseVisual");
    int (*get_config)(Display *, XVisualInfo *, int, int *) =
        (int (*)(Display *, XVisualInfo *, int, int *))dlsym(gl, "glXGetConfig");
    XVisualInfo *(*fb_visual)(Display *, GLXFBConfig) =
        (XVisualInfo * (*)(Display *, GLXFBConfig)) dlsym(gl, "glXGetVisualFromFBConfig");
    if (!choose_fb || !fb_attrib || !choose_vis || !get_config || !fb_visual) {
        fprintf(stderr, "glx_configs: %s lacks a GLX entry point\n", libgl);
        return 2;
    }
    Display *dpy = XOpenDisplay(NULL);
    if (!dpy) {
        fprintf(stderr, "glx_configs: cannot open display %s\n", XDisplayName(NULL));
        return 2;
    }
    int screen = DefaultScreen(dpy);
    for (size_t i = 0; i < NREQUESTS; i++) {
        const request *q = &requests[i];
        int v[10] = {0};
        static const int what[10] = {GLX_RED_SIZE,       GLX_GREEN_SIZE,   GLX_BLUE_SIZE,    GLX_ALPHA_SIZE,
                                     GLX_DEPTH_SIZE,     GLX_STENCIL_SIZE, GLX_DOUBLEBUFFER, GLX_ACCUM_RED_SIZE,
                                     GLX_SAMPLE_BUFFERS, GLX_SAMPLES};
        char bad[160] = "";
        bool any = false;
        if (q->visual) {
            XVisualInfo *vi = choose_vis(dpy, screen, (int *)q->attrs);
            if (vi) {
                any = true;
                for (int k = 0; k < 10; k++)
                    if (get_config(dpy, vi, what[k], &v[k]) != Success)
                        snprintf(bad, sizeof bad, "glXGetConfig(0x%x) failed", (unsigned)what[k]);
                XFree(vi);
            }
        } else {
            int n = 0;
            GLXFBConfig *list = choose_fb(dpy, screen, q->attrs, &n);
            if (list && n > 0) {
                any = true;
                for (int k = 0; k < 10; k++)
                    fb_attrib(dpy, list[0], what[k], &v[k]);
                /* Every config returned meets every size and the buffering. */
                for (int c = 0; c < n && !bad[0]; c++)
                    for (const int *a = q->attrs; a[0] != None && !bad[0]; a += 2) {
                        int have = 0;
                        fb_attrib(dpy, list[c], a[0], &have);
                        if ((is_size(a[0]) && have < a[1]) || (a[0] == GLX_DOUBLEBUFFER && have != a[1]))
                            snprintf(bad, sizeof bad, "config %d of %d has 0x%x = %d, asked %d", c, n, (unsigned)a[0],
                                     have, a[1]);
                    }
                int drawable = 0;
                fb_attrib(dpy, list[0], GLX_DRAWABLE_TYPE, &drawable);
                XVisualInfo *vi = fb_visual(dpy, list[0]);
                if ((drawable & GLX_WINDOW_BIT) && !vi && !bad[0])
                    snprintf(bad, sizeof bad, "a window config with no visual");
                if (vi)
                    XFree(vi);
            }
            if (list)
                XFree(list);
        }
        if (bad[0])
            printf("%s: BAD %s\n", q->name, bad);
        else if (!any)
            printf("%s: none\n", q->name);
        else
            printf("%s: %d %d %d %d %d %d %d %d %d %d\n", q->name, v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8],
                   v[9]);
    }
    XCloseDisplay(dpy);
    return 0;
}

/* The answer to `name` in file `path`. */
static bool read_answer(const char *path, const char *name, answer *out)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "glx_configs: cannot read %s\n", path);
        exit(2);
    }
    char line[512];
    size_t len = strlen(name);
    bool found = false;
    *out = (answer){0};
    while (!found && fgets(line, sizeof line, f)) {
        if (strncmp(line, name, len) || line[len] != ':')
            continue;
        found = true;
        const char *rest = line + len + 2;
        snprintf(out->detail, sizeof out->detail, "%s", rest);
        out->detail[strcspn(out->detail, "\n")] = 0;
        if (!strncmp(rest, "BAD", 3))
            out->bad = true;
        else if (strncmp(rest, "none", 4))
            out->any = sscanf(rest, "%d %d %d %d %d %d %d %d %d %d", &out->r, &out->g, &out->b, &out->a, &out->depth,
                              &out->stencil, &out->db, &out->accum, &out->sample_buffers, &out->samples) == 10;
    }
    fclose(f);
    return found;
}

static const char *allowance_of(const char *name)
{
    for (size_t i = 0; i < sizeof allowed / sizeof allowed[0]; i++)
        if (!strcmp(allowed[i].name, name))
            return allowed[i].why;
    return NULL;
}

/* Differences of size allowed for any request, and why. */
static const char *size_allowance(const answer *m, const answer *f)
{
    bool colour = f->r == m->r && f->g == m->g && f->b == m->b && f->a == m->a;
    bool depth = f->depth == m->depth;
    bool rest = f->stencil == m->stencil && f->db == m->db && f->sample_buffers == m->sample_buffers &&
                f->samples == m->samples;
    bool rgb10 =
        m->r == 10 && m->g == 10 && m->b == 10 && m->a == 2 && f->r == 8 && f->g == 8 && f->b == 8 && f->a == 8;
    bool depth32 = m->depth == 32 && f->depth == 24;
    if (rest && (colour || rgb10) && (depth || depth32) && (rgb10 || depth32))
        return rgb10 ? "RGB10_A2 where Mesa sorts its 10-bit configs first: render draws RGBA8, so the faker has "
                       "no 10-bit config and gives its largest, RGBA8 (the request is met)"
                     : "depth 32 where Mesa sorts its 32-bit depth buffer first: render's depth buffer is 24 bits "
                       "(OSMesa), the faker's largest (the request is met)";
    return NULL;
}

static int run_compare(const char *mesa_path, const char *faker_path)
{
    int failures = 0, held = 0, excused = 0;
    for (size_t i = 0; i < NREQUESTS; i++) {
        const char *name = requests[i].name;
        answer m, f;
        if (!read_answer(mesa_path, name, &m) || !read_answer(faker_path, name, &f)) {
            printf("FAIL %s: no answer\n", name);
            failures++;
            continue;
        }
        if (m.bad || f.bad) {
            printf("FAIL %s: mesa '%s', faker '%s'\n", name, m.detail, f.detail);
            failures++;
            continue;
        }
        if (!m.any) {
            printf("ok   %-40s mesa none, faker %s\n", name, f.detail);
            held++;
            continue;
        }
        bool same = f.any && f.r == m.r && f.g == m.g && f.b == m.b && f.a == m.a && f.depth == m.depth &&
                    f.stencil == m.stencil && f.db == m.db && f.sample_buffers == m.sample_buffers &&
                    f.samples == m.samples;
        const char *why = allowance_of(name);
        if (!why && f.any)
            why = size_allowance(&m, &f);
        if (same) {
            printf("ok   %-40s %s\n", name, f.detail);
            held++;
        } else if (why) {
            printf("diff %-40s mesa %s, faker %s: %s\n", name, m.detail, f.detail, why);
            excused++;
        } else {
            printf("FAIL %-40s mesa %s, faker %s (r g b a depth stencil db accum sample_buffers samples)\n", name,
                   m.detail, f.detail);
            failures++;
        }
    }
    printf("%d held, %d allowed differences, %d failed\n", held, excused, failures);
    return failures ? 1 : 0;
}

int main(int argc, char **argv)
{
    if (argc == 3 && !strcmp(argv[1], "ask"))
        return run_ask(argv[2]);
    if (argc == 4 && !strcmp(argv[1], "compare"))
        return run_compare(argv[2], argv[3]);
    fprintf(stderr, "usage: %s ask LIBGL | compare MESA_ANSWERS FAKER_ANSWERS\n", argv[0]);
    return 2;
}
