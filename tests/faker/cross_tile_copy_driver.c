/* tests/faker/cross_tile_copy_driver.c — faker_cross_tile_copy OUT.txt:
 * copies of the window's pixels whose source and destination lie on
 * different tiles of the test's 2x2 wall (tiles of 32x24 on the 64x48
 * pbuffer, gl21_commands.sh), one labelled line per read-back in OUT.txt:
 *   glCopyPixels of colour from the lower left tile onto the upper right
 *   and back the other way, with a pixel zoom, with pixel transfer scale
 *   and bias (applied once), with GL_XOR logic op, of a source partly
 *   outside the window (overlapping its destination, and zoomed), from an invalid raster position (nothing drawn); of depth and of stencil (read back as
 *   such), and of both (GL_DEPTH_STENCIL);
 *   glCopyTexImage2D of a rectangle across all four tiles (RGBA8,
 *   LUMINANCE, ALPHA, with a border, DEPTH_COMPONENT24), glCopyTexImage1D
 *   of a row across the vertical border, glCopyTexSubImage1D/2D/3D into
 *   textures made with glTexImage, each read back with glGetTexImage and
 *   one drawn over the window;
 *   the program's pixel store (pack and unpack) as it set it after the
 *   copies, and the copies' errors (bad type, negative size, bad target,
 *   a sub-image of no image, out of range) each once.
 * Built with RECORDED_GL_NATIVE (faker_cross_tile_copy_native) it makes
 * the same calls on OSMesa directly: every run through tessera, the wall
 * among them, must write the same file (gl21_commands.sh). */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "recorded_gl.h"

#define W RECORDED_GL_W
#define H RECORDED_GL_H

static FILE *out;

static void frame(const char *label) { recorded_gl_frame(out, label); }

/* A checksum line of the whole window read as format/type. */
static void window_as(const char *label, GLenum format, GLenum type, size_t pixel_bytes)
{
    static uint8_t px[W * H * 8];
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, W, H, format, type, px);
    fprintf(out, "%s: %08x\n", label, recorded_gl_fnv(px, (size_t)(W * H) * pixel_bytes));
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
}

/* The bound texture's level 0 as RGBA floats (or depth), a checksum and
 * its first texel. */
static void texture_as(const char *label, GLenum target, GLenum format, int w, int h, int d)
{
    size_t n = (size_t)w * (size_t)h * (size_t)d * (format == GL_RGBA ? 4 : 1);
    GLfloat *texels = calloc(n, sizeof *texels);
    glGetTexImage(target, 0, format, GL_FLOAT, texels);
    fprintf(out, "%s: %08x first %.6f\n", label, recorded_gl_fnv(texels, n * sizeof *texels), (double)texels[0]);
    free(texels);
}

static void errors(const char *label)
{
    GLenum first = glGetError(), second = glGetError();
    fprintf(out, "%s: 0x%x then 0x%x\n", label, first, second);
}

/* A picture where every pixel differs: colour, depth and stencil drawn
 * with glDrawPixels over the whole window (a wall draws them on every
 * tile). */
static void picture(void)
{
    static GLubyte rgba[W * H * 4], stencil[W * H];
    static GLuint depth[W * H];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            GLubyte *p = &rgba[(y * W + x) * 4];
            p[0] = (GLubyte)(x * 4);
            p[1] = (GLubyte)(y * 5);
            p[2] = (GLubyte)((x * 7 + y * 11) & 255);
            p[3] = (GLubyte)(255 - x - y);
            depth[y * W + x] = (GLuint)(x * 0x1000000u + y * 0x500000u + 0x12345u);
            stencil[y * W + x] = (GLubyte)(x + 3 * y);
        }
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_STENCIL_TEST);
    glWindowPos2i(0, 0);
    glDrawPixels(W, H, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    /* a depth image's fragments take the raster colour: not written */
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDrawPixels(W, H, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, depth);
    glDisable(GL_DEPTH_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDrawPixels(W, H, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, stencil);
}

static void copy_pixels(void)
{
    picture();
    /* from the lower left tile (and across both borders) to the upper right */
    glWindowPos2i(36, 27);
    glCopyPixels(4, 3, 26, 19, GL_COLOR);
    frame("CopyPixels colour from the lower left tile to the upper right");
    /* and back: from the upper right to the lower left, overlapping the
     * border on the way */
    glWindowPos2i(2, 1);
    glCopyPixels(30, 22, 30, 24, GL_COLOR);
    frame("CopyPixels colour from the upper right tile to the lower left");
    picture();
    glPixelZoom(2.0f, 3.0f);
    glWindowPos2i(20, 10);
    glCopyPixels(40, 28, 12, 14, GL_COLOR);
    glPixelZoom(1.0f, 1.0f);
    frame("CopyPixels colour zoomed 2 x 3 across both borders");
    picture();
    glPixelTransferf(GL_RED_SCALE, 0.5f);
    glPixelTransferf(GL_GREEN_BIAS, 0.25f);
    glWindowPos2i(10, 8);
    glCopyPixels(28, 20, 30, 20, GL_COLOR);
    glPixelTransferf(GL_RED_SCALE, 1.0f);
    glPixelTransferf(GL_GREEN_BIAS, 0.0f);
    frame("CopyPixels colour with red scale 0.5 and green bias 0.25 (applied once)");
    picture();
    glEnable(GL_COLOR_LOGIC_OP);
    glLogicOp(GL_XOR);
    glWindowPos2i(30, 2);
    glCopyPixels(2, 26, 28, 20, GL_COLOR);
    glDisable(GL_COLOR_LOGIC_OP);
    frame("CopyPixels colour with GL_XOR from the upper left tile to the lower right");
    /* a source partly outside the window (undefined in GL): where the
     * source overlaps the destination, or zoomed, Mesa draws the outside
     * part as 0, as the wall's gather gives it (docs/walls.md, "Copies
     * across tiles", says where Mesa does otherwise) */
    picture();
    glWindowPos2i(20, 14);
    glCopyPixels(-6, -5, 40, 30, GL_COLOR);
    frame("CopyPixels of a source below and left of the window, overlapping");
    picture();
    glPixelZoom(2.0f, 2.0f);
    glWindowPos2i(10, 6);
    glCopyPixels(-6, -5, 20, 14, GL_COLOR);
    glPixelZoom(1.0f, 1.0f);
    frame("CopyPixels zoomed 2 x 2 of a source below and left of the window");
    /* a raster position outside the view volume is invalid: nothing */
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glRasterPos3f(0.0f, 0.0f, 2.0f);
    glCopyPixels(0, 0, 40, 30, GL_COLOR);
    frame("CopyPixels from an invalid raster position draws nothing");

    picture();
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glWindowPos2i(33, 20);
    glCopyPixels(3, 2, 28, 26, GL_DEPTH);
    glDisable(GL_DEPTH_TEST);
    window_as("CopyPixels depth across both borders, depth read", GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, 4);
    frame("CopyPixels depth across both borders, colour (raster colour)");
    glWindowPos2i(1, 30);
    glCopyPixels(34, 4, 28, 17, GL_STENCIL);
    window_as("CopyPixels stencil from the lower right tile to the upper left", GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, 1);
    picture();
    glEnable(GL_DEPTH_TEST);
    glWindowPos2i(20, 3);
    glCopyPixels(25, 20, 30, 24, GL_DEPTH_STENCIL);
    glDisable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    window_as("CopyPixels depth and stencil, depth read", GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, 4);
    window_as("CopyPixels depth and stencil, stencil read", GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, 1);
}

/* The bound 2D texture drawn over the whole window. */
static void draw_texture(GLenum target)
{
    glEnable(target);
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
    glBegin(GL_QUADS);
    glTexCoord2f(0, 0);
    glVertex2f(-1, -1);
    glTexCoord2f(1, 0);
    glVertex2f(1, -1);
    glTexCoord2f(1, 1);
    glVertex2f(1, 1);
    glTexCoord2f(0, 1);
    glVertex2f(-1, 1);
    glEnd();
    glDisable(target);
}

static void copy_textures(void)
{
    GLuint tex[8];
    glGenTextures(8, tex);
    picture();
    /* the program's own pixel store, which the copies must leave as it is */
    glPixelStorei(GL_PACK_ALIGNMENT, 2);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 9);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 1);

    glBindTexture(GL_TEXTURE_2D, tex[0]);
    glCopyTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 16, 12, 32, 24, 0);
    texture_as("CopyTexImage2D RGBA8 of the centre (four tiles)", GL_TEXTURE_2D, GL_RGBA, 32, 24, 1);
    glBindTexture(GL_TEXTURE_2D, tex[1]);
    glCopyTexImage2D(GL_TEXTURE_2D, 0, GL_LUMINANCE, 20, 4, 24, 40, 0);
    texture_as("CopyTexImage2D LUMINANCE across both borders", GL_TEXTURE_2D, GL_RGBA, 24, 40, 1);
    glBindTexture(GL_TEXTURE_2D, tex[2]);
    glCopyTexImage2D(GL_TEXTURE_2D, 0, GL_ALPHA, 30, 20, 8, 8, 0);
    texture_as("CopyTexImage2D ALPHA at the corner of the four tiles", GL_TEXTURE_2D, GL_RGBA, 8, 8, 1);
    glBindTexture(GL_TEXTURE_2D, tex[3]);
    glCopyTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 27, 19, 10, 10, 1);
    texture_as("CopyTexImage2D with a border of 1", GL_TEXTURE_2D, GL_RGBA, 8, 8, 1);
    glBindTexture(GL_TEXTURE_2D, tex[4]);
    glCopyTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, 12, 10, 40, 28, 0);
    texture_as("CopyTexImage2D DEPTH_COMPONENT24 across both borders", GL_TEXTURE_2D, GL_DEPTH_COMPONENT, 40, 28, 1);
    glBindTexture(GL_TEXTURE_1D, tex[5]);
    glCopyTexImage1D(GL_TEXTURE_1D, 0, GL_RGBA8, 10, 30, 44, 0);
    texture_as("CopyTexImage1D of a row across the vertical border", GL_TEXTURE_1D, GL_RGBA, 44, 1, 1);
    glCopyTexSubImage1D(GL_TEXTURE_1D, 0, 4, 28, 5, 30);
    texture_as("CopyTexSubImage1D from the lower right tile", GL_TEXTURE_1D, GL_RGBA, 44, 1, 1);

    /* sub-images into a texture made with glTexImage, in both directions */
    static GLubyte grey[64 * 64 * 4];
    memset(grey, 0x80, sizeof grey);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    glBindTexture(GL_TEXTURE_2D, tex[6]);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 64, 64, 0, GL_RGBA, GL_UNSIGNED_BYTE, grey);
    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 2, 3, 30, 22, 20, 16);
    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 20, 40, 3, 14, 40, 20);
    texture_as("CopyTexSubImage2D twice, across the borders each way", GL_TEXTURE_2D, GL_RGBA, 64, 64, 1);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 9);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 1);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    draw_texture(GL_TEXTURE_2D);
    frame("the sub-imaged texture drawn over the window");
    picture();
    /* a level of glTexImage's legacy internal format 3 */
    glBindTexture(GL_TEXTURE_2D, tex[1]);
    glTexImage2D(GL_TEXTURE_2D, 0, 3, 16, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, grey);
    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 24, 16, 16, 16);
    texture_as("CopyTexSubImage2D into internal format 3, from the four tiles", GL_TEXTURE_2D, GL_RGBA, 16, 16, 1);
    glBindTexture(GL_TEXTURE_3D, tex[7]);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    glTexImage3D(GL_TEXTURE_3D, 0, GL_RGBA8, 16, 16, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, grey);
    glCopyTexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, 2, 24, 16, 16, 16);
    texture_as("CopyTexSubImage3D into slice 2, from the four tiles", GL_TEXTURE_3D, GL_RGBA, 16, 16, 4);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 9);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 1);

    GLint store[3];
    glGetIntegerv(GL_PACK_ALIGNMENT, &store[0]);
    glGetIntegerv(GL_UNPACK_ROW_LENGTH, &store[1]);
    glGetIntegerv(GL_UNPACK_SKIP_PIXELS, &store[2]);
    fprintf(out, "pixel store after the copies: pack alignment %d, unpack row length %d, skip pixels %d\n", store[0],
            store[1], store[2]);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    errors("no error after the copies");

    glCopyPixels(0, 0, 4, 4, GL_RGBA);
    errors("CopyPixels of type GL_RGBA");
    glCopyPixels(0, 0, -1, 4, GL_COLOR);
    errors("CopyPixels of width -1");
    glCopyTexImage2D(GL_TEXTURE_3D, 0, GL_RGBA8, 0, 0, 4, 4, 0);
    errors("CopyTexImage2D of GL_TEXTURE_3D");
    glBindTexture(GL_TEXTURE_2D, tex[0]);
    glCopyTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 0, 0, 4, 4, 2);
    errors("CopyTexImage2D with border 2");
    glCopyTexSubImage2D(GL_TEXTURE_2D, 3, 0, 0, 0, 0, 4, 4);
    errors("CopyTexSubImage2D of a level with no image");
    glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 30, 0, 0, 0, 4, 4);
    errors("CopyTexSubImage2D past the image's edge");
    glDeleteTextures(8, tex);
}

int main(int argc, char **argv)
{
    out = recorded_gl_start(argc, argv);
    copy_pixels();
    copy_textures();
    recorded_gl_end(out, argv[1]);
    printf("cross-tile copies: written to %s\n", argv[1]);
    return harness_failures ? 1 : 0;
}
