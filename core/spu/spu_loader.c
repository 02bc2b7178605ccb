/* core/spu/spu_loader.c — finding SPU classes: registered in-process classes
 * first, then <name>_spu.so plugins on the search path (TESSERA_SPU_PATH,
 * build tree, install prefix), loaded once and cached for the process.
 * Owns: the registry and the plugin cache (immutable classes, guarded by one
 * mutex). Never: keeps SPU instance state, or unloads a class in use. */
#include <ctype.h>
#include <dirent.h>
#include <dlfcn.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "options.h"
#include "spu_loader.h"
#include "tessera/log.h"

#ifndef TESSERA_BUILD_SPU_DIR
#define TESSERA_BUILD_SPU_DIR ""
#endif
#ifndef TESSERA_INSTALL_SPU_DIR
#define TESSERA_INSTALL_SPU_DIR ""
#endif

#define SPU_FILE_SUFFIX "_spu.so"
#define MAX_SPU_NAME 64

typedef struct loaded_class {
    const tsr_spu_class *cls;
    void *handle; /* kept open for the life of the process: chains may use it */
} loaded_class;

/* Process-wide because classes are immutable descriptions shared by every
 * chain; instances never live here. Every access holds loader_lock. */
static pthread_mutex_t loader_lock = PTHREAD_MUTEX_INITIALIZER;
static const tsr_spu_class **registered;
static size_t registered_count, registered_cap;
static loaded_class *loaded;
static size_t loaded_count, loaded_cap;

static bool is_spu_name(const char *name)
{
    if (!name || !*name || strlen(name) > MAX_SPU_NAME)
        return false;
    for (const char *p = name; *p; p++)
        if (!islower((unsigned char)*p) && !isdigit((unsigned char)*p) && *p != '_')
            return false;
    return true;
}

/* ---- search path ------------------------------------------------------ */

/* Appends `dir` to the ':'-joined `path` unless empty or already there. */
static void path_append(char *path, size_t size, const char *dir, size_t len)
{
    if (len == 0)
        return;
    for (const char *p = path; *p;) {
        size_t n = strcspn(p, ":");
        if (n == len && !strncmp(p, dir, len))
            return;
        p += n + (p[n] == ':');
    }
    size_t used = strlen(path);
    if (used + (used > 0) + len + 1 > size)
        return; /* a search path this long is unusable anyway */
    if (used)
        path[used++] = ':';
    memcpy(path + used, dir, len);
    path[used + len] = '\0';
}

const char *tsr_spu_search_path(char *buf, size_t size)
{
    if (!buf || size == 0)
        return NULL;
    buf[0] = '\0';
    const char *env = getenv("TESSERA_SPU_PATH");
    for (const char *p = env ? env : ""; *p;) {
        size_t n = strcspn(p, ":");
        path_append(buf, size, p, n);
        p += n + (p[n] == ':');
    }
    path_append(buf, size, TESSERA_BUILD_SPU_DIR, strlen(TESSERA_BUILD_SPU_DIR));
    path_append(buf, size, TESSERA_INSTALL_SPU_DIR, strlen(TESSERA_INSTALL_SPU_DIR));
    return buf;
}

/* Calls visit(dir) for each directory of the search path in order; stops
 * early when visit returns false. */
static void each_search_dir(bool (*visit)(const char *dir, void *ctx), void *ctx)
{
    char path[8192];
    tsr_spu_search_path(path, sizeof path);
    for (char *p = path; *p;) {
        size_t n = strcspn(p, ":");
        char saved = p[n];
        p[n] = '\0';
        bool go_on = visit(p, ctx);
        p[n] = saved;
        if (!go_on)
            return;
        p += n + (saved == ':');
    }
}

/* ---- roles ---------------------------------------------------------------- */

static const struct {
    const char *name, *summary;
} roles[] = {
    [TSR_SPU_ROLE_NONE] = {"none", "sends to no node: its node has no to:"},
    [TSR_SPU_ROLE_SERVER] = {"server", "streams to the one server its node's to: names"},
    [TSR_SPU_ROLE_SERVERS] = {"servers", "streams to every server its node's to: names"},
    [TSR_SPU_ROLE_TILED_SERVERS] = {"tiled servers", "sorts its stream among the servers its node's to: names, "
                                                     "each of which has tiles: or a cell of its grid"},
    [TSR_SPU_ROLE_DISPLAY] = {"display", "sends its node's tile images to the one display node "
                                         "its to: names"},
    [TSR_SPU_ROLE_PEERS] = {"peers", "one of the peers that send to the one display node their "
                                     "to: names; knows every peer's address and its rank"},
};
#define ROLE_COUNT (sizeof roles / sizeof roles[0])

const char *tsr_spu_role_name(tsr_spu_role role) { return (unsigned)role < ROLE_COUNT ? roles[role].name : "unknown"; }

const char *tsr_spu_role_summary(tsr_spu_role role)
{
    return (unsigned)role < ROLE_COUNT ? roles[role].summary : "unknown role";
}

/* One option a graph run fills: declared by the class, of an allowed type. */
static int check_filled_option(const tsr_spu_class *cls, const char *what, const char *option, tsr_option_type type,
                               tsr_option_type other, tsr_error *err)
{
    if (!option)
        return TSR_OK;
    for (size_t i = 0; i < cls->option_count; i++) {
        const tsr_option_spec *spec = &cls->options[i];
        if (strcmp(spec->name, option))
            continue;
        if (spec->type == type || spec->type == other)
            return TSR_OK;
        return tsr_error_set(err, TSR_EINVAL, "%s: network.%s names option '%s', which is not %s option", cls->name,
                             what, option,
                             type == TSR_OPT_INT           ? "an int"
                             : type == TSR_OPT_INT_LIST    ? "an int list"
                             : type == TSR_OPT_STRING_LIST ? "a string list"
                                                           : "a string");
    }
    return tsr_error_set(err, TSR_EINVAL, "%s: network.%s names option '%s', which it does not declare", cls->name,
                         what, option);
}

/* The role and the options a graph run fills (tessera/spu.h). */
static int check_network(const tsr_spu_class *cls, tsr_error *err)
{
    const tsr_spu_network *n = &cls->network;
    if ((unsigned)n->role >= ROLE_COUNT)
        return tsr_error_set(err, TSR_EINVAL, "%s: unknown network role %d", cls->name, (int)n->role);
    const struct {
        const char *what, *option;
        tsr_option_type type, other;
    } filled[] = {
        {"server", n->server, TSR_OPT_STRING, TSR_OPT_STRING},
        {"servers", n->servers, TSR_OPT_STRING_LIST, TSR_OPT_STRING_LIST},
        {"display", n->display, TSR_OPT_STRING, TSR_OPT_STRING},
        {"token", n->token, TSR_OPT_STRING, TSR_OPT_STRING},
        {"tiles", n->tiles, TSR_OPT_STRING, TSR_OPT_STRING_LIST},
        {"server_tiles", n->server_tiles, TSR_OPT_STRING, TSR_OPT_STRING_LIST},
        {"rank", n->rank, TSR_OPT_INT, TSR_OPT_INT},
        {"peers", n->peers, TSR_OPT_STRING_LIST, TSR_OPT_STRING_LIST},
    };
    for (size_t i = 0; i < sizeof filled / sizeof filled[0]; i++) {
        int rc = check_filled_option(cls, filled[i].what, filled[i].option, filled[i].type, filled[i].other, err);
        if (rc != TSR_OK)
            return rc;
        for (size_t j = 0; j < i; j++)
            if (filled[i].option && filled[j].option && !strcmp(filled[i].option, filled[j].option))
                return tsr_error_set(err, TSR_EINVAL, "%s: network.%s and network.%s both name option '%s'", cls->name,
                                     filled[j].what, filled[i].what, filled[i].option);
    }
    /* Read by the graph check, not filled: the grid the servers form. */
    int grc = check_filled_option(cls, "grid", n->grid, TSR_OPT_INT_LIST, TSR_OPT_INT_LIST, err);
    if (grc != TSR_OK)
        return grc;
    if (n->grid && n->role != TSR_SPU_ROLE_TILED_SERVERS)
        return tsr_error_set(err, TSR_EINVAL, "%s: network.grid places tiled servers: only role %s has it", cls->name,
                             tsr_spu_role_name(TSR_SPU_ROLE_TILED_SERVERS));
    /* What each role needs filled to reach its nodes. */
    const char *missing = NULL;
    switch (n->role) {
    case TSR_SPU_ROLE_NONE:
        if (n->server || n->servers || n->display || n->token || n->server_tiles || n->rank || n->peers)
            return tsr_error_set(err, TSR_EINVAL,
                                 "%s: network role none sends to no node, so it names no address, "
                                 "token, server tiles, rank or peers option (only tiles)",
                                 cls->name);
        break;
    case TSR_SPU_ROLE_SERVER: missing = !n->server ? "server" : NULL; break;
    case TSR_SPU_ROLE_SERVERS: missing = !n->servers ? "servers" : NULL; break;
    case TSR_SPU_ROLE_TILED_SERVERS:
        missing = !n->servers ? "servers" : !n->server_tiles ? "server_tiles" : NULL;
        break;
    case TSR_SPU_ROLE_DISPLAY: missing = !n->display ? "display" : NULL; break;
    case TSR_SPU_ROLE_PEERS: missing = !n->display ? "display" : !n->peers ? "peers" : !n->rank ? "rank" : NULL; break;
    }
    if (missing)
        return tsr_error_set(err, TSR_EINVAL, "%s: network role %s needs network.%s (the option a graph run fills)",
                             cls->name, tsr_spu_role_name(n->role), missing);
    return TSR_OK;
}

/* ---- checks --------------------------------------------------------------- */

int tsr_spu_class_check(const tsr_spu_class *cls, const char *origin, tsr_error *err)
{
    if (cls->abi != TSR_SPU_ABI)
        return tsr_error_set(err, TSR_EINVAL,
                             "%s: built for SPU ABI %u, this tessera has ABI %u (rebuild the SPU "
                             "against the installed headers)",
                             origin, (unsigned)cls->abi, (unsigned)TSR_SPU_ABI);
    if (cls->dispatch_count != 0 && cls->dispatch_count != TSR_DISPATCH_COUNT)
        return tsr_error_set(err, TSR_EINVAL,
                             "%s: built for a dispatch table of %u commands, this tessera has %u "
                             "(rebuild the SPU against the installed headers)",
                             origin, (unsigned)cls->dispatch_count, (unsigned)TSR_DISPATCH_COUNT);
    if (!is_spu_name(cls->name))
        return tsr_error_set(err, TSR_EINVAL, "%s: SPU name '%s' is not [a-z0-9_]+", origin,
                             cls->name ? cls->name : "(null)");
    if (cls->super && !is_spu_name(cls->super))
        return tsr_error_set(err, TSR_EINVAL, "%s: super SPU name '%s' is not [a-z0-9_]+", cls->name, cls->super);
    if (cls->super && !strcmp(cls->super, cls->name))
        return tsr_error_set(err, TSR_EINVAL, "%s: an SPU cannot be its own super", cls->name);
    if (!cls->create || !cls->destroy)
        return tsr_error_set(err, TSR_EINVAL, "%s: class has no %s function", cls->name,
                             cls->create ? "destroy" : "create");
    int rc = tsr_option_specs_check(cls->name, cls->options, cls->option_count, err);
    return rc == TSR_OK ? check_network(cls, err) : rc;
}

/* ---- the caches (loader_lock held) ------------------------------------ */

static const tsr_spu_class *cached_locked(const char *name)
{
    for (size_t i = 0; i < registered_count; i++)
        if (!strcmp(registered[i]->name, name))
            return registered[i];
    for (size_t i = 0; i < loaded_count; i++)
        if (!strcmp(loaded[i].cls->name, name))
            return loaded[i].cls;
    return NULL;
}

static const tsr_spu_class *load_file_locked(const char *path, const char *name, tsr_error *err)
{
    void *handle = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char *why = dlerror();
        tsr_error_set(err, TSR_EIO, "%s: cannot load %s: %s", name, path, why ? why : "unknown dlopen error");
        return NULL;
    }
    const tsr_spu_class *cls = NULL;
    tsr_spu_describe_fn describe;
    /* POSIX sanctions converting dlsym's object pointer to a function
     * pointer; go through memcpy so -Wpedantic builds stay quiet too. */
    void *sym = dlsym(handle, TSR_SPU_ENTRY_NAME);
    if (!sym) {
        tsr_error_set(err, TSR_EINVAL,
                      "%s: %s has no " TSR_SPU_ENTRY_NAME "() entry point (not an SPU built "
                      "against tessera/spu.h?)",
                      name, path);
        goto fail;
    }
    memcpy(&describe, &sym, sizeof describe);
    cls = describe();
    if (!cls) {
        tsr_error_set(err, TSR_EINVAL, "%s: " TSR_SPU_ENTRY_NAME "() in %s returned no class", name, path);
        goto fail;
    }
    char origin[4096 + MAX_SPU_NAME + 2];
    snprintf(origin, sizeof origin, "%s: %s", name, path);
    if (tsr_spu_class_check(cls, origin, err) != TSR_OK)
        goto fail;
    if (strcmp(cls->name, name)) {
        tsr_error_set(err, TSR_EINVAL, "%s: %s describes an SPU named '%s'", name, path, cls->name);
        goto fail;
    }
    if (loaded_count == loaded_cap) {
        size_t cap = loaded_cap ? 2 * loaded_cap : 16;
        loaded_class *grown = realloc(loaded, cap * sizeof *grown);
        if (!grown) {
            tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", name);
            goto fail;
        }
        loaded = grown;
        loaded_cap = cap;
    }
    loaded[loaded_count++] = (loaded_class){cls, handle};
    tsr_log(TSR_LOG_DEBUG, "loaded SPU '%s' from %s", name, path);
    return cls;
fail:
    dlclose(handle);
    return NULL;
}

/* Names of SPU files in a directory, for listing and suggestions. */
static void each_spu_file(const char *dir, void (*visit)(const char *name, const char *path, void *ctx), void *ctx)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir(d))) {
        size_t len = strlen(e->d_name), suffix = strlen(SPU_FILE_SUFFIX);
        if (len <= suffix || len - suffix > MAX_SPU_NAME || strcmp(e->d_name + len - suffix, SPU_FILE_SUFFIX))
            continue;
        char name[MAX_SPU_NAME + 1];
        memcpy(name, e->d_name, len - suffix);
        name[len - suffix] = '\0';
        if (!is_spu_name(name))
            continue;
        char path[4096];
        if (snprintf(path, sizeof path, "%s/%s", dir, e->d_name) >= (int)sizeof path)
            continue;
        visit(name, path, ctx);
    }
    closedir(d);
}

/* ---- finding one class ------------------------------------------------ */

typedef struct find_ctx {
    const char *name;
    const tsr_spu_class *found;
    bool failed; /* a file was there but could not be used */
    tsr_error *err;
} find_ctx;

static bool find_in_dir(const char *dir, void *arg)
{
    find_ctx *f = arg;
    char path[4096];
    if (snprintf(path, sizeof path, "%s/%s" SPU_FILE_SUFFIX, dir, f->name) >= (int)sizeof path)
        return true;
    if (access(path, F_OK) != 0)
        return true;
    /* The first file on the path is the one meant; a broken one is an
     * error, never silently replaced by a later directory's copy. */
    f->found = load_file_locked(path, f->name, f->err);
    f->failed = !f->found;
    return false;
}

typedef struct suggest_ctx {
    const char *word;
    char best[MAX_SPU_NAME + 1];
    size_t best_distance;
} suggest_ctx;

static void consider_name(const char *name, suggest_ctx *s)
{
    const char *candidate[1] = {name};
    if (tsr_closest_name(s->word, candidate, 1)) {
        size_t d = tsr_edit_distance(s->word, name);
        if (d < s->best_distance) {
            s->best_distance = d;
            snprintf(s->best, sizeof s->best, "%s", name);
        }
    }
}

static void suggest_file(const char *name, const char *path, void *arg)
{
    (void)path;
    consider_name(name, arg);
}

static bool suggest_in_dir(const char *dir, void *arg)
{
    each_spu_file(dir, suggest_file, arg);
    return true;
}

static const tsr_spu_class *find_locked(const char *name, tsr_error *err)
{
    const tsr_spu_class *cls = cached_locked(name);
    if (cls)
        return cls;
    find_ctx f = {.name = name, .err = err};
    each_search_dir(find_in_dir, &f);
    if (f.found || f.failed)
        return f.found;

    suggest_ctx s = {.word = name, .best_distance = (size_t)-1};
    for (size_t i = 0; i < registered_count; i++)
        consider_name(registered[i]->name, &s);
    each_search_dir(suggest_in_dir, &s);
    char path[8192];
    tsr_spu_search_path(path, sizeof path);
    char hint[MAX_SPU_NAME + 32] = "";
    if (s.best[0])
        snprintf(hint, sizeof hint, " (did you mean '%s'?)", s.best);
    tsr_error_set(err, TSR_ENOENT, "unknown SPU '%s'%s: no %s" SPU_FILE_SUFFIX " in %s", name, hint, name,
                  path[0] ? path : "(empty search path)");
    return NULL;
}

const tsr_spu_class *tsr_spu_find(const char *name, tsr_error *err)
{
    if (!is_spu_name(name)) {
        tsr_error_set(err, TSR_EINVAL, "'%s' is not an SPU name ([a-z0-9_]+)", name ? name : "(null)");
        return NULL;
    }
    pthread_mutex_lock(&loader_lock);
    const tsr_spu_class *cls = find_locked(name, err);
    pthread_mutex_unlock(&loader_lock);
    return cls;
}

int tsr_spu_register(const tsr_spu_class *cls, tsr_error *err)
{
    if (!cls)
        return tsr_error_set(err, TSR_EINVAL, "tsr_spu_register: no class");
    int rc = tsr_spu_class_check(cls, cls->name && is_spu_name(cls->name) ? cls->name : "registered SPU", err);
    if (rc != TSR_OK)
        return rc;
    pthread_mutex_lock(&loader_lock);
    for (size_t i = 0; i < registered_count; i++) {
        if (strcmp(registered[i]->name, cls->name))
            continue;
        rc = registered[i] == cls ? TSR_OK
                                  : tsr_error_set(err, TSR_EINVAL,
                                                  "%s: another SPU class of this name is "
                                                  "already registered",
                                                  cls->name);
        goto out;
    }
    if (registered_count == registered_cap) {
        size_t cap = registered_cap ? 2 * registered_cap : 16;
        const tsr_spu_class **grown = realloc(registered, cap * sizeof *grown);
        if (!grown) {
            rc = tsr_error_set(err, TSR_ENOMEM, "%s: out of memory registering", cls->name);
            goto out;
        }
        registered = grown;
        registered_cap = cap;
    }
    registered[registered_count++] = cls;
out:
    pthread_mutex_unlock(&loader_lock);
    return rc;
}

/* ---- listing ---------------------------------------------------------- */

typedef struct list_ctx {
    const tsr_spu_class **items;
    size_t count, cap;
} list_ctx;

static bool list_has(const list_ctx *l, const char *name)
{
    for (size_t i = 0; i < l->count; i++)
        if (!strcmp(l->items[i]->name, name))
            return true;
    return false;
}

static void list_add(list_ctx *l, const tsr_spu_class *cls)
{
    if (l->count == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : 32;
        const tsr_spu_class **grown = realloc(l->items, cap * sizeof *grown);
        if (!grown)
            return;
        l->items = grown;
        l->cap = cap;
    }
    l->items[l->count++] = cls;
}

static void list_file(const char *name, const char *path, void *arg)
{
    list_ctx *l = arg;
    if (list_has(l, name))
        return; /* an earlier directory (or the registry) has it */
    const tsr_spu_class *cls = cached_locked(name);
    if (!cls) {
        tsr_error err;
        tsr_error_clear(&err);
        cls = load_file_locked(path, name, &err);
        if (!cls) {
            tsr_log(TSR_LOG_WARN, "skipping %s: %s", path, err.message);
            return;
        }
    }
    list_add(l, cls);
}

static bool list_dir(const char *dir, void *arg)
{
    each_spu_file(dir, list_file, arg);
    return true;
}

static int by_name(const void *a, const void *b)
{
    const tsr_spu_class *const *x = a, *const *y = b;
    return strcmp((*x)->name, (*y)->name);
}

size_t tsr_spu_list(const tsr_spu_class **out, size_t max)
{
    list_ctx l = {0};
    pthread_mutex_lock(&loader_lock);
    for (size_t i = 0; i < registered_count; i++)
        list_add(&l, registered[i]);
    each_search_dir(list_dir, &l);
    pthread_mutex_unlock(&loader_lock);
    if (l.count > 1)
        qsort(l.items, l.count, sizeof *l.items, by_name);
    for (size_t i = 0; i < l.count && i < max && out; i++)
        out[i] = l.items[i];
    size_t count = l.count;
    free(l.items);
    return count;
}

/* ---- lineage ------------------------------------------------------------ */

size_t tsr_spu_lineage(const tsr_spu_class *cls, const tsr_spu_class *out[TSR_SPU_MAX_SUPER_DEPTH + 1], tsr_error *err)
{
    size_t n = 0;
    out[n++] = cls;
    while (out[n - 1]->super) {
        const tsr_spu_class *last = out[n - 1];
        char trail[512] = "";
        size_t used = 0;
        for (size_t i = 0; i < n && used < sizeof trail; i++) {
            int w = snprintf(trail + used, sizeof trail - used, "%s -> ", out[i]->name);
            if (w < 0)
                break;
            used += (size_t)w;
        }
        for (size_t i = 0; i < n; i++)
            if (!strcmp(out[i]->name, last->super)) {
                tsr_error_set(err, TSR_EINVAL, "%s: super SPUs form a cycle: %s%s", cls->name, trail, last->super);
                return 0;
            }
        if (n == TSR_SPU_MAX_SUPER_DEPTH + 1) {
            tsr_error_set(err, TSR_EINVAL, "%s: more than %d levels of super SPUs: %s%s ...", cls->name,
                          TSR_SPU_MAX_SUPER_DEPTH, trail, last->super);
            return 0;
        }
        tsr_error inner;
        tsr_error_clear(&inner);
        const tsr_spu_class *super = tsr_spu_find(last->super, &inner);
        if (!super) {
            tsr_error_set(err, inner.code, "%s: super SPU '%s' of '%s': %s", cls->name, last->super, last->name,
                          inner.message);
            return 0;
        }
        out[n++] = super;
    }
    return n;
}

/* ---- checking a link's options without building it ---------------------- */

/* The option groups of `cls` and its supers, as the chain parses them. */
static size_t option_groups(const tsr_spu_class *cls, tsr_option_group groups[TSR_SPU_MAX_SUPER_DEPTH + 1],
                            tsr_error *err)
{
    const tsr_spu_class *lineage[TSR_SPU_MAX_SUPER_DEPTH + 1];
    size_t depth = tsr_spu_lineage(cls, lineage, err);
    for (size_t i = 0; i < depth; i++)
        groups[i] = (tsr_option_group){lineage[i]->name, lineage[i]->options, lineage[i]->option_count};
    return depth;
}

const tsr_option_spec *tsr_spu_find_option(const tsr_spu_class *cls, const char *key, tsr_error *err)
{
    tsr_option_group groups[TSR_SPU_MAX_SUPER_DEPTH + 1];
    size_t depth = option_groups(cls, groups, err);
    if (!depth)
        return NULL;
    const tsr_option_spec *spec = tsr_option_groups_find(groups, depth, key);
    if (!spec) {
        /* The parser words the unknown-option message (did you mean). */
        const char *value = "";
        tsr_options_free(tsr_options_parse(cls->name, groups, depth, &key, &value, 1, err));
        if (!err->code)
            tsr_error_set(err, TSR_EINVAL, "%s: unknown option '%s'", cls->name, key);
    }
    return spec;
}

int tsr_spu_check_options(const tsr_spu_class *cls, const char *const *keys, const char *const *values, size_t count,
                          tsr_error *err)
{
    tsr_option_group groups[TSR_SPU_MAX_SUPER_DEPTH + 1];
    size_t depth = option_groups(cls, groups, err);
    if (!depth)
        return err->code ? err->code : TSR_EINVAL;
    tsr_options *all = tsr_options_parse(cls->name, groups, depth, keys, values, count, err);
    if (!all)
        return err->code ? err->code : TSR_EINVAL;
    tsr_options_free(all);
    return TSR_OK;
}
