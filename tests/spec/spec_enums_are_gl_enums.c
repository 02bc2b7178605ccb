/* tests/spec/spec_enums_are_gl_enums.c — test spec_enums_are_gl_enums:
 * every enum in pname_counts and map_components is a GL enum of gl.xml,
 * and no two names in one table share a value (the generator switches on
 * the values, so an alias twice would be a duplicate case label, and two
 * different counts for one value would be a lie).
 * Usage: spec_enums_are_gl_enums SPEC.yaml GL.xml */
#include "spec_test_setup.h"

#include <stdio.h>
#include <string.h>

static int check_table(const char *spec_path, const char *what, const spec_pname_count *t, size_t n,
                       const glxml *x)
{
    int failures = 0;
    for (size_t i = 0; i < n; i++) {
        const glxml_enum *e = glxml_find_enum(x, t[i].name);
        if (!e) {
            fprintf(stderr, "FAIL: %s: %s entry %s is not a GL enum in gl.xml\n", spec_path, what, t[i].name);
            failures++;
            continue;
        }
        for (size_t j = 0; j < i; j++) {
            const glxml_enum *o = glxml_find_enum(x, t[j].name);
            if (o && o->value == e->value) {
                fprintf(stderr, "FAIL: %s: %s lists both %s and %s, which are the same value 0x%llx\n",
                        spec_path, what, t[j].name, t[i].name, e->value);
                failures++;
            }
        }
    }
    return failures;
}

int main(int argc, char **argv)
{
    spec s;
    glxml x;
    int setup = spec_test_load_with_glxml(argc, argv, &s, &x);
    if (setup)
        return setup;
    int failures = 0;
    if (s.npnames == 0) {
        fprintf(stderr, "FAIL: %s has no pname_counts\n", argv[1]);
        failures++;
    }
    failures += check_table(argv[1], "pname_counts", s.pnames, s.npnames, &x);
    failures += check_table(argv[1], "map_components", s.map_components, s.nmap_components, &x);
    printf("%zu pname_counts and %zu map_components checked against %zu gl.xml enums, %d problems\n",
           s.npnames, s.nmap_components, x.nenums, failures);
    glxml_free(&x);
    spec_free(&s);
    return failures ? 1 : 0;
}
