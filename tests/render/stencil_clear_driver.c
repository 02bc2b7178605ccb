/* tests/render/stencil_clear_driver.c — render_stencil_clear solo|shared RAW:
 * frames whose depth clears keep the stencil (glClear without
 * GL_STENCIL_BUFFER_BIT), before and after the stencil is used, through a
 * `render` chain (shared: drawn by a second context, ContextCreateTSR, on
 * the shared window's renderbuffers) or, built with STENCIL_NATIVE
 * (render_stencil_clear_native), with OSMesa itself. render clears the
 * stencil too while the stream has never put another value than 0 in it
 * (spus/render/render.c, render_Clear): every frame's colour, depth and
 * stencil read-back must be OSMesa's own bytes, so the two RAW files must
 * be equal.
 *   0  colour+depth clear, depth-tested triangles;
 *   1  depth-only clear, the same;
 *   2  a stencil clear to 0, then a depth-only clear;
 *   3  the stencil test writes 1 under a triangle (REPLACE), then a
 *      depth-only clear, then a quad drawn where the stencil is 1;
 *   4  a depth-only clear: the triangle's stencil must still be there;
 *   5  glClearStencil(3) and a depth-only clear, a quad where it is 3. */
#ifdef STENCIL_NATIVE
#include <GL/osmesa.h>
#else
#include "tessera/chain.h"
#include "tessera/glapi.h"
#include "tessera/gltsr_gen.h"
#endif
#include <GL/gl.h>
#include <stdio.h>
#include <stdlib.h>

#define W 48
#define H 40

static void triangles(int frame)
{
    glEnable(GL_DEPTH_TEST);
    glBegin(GL_TRIANGLES);
    for (int i = 0; i < 3; i++) {
        float x = -0.8f + 0.5f * (float)i, z = 0.3f * (float)(i - 1) + 0.05f * (float)frame;
        glColor3f(0.2f + 0.3f * (float)i, 0.9f - 0.2f * (float)i, 0.1f * (float)frame);
        glVertex3f(x, -0.7f, z);
        glVertex3f(x + 0.9f, -0.4f, -z);
        glVertex3f(x + 0.3f, 0.8f, 0.5f * z);
    }
    glEnd();
    glDisable(GL_DEPTH_TEST);
}

static void quad_where_stencil_is(GLint value)
{
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_EQUAL, value, 0xff);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    glColor3f(1.0f, 1.0f, 0.0f);
    glRecti(-1, -1, 1, 1);
    glDisable(GL_STENCIL_TEST);
}

static void frame(int f)
{
    glViewport(0, 0, W, H);
    glClearColor(0.1f, 0.1f * (float)f, 0.3f, 1.0f);
    switch (f) {
    case 0: glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT); break;
    case 2:
        glClearStencil(0);
        glClear(GL_STENCIL_BUFFER_BIT);
        glClear(GL_COLOR_BUFFER_BIT);
        glClear(GL_DEPTH_BUFFER_BIT);
        break;
    case 3:
        glEnable(GL_STENCIL_TEST);
        glStencilFunc(GL_ALWAYS, 1, 0xff);
        glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
        glBegin(GL_TRIANGLES);
        glVertex2f(-0.5f, -0.5f);
        glVertex2f(0.6f, -0.3f);
        glVertex2f(0.0f, 0.7f);
        glEnd();
        glDisable(GL_STENCIL_TEST);
        glClear(GL_DEPTH_BUFFER_BIT);
        break;
    case 5:
        glClearStencil(3);
        glClear(GL_DEPTH_BUFFER_BIT);
        break;
    default: glClear(GL_DEPTH_BUFFER_BIT); break;
    }
    triangles(f);
    if (f == 3 || f == 4)
        quad_where_stencil_is(1);
    if (f == 5)
        quad_where_stencil_is(3);
}

static void read_back(FILE *raw)
{
    static unsigned char colour[W * H * 4];
    static GLuint depth[W * H];
    static unsigned char stencil[W * H];
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, colour);
    glReadPixels(0, 0, W, H, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, depth);
    glReadPixels(0, 0, W, H, GL_STENCIL_INDEX, GL_UNSIGNED_BYTE, stencil);
    fwrite(colour, 1, sizeof colour, raw);
    fwrite(depth, 1, sizeof depth, raw);
    fwrite(stencil, 1, sizeof stencil, raw);
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: %s solo|shared RAW\n", argv[0]);
        return 2;
    }
    FILE *raw = fopen(argv[2], "wb");
    if (!raw) {
        fprintf(stderr, "%s: cannot write %s\n", argv[0], argv[2]);
        return 1;
    }
#ifdef STENCIL_NATIVE
    static unsigned char buffer[W * H * 4];
    OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, NULL);
    if (!ctx || !OSMesaMakeCurrent(ctx, buffer, GL_UNSIGNED_BYTE, W, H)) {
        fprintf(stderr, "%s: no OSMesa context\n", argv[0]);
        return 1;
    }
    /* render starts from a cleared stencil; OSMesa's fresh one is
     * undefined, so the reference clears it once to GL's initial 0. */
    glClear(GL_STENCIL_BUFFER_BIT);
#else
    tsr_error err = {0};
    tsr_chain *chain = tsr_chain_create("render output=", &err);
    if (!chain) {
        fprintf(stderr, "%s: %s\n", argv[0], err.message);
        return 1;
    }
    tsr_gl_make_current(tsr_chain_head(chain));
    glWindowCreateTSR(0, W, H);
    if (argv[1][0] == 's' && argv[1][1] == 'h') {
        glContextCreateTSR(1);
        glMakeCurrentTSR(0, 1);
    }
#endif
    for (int f = 0; f < 6; f++) {
        frame(f);
        read_back(raw);
#ifndef STENCIL_NATIVE
        glSwapBuffersTSR(0, 0);
#endif
    }
    if (fclose(raw) != 0)
        return 1;
#ifdef STENCIL_NATIVE
    OSMesaDestroyContext(ctx);
#else
    glWindowDestroyTSR(0);
    tsr_gl_make_current(NULL);
    tsr_chain_destroy(chain);
#endif
    printf("stencil clear: 6 frames written to %s\n", argv[2]);
    return 0;
}
