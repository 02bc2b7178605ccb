/* tests/spec/spec_loader_rejects_bad_specs_test.c — test
 * spec_loader_rejects_bad_specs: small broken specs written to a temp dir
 * must make spec_load fail with "FILE:LINE:COL: message", at the right line,
 * naming the culprit; a well-formed one of the same shape must load. */
#include "spec.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"

/* Lines 1..10 of every case; the case text starts at line 11. */
static const char prefix[] = "version: 1\n"                          /* 1 */
                             "pname_counts:\n"                       /* 2 */
                             "  GL_AMBIENT: 4\n"                     /* 3 */
                             "commands:\n"                           /* 4 */
                             "  - name: Begin\n"                     /* 5 */
                             "    opcode: 1\n"                       /* 6 */
                             "    category: geometry\n"              /* 7 */
                             "    return: void\n"                    /* 8 */
                             "    params:\n"                         /* 9 */
                             "      - {name: mode, type: GLenum}\n"; /* 10 */

typedef struct bad_case {
    const char *name;
    int with_prefix; /* prepend `prefix` */
    const char *text;
    int line;                  /* expected line of the error, 0: any */
    const char *want1, *want2; /* substrings the message must contain */
} bad_case;

static const bad_case cases[] = {
    {"duplicate_opcode", 1, "  - name: End\n    opcode: 1\n    category: geometry\n    return: void\n    params: []\n",
     11, "duplicate opcode 1", "End"},
    {"duplicate_name", 1, "  - name: Begin\n    opcode: 2\n    category: geometry\n    return: void\n    params: []\n",
     11, "duplicate command name", "Begin"},
    {"unknown_category", 1, "  - name: End\n    opcode: 2\n    category: geomtry\n    return: void\n    params: []\n",
     13, "unknown category", "geomtry"},
    {"count_names_missing_param", 1,
     "  - name: Lightfv\n    opcode: 2\n    category: state\n    return: void\n    params:\n"
     "      - {name: light, type: GLenum}\n"
     "      - {name: pname, type: GLenum}\n"
     "      - {name: params, type: const GLfloat *, count: {pname: pnam}}\n",
     18, "'pnam'", "Lightfv"},
    {"count_product_names_missing_param", 1,
     "  - name: Uniform4fv\n    opcode: 2\n    category: state\n    return: void\n    params:\n"
     "      - {name: location, type: GLint}\n"
     "      - {name: count, type: GLsizei}\n"
     "      - {name: value, type: const GLfloat *, count: cnt*4}\n",
     18, "'cnt'", "Uniform4fv"},
    {"count_names_float_param", 1,
     "  - name: Weird\n    opcode: 2\n    category: state\n    return: void\n    params:\n"
     "      - {name: x, type: GLfloat}\n"
     "      - {name: v, type: const GLfloat *, count: x}\n",
     17, "not an integer", "'x'"},
    {"pname_count_on_non_enum", 1,
     "  - name: Lightfv\n    opcode: 2\n    category: state\n    return: void\n    params:\n"
     "      - {name: light, type: GLint}\n"
     "      - {name: params, type: const GLfloat *, count: {pname: light}}\n",
     17, "GLenum", "light"},
    {"pointer_without_count", 1,
     "  - name: Vertex3fv\n    opcode: 2\n    category: geometry\n    return: void\n    params:\n"
     "      - {name: v, type: const GLfloat *}\n",
     16, "has no count", "Vertex3fv"},
    {"out_pointer_on_pack_command", 1,
     "  - name: GetIntegerv\n    opcode: 2\n    category: get\n    return: void\n    params:\n"
     "      - {name: pname, type: GLenum}\n"
     "      - {name: data, type: GLint *, count: {pname: pname}}\n",
     17, "wire: reply", "data"},
    {"return_value_on_pack_command", 1,
     "  - name: GetError\n    opcode: 2\n    category: get\n    return: GLenum\n    params: []\n", 11, "GetError",
     "wire: reply"},
    {"opcode_zero", 1, "  - name: End\n    opcode: 0\n    category: geometry\n    return: void\n    params: []\n", 12,
     "opcode 0", "out of range"},
    {"opcode_above_65534", 1,
     "  - name: End\n    opcode: 65535\n    category: geometry\n    return: void\n    params: []\n", 12, "opcode 65535",
     "out of range"},
    {"opcode_not_a_number", 1,
     "  - name: End\n    opcode: two\n    category: geometry\n    return: void\n    params: []\n", 12, "'two'",
     "not an integer"},
    {"unknown_wire", 1,
     "  - name: End\n    opcode: 2\n    category: geometry\n    return: void\n    wire: packed\n    params: []\n", 15,
     "unknown wire", "packed"},
    {"unknown_command_key", 1,
     "  - name: End\n    opcod: 2\n    category: geometry\n    return: void\n    params: []\n", 12,
     "unknown command key", "opcod"},
    {"duplicate_key", 1,
     "  - name: End\n    opcode: 2\n    opcode: 3\n    category: geometry\n    return: void\n    params: []\n", 13,
     "duplicate key", "opcode"},
    {"unknown_type", 1,
     "  - name: End\n    opcode: 2\n    category: geometry\n    return: void\n    params:\n"
     "      - {name: x, type: GLFloat}\n",
     16, "unknown type", "GLFloat"},
    {"pname_count_zero", 0,
     "version: 1\npname_counts:\n  GL_AMBIENT: 0\ncommands:\n  - name: End\n    opcode: 2\n"
     "    category: geometry\n    return: void\n    params: []\n",
     3, "GL_AMBIENT", "1..4096"},
    {"not_yaml_unclosed_flow", 0, "version: 1\ncommands: [ {name: Begin, opcode: 1\n\n", 0, "not valid YAML", NULL},
    {"not_yaml_binary", 0, "\x01\x02\x03\xff\xfe garbage", 0, "not valid YAML", NULL},
    {"top_level_list", 0, "- version\n- commands\n", 1, "top level must be a mapping", NULL},
    {"wrong_version", 0, "version: 2\ncommands: []\n", 1, "version '2'", NULL},
};

static int write_file(const char *path, const char *a, const char *b)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return -1;
    fputs(a, f);
    fputs(b, f);
    return fclose(f);
}

/* Checks "PATH:LINE:COL: " at the start of err. */
static int check_location(const char *err, const char *path, int want_line)
{
    size_t n = strlen(path);
    if (strncmp(err, path, n) != 0 || err[n] != ':')
        return 0;
    int line = 0, col = 0, used = 0;
    if (sscanf(err + n + 1, "%d:%d: %n", &line, &col, &used) != 2 || used == 0)
        return 0;
    if (line < 1 || col < 1)
        return 0;
    return want_line == 0 || line == want_line;
}

int main(void)
{
    char dir[] = "/tmp/tsr_spec_test_XXXXXX";
    REQUIRE(mkdtemp(dir), "mkdtemp %s: %s", dir, strerror(errno));
    char path[256], err[1024];
    spec s;

    /* Control: the shared prefix plus a good command loads. */
    snprintf(path, sizeof path, "%s/good.yaml", dir);
    REQUIRE(write_file(path, prefix,
                       "  - name: Lightfv\n    opcode: 2\n    category: state\n    return: void\n    params:\n"
                       "      - {name: light, type: GLenum}\n"
                       "      - {name: pname, type: GLenum}\n"
                       "      - {name: params, type: const GLfloat *, count: {pname: pname}}\n") == 0,
            "%s: %s", path, strerror(errno));
    int loaded = spec_load(path, &s, err, sizeof err) == 0;
    CHECK(loaded, "control spec does not load: %s", err);
    if (loaded) {
        const spec_command *c = spec_find(&s, "Lightfv");
        CHECK(s.ncmds == 2 && c && c->line == 11 && c->nparams == 3 && c->params[2].count.kind == SPEC_COUNT_PNAME &&
                  spec_pname_count_of(&s, "GL_AMBIENT") == 4,
              "control spec loaded wrongly: %zu commands, Lightfv %s at line %d with %zu params", s.ncmds,
              c ? "found" : "missing", c ? c->line : 0, c ? c->nparams : 0);
        spec_free(&s);
    }
    unlink(path);

    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const bad_case *bc = &cases[i];
        snprintf(path, sizeof path, "%s/%s.yaml", dir, bc->name);
        int written = write_file(path, bc->with_prefix ? prefix : "", bc->text) == 0;
        CHECK(written, "%s: %s", path, strerror(errno));
        if (!written)
            continue;
        memset(&s, 0x5a, sizeof s);
        err[0] = 0;
        int before = harness_failures;
        int rc = spec_load(path, &s, err, sizeof err);
        CHECK(rc != 0, "%s: spec_load accepted it", bc->name);
        if (rc == 0) {
            spec_free(&s);
        } else {
            /* Each holds on its own; all of them are checked. */
            CHECK(check_location(err, path, bc->line), "%s: message does not start with %s:%d:COL: -> %s", bc->name,
                  path, bc->line, err);
            CHECK(strstr(err, bc->want1) && (!bc->want2 || strstr(err, bc->want2)),
                  "%s: message does not name '%s'%s%s%s -> %s", bc->name, bc->want1, bc->want2 ? " and '" : "",
                  bc->want2 ? bc->want2 : "", bc->want2 ? "'" : "", err);
            CHECK(!s.cmds && !s.ncmds && !s.pnames && !s.npnames && !s.map_components,
                  "%s: spec_load failed but left data in the output", bc->name);
        }
        if (harness_failures == before)
            printf("ok %s: %s\n", bc->name, err);
        unlink(path);
    }

    snprintf(path, sizeof path, "%s/missing.yaml", dir);
    err[0] = 0;
    int missing_rc = spec_load(path, &s, err, sizeof err);
    int missing_ok = missing_rc != 0 && strstr(err, "cannot open") && strncmp(err, path, strlen(path)) == 0;
    CHECK(missing_ok, "missing file: %s", missing_rc == 0 ? "spec_load accepted it" : err);
    if (missing_rc == 0)
        spec_free(&s);
    if (missing_ok)
        printf("ok missing_file: %s\n", err);
    rmdir(dir);
    printf("%zu broken specs, %d failures\n", sizeof cases / sizeof cases[0] + 1, harness_failures);
    return harness_failures ? 1 : 0;
}
