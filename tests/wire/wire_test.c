/* tests/wire/wire_test.c — the wire format tests: every packable command
 * round-trips byte for byte, size and boundary cases, client-array draws,
 * and the unpacker's rejection of malformed buffers. One runner, one test
 * per ctest name (`wire_test NAME`). Uses the real packer, unpacker and
 * generated recorder; never mocks them. */
#include <GL/gl.h>
#include <GL/glext.h>
#include <stdint.h>

#include "roundtrip.h"
#include "tessera/chain.h"
#include "tessera/dev/pixel.h"
#include "tessera/dev/wireloop.h"
#include "tessera/glapi.h"

/* --- every command ----------------------------------------------------------- */

static int roundtrip_all(uint64_t seed, size_t buffer_size)
{
    roundtrip rt;
    CHECK(rt_init(&rt, buffer_size) == 0, "init");
    uint64_t rng = seed;
    char msg[512] = "";
    int calls = 0;
    /* Every packable command once, then a random mix. */
    for (int pass = 0; pass < 2; pass++) {
        int n = pass ? 3 * TSR_DISPATCH_COUNT : TSR_DISPATCH_COUNT;
        for (int i = 0; i < n; i++) {
            int slot = pass ? (int)(tsr_wire_test_rand(&rng) % TSR_DISPATCH_COUNT) : i;
            int rc = tsr_wire_test_call(slot, &rt.expect_table, &rt.pack_table, &rng, msg, sizeof msg);
            CHECK(rc >= 0, "seed %llu, buffer %zu: %s", (unsigned long long)seed, buffer_size, msg);
            calls += rc == 0;
        }
    }
    char what[128];
    snprintf(what, sizeof what, "seed %llu, buffer %zu", (unsigned long long)seed, buffer_size);
    int bad = rt_check(&rt, what);
    fprintf(stderr, "%s: %d calls in %zu buffers, %zu recorded\n", what, calls, rt.nbufs, rt.actual.n);
    CHECK(rt.actual.n == (size_t)calls, "every call must arrive once");
    rt_free(&rt);
    return bad;
}

static int wire_roundtrip_all_commands(void)
{
    int packable = 0;
    for (int s = 0; s < TSR_DISPATCH_COUNT; s++)
        packable += tsr_wire_test_packable(s);
    CHECK(packable > 300, "the spec has %d packable commands", packable);
    const size_t sizes[] = {TSR_PACK_MIN_BUFFER, 4096, 1 << 20};
    for (uint64_t seed = 1; seed <= 5; seed++)
        for (size_t i = 0; i < 3; i++)
            if (roundtrip_all(seed * 7919, sizes[i]))
                return 1;
    return 0;
}

/* --- sizes and boundaries ------------------------------------------------------ */

static int wire_vertex3f_is_13_bytes(void)
{
    roundtrip rt;
    CHECK(rt_init(&rt, 4096) == 0, "init");
    tsr_call_Vertex3f(&rt.pack_table, 1.0f, 2.0f, 3.0f);
    CHECK(tsr_packer_pending(rt.packer) == 13, "one glVertex3f costs %zu bytes", tsr_packer_pending(rt.packer));
    tsr_call_Vertex3f(&rt.pack_table, 4.0f, 5.0f, 6.0f);
    CHECK(tsr_packer_pending(rt.packer) == 26, "two cost %zu bytes", tsr_packer_pending(rt.packer));
    tsr_call_Vertex3f(&rt.expect_table, 1.0f, 2.0f, 3.0f);
    tsr_call_Vertex3f(&rt.expect_table, 4.0f, 5.0f, 6.0f);
    CHECK(rt_check(&rt, "vertex3f") == 0, "roundtrip");
    CHECK(rt.nbufs == 1, "%zu buffers", rt.nbufs);
    uint8_t *b = rt.bufs[0];
    CHECK(buf_nops(b) == 2 && buf_len(b) == 24, "header: %u opcodes, %llu data bytes", buf_nops(b),
          (unsigned long long)buf_len(b));
    CHECK(rt.sizes[0] == TSR_WIRE_HEADER_SIZE + 8 + 24, "buffer of %zu bytes", rt.sizes[0]);
    uint8_t *d = buf_data(b);
    CHECK(d[-1] == TSR_OP_Vertex3f && d[-2] == TSR_OP_Vertex3f, "opcodes grow backwards from the data");
    CHECK(tsr_wire_get_f32(d) == 1.0f && tsr_wire_get_f32(d + 8) == 3.0f && tsr_wire_get_f32(d + 12) == 4.0f,
          "arguments grow forwards");
    float mn[3], mx[3];
    tsr_call_Vertex3f(&rt.pack_table, -1.0f, 7.0f, 0.5f);
    tsr_call_Vertex2f(&rt.pack_table, 3.0f, -2.0f);
    CHECK(tsr_packer_bbox(rt.packer, mn, mx) == 1, "bbox known");
    CHECK(mn[0] == -1.0f && mn[1] == -2.0f && mn[2] == 0.0f && mx[0] == 3.0f && mx[1] == 7.0f && mx[2] == 0.5f,
          "bbox (%g %g %g)-(%g %g %g)", mn[0], mn[1], mn[2], mx[0], mx[1], mx[2]);
    tsr_packer_flush(rt.packer);
    CHECK(tsr_packer_bbox(rt.packer, mn, mx) == 0, "bbox resets after a flush");
    rt_free(&rt);
    return 0;
}

static int wire_extended_opcode_roundtrip(void)
{
    int tested = 0;
    uint64_t rng = 42;
    char msg[512] = "";
    for (int slot = 0; slot < TSR_DISPATCH_COUNT; slot++) {
        int op = tsr_wire_slot_opcode(slot);
        if (op < 255 || !tsr_wire_test_packable(slot))
            continue;
        roundtrip rt;
        CHECK(rt_init(&rt, 1 << 16) == 0, "init");
        int rc = tsr_wire_test_call(slot, &rt.expect_table, &rt.pack_table, &rng, msg, sizeof msg);
        CHECK(rc == 0, "gl%s: %s", tsr_dispatch_name(slot), msg);
        CHECK(rt_check(&rt, tsr_dispatch_name(slot)) == 0, "roundtrip");
        uint8_t *b = rt.bufs[0];
        uint8_t *d = buf_data(b);
        CHECK(buf_nops(b) == 1 && d[-1] == TSR_WIRE_EXTENDED, "gl%s: opcode byte %u", tsr_dispatch_name(slot), d[-1]);
        CHECK(tsr_wire_get_u32(d) == (uint32_t)op, "gl%s: extended opcode %u", tsr_dispatch_name(slot),
              tsr_wire_get_u32(d));
        CHECK(tsr_wire_get_u32(d + 4) == buf_len(b) - 8, "gl%s: extended length %u of %llu", tsr_dispatch_name(slot),
              tsr_wire_get_u32(d + 4), (unsigned long long)buf_len(b));
        rt_free(&rt);
        tested++;
    }
    CHECK(tested > 50, "only %d extended commands", tested);
    fprintf(stderr, "%d extended commands round-trip\n", tested);
    return 0;
}

static int wire_commands_exactly_fill_a_buffer(void)
{
    /* Find a buffer size whose data area holds a whole number of Vertex3f. */
    for (size_t size = 1024; size < 1200; size += 8) {
        roundtrip rt;
        CHECK(rt_init(&rt, size) == 0, "init");
        size_t room = rt.packer->data_room;
        if (room % 12 || rt.packer->op_room < room / 12) {
            rt_free(&rt);
            continue;
        }
        size_t k = room / 12;
        for (size_t i = 0; i < k; i++) {
            tsr_call_Vertex3f(&rt.pack_table, (float)i, 0, 0);
            tsr_call_Vertex3f(&rt.expect_table, (float)i, 0, 0);
        }
        CHECK(rt.nbufs == 0, "no flush before the buffer is full");
        CHECK(rt.packer->data == rt.packer->data_end, "the data area is exactly full");
        tsr_call_Vertex3f(&rt.pack_table, -1, 0, 0);
        tsr_call_Vertex3f(&rt.expect_table, -1, 0, 0);
        CHECK(rt.nbufs == 1 && buf_nops(rt.bufs[0]) == k && buf_len(rt.bufs[0]) == room,
              "the next command flushes the full buffer (%zu buffers)", rt.nbufs);
        CHECK(rt_check(&rt, "exact fill") == 0, "roundtrip");
        rt_free(&rt);
        return 0;
    }
    CHECK(0, "no suitable buffer size found");
    return 1;
}

static int wire_large_command_gets_its_own_buffer(void)
{
    roundtrip rt;
    CHECK(rt_init(&rt, 4096) == 0, "init");
    size_t n = 100000;
    uint8_t *data = malloc(n);
    for (size_t i = 0; i < n; i++)
        data[i] = (uint8_t)(i * 13);
    for (int side = 0; side < 2; side++) {
        const tsr_dispatch *t = side ? &rt.expect_table : &rt.pack_table;
        tsr_call_Vertex3f(t, 1, 2, 3);
        tsr_call_BufferData(t, GL_ARRAY_BUFFER, (GLsizeiptr)n, data, GL_STATIC_DRAW);
        tsr_call_Vertex3f(t, 4, 5, 6);
    }
    CHECK(rt_check(&rt, "oversized") == 0, "roundtrip");
    CHECK(rt.nbufs == 3, "%zu buffers", rt.nbufs);
    CHECK(buf_nops(rt.bufs[1]) == 1 && buf_len(rt.bufs[1]) > n && rt.sizes[1] > 4096,
          "the large command travels alone in a buffer of %zu bytes", rt.sizes[1]);
    free(data);
    rt_free(&rt);
    return 0;
}

static int wire_begin_end_split_across_buffers(void)
{
    const GLenum modes[] = {GL_TRIANGLE_STRIP, GL_TRIANGLE_FAN, GL_POLYGON, GL_QUAD_STRIP};
    for (size_t m = 0; m < sizeof modes / sizeof modes[0]; m++) {
        roundtrip rt;
        CHECK(rt_init(&rt, 512) == 0, "init");
        for (int side = 0; side < 2; side++) {
            const tsr_dispatch *t = side ? &rt.expect_table : &rt.pack_table;
            tsr_call_Begin(t, modes[m]);
            for (int i = 0; i < 300; i++) {
                tsr_call_Color4ub(t, (GLubyte)i, 2, 3, 255);
                tsr_call_Normal3f(t, 0, 0, 1);
                tsr_call_Vertex3d(t, i, i * 0.5, -i);
            }
            tsr_call_End(t);
        }
        CHECK(rt_check(&rt, "begin/end") == 0, "roundtrip");
        CHECK(rt.nbufs > 10, "mode 0x%x: only %zu buffers", modes[m], rt.nbufs);
        /* Each buffer decodes alone, with a fresh unpacker. */
        for (size_t i = 0; i < rt.nbufs; i++) {
            tsr_recorder r;
            tsr_dispatch t;
            tsr_recorder_init(&r);
            tsr_recorder_fill(&t, &r);
            tsr_error err;
            tsr_unpacker *u = tsr_unpacker_create(&t, NULL, NULL, &err);
            int rc = tsr_unpacker_run(u, rt.bufs[i], rt.sizes[i], &err);
            CHECK(rc == 0 && r.n == buf_nops(rt.bufs[i]), "buffer %zu alone: %s", i, err.message);
            tsr_unpacker_destroy(u);
            tsr_recorder_clear(&r);
        }
        rt_free(&rt);
    }
    return 0;
}

/* --- client arrays ---------------------------------------------------------------- */

/* The last parameter of a recorded *Pointer / DrawElements call is the
 * pointer value (count-less pointers are recorded by address). */
static const uint8_t *recorded_pointer(const tsr_rec_call *c)
{
    uintptr_t v;
    memcpy(&v, c->bytes + c->len - sizeof v, sizeof v);
    return (const uint8_t *)v;
}

static int check_sequence(const tsr_recorder *r, const char *const *names, size_t n)
{
    for (size_t i = 0; i < n && i < r->n; i++)
        CHECK(!strcmp(tsr_dispatch_name(r->calls[i].slot), names[i]), "call %zu is gl%s, documented gl%s", i,
              tsr_dispatch_name(r->calls[i].slot), names[i]);
    CHECK(r->n == n, "%zu calls, documented %zu", r->n, n);
    return 0;
}

typedef struct vtx {
    float pos[3];
    float pad; /* stride 16: the packer must compact */
} vtx;

static int wire_client_arrays_draw_arrays_rebuild(void)
{
    roundtrip rt;
    CHECK(rt_init(&rt, 1024) == 0, "init");
    vtx v[40];
    GLubyte color[40][4];
    float tex[40][2];
    float attr[40][4];
    for (int i = 0; i < 40; i++) {
        v[i] = (vtx){{(float)i, (float)i * 2, (float)-i}, 99.0f};
        for (int k = 0; k < 4; k++) {
            color[i][k] = (GLubyte)(i * 4 + k);
            attr[i][k] = (float)(i * 10 + k);
        }
        tex[i][0] = (float)i / 40;
        tex[i][1] = 1 - (float)i / 40;
    }
    const tsr_dispatch *t = &rt.pack_table;
    tsr_call_VertexPointer(t, 3, GL_FLOAT, sizeof(vtx), v);
    tsr_call_EnableClientState(t, GL_VERTEX_ARRAY);
    tsr_call_BindBuffer(t, GL_ARRAY_BUFFER, 7);
    tsr_call_NormalPointer(t, GL_FLOAT, 0, (const void *)(uintptr_t)64);
    tsr_call_BindBuffer(t, GL_ARRAY_BUFFER, 0);
    tsr_call_EnableClientState(t, GL_NORMAL_ARRAY);
    tsr_call_ColorPointer(t, 4, GL_UNSIGNED_BYTE, 0, color);
    tsr_call_EnableClientState(t, GL_COLOR_ARRAY);
    tsr_call_ClientActiveTexture(t, GL_TEXTURE1);
    tsr_call_TexCoordPointer(t, 2, GL_FLOAT, 0, tex);
    tsr_call_EnableClientState(t, GL_TEXTURE_COORD_ARRAY);
    tsr_call_ClientActiveTexture(t, GL_TEXTURE0);
    tsr_call_VertexAttribPointer(t, 3, 4, GL_FLOAT, GL_FALSE, 0, attr);
    tsr_call_EnableVertexAttribArray(t, 3);
    const GLint first = 5;
    const GLsizei count = 9;
    tsr_call_DrawArrays(t, GL_TRIANGLES, first, count);
    float mn[3], mx[3], wmn[3] = {1e30f, 1e30f, 1e30f}, wmx[3] = {-1e30f, -1e30f, -1e30f};
    for (int i = first; i < first + count; i++)
        for (int k = 0; k < 3; k++) {
            wmn[k] = v[i].pos[k] < wmn[k] ? v[i].pos[k] : wmn[k];
            wmx[k] = v[i].pos[k] > wmx[k] ? v[i].pos[k] : wmx[k];
        }
    CHECK(tsr_packer_bbox(rt.packer, mn, mx) && !memcmp(mn, wmn, sizeof mn) && !memcmp(mx, wmx, sizeof mx),
          "the box covers the drawn client-array vertices: (%g %g %g)-(%g %g %g)", mn[0], mn[1], mn[2], mx[0], mx[1],
          mx[2]);
    tsr_packer_flush(rt.packer);
    CHECK(rt.unpack_rc == 0, "unpack: %s", rt.unpack_err.message);
    /* What the receiver sees: BindBuffer(ARRAY_BUFFER, 0) from the client,
     * then the documented rebuild (tessera/dev/wire.h section 6). */
    const char *const names[] = {
        "BindBuffer",
        "BindBuffer",
        "BindBuffer",
        "VertexPointer",
        "EnableClientState",
        "BindBuffer",
        "NormalPointer",
        "EnableClientState",
        "BindBuffer",
        "ColorPointer",
        "EnableClientState",
        "BindBuffer",
        "ClientActiveTexture",
        "TexCoordPointer",
        "EnableClientState",
        "BindBuffer",
        "VertexAttribPointer",
        "EnableVertexAttribArray",
        "DrawArrays",
        "DisableClientState",
        "DisableClientState",
        "DisableClientState",
        "ClientActiveTexture",
        "DisableClientState",
        "DisableVertexAttribArray",
        "ClientActiveTexture",
        "BindBuffer",
    };
    if (check_sequence(&rt.actual, names, sizeof names / sizeof names[0]))
        return 1;
    const tsr_rec_call *c = rt.actual.calls;
    const uint8_t *vp = recorded_pointer(&c[3]);
    for (int i = first; i < first + count; i++)
        CHECK(!memcmp(vp + i * 12, v[i].pos, 12), "vertex %d compacted and addressed by its index", i);
    CHECK(recorded_pointer(&c[6]) == (const uint8_t *)(uintptr_t)64, "buffer arrays keep their offset");
    const uint8_t *cp = recorded_pointer(&c[9]);
    const uint8_t *tp = recorded_pointer(&c[13]);
    const uint8_t *ap = recorded_pointer(&c[16]);
    for (int i = first; i < first + count; i++) {
        CHECK(!memcmp(cp + i * 4, color[i], 4), "color %d", i);
        CHECK(!memcmp(tp + i * 8, tex[i], 8), "texcoord %d", i);
        CHECK(!memcmp(ap + i * 16, attr[i], 16), "attrib %d", i);
    }
    rt_free(&rt);
    return 0;
}

/* glEnable(GL_VERTEX_ARRAY) is glEnableClientState (Mesa takes both;
 * piglit's gl-1.1-color-material-array enables its arrays so): the
 * packer's mirror, never the wire, so the draw carries the arrays; and an
 * Enable of a client array that does come from the wire (a packer that
 * sent it, a forged stream) is dropped: the receiver would keep the array
 * enabled at a pointer it does not own and crash drawing (the server
 * node died with SIGSEGV). Other caps travel as before. */
static int wire_enable_of_a_client_array_is_client_state(void)
{
    roundtrip rt;
    CHECK(rt_init(&rt, 1024) == 0, "init");
    static const float pos[3][2] = {{0, 0}, {1, 0}, {0, 1}};
    static const GLubyte col[3][4] = {{1, 2, 3, 4}, {5, 6, 7, 8}, {9, 10, 11, 12}};
    const tsr_dispatch *t = &rt.pack_table;
    tsr_call_VertexPointer(t, 2, GL_FLOAT, 0, pos);
    tsr_call_ColorPointer(t, 4, GL_UNSIGNED_BYTE, 0, col);
    tsr_call_Enable(t, GL_VERTEX_ARRAY);
    tsr_call_Enable(t, GL_COLOR_ARRAY);
    tsr_call_Enable(t, GL_DEPTH_TEST);
    CHECK(tsr_call_IsEnabled(t, GL_VERTEX_ARRAY) == GL_TRUE && tsr_call_IsEnabled(t, GL_COLOR_ARRAY) == GL_TRUE &&
              rt.nbufs == 0,
          "glEnable of client arrays is answered by the packer's mirror");
    tsr_call_DrawArrays(t, GL_TRIANGLES, 0, 3);
    tsr_call_Disable(t, GL_COLOR_ARRAY);
    CHECK(tsr_call_IsEnabled(t, GL_COLOR_ARRAY) == GL_FALSE, "glDisable of a client array reaches the mirror");
    tsr_pack_Enable(rt.packer, GL_NORMAL_ARRAY); /* on the wire as a forged stream has it */
    tsr_pack_Disable(rt.packer, GL_VERTEX_ARRAY);
    tsr_packer_flush(rt.packer);
    CHECK(rt.unpack_rc == 0, "unpack: %s", rt.unpack_err.message);
    const char *const names[] = {
        "Enable",       "BindBuffer",        "VertexPointer", "EnableClientState",  "BindBuffer",
        "ColorPointer", "EnableClientState", "DrawArrays",    "DisableClientState", "DisableClientState",
        "BindBuffer",
    };
    if (check_sequence(&rt.actual, names, sizeof names / sizeof names[0]))
        return 1;
    GLenum cap;
    memcpy(&cap, rt.actual.calls[0].bytes + sizeof "Enable", sizeof cap); /* after the recorded name */
    CHECK(cap == GL_DEPTH_TEST, "the one glEnable on the wire is GL_DEPTH_TEST's, not 0x%x", cap);
    rt_free(&rt);
    return 0;
}

/* A query whose pname the wire cannot size (GL_CLIP_PLANE0 + 8, or a
 * made-up enum) is GL_INVALID_ENUM with nothing written, answered by the
 * packer: sent, the receiver dropped the whole stream ("unknown enum for
 * pname"; piglit's clip-flag-behavior ended on the wall and through
 * pack). The error is the next glGetError's, once; planes 6 and 7 are
 * known. */
static int wire_query_of_an_unknown_pname_is_invalid_enum_not_a_dropped_stream(void)
{
    roundtrip rt;
    CHECK(rt_init(&rt, 1024) == 0, "init");
    const tsr_dispatch *t = &rt.pack_table;
    GLboolean b[4] = {7, 7, 7, 7};
    GLint iv[4] = {-5, -5, -5, -5};
    tsr_call_GetBooleanv(t, GL_CLIP_PLANE0 + 8, b);
    tsr_call_GetIntegerv(t, 0x7fff0001, iv);
    CHECK(rt.nbufs == 0 && b[0] == 7 && iv[0] == -5, "nothing sent, nothing written (%zu buffers)", rt.nbufs);
    GLenum e = tsr_call_GetError(t);
    CHECK(e == GL_INVALID_ENUM && rt.nbufs == 0, "glGetError answers GL_INVALID_ENUM itself, not 0x%x", e);
    CHECK(tsr_wire_pname_count(GL_CLIP_PLANE0 + 6) == 1 && tsr_wire_pname_count(GL_CLIP_PLANE0 + 7) == 1,
          "clip planes 6 and 7 are sized (Mesa has 8)");
    tsr_call_GetError(t);
    CHECK(rt.nbufs >= 1 && rt.unpack_rc == 0, "the next glGetError asks the receiver (%zu buffers: %s)", rt.nbufs,
          rt.unpack_err.message);
    rt_free(&rt);
    return 0;
}

/* A setter whose array the wire sizes by a pname it does not know
 * (glLightfv, glTexParameteriv, glFogfv of a made-up enum) is
 * GL_INVALID_ENUM for the next glGetError, as GL answers it, with nothing
 * sent and the array not read: the packer dropped it as "not sent:
 * unknown enum for pname" and glGetError said GL_NO_ERROR (piglit's API
 * tests through pack and on the wall; tests/tilesort/gl_errors_driver.c). */
static int wire_setter_of_an_unknown_pname_is_invalid_enum_not_a_dropped_call(void)
{
    roundtrip rt;
    CHECK(rt_init(&rt, 1024) == 0, "init");
    const tsr_dispatch *t = &rt.pack_table;
    const GLfloat *never_read = (const GLfloat *)(uintptr_t)0x10; /* a read would fault */
    tsr_call_Lightfv(t, GL_LIGHT0, 0x7fff0001, never_read);
    GLenum e = tsr_call_GetError(t);
    CHECK(e == GL_INVALID_ENUM && rt.nbufs == 0, "glLightfv: glGetError says 0x%x, %zu buffers sent", e, rt.nbufs);
    tsr_call_TexParameteriv(t, GL_TEXTURE_2D, 0x7fff0002, (const GLint *)never_read);
    tsr_call_Fogfv(t, 0x7fff0003, never_read); /* a second error: GL keeps the first */
    e = tsr_call_GetError(t);
    CHECK(e == GL_INVALID_ENUM && rt.nbufs == 0, "glTexParameteriv: glGetError says 0x%x, %zu buffers sent", e,
          rt.nbufs);
    CHECK(tsr_packer_error(rt.packer)->code == TSR_OK, "no call dropped: %s", tsr_packer_error(rt.packer)->message);
    static const GLfloat ambient[4] = {0.25f, 0.5f, 0.75f, 1.0f};
    tsr_call_Lightfv(t, GL_LIGHT0, GL_AMBIENT, ambient);
    tsr_call_Flush(t);
    CHECK(rt.nbufs == 1 && rt.actual.n >= 1 && !strcmp((const char *)rt.actual.calls[0].bytes, "Lightfv"),
          "a known pname is sent (%zu buffers)", rt.nbufs);
    rt_free(&rt);
    return 0;
}

/* A pixel command GL refuses before it reads a pixel (a packed type with
 * a format it does not go with, a negative size, a type that is none) is
 * the GL error glGetError answers, made by the packer: nothing is sent and
 * its pointer is not read (piglit's draw-pixels passes NULL there and
 * expects GL_INVALID_OPERATION: the packer dropped the call as "NULL
 * pixels", and glGetError said GL_NO_ERROR). A valid combination is sent. */
static int wire_pixel_command_gl_refuses_is_its_gl_error_not_sent_nor_read(void)
{
    roundtrip rt;
    CHECK(rt_init(&rt, 1024) == 0, "init");
    const tsr_dispatch *t = &rt.pack_table;
    /* never dereferenced: a read would fault */
    const void *stale = (const void *)(uintptr_t)0x10;
    struct {
        GLsizei w;
        GLenum format, type, error;
    } cases[] = {
        {4, GL_BGR, GL_UNSIGNED_SHORT_5_6_5, GL_INVALID_OPERATION},
        {4, GL_RGBA, GL_UNSIGNED_BYTE_3_3_2, GL_INVALID_OPERATION},
        {4, GL_RGB, GL_UNSIGNED_SHORT_4_4_4_4, GL_INVALID_OPERATION},
        {4, GL_LUMINANCE, GL_UNSIGNED_INT_2_10_10_10_REV, GL_INVALID_OPERATION},
        {4, GL_RGBA, GL_UNSIGNED_INT_24_8, GL_INVALID_OPERATION},
        {4, GL_RGB, GL_BITMAP, GL_INVALID_ENUM},
        {4, GL_RGB, GL_DOUBLE, GL_INVALID_ENUM},
        {4, 0x1234, GL_UNSIGNED_BYTE, GL_INVALID_ENUM},
        {-1, GL_RGB, GL_UNSIGNED_BYTE, GL_INVALID_VALUE},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        tsr_call_DrawPixels(t, cases[i].w, 4, cases[i].format, cases[i].type, stale);
        GLenum e = tsr_call_GetError(t);
        CHECK(e == cases[i].error && rt.nbufs == 0, "case %zu: glGetError says 0x%x (not 0x%x), %zu buffers sent", i, e,
              cases[i].error, rt.nbufs);
    }
    CHECK(tsr_pixel_image_error(4, 4, 1, GL_RGB, GL_UNSIGNED_SHORT_5_6_5) == GL_NO_ERROR &&
              tsr_pixel_image_error(4, 4, 1, GL_BGRA, GL_UNSIGNED_INT_8_8_8_8_REV) == GL_NO_ERROR &&
              tsr_pixel_image_error(4, 4, 1, GL_DEPTH_STENCIL, GL_UNSIGNED_INT_24_8) == GL_NO_ERROR &&
              tsr_pixel_image_error(8, 1, 1, GL_COLOR_INDEX, GL_BITMAP) == GL_NO_ERROR,
          "valid combinations are no error");
    static const GLushort pixels[4 * 4] = {0};
    tsr_call_DrawPixels(t, 4, 4, GL_RGB, GL_UNSIGNED_SHORT_5_6_5, pixels);
    tsr_packer_flush(rt.packer);
    CHECK(rt.unpack_rc == 0, "unpack: %s", rt.unpack_err.message);
    const char *const names[] = {"DrawPixels"};
    if (check_sequence(&rt.actual, names, 1))
        return 1;
    rt_free(&rt);
    return 0;
}

static int wire_client_arrays_draw_elements_rebuild(void)
{
    roundtrip rt;
    CHECK(rt_init(&rt, 1024) == 0, "init");
    float pos[32][2];
    for (int i = 0; i < 32; i++) {
        pos[i][0] = (float)i;
        pos[i][1] = (float)(i * i);
    }
    const GLushort idx[] = {20, 3, 7, 7, 12, 19, 3, 20};
    const GLsizei count = 8;
    const tsr_dispatch *t = &rt.pack_table;
    tsr_call_VertexPointer(t, 2, GL_FLOAT, 0, pos);
    tsr_call_EnableClientState(t, GL_VERTEX_ARRAY);
    CHECK(tsr_call_IsEnabled(t, GL_VERTEX_ARRAY) == GL_TRUE && tsr_call_IsEnabled(t, GL_COLOR_ARRAY) == GL_FALSE &&
              rt.nbufs == 0,
          "client-array queries are answered by the packer, without a round trip");
    tsr_call_DrawElements(t, GL_LINES, count, GL_UNSIGNED_SHORT, idx);
    /* All arrays and indices in buffer objects: offsets pass through. */
    tsr_call_BindBuffer(t, GL_ARRAY_BUFFER, 5);
    tsr_call_VertexPointer(t, 2, GL_FLOAT, 8, (const void *)(uintptr_t)32);
    tsr_call_BindBuffer(t, GL_ELEMENT_ARRAY_BUFFER, 6);
    tsr_call_DrawElements(t, GL_POINTS, 4, GL_UNSIGNED_INT, (const void *)(uintptr_t)16);
    tsr_packer_flush(rt.packer);
    CHECK(rt.unpack_rc == 0, "unpack: %s", rt.unpack_err.message);
    const char *const names[] = {
        "BindBuffer",         "VertexPointer", "EnableClientState", "BindBuffer", "DrawElements",
        "DisableClientState", "BindBuffer",    "BindBuffer",        "BindBuffer", "BindBuffer",
        "BindBuffer",         "VertexPointer", "EnableClientState", "BindBuffer", "DrawElements",
        "DisableClientState", "BindBuffer",    "BindBuffer",
    };
    if (check_sequence(&rt.actual, names, sizeof names / sizeof names[0]))
        return 1;
    const tsr_rec_call *c = rt.actual.calls;
    const uint8_t *vp = recorded_pointer(&c[1]);
    for (int i = 0; i < count; i++)
        CHECK(!memcmp(vp + idx[i] * 8, pos[idx[i]], 8), "vertex %u reachable through its index", idx[i]);
    CHECK(!memcmp(recorded_pointer(&c[4]), idx, sizeof idx), "indices travel inline");
    CHECK(recorded_pointer(&c[11]) == (const uint8_t *)(uintptr_t)32, "buffer vertex offset kept");
    CHECK(recorded_pointer(&c[14]) == (const uint8_t *)(uintptr_t)16, "element buffer offset kept");
    rt_free(&rt);
    return 0;
}

static int wire_shader_source_roundtrip(void)
{
    roundtrip rt;
    CHECK(rt_init(&rt, 256) == 0, "init");
    const GLchar *src[] = {"void main() {", "  gl_FragColor = vec4(1.0);", "}XXXX"};
    const GLint len[] = {-1, 27, 1};
    for (int side = 0; side < 2; side++) {
        const tsr_dispatch *t = side ? &rt.expect_table : &rt.pack_table;
        tsr_call_ShaderSource(t, 3, 3, src, NULL);
        tsr_call_ShaderSource(t, 4, 3, src, len);
        tsr_call_ShaderSource(t, 5, 0, NULL, NULL);
    }
    CHECK(rt_check(&rt, "ShaderSource") == 0, "roundtrip");
    rt_free(&rt);
    return 0;
}

static int wire_pixel_store_shapes_image_payloads(void)
{
    roundtrip rt;
    CHECK(rt_init(&rt, 4096) == 0, "init");
    uint8_t img[4096];
    for (size_t i = 0; i < sizeof img; i++)
        img[i] = (uint8_t)(i * 7);
    uint8_t out_e[4096], out_x[4096];
    memset(out_e, 0xAB, sizeof out_e);
    memset(out_x, 0xAB, sizeof out_x);
    for (int side = 0; side < 2; side++) {
        const tsr_dispatch *t = side ? &rt.expect_table : &rt.pack_table;
        tsr_call_PixelStorei(t, GL_UNPACK_ALIGNMENT, 8);
        tsr_call_PixelStorei(t, GL_UNPACK_ROW_LENGTH, 13);
        tsr_call_PixelStorei(t, GL_UNPACK_SKIP_ROWS, 2);
        tsr_call_PixelStorei(t, GL_UNPACK_SKIP_PIXELS, 3);
        tsr_call_TexImage2D(t, GL_TEXTURE_2D, 0, GL_RGB, 5, 4, 0, GL_RGB, GL_UNSIGNED_BYTE, img);
        tsr_call_Bitmap(t, 17, 3, 0, 0, 0, 0, img);
        tsr_call_PixelStorei(t, GL_PACK_ALIGNMENT, 1);
        tsr_call_PixelStorei(t, GL_PACK_ROW_LENGTH, 9);
        tsr_call_PixelStorei(t, GL_PACK_SKIP_PIXELS, 1);
        tsr_call_ReadPixels(t, 0, 0, 4, 3, GL_RGBA, GL_UNSIGNED_BYTE, side ? out_e : out_x);
    }
    CHECK(rt_check(&rt, "pixel store") == 0, "roundtrip");
    CHECK(!memcmp(out_e, out_x, sizeof out_e), "ReadPixels wrote the same bytes, and only the pixel spans");
    CHECK(out_x[0] == 0xAB && out_x[4] != 0xAB, "skipped pixel untouched, first pixel written");
    rt_free(&rt);
    return 0;
}

/* --- malformed buffers ------------------------------------------------------------ */

typedef int (*stream_fn)(const tsr_dispatch *t);

/* Packs `fn` into one buffer and returns a copy (caller frees). */
static uint8_t *pack_one(stream_fn fn, size_t *size)
{
    roundtrip rt;
    if (rt_init(&rt, 1 << 16) != 0)
        return NULL;
    rt.decode = 0;
    fn(&rt.pack_table);
    tsr_packer_flush(rt.packer);
    uint8_t *b = NULL;
    if (rt.nbufs == 1) {
        b = rt.bufs[0];
        *size = rt.sizes[0];
        rt.bufs[0] = NULL;
    }
    rt_free(&rt);
    return b;
}

static int run_bad(uint8_t *b, size_t size, const char *must1, const char *must2)
{
    tsr_dispatch nop;
    tsr_dispatch_fill_nop(&nop);
    tsr_error err;
    tsr_unpacker *u = tsr_unpacker_create(&nop, NULL, NULL, &err);
    int rc = tsr_unpacker_run(u, b, size, &err);
    tsr_unpacker_destroy(u);
    fprintf(stderr, "rejected: %s\n", err.message);
    CHECK(rc == TSR_EPROTO, "expected TSR_EPROTO, got %d (%s)", rc, err.message);
    CHECK(strstr(err.message, must1) && strstr(err.message, must2), "message \"%s\" should name \"%s\" and \"%s\"",
          err.message, must1, must2);
    return 0;
}

static int stream_vertices(const tsr_dispatch *t)
{
    tsr_call_Color3f(t, 1, 0, 0);
    tsr_call_Vertex3f(t, 1, 2, 3);
    return 0;
}

static int stream_buffer_data(const tsr_dispatch *t)
{
    static const uint8_t data[24] = {1, 2, 3};
    tsr_call_BufferData(t, GL_ARRAY_BUFFER, 24, data, GL_STATIC_DRAW);
    return 0;
}

static int stream_map(const tsr_dispatch *t)
{
    static GLdouble pts[256];
    tsr_call_Map2d(t, GL_MAP2_VERTEX_3, 0, 1, 111, 2, 0, 1, 3, 2, pts);
    return 0;
}

static int wire_unpack_rejects_unknown_opcode(void)
{
    size_t size;
    uint8_t *b = pack_one(stream_vertices, &size);
    CHECK(b, "pack");
    int unused = 0;
    for (int op = 1; op < 255 && !unused; op++)
        if (!tsr_wire_opcode_name((uint32_t)op))
            unused = op;
    CHECK(unused, "no free single-byte opcode");
    buf_data(b)[-2] = (uint8_t)unused;
    int r = run_bad(b, size, "unknown opcode", "offset");
    buf_data(b)[-2] = 0;
    r |= run_bad(b, size, "unknown opcode 0", "offset");
    free(b);
    return r;
}

static int wire_unpack_rejects_truncated_command(void)
{
    size_t size;
    uint8_t *b = pack_one(stream_vertices, &size);
    CHECK(b, "pack");
    tsr_wire_put_u64(b + 8, buf_len(b) - 4);
    int r = run_bad(b, size - 4, "Vertex3f", "truncated");
    free(b);
    return r;
}

static int wire_unpack_rejects_length_beyond_buffer(void)
{
    size_t size;
    uint8_t *b = pack_one(stream_buffer_data, &size);
    CHECK(b, "pack");
    uint8_t *d = buf_data(b);
    uint64_t len_at = buf_len(b) - 24 - 8; /* the payload is last */
    CHECK(tsr_wire_get_u64(d + len_at) == 24, "payload length where the format puts it");
    tsr_wire_put_u64(d + len_at, (uint64_t)1 << 40);
    int r = run_bad(b, size, "BufferData", "beyond the buffer");
    tsr_wire_put_u64(d + len_at, 25);
    r |= run_bad(b, size, "BufferData", "beyond the buffer");
    tsr_wire_put_u64(d + len_at, 16);
    r |= run_bad(b, size, "BufferData", "does not match");
    /* A header claiming more data than was received. */
    tsr_wire_put_u64(d + len_at, 24);
    tsr_wire_put_u64(b + 8, buf_len(b) + 64);
    r |= run_bad(b, size, "header", "received");
    free(b);
    return r;
}

static int wire_unpack_rejects_count_overflow(void)
{
    size_t size;
    uint8_t *b = pack_one(stream_map, &size);
    CHECK(b, "pack");
    uint8_t *d = buf_data(b);
    size_t at = 0;
    for (size_t i = 0; i + 8 <= buf_len(b); i += 4)
        if (tsr_wire_get_u32(d + i) == 111 && tsr_wire_get_u32(d + i + 4) == 2) {
            at = i;
            break;
        }
    CHECK(at, "ustride/uorder not found");
    tsr_wire_put_u32(d + at, 0x7fffffff);
    tsr_wire_put_u32(d + at + 4, 0x7fffffff);
    /* vstride/vorder follow the two doubles v1, v2. */
    tsr_wire_put_u32(d + at + 24, 0x7fffffff);
    tsr_wire_put_u32(d + at + 28, 0x7fffffff);
    int r = run_bad(b, size, "Map2d", "overflows");
    free(b);
    return r;
}

static int wire_unpack_rejects_negative_size(void)
{
    size_t size;
    uint8_t *b = pack_one(stream_buffer_data, &size);
    CHECK(b, "pack");
    uint8_t *d = buf_data(b);
    size_t at = 0;
    for (size_t i = 0; i + 8 <= buf_len(b); i += 8)
        if (tsr_wire_get_u64(d + i) == 24) {
            at = i;
            break;
        }
    CHECK(at, "size not found");
    tsr_wire_put_u64(d + at, (uint64_t)-5);
    int r = run_bad(b, size, "BufferData", "negative");
    free(b);
    return r;
}

static int wire_unpack_rejects_bad_header(void)
{
    size_t size;
    uint8_t *b = pack_one(stream_vertices, &size);
    CHECK(b, "pack");
    int r = run_bad(b, 10, "shorter than its", "header");
    b[0] ^= 1;
    r |= run_bad(b, size, "magic", "0x");
    free(b);
    return r;
}

/* Mutated real buffers: every result is either a clean decode or
 * TSR_EPROTO, never a crash or an out-of-bounds read (run under ASan). */
static int wire_unpack_survives_mutations(void)
{
    roundtrip rt;
    CHECK(rt_init(&rt, 2048) == 0, "init");
    rt.decode = 0;
    uint64_t rng = 99;
    char msg[512];
    for (int s = 0; s < TSR_DISPATCH_COUNT; s++)
        tsr_wire_test_call(s, &rt.expect_table, &rt.pack_table, &rng, msg, sizeof msg);
    /* The hand-written (custom) formats too. */
    static float pos[16][4];
    static GLubyte col[16][4];
    static const GLubyte idx[] = {0, 15, 3, 9};
    const GLchar *src[] = {"a", "bc", "def"};
    const GLint len[] = {1, -1, 2};
    const tsr_dispatch *t = &rt.pack_table;
    tsr_call_VertexPointer(t, 4, GL_FLOAT, 0, pos);
    tsr_call_ColorPointer(t, 4, GL_UNSIGNED_BYTE, 0, col);
    tsr_call_EnableClientState(t, GL_VERTEX_ARRAY);
    tsr_call_EnableClientState(t, GL_COLOR_ARRAY);
    tsr_call_DrawArrays(t, GL_POINTS, 2, 12);
    tsr_packer_flush(rt.packer);
    tsr_call_DrawElements(t, GL_LINES, 4, GL_UNSIGNED_BYTE, idx);
    tsr_packer_flush(rt.packer);
    tsr_call_ShaderSource(t, 1, 3, src, len);
    tsr_packer_flush(rt.packer);
    CHECK(rt.nbufs > 5, "buffers");
    int ok = 0, rejected = 0;
    for (size_t i = 0; i < rt.nbufs; i++) {
        uint8_t *m = malloc(rt.sizes[i]);
        for (int k = 0; k < 300; k++) {
            memcpy(m, rt.bufs[i], rt.sizes[i]);
            size_t n = rt.sizes[i];
            uint64_t r = tsr_wire_test_rand(&rng);
            size_t at = (size_t)(tsr_wire_test_rand(&rng) % n);
            switch (r % 4) {
            case 0: m[at] ^= (uint8_t)(1u << (r >> 8) % 8); break;
            case 1: n = at; break;
            case 2: m[at] = (uint8_t)(r >> 16); break;
            default:
                if (at + 8 <= n)
                    tsr_wire_put_u64(m + at, r >> 3);
                break;
            }
            int rc = tsr_unpack_fuzz_one(m, n);
            CHECK(rc == 0 || rc == TSR_EPROTO, "mutation %d of buffer %zu: rc %d", k, i, rc);
            if (rc)
                rejected++;
            else
                ok++;
        }
        free(m);
    }
    fprintf(stderr, "%d mutated buffers decoded, %d rejected\n", ok, rejected);
    CHECK(rejected > 0, "mutations must be noticed");
    rt_free(&rt);
    return 0;
}

/* --- SPUs ------------------------------------------------------------------------- */

static int read_file(const char *path, char *buf, size_t size)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    size_t n = fread(buf, 1, size - 1, f);
    buf[n] = '\0';
    fclose(f);
    return 0;
}

static void draw_something(void)
{
    static const GLfloat light[4] = {0.5f, 1, 0, 0};
    glLightfv(GL_LIGHT0, GL_POSITION, light);
    glBegin(GL_TRIANGLES);
    glColor3ub(255, 0, 7);
    glVertex3f(1, 2.5f, -3);
    glEnd();
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    GLuint tex[2] = {0, 0};
    glGenTextures(2, tex);
    glFinish();
}

static int wire_print_spu_traces_calls(void)
{
    const char *direct = "wire_print_direct.txt", *looped = "wire_print_looped.txt";
    char text[256];
    tsr_error err;
    snprintf(text, sizeof text, "print file=%s", direct);
    tsr_chain *c = tsr_chain_create(text, &err);
    CHECK(c, "%s", err.message);
    tsr_gl_make_current(tsr_chain_head(c));
    draw_something();
    tsr_gl_make_current(NULL);
    tsr_chain_destroy(c);
    snprintf(text, sizeof text, "loopback buffer_size=256 ! print file=%s", looped);
    c = tsr_chain_create(text, &err);
    CHECK(c, "%s", err.message);
    tsr_gl_make_current(tsr_chain_head(c));
    draw_something();
    tsr_gl_make_current(NULL);
    tsr_chain_destroy(c);
    static char a[8192], b[8192];
    CHECK(read_file(direct, a, sizeof a) == 0 && read_file(looped, b, sizeof b) == 0, "trace files");
    fputs(a, stderr);
    CHECK(strstr(a, "glVertex3f(1, 2.5, -3)\n") && strstr(a, "glBegin(GL_TRIANGLES)\n") &&
              strstr(a, "glLightfv(GL_LIGHT0, GL_POSITION, {0.5, 1, 0, 0})\n") && strstr(a, "glColor3ub(255, 0, 7)\n"),
          "readable trace lines");
    CHECK(!strcmp(a, b), "the loopback SPU delivers the same calls:\n%s", b);
    return 0;
}


/* --- the in-process wire (tessera/dev/wireloop.h) ---------------------------------- */

static int wire_reply_slot_hands_out_only_the_reply_asked_for(void)
{
    tsr_reply_slot slot = {0};
    tsr_error err = {0};
    const uint8_t *data;
    size_t size;
    CHECK(tsr_reply_slot_take(&slot, "loop#1", 1, &data, &size, &err) == TSR_EPROTO, "an empty slot has no reply");
    CHECK(tsr_reply_slot_store(&slot, 5, (const uint8_t *)"abc", 3, &err) == TSR_OK, "%s", err.message);
    CHECK(tsr_reply_slot_take(&slot, "loop#1", 4, &data, &size, &err) == TSR_EPROTO, "request 4 was not answered");
    CHECK(strstr(err.message, "loop#1") && strstr(err.message, "request 4"), "the error names both: %s", err.message);
    CHECK(tsr_reply_slot_take(&slot, "loop#1", 5, &data, &size, &err) == TSR_OK && size == 3 && !memcmp(data, "abc", 3),
          "the reply to request 5");
    CHECK(tsr_reply_slot_take(&slot, "loop#1", 5, &data, &size, &err) == TSR_EPROTO, "a reply is taken once");
    tsr_reply_slot_free(&slot);
    CHECK(tsr_reply_slot_store(&slot, 6, NULL, 0, &err) == TSR_OK, "%s", err.message);
    CHECK(tsr_reply_slot_take(&slot, "loop#1", 6, &data, &size, &err) == TSR_OK && data && size == 0,
          "an empty reply still gets a valid pointer");
    tsr_reply_slot_free(&slot);
    return 0;
}

typedef struct loop_watch {
    size_t buffers, bytes, replies;
} loop_watch;

static void watch_buffer(void *ctx, const uint8_t *buf, size_t size)
{
    loop_watch *w = ctx;
    (void)buf;
    w->buffers++;
    w->bytes += size;
}

static void watch_reply(void *ctx, uint32_t id, const uint8_t *data, size_t size)
{
    (void)id, (void)data, (void)size;
    ((loop_watch *)ctx)->replies++;
}

static int wire_loop_shows_its_observer_every_buffer_and_reply_and_destroy_flushes(void)
{
    const char *trace = "wire_loop_trace.txt";
    char text[128];
    snprintf(text, sizeof text, "print file=%s", trace);
    tsr_error err = {0};
    tsr_chain *child = tsr_chain_create(text, &err);
    CHECK(child, "%s", err.message);
    loop_watch w = {0};
    tsr_wire_loop_observer observer = {.buffer = watch_buffer, .reply = watch_reply, .ctx = &w};
    tsr_wire_loop *loop = tsr_wire_loop_create("loop#test", 4096, tsr_chain_head(child), &observer, &err);
    CHECK(loop, "%s", err.message);
    tsr_dispatch table;
    tsr_wire_loop_fill_dispatch(loop, &table);
    tsr_gl_make_current(&table);
    glBegin(GL_POINTS);
    glVertex3f(1, 2, 3);
    glEnd();
    CHECK(w.buffers == 0, "nothing flushed yet");
    CHECK(tsr_wire_loop_flush(loop) == 0, "flush");
    CHECK(w.buffers == 1 && w.bytes > 0, "one buffer seen (%zu)", w.buffers);
    GLuint lists = glGenLists(2); /* a request: the child's answer comes back through the loop */
    CHECK(w.replies == 1, "the reply was observed (%zu)", w.replies);
    (void)lists;
    glColor3ub(1, 2, 3);
    tsr_gl_make_current(NULL);
    size_t before_destroy = w.buffers;
    tsr_wire_loop_destroy(loop);
    CHECK(w.buffers == before_destroy + 1, "destroy flushed the pending colour");
    tsr_chain_destroy(child);
    static char got[4096];
    CHECK(read_file(trace, got, sizeof got) == 0, "trace file");
    CHECK(strstr(got, "glVertex3f(1, 2, 3)\n") && strstr(got, "glGenLists(2)") && strstr(got, "glColor3ub(1, 2, 3)\n"),
          "the child got every call:\n%s", got);
    return 0;
}

static const struct {
    const char *name;
    int (*fn)(void);
} tests[] = {
    {"wire_roundtrip_all_commands", wire_roundtrip_all_commands},
    {"wire_vertex3f_is_13_bytes", wire_vertex3f_is_13_bytes},
    {"wire_extended_opcode_roundtrip", wire_extended_opcode_roundtrip},
    {"wire_commands_exactly_fill_a_buffer", wire_commands_exactly_fill_a_buffer},
    {"wire_large_command_gets_its_own_buffer", wire_large_command_gets_its_own_buffer},
    {"wire_begin_end_split_across_buffers", wire_begin_end_split_across_buffers},
    {"wire_client_arrays_draw_arrays_rebuild", wire_client_arrays_draw_arrays_rebuild},
    {"wire_client_arrays_draw_elements_rebuild", wire_client_arrays_draw_elements_rebuild},
    {"wire_enable_of_a_client_array_is_client_state", wire_enable_of_a_client_array_is_client_state},
    {"wire_query_of_an_unknown_pname_is_invalid_enum_not_a_dropped_stream",
     wire_query_of_an_unknown_pname_is_invalid_enum_not_a_dropped_stream},
    {"wire_setter_of_an_unknown_pname_is_invalid_enum_not_a_dropped_call",
     wire_setter_of_an_unknown_pname_is_invalid_enum_not_a_dropped_call},
    {"wire_pixel_command_gl_refuses_is_its_gl_error_not_sent_nor_read",
     wire_pixel_command_gl_refuses_is_its_gl_error_not_sent_nor_read},
    {"wire_shader_source_roundtrip", wire_shader_source_roundtrip},
    {"wire_pixel_store_shapes_image_payloads", wire_pixel_store_shapes_image_payloads},
    {"wire_unpack_rejects_unknown_opcode", wire_unpack_rejects_unknown_opcode},
    {"wire_unpack_rejects_truncated_command", wire_unpack_rejects_truncated_command},
    {"wire_unpack_rejects_length_beyond_buffer", wire_unpack_rejects_length_beyond_buffer},
    {"wire_unpack_rejects_count_overflow", wire_unpack_rejects_count_overflow},
    {"wire_unpack_rejects_negative_size", wire_unpack_rejects_negative_size},
    {"wire_unpack_rejects_bad_header", wire_unpack_rejects_bad_header},
    {"wire_unpack_survives_mutations", wire_unpack_survives_mutations},
    {"wire_print_spu_traces_calls", wire_print_spu_traces_calls},
    {"wire_reply_slot_hands_out_only_the_reply_asked_for", wire_reply_slot_hands_out_only_the_reply_asked_for},
    {"wire_loop_shows_its_observer_every_buffer_and_reply_and_destroy_flushes",
     wire_loop_shows_its_observer_every_buffer_and_reply_and_destroy_flushes},
};

int main(int argc, char **argv)
{
    int failed = 0, ran = 0;
    for (size_t i = 0; i < sizeof tests / sizeof tests[0]; i++) {
        if (argc > 1 && strcmp(argv[1], tests[i].name) != 0)
            continue;
        ran++;
        int rc = tests[i].fn();
        fprintf(stderr, "%s: %s\n", tests[i].name, rc ? "FAILED" : "ok");
        failed += rc != 0;
    }
    if (!ran) {
        fprintf(stderr, "unknown test %s\n", argc > 1 ? argv[1] : "");
        return 2;
    }
    return failed ? 1 : 0;
}
