/* gen/gen_test.c — placeholder while step 1 lands. */
#include "gen.h"
void gen_emit_test_support(const gen *g) { fclose(gen_open(g, "src/wire_test_gen.h")); fclose(gen_open(g, "src/wire_test_gen.c")); }
