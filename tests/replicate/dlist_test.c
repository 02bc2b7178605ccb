/* tests/replicate/dlist_test.c — the display-list recorder (tessera/dev/dlist.h)
 * that late joiners (client/join.h) use, with the real packer, unpacker and
 * state tracker:
 *   define_all_is_byte_exact  a list defined again through a packer is
 *                             the same wire bytes as the application's
 *   call_equals_direct        calling lists (nested, CallLists with a
 *                             base, COMPILE_AND_EXECUTE) leaves a tracker
 *                             in the same state as making the calls
 *                             directly; GL_COMPILE alone changes nothing
 *   immediate_and_delete      commands GL runs at once while compiling
 *                             (PixelStore) reach the tracker, the body
 *                             starts with the unpack store it needs, and
 *                             DeleteLists forgets bodies
 * usage: dlist_test NAME */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/dev/dlist.h"
#include "tessera/dev/pack.h"
#include "tessera/dev/state.h"
#include "tessera/dev/unpack.h"

#include "harness.h"

typedef struct mem {
    uint8_t *b;
    size_t n;
} mem;

static int mem_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    (void)err;
    mem *m = ctx;
    uint8_t *p = realloc(m->b, m->n + size);
    if (!p)
        return TSR_ENOMEM;
    memcpy(p + m->n, buf, size);
    m->b = p;
    m->n += size;
    return TSR_OK;
}

typedef struct packed {
    tsr_packer *p;
    tsr_dispatch d;
    mem m;
} packed;

static void packed_init(packed *k)
{
    tsr_error err = {0};
    memset(k, 0, sizeof *k);
    tsr_pack_sink sink = {.flush = mem_flush, .ctx = &k->m};
    k->p = tsr_packer_create(1 << 20, &sink, &err);
    if (!k->p) {
        fprintf(stderr, "packer: %s\n", err.message);
        exit(1);
    }
    tsr_packer_fill_dispatch(k->p, &k->d);
}

static void packed_free(packed *k)
{
    tsr_packer_destroy(k->p);
    free(k->m.b);
}

/* Runs every buffer of `m` (concatenated wire buffers) into `target`. */
static void run_all(const mem *m, const tsr_dispatch *target)
{
    tsr_error err = {0};
    tsr_unpacker *u = tsr_unpacker_create(target, NULL, NULL, &err);
    for (size_t pos = 0; u && pos < m->n;) {
        size_t size = tsr_wire_buffer_size(m->b + pos, m->n - pos, &err);
        CHECK(size && tsr_unpacker_run(u, m->b + pos, size, &err) == TSR_OK, "unpack: %s", err.message);
        if (!size)
            break;
        pos += size;
    }
    tsr_unpacker_destroy(u);
}

static void sphere_body(const tsr_dispatch *d)
{
    for (int i = 0; i < 12; i++) {
        tsr_call_Begin(d, GL_QUAD_STRIP);
        for (int j = 0; j <= 24; j++) {
            float a = (float)j * 0.26f + (float)i * 0.37f;
            tsr_call_Normal3f(d, cosf(a), sinf(a), cosf(a * 1.7f));
            tsr_call_Vertex3f(d, sinf(a), cosf(a), a);
        }
        tsr_call_End(d);
    }
    GLfloat spec[4] = {0.9f, 0.8f, 0.7f, 1};
    tsr_call_Materialfv(d, GL_FRONT, GL_SPECULAR, spec);
    tsr_call_Color4f(d, 0.25f, 0.5f, 0.75f, 1);
}

static void define_all_is_byte_exact(void)
{
    packed app, again;
    packed_init(&app);
    packed_init(&again);
    tsr_call_NewList(&app.d, 7, GL_COMPILE);
    sphere_body(&app.d);
    tsr_call_CallList(&app.d, 3);
    tsr_call_EndList(&app.d);
    tsr_packer_flush(app.p);

    tsr_error err = {0};
    tsr_dispatch nop;
    tsr_dispatch_fill_nop(&nop);
    tsr_dlist_store *s = tsr_dlist_create(&nop, &err);
    CHECK(s != NULL, "create: %s", err.message);
    run_all(&app.m, tsr_dlist_table(s));
    CHECK(tsr_dlist_count(s) == 1 && tsr_dlist_has(s, 7), "one list, 7, recorded (count %zu)", tsr_dlist_count(s));
    CHECK(tsr_dlist_define_all(s, &again.d, &err) == 1, "define_all: %s", err.message);
    tsr_packer_flush(again.p);
    CHECK(again.m.n == app.m.n && !memcmp(again.m.b, app.m.b, app.m.n),
          "defined again: %zu bytes, the application's: %zu, or they differ", again.m.n, app.m.n);
    tsr_dlist_destroy(s);
    packed_free(&app);
    packed_free(&again);
}

/* The calls of the lists below, made directly. */
static void direct_calls(const tsr_dispatch *d, int times)
{
    for (int t = 0; t < times; t++) {
        tsr_call_Translatef(d, 1, 2, 3);
        tsr_call_Color4f(d, 0.1f, 0.2f, 0.3f, 0.4f);
        tsr_call_Rotatef(d, 30, 0, 1, 0); /* list 11, called by list 10 */
        tsr_call_Normal3f(d, 0, 1, 0);
        GLfloat amb[4] = {0.3f, 0.2f, 0.1f, 1};
        tsr_call_Materialfv(d, GL_FRONT, GL_AMBIENT, amb);
        tsr_call_Enable(d, GL_LIGHTING);
    }
}

typedef struct caller {
    tsr_dlist_store *s;
    tsr_dispatch table;
} caller;

static void caller_CallList(void *self, GLuint list)
{
    caller *c = self;
    tsr_error err = {0};
    CHECK(tsr_dlist_call(c->s, list, &c->table, &err) == TSR_OK, "call %u: %s", list, err.message);
}

static void caller_CallLists(void *self, GLsizei n, GLenum type, const void *lists)
{
    CHECK(type == GL_UNSIGNED_BYTE, "CallLists type 0x%x", type);
    for (GLsizei i = 0; i < n; i++)
        caller_CallList(self, 9u + ((const GLubyte *)lists)[i]); /* the base the test set */
}

/* Every value, and the matrix the lists change (top and depth). */
static int same_state(tsr_state_ctx *a, tsr_state_ctx *b)
{
    return !memcmp(tsr_state_values_of(a), tsr_state_values_of(b), sizeof(tsr_state_values)) &&
           !memcmp(tsr_state_modelview(a), tsr_state_modelview(b), 16 * sizeof(GLfloat)) &&
           tsr_state_stacks_of(a)->modelview_depth == tsr_state_stacks_of(b)->modelview_depth;
}

static void call_equals_direct(void)
{
    tsr_error err = {0};
    tsr_state_tracker *t = tsr_state_tracker_create(&err);
    tsr_state_ctx *direct = tsr_state_ctx_create(t, &err), *listed = tsr_state_ctx_create(t, &err);
    tsr_dispatch dd;
    tsr_dispatch_fill_nop(&dd);
    tsr_state_fill_dispatch(direct, &dd);
    caller c;
    tsr_dispatch_fill_nop(&c.table);
    tsr_state_fill_dispatch(listed, &c.table);
    tsr_set_CallList(&c.table, caller_CallList, &c);
    tsr_set_CallLists(&c.table, caller_CallLists, &c);
    c.s = tsr_dlist_create(&c.table, &err);
    const tsr_dispatch *in = tsr_dlist_table(c.s);

    /* list 11: a rotation; list 10: translate, colour, list 11, normal,
     * material, enable. Compiling changes nothing. */
    tsr_call_NewList(in, 11, GL_COMPILE);
    tsr_call_Rotatef(in, 30, 0, 1, 0);
    tsr_call_EndList(in);
    tsr_call_NewList(in, 10, GL_COMPILE);
    tsr_call_Translatef(in, 1, 2, 3);
    tsr_call_Color4f(in, 0.1f, 0.2f, 0.3f, 0.4f);
    tsr_call_CallList(in, 11);
    tsr_call_Normal3f(in, 0, 1, 0);
    GLfloat amb[4] = {0.3f, 0.2f, 0.1f, 1};
    tsr_call_Materialfv(in, GL_FRONT, GL_AMBIENT, amb);
    tsr_call_Enable(in, GL_LIGHTING);
    tsr_call_EndList(in);
    CHECK(same_state(direct, listed), "compiling lists changed the tracked state");

    tsr_call_CallList(in, 10);
    direct_calls(&dd, 1);
    CHECK(same_state(direct, listed), "after glCallList(10) (nesting 11) the states differ");

    GLubyte names[2] = {1, 1}; /* 9 + 1 = list 10, twice */
    tsr_call_CallLists(in, 2, GL_UNSIGNED_BYTE, names);
    direct_calls(&dd, 2);
    CHECK(same_state(direct, listed), "after glCallLists the states differ");

    /* GL_COMPILE_AND_EXECUTE: recorded and run once. */
    tsr_call_NewList(in, 12, GL_COMPILE_AND_EXECUTE);
    tsr_call_CallList(in, 10);
    tsr_call_EndList(in);
    direct_calls(&dd, 1);
    CHECK(same_state(direct, listed), "after glNewList(GL_COMPILE_AND_EXECUTE) the states differ");
    CHECK(tsr_dlist_count(c.s) == 3, "3 lists recorded, not %zu", tsr_dlist_count(c.s));

    tsr_dlist_destroy(c.s);
    tsr_state_tracker_destroy(t);
}

static void immediate_and_delete(void)
{
    tsr_error err = {0};
    tsr_state_tracker *t = tsr_state_tracker_create(&err);
    tsr_state_ctx *ctx = tsr_state_ctx_create(t, &err);
    tsr_dispatch next;
    tsr_dispatch_fill_nop(&next);
    tsr_state_fill_dispatch(ctx, &next);
    tsr_dlist_store *s = tsr_dlist_create(&next, &err);
    const tsr_dispatch *in = tsr_dlist_table(s);

    /* A bitmap in a list under a non-default unpack alignment set before
     * the list: the body must say so, or it decodes to other bytes. */
    packed app, again;
    packed_init(&app);
    packed_init(&again);
    tsr_call_PixelStorei(&app.d, GL_UNPACK_ALIGNMENT, 1);
    tsr_call_NewList(&app.d, 5, GL_COMPILE);
    static const GLubyte bits[3 * 5] = {0xff, 0x81, 0xff, 0x42, 0x24, 0x18, 0x81, 0x42,
                                        0x24, 0x18, 0xff, 0x00, 0xaa, 0x55, 0xaa};
    tsr_call_Bitmap(&app.d, 20, 5, 0, 0, 21, 0, bits);
    tsr_call_PixelStorei(&app.d, GL_UNPACK_ROW_LENGTH, 24); /* runs at once: reaches the tracker now */
    tsr_call_EndList(&app.d);
    tsr_packer_flush(app.p);
    run_all(&app.m, in);
    GLint v = 0;
    CHECK(tsr_state_get_integerv(ctx, GL_UNPACK_ROW_LENGTH, &v) && v == 24,
          "glPixelStore inside glNewList did not reach the tracker (row length %d)", v);
    CHECK(tsr_dlist_has(s, 5), "list 5 not recorded");
    CHECK(tsr_dlist_define_all(s, &again.d, &err) == 1, "define_all: %s", err.message);
    tsr_packer_flush(again.p);
    /* Decoding the definition with a fresh unpacker (default store) must
     * give the application's bitmap bytes: record what Bitmap receives. */
    packed check;
    packed_init(&check);
    tsr_dispatch nop;
    tsr_dispatch_fill_nop(&nop);
    tsr_dlist_store *s2 = tsr_dlist_create(&nop, &err);
    run_all(&again.m, tsr_dlist_table(s2));
    CHECK(tsr_dlist_define_all(s2, &check.d, &err) == 1, "define_all (again): %s", err.message);
    tsr_packer_flush(check.p);
    CHECK(check.m.n == again.m.n && !memcmp(check.m.b, again.m.b, again.m.n),
          "a definition decoded and defined again is not the same bytes");
    /* ... and the renderer's pixel store ends at GL's defaults. */
    tsr_pixel_store defaults;
    tsr_pixel_store_init(&defaults);
    CHECK(!memcmp(&again.p->pixels, &defaults, sizeof defaults),
          "after define_all the renderer's pixel store is not GL's default");

    tsr_call_DeleteLists(in, 1, 100);
    CHECK(tsr_dlist_count(s) == 0 && !tsr_dlist_has(s, 5), "DeleteLists(1, 100) left %zu lists", tsr_dlist_count(s));
    CHECK(!tsr_state_is_list(ctx, 5), "the tracker still knows list 5");

    tsr_dlist_destroy(s2);
    tsr_dlist_destroy(s);
    packed_free(&app);
    packed_free(&again);
    packed_free(&check);
    tsr_state_tracker_destroy(t);
}

int main(int argc, char **argv)
{
    static const struct {
        const char *name;
        void (*fn)(void);
    } tests[] = {
        {"define_all_is_byte_exact", define_all_is_byte_exact},
        {"call_equals_direct", call_equals_direct},
        {"immediate_and_delete", immediate_and_delete},
    };
    for (size_t i = 0; argc == 2 && i < sizeof tests / sizeof tests[0]; i++)
        if (!strcmp(argv[1], tests[i].name)) {
            tests[i].fn();
            if (harness_failures)
                return 1;
            printf("PASS: dlist %s\n", argv[1]);
            return 0;
        }
    fprintf(stderr, "usage: dlist_test define_all_is_byte_exact|call_equals_direct|immediate_and_delete\n");
    return 2;
}
