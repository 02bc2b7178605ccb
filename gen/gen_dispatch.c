/* gen/gen_dispatch.c — emits the dispatch table (tessera/dispatch_gen.h,
 * dispatch_gen.c), the real-GL procs table used by the render SPU
 * (tessera/glprocs_gen.h, glprocs_gen.c), the prototypes of tessera's own
 * GL extensions (tessera/gltsr_gen.h) and the exported gl* entry points of
 * libtessera_gl (gl_entry_gen.c). Never emits code with global state except
 * constant tables. */
#include "gen.h"

#include <stdlib.h>
#include <string.h>

static void emit_return_zero(FILE *f, const spec_command *c)
{
    if (gen_is_void(c->ret))
        fprintf(f, "return;");
    else
        fprintf(f, "return (%s)0;", c->ret);
}

static void emit_dispatch_h(const gen *g)
{
    FILE *f = gen_open(g, "include/tessera/dispatch_gen.h");
    /* Part of tessera/dispatch.h, which defines tsr_entry before including
     * it; included on its own it includes that header instead, which then
     * brings this one in at the right place. */
    fprintf(f, "/* The dispatch table type: one tsr_entry per spec command, in spec order.\n"
               " * Part of tessera/dispatch.h (read that header first), which includes it\n"
               " * once tsr_entry is defined; included alone it includes that header. */\n"
               "#ifndef TESSERA_DISPATCH_H\n#include \"tessera/dispatch.h\"\n"
               "#elif !defined(TESSERA_DISPATCH_GEN_H)\n#define TESSERA_DISPATCH_GEN_H\n\n"
               "#include <GL/gl.h>\n#include <GL/glext.h>\n\n"
               "#ifdef __cplusplus\nextern \"C\" {\n#endif\n\n");
    fprintf(f, "#define TSR_DISPATCH_COUNT %zu\n\n", g->ncmds);
    for (size_t i = 0; i < g->ncmds; i++) {
        const spec_command *c = g->cmds[i].sc;
        fprintf(f, "typedef %s (*tsr_fn_%s)(", c->ret, c->name);
        gen_print_params(f, c, 1, 0);
        fprintf(f, ");\n");
    }
    fprintf(f, "\ntypedef struct tsr_dispatch {\n    union {\n        struct {\n");
    for (size_t i = 0; i < g->ncmds; i++)
        fprintf(f, "            tsr_entry %s;\n", g->cmds[i].sc->name);
    fprintf(f, "        };\n        tsr_entry slots[TSR_DISPATCH_COUNT];\n    };\n} tsr_dispatch;\n\n");
    for (size_t i = 0; i < g->ncmds; i++)
        fprintf(f, "#define TSR_SLOT_%s %zu\n", g->cmds[i].sc->name, i);
    fprintf(f, "\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const spec_command *c = g->cmds[i].sc;
        fprintf(f, "static inline %s tsr_call_%s(const tsr_dispatch *d", c->ret, c->name);
        if (c->nparams)
            fprintf(f, ", ");
        gen_print_params(f, c, 0, 0);
        fprintf(f, ")\n{\n    %s((tsr_fn_%s)d->%s.fn)(d->%s.self", gen_is_void(c->ret) ? "" : "return ", c->name,
                c->name, c->name);
        gen_print_args(f, c, 1);
        fprintf(f, ");\n}\n");
        fprintf(f,
                "static inline void tsr_set_%s(tsr_dispatch *d, tsr_fn_%s fn, void *self)\n"
                "{\n    d->%s.fn = (tsr_proc)fn;\n    d->%s.self = self;\n}\n",
                c->name, c->name, c->name, c->name);
    }
    fprintf(f, "\n#ifdef __cplusplus\n}\n#endif\n#endif\n");
    gen_close(f);
}

static int name_cmp(const void *a, const void *b)
{
    const gen_cmd *x = *(const gen_cmd *const *)a, *y = *(const gen_cmd *const *)b;
    return strcmp(x->sc->name, y->sc->name);
}

static void emit_nop(FILE *f, const spec_command *c, const char *prefix)
{
    fprintf(f, "static %s %s%s(", c->ret, prefix, c->name);
    gen_print_params(f, c, 1, 0);
    fprintf(f, ")\n{\n    (void)self;\n");
    for (size_t k = 0; k < c->nparams; k++)
        fprintf(f, "    (void)%s;\n", c->params[k].name);
    fprintf(f, "    ");
    emit_return_zero(f, c);
    fprintf(f, "\n}\n");
}

static const char *category_enum(const char *category)
{
    static const char *const names[][2] = {
        {"geometry", "TSR_CAT_GEOMETRY"}, {"state", "TSR_CAT_STATE"},   {"frame", "TSR_CAT_FRAME"},
        {"get", "TSR_CAT_GET"},           {"object", "TSR_CAT_OBJECT"}, {"client", "TSR_CAT_CLIENT"},
        {"special", "TSR_CAT_SPECIAL"},
    };
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!strcmp(names[i][0], category))
            return names[i][1];
    return "TSR_CAT_SPECIAL"; /* the spec loader rejects unknown categories */
}

static int has_output(const spec_command *c)
{
    if (!gen_is_void(c->ret))
        return 1;
    for (size_t k = 0; k < c->nparams; k++)
        if (c->params[k].dir_out)
            return 1;
    return 0;
}

/* Per-slot category and flags (tessera/dispatch.h). */
static void emit_slot_info(FILE *f, const gen *g)
{
    fprintf(f, "\nstatic const unsigned char slot_categories[TSR_DISPATCH_COUNT] = {\n");
    for (size_t i = 0; i < g->ncmds; i++)
        fprintf(f, "    %s, /* %s */\n", category_enum(g->cmds[i].sc->category), g->cmds[i].sc->name);
    fprintf(f, "};\n\nstatic const unsigned char slot_flags[TSR_DISPATCH_COUNT] = {\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const spec_command *c = g->cmds[i].sc;
        fprintf(f, "    0%s%s%s,\n", has_output(c) ? " | TSR_CMD_OUTPUT" : "",
                c->wire == SPEC_WIRE_LOCAL ? " | TSR_CMD_LOCAL" : "", c->vertex ? " | TSR_CMD_POSITION" : "");
    }
    fprintf(f, "};\n\n"
               "int tsr_dispatch_category(int slot)\n{\n"
               "    return slot < 0 || slot >= TSR_DISPATCH_COUNT ? -1 : (int)slot_categories[slot];\n}\n\n"
               "unsigned tsr_dispatch_flags(int slot)\n{\n"
               "    return slot < 0 || slot >= TSR_DISPATCH_COUNT ? 0u : (unsigned)slot_flags[slot];\n}\n");
}

/* One hook and one tee trampoline per command, each calling typed
 * function pointers, and the tables that install them by slot. */
static void emit_wrappers(FILE *f, const gen *g)
{
    for (size_t i = 0; i < g->ncmds; i++) {
        const spec_command *c = g->cmds[i].sc;
        int value = !gen_is_void(c->ret);
        fprintf(f, "\nstatic %s hook_%s(", c->ret, c->name);
        gen_print_params(f, c, 1, 0);
        fprintf(
            f,
            ")\n{\n    tsr_hook *tsr_h_ = self;\n    if (tsr_h_->before)\n        tsr_h_->before(tsr_h_->ctx, %zu);\n    ",
            i);
        if (value)
            fprintf(f, "%s tsr_result_ = ", c->ret);
        fprintf(f, "((tsr_fn_%s)tsr_h_->next.fn)(tsr_h_->next.self", c->name);
        gen_print_args(f, c, 1);
        fprintf(f, ");\n    if (tsr_h_->after)\n        tsr_h_->after(tsr_h_->ctx, %zu);\n", i);
        if (value)
            fprintf(f, "    return tsr_result_;\n");
        fprintf(f, "}\n");
        fprintf(f, "static %s tee_%s(", c->ret, c->name);
        gen_print_params(f, c, 1, 0);
        fprintf(f, ")\n{\n    tsr_tee *tsr_t_ = self;\n    ((tsr_fn_%s)tsr_t_->first.fn)(tsr_t_->first.self", c->name);
        gen_print_args(f, c, 1);
        fprintf(f, ");\n    %s((tsr_fn_%s)tsr_t_->second.fn)(tsr_t_->second.self", value ? "return " : "", c->name);
        gen_print_args(f, c, 1);
        fprintf(f, ");\n}\n");
    }
    fprintf(f, "\nstatic const tsr_proc hook_fns[TSR_DISPATCH_COUNT] = {\n");
    for (size_t i = 0; i < g->ncmds; i++)
        fprintf(f, "    (tsr_proc)hook_%s,\n", g->cmds[i].sc->name);
    fprintf(f, "};\n\nstatic const tsr_proc tee_fns[TSR_DISPATCH_COUNT] = {\n");
    for (size_t i = 0; i < g->ncmds; i++)
        fprintf(f, "    (tsr_proc)tee_%s,\n", g->cmds[i].sc->name);
    fprintf(f, "};\n\n"
               "void tsr_dispatch_hook(tsr_dispatch *d, int slot, tsr_hook *hook)\n{\n"
               "    if (slot < 0 || slot >= TSR_DISPATCH_COUNT)\n        return;\n"
               "    hook->next = d->slots[slot];\n"
               "    d->slots[slot].fn = hook_fns[slot];\n    d->slots[slot].self = hook;\n}\n\n"
               "void tsr_dispatch_tee(tsr_dispatch *d, int slot, tsr_tee *tee)\n{\n"
               "    if (slot < 0 || slot >= TSR_DISPATCH_COUNT)\n        return;\n"
               "    d->slots[slot].fn = tee_fns[slot];\n    d->slots[slot].self = tee;\n}\n");
}

static void emit_dispatch_c(const gen *g)
{
    FILE *f = gen_open(g, "src/dispatch_gen.c");
    fprintf(f, "/* Slot names, name lookup and the no-op table (tessera/dispatch.h). */\n"
               "#include <stdlib.h>\n#include <string.h>\n#include \"tessera/dispatch.h\"\n\n");
    fprintf(f, "static const char *const slot_names[TSR_DISPATCH_COUNT] = {\n");
    for (size_t i = 0; i < g->ncmds; i++)
        fprintf(f, "    \"%s\",\n", g->cmds[i].sc->name);
    fprintf(f, "};\n\n");
    const gen_cmd **sorted = malloc((g->ncmds ? g->ncmds : 1) * sizeof *sorted);
    for (size_t i = 0; i < g->ncmds; i++)
        sorted[i] = &g->cmds[i];
    qsort(sorted, g->ncmds, sizeof *sorted, name_cmp);
    fprintf(f,
            "/* Slots sorted by name, for bsearch. */\nstatic const unsigned short by_name[TSR_DISPATCH_COUNT] = {\n");
    for (size_t i = 0; i < g->ncmds; i++)
        fprintf(f, "    %d, /* %s */\n", sorted[i]->slot, sorted[i]->sc->name);
    fprintf(f, "};\n\n");
    free(sorted);
    fprintf(
        f,
        "static int compare_name(const void *key, const void *elem)\n"
        "{\n    return strcmp((const char *)key, slot_names[*(const unsigned short *)elem]);\n}\n\n"
        "int tsr_dispatch_slot(const char *name)\n{\n"
        "    if (!name)\n        return -1;\n"
        "    if (name[0] == 'g' && name[1] == 'l' && name[2] >= 'A' && name[2] <= 'Z')\n"
        "        name += 2;\n"
        "    const unsigned short *hit = bsearch(name, by_name, TSR_DISPATCH_COUNT, sizeof by_name[0], compare_name);\n"
        "    return hit ? (int)*hit : -1;\n}\n\n"
        "const char *tsr_dispatch_name(int slot)\n{\n"
        "    if (slot < 0 || slot >= TSR_DISPATCH_COUNT)\n        return NULL;\n"
        "    return slot_names[slot];\n}\n\n");
    for (size_t i = 0; i < g->ncmds; i++)
        emit_nop(f, g->cmds[i].sc, "nop_");
    fprintf(f, "\nvoid tsr_dispatch_fill_nop(tsr_dispatch *d)\n{\n");
    for (size_t i = 0; i < g->ncmds; i++)
        fprintf(f, "    tsr_set_%s(d, nop_%s, NULL);\n", g->cmds[i].sc->name, g->cmds[i].sc->name);
    fprintf(f, "}\n");
    emit_slot_info(f, g);
    emit_wrappers(f, g);
    gen_close(f);
}

static void emit_glprocs(const gen *g)
{
    FILE *f = gen_open(g, "include/tessera/glprocs_gen.h");
    fprintf(f, "/* tsr_gl_procs: the real GL functions of every Khronos command in the spec,\n"
               " * resolved through a get-proc-address function (OSMesaGetProcAddress), so\n"
               " * code that renders never links against gl* symbols. */\n"
               "#ifndef TESSERA_GLPROCS_GEN_H\n#define TESSERA_GLPROCS_GEN_H\n\n"
               "#include \"tessera/dispatch.h\"\n#include \"tessera/error.h\"\n#include \"tessera/export.h\"\n\n"
               "#ifdef __cplusplus\nextern \"C\" {\n#endif\n\n"
               "typedef struct tsr_gl_procs {\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const spec_command *c = g->cmds[i].sc;
        if (!c->khronos)
            continue;
        fprintf(f, "    %s (GLAPIENTRY *%s)(", c->ret, c->name);
        gen_print_params(f, c, 0, 1);
        fprintf(f, ");\n");
    }
    fprintf(f, "} tsr_gl_procs;\n\n"
               "/* Resolves every function with getproc(\"glName\", ctx). Fails with TSR_ENOENT\n"
               " * naming the first function that does not resolve. */\n"
               "TSR_API int tsr_gl_procs_load(tsr_gl_procs *p, tsr_proc (*getproc)(const char *gl_name, void *ctx),\n"
               "                              void *ctx, tsr_error *err);\n"
               "/* Points every Khronos slot of `d` at a trampoline calling p's function\n"
               " * (self = p, which must outlive d); tessera's own (TSR) slots are untouched. */\n"
               "TSR_API void tsr_gl_procs_fill_dispatch(const tsr_gl_procs *p, tsr_dispatch *d);\n\n"
               "#ifdef __cplusplus\n}\n#endif\n#endif\n");
    gen_close(f);

    f = gen_open(g, "src/glprocs_gen.c");
    fprintf(f, "/* Loading and trampolines of tsr_gl_procs (tessera/glprocs_gen.h). */\n"
               "#include <stddef.h>\n#include \"tessera/glprocs_gen.h\"\n\n");
    fprintf(f, "int tsr_gl_procs_load(tsr_gl_procs *p, tsr_proc (*getproc)(const char *gl_name, void *ctx),\n"
               "                      void *ctx, tsr_error *err)\n{\n    tsr_proc fn;\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const spec_command *c = g->cmds[i].sc;
        if (!c->khronos)
            continue;
        fprintf(f,
                "    if (!(fn = getproc(\"gl%s\", ctx)))\n"
                "        return tsr_error_set(err, TSR_ENOENT, \"GL function gl%s is not available\");\n"
                "    p->%s = (%s (GLAPIENTRY *)(",
                c->name, c->name, c->name, c->ret);
        gen_print_params(f, c, 0, 1);
        fprintf(f, "))fn;\n");
    }
    fprintf(f, "    return TSR_OK;\n}\n\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const spec_command *c = g->cmds[i].sc;
        if (!c->khronos)
            continue;
        fprintf(f, "static %s tramp_%s(", c->ret, c->name);
        gen_print_params(f, c, 1, 0);
        fprintf(f, ")\n{\n    %s((const tsr_gl_procs *)self)->%s(", gen_is_void(c->ret) ? "" : "return ", c->name);
        gen_print_args(f, c, 0);
        fprintf(f, ");\n}\n");
    }
    fprintf(f, "\nvoid tsr_gl_procs_fill_dispatch(const tsr_gl_procs *p, tsr_dispatch *d)\n{\n"
               "    void *self = (void *)p;\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const spec_command *c = g->cmds[i].sc;
        if (c->khronos)
            fprintf(f, "    tsr_set_%s(d, tramp_%s, self);\n", c->name, c->name);
    }
    fprintf(f, "}\n");
    gen_close(f);
}

static void emit_gl_entry(const gen *g)
{
    FILE *f = gen_open(g, "include/tessera/gltsr_gen.h");
    fprintf(f, "/* Prototypes of tessera's own GL extension entry points (exported by\n"
               " * libtessera_gl like every other gl* function of the spec). */\n"
               "#ifndef TESSERA_GLTSR_GEN_H\n#define TESSERA_GLTSR_GEN_H\n\n"
               "#include <GL/gl.h>\n#include <GL/glext.h>\n\n"
               "#ifdef __cplusplus\nextern \"C\" {\n#endif\n\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const spec_command *c = g->cmds[i].sc;
        if (c->khronos)
            continue;
        fprintf(f, "GLAPI %s GLAPIENTRY gl%s(", c->ret, c->name);
        gen_print_params(f, c, 0, 1);
        fprintf(f, ");\n");
    }
    fprintf(f, "\n#ifdef __cplusplus\n}\n#endif\n#endif\n");
    gen_close(f);

    f = gen_open(g, "src/gl_entry_gen.c");
    fprintf(f,
            "/* Exported gl* entry points: each reads the calling thread's current table\n"
            " * (one TLS load) and jumps through its slot; no table: nothing happens\n"
            " * and 0 is returned, as GL does with no current context (logged once a\n"
            " * thread, tsr_gl_no_context). */\n"
            "#include \"tessera/dispatch.h\"\n#include \"tessera/gltsr_gen.h\"\n#include \"spu/glapi_internal.h\"\n\n"
            "/* gl.h declares a few parameters as arrays (GLfloat m[16]); ours are pointers. */\n"
            "#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 11\n"
            "#pragma GCC diagnostic ignored \"-Warray-parameter\"\n#endif\n\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const spec_command *c = g->cmds[i].sc;
        fprintf(f, "TSR_API %s GLAPIENTRY gl%s(", c->ret, c->name);
        gen_print_params(f, c, 0, 1);
        fprintf(f,
                ")\n{\n    const tsr_dispatch *d = tsr_gl_current_table;\n"
                "    if (__builtin_expect(d == NULL, 0)) {\n        tsr_gl_no_context(\"gl%s\");\n        ",
                c->name);
        emit_return_zero(f, c);
        fprintf(f, "\n    }");
        fprintf(f, "\n    %s((tsr_fn_%s)d->%s.fn)(d->%s.self", gen_is_void(c->ret) ? "" : "return ", c->name, c->name,
                c->name);
        gen_print_args(f, c, 1);
        fprintf(f, ");\n}\n");
    }
    gen_close(f);
}

void gen_emit_dispatch(const gen *g)
{
    emit_dispatch_h(g);
    emit_dispatch_c(g);
    emit_glprocs(g);
    emit_gl_entry(g);
}
