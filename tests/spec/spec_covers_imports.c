/* tests/spec/spec_covers_imports.c — test spec_covers_imports: every gl*
 * function in tests/data/gl_imports.txt (what glxgears, xscreensaver-gl and
 * libGLU import from libGL) is a spec command, so the faker exports it.
 * Usage: spec_covers_imports SPEC.yaml gl_imports.txt */
#include "spec_test_setup.h"

#include <stdio.h>
#include <string.h>

int main(int argc, char **argv)
{
    spec s;
    FILE *f;
    int setup = spec_test_load_with_file(argc, argv, "gl_imports.txt", &s, &f);
    if (setup)
        return setup;
    char line[256];
    int lineno = 0, failures = 0, names = 0;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        line[strcspn(line, "\r\n")] = 0;
        if (!line[0] || line[0] == '#')
            continue;
        if (strncmp(line, "gl", 2) != 0 || line[2] < 'A' || line[2] > 'Z') {
            fprintf(stderr, "FAIL: %s:%d: '%s' is not a gl* function name\n", argv[2], lineno, line);
            failures++;
            continue;
        }
        names++;
        if (!spec_find(&s, line + 2)) {
            fprintf(stderr, "FAIL: %s:%d: %s is imported by a program but missing from %s\n", argv[2], lineno,
                    line, argv[1]);
            failures++;
        }
    }
    fclose(f);
    printf("%d imported gl functions, %d missing from the spec\n", names, failures);
    if (names == 0) {
        fprintf(stderr, "FAIL: %s lists no functions\n", argv[2]);
        failures++;
    }
    spec_free(&s);
    return failures ? 1 : 0;
}
