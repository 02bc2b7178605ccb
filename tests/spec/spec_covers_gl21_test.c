/* tests/spec/spec_covers_gl21_test.c — test spec_covers_gl21: every command that
 * gl.xml's GL 1.0-2.1 features require is a spec command, except the ones
 * listed below as not yet done, each with what it still needs. The list
 * may only shrink: a listed command that is in the spec fails the test
 * (take it off the list). Prints every missing command, one a line.
 * Usage: spec_covers_gl21 SPEC.yaml GL.xml */
#include "spec_test_setup.h"

#include <stdio.h>
#include <string.h>

#include "harness.h"

/* Empty since the server-sized gets landed (core/wire/sized_get.c); a
 * command that cannot be done yet goes here with what it still needs. */
static const struct {
    const char *name, *why;
} not_yet[] = {{NULL, NULL}};

static const char *not_yet_reason(const char *glname)
{
    for (size_t i = 0; not_yet[i].name; i++)
        if (!strcmp(not_yet[i].name, glname))
            return not_yet[i].why;
    return NULL;
}

int main(int argc, char **argv)
{
    spec s;
    glxml x;
    int setup = spec_test_load_with_glxml(argc, argv, &s, &x);
    if (setup)
        return setup;

    size_t core = 0, missing = 0, waiting = 0;
    for (size_t i = 0; i < x.ncmds; i++) {
        const glxml_command *k = &x.cmds[i];
        if (k->gl_version < 10 || k->gl_version > 21)
            continue;
        core++;
        const char *why = not_yet_reason(k->name);
        int in_spec = strncmp(k->name, "gl", 2) == 0 && spec_find(&s, k->name + 2) != NULL;
        if (why) {
            waiting++;
            CHECK(!in_spec, "%s is in %s now: take it off the not-yet list of %s", k->name, argv[1], __FILE__);
            if (!in_spec)
                printf("not yet: %s (%s)\n", k->name, why);
            continue;
        }
        if (!in_spec)
            missing++;
        CHECK(in_spec, "%s:%d: %s (GL %d.%d) is missing from %s", argv[2], k->line, k->name, k->gl_version / 10,
              k->gl_version % 10, argv[1]);
    }
    for (size_t i = 0; not_yet[i].name; i++) {
        const glxml_command *k = glxml_find_command(&x, not_yet[i].name);
        CHECK(k && k->gl_version >= 10 && k->gl_version <= 21, "%s on the not-yet list is no GL 1.0-2.1 command",
              not_yet[i].name);
    }
    printf("%zu GL 1.0-2.1 commands in %s: %zu missing, %zu not yet done\n", core, argv[2], missing, waiting);
    CHECK(core > 500, "only %zu GL 1.0-2.1 commands found in %s", core, argv[2]);
    glxml_free(&x);
    spec_free(&s);
    return harness_failures ? 1 : 0;
}
