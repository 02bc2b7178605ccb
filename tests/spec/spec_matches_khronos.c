/* tests/spec/spec_matches_khronos.c — test spec_matches_khronos: every
 * spec command with khronos: true exists in gl.xml with the same return
 * type, parameter count and parameter types (normalised C spelling).
 * Usage: spec_matches_khronos SPEC.yaml GL.xml. Fails, naming the command,
 * on any mismatch; fails (never skips) when gl.xml is missing. */
#include "spec_test_setup.h"

#include <stdio.h>
#include <string.h>

int main(int argc, char **argv)
{
    spec s;
    glxml x;
    int setup = spec_test_load_with_glxml(argc, argv, &s, &x);
    if (setup)
        return setup;

    int failures = 0;
    size_t checked = 0;
    for (size_t i = 0; i < s.ncmds; i++) {
        const spec_command *c = &s.cmds[i];
        if (!c->khronos)
            continue;
        char glname[256];
        snprintf(glname, sizeof glname, "gl%s", c->name);
        const glxml_command *k = glxml_find_command(&x, glname);
        if (!k) {
            fprintf(stderr, "FAIL: %s:%d: %s is not in %s\n", argv[1], c->line, glname, argv[2]);
            failures++;
            continue;
        }
        checked++;
        char a[256], b[256];
        if (strcmp(glxml_normalise_type(c->ret, a, sizeof a), glxml_normalise_type(k->ret, b, sizeof b)) != 0) {
            fprintf(stderr, "FAIL: %s:%d: %s returns '%s' in the spec but '%s' in gl.xml\n", argv[1], c->line,
                    glname, c->ret, b);
            failures++;
        }
        if (c->nparams != k->nparams) {
            fprintf(stderr, "FAIL: %s:%d: %s has %zu parameters in the spec but %zu in gl.xml\n", argv[1],
                    c->line, glname, c->nparams, k->nparams);
            failures++;
            continue;
        }
        for (size_t j = 0; j < c->nparams; j++) {
            glxml_normalise_type(c->params[j].type, a, sizeof a);
            glxml_normalise_type(k->params[j].type, b, sizeof b);
            if (strcmp(a, b) != 0) {
                fprintf(stderr, "FAIL: %s:%d: %s parameter %zu (%s) is '%s' in the spec but '%s' in gl.xml\n",
                        argv[1], c->line, glname, j + 1, c->params[j].name, c->params[j].type, b);
                failures++;
            }
        }
    }
    printf("%zu spec commands checked against %zu gl.xml commands, %d mismatches\n", checked, x.ncmds,
           failures);
    if (checked == 0) {
        fprintf(stderr, "FAIL: no spec command was checked\n");
        failures++;
    }
    glxml_free(&x);
    spec_free(&s);
    return failures ? 1 : 0;
}
