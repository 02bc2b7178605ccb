/* core/spu/options.c — typed SPU options: text values parsed and range-checked
 * against an SPU's declarations before create() runs, and the accessors SPUs
 * read them with. Owns: every tsr_options and its strings and arrays.
 * Never: lets a bad value through to an SPU, or aborts on bad input. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "options.h"
#include "tessera/log.h"

typedef struct option_value {
    const tsr_option_spec *spec;
    bool b;
    int64_t i;
    double f;
    char *s;  /* TSR_OPT_STRING, TSR_OPT_ENUM */
    size_t n; /* list length */
    int64_t *ints;
    double *floats;
    char **strings;
} option_value;

struct tsr_options {
    char *spu; /* for accessor diagnostics */
    size_t count;
    option_value *values;
};

const char *tsr_option_type_name(tsr_option_type type)
{
    switch (type) {
    case TSR_OPT_BOOL: return "bool";
    case TSR_OPT_INT: return "int";
    case TSR_OPT_FLOAT: return "float";
    case TSR_OPT_STRING: return "string";
    case TSR_OPT_ENUM: return "enum";
    case TSR_OPT_INT_LIST: return "int list";
    case TSR_OPT_FLOAT_LIST: return "float list";
    case TSR_OPT_STRING_LIST: return "string list";
    }
    return "unknown";
}

/* ---- parsing one value ---------------------------------------------- */

static bool range_is_set(const tsr_option_spec *spec) { return spec->min <= spec->max; }

/* The detail of a parse failure ("'abc' is not an integer") goes into
 * `why`; the caller adds who (SPU, option, default or element). */
static bool parse_bool(const char *text, bool *out, char *why, size_t whysz)
{
    static const char *const yes[] = {"true", "yes", "on", "1"};
    static const char *const no[] = {"false", "no", "off", "0"};
    for (size_t i = 0; i < 4; i++) {
        if (!strcasecmp(text, yes[i])) {
            *out = true;
            return true;
        }
        if (!strcasecmp(text, no[i])) {
            *out = false;
            return true;
        }
    }
    snprintf(why, whysz, "'%s' is not a boolean (true/false, yes/no, on/off, 1/0)", text);
    return false;
}

static bool check_range(const tsr_option_spec *spec, double v, const char *text, char *why, size_t whysz)
{
    if (range_is_set(spec) && (v < spec->min || v > spec->max)) {
        snprintf(why, whysz, "'%s' is out of range [%.15g, %.15g]", text, spec->min, spec->max);
        return false;
    }
    return true;
}

static bool parse_int(const tsr_option_spec *spec, const char *text, int64_t *out, char *why, size_t whysz)
{
    /* Base 10 only ("010" is ten, not eight), an optional sign, digits, and
     * nothing else: strtoll alone would accept leading blanks. */
    const char *p = text;
    if (*p == '+' || *p == '-')
        p++;
    if (!isdigit((unsigned char)*p)) {
        snprintf(why, whysz, "'%s' is not an integer", text);
        return false;
    }
    char *end;
    errno = 0;
    long long v = strtoll(text, &end, 10);
    if (*end != '\0') {
        snprintf(why, whysz, "'%s' is not an integer", text);
        return false;
    }
    if (errno == ERANGE) {
        snprintf(why, whysz, "'%s' does not fit in a 64-bit integer", text);
        return false;
    }
    if (!check_range(spec, (double)v, text, why, whysz))
        return false;
    *out = v;
    return true;
}

static bool parse_float(const tsr_option_spec *spec, const char *text, double *out, char *why, size_t whysz)
{
    const char *p = text;
    if (*p == '+' || *p == '-')
        p++;
    if (!isdigit((unsigned char)*p) && !(*p == '.' && isdigit((unsigned char)p[1])) && strncasecmp(p, "inf", 3) &&
        strncasecmp(p, "nan", 3)) {
        snprintf(why, whysz, "'%s' is not a number", text);
        return false;
    }
    char *end;
    errno = 0;
    double v = strtod(text, &end);
    if (*end != '\0') {
        snprintf(why, whysz, "'%s' is not a number", text);
        return false;
    }
    /* NaN compares false against any range and infinities overflow every
     * consumer; an SPU option never needs them. */
    if (!isfinite(v)) {
        snprintf(why, whysz, "'%s' is not a finite number", text);
        return false;
    }
    if (!check_range(spec, v, text, why, whysz))
        return false;
    *out = v;
    return true;
}

/* Copies the `index`-th '|'-separated choice into buf; false past the end. */
static bool enum_choice(const char *choices, size_t index, char *buf, size_t size)
{
    const char *p = choices;
    for (size_t i = 0; i < index; i++) {
        p = strchr(p, '|');
        if (!p)
            return false;
        p++;
    }
    size_t len = strcspn(p, "|");
    if (len >= size)
        len = size - 1;
    memcpy(buf, p, len);
    buf[len] = '\0';
    return true;
}

static bool parse_enum(const tsr_option_spec *spec, const char *text, char *why, size_t whysz)
{
    const char *choices = spec->choices ? spec->choices : "";
    char names[32][TSR_SUGGEST_MAX_LEN + 1];
    const char *candidates[32];
    size_t n = 0;
    for (const char *p = choices;;) {
        size_t len = strcspn(p, "|");
        if (len == strlen(text) && !strncmp(p, text, len))
            return true;
        if (n < 32 && len <= TSR_SUGGEST_MAX_LEN) {
            memcpy(names[n], p, len);
            names[n][len] = '\0';
            candidates[n] = names[n];
            n++;
        }
        if (p[len] != '|')
            break;
        p += len + 1;
    }
    const char *hint = tsr_closest_name(text, candidates, n);
    if (hint)
        snprintf(why, whysz, "'%s' is not one of %s (did you mean '%s'?)", text, choices, hint);
    else
        snprintf(why, whysz, "'%s' is not one of %s", text, choices);
    return false;
}

static void value_free(option_value *v)
{
    free(v->s);
    free(v->ints);
    free(v->floats);
    if (v->strings)
        for (size_t i = 0; i < v->n; i++)
            free(v->strings[i]);
    free(v->strings);
    memset(v, 0, sizeof *v);
}

static char *dup_range(const char *s, size_t len)
{
    char *d = malloc(len + 1);
    if (d) {
        memcpy(d, s, len);
        d[len] = '\0';
    }
    return d;
}

/* Parses a comma-separated list; elements are trimmed of blanks, so
 * "1, 2, 3" works. The empty text is the empty list. */
static int parse_list(const tsr_option_spec *spec, const char *text, option_value *out, char *why, size_t whysz)
{
    size_t n = 0;
    if (*text) {
        n = 1;
        for (const char *p = text; *p; p++)
            n += *p == ',';
    }
    out->n = n;
    if (n == 0)
        return TSR_OK;
    if (spec->type == TSR_OPT_INT_LIST)
        out->ints = calloc(n, sizeof *out->ints);
    else if (spec->type == TSR_OPT_FLOAT_LIST)
        out->floats = calloc(n, sizeof *out->floats);
    else
        out->strings = calloc(n, sizeof *out->strings);
    if (!out->ints && !out->floats && !out->strings) {
        out->n = 0;
        snprintf(why, whysz, "out of memory");
        return TSR_ENOMEM;
    }
    const char *p = text;
    for (size_t i = 0; i < n; i++) {
        size_t len = strcspn(p, ",");
        const char *start = p, *stop = p + len;
        while (start < stop && isspace((unsigned char)*start))
            start++;
        while (stop > start && isspace((unsigned char)stop[-1]))
            stop--;
        char *element = dup_range(start, (size_t)(stop - start));
        if (!element) {
            snprintf(why, whysz, "out of memory");
            return TSR_ENOMEM;
        }
        char detail[256];
        bool ok = true;
        if (spec->type == TSR_OPT_INT_LIST)
            ok = parse_int(spec, element, &out->ints[i], detail, sizeof detail);
        else if (spec->type == TSR_OPT_FLOAT_LIST)
            ok = parse_float(spec, element, &out->floats[i], detail, sizeof detail);
        if (!ok) {
            snprintf(why, whysz, "element %zu of '%s': %s", i + 1, text, detail);
            free(element);
            return TSR_EINVAL;
        }
        if (spec->type == TSR_OPT_STRING_LIST)
            out->strings[i] = element;
        else
            free(element);
        p += len + (p[len] == ',');
    }
    return TSR_OK;
}

/* Parses `text` for `spec` into `out` (which owns what it allocates, even
 * on failure). On failure `why` holds the detail. */
static int parse_value(const tsr_option_spec *spec, const char *text, option_value *out, char *why, size_t whysz)
{
    out->spec = spec;
    switch (spec->type) {
    case TSR_OPT_BOOL: return parse_bool(text, &out->b, why, whysz) ? TSR_OK : TSR_EINVAL;
    case TSR_OPT_INT: return parse_int(spec, text, &out->i, why, whysz) ? TSR_OK : TSR_EINVAL;
    case TSR_OPT_FLOAT: return parse_float(spec, text, &out->f, why, whysz) ? TSR_OK : TSR_EINVAL;
    case TSR_OPT_ENUM:
    case TSR_OPT_STRING:
        /* An accepted enum is kept as its string, like a string option. */
        if (spec->type == TSR_OPT_ENUM && !parse_enum(spec, text, why, whysz))
            return TSR_EINVAL;
        out->s = strdup(text);
        if (!out->s) {
            snprintf(why, whysz, "out of memory");
            return TSR_ENOMEM;
        }
        return TSR_OK;
    case TSR_OPT_INT_LIST:
    case TSR_OPT_FLOAT_LIST:
    case TSR_OPT_STRING_LIST: return parse_list(spec, text, out, why, whysz);
    }
    snprintf(why, whysz, "option type %d is unknown", (int)spec->type);
    return TSR_EINVAL;
}

/* The text a missing default stands for: the type's zero value, or the
 * first choice of an enum. Parsed like any other default. */
static const char *default_text(const tsr_option_spec *spec, char *buf, size_t size)
{
    if (spec->default_value)
        return spec->default_value;
    switch (spec->type) {
    case TSR_OPT_BOOL: return "false";
    case TSR_OPT_INT:
    case TSR_OPT_FLOAT: return "0";
    case TSR_OPT_ENUM:
        if (spec->choices && enum_choice(spec->choices, 0, buf, size))
            return buf;
        return "";
    default: return "";
    }
}

static int parse_default(const char *spu, const tsr_option_spec *spec, option_value *out, tsr_error *err)
{
    char buf[TSR_SUGGEST_MAX_LEN + 1];
    char why[400];
    int rc = parse_value(spec, default_text(spec, buf, sizeof buf), out, why, sizeof why);
    if (rc != TSR_OK)
        return tsr_error_set(err, rc, "%s: option '%s': bad default: %s", spu, spec->name, why);
    return TSR_OK;
}

int tsr_option_check_value(const char *spu, const tsr_option_spec *spec, const char *text, tsr_error *err)
{
    option_value v = {0};
    char why[400];
    int rc = parse_value(spec, text, &v, why, sizeof why);
    value_free(&v);
    if (rc != TSR_OK)
        return tsr_error_set(err, rc, "%s: option '%s': %s", spu, spec->name, why);
    return TSR_OK;
}

/* ---- declarations ---------------------------------------------------- */

static bool is_option_name(const char *name)
{
    if (!name || !islower((unsigned char)*name))
        return false;
    for (const char *p = name; *p; p++)
        if (!islower((unsigned char)*p) && !isdigit((unsigned char)*p) && *p != '_')
            return false;
    return strlen(name) <= TSR_SUGGEST_MAX_LEN;
}

int tsr_option_specs_check(const char *spu, const tsr_option_spec *specs, size_t count, tsr_error *err)
{
    if (count > 0 && !specs)
        return tsr_error_set(err, TSR_EINVAL, "%s: declares %zu options but no option table", spu, count);
    for (size_t i = 0; i < count; i++) {
        const tsr_option_spec *spec = &specs[i];
        if (!is_option_name(spec->name))
            return tsr_error_set(err, TSR_EINVAL, "%s: option %zu: '%s' is not a lower_snake_case name", spu, i + 1,
                                 spec->name ? spec->name : "(null)");
        for (size_t j = 0; j < i; j++)
            if (!strcmp(specs[j].name, spec->name))
                return tsr_error_set(err, TSR_EINVAL, "%s: option '%s' is declared twice", spu, spec->name);
        if ((unsigned)spec->type > (unsigned)TSR_OPT_STRING_LIST)
            return tsr_error_set(err, TSR_EINVAL, "%s: option '%s': unknown type %d", spu, spec->name, (int)spec->type);
        if (spec->type == TSR_OPT_ENUM) {
            const char *c = spec->choices;
            if (!c || !*c || *c == '|' || c[strlen(c) - 1] == '|' || strstr(c, "||"))
                return tsr_error_set(err, TSR_EINVAL,
                                     "%s: option '%s': enum choices '%s' must be names "
                                     "separated by '|'",
                                     spu, spec->name, c ? c : "(null)");
        }
        option_value v = {0};
        int rc = parse_default(spu, spec, &v, err);
        value_free(&v);
        if (rc != TSR_OK)
            return rc;
    }
    return TSR_OK;
}

const tsr_option_spec *tsr_option_groups_find(const tsr_option_group *groups, size_t ngroups, const char *name)
{
    for (size_t g = 0; g < ngroups; g++)
        for (size_t i = 0; i < groups[g].count; i++)
            if (!strcmp(groups[g].specs[i].name, name))
                return &groups[g].specs[i];
    return NULL;
}

/* ---- a whole option set ---------------------------------------------- */

static int unknown_option(const char *spu, const tsr_option_group *groups, size_t ngroups, const char *key,
                          tsr_error *err)
{
    size_t total = 0;
    for (size_t g = 0; g < ngroups; g++)
        total += groups[g].count;
    if (total == 0)
        return tsr_error_set(err, TSR_EINVAL, "%s: unknown option '%s' (%s has no options)", spu, key, spu);
    const char **names = malloc(total * sizeof *names);
    if (!names)
        return tsr_error_set(err, TSR_ENOMEM, "%s: unknown option '%s'", spu, key);
    size_t n = 0;
    for (size_t g = 0; g < ngroups; g++)
        for (size_t i = 0; i < groups[g].count; i++)
            names[n++] = groups[g].specs[i].name;
    const char *hint = tsr_closest_name(key, names, n);
    if (hint) {
        tsr_error_set(err, TSR_EINVAL, "%s: unknown option '%s' (did you mean '%s'?)", spu, key, hint);
    } else {
        char list[400] = "";
        size_t used = 0;
        for (size_t i = 0; i < n && used < sizeof list; i++) {
            bool seen = false; /* a subclass may re-declare a super's option */
            for (size_t j = 0; j < i; j++)
                seen |= !strcmp(names[j], names[i]);
            if (seen)
                continue;
            int w = snprintf(list + used, sizeof list - used, "%s%s", used ? ", " : "", names[i]);
            if (w < 0)
                break;
            used += (size_t)w;
        }
        tsr_error_set(err, TSR_EINVAL, "%s: unknown option '%s' (options: %s)", spu, key, list);
    }
    free(names);
    return TSR_EINVAL;
}

tsr_options *tsr_options_parse(const char *spu, const tsr_option_group *groups, size_t ngroups, const char *const *keys,
                               const char *const *values, size_t count, tsr_error *err)
{
    /* Check the keys first so a typo is reported before any value. */
    for (size_t k = 0; k < count; k++) {
        if (!keys[k] || !*keys[k]) {
            tsr_error_set(err, TSR_EINVAL, "%s: option %zu has no name", spu, k + 1);
            return NULL;
        }
        if (!tsr_option_groups_find(groups, ngroups, keys[k])) {
            unknown_option(spu, groups, ngroups, keys[k], err);
            return NULL;
        }
        for (size_t j = 0; j < k; j++)
            if (!strcmp(keys[j], keys[k])) {
                tsr_error_set(err, TSR_EINVAL, "%s: option '%s' is given twice", spu, keys[k]);
                return NULL;
            }
    }

    tsr_options *o = calloc(1, sizeof *o);
    size_t total = 0;
    for (size_t g = 0; g < ngroups; g++)
        total += groups[g].count;
    if (!o || !(o->spu = strdup(spu)) || (total && !(o->values = calloc(total, sizeof *o->values)))) {
        tsr_options_free(o);
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory for options", spu);
        return NULL;
    }
    for (size_t g = 0; g < ngroups; g++) {
        for (size_t i = 0; i < groups[g].count; i++) {
            const tsr_option_spec *spec = &groups[g].specs[i];
            if (tsr_option_groups_find(groups, ngroups, spec->name) != spec)
                continue; /* overridden by a nearer declaration */
            option_value *v = &o->values[o->count++];
            const char *given = NULL;
            for (size_t k = 0; k < count; k++)
                if (!strcmp(keys[k], spec->name))
                    given = values[k] ? values[k] : "";
            int rc;
            if (given) {
                char why[400];
                rc = parse_value(spec, given, v, why, sizeof why);
                if (rc != TSR_OK)
                    tsr_error_set(err, rc, "%s: option '%s': %s", spu, spec->name, why);
            } else {
                /* Declarations were checked when the class was registered
                 * or loaded, but a default can still fail to allocate. */
                rc = parse_default(groups[g].owner ? groups[g].owner : spu, spec, v, err);
            }
            if (rc != TSR_OK) {
                tsr_options_free(o);
                return NULL;
            }
        }
    }
    return o;
}

void tsr_options_free(tsr_options *options)
{
    if (!options)
        return;
    for (size_t i = 0; i < options->count; i++)
        value_free(&options->values[i]);
    free(options->values);
    free(options->spu);
    free(options);
}

/* ---- accessors -------------------------------------------------------- */

/* The value of `name` if it has one of the two accepted types; otherwise
 * logs the programming error and returns NULL. */
static const option_value *lookup(const tsr_options *o, const char *name, const char *accessor, tsr_option_type want,
                                  tsr_option_type also)
{
    if (!o || !name) {
        tsr_log(TSR_LOG_ERROR, "%s: called with %s", accessor, o ? "no option name" : "no options");
        return NULL;
    }
    for (size_t i = 0; i < o->count; i++) {
        const option_value *v = &o->values[i];
        if (strcmp(v->spec->name, name))
            continue;
        if (v->spec->type != want && v->spec->type != also) {
            tsr_log(TSR_LOG_ERROR, "%s: %s('%s'): the option is declared as %s", o->spu, accessor, name,
                    tsr_option_type_name(v->spec->type));
            return NULL;
        }
        return v;
    }
    tsr_log(TSR_LOG_ERROR, "%s: %s('%s'): no such option is declared", o->spu, accessor, name);
    return NULL;
}

bool tsr_options_bool(const tsr_options *o, const char *name)
{
    const option_value *v = lookup(o, name, "tsr_options_bool", TSR_OPT_BOOL, TSR_OPT_BOOL);
    return v ? v->b : false;
}

int64_t tsr_options_int(const tsr_options *o, const char *name)
{
    const option_value *v = lookup(o, name, "tsr_options_int", TSR_OPT_INT, TSR_OPT_INT);
    return v ? v->i : 0;
}

double tsr_options_float(const tsr_options *o, const char *name)
{
    const option_value *v = lookup(o, name, "tsr_options_float", TSR_OPT_FLOAT, TSR_OPT_FLOAT);
    return v ? v->f : 0.0;
}

const char *tsr_options_string(const tsr_options *o, const char *name)
{
    const option_value *v = lookup(o, name, "tsr_options_string", TSR_OPT_STRING, TSR_OPT_ENUM);
    return v ? v->s : NULL;
}

size_t tsr_options_count(const tsr_options *o, const char *name)
{
    if (!o || !name) {
        tsr_log(TSR_LOG_ERROR, "tsr_options_count: called with %s", o ? "no option name" : "no options");
        return 0;
    }
    for (size_t i = 0; i < o->count; i++) {
        const option_value *v = &o->values[i];
        if (strcmp(v->spec->name, name))
            continue;
        if (v->spec->type == TSR_OPT_INT_LIST || v->spec->type == TSR_OPT_FLOAT_LIST ||
            v->spec->type == TSR_OPT_STRING_LIST)
            return v->n;
        tsr_log(TSR_LOG_ERROR, "%s: tsr_options_count('%s'): the option is declared as %s, not a list", o->spu, name,
                tsr_option_type_name(v->spec->type));
        return 0;
    }
    tsr_log(TSR_LOG_ERROR, "%s: tsr_options_count('%s'): no such option is declared", o->spu, name);
    return 0;
}

static bool index_ok(const tsr_options *o, const option_value *v, size_t i, const char *accessor)
{
    if (!v)
        return false;
    if (i >= v->n) {
        tsr_log(TSR_LOG_ERROR, "%s: %s('%s', %zu): the list has %zu elements", o->spu, accessor, v->spec->name, i,
                v->n);
        return false;
    }
    return true;
}

int64_t tsr_options_int_at(const tsr_options *o, const char *name, size_t i)
{
    const option_value *v = lookup(o, name, "tsr_options_int_at", TSR_OPT_INT_LIST, TSR_OPT_INT_LIST);
    return index_ok(o, v, i, "tsr_options_int_at") ? v->ints[i] : 0;
}

double tsr_options_float_at(const tsr_options *o, const char *name, size_t i)
{
    const option_value *v = lookup(o, name, "tsr_options_float_at", TSR_OPT_FLOAT_LIST, TSR_OPT_FLOAT_LIST);
    return index_ok(o, v, i, "tsr_options_float_at") ? v->floats[i] : 0.0;
}

const char *tsr_options_string_at(const tsr_options *o, const char *name, size_t i)
{
    const option_value *v = lookup(o, name, "tsr_options_string_at", TSR_OPT_STRING_LIST, TSR_OPT_STRING_LIST);
    return index_ok(o, v, i, "tsr_options_string_at") ? v->strings[i] : NULL;
}
