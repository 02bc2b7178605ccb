/* bench/faker/swap_stamp.c — an LD_PRELOAD object for exec_startup_ms: at
 * a program's first glXSwapBuffers (or eglSwapBuffers) it lets the real
 * one run (the faker's under `tessera exec`, the system's natively), then
 * writes the CLOCK_REALTIME nanoseconds to $SWAP_STAMP_FILE and ends the
 * process with status 0, so both runs are timed the same way: from the
 * launch to the first frame's swap returning. Benchmark-only, never
 * installed. */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE
#endif
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>

static void stamp_and_exit(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    const char *path = getenv("SWAP_STAMP_FILE");
    FILE *f = path ? fopen(path, "w") : NULL;
    if (f) {
        fprintf(f, "%lld\n", (long long)ts.tv_sec * 1000000000LL + ts.tv_nsec);
        fclose(f);
    }
    _exit(0);
}

void glXSwapBuffers(void *dpy, unsigned long drawable)
{
    void (*real)(void *, unsigned long) = (void (*)(void *, unsigned long))dlsym(RTLD_NEXT, "glXSwapBuffers");
    if (real)
        real(dpy, drawable);
    stamp_and_exit();
}

unsigned eglSwapBuffers(void *dpy, void *surface)
{
    unsigned (*real)(void *, void *) = (unsigned (*)(void *, void *))dlsym(RTLD_NEXT, "eglSwapBuffers");
    if (real)
        real(dpy, surface);
    stamp_and_exit();
    return 1;
}
