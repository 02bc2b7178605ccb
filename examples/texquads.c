/* examples/texquads.c — textured quads, wide lines, large points, blending:
 * a mipmapped checker texture and an unmipmapped gradient texture
 * modulated by vertex colours, a translucent overlay, 6-pixel lines and
 * 10-pixel points that swing across the window. Ordinary GL 1.x code; owns
 * only its textures and drawing. Deterministic per frame. */
#include <math.h>
#include <stdlib.h>

#include <GL/gl.h>

#include "common/exapp.h"

#define CHECKER_SIZE 64
#define GRADIENT_SIZE 32
#define PI_F 3.14159265358979f

/* Builds every mip level of an 8x8-cell checker with a colour tint, each
 * level box-filtered from the previous one, and uploads them. */
static void upload_checker_mipmaps(void)
{
    int size = CHECKER_SIZE;
    unsigned char *level = malloc((size_t)size * size * 4);
    if (!level)
        return;
    for (int y = 0; y < size; y++)
        for (int x = 0; x < size; x++) {
            unsigned char *p = level + 4 * ((size_t)y * size + x);
            int on = ((x / 8) + (y / 8)) & 1;
            p[0] = (unsigned char)(on ? 240 : 40 + 2 * x);
            p[1] = (unsigned char)(on ? 240 : 60);
            p[2] = (unsigned char)(on ? 200 : 40 + 2 * y);
            p[3] = 255;
        }
    for (int lod = 0;; lod++) {
        glTexImage2D(GL_TEXTURE_2D, lod, GL_RGBA, size, size, 0, GL_RGBA, GL_UNSIGNED_BYTE, level);
        if (size == 1)
            break;
        int half = size / 2;
        for (int y = 0; y < half; y++)
            for (int x = 0; x < half; x++)
                for (int c = 0; c < 4; c++) {
                    int sum = level[4 * ((2 * y) * size + 2 * x) + c] + level[4 * ((2 * y) * size + 2 * x + 1) + c] +
                              level[4 * ((2 * y + 1) * size + 2 * x) + c] +
                              level[4 * ((2 * y + 1) * size + 2 * x + 1) + c];
                    /* in place is safe: row y of the result is written
                     * after rows 2y and 2y+1 of the source were read */
                    level[4 * (y * half + x) + c] = (unsigned char)((sum + 2) / 4);
                }
        size = half;
    }
    free(level);
}

static void upload_gradient(void)
{
    unsigned char pixels[GRADIENT_SIZE][GRADIENT_SIZE][4];
    for (int y = 0; y < GRADIENT_SIZE; y++)
        for (int x = 0; x < GRADIENT_SIZE; x++) {
            pixels[y][x][0] = (unsigned char)(x * 255 / (GRADIENT_SIZE - 1));
            pixels[y][x][1] = (unsigned char)(y * 255 / (GRADIENT_SIZE - 1));
            pixels[y][x][2] = (unsigned char)(255 - x * 255 / (GRADIENT_SIZE - 1));
            pixels[y][x][3] = (unsigned char)(128 + y * 127 / (GRADIENT_SIZE - 1));
        }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, GRADIENT_SIZE, GRADIENT_SIZE, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
}

static void setup(const exapp *app, GLuint textures[2])
{
    glViewport(0, 0, app->width, app->height);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    double aspect = (double)app->width / (double)app->height;
    glFrustum(-0.5 * aspect, 0.5 * aspect, -0.5, 0.5, 1.0, 50.0);
    glMatrixMode(GL_MODELVIEW);
    glClearColor(0.15f, 0.12f, 0.1f, 1.0f);
    glEnable(GL_DEPTH_TEST);

    glGenTextures(2, textures);
    glBindTexture(GL_TEXTURE_2D, textures[0]);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    upload_checker_mipmaps();

    glBindTexture(GL_TEXTURE_2D, textures[1]);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    upload_gradient();

    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
}

static void draw_floor(GLuint checker, float t)
{
    glBindTexture(GL_TEXTURE_2D, checker);
    glEnable(GL_TEXTURE_2D);
    glPushMatrix();
    glTranslatef(0, -1.2f, -6.0f);
    glRotatef(t * 10.0f, 0, 1, 0);
    glBegin(GL_QUADS);
    glColor3f(1.0f, 0.9f, 0.8f);
    glTexCoord2f(0, 0);
    glVertex3f(-8, 0, 8);
    glTexCoord2f(12, 0);
    glVertex3f(8, 0, 8);
    glColor3f(0.5f, 0.6f, 0.9f);
    glTexCoord2f(12, 12);
    glVertex3f(8, 0, -8);
    glTexCoord2f(0, 12);
    glVertex3f(-8, 0, -8);
    glEnd();
    glPopMatrix();
    glDisable(GL_TEXTURE_2D);
}

static void draw_panels(GLuint gradient, GLuint checker, float t)
{
    glEnable(GL_TEXTURE_2D);
    for (int i = 0; i < 3; i++) {
        glBindTexture(GL_TEXTURE_2D, i == 1 ? checker : gradient);
        glPushMatrix();
        glTranslatef(-1.6f + 1.6f * (float)i, 0.2f, -5.0f + 0.3f * (float)i);
        glRotatef(25.0f * t + 40.0f * (float)i, 0.3f, 1, 0.1f);
        glBegin(GL_QUADS);
        glColor4f(1, 1, 1, 1);
        glTexCoord2f(0, 0);
        glVertex3f(-0.6f, -0.6f, 0);
        glColor4f(1, 0.7f, 0.7f, 1);
        glTexCoord2f(1, 0);
        glVertex3f(0.6f, -0.6f, 0);
        glColor4f(0.7f, 1, 0.7f, 1);
        glTexCoord2f(1, 1);
        glVertex3f(0.6f, 0.6f, 0);
        glColor4f(0.7f, 0.7f, 1, 1);
        glTexCoord2f(0, 1);
        glVertex3f(-0.6f, 0.6f, 0);
        glEnd();
        glPopMatrix();
    }
    glDisable(GL_TEXTURE_2D);
}

/* Translucent gradient overlay and wide lines / large points in a 2D
 * pixel projection, drawn last with blending and no depth test. */
static void draw_overlay(const exapp *app, GLuint gradient, float t)
{
    glMatrixMode(GL_PROJECTION);
    glPushMatrix();
    glLoadIdentity();
    glOrtho(0, app->width, 0, app->height, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glPushMatrix();
    glLoadIdentity();
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);

    float w = (float)app->width, h = (float)app->height;
    glBindTexture(GL_TEXTURE_2D, gradient);
    glEnable(GL_TEXTURE_2D);
    glBegin(GL_QUADS);
    glColor4f(1, 1, 1, 0.6f);
    glTexCoord2f(0, 0);
    glVertex2f(0.05f * w, 0.05f * h);
    glTexCoord2f(1, 0);
    glVertex2f(0.35f * w, 0.05f * h);
    glTexCoord2f(1, 1);
    glVertex2f(0.35f * w, 0.3f * h);
    glTexCoord2f(0, 1);
    glVertex2f(0.05f * w, 0.3f * h);
    glEnd();
    glDisable(GL_TEXTURE_2D);

    glLineWidth(6.0f);
    glBegin(GL_LINES);
    for (int i = 0; i < 6; i++) {
        float a = t * 0.3f + (float)i * PI_F / 6.0f;
        glColor4f(1.0f, 0.3f + 0.1f * (float)i, 0.2f, 0.7f);
        glVertex2f(0.7f * w + 0.25f * h * cosf(a), 0.7f * h + 0.25f * h * sinf(a));
        glColor4f(0.2f, 0.5f, 1.0f, 0.7f);
        glVertex2f(0.7f * w - 0.25f * h * cosf(a), 0.7f * h - 0.25f * h * sinf(a));
    }
    glEnd();
    glLineWidth(1.0f);

    glPointSize(10.0f);
    glBegin(GL_POINTS);
    for (int i = 0; i < 24; i++) {
        float a = (float)i * 2.0f * PI_F / 24.0f + 0.2f * t;
        float r = 0.2f * h + 0.08f * h * sinf(3.0f * a + t);
        glColor4f(0.5f + 0.5f * cosf(a), 0.5f + 0.5f * sinf(a), 0.8f, 0.8f);
        glVertex2f(0.22f * w + r * cosf(a), 0.68f * h + r * sinf(a));
    }
    glEnd();
    glPointSize(1.0f);

    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glPopMatrix();
    glMatrixMode(GL_PROJECTION);
    glPopMatrix();
    glMatrixMode(GL_MODELVIEW);
}

int main(int argc, char **argv)
{
    exapp app;
    if (!exapp_init(&app, "texquads", argc, argv, 640, 480))
        return exapp_finish(&app);
    GLuint textures[2];
    setup(&app, textures);
    for (int f = 0; f < app.frames; f++) {
        float t = (float)f;
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glLoadIdentity();
        draw_floor(textures[0], t);
        draw_panels(textures[1], textures[0], t);
        draw_overlay(&app, textures[1], t);
        if (!exapp_swap(&app))
            break;
    }
    glDeleteTextures(2, textures);
    return exapp_finish(&app);
}
