/* tests/state/state_test.c — the state tracker (tessera/dev/state.h) against real
 * GL: OSMesa loaded with dlopen and every GL entry resolved through
 * OSMesaGetProcAddress, as the render SPU does. One program, one ctest per
 * behaviour (`state_test NAME [SEEDS]`):
 *
 *  covers_spec           every state/object/client/current-attribute command
 *                        of the spec is tracked or listed as untracked with a
 *                        reason, never both
 *  diff_matches_osmesa   (a)+(e) for random call sequences (every group): the
 *                        sequence goes to the tracker and, separately, straight
 *                        to OSMesa context B; the tracker's diff goes into a
 *                        fresh OSMesa context A (directly, or through the real
 *                        packer and unpacker on odd seeds). Every get the
 *                        tracker answers must equal A's answer exactly and B's
 *                        (matrix-derived values within 1e-5: GL does that
 *                        arithmetic itself); A and B must agree on texels,
 *                        buffer contents and every answered pname; a second
 *                        diff emits nothing (c)
 *  unchanged_is_zero_bytes (b) through the real packer
 *  switch_only_differing_groups (d) for one change in each group
 *  many_renderers        bit vectors grow past 64 and 128 renderers
 *  lazy_textures         unbound textures are not sent; a changed texture
 *                        sends only the new image call
 *  image_units           bindings on units past the coordinate units reach
 *                        OSMesa; a change there costs that unit's calls
 *  list_compile          glNewList(GL_COMPILE) leaves the state alone
 *  buffers_unbound_reach_renderer  a diff sends every buffer with data the
 *                        renderer lacks, bound or not, once
 *  get_count_table       tsr_state_get_count's table says, for every 16-bit
 *                        enum, how many values the tracker's get writes
 *  glsl_diff_matches_osmesa  random shader/program/uniform sequences: the
 *                        calls go to the tracker and (names from the
 *                        tracker, CreateShaderTSR/CreateProgramTSR, through
 *                        tessera/glsl_names.h) to OSMesa context B; the diff
 *                        plus tsr_state_send_shader/_program of every object
 *                        go into a fresh context A (directly, or through the
 *                        real wire on odd seeds). What the tracker answers
 *                        equals A and B; compile/link status, active
 *                        uniforms, every uniform's location and value, and
 *                        the pixels of a triangle drawn with the current
 *                        program are equal in A and B (B's driver names
 *                        differ: it made and deleted other objects first);
 *                        a second diff and second sends emit nothing
 *  glsl_lazy             a program reaches a renderer when it is current in
 *                        a diff, once; uniform changes send one call; a
 *                        deleted program leaves the renderer; unchanged
 *                        state sends nothing
 *
 * Debugging a failing seed: STATE_SEED=N starts at seed N; STATE_TRACE=1
 * prints the calls sent to OSMesa directly, then the diff (direct path).
 */
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/osmesa.h>

#include "tessera/dev/pack.h"
#include "tessera/dev/state.h"
#include "tessera/glsl_names.h"
#include "tessera/glprocs_gen.h"
#include "trace_gen.h"
#include "tessera/dev/unpack.h"

#include "harness.h"

/* --- OSMesa through dlopen ------------------------------------------------------ */
typedef struct osm {
    void *lib;
    OSMesaContext (*CreateContextExt)(GLenum, GLint, GLint, GLint, OSMesaContext);
    GLboolean (*MakeCurrent)(OSMesaContext, void *, GLenum, GLsizei, GLsizei);
    void (*DestroyContext)(OSMesaContext);
    OSMESAproc (*GetProcAddress)(const char *);
} osm;

typedef struct gl_env {
    OSMesaContext ctx;
    unsigned char *buf; /* color buffer: static, see gl_open */
    tsr_gl_procs gl;
    tsr_dispatch d;
    void (*GetVertexAttribfv)(GLuint, GLenum, GLfloat *);
    void (*GetBufferSubData)(GLenum, GLintptr, GLsizeiptr, void *);
} gl_env;

static osm M;

static tsr_proc getproc(const char *name, void *ctx)
{
    (void)ctx;
    return (tsr_proc)M.GetProcAddress(name);
}

static void osm_load(void)
{
    /* No llvmpipe rasterizer threads: nothing is drawn here, and this test
     * makes and destroys hundreds of contexts; under ASan, Mesa's threads
     * were seen writing into memory freed with a destroyed context. */
    setenv("LP_NUM_THREADS", "0", 1);
    M.lib = dlopen("libOSMesa.so.8", RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
    if (!M.lib) {
        fprintf(stderr, "state_test: cannot load libOSMesa.so.8: %s\n", dlerror());
        exit(1);
    }
    *(void **)&M.CreateContextExt = dlsym(M.lib, "OSMesaCreateContextExt");
    *(void **)&M.MakeCurrent = dlsym(M.lib, "OSMesaMakeCurrent");
    *(void **)&M.DestroyContext = dlsym(M.lib, "OSMesaDestroyContext");
    *(void **)&M.GetProcAddress = dlsym(M.lib, "OSMesaGetProcAddress");
    if (!M.CreateContextExt || !M.MakeCurrent || !M.DestroyContext || !M.GetProcAddress) {
        fprintf(stderr, "state_test: OSMesa lacks an entry point\n");
        exit(1);
    }
}

/* Same attributes as the render SPU and the native reference. */
static gl_env *gl_open(void)
{
    gl_env *e = calloc(1, sizeof *e);
    tsr_error err = {0};
    /* Mesa (llvmpipe) may still touch a context's color buffer after
     * OSMesaDestroyContext returns, so the buffers outlive every context
     * (two in use at a time, rotating over four). */
    static unsigned char buffers[4][64 * 64 * 4];
    static unsigned next;
    e->buf = buffers[next++ % 4];
    e->ctx = M.CreateContextExt(OSMESA_RGBA, 24, 8, 0, NULL);
    if (!e->ctx || !M.MakeCurrent(e->ctx, e->buf, GL_UNSIGNED_BYTE, 64, 64) ||
        tsr_gl_procs_load(&e->gl, getproc, NULL, &err) != TSR_OK) {
        fprintf(stderr, "state_test: OSMesa context: %s\n", err.message);
        exit(1);
    }
    tsr_dispatch_fill_nop(&e->d);
    tsr_gl_procs_fill_dispatch(&e->gl, &e->d);
    *(void **)&e->GetVertexAttribfv = (void *)M.GetProcAddress("glGetVertexAttribfv");
    *(void **)&e->GetBufferSubData = (void *)M.GetProcAddress("glGetBufferSubData");
    return e;
}

static void gl_use(gl_env *e) { M.MakeCurrent(e->ctx, e->buf, GL_UNSIGNED_BYTE, 64, 64); }

static void gl_close(gl_env *e)
{
    M.MakeCurrent(NULL, NULL, 0, 0, 0);
    M.DestroyContext(e->ctx);
    free(e);
}

/* --- random call sequences --------------------------------------------------------- */
static uint64_t rnd(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
static int ri(uint64_t *s, int n) { return (int)(rnd(s) % (uint64_t)n); }
/* Image units past the coordinate units the random sequences select and
 * the comparisons ask: below 32, as Mesa 22's glTranslate and the other
 * texture matrix calls crash on a unit past its 32 texture matrix stacks
 * (the tracker never sends those: state_matrix.c). */
static const GLuint high_units[] = {8, 9, 20, 31};
enum { NHIGH = sizeof high_units / sizeof high_units[0] };
/* Values with few bits (exact in float) and some that are not. */
static GLfloat rf(uint64_t *s)
{
    return ri(s, 2) ? (GLfloat)(ri(s, 33) - 16) / 8.0f : (GLfloat)(rnd(s) % 100000) / 77777.0f;
}
static GLfloat r01(uint64_t *s) { return (GLfloat)ri(s, 1001) / 1000.0f; }
#define PICK(s, ...) \
    ((const GLenum[]){__VA_ARGS__})[ri(s, (int)(sizeof((const GLenum[]){__VA_ARGS__}) / sizeof(GLenum)))]

static uint8_t scratch[1 << 16];
/* What the sequence did so far (reset per sequence). Mesa 22.3 departs
 * from GL in two places the test must step around, both measured:
 *  - with pixel-transfer operations active, glTexImage ignores
 *    GL_UNPACK_SKIP_PIXELS (and other uploads come out differently), so
 *    uploads are made with the transfer modes at identity (the tracker
 *    itself records and replays the modes of each upload, as GL says);
 *  - with GL_COLOR_MATERIAL, the stored material follows glColor only at
 *    draws (rendering uses the color itself), so stored materials are not
 *    compared once color material was used. Materials are such pending
 *    immediate-mode values in Mesa too, so neither are they after a
 *    PopAttrib of GL_LIGHTING_BIT.
 * (Two more are noted where the calls are made: PushAttrib without
 * GL_CURRENT_BIT, no GL_GENERATE_MIPMAP on cube maps.)
 * And Mesa's glPopAttrib restores less than GL 2.1 says in several places
 * (measured: GL_COLOR_SUM, GL_GENERATE_MIPMAP_HINT, GL_FOG_COORD_SRC, light
 * enables, the viewport, texture levels made with GL_GENERATE_MIPMAP),
 * so for sequences with a PopAttrib only the diffed context (a) is held
 * to the tracker; the direct comparison (e) covers the other sequences. */
static int seq_transfer_used, seq_color_material_used, seq_popattrib_used;

/* Client arrays need an address that stays valid: scratch. */
static void random_call(uint64_t *s, const tsr_dispatch *d, int *attrib_depth, int *client_depth)
{
    GLfloat v[16];
    for (int i = 0; i < 16; i++)
        v[i] = rf(s);
    switch (ri(s, 40)) {
    case 0:
    case 1: {
        static const GLenum caps[] = {GL_ALPHA_TEST,
                                      GL_AUTO_NORMAL,
                                      GL_BLEND,
                                      GL_CLIP_PLANE0,
                                      GL_CLIP_PLANE5,
                                      GL_COLOR_LOGIC_OP,
                                      GL_COLOR_MATERIAL,
                                      GL_CULL_FACE,
                                      GL_DEPTH_TEST,
                                      GL_DITHER,
                                      GL_FOG,
                                      GL_LIGHT0,
                                      GL_LIGHT3,
                                      GL_LIGHT7,
                                      GL_LIGHTING,
                                      GL_LINE_SMOOTH,
                                      GL_LINE_STIPPLE,
                                      GL_NORMALIZE,
                                      GL_POINT_SMOOTH,
                                      GL_POLYGON_OFFSET_FILL,
                                      GL_POLYGON_OFFSET_LINE,
                                      GL_POLYGON_SMOOTH,
                                      GL_POLYGON_STIPPLE,
                                      GL_RESCALE_NORMAL,
                                      GL_SCISSOR_TEST,
                                      GL_STENCIL_TEST,
                                      GL_MULTISAMPLE,
                                      GL_SAMPLE_COVERAGE,
                                      GL_POINT_SPRITE,
                                      GL_MAP1_VERTEX_3,
                                      GL_MAP2_NORMAL,
                                      GL_TEXTURE_1D,
                                      GL_TEXTURE_2D,
                                      GL_TEXTURE_3D,
                                      GL_TEXTURE_CUBE_MAP,
                                      GL_TEXTURE_GEN_S,
                                      GL_TEXTURE_GEN_Q,
                                      GL_COLOR_SUM};
        GLenum cap = caps[ri(s, sizeof caps / sizeof caps[0])];
        seq_color_material_used |= cap == GL_COLOR_MATERIAL;
        if (ri(s, 2))
            tsr_call_Enable(d, cap);
        else
            tsr_call_Disable(d, cap);
        break;
    }
    case 2: /* current attributes in several forms */
        switch (ri(s, 8)) {
        case 0: tsr_call_Color4f(d, r01(s), r01(s), r01(s), r01(s)); break;
        case 1: tsr_call_Color3ub(d, (GLubyte)ri(s, 256), (GLubyte)ri(s, 256), (GLubyte)ri(s, 256)); break;
        case 2: tsr_call_Color4b(d, (GLbyte)(ri(s, 256) - 128), (GLbyte)(ri(s, 256) - 128), 5, 127); break;
        case 3: tsr_call_Normal3f(d, v[0], v[1], v[2]); break;
        case 4: tsr_call_Normal3s(d, (GLshort)(ri(s, 65536) - 32768), 7, -9); break;
        case 5: tsr_call_TexCoord2f(d, v[0], v[1]); break;
        case 6: tsr_call_MultiTexCoord4f(d, GL_TEXTURE0 + (GLenum)ri(s, 8), v[0], v[1], v[2], v[3]); break;
        default: tsr_call_EdgeFlag(d, (GLboolean)ri(s, 2)); break;
        }
        break;
    case 3: tsr_call_VertexAttrib4f(d, 1 + (GLuint)ri(s, 15), v[0], v[1], v[2], v[3]); break;
    case 4:
        if (ri(s, 2))
            tsr_call_Viewport(d, ri(s, 20) - 10, ri(s, 20), 1 + ri(s, 60), 1 + ri(s, 60));
        else
            tsr_call_Scissor(d, ri(s, 20), ri(s, 20) - 5, ri(s, 70), ri(s, 70));
        break;
    case 5: tsr_call_DepthRange(d, r01(s), r01(s)); break;
    case 6:
        switch (ri(s, 5)) {
        case 0:
            tsr_call_BlendFunc(d, PICK(s, GL_ONE, GL_SRC_ALPHA, GL_DST_COLOR, GL_ZERO),
                               PICK(s, GL_ZERO, GL_ONE_MINUS_SRC_ALPHA, GL_SRC_COLOR));
            break;
        case 1: tsr_call_BlendFuncSeparate(d, GL_SRC_ALPHA, GL_ONE, PICK(s, GL_ONE, GL_ZERO), GL_DST_ALPHA); break;
        case 2: tsr_call_BlendEquation(d, PICK(s, GL_FUNC_ADD, GL_FUNC_SUBTRACT, GL_MIN, GL_MAX)); break;
        case 3: tsr_call_BlendEquationSeparate(d, GL_FUNC_REVERSE_SUBTRACT, PICK(s, GL_FUNC_ADD, GL_MAX)); break;
        default: tsr_call_BlendColor(d, r01(s), r01(s), r01(s), r01(s)); break;
        }
        break;
    case 7:
        switch (ri(s, 7)) {
        case 0: tsr_call_AlphaFunc(d, PICK(s, GL_LESS, GL_GEQUAL, GL_NEVER, GL_ALWAYS), r01(s)); break;
        case 1: tsr_call_LogicOp(d, PICK(s, GL_XOR, GL_COPY, GL_AND, GL_INVERT)); break;
        case 2:
            tsr_call_ColorMask(d, (GLboolean)ri(s, 2), (GLboolean)ri(s, 2), (GLboolean)ri(s, 2), (GLboolean)ri(s, 2));
            break;
        case 3: tsr_call_ClearColor(d, r01(s), r01(s), r01(s), r01(s)); break;
        case 4: tsr_call_ClearColorIiEXT(d, ri(s, 1000) - 500, -1, 1 << 30, ri(s, 3)); break;
        case 5: tsr_call_ClearColorIuiEXT(d, (GLuint)ri(s, 1000), 0xffffffffu, 7, (GLuint)ri(s, 3)); break;
        default: tsr_call_ClearAccum(d, r01(s), -r01(s), r01(s), r01(s)); break;
        }
        break;
    case 8:
        switch (ri(s, 3)) {
        case 0: tsr_call_DepthFunc(d, PICK(s, GL_LESS, GL_LEQUAL, GL_GREATER, GL_ALWAYS)); break;
        case 1: tsr_call_DepthMask(d, (GLboolean)ri(s, 2)); break;
        default: tsr_call_ClearDepth(d, r01(s)); break;
        }
        break;
    case 9:
        switch (ri(s, 7)) {
        case 0: tsr_call_StencilFunc(d, PICK(s, GL_EQUAL, GL_LESS, GL_ALWAYS), ri(s, 256), (GLuint)ri(s, 256)); break;
        case 1:
            tsr_call_StencilFuncSeparate(d, PICK(s, GL_FRONT, GL_BACK, GL_FRONT_AND_BACK), GL_NOTEQUAL, ri(s, 256),
                                         0xf0);
            break;
        case 2:
            tsr_call_StencilOp(d, PICK(s, GL_KEEP, GL_ZERO, GL_INCR), GL_REPLACE, PICK(s, GL_INVERT, GL_DECR_WRAP));
            break;
        case 3: tsr_call_StencilOpSeparate(d, PICK(s, GL_FRONT, GL_BACK), GL_INCR_WRAP, GL_KEEP, GL_ZERO); break;
        case 4: tsr_call_StencilMask(d, (GLuint)ri(s, 256)); break;
        case 5: tsr_call_StencilMaskSeparate(d, PICK(s, GL_FRONT, GL_BACK), (GLuint)ri(s, 256)); break;
        default: tsr_call_ClearStencil(d, ri(s, 256)); break;
        }
        break;
    case 10:
        switch (ri(s, 4)) {
        case 0: tsr_call_Fogi(d, GL_FOG_MODE, (GLint)PICK(s, GL_LINEAR, GL_EXP, GL_EXP2)); break;
        case 1: tsr_call_Fogf(d, PICK(s, GL_FOG_DENSITY, GL_FOG_START, GL_FOG_END), r01(s) * 10); break;
        case 2: tsr_call_Fogfv(d, GL_FOG_COLOR, (GLfloat[]){r01(s), r01(s), r01(s), r01(s)}); break;
        default: tsr_call_Fogi(d, GL_FOG_COORD_SRC, (GLint)PICK(s, GL_FOG_COORD, GL_FRAGMENT_DEPTH)); break;
        }
        break;
    case 11:
    case 12: {
        GLenum l = GL_LIGHT0 + (GLenum)ri(s, 8);
        switch (ri(s, 5)) {
        case 0: tsr_call_Lightfv(d, l, PICK(s, GL_AMBIENT, GL_DIFFUSE, GL_SPECULAR), v); break;
        case 1: tsr_call_Lightfv(d, l, PICK(s, GL_POSITION, GL_SPOT_DIRECTION), v); break;
        case 2: tsr_call_Lightf(d, l, GL_SPOT_EXPONENT, (GLfloat)ri(s, 129)); break;
        case 3: tsr_call_Lightf(d, l, GL_SPOT_CUTOFF, ri(s, 4) ? (GLfloat)ri(s, 91) : 180.0f); break;
        default:
            tsr_call_Lightf(d, l, PICK(s, GL_CONSTANT_ATTENUATION, GL_LINEAR_ATTENUATION, GL_QUADRATIC_ATTENUATION),
                            r01(s) * 3);
            break;
        }
        break;
    }
    case 13:
        switch (ri(s, 4)) {
        case 0: tsr_call_LightModelfv(d, GL_LIGHT_MODEL_AMBIENT, v); break;
        case 1: tsr_call_LightModeli(d, PICK(s, GL_LIGHT_MODEL_LOCAL_VIEWER, GL_LIGHT_MODEL_TWO_SIDE), ri(s, 2)); break;
        case 2:
            tsr_call_LightModeli(d, GL_LIGHT_MODEL_COLOR_CONTROL,
                                 (GLint)PICK(s, GL_SINGLE_COLOR, GL_SEPARATE_SPECULAR_COLOR));
            break;
        default: tsr_call_ShadeModel(d, PICK(s, GL_FLAT, GL_SMOOTH)); break;
        }
        break;
    case 14: {
        GLenum face = PICK(s, GL_FRONT, GL_BACK, GL_FRONT_AND_BACK);
        switch (ri(s, 3)) {
        case 0:
            tsr_call_Materialfv(d, face,
                                PICK(s, GL_AMBIENT, GL_DIFFUSE, GL_SPECULAR, GL_EMISSION, GL_AMBIENT_AND_DIFFUSE), v);
            break;
        case 1: tsr_call_Materialf(d, face, GL_SHININESS, (GLfloat)ri(s, 129)); break;
        default:
            tsr_call_ColorMaterial(d, face,
                                   PICK(s, GL_AMBIENT, GL_DIFFUSE, GL_SPECULAR, GL_EMISSION, GL_AMBIENT_AND_DIFFUSE));
            break;
        }
        break;
    }
    case 15:
        switch (ri(s, 6)) {
        case 0: tsr_call_CullFace(d, PICK(s, GL_FRONT, GL_BACK, GL_FRONT_AND_BACK)); break;
        case 1: tsr_call_FrontFace(d, PICK(s, GL_CW, GL_CCW)); break;
        case 2:
            tsr_call_PolygonMode(d, PICK(s, GL_FRONT, GL_BACK, GL_FRONT_AND_BACK), PICK(s, GL_POINT, GL_LINE, GL_FILL));
            break;
        case 3: tsr_call_PolygonOffset(d, v[0], v[1]); break;
        case 4: {
            uint8_t *p = scratch + 1024;
            for (int i = 0; i < 4096; i++)
                p[i] = (uint8_t)rnd(s);
            /* Mesa 22.3's bitmap unpacker writes one byte past its
             * 128-byte stipple buffer when GL_UNPACK_SKIP_PIXELS is not 0
             * (valgrind: "Invalid write of size 1 ... 0 bytes after a block
             * of size 128" under glPolygonStipple); under ASan that
             * corrupts the allocator. Stipples are uploaded without skipped
             * pixels here; the setting itself is still tracked and tested. */
            tsr_call_PixelStorei(d, GL_UNPACK_SKIP_PIXELS, 0);
            tsr_call_PolygonStipple(d, p);
            break;
        }
        default: tsr_call_LineStipple(d, 1 + ri(s, 256), (GLushort)ri(s, 65536)); break;
        }
        break;
    case 16:
        switch (ri(s, 5)) {
        case 0: tsr_call_LineWidth(d, 1.0f + (GLfloat)ri(s, 16) / 4.0f); break;
        case 1: tsr_call_PointSize(d, 1.0f + (GLfloat)ri(s, 40) / 4.0f); break;
        case 2:
            tsr_call_PointParameterf(d, PICK(s, GL_POINT_SIZE_MIN, GL_POINT_SIZE_MAX, GL_POINT_FADE_THRESHOLD_SIZE),
                                     (GLfloat)ri(s, 20));
            break;
        case 3: tsr_call_PointParameterfv(d, GL_POINT_DISTANCE_ATTENUATION, (GLfloat[]){r01(s), r01(s), r01(s)}); break;
        default:
            tsr_call_PointParameteri(d, GL_POINT_SPRITE_COORD_ORIGIN, (GLint)PICK(s, GL_LOWER_LEFT, GL_UPPER_LEFT));
            break;
        }
        break;
    case 17:
        tsr_call_Hint(d,
                      PICK(s, GL_PERSPECTIVE_CORRECTION_HINT, GL_POINT_SMOOTH_HINT, GL_LINE_SMOOTH_HINT,
                           GL_POLYGON_SMOOTH_HINT, GL_FOG_HINT, GL_GENERATE_MIPMAP_HINT),
                      PICK(s, GL_FASTEST, GL_NICEST, GL_DONT_CARE));
        break;
    case 18:
        switch (ri(s, 4)) {
        case 0: tsr_call_PixelStorei(d, PICK(s, GL_UNPACK_ALIGNMENT, GL_PACK_ALIGNMENT), 1 << ri(s, 4)); break;
        case 1:
            tsr_call_PixelStorei(d,
                                 PICK(s, GL_UNPACK_ROW_LENGTH, GL_UNPACK_SKIP_ROWS, GL_UNPACK_SKIP_PIXELS,
                                      GL_PACK_ROW_LENGTH, GL_PACK_SKIP_PIXELS),
                                 ri(s, 2) ? 0 : ri(s, 12));
            break;
        case 2:
            tsr_call_PixelStorei(d, PICK(s, GL_UNPACK_LSB_FIRST, GL_PACK_LSB_FIRST, GL_UNPACK_SWAP_BYTES), ri(s, 2));
            break;
        default: tsr_call_PixelStoref(d, GL_UNPACK_IMAGE_HEIGHT, (GLfloat)ri(s, 4)); break;
        }
        break;
    case 19:
        seq_transfer_used = 1;
        if (ri(s, 2))
            tsr_call_PixelZoom(d, v[0], v[1]);
        else if (ri(s, 2))
            tsr_call_PixelTransferf(d, PICK(s, GL_RED_SCALE, GL_GREEN_BIAS, GL_ALPHA_SCALE, GL_DEPTH_BIAS), v[2]);
        else
            tsr_call_PixelTransferi(d, PICK(s, GL_INDEX_SHIFT, GL_INDEX_OFFSET, GL_MAP_COLOR), ri(s, 2));
        break;
    case 20: { /* a coordinate unit, or one of the image units past them */
        GLuint u = (GLuint)ri(s, TSR_STATE_UNITS + NHIGH);
        tsr_call_ActiveTexture(d, GL_TEXTURE0 + (u < TSR_STATE_UNITS ? u : high_units[u - TSR_STATE_UNITS]));
        break;
    }
    case 21: {
        static const GLenum targets[] = {GL_TEXTURE_1D, GL_TEXTURE_2D, GL_TEXTURE_2D, GL_TEXTURE_3D,
                                         GL_TEXTURE_CUBE_MAP};
        GLenum t = targets[ri(s, 5)];
        /* names by target so a name never meets two targets */
        GLuint base = t == GL_TEXTURE_1D ? 10 : t == GL_TEXTURE_2D ? 20 : t == GL_TEXTURE_3D ? 30 : 40;
        GLuint name = ri(s, 4) ? base + (GLuint)ri(s, 3) : 0;
        tsr_call_BindTexture(d, t, name);
        break;
    }
    case 22: {
        GLenum t = PICK(s, GL_TEXTURE_2D, GL_TEXTURE_1D, GL_TEXTURE_3D, GL_TEXTURE_CUBE_MAP);
        int k = ri(s, 8);
        switch (k) {
        case 0:
            tsr_call_TexParameteri(d, t, GL_TEXTURE_MIN_FILTER,
                                   (GLint)PICK(s, GL_NEAREST, GL_LINEAR, GL_LINEAR_MIPMAP_LINEAR));
            break;
        case 1:
            tsr_call_TexParameteri(d, t, PICK(s, GL_TEXTURE_WRAP_S, GL_TEXTURE_WRAP_T, GL_TEXTURE_WRAP_R),
                                   (GLint)PICK(s, GL_CLAMP_TO_EDGE, GL_REPEAT, GL_MIRRORED_REPEAT));
            break;
        case 2:
            tsr_call_TexParameterfv(d, t, GL_TEXTURE_BORDER_COLOR, (GLfloat[]){r01(s), r01(s), r01(s), r01(s)});
            break;
        case 3:
            tsr_call_TexParameterf(
                d, t, PICK(s, GL_TEXTURE_MIN_LOD, GL_TEXTURE_MAX_LOD, GL_TEXTURE_LOD_BIAS, GL_TEXTURE_PRIORITY),
                r01(s) * 4);
            break;
        case 4: tsr_call_TexParameteri(d, t, PICK(s, GL_TEXTURE_BASE_LEVEL, GL_TEXTURE_MAX_LEVEL), ri(s, 5)); break;
        case 5:
            tsr_call_TexParameterIivEXT(d, t, GL_TEXTURE_BORDER_COLOR,
                                        (GLint[]){ri(s, 1000) - 500, -7, 1 << 24, ri(s, 2)});
            break;
        case 6:
            tsr_call_TexParameterIuivEXT(d, t, GL_TEXTURE_BORDER_COLOR,
                                         (GLuint[]){(GLuint)ri(s, 1000), 0xfffffff0u, 3, (GLuint)ri(s, 2)});
            break;
        default: {
            /* Not GL_GENERATE_MIPMAP on cube maps: uploading a face of an
             * incomplete cube with it on crashes Mesa 22.3 (measured). */
            GLenum p = PICK(s, GL_GENERATE_MIPMAP, GL_TEXTURE_MAG_FILTER);
            if (t == GL_TEXTURE_CUBE_MAP)
                p = GL_TEXTURE_MAG_FILTER;
            tsr_call_TexParameteri(d, t, p, ri(s, 2) ? GL_NEAREST : GL_LINEAR);
            break;
        }
        }
        break;
    }
    case 23:
    case 24: {
        GLenum fmt = PICK(s, GL_RGBA, GL_RGB, GL_LUMINANCE);
        /* One internal format per mipmapped texture (levels of different
         * formats make an inconsistent texture whose contents are again the
         * implementation's affair); 3D textures have one level. */
        GLint ifmt3 = (GLint)PICK(s, GL_RGBA, GL_RGB8, GL_LUMINANCE8, GL_RGBA4), ifmt = GL_RGBA;
        /* Consistent mipmap chains (8x4 base): what GL returns for an
         * inconsistent, incomplete texture is the implementation's affair. */
        int lv = ri(s, 3);
        GLsizei w = 8 >> lv, h = 4 >> lv > 0 ? 4 >> lv : 1;
        for (int i = 0; i < 8192; i++)
            scratch[i] = (uint8_t)rnd(s);
        int which = ri(s, 6);
        if (seq_transfer_used) {
            static const GLenum scales[] = {GL_RED_SCALE, GL_GREEN_SCALE, GL_BLUE_SCALE, GL_ALPHA_SCALE,
                                            GL_DEPTH_SCALE};
            static const GLenum biases[] = {GL_RED_BIAS,   GL_GREEN_BIAS,  GL_BLUE_BIAS,    GL_ALPHA_BIAS,
                                            GL_DEPTH_BIAS, GL_INDEX_SHIFT, GL_INDEX_OFFSET, GL_MAP_COLOR};
            for (int i = 0; i < 5; i++)
                tsr_call_PixelTransferf(d, scales[i], 1.0f);
            for (int i = 0; i < 8; i++)
                tsr_call_PixelTransferf(d, biases[i], 0.0f);
        }
        if (which == 0)
            tsr_call_TexImage1D(d, GL_TEXTURE_1D, lv, ifmt, w, 0, fmt, GL_UNSIGNED_BYTE, scratch);
        else if (which == 1)
            tsr_call_TexImage3D(d, GL_TEXTURE_3D, 0, ifmt3, 8, 4, 1 + ri(s, 3), 0, fmt, GL_UNSIGNED_BYTE, scratch);
        else if (which == 2)
            tsr_call_TexImage2D(d, GL_TEXTURE_CUBE_MAP_POSITIVE_X + (GLenum)ri(s, 6), 0, ifmt, 4, 4, 0, fmt,
                                GL_UNSIGNED_BYTE, scratch);
        else if (which == 3)
            tsr_call_TexSubImage2D(d, GL_TEXTURE_2D, 0, ri(s, 2), ri(s, 2), 1 + ri(s, 2), 1 + ri(s, 2), fmt,
                                   GL_UNSIGNED_BYTE, scratch);
        else if (which == 4 && ri(s, 3) == 0)
            tsr_call_GenerateMipmap(d, GL_TEXTURE_2D);
        else {
            /* NULL pixels leave the contents undefined (they differ freely
             * between contexts), so a full sub-image defines them after. */
            tsr_call_TexImage2D(d, GL_TEXTURE_2D, lv, ifmt, w, h, 0, fmt, GL_UNSIGNED_BYTE, ri(s, 8) ? scratch : NULL);
            tsr_call_TexSubImage2D(d, GL_TEXTURE_2D, lv, 0, 0, w, h, fmt, GL_UNSIGNED_BYTE, scratch + 1);
        }
        break;
    }
    case 25: {
        switch (ri(s, 4)) {
        case 0:
            tsr_call_TexEnvi(d, GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE,
                             (GLint)PICK(s, GL_MODULATE, GL_REPLACE, GL_DECAL, GL_BLEND, GL_ADD, GL_COMBINE));
            break;
        case 1:
            tsr_call_TexEnvfv(d, GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, (GLfloat[]){r01(s), r01(s), r01(s), r01(s)});
            break;
        case 2:
            tsr_call_TexEnvi(d, GL_TEXTURE_ENV, PICK(s, GL_COMBINE_RGB, GL_COMBINE_ALPHA),
                             (GLint)PICK(s, GL_REPLACE, GL_ADD, GL_INTERPOLATE, GL_SUBTRACT));
            break;
        default:
            tsr_call_TexEnvf(d, GL_TEXTURE_ENV, PICK(s, GL_RGB_SCALE, GL_ALPHA_SCALE), (GLfloat)(1 << ri(s, 3)));
            break;
        }
        break;
    }
    case 26:
        switch (ri(s, 3)) {
        case 0:
            tsr_call_TexGeni(d, PICK(s, GL_S, GL_T, GL_R, GL_Q), GL_TEXTURE_GEN_MODE,
                             (GLint)PICK(s, GL_OBJECT_LINEAR, GL_EYE_LINEAR));
            break;
        case 1: tsr_call_TexGenfv(d, PICK(s, GL_S, GL_T, GL_R, GL_Q), GL_OBJECT_PLANE, v); break;
        default: tsr_call_TexGenfv(d, PICK(s, GL_S, GL_T, GL_R, GL_Q), GL_EYE_PLANE, v); break;
        }
        break;
    case 27: tsr_call_MatrixMode(d, PICK(s, GL_MODELVIEW, GL_MODELVIEW, GL_PROJECTION, GL_TEXTURE)); break;
    case 28:
    case 29:
        switch (ri(s, 8)) {
        case 0: tsr_call_LoadIdentity(d); break;
        case 1: tsr_call_Translatef(d, v[0], v[1], v[2]); break;
        case 2: tsr_call_Scalef(d, 1 + r01(s), 1 + r01(s), 1 - r01(s) / 2); break;
        case 3: tsr_call_Rotatef(d, (GLfloat)ri(s, 360), v[0], v[1], 1.0f); break;
        case 4: tsr_call_Frustum(d, -1, 1, -1, 1, 1, 10 + ri(s, 90)); break;
        case 5: tsr_call_Ortho(d, -2, 2, -1.5, 1.5, -1, 1 + ri(s, 9)); break;
        case 6: tsr_call_MultMatrixf(d, v); break;
        default: tsr_call_LoadMatrixf(d, v); break;
        }
        break;
    case 30:
        if (ri(s, 2))
            tsr_call_PushMatrix(d);
        else
            tsr_call_PopMatrix(d);
        break;
    case 31: tsr_call_ClipPlane(d, GL_CLIP_PLANE0 + (GLenum)ri(s, 6), (GLdouble[]){v[0], v[1], v[2], v[3]}); break;
    case 32:
        if (ri(s, 2) && *attrib_depth < 8) {
            /* Never GL_CURRENT_BIT: Mesa 22.3's PopAttrib loses the saved
             * current values to a glColor/glVertexAttrib made after the push
             * (measured); the tracker restores them as GL says. */
            GLbitfield mask = (ri(s, 3) ? (GLbitfield)rnd(s) & ~GL_EVAL_BIT : GL_ALL_ATTRIB_BITS) & ~GL_CURRENT_BIT;
            seq_color_material_used |= (mask & GL_LIGHTING_BIT) != 0;
            tsr_call_PushAttrib(d, mask);
            ++*attrib_depth;
        } else if (*attrib_depth > 0) {
            seq_popattrib_used = 1;
            tsr_call_PopAttrib(d);
            --*attrib_depth;
        }
        break;
    case 33:
        if (ri(s, 2)) {
            tsr_call_ListBase(d, (GLuint)ri(s, 100));
        } else {
            tsr_call_SampleCoverage(d, r01(s), (GLboolean)ri(s, 2));
        }
        break;
    case 34: {
        switch (ri(s, 3)) {
        case 0: tsr_call_BindBuffer(d, PICK(s, GL_ARRAY_BUFFER, GL_ELEMENT_ARRAY_BUFFER), (GLuint)ri(s, 4)); break;
        case 1:
            for (int i = 0; i < 256; i++)
                scratch[8192 + i] = (uint8_t)rnd(s);
            tsr_call_BufferData(d, GL_ARRAY_BUFFER, 16 + ri(s, 200), scratch + 8192,
                                PICK(s, GL_STATIC_DRAW, GL_STREAM_DRAW));
            break;
        default: tsr_call_BufferSubData(d, GL_ARRAY_BUFFER, ri(s, 8), 8, scratch + 8192 + ri(s, 64)); break;
        }
        break;
    }
    case 35:
        switch (ri(s, 5)) {
        case 0:
            tsr_call_VertexPointer(d, 2 + ri(s, 3), PICK(s, GL_FLOAT, GL_SHORT, GL_DOUBLE), 4 * ri(s, 8),
                                   scratch + ri(s, 64));
            break;
        case 1: tsr_call_ColorPointer(d, 3 + ri(s, 2), PICK(s, GL_UNSIGNED_BYTE, GL_FLOAT), 0, scratch + 16); break;
        case 2: tsr_call_TexCoordPointer(d, 1 + ri(s, 4), GL_FLOAT, 8 * ri(s, 4), scratch + 32); break;
        case 3: tsr_call_NormalPointer(d, PICK(s, GL_FLOAT, GL_BYTE), 0, scratch); break;
        default:
            tsr_call_InterleavedArrays(d, PICK(s, GL_V3F, GL_C4UB_V3F, GL_T2F_N3F_V3F, GL_T4F_C4F_N3F_V4F), 0,
                                       scratch + 64);
            break;
        }
        break;
    case 36:
        if (ri(s, 3) == 0)
            tsr_call_ClientActiveTexture(d, GL_TEXTURE0 + (GLenum)ri(s, 8));
        else if (ri(s, 2))
            tsr_call_EnableClientState(d, PICK(s, GL_VERTEX_ARRAY, GL_NORMAL_ARRAY, GL_COLOR_ARRAY,
                                               GL_TEXTURE_COORD_ARRAY, GL_EDGE_FLAG_ARRAY));
        else
            tsr_call_DisableClientState(
                d, PICK(s, GL_VERTEX_ARRAY, GL_NORMAL_ARRAY, GL_COLOR_ARRAY, GL_TEXTURE_COORD_ARRAY));
        break;
    case 37:
        if (ri(s, 2) && *client_depth < 8) {
            tsr_call_PushClientAttrib(
                d, PICK(s, GL_CLIENT_PIXEL_STORE_BIT, GL_CLIENT_VERTEX_ARRAY_BIT, GL_CLIENT_ALL_ATTRIB_BITS));
            ++*client_depth;
        } else if (*client_depth > 0) {
            tsr_call_PopClientAttrib(d);
            --*client_depth;
        }
        break;
    case 38: {
        GLuint names[2] = {20 + (GLuint)ri(s, 3), 10 + (GLuint)ri(s, 3)};
        /* Not under a pushed GL_TEXTURE_BIT: Mesa's PopAttrib rebinds the
         * saved texture and so revives a deleted name. */
        if (ri(s, 4) == 0 && !*attrib_depth)
            tsr_call_DeleteTextures(d, 2, names);
        else
            tsr_call_ActiveTexture(d, GL_TEXTURE0);
        break;
    }
    default:
        if (ri(s, 4) == 0) {
            /* Not while a client attribute stack could bring the name back
             * (popping a binding of a deleted buffer: Mesa revives it). */
            GLuint b = 1 + (GLuint)ri(s, 3);
            if (!*client_depth)
                tsr_call_DeleteBuffers(d, 1, &b);
        } else {
            tsr_call_TexGeni(d, GL_S, GL_TEXTURE_GEN_MODE,
                             (GLint)PICK(s, GL_SPHERE_MAP, GL_REFLECTION_MAP, GL_NORMAL_MAP));
        }
        break;
    }
}

/* The same sequence for a seed, into any table. The first call sizes the
 * window as a window system would (OSMesa did it when made current). */
static void run_sequence(uint64_t seed, const tsr_dispatch *d, int calls)
{
    uint64_t s = seed * 7919 + 1;
    int ad = 0, cd = 0;
    seq_transfer_used = seq_color_material_used = seq_popattrib_used = 0;
    tsr_call_WindowCreateTSR(d, 0, 64, 64);
    for (int i = 0; i < calls; i++) {
        random_call(&s, d, &ad, &cd);
    }
}

/* --- comparing ------------------------------------------------------------------------- */
static GLenum answered[4096];
static size_t nanswered;

/* Every pname the tracker answers, found by asking it about each enum of
 * the GL ranges that hold state. */
static void find_answered(void)
{
    static const GLenum ranges[][2] = {{0x0B00, 0x0DFF}, {0x0300, 0x0400}, {0x2A00, 0x2A30},
                                       {0x3000, 0x3010}, {0x4000, 0x4010}, {0x8000, 0x8FFF}};
    for (size_t r = 0; r < sizeof ranges / sizeof ranges[0]; r++)
        for (GLenum p = ranges[r][0]; p <= ranges[r][1]; p++)
            if (tsr_state_get_count(p) > 0 && nanswered < 4096)
                answered[nanswered++] = p;
}

static int derived_pname(GLenum p)
{
    return p == GL_MODELVIEW_MATRIX || p == GL_PROJECTION_MATRIX || p == GL_TEXTURE_MATRIX ||
           p == GL_TRANSPOSE_MODELVIEW_MATRIX || p == GL_TRANSPOSE_PROJECTION_MATRIX ||
           p == GL_TRANSPOSE_TEXTURE_MATRIX;
}

/* Client-side state a renderer never receives (arrays travel with each
 * draw, PushAttrib is resolved by the tracker): compared only with the
 * context that got the calls themselves. */
static int client_pname(GLenum p)
{
    return (p >= GL_VERTEX_ARRAY && p <= GL_EDGE_FLAG_ARRAY_STRIDE) ||
           (p >= GL_FOG_COORD_ARRAY_TYPE && p <= GL_FOG_COORD_ARRAY) ||
           (p >= GL_SECONDARY_COLOR_ARRAY_SIZE && p <= GL_SECONDARY_COLOR_ARRAY) || p == GL_CLIENT_ACTIVE_TEXTURE ||
           p == GL_ATTRIB_STACK_DEPTH || p == GL_CLIENT_ATTRIB_STACK_DEPTH ||
           (p >= GL_VERTEX_ARRAY_BUFFER_BINDING && p <= GL_WEIGHT_ARRAY_BUFFER_BINDING);
}

static int close_enough(double a, double b, int tolerant)
{
    if (a == b || (isnan(a) && isnan(b)))
        return 1;
    return tolerant && fabs(a - b) <= 1e-5 * (1.0 + fabs(a) + fabs(b));
}

static int report(const char *what, unsigned p, int i, double want, double got, int *shown)
{
    if ((*shown)++ < 12)
        fprintf(stderr, "  %s 0x%04x[%d]: tracker %.9g, GL %.9g\n", what, p, i, want, got);
    return 1;
}

/* Compares every answer of the tracker with GL env e. `tolerant`: values
 * GL computes itself (matrices, eye-space transforms) within 1e-5. Returns
 * the number of mismatches; *count gets the number of values compared. */
static int compare_gets(tsr_state_ctx *c, tsr_dispatch *tracker_table, gl_env *e, int tolerant, long *count)
{
    int bad = 0, shown = 0;
    gl_use(e);
    const tsr_state_values *tv = tsr_state_values_of(c);
    GLuint unit = tv->active_texture;
    for (GLuint i = 0; i < TSR_STATE_UNITS + NHIGH; i++) {
        GLuint u = i < TSR_STATE_UNITS ? i : high_units[i - TSR_STATE_UNITS];
        /* Per-unit values are asked with each unit active, on both sides. */
        tsr_call_ActiveTexture(tracker_table, GL_TEXTURE0 + u);
        e->gl.ActiveTexture(GL_TEXTURE0 + u);
        for (size_t k = 0; k < nanswered; k++) {
            GLenum p = answered[k];
            GLdouble td[16], gd[16];
            GLfloat tf[16], gf[16];
            GLint ti[16], gi[16];
            GLboolean tb[16], gb[16];
            if (!tsr_state_get_doublev(c, p, td) || (!tolerant && client_pname(p)))
                continue;
            int n = tsr_state_get_count(p);
            tsr_state_get_floatv(c, p, tf);
            tsr_state_get_integerv(c, p, ti);
            tsr_state_get_booleanv(c, p, tb);
            e->gl.GetDoublev(p, gd);
            e->gl.GetFloatv(p, gf);
            e->gl.GetIntegerv(p, gi);
            e->gl.GetBooleanv(p, gb);
            int tol = tolerant && derived_pname(p);
            for (int i = 0; i < n; i++) {
                ++*count;
                if (!close_enough(td[i], gd[i], tol))
                    bad += report("GetDoublev", p, i, td[i], gd[i], &shown);
                if (!close_enough(tf[i], gf[i], tol))
                    bad += report("GetFloatv", p, i, tf[i], gf[i], &shown);
                if (!tol && ti[i] != gi[i])
                    bad += report("GetIntegerv", p, i, ti[i], gi[i], &shown);
                if (!tol && tb[i] != gb[i])
                    bad += report("GetBooleanv", p, i, tb[i], gb[i], &shown);
            }
        }
        static const GLenum envs[] = {GL_TEXTURE_ENV_MODE, GL_TEXTURE_ENV_COLOR, GL_COMBINE_RGB,  GL_COMBINE_ALPHA,
                                      GL_SRC0_RGB,         GL_SRC1_ALPHA,        GL_OPERAND2_RGB, GL_OPERAND0_ALPHA,
                                      GL_RGB_SCALE,        GL_ALPHA_SCALE};
        for (size_t k = 0; k < sizeof envs / sizeof envs[0]; k++) {
            GLfloat t[4] = {0}, g[4] = {0};
            tsr_state_get_tex_envfv(c, GL_TEXTURE_ENV, envs[k], t);
            e->gl.GetTexEnvfv(GL_TEXTURE_ENV, envs[k], g);
            for (int i = 0; i < 4; i++, ++*count)
                if (t[i] != g[i])
                    bad += report("GetTexEnvfv", envs[k], i, t[i], g[i], &shown);
        }
        for (GLenum coord = GL_S; coord <= GL_Q; coord++) {
            static const GLenum gens[] = {GL_TEXTURE_GEN_MODE, GL_OBJECT_PLANE, GL_EYE_PLANE};
            for (int k = 0; k < 3; k++) {
                GLfloat t[4] = {0}, g[4] = {0};
                tsr_state_get_tex_genfv(c, coord, gens[k], t);
                e->gl.GetTexGenfv(coord, gens[k], g);
                for (int i = 0; i < 4; i++, ++*count)
                    if (!close_enough(t[i], g[i], tolerant && gens[k] == GL_EYE_PLANE))
                        bad += report("GetTexGenfv", coord * 16 + (GLenum)k, i, t[i], g[i], &shown);
            }
        }
        static const GLenum targets[] = {GL_TEXTURE_1D, GL_TEXTURE_2D, GL_TEXTURE_3D, GL_TEXTURE_CUBE_MAP};
        static const GLenum tparams[] = {
            GL_TEXTURE_MIN_FILTER,   GL_TEXTURE_MAG_FILTER, GL_TEXTURE_WRAP_S,  GL_TEXTURE_WRAP_T,  GL_TEXTURE_WRAP_R,
            GL_TEXTURE_BORDER_COLOR, GL_TEXTURE_PRIORITY,   GL_TEXTURE_MIN_LOD, GL_TEXTURE_MAX_LOD, GL_TEXTURE_LOD_BIAS,
            GL_TEXTURE_BASE_LEVEL,   GL_TEXTURE_MAX_LEVEL,  GL_GENERATE_MIPMAP};
        for (int t = 0; t < 4; t++) {
            for (size_t k = 0; k < sizeof tparams / sizeof tparams[0]; k++) {
                GLfloat tv4[4] = {0}, gv4[4] = {0};
                if (!tsr_state_get_tex_parameterfv(c, targets[t], tparams[k], tv4))
                    continue;
                e->gl.GetTexParameterfv(targets[t], tparams[k], gv4);
                for (int i = 0; i < 4; i++, ++*count)
                    if (tv4[i] != gv4[i])
                        bad += report("GetTexParameterfv", targets[t] * 16 + (GLenum)k, i, tv4[i], gv4[i], &shown);
            }
            /* GL_EXT_texture_integer border colours, as GLints either way */
            static const GLenum int_types[] = {GL_INT, GL_UNSIGNED_INT};
            for (int k = 0; k < 2; k++) {
                GLint ti4[4] = {0}, gi4[4] = {0};
                if (!tsr_state_get_tex_parameter_int(c, targets[t], GL_TEXTURE_BORDER_COLOR, int_types[k], ti4))
                    continue;
                if (int_types[k] == GL_INT)
                    e->gl.GetTexParameterIivEXT(targets[t], GL_TEXTURE_BORDER_COLOR, gi4);
                else
                    e->gl.GetTexParameterIuivEXT(targets[t], GL_TEXTURE_BORDER_COLOR, (GLuint *)gi4);
                for (int i = 0; i < 4; i++, ++*count)
                    if (ti4[i] != gi4[i])
                        bad += report("GetTexParameterI*vEXT", targets[t] * 16 + (GLenum)k, i, ti4[i], gi4[i], &shown);
            }
            GLenum face = targets[t] == GL_TEXTURE_CUBE_MAP ? GL_TEXTURE_CUBE_MAP_POSITIVE_X : targets[t];
            for (GLint level = 0; level < 3; level++) {
                static const GLenum lp[] = {GL_TEXTURE_WIDTH, GL_TEXTURE_HEIGHT, GL_TEXTURE_DEPTH, GL_TEXTURE_BORDER};
                for (int k = 0; k < 4; k++) {
                    GLint a = -1, b = -2;
                    if (!tsr_state_get_tex_level_parameteriv(c, face, level, lp[k], &a))
                        continue;
                    e->gl.GetTexLevelParameteriv(face, level, lp[k], &b);
                    ++*count;
                    if (a != b)
                        bad += report("GetTexLevelParameteriv", lp[k], level, a, b, &shown);
                }
            }
        }
    }
    tsr_call_ActiveTexture(tracker_table, GL_TEXTURE0 + unit);
    e->gl.ActiveTexture(GL_TEXTURE0 + unit);
    for (GLenum l = GL_LIGHT0; l < GL_LIGHT0 + 8; l++) {
        static const GLenum lps[] = {GL_AMBIENT,
                                     GL_DIFFUSE,
                                     GL_SPECULAR,
                                     GL_POSITION,
                                     GL_SPOT_DIRECTION,
                                     GL_SPOT_EXPONENT,
                                     GL_SPOT_CUTOFF,
                                     GL_CONSTANT_ATTENUATION,
                                     GL_LINEAR_ATTENUATION,
                                     GL_QUADRATIC_ATTENUATION};
        for (size_t k = 0; k < sizeof lps / sizeof lps[0]; k++) {
            GLfloat t[4] = {0}, g[4] = {0};
            tsr_state_get_lightfv(c, l, lps[k], t);
            e->gl.GetLightfv(l, lps[k], g);
            int tol = tolerant && (lps[k] == GL_POSITION || lps[k] == GL_SPOT_DIRECTION);
            for (int i = 0; i < 4; i++, ++*count)
                if (!close_enough(t[i], g[i], tol))
                    bad += report("GetLightfv", l * 16 + (GLenum)k, i, t[i], g[i], &shown);
        }
    }
    for (int f = 0; f < 2 && !seq_color_material_used; f++) {
        static const GLenum mps[] = {GL_AMBIENT, GL_DIFFUSE, GL_SPECULAR, GL_EMISSION, GL_SHININESS};
        for (size_t k = 0; k < 5; k++) {
            GLfloat t[4] = {0}, g[4] = {0};
            tsr_state_get_materialfv(c, f ? GL_BACK : GL_FRONT, mps[k], t);
            e->gl.GetMaterialfv(f ? GL_BACK : GL_FRONT, mps[k], g);
            for (int i = 0; i < 4; i++, ++*count)
                if (t[i] != g[i])
                    bad += report("GetMaterialfv", mps[k] + (GLenum)f, i, t[i], g[i], &shown);
        }
    }
    for (GLenum p = GL_CLIP_PLANE0; p < GL_CLIP_PLANE0 + 6; p++) {
        GLdouble t[4], g[4];
        tsr_state_get_clip_plane(c, p, t);
        e->gl.GetClipPlane(p, g);
        for (int i = 0; i < 4; i++, ++*count)
            if (!close_enough(t[i], g[i], tolerant))
                bad += report("GetClipPlane", p, i, t[i], g[i], &shown);
    }
    {
        static GLubyte t[1 << 14], g[1 << 14];
        memset(t, 0, sizeof t);
        memset(g, 0, sizeof g);
        int answered_here = tsr_state_get_polygon_stipple(c, t);
        e->gl.GetPolygonStipple(g);
        ++*count;
        if (answered_here && memcmp(t, g, sizeof t) != 0)
            bad += report("GetPolygonStipple", 0, 0, 0, 1, &shown);
    }
    for (GLuint i = 1; i < TSR_STATE_ATTRIBS; i++) {
        GLfloat g[4];
        e->GetVertexAttribfv(i, GL_CURRENT_VERTEX_ATTRIB, g);
        for (int k = 0; k < 4; k++, ++*count)
            if (tv->attrib[i][k] != g[k])
                bad += report("GetVertexAttribfv", i, k, tv->attrib[i][k], g[k], &shown);
    }
    {
        GLint t = -1, g = -2;
        if (tsr_state_get_buffer_parameteriv(c, GL_ARRAY_BUFFER, GL_BUFFER_SIZE, &t)) {
            e->gl.GetBufferParameteriv(GL_ARRAY_BUFFER, GL_BUFFER_SIZE, &g);
            ++*count;
            if (t != g)
                bad += report("GetBufferParameteriv", GL_BUFFER_SIZE, 0, t, g, &shown);
        }
    }
    /* Objects reach a renderer lazily (when bound where they are used), so
     * names only exist everywhere in the context given the calls. */
    for (GLuint n = 0; n < 50 && tolerant; n++) {
        ++*count;
        if (tsr_state_is_texture(c, n) != e->gl.IsTexture(n))
            bad += report("IsTexture", n, 0, tsr_state_is_texture(c, n), e->gl.IsTexture(n), &shown);
        if (tsr_state_is_buffer(c, n) != e->gl.IsBuffer(n))
            bad += report("IsBuffer", n, 0, tsr_state_is_buffer(c, n), e->gl.IsBuffer(n), &shown);
    }
    GLenum err = e->gl.GetError();
    (void)err; /* the random sequence makes legal-but-rejected calls on purpose */
    return bad;
}

/* Texels of every bound texture level and the bound buffer's bytes must be
 * the same in A (diffed) and B (called directly). */
static int compare_objects(gl_env *a, gl_env *b)
{
    int bad = 0;
    static uint8_t ta[1 << 16], tb[1 << 16];
    static const GLenum targets[] = {GL_TEXTURE_1D, GL_TEXTURE_2D, GL_TEXTURE_3D, GL_TEXTURE_CUBE_MAP_POSITIVE_X};
    static const GLenum bindings[] = {GL_TEXTURE_BINDING_1D, GL_TEXTURE_BINDING_2D, GL_TEXTURE_BINDING_3D,
                                      GL_TEXTURE_BINDING_CUBE_MAP};
    for (GLuint i = 0; i < TSR_STATE_UNITS + NHIGH; i++)
        for (int t = 0; t < 4; t++)
            for (GLint level = 0; level < 3; level++) {
                GLuint u = i < TSR_STATE_UNITS ? i : high_units[i - TSR_STATE_UNITS];
                GLint wa = 0, wb = 0, na = 0, nb = 0;
                gl_env *envs[2] = {a, b};
                uint8_t *bufs[2] = {ta, tb};
                GLint *ws[2] = {&wa, &wb}, *ns[2] = {&na, &nb};
                for (int k = 0; k < 2; k++) {
                    gl_env *e = envs[k];
                    gl_use(e);
                    GLint old;
                    e->gl.GetIntegerv(GL_ACTIVE_TEXTURE, &old);
                    e->gl.ActiveTexture(GL_TEXTURE0 + u);
                    e->gl.GetIntegerv(bindings[t], ns[k]);
                    e->gl.GetTexLevelParameteriv(targets[t], level, GL_TEXTURE_WIDTH, ws[k]);
                    memset(bufs[k], 0xcd, sizeof ta);
                    if (*ws[k] > 0) {
                        e->gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
                        e->gl.PixelStorei(GL_PACK_ROW_LENGTH, 0);
                        e->gl.PixelStorei(GL_PACK_SKIP_PIXELS, 0);
                        e->gl.PixelStorei(GL_PACK_SKIP_ROWS, 0);
                        e->gl.PixelStorei(GL_PACK_LSB_FIRST, 0);
                        e->gl.PixelStorei(GL_PACK_SWAP_BYTES, 0);
                        e->gl.GetTexImage(targets[t], level, GL_RGBA, GL_UNSIGNED_BYTE, bufs[k]);
                    }
                    e->gl.ActiveTexture((GLenum)old);
                }
                if (na != nb || wa != wb || memcmp(ta, tb, sizeof ta) != 0) {
                    if (getenv("STATE_TRACE")) {
                        size_t first = 0;
                        while (first < sizeof ta && ta[first] == tb[first])
                            first++;
                        fprintf(stderr, "  first differing byte %zu: A", first);
                        for (size_t i = first - first % 4; i < first - first % 4 + 12 && i < sizeof ta; i++)
                            fprintf(stderr, " %02x", ta[i]);
                        fprintf(stderr, " / B");
                        for (size_t i = first - first % 4; i < first - first % 4 + 12 && i < sizeof ta; i++)
                            fprintf(stderr, " %02x", tb[i]);
                        fputc('\n', stderr);
                    }
                    if (bad++ < 5)
                        fprintf(stderr, "  texture unit %u target 0x%x level %d: names %d/%d widths %d/%d %s\n", u,
                                targets[t], level, na, nb, wa, wb, memcmp(ta, tb, sizeof ta) ? "texels differ" : "");
                }
            }
    GLint sa = 0, sb = 0;
    gl_use(a);
    a->gl.GetBufferParameteriv(GL_ARRAY_BUFFER, GL_BUFFER_SIZE, &sa);
    if (sa > 0)
        a->GetBufferSubData(GL_ARRAY_BUFFER, 0, sa, ta);
    gl_use(b);
    b->gl.GetBufferParameteriv(GL_ARRAY_BUFFER, GL_BUFFER_SIZE, &sb);
    if (sb > 0)
        b->GetBufferSubData(GL_ARRAY_BUFFER, 0, sb, tb);
    if (sa != sb || (sa > 0 && memcmp(ta, tb, (size_t)sa) != 0)) {
        fprintf(stderr, "  array buffer: sizes %d/%d or bytes differ\n", sa, sb);
        bad++;
    }
    return bad;
}

/* --- a packer whose buffers go straight into an unpacker ------------------------------- */
typedef struct wire {
    tsr_packer *p;
    tsr_unpacker *u;
    tsr_dispatch table; /* the packer's table */
    uint64_t bytes, buffers;
} wire;

static int wire_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    wire *w = ctx;
    w->bytes += size;
    w->buffers++;
    if (!w->u)
        return 0;
    return tsr_unpacker_run(w->u, buf, size, err) < 0 ? TSR_EPROTO : 0;
}

static wire *wire_open(const tsr_dispatch *target)
{
    wire *w = calloc(1, sizeof *w);
    tsr_error err = {0};
    tsr_pack_sink sink = {.flush = wire_flush, .ctx = w};
    w->p = tsr_packer_create(1 << 16, &sink, &err);
    if (target)
        w->u = tsr_unpacker_create(target, NULL, NULL, &err);
    if (!w->p || (target && !w->u)) {
        fprintf(stderr, "state_test: %s\n", err.message);
        exit(1);
    }
    tsr_dispatch_fill_nop(&w->table);
    tsr_packer_fill_dispatch(w->p, &w->table);
    return w;
}

static void wire_close(wire *w)
{
    tsr_packer_destroy(w->p);
    if (w->u)
        tsr_unpacker_destroy(w->u);
    free(w);
}

/* --- the tests --------------------------------------------------------------------------- */
/* A tracker with one context, one renderer's shadow and a table that
 * feeds the context (static: a dispatch table is large for the stack). */
#define TRACKED(t, c, s, d)                                 \
    tsr_state_tracker *t = tsr_state_tracker_create(NULL);  \
    tsr_state_ctx *c = tsr_state_ctx_create(t, NULL);       \
    tsr_state_shadow *s = tsr_state_shadow_create(t, NULL); \
    static tsr_dispatch d;                                  \
    tsr_dispatch_fill_nop(&d);                              \
    tsr_state_fill_dispatch(c, &d)

static int seeds_arg = 100;

static void test_covers_spec(void)
{
    tsr_state_tracker *t = tsr_state_tracker_create(NULL);
    tsr_state_ctx *c = tsr_state_ctx_create(t, NULL);
    static tsr_dispatch d;
    memset(&d, 0, sizeof d);
    tsr_state_fill_dispatch(c, &d);
    const char *name, *cat;
    int n = 0, tracked = 0;
    for (size_t i = 0; tsr_state_spec_command(i, &name, &cat); i++, n++) {
        int slot = tsr_dispatch_slot(name);
        CHECK(slot >= 0, "%s is in the generated list but has no slot", name);
        if (slot < 0)
            continue;
        int listed = 0;
        for (const tsr_state_untracked_cmd *u = tsr_state_untracked; u->name; u++)
            if (!strcmp(u->name, name)) {
                listed = 1;
                CHECK(strlen(u->why) > 20, "%s: the reason must say why", name);
            }
        int set = d.slots[slot].fn != NULL;
        tracked += set;
        CHECK(set || listed, "%s (%s) is neither tracked nor listed in tsr_state_untracked", name, cat);
        CHECK(!(set && listed), "%s is tracked and also listed as untracked", name);
    }
    for (const tsr_state_untracked_cmd *u = tsr_state_untracked; u->name; u++) {
        int found = 0;
        for (size_t i = 0; tsr_state_spec_command(i, &name, &cat); i++)
            found |= !strcmp(name, u->name);
        CHECK(found, "untracked %s is not a state/object/client command of the spec", u->name);
    }
    printf("%d commands to cover, %d tracked\n", n, tracked);
    CHECK(n > 250 && tracked > 200, "coverage list looks wrong (%d, %d)", n, tracked);
    tsr_state_tracker_destroy(t);
}

static void test_diff_matches_osmesa(void)
{
    find_answered();
    CHECK(nanswered > 150, "tracker answers only %zu pnames", nanswered);
    long compared = 0, commands = 0;
    int direct_seeds = 0;
    int first_seed = getenv("STATE_SEED") ? atoi(getenv("STATE_SEED")) : 0;
    for (int seed = first_seed; seed < seeds_arg; seed++) {
        TRACKED(t, c, s, tt);
        int calls = 20 + seed % 200;
        run_sequence((uint64_t)seed, &tt, calls);

        gl_env *b = gl_open();
        if (getenv("STATE_TRACE")) {
            static tsr_dispatch traced;
            tsr_tracer tr = {.out = stderr, .child = &b->d};
            tsr_trace_fill(&traced, &tr);
            run_sequence((uint64_t)seed, &traced, calls);
        } else {
            run_sequence((uint64_t)seed, &b->d, calls);
        }
        b->gl.Finish();

        gl_env *a = gl_open();
        tsr_state_diff_stats st;
        uint32_t n;
        if ((seed & 1) && !getenv("STATE_TRACE")) { /* through the real wire */
            wire *w = wire_open(&a->d);
            n = tsr_state_diff(c, s, &w->table, &st);
            CHECK(tsr_packer_flush(w->p) == 0, "seed %d: packer flush: %s", seed, tsr_packer_error(w->p)->message);
            CHECK(tsr_packer_error(w->p)->code == TSR_OK, "seed %d: %s", seed, tsr_packer_error(w->p)->message);
            wire_close(w);
        } else if (getenv("STATE_TRACE")) { /* print what the diff sends */
            static tsr_dispatch traced;
            tsr_tracer tr = {.out = stderr, .child = &a->d};
            tsr_trace_fill(&traced, &tr);
            n = tsr_state_diff(c, s, &traced, &st);
        } else {
            n = tsr_state_diff(c, s, &a->d, &st);
        }
        commands += n;
        a->gl.Finish();
        /* (c) a second diff has nothing to do */
        tsr_state_diff_stats st2;
        CHECK(tsr_state_diff(c, s, &a->d, &st2) == 0 && st2.members_visited == 0,
              "seed %d: second diff emitted %u commands", seed, st2.commands);

        long before = compared;
        int bad_a = compare_gets(c, &tt, a, 0, &compared);
        CHECK(bad_a == 0, "seed %d (%d calls): %d tracker answers differ from the diffed OSMesa context", seed, calls,
              bad_a);
        if (!seq_popattrib_used) {
            direct_seeds++;
            int bad_b = compare_gets(c, &tt, b, 1, &compared);
            CHECK(bad_b == 0, "seed %d (%d calls): %d tracker answers differ from OSMesa given the same calls", seed,
                  calls, bad_b);
            int bad_o = compare_objects(a, b);
            CHECK(bad_o == 0, "seed %d: %d texture/buffer contents differ between diffed and direct contexts", seed,
                  bad_o);
        }
        CHECK(compared - before > 1000, "seed %d compared only %ld values", seed, compared - before);
        gl_close(a);
        gl_close(b);
        tsr_state_tracker_destroy(t);
    }
    printf("%d seeds, %ld values compared, %ld commands diffed; %d seeds (no PopAttrib) also compared with "
           "OSMesa given the calls directly\n",
           seeds_arg, compared, commands, direct_seeds);
    CHECK(direct_seeds > seeds_arg / 3, "only %d seeds compared directly", direct_seeds);
}

static void test_unchanged_is_zero_bytes(void)
{
    tsr_state_tracker *t = tsr_state_tracker_create(NULL);
    tsr_state_ctx *fresh = tsr_state_ctx_create(t, NULL);
    tsr_state_shadow *s = tsr_state_shadow_create(t, NULL);
    wire *w = wire_open(NULL);
    /* A context nobody changed against a renderer nobody changed. */
    CHECK(tsr_state_diff(fresh, s, &w->table, NULL) == 0, "fresh context emits commands");
    tsr_packer_flush(w->p);
    CHECK(w->bytes == 0, "fresh context diffed to %llu bytes", (unsigned long long)w->bytes);
    for (int seed = 0; seed < seeds_arg; seed++) {
        tsr_state_ctx *c1 = tsr_state_ctx_create(t, NULL), *c2 = tsr_state_ctx_create(t, NULL);
        tsr_state_shadow *r = tsr_state_shadow_create(t, NULL);
        static tsr_dispatch d1, d2;
        tsr_dispatch_fill_nop(&d1);
        tsr_dispatch_fill_nop(&d2);
        tsr_state_fill_dispatch(c1, &d1);
        tsr_state_fill_dispatch(c2, &d2);
        run_sequence((uint64_t)seed, &d1, 150);
        run_sequence((uint64_t)seed, &d2, 150);
        /* Each renderer has its own stream: the packer mirrors the pixel
         * store of the renderer it feeds. */
        wire_close(w);
        w = wire_open(NULL);
        uint64_t b0 = w->bytes;
        tsr_state_diff(c1, r, &w->table, NULL);
        tsr_packer_flush(w->p);
        uint64_t first = w->bytes - b0;
        CHECK(first > 0, "seed %d: the first diff packed nothing", seed);
        /* Unchanged: again, and the identical context on the same renderer. */
        b0 = w->bytes;
        uint32_t n1 = tsr_state_diff(c1, r, &w->table, NULL);
        uint32_t n2 = tsr_state_diff(c2, r, &w->table, NULL);
        uint32_t n3 = tsr_state_diff(c1, r, &w->table, NULL);
        CHECK(tsr_packer_pending(w->p) == 0, "seed %d: unchanged diffs packed %zu bytes", seed,
              tsr_packer_pending(w->p));
        tsr_packer_flush(w->p);
        CHECK(n1 == 0 && n2 == 0 && n3 == 0 && w->bytes == b0,
              "seed %d: unchanged state diffed to %u/%u/%u commands, %llu bytes", seed, n1, n2, n3,
              (unsigned long long)(w->bytes - b0));
        tsr_state_ctx_destroy(c1);
        tsr_state_ctx_destroy(c2);
        tsr_state_shadow_destroy(r);
    }
    wire_close(w);
    tsr_state_tracker_destroy(t);
}

/* One change per group, made on context B only (values no random
 * sequence produces, so they always differ). */
static void change_group(int g, const tsr_dispatch *d, tsr_state_ctx *c)
{
    GLboolean on = GL_FALSE;
    switch (g) {
    case TSR_SG_ENABLE:
        tsr_state_is_enabled(c, GL_FOG, &on);
        if (on)
            tsr_call_Disable(d, GL_FOG);
        else
            tsr_call_Enable(d, GL_FOG);
        break;
    case TSR_SG_CURRENT: tsr_call_Color4f(d, 0.0123f, 0.5f, 0.25f, 1.0f); break;
    case TSR_SG_VIEWPORT: tsr_call_Viewport(d, 3, 5, 61, 59); break;
    case TSR_SG_COLORBUF: tsr_call_ClearColor(d, 0.0123f, 0.5f, 0.25f, 1.0f); break;
    case TSR_SG_DEPTH: tsr_call_ClearDepth(d, 0.0123); break;
    case TSR_SG_STENCIL: tsr_call_ClearStencil(d, 1000); break;
    case TSR_SG_FOG: tsr_call_Fogf(d, GL_FOG_START, 123.25f); break;
    case TSR_SG_LIGHTING: tsr_call_Lightf(d, GL_LIGHT2, GL_SPOT_EXPONENT, 127.5f); break;
    case TSR_SG_RASTER: tsr_call_LineWidth(d, 9.75f); break;
    case TSR_SG_HINT: {
        GLint h = 0;
        tsr_state_get_integerv(c, GL_FOG_HINT, &h);
        tsr_call_Hint(d, GL_FOG_HINT, h == GL_NICEST ? GL_FASTEST : GL_NICEST);
        break;
    }
    case TSR_SG_TEXTURE:
        tsr_call_ActiveTexture(d, GL_TEXTURE0); /* a coordinate unit: one past them has no environment */
        tsr_call_TexEnvfv(d, GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, (GLfloat[]){0.0123f, 0, 0, 1});
        break;
    case TSR_SG_BUFFER: tsr_call_BindBuffer(d, GL_ELEMENT_ARRAY_BUFFER, 77); break;
    case TSR_SG_MISC: tsr_call_ListBase(d, 4242); break;
    case TSR_SG_PIXEL: tsr_call_PixelZoom(d, 3.5f, -2.25f); break;
    case TSR_SG_TRANSFORM: /* the modelview: a unit past the coordinate units has no texture matrix */
        tsr_call_MatrixMode(d, GL_MODELVIEW);
        tsr_call_Translatef(d, 0.0123f, 7, 9);
        break;
    case TSR_SG_PROGRAM: {
        GLuint p = tsr_call_CreateProgram(d);
        tsr_call_LinkProgram(d, p);
        tsr_call_UseProgram(d, p);
        break;
    }
    default: break;
    }
}

static void test_switch_only_differing_groups(void)
{
    for (int seed = 0; seed < seeds_arg; seed++)
        for (int g = -1; g < TSR_SG_COUNT; g++) {
            tsr_state_tracker *t = tsr_state_tracker_create(NULL);
            tsr_state_ctx *a = tsr_state_ctx_create(t, NULL), *b = tsr_state_ctx_create(t, NULL);
            tsr_state_shadow *r = tsr_state_shadow_create(t, NULL);
            static tsr_dispatch da, db, nop;
            tsr_dispatch_fill_nop(&da);
            tsr_dispatch_fill_nop(&db);
            tsr_dispatch_fill_nop(&nop);
            tsr_state_fill_dispatch(a, &da);
            tsr_state_fill_dispatch(b, &db);
            run_sequence((uint64_t)seed, &da, 100);
            run_sequence((uint64_t)seed, &db, 100);
            if (g >= 0)
                change_group(g, &db, b);
            uint32_t expect = g >= 0 ? 1u << g : 0;
            tsr_state_diff(a, r, &nop, NULL); /* r holds A */
            for (int round = 0; round < 3; round++) {
                tsr_state_diff_stats sb, sa;
                uint32_t nb = tsr_state_diff(b, r, &nop, &sb);
                uint32_t na = tsr_state_diff(a, r, &nop, &sa);
                CHECK(sb.group_mask == expect && sa.group_mask == expect,
                      "seed %d group %s round %d: switch A->B emitted groups 0x%x, B->A 0x%x, expected 0x%x", seed,
                      g >= 0 ? tsr_state_group_name(g) : "(none)", round, sb.group_mask, sa.group_mask, expect);
                CHECK((g < 0) == (nb == 0) && (g < 0) == (na == 0), "seed %d group %d: %u and %u commands", seed, g, nb,
                      na);
                /* Once B has met r, identical contexts look at nothing. */
                CHECK(g >= 0 || round == 0 || (sb.groups_visited == 0 && sa.groups_visited == 0),
                      "seed %d: identical contexts visited %u/%u groups", seed, sb.groups_visited, sa.groups_visited);
            }
            tsr_state_tracker_destroy(t);
        }
}

static void test_many_renderers(void)
{
    tsr_state_tracker *t = tsr_state_tracker_create(NULL);
    tsr_state_ctx *c = tsr_state_ctx_create(t, NULL);
    static tsr_dispatch d, nop;
    tsr_dispatch_fill_nop(&d);
    tsr_dispatch_fill_nop(&nop);
    tsr_state_fill_dispatch(c, &d);
    run_sequence(3, &d, 120);
    enum { N = 300 };
    tsr_state_shadow *r[N];
    uint32_t first = 0;
    for (int i = 0; i < N; i++) {
        r[i] = tsr_state_shadow_create(t, NULL);
        CHECK(r[i] && tsr_state_shadow_id(r[i]) == i, "renderer %d", i);
        uint32_t n = tsr_state_diff(c, r[i], &nop, NULL);
        if (i == 0)
            first = n;
        CHECK(n == first && n > 0, "renderer %d got %u commands, renderer 0 got %u", i, n, first);
    }
    /* One change: every renderer sees exactly it, once. */
    tsr_call_PointSize(&d, 17.5f);
    for (int i = 0; i < N; i++) {
        CHECK(tsr_state_is_dirty(c, r[i]), "renderer %d not dirty", i);
        CHECK(tsr_state_diff(c, r[i], &nop, NULL) == 1, "renderer %d", i);
        CHECK(tsr_state_diff(c, r[i], &nop, NULL) == 0, "renderer %d twice", i);
    }
    /* Ids are reused; a new renderer starts dirty; a new context too. */
    tsr_state_shadow_destroy(r[70]);
    r[70] = tsr_state_shadow_create(t, NULL);
    CHECK(tsr_state_shadow_id(r[70]) == 70, "id reuse gave %d", tsr_state_shadow_id(r[70]));
    tsr_state_shadow *extra = tsr_state_shadow_create(t, NULL);
    CHECK(tsr_state_shadow_id(extra) == N, "next id %d", tsr_state_shadow_id(extra));
    uint32_t fresh = tsr_state_diff(c, extra, &nop, NULL);
    CHECK(fresh > 0 && tsr_state_diff(c, r[70], &nop, NULL) == fresh, "re-created renderer is not like a new one");
    tsr_state_ctx *c2 = tsr_state_ctx_create(t, NULL);
    for (int i = 0; i < N; i++)
        CHECK(tsr_state_is_dirty(c2, r[i]), "new context clean for %d", i);
    tsr_state_tracker_destroy(t);
}

/* Counts the image calls a diff emits. */
typedef struct counter {
    int images, subimages, binds;
} counter;
static void cnt_TexImage2D(void *self, GLenum t, GLint l, GLint i, GLsizei w, GLsizei h, GLint b, GLenum f, GLenum ty,
                           const void *p)
{
    (void)t, (void)l, (void)i, (void)w, (void)h, (void)b, (void)f, (void)ty, (void)p;
    ((counter *)self)->images++;
}
static void cnt_TexSubImage2D(void *self, GLenum t, GLint l, GLint x, GLint y, GLsizei w, GLsizei h, GLenum f,
                              GLenum ty, const void *p)
{
    (void)t, (void)l, (void)x, (void)y, (void)w, (void)h, (void)f, (void)ty, (void)p;
    ((counter *)self)->subimages++;
}
static void cnt_BindTexture(void *self, GLenum t, GLuint n)
{
    (void)t, (void)n;
    ((counter *)self)->binds++;
}

static void test_lazy_textures(void)
{
    TRACKED(t, c, r, d);
    static tsr_dispatch out;
    counter k = {0};
    tsr_dispatch_fill_nop(&out);
    tsr_set_TexImage2D(&out, cnt_TexImage2D, &k);
    tsr_set_TexSubImage2D(&out, cnt_TexSubImage2D, &k);
    tsr_set_BindTexture(&out, cnt_BindTexture, &k);
    uint8_t px[4 * 16] = {1, 2, 3};
    GLuint names[3];
    tsr_call_GenTextures(&d, 3, names);
    CHECK(names[0] == 1 && names[1] == 2 && names[2] == 3, "names %u %u %u", names[0], names[1], names[2]);
    for (int i = 0; i < 3; i++) {
        tsr_call_BindTexture(&d, GL_TEXTURE_2D, names[i]);
        tsr_call_TexImage2D(&d, GL_TEXTURE_2D, 0, GL_RGBA, 4, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, px);
    }
    tsr_call_BindTexture(&d, GL_TEXTURE_2D, 0);
    tsr_state_diff(c, r, &out, NULL);
    CHECK(k.images == 0, "unbound textures were sent (%d images)", k.images);
    tsr_call_BindTexture(&d, GL_TEXTURE_2D, names[1]);
    tsr_state_diff(c, r, &out, NULL);
    CHECK(k.images == 1, "binding one texture sent %d images", k.images);
    tsr_call_TexSubImage2D(&d, GL_TEXTURE_2D, 0, 1, 1, 2, 2, GL_RGBA, GL_UNSIGNED_BYTE, px);
    tsr_state_diff(c, r, &out, NULL);
    CHECK(k.images == 1 && k.subimages == 1, "a sub-image sent %d images, %d sub-images", k.images, k.subimages);
    tsr_call_BindTexture(&d, GL_TEXTURE_2D, names[2]);
    tsr_call_BindTexture(&d, GL_TEXTURE_2D, names[1]);
    int binds = k.binds;
    tsr_state_diff(c, r, &out, NULL);
    CHECK(k.images == 1 && k.binds == binds, "rebinding the same texture sent %d images, %d binds", k.images,
          k.binds - binds);
    tsr_state_tracker_destroy(t);
}

/* Image units past the coordinate units: two contexts bind textures (and
 * one a LOD bias) on units 8 to 191; each diff into a real OSMesa context
 * leaves there the bindings the tracker answers on every unit, a change on
 * one unit costs one member and the calls of that unit, and a context
 * that never used those units unbinds what another left on the renderer. */
static void test_image_units(void)
{
    TRACKED(t, c, r, d);
    tsr_state_ctx *other = tsr_state_ctx_create(t, NULL);
    static tsr_dispatch od, counted;
    tsr_dispatch_fill_nop(&od);
    tsr_state_fill_dispatch(other, &od);
    counter k = {0};
    tsr_dispatch_fill_nop(&counted);
    tsr_set_TexImage2D(&counted, cnt_TexImage2D, &k);
    tsr_set_BindTexture(&counted, cnt_BindTexture, &k);
    static const GLuint used[] = {8, 40, 63, 64, 150, 191};
    enum { NUSED = sizeof used / sizeof used[0] };
    GLuint names[NUSED];
    tsr_call_GenTextures(&d, NUSED, names);
    uint8_t px[4] = {1, 2, 3, 4};
    for (int i = 0; i < NUSED; i++) {
        tsr_call_ActiveTexture(&d, GL_TEXTURE0 + used[i]);
        tsr_call_BindTexture(&d, i % 2 ? GL_TEXTURE_2D : GL_TEXTURE_3D, names[i]);
        if (i % 2)
            tsr_call_TexImage2D(&d, GL_TEXTURE_2D, 0, GL_RGBA, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, px);
    }
    tsr_call_TexEnvf(&d, GL_TEXTURE_FILTER_CONTROL, GL_TEXTURE_LOD_BIAS, 2.5f);
    CHECK(tsr_state_take_error(c) == GL_NO_ERROR, "binding on units 8 to 191 raised an error");
    tsr_call_ActiveTexture(&d, GL_TEXTURE0 + TSR_STATE_IMAGE_UNITS);
    CHECK(tsr_state_take_error(c) == GL_INVALID_ENUM, "glActiveTexture past the image units raised no GL_INVALID_ENUM");
    tsr_call_TexGeni(&d, GL_S, GL_TEXTURE_GEN_MODE, GL_OBJECT_LINEAR);
    CHECK(tsr_state_take_error(c) == GL_INVALID_OPERATION, "glTexGen past the coordinate units was taken");
    tsr_call_Enable(&d, GL_TEXTURE_2D);
    CHECK(tsr_state_take_error(c) == GL_NO_ERROR, "glEnable(GL_TEXTURE_2D) past the coordinate units raised an error");
    GLint got = 0;
    CHECK(tsr_state_get_integerv(c, GL_ACTIVE_TEXTURE, &got) && got == (GLint)(GL_TEXTURE0 + 191),
          "GL_ACTIVE_TEXTURE answers 0x%x", (unsigned)got);

    gl_env *a = gl_open();
    tsr_state_diff(c, r, &a->d, NULL);
    a->gl.Finish();
    static const GLenum bindings[] = {GL_TEXTURE_BINDING_2D, GL_TEXTURE_BINDING_3D};
    int differ = 0;
    GLfloat bias = 0;
    gl_use(a);
    for (GLuint u = 0; u < TSR_STATE_IMAGE_UNITS; u++) {
        tsr_call_ActiveTexture(&d, GL_TEXTURE0 + u);
        a->gl.ActiveTexture(GL_TEXTURE0 + u);
        for (int b = 0; b < 2; b++) {
            GLint want = -1, have = -2;
            tsr_state_get_integerv(c, bindings[b], &want);
            a->gl.GetIntegerv(bindings[b], &have);
            differ += want != have;
        }
        if (u == 191)
            a->gl.GetTexEnvfv(GL_TEXTURE_FILTER_CONTROL, GL_TEXTURE_LOD_BIAS, &bias);
    }
    CHECK(differ == 0, "%d bindings of the diffed OSMesa context differ from the tracker's", differ);
    CHECK(bias == 2.5f, "unit 191's LOD bias is %g on the diffed context", bias);
    CHECK(a->gl.GetError() == GL_NO_ERROR, "the diff raised a GL error");
    tsr_state_diff(c, r, &counted, NULL); /* the selections above */

    /* one unit rebound: one member, that unit's calls */
    tsr_call_ActiveTexture(&d, GL_TEXTURE0 + 150);
    tsr_call_BindTexture(&d, GL_TEXTURE_2D, names[1]); /* (150 has a 3D texture bound too) */
    tsr_call_ActiveTexture(&d, GL_TEXTURE0);
    tsr_state_diff_stats st;
    k = (counter){0};
    uint32_t n = tsr_state_diff(c, r, &counted, &st);
    CHECK(st.members_visited == 2 && k.binds == 1 && k.images == 0 && n == 3,
          "one rebinding on unit 150: %u members, %d binds, %d images, %u calls (want 2 members: the units' past 8 and "
          "unit 0's, which carries the selector; 1 bind; 3 calls: select 150, bind, select 0)",
          st.members_visited, k.binds, k.images, n);

    /* another context that never used units past 8 unbinds them there */
    k = (counter){0};
    tsr_state_diff(other, r, &counted, NULL);
    CHECK(k.binds == NUSED + 1, "the other context unbound %d bindings, want %d", k.binds, NUSED + 1);
    k = (counter){0};
    tsr_state_diff(c, r, &counted, NULL);
    CHECK(k.binds == NUSED + 1 && k.images == 0, "back to the first context: %d binds, %d images (want %d, 0)", k.binds,
          k.images, NUSED + 1);

    /* the servers' count narrows the units */
    tsr_state_tracker_set_image_units(t, 64);
    tsr_call_ActiveTexture(&d, GL_TEXTURE0 + 64);
    CHECK(tsr_state_take_error(c) == GL_INVALID_ENUM, "glActiveTexture past the servers' 64 units was taken");
    gl_close(a);
    tsr_state_tracker_destroy(t);
}

/* What a diff does to buffers: which buffer each BufferData filled. */
typedef struct buf_log {
    GLuint bound; /* GL_ARRAY_BUFFER on the renderer */
    GLuint filled[8];
    GLsizeiptr size[8];
    int n;
} buf_log;
static void log_BindBuffer(void *self, GLenum target, GLuint name)
{
    buf_log *l = self;
    if (target == GL_ARRAY_BUFFER)
        l->bound = name;
}
static void log_BufferData(void *self, GLenum target, GLsizeiptr size, const void *data, GLenum usage)
{
    buf_log *l = self;
    (void)data;
    (void)usage;
    if (target == GL_ARRAY_BUFFER && l->n < 8) {
        l->size[l->n] = size;
        l->filled[l->n++] = l->bound;
    }
}
static int log_filled(const buf_log *l, GLuint name, GLsizeiptr size)
{
    int times = 0;
    for (int i = 0; i < l->n; i++)
        times += l->filled[i] == name && l->size[i] == size;
    return times;
}

/* A diff precedes a stream whose draws carry their own arrays (buffer name
 * and offset), and is taken with the state at that stream's end: every
 * buffer with data reaches the renderer, also one that no binding and no
 * enabled array names at the diff (xscreensaver's romanboy binds its
 * buffers in turn around each draw; the first never reached a tilesort
 * server). Once each, and again after it changed. */
static void test_buffers_unbound_reach_renderer(void)
{
    TRACKED(t, c, r, d);
    static tsr_dispatch out;
    buf_log l = {0};
    tsr_dispatch_fill_nop(&out);
    tsr_set_BindBuffer(&out, log_BindBuffer, &l);
    tsr_set_BufferData(&out, log_BufferData, &l);
    static uint8_t data[300];
    GLuint names[3];
    tsr_call_GenBuffers(&d, 3, names);
    for (int i = 0; i < 3; i++) {
        GLenum target = i == 2 ? GL_ELEMENT_ARRAY_BUFFER : GL_ARRAY_BUFFER;
        tsr_call_BindBuffer(&d, target, names[i]);
        tsr_call_BufferData(&d, target, 100 * (i + 1), data, GL_STATIC_DRAW);
        tsr_call_BindBuffer(&d, target, 0);
    }
    /* romanboy's draw: the diff sees buffers 2 and 3 bound, no array on */
    tsr_call_BindBuffer(&d, GL_ARRAY_BUFFER, names[0]);
    tsr_call_BindBuffer(&d, GL_ARRAY_BUFFER, names[1]);
    tsr_call_BindBuffer(&d, GL_ELEMENT_ARRAY_BUFFER, names[2]);
    tsr_state_diff(c, r, &out, NULL);
    for (int i = 0; i < 3; i++)
        CHECK(log_filled(&l, names[i], 100 * (i + 1)) == 1, "buffer %u (%d bytes) filled %d times, not once", names[i],
              100 * (i + 1), log_filled(&l, names[i], 100 * (i + 1)));
    CHECK(l.n == 3 && l.bound == names[1], "%d BufferData, GL_ARRAY_BUFFER left at %u (want 3, %u)", l.n, l.bound,
          names[1]);
    tsr_state_diff(c, r, &out, NULL);
    CHECK(l.n == 3, "a second diff sent %d BufferData", l.n - 3);
    tsr_call_BindBuffer(&d, GL_ARRAY_BUFFER, names[0]);
    tsr_call_BufferData(&d, GL_ARRAY_BUFFER, 50, data, GL_STATIC_DRAW);
    tsr_call_BindBuffer(&d, GL_ARRAY_BUFFER, 0);
    tsr_state_diff(c, r, &out, NULL);
    CHECK(l.n == 4 && log_filled(&l, names[0], 50) == 1 && l.bound == 0,
          "refilling unbound buffer %u: %d BufferData, GL_ARRAY_BUFFER left at %u", names[0], l.n - 3, l.bound);
    tsr_state_tracker_destroy(t);
}

/* Inside glNewList(GL_COMPILE) state calls are recorded, not executed:
 * the tracker must not change (COMPILE_AND_EXECUTE does), while the calls
 * GL runs at once (pixel store, client state, deletes) still count. */
static void test_list_compile(void)
{
    tsr_state_tracker *t = tsr_state_tracker_create(NULL);
    tsr_state_ctx *c = tsr_state_ctx_create(t, NULL);
    static tsr_dispatch d;
    tsr_dispatch_fill_nop(&d);
    tsr_state_fill_dispatch(c, &d);
    GLuint base = tsr_call_GenLists(&d, 3);
    CHECK(base == 1 && tsr_state_is_list(c, 1) && tsr_state_is_list(c, 3) && !tsr_state_is_list(c, 4),
          "GenLists gave %u", base);
    GLboolean on = GL_TRUE;
    GLfloat color[4];
    GLint v = 0;
    tsr_call_NewList(&d, base, GL_COMPILE);
    tsr_call_Enable(&d, GL_FOG);
    tsr_call_Color4f(&d, 0.5f, 0.25f, 0.125f, 1);
    tsr_call_PixelStorei(&d, GL_UNPACK_ALIGNMENT, 2);
    tsr_state_get_integerv(c, GL_LIST_INDEX, &v);
    CHECK(v == (GLint)base, "GL_LIST_INDEX %d", v);
    tsr_call_EndList(&d);
    tsr_state_is_enabled(c, GL_FOG, &on);
    tsr_state_get_floatv(c, GL_CURRENT_COLOR, color);
    tsr_state_get_integerv(c, GL_UNPACK_ALIGNMENT, &v);
    CHECK(!on && color[0] == 1.0f && v == 2, "GL_COMPILE: fog %d color %g alignment %d", on, color[0], v);
    tsr_call_NewList(&d, base + 1, GL_COMPILE_AND_EXECUTE);
    tsr_call_Enable(&d, GL_FOG);
    tsr_call_EndList(&d);
    tsr_state_is_enabled(c, GL_FOG, &on);
    CHECK(on, "GL_COMPILE_AND_EXECUTE did not enable fog");
    tsr_call_DeleteLists(&d, base, 3);
    CHECK(!tsr_state_is_list(c, base + 1), "list survived DeleteLists");
    tsr_state_tracker_destroy(t);
}

/* --- the count table ------------------------------------------------------------- */
/* How many values tsr_state_get_doublev wrote for pname (-1: declined), told
 * by a sentinel no conversion from the tracker's values produces (a NaN
 * with a payload a float widened to double never has). A gap (a sentinel
 * before a written value) counts as a mismatch: -2. */
static int values_written(const tsr_state_ctx *c, GLenum pname)
{
    enum { N = 64 };
    static const uint64_t sentinel = 0x7ff4deadbeefcafeull;
    GLdouble out[N];
    for (int i = 0; i < N; i++)
        memcpy(&out[i], &sentinel, sizeof sentinel);
    if (!tsr_state_get_doublev(c, pname, out))
        return -1;
    int n = 0;
    while (n < N && memcmp(&out[n], &sentinel, sizeof sentinel) != 0)
        n++;
    for (int i = n; i < N; i++)
        if (memcmp(&out[i], &sentinel, sizeof sentinel) != 0)
            return -2;
    return n;
}

/* tsr_state_get_count is a table. It replaced asking a context's lookup
 * for the shape of each answer, so the oracle is that old way: a context's
 * own gets. A fresh context, and one that also knows what starts unknown
 * (window size, draw and read buffer, maximum point size), must answer
 * exactly the pnames with a count, and write exactly count values; where
 * the spec gives a pname's count (the wire's table), it must agree. */
static void test_get_count_table(void)
{
    tsr_state_tracker *t = tsr_state_tracker_create(NULL);
    tsr_state_ctx *fresh = tsr_state_ctx_create(t, NULL), *known = tsr_state_ctx_create(t, NULL);
    static tsr_dispatch d;
    tsr_dispatch_fill_nop(&d);
    tsr_state_fill_dispatch(known, &d);
    tsr_call_WindowCreateTSR(&d, 0, 64, 64);
    tsr_call_DrawBuffer(&d, GL_BACK);
    tsr_call_ReadBuffer(&d, GL_BACK);
    tsr_call_PointParameterf(&d, GL_POINT_SIZE_MAX, 64.0f);
    int answered = 0, declined_fresh = 0, bad = 0;
    for (GLenum p = 0; p <= 0xFFFF; p++) {
        int n = tsr_state_get_count(p), k = values_written(known, p), f = values_written(fresh, p);
        if (n > 0)
            answered++;
        if (n > 0 && f == -1)
            declined_fresh++;
        int ok = n > 0 ? k == n && (f == n || f == -1) : n == 0 && k == -1 && f == -1;
        int spec = tsr_wire_pname_count(p);
        if (n > 0 && spec > 0 && spec != n)
            ok = 0;
        if (!ok && bad++ < 12)
            fprintf(stderr, "  pname 0x%04x: table %d, the context wrote %d (a fresh one %d), spec %d\n", p, n, k, f,
                    spec);
    }
    CHECK(bad == 0, "%d pnames where the count table and the tracker's gets differ", bad);
    CHECK(answered > 200, "the table answers only %d pnames", answered);
    CHECK(declined_fresh == 5,
          "a fresh context declined %d answered pnames (viewport, scissor box, draw and read "
          "buffer, maximum point size: 5)",
          declined_fresh);
    tsr_state_tracker_destroy(t);
}

/* --- matrices: the renderer's bits and history -------------------------------- */
/* Random matrix operations (all three stacks, single-axis and zero-angle
 * rotations, Frustum/Ortho from doubles, loads, products, pushes) go to the
 * tracker and to OSMesa A; a diff brings a fresh OSMesa B up to date. Every
 * matrix must be bit-identical in all three, and a lit, specular sphere
 * drawn in A and in B must give the same pixels: Mesa classifies a matrix
 * from its history (glRotate, glTranslate, ...) or, after glLoadMatrix,
 * from its values, and lighting rounds differently by class, so the diff
 * replays the operations (tessera/dev/state.h, tsr_state_recipe). */
static void matrix_ops(uint64_t seed, const tsr_dispatch *d, int n)
{
    uint64_t r = seed * 7919 + 13;
    tsr_call_MatrixMode(d, GL_PROJECTION);
    tsr_call_LoadIdentity(d);
    tsr_call_Frustum(d, -0.4 * (4.0 / 3.0), 0.4 * (4.0 / 3.0), -0.4, 0.4, 1.0, 20.0);
    tsr_call_MatrixMode(d, GL_MODELVIEW);
    tsr_call_LoadIdentity(d);
    tsr_call_Translatef(d, 0, 0, -5.0f);
    int depth = 1;
    for (int i = 0; i < n; i++) {
        float a = (float)(rnd(&r) % 720) * 0.5f - 180.0f, x = (float)(rnd(&r) % 200) / 100.0f - 1.0f;
        switch (rnd(&r) % 15) {
        case 0: tsr_call_Rotatef(d, a, 1, 0, 0); break;
        case 1: tsr_call_Rotatef(d, a, 0, -1, 0); break;
        case 2: tsr_call_Rotatef(d, a, 0, 0, 1); break;
        case 3: tsr_call_Rotatef(d, a, x, 1, 0.3f); break;
        case 4: tsr_call_Rotatef(d, 0, 0, 1, 0); break;
        case 5: tsr_call_Translatef(d, x, 0.1f, -0.2f); break;
        case 6: tsr_call_Scalef(d, 0.9f + 0.1f * x, 0.9f + 0.1f * x, 0.9f + 0.1f * x); break;
        case 7: tsr_call_Scalef(d, 1.0f, 0.8f, 1.2f); break;
        case 8:
            if (depth < 8) {
                tsr_call_PushMatrix(d);
                depth++;
            }
            break;
        case 9:
            if (depth > 1) {
                tsr_call_PopMatrix(d);
                depth--;
            }
            break;
        case 10: {
            GLfloat m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.1f * x, 0, 0, 1};
            tsr_call_MultMatrixf(d, m);
            break;
        }
        case 11: {
            GLfloat m[16] = {0.8f, 0, 0.1f, 0, 0, 1, 0, 0, -0.1f, 0, 0.8f, 0, 0, 0, -5.0f + x, 1};
            tsr_call_LoadMatrixf(d, m);
            break;
        }
        case 13: {
            /* the identity by value, with negative zeros (gears' own glMultMatrixf) */
            GLfloat m[16] = {1, 0, -0.0f, 0, -0.0f, 1, -0.0f, 0, 0, 0, 1, 0, 0, 0, 0, 1};
            tsr_call_MultMatrixf(d, m);
            break;
        }
        case 12:
            tsr_call_MatrixMode(d, GL_TEXTURE);
            tsr_call_Ortho(d, -1.3 + x, 1.7, -0.9, 1.1 + x, -1.5, 7.0);
            tsr_call_MatrixMode(d, GL_MODELVIEW);
            break;
        default:
            tsr_call_LoadIdentity(d);
            tsr_call_Translatef(d, 0, 0, -5.0f);
            break;
        }
    }
}

static int matrices_differ(gl_env *x, gl_env *y, int seed, const char *what)
{
    static const GLenum which[3] = {GL_MODELVIEW_MATRIX, GL_PROJECTION_MATRIX, GL_TEXTURE_MATRIX};
    for (int k = 0; k < 3; k++) {
        GLfloat mx[16], my[16];
        gl_use(x);
        x->gl.GetFloatv(which[k], mx);
        gl_use(y);
        y->gl.GetFloatv(which[k], my);
        if (memcmp(mx, my, sizeof mx)) {
            CHECK(0, "seed %d: %s: matrix %d differs in its bits", seed, what, k);
            return 1;
        }
    }
    return 0;
}

static void lit_sphere(gl_env *e)
{
    gl_use(e);
    const tsr_dispatch *d = &e->d;
    static const GLfloat light[4] = {1, 2, 3, 0}, spec[4] = {0.9f, 0.9f, 0.9f, 1};
    tsr_call_Viewport(d, 0, 0, 64, 64);
    tsr_call_Clear(d, GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    tsr_call_Enable(d, GL_DEPTH_TEST);
    tsr_call_Enable(d, GL_LIGHTING);
    tsr_call_Enable(d, GL_LIGHT0);
    tsr_call_Enable(d, GL_NORMALIZE);
    tsr_call_Lightfv(d, GL_LIGHT0, GL_SPECULAR, spec);
    tsr_call_Materialfv(d, GL_FRONT_AND_BACK, GL_SPECULAR, spec);
    tsr_call_Materialf(d, GL_FRONT_AND_BACK, GL_SHININESS, 40);
    tsr_call_PushMatrix(d);
    tsr_call_LoadIdentity(d);
    tsr_call_Lightfv(d, GL_LIGHT0, GL_POSITION, light);
    tsr_call_PopMatrix(d);
    for (int i = 0; i < 16; i++) {
        tsr_call_Begin(d, GL_QUAD_STRIP);
        for (int j = 0; j <= 24; j++)
            for (int k = 1; k >= 0; k--) {
                float th = 3.14159265f * (float)(i + k) / 16.0f, ph = 6.2831853f * (float)j / 24.0f;
                float v[3] = {sinf(th) * cosf(ph), cosf(th), sinf(th) * sinf(ph)};
                tsr_call_Normal3fv(d, v);
                tsr_call_Vertex3fv(d, v);
            }
        tsr_call_End(d);
    }
    e->gl.Finish();
}

static void test_matrices_bit_identical(void)
{
    long drawn = 0;
    for (int seed = 0; seed < seeds_arg; seed++) {
        TRACKED(t, c, s, tt);
        int n = 5 + seed % 40;
        matrix_ops((uint64_t)seed, &tt, n);
        gl_env *a = gl_open();
        matrix_ops((uint64_t)seed, &a->d, n);
        gl_env *b = gl_open();
        tsr_state_diff(c, s, &b->d, NULL);
        int bad = matrices_differ(a, b, seed, "renderer given the diff");
        GLfloat m[16];
        gl_use(a);
        a->gl.GetFloatv(GL_MODELVIEW_MATRIX, m);
        if (!bad && memcmp(m, tsr_state_modelview(c), sizeof m))
            CHECK(0, "seed %d: tracker's modelview differs from OSMesa's in its bits", seed);
        if (!bad) {
            lit_sphere(a);
            lit_sphere(b);
            if (memcmp(a->buf, b->buf, 64 * 64 * 4))
                CHECK(0, "seed %d: a lit sphere differs between OSMesa given the calls and given the diff", seed);
            drawn++;
        }
        gl_close(a);
        gl_close(b);
        tsr_state_tracker_destroy(t);
    }
    printf("%d seeds: matrices bit-identical, %ld lit spheres pixel-identical\n", seeds_arg, drawn);
}

/* glxgears' view: glLoadIdentity, glMultMatrixf of the identity written
 * with negative zeros, glTranslated. Mesa returns from a glMultMatrix of
 * the identity by value without touching the matrix or its class, so the
 * renderer must be given the translation alone, not a loaded product (a
 * loaded matrix is lit with other rounding: 1 pixel of a 320x240 gears
 * frame differed on a wall). The diff must bring B to A's bits and A's
 * lit pixels. */
static void test_multmatrix_of_the_identity_keeps_the_matrix_class(void)
{
    static const GLfloat signed_zero_identity[16] = {1, 0, -0.0f, 0, -0.0f, 1, -0.0f, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    TRACKED(t, c, s, tt);
    gl_env *a = gl_open();
    const tsr_dispatch *both[2] = {&tt, &a->d};
    for (int k = 0; k < 2; k++) {
        if (k == 1)
            gl_use(a);
        tsr_call_MatrixMode(both[k], GL_MODELVIEW);
        tsr_call_LoadIdentity(both[k]);
        tsr_call_MultMatrixf(both[k], signed_zero_identity);
        tsr_call_Translated(both[k], -0.0, -0.0, -5.0);
        tsr_call_Rotatef(both[k], 20, 1, 0, 0);
    }
    const tsr_state_recipe *r = &tsr_state_stacks_of(c)->modelview_recipe[0];
    CHECK(r->base_is_identity && r->count == 2,
          "the recipe is the translation and the rotation on the identity "
          "(base %s, %u operations)",
          r->base_is_identity ? "identity" : "loaded", r->count);
    gl_env *b = gl_open();
    tsr_state_diff(c, s, &b->d, NULL);
    if (!matrices_differ(a, b, 0, "after an identity glMultMatrixf")) {
        lit_sphere(a);
        lit_sphere(b);
        CHECK(!memcmp(a->buf, b->buf, 64 * 64 * 4), "a lit sphere differs between the calls and the diff");
    }
    gl_close(a);
    gl_close(b);
    tsr_state_tracker_destroy(t);
}

/* antinspect's ant: a glMultMatrixf of its general shadow projection, a
 * glLoadIdentity (the class stays general), a glScalef(1, 1, 1), then
 * some twenty rotations and translations and two scales. Mesa classifies
 * the product by that history (general: inverted by its general routine),
 * not from its values as it does a loaded matrix (3D); no operation gives
 * a loaded matrix a general class back, so the renderer must be given the
 * history itself: it then inverts and lights with the very same rounding.
 * (The recipe held 16 operations and sent the 17th product loaded: 1 pixel
 * of antinspect's frames 4 and 9 differed on a wall.) glClipPlane shows the
 * inverse modelview's bits; the lit sphere, the pixels. Checked for
 * antinspect's length, glsnake's (124) and for the longest history a
 * recipe keeps. */
static void long_history(int n)
{
    static const GLfloat ops[][5] = {
        {'T', 0.05f, 0, -0.2f}, {'S', 1, 1, 1},      {'R', 7.62f, 1, 0, 0}, {'R', 30, 1, 0, 0},
        {'R', 180, 0, 1, 0},    {'R', -30, 0, 1, 0}, {'R', 1.2f, 0, 1, 0},  {'T', 0.024f, 0, 0},
        {'T', 0, 0.012f, 0},    {'R', 90, 0, 1, 0},  {'R', 10, 0, 1, 0},    {'R', 40, 0, 0, 1},
        {'T', 0, -0.008f, 0},   {'R', 180, 0, 1, 0}, {'R', 90, 0, 0, 1},    {'R', 121.2f, 0, 1, 0},
    };
    static const GLfloat shadow[16] = {9.6f, 0, 0, 0, 0, -9.5e-6f, 0, -1, 0, 0, 9.6f, 0, 0, 9.6e-5f, 0, 9.6f};
    const int nops = (int)(sizeof ops / sizeof ops[0]);
    tsr_state_tracker *t = tsr_state_tracker_create(NULL);
    tsr_state_ctx *c = tsr_state_ctx_create(t, NULL);
    tsr_state_shadow *s = tsr_state_shadow_create(t, NULL);
    static tsr_dispatch tt;
    tsr_dispatch_fill_nop(&tt);
    tsr_state_fill_dispatch(c, &tt);
    gl_env *a = gl_open();
    const tsr_dispatch *both[2] = {&tt, &a->d};
    for (int k = 0; k < 2; k++) {
        if (k == 1)
            gl_use(a);
        tsr_call_MatrixMode(both[k], GL_MODELVIEW);
        tsr_call_MultMatrixf(both[k], shadow);
        tsr_call_LoadIdentity(both[k]);
        for (int i = 0; i < n - 2; i++) {
            const GLfloat *o = ops[i < 2 ? i : 2 + (i - 2) % (nops - 2)];
            if (o[0] == 'T')
                tsr_call_Translatef(both[k], o[1], o[2], o[3]);
            else if (o[0] == 'S')
                tsr_call_Scalef(both[k], o[1], o[2], o[3]);
            else
                tsr_call_Rotatef(both[k], o[1], o[2], o[3], o[4]);
        }
        tsr_call_Scalef(both[k], 1, 1.3f, 1);
        tsr_call_Scalef(both[k], 0.5f, 0.5f, 0.5f);
    }
    gl_env *b = gl_open();
    tsr_state_diff(c, s, &b->d, NULL);
    if (!matrices_differ(a, b, n, "operations, then the diff")) {
        static const GLdouble plane[4] = {0.3, 0.7, -0.2, 0.1};
        GLdouble pa[4], pb[4];
        gl_use(a);
        tsr_call_ClipPlane(&a->d, GL_CLIP_PLANE0, plane);
        a->gl.GetClipPlane(GL_CLIP_PLANE0, pa);
        gl_use(b);
        tsr_call_ClipPlane(&b->d, GL_CLIP_PLANE0, plane);
        b->gl.GetClipPlane(GL_CLIP_PLANE0, pb);
        CHECK(!memcmp(pa, pb, sizeof pa),
              "%d operations: the inverse modelview differs (clip plane %.9g %.9g %.9g %.9g, given the diff "
              "%.9g %.9g %.9g %.9g)",
              n, pa[0], pa[1], pa[2], pa[3], pb[0], pb[1], pb[2], pb[3]);
        lit_sphere(a);
        lit_sphere(b);
        CHECK(!memcmp(a->buf, b->buf, 64 * 64 * 4),
              "%d operations: a lit sphere differs between the calls and the diff", n);
    }
    gl_close(a);
    gl_close(b);
    tsr_state_tracker_destroy(t);
}

static void test_long_matrix_history_keeps_the_matrix_class(void)
{
    long_history(22);
    long_history(124); /* glsnake's longest (64 operations sent it loaded: 1 pixel of a wall differed) */
    long_history(TSR_STATE_RECIPE_OPS);
    if (!harness_failures)
        printf("histories of 22, 124 and %d operations: inverse modelview bits and lit pixels equal\n",
               TSR_STATE_RECIPE_OPS);
}

/* --- shaders and programs ------------------------------------------------------------ */
static const char *const glsl_vs[] = {
    "uniform float u_f;\nuniform vec3 u_v3;\nattribute float a_s;\nvarying vec4 col;\n"
    "void main() {\n  gl_Position = ftransform() + vec4(u_f * 0.01, u_v3.x * 0.01, 0.0, 0.0);\n"
    "  col = vec4(u_v3, a_s);\n  gl_FrontColor = gl_Color;\n}\n",
    "uniform mat3 u_m3;\nuniform vec2 u_v2[3];\nvarying vec4 col;\n"
    "void main() {\n  vec4 p = gl_Vertex;\n  p.xyz = u_m3 * p.xyz;\n  p.xy += (u_v2[0] + u_v2[1] + u_v2[2]) * 0.1;\n"
    "  gl_Position = gl_ModelViewProjectionMatrix * p;\n  col = gl_Color;\n  gl_FrontColor = gl_Color;\n}\n",
};
static const char *const glsl_fs[] = {
    "uniform vec4 u_c;\nuniform int u_i;\nvarying vec4 col;\n"
    "void main() { gl_FragColor = col * u_c + float(u_i) * 0.01; }\n",
    "uniform mat2 u_m2;\nuniform ivec2 u_i2;\nuniform float u_a[4];\nvarying vec4 col;\n"
    "void main() {\n  gl_FragColor = vec4(u_m2 * col.xy, col.z + float(u_i2.x - u_i2.y) * 0.01 + u_a[0] + u_a[1] + "
    "u_a[2] + u_a[3], 1.0);\n}\n",
    "uniform vec4 u_c;\nuniform mat4 u_m4;\nvoid main() { gl_FragColor = u_m4 * gl_Color + u_c * 0.5; }\n",
};
/* Uniforms of the sources: name, kind (f/i/m), components or matrix side, array length. */
typedef struct glsl_uni {
    const char *name;
    char kind;
    int n, len;
} glsl_uni;
static const glsl_uni glsl_unis[] = {
    {"u_f", 'f', 1, 1}, {"u_v3", 'f', 3, 1}, {"u_m3", 'm', 3, 1}, {"u_v2", 'f', 2, 3}, {"u_c", 'f', 4, 1},
    {"u_i", 'i', 1, 1}, {"u_m2", 'm', 2, 1}, {"u_i2", 'i', 2, 1}, {"u_a", 'f', 1, 4},  {"u_m4", 'm', 4, 1},
};
#define GLSL_UNIS ((int)(sizeof glsl_unis / sizeof glsl_unis[0]))
#define GLSL_NAMES 40

/* The test's own record of what it did (to make valid links and pick
 * uniforms); the tracker is never asked for it. */
typedef struct glsl_model {
    int src[GLSL_NAMES];      /* shader: 0..1 vertex source, 10..12 fragment; -1 no object */
    int compiled[GLSL_NAMES]; /* source at the last compile, -1 never */
    int deleted[GLSL_NAMES];  /* shader deleted while attached */
    int program[GLSL_NAMES];  /* a program object lives under this name */
    int prog_deleted[GLSL_NAMES];
    unsigned char att[GLSL_NAMES][GLSL_NAMES];
    int usable[GLSL_NAMES]; /* last link had a valid combination */
    GLuint current;
} glsl_model;

static int attached_count(const glsl_model *m, int s)
{
    int k = 0;
    for (int p = 0; p < GLSL_NAMES; p++)
        k += m->att[p][s];
    return k;
}

static void model_free_shader(glsl_model *m, int s)
{
    m->src[s] = -1;
    m->deleted[s] = 0;
}

static void model_detach(glsl_model *m, int p, int s)
{
    m->att[p][s] = 0;
    if (m->deleted[s] && !attached_count(m, s))
        model_free_shader(m, s);
}

static void model_free_program(glsl_model *m, int p)
{
    m->program[p] = 0;
    m->prog_deleted[p] = 0;
    m->usable[p] = 0;
    for (int s = 0; s < GLSL_NAMES; s++)
        if (m->att[p][s])
            model_detach(m, p, s);
}

/* Whether program p's attached shaders make a program that links: at most
 * one vertex and one fragment shader, all compiled, at least one, and a
 * fragment shader reading `col` only with a vertex shader. */
static int links(const glsl_model *m, int p)
{
    int vs = -1, fs = -1, n = 0;
    for (int s = 0; s < GLSL_NAMES; s++) {
        if (!m->att[p][s])
            continue;
        n++;
        if (m->compiled[s] < 0 || m->compiled[s] != m->src[s])
            return 0;
        if (m->src[s] < 10) {
            if (vs >= 0)
                return 0;
            vs = m->src[s];
        } else {
            if (fs >= 0)
                return 0;
            fs = m->src[s] - 10;
        }
    }
    return n > 0 && !(vs < 0 && fs >= 0 && fs < 2);
}

static GLfloat glsl_val(uint64_t *r) { return (GLfloat)(ri(r, 17) - 8) / 8.0f; }

/* A random live shader (program), or a random name when there is none. */
static int pick(const glsl_model *m, uint64_t *r, int program)
{
    int live[GLSL_NAMES], n = 0;
    for (int i = 1; i < GLSL_NAMES; i++)
        if (program ? m->program[i] != 0 : m->src[i] >= 0)
            live[n++] = i;
    return n ? live[ri(r, n)] : 1 + ri(r, GLSL_NAMES - 1);
}

/* Every call goes to the tracker (tt) and to context B (bd, through its
 * name map), B under the tracker's names (CreateShaderTSR/CreateProgramTSR). */
static void glsl_sequence(uint64_t seed, int calls, const tsr_dispatch *tt, const tsr_dispatch *bd, glsl_model *m)
{
    uint64_t st = seed * 7919u + 17u, *r = &st;
    memset(m, 0, sizeof *m);
    for (int i = 0; i < GLSL_NAMES; i++)
        m->src[i] = m->compiled[i] = -1;
    tsr_call_Viewport(tt, 0, 0, 64, 64);
    tsr_call_Viewport(bd, 0, 0, 64, 64);
    for (int k = 0; k < calls; k++) {
        int n = pick(m, r, 0), p = pick(m, r, 1);
        int shader = m->src[n] >= 0, prog = m->program[p] && !m->prog_deleted[p];
        int op = ri(r, 19);
        if (op >= 16) { /* build a program that links, as applications do, and maybe use it */
            GLuint q = tsr_call_CreateProgram(tt);
            if (!q || q >= GLSL_NAMES)
                continue;
            tsr_call_CreateProgramTSR(bd, q);
            m->program[q] = 1;
            int vs = ri(r, 3) - 1, fs = vs < 0 ? 2 : ri(r, 4) - 1; /* -1: none */
            for (int stage = 0; stage < 2; stage++) {
                int idx = stage ? fs : vs;
                if (idx < 0)
                    continue;
                GLenum type = stage ? GL_FRAGMENT_SHADER : GL_VERTEX_SHADER;
                GLuint sh = tsr_call_CreateShader(tt, type);
                if (!sh || sh >= GLSL_NAMES)
                    continue;
                tsr_call_CreateShaderTSR(bd, sh, type);
                const char *text = stage ? glsl_fs[idx] : glsl_vs[idx];
                tsr_call_ShaderSource(tt, sh, 1, &text, NULL);
                tsr_call_ShaderSource(bd, sh, 1, &text, NULL);
                tsr_call_CompileShader(tt, sh);
                tsr_call_CompileShader(bd, sh);
                m->src[sh] = m->compiled[sh] = stage ? 10 + idx : idx;
                tsr_call_AttachShader(tt, q, sh);
                tsr_call_AttachShader(bd, q, sh);
                m->att[q][sh] = 1;
            }
            if (ri(r, 2)) {
                tsr_call_BindAttribLocation(tt, q, 3, "a_s");
                tsr_call_BindAttribLocation(bd, q, 3, "a_s");
            }
            if (links(m, (int)q)) {
                tsr_call_LinkProgram(tt, q);
                tsr_call_LinkProgram(bd, q);
                m->usable[q] = 1;
                if (ri(r, 2)) {
                    tsr_call_UseProgram(tt, q);
                    tsr_call_UseProgram(bd, q);
                    GLuint old = m->current;
                    m->current = q;
                    if (old != q && old && m->prog_deleted[old])
                        model_free_program(m, (int)old);
                }
            }
            continue;
        }
        switch (op) {
        case 0:
        case 1: { /* a new shader with a source, usually compiled */
            int fs = ri(r, 2), idx = fs ? ri(r, 3) : ri(r, 2);
            GLenum type = fs ? GL_FRAGMENT_SHADER : GL_VERTEX_SHADER;
            GLuint s = tsr_call_CreateShader(tt, type);
            if (!s || s >= GLSL_NAMES)
                break;
            tsr_call_CreateShaderTSR(bd, s, type);
            const char *text = fs ? glsl_fs[idx] : glsl_vs[idx];
            tsr_call_ShaderSource(tt, s, 1, &text, NULL);
            tsr_call_ShaderSource(bd, s, 1, &text, NULL);
            m->src[s] = fs ? 10 + idx : idx;
            m->compiled[s] = -1;
            if (ri(r, 5)) {
                tsr_call_CompileShader(tt, s);
                tsr_call_CompileShader(bd, s);
                m->compiled[s] = m->src[s];
            }
            break;
        }
        case 2: /* another source of the same type (two strings), compiled or not */
            if (shader) {
                int fs = m->src[n] >= 10, idx = fs ? ri(r, 3) : ri(r, 2);
                const char *text = fs ? glsl_fs[idx] : glsl_vs[idx];
                size_t half = strlen(text) / 2;
                const GLchar *parts[2] = {text, text + half};
                const GLint lens[2] = {(GLint)half, -1};
                tsr_call_ShaderSource(tt, (GLuint)n, 2, parts, lens);
                tsr_call_ShaderSource(bd, (GLuint)n, 2, parts, lens);
                m->src[n] = fs ? 10 + idx : idx;
                if (ri(r, 2)) {
                    tsr_call_CompileShader(tt, (GLuint)n);
                    tsr_call_CompileShader(bd, (GLuint)n);
                    m->compiled[n] = m->src[n];
                }
            }
            break;
        case 3: { /* a new program */
            GLuint q = tsr_call_CreateProgram(tt);
            if (!q || q >= GLSL_NAMES)
                break;
            tsr_call_CreateProgramTSR(bd, q);
            m->program[q] = 1;
            break;
        }
        case 4:
        case 5: /* attach */
            if (shader && m->program[p] && !m->att[p][n]) {
                tsr_call_AttachShader(tt, (GLuint)p, (GLuint)n);
                tsr_call_AttachShader(bd, (GLuint)p, (GLuint)n);
                m->att[p][n] = 1;
            }
            break;
        case 6: /* detach */
            if (m->program[p] && m->att[p][n]) {
                tsr_call_DetachShader(tt, (GLuint)p, (GLuint)n);
                tsr_call_DetachShader(bd, (GLuint)p, (GLuint)n);
                model_detach(m, p, n);
            }
            break;
        case 7: /* attribute binding */
            if (prog) {
                GLuint idx = (GLuint)(1 + ri(r, 5));
                tsr_call_BindAttribLocation(tt, (GLuint)p, idx, "a_s");
                tsr_call_BindAttribLocation(bd, (GLuint)p, idx, "a_s");
            }
            break;
        case 8:
        case 9: /* link (only valid combinations become usable) */
            /* A failed relink of the program in use leaves GL drawing with the
             * old executable, which the tracker cannot rebuild (README): not done. */
            if (m->program[p] && (links(m, p) || (ri(r, 4) == 0 && m->current != (GLuint)p))) {
                tsr_call_LinkProgram(tt, (GLuint)p);
                tsr_call_LinkProgram(bd, (GLuint)p);
                m->usable[p] = links(m, p);
                if (ri(r, 2)) /* then the shaders often go, as in many programs */
                    for (int s = 0; s < GLSL_NAMES; s++)
                        if (m->att[p][s] && !m->deleted[s]) {
                            tsr_call_DeleteShader(tt, (GLuint)s);
                            tsr_call_DeleteShader(bd, (GLuint)s);
                            m->deleted[s] = 1;
                        }
            }
            break;
        case 10: /* use a usable program, or none */
        {
            GLuint q = ri(r, 4) == 0 ? 0 : (GLuint)p;
            if (q && !(prog && m->usable[p]))
                break;
            tsr_call_UseProgram(tt, q);
            tsr_call_UseProgram(bd, q);
            GLuint old = m->current;
            m->current = q;
            if (old != q && old && m->prog_deleted[old])
                model_free_program(m, (int)old);
        } break;
        case 11:
        case 12:
        case 13: { /* a uniform of the current program */
            if (!m->current || !m->usable[m->current])
                break;
            const glsl_uni *u = &glsl_unis[ri(r, GLSL_UNIS)];
            char name[32];
            int first = u->len > 1 ? ri(r, u->len) : 0;
            if (first)
                snprintf(name, sizeof name, "%s[%d]", u->name, first);
            else
                snprintf(name, sizeof name, "%s", u->name);
            /* the location comes from a renderer (B), as tilesort asks its first server */
            GLint loc = tsr_call_GetUniformLocation(bd, m->current, name);
            if (loc < 0)
                break;
            GLsizei count = u->len > 1 ? 1 + ri(r, u->len - first) : 1;
            GLfloat f[64];
            GLint iv[64];
            for (int i = 0; i < 64; i++) {
                f[i] = glsl_val(r);
                iv[i] = ri(r, 19) - 9;
            }
            const tsr_dispatch *both[2] = {tt, bd};
            int vec = count > 1 || ri(r, 2);
            for (int w = 0; w < 2; w++) {
                const tsr_dispatch *d = both[w];
                if (u->kind == 'm') {
                    GLboolean tr = (GLboolean)(u->n == 4 && (k & 1));
                    if (u->n == 2)
                        tsr_call_UniformMatrix2fv(d, loc, count, tr, f);
                    else if (u->n == 3)
                        tsr_call_UniformMatrix3fv(d, loc, count, tr, f);
                    else
                        tsr_call_UniformMatrix4fv(d, loc, count, tr, f);
                } else if (u->kind == 'i') {
                    if (u->n == 1) {
                        if (vec)
                            tsr_call_Uniform1iv(d, loc, count, iv);
                        else
                            tsr_call_Uniform1i(d, loc, iv[0]);
                    } else {
                        if (vec)
                            tsr_call_Uniform2iv(d, loc, count, iv);
                        else
                            tsr_call_Uniform2i(d, loc, iv[0], iv[1]);
                    }
                } else if (u->n == 1) {
                    if (vec)
                        tsr_call_Uniform1fv(d, loc, count, f);
                    else
                        tsr_call_Uniform1f(d, loc, f[0]);
                } else if (u->n == 2) {
                    if (vec)
                        tsr_call_Uniform2fv(d, loc, count, f);
                    else
                        tsr_call_Uniform2f(d, loc, f[0], f[1]);
                } else if (u->n == 3) {
                    if (vec)
                        tsr_call_Uniform3fv(d, loc, count, f);
                    else
                        tsr_call_Uniform3f(d, loc, f[0], f[1], f[2]);
                } else {
                    if (vec)
                        tsr_call_Uniform4fv(d, loc, count, f);
                    else
                        tsr_call_Uniform4f(d, loc, f[0], f[1], f[2], f[3]);
                }
            }
            break;
        }
        case 14: /* delete a shader (waits while attached) */
            if (shader && !m->deleted[n]) {
                tsr_call_DeleteShader(tt, (GLuint)n);
                tsr_call_DeleteShader(bd, (GLuint)n);
                if (attached_count(m, n))
                    m->deleted[n] = 1;
                else
                    model_free_shader(m, n);
            }
            break;
        case 15: /* delete a program (waits while current); or validate one */
            if (prog && ri(r, 3)) {
                tsr_call_DeleteProgram(tt, (GLuint)p);
                tsr_call_DeleteProgram(bd, (GLuint)p);
                if (m->current == (GLuint)p)
                    m->prog_deleted[p] = 1;
                else
                    model_free_program(m, p);
            } else if (prog) {
                tsr_call_ValidateProgram(tt, (GLuint)p);
                tsr_call_ValidateProgram(bd, (GLuint)p);
            }
            break;
        }
    }
}

static int glsl_exists(const tsr_state_ctx *c, GLuint n, int program)
{
    GLint v;
    return program ? tsr_state_get_programiv(c, n, GL_ATTACHED_SHADERS, &v)
                   : tsr_state_get_shaderiv(c, n, GL_SHADER_TYPE, &v);
}

typedef void (*get_uniformfv_fn)(GLuint, GLint, GLfloat *);
typedef void (*get_uniformiv_fn)(GLuint, GLint, GLint *);

/* Draws a triangle over the window with the current state and reads it. */
static void glsl_draw(gl_env *e, unsigned char *px)
{
    gl_use(e);
    e->gl.ClearColor(0.1f, 0.2f, 0.3f, 1.0f);
    e->gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    e->gl.Begin(GL_TRIANGLES);
    e->gl.Color4f(0.9f, 0.5f, 0.25f, 1.0f);
    e->gl.Vertex3f(-0.9f, -0.9f, 0.0f);
    e->gl.Color4f(0.2f, 0.7f, 0.4f, 1.0f);
    e->gl.Vertex3f(0.9f, -0.8f, 0.1f);
    e->gl.Color4f(0.3f, 0.3f, 1.0f, 1.0f);
    e->gl.Vertex3f(0.0f, 0.9f, -0.1f);
    e->gl.End();
    e->gl.Finish();
    e->gl.ReadPixels(0, 0, 64, 64, GL_RGBA, GL_UNSIGNED_BYTE, px);
}

static void test_glsl_diff_matches_osmesa(void)
{
    get_uniformfv_fn get_f = (get_uniformfv_fn)M.GetProcAddress("glGetUniformfv");
    get_uniformiv_fn get_i = (get_uniformiv_fn)M.GetProcAddress("glGetUniformiv");
    long compared = 0, commands = 0, drawn = 0, with_program = 0, locations = 0;
    int first_seed = getenv("STATE_SEED") ? atoi(getenv("STATE_SEED")) : 0;
    for (int seed = first_seed; seed < seeds_arg; seed++) {
        TRACKED(t, c, s, tt);
        gl_env *b = gl_open();
        tsr_error err = {0};
        tsr_glsl_names *bn = tsr_glsl_names_create(&b->d, &err);
        /* B's driver hands out other names than A's: it made (and deleted) objects first */
        for (int i = 0; i < 1 + seed % 5; i++)
            b->gl.DeleteShader(b->gl.CreateShader(GL_VERTEX_SHADER));
        GLuint keep = b->gl.CreateProgram();
        static glsl_model m;
        int calls = 30 + seed % 150;
        glsl_sequence((uint64_t)seed, calls, &tt, &b->d, &m);
        b->gl.Finish();

        gl_env *a = gl_open();
        tsr_glsl_names *an = tsr_glsl_names_create(&a->d, &err);
        CHECK(an && bn, "name maps: %s", err.message);
        uint32_t n = 0, again = 0;
        if (seed & 1) { /* through the real wire */
            wire *w = wire_open(&a->d);
            n = tsr_state_diff(c, s, &w->table, NULL);
            n += tsr_state_send_glsl_all(c, s, &w->table);
            CHECK(tsr_packer_flush(w->p) == 0, "seed %d: %s", seed, tsr_packer_error(w->p)->message);
            wire_close(w);
        } else {
            n = tsr_state_diff(c, s, &a->d, NULL);
            n += tsr_state_send_glsl_all(c, s, &a->d);
        }
        commands += n;
        /* unchanged: nothing more to send */
        again = tsr_state_diff(c, s, &a->d, NULL) + tsr_state_send_glsl_all(c, s, &a->d);
        for (GLuint q = 1; q < GLSL_NAMES; q++)
            again += tsr_state_send_shader(c, s, q, &a->d) + tsr_state_send_program(c, s, q, &a->d);
        CHECK(again == 0, "seed %d: sending unchanged objects again emitted %u calls", seed, again);
        if (again && getenv("STATE_TRACE")) {
            static tsr_dispatch traced;
            tsr_tracer tr = {.out = stderr, .child = &a->d};
            tsr_trace_fill(&traced, &tr);
            fprintf(stderr, "--- a third send:\n");
            tsr_state_diff(c, s, &traced, NULL);
            tsr_state_send_glsl_all(c, s, &traced);
        }
        a->gl.Finish();

        gl_env *envs[2] = {a, b};
        GLint cur[2] = {-1, -1}, tcur = -2;
        tsr_state_get_integerv(c, GL_CURRENT_PROGRAM, &tcur);
        for (int e = 0; e < 2; e++) {
            gl_use(envs[e]);
            tsr_call_GetIntegerv(&envs[e]->d, GL_CURRENT_PROGRAM, &cur[e]);
        }
        CHECK(cur[0] == tcur && cur[1] == tcur, "seed %d: current program tracker %d, A %d, B %d", seed, tcur, cur[0],
              cur[1]);
        with_program += tcur != 0;
        for (GLuint q = 1; q < GLSL_NAMES; q++) {
            static const GLenum sp[] = {GL_SHADER_TYPE, GL_DELETE_STATUS, GL_SHADER_SOURCE_LENGTH, GL_COMPILE_STATUS};
            static const GLenum pp[] = {GL_DELETE_STATUS,   GL_ATTACHED_SHADERS,  GL_LINK_STATUS,
                                        GL_ACTIVE_UNIFORMS, GL_ACTIVE_ATTRIBUTES, GL_VALIDATE_STATUS};
            for (int program = 0; program < 2; program++) {
                const GLenum *pn = program ? pp : sp;
                int count = program ? 6 : 4;
                for (int k = 0; k < count; k++) {
                    GLint v[2] = {-7, -7}, tv = -7;
                    int known =
                        program ? tsr_state_get_programiv(c, q, pn[k], &tv) : tsr_state_get_shaderiv(c, q, pn[k], &tv);
                    int exists = glsl_exists(c, q, program);
                    for (int e = 0; e < 2; e++) {
                        gl_use(envs[e]);
                        if (!exists)
                            continue;
                        if (program)
                            tsr_call_GetProgramiv(&envs[e]->d, q, pn[k], &v[e]);
                        else
                            tsr_call_GetShaderiv(&envs[e]->d, q, pn[k], &v[e]);
                    }
                    if (!exists)
                        continue;
                    compared++;
                    /* validation depends on the state at glValidateProgram: A validated later */
                    if (pn[k] != GL_VALIDATE_STATUS)
                        CHECK(v[0] == v[1], "seed %d: %s %u pname 0x%x: A %d, B %d", seed,
                              program ? "program" : "shader", q, pn[k], v[0], v[1]);
                    if (known)
                        CHECK(tv == v[0] && tv == v[1], "seed %d: %s %u pname 0x%x: tracker %d, A %d, B %d", seed,
                              program ? "program" : "shader", q, pn[k], tv, v[0], v[1]);
                }
            }
            if (!glsl_exists(c, q, 1) || !m.usable[q])
                continue;
            for (int u = 0; u < GLSL_UNIS; u++)
                for (int el = 0; el < glsl_unis[u].len; el++) {
                    char name[32];
                    snprintf(name, sizeof name, el ? "%s[%d]" : "%s", glsl_unis[u].name, el);
                    GLint loc[2];
                    GLfloat fv[2][16];
                    GLint iv[2][16];
                    for (int e = 0; e < 2; e++) {
                        gl_use(envs[e]);
                        loc[e] = tsr_call_GetUniformLocation(&envs[e]->d, q, name);
                        memset(fv[e], 0, sizeof fv[e]);
                        memset(iv[e], 0, sizeof iv[e]);
                        GLuint drv = tsr_glsl_names_driver(e ? bn : an, q);
                        if (loc[e] >= 0 && glsl_unis[u].kind == 'i')
                            get_i(drv, loc[e], iv[e]);
                        else if (loc[e] >= 0)
                            get_f(drv, loc[e], fv[e]);
                    }
                    CHECK(loc[0] == loc[1], "seed %d: program %u: %s at %d in A, %d in B", seed, q, name, loc[0],
                          loc[1]);
                    if (loc[0] < 0)
                        continue;
                    locations++;
                    CHECK(!memcmp(fv[0], fv[1], sizeof fv[0]) && !memcmp(iv[0], iv[1], sizeof iv[0]),
                          "seed %d: program %u: %s has other values in A (%g %g ...) and B (%g %g ...)", seed, q, name,
                          fv[0][0], fv[0][1], fv[1][0], fv[1][1]);
                    compared++;
                }
        }
        CHECK(tsr_glsl_names_driver(an, 1) != tsr_glsl_names_driver(bn, 1) || !glsl_exists(c, 1, 0),
              "seed %d: A and B gave the same driver names: the test does not show names are mapped", seed);
        static unsigned char pa[64 * 64 * 4], pb[64 * 64 * 4];
        glsl_draw(a, pa);
        glsl_draw(b, pb);
        int differ = 0;
        for (size_t i = 0; i < sizeof pa; i += 4)
            differ += memcmp(pa + i, pb + i, 4) != 0;
        CHECK(differ == 0, "seed %d: %d pixels differ between A (diffed) and B (direct), program %d", seed, differ,
              tcur);
        drawn++;
        gl_use(b);
        b->gl.DeleteProgram(keep);
        tsr_glsl_names_destroy(an);
        tsr_glsl_names_destroy(bn);
        gl_close(a);
        gl_close(b);
        tsr_state_tracker_destroy(t);
    }
    printf("%d seeds: %ld values compared (%ld uniform locations), %ld calls sent, %ld triangles pixel-identical "
           "(%ld drawn with a program)\n",
           seeds_arg - first_seed, compared, locations, commands, drawn, with_program);
    CHECK(with_program > (seeds_arg - first_seed) / 4, "only %ld sequences ended with a program in use", with_program);
    CHECK(locations > (seeds_arg - first_seed), "only %ld uniform locations compared", locations);
}
/* Counting table for the lazy-program test: which calls a diff emits. */
enum { GC_CREATEPROG, GC_CREATESH, GC_LINK, GC_UNIFORM, GC_USE, GC_DELPROG, GC_N };
static int gcount[GC_N];
static void gc_CreateProgramTSR(void *self, GLuint p)
{
    (void)self, (void)p;
    gcount[GC_CREATEPROG]++;
}
static void gc_CreateShaderTSR(void *self, GLuint s, GLenum t)
{
    (void)self, (void)s, (void)t;
    gcount[GC_CREATESH]++;
}
static void gc_LinkProgram(void *self, GLuint p)
{
    (void)self, (void)p;
    gcount[GC_LINK]++;
}
static void gc_Uniform4fv(void *self, GLint l, GLsizei n, const GLfloat *v)
{
    (void)self, (void)l, (void)n, (void)v;
    gcount[GC_UNIFORM]++;
}
static void gc_UseProgram(void *self, GLuint p)
{
    (void)self, (void)p;
    gcount[GC_USE]++;
}
static void gc_DeleteProgram(void *self, GLuint p)
{
    (void)self, (void)p;
    gcount[GC_DELPROG]++;
}

static GLuint lazy_program(const tsr_dispatch *d, int k)
{
    GLuint p = tsr_call_CreateProgram(d);
    for (int stage = 0; stage < 2; stage++) {
        GLuint s = tsr_call_CreateShader(d, stage ? GL_FRAGMENT_SHADER : GL_VERTEX_SHADER);
        const char *text = stage ? glsl_fs[k % 3] : glsl_vs[k % 2];
        tsr_call_ShaderSource(d, s, 1, &text, NULL);
        tsr_call_CompileShader(d, s);
        tsr_call_AttachShader(d, p, s);
        tsr_call_DeleteShader(d, s); /* attached: deleted with the program */
    }
    tsr_call_LinkProgram(d, p);
    return p;
}

/* Expected counts of one diff: created programs, created shaders, links,
 * uniform calls, UseProgram, DeleteProgram, and the total. */
static void lazy_expect(tsr_state_ctx *c, tsr_state_shadow *r, const tsr_dispatch *cnt, const char *what, int cp,
                        int cs, int ln, int un, int use, int del, uint32_t total)
{
    memset(gcount, 0, sizeof gcount);
    uint32_t n = tsr_state_diff(c, r, cnt, NULL);
    CHECK(gcount[GC_CREATEPROG] == cp && gcount[GC_CREATESH] == cs && gcount[GC_LINK] == ln &&
              gcount[GC_UNIFORM] == un && gcount[GC_USE] == use && gcount[GC_DELPROG] == del && n == total,
          "%s: %u calls: %d programs, %d shaders created, %d links, %d uniforms, %d uses, %d deletes", what, n,
          gcount[GC_CREATEPROG], gcount[GC_CREATESH], gcount[GC_LINK], gcount[GC_UNIFORM], gcount[GC_USE],
          gcount[GC_DELPROG]);
}

static void test_glsl_lazy(void)
{
    TRACKED(t, c, r, tt);
    static tsr_dispatch cnt;
    tsr_dispatch_fill_nop(&cnt);
    tsr_set_CreateProgramTSR(&cnt, gc_CreateProgramTSR, NULL);
    tsr_set_CreateShaderTSR(&cnt, gc_CreateShaderTSR, NULL);
    tsr_set_LinkProgram(&cnt, gc_LinkProgram, NULL);
    tsr_set_Uniform4fv(&cnt, gc_Uniform4fv, NULL);
    tsr_set_UseProgram(&cnt, gc_UseProgram, NULL);
    tsr_set_DeleteProgram(&cnt, gc_DeleteProgram, NULL);
    tsr_state_diff(c, r, &cnt, NULL); /* the initial state */
    GLuint p1 = lazy_program(&tt, 0), p2 = lazy_program(&tt, 1), p3 = lazy_program(&tt, 2);
    CHECK(p1 && p2 > p1 && p3 > p2, "program names %u %u %u", p1, p2, p3);
    lazy_expect(c, r, &cnt, "programs nobody uses", 0, 0, 0, 0, 0, 0, 0);
    tsr_call_UseProgram(&tt, p2);
    tsr_call_Uniform4f(&tt, 0, 1, 2, 3, 4);
    /* created, 2 shaders made, sourced, compiled and attached, linked, used, uniform set */
    lazy_expect(c, r, &cnt, "first use", 1, 2, 1, 1, 1, 0, 1 + 2 * 4 + 1 + 1 + 1);
    lazy_expect(c, r, &cnt, "unchanged", 0, 0, 0, 0, 0, 0, 0);
    tsr_call_Uniform4f(&tt, 0, 5, 6, 7, 8);
    lazy_expect(c, r, &cnt, "a new uniform value", 0, 0, 0, 1, 0, 0, 1);
    tsr_call_Uniform4f(&tt, 1, 5, 6, 7, 8);
    tsr_call_Uniform4f(&tt, 1, 5, 6, 7, 9);
    lazy_expect(c, r, &cnt, "a value set twice", 0, 0, 0, 1, 0, 0, 1);
    tsr_call_UseProgram(&tt, p1);
    lazy_expect(c, r, &cnt, "second program", 1, 2, 1, 0, 1, 0, 1 + 2 * 4 + 1 + 1);
    tsr_call_UseProgram(&tt, p2);
    lazy_expect(c, r, &cnt, "back to the first", 0, 0, 0, 0, 1, 0, 1);
    tsr_call_DeleteProgram(&tt, p3);
    lazy_expect(c, r, &cnt, "a program the renderer never had is deleted", 0, 0, 0, 0, 0, 0, 0);
    tsr_call_DeleteProgram(&tt, p1);
    /* the program, and its two shaders (the client's went with it) */
    lazy_expect(c, r, &cnt, "a program the renderer has is deleted", 0, 0, 0, 0, 0, 1, 3);
    tsr_call_LinkProgram(&tt, p2);
    lazy_expect(c, r, &cnt, "relink (uniforms back to 0)", 0, 0, 1, 0, 0, 0, 1);
    /* a second renderer joining now gets only what is needed */
    tsr_state_shadow *r2 = tsr_state_shadow_create(t, NULL);
    memset(gcount, 0, sizeof gcount);
    tsr_state_diff(c, r2, &cnt, NULL);
    CHECK(gcount[GC_CREATEPROG] == 1 && gcount[GC_LINK] == 1 && gcount[GC_UNIFORM] == 0,
          "new renderer: %d programs, %d links, %d uniforms", gcount[GC_CREATEPROG], gcount[GC_LINK],
          gcount[GC_UNIFORM]);
    printf("programs go to a renderer when it draws with them, once; unchanged state sends nothing\n");
    tsr_state_tracker_destroy(t);
}


int main(int argc, char **argv)
{
    static const struct {
        const char *name;
        void (*fn)(void);
        int gl;
    } tests[] = {
        {"covers_spec", test_covers_spec, 0},
        {"diff_matches_osmesa", test_diff_matches_osmesa, 1},
        {"unchanged_is_zero_bytes", test_unchanged_is_zero_bytes, 0},
        {"switch_only_differing_groups", test_switch_only_differing_groups, 0},
        {"many_renderers", test_many_renderers, 0},
        {"lazy_textures", test_lazy_textures, 0},
        {"image_units", test_image_units, 1},
        {"list_compile", test_list_compile, 0},
        {"buffers_unbound_reach_renderer", test_buffers_unbound_reach_renderer, 0},
        {"get_count_table", test_get_count_table, 0},
        {"matrices_bit_identical", test_matrices_bit_identical, 1},
        {"multmatrix_of_the_identity_keeps_the_matrix_class", test_multmatrix_of_the_identity_keeps_the_matrix_class,
         1},
        {"long_matrix_history_keeps_the_matrix_class", test_long_matrix_history_keeps_the_matrix_class, 1},
        {"glsl_diff_matches_osmesa", test_glsl_diff_matches_osmesa, 1},
        {"glsl_lazy", test_glsl_lazy, 0},
    };
    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: state_test TEST [SEEDS]\n");
        return 2;
    }
    if (argc == 3)
        seeds_arg = atoi(argv[2]);
    for (size_t i = 0; i < sizeof tests / sizeof tests[0]; i++)
        if (!strcmp(argv[1], tests[i].name)) {
            if (tests[i].gl)
                osm_load();
            tests[i].fn();
            if (harness_failures)
                fprintf(stderr, "%s: %d check(s) failed\n", argv[1], harness_failures);
            return harness_failures ? 1 : 0;
        }
    fprintf(stderr, "state_test: unknown test '%s'\n", argv[1]);
    return 2;
}
