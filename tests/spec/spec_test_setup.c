/* tests/spec/spec_test_setup.c — see spec_test_setup.h. */
#include "spec_test_setup.h"

#include <unistd.h>

static int load_spec(int argc, char **argv, const char *what, spec *s)
{
    if (argc != 3) {
        fprintf(stderr, "usage: %s SPEC.yaml %s\n", argv[0], what);
        return 2;
    }
    char err[1024];
    if (spec_load(argv[1], s, err, sizeof err)) {
        fprintf(stderr, "FAIL: %s\n", err);
        return 1;
    }
    return 0;
}

int spec_test_load_with_glxml(int argc, char **argv, spec *s, glxml *x)
{
    if (argc == 3 && access(argv[2], R_OK) != 0) {
        fprintf(stderr, "FAIL: %s is missing: install the Khronos registry (apt-get install khronos-api)\n",
                argv[2]);
        return 1;
    }
    int rc = load_spec(argc, argv, "GL.xml", s);
    if (rc)
        return rc;
    char err[1024];
    if (glxml_load(argv[2], x, err, sizeof err)) {
        fprintf(stderr, "FAIL: %s\n", err);
        spec_free(s);
        return 1;
    }
    return 0;
}

int spec_test_load_with_file(int argc, char **argv, const char *what, spec *s, FILE **f)
{
    int rc = load_spec(argc, argv, what, s);
    if (rc)
        return rc;
    *f = fopen(argv[2], "r");
    if (!*f) {
        perror(argv[2]);
        spec_free(s);
        return 1;
    }
    return 0;
}
