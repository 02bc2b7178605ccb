/* tests/fuzz/seed_writer.c — writes the fuzz corpus seeds: real streams made
 * by the real packer (immediate-mode spheres, textures, display lists,
 * client arrays and buffer objects, gets with replies, extended opcodes,
 * pixel and shader commands), named ok-*.bin, and malformed streams derived
 * from single packed commands at the offsets tessera/dev/wire.h documents, named
 * bad-*.bin. Every seed is checked through fuzz_unpack_one() before it is
 * written: ok-* must decode, bad-* must be rejected (the replay test holds
 * the committed corpus to the same rule). Replies are answered by a real
 * unpacker over the generated recording table (it stands in for GL). The
 * every-command seeds call each packable command once with random valid
 * arguments (the generated wire-test calls).
 * Usage: fuzz_seed_writer OUTDIR   (exit 0: every seed written and checked) */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>
#include <GL/glext.h>

#include "fuzz_unpack.h"
#include "tessera/dev/pack.h"
#include "tessera/dispatch.h"
#include "tessera/dev/unpack.h"
#include "tessera/dev/wire.h"
#include "wire_test_gen.h"

/* "every command" calls each reply command of the spec once */
#define MAX_REPLIES 256

typedef struct stored_reply {
    uint32_t id;
    uint8_t *bytes;
    size_t size;
} stored_reply;

/* Everything the packer flushed for one scenario, plus the answers. */
typedef struct capture {
    uint8_t *bytes;
    size_t len, cap;
    size_t buffers;
    size_t first_buffer_size;
    tsr_dispatch *answer_table;
    tsr_recorder answer_gl; /* stands in for GL behind the answering unpacker */
    tsr_unpacker *answer;
    stored_reply replies[MAX_REPLIES];
    size_t nreplies;
} capture;

static int store_answer(void *ctx, uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    capture *c = ctx;
    if (c->nreplies == MAX_REPLIES)
        return tsr_error_set(err, TSR_ENOMEM, "seed_writer: more than %d replies", MAX_REPLIES);
    stored_reply *r = &c->replies[c->nreplies];
    r->bytes = malloc(size ? size : 1);
    if (!r->bytes)
        return tsr_error_set(err, TSR_ENOMEM, "seed_writer: out of memory");
    memcpy(r->bytes, data, size);
    r->size = size;
    r->id = id;
    c->nreplies++;
    return 0;
}

static int capture_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    capture *c = ctx;
    if (c->len + size > c->cap) {
        size_t cap = c->cap ? c->cap : 4096;
        while (cap < c->len + size)
            cap *= 2;
        uint8_t *p = realloc(c->bytes, cap);
        if (!p)
            return tsr_error_set(err, TSR_ENOMEM, "seed_writer: out of memory");
        c->bytes = p;
        c->cap = cap;
    }
    memcpy(c->bytes + c->len, buf, size);
    c->len += size;
    if (c->buffers++ == 0)
        c->first_buffer_size = size;
    return tsr_unpacker_run(c->answer, buf, size, err);
}

static int capture_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    capture *c = ctx;
    for (size_t i = 0; i < c->nreplies; i++) {
        if (c->replies[i].id == id) {
            *data = c->replies[i].bytes;
            *size = c->replies[i].size;
            return 0;
        }
    }
    return tsr_error_set(err, TSR_EPROTO, "seed_writer: no reply to request %u", id);
}

static void capture_free(capture *c)
{
    for (size_t i = 0; i < c->nreplies; i++)
        free(c->replies[i].bytes);
    tsr_unpacker_destroy(c->answer);
    tsr_recorder_clear(&c->answer_gl);
    free(c->answer_table);
    free(c->bytes);
    memset(c, 0, sizeof *c);
}

typedef void (*scenario_fn)(const tsr_dispatch *gl);

/* Runs `fn` against a packer whose buffers hold `buffer_size` bytes and
 * captures the stream. Returns 0, or -1 with a message printed. */
static int record(const char *name, size_t buffer_size, scenario_fn fn, capture *c)
{
    memset(c, 0, sizeof *c);
    tsr_error err;
    tsr_error_clear(&err);
    c->answer_table = malloc(sizeof *c->answer_table);
    if (!c->answer_table)
        return -1;
    tsr_recorder_init(&c->answer_gl);
    tsr_recorder_fill(c->answer_table, &c->answer_gl);
    c->answer = tsr_unpacker_create(c->answer_table, store_answer, c, &err);
    tsr_pack_sink sink = {.flush = capture_flush, .reply = capture_reply, .ctx = c};
    tsr_packer *p = c->answer ? tsr_packer_create(buffer_size, &sink, &err) : NULL;
    tsr_dispatch *gl = malloc(sizeof *gl);
    if (!p || !gl) {
        fprintf(stderr, "seed_writer: %s: %s\n", name, err.message[0] ? err.message : "out of memory");
        tsr_packer_destroy(p);
        free(gl);
        return -1;
    }
    tsr_dispatch_fill_nop(gl);
    tsr_packer_fill_dispatch(p, gl);
    fn(gl);
    tsr_packer_flush(p);
    const tsr_error *perr = tsr_packer_error(p);
    int rc = 0;
    if (perr->code != TSR_OK) {
        fprintf(stderr, "seed_writer: %s: packer error: %s\n", name, perr->message);
        rc = -1;
    }
    tsr_packer_destroy(p);
    free(gl);
    return rc;
}

/* --- valid scenarios ------------------------------------------------------- */

static void sphere(const tsr_dispatch *gl, float radius, int stacks, int slices)
{
    for (int i = 0; i < stacks; i++) {
        float a0 = 3.14159265f * (float)i / (float)stacks - 1.5707963f;
        float a1 = 3.14159265f * (float)(i + 1) / (float)stacks - 1.5707963f;
        tsr_call_Begin(gl, GL_QUAD_STRIP);
        for (int j = 0; j <= slices; j++) {
            float b = 6.2831853f * (float)j / (float)slices;
            /* cheap cos/sin stand-ins keep the seed deterministic across libms */
            float cb = 1.0f - b * b / 2.0f + b * b * b * b / 24.0f, sb = b - b * b * b / 6.0f;
            float c0 = 1.0f - a0 * a0 / 2.0f, s0 = a0 - a0 * a0 * a0 / 6.0f;
            float c1 = 1.0f - a1 * a1 / 2.0f, s1 = a1 - a1 * a1 * a1 / 6.0f;
            tsr_call_Normal3f(gl, c0 * cb, c0 * sb, s0);
            tsr_call_Vertex3f(gl, radius * c0 * cb, radius * c0 * sb, radius * s0);
            tsr_call_Normal3f(gl, c1 * cb, c1 * sb, s1);
            tsr_call_Vertex3f(gl, radius * c1 * cb, radius * c1 * sb, radius * s1);
        }
        tsr_call_End(gl);
    }
}

static void scenario_spheres(const tsr_dispatch *gl)
{
    static const GLfloat light_pos[4] = {1, 2, 3, 0}, diffuse[4] = {1, 1, 0.9f, 1};
    static const GLfloat red[4] = {0.8f, 0.1f, 0.1f, 1}, blue[4] = {0.1f, 0.2f, 0.9f, 1};
    tsr_call_Viewport(gl, 0, 0, 256, 256);
    tsr_call_ClearColor(gl, 0.1f, 0.1f, 0.2f, 1.0f);
    tsr_call_Clear(gl, GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    tsr_call_MatrixMode(gl, GL_PROJECTION);
    tsr_call_LoadIdentity(gl);
    tsr_call_Frustum(gl, -1, 1, -1, 1, 1, 20);
    tsr_call_MatrixMode(gl, GL_MODELVIEW);
    tsr_call_LoadIdentity(gl);
    tsr_call_Translatef(gl, 0, 0, -6);
    tsr_call_Enable(gl, GL_DEPTH_TEST);
    tsr_call_Enable(gl, GL_LIGHTING);
    tsr_call_Enable(gl, GL_LIGHT0);
    tsr_call_Lightfv(gl, GL_LIGHT0, GL_POSITION, light_pos);
    tsr_call_Lightfv(gl, GL_LIGHT0, GL_DIFFUSE, diffuse);
    tsr_call_Materialf(gl, GL_FRONT, GL_SHININESS, 20.0f);
    for (int k = 0; k < 2; k++) {
        tsr_call_PushMatrix(gl);
        tsr_call_Translatef(gl, k ? 1.2f : -1.2f, 0, 0);
        tsr_call_Rotatef(gl, 30.0f * (float)k, 0, 1, 0);
        tsr_call_Materialfv(gl, GL_FRONT, GL_AMBIENT_AND_DIFFUSE, k ? blue : red);
        sphere(gl, 1.0f, 6, 10);
        tsr_call_PopMatrix(gl);
    }
    tsr_call_Disable(gl, GL_LIGHTING);
    tsr_call_Color4f(gl, 1, 1, 1, 0.5f);
    tsr_call_Color3ub(gl, 200, 100, 50);
    tsr_call_Begin(gl, GL_LINES);
    tsr_call_Vertex3f(gl, -2, -2, 0);
    tsr_call_Vertex3f(gl, 2, 2, 0);
    tsr_call_End(gl);
    tsr_call_Flush(gl);
    tsr_call_SwapBuffersTSR(gl, 0, 0);
}

static void scenario_texture(const tsr_dispatch *gl)
{
    GLuint tex[2] = {0, 0};
    GLubyte image[8 * 8 * 3];
    for (unsigned i = 0; i < sizeof image; i++)
        image[i] = (GLubyte)(i * 7u);
    tsr_call_GenTextures(gl, 2, tex);
    tsr_call_BindTexture(gl, GL_TEXTURE_2D, tex[0]);
    tsr_call_TexParameteri(gl, GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    tsr_call_TexParameteri(gl, GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    tsr_call_TexParameteri(gl, GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    tsr_call_PixelStorei(gl, GL_UNPACK_ALIGNMENT, 1);
    tsr_call_TexImage2D(gl, GL_TEXTURE_2D, 0, GL_RGB, 8, 8, 0, GL_RGB, GL_UNSIGNED_BYTE, image);
    /* A sub-image read with row length and skips: the payload size depends
     * on the mirrored pixel store. */
    tsr_call_PixelStorei(gl, GL_UNPACK_ROW_LENGTH, 8);
    tsr_call_PixelStorei(gl, GL_UNPACK_SKIP_PIXELS, 2);
    tsr_call_PixelStorei(gl, GL_UNPACK_SKIP_ROWS, 1);
    tsr_call_TexSubImage2D(gl, GL_TEXTURE_2D, 0, 2, 2, 4, 4, GL_RGB, GL_UNSIGNED_BYTE, image);
    tsr_call_PixelStorei(gl, GL_UNPACK_ROW_LENGTH, 0);
    tsr_call_PixelStorei(gl, GL_UNPACK_SKIP_PIXELS, 0);
    tsr_call_PixelStorei(gl, GL_UNPACK_SKIP_ROWS, 0);
    tsr_call_PixelStorei(gl, GL_UNPACK_ALIGNMENT, 4);
    tsr_call_BindTexture(gl, GL_TEXTURE_2D, tex[1]);
    tsr_call_TexImage2D(gl, GL_TEXTURE_2D, 0, GL_RGBA, 16, 16, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    tsr_call_TexEnvi(gl, GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    tsr_call_Enable(gl, GL_TEXTURE_2D);
    tsr_call_Begin(gl, GL_QUADS);
    tsr_call_TexCoord2f(gl, 0, 0);
    tsr_call_Vertex2f(gl, -1, -1);
    tsr_call_TexCoord2f(gl, 1, 0);
    tsr_call_Vertex2f(gl, 1, -1);
    tsr_call_TexCoord2f(gl, 1, 1);
    tsr_call_Vertex2f(gl, 1, 1);
    tsr_call_TexCoord2f(gl, 0, 1);
    tsr_call_Vertex2f(gl, -1, 1);
    tsr_call_End(gl);
    tsr_call_DeleteTextures(gl, 2, tex);
}

static void scenario_lists(const tsr_dispatch *gl)
{
    GLuint base = tsr_call_GenLists(gl, 3);
    if (base == 0) /* the answering server has no GL: use what GL would return */
        base = 1;
    tsr_call_NewList(gl, base, GL_COMPILE);
    tsr_call_Begin(gl, GL_TRIANGLES);
    tsr_call_Vertex3f(gl, 0, 0, 0);
    tsr_call_Vertex3f(gl, 1, 0, 0);
    tsr_call_Vertex3f(gl, 0, 1, 0);
    tsr_call_End(gl);
    tsr_call_EndList(gl);
    tsr_call_NewList(gl, base + 1, GL_COMPILE_AND_EXECUTE);
    tsr_call_Translatef(gl, 0.5f, 0, 0);
    tsr_call_CallList(gl, base);
    tsr_call_EndList(gl);
    tsr_call_CallList(gl, base);
    tsr_call_ListBase(gl, base);
    const GLubyte ids8[3] = {0, 1, 0};
    tsr_call_CallLists(gl, 3, GL_UNSIGNED_BYTE, ids8);
    const GLint ids32[2] = {1, 0};
    tsr_call_CallLists(gl, 2, GL_INT, ids32);
    const GLubyte ids16be[4] = {0, 1, 0, 0};
    tsr_call_CallLists(gl, 2, GL_2_BYTES, ids16be);
    tsr_call_IsList(gl, base);
    tsr_call_DeleteLists(gl, base, 3);
}

static void scenario_arrays(const tsr_dispatch *gl)
{
    GLfloat verts[12 * 3], normals[12 * 3], tex[12 * 2], interleaved[12 * 6];
    GLubyte colors[12 * 4];
    for (int i = 0; i < 12; i++) {
        for (int k = 0; k < 3; k++) {
            verts[3 * i + k] = (float)(i * 3 + k) * 0.1f;
            normals[3 * i + k] = k == 2 ? 1.0f : 0.0f;
            interleaved[6 * i + k] = verts[3 * i + k];
            interleaved[6 * i + 3 + k] = normals[3 * i + k];
        }
        tex[2 * i] = (float)i / 12.0f;
        tex[2 * i + 1] = 1.0f - (float)i / 12.0f;
        for (int k = 0; k < 4; k++)
            colors[4 * i + k] = (GLubyte)(i * 20 + k);
    }
    const GLubyte idx8[6] = {0, 1, 2, 2, 3, 0};
    const GLushort idx16[6] = {4, 5, 6, 6, 7, 4};
    const GLuint idx32[3] = {9, 10, 11};

    tsr_call_VertexPointer(gl, 3, GL_FLOAT, 0, verts);
    tsr_call_NormalPointer(gl, GL_FLOAT, 0, normals);
    tsr_call_ColorPointer(gl, 4, GL_UNSIGNED_BYTE, 0, colors);
    tsr_call_ClientActiveTexture(gl, GL_TEXTURE1);
    tsr_call_TexCoordPointer(gl, 2, GL_FLOAT, 0, tex);
    tsr_call_EnableClientState(gl, GL_TEXTURE_COORD_ARRAY);
    tsr_call_ClientActiveTexture(gl, GL_TEXTURE0);
    tsr_call_EnableClientState(gl, GL_VERTEX_ARRAY);
    tsr_call_EnableClientState(gl, GL_NORMAL_ARRAY);
    tsr_call_EnableClientState(gl, GL_COLOR_ARRAY);
    tsr_call_DrawArrays(gl, GL_TRIANGLES, 3, 9);
    tsr_call_DrawElements(gl, GL_TRIANGLES, 6, GL_UNSIGNED_BYTE, idx8);
    tsr_call_DrawElements(gl, GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, idx16);
    tsr_call_DrawElements(gl, GL_TRIANGLES, 3, GL_UNSIGNED_INT, idx32);
    tsr_call_DisableClientState(gl, GL_COLOR_ARRAY);
    /* Interleaved with a stride: the packer compacts it. */
    tsr_call_VertexPointer(gl, 3, GL_FLOAT, 6 * sizeof(GLfloat), interleaved);
    tsr_call_NormalPointer(gl, GL_FLOAT, 6 * sizeof(GLfloat), interleaved + 3);
    tsr_call_DrawArrays(gl, GL_TRIANGLE_STRIP, 0, 12);

    /* Buffer objects: arrays and indices live on the server. */
    GLuint bufs[2] = {0, 0};
    tsr_call_GenBuffers(gl, 2, bufs);
    /* The answering server has no GL behind it and returns zeros; pick the
     * names a real GL would have (any unused name is valid to bind). */
    if (bufs[0] == 0 && bufs[1] == 0) {
        bufs[0] = 1;
        bufs[1] = 2;
    }
    tsr_call_BindBuffer(gl, GL_ARRAY_BUFFER, bufs[0]);
    tsr_call_BufferData(gl, GL_ARRAY_BUFFER, sizeof verts, verts, GL_STATIC_DRAW);
    tsr_call_VertexPointer(gl, 3, GL_FLOAT, 0, (const void *)0);
    tsr_call_DisableClientState(gl, GL_NORMAL_ARRAY);
    tsr_call_ClientActiveTexture(gl, GL_TEXTURE1);
    tsr_call_DisableClientState(gl, GL_TEXTURE_COORD_ARRAY);
    tsr_call_ClientActiveTexture(gl, GL_TEXTURE0);
    tsr_call_DrawArrays(gl, GL_POINTS, 0, 12);
    tsr_call_BindBuffer(gl, GL_ELEMENT_ARRAY_BUFFER, bufs[1]);
    tsr_call_BufferData(gl, GL_ELEMENT_ARRAY_BUFFER, sizeof idx16, idx16, GL_STATIC_DRAW);
    tsr_call_DrawElements(gl, GL_TRIANGLES, 6, GL_UNSIGNED_SHORT, (const void *)0);
    tsr_call_BufferSubData(gl, GL_ARRAY_BUFFER, 12, 24, verts);
    tsr_call_BindBuffer(gl, GL_ELEMENT_ARRAY_BUFFER, 0);
    tsr_call_BindBuffer(gl, GL_ARRAY_BUFFER, 0);
    tsr_call_DisableClientState(gl, GL_VERTEX_ARRAY);
    tsr_call_DeleteBuffers(gl, 2, bufs);
}

static void scenario_gets(const tsr_dispatch *gl)
{
    GLint viewport[4];
    GLfloat matrix[16], light[4];
    GLdouble projection[16];
    GLboolean depth[1];
    GLubyte pixels[4 * 4 * 4];
    GLubyte teximage[64];
    tsr_call_GetError(gl);
    tsr_call_GetIntegerv(gl, GL_VIEWPORT, viewport);
    tsr_call_GetFloatv(gl, GL_MODELVIEW_MATRIX, matrix);
    tsr_call_GetDoublev(gl, GL_PROJECTION_MATRIX, projection);
    tsr_call_GetBooleanv(gl, GL_DEPTH_TEST, depth);
    tsr_call_GetString(gl, GL_VERSION);
    tsr_call_GetLightfv(gl, GL_LIGHT0, GL_POSITION, light);
    tsr_call_IsEnabled(gl, GL_LIGHTING);
    tsr_call_IsTexture(gl, 1);
    tsr_call_ReadPixels(gl, 0, 0, 4, 4, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    tsr_call_PixelStorei(gl, GL_PACK_ALIGNMENT, 1);
    tsr_call_ReadPixels(gl, 1, 1, 3, 3, GL_RGB, GL_UNSIGNED_BYTE, pixels);
    tsr_call_GetTexImage(gl, GL_TEXTURE_2D, 0, GL_RGBA, GL_UNSIGNED_BYTE, teximage);
    tsr_call_Finish(gl);
}

static void scenario_extended(const tsr_dispatch *gl)
{
    static const GLfloat ctrl[4 * 3] = {-1, 0, 0, -0.5f, 1, 0, 0.5f, -1, 0, 1, 0, 0};
    static const GLfloat coord2[2] = {0.25f, 0.75f};
    tsr_call_WindowCreateTSR(gl, 1, 64, 64);
    tsr_call_WindowSizeTSR(gl, 1, 32, 48);
    tsr_call_BarrierCreateTSR(gl, 7, 2);
    tsr_call_BarrierExecTSR(gl, 7);
    tsr_call_SemaphoreCreateTSR(gl, 3, 1);
    tsr_call_SemaphorePTSR(gl, 3);
    tsr_call_SemaphoreVTSR(gl, 3);
    tsr_call_Map1f(gl, GL_MAP1_VERTEX_3, 0, 1, 3, 4, ctrl);
    tsr_call_Enable(gl, GL_MAP1_VERTEX_3);
    tsr_call_MapGrid1f(gl, 8, 0, 1);
    tsr_call_EvalMesh1(gl, GL_LINE, 0, 8);
    tsr_call_Begin(gl, GL_LINE_STRIP);
    tsr_call_EvalCoord1f(gl, 0.5f);
    tsr_call_EvalCoord2fv(gl, coord2);
    tsr_call_EvalPoint1(gl, 3);
    tsr_call_TexCoord3s(gl, 1, 2, 3);
    tsr_call_TexCoord4d(gl, 0.1, 0.2, 0.3, 1.0);
    tsr_call_Vertex4f(gl, 1, 2, 3, 2);
    tsr_call_End(gl);
    tsr_call_Rectf(gl, -0.5f, -0.5f, 0.5f, 0.5f);
    tsr_call_CallList(gl, 5);
    tsr_call_BarrierDestroyTSR(gl, 7);
    tsr_call_SemaphoreDestroyTSR(gl, 3);
    tsr_call_WindowDestroyTSR(gl, 1);
}

static void scenario_pixels_shaders(const tsr_dispatch *gl)
{
    /* 16x16 bitmap rows are 2 bytes padded to the unpack alignment (4): GL reads 62 */
    GLubyte stipple[128], bitmap[4 * 16], pixels[4 * 4 * 4];
    for (unsigned i = 0; i < sizeof stipple; i++)
        stipple[i] = (GLubyte)(i & 1 ? 0xaa : 0x55);
    for (unsigned i = 0; i < sizeof bitmap; i++)
        bitmap[i] = (GLubyte)(0x81 + i);
    memset(pixels, 0x7f, sizeof pixels);
    static const GLfloat fog[4] = {0.5f, 0.5f, 0.5f, 1}, bounds[6] = {-1, -1, -1, 1, 1, 1};
    tsr_call_PolygonStipple(gl, stipple);
    tsr_call_Enable(gl, GL_POLYGON_STIPPLE);
    tsr_call_RasterPos2f(gl, 0, 0);
    tsr_call_Bitmap(gl, 16, 16, 0, 0, 1, 0, bitmap);
    tsr_call_DrawPixels(gl, 4, 4, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    tsr_call_Fogfv(gl, GL_FOG_COLOR, fog);
    tsr_call_Fogi(gl, GL_FOG_MODE, GL_LINEAR);
    tsr_call_TexEnvfv(gl, GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, fog);
    tsr_call_BoundsInfoTSR(gl, bounds);
    GLuint vs = tsr_call_CreateShader(gl, GL_VERTEX_SHADER);
    const GLchar *sources[2] = {"void main() {", " gl_Position = ftransform(); }"};
    const GLint lengths[2] = {13, -1};
    tsr_call_ShaderSource(gl, vs, 2, sources, NULL);
    tsr_call_ShaderSource(gl, vs, 2, sources, lengths);
    tsr_call_CompileShader(gl, vs);
    GLuint prog = tsr_call_CreateProgram(gl);
    tsr_call_AttachShader(gl, prog, vs);
    tsr_call_LinkProgram(gl, prog);
    tsr_call_UseProgram(gl, prog);
    tsr_call_Uniform4f(gl, 0, 1, 2, 3, 4);
    tsr_call_UseProgram(gl, 0);
    tsr_call_DeleteShader(gl, vs);
    tsr_call_DeleteProgram(gl, prog);
}

/* Every packable command once, in spec order, with random valid arguments
 * made by the generated wire-test code (it calls the same arguments on a
 * local recorder; differences are H2's wire tests' business, counted here
 * only to be reported). */
static void every_command(const tsr_dispatch *gl, uint64_t seed)
{
    tsr_dispatch *expect = malloc(sizeof *expect);
    tsr_recorder *rec = malloc(sizeof *rec);
    if (!expect || !rec) {
        free(expect);
        free(rec);
        return;
    }
    tsr_recorder_init(rec);
    tsr_recorder_fill(expect, rec);
    uint64_t rng = seed;
    int disagreements = 0;
    for (int slot = 0; slot < TSR_DISPATCH_COUNT; slot++) {
        char msg[512];
        int rc = tsr_wire_test_call(slot, expect, gl, &rng, msg, sizeof msg);
        if (rc < 0 && disagreements++ < 3)
            fprintf(stderr, "seed_writer: note: gl%s: %s\n", tsr_dispatch_name(slot), msg);
        tsr_recorder_clear(rec);
        tsr_recorder_fill(expect, rec);
    }
    if (disagreements)
        fprintf(stderr, "seed_writer: note: %d command(s) disagreed (see the wire tests)\n", disagreements);
    tsr_recorder_clear(rec);
    free(rec);
    free(expect);
}

static void scenario_every_command_a(const tsr_dispatch *gl) { every_command(gl, 0x9e3779b97f4a7c15u); }
static void scenario_every_command_b(const tsr_dispatch *gl) { every_command(gl, 0x1234567887654321u); }

/* --- single commands, the raw material of malformed seeds ------------------ */

static void one_vertex3f(const tsr_dispatch *gl) { tsr_call_Vertex3f(gl, 1, 2, 3); }
static void one_calllists(const tsr_dispatch *gl)
{
    static const GLubyte ids[4] = {1, 2, 3, 4};
    tsr_call_CallLists(gl, 4, GL_UNSIGNED_BYTE, ids);
}
static void one_window_create(const tsr_dispatch *gl) { tsr_call_WindowCreateTSR(gl, 1, 64, 64); }
static void one_readpixels(const tsr_dispatch *gl)
{
    GLubyte px[4 * 4 * 4];
    tsr_call_ReadPixels(gl, 0, 0, 4, 4, GL_RGBA, GL_UNSIGNED_BYTE, px);
}
static void one_getfloatv(const tsr_dispatch *gl)
{
    GLfloat m[16];
    tsr_call_GetFloatv(gl, GL_MODELVIEW_MATRIX, m);
}
static void one_drawarrays(const tsr_dispatch *gl)
{
    static const GLfloat v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    tsr_call_VertexPointer(gl, 3, GL_FLOAT, 0, v);
    tsr_call_EnableClientState(gl, GL_VERTEX_ARRAY);
    tsr_call_DrawArrays(gl, GL_TRIANGLES, 0, 3);
}
static void one_teximage(const tsr_dispatch *gl)
{
    GLubyte img[8 * 8 * 4] = {0};
    tsr_call_TexImage2D(gl, GL_TEXTURE_2D, 0, GL_RGBA, 8, 8, 0, GL_RGBA, GL_UNSIGNED_BYTE, img);
}

/* --- writing and checking -------------------------------------------------- */

static int write_seed(const char *dir, const char *name, const uint8_t *bytes, size_t size)
{
    int expect_ok = strncmp(name, "ok-", 3) == 0;
    char why[512] = "";
    int rc = fuzz_unpack_explain(bytes, size, why, sizeof why);
    if ((rc == 0) != expect_ok) {
        fprintf(stderr, "seed_writer: %s: expected the unpacker to %s it, got %s\n", name,
                expect_ok ? "accept" : "reject", rc == 0 ? "accepted" : "rejected");
        return -1;
    }
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(bytes, 1, size, f) != size) {
        fprintf(stderr, "seed_writer: %s: %s\n", path, strerror(errno));
        if (f)
            fclose(f);
        return -1;
    }
    fclose(f);
    printf("%-36s %7zu bytes  %s\n", name, size, rc == 0 ? "decodes" : why);
    return 0;
}

static uint8_t *data_start(uint8_t *buf)
{
    return buf + TSR_WIRE_HEADER_SIZE + tsr_wire_align8(tsr_wire_get_u32(buf + 4));
}

/* Where the first command's own fields start: after the 8-byte extension
 * header (u32 opcode, u32 length) when its opcode byte is 255. */
static uint8_t *fields_start(uint8_t *buf)
{
    uint8_t *d = data_start(buf);
    return d[-1] == TSR_WIRE_EXTENDED ? d + 8 : d;
}

/* The first buffer of a single-command capture, copied so it can be
 * mutated; its data starts at data_start(). */
static uint8_t *single(const char *name, scenario_fn fn, size_t *size)
{
    capture c;
    if (record(name, 4096, fn, &c) != 0 || c.buffers == 0) {
        capture_free(&c);
        return NULL;
    }
    uint8_t *copy = malloc(c.first_buffer_size);
    if (copy) {
        memcpy(copy, c.bytes, c.first_buffer_size);
        *size = c.first_buffer_size;
    }
    capture_free(&c);
    return copy;
}

static int write_malformed(const char *dir, const uint8_t *spheres, size_t spheres_first)
{
    int failures = 0;
    size_t n;
    uint8_t *b;

    /* Header lies. */
    b = malloc(spheres_first);
    if (!b)
        return 1;
    memcpy(b, spheres, spheres_first);
    b[0] ^= 0xff;
    failures += write_seed(dir, "bad-magic.bin", b, spheres_first) != 0;
    failures += write_seed(dir, "bad-truncated.bin", spheres, spheres_first - 5) != 0;
    memcpy(b, spheres, spheres_first);
    tsr_wire_put_u32(b + 4, 0xffffffffu);
    failures += write_seed(dir, "bad-opcode-count-huge.bin", b, spheres_first) != 0;
    free(b);

    /* Vertex3f with 8 of its 12 data bytes (header consistent). */
    if ((b = single("vertex3f", one_vertex3f, &n)) != NULL) {
        tsr_wire_put_u64(b + 8, tsr_wire_get_u64(b + 8) - 4);
        failures += write_seed(dir, "bad-vertex3f-short-data.bin", b, n - 4) != 0;
        free(b);
    }
    /* Opcode 0 and an unassigned one-byte opcode. */
    if ((b = single("vertex3f", one_vertex3f, &n)) != NULL) {
        uint8_t *op = data_start(b) - 1;
        *op = 0;
        failures += write_seed(dir, "bad-opcode-zero.bin", b, n) != 0;
        for (unsigned code = 254; code > 0; code--) {
            if (tsr_wire_opcode_name(code) == NULL) {
                *op = (uint8_t)code;
                failures += write_seed(dir, "bad-opcode-unassigned.bin", b, n) != 0;
                break;
            }
        }
        free(b);
    }
    /* CallLists(4, GL_UNSIGNED_BYTE): n at 0, type at 4, u64 length at 8. */
    if ((b = single("calllists", one_calllists, &n)) != NULL) {
        uint8_t *d = fields_start(b);
        tsr_wire_put_u64(d + 8, UINT64_MAX - 15);
        failures += write_seed(dir, "bad-calllists-length-huge.bin", b, n) != 0;
        tsr_wire_put_u64(d + 8, 3);
        failures += write_seed(dir, "bad-calllists-length-short.bin", b, n) != 0;
        tsr_wire_put_u64(d + 8, 4);
        tsr_wire_put_u32(d, 0xffffffffu);
        failures += write_seed(dir, "bad-calllists-count-negative.bin", b, n) != 0;
        tsr_wire_put_u32(d, 4);
        tsr_wire_put_u32(d + 4, GL_FLOAT + 0x100);
        failures += write_seed(dir, "bad-calllists-type-unknown.bin", b, n) != 0;
        free(b);
    }
    /* Extended opcode (WindowCreateTSR): u32 opcode, u32 length at data 0. */
    if ((b = single("windowcreate", one_window_create, &n)) != NULL) {
        uint8_t *d = data_start(b);
        uint32_t len = tsr_wire_get_u32(d + 4);
        tsr_wire_put_u32(d + 4, 0x7fffffffu);
        failures += write_seed(dir, "bad-extended-length-huge.bin", b, n) != 0;
        tsr_wire_put_u32(d + 4, len);
        tsr_wire_put_u32(d, 65000);
        failures += write_seed(dir, "bad-extended-opcode-unknown.bin", b, n) != 0;
        tsr_wire_put_u32(d, 5); /* a one-byte opcode sent as extended */
        failures += write_seed(dir, "bad-extended-opcode-small.bin", b, n) != 0;
        free(b);
    }
    /* ReadPixels asking for a huge output: x, y, width, height at 0..15. */
    if ((b = single("readpixels", one_readpixels, &n)) != NULL) {
        uint8_t *d = fields_start(b);
        tsr_wire_put_u32(d + 8, 1u << 20);
        tsr_wire_put_u32(d + 12, 1u << 20);
        failures += write_seed(dir, "bad-readpixels-huge.bin", b, n) != 0;
        tsr_wire_put_u32(d + 8, 0xfffffffcu);
        tsr_wire_put_u32(d + 12, 4);
        failures += write_seed(dir, "bad-readpixels-negative.bin", b, n) != 0;
        free(b);
    }
    /* GetFloatv with a pname the spec has no count for. */
    if ((b = single("getfloatv", one_getfloatv, &n)) != NULL) {
        tsr_wire_put_u32(fields_start(b), 0x1234);
        failures += write_seed(dir, "bad-getfloatv-pname-unknown.bin", b, n) != 0;
        free(b);
    }
    /* DrawArrays: mode, first, count; a count beyond the inline array. */
    if ((b = single("drawarrays", one_drawarrays, &n)) != NULL) {
        uint8_t *d = fields_start(b);
        tsr_wire_put_u32(d + 8, 1000000);
        failures += write_seed(dir, "bad-drawarrays-count-past-array.bin", b, n) != 0;
        free(b);
    }
    /* TexImage2D claiming a larger image than its payload (width at 12). */
    if ((b = single("teximage", one_teximage, &n)) != NULL) {
        tsr_wire_put_u32(fields_start(b) + 12, 64);
        failures += write_seed(dir, "bad-teximage-payload-short.bin", b, n) != 0;
        free(b);
    }
    return failures;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: %s OUTDIR\n", argv[0]);
        return 2;
    }
    const char *dir = argv[1];
    static const struct {
        const char *name;
        size_t buffer_size;
        scenario_fn fn;
    } valid[] = {
        {"ok-spheres.bin", 2048, scenario_spheres},
        {"ok-spheres-one-buffer.bin", 1 << 16, scenario_spheres},
        {"ok-texture.bin", 4096, scenario_texture},
        {"ok-lists.bin", 4096, scenario_lists},
        {"ok-arrays.bin", 4096, scenario_arrays},
        {"ok-gets.bin", 4096, scenario_gets},
        {"ok-extended.bin", 4096, scenario_extended},
        {"ok-pixels-shaders.bin", 4096, scenario_pixels_shaders},
        {"ok-every-command-a.bin", 1 << 16, scenario_every_command_a},
        {"ok-every-command-b.bin", 8192, scenario_every_command_b},
    };
    int failures = 0;
    uint8_t *spheres = NULL;
    size_t spheres_first = 0;
    for (size_t i = 0; i < sizeof valid / sizeof valid[0]; i++) {
        capture c;
        if (record(valid[i].name, valid[i].buffer_size, valid[i].fn, &c) != 0) {
            failures++;
        } else {
            failures += write_seed(dir, valid[i].name, c.bytes, c.len) != 0;
            if (i == 0 && c.first_buffer_size > 16) {
                spheres = malloc(c.first_buffer_size);
                if (spheres) {
                    memcpy(spheres, c.bytes, c.first_buffer_size);
                    spheres_first = c.first_buffer_size;
                }
            }
        }
        capture_free(&c);
    }
    if (spheres)
        failures += write_malformed(dir, spheres, spheres_first);
    else
        failures++;
    free(spheres);
    if (failures)
        fprintf(stderr, "seed_writer: %d seed(s) failed\n", failures);
    return failures ? 1 : 0;
}
