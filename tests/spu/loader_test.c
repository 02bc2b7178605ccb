/* tests/spu/loader_test.c — finding SPU classes: real plugin files in the
 * build tree and on TESSERA_SPU_PATH, broken plugins, the registry, the
 * sorted list, and concurrent lookups. Arguments after the test name:
 * BUILD_SPU_DIR ENV_DIR BAD_DIR. Owns nothing. Never: fakes a plugin file. */
#include <pthread.h>
#include <stdlib.h>

#include "spu_test.h"
#include "tessera/spu.h"

static const char *build_spu_dir(void) { return spu_test_argv[0]; }
static const char *env_dir(void) { return spu_test_argv[1]; }
static const char *bad_dir(void) { return spu_test_argv[2]; }

static void *noop_create(const tsr_spu_init *init, tsr_error *err)
{
    (void)init;
    (void)err;
    return malloc(1);
}
static void noop_destroy(void *self) { free(self); }

static void test_finds_build_tree_plugin(void)
{
    unsetenv("TESSERA_SPU_PATH");
    char path[4096];
    CHECK_CONTAINS(tsr_spu_search_path(path, sizeof path), build_spu_dir());
    tsr_error err;
    tsr_error_clear(&err);
    const tsr_spu_class *cls = tsr_spu_find("passthrough", &err);
    if (!cls)
        fprintf(stderr, "error: %s\n", err.message);
    REQUIRE(cls);
    CHECK_STR(cls->name, "passthrough");
    CHECK_STR(cls->summary, "passes every call to the next SPU unchanged");
    CHECK(cls->abi == TSR_SPU_ABI);
    /* Cached: the same class on the next lookup. */
    CHECK(tsr_spu_find("passthrough", &err) == cls);
}

static void test_env_path_first(void)
{
    setenv("TESSERA_SPU_PATH", env_dir(), 1);
    char path[4096];
    tsr_spu_search_path(path, sizeof path);
    CHECK(strncmp(path, env_dir(), strlen(env_dir())) == 0);
    tsr_error err;
    const tsr_spu_class *cls = tsr_spu_find("passthrough", &err);
    REQUIRE(cls);
    CHECK_STR(cls->summary, "test copy found first on TESSERA_SPU_PATH");
    /* The listing agrees: one passthrough, the one first on the path. */
    const tsr_spu_class *all[256];
    size_t n = tsr_spu_list(all, 256);
    size_t seen = 0;
    for (size_t i = 0; i < n && i < 256; i++)
        if (!strcmp(all[i]->name, "passthrough")) {
            seen++;
            CHECK(all[i] == cls);
        }
    CHECK(seen == 1);
}

static void test_missing_spu_names_search_path(void)
{
    char env[4096];
    snprintf(env, sizeof env, "/nonexistent/tessera-spus:%s", env_dir());
    setenv("TESSERA_SPU_PATH", env, 1);
    char path[4096];
    tsr_spu_search_path(path, sizeof path);
    CHECK_CONTAINS(path, "/nonexistent/tessera-spus:");
    CHECK_CONTAINS(path, build_spu_dir());
    tsr_error err;
    CHECK(tsr_spu_find("zzqqxx", &err) == NULL);
    CHECK(err.code == TSR_ENOENT);
    char expected[8192];
    snprintf(expected, sizeof expected, "unknown SPU 'zzqqxx': no zzqqxx_spu.so in %s", path);
    CHECK_STR(err.message, expected);
    /* A near miss gets a suggestion. */
    CHECK(tsr_spu_find("pasthrough", &err) == NULL);
    CHECK_CONTAINS(err.message, "unknown SPU 'pasthrough' (did you mean 'passthrough'?)");
}

static void expect_bad_plugin(const char *name, const char *fmt)
{
    setenv("TESSERA_SPU_PATH", bad_dir(), 1);
    char file[4096], expected[8192];
    snprintf(file, sizeof file, "%s/%s_spu.so", bad_dir(), name);
    snprintf(expected, sizeof expected, fmt, file);
    tsr_error err;
    tsr_error_clear(&err);
    CHECK(tsr_spu_find(name, &err) == NULL);
    CHECK(err.code == TSR_EINVAL);
    CHECK_STR(err.message, expected);
}

static void test_rejects_file_without_entry_point(void)
{
    expect_bad_plugin("noentry", "noentry: %s has no tsr_spu_describe() entry point (not an SPU "
                                 "built against tessera/spu.h?)");
}

static void test_rejects_abi_mismatch(void)
{
    char fmt[256];
    snprintf(fmt, sizeof fmt,
             "oldabi: %%s: built for SPU ABI %u, this tessera has ABI %u (rebuild the SPU against the "
             "installed headers)",
             TSR_SPU_ABI + 1000, TSR_SPU_ABI);
    expect_bad_plugin("oldabi", fmt);
}

/* A plugin built against older headers (ABI 1, before roles; an ABI 2 one,
 * before tsr_spu_network.grid, is refused by the same comparison): one line
 * naming the plugin and both versions, nothing past `abi` read. */
static void test_rejects_previous_abi(void)
{
    char fmt[256];
    snprintf(fmt, sizeof fmt,
             "prevabi: %%s: built for SPU ABI 1, this tessera has ABI %u (rebuild the SPU against "
             "the installed headers)",
             TSR_SPU_ABI);
    CHECK(TSR_SPU_ABI == 5);
    expect_bad_plugin("prevabi", fmt);
}

static void test_rejects_name_mismatch(void)
{
    expect_bad_plugin("misnamed", "misnamed: %s describes an SPU named 'othername'");
}

static void test_rejects_bad_names(void)
{
    tsr_error err;
    CHECK(tsr_spu_find("../etc/passwd", &err) == NULL);
    CHECK_STR(err.message, "'../etc/passwd' is not an SPU name ([a-z0-9_]+)");
    CHECK(tsr_spu_find("", &err) == NULL);
    CHECK_STR(err.message, "'' is not an SPU name ([a-z0-9_]+)");
}

static void test_registered_class_wins(void)
{
    unsetenv("TESSERA_SPU_PATH");
    static const tsr_spu_class mine = {.abi = TSR_SPU_ABI,
                                       .name = "passthrough",
                                       .summary = "registered in-process",
                                       .create = noop_create,
                                       .destroy = noop_destroy};
    tsr_error err;
    CHECK(tsr_spu_register(&mine, &err) == TSR_OK);
    CHECK(tsr_spu_register(&mine, &err) == TSR_OK); /* again: harmless */
    CHECK(tsr_spu_find("passthrough", &err) == &mine);
    static const tsr_spu_class other = {
        .abi = TSR_SPU_ABI, .name = "passthrough", .create = noop_create, .destroy = noop_destroy};
    CHECK(tsr_spu_register(&other, &err) == TSR_EINVAL);
    CHECK_STR(err.message, "passthrough: another SPU class of this name is already registered");
}

static void test_register_rejects_bad_class(void)
{
    static const tsr_option_spec bad_default[] = {
        {.name = "width", .type = TSR_OPT_INT, .default_value = "wide", .min = 1, .max = 10}};
    static const tsr_spu_class bad = {.abi = TSR_SPU_ABI,
                                      .name = "badspu",
                                      .options = bad_default,
                                      .option_count = 1,
                                      .create = noop_create,
                                      .destroy = noop_destroy};
    tsr_error err;
    CHECK(tsr_spu_register(&bad, &err) == TSR_EINVAL);
    CHECK_STR(err.message, "badspu: option 'width': bad default: 'wide' is not an integer");
    static const tsr_spu_class no_create = {.abi = TSR_SPU_ABI, .name = "nocreate", .destroy = noop_destroy};
    CHECK(tsr_spu_register(&no_create, &err) == TSR_EINVAL);
    CHECK_STR(err.message, "nocreate: class has no create function");
    static const tsr_spu_class wrong_count = {.abi = TSR_SPU_ABI,
                                              .name = "wrongcount",
                                              .dispatch_count = TSR_DISPATCH_COUNT + 1,
                                              .create = noop_create,
                                              .destroy = noop_destroy};
    CHECK(tsr_spu_register(&wrong_count, &err) == TSR_EINVAL);
    CHECK_CONTAINS(err.message, "wrongcount: built for a dispatch table of");
    CHECK(tsr_spu_find("badspu", &err) == NULL);
}

/* The network declaration (tsr_spu_class.network) is checked like the
 * options: what a role needs, and only options the class declares, of the
 * type the mothership fills. */
static void test_register_rejects_bad_network_declaration(void)
{
    static const tsr_option_spec opts[] = {
        {.name = "to", .type = TSR_OPT_STRING, .default_value = "", .min = 1, .max = 0},
        {.name = "all", .type = TSR_OPT_STRING_LIST, .default_value = "", .min = 1, .max = 0},
        {.name = "place", .type = TSR_OPT_INT, .default_value = "0", .min = 0, .max = 9},
    };
#define NET_CLASS(id, ...)                                                                         \
    {                                                                                              \
        .abi = TSR_SPU_ABI, .name = id, .options = opts, .option_count = 3, .create = noop_create, \
        .destroy = noop_destroy, .network = __VA_ARGS__                                            \
    }
    static const struct {
        tsr_spu_class cls;
        const char *message;
    } bad[] = {
        {NET_CLASS("n_noaddr", {.role = TSR_SPU_ROLE_SERVER}),
         "n_noaddr: network role server needs network.server (the option a graph run fills)"},
        {NET_CLASS("n_tiled", {.role = TSR_SPU_ROLE_TILED_SERVERS, .servers = "all"}),
         "n_tiled: network role tiled servers needs network.server_tiles (the option a graph run "
         "fills)"},
        {NET_CLASS("n_peers", {.role = TSR_SPU_ROLE_PEERS, .display = "to", .peers = "all"}),
         "n_peers: network role peers needs network.rank (the option a graph run fills)"},
        {NET_CLASS("n_undeclared", {.role = TSR_SPU_ROLE_SERVER, .server = "server"}),
         "n_undeclared: network.server names option 'server', which it does not declare"},
        {NET_CLASS("n_type", {.role = TSR_SPU_ROLE_SERVERS, .servers = "to"}),
         "n_type: network.servers names option 'to', which is not a string list option"},
        {NET_CLASS("n_rank", {.role = TSR_SPU_ROLE_DISPLAY, .display = "to", .rank = "all"}),
         "n_rank: network.rank names option 'all', which is not an int option"},
        {NET_CLASS("n_twice", {.role = TSR_SPU_ROLE_SERVER, .server = "to", .token = "to"}),
         "n_twice: network.server and network.token both name option 'to'"},
        {NET_CLASS("n_none", {.role = TSR_SPU_ROLE_NONE, .server = "to"}),
         "n_none: network role none sends to no node, so it names no address, token, server "
         "tiles, rank or peers option (only tiles)"},
        {NET_CLASS("n_role", {.role = (tsr_spu_role)42, .server = "to"}), "n_role: unknown network role 42"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        tsr_error err;
        tsr_error_clear(&err);
        CHECK(tsr_spu_register(&bad[i].cls, &err) == TSR_EINVAL);
        CHECK_STR(err.message, bad[i].message);
    }
    static const tsr_spu_class good =
        NET_CLASS("n_good", {.role = TSR_SPU_ROLE_PEERS, .display = "to", .peers = "all", .rank = "place"});
    tsr_error err;
    CHECK(tsr_spu_register(&good, &err) == TSR_OK);
    CHECK(tsr_spu_find("n_good", &err) == &good);
    CHECK_STR(tsr_spu_role_name(good.network.role), "peers");
    CHECK_STR(tsr_spu_role_name((tsr_spu_role)42), "unknown");
#undef NET_CLASS
}

static void test_list_sorted_deduplicated(void)
{
    char env[8192];
    snprintf(env, sizeof env, "%s:%s", env_dir(), bad_dir());
    setenv("TESSERA_SPU_PATH", env, 1);
    static const tsr_spu_class first = {
        .abi = TSR_SPU_ABI, .name = "aaa_registered", .create = noop_create, .destroy = noop_destroy};
    tsr_error err;
    REQUIRE(tsr_spu_register(&first, &err) == TSR_OK);
    size_t n = tsr_spu_list(NULL, 0);
    REQUIRE(n >= 2);
    const tsr_spu_class **all = calloc(n, sizeof *all);
    REQUIRE(all);
    CHECK(tsr_spu_list(all, n) == n);
    CHECK_STR(all[0]->name, "aaa_registered");
    bool has_passthrough = false;
    for (size_t i = 0; i < n; i++) {
        if (i > 0)
            CHECK(strcmp(all[i - 1]->name, all[i]->name) < 0); /* sorted, no duplicates */
        has_passthrough |= !strcmp(all[i]->name, "passthrough");
        /* Broken plugins on the path are skipped, not listed. */
        CHECK(strcmp(all[i]->name, "oldabi") && strcmp(all[i]->name, "othername"));
    }
    CHECK(has_passthrough);
    free(all);
}

static void *find_many(void *arg)
{
    const tsr_spu_class **out = arg;
    for (int i = 0; i < 50; i++) {
        tsr_error err;
        const tsr_spu_class *cls = tsr_spu_find("passthrough", &err);
        if (!cls || (*out && *out != cls))
            return NULL;
        *out = cls;
        if (i % 10 == 0)
            tsr_spu_list(NULL, 0);
    }
    return arg;
}

static void test_find_is_thread_safe(void)
{
    unsetenv("TESSERA_SPU_PATH");
    enum { THREADS = 8 };
    pthread_t threads[THREADS];
    const tsr_spu_class *found[THREADS] = {0};
    for (int i = 0; i < THREADS; i++)
        REQUIRE(pthread_create(&threads[i], NULL, find_many, &found[i]) == 0);
    for (int i = 0; i < THREADS; i++) {
        void *result;
        pthread_join(threads[i], &result);
        CHECK(result == &found[i]);
        CHECK(found[i] != NULL && found[i] == found[0]);
    }
}

static const spu_test_case tests[] = {
    {"spu_loader_finds_build_tree_plugin", test_finds_build_tree_plugin},
    {"spu_loader_env_path_first", test_env_path_first},
    {"spu_loader_missing_spu_names_search_path", test_missing_spu_names_search_path},
    {"spu_loader_rejects_file_without_entry_point", test_rejects_file_without_entry_point},
    {"spu_loader_rejects_abi_mismatch", test_rejects_abi_mismatch},
    {"spu_loader_rejects_name_mismatch", test_rejects_name_mismatch},
    {"spu_loader_rejects_bad_names", test_rejects_bad_names},
    {"spu_loader_registered_class_wins", test_registered_class_wins},
    {"spu_loader_register_rejects_bad_class", test_register_rejects_bad_class},
    {"spu_loader_register_rejects_bad_network_declaration", test_register_rejects_bad_network_declaration},
    {"spu_loader_rejects_previous_abi", test_rejects_previous_abi},
    {"spu_loader_list_sorted_deduplicated", test_list_sorted_deduplicated},
    {"spu_loader_find_is_thread_safe", test_find_is_thread_safe},
};

SPU_TEST_MAIN(tests)
