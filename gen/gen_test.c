/* gen/gen_test.c — emits wire test support (src/wire_test_gen.[ch]), built
 * only into tests: a recording table (every slot records its name, argument
 * bytes and pointed-to bytes, and writes a deterministic pattern into its
 * outputs, standing in for GL) and, per packable command, a call with
 * random but valid arguments made identically on two tables so their
 * recordings and outputs can be compared byte for byte. */
#include "gen.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

static int is_pixel_store(const spec_command *c)
{
    return !strcmp(c->name, "PixelStorei") || !strcmp(c->name, "PixelStoref");
}

static const spec_param *depth2_length(const spec_command *c)
{
    for (size_t i = 0; i < c->nparams; i++)
        if (!strcmp(c->params[i].name, "length") && c->params[i].pointer_depth == 1)
            return &c->params[i];
    return NULL;
}

static void emit_out_fill(FILE *f, const gen_cmd *gc, const gen_param *gp, int slot)
{
    const spec_param *sp = gp->sp;
    const spec_count *k = &sp->count;
    gen_emit_count(f, gc, gp, "&tsr_r->pixels.pack");
    if (k->kind == SPEC_COUNT_IMAGE || k->kind == SPEC_COUNT_BITMAP) {
        const char *h = k->args[1];
        const char *d = k->kind == SPEC_COUNT_IMAGE ? k->args[2] : "1";
        fprintf(
            f,
            "    (void)tsr_len_%s;\n    if (%s)\n        fill_spans(&tsr_lay_%s, (int64_t)(%s), (int64_t)(%s), %s, %d);\n",
            sp->name, sp->name, sp->name, h, d, sp->name, slot);
    } else {
        fprintf(f, "    if (%s)\n        fill_pattern(%s, tsr_len_%s, %d);\n", sp->name, sp->name, sp->name, slot);
    }
}

static void emit_recorder(FILE *f, const gen *g)
{
    for (size_t i = 0; i < g->ncmds; i++) {
        const gen_cmd *gc = &g->cmds[i];
        const spec_command *c = gc->sc;
        fprintf(f, "static %s rc_%s(", c->ret, c->name);
        gen_print_params(f, c, 1, 0);
        fprintf(f, ")\n{\n    tsr_recorder *tsr_r = self;\n    rec_buf tsr_b = {0};\n    const char *tsr_why = NULL;\n"
                   "    (void)tsr_why;\n");
        for (size_t k = 0; k < c->nparams; k++) {
            const spec_count *ck = &c->params[k].count;
            if (c->params[k].pointer_depth == 1 && (ck->kind == SPEC_COUNT_IMAGE || ck->kind == SPEC_COUNT_BITMAP))
                fprintf(f, "    tsr_pixel_layout tsr_lay_%s;\n", c->params[k].name);
        }
        fprintf(f, "    rb_put(&tsr_b, \"%s\", %zu);\n", c->name, strlen(c->name) + 1);
        for (size_t k = 0; k < c->nparams; k++) {
            const spec_param *sp = &c->params[k];
            gen_param tmp = {.sp = sp, .type = gen_type_find(sp->base_type)};
            tmp.elem_size = tmp.type ? tmp.type->size : 1;
            if (sp->pointer_depth == 0) {
                fprintf(f, "    rb_put(&tsr_b, &%s, sizeof %s);\n", sp->name, sp->name);
            } else if (sp->dir_out) {
                fprintf(f, "    rb_u8(&tsr_b, %s ? 2 : 0);\n", sp->name);
            } else if (sp->pointer_depth == 2 && sp->count.kind == SPEC_COUNT_EXPR) {
                const spec_param *len = depth2_length(c);
                fprintf(f, "    if (!%s) {\n        rb_u8(&tsr_b, 0);\n    } else {\n        rb_u8(&tsr_b, 1);\n",
                        sp->name);
                fprintf(f, "        for (int64_t i = 0; i < (int64_t)(%s); i++) {\n", sp->count.args[0]);
                if (len)
                    fprintf(f, "            uint64_t n = %s && %s[i] >= 0 ? (uint64_t)%s[i] : strlen(%s[i]);\n",
                            len->name, len->name, len->name, sp->name);
                else
                    fprintf(f, "            uint64_t n = strlen(%s[i]);\n", sp->name);
                fprintf(
                    f,
                    "            rb_put(&tsr_b, &n, 8);\n            rb_put(&tsr_b, %s[i], (size_t)n);\n        }\n    }\n",
                    sp->name);
            } else if (sp->count.kind == SPEC_COUNT_NONE || sp->pointer_depth == 2) {
                fprintf(f, "    { uintptr_t v = (uintptr_t)%s; rb_put(&tsr_b, &v, sizeof v); }\n", sp->name);
            } else {
                fprintf(f, "    if (!%s) {\n        rb_u8(&tsr_b, 0);\n    } else {\n", sp->name);
                gen_emit_count(f, gc, &tmp, "&tsr_r->pixels.unpack");
                fprintf(
                    f,
                    "    rb_u8(&tsr_b, 1);\n    rb_put(&tsr_b, &tsr_len_%s, 8);\n    rb_put(&tsr_b, %s, (size_t)tsr_len_%s);\n    }\n",
                    sp->name, sp->name, sp->name);
            }
        }
        for (size_t k = 0; k < c->nparams; k++) {
            const spec_param *sp = &c->params[k];
            if (!sp->dir_out || sp->count.kind == SPEC_COUNT_NONE || sp->pointer_depth != 1)
                continue;
            gen_param tmp = {.sp = sp, .type = gen_type_find(sp->base_type)};
            tmp.elem_size = tmp.type ? tmp.type->size : 1;
            fprintf(f, "    {\n");
            emit_out_fill(f, gc, &tmp, gc->slot);
            fprintf(f, "    }\n");
        }
        if (is_pixel_store(c))
            fprintf(f, "    tsr_pixel_store_set(&tsr_r->pixels, pname, (double)param);\n");
        fprintf(
            f,
            "    goto tsr_done;\ntsr_invalid:\n    rb_u8(&tsr_b, 0xEE);\n    rb_put(&tsr_b, tsr_why, strlen(tsr_why));\n"
            "tsr_done:\n    rec_add(tsr_r, %d, &tsr_b);\n",
            gc->slot);
        if (gen_is_void(c->ret))
            fprintf(f, "}\n");
        else if (strchr(c->ret, '*'))
            fprintf(f, "    return (%s)\"tessera recorder %s\";\n}\n", c->ret, c->name);
        else
            fprintf(f, "    return (%s)%d;\n}\n", c->ret, gc->slot % 2 ? gc->slot * 7 + 3 : 1);
    }
    fprintf(f, "\nvoid tsr_recorder_fill(tsr_dispatch *d, tsr_recorder *r)\n{\n");
    for (size_t i = 0; i < g->ncmds; i++)
        fprintf(f, "    tsr_set_%s(d, rc_%s, r);\n", g->cmds[i].sc->name, g->cmds[i].sc->name);
    fprintf(f, "}\n\n");
}

/* Roles of scalar parameters in a random call. */
enum role {
    R_RANDOM,
    R_SMALL,
    R_PNAME,
    R_WH,
    R_DEPTH,
    R_BITMAP,
    R_FORMAT,
    R_TYPE,
    R_TYPED_TYPE,
    R_BYTES,
    R_MAP_TARGET,
    R_MAP_STRIDE,
    R_MAP_ORDER
};

static enum role role_of(const spec_command *c, const char *name)
{
    for (size_t i = 0; i < c->nparams; i++) {
        const spec_count *k = &c->params[i].count;
        for (size_t a = 0; a < k->nargs; a++) {
            if (strcmp(k->args[a], name) != 0)
                continue;
            switch (k->kind) {
            case SPEC_COUNT_EXPR: return R_SMALL;
            case SPEC_COUNT_PNAME: return R_PNAME;
            case SPEC_COUNT_IMAGE: return a < 2 ? R_WH : a == 2 ? R_DEPTH : a == 3 ? R_FORMAT : R_TYPE;
            case SPEC_COUNT_BITMAP: return R_BITMAP;
            case SPEC_COUNT_TYPED: return a == 0 ? R_SMALL : R_TYPED_TYPE;
            case SPEC_COUNT_BYTES: return R_BYTES;
            case SPEC_COUNT_MAP: return a == 0 ? R_MAP_TARGET : a % 2 ? R_MAP_STRIDE : R_MAP_ORDER;
            default: break;
            }
        }
    }
    return R_RANDOM;
}


/* glGet* pnames of client-array state: a packer answers them from its
 * mirrors (core/wire/pack_mirror.c, client_gets) without sending the
 * call, so a round trip of random pnames leaves them out; one the mirror
 * answers and this list lacks fails wire_roundtrip_all_commands. */
static int answered_by_packer(const char *pname)
{
    static const char *const names[] = {"GL_CLIENT_ACTIVE_TEXTURE",
                                        "GL_VERTEX_ARRAY",
                                        "GL_NORMAL_ARRAY",
                                        "GL_COLOR_ARRAY",
                                        "GL_EDGE_FLAG_ARRAY",
                                        "GL_SECONDARY_COLOR_ARRAY",
                                        "GL_FOG_COORD_ARRAY",
                                        "GL_INDEX_ARRAY",
                                        "GL_TEXTURE_COORD_ARRAY",
                                        "GL_VERTEX_ARRAY_SIZE",
                                        "GL_VERTEX_ARRAY_TYPE",
                                        "GL_VERTEX_ARRAY_STRIDE",
                                        "GL_VERTEX_ARRAY_BUFFER_BINDING",
                                        "GL_NORMAL_ARRAY_TYPE",
                                        "GL_NORMAL_ARRAY_STRIDE",
                                        "GL_NORMAL_ARRAY_BUFFER_BINDING",
                                        "GL_COLOR_ARRAY_SIZE",
                                        "GL_COLOR_ARRAY_TYPE",
                                        "GL_COLOR_ARRAY_STRIDE",
                                        "GL_COLOR_ARRAY_BUFFER_BINDING",
                                        "GL_EDGE_FLAG_ARRAY_STRIDE",
                                        "GL_EDGE_FLAG_ARRAY_BUFFER_BINDING",
                                        "GL_SECONDARY_COLOR_ARRAY_SIZE",
                                        "GL_SECONDARY_COLOR_ARRAY_TYPE",
                                        "GL_SECONDARY_COLOR_ARRAY_STRIDE",
                                        "GL_SECONDARY_COLOR_ARRAY_BUFFER_BINDING",
                                        "GL_FOG_COORD_ARRAY_TYPE",
                                        "GL_FOG_COORD_ARRAY_STRIDE",
                                        "GL_FOG_COORD_ARRAY_BUFFER_BINDING",
                                        "GL_INDEX_ARRAY_TYPE",
                                        "GL_INDEX_ARRAY_STRIDE",
                                        "GL_INDEX_ARRAY_BUFFER_BINDING",
                                        "GL_TEXTURE_COORD_ARRAY_SIZE",
                                        "GL_TEXTURE_COORD_ARRAY_TYPE",
                                        "GL_TEXTURE_COORD_ARRAY_STRIDE",
                                        "GL_TEXTURE_COORD_ARRAY_BUFFER_BINDING"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!strcmp(names[i], pname))
            return 1;
    return 0;
}
static void emit_random_call(FILE *f, const gen_cmd *gc)
{
    const spec_command *c = gc->sc;
    fprintf(
        f,
        "static int tc_%s(const tsr_dispatch *tsr_e, const tsr_dispatch *tsr_x, uint64_t *rng, char *msg, size_t msgsz)\n{\n"
        "    const char *tsr_why = NULL;\n    int tsr_rc = 0;\n    void *tsr_mem[16];\n    int tsr_nmem = 0;\n"
        "    tsr_pixel_store tsr_ps;\n    tsr_pixel_store_init(&tsr_ps);\n"
        "    const int tsr_pair = (int)(tsr_wire_test_rand(rng) %% PIXEL_PAIRS);\n    (void)tsr_pair;\n",
        c->name);
    for (size_t k = 0; k < c->nparams; k++) {
        const spec_count *ck = &c->params[k].count;
        if (c->params[k].pointer_depth == 1 && (ck->kind == SPEC_COUNT_IMAGE || ck->kind == SPEC_COUNT_BITMAP))
            fprintf(f, "    tsr_pixel_layout tsr_lay_%s;\n", c->params[k].name);
    }
    /* Map targets first: strides depend on them. */
    for (size_t k = 0; k < c->nparams; k++) {
        const spec_param *sp = &c->params[k];
        if (sp->pointer_depth)
            continue;
        if (role_of(c, sp->name) == R_MAP_TARGET)
            fprintf(f, "    %s %s = map_targets[tsr_wire_test_rand(rng) %% MAP_TARGETS];\n", sp->type, sp->name);
    }
    for (size_t k = 0; k < c->nparams; k++) {
        const spec_param *sp = &c->params[k];
        if (sp->pointer_depth)
            continue;
        const char *n = sp->name;
        const char *t = sp->type;
        switch (role_of(c, n)) {
        case R_MAP_TARGET: break;
        case R_SMALL: fprintf(f, "    %s %s = (%s)(tsr_wire_test_rand(rng) %% 5);\n", t, n, t); break;
        case R_PNAME: fprintf(f, "    %s %s = (%s)pnames[tsr_wire_test_rand(rng) %% PNAMES];\n", t, n, t); break;
        case R_WH: fprintf(f, "    %s %s = (%s)(tsr_wire_test_rand(rng) %% 6);\n", t, n, t); break;
        case R_DEPTH: fprintf(f, "    %s %s = (%s)(tsr_wire_test_rand(rng) %% 3);\n", t, n, t); break;
        case R_BITMAP: fprintf(f, "    %s %s = (%s)(tsr_wire_test_rand(rng) %% 21);\n", t, n, t); break;
        case R_FORMAT: fprintf(f, "    %s %s = (%s)pixel_pairs[tsr_pair][0];\n", t, n, t); break;
        case R_TYPE: fprintf(f, "    %s %s = (%s)pixel_pairs[tsr_pair][1];\n", t, n, t); break;
        case R_TYPED_TYPE:
            fprintf(f, "    %s %s = (%s)typed_types[tsr_wire_test_rand(rng) %% TYPED_TYPES];\n", t, n, t);
            break;
        case R_BYTES: fprintf(f, "    %s %s = (%s)(tsr_wire_test_rand(rng) %% 41);\n", t, n, t); break;
        case R_MAP_ORDER: fprintf(f, "    %s %s = (%s)(1 + tsr_wire_test_rand(rng) %% 4);\n", t, n, t); break;
        case R_MAP_STRIDE: {
            const char *target = NULL;
            for (size_t i = 0; i < c->nparams; i++)
                if (c->params[i].count.kind == SPEC_COUNT_MAP)
                    target = c->params[i].count.args[0];
            fprintf(f, "    %s %s = (%s)(tsr_wire_map_components((GLenum)%s) + (int)(tsr_wire_test_rand(rng) %% 3));\n",
                    t, n, t, target);
            break;
        }
        case R_RANDOM:
            fprintf(f,
                    "    %s %s;\n    { uint64_t tsr_v = tsr_wire_test_rand(rng); memcpy(&%s, &tsr_v, sizeof %s); }\n",
                    t, n, n, n);
            break;
        }
    }
    /* Input pointers: random content of the size the arguments imply. */
    for (size_t k = 0; k < c->nparams; k++) {
        const gen_param *gp = &gc->params[k];
        const spec_param *sp = gp->sp;
        if (gp->kind == GEN_P_FIXED) {
            fprintf(
                f,
                "    uint8_t tsr_fix_%s[%zu];\n    fill_random(tsr_fix_%s, %zu, rng);\n    %s%s%s = (%s)(void *)tsr_fix_%s;\n",
                sp->name, gp->size, sp->name, gp->size, sp->type, sp->type[strlen(sp->type) - 1] == '*' ? "" : " ",
                sp->name, sp->type, sp->name);
        } else if (gp->kind == GEN_P_VAR && sp->count.kind == SPEC_COUNT_STRING) {
            fprintf(f,
                    "    char *tsr_str_%s = random_string(rng);\n    tsr_mem[tsr_nmem++] = tsr_str_%s;\n"
                    "    %s%s%s = (%s)tsr_str_%s;\n",
                    sp->name, sp->name, sp->type, sp->type[strlen(sp->type) - 1] == '*' ? "" : " ", sp->name, sp->type,
                    sp->name);
        } else if (gp->kind == GEN_P_VAR) {
            fprintf(f, "    %s%s%s = NULL;\n    {\n", sp->type, sp->type[strlen(sp->type) - 1] == '*' ? "" : " ",
                    sp->name);
            gen_emit_count(f, gc, gp, "&tsr_ps.unpack");
            fprintf(f,
                    "    uint8_t *m = malloc((size_t)tsr_len_%s + 1);\n    tsr_mem[tsr_nmem++] = m;\n"
                    "    fill_random(m, (size_t)tsr_len_%s, rng);\n",
                    sp->name, sp->name);
            if (sp->nullable)
                fprintf(f, "    if (tsr_wire_test_rand(rng) %% 4)\n    ");
            fprintf(f, "    %s = (%s)(void *)m;\n    }\n", sp->name, sp->type);
        }
    }
    /* Outputs: one buffer per table, zeroed. */
    for (size_t k = 0; k < c->nparams; k++) {
        const gen_param *gp = &gc->params[k];
        if (gp->kind != GEN_P_OUT)
            continue;
        const char *n = gp->sp->name;
        gen_emit_count(f, gc, gp, "&tsr_ps.pack");
        fprintf(
            f,
            "    uint8_t *tsr_oe_%s = calloc(1, (size_t)tsr_len_%s + 1), *tsr_ox_%s = calloc(1, (size_t)tsr_len_%s + 1);\n"
            "    tsr_mem[tsr_nmem++] = tsr_oe_%s;\n    tsr_mem[tsr_nmem++] = tsr_ox_%s;\n",
            n, n, n, n, n, n);
    }
    for (int side = 0; side < 2; side++) {
        const char *table = side ? "tsr_x" : "tsr_e";
        const char *tag = side ? "ox" : "oe";
        fprintf(f, "    ");
        if (!gc->is_void)
            fprintf(f, "%s tsr_ret_%s = ", c->ret, tag);
        fprintf(f, "tsr_call_%s(%s", c->name, table);
        for (size_t k = 0; k < c->nparams; k++) {
            const gen_param *gp = &gc->params[k];
            if (gp->kind == GEN_P_OUT)
                fprintf(f, ", (%s)(void *)tsr_%s_%s", gp->sp->type, tag, gp->sp->name);
            else
                fprintf(f, ", %s", gp->sp->name);
        }
        fprintf(f, ");\n");
    }
    if (!gc->is_void) {
        if (gc->ret_is_string)
            fprintf(
                f,
                "    if (!tsr_ret_oe || !tsr_ret_ox || strcmp((const char *)tsr_ret_oe, (const char *)tsr_ret_ox)) {\n");
        else
            fprintf(f, "    if (memcmp(&tsr_ret_oe, &tsr_ret_ox, sizeof tsr_ret_oe)) {\n");
        fprintf(f, "        snprintf(msg, msgsz, \"gl%s: return values differ\");\n        tsr_rc = -1;\n    }\n",
                c->name);
    }
    for (size_t k = 0; k < c->nparams; k++) {
        const gen_param *gp = &gc->params[k];
        if (gp->kind != GEN_P_OUT)
            continue;
        const char *n = gp->sp->name;
        fprintf(
            f,
            "    if (memcmp(tsr_oe_%s, tsr_ox_%s, (size_t)tsr_len_%s + 1)) {\n"
            "        snprintf(msg, msgsz, \"gl%s: output %s differs (%%llu bytes)\", (unsigned long long)tsr_len_%s);\n"
            "        tsr_rc = -1;\n    }\n",
            n, n, n, c->name, n, n);
    }
    fprintf(
        f,
        "    goto tsr_done;\ntsr_invalid:\n    snprintf(msg, msgsz, \"gl%s: test generator made invalid arguments: %%s\", tsr_why);\n"
        "    tsr_rc = -2;\ntsr_done:\n"
        "    for (int i = 0; i < tsr_nmem; i++)\n        free(tsr_mem[i]);\n    return tsr_rc;\n}\n\n",
        c->name);
}

void gen_emit_test_support(const gen *g)
{
    FILE *f = gen_open(g, "src/wire_test_gen.h");
    fprintf(
        f,
        "/* Wire test support: a recording table and random-argument calls. */\n"
        "#ifndef TSR_WIRE_TEST_GEN_H\n#define TSR_WIRE_TEST_GEN_H\n\n"
        "#include <stddef.h>\n#include <stdint.h>\n#include \"tessera/dispatch.h\"\n#include \"tessera/dev/pixel.h\"\n\n"
        "typedef struct tsr_rec_call {\n    int slot;\n    size_t len;\n    uint8_t *bytes;\n} tsr_rec_call;\n\n"
        "/* Stands in for GL: records every call (name, argument bytes, the bytes\n"
        " * its input pointers address), fills outputs with a pattern, returns a\n"
        " * value derived from the slot. Mirrors PixelStore like GL. */\n"
        "typedef struct tsr_recorder {\n    tsr_rec_call *calls;\n    size_t n, cap;\n    tsr_pixel_store pixels;\n} tsr_recorder;\n\n"
        "void tsr_recorder_init(tsr_recorder *r);\n"
        "void tsr_recorder_fill(tsr_dispatch *d, tsr_recorder *r);\n"
        "void tsr_recorder_clear(tsr_recorder *r);\n"
        "/* 0 when both recorded the same calls byte for byte; else -1 and a\n"
        " * message naming the first difference. */\n"
        "int tsr_recorder_compare(const tsr_recorder *a, const tsr_recorder *b, char *msg, size_t msgsz);\n\n"
        "uint64_t tsr_wire_test_rand(uint64_t *state);\n"
        "/* 1 for commands with wire pack/reply. */\n"
        "int tsr_wire_test_packable(int slot);\n"
        "/* Calls `slot` with the same random valid arguments on `expect` and\n"
        " * `actual`; 0 when return values and outputs agree, -1 (message) when\n"
        " * not, -2 on a generator bug, 1 when the command is not packable. */\n"
        "int tsr_wire_test_call(int slot, const tsr_dispatch *expect, const tsr_dispatch *actual, uint64_t *rng,\n"
        "                       char *msg, size_t msgsz);\n\n#endif\n");
    gen_close(f);

    f = gen_open(g, "src/wire_test_gen.c");
    fprintf(
        f,
        "/* Every function shares one shape; not all of them need every label. */\n"
        "#pragma GCC diagnostic ignored \"-Wunused-label\"\n"
        "#include <stdio.h>\n#include <stdlib.h>\n#include <string.h>\n"
        "#include \"wire_test_gen.h\"\n#include \"wire_gen.h\"\n\n"
        "typedef struct rec_buf {\n    uint8_t *b;\n    size_t n, cap;\n} rec_buf;\n\n"
        "static void rb_put(rec_buf *b, const void *p, size_t n)\n{\n"
        "    if (b->n + n > b->cap) {\n        size_t cap = b->cap ? b->cap : 64;\n"
        "        while (cap < b->n + n)\n            cap *= 2;\n"
        "        uint8_t *nb = realloc(b->b, cap);\n        if (!nb)\n            abort();\n"
        "        b->b = nb;\n        b->cap = cap;\n    }\n"
        "    if (n)\n        memcpy(b->b + b->n, p, n);\n    b->n += n;\n}\n\n"
        "static void rb_u8(rec_buf *b, uint8_t v)\n{\n    rb_put(b, &v, 1);\n}\n\n"
        "static void rec_add(tsr_recorder *r, int slot, rec_buf *b)\n{\n"
        "    if (r->n == r->cap) {\n        r->cap = r->cap ? r->cap * 2 : 256;\n"
        "        r->calls = realloc(r->calls, r->cap * sizeof *r->calls);\n        if (!r->calls)\n            abort();\n    }\n"
        "    r->calls[r->n].slot = slot;\n    r->calls[r->n].len = b->n;\n    r->calls[r->n].bytes = b->b;\n    r->n++;\n}\n\n"
        "static void fill_pattern(void *dst, uint64_t n, int slot)\n{\n"
        "    uint8_t *d = dst;\n    for (uint64_t i = 0; i < n; i++)\n        d[i] = (uint8_t)(slot * 31 + i * 7 + 1);\n}\n\n"
        "static void fill_spans(const tsr_pixel_layout *l, int64_t h, int64_t depth, void *dst, int slot)\n{\n"
        "    uint8_t *src = malloc((size_t)l->extent + 1);\n    if (!src)\n        abort();\n"
        "    fill_pattern(src, l->extent, slot);\n    tsr_pixel_copy_spans(l, h, depth, dst, src);\n    free(src);\n}\n\n"
        "uint64_t tsr_wire_test_rand(uint64_t *s)\n{\n"
        "    /* splitmix64 */\n    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);\n"
        "    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;\n    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;\n"
        "    return z ^ (z >> 31);\n}\n\n"
        "static void fill_random(uint8_t *d, size_t n, uint64_t *rng)\n{\n"
        "    for (size_t i = 0; i < n; i++)\n        d[i] = (uint8_t)tsr_wire_test_rand(rng);\n}\n\n"
        "static char *random_string(uint64_t *rng)\n{\n"
        "    size_t n = (size_t)(tsr_wire_test_rand(rng) %% 24);\n    char *s = malloc(n + 1);\n    if (!s)\n        abort();\n"
        "    for (size_t i = 0; i < n; i++)\n        s[i] = (char)(' ' + tsr_wire_test_rand(rng) %% 95);\n"
        "    s[n] = '\\0';\n    return s;\n}\n\n"
        "void tsr_recorder_init(tsr_recorder *r)\n{\n    memset(r, 0, sizeof *r);\n    tsr_pixel_store_init(&r->pixels);\n}\n\n"
        "void tsr_recorder_clear(tsr_recorder *r)\n{\n"
        "    for (size_t i = 0; i < r->n; i++)\n        free(r->calls[i].bytes);\n"
        "    free(r->calls);\n    tsr_recorder_init(r);\n}\n\n"
        "int tsr_recorder_compare(const tsr_recorder *a, const tsr_recorder *b, char *msg, size_t msgsz)\n{\n"
        "    size_t n = a->n < b->n ? a->n : b->n;\n"
        "    for (size_t i = 0; i < n; i++) {\n"
        "        const tsr_rec_call *x = &a->calls[i], *y = &b->calls[i];\n"
        "        if (x->slot != y->slot) {\n"
        "            snprintf(msg, msgsz, \"call %%zu: gl%%s expected, gl%%s recorded\", i, tsr_dispatch_name(x->slot), tsr_dispatch_name(y->slot));\n"
        "            return -1;\n        }\n"
        "        size_t m = x->len < y->len ? x->len : y->len;\n"
        "        for (size_t k = 0; k < m; k++)\n"
        "            if (x->bytes[k] != y->bytes[k]) {\n"
        "                snprintf(msg, msgsz, \"call %%zu (gl%%s): recorded byte %%zu differs (0x%%02x expected, 0x%%02x recorded)\", i,\n"
        "                         tsr_dispatch_name(x->slot), k, x->bytes[k], y->bytes[k]);\n"
        "                return -1;\n            }\n"
        "        if (x->len != y->len) {\n"
        "            snprintf(msg, msgsz, \"call %%zu (gl%%s): %%zu bytes expected, %%zu recorded\", i, tsr_dispatch_name(x->slot), x->len, y->len);\n"
        "            return -1;\n        }\n    }\n"
        "    if (a->n != b->n) {\n"
        "        snprintf(msg, msgsz, \"%%zu calls expected, %%zu recorded\", a->n, b->n);\n        return -1;\n    }\n"
        "    return 0;\n}\n\n");
    fprintf(f, "static const GLenum pnames[] = {\n");
    size_t np = 0;
    for (size_t i = 0; i < g->s->npnames; i++) {
        if (answered_by_packer(g->s->pnames[i].name))
            continue;
        int found;
        unsigned long long v = gen_enum_value(&g->enums, g->s->pnames[i].name, &found);
        fprintf(f, "    0x%llx, /* %s */\n", v, g->s->pnames[i].name);
        np++;
    }
    if (!np)
        fprintf(f, "    0\n");
    fprintf(f, "};\n#define PNAMES (sizeof pnames / sizeof pnames[0])\n\n");
    fprintf(f, "static const GLenum map_targets[] = {\n");
    for (size_t i = 0; i < g->s->nmap_components; i++) {
        int found;
        unsigned long long v = gen_enum_value(&g->enums, g->s->map_components[i].name, &found);
        fprintf(f, "    0x%llx, /* %s */\n", v, g->s->map_components[i].name);
    }
    if (!g->s->nmap_components)
        fprintf(f, "    0\n");
    fprintf(f,
            "};\n#define MAP_TARGETS (sizeof map_targets / sizeof map_targets[0])\n\n"
            "static const GLenum pixel_pairs[][2] = {\n"
            "    {GL_RGBA, GL_UNSIGNED_BYTE}, {GL_RGB, GL_UNSIGNED_BYTE}, {GL_LUMINANCE, GL_FLOAT},\n"
            "    {GL_RGBA, GL_UNSIGNED_SHORT_4_4_4_4}, {GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT},\n"
            "    {GL_BGRA, GL_UNSIGNED_INT_8_8_8_8_REV}, {GL_COLOR_INDEX, GL_BITMAP}, {GL_LUMINANCE_ALPHA, GL_BYTE},\n"
            "};\n#define PIXEL_PAIRS (sizeof pixel_pairs / sizeof pixel_pairs[0])\n\n"
            "static const GLenum typed_types[] = {\n"
            "    GL_BYTE, GL_UNSIGNED_BYTE, GL_SHORT, GL_UNSIGNED_SHORT, GL_INT, GL_UNSIGNED_INT, GL_FLOAT,\n"
            "    GL_2_BYTES, GL_3_BYTES, GL_4_BYTES,\n"
            "};\n#define TYPED_TYPES (sizeof typed_types / sizeof typed_types[0])\n\n");
    emit_recorder(f, g);
    for (size_t i = 0; i < g->ncmds; i++)
        if (g->cmds[i].packable)
            emit_random_call(f, &g->cmds[i]);
    fprintf(f, "int tsr_wire_test_packable(int slot)\n{\n    switch (slot) {\n");
    for (size_t i = 0; i < g->ncmds; i++)
        if (g->cmds[i].packable)
            fprintf(f, "    case %d:\n", g->cmds[i].slot);
    fprintf(f, "        return 1;\n    default:\n        return 0;\n    }\n}\n\n");
    fprintf(f,
            "int tsr_wire_test_call(int slot, const tsr_dispatch *expect, const tsr_dispatch *actual, uint64_t *rng,\n"
            "                       char *msg, size_t msgsz)\n{\n    switch (slot) {\n");
    for (size_t i = 0; i < g->ncmds; i++)
        if (g->cmds[i].packable)
            fprintf(f, "    case %d: return tc_%s(expect, actual, rng, msg, msgsz);\n", g->cmds[i].slot,
                    g->cmds[i].sc->name);
    fprintf(f, "    default: return 1;\n    }\n}\n");
    gen_close(f);
}
