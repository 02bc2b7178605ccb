/* tests/spec/spec_covers_imports_test.c — test spec_covers_imports: every gl*
 * function in tests/data/gl_imports.txt (what glxgears, xscreensaver-gl and
 * libGLU import from libGL) is a spec command, so the faker exports it.
 * Usage: spec_covers_imports SPEC.yaml gl_imports.txt */
#include "spec_test_setup.h"

#include <stdio.h>
#include <string.h>

#include "harness.h"

int main(int argc, char **argv)
{
    spec s;
    FILE *f;
    int setup = spec_test_load_with_file(argc, argv, "gl_imports.txt", &s, &f);
    if (setup)
        return setup;
    char line[256];
    int lineno = 0, names = 0;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        line[strcspn(line, "\r\n")] = 0;
        if (!line[0] || line[0] == '#')
            continue;
        int gl_name = strncmp(line, "gl", 2) == 0 && line[2] >= 'A' && line[2] <= 'Z';
        CHECK(gl_name, "%s:%d: '%s' is not a gl* function name", argv[2], lineno, line);
        if (!gl_name)
            continue;
        names++;
        CHECK(spec_find(&s, line + 2), "%s:%d: %s is imported by a program but missing from %s", argv[2], lineno, line,
              argv[1]);
    }
    fclose(f);
    printf("%d imported gl functions, %d missing from the spec\n", names, harness_failures);
    CHECK(names > 0, "%s lists no functions", argv[2]);
    spec_free(&s);
    return harness_failures ? 1 : 0;
}
