/* tests/psubmit/psubmit_driver.c — small clients of a shared-mode server
 * node (server/node.h) for parallel-API behaviours psubmit cannot show.
 * Each role sends its commands through CHAIN (normally "pack server=ADDR")
 * and ends by destroying the chain, which waits for the server's
 * confirmation (or error):
 *   sem-first CHAIN    draws a red quad over the left two thirds, then V(5)
 *                      (psubmit.sh starts it once the node has logged that
 *                      sem-second waits on 5)
 *   sem-second CHAIN   P(5) first, then a green quad over the right two
 *                      thirds, then swaps: the overlap is green only if
 *                      the server held it until sem-first's V
 *   sem-reference CHAIN  both parts in that order in one stream (the
 *                      expected picture, drawn by a local render chain)
 *   p-forever CHAIN    creates semaphore 7 with value 0 and does P(7)
 *   barrier-wait CHAIN creates barrier 3 for 2 clients and waits at it
 *   barrier-leave CHAIN  creates barrier 3 for 2 clients and ends without
 *                      reaching it
 *   barrier-hold CHAIN creates barrier 3 for 2 clients, reads a pixel back
 *                      (the node has run it), prints "barrier-hold: held";
 *                      on SIGUSR1 reads one back again and prints
 *                      "barrier-hold: served again"; then holds its
 *                      connection, without reaching the barrier, until
 *                      killed (at most 30 s)
 *   swap-owner CHAIN   swaps, waits at barrier 4 (2 clients), swaps again
 *   swap-other CHAIN   waits at barrier 4, then swaps: the server must
 *                      ignore it (swap-owner swapped first)
 * Exit status: 0 when the chain finished cleanly, 1 otherwise (the pack
 * SPU exits 1 itself when the server dropped the stream). Owns only its
 * drawing. */
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include <GL/gl.h>

#include "tessera/chain.h"
#include "tessera/glapi.h"
#include "tessera/gltsr_gen.h"

#define WIDTH 96
#define HEIGHT 64
#define SEMAPHORE_ORDER 5
#define SEMAPHORE_NEVER 7
#define BARRIER_PAIR 3
#define BARRIER_SWAP 4

static void start(void)
{
    glWindowCreateTSR(0, WIDTH, HEIGHT);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0, 3, 0, 1, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
}

static void quad(float x0, float x1, float r, float g, float b)
{
    glColor3f(r, g, b);
    glBegin(GL_QUADS);
    glVertex2f(x0, 0.1f);
    glVertex2f(x1, 0.1f);
    glVertex2f(x1, 0.9f);
    glVertex2f(x0, 0.9f);
    glEnd();
}

/* A read-back is a round trip: when it returns, the node has run every
 * command sent before it. */
static void node_has_run_all(void)
{
    GLubyte pixel[4];
    glReadPixels(0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixel);
}

/* barrier-hold: tells the script (stderr) when the node has run its
 * stream, answers once more after SIGUSR1 (the script's "is the node still
 * serving?"), then keeps its connection open until the script kills it;
 * each wait is bounded so that a lost signal cannot hang the test. */
static void hold_barrier(void)
{
    sigset_t usr1;
    sigemptyset(&usr1);
    sigaddset(&usr1, SIGUSR1);
    sigprocmask(SIG_BLOCK, &usr1, NULL);
    node_has_run_all();
    fprintf(stderr, "barrier-hold: held\n");
    struct timespec bound = {.tv_sec = 30};
    if (sigtimedwait(&usr1, NULL, &bound) == SIGUSR1) {
        node_has_run_all();
        fprintf(stderr, "barrier-hold: served again\n");
    }
    sigtimedwait(&usr1, NULL, &bound);
}

static void first_part(void)
{
    glClearColor(0.1f, 0.1f, 0.3f, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    quad(0.0f, 2.0f, 1, 0, 0);
}

static void second_part(void) { quad(1.0f, 3.0f, 0, 1, 0); }

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: psubmit_driver ROLE CHAIN\n");
        return 2;
    }
    const char *role = argv[1];
    tsr_error err = {0};
    tsr_chain *chain = tsr_chain_create(argv[2], &err);
    if (!chain) {
        fprintf(stderr, "psubmit_driver: %s\n", err.message);
        return 1;
    }
    tsr_gl_make_current(tsr_chain_head(chain));
    start();
    int known = 1;
    if (!strcmp(role, "sem-first")) {
        glSemaphoreCreateTSR(SEMAPHORE_ORDER, 0);
        first_part();
        glSemaphoreVTSR(SEMAPHORE_ORDER);
    } else if (!strcmp(role, "sem-second")) {
        glSemaphoreCreateTSR(SEMAPHORE_ORDER, 0);
        glSemaphorePTSR(SEMAPHORE_ORDER);
        second_part();
        glSwapBuffersTSR(0, 0);
    } else if (!strcmp(role, "sem-reference")) {
        first_part();
        second_part();
        glSwapBuffersTSR(0, 0);
    } else if (!strcmp(role, "p-forever")) {
        glSemaphoreCreateTSR(SEMAPHORE_NEVER, 0);
        glSemaphorePTSR(SEMAPHORE_NEVER);
    } else if (!strcmp(role, "barrier-wait")) {
        glBarrierCreateTSR(BARRIER_PAIR, 2);
        glBarrierExecTSR(BARRIER_PAIR);
    } else if (!strcmp(role, "barrier-leave")) {
        glBarrierCreateTSR(BARRIER_PAIR, 2);
    } else if (!strcmp(role, "barrier-hold")) {
        glBarrierCreateTSR(BARRIER_PAIR, 2);
        hold_barrier();
    } else if (!strcmp(role, "swap-owner")) {
        glBarrierCreateTSR(BARRIER_SWAP, 2);
        first_part();
        glSwapBuffersTSR(0, 0);
        glBarrierExecTSR(BARRIER_SWAP);
        glSwapBuffersTSR(0, 0);
    } else if (!strcmp(role, "swap-other")) {
        glBarrierCreateTSR(BARRIER_SWAP, 2);
        glBarrierExecTSR(BARRIER_SWAP);
        glSwapBuffersTSR(0, 0);
    } else {
        known = 0;
    }
    glFinish();
    tsr_gl_make_current(NULL);
    tsr_chain_destroy(chain);
    if (!known) {
        fprintf(stderr, "psubmit_driver: unknown role '%s'\n", role);
        return 2;
    }
    return 0;
}
