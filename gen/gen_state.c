/* gen/gen_state.c — emits src/state_gen.c for the state tracker
 * (core/state/):
 *   - one tracker function per current-attribute command of the spec
 *     (Color*, Normal*, TexCoord*, MultiTexCoord*, EdgeFlag*, VertexAttrib*
 *     in every type and vector form), each converting its arguments the
 *     way GL does (signed/unsigned normalisation for colors and normals,
 *     with Mesa's float arithmetic so gets agree bit for bit) and calling
 *     the tracker's one float entry point; st_gen_fill_current() sets them
 *     all in a dispatch table. Writing ~110 of these by hand would be the
 *     kind of repetition the spec exists to remove.
 *   - the list of commands the tracker must cover (categories state,
 *     object, client, plus those current-attribute commands), for the
 *     coverage test: each is implemented or listed in tsr_state_untracked
 *     with a reason (tsr_state_spec_command()).
 * Which commands are current-attribute commands is decided from the name
 * and parameter shapes; a name that looks like one but does not fit the
 * shape stops the generator (the spec changed in a way this must learn). */
#include "gen.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

typedef struct attr_cmd {
    const char *kind;   /* "color", "normal", "texcoord", "multitexcoord", "edgeflag", "attrib" */
    int n;              /* components given */
    const char *suffix; /* "b", "ub", "f", ... */
    int vector;         /* the v form */
    int normalized;     /* VertexAttrib4N*: integers mapped to [-1, 1] / [0, 1] */
} attr_cmd;

/* Parses NAME = PREFIX N? SUFFIX v? for the attribute prefixes. */
static int parse_attr(const char *name, attr_cmd *a)
{
    static const struct {
        const char *prefix, *kind;
    } prefixes[] = {
        {"MultiTexCoord", "multitexcoord"}, {"TexCoord", "texcoord"}, {"Color", "color"}, {"Normal", "normal"},
        {"VertexAttrib", "attrib"},
    };
    static const char *const suffixes[] = {"ub", "us", "ui", "b", "s", "i", "f", "d"};
    if (!strcmp(name, "EdgeFlag") || !strcmp(name, "EdgeFlagv")) {
        *a = (attr_cmd){"edgeflag", 1, "", name[8] == 'v', 0};
        return 1;
    }
    for (size_t i = 0; i < sizeof prefixes / sizeof prefixes[0]; i++) {
        size_t pl = strlen(prefixes[i].prefix);
        if (strncmp(name, prefixes[i].prefix, pl) != 0)
            continue;
        const char *p = name + pl;
        if (!isdigit((unsigned char)*p))
            return 0;
        a->kind = prefixes[i].kind;
        a->n = *p++ - '0';
        a->normalized = !strcmp(a->kind, "attrib") && *p == 'N';
        if (a->normalized)
            p++;
        for (size_t s = 0; s < sizeof suffixes / sizeof suffixes[0]; s++) {
            size_t sl = strlen(suffixes[s]);
            if (!strncmp(p, suffixes[s], sl) && (!p[sl] || !strcmp(p + sl, "v"))) {
                a->suffix = suffixes[s];
                a->vector = p[sl] == 'v';
                return 1;
            }
        }
        return 0;
    }
    return 0;
}

/* Writes into buf the C expression converting component `e` of the
 * command's type to GLfloat. */
static void conv(char *buf, size_t size, const attr_cmd *a, const char *e)
{
    int norm = !strcmp(a->kind, "color") || !strcmp(a->kind, "normal") || a->normalized;
    const char *s = a->suffix;
    if (!norm || !strcmp(s, "f") || !strcmp(s, "d"))
        snprintf(buf, size, "(GLfloat)(%s)", e);
    else if (!strcmp(s, "b"))
        snprintf(buf, size, "((2.0F * (GLfloat)(%s) + 1.0F) * (1.0F / 255.0F))", e);
    else if (!strcmp(s, "s"))
        snprintf(buf, size, "((2.0F * (GLfloat)(%s) + 1.0F) * (1.0F / 65535.0F))", e);
    else if (!strcmp(s, "i"))
        snprintf(buf, size, "((GLfloat)((2.0F * (GLfloat)(%s) + 1.0F) * (1.0F / 4294967294.0)))", e);
    else if (!strcmp(s, "ub"))
        snprintf(buf, size, "((GLfloat)(%s) / 255.0F)", e);
    else if (!strcmp(s, "us"))
        snprintf(buf, size, "((GLfloat)(%s) * (1.0F / 65535.0F))", e);
    else /* ui */
        snprintf(buf, size, "((GLfloat)((%s) * (1.0F / 4294967295.0)))", e);
}

static void die_shape(const spec_command *c)
{
    fprintf(stderr,
            "tsr-gen: spec/gl.yaml:%d: %s looks like a current-attribute command but its "
            "parameters do not fit gen/gen_state.c\n",
            c->line, c->name);
    exit(1);
}

/* Emits the tracker function for one attribute command. */
static void emit_attr(FILE *f, const spec_command *c, const attr_cmd *a)
{
    size_t lead = (!strcmp(a->kind, "multitexcoord") || !strcmp(a->kind, "attrib")) ? 1 : 0;
    size_t want = lead + (a->vector ? 1 : (size_t)a->n);
    if (c->nparams != want || (a->vector && c->params[lead].pointer_depth != 1))
        die_shape(c);
    fprintf(f, "static void sg_%s(", c->name);
    gen_print_params(f, c, 1, 0);
    fprintf(f, ")\n{\n");
    char comp[4][128];
    const char *defaults[4] = {"0.0F", "0.0F", "0.0F", "1.0F"};
    for (int i = 0; i < 4; i++) {
        char e[64];
        if (i < a->n) {
            if (a->vector)
                snprintf(e, sizeof e, "%s[%d]", c->params[lead].name, i);
            else
                snprintf(e, sizeof e, "%s", c->params[lead + (size_t)i].name);
            conv(comp[i], sizeof comp[i], a, e);
        } else {
            snprintf(comp[i], sizeof comp[i], "%s", defaults[i]);
        }
    }
    if (!strcmp(a->kind, "color")) {
        if (a->n < 3)
            die_shape(c);
        fprintf(f, "    st_cur_color(self, %s, %s, %s, %s);\n", comp[0], comp[1], comp[2], comp[3]);
    } else if (!strcmp(a->kind, "normal")) {
        if (a->n != 3)
            die_shape(c);
        fprintf(f, "    st_cur_normal(self, %s, %s, %s);\n", comp[0], comp[1], comp[2]);
    } else if (!strcmp(a->kind, "texcoord")) {
        fprintf(f, "    st_cur_texcoord(self, GL_TEXTURE0, %s, %s, %s, %s);\n", comp[0], comp[1], comp[2], comp[3]);
    } else if (!strcmp(a->kind, "multitexcoord")) {
        fprintf(f, "    st_cur_texcoord(self, %s, %s, %s, %s, %s);\n", c->params[0].name, comp[0], comp[1], comp[2],
                comp[3]);
    } else if (!strcmp(a->kind, "attrib")) {
        fprintf(f, "    st_cur_attrib(self, %s, %s, %s, %s, %s);\n", c->params[0].name, comp[0], comp[1], comp[2],
                comp[3]);
    } else {
        fprintf(f, "    st_cur_edgeflag(self, %s%s);\n", c->params[0].name, a->vector ? "[0]" : "");
    }
    fprintf(f, "}\n\n");
}

static int tracked_category(const char *cat)
{
    return !strcmp(cat, "state") || !strcmp(cat, "object") || !strcmp(cat, "client");
}

void gen_emit_state(const gen *g)
{
    FILE *f = gen_open(g, "src/state_gen.c");
    fprintf(f, "/* The state tracker's current-attribute entry points and the list of\n"
               " * commands it covers (gen/gen_state.c). */\n"
               "#include \"state/state_internal.h\"\n\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const spec_command *c = g->cmds[i].sc;
        attr_cmd a;
        if (!strcmp(c->category, "geometry") && parse_attr(c->name, &a))
            emit_attr(f, c, &a);
    }
    fprintf(f, "void st_gen_fill_current(tsr_state_ctx *c, tsr_dispatch *d);\n"
               "void st_gen_fill_current(tsr_state_ctx *c, tsr_dispatch *d)\n{\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const spec_command *c = g->cmds[i].sc;
        attr_cmd a;
        if (!strcmp(c->category, "geometry") && parse_attr(c->name, &a))
            fprintf(f, "    tsr_set_%s(d, sg_%s, c);\n", c->name, c->name);
    }
    fprintf(f, "}\n\n");
    fprintf(f, "static const struct { const char *name, *category; } spec_cmds[] = {\n");
    for (size_t i = 0; i < g->ncmds; i++) {
        const spec_command *c = g->cmds[i].sc;
        attr_cmd a;
        if (tracked_category(c->category))
            fprintf(f, "    {\"%s\", \"%s\"},\n", c->name, c->category);
        else if (!strcmp(c->category, "geometry") && parse_attr(c->name, &a))
            fprintf(f, "    {\"%s\", \"current\"},\n", c->name);
    }
    fprintf(f, "};\n\n"
               "int tsr_state_spec_command(size_t i, const char **name, const char **category)\n{\n"
               "    if (i >= sizeof spec_cmds / sizeof spec_cmds[0])\n"
               "        return 0;\n"
               "    *name = spec_cmds[i].name;\n"
               "    *category = spec_cmds[i].category;\n"
               "    return 1;\n}\n");
    gen_close(f);
}
