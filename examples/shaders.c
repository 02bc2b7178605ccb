/* examples/shaders.c — GLSL programs (OpenGL 2.0) drawn like a GL 1.x
 * program draws: a waving grid whose vertex shader moves every vertex
 * (uniforms: time, amplitude, a 2x2 twist matrix, a tint, a band count;
 * a per-vertex attribute bound with glBindAttribLocation), small quads
 * whose fragment-only program stripes them by window position (fixed-
 * function vertices: a sort-first wall can place them by their box), and
 * a fixed-function frame around it all. Uniforms change every frame; at
 * frame 3 the stripe program is relinked from a new source (uniforms go
 * back to 0 and are set again). Shaders are detached and deleted after
 * linking, as many programs do. Deterministic per frame. Owns only its
 * programs and drawing. */
#define GL_GLEXT_PROTOTYPES 1
#include <math.h>
#include <stdio.h>

#include <GL/gl.h>
#include <GL/glext.h>

#include "common/exapp.h"

#define GRID 24

static const char *wave_vs = "uniform float time;\n"
                             "uniform float amplitude;\n"
                             "uniform mat2 twist;\n"
                             "attribute float shade;\n"
                             "varying float v_shade;\n"
                             "void main() {\n"
                             "    vec4 p = gl_Vertex;\n"
                             "    p.xy = twist * p.xy;\n"
                             "    p.z += amplitude * sin(3.0 * p.x + time) * cos(2.0 * p.y - 0.5 * time);\n"
                             "    v_shade = shade;\n"
                             "    gl_FrontColor = gl_Color;\n"
                             "    gl_Position = gl_ModelViewProjectionMatrix * p;\n"
                             "}\n";

static const char *wave_fs = "uniform vec3 tint;\n"
                             "uniform int bands;\n"
                             "varying float v_shade;\n"
                             "void main() {\n"
                             "    float b = floor(v_shade * float(bands)) / float(bands);\n"
                             "    gl_FragColor = vec4(gl_Color.rgb * tint * (0.4 + 0.6 * b), 1.0);\n"
                             "}\n";

static const char *stripe_fs[2] = {
    "uniform vec4 pulse;\n"
    "uniform float width;\n"
    "void main() {\n"
    "    float s = step(0.5, fract((gl_FragCoord.x + gl_FragCoord.y) / width));\n"
    "    gl_FragColor = mix(gl_Color, pulse, s);\n"
    "}\n",
    "uniform vec4 pulse;\n"
    "uniform float width;\n"
    "void main() {\n"
    "    float s = step(0.5, fract(gl_FragCoord.y / width));\n"
    "    gl_FragColor = mix(pulse, gl_Color.bgra, s);\n"
    "}\n",
};

static GLuint compile(GLenum type, const char *src)
{
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        fprintf(stderr, "shaders: a shader does not compile: %s\n", log);
    }
    return s;
}

/* Links program p from the given shaders, then detaches and deletes them. */
static int link(GLuint p, GLuint vs, GLuint fs)
{
    if (vs)
        glAttachShader(p, vs);
    glAttachShader(p, fs);
    glLinkProgram(p);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        glGetProgramInfoLog(p, sizeof log, NULL, log);
        fprintf(stderr, "shaders: a program does not link: %s\n", log);
    }
    if (vs) {
        glDetachShader(p, vs);
        glDeleteShader(vs);
    }
    glDetachShader(p, fs);
    glDeleteShader(fs);
    return ok;
}

static void draw_wave(GLuint prog, int frame)
{
    float t = 0.35f * (float)frame;
    glUseProgram(prog);
    glUniform1f(glGetUniformLocation(prog, "time"), t);
    glUniform1f(glGetUniformLocation(prog, "amplitude"), 0.12f + 0.04f * sinf(t));
    GLfloat c = cosf(0.2f * t), s = sinf(0.2f * t);
    const GLfloat twist[4] = {c, s, -s, c};
    glUniformMatrix2fv(glGetUniformLocation(prog, "twist"), 1, GL_FALSE, twist);
    glUniform3f(glGetUniformLocation(prog, "tint"), 1.0f, 0.8f + 0.2f * s, 0.7f + 0.3f * c);
    glUniform1i(glGetUniformLocation(prog, "bands"), 3 + frame % 4);
    glPushMatrix();
    glTranslatef(0.0f, 0.0f, -2.6f);
    glRotatef(-55.0f, 1.0f, 0.0f, 0.0f);
    for (int j = 0; j < GRID; j++) {
        glBegin(GL_TRIANGLE_STRIP);
        for (int i = 0; i <= GRID; i++)
            for (int k = 0; k < 2; k++) {
                float x = -1.0f + 2.0f * (float)i / GRID, y = -1.0f + 2.0f * (float)(j + k) / GRID;
                glColor3f(0.5f + 0.5f * x, 0.5f + 0.5f * y, 0.6f);
                glVertexAttrib1f(1, 0.5f + 0.5f * sinf(4.0f * x * y + 0.1f * (float)frame));
                glVertex3f(x, y, 0.0f);
            }
        glEnd();
    }
    glPopMatrix();
}

static void draw_stripes(GLuint prog, int frame)
{
    glUseProgram(prog);
    float t = 0.5f * (float)frame;
    glUniform4f(glGetUniformLocation(prog, "pulse"), 0.5f + 0.5f * sinf(t), 0.3f, 0.5f + 0.5f * cosf(t), 1.0f);
    glUniform1f(glGetUniformLocation(prog, "width"), 6.0f + (float)(frame % 5));
    glPushMatrix();
    glTranslatef(0.0f, 0.0f, -2.0f);
    for (int q = 0; q < 4; q++) {
        float cx = (q & 1 ? 0.42f : -0.42f) + 0.05f * sinf(t + (float)q);
        float cy = q & 2 ? 0.28f : -0.28f;
        glBegin(GL_QUADS);
        glColor3f(q & 1 ? 1.0f : 0.2f, 0.9f, q & 2 ? 1.0f : 0.3f);
        glVertex3f(cx - 0.12f, cy - 0.1f, 0.0f);
        glVertex3f(cx + 0.12f, cy - 0.1f, 0.0f);
        glVertex3f(cx + 0.12f, cy + 0.1f, 0.0f);
        glVertex3f(cx - 0.12f, cy + 0.1f, 0.0f);
        glEnd();
    }
    glPopMatrix();
}

static void draw_frame(void)
{
    glUseProgram(0);
    glPushMatrix();
    glTranslatef(0.0f, 0.0f, -2.0f);
    glColor3f(0.9f, 0.9f, 0.9f);
    glLineWidth(3.0f);
    glBegin(GL_LINE_LOOP);
    glVertex3f(-0.7f, -0.5f, 0.0f);
    glVertex3f(0.7f, -0.5f, 0.0f);
    glVertex3f(0.7f, 0.5f, 0.0f);
    glVertex3f(-0.7f, 0.5f, 0.0f);
    glEnd();
    glPopMatrix();
}

int main(int argc, char **argv)
{
    exapp app;
    if (!exapp_init(&app, "shaders", argc, argv, 400, 300))
        return app.exit_code;
    glViewport(0, 0, app.width, app.height);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    double aspect = (double)app.width / (double)app.height;
    glFrustum(-0.5 * aspect, 0.5 * aspect, -0.5, 0.5, 1.0, 20.0);
    glMatrixMode(GL_MODELVIEW);
    glClearColor(0.08f, 0.1f, 0.14f, 1.0f);
    glEnable(GL_DEPTH_TEST);

    GLuint wave = glCreateProgram();
    glBindAttribLocation(wave, 1, "shade");
    int ok = link(wave, compile(GL_VERTEX_SHADER, wave_vs), compile(GL_FRAGMENT_SHADER, wave_fs));
    GLuint stripes = glCreateProgram();
    ok &= link(stripes, 0, compile(GL_FRAGMENT_SHADER, stripe_fs[0]));
    if (!ok) {
        exapp_finish(&app);
        return 1;
    }
    for (int f = 0; f < app.frames; f++) {
        if (f == 3) /* a new source for the stripes: relinked, uniforms back to 0 */
            link(stripes, 0, compile(GL_FRAGMENT_SHADER, stripe_fs[1]));
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glLoadIdentity();
        draw_wave(wave, f);
        draw_stripes(stripes, f);
        draw_frame();
        if (!exapp_swap(&app))
            break;
    }
    glDeleteProgram(wave);
    glDeleteProgram(stripes);
    return exapp_finish(&app);
}
