/* gen/gen_trace.c — emits the call tracer of the print SPU
 * (src/trace_gen.h, src/trace_gen.c): one readable line per call, enums by
 * name (table generated from the GL headers), floats with %g (or %a,
 * bit-exact, when the tracer's hex_floats is set), small
 * fixed-size vectors and strings by content, then the call goes on to the
 * child table. The generated code keeps no state outside the tracer
 * object it is given. */
#include "gen.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

static int by_value(const void *a, const void *b)
{
    const gen_enum *x = *(const gen_enum *const *)a, *y = *(const gen_enum *const *)b;
    if (x->value != y->value)
        return x->value < y->value ? -1 : 1;
    return x->seq < y->seq ? -1 : x->seq > y->seq;
}

/* Enum names worth printing: not extension markers (lowercase), not bit
 * masks, not version macros. */
static int printable_enum(const gen_enum *e)
{
    for (const char *p = e->name; *p; p++)
        if (islower((unsigned char)*p))
            return 0;
    size_t n = strlen(e->name);
    if (n > 4 && !strcmp(e->name + n - 4, "_BIT"))
        return 0;
    if (strstr(e->name, "_BITS") || !strncmp(e->name, "GL_VERSION_", 11))
        return 0;
    return e->value <= 0xFFFFFFFFull;
}

static void emit_scalar_print(FILE *f, const spec_param *p, const gen_type *t, const char *expr)
{
    if (!t) {
        fprintf(f, "    fprintf(tsr_t->out, \"%%p\", (const void *)%s);\n", expr);
    } else if (t->is_enum) {
        fprintf(f, "    tsr_trace_print_enum(tsr_t->out, %s);\n", expr);
    } else if (t->is_float) {
        fprintf(f, "    tsr_trace_print_float(tsr_t, (double)%s);\n", expr);
    } else if (!strcmp(p->base_type, "GLbitfield")) {
        fprintf(f, "    fprintf(tsr_t->out, \"0x%%x\", (unsigned)%s);\n", expr);
    } else if (!strcmp(p->base_type, "GLboolean")) {
        fprintf(f, "    fputs(%s ? \"GL_TRUE\" : \"GL_FALSE\", tsr_t->out);\n", expr);
    } else if (t->is_signed) {
        fprintf(f, "    fprintf(tsr_t->out, \"%%lld\", (long long)%s);\n", expr);
    } else {
        fprintf(f, "    fprintf(tsr_t->out, \"%%llu\", (unsigned long long)%s);\n", expr);
    }
}

static void emit_param_print(FILE *f, const spec_param *p)
{
    const gen_type *t = gen_type_find(p->base_type);
    if (p->pointer_depth == 0) {
        emit_scalar_print(f, p, t, p->name);
        return;
    }
    if (p->pointer_depth == 1 && !p->dir_out && p->count.kind == SPEC_COUNT_STRING) {
        fprintf(f, "    tsr_trace_print_string(tsr_t->out, (const char *)%s);\n", p->name);
        return;
    }
    if (p->pointer_depth == 1 && !p->dir_out && t && p->count.kind == SPEC_COUNT_FIXED && p->count.fixed <= 16) {
        fprintf(f,
                "    if (!%s) {\n        fputs(\"NULL\", tsr_t->out);\n    } else {\n        fputc('{', tsr_t->out);\n",
                p->name);
        fprintf(
            f,
            "        for (int i = 0; i < %ld; i++) {\n            if (i)\n                fputs(\", \", tsr_t->out);\n    ",
            p->count.fixed);
        char expr[128];
        snprintf(expr, sizeof expr, "%s[i]", p->name);
        emit_scalar_print(f, p, t, expr);
        fprintf(f, "        }\n        fputc('}', tsr_t->out);\n    }\n");
        return;
    }
    if (p->pointer_depth == 1 && !p->dir_out && t && p->count.kind == SPEC_COUNT_PNAME) {
        fprintf(
            f,
            "    {\n        int n = tsr_wire_pname_count((GLenum)%s);\n"
            "        if (!%s || n <= 0 || n > 16) {\n            fputs(%s ? \"<data>\" : \"NULL\", tsr_t->out);\n"
            "        } else {\n            fputc('{', tsr_t->out);\n"
            "            for (int i = 0; i < n; i++) {\n                if (i)\n                    fputs(\", \", tsr_t->out);\n    ",
            p->count.args[0], p->name, p->name);
        char expr[128];
        snprintf(expr, sizeof expr, "%s[i]", p->name);
        emit_scalar_print(f, p, t, expr);
        fprintf(f, "            }\n            fputc('}', tsr_t->out);\n        }\n    }\n");
        return;
    }
    /* Addresses differ between runs and processes: print presence only. */
    fprintf(f, "    fputs(%s ? \"<%s>\" : \"NULL\", tsr_t->out);\n", p->name, p->dir_out ? "out" : "data");
}

void gen_emit_trace(const gen *g)
{
    FILE *f = gen_open(g, "src/trace_gen.h");
    fprintf(f, "/* The call tracer of the print SPU. */\n"
               "#ifndef TSR_TRACE_GEN_H\n#define TSR_TRACE_GEN_H\n\n"
               "#include <stdio.h>\n#include \"tessera/dispatch.h\"\n\n"
               "typedef struct tsr_tracer {\n"
               "    FILE *out;                  /* one line per call */\n"
               "    const tsr_dispatch *child;  /* every call is forwarded here */\n"
               "    int hex_floats;             /* floats with %%a (exact bits), else %%g */\n"
               "} tsr_tracer;\n\n"
               "/* Sets every slot of `table` to a tracing function with self = t. */\n"
               "void tsr_trace_fill(tsr_dispatch *table, tsr_tracer *t);\n"
               "/* \"GL_TRIANGLES\" for 0x0004 (the first name the GL headers give a\n"
               " * value), NULL when unknown. */\n"
               "const char *tsr_trace_enum_name(GLenum value);\n"
               "void tsr_trace_print_enum(FILE *out, GLenum value);\n"
               "void tsr_trace_print_string(FILE *out, const char *s);\n"
               "void tsr_trace_print_float(const tsr_tracer *t, double v);\n\n#endif\n");
    gen_close(f);

    f = gen_open(g, "src/trace_gen.c");
    fprintf(f, "#include <stdlib.h>\n#include \"trace_gen.h\"\n#include \"tessera/dev/pack.h\"\n\n");
    const gen_enum **v = malloc((g->enums.n ? g->enums.n : 1) * sizeof *v);
    size_t n = 0;
    for (size_t i = 0; i < g->enums.n; i++)
        if (printable_enum(&g->enums.v[i]))
            v[n++] = &g->enums.v[i];
    qsort(v, n, sizeof *v, by_value);
    fprintf(f, "static const struct { GLenum value; const char *name; } enum_names[] = {\n");
    for (size_t i = 0; i < n; i++) {
        if (i && v[i]->value == v[i - 1]->value)
            continue;
        fprintf(f, "    {0x%llxu, \"%s\"},\n", v[i]->value, v[i]->name);
    }
    fprintf(f, "};\n\n");
    free(v);
    fprintf(
        f,
        "const char *tsr_trace_enum_name(GLenum value)\n{\n"
        "    size_t lo = 0, hi = sizeof enum_names / sizeof enum_names[0];\n"
        "    while (lo < hi) {\n        size_t mid = (lo + hi) / 2;\n"
        "        if (enum_names[mid].value == value)\n            return enum_names[mid].name;\n"
        "        if (enum_names[mid].value < value)\n            lo = mid + 1;\n        else\n            hi = mid;\n    }\n"
        "    return NULL;\n}\n\n"
        "void tsr_trace_print_enum(FILE *out, GLenum value)\n{\n"
        "    const char *name = tsr_trace_enum_name(value);\n"
        "    if (name)\n        fputs(name, out);\n    else\n        fprintf(out, \"0x%%x\", (unsigned)value);\n}\n\n"
        "void tsr_trace_print_float(const tsr_tracer *t, double v)\n{\n"
        "    if (t->hex_floats)\n        fprintf(t->out, \"%%a\", v);\n    else\n        fprintf(t->out, \"%%g\", v);\n}\n\n"
        "void tsr_trace_print_string(FILE *out, const char *s)\n{\n"
        "    if (!s) {\n        fputs(\"NULL\", out);\n        return;\n    }\n"
        "    fputc('\"', out);\n"
        "    for (int i = 0; s[i] && i < 80; i++) {\n"
        "        unsigned char c = (unsigned char)s[i];\n"
        "        if (c == '\"' || c == '\\\\')\n            fprintf(out, \"\\\\%%c\", c);\n"
        "        else if (c < 32 || c > 126)\n            fprintf(out, \"\\\\x%%02x\", c);\n"
        "        else\n            fputc(c, out);\n    }\n"
        "    fputc('\"', out);\n}\n\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const spec_command *c = g->cmds[i].sc;
        fprintf(f, "static %s tr_%s(", c->ret, c->name);
        gen_print_params(f, c, 1, 0);
        fprintf(f, ")\n{\n    const tsr_tracer *tsr_t = self;\n    fputs(\"gl%s(\", tsr_t->out);\n", c->name);
        for (size_t k = 0; k < c->nparams; k++) {
            if (k)
                fprintf(f, "    fputs(\", \", tsr_t->out);\n");
            emit_param_print(f, &c->params[k]);
        }
        if (gen_is_void(c->ret)) {
            fprintf(f, "    fputs(\")\\n\", tsr_t->out);\n    tsr_call_%s(tsr_t->child", c->name);
            gen_print_args(f, c, 1);
            fprintf(f, ");\n}\n");
        } else {
            fprintf(f, "    fputs(\") = \", tsr_t->out);\n    %s r = tsr_call_%s(tsr_t->child", c->ret, c->name);
            gen_print_args(f, c, 1);
            fprintf(f, ");\n");
            spec_param rp = {.name = "r", .type = c->ret, .base_type = c->ret};
            if (strchr(c->ret, '*'))
                fprintf(f, "    tsr_trace_print_string(tsr_t->out, (const char *)r);\n");
            else
                emit_scalar_print(f, &rp, gen_type_find(c->ret), "r");
            fprintf(f, "    fputc('\\n', tsr_t->out);\n    return r;\n}\n");
        }
    }
    fprintf(f, "\nvoid tsr_trace_fill(tsr_dispatch *table, tsr_tracer *t)\n{\n");
    for (size_t i = 0; i < g->ncmds; i++)
        fprintf(f, "    tsr_set_%s(table, tr_%s, t);\n", g->cmds[i].sc->name, g->cmds[i].sc->name);
    fprintf(f, "}\n");
    gen_close(f);
}
