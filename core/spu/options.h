/* core/spu/options.h — internal: parsing and validating SPU option text against
 * the declarations of an SPU class and its supers (tessera/options.h is the
 * SPU-facing half). Owns: tsr_options values and their memory.
 * Never: accepts a value it cannot represent exactly as declared. */
#ifndef TSR_CORE_OPTIONS_H
#define TSR_CORE_OPTIONS_H

#include <stddef.h>

#include "tessera/error.h"
#include "tessera/dev/util.h"
#include "tessera/options.h"

/* The options one class declares itself. The option set of an SPU is its
 * own group followed by its super's groups, nearest first; a name declared
 * twice resolves to the nearest declaration (a subclass may override a
 * default). */
typedef struct tsr_option_group {
    const char *owner; /* class name, for messages */
    const tsr_option_spec *specs;
    size_t count;
} tsr_option_group;

/* Checks a class's declarations: lower_snake_case unique names, known types,
 * enum choices, and that every default parses and is in range. Messages name
 * `spu`: "bad: option 'width': bad default: 'abc' is not an integer". */
int tsr_option_specs_check(const char *spu, const tsr_option_spec *specs, size_t count, tsr_error *err);

/* The nearest declaration of `name`, or NULL. */
const tsr_option_spec *tsr_option_groups_find(const tsr_option_group *groups, size_t ngroups, const char *name);

/* Parses `count` key=value pairs for the SPU `spu` against its option set;
 * undeclared keys, keys given twice and bad values fail with a message
 * naming the SPU, the option and the value (with a did-you-mean suggestion
 * for misspelt names). Options not given take their declared defaults.
 * Returns NULL with `err` filled on failure. */
tsr_options *tsr_options_parse(const char *spu, const tsr_option_group *groups, size_t ngroups, const char *const *keys,
                               const char *const *values, size_t count, tsr_error *err);
void tsr_options_free(tsr_options *options);


#endif
