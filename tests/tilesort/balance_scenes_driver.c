/* tests/tilesort/balance_scenes_driver.c — the scenes where a load balancer's
 * arithmetic fails if it is not careful (issue 13, item 5), each held for
 * four frames so the balancer re-splits on it (frame / 4 % 4):
 *   0 the whole cost in one pixel: 6000 one-pixel points on pixel
 *     (101, 73)
 *   1 one window-sized primitive (a quad over the whole window)
 *   2 an empty frame: only the clear
 *   3 an ordinary scene: rows of small triangles over the window, three
 *     times as dense in the left half
 * and, with --static, scene 3 only (the convergence tests' static scene).
 * Every frame clears: a server whose region moved must not show pixels it
 * drew for its old region.
 * Built twice like the examples (examples/common/exapp.h): -native is the
 * reference. The program never calls glViewport (GL's is the window's).
 * Deterministic per frame. */
#include <stdbool.h>

#include <GL/gl.h>

#include "common/exapp.h"

static void one_pixel(const exapp *app)
{
    /* a pixel centre in window coordinates, drawn with an identity
     * modelview and an orthographic projection of the window */
    float x = 101.5f, y = 73.5f;
    glBegin(GL_POINTS);
    for (int i = 0; i < 6000; i++) {
        glColor3f((float)(i % 7) / 7.0f, 0.5f, (float)(i % 3) / 3.0f);
        glVertex2f(x, y);
    }
    glEnd();
    (void)app;
}

static void window_quad(const exapp *app)
{
    glBegin(GL_QUADS);
    glColor3f(0.2f, 0.6f, 0.3f);
    glVertex2f(0, 0);
    glColor3f(0.8f, 0.6f, 0.3f);
    glVertex2f((float)app->width, 0);
    glColor3f(0.8f, 0.2f, 0.7f);
    glVertex2f((float)app->width, (float)app->height);
    glColor3f(0.2f, 0.2f, 0.9f);
    glVertex2f(0, (float)app->height);
    glEnd();
}

static void field(const exapp *app)
{
    /* rows of small triangles drawn in screen order (so each geometry
     * buffer stays local), three times as dense in the left half */
    float w = (float)app->width, h = (float)app->height;
    glBegin(GL_TRIANGLES);
    for (int j = 0; j < 24; j++)
        for (int i = 0; i < 80; i++) {
            float u = (float)i / 80.0f;
            float x = (u < 0.75f ? u / 1.5f : 0.5f + (u - 0.75f) * 2.0f) * (w - 12) + 2;
            float y = ((float)j + 0.5f) / 24.0f * (h - 12) + 2;
            glColor3f(u, (float)j / 24.0f, 1.0f - u);
            glVertex2f(x, y);
            glVertex2f(x + 9, y + 1);
            glVertex2f(x + 4, y + 7);
        }
    glEnd();
}

int main(int argc, char **argv)
{
    exapp app;
    bool still = false;
    if (!exapp_init_flag(&app, "balance_scenes", argc, argv, 256, 192, "--static",
                         "  --static         the ordinary scene only, every frame", &still))
        return app.exit_code;
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0, app.width, 0, app.height, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glClearColor(0.05f, 0.05f, 0.1f, 1.0f);
    while (app.frame < app.frames) {
        int scene = still ? 3 : app.frame / 4 % 4;
        glClear(GL_COLOR_BUFFER_BIT);
        if (scene == 0)
            one_pixel(&app);
        else if (scene == 1)
            window_quad(&app);
        else if (scene == 3)
            field(&app);
        if (!exapp_swap(&app))
            break;
    }
    return exapp_finish(&app);
}
