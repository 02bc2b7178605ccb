/* tests/faker/maps_at_exit.c — LD_PRELOAD'ed by tests/faker/only_faker.sh
 * into programs that end by themselves (glxinfo, a piglit test, apitrace's
 * replayers): at exit it copies the process's /proc/self/maps, which then
 * holds every library it loaded, including those it dlopen'ed, to
 * $FAKER_MAPS_DIR/maps.PID. Depends on libc only; does nothing else. */
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

__attribute__((destructor)) static void copy_maps_at_exit(void)
{
    const char *dir = getenv("FAKER_MAPS_DIR");
    if (!dir)
        return;
    char path[4096];
    snprintf(path, sizeof path, "%s/maps.%ld", dir, (long)getpid());
    FILE *in = fopen("/proc/self/maps", "r"), *out = fopen(path, "w");
    char buf[8192];
    size_t n;
    while (in && out && (n = fread(buf, 1, sizeof buf, in)) > 0)
        fwrite(buf, 1, n, out);
    if (in)
        fclose(in);
    if (out)
        fclose(out);
}
