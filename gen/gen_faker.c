/* gen/gen_faker.c — tsr-gen-faker: the faker's gl* names beyond the spec,
 * generated from the Khronos registry (gl.xml) and spec/gl.yaml. Host tool
 * only. Usage:
 *   tsr-gen-faker SPEC.yaml GL_XML OUTDIR
 * Writes into OUTDIR:
 *   faker_alias_gen.c  one exported entry per registry command that gl.xml
 *                      declares an alias of a spec command (glActiveTextureARB
 *                      -> ActiveTexture): it jumps through the same slot as
 *                      the spec's own entry (gl_entry_gen.c), same code shape;
 *   faker_stubs_gen.c  one exported entry per other command of GL 1.0-2.1
 *                      and of every ARB/EXT/KHR extension the registry marks
 *                      for "gl": it logs one warning naming the function the
 *                      first time and otherwise does nothing (returns 0); the
 *                      sorted name -> entry table of every gl* the faker
 *                      exports (spec, aliases, stubs: GetProcAddress) and the
 *                      GL_EXTENSIONS string: the registry's extensions whose
 *                      every command is a spec command or an alias of one,
 *                      and those without commands that EXTENSIONS.txt
 *                      (spec/gl_extensions.txt) lists, each with the reason
 *                      it works end to end.
 * The registry is scanned as text (its layout is regular; no XML library on
 * the build machine is assumed). */
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "spec.h"

static void die(const char *msg, const char *detail)
{
    fprintf(stderr, "tsr-gen-faker: %s%s%s\n", msg, detail ? ": " : "", detail ? detail : "");
    exit(1);
}

static void *xrealloc(void *p, size_t n)
{
    p = realloc(p, n ? n : 1);
    if (!p)
        die("out of memory", NULL);
    return p;
}

static char *xstrndup(const char *s, size_t n)
{
    char *r = xrealloc(NULL, n + 1);
    memcpy(r, s, n);
    r[n] = '\0';
    return r;
}

typedef enum ret_kind { RET_VOID, RET_INT, RET_FLOAT, RET_DOUBLE } ret_kind;

typedef struct xcmd {
    char *name;  /* "glActiveTextureARB" */
    char *alias; /* "glActiveTexture" or NULL */
    ret_kind ret;
    int nparams;
    int wanted;                  /* required by GL 1.0-2.1 or an ARB/EXT/KHR extension */
    const spec_command *spec;    /* the spec command it is, or NULL */
    const spec_command *aliased; /* the spec command it aliases, or NULL */
} xcmd;

static xcmd *cmds;
static size_t ncmds;

static int xcmd_cmp(const void *a, const void *b) { return strcmp(((const xcmd *)a)->name, ((const xcmd *)b)->name); }

static xcmd *find_cmd(const char *name)
{
    xcmd key = {.name = (char *)name};
    return bsearch(&key, cmds, ncmds, sizeof *cmds, xcmd_cmp);
}

static char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        die(strerror(errno), path);
    size_t cap = 1 << 20, n = 0;
    char *buf = xrealloc(NULL, cap);
    size_t got;
    while ((got = fread(buf + n, 1, cap - n - 1, f)) > 0) {
        n += got;
        if (cap - n < 2)
            buf = xrealloc(buf, cap *= 2);
    }
    fclose(f);
    buf[n] = '\0';
    return buf;
}

/* The value of attribute `attr` inside the tag starting at `tag`
 * (up to its '>'), or NULL. */
static char *tag_attr(const char *tag, const char *attr)
{
    const char *end = strchr(tag, '>');
    char pat[64];
    snprintf(pat, sizeof pat, " %s=\"", attr);
    const char *p = strstr(tag, pat);
    if (!p || (end && p > end))
        return NULL;
    p += strlen(pat);
    const char *q = strchr(p, '"');
    return q ? xstrndup(p, (size_t)(q - p)) : NULL;
}

/* Return type text of a <proto> (tags removed, trimmed) -> kind. */
static ret_kind proto_kind(const char *proto, const char *name_tag)
{
    char text[256];
    size_t n = 0;
    int in_tag = 0;
    for (const char *p = proto; p < name_tag && n + 1 < sizeof text; p++) {
        if (*p == '<')
            in_tag = 1;
        else if (*p == '>')
            in_tag = 0;
        else if (!in_tag)
            text[n++] = *p;
    }
    text[n] = '\0';
    if (strchr(text, '*'))
        return RET_INT; /* pointers come back in the same register */
    char word[64];
    if (sscanf(text, " const %63s", word) != 1 && sscanf(text, " %63s", word) != 1)
        die("cannot read a return type", proto);
    if (!strcmp(word, "void"))
        return RET_VOID;
    if (!strcmp(word, "GLfloat") || !strcmp(word, "GLclampf"))
        return RET_FLOAT;
    if (!strcmp(word, "GLdouble") || !strcmp(word, "GLclampd"))
        return RET_DOUBLE;
    return RET_INT;
}

/* <command> or <command attr=...> (not <commands>, not <command .../>). */
static const char *next_command(const char *p, const char *limit)
{
    while ((p = strstr(p, "<command")) && p < limit) {
        if (p[8] == '>' || p[8] == ' ')
            return p;
        p++;
    }
    return NULL;
}

static void parse_commands(const char *xml)
{
    size_t cap = 0;
    const char *limit = strstr(xml, "</commands>");
    if (!limit)
        die("no </commands>", NULL);
    for (const char *p = next_command(xml, limit); p; p = next_command(p + 1, limit)) {
        const char *end = strstr(p, "</command>");
        if (!end)
            die("unterminated <command>", NULL);
        const char *proto = strstr(p, "<proto");
        const char *name = proto ? strstr(proto, "<name>") : NULL;
        if (!name || name > end)
            die("a <command> without <proto><name>", NULL);
        const char *name_end = strstr(name, "</name>");
        if (ncmds == cap)
            cmds = xrealloc(cmds, (cap = cap ? cap * 2 : 4096) * sizeof *cmds);
        xcmd *c = &cmds[ncmds++];
        memset(c, 0, sizeof *c);
        c->name = xstrndup(name + 6, (size_t)(name_end - name - 6));
        c->ret = proto_kind(strchr(proto, '>') + 1, name);
        for (const char *q = strstr(p, "<param"); q && q < end; q = strstr(q + 1, "<param"))
            c->nparams++;
        const char *alias = strstr(p, "<alias ");
        if (alias && alias < end)
            c->alias = tag_attr(alias, "name");
        p = end;
    }
    qsort(cmds, ncmds, sizeof *cmds, xcmd_cmp);
}

/* Marks the <command name=.../> of every <require> in [p, end) whose api
 * is absent or "gl" (calls mark(name, ctx)). */
static void each_required(const char *p, const char *end, void (*mark)(xcmd *, void *), void *ctx)
{
    for (const char *r = strstr(p, "<require"); r && r < end; r = strstr(r + 1, "<require")) {
        const char *rend = strstr(r, "</require>");
        const char *selfclose = strstr(r, "/>");
        const char *gt = strchr(r, '>');
        if (selfclose && gt && selfclose + 1 == gt)
            continue; /* <require/> */
        if (!rend || rend > end)
            break;
        char *api = tag_attr(r, "api");
        int ok = !api || !strcmp(api, "gl");
        free(api);
        if (!ok)
            continue;
        for (const char *c = strstr(r, "<command "); c && c < rend; c = strstr(c + 1, "<command ")) {
            char *name = tag_attr(c, "name");
            xcmd *x = name ? find_cmd(name) : NULL;
            if (!x)
                die("a required command the registry does not define", name);
            mark(x, ctx);
            free(name);
        }
    }
}

static void mark_wanted(xcmd *x, void *ctx)
{
    (void)ctx;
    x->wanted = 1;
}

static void parse_features(const char *xml)
{
    for (const char *p = strstr(xml, "<feature "); p; p = strstr(p + 1, "<feature ")) {
        const char *end = strstr(p, "</feature>");
        char *api = tag_attr(p, "api"), *number = tag_attr(p, "number");
        if (!end || !api || !number)
            die("a <feature> without api/number or end", NULL);
        if (!strcmp(api, "gl") && strtod(number, NULL) <= 2.1 + 1e-9)
            each_required(p, end, mark_wanted, NULL);
        free(api);
        free(number);
    }
}

static int supports_gl(const char *supported)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s", supported);
    for (char *tok = strtok(buf, "|"); tok; tok = strtok(NULL, "|"))
        if (!strcmp(tok, "gl"))
            return 1;
    return 0;
}

typedef struct ext_state {
    int commands;
    int covered;
} ext_state;

static void count_covered(xcmd *x, void *ctx)
{
    ext_state *st = ctx;
    st->commands++;
    if (x->spec || x->aliased)
        st->covered++;
}

/* spec/gl_extensions.txt: the extensions without commands of their own
 * that are offered, and ("-NAME") those withheld although the spec has
 * their commands; each is found in the registry once (found). */
typedef struct listed_ext {
    char **names;
    int *found;
    int *withheld;
    size_t count;
} listed_ext;

static void read_listed(const char *path, listed_ext *l)
{
    char *text = read_file(path);
    for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
        if (line[0] == '#' || line[0] == '\0')
            continue;
        size_t n = strcspn(line, "\t");
        if (line[n] != '\t' || line[n + 1] == '\0')
            die("a listed extension without its reason (NAME<TAB>why)", line);
        int withheld = line[0] == '-';
        l->names = xrealloc(l->names, (l->count + 1) * sizeof *l->names);
        l->found = xrealloc(l->found, (l->count + 1) * sizeof *l->found);
        l->withheld = xrealloc(l->withheld, (l->count + 1) * sizeof *l->withheld);
        l->names[l->count] = xstrndup(line + withheld, n - (size_t)withheld);
        l->withheld[l->count] = withheld;
        l->found[l->count++] = 0;
    }
    free(text);
}

static void append_name(char **ext, size_t *ext_len, const char *name)
{
    size_t n = strlen(name);
    *ext = xrealloc(*ext, *ext_len + n + 2);
    memcpy(*ext + *ext_len, name, n);
    (*ext)[*ext_len + n] = ' ';
    (*ext)[*ext_len + n + 1] = '\0';
    *ext_len += n + 1;
}

/* Marks extension commands wanted; appends offered extension names to ext:
 * those whose every command the spec has, and the listed ones (which must
 * have no command the spec lacks). */
static void parse_extensions(const char *xml, listed_ext *listed, char **ext, size_t *ext_len)
{
    const char *start = strstr(xml, "<extensions>");
    if (!start)
        die("no <extensions>", NULL);
    for (const char *p = strstr(start, "<extension "); p; p = strstr(p + 1, "<extension ")) {
        char *name = tag_attr(p, "name"), *supported = tag_attr(p, "supported");
        const char *gt = strchr(p, '>');
        const char *end = gt && gt[-1] == '/' ? gt : strstr(p, "</extension>");
        if (!name || !supported || !end)
            die("an <extension> without name/supported or end", name);
        int is_listed = 0, is_withheld = 0;
        for (size_t i = 0; i < listed->count; i++)
            if (!strcmp(listed->names[i], name)) {
                listed->found[i] = 1;
                if (listed->withheld[i])
                    is_withheld = 1;
                else
                    is_listed = 1;
            }
        if (is_listed && !supports_gl(supported))
            die("a listed extension the registry does not support for gl", name);
        if (supports_gl(supported)) {
            ext_state st = {0, 0};
            if (gt[-1] != '/') {
                if (!strncmp(name, "GL_ARB_", 7) || !strncmp(name, "GL_EXT_", 7) || !strncmp(name, "GL_KHR_", 7))
                    each_required(p, end, mark_wanted, NULL);
                each_required(p, end, count_covered, &st);
            }
            if (is_listed && st.covered != st.commands)
                die("a listed extension has commands the spec does not have", name);
            if (is_withheld && !(st.commands > 0 && st.covered == st.commands))
                die("a withheld extension the rule would not offer anyway", name);
            if (((st.commands > 0 && st.covered == st.commands) || is_listed) && !is_withheld)
                append_name(ext, ext_len, name);
        }
        free(name);
        free(supported);
    }
    for (size_t i = 0; i < listed->count; i++)
        if (!listed->found[i])
            die("a listed extension the registry does not have", listed->names[i]);
}

static FILE *open_out(const char *dir, const char *name)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (!f)
        die(strerror(errno), path);
    fprintf(f, "/* Generated by tsr-gen-faker from spec/gl.yaml and gl.xml: do not edit. */\n");
    return f;
}

static void close_out(FILE *f)
{
    if (ferror(f) || fclose(f) != 0)
        die("write error", NULL);
}

static void print_params(FILE *f, const spec_command *c)
{
    for (size_t i = 0; i < c->nparams; i++) {
        const char *t = c->params[i].type;
        size_t n = strlen(t);
        fprintf(f, "%s%s%s%s", i ? ", " : "", t, n && t[n - 1] == '*' ? "" : " ", c->params[i].name);
    }
    if (!c->nparams)
        fprintf(f, "void");
}

static void emit_alias(const char *dir)
{
    FILE *f = open_out(dir, "faker_alias_gen.c");
    fprintf(f, "/* Registry aliases of spec commands: each jumps through the spec command's\n"
               " * slot of the calling thread's current table, like gl_entry_gen.c. */\n"
               "#include \"tessera/dispatch.h\"\n#include \"spu/glapi_internal.h\"\n\n"
               "#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 11\n"
               "#pragma GCC diagnostic ignored \"-Warray-parameter\"\n#endif\n\n");
    for (size_t i = 0; i < ncmds; i++) {
        const xcmd *x = &cmds[i];
        if (!x->aliased)
            continue;
        const spec_command *c = x->aliased;
        int value = strcmp(c->ret, "void") != 0;
        fprintf(f, "__attribute__((visibility(\"default\"))) %s GLAPIENTRY %s(", c->ret, x->name);
        print_params(f, c);
        fprintf(f, ");\n%s GLAPIENTRY %s(", c->ret, x->name);
        print_params(f, c);
        fprintf(f,
                ")\n{\n    const tsr_dispatch *d = tsr_gl_current_table;\n"
                "    if (__builtin_expect(d == NULL, 0))\n        return%s;\n"
                "    %s((tsr_fn_%s)d->%s.fn)(d->%s.self",
                value ? " 0" : "", value ? "return " : "", c->name, c->name, c->name);
        for (size_t k = 0; k < c->nparams; k++)
            fprintf(f, ", %s", c->params[k].name);
        fprintf(f, ");\n}\n");
    }
    close_out(f);
}

static void emit_stubs(const char *dir, const char *extensions)
{
    FILE *f = open_out(dir, "faker_stubs_gen.c");
    fprintf(f, "/* Unsupported GL commands (one warning each, then nothing), the table of\n"
               " * every exported gl* name and the GL_EXTENSIONS string. No GL header is\n"
               " * included: the stubs ignore their arguments (the caller owns them in the\n"
               " * x86-64/aarch64 C ABI) and return zero of the return register's kind. */\n"
               "#include <stdatomic.h>\n#include <stddef.h>\n#include \"faker_gl.h\"\n\n");
    size_t nstubs = 0, nnames = 0;
    for (size_t i = 0; i < ncmds; i++) {
        if (cmds[i].spec || cmds[i].aliased)
            fprintf(f, "extern void %s(void);\n", cmds[i].name);
        if (cmds[i].wanted && !cmds[i].spec && !cmds[i].aliased)
            nstubs++;
    }
    fprintf(f, "\nstatic atomic_flag warned[%zu];\n\n", nstubs ? nstubs : 1);
    static const char *const rtype[] = {"void", "unsigned long", "float", "double"};
    size_t k = 0;
    for (size_t i = 0; i < ncmds; i++) {
        const xcmd *x = &cmds[i];
        if (!x->wanted || x->spec || x->aliased)
            continue;
        fprintf(f,
                "TSR_FAKER_API %s %s(void);\n%s %s(void)\n{\n"
                "    if (!atomic_flag_test_and_set(&warned[%zu]))\n"
                "        tsr_faker_unsupported(\"%s\");\n",
                rtype[x->ret], x->name, rtype[x->ret], x->name, k++, x->name);
        if (x->ret != RET_VOID)
            fprintf(f, "    return 0;\n");
        fprintf(f, "}\n");
    }
    fprintf(f, "\n/* Every exported gl* name, sorted (strcmp). */\nconst tsr_faker_proc tsr_faker_gl_procs[] = {\n");
    for (size_t i = 0; i < ncmds; i++) {
        const xcmd *x = &cmds[i];
        if (x->spec || x->aliased || x->wanted) {
            fprintf(f, "    {\"%s\", (void (*)(void))%s},\n", x->name, x->name);
            nnames++;
        }
    }
    fprintf(f, "};\nconst size_t tsr_faker_gl_proc_count = %zu;\n", nnames);
    fprintf(f, "const size_t tsr_faker_gl_stub_count = %zu;\n", nstubs);
    fprintf(f,
            "\n/* Registry extensions whose every command the spec has, and those\n"
            " * without commands that spec/gl_extensions.txt lists. */\n"
            "const char tsr_faker_gl_extensions[] = \"%s\";\n",
            extensions);
    close_out(f);
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: tsr-gen-faker SPEC.yaml GL_XML EXTENSIONS.txt OUTDIR\n");
        return 2;
    }
    static spec s;
    char err[1024];
    if (spec_load(argv[1], &s, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return 1;
    }
    char *xml = read_file(argv[2]);
    const char *commands = strstr(xml, "<commands namespace=\"GL\">");
    if (!commands)
        die("no <commands namespace=\"GL\"> in", argv[2]);
    parse_commands(commands);
    /* Spec commands that the registry lacks (tessera's own: khronos false)
     * are exported by gl_entry_gen.c and belong in the name table too. */
    for (size_t i = 0; i < s.ncmds; i++) {
        char name[256];
        snprintf(name, sizeof name, "gl%s", s.cmds[i].name);
        xcmd *x = find_cmd(name);
        if (!x) {
            if (s.cmds[i].khronos)
                die("a spec command the registry does not have", name);
            cmds = xrealloc(cmds, (ncmds + 1) * sizeof *cmds);
            memset(&cmds[ncmds], 0, sizeof *cmds);
            cmds[ncmds].name = xstrndup(name, strlen(name));
            ncmds++;
            qsort(cmds, ncmds, sizeof *cmds, xcmd_cmp);
            x = find_cmd(name);
        }
        x->spec = &s.cmds[i];
    }
    for (size_t i = 0; i < ncmds; i++) {
        xcmd *x = &cmds[i];
        if (x->spec || !x->alias)
            continue;
        xcmd *target = find_cmd(x->alias);
        /* Same parameter count, or it is no drop-in alias: then a stub. */
        if (target && target->spec && (size_t)x->nparams == target->spec->nparams)
            x->aliased = target->spec;
    }
    parse_features(xml);
    char *extensions = xrealloc(NULL, 1);
    size_t ext_len = 0;
    extensions[0] = '\0';
    listed_ext listed = {NULL, NULL, NULL, 0};
    read_listed(argv[3], &listed);
    parse_extensions(xml, &listed, &extensions, &ext_len);
    for (size_t i = 0; i < listed.count; i++)
        free(listed.names[i]);
    free(listed.names);
    free(listed.found);
    /* Each name ends with a space, the last one too, as in Mesa's string:
     * programs print the list with its spaces turned into line ends
     * (piglit's glinfo), and what they print next must start a line. */
    mkdir(argv[4], 0777);
    emit_alias(argv[4]);
    emit_stubs(argv[4], extensions);
    free(extensions);
    free(xml);
    spec_free(&s);
    return 0;
}
