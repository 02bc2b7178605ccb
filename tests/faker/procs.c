/* tests/faker/procs.c — faker_procs FAKER_DIR NAMES_FILE: for every name in
 * NAMES_FILE (one a line: every gl*, glX* and egl* symbol the faker's
 * libraries define, from nm), glXGetProcAddress, glXGetProcAddressARB
 * (gl*, glX*) and eglGetProcAddress (gl*, egl*) return exactly the
 * symbol's address (dlsym), and each returns NULL for names the faker does
 * not define. Prints the counts checked; fails naming each mismatch. */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef void (*proc)(void);
typedef proc (*glx_gpa)(const unsigned char *);
typedef proc (*egl_gpa)(const char *);

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: faker_procs FAKER_DIR NAMES_FILE\n");
        return 2;
    }
    char path[4096];
    snprintf(path, sizeof path, "%s/libGL.so.1", argv[1]);
    void *gl = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    snprintf(path, sizeof path, "%s/libEGL.so.1", argv[1]);
    void *egl = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!gl || !egl) {
        fprintf(stderr, "FAIL: cannot load the faker: %s\n", dlerror());
        return 1;
    }
    glx_gpa gpa = (glx_gpa)dlsym(gl, "glXGetProcAddress");
    glx_gpa gpa_arb = (glx_gpa)dlsym(gl, "glXGetProcAddressARB");
    egl_gpa egpa = (egl_gpa)dlsym(egl, "eglGetProcAddress");
    if (!gpa || !gpa_arb || !egpa) {
        fprintf(stderr, "FAIL: the faker lacks glXGetProcAddress(ARB) or eglGetProcAddress\n");
        return 1;
    }
    FILE *f = fopen(argv[2], "r");
    if (!f) {
        perror(argv[2]);
        return 1;
    }
    char name[512];
    int failures = 0, ngl = 0, nglx = 0, negl = 0;
    while (fscanf(f, "%511s", name) == 1) {
        int is_egl = !strncmp(name, "egl", 3), is_glx = !strncmp(name, "glX", 3);
        void *lib = is_egl ? egl : gl;
        proc want = (proc)dlsym(lib, name);
        if (!want) {
            printf("FAIL: %s is in the list but dlsym finds nothing\n", name);
            failures++;
            continue;
        }
        if (!is_egl) {
            if (gpa((const unsigned char *)name) != want || gpa_arb((const unsigned char *)name) != want) {
                printf("FAIL: glXGetProcAddress(\"%s\") is not dlsym's %p\n", name, (void *)want);
                failures++;
            }
        }
        if (!is_glx && egpa(name) != want) {
            printf("FAIL: eglGetProcAddress(\"%s\") is not dlsym's %p\n", name, (void *)want);
            failures++;
        }
        if (is_egl)
            negl++;
        else if (is_glx)
            nglx++;
        else
            ngl++;
    }
    fclose(f);
    static const char *const unknown[] = {"glNoSuchFunctionTSR", "glXNoSuchFunction", "eglNoSuchFunction",
                                          "gl", "", "glVertex3", "glVertex3fv_", "glx", "glXSwapBuffersX"};
    for (size_t i = 0; i < sizeof unknown / sizeof unknown[0]; i++) {
        if (gpa((const unsigned char *)unknown[i]) || egpa(unknown[i])) {
            printf("FAIL: GetProcAddress(\"%s\") is not NULL\n", unknown[i]);
            failures++;
        }
    }
    if (gpa(NULL) || egpa(NULL)) {
        printf("FAIL: GetProcAddress(NULL) is not NULL\n");
        failures++;
    }
    /* A sanity floor: the spec alone has hundreds of gl*; GLX/EGL dozens. */
    if (ngl < 1000 || nglx < 30 || negl < 25) {
        printf("FAIL: too few names checked (gl %d, glX %d, egl %d): is the list complete?\n", ngl, nglx, negl);
        failures++;
    }
    printf("checked %d gl*, %d glX*, %d egl* names and %zu unknown ones: %d failures\n", ngl, nglx, negl,
           sizeof unknown / sizeof unknown[0], failures);
    dlclose(egl);
    dlclose(gl);
    return failures ? 1 : 0;
}
