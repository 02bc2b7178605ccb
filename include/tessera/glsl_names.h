/* tessera/glsl_names.h — a renderer's map from the stream's shader and
 * program names to its GL driver's names.
 *
 * Why: glCreateShader/glCreateProgram return a name the driver picks. A
 * sender that tracks programs (tessera/dev/state.h: tilesort, replicate with late
 * joiners) allocates names itself, like glGen*, and creates objects with
 * CreateShaderTSR(name, type) / CreateProgramTSR(name), so a renderer that
 * gets a program lazily, or joins late, knows it under the same name as
 * the others even though its driver handed out different ones. A plain
 * glCreateShader (pack: a round trip to one server) still works: the
 * driver's name becomes the stream's name when that name is free.
 *
 * Owns: the two maps (stream -> driver, driver -> stream) and a copy of the
 * table slots it wraps. Installed on a renderer's table (the render SPU,
 * tests): every slot that takes or returns a shader or program name is
 * wrapped, and glGet(GL_CURRENT_PROGRAM) is mapped back. A name the stream
 * never created reaches the driver as a name it never gave out (GL's
 * INVALID_VALUE, as for an unknown name). Entries live until the driver
 * hands out the same name again (a deleted shader may still be attached,
 * so its name stays valid in the stream until then). Never: calls GL
 * other than through the wrapped slots; keeps global state. */
#ifndef TESSERA_GLSL_NAMES_H
#define TESSERA_GLSL_NAMES_H

#include <GL/gl.h>

#include "tessera/dispatch.h"
#include "tessera/error.h"
#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct tsr_glsl_names tsr_glsl_names;

/* Wraps the shader/program slots of `table` (fill it first: the current
 * slots are the ones called). The map must outlive the table's use. */
TSR_API tsr_glsl_names *tsr_glsl_names_create(tsr_dispatch *table, tsr_error *err);
TSR_API void tsr_glsl_names_destroy(tsr_glsl_names *m);
/* The driver's name of stream name `name` (0 for 0; statistics, tests). */
TSR_API GLuint tsr_glsl_names_driver(const tsr_glsl_names *m, GLuint name);

#ifdef __cplusplus
}
#endif
#endif
