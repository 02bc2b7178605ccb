/* mothership/faker.h — whether an app node's program runs under the faker
 * (faker/: tessera's libGL.so.1/libEGL.so.1/libOpenGL.so.0), as `tessera
 * exec` runs it. Decided from the program file itself, so graphs need no
 * key for it: a program whose ELF dynamic section names libtessera_gl (the
 * examples) already enters its chain; any other program (glxgears, a
 * script, a static or 32-bit binary) gets the faker's directory first in
 * LD_LIBRARY_PATH (harmless for a program that loads no GL).
 * Owns nothing; never runs the program or loads it. */
#ifndef TSR_MOTHERSHIP_FAKER_H
#define TSR_MOTHERSHIP_FAKER_H

#include <stdbool.h>

/* true when the ELF file at `path` has a DT_NEEDED libtessera_gl.so*. */
bool tsr_ms_links_tessera_gl(const char *path);

/* The faker's directory: $TESSERA_FAKER_DIR when it holds libGL.so.1
 * (the tessera program sets it for the nodes it starts), else NULL. */
const char *tsr_ms_faker_dir(void);

#endif
