/* tests/render/drawpixels_driver.c — one frame per DrawPixels case through
 * a render chain, for tests/render/drawpixels.sh to compare with
 * fast_drawpixels=true and =false (spus/render/drawpixels.c):
 *   drawpixels_driver solo|shared true|false PATTERN
 * shared: the frames are drawn by a second context (ContextCreateTSR), as
 * the sort-last display's peers draw. Random images at odd sizes and
 * offsets, partly outside the window, under the scissor, with unpack
 * row length/skips/alignment, BGRA; and each state that must take the
 * plain path (blending, texturing, zoom, scale, depth test, colour mask,
 * alpha test, logic op, fog, a fractional raster position, a display list,
 * rasterizer discard).
 * Then scissored colour clears (render_fastdraw_clear): byte-valued and
 * other colours, partly outside the window, an empty box, a colour mask,
 * colour with depth, a display list, fragment state Clear ignores, no draw
 * buffer, clamped values, rasterizer discard, and 256 clears of every
 * channel value.
 * After each case it checks through glGet that the state the fast path
 * touches is the application's again. Prints "expect_fast: N of M" and
 * "expect_fast_clear: N of M". */
#define GL_GLEXT_PROTOTYPES
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>
#include <GL/glext.h>

#include "tessera/chain.h"
#include "tessera/glapi.h"
#include "tessera/gltsr_gen.h"

#define W 131
#define H 83

static unsigned rng = 12345u;
static unsigned char next_byte(void)
{
    rng = rng * 1103515245u + 12345u;
    return (unsigned char)(rng >> 16);
}

static unsigned char *random_image(size_t bytes)
{
    unsigned char *p = malloc(bytes);
    if (!p) {
        fprintf(stderr, "drawpixels_driver: out of memory\n");
        exit(1);
    }
    for (size_t i = 0; i < bytes; i++)
        p[i] = next_byte();
    return p;
}

static int failures;
static void expect_int(GLenum pname, GLint want, int frame, const char *what)
{
    GLint v = -1;
    glGetIntegerv(pname, &v);
    if (v != want) {
        fprintf(stderr, "drawpixels_driver: case %d: %s is %d after DrawPixels, was %d\n", frame, what, v, want);
        failures++;
    }
}

/* A textured, lit-free background so texture bindings matter. */
static void background(int frame)
{
    glClearColor(0.1f * (float)(frame % 7), 0.3f, 0.6f, 1.0f);
    glClearDepth(0.5);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glBegin(GL_TRIANGLES);
    glColor3f(0.9f, 0.2f, 0.1f);
    glVertex2f(-1, -1);
    glVertex2f(1, -1);
    glVertex2f(0, 1);
    glEnd();
}

int main(int argc, char **argv)
{
    if (argc != 4 || (strcmp(argv[1], "solo") && strcmp(argv[1], "shared"))) {
        fprintf(stderr, "usage: drawpixels_driver solo|shared true|false PATTERN\n");
        return 2;
    }
    char text[700];
    snprintf(text, sizeof text, "render output=\"%s\" fast_drawpixels=%s", argv[3], argv[2]);
    tsr_error err = {0};
    tsr_chain *chain = tsr_chain_create(text, &err);
    if (!chain) {
        fprintf(stderr, "drawpixels_driver: %s\n", err.message);
        return 1;
    }
    tsr_gl_make_current(tsr_chain_head(chain));
    glWindowCreateTSR(0, W, H);
    if (!strcmp(argv[1], "shared")) {
        glContextCreateTSR(1);
        glMakeCurrentTSR(0, 1);
    }
    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    unsigned char texels[4 * 4 * 4];
    for (size_t i = 0; i < sizeof texels; i++)
        texels[i] = next_byte();
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 4, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glViewport(0, 0, W, H);
    int fast = 0, calls = 0;
    enum { CASES = 19 };
    for (int c = 0; c < CASES; c++) {
        background(c);
        int x = 7, y = 5, w = 50, h = 30;
        GLenum format = GL_RGBA;
        int row_length = 0, skip_rows = 0, skip_pixels = 0, alignment = 4;
        bool want_fast = false;
        GLuint list = 0;
        switch (c) {
        case 0: want_fast = true; break;
        case 1: x = -9, y = 60, w = 151, h = 40, want_fast = true; break; /* past three edges */
        case 2:
            glEnable(GL_SCISSOR_TEST);
            glScissor(10, 11, 61, 43);
            x = 3, y = 2, w = 91, h = 71, want_fast = true;
            break;
        case 3: row_length = 67, skip_rows = 2, skip_pixels = 3, alignment = 8, w = 33, h = 21, want_fast = true; break;
        case 4: format = GL_BGRA, w = 77, h = 45, x = 20, y = 30, want_fast = true; break;
        case 5:
            glEnable(GL_BLEND);
            glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
            break;
        case 6:
            glActiveTexture(GL_TEXTURE1);
            glBindTexture(GL_TEXTURE_2D, tex);
            glEnable(GL_TEXTURE_2D);
            glActiveTexture(GL_TEXTURE0);
            break;
        case 7: glPixelZoom(2.0f, 1.0f); break;
        case 8: glPixelTransferf(GL_RED_SCALE, 0.5f); break;
        case 9:
            glEnable(GL_DEPTH_TEST);
            glDepthFunc(GL_LESS);
            break;
        case 10: glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_TRUE); break;
        case 11:
            glEnable(GL_ALPHA_TEST);
            glAlphaFunc(GL_GREATER, 0.5f);
            break;
        case 12:
            glEnable(GL_COLOR_LOGIC_OP);
            glLogicOp(GL_XOR);
            break;
        case 13: glEnable(GL_FOG); break;
        case 14: break;                            /* a fractional raster position, below */
        case 15: x = 500, want_fast = true; break; /* wholly outside: nothing drawn */
        case 16: x = -3, y = -4, w = 140, h = 90, want_fast = true; break;
        case 17: list = glGenLists(1); break;
        case 18: glEnable(GL_RASTERIZER_DISCARD); break; /* GL 3.0: nothing is drawn */
        }
        glPixelStorei(GL_UNPACK_ROW_LENGTH, row_length);
        glPixelStorei(GL_UNPACK_SKIP_ROWS, skip_rows);
        glPixelStorei(GL_UNPACK_SKIP_PIXELS, skip_pixels);
        glPixelStorei(GL_UNPACK_ALIGNMENT, alignment);
        int rl = row_length ? row_length : w;
        size_t stride = ((size_t)rl * 4 + (size_t)alignment - 1) / (size_t)alignment * (size_t)alignment;
        unsigned char *img = random_image(stride * (size_t)(h + skip_rows) + 64);
        if (c == 14)
            glWindowPos2f(10.5f, 7.25f);
        else
            glWindowPos2i(x, y);
        if (list) {
            glNewList(list, GL_COMPILE);
            glDrawPixels(w, h, format, GL_UNSIGNED_BYTE, img);
            glEndList();
            glCallList(list);
            glDeleteLists(list, 1);
        } else {
            glDrawPixels(w, h, format, GL_UNSIGNED_BYTE, img);
        }
        calls++;
        fast += want_fast;
        free(img);
        /* What the fast path touches is the application's again. */
        expect_int(GL_TEXTURE_BINDING_2D, (GLint)tex, c, "GL_TEXTURE_BINDING_2D");
        expect_int(GL_UNPACK_ROW_LENGTH, row_length, c, "GL_UNPACK_ROW_LENGTH");
        expect_int(GL_UNPACK_SKIP_ROWS, skip_rows, c, "GL_UNPACK_SKIP_ROWS");
        expect_int(GL_UNPACK_SKIP_PIXELS, skip_pixels, c, "GL_UNPACK_SKIP_PIXELS");
        expect_int(GL_UNPACK_ALIGNMENT, alignment, c, "GL_UNPACK_ALIGNMENT");
        expect_int(GL_ACTIVE_TEXTURE, GL_TEXTURE0, c, "GL_ACTIVE_TEXTURE");
        if (glIsEnabled(GL_SCISSOR_TEST) != (c == 2)) {
            fprintf(stderr, "drawpixels_driver: case %d: scissor test changed\n", c);
            failures++;
        }
        GLenum e = glGetError();
        if (e != GL_NO_ERROR) {
            fprintf(stderr, "drawpixels_driver: case %d: GL error 0x%x\n", c, e);
            failures++;
        }
        glSwapBuffersTSR(0, 0);
        /* Back to the defaults for the next case. */
        glDisable(GL_SCISSOR_TEST);
        glDisable(GL_BLEND);
        glActiveTexture(GL_TEXTURE1);
        glDisable(GL_TEXTURE_2D);
        glActiveTexture(GL_TEXTURE0);
        glPixelZoom(1.0f, 1.0f);
        glPixelTransferf(GL_RED_SCALE, 1.0f);
        glDisable(GL_DEPTH_TEST);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDisable(GL_ALPHA_TEST);
        glDisable(GL_COLOR_LOGIC_OP);
        glDisable(GL_FOG);
        glDisable(GL_RASTERIZER_DISCARD);
    }
    /* Scissored colour clears (render_fastdraw_clear): one frame each. */
    int clear_fast = 0, clears = 0;
    GLint draw_buffer = GL_NONE;
    glGetIntegerv(GL_DRAW_BUFFER, &draw_buffer);
    enum { CLEAR_CASES = 13 };
    for (int c = 0; c < CLEAR_CASES; c++) {
        background(c);
        bool want_fast = false, scissor = true, colour_only = true;
        GLfloat colour[4] = {37 / 255.0f, 1.0f, 0.0f, 200 / 255.0f};
        int box[4] = {9, 7, 61, 43};
        GLuint list = 0;
        switch (c) {
        case 0: want_fast = true; break;
        case 1: box[0] = -20, box[1] = 50, box[2] = 400, box[3] = 400, want_fast = true; break; /* past the window */
        case 2: box[2] = 0, want_fast = true; break;                                            /* empty: nothing */
        case 3: colour[1] = 0.3f; break; /* not a byte value: GL's clear */
        case 4: scissor = false; break;  /* a fill already */
        case 5: glColorMask(GL_TRUE, GL_TRUE, GL_FALSE, GL_TRUE); break;
        case 6: colour_only = false; break; /* colour and depth */
        case 7: list = glGenLists(1); break;
        case 8: /* every byte value, one row of boxes per channel value: below */ want_fast = true; break;
        case 9: /* fragment state that Clear ignores, so the fast path too */
            glEnable(GL_BLEND);
            glBlendFunc(GL_ZERO, GL_ONE);
            glEnable(GL_DEPTH_TEST);
            glDepthFunc(GL_NEVER);
            glActiveTexture(GL_TEXTURE1);
            glBindTexture(GL_TEXTURE_2D, tex);
            glEnable(GL_TEXTURE_2D);
            glActiveTexture(GL_TEXTURE0);
            want_fast = true;
            break;
        case 10: glDrawBuffer(GL_NONE); break;                                 /* no colour buffer */
        case 11: colour[0] = 1.5f, colour[3] = -1.0f, want_fast = true; break; /* clamped to 1 and 0 */
        case 12: glEnable(GL_RASTERIZER_DISCARD); break;                       /* nothing is cleared */
        }
        glClearColor(colour[0], colour[1], colour[2], colour[3]);
        if (scissor)
            glEnable(GL_SCISSOR_TEST);
        if (c == 8) {
            /* 256 clears: channel values k / 255 for every k */
            for (int k = 0; k < 256; k++) {
                glClearColor((GLfloat)k / 255.0f, (GLfloat)(255 - k) / 255.0f, (GLfloat)((k * 7) % 256) / 255.0f,
                             (GLfloat)((k * 13) % 256) / 255.0f);
                glScissor((k % 32) * 4, (k / 32) * 10, 3, 9);
                glClear(GL_COLOR_BUFFER_BIT);
                clears++;
                clear_fast++;
            }
        } else {
            glScissor(box[0], box[1], box[2], box[3]);
            if (list) {
                glNewList(list, GL_COMPILE);
                glClear(GL_COLOR_BUFFER_BIT);
                glEndList();
                glCallList(list);
                glDeleteLists(list, 1);
            } else {
                glClear(colour_only ? GL_COLOR_BUFFER_BIT : GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            }
            /* GL's own clear of colour alone is the only one render sees
             * as a colour clear (a list's runs inside GL). */
            clears += colour_only && !list;
            clear_fast += want_fast;
        }
        expect_int(GL_TEXTURE_BINDING_2D, (GLint)tex, CASES + c, "GL_TEXTURE_BINDING_2D");
        expect_int(GL_UNPACK_ALIGNMENT, 4, CASES + c, "GL_UNPACK_ALIGNMENT");
        expect_int(GL_UNPACK_ROW_LENGTH, 0, CASES + c, "GL_UNPACK_ROW_LENGTH");
        if (glIsEnabled(GL_SCISSOR_TEST) != scissor) {
            fprintf(stderr, "drawpixels_driver: clear case %d: scissor test changed\n", c);
            failures++;
        }
        GLenum e = glGetError();
        if (e != GL_NO_ERROR) {
            fprintf(stderr, "drawpixels_driver: clear case %d: GL error 0x%x\n", c, e);
            failures++;
        }
        glSwapBuffersTSR(0, 0);
        glDisable(GL_SCISSOR_TEST);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDisable(GL_BLEND);
        glDisable(GL_DEPTH_TEST);
        glActiveTexture(GL_TEXTURE1);
        glDisable(GL_TEXTURE_2D);
        glActiveTexture(GL_TEXTURE0);
        glDrawBuffer((GLenum)draw_buffer);
        glDisable(GL_RASTERIZER_DISCARD);
    }
    /* The texture names the fast path keeps are the client's share
     * group's: a client that binds names it never generated (legal in
     * GL 2.1) must find GL's default objects there, in either run, and
     * the fast path must never overwrite what it put in them. Names 9-12
     * are bound by display lists compiled before the fast path makes its
     * textures anew (after the names below 9 are taken), run after. */
    GLuint lists = glGenLists(4);
    for (GLuint k = 0; k < 4; k++) {
        glNewList(lists + k, GL_COMPILE);
        glBindTexture(GL_TEXTURE_2D, 9 + k);
        glEndList();
    }
    unsigned char mine[2 * 2 * 4];
    for (size_t i = 0; i < sizeof mine; i++)
        mine[i] = next_byte();
    for (GLuint name = 1; name <= 8; name++) {
        if (name == tex)
            continue;
        if (glIsTexture(name)) {
            fprintf(stderr, "drawpixels_driver: texture %u exists before the client bound it\n", name);
            failures++;
        }
        glBindTexture(GL_TEXTURE_2D, name);
        GLint width = -1;
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &width);
        if (width != 0) {
            fprintf(stderr, "drawpixels_driver: texture %u, bound first, is %d wide, not GL's default\n", name, width);
            failures++;
        }
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 2, 2, 0, GL_RGBA, GL_UNSIGNED_BYTE, mine);
        glBindTexture(GL_TEXTURE_2D, tex);
        /* the fast paths again: they make their textures anew */
        unsigned char *img = random_image(4 * 50 * 30);
        glWindowPos2i(7, 5);
        glDrawPixels(50, 30, GL_RGBA, GL_UNSIGNED_BYTE, img);
        free(img);
        calls++;
        fast++;
        glEnable(GL_SCISSOR_TEST);
        glScissor(9, 7, 61, 43);
        glClear(GL_COLOR_BUFFER_BIT);
        glDisable(GL_SCISSOR_TEST);
        clears++;
        clear_fast++;
    }
    for (GLuint k = 0; k < 4; k++) {
        glCallList(lists + k);
        GLint width = -1;
        glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &width);
        if (width != 0) {
            fprintf(stderr, "drawpixels_driver: a list bound texture %u as %d wide, not GL's default\n", 9 + k, width);
            failures++;
        }
    }
    glDeleteLists(lists, 4);
    for (GLuint name = 1; name <= 8; name++) {
        if (name == tex)
            continue;
        glBindTexture(GL_TEXTURE_2D, name);
        unsigned char got[sizeof mine];
        glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, got);
        if (memcmp(got, mine, sizeof mine)) {
            fprintf(stderr, "drawpixels_driver: the client's texture %u changed under DrawPixels/Clear\n", name);
            failures++;
        }
    }
    glBindTexture(GL_TEXTURE_2D, tex);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        fprintf(stderr, "drawpixels_driver: client texture names: GL error 0x%x\n", e);
        failures++;
    }
    printf("expect_fast: %d of %d\n", fast, calls);
    printf("expect_fast_clear: %d of %d\n", clear_fast, clears);
    glWindowDestroyTSR(0);
    tsr_gl_make_current(NULL);
    tsr_chain_destroy(chain);
    return failures ? 1 : 0;
}
