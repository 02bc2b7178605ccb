/* tests/render/tiles_driver.c — drives render SPU chains as tile servers
 * and checks them against a full-window render of the same scene:
 *
 *   tiles_driver compare DIR WxH FRAMES [--option] [--contexts] [--loopback] SERVER...
 *       Renders FRAMES frames of the test scene once at full window size
 *       (DIR/ref-N.png), then once per SERVER: a chain "render" that gets
 *       TilesTSR before every frame (or, with --option, its first tiles as
 *       the `tiles` option and no TilesTSR before frame 0). SERVER lists the
 *       tiles per frame: "X:Y:W:H,X:Y:W:H/X:Y:W:H/..." — frame N takes the
 *       Nth '/' part (the last one for later frames); "-" is count 0 (the
 *       whole window). Every tile PNG the server wrote
 *       (DIR/sK-N.png, DIR/sK-N-tI.png with several tiles) must equal the
 *       same pixels of the reference: prints one line per tile with
 *       differing_pixels and exits 1 on any difference or missing file.
 *       --loopback: the servers' chains start with the loopback SPU, so
 *       TilesTSR and the scissor queries cross the wire format (packed,
 *       unpacked, replies returned).
 *       --contexts: the scene is drawn by two contexts (ContextCreateTSR,
 *       MakeCurrentTSR), each with its own scissor state, into one
 *       framebuffer, in the reference too.
 *       The scene also checks that glGet/glIsEnabled of the scissor give
 *       the application's values on the tile servers.
 *   tiles_driver parse
 *       Checks tsr_tiles_parse (tessera/tiles.h) on good and bad texts.
 *   tiles_driver crop IN.png X Y W H OUT.png
 *       Writes the rectangle X,Y,W,H (GL window pixels, origin bottom-left)
 *       of IN.png as OUT.png (to compare a tile with `tessera imgdiff`).
 *   tiles_driver rss WxH FRAMES TILES [--tilestsr] [--contexts]
 *       Renders FRAMES frames with TILES ("-": none, the whole window; as
 *       the `tiles` option, or with --tilestsr as TilesTSR after the
 *       window exists; --contexts: two contexts, shared mode first) and
 *       prints the process's resident memory after the last frame (chain
 *       still alive) and its peak: "vmrss_mb: X" and "vmhwm_mb: Y".
 *
 * The scene: a full clear, a clear inside an application scissor box that
 * crosses tile borders, triangles in perspective drawn inside a pushed
 * scissor (PushAttrib/PopAttrib of GL_SCISSOR_BIT and GL_ENABLE_BIT), wide
 * lines and large points centred on and just beside the quarter lines of
 * the window (where tile borders are), a display list that sets its own
 * scissor, and glDrawPixels/glBitmap across the centre. */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>

#include "tessera/chain.h"
#include "tessera/glapi.h"
#include "harness.h"
#include "tessera/gltsr_gen.h"
#include "tessera/image.h"
#include "tessera/tiles.h"

#define MAX_FRAMES 8

static int measure; /* rss: read memory before the chain goes */
static double measured_rss, measured_hwm;

static double status_mb(const char *key)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    double kb = -1;
    size_t len = strlen(key);
    while (f && fgets(line, sizeof line, f))
        if (!strncmp(line, key, len) && line[len] == ':')
            kb = atof(line + len + 1);
    if (f)
        fclose(f);
    return kb / 1024.0;
}

static void expect_scissor(const char *where, const GLint want[4], GLboolean want_on)
{
    GLint box[4] = {-1, -1, -1, -1};
    glGetIntegerv(GL_SCISSOR_BOX, box);
    GLboolean on = glIsEnabled(GL_SCISSOR_TEST);
    GLfloat fbox[4] = {0};
    glGetFloatv(GL_SCISSOR_BOX, fbox);
    CHECK(!memcmp(box, want, sizeof box) && on == want_on && (GLint)fbox[2] == want[2],
          "%s: glGet scissor gave [%d %d %d %d] %s, want [%d %d %d %d] %s", where, box[0], box[1], box[2], box[3],
          on ? "on" : "off", want[0], want[1], want[2], want[3], want_on ? "on" : "off");
}

/* Part `part` of the scene (0: background and scissored clears, 1: the
 * rest); `check`: query the scissor state (a server's answers must be the
 * application's). */
static void draw_part(int part, int frame, int w, int h, GLuint list)
{
    float t = (float)frame;
    if (part == 0) {
        glViewport(0, 0, w, h);
        glDisable(GL_SCISSOR_TEST);
        glClearColor(0.1f, 0.15f + 0.05f * t, 0.2f, 1);
        glClearDepth(1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        /* A full-window clear with the application's scissor on: only its
         * box (crossing the centre, where 2x2 tiles meet) changes. */
        GLint box[4] = {w / 3 + frame, h / 4, w / 3, h / 2 - frame};
        glEnable(GL_SCISSOR_TEST);
        glScissor(box[0], box[1], box[2], box[3]);
        glClearColor(0.7f, 0.2f, 0.1f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        expect_scissor("after scissored clear", box, GL_TRUE);
        return;
    }
    GLint box[4] = {w / 5, h / 6, 3 * w / 5, 2 * h / 3};
    glEnable(GL_SCISSOR_TEST);
    glScissor(box[0], box[1], box[2], box[3]);
    glEnable(GL_DEPTH_TEST);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glFrustum(-1.0, 1.0, -0.75, 0.75, 1.5, 20.0);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glTranslatef(0, 0, -4);
    glRotatef(11.0f * t + 7.0f, 0.3f, 1, 0.2f);

    /* Triangles inside a pushed scissor box of their own. */
    glPushAttrib(GL_SCISSOR_BIT);
    glScissor(w / 8, h / 8, 3 * w / 4 + 1, 3 * h / 4 - 1);
    glBegin(GL_TRIANGLES);
    for (int i = 0; i < 40; i++) {
        float a = (float)i * 0.61f, r = 0.3f + 0.03f * (float)i;
        glColor3f(0.5f + 0.5f * (float)(i % 3) / 2, (float)i / 40.0f, 1.0f - (float)i / 40.0f);
        glVertex3f(r * (a - 6.0f) / 6.0f, -1.1f + 0.05f * (float)i, 0.3f * (float)(i % 5) - 0.6f);
        glVertex3f(1.2f - 0.06f * (float)i, 0.9f - 0.04f * (float)i, 0.1f * (float)(i % 7));
        glVertex3f(-1.3f + 0.07f * (float)i, 0.02f * (float)i - 0.8f, -0.2f * (float)(i % 3));
    }
    glEnd();
    glPopAttrib();
    expect_scissor("after PopAttrib(GL_SCISSOR_BIT)", box, GL_TRUE);

    /* Wide lines and large points on and beside the quarter lines, drawn
     * without the application's scissor (pushed with GL_ENABLE_BIT). */
    glPushAttrib(GL_ENABLE_BIT);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_DEPTH_TEST);
    expect_scissor("scissor disabled inside PushAttrib(GL_ENABLE_BIT)", box, GL_FALSE);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0, w, 0, h, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glLineWidth(7.0f);
    glBegin(GL_LINES);
    for (int q = 1; q < 4; q++) {
        float x = (float)(q * w) / 4.0f, y = (float)(q * h) / 4.0f;
        glColor3f(1, 1, 0.2f * (float)q);
        glVertex2f(x + 2.5f + t, 0);
        glVertex2f(x - 3.5f, (float)h);
        glColor3f(0.2f * (float)q, 1, 1);
        glVertex2f(0, y - 2.5f);
        glVertex2f((float)w, y + 3.0f + t);
    }
    glEnd();
    glPointSize(15.0f);
    glBegin(GL_POINTS);
    for (int q = 1; q < 4; q++)
        for (int k = -2; k <= 2; k++) {
            float x = (float)(q * w) / 4.0f + 3.0f * (float)k + 0.5f;
            float y = (float)(q * h) / 4.0f - 2.0f * (float)k;
            glColor3f(0.3f * (float)(k + 2) / 2, 0.2f * (float)q, 1);
            glVertex2f(x, (float)h * (0.1f + 0.2f * (float)(k + 2)));
            glVertex2f((float)w * (0.1f + 0.2f * (float)(k + 2)), y);
            glVertex2f(x, y);
        }
    glEnd();
    /* Pixels placed across the centre. */
    /* Bitmap rows are 2 bytes, padded to GL_UNPACK_ALIGNMENT 4. */
    static GLubyte pixels[24 * 18 * 4], bits[16 * 4];
    for (int i = 0; i < 24 * 18 * 4; i++)
        pixels[i] = (GLubyte)(i * 7 + frame);
    for (int i = 0; i < (int)sizeof bits; i++)
        bits[i] = (GLubyte)(0xA5 ^ i);
    glRasterPos2i(w / 2 - 12, h / 2 - 9);
    glDrawPixels(24, 18, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    glColor3f(1, 1, 1);
    glRasterPos2i(w / 4 - 8, 3 * h / 4 - 8);
    glBitmap(16, 16, 0, 0, 0, 0, bits);
    glPopAttrib();
    expect_scissor("after PopAttrib(GL_ENABLE_BIT)", box, GL_TRUE);

    /* A list compiled and executed at once (frame 0), then called: it
     * pushes, scissors, draws and pops, so the scissor is as before. */
    glEnable(GL_SCISSOR_TEST);
    glScissor(box[0], box[1], box[2], box[3]);
    if (glIsList(list + 1)) {
        GLuint id = 1;
        glListBase(list);
        glCallLists(1, GL_UNSIGNED_INT, &id);
        glListBase(0);
    } else {
        glNewList(list + 1, GL_COMPILE_AND_EXECUTE);
        glPushAttrib(GL_SCISSOR_BIT);
        glScissor(w / 10, h / 2, w / 2, h / 3);
        glBegin(GL_TRIANGLES);
        glColor3f(0.2f, 0.9f, 0.3f);
        glVertex2f(0, 0);
        glVertex2f((float)w, (float)h * 0.6f);
        glVertex2f((float)w * 0.2f, (float)h);
        glEnd();
        glPopAttrib();
        glEndList();
    }
    expect_scissor("after the compile-and-execute list", box, GL_TRUE);

    /* A display list with scissor commands of its own. */
    glCallList(list);
    GLint list_box[4] = {w / 2 - 5, h / 3, w / 3, h / 3};
    expect_scissor("after the display list", list_box, GL_FALSE);
}

static GLuint make_list(int w, int h)
{
    GLuint list = glGenLists(2); /* list + 1: draw_part's compile-and-execute one */
    glNewList(list, GL_COMPILE);
    glEnable(GL_SCISSOR_TEST);
    glScissor(w / 2 - 5, h / 3, w / 3, h / 3);
    glBegin(GL_QUADS);
    glColor3f(0.9f, 0.9f, 0.9f);
    glVertex2f(0, 0);
    glVertex2f((float)w, 0);
    glColor3f(0.1f, 0.5f, 0.9f);
    glVertex2f((float)w, (float)h);
    glVertex2f(0, (float)h);
    glEnd();
    glDisable(GL_SCISSOR_TEST);
    glEndList();
    return list;
}

typedef struct server {
    const char *spec[MAX_FRAMES];
    int nspec;
} server;

/* Sends the tiles of `text` ("-" or "X:Y:W:H,...") as TilesTSR. */
static int send_tiles(const char *text)
{
    tsr_tile *tiles = NULL;
    size_t n = 0;
    tsr_error err = {0};
    if (strcmp(text, "-") && tsr_tiles_parse(text, false, &tiles, &n, &err) != TSR_OK) {
        fprintf(stderr, "tiles_driver: %s\n", err.message);
        return -1;
    }
    GLint rects[4 * 64];
    if (n > 64)
        n = 64;
    for (size_t i = 0; i < n; i++) {
        rects[4 * i] = tiles[i].x;
        rects[4 * i + 1] = tiles[i].y;
        rects[4 * i + 2] = tiles[i].width;
        rects[4 * i + 3] = tiles[i].height;
    }
    glTilesTSR(0, (GLsizei)n, rects);
    free(tiles);
    return 0;
}

/* A server with fixed tiles must leave every pixel outside their bounding
 * rectangle as the renderbuffer started: 0 (the scene's clears have alpha
 * 1). Read through the chain: the render SPU reads its framebuffer. */
static int check_outside(const char *text, int w, int h)
{
    tsr_tile *tiles = NULL;
    size_t n = 0;
    tsr_error err = {0};
    if (tsr_tiles_parse(text, false, &tiles, &n, &err) != TSR_OK || n == 0) {
        fprintf(stderr, "tiles_driver: %s\n", err.message);
        return -1;
    }
    int x0 = w, y0 = h, x1 = 0, y1 = 0;
    for (size_t i = 0; i < n; i++) {
        x0 = tiles[i].x < x0 ? tiles[i].x : x0;
        y0 = tiles[i].y < y0 ? tiles[i].y : y0;
        x1 = tiles[i].x + tiles[i].width > x1 ? tiles[i].x + tiles[i].width : x1;
        y1 = tiles[i].y + tiles[i].height > y1 ? tiles[i].y + tiles[i].height : y1;
    }
    free(tiles);
    GLubyte *px = calloc((size_t)w * (size_t)h, 4);
    if (!px)
        return -1;
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, px);
    long drawn = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            if ((x < x0 || x >= x1 || y < y0 || y >= y1) && px[((size_t)y * (size_t)w + (size_t)x) * 4 + 3])
                drawn++;
    free(px);
    printf("tiles %s: pixels drawn outside their bounding rectangle: %ld\n", text, drawn);
    return drawn ? -1 : 0;
}

/* Runs the scene through `chain_text`; `srv` NULL: no tiles at all. */
static int run_chain(const char *chain_text, int w, int h, int frames, const server *srv, int via_option, int contexts,
                     int check)
{
    tsr_error err = {0};
    tsr_chain *chain = tsr_chain_create(chain_text, &err);
    if (!chain) {
        fprintf(stderr, "tiles_driver: %s\n", err.message);
        return -1;
    }
    tsr_gl_make_current(tsr_chain_head(chain));
    glWindowCreateTSR(0, w, h);
    if (contexts) {
        glContextCreateTSR(1);
        glContextCreateTSR(2);
    }
    GLuint lists[3] = {0, 0, 0};
    int rc = 0;
    for (int f = 0; f < frames && rc == 0; f++) {
        if (srv && !(via_option && f == 0))
            rc = send_tiles(srv->spec[f < srv->nspec ? f : srv->nspec - 1]);
        for (int part = 0; part < 2 && rc == 0; part++) {
            int c = contexts ? 1 + part : 0;
            if (contexts)
                glMakeCurrentTSR(0, c);
            if (!lists[c])
                lists[c] = make_list(w, h);
            draw_part(part, f, w, h, lists[c]);
        }
        if (contexts)
            glMakeCurrentTSR(0, 0);
        glSwapBuffersTSR(0, 0);
    }
    if (rc == 0 && check && srv && srv->nspec == 1 && strcmp(srv->spec[0], "-"))
        rc = check_outside(srv->spec[0], w, h);
    if (measure) {
        measured_rss = status_mb("VmRSS");
        measured_hwm = status_mb("VmHWM");
    }
    glWindowDestroyTSR(0);
    tsr_gl_make_current(NULL);
    tsr_chain_destroy(chain);
    return rc;
}

static int parse_size(const char *s, int *w, int *h)
{
    return sscanf(s, "%dx%d", w, h) == 2 && *w > 0 && *h > 0 && *w <= 16384 && *h <= 16384 ? 0 : -1;
}

/* Compares tile `t` of server `k`, frame `f` with the reference. */
static int compare_tile(const char *dir, int k, int f, size_t i, size_t n, const tsr_tile *t, const tsr_image *ref)
{
    char path[4096];
    if (n == 1)
        snprintf(path, sizeof path, "%s/s%d-%d.png", dir, k, f);
    else
        snprintf(path, sizeof path, "%s/s%d-%d-t%zu.png", dir, k, f, i);
    tsr_image got = {0}, want = {0};
    tsr_error err = {0};
    if (tsr_image_read_png(&got, path, &err) != TSR_OK) {
        fprintf(stderr, "tiles_driver: %s\n", err.message);
        return 1;
    }
    int rc = 1;
    if (tsr_image_alloc(&want, t->width, t->height, &err) == TSR_OK) {
        /* tsr_image rows are top first; GL's y is bottom-up. */
        for (int y = 0; y < t->height; y++)
            memcpy(want.pixels + (size_t)y * (size_t)t->width * 4,
                   ref->pixels + ((size_t)(ref->height - t->y - t->height + y) * (size_t)ref->width + (size_t)t->x) * 4,
                   (size_t)t->width * 4);
        tsr_image_diff d;
        if (tsr_image_compare(&got, &want, 0, &d, &err) == TSR_OK) {
            printf("server %d frame %d tile %zu [%d, %d, %d, %d]: differing_pixels: %llu\n", k, f, i, t->x, t->y,
                   t->width, t->height, (unsigned long long)d.differing_pixels);
            rc = d.differing_pixels != 0;
        }
    }
    if (rc && err.message[0])
        fprintf(stderr, "tiles_driver: %s: %s\n", path, err.message);
    tsr_image_free(&got);
    tsr_image_free(&want);
    return rc;
}

static int cmd_compare(int argc, char **argv)
{
    const char *dir = argv[2];
    int w, h, frames = atoi(argv[4]), via_option = 0, contexts = 0;
    const char *prefix = "";
    if (parse_size(argv[3], &w, &h) || frames < 1 || frames > MAX_FRAMES)
        return 2;
    server servers[16];
    int nservers = 0;
    for (int a = 5; a < argc; a++) {
        if (!strcmp(argv[a], "--option")) {
            via_option = 1;
        } else if (!strcmp(argv[a], "--contexts")) {
            contexts = 1;
        } else if (!strcmp(argv[a], "--loopback")) {
            prefix = "loopback ! ";
        } else if (nservers < 16) {
            server *s = &servers[nservers++];
            s->nspec = 0;
            for (char *p = strtok(argv[a], "/"); p && s->nspec < MAX_FRAMES; p = strtok(NULL, "/"))
                s->spec[s->nspec++] = p;
        }
    }
    if (!nservers)
        return 2;
    char chain_text[8192];
    snprintf(chain_text, sizeof chain_text, "render output=\"%s/ref-%%d.png\"", dir);
    if (run_chain(chain_text, w, h, frames, NULL, 0, contexts, 0) != 0)
        return 1;
    for (int k = 0; k < nservers; k++) {
        int n = snprintf(chain_text, sizeof chain_text, "%srender output=\"%s/s%d-%%d.png\"", prefix, dir, k);
        if (via_option && strcmp(servers[k].spec[0], "-"))
            snprintf(chain_text + n, sizeof chain_text - (size_t)n, " tiles=%s", servers[k].spec[0]);
        if (run_chain(chain_text, w, h, frames, &servers[k], via_option, contexts, 1) != 0)
            return 1;
    }
    int bad = 0;
    for (int f = 0; f < frames; f++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/ref-%d.png", dir, f);
        tsr_image ref = {0};
        tsr_error err = {0};
        if (tsr_image_read_png(&ref, path, &err) != TSR_OK) {
            fprintf(stderr, "tiles_driver: %s\n", err.message);
            return 1;
        }
        for (int k = 0; k < nservers; k++) {
            const char *spec = servers[k].spec[f < servers[k].nspec ? f : servers[k].nspec - 1];
            tsr_tile *tiles = NULL, whole = {0, 0, 0, w, h};
            size_t n = 1;
            if (strcmp(spec, "-") && tsr_tiles_parse(spec, false, &tiles, &n, &err) != TSR_OK) {
                fprintf(stderr, "tiles_driver: %s\n", err.message);
                return 2;
            }
            for (size_t i = 0; i < n; i++)
                bad += compare_tile(dir, k, f, i, n, tiles ? &tiles[i] : &whole, &ref);
            free(tiles);
        }
        tsr_image_free(&ref);
    }
    if (harness_failures)
        fprintf(stderr, "tiles_driver: %d wrong scissor answers\n", harness_failures);
    return bad || harness_failures ? 1 : 0;
}

static int cmd_rss(int argc, char **argv)
{
    int w, h, frames = atoi(argv[3]), tilestsr = 0, contexts = 0;
    if (parse_size(argv[2], &w, &h) || frames < 1 || frames > MAX_FRAMES)
        return 2;
    for (int a = 5; a < argc; a++) {
        if (!strcmp(argv[a], "--tilestsr"))
            tilestsr = 1;
        else if (!strcmp(argv[a], "--contexts"))
            contexts = 1;
        else
            return 2;
    }
    server s = {.spec = {argv[4]}, .nspec = 1};
    int none = !strcmp(argv[4], "-"), option = !none && !tilestsr;
    char chain_text[256];
    snprintf(chain_text, sizeof chain_text, "render%s%s", option ? " tiles=" : "", option ? argv[4] : "");
    measure = 1;
    if (run_chain(chain_text, w, h, frames, none ? NULL : &s, option, contexts, 0) != 0)
        return 1;
    printf("vmrss_mb: %.1f\nvmhwm_mb: %.1f\n", measured_rss, measured_hwm);
    return harness_failures ? 1 : 0;
}

static int cmd_crop(char **argv)
{
    tsr_image in = {0}, out = {0};
    tsr_error err = {0};
    int x = atoi(argv[3]), y = atoi(argv[4]), w = atoi(argv[5]), h = atoi(argv[6]);
    if (tsr_image_read_png(&in, argv[2], &err) != TSR_OK) {
        fprintf(stderr, "tiles_driver: %s\n", err.message);
        return 1;
    }
    int rc = 1;
    if (x < 0 || y < 0 || w < 1 || h < 1 || x + w > in.width || y + h > in.height)
        fprintf(stderr, "tiles_driver: crop %d,%d %dx%d is outside %s (%dx%d)\n", x, y, w, h, argv[2], in.width,
                in.height);
    else if (tsr_image_alloc(&out, w, h, &err) == TSR_OK) {
        for (int row = 0; row < h; row++)
            memcpy(out.pixels + (size_t)row * (size_t)w * 4,
                   in.pixels + ((size_t)(in.height - y - h + row) * (size_t)in.width + (size_t)x) * 4, (size_t)w * 4);
        rc = tsr_image_write_png(&out, argv[7], &err) != TSR_OK;
    }
    if (rc && err.message[0])
        fprintf(stderr, "tiles_driver: %s\n", err.message);
    tsr_image_free(&in);
    tsr_image_free(&out);
    return rc;
}

/* tsr_tiles_parse: both forms, and one error per kind naming the tile. */
static int cmd_parse(void)
{
    static const struct {
        const char *text;
        bool with_server;
        int count;           /* -1: must fail */
        int last[5];         /* the last tile: server x y w h */
        const char *message; /* expected error */
    } cases[] = {
        {"", false, 0, {0}, NULL},
        {"0:0:512:384", false, 1, {0, 0, 0, 512, 384}, NULL},
        {"0:0:512:384,512:384:512:384", false, 2, {0, 512, 384, 512, 384}, NULL},
        {"0:0:0:512:384,3:512:0:512:384", true, 2, {3, 512, 0, 512, 384}, NULL},
        {"0:0:512", false, -1, {0}, "tile 1 '0:0:512': expected X:Y:W:H"},
        {"0:0:1:1,0:0:0:1", false, -1, {0}, "tile 2 '0:0:0:1': width must be 1..16384"},
        {"0:-1:1:1", false, -1, {0}, "tile 1 '0:-1:1:1': y must be 0..16383"},
        {"0:0:1:1x", false, -1, {0}, "tile 1 '0:0:1:1x': expected X:Y:W:H"},
        {"0:0:1:1,", false, -1, {0}, "tile 2 '': expected X:Y:W:H"},
        {"0:0:1:1", true, -1, {0}, "tile 1 '0:0:1:1': expected S:X:Y:W:H"},
        {"-1:0:0:1:1", true, -1, {0}, "tile 1 '-1:0:0:1:1': server index must be >= 0"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        tsr_tile *tiles = NULL;
        size_t n = 0;
        tsr_error err = {0};
        int rc = tsr_tiles_parse(cases[i].text, cases[i].with_server, &tiles, &n, &err);
        bool ok;
        if (cases[i].count < 0) {
            ok = rc == TSR_EINVAL && !strcmp(err.message, cases[i].message) && !tiles;
        } else {
            const int *w = cases[i].last;
            ok = rc == TSR_OK && n == (size_t)cases[i].count &&
                 (n == 0 || (tiles[n - 1].server == w[0] && tiles[n - 1].x == w[1] && tiles[n - 1].y == w[2] &&
                             tiles[n - 1].width == w[3] && tiles[n - 1].height == w[4]));
        }
        CHECK(ok, "tiles '%s': %s%s", cases[i].text,
              rc == TSR_OK ? "parsed" : "error: ", rc == TSR_OK ? "" : err.message);
        if (ok)
            printf("ok '%s'\n", cases[i].text);
        free(tiles);
    }
    return harness_failures ? 1 : 0;
}

int main(int argc, char **argv)
{
    if (argc == 2 && !strcmp(argv[1], "parse"))
        return cmd_parse();
    if (argc == 8 && !strcmp(argv[1], "crop"))
        return cmd_crop(argv);
    if (argc >= 6 && !strcmp(argv[1], "compare")) {
        int rc = cmd_compare(argc, argv);
        if (rc == 2)
            fprintf(stderr, "tiles_driver: bad arguments\n");
        return rc;
    }
    if (argc >= 5 && argc <= 7 && !strcmp(argv[1], "rss")) {
        int rc = cmd_rss(argc, argv);
        if (rc == 2)
            fprintf(stderr, "tiles_driver: bad arguments\n");
        return rc;
    }
    fprintf(stderr, "usage: tiles_driver parse\n"
                    "       tiles_driver compare DIR WxH FRAMES [--option] [--contexts] [--loopback]\n"
                    "                           SERVER...\n"
                    "       tiles_driver crop IN.png X Y W H OUT.png\n"
                    "       tiles_driver rss WxH FRAMES TILES|- [--tilestsr] [--contexts]\n");
    return 2;
}
