/* tests/faker/egl_share_client_state_driver.c — faker_egl_share_client_state RAW:
 * two EGL contexts of ONE share group on one thread, each with a 32x24
 * pbuffer, whose client state differs, used in turn. Pixel store and
 * client arrays are per context in GL, but a share group's calls travel
 * in one tessera stream (faker/core.c), so the packer's and the
 * unpacker's mirrors of that state must follow the stream's
 * MakeCurrentTSR, not be one per stream:
 *   A unpacks with alignment 1 and a row length of 5 and packs with
 *     alignment 1; its vertex array is its own triangle.
 *   B keeps every default (unpack and pack alignment 4, no row length)
 *     and has another triangle in its vertex array and a colour array.
 * Each context, in turn (A, B, A, B), uploads a 3x3 RGB texture laid out
 * for its own unpack state (padding bytes poisoned), draws its arrays
 * textured, and reads a 7x5 block back laid out for its own pack state;
 * RAW gets every read-back block (as GL laid it out) and the frames.
 * Built with SHARE_NATIVE (faker_egl_share_client_state_native, OSMesa
 * with two contexts sharing), the same calls in the same order: the run
 * through the faker must write the same bytes. */
#ifdef SHARE_NATIVE
#include <GL/osmesa.h>
#else
#include <EGL/egl.h>
#endif
#include <GL/gl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

#define W 32
#define H 24
#define TEXELS 3

typedef struct ctx_state {
    int unpack_alignment, unpack_row_length, pack_alignment;
    GLfloat vertices[6];
    GLubyte colours[12];
    int use_colours;
    GLuint texture;
} ctx_state;

static ctx_state states[2] = {
    {1, 5, 1, {-0.9f, -0.9f, 0.8f, -0.6f, -0.2f, 0.9f}, {0}, 0, 0},
    {4, 0, 4, {0.9f, -0.8f, 0.1f, 0.9f, -0.7f, -0.1f}, {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255}, 1, 0},
};

/* The state each context sets once, after it was first made current. */
static void set_up(ctx_state *s)
{
    glPixelStorei(GL_UNPACK_ALIGNMENT, s->unpack_alignment);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, s->unpack_row_length);
    glPixelStorei(GL_PACK_ALIGNMENT, s->pack_alignment);
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(2, GL_FLOAT, 0, s->vertices);
    if (s->use_colours) {
        glEnableClientState(GL_COLOR_ARRAY);
        glColorPointer(4, GL_UNSIGNED_BYTE, 0, s->colours);
    }
    glGenTextures(1, &s->texture);
}

static size_t row_bytes(int pixels, int bytes_per_pixel, int alignment)
{
    size_t raw = (size_t)pixels * (size_t)bytes_per_pixel;
    return (raw + (size_t)alignment - 1) / (size_t)alignment * (size_t)alignment;
}

/* One turn of context `k` in round `round`: its texture, its draw, its
 * read-back, appended to `raw`. */
static void turn(int k, int round, FILE *raw)
{
    ctx_state *s = &states[k];
    int row_pixels = s->unpack_row_length ? s->unpack_row_length : TEXELS;
    size_t stride = row_bytes(row_pixels, 3, s->unpack_alignment);
    unsigned char texels[64];
    memset(texels, 0xA5, sizeof texels); /* poisoned padding: visible if it is read as a texel */
    for (int y = 0; y < TEXELS; y++)
        for (int x = 0; x < TEXELS; x++)
            for (int c = 0; c < 3; c++)
                texels[(size_t)y * stride + (size_t)x * 3 + (size_t)c] =
                    (unsigned char)(40 * x + 70 * y + 25 * c + 60 * k + 10 * round);
    glBindTexture(GL_TEXTURE_2D, s->texture);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, TEXELS, TEXELS, 0, GL_RGB, GL_UNSIGNED_BYTE, texels);
    glViewport(0, 0, W, H);
    glClearColor(0.1f * (float)k, 0.2f, 0.05f * (float)round, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glEnable(GL_TEXTURE_2D);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    static const GLfloat uv[6] = {0.0f, 0.0f, 1.0f, 0.0f, 0.5f, 1.0f};
    glEnableClientState(GL_TEXTURE_COORD_ARRAY);
    glTexCoordPointer(2, GL_FLOAT, 0, uv);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisableClientState(GL_TEXTURE_COORD_ARRAY);
    glDisable(GL_TEXTURE_2D);
    unsigned char block[256];
    memset(block, 0, sizeof block);
    glReadPixels(3, 2, 7, 5, GL_RGB, GL_UNSIGNED_BYTE, block);
    fwrite(block, 1, row_bytes(7, 3, s->pack_alignment) * 5, raw);
    static unsigned char frame[W * H * 4];
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, frame);
    glPixelStorei(GL_PACK_ALIGNMENT, s->pack_alignment);
    fwrite(frame, 1, sizeof frame, raw);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s RAW\n", argv[0]);
        return 2;
    }
    FILE *raw = fopen(argv[1], "wb");
    REQUIRE(raw, "cannot write the RAW file");
#ifdef SHARE_NATIVE
    static unsigned char buffers[2][W * H * 4];
    OSMesaContext a = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, NULL);
    OSMesaContext b = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, a);
    REQUIRE(a && b, "two OSMesa contexts of one share group");
#define MAKE(k) REQUIRE(OSMesaMakeCurrent((k) ? b : a, buffers[k], GL_UNSIGNED_BYTE, W, H), "OSMesaMakeCurrent")
#else
    EGLDisplay dpy = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    REQUIRE(dpy != EGL_NO_DISPLAY && eglInitialize(dpy, NULL, NULL) && eglBindAPI(EGL_OPENGL_API), "EGL display");
    static const EGLint config_attrs[] = {
        EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_DEPTH_SIZE, 24, EGL_NONE};
    EGLConfig config;
    EGLint n = 0;
    REQUIRE(eglChooseConfig(dpy, config_attrs, &config, 1, &n) && n == 1, "an EGL config");
    EGLContext a = eglCreateContext(dpy, config, EGL_NO_CONTEXT, NULL);
    EGLContext b = eglCreateContext(dpy, config, a, NULL);
    static const EGLint surface_attrs[] = {EGL_WIDTH, W, EGL_HEIGHT, H, EGL_NONE};
    EGLSurface surfaces[2] = {eglCreatePbufferSurface(dpy, config, surface_attrs),
                              eglCreatePbufferSurface(dpy, config, surface_attrs)};
    REQUIRE(a && b && surfaces[0] && surfaces[1], "two EGL contexts of one share group and their pbuffers");
#define MAKE(k) REQUIRE(eglMakeCurrent(dpy, surfaces[k], surfaces[k], (k) ? b : a), "eglMakeCurrent")
#endif
    for (int k = 0; k < 2; k++) {
        MAKE(k);
        set_up(&states[k]);
    }
    for (int round = 0; round < 2; round++)
        for (int k = 0; k < 2; k++) {
            MAKE(k);
            turn(k, round, raw);
        }
    glFinish();
    REQUIRE(fclose(raw) == 0, "cannot write the RAW file");
#ifdef SHARE_NATIVE
    OSMesaDestroyContext(b);
    OSMesaDestroyContext(a);
#else
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(dpy, b);
    eglDestroyContext(dpy, a);
    eglDestroySurface(dpy, surfaces[0]);
    eglDestroySurface(dpy, surfaces[1]);
    eglTerminate(dpy);
#endif
    printf("share client state: 2 contexts x 2 rounds written to %s\n", argv[1]);
    return 0;
}
