/* tests/faker/procs_test.c — faker_procs FAKER_DIR NAMES_FILE: for every name in
 * NAMES_FILE (one a line: every gl*, glX* and egl* symbol the faker's
 * libraries define, from nm), glXGetProcAddress, glXGetProcAddressARB
 * (gl*, glX*) and eglGetProcAddress (gl*, egl*) return exactly the
 * symbol's address (dlsym), and each returns NULL for names the faker does
 * not define. Prints the counts checked; fails naming each mismatch. */
#include <dlfcn.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

typedef void (*proc)(void);
typedef proc (*glx_gpa)(const unsigned char *);
typedef proc (*egl_gpa)(const char *);

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: faker_procs FAKER_DIR NAMES_FILE\n");
        return 2;
    }
    setvbuf(stdout, NULL, _IOLBF, 0); /* in order with the reports on stderr */
    char path[4096];
    snprintf(path, sizeof path, "%s/libGL.so.1", argv[1]);
    void *gl = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    snprintf(path, sizeof path, "%s/libEGL.so.1", argv[1]);
    void *egl = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    REQUIRE(gl && egl, "cannot load the faker: %s", dlerror());
    glx_gpa gpa = (glx_gpa)dlsym(gl, "glXGetProcAddress");
    glx_gpa gpa_arb = (glx_gpa)dlsym(gl, "glXGetProcAddressARB");
    egl_gpa egpa = (egl_gpa)dlsym(egl, "eglGetProcAddress");
    REQUIRE(gpa && gpa_arb && egpa, "the faker lacks glXGetProcAddress(ARB) or eglGetProcAddress");
    FILE *f = fopen(argv[2], "r");
    REQUIRE(f, "%s: %s", argv[2], strerror(errno));
    char name[512];
    int ngl = 0, nglx = 0, negl = 0;
    while (fscanf(f, "%511s", name) == 1) {
        int is_egl = !strncmp(name, "egl", 3), is_glx = !strncmp(name, "glX", 3);
        void *lib = is_egl ? egl : gl;
        proc want = (proc)dlsym(lib, name);
        CHECK(want, "%s is in the list but dlsym finds nothing", name);
        if (!want)
            continue;
        if (!is_egl)
            CHECK(gpa((const unsigned char *)name) == want && gpa_arb((const unsigned char *)name) == want,
                  "glXGetProcAddress(\"%s\") is not dlsym's %p", name, (void *)want);
        if (!is_glx)
            CHECK(egpa(name) == want, "eglGetProcAddress(\"%s\") is not dlsym's %p", name, (void *)want);
        if (is_egl)
            negl++;
        else if (is_glx)
            nglx++;
        else
            ngl++;
    }
    fclose(f);
    static const char *const unknown[] = {
        "glNoSuchFunctionTSR", "glXNoSuchFunction", "eglNoSuchFunction", "gl", "", "glVertex3", "glVertex3fv_", "glx",
        "glXSwapBuffersX"};
    for (size_t i = 0; i < sizeof unknown / sizeof unknown[0]; i++)
        CHECK(!gpa((const unsigned char *)unknown[i]) && !egpa(unknown[i]), "GetProcAddress(\"%s\") is not NULL",
              unknown[i]);
    CHECK(!gpa(NULL) && !egpa(NULL), "GetProcAddress(NULL) is not NULL");
    /* A sanity floor: the spec alone has hundreds of gl*; GLX/EGL dozens. */
    CHECK(ngl >= 1000 && nglx >= 30 && negl >= 25,
          "too few names checked (gl %d, glX %d, egl %d): is the list complete?", ngl, nglx, negl);
    printf("checked %d gl*, %d glX*, %d egl* names and %zu unknown ones: %d failures\n", ngl, nglx, negl,
           sizeof unknown / sizeof unknown[0], harness_failures);
    dlclose(egl);
    dlclose(gl);
    return harness_failures ? 1 : 0;
}
