/* core/spu/chain.c — building and tearing down a chain of SPU instances: text
 * parsing, option validation, super instances, and slot resolution (own
 * slot, else super's, else child's). Owns: the instances, their options and
 * resolved tables. Never: creates an instance with unvalidated options, or
 * leaves a table slot empty. */
#include <ctype.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "chain.h"
#include "options.h"
#include "spu_loader.h"
#include "tessera/dev/native.h"

/* One created instance; a subclass owns its super instance. */
typedef struct tsr_instance {
    const tsr_spu_class *cls;
    void *self;
    tsr_options *options;
    struct tsr_instance *super;
    char name[96];
    tsr_dispatch table; /* resolved: every slot set */
} tsr_instance;

struct tsr_chain {
    tsr_instance **links; /* links[0] is where calls enter */
    size_t count;
    tsr_dispatch end;                   /* no-ops after the last SPU */
    tsr_native_windows *native_windows; /* its SPUs' (tessera/dev/native.h) */
};

/* ---- text form ---------------------------------------------------------- */

typedef struct text_builder {
    tsr_chain_text *out;
    size_t link_cap;
    size_t option_cap; /* of the last link */
} text_builder;

static char *dup_range(const char *s, size_t len)
{
    char *d = malloc(len + 1);
    if (d) {
        memcpy(d, s, len);
        d[len] = '\0';
    }
    return d;
}

void tsr_chain_text_free(tsr_chain_text *parsed)
{
    if (!parsed)
        return;
    for (size_t i = 0; i < parsed->count; i++) {
        tsr_chain_link *l = &parsed->links[i];
        for (size_t k = 0; k < l->option_count; k++) {
            free((char *)l->keys[k]);
            free((char *)l->values[k]);
        }
        free((void *)l->keys);
        free((void *)l->values);
        free((char *)l->spu);
    }
    free(parsed->links);
    parsed->links = NULL;
    parsed->count = 0;
}

static int add_link(text_builder *b, char *spu)
{
    tsr_chain_text *t = b->out;
    if (t->count == b->link_cap) {
        size_t cap = b->link_cap ? 2 * b->link_cap : 4;
        tsr_chain_link *grown = realloc(t->links, cap * sizeof *grown);
        if (!grown)
            return TSR_ENOMEM;
        t->links = grown;
        b->link_cap = cap;
    }
    t->links[t->count++] = (tsr_chain_link){.spu = spu};
    b->option_cap = 0;
    return TSR_OK;
}

static int add_option(text_builder *b, char *key, char *value)
{
    tsr_chain_link *l = &b->out->links[b->out->count - 1];
    if (l->option_count == b->option_cap) {
        size_t cap = b->option_cap ? 2 * b->option_cap : 4;
        const char **keys = realloc((void *)l->keys, cap * sizeof *keys);
        if (keys)
            l->keys = keys;
        const char **values = keys ? realloc((void *)l->values, cap * sizeof *values) : NULL;
        if (!values)
            return TSR_ENOMEM;
        l->values = values;
        b->option_cap = cap;
    }
    ((const char **)l->keys)[l->option_count] = key;
    ((const char **)l->values)[l->option_count] = value;
    l->option_count++;
    return TSR_OK;
}

static bool is_separator(char c) { return c == '\0' || c == '!' || isspace((unsigned char)c); }

/* Reads a quoted value starting at the opening quote *p; "\"" and "\\" are
 * the only escapes. Returns NULL (err filled) when unterminated. */
static char *read_quoted(const char **p, const char *text, const char *token, tsr_error *err)
{
    const char *start = *p;
    const char *s = start + 1;
    size_t len = 0;
    for (const char *q = s; *q != '"'; q++, len++) {
        if (!*q) {
            tsr_error_set(err, TSR_EINVAL, "chain: unterminated quote in '%s' (column %d)", token,
                          (int)(start - text) + 1);
            return NULL;
        }
        if (*q == '\\' && (q[1] == '"' || q[1] == '\\'))
            q++;
    }
    char *value = malloc(len + 1);
    if (!value) {
        tsr_error_set(err, TSR_ENOMEM, "chain: out of memory");
        return NULL;
    }
    size_t n = 0;
    for (; *s != '"'; s++) {
        if (*s == '\\' && (s[1] == '"' || s[1] == '\\'))
            s++;
        value[n++] = *s;
    }
    value[n] = '\0';
    *p = s + 1;
    return value;
}

int tsr_chain_text_parse(const char *text, tsr_chain_text *out, tsr_error *err)
{
    out->links = NULL;
    out->count = 0;
    if (!text)
        return tsr_error_set(err, TSR_EINVAL, "chain: no chain text");
    text_builder b = {.out = out};
    bool expect_spu = true; /* at the start or right after '!' */
    int bang_column = 0;
    const char *p = text;
    int rc = TSR_OK;
    for (;;) {
        while (isspace((unsigned char)*p))
            p++;
        if (!*p)
            break;
        int column = (int)(p - text) + 1;
        if (*p == '!') {
            if (expect_spu) {
                rc = tsr_error_set(err, TSR_EINVAL, "chain: '!' (column %d) has no SPU before it", column);
                goto fail;
            }
            expect_spu = true;
            bang_column = column;
            p++;
            continue;
        }
        /* The token for messages: up to the next blank or '!'. */
        size_t token_len = 0;
        while (!is_separator(p[token_len]))
            token_len++;
        char token[128];
        snprintf(token, sizeof token, "%.*s", (int)(token_len < 100 ? token_len : 100), p);
        if (expect_spu) {
            for (size_t i = 0; i < token_len; i++)
                if (!islower((unsigned char)p[i]) && !isdigit((unsigned char)p[i]) && p[i] != '_') {
                    rc = tsr_error_set(err, TSR_EINVAL, "chain: '%s' (column %d) is not an SPU name ([a-z0-9_]+)",
                                       token, column);
                    goto fail;
                }
            char *spu = dup_range(p, token_len);
            if (!spu || add_link(&b, spu) != TSR_OK) {
                free(spu);
                rc = tsr_error_set(err, TSR_ENOMEM, "chain: out of memory");
                goto fail;
            }
            expect_spu = false;
            p += token_len;
            continue;
        }
        const char *spu = out->links[out->count - 1].spu;
        size_t key_len = strcspn(p, "= \t\r\n\f\v!\"");
        if (p[key_len] != '=') {
            rc = tsr_error_set(err, TSR_EINVAL, "chain: '%s' after '%s' (column %d) is not key=value", token, spu,
                               column);
            goto fail;
        }
        if (key_len == 0) {
            rc = tsr_error_set(err, TSR_EINVAL, "chain: '%s' after '%s' (column %d) has no option name", token, spu,
                               column);
            goto fail;
        }
        const char *v = p + key_len + 1;
        char *value;
        if (*v == '"') {
            value = read_quoted(&v, text, token, err);
            if (!value) {
                rc = err ? err->code : TSR_EINVAL;
                goto fail;
            }
            if (!is_separator(*v)) {
                free(value);
                rc = tsr_error_set(err, TSR_EINVAL,
                                   "chain: '%c' right after the closing quote of option '%.*s' "
                                   "(column %d)",
                                   *v, (int)key_len, p, (int)(v - text) + 1);
                goto fail;
            }
        } else {
            size_t len = 0;
            while (!is_separator(v[len])) {
                if (v[len] == '"') {
                    rc = tsr_error_set(err, TSR_EINVAL,
                                       "chain: quote inside the value of '%s' (column %d): quote "
                                       "the whole value, key=\"...\"",
                                       token, column);
                    goto fail;
                }
                len++;
            }
            value = dup_range(v, len);
            v += len;
        }
        char *key = dup_range(p, key_len);
        if (!value || !key || add_option(&b, key, value) != TSR_OK) {
            free(key);
            free(value);
            rc = tsr_error_set(err, TSR_ENOMEM, "chain: out of memory");
            goto fail;
        }
        p = v;
    }
    if (out->count == 0)
        return tsr_error_set(err, TSR_EINVAL, "chain: empty chain (no SPU named)");
    if (expect_spu) {
        rc = tsr_error_set(err, TSR_EINVAL, "chain: '!' (column %d) is not followed by an SPU", bang_column);
        goto fail;
    }
    return TSR_OK;
fail:
    tsr_chain_text_free(out);
    return rc;
}

/* ---- links to text ------------------------------------------------------- */

/* Appends `n` bytes to the growing text (*out, *len, *cap); false when out
 * of memory. */
static bool text_add(char **out, size_t *len, size_t *cap, const char *s, size_t n)
{
    if (*len + n + 1 > *cap) {
        size_t grown_cap = *cap ? *cap : 128;
        while (grown_cap < *len + n + 1)
            grown_cap *= 2;
        char *grown = realloc(*out, grown_cap);
        if (!grown)
            return false;
        *out = grown;
        *cap = grown_cap;
    }
    memcpy(*out + *len, s, n);
    *len += n;
    (*out)[*len] = '\0';
    return true;
}

char *tsr_chain_links_text(const tsr_chain_link *links, size_t count, tsr_error *err)
{
    char *out = NULL;
    size_t len = 0, cap = 0;
    bool ok = count > 0 && links;
    if (!ok) {
        tsr_error_set(err, TSR_EINVAL, "chain: empty chain (no SPU named)");
        return NULL;
    }
    for (size_t i = 0; i < count && ok; i++) {
        if (i)
            ok = text_add(&out, &len, &cap, " ! ", 3);
        ok = ok && text_add(&out, &len, &cap, links[i].spu, strlen(links[i].spu));
        for (size_t k = 0; k < links[i].option_count && ok; k++) {
            ok = text_add(&out, &len, &cap, " ", 1) &&
                 text_add(&out, &len, &cap, links[i].keys[k], strlen(links[i].keys[k])) &&
                 text_add(&out, &len, &cap, "=\"", 2);
            /* The parser's two escapes (read_quoted). */
            for (const char *v = links[i].values[k]; *v && ok; v++) {
                if (*v == '"' || *v == '\\')
                    ok = text_add(&out, &len, &cap, "\\", 1);
                ok = ok && text_add(&out, &len, &cap, v, 1);
            }
            ok = ok && text_add(&out, &len, &cap, "\"", 1);
        }
    }
    if (!ok) {
        free(out);
        tsr_error_set(err, TSR_ENOMEM, "chain: out of memory for the chain text");
        return NULL;
    }
    return out;
}

/* ---- instances ------------------------------------------------------------ */

static void instance_destroy(tsr_instance *inst)
{
    /* A subclass goes before its super: it may still hold the super's
     * table while it shuts down. */
    while (inst) {
        tsr_instance *super = inst->super;
        if (inst->self)
            inst->cls->destroy(inst->self);
        tsr_options_free(inst->options);
        free(inst);
        inst = super;
    }
}

/* The option groups of lineage[level..]: the level's own declarations
 * first, then its supers'. */
static size_t lineage_groups(const tsr_spu_class *const *lineage, size_t depth, size_t level, tsr_option_group *groups)
{
    size_t n = 0;
    for (size_t j = level; j < depth; j++)
        groups[n++] = (tsr_option_group){lineage[j]->name, lineage[j]->options, lineage[j]->option_count};
    return n;
}

/* Parses the link's options for lineage[level]. The chain's own SPU
 * (level 0) must know every key; a super receives only the keys its own
 * option set declares. */
static tsr_options *parse_level_options(const tsr_spu_class *const *lineage, size_t depth, size_t level,
                                        const tsr_chain_link *link, tsr_error *err)
{
    tsr_option_group groups[TSR_SPU_MAX_SUPER_DEPTH + 1];
    size_t ngroups = lineage_groups(lineage, depth, level, groups);
    if (level == 0)
        return tsr_options_parse(lineage[0]->name, groups, ngroups, link->keys, link->values, link->option_count, err);
    const char **keys = NULL, **values = NULL;
    size_t n = 0;
    if (link->option_count) {
        keys = malloc(link->option_count * sizeof *keys);
        values = malloc(link->option_count * sizeof *values);
        if (!keys || !values) {
            free(keys);
            free(values);
            tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", lineage[level]->name);
            return NULL;
        }
        for (size_t k = 0; k < link->option_count; k++)
            if (tsr_option_groups_find(groups, ngroups, link->keys[k])) {
                keys[n] = link->keys[k];
                values[n++] = link->values[k];
            }
    }
    tsr_options *o = tsr_options_parse(lineage[level]->name, groups, ngroups, keys, values, n, err);
    free(keys);
    free(values);
    return o;
}

/* Creates lineage[level] (and, first, its supers) with `child` after it. */
static tsr_instance *instance_create(const tsr_spu_class *const *lineage, size_t depth, size_t level, const char *name,
                                     const tsr_chain_link *link, const tsr_dispatch *child,
                                     tsr_native_windows *native_windows, tsr_error *err)
{
    const tsr_spu_class *cls = lineage[level];
    tsr_instance *inst = calloc(1, sizeof *inst);
    if (!inst) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", name);
        return NULL;
    }
    inst->cls = cls;
    snprintf(inst->name, sizeof inst->name, "%s", name);
    inst->options = parse_level_options(lineage, depth, level, link, err);
    if (!inst->options)
        goto fail;
    if (level + 1 < depth) {
        char super_name[sizeof inst->name];
        snprintf(super_name, sizeof super_name, "%.60s.%.30s", name, lineage[level + 1]->name);
        inst->super = instance_create(lineage, depth, level + 1, super_name, link, child, native_windows, err);
        if (!inst->super)
            goto fail;
    }
    /* The table starts empty so the slots the SPU leaves alone are known. */
    tsr_spu_init init = {
        .instance_name = inst->name,
        .options = inst->options,
        .child = child,
        .super = inst->super ? &inst->super->table : NULL,
        .table = &inst->table,
        .native_windows = native_windows,
        .super_instance = inst->super ? inst->super->self : NULL,
        .super_api = inst->super ? inst->super->cls->api : NULL,
    };
    tsr_error spu_err;
    tsr_error_clear(&spu_err);
    inst->self = cls->create(&init, &spu_err);
    if (!inst->self) {
        if (spu_err.code == TSR_OK)
            tsr_error_set(err, TSR_EINVAL, "%s: create failed (no reason given)", inst->name);
        else if (err)
            *err = spu_err;
        goto fail;
    }
    const tsr_dispatch *fallback = inst->super ? &inst->super->table : child;
    for (size_t i = 0; i < TSR_DISPATCH_COUNT; i++)
        if (!inst->table.slots[i].fn)
            inst->table.slots[i] = fallback->slots[i];
    return inst;
fail:
    instance_destroy(inst);
    return NULL;
}

/* ---- chains --------------------------------------------------------------- */

typedef struct resolved_link {
    const tsr_spu_class *lineage[TSR_SPU_MAX_SUPER_DEPTH + 1];
    size_t depth;
} resolved_link;

/* Finds every class and checks every option before anything is created,
 * so a mistake in any link costs no create()/destroy() round. */
static int resolve_links(const tsr_chain_link *links, size_t count, resolved_link *out, tsr_error *err)
{
    for (size_t i = 0; i < count; i++) {
        const tsr_chain_link *link = &links[i];
        if (!link->spu)
            return tsr_error_set(err, TSR_EINVAL, "chain: link %zu names no SPU", i + 1);
        if (link->option_count && (!link->keys || !link->values))
            return tsr_error_set(err, TSR_EINVAL, "%s: %zu options but no keys or values", link->spu,
                                 link->option_count);
        const tsr_spu_class *cls = tsr_spu_find(link->spu, err);
        if (!cls)
            return err ? err->code : TSR_ENOENT;
        out[i].depth = tsr_spu_lineage(cls, out[i].lineage, err);
        if (out[i].depth == 0)
            return err ? err->code : TSR_EINVAL;
        for (size_t level = 0; level < out[i].depth; level++) {
            tsr_options *o = parse_level_options(out[i].lineage, out[i].depth, level, link, err);
            if (!o)
                return err ? err->code : TSR_EINVAL;
            tsr_options_free(o);
        }
    }
    return TSR_OK;
}

tsr_chain *tsr_chain_create_links(const tsr_chain_link *links, size_t count, tsr_error *err)
{
    if (count == 0 || !links) {
        tsr_error_set(err, TSR_EINVAL, "chain: empty chain (no SPU named)");
        return NULL;
    }
    resolved_link *resolved = calloc(count, sizeof *resolved);
    tsr_chain *chain = calloc(1, sizeof *chain);
    if (chain) {
        chain->links = calloc(count, sizeof *chain->links);
        chain->native_windows = tsr_native_windows_create();
    }
    if (!resolved || !chain || !chain->links || !chain->native_windows) {
        tsr_error_set(err, TSR_ENOMEM, "chain: out of memory");
        goto fail;
    }
    chain->count = count;
    tsr_dispatch_fill_nop(&chain->end);
    if (resolve_links(links, count, resolved, err) != TSR_OK)
        goto fail;
    /* Last to first: each SPU is created knowing its child's final table. */
    for (size_t i = count; i-- > 0;) {
        unsigned same_before = 1;
        for (size_t j = 0; j < i; j++)
            same_before += !strcmp(links[j].spu, links[i].spu);
        char name[64];
        snprintf(name, sizeof name, "%.40s#%u", links[i].spu, same_before);
        const tsr_dispatch *child = i + 1 < count ? &chain->links[i + 1]->table : &chain->end;
        chain->links[i] = instance_create(resolved[i].lineage, resolved[i].depth, 0, name, &links[i], child,
                                          chain->native_windows, err);
        if (!chain->links[i])
            goto fail;
    }
    free(resolved);
    return chain;
fail:
    free(resolved);
    tsr_chain_destroy(chain);
    return NULL;
}

tsr_chain *tsr_chain_create(const char *text, tsr_error *err)
{
    tsr_chain_text parsed;
    if (tsr_chain_text_parse(text, &parsed, err) != TSR_OK)
        return NULL;
    tsr_chain *chain = tsr_chain_create_links(parsed.links, parsed.count, err);
    tsr_chain_text_free(&parsed);
    return chain;
}

const tsr_dispatch *tsr_chain_head(const tsr_chain *chain)
{
    if (!chain || chain->count == 0 || !chain->links[0])
        return NULL;
    return &chain->links[0]->table;
}

void tsr_chain_destroy(tsr_chain *chain)
{
    if (!chain)
        return;
    /* First to last: calls flow downstream, so nothing still alive can call
     * into an instance that is already gone. */
    for (size_t i = 0; i < chain->count; i++)
        if (chain->links && chain->links[i])
            instance_destroy(chain->links[i]);
    free(chain->links);
    tsr_native_windows_destroy(chain->native_windows);
    free(chain);
}

tsr_native_windows *tsr_chain_native_windows(const tsr_chain *chain) { return chain ? chain->native_windows : NULL; }
