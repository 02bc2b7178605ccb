/* tests/spec/spec_enums_are_gl_enums_test.c — test spec_enums_are_gl_enums:
 * every enum in pname_counts and map_components is a GL enum of gl.xml,
 * and no two names in one table share a value (the generator switches on
 * the values, so an alias twice would be a duplicate case label, and two
 * different counts for one value would be a lie).
 * Usage: spec_enums_are_gl_enums SPEC.yaml GL.xml */
#include "spec_test_setup.h"

#include <stdio.h>
#include <string.h>

#include "harness.h"

static void check_table(const char *spec_path, const char *what, const spec_pname_count *t, size_t n, const glxml *x)
{
    for (size_t i = 0; i < n; i++) {
        const glxml_enum *e = glxml_find_enum(x, t[i].name);
        CHECK(e, "%s: %s entry %s is not a GL enum in gl.xml", spec_path, what, t[i].name);
        if (!e)
            continue;
        for (size_t j = 0; j < i; j++) {
            const glxml_enum *o = glxml_find_enum(x, t[j].name);
            CHECK(!o || o->value != e->value, "%s: %s lists both %s and %s, which are the same value 0x%llx", spec_path,
                  what, t[j].name, t[i].name, e->value);
        }
    }
}

int main(int argc, char **argv)
{
    spec s;
    glxml x;
    int setup = spec_test_load_with_glxml(argc, argv, &s, &x);
    if (setup)
        return setup;
    CHECK(s.npnames > 0, "%s has no pname_counts", argv[1]);
    check_table(argv[1], "pname_counts", s.pnames, s.npnames, &x);
    check_table(argv[1], "map_components", s.map_components, s.nmap_components, &x);
    printf("%zu pname_counts and %zu map_components checked against %zu gl.xml enums, %d problems\n", s.npnames,
           s.nmap_components, x.nenums, harness_failures);
    glxml_free(&x);
    spec_free(&s);
    return harness_failures ? 1 : 0;
}
