/* tests/capture/asks_driver.c — a program whose stream depends on the answers it
 * gets back: `asks CHAIN FRAMES` (64x48, through libtessera_gl) asks
 * glGenLists for list names, glGetIntegerv(GL_VIEWPORT) for the window,
 * glGetFloatv for a matrix and glReadPixels for a pixel of each frame, and
 * draws the next frame from them (list names, rectangle size, colour). A
 * capture of it replays exactly only if the replay feeds the stream as
 * captured, whatever its chain would answer. Prints each answer it got. */
#include <GL/gl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/chain.h"
#include "tessera/glapi.h"
#include "tessera/gltsr_gen.h"

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: asks CHAIN|- FRAMES (-: $TESSERA_CHAIN)\n");
        return 2;
    }
    int frames = atoi(argv[2]);
    const char *text = strcmp(argv[1], "-") ? argv[1] : getenv("TESSERA_CHAIN");
    tsr_error err = {0};
    tsr_chain *chain = tsr_chain_create(text ? text : "", &err);
    if (!chain) {
        fprintf(stderr, "asks: %s\n", err.message);
        return 1;
    }
    tsr_gl_make_current(tsr_chain_head(chain));
    glWindowCreateTSR(0, 64, 48);
    glViewport(0, 0, 64, 48);
    GLuint lists = glGenLists(2);
    printf("glGenLists: %u\n", lists);
    glNewList(lists, GL_COMPILE);
    glBegin(GL_TRIANGLES);
    glVertex2f(-0.8f, -0.8f);
    glVertex2f(0.8f, -0.8f);
    glVertex2f(0.0f, 0.8f);
    glEnd();
    glEndList();
    glNewList(lists + 1, GL_COMPILE);
    glRotatef(17.0f, 0, 0, 1);
    glEndList();
    GLubyte pixel[4] = {0, 0, 0, 0};
    for (int f = 0; f < frames; f++) {
        GLint vp[4] = {0, 0, 0, 0};
        glGetIntegerv(GL_VIEWPORT, vp);
        GLfloat m[16] = {0};
        glGetFloatv(GL_MODELVIEW_MATRIX, m);
        printf("frame %d: viewport %d %d %d %d, m[0] %g, pixel %u %u %u\n", f, vp[0], vp[1], vp[2], vp[3], m[0],
               pixel[0], pixel[1], pixel[2]);
        glClearColor(pixel[0] / 255.0f, 0.2f, 0.3f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        glMatrixMode(GL_MODELVIEW);
        glLoadIdentity();
        for (int i = 0; i <= f; i++)
            glCallList(lists + 1);
        glColor3f(1.0f - f * 0.2f, 0.5f, (GLfloat)vp[2] / 128.0f);
        glCallList(lists);
        glRecti(vp[2] / 4, vp[3] / 4, vp[2] / 3, vp[3] / 3);
        glReadPixels(vp[2] / 2, vp[3] / 2, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixel);
        glSwapBuffersTSR(0, 0);
    }
    glDeleteLists(lists, 2);
    glWindowDestroyTSR(0);
    tsr_gl_make_current(NULL);
    tsr_chain_destroy(chain);
    return 0;
}
