/* gen/spec.c — loads spec/gl.yaml (format: spec/README.md) into the plain
 * structs of gen/spec.h and validates it, with FILE:LINE:COL messages.
 * Owns: the parsed spec (freed by spec_free). Never exits or prints: every
 * problem is returned as one error line for the caller to report. */
#include "spec.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

/* Value (non-pointer) types a parameter or return value may have. Keeping
 * the list closed catches typos ("GLFloat") at load time instead of in the
 * generated C. */
static const char *const known_base_types[] = {
    "void",    "GLboolean",  "GLbyte",  "GLubyte",  "GLshort",  "GLushort",    "GLint",     "GLuint",   "GLsizei",
    "GLenum",  "GLbitfield", "GLfloat", "GLclampf", "GLdouble", "GLclampd",    "GLchar",    "GLintptr", "GLsizeiptr",
    "GLint64", "GLuint64",   "GLhalf",  "GLfixed",  "GLsync",   "GLhandleARB", "GLcharARB",
};

static const char *const known_categories[] = {
    "geometry", "state", "frame", "get", "object", "client", "special",
};

/* Integer types a count may be computed from. */
static const char *const integer_types[] = {
    "GLint",   "GLuint",     "GLsizei",  "GLshort", "GLushort", "GLbyte",
    "GLubyte", "GLsizeiptr", "GLintptr", "GLint64", "GLuint64",
};

typedef struct loader {
    const char *path;
    yaml_document_t doc;
    char *err;
    size_t errsz;
} loader;

static int contains(const char *const *list, size_t n, const char *s)
{
    for (size_t i = 0; i < n; i++)
        if (strcmp(list[i], s) == 0)
            return 1;
    return 0;
}

#define COUNT_OF(a) (sizeof(a) / sizeof((a)[0]))

static int fail_at(loader *ld, yaml_mark_t mark, const char *fmt, ...)
{
    int n = snprintf(ld->err, ld->errsz, "%s:%zu:%zu: ", ld->path, mark.line + 1, mark.column + 1);
    if (n >= 0 && (size_t)n < ld->errsz) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(ld->err + n, ld->errsz - (size_t)n, fmt, ap);
        va_end(ap);
    }
    return -1;
}

static int fail(loader *ld, const yaml_node_t *node, const char *fmt, ...)
{
    int n =
        snprintf(ld->err, ld->errsz, "%s:%zu:%zu: ", ld->path, node->start_mark.line + 1, node->start_mark.column + 1);
    if (n >= 0 && (size_t)n < ld->errsz) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(ld->err + n, ld->errsz - (size_t)n, fmt, ap);
        va_end(ap);
    }
    return -1;
}

static char *dup_str(const char *s)
{
    size_t n = strlen(s) + 1;
    char *p = malloc(n);
    if (p)
        memcpy(p, s, n);
    return p;
}

static yaml_node_t *node_at(loader *ld, int id) { return yaml_document_get_node(&ld->doc, id); }

static const char *scalar(const yaml_node_t *n)
{
    return n && n->type == YAML_SCALAR_NODE ? (const char *)n->data.scalar.value : NULL;
}

static const char *kind_name(const yaml_node_t *n)
{
    switch (n->type) {
    case YAML_SCALAR_NODE: return "a scalar";
    case YAML_SEQUENCE_NODE: return "a list";
    case YAML_MAPPING_NODE: return "a mapping";
    default: return "empty";
    }
}

static int expect_scalar(loader *ld, const yaml_node_t *n, const char *what, const char **out)
{
    *out = "";
    if (n->type != YAML_SCALAR_NODE)
        return fail(ld, n, "%s must be a scalar, not %s", what, kind_name(n));
    *out = scalar(n);
    return 0;
}

static int parse_long(const char *s, long *out)
{
    if (!s || !*s)
        return -1;
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || *end)
        return -1;
    *out = v;
    return 0;
}

static int is_identifier(const char *s)
{
    if (!s || !(isalpha((unsigned char)*s) || *s == '_'))
        return 0;
    for (; *s; s++)
        if (!(isalnum((unsigned char)*s) || *s == '_'))
            return 0;
    return 1;
}

static int parse_bool(loader *ld, const yaml_node_t *n, const char *what, int *out)
{
    const char *s;
    if (expect_scalar(ld, n, what, &s))
        return -1;
    if (!strcmp(s, "true") || !strcmp(s, "yes"))
        *out = 1;
    else if (!strcmp(s, "false") || !strcmp(s, "no"))
        *out = 0;
    else
        return fail(ld, n, "%s must be true or false, not '%s'", what, s);
    return 0;
}

/* Rejects keys that appear twice in one mapping: libyaml keeps both and a
 * silently ignored duplicate is a spec bug. */
static int check_duplicate_keys(loader *ld, const yaml_node_t *map)
{
    for (yaml_node_pair_t *a = map->data.mapping.pairs.start; a < map->data.mapping.pairs.top; a++) {
        const char *ka = scalar(node_at(ld, a->key));
        if (!ka)
            return fail(ld, node_at(ld, a->key), "mapping keys must be scalars");
        for (yaml_node_pair_t *b = a + 1; b < map->data.mapping.pairs.top; b++) {
            const char *kb = scalar(node_at(ld, b->key));
            if (kb && !strcmp(ka, kb))
                return fail(ld, node_at(ld, b->key), "duplicate key '%s'", kb);
        }
    }
    return 0;
}

/* ---- types ------------------------------------------------------------ */

/* Splits a C type as written in the GL headers ("const GLchar *const *")
 * into base type, pointer depth and pointee constness. */
static int parse_type(loader *ld, const yaml_node_t *n, const char *text, char **base, int *depth, int *is_const)
{
    char buf[128];
    size_t len = strlen(text);
    if (len >= sizeof buf)
        return fail(ld, n, "type '%s' is too long", text);
    memcpy(buf, text, len + 1);

    int stars = 0, leading_const = 0, inner_const = 0;
    char *ident = NULL;
    char *save = NULL;
    /* Separate '*' from identifiers so strtok sees them as tokens. */
    char spaced[3 * sizeof buf];
    size_t o = 0;
    for (size_t i = 0; buf[i]; i++) {
        if (buf[i] == '*') {
            spaced[o++] = ' ';
            spaced[o++] = '*';
            spaced[o++] = ' ';
        } else {
            spaced[o++] = buf[i];
        }
    }
    spaced[o] = 0;
    for (char *tok = strtok_r(spaced, " \t", &save); tok; tok = strtok_r(NULL, " \t", &save)) {
        if (!strcmp(tok, "*")) {
            if (!ident)
                return fail(ld, n, "type '%s': '*' before the type name", text);
            stars++;
        } else if (!strcmp(tok, "const")) {
            if (!ident)
                leading_const = 1;
            else if (stars == 0)
                inner_const = 1; /* "GLfloat const *" */
            /* "T *const *": constness of the pointer itself, not the data */
        } else {
            if (ident)
                return fail(ld, n, "type '%s' names two types", text);
            ident = tok;
        }
    }
    if (!ident)
        return fail(ld, n, "type '%s' has no type name", text);
    if (!contains(known_base_types, COUNT_OF(known_base_types), ident))
        return fail(ld, n, "unknown type '%s' in '%s'", ident, text);
    if (stars > 2)
        return fail(ld, n, "type '%s': more than two levels of pointer", text);
    if (stars == 0 && strcmp(ident, "void") == 0)
        return fail(ld, n, "a parameter cannot be 'void'");
    *base = dup_str(ident);
    if (!*base)
        return fail(ld, n, "out of memory");
    *depth = stars;
    *is_const = leading_const || inner_const;
    return 0;
}

/* ---- counts ----------------------------------------------------------- */

static int push_arg(loader *ld, const yaml_node_t *n, spec_count *c, const char *text)
{
    char **grown = realloc(c->args, (c->nargs + 1) * sizeof *grown);
    if (!grown)
        return fail(ld, n, "out of memory");
    c->args = grown;
    c->args[c->nargs] = dup_str(text);
    if (!c->args[c->nargs])
        return fail(ld, n, "out of memory");
    c->nargs++;
    return 0;
}

/* "n", "4", "n*4", "count * 16": factors into args. */
static int parse_product(loader *ld, const yaml_node_t *n, const char *text, spec_count *c)
{
    char buf[128];
    size_t len = strlen(text);
    if (len == 0 || len >= sizeof buf)
        return fail(ld, n, "bad count expression '%s'", text);
    memcpy(buf, text, len + 1);
    char *save = NULL;
    for (char *tok = strtok_r(buf, "*", &save); tok; tok = strtok_r(NULL, "*", &save)) {
        while (isspace((unsigned char)*tok))
            tok++;
        char *end = tok + strlen(tok);
        while (end > tok && isspace((unsigned char)end[-1]))
            *--end = 0;
        long v;
        if (parse_long(tok, &v) == 0) {
            if (v <= 0)
                return fail(ld, n, "count factor %ld must be positive", v);
        } else if (!is_identifier(tok)) {
            return fail(ld, n, "bad count factor '%s' in '%s'", tok, text);
        }
        if (push_arg(ld, n, c, tok))
            return -1;
    }
    if (c->nargs == 0)
        return fail(ld, n, "empty count expression '%s'", text);
    /* An empty factor ("n**2", "*n") is a typo, not a product. */
    if (strstr(text, "**") || text[0] == '*' || text[len - 1] == '*')
        return fail(ld, n, "bad count expression '%s'", text);
    return 0;
}

static int parse_arg_list(loader *ld, const yaml_node_t *v, const char *form, size_t min, size_t max, spec_count *c)
{
    if (v->type != YAML_SEQUENCE_NODE)
        return fail(ld, v, "count form '%s' takes a list", form);
    size_t n = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
    if (n < min || n > max) {
        if (min == max)
            return fail(ld, v, "count form '%s' takes %zu arguments, not %zu", form, min, n);
        return fail(ld, v, "count form '%s' takes %zu to %zu arguments, not %zu", form, min, max, n);
    }
    for (yaml_node_item_t *it = v->data.sequence.items.start; it < v->data.sequence.items.top; it++) {
        yaml_node_t *a = node_at(ld, *it);
        const char *s;
        if (expect_scalar(ld, a, "a count argument", &s))
            return -1;
        long num;
        if (parse_long(s, &num) != 0 && !is_identifier(s))
            return fail(ld, a, "count argument '%s' is neither a parameter name nor an integer", s);
        if (push_arg(ld, a, c, s))
            return -1;
    }
    return 0;
}

static int parse_count(loader *ld, const yaml_node_t *n, spec_count *c)
{
    if (n->type == YAML_SCALAR_NODE) {
        const char *s = scalar(n);
        long v;
        if (parse_long(s, &v) == 0) {
            if (v <= 0 || v > INT_MAX)
                return fail(ld, n, "count %ld must be positive", v);
            c->kind = SPEC_COUNT_FIXED;
            c->fixed = v;
            return 0;
        }
        c->kind = SPEC_COUNT_EXPR;
        return parse_product(ld, n, s, c);
    }
    if (n->type != YAML_MAPPING_NODE)
        return fail(ld, n, "count must be an integer, an expression or a mapping");
    size_t pairs = (size_t)(n->data.mapping.pairs.top - n->data.mapping.pairs.start);
    if (pairs != 1)
        return fail(ld, n, "count mapping must have exactly one key (pname, image, bitmap, typed, bytes, string, map)");
    yaml_node_pair_t *p = n->data.mapping.pairs.start;
    yaml_node_t *k = node_at(ld, p->key), *v = node_at(ld, p->value);
    const char *form = scalar(k);
    if (!form)
        return fail(ld, k, "count form must be a scalar");
    if (!strcmp(form, "pname")) {
        const char *s;
        c->kind = SPEC_COUNT_PNAME;
        if (expect_scalar(ld, v, "pname", &s))
            return -1;
        if (!is_identifier(s))
            return fail(ld, v, "pname must name a parameter, not '%s'", s);
        return push_arg(ld, v, c, s);
    }
    if (!strcmp(form, "image")) {
        c->kind = SPEC_COUNT_IMAGE;
        return parse_arg_list(ld, v, form, 5, 5, c);
    }
    if (!strcmp(form, "bitmap")) {
        c->kind = SPEC_COUNT_BITMAP;
        return parse_arg_list(ld, v, form, 2, 2, c);
    }
    if (!strcmp(form, "typed")) {
        c->kind = SPEC_COUNT_TYPED;
        return parse_arg_list(ld, v, form, 2, 2, c);
    }
    if (!strcmp(form, "map")) {
        c->kind = SPEC_COUNT_MAP;
        if (v->type == YAML_SEQUENCE_NODE) {
            size_t nargs = (size_t)(v->data.sequence.items.top - v->data.sequence.items.start);
            if (nargs != 3 && nargs != 5)
                return fail(ld, v, "count form 'map' takes 3 (1D) or 5 (2D) arguments, not %zu", nargs);
        }
        return parse_arg_list(ld, v, form, 3, 5, c);
    }
    if (!strcmp(form, "bytes")) {
        const char *s;
        c->kind = SPEC_COUNT_BYTES;
        if (expect_scalar(ld, v, "bytes", &s))
            return -1;
        return parse_product(ld, v, s, c);
    }
    if (!strcmp(form, "string")) {
        int on;
        c->kind = SPEC_COUNT_STRING;
        if (parse_bool(ld, v, "string", &on))
            return -1;
        if (!on)
            return fail(ld, v, "'string: false' is not a count; leave the count out instead");
        return 0;
    }
    return fail(ld, k, "unknown count form '%s' (pname, image, bitmap, typed, bytes, string, map)", form);
}

/* ---- commands --------------------------------------------------------- */

static void free_count(spec_count *c)
{
    for (size_t i = 0; i < c->nargs; i++)
        free(c->args[i]);
    free(c->args);
}

static void free_command(spec_command *c)
{
    for (size_t i = 0; i < c->nparams; i++) {
        free(c->params[i].name);
        free(c->params[i].type);
        free(c->params[i].base_type);
        free_count(&c->params[i].count);
    }
    free(c->params);
    free(c->name);
    free(c->category);
    free(c->ret);
    free(c->vertex);
}

static int parse_param(loader *ld, const yaml_node_t *n, spec_param *p, yaml_node_t **count_node)
{
    if (n->type != YAML_MAPPING_NODE)
        return fail(ld, n, "a parameter must be a mapping {name, type, ...}");
    if (check_duplicate_keys(ld, n))
        return -1;
    int have_dir = 0;
    yaml_node_t *dir_node = NULL;
    *count_node = NULL;
    for (yaml_node_pair_t *pr = n->data.mapping.pairs.start; pr < n->data.mapping.pairs.top; pr++) {
        yaml_node_t *k = node_at(ld, pr->key), *v = node_at(ld, pr->value);
        const char *key = scalar(k), *s;
        if (!strcmp(key, "name")) {
            if (expect_scalar(ld, v, "name", &s))
                return -1;
            if (!is_identifier(s))
                return fail(ld, v, "parameter name '%s' is not a C identifier", s);
            if (!(p->name = dup_str(s)))
                return fail(ld, v, "out of memory");
        } else if (!strcmp(key, "type")) {
            if (expect_scalar(ld, v, "type", &s))
                return -1;
            if (!(p->type = dup_str(s)))
                return fail(ld, v, "out of memory");
            if (parse_type(ld, v, s, &p->base_type, &p->pointer_depth, &p->is_const))
                return -1;
        } else if (!strcmp(key, "dir")) {
            if (expect_scalar(ld, v, "dir", &s))
                return -1;
            if (!strcmp(s, "out"))
                p->dir_out = 1;
            else if (strcmp(s, "in") != 0)
                return fail(ld, v, "dir must be 'in' or 'out', not '%s'", s);
            have_dir = 1;
            dir_node = v;
        } else if (!strcmp(key, "nullable")) {
            if (parse_bool(ld, v, "nullable", &p->nullable))
                return -1;
        } else if (!strcmp(key, "count")) {
            *count_node = v;
            if (parse_count(ld, v, &p->count))
                return -1;
        } else {
            return fail(ld, k, "unknown parameter key '%s' (name, type, dir, count, nullable)", key);
        }
    }
    if (!p->name)
        return fail(ld, n, "parameter without a name");
    if (!p->type)
        return fail(ld, n, "parameter '%s' has no type", p->name);
    if (p->pointer_depth == 0) {
        if (have_dir)
            return fail(ld, dir_node, "parameter '%s' is not a pointer; 'dir' makes no sense", p->name);
        if (*count_node)
            return fail(ld, *count_node, "parameter '%s' is not a pointer; 'count' makes no sense", p->name);
        if (p->nullable)
            return fail(ld, n, "parameter '%s' is not a pointer; it cannot be nullable", p->name);
    } else if (!have_dir) {
        /* Non-const pointers are written by the command. */
        p->dir_out = !p->is_const;
    } else if (p->dir_out && p->is_const) {
        return fail(ld, dir_node, "parameter '%s' is const; it cannot be 'dir: out'", p->name);
    }
    return 0;
}

static const spec_param *find_param(const spec_command *c, const char *name)
{
    for (size_t i = 0; i < c->nparams; i++)
        if (c->params[i].name && !strcmp(c->params[i].name, name))
            return &c->params[i];
    return NULL;
}

/* A count argument must be an integer literal or an integer-valued
 * parameter of the same command (or, where `want_enum`, a GLenum one). */
static int check_count_arg(loader *ld, const yaml_node_t *where, const spec_command *c, const spec_param *p,
                           const char *arg, int want_enum, int allow_literal)
{
    long v;
    if (parse_long(arg, &v) == 0) {
        if (!allow_literal)
            return fail(ld, where, "%s: count of '%s' must name a parameter, not %s", c->name, p->name, arg);
        if (v <= 0)
            return fail(ld, where, "%s: count of '%s' has non-positive factor %ld", c->name, p->name, v);
        return 0;
    }
    const spec_param *ref = find_param(c, arg);
    if (!ref)
        return fail(ld, where, "%s: count of '%s' names '%s', which is not a parameter of %s", c->name, p->name, arg,
                    c->name);
    if (ref == p)
        return fail(ld, where, "%s: count of '%s' refers to itself", c->name, p->name);
    if (ref->pointer_depth)
        return fail(ld, where, "%s: count of '%s' names pointer parameter '%s'", c->name, p->name, arg);
    if (want_enum && strcmp(ref->base_type, "GLenum") != 0)
        return fail(ld, where, "%s: count of '%s' needs GLenum parameter, but '%s' is %s", c->name, p->name, arg,
                    ref->type);
    if (!want_enum && !contains(integer_types, COUNT_OF(integer_types), ref->base_type))
        return fail(ld, where, "%s: count of '%s' names '%s' of type %s, which is not an integer", c->name, p->name,
                    arg, ref->type);
    return 0;
}

static int check_counts(loader *ld, const spec_command *c, const spec_param *p, const yaml_node_t *where)
{
    const spec_count *k = &p->count;
    switch (k->kind) {
    case SPEC_COUNT_NONE:
    case SPEC_COUNT_FIXED:
    case SPEC_COUNT_STRING: return 0;
    case SPEC_COUNT_EXPR:
    case SPEC_COUNT_BYTES:
        for (size_t i = 0; i < k->nargs; i++)
            if (check_count_arg(ld, where, c, p, k->args[i], 0, 1))
                return -1;
        return 0;
    case SPEC_COUNT_PNAME: return check_count_arg(ld, where, c, p, k->args[0], 1, 0);
    case SPEC_COUNT_IMAGE:
        /* w, h, d: sizes (d may be a literal 1); format, type: enums. */
        for (size_t i = 0; i < 3; i++)
            if (check_count_arg(ld, where, c, p, k->args[i], 0, 1))
                return -1;
        for (size_t i = 3; i < 5; i++)
            if (check_count_arg(ld, where, c, p, k->args[i], 1, 0))
                return -1;
        return 0;
    case SPEC_COUNT_BITMAP:
        for (size_t i = 0; i < 2; i++)
            if (check_count_arg(ld, where, c, p, k->args[i], 0, 1))
                return -1;
        return 0;
    case SPEC_COUNT_TYPED:
        if (check_count_arg(ld, where, c, p, k->args[0], 0, 1))
            return -1;
        return check_count_arg(ld, where, c, p, k->args[1], 1, 0);
    case SPEC_COUNT_MAP:
        if (check_count_arg(ld, where, c, p, k->args[0], 1, 0))
            return -1;
        for (size_t i = 1; i < k->nargs; i++)
            if (check_count_arg(ld, where, c, p, k->args[i], 0, 1))
                return -1;
        return 0;
    }
    return 0;
}

static int parse_command(loader *ld, const yaml_node_t *n, spec_command *c)
{
    if (n->type != YAML_MAPPING_NODE)
        return fail(ld, n, "a command must be a mapping {name, opcode, ...}");
    if (check_duplicate_keys(ld, n))
        return -1;
    c->line = (int)n->start_mark.line + 1;
    c->khronos = 1;
    c->opcode = -1;
    c->wire = SPEC_WIRE_PACK;
    yaml_node_t *params_node = NULL, *wire_node = NULL, *opcode_node = NULL;
    for (yaml_node_pair_t *pr = n->data.mapping.pairs.start; pr < n->data.mapping.pairs.top; pr++) {
        yaml_node_t *k = node_at(ld, pr->key), *v = node_at(ld, pr->value);
        const char *key = scalar(k), *s;
        if (!strcmp(key, "params")) {
            params_node = v;
            continue;
        }
        if (!strcmp(key, "khronos")) {
            if (parse_bool(ld, v, "khronos", &c->khronos))
                return -1;
            continue;
        }
        if (expect_scalar(ld, v, key, &s))
            return -1;
        if (!strcmp(key, "name")) {
            if (!is_identifier(s))
                return fail(ld, v, "command name '%s' is not a C identifier", s);
            if (!strncmp(s, "gl", 2) && isupper((unsigned char)s[2]))
                return fail(ld, v, "command name '%s' must not carry the 'gl' prefix", s);
            if (!(c->name = dup_str(s)))
                return fail(ld, v, "out of memory");
        } else if (!strcmp(key, "opcode")) {
            long op;
            opcode_node = v;
            if (parse_long(s, &op) != 0)
                return fail(ld, v, "opcode '%s' is not an integer", s);
            if (op < 1 || op > 65534)
                return fail(ld, v, "opcode %ld out of range 1..65534", op);
            c->opcode = (int)op;
        } else if (!strcmp(key, "category")) {
            if (!contains(known_categories, COUNT_OF(known_categories), s))
                return fail(ld, v, "unknown category '%s' (geometry, state, frame, get, object, client, special)", s);
            if (!(c->category = dup_str(s)))
                return fail(ld, v, "out of memory");
        } else if (!strcmp(key, "return")) {
            int depth, is_const;
            char *base = NULL;
            if (strcmp(s, "void") != 0) {
                if (parse_type(ld, v, s, &base, &depth, &is_const))
                    return -1;
                free(base);
            }
            if (!(c->ret = dup_str(s)))
                return fail(ld, v, "out of memory");
        } else if (!strcmp(key, "wire")) {
            wire_node = v;
            if (!strcmp(s, "pack"))
                c->wire = SPEC_WIRE_PACK;
            else if (!strcmp(s, "reply"))
                c->wire = SPEC_WIRE_REPLY;
            else if (!strcmp(s, "local"))
                c->wire = SPEC_WIRE_LOCAL;
            else if (!strcmp(s, "custom"))
                c->wire = SPEC_WIRE_CUSTOM;
            else
                return fail(ld, v, "unknown wire kind '%s' (pack, reply, local, custom)", s);
        } else if (!strcmp(key, "vertex")) {
            if (strcmp(s, "position") != 0)
                return fail(ld, v, "vertex must be 'position', not '%s'", s);
            if (!(c->vertex = dup_str(s)))
                return fail(ld, v, "out of memory");
        } else {
            return fail(
                ld, k, "unknown command key '%s' (name, opcode, category, return, params, wire, vertex, khronos)", key);
        }
    }
    if (!c->name)
        return fail(ld, n, "command without a name");
    if (!opcode_node)
        return fail(ld, n, "%s: no opcode", c->name);
    if (!c->category)
        return fail(ld, n, "%s: no category", c->name);
    if (!c->ret)
        return fail(ld, n, "%s: no return type", c->name);

    if (params_node) {
        if (params_node->type != YAML_SEQUENCE_NODE)
            return fail(ld, params_node, "%s: params must be a list", c->name);
        size_t np = (size_t)(params_node->data.sequence.items.top - params_node->data.sequence.items.start);
        if (np) {
            c->params = calloc(np, sizeof *c->params);
            if (!c->params)
                return fail(ld, params_node, "out of memory");
        }
        yaml_node_t **count_nodes = calloc(np ? np : 1, sizeof *count_nodes);
        if (!count_nodes)
            return fail(ld, params_node, "out of memory");
        int rc = 0;
        for (size_t i = 0; i < np && rc == 0; i++) {
            yaml_node_t *pn = node_at(ld, params_node->data.sequence.items.start[i]);
            c->nparams = i + 1;
            rc = parse_param(ld, pn, &c->params[i], &count_nodes[i]);
            for (size_t j = 0; rc == 0 && j < i; j++)
                if (!strcmp(c->params[j].name, c->params[i].name))
                    rc = fail(ld, pn, "%s: duplicate parameter '%s'", c->name, c->params[i].name);
        }
        /* Counts may refer to later parameters, so check after all are read. */
        for (size_t i = 0; i < np && rc == 0; i++) {
            spec_param *p = &c->params[i];
            yaml_node_t *pn = node_at(ld, params_node->data.sequence.items.start[i]);
            if (p->pointer_depth && p->count.kind == SPEC_COUNT_NONE && c->wire != SPEC_WIRE_LOCAL &&
                c->wire != SPEC_WIRE_CUSTOM)
                rc = fail(ld, pn, "%s: pointer parameter '%s' has no count (needed unless wire is local or custom)",
                          c->name, p->name);
            else if (count_nodes[i])
                rc = check_counts(ld, c, p, count_nodes[i]);
            if (rc == 0 && p->dir_out && c->wire == SPEC_WIRE_PACK)
                rc = fail(ld, pn, "%s: output parameter '%s' needs 'wire: reply' (or local/custom)", c->name, p->name);
        }
        free(count_nodes);
        if (rc)
            return -1;
    }
    if (strcmp(c->ret, "void") != 0 && c->wire == SPEC_WIRE_PACK)
        return fail(ld, wire_node ? wire_node : n, "%s returns %s, so it needs 'wire: reply' (or local/custom)",
                    c->name, c->ret);
    if (c->vertex && strcmp(c->category, "geometry") != 0)
        return fail(ld, n, "%s: 'vertex: position' only fits category geometry", c->name);
    return 0;
}

/* ---- top level -------------------------------------------------------- */

/* `pname_counts` and `map_components`: GL_ENUM -> positive count. */
static int parse_enum_counts(loader *ld, const yaml_node_t *n, const char *what, spec_pname_count **table,
                             size_t *count_out)
{
    if (n->type != YAML_MAPPING_NODE)
        return fail(ld, n, "%s must be a mapping of GL_ENUM: count", what);
    if (check_duplicate_keys(ld, n))
        return -1;
    size_t np = (size_t)(n->data.mapping.pairs.top - n->data.mapping.pairs.start);
    if (np == 0)
        return 0;
    *table = calloc(np, sizeof **table);
    if (!*table)
        return fail(ld, n, "out of memory");
    for (yaml_node_pair_t *pr = n->data.mapping.pairs.start; pr < n->data.mapping.pairs.top; pr++) {
        yaml_node_t *k = node_at(ld, pr->key), *v = node_at(ld, pr->value);
        const char *key = scalar(k), *val;
        long count;
        if (strncmp(key, "GL_", 3) != 0 || !is_identifier(key))
            return fail(ld, k, "pname '%s' must be a GL enum name (GL_...)", key);
        if (expect_scalar(ld, v, key, &val))
            return -1;
        if (parse_long(val, &count) != 0 || count <= 0 || count > 4096)
            return fail(ld, v, "count of %s must be an integer in 1..4096, not '%s'", key, val);
        spec_pname_count *pc = &(*table)[(*count_out)++];
        if (!(pc->name = dup_str(key)))
            return fail(ld, k, "out of memory");
        pc->count = (int)count;
    }
    return 0;
}

static int parse_commands(loader *ld, const yaml_node_t *n, spec *s)
{
    if (n->type != YAML_SEQUENCE_NODE)
        return fail(ld, n, "commands must be a list");
    size_t nc = (size_t)(n->data.sequence.items.top - n->data.sequence.items.start);
    if (nc == 0)
        return fail(ld, n, "commands is empty");
    s->cmds = calloc(nc, sizeof *s->cmds);
    if (!s->cmds)
        return fail(ld, n, "out of memory");
    for (size_t i = 0; i < nc; i++) {
        yaml_node_t *cn = node_at(ld, n->data.sequence.items.start[i]);
        s->ncmds = i + 1;
        if (parse_command(ld, cn, &s->cmds[i]))
            return -1;
        const spec_command *c = &s->cmds[i];
        for (size_t j = 0; j < i; j++) {
            if (!strcmp(s->cmds[j].name, c->name))
                return fail(ld, cn, "duplicate command name '%s' (first at line %d)", c->name, s->cmds[j].line);
            if (s->cmds[j].opcode == c->opcode)
                return fail(ld, cn, "%s: duplicate opcode %d (already used by %s at line %d)", c->name, c->opcode,
                            s->cmds[j].name, s->cmds[j].line);
        }
    }
    return 0;
}

static int parse_root(loader *ld, spec *s)
{
    yaml_node_t *root = yaml_document_get_root_node(&ld->doc);
    if (!root) {
        yaml_mark_t start = {0, 0, 0};
        return fail_at(ld, start, "empty file; expected a mapping with version, pname_counts, commands");
    }
    if (root->type != YAML_MAPPING_NODE)
        return fail(ld, root, "top level must be a mapping with version, pname_counts, commands, not %s",
                    kind_name(root));
    if (check_duplicate_keys(ld, root))
        return -1;
    yaml_node_t *version = NULL, *pnames = NULL, *maps = NULL, *commands = NULL;
    for (yaml_node_pair_t *pr = root->data.mapping.pairs.start; pr < root->data.mapping.pairs.top; pr++) {
        yaml_node_t *k = node_at(ld, pr->key);
        const char *key = scalar(k);
        if (!strcmp(key, "version"))
            version = node_at(ld, pr->value);
        else if (!strcmp(key, "pname_counts"))
            pnames = node_at(ld, pr->value);
        else if (!strcmp(key, "map_components"))
            maps = node_at(ld, pr->value);
        else if (!strcmp(key, "commands"))
            commands = node_at(ld, pr->value);
        else
            return fail(ld, k, "unknown top-level key '%s' (version, pname_counts, map_components, commands)", key);
    }
    if (!version)
        return fail(ld, root, "missing 'version: 1'");
    const char *vs = scalar(version);
    if (!vs || strcmp(vs, "1") != 0)
        return fail(ld, version, "unsupported spec version '%s' (this loader reads version 1)", vs ? vs : "?");
    if (!commands)
        return fail(ld, root, "missing 'commands'");
    if (pnames && parse_enum_counts(ld, pnames, "pname_counts", &s->pnames, &s->npnames))
        return -1;
    if (maps && parse_enum_counts(ld, maps, "map_components", &s->map_components, &s->nmap_components))
        return -1;
    if (parse_commands(ld, commands, s))
        return -1;
    /* Enum-sized counts need their table, or every such call would fail. */
    for (size_t i = 0; i < s->ncmds; i++) {
        const spec_command *c = &s->cmds[i];
        for (size_t j = 0; j < c->nparams; j++) {
            spec_count_kind kind = c->params[j].count.kind;
            yaml_mark_t at = {0, (size_t)c->line - 1, 0};
            if (kind == SPEC_COUNT_PNAME && s->npnames == 0)
                return fail_at(ld, at, "%s: count {pname: ...} but the file has no pname_counts", c->name);
            if (kind == SPEC_COUNT_MAP && s->nmap_components == 0)
                return fail_at(ld, at, "%s: count {map: ...} but the file has no map_components", c->name);
        }
    }
    return 0;
}

int spec_load(const char *path, spec *out, char *err, size_t errsz)
{
    char dummy[1];
    loader ld = {.path = path, .err = errsz ? err : dummy, .errsz = errsz ? errsz : sizeof dummy};
    memset(out, 0, sizeof *out);
    ld.err[0] = 0;

    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(ld.err, ld.errsz, "%s:0:0: cannot open: %s", path, strerror(errno));
        return -1;
    }
    yaml_parser_t parser;
    if (!yaml_parser_initialize(&parser)) {
        fclose(f);
        snprintf(ld.err, ld.errsz, "%s:0:0: cannot initialise the YAML parser", path);
        return -1;
    }
    yaml_parser_set_input_file(&parser, f);
    int rc;
    if (!yaml_parser_load(&parser, &ld.doc)) {
        yaml_mark_t m = parser.problem_mark;
        rc = fail_at(&ld, m, "not valid YAML: %s%s%s", parser.problem ? parser.problem : "parse error",
                     parser.context ? " " : "", parser.context ? parser.context : "");
        yaml_parser_delete(&parser);
        fclose(f);
        return rc;
    }
    yaml_parser_delete(&parser);
    fclose(f);

    rc = parse_root(&ld, out);
    yaml_document_delete(&ld.doc);
    if (rc) {
        spec_free(out);
        return -1;
    }
    return 0;
}

void spec_free(spec *s)
{
    if (!s)
        return;
    for (size_t i = 0; i < s->ncmds; i++)
        free_command(&s->cmds[i]);
    free(s->cmds);
    for (size_t i = 0; i < s->npnames; i++)
        free(s->pnames[i].name);
    free(s->pnames);
    for (size_t i = 0; i < s->nmap_components; i++)
        free(s->map_components[i].name);
    free(s->map_components);
    memset(s, 0, sizeof *s);
}

const spec_command *spec_find(const spec *s, const char *name)
{
    for (size_t i = 0; i < s->ncmds; i++)
        if (!strcmp(s->cmds[i].name, name))
            return &s->cmds[i];
    return NULL;
}

static int enum_count_of(const spec_pname_count *table, size_t n, const char *enum_name)
{
    for (size_t i = 0; i < n; i++)
        if (!strcmp(table[i].name, enum_name))
            return table[i].count;
    return -1;
}

int spec_pname_count_of(const spec *s, const char *enum_name)
{
    return enum_count_of(s->pnames, s->npnames, enum_name);
}

int spec_map_components_of(const spec *s, const char *enum_name)
{
    return enum_count_of(s->map_components, s->nmap_components, enum_name);
}
