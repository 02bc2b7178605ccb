/* tests/spec/spec_matches_khronos_test.c — test spec_matches_khronos: every
 * spec command with khronos: true exists in gl.xml with the same return
 * type, parameter count and parameter types (normalised C spelling).
 * Usage: spec_matches_khronos SPEC.yaml GL.xml. Fails, naming the command,
 * on any mismatch; fails (never skips) when gl.xml is missing. */
#include "spec_test_setup.h"

#include <stdio.h>
#include <string.h>

#include "harness.h"

int main(int argc, char **argv)
{
    spec s;
    glxml x;
    int setup = spec_test_load_with_glxml(argc, argv, &s, &x);
    if (setup)
        return setup;

    size_t checked = 0;
    for (size_t i = 0; i < s.ncmds; i++) {
        const spec_command *c = &s.cmds[i];
        if (!c->khronos)
            continue;
        char glname[256];
        snprintf(glname, sizeof glname, "gl%s", c->name);
        const glxml_command *k = glxml_find_command(&x, glname);
        CHECK(k, "%s:%d: %s is not in %s", argv[1], c->line, glname, argv[2]);
        if (!k)
            continue;
        checked++;
        char a[256], b[256];
        glxml_normalise_type(c->ret, a, sizeof a);
        glxml_normalise_type(k->ret, b, sizeof b);
        CHECK(strcmp(a, b) == 0, "%s:%d: %s returns '%s' in the spec but '%s' in gl.xml", argv[1], c->line, glname,
              c->ret, b);
        CHECK(c->nparams == k->nparams, "%s:%d: %s has %zu parameters in the spec but %zu in gl.xml", argv[1], c->line,
              glname, c->nparams, k->nparams);
        if (c->nparams != k->nparams)
            continue;
        for (size_t j = 0; j < c->nparams; j++) {
            glxml_normalise_type(c->params[j].type, a, sizeof a);
            glxml_normalise_type(k->params[j].type, b, sizeof b);
            CHECK(strcmp(a, b) == 0, "%s:%d: %s parameter %zu (%s) is '%s' in the spec but '%s' in gl.xml", argv[1],
                  c->line, glname, j + 1, c->params[j].name, c->params[j].type, b);
        }
    }
    printf("%zu spec commands checked against %zu gl.xml commands, %d mismatches\n", checked, x.ncmds,
           harness_failures);
    CHECK(checked > 0, "no spec command was checked");
    glxml_free(&x);
    spec_free(&s);
    return harness_failures ? 1 : 0;
}
