/* tests/spec/spec_test_setup.c — see spec_test_setup.h. */
#include "spec_test_setup.h"

#include <errno.h>
#include <unistd.h>

#include "harness.h"

static int load_spec(int argc, char **argv, const char *what, spec *s)
{
    if (argc != 3) {
        fprintf(stderr, "usage: %s SPEC.yaml %s\n", argv[0], what);
        return 2;
    }
    char err[1024];
    REQUIRE(spec_load(argv[1], s, err, sizeof err) == 0, "%s", err);
    return 0;
}

int spec_test_load_with_glxml(int argc, char **argv, spec *s, glxml *x)
{
    REQUIRE(argc != 3 || access(argv[2], R_OK) == 0,
            "%s is missing: install the Khronos registry (apt-get install khronos-api)", argv[2]);
    int rc = load_spec(argc, argv, "GL.xml", s);
    if (rc)
        return rc;
    char err[1024];
    REQUIRE(glxml_load(argv[2], x, err, sizeof err) == 0, "%s", err);
    return 0;
}

int spec_test_load_with_file(int argc, char **argv, const char *what, spec *s, FILE **f)
{
    int rc = load_spec(argc, argv, what, s);
    if (rc)
        return rc;
    *f = fopen(argv[2], "r");
    REQUIRE(*f, "%s: %s", argv[2], strerror(errno));
    return 0;
}
