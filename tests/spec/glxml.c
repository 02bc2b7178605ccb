/* tests/spec/glxml.c — reads the Khronos gl.xml registry (commands and
 * enums) with a small, strict XML scanner: tags, attributes, text,
 * comments, processing instructions and the five predefined entities.
 * Owns the parsed tables. Never reads past the buffer; bad XML is an error. */
#include "glxml.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_DEPTH = 64, MAX_NAME = 64, MAX_ATTRS = 16 };

typedef struct strbuf {
    char *p;
    size_t len, cap;
} strbuf;

static int sb_append(strbuf *b, const char *s, size_t n)
{
    if (b->len + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 64;
        while (cap < b->len + n + 1)
            cap *= 2;
        char *p = realloc(b->p, cap);
        if (!p)
            return -1;
        b->p = p;
        b->cap = cap;
    }
    memcpy(b->p + b->len, s, n);
    b->len += n;
    b->p[b->len] = 0;
    return 0;
}

static void sb_clear(strbuf *b)
{
    b->len = 0;
    if (b->p)
        b->p[0] = 0;
}

/* Copy of `s` without leading/trailing white space. */
static char *dup_trimmed(const char *s)
{
    if (!s)
        s = "";
    while (isspace((unsigned char)*s))
        s++;
    size_t n = strlen(s);
    while (n && isspace((unsigned char)s[n - 1]))
        n--;
    char *d = malloc(n + 1);
    if (d) {
        memcpy(d, s, n);
        d[n] = 0;
    }
    return d;
}

typedef struct attr {
    char name[MAX_NAME];
    strbuf value;
} attr;

typedef struct scanner {
    const char *path;
    const char *buf;
    size_t len, pos;
    int line;
    char *err;
    size_t errsz;

    char stack[MAX_DEPTH][MAX_NAME];
    int depth;
    attr attrs[MAX_ATTRS];
    int nattrs;

    /* what we are collecting */
    int in_command, in_proto, in_param, in_name;
    char *param_group; /* group attribute of the open <param> */
    strbuf type, name;
    glxml_command cur;
    size_t cur_cap;
    glxml *out;
    size_t cmd_cap, enum_cap;

    /* <feature api="gl" number="2.1"><require><enum name=.../> */
    int feature_version; /* 0 outside a GL feature */
    struct required {
        char *name;
        int version;
        int is_command; /* <command> (else <enum>) */
    } * required;
    size_t nrequired, required_cap;
} scanner;

static int fail(scanner *s, const char *fmt, ...)
{
    int n = snprintf(s->err, s->errsz, "%s:%d: ", s->path, s->line);
    if (n >= 0 && (size_t)n < s->errsz) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(s->err + n, s->errsz - (size_t)n, fmt, ap);
        va_end(ap);
    }
    return -1;
}

static void advance(scanner *s, size_t n)
{
    for (size_t i = 0; i < n && s->pos < s->len; i++, s->pos++)
        if (s->buf[s->pos] == '\n')
            s->line++;
}

static int starts_with(const scanner *s, const char *lit)
{
    size_t n = strlen(lit);
    return s->len - s->pos >= n && memcmp(s->buf + s->pos, lit, n) == 0;
}

/* Skips to just past `end`; error if the file ends first. */
static int skip_past(scanner *s, const char *end, const char *what)
{
    size_t n = strlen(end);
    while (s->pos < s->len) {
        if (starts_with(s, end)) {
            advance(s, n);
            return 0;
        }
        advance(s, 1);
    }
    return fail(s, "unterminated %s", what);
}

/* Appends text [from, to) to `out` with entities decoded. */
static int decode_text(scanner *s, size_t from, size_t to, strbuf *out)
{
    static const struct {
        const char *ent;
        char ch;
    } ents[] = {{"&lt;", '<'}, {"&gt;", '>'}, {"&amp;", '&'}, {"&quot;", '"'}, {"&apos;", '\''}};
    for (size_t i = from; i < to;) {
        if (s->buf[i] != '&') {
            size_t j = i;
            while (j < to && s->buf[j] != '&')
                j++;
            if (sb_append(out, s->buf + i, j - i))
                return fail(s, "out of memory");
            i = j;
            continue;
        }
        int done = 0;
        for (size_t e = 0; e < sizeof ents / sizeof ents[0] && !done; e++) {
            size_t n = strlen(ents[e].ent);
            if (to - i >= n && memcmp(s->buf + i, ents[e].ent, n) == 0) {
                if (sb_append(out, &ents[e].ch, 1))
                    return fail(s, "out of memory");
                i += n;
                done = 1;
            }
        }
        if (!done && to - i >= 4 && s->buf[i + 1] == '#') {
            char *end;
            int hex = s->buf[i + 2] == 'x';
            unsigned long v = strtoul(s->buf + i + (hex ? 3 : 2), &end, hex ? 16 : 10);
            if (end < s->buf + to && *end == ';' && v > 0 && v < 128) {
                char c = (char)v;
                if (sb_append(out, &c, 1))
                    return fail(s, "out of memory");
                i = (size_t)(end - s->buf) + 1;
                done = 1;
            }
        }
        if (!done)
            return fail(s, "unknown entity");
    }
    return 0;
}

static int read_name(scanner *s, char *dst)
{
    size_t n = 0;
    while (s->pos < s->len) {
        char c = s->buf[s->pos];
        if (!(isalnum((unsigned char)c) || c == '_' || c == '-' || c == ':' || c == '.'))
            break;
        if (n + 1 >= MAX_NAME)
            return fail(s, "name too long");
        dst[n++] = c;
        advance(s, 1);
    }
    dst[n] = 0;
    return n ? 0 : fail(s, "expected a name");
}

static void skip_space(scanner *s)
{
    while (s->pos < s->len && isspace((unsigned char)s->buf[s->pos]))
        advance(s, 1);
}

static const char *attr_value(const scanner *s, const char *name)
{
    for (int i = 0; i < s->nattrs; i++)
        if (!strcmp(s->attrs[i].name, name))
            return s->attrs[i].value.p ? s->attrs[i].value.p : "";
    return NULL;
}

/* ---- building the tables ---------------------------------------------- */

static int compare_enum_names(const void *a, const void *b)
{
    return strcmp(((const glxml_enum *)a)->name, ((const glxml_enum *)b)->name);
}

static int push_enum(scanner *s)
{
    const char *name = attr_value(s, "name"), *value = attr_value(s, "value"), *api = attr_value(s, "api");
    if (!name || !value || (api && strcmp(api, "gl") != 0))
        return 0;
    glxml *x = s->out;
    if (x->nenums == s->enum_cap) {
        size_t cap = s->enum_cap ? s->enum_cap * 2 : 1024;
        glxml_enum *e = realloc(x->enums, cap * sizeof *e);
        if (!e)
            return fail(s, "out of memory");
        x->enums = e;
        s->enum_cap = cap;
    }
    char *end;
    errno = 0;
    unsigned long long v = value[0] == '-' ? (unsigned long long)strtoll(value, &end, 0) : strtoull(value, &end, 0);
    if (errno || *end)
        return fail(s, "enum %s has bad value '%s'", name, value);
    glxml_enum *e = &x->enums[x->nenums];
    memset(e, 0, sizeof *e);
    const char *groups = attr_value(s, "group");
    if (!(e->name = dup_trimmed(name)) || (groups && !(e->groups = dup_trimmed(groups)))) {
        free(e->name);
        return fail(s, "out of memory");
    }
    e->value = v;
    x->nenums++;
    return 0;
}

static int push_required(scanner *s, int is_command)
{
    const char *name = attr_value(s, "name");
    if (!name)
        return 0;
    if (s->nrequired == s->required_cap) {
        size_t cap = s->required_cap ? s->required_cap * 2 : 1024;
        struct required *r = realloc(s->required, cap * sizeof *r);
        if (!r)
            return fail(s, "out of memory");
        s->required = r;
        s->required_cap = cap;
    }
    if (!(s->required[s->nrequired].name = dup_trimmed(name)))
        return fail(s, "out of memory");
    s->required[s->nrequired].is_command = is_command;
    s->required[s->nrequired++].version = s->feature_version;
    return 0;
}

/* "2.1" -> 21; 0 when malformed. */
static int parse_version(const char *v)
{
    int major = 0, minor = 0;
    if (!v || sscanf(v, "%d.%d", &major, &minor) != 2 || major < 1 || minor < 0 || minor > 9)
        return 0;
    return major * 10 + minor;
}

static int push_param(scanner *s)
{
    glxml_command *c = &s->cur;
    if (c->nparams == s->cur_cap) {
        size_t cap = s->cur_cap ? s->cur_cap * 2 : 8;
        glxml_param *p = realloc(c->params, cap * sizeof *p);
        if (!p)
            return fail(s, "out of memory");
        c->params = p;
        s->cur_cap = cap;
    }
    glxml_param *p = &c->params[c->nparams];
    p->name = dup_trimmed(s->name.p);
    p->type = dup_trimmed(s->type.p);
    p->group = s->param_group;
    s->param_group = NULL;
    if (!p->name || !p->type) {
        free(p->name);
        free(p->type);
        free(p->group);
        return fail(s, "out of memory");
    }
    if (!p->name[0])
        return fail(s, "<param> without <name> in %s", c->name ? c->name : "?");
    c->nparams++;
    return 0;
}

static void free_command(glxml_command *c)
{
    for (size_t i = 0; i < c->nparams; i++) {
        free(c->params[i].name);
        free(c->params[i].type);
        free(c->params[i].group);
    }
    free(c->params);
    free(c->name);
    free(c->ret);
    memset(c, 0, sizeof *c);
}

static int push_command(scanner *s)
{
    glxml *x = s->out;
    if (!s->cur.name)
        return fail(s, "<command> without <proto><name>");
    if (x->ncmds == s->cmd_cap) {
        size_t cap = s->cmd_cap ? s->cmd_cap * 2 : 1024;
        glxml_command *c = realloc(x->cmds, cap * sizeof *c);
        if (!c)
            return fail(s, "out of memory");
        x->cmds = c;
        s->cmd_cap = cap;
    }
    x->cmds[x->ncmds++] = s->cur;
    memset(&s->cur, 0, sizeof s->cur);
    s->cur_cap = 0;
    return 0;
}

static const char *parent(const scanner *s) { return s->depth >= 2 ? s->stack[s->depth - 2] : ""; }

static int on_start(scanner *s, const char *tag)
{
    if (!strcmp(tag, "command") && !strcmp(parent(s), "commands")) {
        s->in_command = 1;
        free_command(&s->cur);
        s->cur_cap = 0;
        s->cur.line = s->line;
    } else if (s->in_command && !strcmp(tag, "proto")) {
        s->in_proto = 1;
        sb_clear(&s->type);
        sb_clear(&s->name);
    } else if (s->in_command && !strcmp(tag, "param")) {
        const char *group = attr_value(s, "group");
        s->in_param = 1;
        sb_clear(&s->type);
        sb_clear(&s->name);
        free(s->param_group);
        s->param_group = NULL;
        if (group && !(s->param_group = dup_trimmed(group)))
            return fail(s, "out of memory");
    } else if ((s->in_proto || s->in_param) && !strcmp(tag, "name")) {
        s->in_name = 1;
    } else if (!strcmp(tag, "enum") && !strcmp(parent(s), "enums")) {
        return push_enum(s);
    } else if (!strcmp(tag, "feature")) {
        const char *api = attr_value(s, "api");
        s->feature_version = api && !strcmp(api, "gl") ? parse_version(attr_value(s, "number")) : 0;
    } else if (s->feature_version && !strcmp(tag, "enum") && !strcmp(parent(s), "require")) {
        return push_required(s, 0);
    } else if (s->feature_version && !strcmp(tag, "command") && !strcmp(parent(s), "require")) {
        return push_required(s, 1);
    }
    return 0;
}

static int on_end(scanner *s, const char *tag)
{
    if (s->in_name && !strcmp(tag, "name")) {
        s->in_name = 0;
    } else if (s->in_proto && !strcmp(tag, "proto")) {
        s->in_proto = 0;
        free(s->cur.name);
        free(s->cur.ret);
        s->cur.name = dup_trimmed(s->name.p);
        s->cur.ret = dup_trimmed(s->type.p);
        if (!s->cur.name || !s->cur.ret)
            return fail(s, "out of memory");
    } else if (s->in_param && !strcmp(tag, "param")) {
        s->in_param = 0;
        return push_param(s);
    } else if (s->in_command && !strcmp(tag, "command")) {
        s->in_command = 0;
        return push_command(s);
    } else if (!strcmp(tag, "feature")) {
        s->feature_version = 0;
    }
    return 0;
}

static int on_text(scanner *s, size_t from, size_t to)
{
    if (!(s->in_proto || s->in_param))
        return 0;
    strbuf *dst = s->in_name ? &s->name : &s->type;
    /* Keep token boundaries: "const<ptype>GLfloat</ptype> *" pieces. */
    if (!s->in_name && sb_append(dst, " ", 1))
        return fail(s, "out of memory");
    return decode_text(s, from, to, dst);
}

/* ---- the scanner ------------------------------------------------------ */

static int scan_tag(scanner *s)
{
    if (starts_with(s, "<!--"))
        return skip_past(s, "-->", "comment");
    if (starts_with(s, "<?"))
        return skip_past(s, "?>", "processing instruction");
    if (starts_with(s, "<![CDATA[")) {
        advance(s, 9);
        size_t from = s->pos;
        if (skip_past(s, "]]>", "CDATA section"))
            return -1;
        strbuf *dst = s->in_name ? &s->name : &s->type;
        if ((s->in_proto || s->in_param) && sb_append(dst, s->buf + from, s->pos - 3 - from))
            return fail(s, "out of memory");
        return 0;
    }
    if (starts_with(s, "<!"))
        return skip_past(s, ">", "declaration");
    if (starts_with(s, "</")) {
        char tag[MAX_NAME];
        advance(s, 2);
        if (read_name(s, tag))
            return -1;
        skip_space(s);
        if (s->pos >= s->len || s->buf[s->pos] != '>')
            return fail(s, "expected '>' after </%s", tag);
        advance(s, 1);
        if (s->depth == 0 || strcmp(s->stack[s->depth - 1], tag) != 0)
            return fail(s, "</%s> does not close <%s>", tag, s->depth ? s->stack[s->depth - 1] : "(nothing)");
        int rc = on_end(s, tag);
        s->depth--;
        return rc;
    }
    char tag[MAX_NAME];
    advance(s, 1);
    if (read_name(s, tag))
        return -1;
    for (int i = 0; i < s->nattrs; i++)
        sb_clear(&s->attrs[i].value);
    s->nattrs = 0;
    for (;;) {
        skip_space(s);
        if (s->pos >= s->len)
            return fail(s, "unterminated <%s>", tag);
        char c = s->buf[s->pos];
        if (c == '>' || (c == '/' && starts_with(s, "/>")))
            break;
        if (s->nattrs == MAX_ATTRS)
            return fail(s, "<%s> has too many attributes", tag);
        attr *a = &s->attrs[s->nattrs];
        if (read_name(s, a->name))
            return -1;
        skip_space(s);
        if (s->pos >= s->len || s->buf[s->pos] != '=')
            return fail(s, "attribute %s of <%s> has no value", a->name, tag);
        advance(s, 1);
        skip_space(s);
        if (s->pos >= s->len || (s->buf[s->pos] != '"' && s->buf[s->pos] != '\''))
            return fail(s, "attribute %s of <%s> is not quoted", a->name, tag);
        char quote = s->buf[s->pos];
        advance(s, 1);
        size_t from = s->pos;
        while (s->pos < s->len && s->buf[s->pos] != quote && s->buf[s->pos] != '<')
            advance(s, 1);
        if (s->pos >= s->len || s->buf[s->pos] != quote)
            return fail(s, "unterminated value of attribute %s", a->name);
        sb_clear(&a->value);
        if (decode_text(s, from, s->pos, &a->value))
            return -1;
        advance(s, 1);
        s->nattrs++;
    }
    int self_closing = s->buf[s->pos] == '/';
    advance(s, self_closing ? 2 : 1);
    if (s->depth == MAX_DEPTH)
        return fail(s, "elements nested too deeply");
    memcpy(s->stack[s->depth++], tag, MAX_NAME);
    int rc = on_start(s, tag);
    if (rc == 0 && self_closing) {
        rc = on_end(s, tag);
        s->depth--;
    }
    return rc;
}

static int scan(scanner *s)
{
    while (s->pos < s->len) {
        if (s->buf[s->pos] == '<') {
            if (scan_tag(s))
                return -1;
            continue;
        }
        size_t from = s->pos;
        while (s->pos < s->len && s->buf[s->pos] != '<')
            advance(s, 1);
        if (on_text(s, from, s->pos))
            return -1;
    }
    if (s->depth)
        return fail(s, "file ends inside <%s>", s->stack[s->depth - 1]);
    return 0;
}

int glxml_load(const char *path, glxml *out, char *err, size_t errsz)
{
    memset(out, 0, sizeof *out);
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err, errsz, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    char *buf = NULL;
    size_t len = 0, cap = 0;
    for (;;) {
        if (len + 65536 > cap) {
            cap = cap ? cap * 2 : 1 << 20;
            char *p = realloc(buf, cap);
            if (!p) {
                free(buf);
                fclose(f);
                snprintf(err, errsz, "%s: out of memory", path);
                return -1;
            }
            buf = p;
        }
        size_t n = fread(buf + len, 1, cap - len, f);
        len += n;
        if (n == 0)
            break;
    }
    int read_error = ferror(f);
    fclose(f);
    if (read_error) {
        free(buf);
        snprintf(err, errsz, "%s: read error", path);
        return -1;
    }

    scanner s = {.path = path, .buf = buf, .len = len, .line = 1, .err = err, .errsz = errsz, .out = out};
    int rc = scan(&s);
    if (rc == 0 && out->ncmds == 0)
        rc = fail(&s, "no <commands><command> entries found");
    if (rc == 0) {
        qsort(out->enums, out->nenums, sizeof *out->enums, compare_enum_names);
        for (size_t i = 0; i < s.nrequired; i++) {
            int *version;
            if (s.required[i].is_command) {
                glxml_command *c = (glxml_command *)glxml_find_command(out, s.required[i].name);
                version = c ? &c->gl_version : NULL;
            } else {
                glxml_enum *e = (glxml_enum *)glxml_find_enum(out, s.required[i].name);
                version = e ? &e->gl_version : NULL;
            }
            if (version && (*version == 0 || s.required[i].version < *version))
                *version = s.required[i].version;
        }
    }
    for (size_t i = 0; i < s.nrequired; i++)
        free(s.required[i].name);
    free(s.required);
    free(s.param_group);
    free_command(&s.cur);
    free(s.type.p);
    free(s.name.p);
    for (int i = 0; i < MAX_ATTRS; i++)
        free(s.attrs[i].value.p);
    free(buf);
    if (rc)
        glxml_free(out);
    return rc;
}

void glxml_free(glxml *x)
{
    for (size_t i = 0; i < x->ncmds; i++)
        free_command(&x->cmds[i]);
    free(x->cmds);
    for (size_t i = 0; i < x->nenums; i++) {
        free(x->enums[i].name);
        free(x->enums[i].groups);
    }
    free(x->enums);
    memset(x, 0, sizeof *x);
}

const glxml_command *glxml_find_command(const glxml *x, const char *name)
{
    for (size_t i = 0; i < x->ncmds; i++)
        if (!strcmp(x->cmds[i].name, name))
            return &x->cmds[i];
    return NULL;
}

const glxml_enum *glxml_find_enum(const glxml *x, const char *name)
{
    glxml_enum key = {.name = (char *)name};
    return x->nenums ? bsearch(&key, x->enums, x->nenums, sizeof *x->enums, compare_enum_names) : NULL;
}

int glxml_enum_in_group(const glxml_enum *e, const char *group)
{
    size_t n = strlen(group);
    for (const char *p = e->groups; p && *p;) {
        const char *end = strchr(p, ',');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        if (len == n && !strncmp(p, group, n))
            return 1;
        p = end ? end + 1 : p + len;
    }
    return 0;
}

char *glxml_normalise_type(const char *type, char *buf, size_t bufsz)
{
    size_t o = 0;
    if (!bufsz)
        return buf;
    buf[0] = 0;
    for (const char *p = type; *p;) {
        const char *tok = p;
        size_t n;
        if (isspace((unsigned char)*p)) {
            p++;
            continue;
        }
        if (*p == '*') {
            n = 1;
        } else if (isalnum((unsigned char)*p) || *p == '_') {
            n = 0;
            while (isalnum((unsigned char)p[n]) || p[n] == '_')
                n++;
        } else {
            n = 1; /* any other character stands for itself */
        }
        p += n;
        if (n == 6 && !strncmp(tok, "GLvoid", 6)) {
            tok = "void";
            n = 4;
        }
        if (o + n + 2 > bufsz)
            break;
        if (o)
            buf[o++] = ' ';
        memcpy(buf + o, tok, n);
        o += n;
        buf[o] = 0;
    }
    return buf;
}
