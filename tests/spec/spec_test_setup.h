/* tests/spec/spec_test_setup.h — the start every spec test shares: check
 * the command line (SPEC.yaml plus one more file), load the spec, and
 * either load gl.xml or open a data file. When anything is missing a
 * REQUIRE of tests/harness.h reports it and exits 1 (the tests fail,
 * never skip). */
#ifndef TSR_TESTS_SPEC_TEST_SETUP_H
#define TSR_TESTS_SPEC_TEST_SETUP_H

#include <stdio.h>

#include "glxml.h"
#include "spec.h"

/* argv[1] = SPEC.yaml, argv[2] = the Khronos gl.xml. 0 = both loaded
 * (free with spec_free / glxml_free); 2 = usage; a failure exits 1. */
int spec_test_load_with_glxml(int argc, char **argv, spec *s, glxml *x);
/* argv[1] = SPEC.yaml, argv[2] = a data file (`what` names it in the
 * usage line). 0 = loaded and *f open; 2 = usage; a failure exits 1. */
int spec_test_load_with_file(int argc, char **argv, const char *what, spec *s, FILE **f);

#endif
