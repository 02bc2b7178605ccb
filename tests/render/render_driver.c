/* tests/render/render_driver.c — drives render SPU chains directly from
 * GL code linked against libtessera_gl, for behaviours the examples do not
 * show:
 *   both DIR FRAMES           two chains at once on two threads, each
 *                             drawing its own scene (DIR/a-N.png, b-N.png)
 *   single A|B PATTERN FRAMES one scene alone (the reference for `both`)
 *   no-window PATTERN         draw and swap without any window command
 * Owns only its scenes; the test scripts judge the PNGs. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>

#include "tessera/chain.h"
#include "tessera/glapi.h"
#include "tessera/gltsr_gen.h"

typedef struct scene_job {
    char which; /* 'A' or 'B': picks colours, motion and window size */
    char chain_text[600];
    int frames;
    int exit_code;
    char message[600];
} scene_job;

/* Deterministic per (scene, frame): overlapping depth-tested triangles. */
static void draw_scene(char which, int frame, int width, int height)
{
    float base = which == 'A' ? 0.2f : 0.7f;
    glViewport(0, 0, width, height);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(-1, 1, -1, 1, -2, 2);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glRotatef((which == 'A' ? 9.0f : -13.0f) * (float)frame, 0, 0, 1);
    glClearColor(base, 0.1f, 1.0f - base, 1);
    glEnable(GL_DEPTH_TEST);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glBegin(GL_TRIANGLES);
    for (int i = 0; i < 12; i++) {
        float a = (float)i * 0.5236f;
        float r = 0.2f + 0.06f * (float)i;
        glColor3f(base, (float)i / 12.0f, 1.0f - (float)i / 12.0f);
        glVertex3f(r * (a - 3.0f) / 3.0f, -0.8f, 0.1f * (float)(i % 5) - 0.2f);
        glVertex3f(0.9f - 0.1f * (float)i, 0.7f * (which == 'A' ? 1.0f : -1.0f), 0.0f);
        glVertex3f(-0.9f + 0.12f * (float)i, 0.1f * (float)i - 0.5f, -0.1f * (float)(i % 3));
    }
    glEnd();
}

static void *run_scene(void *arg)
{
    scene_job *job = arg;
    int width = job->which == 'A' ? 160 : 200, height = job->which == 'A' ? 120 : 150;
    tsr_error err = {0};
    tsr_chain *chain = tsr_chain_create(job->chain_text, &err);
    if (!chain) {
        snprintf(job->message, sizeof job->message, "chain %c: %s", job->which, err.message);
        job->exit_code = 1;
        return NULL;
    }
    tsr_gl_make_current(tsr_chain_head(chain));
    glWindowCreateTSR(0, width, height);
    for (int f = 0; f < job->frames; f++) {
        draw_scene(job->which, f, width, height);
        glSwapBuffersTSR(0, 0);
    }
    glWindowDestroyTSR(0);
    tsr_gl_make_current(NULL);
    tsr_chain_destroy(chain);
    return NULL;
}

int main(int argc, char **argv)
{
    if (argc == 4 && !strcmp(argv[1], "both")) {
        scene_job jobs[2] = {{.which = 'A'}, {.which = 'B'}};
        pthread_t threads[2];
        for (int i = 0; i < 2; i++) {
            jobs[i].frames = atoi(argv[3]);
            snprintf(jobs[i].chain_text, sizeof jobs[i].chain_text, "render output=\"%s/%c-%%d.png\"", argv[2],
                     i ? 'b' : 'a');
            if (pthread_create(&threads[i], NULL, run_scene, &jobs[i]) != 0) {
                fprintf(stderr, "render_driver: pthread_create failed\n");
                return 1;
            }
        }
        int rc = 0;
        for (int i = 0; i < 2; i++) {
            pthread_join(threads[i], NULL);
            if (jobs[i].exit_code) {
                fprintf(stderr, "render_driver: %s\n", jobs[i].message);
                rc = 1;
            }
        }
        return rc;
    }
    if (argc == 3 && !strcmp(argv[1], "no-window")) {
        char chain_text[600];
        snprintf(chain_text, sizeof chain_text, "render output=\"%s\"", argv[2]);
        tsr_error err = {0};
        tsr_chain *chain = tsr_chain_create(chain_text, &err);
        if (!chain) {
            fprintf(stderr, "render_driver: %s\n", err.message);
            return 1;
        }
        tsr_gl_make_current(tsr_chain_head(chain));
        draw_scene('A', 0, 512, 512);
        glSwapBuffersTSR(0, 0);
        tsr_gl_make_current(NULL);
        tsr_chain_destroy(chain);
        return 0;
    }
    if (argc == 5 && !strcmp(argv[1], "single") && (argv[2][0] == 'A' || argv[2][0] == 'B')) {
        scene_job job = {.which = argv[2][0], .frames = atoi(argv[4])};
        snprintf(job.chain_text, sizeof job.chain_text, "render output=\"%s\"", argv[3]);
        run_scene(&job);
        if (job.exit_code)
            fprintf(stderr, "render_driver: %s\n", job.message);
        return job.exit_code;
    }
    fprintf(stderr, "usage: render_driver both DIR FRAMES | single A|B PATTERN FRAMES |\n"
                    "                     no-window PATTERN\n");
    return 2;
}
