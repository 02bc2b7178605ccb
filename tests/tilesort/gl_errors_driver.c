/* tests/tilesort/gl_errors_driver.c — GL errors and invalid queries as
 * programs make them, each answer printed on stdout: the test
 * (tilesort.sh records) runs the -native build (OSMesa itself, the
 * reference) and this one through render, pack -> node -> render and a
 * tile wall, and wants the same lines and the same frames.
 *
 * Every case makes one or two calls GL refuses (or none, as a control)
 * and prints what glGetError answers then and once more (Mesa keeps one
 * error: the first, and the second call says GL_NO_ERROR), and what an
 * invalid get wrote (GL writes nothing: the values printed are the
 * sentinels put there before). The cases: gets of a pname no GL knows, of
 * every kind the wire sizes by pname (a wall and pack once dropped the
 * program there); setters of such a pname; commands refused on the wall's
 * broadcast path (frame commands, objects); draws GL refuses, some of
 * whose vertices fall in one tile only (a wall sends them to the servers
 * whose tiles they touch); glBegin inside glBegin, then glClear GL refuses
 * (GL's answer is the first); shader sources and uniforms GL refuses;
 * proxy textures of sizes GL takes and refuses (3D ones of gigabytes,
 * as piglit's tex3d-maxsize asks); texture images and
 * sub-images GL refuses, and a sub-image of a generated mipmap level GL
 * keeps. Between the cases a
 * drawn frame shows that the wall still draws. Built twice like the
 * examples (examples/common/exapp.h). */
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <stdio.h>
#include <string.h>

#include "common/exapp.h"

#define NO_SUCH_PNAME 0x7fff0001u

/* The two answers: GL's error now, and after it (GL_NO_ERROR). */
static void errors(const char *what)
{
    GLenum first = glGetError();
    GLenum second = glGetError();
    printf("%s: error 0x%x then 0x%x\n", what, first, second);
}

static void ints(const char *what, const GLint *v, int n)
{
    printf("%s: wrote", what);
    for (int i = 0; i < n; i++)
        printf(" %d", v[i]);
    printf("\n");
    errors(what);
}

static void floats(const char *what, const GLfloat *v, int n)
{
    printf("%s: wrote", what);
    for (int i = 0; i < n; i++) {
        unsigned bits;
        memcpy(&bits, &v[i], 4);
        printf(" %08x", bits);
    }
    printf("\n");
    errors(what);
}

#define SENTINELS(v)                                             \
    do {                                                         \
        for (size_t i_ = 0; i_ < sizeof(v) / sizeof(v)[0]; i_++) \
            (v)[i_] = -7;                                        \
    } while (0)

/* Gets of pnames no GL knows, of every kind sized by the pname. */
static void unknown_pname_gets(GLuint shader, GLuint program, GLuint buffer)
{
    GLint iv[16];
    GLfloat fv[16];
    GLboolean bv[16];
    GLdouble dv[16];
    SENTINELS(iv);
    glGetIntegerv(NO_SUCH_PNAME, iv);
    ints("glGetIntegerv(unknown)", iv, 4);
    memset(bv, 0x5a, sizeof bv);
    glGetBooleanv(GL_CLIP_PLANE0 + 8, bv);
    printf("glGetBooleanv(GL_CLIP_PLANE0 + 8): wrote %d\n", bv[0]);
    errors("glGetBooleanv(GL_CLIP_PLANE0 + 8)");
    SENTINELS(fv);
    glGetFloatv(NO_SUCH_PNAME, fv);
    floats("glGetFloatv(unknown)", fv, 4);
    SENTINELS(dv);
    glGetDoublev(NO_SUCH_PNAME, dv);
    printf("glGetDoublev(unknown): wrote %g\n", dv[0]);
    errors("glGetDoublev(unknown)");
    SENTINELS(fv);
    glGetLightfv(GL_LIGHT0, NO_SUCH_PNAME, fv);
    floats("glGetLightfv(unknown)", fv, 4);
    SENTINELS(fv);
    glGetMaterialfv(GL_FRONT, NO_SUCH_PNAME, fv);
    floats("glGetMaterialfv(unknown)", fv, 4);
    SENTINELS(fv);
    glGetTexEnvfv(GL_TEXTURE_ENV, NO_SUCH_PNAME, fv);
    floats("glGetTexEnvfv(unknown)", fv, 4);
    SENTINELS(fv);
    glGetTexGenfv(GL_S, NO_SUCH_PNAME, fv);
    floats("glGetTexGenfv(unknown)", fv, 4);
    SENTINELS(fv);
    glGetTexParameterfv(GL_TEXTURE_2D, NO_SUCH_PNAME, fv);
    floats("glGetTexParameterfv(unknown)", fv, 4);
    SENTINELS(iv);
    glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, NO_SUCH_PNAME, iv);
    ints("glGetTexLevelParameteriv(unknown)", iv, 4);
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    SENTINELS(iv);
    glGetBufferParameteriv(GL_ARRAY_BUFFER, NO_SUCH_PNAME, iv);
    ints("glGetBufferParameteriv(unknown)", iv, 4);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    SENTINELS(iv);
    glGetShaderiv(shader, NO_SUCH_PNAME, iv);
    ints("glGetShaderiv(unknown)", iv, 4);
    SENTINELS(iv);
    glGetProgramiv(program, NO_SUCH_PNAME, iv);
    ints("glGetProgramiv(unknown)", iv, 4);
    /* only the errors: what these two write differs (Mesa writes 0 to the
     * first value of glGetVertexAttribfv; pack's reply of glGetQueryiv
     * carries the receiver's untouched zero) */
    glGetQueryiv(GL_SAMPLES_PASSED, NO_SUCH_PNAME, iv);
    errors("glGetQueryiv(unknown)");
    glGetVertexAttribfv(0, NO_SUCH_PNAME, fv);
    errors("glGetVertexAttribfv(unknown)");
    printf("glIsEnabled(unknown): %d\n", glIsEnabled(NO_SUCH_PNAME));
    errors("glIsEnabled(unknown)");
    /* and a known one after them all: the program goes on */
    SENTINELS(iv);
    glGetIntegerv(GL_MATRIX_MODE, iv);
    ints("glGetIntegerv(GL_MATRIX_MODE)", iv, 1);
}

/* Setters of pnames no GL knows. */
static void unknown_pname_setters(void)
{
    static const GLfloat v[4] = {0.5f, 0.25f, 0.125f, 1.0f};
    static const GLint iv[4] = {1, 2, 3, 4};
    glLightfv(GL_LIGHT0, NO_SUCH_PNAME, v);
    errors("glLightfv(unknown)");
    glMaterialfv(GL_FRONT, NO_SUCH_PNAME, v);
    errors("glMaterialfv(unknown)");
    glTexParameterfv(GL_TEXTURE_2D, NO_SUCH_PNAME, v);
    errors("glTexParameterfv(unknown)");
    glTexParameteriv(GL_TEXTURE_2D, NO_SUCH_PNAME, iv);
    errors("glTexParameteriv(unknown)");
    glTexEnvfv(GL_TEXTURE_ENV, NO_SUCH_PNAME, v);
    errors("glTexEnvfv(unknown)");
    glTexGenfv(GL_S, NO_SUCH_PNAME, v);
    errors("glTexGenfv(unknown)");
    glFogfv(NO_SUCH_PNAME, v);
    errors("glFogfv(unknown)");
    glLightModelfv(NO_SUCH_PNAME, v);
    errors("glLightModelfv(unknown)");
    glPixelStorei(NO_SUCH_PNAME, 1);
    errors("glPixelStorei(unknown)");
    glHint(NO_SUCH_PNAME, GL_NICEST);
    errors("glHint(unknown)");
}

/* Values GL refuses in state the tracker keeps. */
static void refused_state(void)
{
    glEnable(GL_CLIP_PLANE0 + 8);
    errors("glEnable(GL_CLIP_PLANE0 + 8)");
    glDisable(NO_SUCH_PNAME);
    errors("glDisable(unknown)");
    glMatrixMode(NO_SUCH_PNAME);
    errors("glMatrixMode(unknown)");
    glDepthFunc(NO_SUCH_PNAME);
    errors("glDepthFunc(unknown)");
    glPixelStoref(GL_UNPACK_ROW_LENGTH, -0.9f);
    errors("glPixelStoref(GL_UNPACK_ROW_LENGTH, -0.9)");
    glLineWidth(-1.0f);
    errors("glLineWidth(-1)");
    glMatrixMode(GL_MODELVIEW);
    glPopMatrix();
    errors("glPopMatrix() at depth 1");
    glPopAttrib();
    errors("glPopAttrib() at depth 0");
    glPixelStorei(GL_UNPACK_ALIGNMENT, 3);
    errors("glPixelStorei(GL_UNPACK_ALIGNMENT, 3)");
    GLint alignment = -7;
    glGetIntegerv(GL_UNPACK_ALIGNMENT, &alignment);
    ints("glGetIntegerv(GL_UNPACK_ALIGNMENT)", &alignment, 1);
    glEndList();
    errors("glEndList() outside glNewList");
}

/* Commands that go to every server, refused. */
static void refused_broadcast(void)
{
    glClear(0x80000000u);
    errors("glClear(bad bit)");
    glNewList(0, GL_COMPILE);
    errors("glNewList(0)");
    glCallList(12345); /* a list never made: no error */
    errors("glCallList(never made)");
    glEnd();
    errors("glEnd() outside glBegin");
}

/* Draws GL refuses, and an error on one tile's server before one on every
 * server: a refused draw inside glBegin (GL_INVALID_OPERATION) whose
 * vertices are in the lower-left tile only, then glClear of a bad bit. */
static void refused_draws(void)
{
    static const GLfloat tri[3][2] = {{-0.9f, -0.9f}, {-0.7f, -0.9f}, {-0.8f, -0.7f}};
    glEnableClientState(GL_VERTEX_ARRAY);
    glVertexPointer(2, GL_FLOAT, 0, tri);
    glDrawArrays(NO_SUCH_PNAME, 0, 3);
    errors("glDrawArrays(unknown mode)");
    glDrawArrays(GL_TRIANGLES, 0, -1);
    errors("glDrawArrays(count -1)");
    static const GLubyte idx[3] = {0, 1, 2};
    glDrawElements(GL_TRIANGLES, 3, GL_FLOAT, idx);
    errors("glDrawElements(type GL_FLOAT)");
    glDisableClientState(GL_VERTEX_ARRAY);
    glBegin(NO_SUCH_PNAME);
    glVertex2f(-0.9f, -0.9f);
    glEnd();
    errors("glBegin(unknown mode)");
    glBegin(GL_TRIANGLES);
    glVertex2f(-0.9f, -0.9f);
    glVertex2f(-0.7f, -0.9f);
    glBegin(GL_POINTS);
    glVertex2f(-0.8f, -0.7f);
    glEnd();
    glClear(0x80000000u);
    errors("glBegin inside glBegin in one tile, then glClear(bad bit)");
}

/* Proxy textures (piglit's proxy-texture): a size GL takes, then calls GL
 * refuses, which leave the proxy as it was. */
static void proxies(void)
{
    GLint w = -7;
    glTexImage2D(GL_PROXY_TEXTURE_2D, 0, GL_RGBA, 64, 32, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    glGetTexLevelParameteriv(GL_PROXY_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &w);
    ints("proxy 64x32: width", &w, 1);
    glTexImage2D(GL_PROXY_TEXTURE_2D, 0, GL_RGBA, 16, 16, 3, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    errors("proxy of border 3");
    glTexImage2D(GL_PROXY_TEXTURE_2D, -1, GL_RGBA, 16, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    errors("proxy of level -1");
    glTexImage2D(GL_PROXY_TEXTURE_2D, 0, GL_RGBA, -16, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    errors("proxy of width -16");
    w = -7;
    glGetTexLevelParameteriv(GL_PROXY_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &w);
    ints("proxy after them: width", &w, 1);
    glTexImage1D(GL_PROXY_TEXTURE_1D, 0, GL_RGBA, 1 << 20, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    w = -7;
    glGetTexLevelParameteriv(GL_PROXY_TEXTURE_1D, 0, GL_TEXTURE_WIDTH, &w);
    ints("1D proxy too wide: width", &w, 1);
    /* the sizes piglit's tex3d-maxsize asks of 3D proxies (a proxy
     * allocates nothing: 256 MiB to 8 GiB are only answered) */
    static const GLsizei sizes[3][3] = {{512, 512, 1024}, {1024, 1024, 2048}, {2048, 2048, 2048}};
    for (int k = 0; k < 3; k++) {
        GLint whd[3] = {-7, -7, -7};
        glTexImage3D(GL_PROXY_TEXTURE_3D, 0, GL_INTENSITY8, sizes[k][0], sizes[k][1], sizes[k][2], 0, GL_RGBA,
                     GL_UNSIGNED_BYTE, NULL);
        glGetTexLevelParameteriv(GL_PROXY_TEXTURE_3D, 0, GL_TEXTURE_WIDTH, &whd[0]);
        glGetTexLevelParameteriv(GL_PROXY_TEXTURE_3D, 0, GL_TEXTURE_HEIGHT, &whd[1]);
        glGetTexLevelParameteriv(GL_PROXY_TEXTURE_3D, 0, GL_TEXTURE_DEPTH, &whd[2]);
        printf("3D proxy %dx%dx%d GL_INTENSITY8:", (int)sizes[k][0], (int)sizes[k][1], (int)sizes[k][2]);
        ints(" size", whd, 3);
    }
}

/* Texture images GL refuses (piglit's teximage-errors): a wall's tracker
 * keeps images and sends them later, so it must refuse what GL refuses
 * (else no server sees the call, or every later state sent repeats it),
 * and keep what GL keeps: a sub-image of a level made by mipmap
 * generation, read back. */
static void refused_textures(void)
{
    GLuint tex = 0;
    glGenTextures(1, &tex);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexImage1D(GL_TEXTURE_2D, 0, GL_RGBA, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    errors("glTexImage1D(GL_TEXTURE_2D)");
    glTexImage2D(GL_TEXTURE_CUBE_MAP, 0, GL_RGBA, 16, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    errors("glTexImage2D(GL_TEXTURE_CUBE_MAP)");
    glTexImage2D(GL_TEXTURE_2D, 2000, GL_RGBA, 16, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    errors("glTexImage2D(level 2000)");
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 1 << 20, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    errors("glTexImage2D(width 1 << 20)");
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 8, 8, 2, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    errors("glTexImage2D(border 2)");
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 4, 4, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    errors("glTexSubImage2D(no image yet)");
    static GLubyte texels[8 * 8 * 4];
    for (size_t i = 0; i < sizeof texels; i++)
        texels[i] = (GLubyte)(i * 7);
    glTexParameteri(GL_TEXTURE_2D, GL_GENERATE_MIPMAP, GL_TRUE);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, 8, 8, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    errors("an 8x8 image with mipmaps generated");
    glTexSubImage2D(GL_TEXTURE_2D, 0, 4, 4, 8, 8, GL_RGBA, GL_FLOAT, NULL);
    errors("glTexSubImage2D(past the image, NULL pixels)");
    glTexSubImage2D(GL_TEXTURE_2D, 0, -1, 0, 2, 2, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    errors("glTexSubImage2D(x -1)");
    glTexSubImage2D(GL_PROXY_TEXTURE_2D, 0, 0, 0, 2, 2, GL_RGBA, GL_UNSIGNED_BYTE, texels);
    errors("glTexSubImage2D(GL_PROXY_TEXTURE_2D)");
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 2, 2, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    errors("glTexSubImage2D(NULL pixels)");
    glTexParameteri(GL_TEXTURE_2D, GL_GENERATE_MIPMAP, GL_FALSE);
    static const GLubyte red[2 * 2 * 4] = {255, 0, 0, 255, 255, 0, 0, 255, 255, 0, 0, 255, 255, 0, 0, 255};
    glTexSubImage2D(GL_TEXTURE_2D, 1, 1, 1, 2, 2, GL_RGBA, GL_UNSIGNED_BYTE, red);
    errors("glTexSubImage2D(a generated level)");
    GLubyte level1[4 * 4 * 4];
    memset(level1, 0x55, sizeof level1);
    glGetTexImage(GL_TEXTURE_2D, 1, GL_RGBA, GL_UNSIGNED_BYTE, level1);
    printf("level 1 read back:");
    for (size_t i = 0; i < sizeof level1; i += 4)
        printf(" %02x%02x%02x%02x", level1[i], level1[i + 1], level1[i + 2], level1[i + 3]);
    printf("\n");
    errors("glGetTexImage(level 1)");
    glBindTexture(GL_TEXTURE_2D, 0);
    glDeleteTextures(1, &tex);
}

/* Shader sources and uniforms GL refuses (piglit's shadersource-errors,
 * uniform-neg-location): the wall keeps both in the tracker. */
static void refused_glsl(GLuint shader, GLuint program)
{
    static const GLchar *const vs = "void main() { gl_Position = ftransform(); }";
    static const GLchar *const fs = "uniform float k; void main() { gl_FragColor = vec4(k); }";
    glShaderSource(shader, -1, &vs, NULL);
    errors("glShaderSource(count -1)");
    glShaderSource(program, 1, &vs, NULL);
    errors("glShaderSource(a program)");
    glShaderSource(54321, 1, &vs, NULL);
    errors("glShaderSource(no object)");
    static const GLfloat one[1] = {1.0f};
    glUseProgram(0);
    glUniform1f(-1, 1.0f);
    errors("glUniform1f(-1) with no program");
    /* (glUniform1fv(0, -1, v) with no program: GL_INVALID_OPERATION in
     * Mesa, which checks the program first; a packer, which cannot know
     * the receiver's program, answers GL_INVALID_VALUE) */
    GLuint linked = glCreateProgram(), v = glCreateShader(GL_VERTEX_SHADER), f = glCreateShader(GL_FRAGMENT_SHADER);
    glShaderSource(v, 1, &vs, NULL);
    glShaderSource(f, 1, &fs, NULL);
    glCompileShader(v);
    glCompileShader(f);
    glAttachShader(linked, v);
    glAttachShader(linked, f);
    glLinkProgram(linked);
    glUseProgram(linked);
    errors("a linked program in use");
    glUniform1f(-1, 1.0f);
    errors("glUniform1f(-1)");
    glUniform1f(-2, 1.0f);
    errors("glUniform1f(-2)");
    glUniform1fv(-1, -1, one);
    errors("glUniform1fv(-1, count -1)");
    glUseProgram(0);
    glDeleteProgram(linked);
    glDeleteShader(v);
    glDeleteShader(f);
    errors("the program deleted");
}

static void scene(int frame)
{
    glClearColor(0.1f, 0.1f, 0.2f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glRotatef(9.0f * (float)frame, 0, 0, 1);
    glBegin(GL_TRIANGLES);
    glColor3f(1, 0.5f, 0);
    glVertex2f(-0.8f, -0.8f);
    glColor3f(0, 1, 0.5f);
    glVertex2f(0.8f, -0.6f);
    glColor3f(0.5f, 0, 1);
    glVertex2f(0.1f, 0.9f);
    glEnd();
}

int main(int argc, char **argv)
{
    exapp app;
    if (!exapp_init(&app, "gl_errors", argc, argv, 320, 240))
        return app.exit_code;
    GLuint shader = glCreateShader(GL_VERTEX_SHADER);
    GLuint program = glCreateProgram();
    GLuint buffer = 0;
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    glBufferData(GL_ARRAY_BUFFER, 64, NULL, GL_STATIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    errors("set-up");
    for (int f = 0; f < app.frames; f++) {
        printf("frame %d\n", f);
        scene(f);
        errors("scene");
        unknown_pname_gets(shader, program, buffer);
        unknown_pname_setters();
        refused_state();
        refused_broadcast();
        refused_draws();
        refused_glsl(shader, program);
        proxies();
        refused_textures();
        scene(f);
        errors("scene again");
        if (!exapp_swap(&app))
            break;
    }
    glDeleteShader(shader);
    glDeleteProgram(program);
    glDeleteBuffers(1, &buffer);
    return exapp_finish(&app);
}
