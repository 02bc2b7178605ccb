/* tests/spu/chain_test.c — building chains: slot resolution through super
 * and child (real calls through tsr_call_*), options shared with a super,
 * creation and destruction order, text parsing, and the exact messages for
 * unknown SPUs, unknown options and wrong types. The test classes are
 * registered in-process; `passthrough` is the real plugin. Owns a journal
 * of calls (test-only state). Never: inspects table internals where a call
 * can show the behaviour. */
#include <stdarg.h>
#include <stdlib.h>
#include <unistd.h>

#include "spu_test.h"
#include "tessera/chain.h"
#include "tessera/dev/native.h"
#include "tessera/spu.h"

/* What the test SPUs did, in order: "sub#1: Color3f 2" ... */
static char journal[64][128];
static size_t journal_len;

static void note(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static void note(const char *fmt, ...)
{
    if (journal_len == 64)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(journal[journal_len++], sizeof journal[0], fmt, ap);
    va_end(ap);
}

static void journal_reset(void) { journal_len = 0; }

static void check_journal(const char *const *expected, size_t n, int line)
{
    bool same = journal_len == n;
    for (size_t i = 0; same && i < n; i++)
        same = !strcmp(journal[i], expected[i]);
    if (same)
        return;
    fprintf(stderr, "chain_test.c:%d: journal differs\n  got:\n", line);
    for (size_t i = 0; i < journal_len; i++)
        fprintf(stderr, "    %s\n", journal[i]);
    fprintf(stderr, "  expected:\n");
    for (size_t i = 0; i < n; i++)
        fprintf(stderr, "    %s\n", expected[i]);
    harness_failures++;
}
#define CHECK_JOURNAL(...)                                                          \
    do {                                                                            \
        static const char *const expected_[] = {__VA_ARGS__};                       \
        check_journal(expected_, sizeof expected_ / sizeof expected_[0], __LINE__); \
    } while (0)

/* An instance of any test SPU: its name, where calls go next, its super. */
typedef struct test_spu {
    char name[96];
    const tsr_dispatch *child;
    const tsr_dispatch *super;
} test_spu;

static test_spu *test_spu_new(const tsr_spu_init *init)
{
    test_spu *t = calloc(1, sizeof *t);
    if (t) {
        snprintf(t->name, sizeof t->name, "%s", init->instance_name);
        t->child = init->child;
        t->super = init->super;
        note("create %s", t->name);
    }
    return t;
}

static void test_spu_destroy(void *self)
{
    test_spu *t = self;
    note("destroy %s", t->name);
    free(t);
}

/* inh_super implements Vertex3f (A) and Color3f (B), passing both on. */
static void super_Vertex3f(void *self, GLfloat x, GLfloat y, GLfloat z)
{
    test_spu *t = self;
    note("%s: Vertex3f %g", t->name, x);
    tsr_call_Vertex3f(t->child, x, y, z);
}
static void super_Color3f(void *self, GLfloat r, GLfloat g, GLfloat b)
{
    test_spu *t = self;
    note("%s: Color3f %g", t->name, r);
    tsr_call_Color3f(t->child, r, g, b);
}
static void *super_create(const tsr_spu_init *init, tsr_error *err)
{
    (void)err;
    test_spu *t = test_spu_new(init);
    if (t) {
        tsr_set_Vertex3f(init->table, super_Vertex3f, t);
        tsr_set_Color3f(init->table, super_Color3f, t);
        note("%s: level=%lld", t->name, (long long)tsr_options_int(init->options, "level"));
    }
    return t;
}

/* inh_sub inherits inh_super and overrides only Color3f (B), then calls
 * its super's version, as a subclass method would. */
static void sub_Color3f(void *self, GLfloat r, GLfloat g, GLfloat b)
{
    test_spu *t = self;
    note("%s: Color3f %g", t->name, r);
    tsr_call_Color3f(t->super, r, g, b);
}
static void *sub_create(const tsr_spu_init *init, tsr_error *err)
{
    (void)err;
    test_spu *t = test_spu_new(init);
    if (t) {
        tsr_set_Color3f(init->table, sub_Color3f, t);
        /* Options a super declares reach the subclass too. */
        note("%s: level=%lld tag=%s", t->name, (long long)tsr_options_int(init->options, "level"),
             tsr_options_string(init->options, "tag"));
    }
    return t;
}

/* What api_super publishes for its subclasses (tsr_spu_class.api), as
 * render publishes tessera/dev/render.h: called with the super instance. */
typedef struct super_api {
    const char *(*name_of)(const void *instance);
} super_api;
static const char *super_name_of(const void *instance) { return ((const test_spu *)instance)->name; }
static const super_api the_super_api = {.name_of = super_name_of};

/* api_sub inherits api_super and asks it, through its api, for its name. */
static void *api_sub_create(const tsr_spu_init *init, tsr_error *err)
{
    (void)err;
    test_spu *t = test_spu_new(init);
    const super_api *api = init->super_api;
    if (t)
        note("%s: super %s", t->name, api && init->super_instance ? api->name_of(init->super_instance) : "(none)");
    return t;
}

/* inh_child records Vertex3f, Color3f and Normal3f (C). */
static void child_Vertex3f(void *self, GLfloat x, GLfloat y, GLfloat z)
{
    (void)y, (void)z;
    note("%s: Vertex3f %g", ((test_spu *)self)->name, x);
}
static void child_Color3f(void *self, GLfloat r, GLfloat g, GLfloat b)
{
    (void)g, (void)b;
    note("%s: Color3f %g", ((test_spu *)self)->name, r);
}
static void child_Normal3f(void *self, GLfloat x, GLfloat y, GLfloat z)
{
    (void)y, (void)z;
    note("%s: Normal3f %g", ((test_spu *)self)->name, x);
}
static void *child_create(const tsr_spu_init *init, tsr_error *err)
{
    (void)err;
    test_spu *t = test_spu_new(init);
    if (t) {
        tsr_set_Vertex3f(init->table, child_Vertex3f, t);
        tsr_set_Color3f(init->table, child_Color3f, t);
        tsr_set_Normal3f(init->table, child_Normal3f, t);
    }
    return t;
}

static void *failing_create(const tsr_spu_init *init, tsr_error *err)
{
    tsr_error_set(err, TSR_EIO, "%s: cannot open the display", init->instance_name);
    return NULL;
}

static const tsr_option_spec super_options[] = {
    {.name = "level", .type = TSR_OPT_INT, .default_value = "1", .min = 0, .max = 9, .help = "a super's option"},
};
static const tsr_option_spec sub_options[] = {
    {.name = "tag",
     .type = TSR_OPT_STRING,
     .default_value = "none",
     .min = 1,
     .max = 0,
     .help = "a subclass's own option"},
};
static const tsr_option_spec msg_options[] = {
    {.name = "width", .type = TSR_OPT_INT, .default_value = "1024", .min = 1, .max = 16384},
    {.name = "verbose", .type = TSR_OPT_BOOL, .min = 1, .max = 0},
    {.name = "output", .type = TSR_OPT_STRING, .min = 1, .max = 0},
};

#define TEST_CLASS(cname, csuper, opts, nopts, create_fn)                                         \
    {                                                                                             \
        .abi = TSR_SPU_ABI, .dispatch_count = TSR_DISPATCH_COUNT, .name = cname, .super = csuper, \
        .summary = "chain test SPU", .options = opts, .option_count = nopts, .create = create_fn, \
        .destroy = test_spu_destroy                                                               \
    }

static const tsr_spu_class test_classes[] = {
    TEST_CLASS("inh_super", NULL, super_options, 1, super_create),
    TEST_CLASS("inh_sub", "inh_super", sub_options, 1, sub_create),
    TEST_CLASS("inh_child", NULL, NULL, 0, child_create),
    TEST_CLASS("msg_render", NULL, msg_options, 3, child_create),
    TEST_CLASS("failing", NULL, NULL, 0, failing_create),
    /* cyc_a -> cyc_b -> cyc_a */
    TEST_CLASS("cyc_a", "cyc_b", NULL, 0, child_create),
    TEST_CLASS("cyc_b", "cyc_a", NULL, 0, child_create),
    /* deep0 -> deep1 -> ... -> deep9: nine supers, one too many */
    TEST_CLASS("deep0", "deep1", NULL, 0, child_create),
    TEST_CLASS("deep1", "deep2", NULL, 0, child_create),
    TEST_CLASS("deep2", "deep3", NULL, 0, child_create),
    TEST_CLASS("deep3", "deep4", NULL, 0, child_create),
    TEST_CLASS("deep4", "deep5", NULL, 0, child_create),
    TEST_CLASS("deep5", "deep6", NULL, 0, child_create),
    TEST_CLASS("deep6", "deep7", NULL, 0, child_create),
    TEST_CLASS("deep7", "deep8", NULL, 0, child_create),
    TEST_CLASS("deep8", "deep9", NULL, 0, child_create),
    TEST_CLASS("deep9", NULL, NULL, 0, child_create),
    TEST_CLASS("orphan", "no_such_super", NULL, 0, child_create),
    {.abi = TSR_SPU_ABI,
     .dispatch_count = TSR_DISPATCH_COUNT,
     .name = "api_super",
     .summary = "chain test SPU with an api",
     .options = super_options,
     .option_count = 1,
     .create = super_create,
     .destroy = test_spu_destroy,
     .api = &the_super_api},
    TEST_CLASS("api_sub", "api_super", NULL, 0, api_sub_create),
    TEST_CLASS("api_alone", NULL, NULL, 0, api_sub_create),
};

static void register_test_classes(void)
{
    for (size_t i = 0; i < sizeof test_classes / sizeof test_classes[0]; i++) {
        tsr_error err;
        if (tsr_spu_register(&test_classes[i], &err) != TSR_OK) {
            fprintf(stderr, "register %s: %s\n", test_classes[i].name, err.message);
            exit(1);
        }
    }
}

static tsr_chain *chain_ok(const char *text)
{
    tsr_error err;
    tsr_error_clear(&err);
    tsr_chain *chain = tsr_chain_create(text, &err);
    if (!chain)
        fprintf(stderr, "chain '%s': %s\n", text, err.message);
    REQUIRE(chain);
    return chain;
}

/* The message of a chain that must fail. */
static const char *chain_error(const char *text, int code)
{
    static tsr_error err;
    tsr_error_clear(&err);
    journal_reset();
    tsr_chain *chain = tsr_chain_create(text, &err);
    CHECK(chain == NULL);
    tsr_chain_destroy(chain);
    if (err.code != code)
        fprintf(stderr, "chain '%s': code %s, expected %s\n", text, tsr_error_name(err.code), tsr_error_name(code));
    CHECK(err.code == code);
    return err.message;
}

static void test_inheritance(void)
{
    register_test_classes();
    tsr_chain *chain = chain_ok("inh_sub level=3 tag=x ! inh_child");
    const tsr_dispatch *head = tsr_chain_head(chain);
    REQUIRE(head);

    journal_reset();
    tsr_call_Vertex3f(head, 1, 0, 0); /* A: only the super implements it */
    CHECK_JOURNAL("inh_sub#1.inh_super: Vertex3f 1", "inh_child#1: Vertex3f 1");

    journal_reset();
    tsr_call_Color3f(head, 2, 0, 0); /* B: the subclass overrides it */
    CHECK_JOURNAL("inh_sub#1: Color3f 2", "inh_sub#1.inh_super: Color3f 2", "inh_child#1: Color3f 2");

    journal_reset();
    tsr_call_Normal3f(head, 3, 0, 0); /* C: neither does; the child gets it */
    CHECK_JOURNAL("inh_child#1: Normal3f 3");

    journal_reset();
    tsr_call_Begin(head, GL_TRIANGLES); /* nobody: ends in the no-op table */
    tsr_call_End(head);
    CHECK(journal_len == 0);

    journal_reset();
    tsr_chain_destroy(chain);
    CHECK_JOURNAL("destroy inh_sub#1", "destroy inh_sub#1.inh_super", "destroy inh_child#1");
}

static void test_super_options_accepted(void)
{
    register_test_classes();
    journal_reset();
    tsr_chain *chain = chain_ok("inh_sub level=7 ! inh_child");
    /* Last to first; the super before its subclass; both see `level`. */
    CHECK_JOURNAL("create inh_child#1", "create inh_sub#1.inh_super", "inh_sub#1.inh_super: level=7",
                  "create inh_sub#1", "inh_sub#1: level=7 tag=none");
    tsr_chain_destroy(chain);
    /* The super alone does not know the subclass's option. */
    CHECK_STR(chain_error("inh_super tag=x", TSR_EINVAL), "inh_super: unknown option 'tag' (options: level)");
    CHECK_STR(chain_error("inh_sub level=12", TSR_EINVAL), "inh_sub: option 'level': '12' is out of range [0, 9]");
}

/* A subclass gets its super instance and the super class's api; an SPU
 * without a super gets neither. */
static void test_subclass_calls_super_api(void)
{
    register_test_classes();
    journal_reset();
    tsr_chain *chain = chain_ok("api_sub ! inh_child");
    CHECK_JOURNAL("create inh_child#1", "create api_sub#1.api_super", "api_sub#1.api_super: level=1",
                  "create api_sub#1", "api_sub#1: super api_sub#1.api_super");
    tsr_chain_destroy(chain);
    journal_reset();
    chain = chain_ok("api_alone");
    CHECK_JOURNAL("create api_alone#1", "api_alone#1: super (none)");
    tsr_chain_destroy(chain);
}

static void test_rejects_unknown_option(void)
{
    register_test_classes();
    CHECK_STR(chain_error("msg_render widht=640", TSR_EINVAL),
              "msg_render: unknown option 'widht' (did you mean 'width'?)");
    CHECK_STR(chain_error("inh_child ! msg_render colour=red", TSR_EINVAL),
              "msg_render: unknown option 'colour' (options: width, verbose, output)");
    CHECK_STR(chain_error("inh_child x=1", TSR_EINVAL), "inh_child: unknown option 'x' (inh_child has no options)");
    /* Nothing was created for a chain that cannot be built. */
    CHECK(journal_len == 0);
}

static void test_rejects_wrong_type(void)
{
    register_test_classes();
    CHECK_STR(chain_error("msg_render width=abc", TSR_EINVAL), "msg_render: option 'width': 'abc' is not an integer");
    CHECK_STR(chain_error("msg_render verbose=2", TSR_EINVAL),
              "msg_render: option 'verbose': '2' is not a boolean (true/false, yes/no, on/off, "
              "1/0)");
    CHECK_STR(chain_error("msg_render width=0", TSR_EINVAL),
              "msg_render: option 'width': '0' is out of range [1, 16384]");
    CHECK(journal_len == 0);
}

static void test_rejects_unknown_spu(void)
{
    register_test_classes();
    char path[4096], expected[8192];
    tsr_spu_search_path(path, sizeof path);
    snprintf(expected, sizeof expected, "unknown SPU 'zzqqxx': no zzqqxx_spu.so in %s", path);
    CHECK_STR(chain_error("inh_child ! zzqqxx", TSR_ENOENT), expected);
    CHECK_CONTAINS(chain_error("inh_chlid", TSR_ENOENT),
                   "unknown SPU 'inh_chlid' (did you mean 'inh_child'?): no inh_chlid_spu.so in ");
}

static void test_rejects_bad_supers(void)
{
    register_test_classes();
    CHECK_STR(chain_error("cyc_a", TSR_EINVAL), "cyc_a: super SPUs form a cycle: cyc_a -> cyc_b -> cyc_a");
    CHECK_STR(chain_error("deep0", TSR_EINVAL),
              "deep0: more than 8 levels of super SPUs: deep0 -> deep1 -> deep2 -> deep3 -> "
              "deep4 -> deep5 -> deep6 -> deep7 -> deep8 -> deep9 ...");
    journal_reset();
    tsr_chain_destroy(chain_ok("deep1")); /* exactly eight supers is fine */
    CHECK(journal_len == 18);
    CHECK_CONTAINS(chain_error("orphan", TSR_ENOENT),
                   "orphan: super SPU 'no_such_super' of 'orphan': unknown SPU 'no_such_super'");
}

static void test_empty_is_error(void)
{
    CHECK_STR(chain_error("", TSR_EINVAL), "chain: empty chain (no SPU named)");
    CHECK_STR(chain_error("   ", TSR_EINVAL), "chain: empty chain (no SPU named)");
    tsr_error err;
    CHECK(tsr_chain_create_links(NULL, 0, &err) == NULL);
    CHECK_STR(err.message, "chain: empty chain (no SPU named)");
    CHECK(tsr_chain_head(NULL) == NULL);
    tsr_chain_destroy(NULL);
}

static void test_parse_errors_name_token(void)
{
    CHECK_STR(chain_error("! inh_child", TSR_EINVAL), "chain: '!' (column 1) has no SPU before it");
    CHECK_STR(chain_error("inh_child ! ! inh_child", TSR_EINVAL), "chain: '!' (column 13) has no SPU before it");
    CHECK_STR(chain_error("inh_child !", TSR_EINVAL), "chain: '!' (column 11) is not followed by an SPU");
    CHECK_STR(chain_error("msg_render width", TSR_EINVAL),
              "chain: 'width' after 'msg_render' (column 12) is not key=value");
    CHECK_STR(chain_error("msg_render =5", TSR_EINVAL),
              "chain: '=5' after 'msg_render' (column 12) has no option name");
    CHECK_STR(chain_error("Render", TSR_EINVAL), "chain: 'Render' (column 1) is not an SPU name ([a-z0-9_]+)");
    CHECK_STR(chain_error("msg_render output=\"a b", TSR_EINVAL),
              "chain: unterminated quote in 'output=\"a' (column 19)");
    CHECK_STR(chain_error("msg_render output=\"a\"b", TSR_EINVAL),
              "chain: 'b' right after the closing quote of option 'output' (column 22)");
    CHECK_STR(chain_error("msg_render output=a\"b\"", TSR_EINVAL),
              "chain: quote inside the value of 'output=a\"b\"' (column 12): quote the whole "
              "value, key=\"...\"");
}

/* A recording SPU's view of the option it was given, through the journal. */
static void *echo_create(const tsr_spu_init *init, tsr_error *err)
{
    (void)err;
    test_spu *t = test_spu_new(init);
    if (t)
        note("output=[%s]", tsr_options_string(init->options, "output"));
    return t;
}

static void test_parse_quoted_values(void)
{
    static const tsr_spu_class echo = {.abi = TSR_SPU_ABI,
                                       .name = "echo",
                                       .options = msg_options,
                                       .option_count = 3,
                                       .create = echo_create,
                                       .destroy = test_spu_destroy};
    tsr_error err;
    REQUIRE(tsr_spu_register(&echo, &err) == TSR_OK);
    journal_reset();
    tsr_chain *chain = chain_ok("echo output=\"frames/a b!c.png\" width=5!echo   output=\"say "
                                "\\\"hi\\\" \\\\o/\" ! echo output=\"\"");
    CHECK_JOURNAL("create echo#3", "output=[]", "create echo#2", "output=[say \"hi\" \\o/]", "create echo#1",
                  "output=[frames/a b!c.png]");
    tsr_chain_destroy(chain);

    /* The same chain as links, without text. */
    const char *keys[] = {"output", "width"}, *values[] = {"x y", "7"};
    tsr_chain_link links[] = {{.spu = "echo", .keys = keys, .values = values, .option_count = 2}, {.spu = "inh_child"}};
    register_test_classes();
    journal_reset();
    chain = tsr_chain_create_links(links, 2, &err);
    REQUIRE(chain);
    CHECK_JOURNAL("create inh_child#1", "create echo#1", "output=[x y]");
    tsr_chain_destroy(chain);
}

/* Links to text (what an app node gets as TESSERA_CHAIN from its links):
 * every value quoted and escaped, read back unchanged by the parser. */
static void test_links_text_reads_back(void)
{
    static const tsr_spu_class echo = {.abi = TSR_SPU_ABI,
                                       .name = "echo",
                                       .options = msg_options,
                                       .option_count = 3,
                                       .create = echo_create,
                                       .destroy = test_spu_destroy};
    tsr_error err;
    REQUIRE(tsr_spu_register(&echo, &err) == TSR_OK);
    const char *keys[] = {"output", "width"};
    const char *hard[] = {"say \"hi\" \\o/ ! x=y", "5"}, *empty[] = {""};
    tsr_chain_link links[] = {{.spu = "echo", .keys = keys, .values = hard, .option_count = 2},
                              {.spu = "echo", .keys = keys, .values = empty, .option_count = 1},
                              {.spu = "echo"}};
    char *text = tsr_chain_links_text(links, 3, &err);
    REQUIRE(text);
    CHECK_STR(text, "echo output=\"say \\\"hi\\\" \\\\o/ ! x=y\" width=\"5\" ! echo output=\"\" ! echo");
    journal_reset();
    tsr_chain *chain = chain_ok(text);
    CHECK_JOURNAL("create echo#3", "output=[]", "create echo#2", "output=[]", "create echo#1",
                  "output=[say \"hi\" \\o/ ! x=y]");
    tsr_chain_destroy(chain);
    free(text);
    CHECK(tsr_chain_links_text(links, 0, &err) == NULL && err.code == TSR_EINVAL);
}

static void test_create_failure_cleans_up(void)
{
    register_test_classes();
    journal_reset();
    tsr_error err;
    CHECK(tsr_chain_create("inh_child ! failing ! inh_sub ! inh_child", &err) == NULL);
    CHECK(err.code == TSR_EIO);
    CHECK_STR(err.message, "failing#1: cannot open the display");
    /* What was created is destroyed again, first to last. */
    CHECK_JOURNAL("create inh_child#2", "create inh_sub#1.inh_super", "inh_sub#1.inh_super: level=1",
                  "create inh_sub#1", "inh_sub#1: level=1 tag=none", "destroy inh_sub#1", "destroy inh_sub#1.inh_super",
                  "destroy inh_child#2");
}

static void test_unset_slots_reach_child(void)
{
    /* The real passthrough plugin implements nothing: every call must reach
     * the SPU after it. */
    unsetenv("TESSERA_SPU_PATH");
    register_test_classes();
    journal_reset();
    tsr_chain *chain = chain_ok("passthrough verbose=off ! passthrough ! inh_child");
    journal_reset();
    const tsr_dispatch *head = tsr_chain_head(chain);
    tsr_call_Vertex3f(head, 4, 0, 0);
    tsr_call_Normal3f(head, 5, 0, 0);
    CHECK_JOURNAL("inh_child#1: Vertex3f 4", "inh_child#1: Normal3f 5");
    /* No slot of the head is left empty. */
    for (size_t i = 0; i < TSR_DISPATCH_COUNT; i++)
        CHECK(head->slots[i].fn != NULL);
    tsr_chain_destroy(chain);
}

/* Creates and destroys `text` with stderr captured; returns what was said. */
static const char *chain_stderr(const char *text)
{
    static char said[2048];
    char path[] = "/tmp/tessera_chain_test_XXXXXX";
    int fd = mkstemp(path);
    REQUIRE(fd >= 0);
    fflush(stderr);
    int saved = dup(STDERR_FILENO);
    REQUIRE(saved >= 0 && dup2(fd, STDERR_FILENO) >= 0);
    tsr_chain_destroy(chain_ok(text));
    fflush(stderr);
    dup2(saved, STDERR_FILENO);
    close(saved);
    ssize_t n = pread(fd, said, sizeof said - 1, 0);
    said[n > 0 ? n : 0] = '\0';
    close(fd);
    unlink(path);
    return said;
}

static void test_passthrough_verbose_option(void)
{
    unsetenv("TESSERA_SPU_PATH");
    CHECK_STR(chain_stderr("passthrough verbose=yes ! passthrough"),
              "tessera: passthrough#1: created; every call goes straight to the next SPU\n"
              "tessera: passthrough#1: destroyed\n");
    CHECK_STR(chain_stderr("passthrough ! passthrough verbose=false"), "");
}

/* An SPU that draws back into the program's windows (render's
 * window_output=app) reads them from its chain's table: it says at each
 * Vertex3f(W) what window W is in the table it was created with. */
typedef struct native_reader {
    char name[96];
    tsr_native_windows *windows;
} native_reader;

static void native_reader_Vertex3f(void *self, GLfloat x, GLfloat y, GLfloat z)
{
    (void)y;
    (void)z;
    native_reader *r = self;
    char dpy[64];
    unsigned long xid = 0;
    if (tsr_native_window_get(r->windows, (int)x, dpy, sizeof dpy, &xid))
        note("%s: window %d is %#lx on '%s'", r->name, (int)x, xid, dpy);
    else
        note("%s: window %d unknown", r->name, (int)x);
}

static void *native_reader_create(const tsr_spu_init *init, tsr_error *err)
{
    (void)err;
    native_reader *r = calloc(1, sizeof *r);
    if (r) {
        snprintf(r->name, sizeof r->name, "%s", init->instance_name);
        r->windows = init->native_windows;
        tsr_set_Vertex3f(init->table, native_reader_Vertex3f, r);
    }
    return r;
}

/* Two chains in one process (two programs' worth of windows, or two
 * streams of the faker) keep two tables: what one chain's windows are
 * never shows in the other, a super instance reads its chain's table, and
 * one chain outlives the other's. */
static void test_native_windows_per_chain(void)
{
    static const tsr_spu_class reader = {
        .abi = TSR_SPU_ABI, .name = "native_reader", .create = native_reader_create, .destroy = free};
    static const tsr_spu_class sub = {.abi = TSR_SPU_ABI,
                                      .name = "native_sub",
                                      .super = "native_reader",
                                      .create = echo_create,
                                      .destroy = test_spu_destroy};
    tsr_error err;
    REQUIRE(tsr_spu_register(&reader, &err) == TSR_OK);
    REQUIRE(tsr_spu_register(&sub, &err) == TSR_OK);
    tsr_chain *a = chain_ok("native_sub"), *b = chain_ok("native_reader");
    tsr_native_windows *wa = tsr_chain_native_windows(a), *wb = tsr_chain_native_windows(b);
    REQUIRE(wa && wb && wa != wb);
    CHECK(tsr_native_window_set(wa, 0, ":5", 0x200002) == 0);
    CHECK(tsr_native_window_set(wb, 0, ":7", 0x400004) == 0);
    CHECK(tsr_native_window_set(wb, 3, NULL, 0x400009) == 0);
    journal_reset();
    tsr_call_Vertex3f(tsr_chain_head(a), 0, 0, 0);
    tsr_call_Vertex3f(tsr_chain_head(b), 0, 0, 0);
    tsr_call_Vertex3f(tsr_chain_head(a), 3, 0, 0);
    tsr_call_Vertex3f(tsr_chain_head(b), 3, 0, 0);
    CHECK(tsr_native_window_set(wa, 0, NULL, 0) == 0); /* forgets a's window 0 only */
    tsr_call_Vertex3f(tsr_chain_head(a), 0, 0, 0);
    tsr_call_Vertex3f(tsr_chain_head(b), 0, 0, 0);
    CHECK_JOURNAL("native_sub#1.native_reader: window 0 is 0x200002 on ':5'",
                  "native_reader#1: window 0 is 0x400004 on ':7'", "native_sub#1.native_reader: window 3 unknown",
                  "native_reader#1: window 3 is 0x400009 on ''", "native_sub#1.native_reader: window 0 unknown",
                  "native_reader#1: window 0 is 0x400004 on ':7'");
    tsr_chain_destroy(a);
    journal_reset();
    tsr_call_Vertex3f(tsr_chain_head(b), 0, 0, 0);
    CHECK_JOURNAL("native_reader#1: window 0 is 0x400004 on ':7'");
    tsr_chain_destroy(b);
    /* Without a table (an SPU created outside a chain): nothing is found. */
    CHECK(tsr_native_window_get(NULL, 0, NULL, 0, NULL) == 0);
    CHECK(tsr_native_window_set(NULL, 0, ":5", 1) == -1);
}

static const spu_test_case tests[] = {
    {"spu_chain_inheritance", test_inheritance},
    {"spu_chain_super_options_accepted", test_super_options_accepted},
    {"spu_chain_subclass_calls_super_api", test_subclass_calls_super_api},
    {"spu_chain_rejects_unknown_option", test_rejects_unknown_option},
    {"spu_chain_rejects_wrong_type", test_rejects_wrong_type},
    {"spu_chain_rejects_unknown_spu", test_rejects_unknown_spu},
    {"spu_chain_rejects_super_cycle_and_depth", test_rejects_bad_supers},
    {"spu_chain_empty_is_error", test_empty_is_error},
    {"spu_chain_parse_errors_name_token", test_parse_errors_name_token},
    {"spu_chain_parse_quoted_values", test_parse_quoted_values},
    {"spu_chain_create_failure_cleans_up", test_create_failure_cleans_up},
    {"spu_chain_links_text_reads_back", test_links_text_reads_back},
    {"spu_chain_unset_slots_reach_child", test_unset_slots_reach_child},
    {"spu_passthrough_verbose_option", test_passthrough_verbose_option},
    {"spu_chain_native_windows_per_chain", test_native_windows_per_chain},
};

SPU_TEST_MAIN(tests)
