/* gen/gen_trace.c — placeholder while step 1 lands. */
#include "gen.h"
void gen_emit_trace(const gen *g) { fclose(gen_open(g, "src/trace_gen.h")); fclose(gen_open(g, "src/trace_gen.c")); }
