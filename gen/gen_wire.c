/* gen/gen_wire.c — emits the wire code: opcodes and inline packers
 * (src/wire_gen.h), out-of-line packers and the packer dispatch filler
 * (src/pack_gen.c), the validating decoder (src/unpack_gen.c) and the
 * pname/opcode tables (src/wire_tables_gen.c). The layout rules are those
 * of tessera/dev/wire.h; gen_main.c computes each command's layout once.
 * Generated locals carry a tsr_ prefix so they never clash with spec
 * parameter names. */
#include "gen.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

/* Commands whose packing or unpacking also updates a mirror of client state
 * (pixel store, buffer bindings). The one place such exceptions live. */
static const struct {
    const char *name;
    const char *pack_hook;   /* runs after packing, with the packer in tsr_p */
    const char *unpack_hook; /* runs before dispatch, with the unpacker in u */
} hooks[] = {
    {"PixelStorei", "tsr_packer_mirror_PixelStore(tsr_p, pname, (double)param);",
     "tsr_pixel_store_set(&u->pixels, pname, (double)param);"},
    {"PixelStoref", "tsr_packer_mirror_PixelStore(tsr_p, pname, (double)param);",
     "tsr_pixel_store_set(&u->pixels, pname, (double)param);"},
    {"BindBuffer", "tsr_packer_mirror_BindBuffer(tsr_p, target, buffer);",
     "tsr_unpacker_note_BindBuffer(u, target, buffer);"},
    {"DeleteBuffers", "tsr_packer_mirror_DeleteBuffers(tsr_p, n, buffers);",
     "tsr_unpacker_note_DeleteBuffers(u, n, buffers);"},
    /* Pixel store and client arrays are per context; a share group's
     * contexts share one stream (tessera/dev/pack.h). */
    {"MakeCurrentTSR", "tsr_packer_mirror_MakeCurrent(tsr_p, context);", "tsr_unpacker_note_MakeCurrent(u, context);"},
    {"ContextDestroyTSR", "tsr_packer_mirror_ContextDestroy(tsr_p, context);",
     "tsr_unpacker_note_ContextDestroy(u, context);"},
    /* A budgeted stream's buffer bytes (tessera/dev/unpack.h). */
    {"BufferData", NULL, "if (tsr_unpacker_check_BufferData(u, target, size, err) != 0) return err->code;"},
    /* Commands that must reach the receiver now, not when the buffer fills. */
    {"Flush", "tsr_packer_flush(tsr_p);", NULL},
    {"Finish", "tsr_packer_flush(tsr_p);", NULL},
    {"SwapBuffersTSR", "tsr_packer_flush(tsr_p);", NULL},
    /* The stream's shader and program names (GL checks a name before it
     * reads a call's pointers; the packer must too). */
    {"CreateShaderTSR", "tsr_packer_note_glsl_name(tsr_p, shader, 0);", NULL},
    {"CreateProgramTSR", "tsr_packer_note_glsl_name(tsr_p, program, 1);", NULL},
};

/* Reply commands whose returned value the packer records: code run once
 * the reply's return value is in tsr_ret. */
static const struct {
    const char *name;
    const char *after;
} reply_hooks[] = {
    {"CreateShader", "tsr_packer_note_glsl_name(tsr_p, tsr_ret, 0);"},
    {"CreateProgram", "tsr_packer_note_glsl_name(tsr_p, tsr_ret, 1);"},
};

/* Queries the packer answers itself because the receiver never sees the
 * state they ask about (client arrays are `local`): code run before
 * packing that may return early. */
static const struct {
    const char *name;
    const char *pre;
} pack_answers[] = {
    {"IsEnabled",
     "{ GLboolean tsr_local; if (tsr_packer_answer_IsEnabled(tsr_p, cap, &tsr_local)) return tsr_local; }"},
    {"GetBooleanv", "if (tsr_packer_answer_client_get(tsr_p, pname, GL_BOOL, data)) return;"},
    {"GetIntegerv", "if (tsr_packer_answer_client_get(tsr_p, pname, GL_INT, data)) return;"},
    {"GetFloatv", "if (tsr_packer_answer_client_get(tsr_p, pname, GL_FLOAT, data)) return;"},
    {"GetDoublev", "if (tsr_packer_answer_client_get(tsr_p, pname, GL_DOUBLE, data)) return;"},
    /* the mapping of a buffer is the packer's own (pack_map.c): the
     * receiver's buffer is never mapped */
    {"GetBufferParameteriv", "if (tsr_packer_answer_buffer_mapping(tsr_p, target, pname, params)) return;"},
    /* an error the packer found itself (an unknown pname) comes first */
    {"GetError", "{ GLenum tsr_local = tsr_packer_take_local_error(tsr_p); if (tsr_local) return tsr_local; }"},
    /* glEnable/glDisable of a client array is glEnable/DisableClientState
     * (Mesa takes both): the mirror's, never the receiver's (whose arrays
     * are the ones each draw carries inline) */
    {"Enable", "if (tsr_packer_local_enable_array(tsr_p, cap, 1)) return;"},
    {"Disable", "if (tsr_packer_local_enable_array(tsr_p, cap, 0)) return;"},
};

/* Commands the unpacker drops when the condition holds, with the
 * arguments decoded (inline-decoded commands only): a client array's
 * enable never comes from the wire (the packer keeps it local), and one
 * that did would leave the receiver's array enabled at a pointer it does
 * not own. */
static const struct {
    const char *name;
    const char *when;
} unpack_drops[] = {
    {"Enable", "tsr_wire_is_client_array(cap)"},
    {"Disable", "tsr_wire_is_client_array(cap)"},
};

static const char *unpack_drop(const spec_command *c)
{
    for (size_t i = 0; i < sizeof unpack_drops / sizeof unpack_drops[0]; i++)
        if (!strcmp(unpack_drops[i].name, c->name))
            return unpack_drops[i].when;
    return NULL;
}

static const char *pack_answer(const spec_command *c)
{
    for (size_t i = 0; i < sizeof pack_answers / sizeof pack_answers[0]; i++)
        if (!strcmp(pack_answers[i].name, c->name))
            return pack_answers[i].pre;
    return NULL;
}

static const char *pack_hook(const spec_command *c)
{
    for (size_t i = 0; i < sizeof hooks / sizeof hooks[0]; i++)
        if (!strcmp(hooks[i].name, c->name))
            return hooks[i].pack_hook;
    return NULL;
}

static const char *reply_hook(const spec_command *c)
{
    for (size_t i = 0; i < sizeof reply_hooks / sizeof reply_hooks[0]; i++)
        if (!strcmp(reply_hooks[i].name, c->name))
            return reply_hooks[i].after;
    return NULL;
}

static const char *unpack_hook(const spec_command *c)
{
    for (size_t i = 0; i < sizeof hooks / sizeof hooks[0]; i++)
        if (!strcmp(hooks[i].name, c->name))
            return hooks[i].unpack_hook;
    return NULL;
}

static int is_literal(const char *s) { return isdigit((unsigned char)s[0]) || s[0] == '-'; }

static const spec_param *param_named(const spec_command *c, const char *name)
{
    for (size_t i = 0; i < c->nparams; i++)
        if (!strcmp(c->params[i].name, name))
            return &c->params[i];
    return NULL;
}

/* Emits a check that `arg` (a parameter or literal) is not negative. */
static void emit_nonneg(FILE *f, const gen_cmd *gc, const char *arg, const char *modes)
{
    const spec_command *c = gc->sc;
    if (is_literal(arg))
        return;
    const spec_param *p = param_named(c, arg);
    const gen_type *t = p ? gen_type_find(p->base_type) : NULL;
    if (!t || !t->is_signed || t->is_float)
        return;
    if (!strncmp(modes, "&tsr_p->", 8)) {
        /* packing: a negative count is GL_INVALID_VALUE for glGetError
         * (glUniform1fv(loc, -1, v)), the program's error, not a dropped
         * command */
        fprintf(f, "        if (%s < 0) { tsr_packer_local_error(tsr_p, GL_INVALID_VALUE); ", arg);
        if (gc->is_void)
            fprintf(f, "return; }\n");
        else
            fprintf(f, "return (%s)0; }\n", c->ret);
        return;
    }
    fprintf(f, "        if (%s < 0) { tsr_why = \"negative count %s\"; goto tsr_invalid; }\n", arg, arg);
}

/* Emits code computing `uint64_t tsr_len_NAME`, the byte size the pointer
 * parameter addresses, from the other arguments. `modes` is an expression
 * of type const tsr_pixel_modes * for image counts. Jumps to tsr_invalid
 * with tsr_why set when the arguments imply no valid size. */
void gen_emit_count(FILE *f, const gen_cmd *gc, const gen_param *gp, const char *modes)
{
    const spec_param *sp = gp->sp;
    const spec_count *k = &sp->count;
    fprintf(f, "    uint64_t tsr_len_%s = 0;\n    {\n", sp->name);
    switch (k->kind) {
    case SPEC_COUNT_FIXED:
        fprintf(f, "        tsr_len_%s = %zuu;\n", sp->name, (size_t)k->fixed * gp->elem_size);
        break;
    case SPEC_COUNT_EXPR:
    case SPEC_COUNT_BYTES:
        /* A product of parameters and integers: elements, or bytes. */
        fprintf(f, "        uint64_t tsr_c = %zuu;\n", k->kind == SPEC_COUNT_BYTES ? (size_t)1 : gp->elem_size);
        for (size_t i = 0; i < k->nargs; i++) {
            emit_nonneg(f, gc, k->args[i], modes);
            fprintf(
                f,
                "        if (__builtin_mul_overflow(tsr_c, (uint64_t)(%s), &tsr_c)) { tsr_why = \"count of %s overflows\"; goto tsr_invalid; }\n",
                k->args[i], sp->name);
        }
        fprintf(f, "        tsr_len_%s = tsr_c;\n", sp->name);
        break;
    case SPEC_COUNT_PNAME:
        if (!strncmp(modes, "&tsr_p->", 8)) {
            /* A pname no GL knows is GL_INVALID_ENUM for glGetError (GL
             * ignores the call), not a dropped command: the application
             * asks glGetError and goes on (piglit's API tests) */
            fprintf(f,
                    "        if (tsr_wire_pname_count((GLenum)%s) < 0) { "
                    "tsr_packer_local_error(tsr_p, GL_INVALID_ENUM); ",
                    k->args[0]);
            if (gc->is_void)
                fprintf(f, "return; }\n");
            else
                fprintf(f, "return (%s)0; }\n", gc->sc->ret);
        }
        fprintf(f,
                "        int tsr_k = tsr_wire_pname_count((GLenum)%s);\n"
                "        if (tsr_k < 0) { tsr_why = \"unknown enum for %s\"; goto tsr_invalid; }\n"
                "        tsr_len_%s = (uint64_t)tsr_k * %zuu;\n",
                k->args[0], k->args[0], sp->name, gp->elem_size);
        break;
    case SPEC_COUNT_IMAGE:
    case SPEC_COUNT_BITMAP: {
        const char *w = k->args[0], *h = k->args[1];
        const char *d = k->kind == SPEC_COUNT_IMAGE ? k->args[2] : "1";
        const char *format = k->kind == SPEC_COUNT_IMAGE ? k->args[3] : "GL_COLOR_INDEX";
        const char *type = k->kind == SPEC_COUNT_IMAGE ? k->args[4] : "GL_BITMAP";
        int dims = is_literal(d) ? 2 : 3;
        if (!strncmp(modes, "&tsr_p->", 8)) {
            /* GL checks sizes, format and type before it reads a pixel:
             * such a call is a GL error for glGetError, not a dropped
             * command, and its pointer (often NULL or stale) is not read */
            fprintf(f,
                    "        GLenum tsr_gl_error = tsr_pixel_image_error((int64_t)(%s), (int64_t)(%s), (int64_t)(%s), "
                    "(GLenum)(%s), (GLenum)(%s));\n"
                    "        if (tsr_gl_error) { tsr_packer_local_error(tsr_p, tsr_gl_error); ",
                    w, h, d, format, type);
            if (gc->is_void)
                fprintf(f, "return; }\n");
            else
                fprintf(f, "return (%s)0; }\n", gc->sc->ret);
        }
        fprintf(
            f,
            "        if (tsr_pixel_layout_of(%s, %d, (int64_t)(%s), (int64_t)(%s), (int64_t)(%s), (GLenum)(%s), (GLenum)(%s), &tsr_lay_%s) != 0) {\n"
            "            tsr_why = \"invalid size, format or type of %s\"; goto tsr_invalid; }\n"
            "        tsr_len_%s = tsr_lay_%s.extent;\n",
            modes, dims, w, h, d, format, type, sp->name, sp->name, sp->name, sp->name);
        break;
    }
    case SPEC_COUNT_TYPED:
        emit_nonneg(f, gc, k->args[0], modes);
        fprintf(
            f,
            "        size_t tsr_t = tsr_gl_type_size((GLenum)%s);\n"
            "        if (!tsr_t) { tsr_why = \"unknown element type of %s\"; goto tsr_invalid; }\n"
            "        if (__builtin_mul_overflow((uint64_t)(%s), (uint64_t)tsr_t, &tsr_len_%s)) { tsr_why = \"count of %s overflows\"; goto tsr_invalid; }\n",
            k->args[1], sp->name, k->args[0], sp->name, sp->name);
        break;
    case SPEC_COUNT_MAP: {
        /* ((order-1)*stride [+ (vorder-1)*vstride] + pname_counts[target]) elements */
        fprintf(f,
                "        int tsr_k = tsr_wire_map_components((GLenum)%s);\n"
                "        if (tsr_k < 0) { tsr_why = \"unknown map target\"; goto tsr_invalid; }\n"
                "        uint64_t tsr_c = (uint64_t)tsr_k, tsr_t;\n",
                k->args[0]);
        for (size_t i = 1; i + 1 < k->nargs; i += 2) {
            const char *stride = k->args[i], *order = k->args[i + 1];
            fprintf(
                f,
                "        if ((int64_t)(%s) < 1) { tsr_why = \"map order below 1\"; goto tsr_invalid; }\n"
                "        if ((int64_t)(%s) < 0) { tsr_why = \"negative map stride\"; goto tsr_invalid; }\n"
                "        if (__builtin_mul_overflow((uint64_t)(%s) - 1u, (uint64_t)(%s), &tsr_t) || __builtin_add_overflow(tsr_c, tsr_t, &tsr_c)) {\n"
                "            tsr_why = \"map size overflows\"; goto tsr_invalid; }\n",
                order, stride, order, stride);
        }
        fprintf(
            f,
            "        if (__builtin_mul_overflow(tsr_c, (uint64_t)%zuu, &tsr_len_%s)) { tsr_why = \"map size overflows\"; goto tsr_invalid; }\n",
            gp->elem_size, sp->name);
        break;
    }
    case SPEC_COUNT_STRING:
        fprintf(f, "        tsr_len_%s = (uint64_t)strlen((const char *)%s) + 1u;\n", sp->name, sp->name);
        break;
    case SPEC_COUNT_NONE: break;
    }
    fprintf(f, "    }\n");
}

static int needs_layout(const gen_param *gp)
{
    return gp->sp->count.kind == SPEC_COUNT_IMAGE || gp->sp->count.kind == SPEC_COUNT_BITMAP;
}

static void declare_layouts(FILE *f, const gen_cmd *gc, int outs)
{
    for (size_t i = 0; i < gc->sc->nparams; i++) {
        const gen_param *gp = &gc->params[i];
        if ((gp->kind == GEN_P_VAR || (outs && gp->kind == GEN_P_OUT)) && needs_layout(gp))
            fprintf(f, "    tsr_pixel_layout tsr_lay_%s;\n", gp->sp->name);
    }
}

static int has_bbox(const gen_cmd *gc) { return gc->sc->vertex && !strcmp(gc->sc->vertex, "position"); }

/* Emits the bounding-box update of a vertex-position command. */
static void emit_bbox(FILE *f, const gen_cmd *gc)
{
    const spec_command *c = gc->sc;
    char comp[4][64];
    int n = 0;
    if (c->nparams == 1 && c->params[0].pointer_depth == 1 && c->params[0].count.kind == SPEC_COUNT_FIXED) {
        for (long i = 0; i < c->params[0].count.fixed && n < 4; i++)
            snprintf(comp[n++], sizeof comp[0], "(float)%s[%ld]", c->params[0].name, i);
    } else {
        for (size_t i = 0; i < c->nparams && n < 4; i++)
            snprintf(comp[n++], sizeof comp[0], "(float)%s", c->params[i].name);
    }
    if (n == 2)
        fprintf(f, "    tsr_packer_bbox3(tsr_p, %s, %s, 0.0f);\n", comp[0], comp[1]);
    else if (n == 3)
        fprintf(f, "    tsr_packer_bbox3(tsr_p, %s, %s, %s);\n", comp[0], comp[1], comp[2]);
    else if (n == 4)
        fprintf(f, "    tsr_packer_bbox4(tsr_p, %s, %s, %s, %s);\n", comp[0], comp[1], comp[2], comp[3]);
}

/* Fixed-size commands pack inline; their slow path never fails (tessera/dev/pack.h
 * TSR_PACK_MAX_FIXED), so the inline code has no NULL check. */
static int is_inline_pack(const gen_cmd *gc)
{
    return gc->packable && !gc->is_reply && !gc->nvar && gc->sc->opcode < 255 && gc->fixed_size <= 256;
}

static void emit_pack_signature(FILE *f, const gen_cmd *gc, const char *prefix)
{
    const spec_command *c = gc->sc;
    fprintf(f, "%s%s tsr_pack_%s(tsr_packer *tsr_p", prefix, c->ret, c->name);
    if (c->nparams)
        fprintf(f, ", ");
    gen_print_params(f, c, 0, 0);
    fprintf(f, ")");
}

static void emit_put_fixed(FILE *f, const gen_cmd *gc)
{
    for (size_t i = 0; i < gc->sc->nparams; i++) {
        const gen_param *gp = &gc->params[i];
        if (gp->kind == GEN_P_SCALAR)
            fprintf(f, "    memcpy(tsr_a + %zu, &%s, %zu);\n", gp->offset, gp->sp->name, gp->size);
        else if (gp->kind == GEN_P_FIXED)
            fprintf(f, "    memcpy(tsr_a + %zu, %s, %zu);\n", gp->offset, gp->sp->name, gp->size);
    }
}

static void emit_inline_pack(FILE *f, const gen_cmd *gc)
{
    const spec_command *c = gc->sc;
    emit_pack_signature(f, gc, "static inline ");
    fprintf(f, "\n{\n    uint8_t *tsr_a = tsr_packer_cmd(tsr_p, %d, %zu, %zu);\n", c->opcode, gc->fixed_size,
            gc->align);
    emit_put_fixed(f, gc);
    if (!gc->fixed_size)
        fprintf(f, "    (void)tsr_a;\n");
    const char *hook = pack_hook(c);
    if (hook)
        fprintf(f, "    %s\n", hook);
    if (has_bbox(gc))
        emit_bbox(f, gc);
    fprintf(f, "}\n");
}

static void emit_return_zero(FILE *f, const gen_cmd *gc)
{
    if (gc->is_void)
        fprintf(f, "return;");
    else
        fprintf(f, "return (%s)0;", gc->sc->ret);
}

static void emit_outline_pack(FILE *f, const gen_cmd *gc)
{
    const spec_command *c = gc->sc;
    /* A reply's checks jump to tsr_bad_reply, the arguments' to tsr_invalid. */
    int uses_bad_reply = gc->is_reply && (gc->nout || (!gc->is_void && !gc->ret_is_string));
    int uses_invalid = gc->nvar || gc->nout || (!gc->is_void && !gc->ret_is_string && !gc->is_reply);
    emit_pack_signature(f, gc, "");
    fprintf(f, "\n{\n");
    if (uses_invalid || uses_bad_reply)
        fprintf(f, "    const char *tsr_why = NULL;\n");
    if (pack_answer(c))
        fprintf(f, "    %s\n", pack_answer(c));
    /* An output sized by a pname the wire does not know: GL's answer is
     * GL_INVALID_ENUM and nothing written; sent, the receiver could not
     * size the reply and would drop the stream (piglit's
     * clip-flag-behavior asks glGetBooleanv(GL_CLIP_PLANE0 + 8)). */
    for (size_t i = 0; i < c->nparams; i++) {
        const gen_param *gp = &gc->params[i];
        if (gp->kind == GEN_P_OUT && gp->sp->count.kind == SPEC_COUNT_PNAME) {
            fprintf(f,
                    "    if (tsr_wire_pname_count((GLenum)%s) < 0) {\n"
                    "        tsr_packer_local_error(tsr_p, GL_INVALID_ENUM);\n        ",
                    gp->sp->count.args[0]);
            emit_return_zero(f, gc);
            fprintf(f, "\n    }\n");
            break;
        }
    }
    for (size_t i = 0; i < c->nparams; i++) {
        const gen_param *gp = &gc->params[i];
        if (gp->kind == GEN_P_OUT && needs_layout(gp)) {
            /* with a pixel pack buffer bound, the pointer is an offset in
             * it and the answer stays on the receiver (pack_buffer_get.c) */
            int nargs = 0;
            fprintf(f, "    {\n        const GLint tsr_args[] = {");
            for (size_t k = 0; k < i; k++)
                if (gc->params[k].kind == GEN_P_SCALAR)
                    fprintf(f, "%s(GLint)%s", nargs++ ? ", " : "", gc->params[k].sp->name);
            if (!nargs)
                fprintf(f, "0");
            fprintf(f, "};\n        if (tsr_packer_get_into_pack_buffer(tsr_p, %d, tsr_args, %d, %s)) {\n            ",
                    c->opcode, nargs, gp->sp->name);
            emit_return_zero(f, gc);
            fprintf(f, "\n        }\n    }\n");
            break;
        }
    }
    if (!gc->is_void)
        fprintf(f, "    %s tsr_ret = (%s)0;\n", c->ret, c->ret);
    declare_layouts(f, gc, 1);
    fprintf(f, "    uint64_t tsr_size = %zu;\n", gc->fixed_size);
    for (size_t i = 0; i < c->nparams; i++) {
        const gen_param *gp = &gc->params[i];
        if (gp->kind != GEN_P_VAR)
            continue;
        const char *n = gp->sp->name;
        /* With a GL_PIXEL_UNPACK_BUFFER bound, a pixel pointer is an offset
         * into it (GL 2.1 3.6.4): it travels as TSR_WIRE_OFFSET and the
         * offset, and the packer never reads it (tessera/dev/wire.h). */
        int pixel_source = needs_layout(gp);
        const char *buffer = pixel_source ? " || tsr_p->pixels.unpack_buffer" : "";
        if (gp->sp->nullable)
            fprintf(f, "    uint64_t tsr_wlen_%s = TSR_WIRE_NULL;\n    if (%s%s) {\n", n, n, buffer);
        else
            fprintf(f, "    uint64_t tsr_wlen_%s;\n    {\n", n);
        gen_emit_count(f, gc, gp, "&tsr_p->pixels.unpack");
        if (!gp->sp->nullable)
            fprintf(f, "    if (!%s && tsr_len_%s%s) { tsr_why = \"NULL %s\"; goto tsr_invalid; }\n", n, n,
                    pixel_source ? " && !tsr_p->pixels.unpack_buffer" : "", n);
        if (pixel_source)
            fprintf(f, "    tsr_wlen_%s = tsr_p->pixels.unpack_buffer ? TSR_WIRE_OFFSET : tsr_len_%s;\n    }\n", n, n);
        else
            fprintf(f, "    tsr_wlen_%s = tsr_len_%s;\n    }\n", n, n);
        fprintf(
            f,
            "    tsr_size = tsr_wire_align8(tsr_size) + 8u;\n"
            "    if (tsr_wlen_%s == TSR_WIRE_OFFSET)\n        tsr_size += 8u;\n"
            "    else if (tsr_wlen_%s != TSR_WIRE_NULL && __builtin_add_overflow(tsr_size, tsr_wlen_%s, &tsr_size)) {\n"
            "        tsr_why = \"size overflows\"; goto tsr_invalid; }\n",
            n, n, n);
    }
    if (gc->is_reply)
        fprintf(f, "    uint32_t tsr_id = tsr_p->next_request++;\n");
    fprintf(f, "    uint8_t *tsr_a = tsr_packer_cmd_var(tsr_p, %d, tsr_size, %zu);\n    if (!tsr_a)\n        ",
            c->opcode, gc->align);
    emit_return_zero(f, gc);
    fprintf(f, "\n");
    emit_put_fixed(f, gc);
    if (gc->is_reply)
        fprintf(f, "    memcpy(tsr_a + %zu, &tsr_id, 4);\n", gc->reqid_offset);
    if (gc->nvar)
        fprintf(f, "    uint64_t tsr_q = %zu;\n", gc->fixed_size);
    for (size_t i = 0; i < c->nparams; i++) {
        const gen_param *gp = &gc->params[i];
        if (gp->kind != GEN_P_VAR)
            continue;
        const char *n = gp->sp->name;
        fprintf(f,
                "    tsr_q = tsr_wire_align8(tsr_q);\n"
                "    tsr_wire_put_u64(tsr_a + tsr_q, tsr_wlen_%s);\n    tsr_q += 8u;\n"
                "    if (tsr_wlen_%s == TSR_WIRE_OFFSET) {\n"
                "        tsr_wire_put_u64(tsr_a + tsr_q, (uint64_t)(uintptr_t)%s);\n        tsr_q += 8u;\n"
                "    } else if (tsr_wlen_%s != TSR_WIRE_NULL && tsr_wlen_%s) {\n"
                "        memcpy(tsr_a + tsr_q, %s, (size_t)tsr_wlen_%s);\n        tsr_q += tsr_wlen_%s;\n    }\n",
                n, n, n, n, n, n, n, n);
    }
    if (gc->nvar)
        fprintf(f, "    (void)tsr_q;\n");
    const char *hook = pack_hook(c);
    if (hook)
        fprintf(f, "    %s\n", hook);
    if (has_bbox(gc))
        emit_bbox(f, gc);
    if (gc->is_reply) {
        fprintf(f, "    size_t tsr_rsize = 0, tsr_rpos = 0;\n"
                   "    uint64_t tsr_ilen;\n"
                   "    const uint8_t *tsr_item;\n"
                   "    const uint8_t *tsr_r = tsr_packer_request(tsr_p, tsr_id, &tsr_rsize);\n"
                   "    if (!tsr_r)\n        ");
        emit_return_zero(f, gc);
        fprintf(f, "\n");
        if (!gc->is_void) {
            fprintf(f,
                    "    tsr_item = tsr_packer_reply_item(tsr_p, tsr_r, tsr_rsize, &tsr_rpos, &tsr_ilen, \"%s\");\n"
                    "    if (!tsr_item)\n        ",
                    c->name);
            emit_return_zero(f, gc);
            fprintf(f, "\n");
            if (gc->ret_is_string)
                fprintf(f, "    tsr_ret = tsr_ilen ? (%s)tsr_packer_keep_string(tsr_p, tsr_item, tsr_ilen) : NULL;\n",
                        c->ret);
            else
                fprintf(
                    f,
                    "    if (tsr_ilen != sizeof tsr_ret) { tsr_why = \"a wrong return size\"; goto tsr_bad_reply; }\n"
                    "    memcpy(&tsr_ret, tsr_item, sizeof tsr_ret);\n");
        }
        for (size_t i = 0; i < c->nparams; i++) {
            const gen_param *gp = &gc->params[i];
            if (gp->kind != GEN_P_OUT)
                continue;
            const char *n = gp->sp->name;
            fprintf(f,
                    "    tsr_item = tsr_packer_reply_item(tsr_p, tsr_r, tsr_rsize, &tsr_rpos, &tsr_ilen, \"%s\");\n"
                    "    if (!tsr_item)\n        ",
                    c->name);
            emit_return_zero(f, gc);
            fprintf(f, "\n    {\n");
            gen_emit_count(f, gc, gp, "&tsr_p->pixels.pack");
            fprintf(
                f,
                "    if (tsr_ilen != tsr_len_%s) { tsr_why = \"the size of %s differs from the request\"; goto tsr_bad_reply; }\n",
                n, n);
            if (needs_layout(gp)) {
                const spec_count *k = &gp->sp->count;
                const char *h = k->args[1];
                const char *d = k->kind == SPEC_COUNT_IMAGE ? k->args[2] : "1";
                fprintf(
                    f,
                    "    if (%s)\n        tsr_pixel_copy_spans(&tsr_lay_%s, (int64_t)(%s), (int64_t)(%s), %s, tsr_item);\n",
                    n, n, h, d, n);
            } else {
                fprintf(f, "    if (%s && tsr_ilen)\n        memcpy(%s, tsr_item, (size_t)tsr_ilen);\n", n, n);
            }
            fprintf(f, "    }\n");
        }
    }
    if (gc->is_reply && reply_hook(c))
        fprintf(f, "    %s\n", reply_hook(c));
    if (gc->is_void)
        fprintf(f, "    return;\n");
    else
        fprintf(f, "    return tsr_ret;\n");
    if (uses_invalid) {
        /* unused when every count is fixed and only the reply is checked */
        fprintf(f, "tsr_invalid: __attribute__((unused));\n    tsr_packer_drop(tsr_p, \"%s\", tsr_why);\n    ",
                c->name);
        emit_return_zero(f, gc);
        fprintf(f, "\n");
    }
    /* A reply that does not decode is the answering server's fault, not
     * the application's: the sink learns it (tessera/dev/pack.h). */
    if (uses_bad_reply) {
        fprintf(f, "tsr_bad_reply:\n    tsr_packer_reply_bad(tsr_p, \"%s\", tsr_why);\n    ", c->name);
        emit_return_zero(f, gc);
        fprintf(f, "\n");
    }
    fprintf(f, "}\n\n");
}

static void emit_local_custom_protos(FILE *f, const gen_cmd *gc)
{
    const spec_command *c = gc->sc;
    fprintf(f, "%s tsr_packer_%s_%s(tsr_packer *tsr_p", c->ret, gc->is_local ? "local" : "custom", c->name);
    if (c->nparams)
        fprintf(f, ", ");
    gen_print_params(f, c, 0, 0);
    fprintf(f, ");\n");
    if (gc->is_custom)
        fprintf(
            f,
            "int tsr_unpack_custom_%s(struct tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len,\n"
            "                        size_t *pos, tsr_error *err);\n",
            c->name);
}

static void emit_wire_h(const gen *g)
{
    FILE *f = gen_open(g, "src/wire_gen.h");
    fprintf(
        f,
        "/* Opcodes and packers of every spec command (private to libtessera, its\n"
        " * tests and benchmarks; never installed). Fixed-size commands pack inline. */\n"
        "#ifndef TSR_WIRE_GEN_H\n#define TSR_WIRE_GEN_H\n\n"
        "#include <string.h>\n#include \"tessera/dev/pack.h\"\n\n"
        "_Static_assert(sizeof(GLintptr) == 8 && sizeof(GLsizeiptr) == 8, \"wire sizes assume 64-bit GLintptr\");\n"
        "_Static_assert(sizeof(GLboolean) == 1 && sizeof(GLenum) == 4 && sizeof(GLdouble) == 8, \"GL type sizes\");\n\n"
        "struct tsr_unpacker;\n\nenum tsr_opcode {\n");
    for (size_t i = 0; i < g->ncmds; i++)
        fprintf(f, "    TSR_OP_%s = %d,\n", g->cmds[i].sc->name, g->cmds[i].sc->opcode);
    fprintf(f, "};\n\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const gen_cmd *gc = &g->cmds[i];
        if (gc->is_local || gc->is_custom)
            emit_local_custom_protos(f, gc);
    }
    fprintf(f, "\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const gen_cmd *gc = &g->cmds[i];
        if (!gc->packable)
            continue;
        if (is_inline_pack(gc)) {
            emit_inline_pack(f, gc);
        } else {
            emit_pack_signature(f, gc, "");
            fprintf(f, ";\n");
        }
    }
    fprintf(f, "\n#endif\n");
    gen_close(f);
}

static void emit_pack_c(const gen *g)
{
    FILE *f = gen_open(g, "src/pack_gen.c");
    fprintf(f, "/* Out-of-line packers (variable size, replies, extended opcodes) and the\n"
               " * dispatch filler that turns a packer into an SPU table. */\n"
               "#include <stdint.h>\n#include <string.h>\n#include \"wire_gen.h\"\n"
               "#include \"wire/wire_internal.h\"\n\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const gen_cmd *gc = &g->cmds[i];
        if (gc->packable && !is_inline_pack(gc))
            emit_outline_pack(f, gc);
    }
    for (size_t i = 0; i < g->ncmds; i++) {
        const gen_cmd *gc = &g->cmds[i];
        const spec_command *c = gc->sc;
        fprintf(f, "static %s pk_%s(", c->ret, c->name);
        gen_print_params(f, c, 1, 0);
        fprintf(f, ")\n{\n");
        /* an inline packer's early answer runs here, where the packer's
         * internal header is seen */
        if (gc->packable && is_inline_pack(gc) && pack_answer(c))
            fprintf(f, "    tsr_packer *tsr_p = (tsr_packer *)self;\n    %s\n", pack_answer(c));
        fprintf(f, "    %s", gc->is_void ? "" : "return ");
        if (gc->packable)
            fprintf(f, "tsr_pack_%s((tsr_packer *)self", c->name);
        else
            fprintf(f, "tsr_packer_%s_%s((tsr_packer *)self", gc->is_local ? "local" : "custom", c->name);
        gen_print_args(f, c, 1);
        fprintf(f, ");\n}\n");
    }
    fprintf(f, "\nvoid tsr_packer_fill_dispatch(tsr_packer *p, tsr_dispatch *d)\n{\n");
    for (size_t i = 0; i < g->ncmds; i++)
        fprintf(f, "    tsr_set_%s(d, pk_%s, p);\n", g->cmds[i].sc->name, g->cmds[i].sc->name);
    fprintf(f, "}\n");
    gen_close(f);
}

/* --- unpacker ------------------------------------------------------------ */

static void emit_call(FILE *f, const gen_cmd *gc, const char *table, int with_ret)
{
    const spec_command *c = gc->sc;
    fprintf(f, "    %stsr_call_%s(%s", with_ret && !gc->is_void ? "tsr_ret = " : "", c->name, table);
    for (size_t i = 0; i < c->nparams; i++) {
        const gen_param *gp = &gc->params[i];
        if (gp->kind == GEN_P_OUT)
            fprintf(f, ", (%s)tsr_out_%s", gp->sp->type, gp->sp->name);
        else
            fprintf(f, ", %s", gp->sp->name);
    }
    fprintf(f, ");\n");
}

static int is_inline_unpack(const gen_cmd *gc) { return gc->packable && !gc->is_reply && !gc->nvar; }

/* Decoding of a fixed-size command, inline in the switch: `tsr_pos` is the
 * data offset, aligned here. */
static void emit_inline_case(FILE *f, const gen_cmd *gc)
{
    const spec_command *c = gc->sc;
    fprintf(f, "    case %d: { /* %s */\n", c->opcode, c->name);
    if (gc->align > 1)
        fprintf(f, "        tsr_pos = (tsr_pos + %zuu) & ~(size_t)%zuu;\n", gc->align - 1, gc->align - 1);
    fprintf(f, "        if (TSR_UNLIKELY(tsr_pos + %zuu > tsr_len)) { tsr_need = %zu; goto tsr_truncated; }\n",
            gc->fixed_size, gc->fixed_size);
    fprintf(f, "        const uint8_t *tsr_a = tsr_b + tsr_pos;\n        (void)tsr_a;\n");
    for (size_t i = 0; i < c->nparams; i++) {
        const gen_param *gp = &gc->params[i];
        const spec_param *sp = gp->sp;
        if (gp->kind == GEN_P_SCALAR)
            fprintf(f, "        %s %s;\n        memcpy(&%s, tsr_a + %zu, %zu);\n", sp->type, sp->name, sp->name,
                    gp->offset, gp->size);
        else
            fprintf(f, "        %s%s%s = (%s)(tsr_a + %zu);\n", sp->type,
                    sp->type[strlen(sp->type) - 1] == '*' ? "" : " ", sp->name, sp->type, gp->offset);
    }
    const char *hook = unpack_hook(c);
    if (hook)
        fprintf(f, "        %s\n", hook);
    if (unpack_drop(c))
        fprintf(f, "        if (!(%s))\n        ", unpack_drop(c));
    else
        fprintf(f, "    ");
    emit_call(f, gc, "tsr_d", 0);
    fprintf(f, "        tsr_pos += %zuu;\n        break;\n    }\n", gc->fixed_size);
}

static void emit_outline_unpack(FILE *f, const gen_cmd *gc)
{
    const spec_command *c = gc->sc;
    fprintf(f,
            "static int up_%s(tsr_unpacker *u, const tsr_dispatch *tsr_d, const uint8_t *tsr_b, size_t tsr_len,\n"
            "                 size_t *tsr_pos, tsr_error *err)\n{\n"
            "    const char *tsr_why = NULL;\n"
            "    (void)u;\n"
            "    size_t tsr_at = (*tsr_pos + %zuu) & ~(size_t)%zuu;\n"
            "    if (tsr_at + %zuu > tsr_len) { tsr_why = \"truncated\"; goto tsr_invalid; }\n"
            "    const uint8_t *tsr_a = tsr_b + tsr_at;\n    (void)tsr_a;\n",
            c->name, gc->align - 1, gc->align - 1, gc->fixed_size);
    declare_layouts(f, gc, 1);
    for (size_t i = 0; i < c->nparams; i++) {
        const gen_param *gp = &gc->params[i];
        const spec_param *sp = gp->sp;
        if (gp->kind == GEN_P_SCALAR)
            fprintf(f, "    %s %s;\n    memcpy(&%s, tsr_a + %zu, %zu);\n", sp->type, sp->name, sp->name, gp->offset,
                    gp->size);
        else if (gp->kind == GEN_P_FIXED)
            fprintf(f, "    %s%s%s = (%s)(tsr_a + %zu);\n", sp->type, sp->type[strlen(sp->type) - 1] == '*' ? "" : " ",
                    sp->name, sp->type, gp->offset);
    }
    if (gc->is_reply)
        fprintf(f, "    uint32_t tsr_id;\n    memcpy(&tsr_id, tsr_a + %zu, 4);\n", gc->reqid_offset);
    fprintf(f, "    size_t tsr_q = tsr_at + %zuu;\n", gc->fixed_size);
    for (size_t i = 0; i < c->nparams; i++) {
        const gen_param *gp = &gc->params[i];
        if (gp->kind != GEN_P_VAR)
            continue;
        const spec_param *sp = gp->sp;
        const char *n = sp->name;
        fprintf(f,
                "    %s%s%s = NULL;\n"
                "    tsr_q = (tsr_q + 7u) & ~(size_t)7u;\n"
                "    if (tsr_q + 8u > tsr_len) { tsr_why = \"truncated before the length of %s\"; goto tsr_invalid; }\n"
                "    uint64_t tsr_got_%s = tsr_wire_get_u64(tsr_b + tsr_q);\n"
                "    tsr_q += 8u;\n"
                "    if (tsr_got_%s == TSR_WIRE_NULL) {\n",
                sp->type, sp->type[strlen(sp->type) - 1] == '*' ? "" : " ", n, n, n, n);
        if (!sp->nullable)
            fprintf(f, "        tsr_why = \"NULL %s\"; goto tsr_invalid;\n", n);
        /* An offset into the receiver's GL_PIXEL_UNPACK_BUFFER: only with
         * one bound there (GL bounds-checks the offset in the buffer), so
         * a stream never makes the receiver's GL read a pointer of its
         * choosing. */
        if (needs_layout(gp))
            fprintf(
                f,
                "    } else if (tsr_got_%s == TSR_WIRE_OFFSET) {\n"
                "        if (!u->pixels.unpack_buffer) { tsr_why = \"an offset for %s with no pixel unpack buffer bound\"; goto tsr_invalid; }\n"
                "        if (tsr_q + 8u > tsr_len) { tsr_why = \"truncated before the offset of %s\"; goto tsr_invalid; }\n"
                "        %s = (%s)(uintptr_t)tsr_wire_get_u64(tsr_b + tsr_q);\n"
                "        tsr_q += 8u;\n",
                n, n, n, n, sp->type);
        fprintf(
            f,
            "    } else {\n"
            "        if (tsr_got_%s > tsr_len - tsr_q) { tsr_why = \"length of %s beyond the buffer\"; goto tsr_invalid; }\n"
            "        %s = (%s)(tsr_b + tsr_q);\n"
            "        tsr_q += (size_t)tsr_got_%s;\n",
            n, n, n, sp->type, n);
        if (sp->count.kind == SPEC_COUNT_STRING) {
            fprintf(
                f,
                "        if (!tsr_got_%s || ((const char *)%s)[tsr_got_%s - 1] != '\\0') { tsr_why = \"string %s is not NUL-terminated\"; goto tsr_invalid; }\n",
                n, n, n, n);
        } else {
            gen_emit_count(f, gc, gp, "&u->pixels.unpack");
            fprintf(
                f,
                "        if (tsr_len_%s != tsr_got_%s) { tsr_why = \"length of %s does not match its count\"; goto tsr_invalid; }\n",
                n, n, n);
        }
        fprintf(f, "    }\n");
    }
    /* Outputs: sized from the arguments (pack pixel store), allocated by
     * the unpacker, zero-filled. */
    int nout = 0;
    for (size_t i = 0; i < c->nparams; i++) {
        const gen_param *gp = &gc->params[i];
        if (gp->kind != GEN_P_OUT)
            continue;
        gen_emit_count(f, gc, gp, "&u->pixels.pack");
        nout++;
    }
    if (nout) {
        fprintf(f, "    uint64_t tsr_osize[%d] = {", nout);
        for (size_t i = 0; i < c->nparams; i++)
            if (gc->params[i].kind == GEN_P_OUT)
                fprintf(f, "tsr_len_%s, ", gc->params[i].sp->name);
        fprintf(f, "};\n    uint8_t *tsr_optr[%d];\n", nout);
        fprintf(
            f,
            "    if (tsr_unpacker_outputs(u, %d, tsr_osize, tsr_optr) != 0) { tsr_why = u->outputs_why; goto tsr_invalid; }\n",
            nout);
        int k = 0;
        for (size_t i = 0; i < c->nparams; i++)
            if (gc->params[i].kind == GEN_P_OUT)
                fprintf(f, "    void *tsr_out_%s = tsr_optr[%d];\n", gc->params[i].sp->name, k++);
    }
    const char *hook = unpack_hook(c);
    if (hook)
        fprintf(f, "    %s\n", hook);
    if (!gc->is_void)
        fprintf(f, "    %s tsr_ret;\n", c->ret);
    emit_call(f, gc, "tsr_d", 1);
    if (gc->is_reply) {
        if (gc->is_void)
            fprintf(f, "    const void *tsr_rv = NULL;\n    uint64_t tsr_rvlen = TSR_WIRE_NULL;\n");
        else if (gc->ret_is_string)
            fprintf(
                f,
                "    const void *tsr_rv = tsr_ret;\n    uint64_t tsr_rvlen = tsr_ret ? strlen((const char *)tsr_ret) + 1u : 0u;\n");
        else
            fprintf(f, "    const void *tsr_rv = &tsr_ret;\n    uint64_t tsr_rvlen = sizeof tsr_ret;\n");
        if (nout)
            fprintf(
                f, "    int tsr_rc = tsr_unpacker_reply(u, tsr_id, tsr_rv, tsr_rvlen, %d, tsr_osize, tsr_optr, err);\n",
                nout);
        else
            fprintf(f, "    int tsr_rc = tsr_unpacker_reply(u, tsr_id, tsr_rv, tsr_rvlen, 0, NULL, NULL, err);\n");
        fprintf(f, "    if (tsr_rc)\n        return tsr_rc;\n");
    }
    fprintf(
        f,
        "    *tsr_pos = tsr_q;\n    return 0;\n"
        "tsr_invalid:\n"
        "    return tsr_error_set(err, TSR_EPROTO, \"command %s (opcode %d) at data offset %%zu: %%s\", *tsr_pos, tsr_why);\n"
        "}\n\n",
        c->name, c->opcode);
}

static void emit_case(FILE *f, const gen_cmd *gc)
{
    if (gc->is_custom)
        fprintf(f,
                "    case %d: /* %s */\n"
                "        if (tsr_unpack_custom_%s(u, tsr_d, tsr_b, tsr_len, &tsr_pos, err) != 0)\n"
                "            return err->code;\n        break;\n",
                gc->sc->opcode, gc->sc->name, gc->sc->name);
    else if (is_inline_unpack(gc))
        emit_inline_case(f, gc);
    else
        fprintf(f,
                "    case %d: /* %s */\n"
                "        if (up_%s(u, tsr_d, tsr_b, tsr_len, &tsr_pos, err) != 0)\n"
                "            return err->code;\n        break;\n",
                gc->sc->opcode, gc->sc->name, gc->sc->name);
}

static void emit_unpack_c(const gen *g)
{
    FILE *f = gen_open(g, "src/unpack_gen.c");
    fprintf(f, "/* The validating decoder: walks the opcodes of one buffer and calls the\n"
               " * target table; every length is checked before it is used. */\n"
               "#include <stdint.h>\n#include <string.h>\n#include \"wire_gen.h\"\n#include \"tessera/dev/unpack.h\"\n"
               "#include \"wire/wire_internal.h\"\n\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const gen_cmd *gc = &g->cmds[i];
        if ((gc->packable && !is_inline_unpack(gc)))
            emit_outline_unpack(f, gc);
    }
    fprintf(
        f,
        "int tsr_unpack_commands(tsr_unpacker *u, const tsr_dispatch *tsr_d, const uint8_t *tsr_b, uint32_t tsr_nops,\n"
        "                        size_t tsr_len, tsr_error *err)\n{\n"
        "    /* Starts at the unpacker's resume point (0, 0 for a new buffer). */\n"
        "    size_t tsr_pos = u->resume_pos, tsr_at = 0, tsr_need = 0;\n"
        "    uint32_t tsr_op = 0;\n"
        "    for (uint32_t tsr_k = u->resume_command; tsr_k < tsr_nops; tsr_k++) {\n"
        "        tsr_at = tsr_pos;\n"
        "        tsr_op = tsr_b[-1 - (ptrdiff_t)tsr_k];\n"
        "        switch (tsr_op) {\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const gen_cmd *gc = &g->cmds[i];
        if ((gc->packable || gc->is_custom) && gc->sc->opcode < 255)
            emit_case(f, gc);
    }
    fprintf(
        f,
        "    case 255: {\n"
        "        tsr_pos = (tsr_pos + 7u) & ~(size_t)7u;\n"
        "        if (tsr_pos + 8u > tsr_len) { tsr_need = 8; goto tsr_truncated; }\n"
        "        tsr_op = tsr_wire_get_u32(tsr_b + tsr_pos);\n"
        "        uint32_t tsr_xlen = tsr_wire_get_u32(tsr_b + tsr_pos + 4);\n"
        "        tsr_pos += 8u;\n"
        "        size_t tsr_xstart = tsr_pos;\n"
        "        if (tsr_xlen != TSR_WIRE_EXT_LEN_UNKNOWN && tsr_xlen > tsr_len - tsr_pos) { tsr_need = tsr_xlen; goto tsr_truncated; }\n"
        "        switch (tsr_op) {\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const gen_cmd *gc = &g->cmds[i];
        if ((gc->packable || gc->is_custom) && gc->sc->opcode >= 255)
            emit_case(f, gc);
    }
    fprintf(
        f,
        "        default:\n"
        "            return tsr_error_set(err, TSR_EPROTO, \"unknown extended opcode %%u at data offset %%zu\", tsr_op, tsr_at);\n"
        "        }\n"
        "        if (tsr_xlen != TSR_WIRE_EXT_LEN_UNKNOWN && tsr_pos - tsr_xstart != tsr_xlen)\n"
        "            return tsr_error_set(err, TSR_EPROTO, \"command %%s (opcode %%u) at data offset %%zu: length %%u in the extended header, %%zu used\",\n"
        "                                 tsr_wire_opcode_name(tsr_op), tsr_op, tsr_at, tsr_xlen, tsr_pos - tsr_xstart);\n"
        "        break;\n    }\n"
        "    default:\n"
        "        return tsr_error_set(err, TSR_EPROTO, \"unknown opcode %%u (command #%%u) at data offset %%zu\", tsr_op, tsr_k, tsr_at);\n"
        "        }\n"
        "        /* A handler asked to stop here (tsr_unpacker_yield): remember\n"
        "         * where the next command starts. */\n"
        "        if (TSR_UNLIKELY(u->yield)) {\n"
        "            u->yield = 0;\n"
        "            u->resume_command = tsr_k + 1;\n"
        "            u->resume_pos = tsr_pos;\n"
        "            return TSR_UNPACK_YIELDED;\n"
        "        }\n"
        "    }\n"
        "    if (tsr_pos != tsr_len)\n"
        "        return tsr_error_set(err, TSR_EPROTO, \"%%zu data bytes after the last command (offset %%zu)\", tsr_len - tsr_pos, tsr_pos);\n"
        "    return 0;\n"
        "tsr_truncated:\n"
        "    return tsr_error_set(err, TSR_EPROTO, \"command %%s (opcode %%u) at data offset %%zu: truncated (needs %%zu bytes, %%zu left)\",\n"
        "                         tsr_wire_opcode_name(tsr_op) ? tsr_wire_opcode_name(tsr_op) : \"?\", tsr_op, tsr_at, tsr_need,\n"
        "                         tsr_pos <= tsr_len ? tsr_len - tsr_pos : 0);\n"
        "}\n");
    gen_close(f);
}

static int cmp_opcode(const void *a, const void *b)
{
    const gen_cmd *x = *(const gen_cmd *const *)a, *y = *(const gen_cmd *const *)b;
    return (x->sc->opcode > y->sc->opcode) - (x->sc->opcode < y->sc->opcode);
}

static void emit_tables(const gen *g)
{
    FILE *f = gen_open(g, "src/wire_tables_gen.c");
    fprintf(f, "/* Tables of the wire: pname element counts and opcode names. */\n"
               "#include <stdlib.h>\n#include \"wire_gen.h\"\n\n");
    fprintf(f, "int tsr_wire_pname_count(GLenum pname)\n{\n    switch (pname) {\n");
    /* Two pnames with one value (aliases) must agree; the first wins. */
    for (size_t i = 0; i < g->s->npnames; i++) {
        int found;
        unsigned long long v = gen_enum_value(&g->enums, g->s->pnames[i].name, &found);
        int dup = 0;
        for (size_t j = 0; j < i; j++) {
            int f2;
            if (gen_enum_value(&g->enums, g->s->pnames[j].name, &f2) == v)
                dup = 1;
        }
        if (!dup)
            fprintf(f, "    case 0x%llx: return %d; /* %s */\n", v, g->s->pnames[i].count, g->s->pnames[i].name);
    }
    fprintf(f, "    default: return -1;\n    }\n}\n\n");
    fprintf(f, "int tsr_wire_map_components(GLenum target)\n{\n    switch (target) {\n");
    for (size_t i = 0; i < g->s->nmap_components; i++) {
        int found;
        unsigned long long v = gen_enum_value(&g->enums, g->s->map_components[i].name, &found);
        fprintf(f, "    case 0x%llx: return %d; /* %s */\n", v, g->s->map_components[i].count,
                g->s->map_components[i].name);
    }
    fprintf(f, "    default: return -1;\n    }\n}\n\n");
    const gen_cmd **v = malloc((g->ncmds ? g->ncmds : 1) * sizeof *v);
    for (size_t i = 0; i < g->ncmds; i++)
        v[i] = &g->cmds[i];
    qsort(v, g->ncmds, sizeof *v, cmp_opcode);
    fprintf(f, "static const struct { unsigned opcode; const char *name; } names[] = {\n");
    for (size_t i = 0; i < g->ncmds; i++)
        fprintf(f, "    {%d, \"%s\"},\n", v[i]->sc->opcode, v[i]->sc->name);
    fprintf(f, "};\n\n");
    free(v);
    fprintf(
        f,
        "const char *tsr_wire_opcode_name(uint32_t opcode)\n{\n"
        "    size_t lo = 0, hi = sizeof names / sizeof names[0];\n"
        "    while (lo < hi) {\n        size_t mid = (lo + hi) / 2;\n"
        "        if (names[mid].opcode == opcode)\n            return names[mid].name;\n"
        "        if (names[mid].opcode < opcode)\n            lo = mid + 1;\n        else\n            hi = mid;\n    }\n"
        "    return NULL;\n}\n\n");
    fprintf(f, "static const unsigned short slot_opcodes[TSR_DISPATCH_COUNT] = {\n");
    for (size_t i = 0; i < g->ncmds; i++)
        fprintf(f, "    %d, /* %s */\n", g->cmds[i].sc->opcode, g->cmds[i].sc->name);
    fprintf(f, "};\n\nint tsr_wire_slot_opcode(int slot)\n{\n"
               "    return slot >= 0 && slot < TSR_DISPATCH_COUNT ? (int)slot_opcodes[slot] : -1;\n}\n");
    gen_close(f);
}

void gen_emit_wire(const gen *g)
{
    emit_wire_h(g);
    emit_pack_c(g);
    emit_unpack_c(g);
    emit_tables(g);
}
