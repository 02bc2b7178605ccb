/* tessera/options.h — typed SPU options: the declarations an SPU publishes
 * and the validated values it receives. Values are parsed and range-checked
 * by the loader before create() runs, so an SPU never sees a bad value. */
#ifndef TESSERA_OPTIONS_H
#define TESSERA_OPTIONS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "tessera/error.h"
#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum tsr_option_type {
    TSR_OPT_BOOL,
    TSR_OPT_INT,
    TSR_OPT_FLOAT,
    TSR_OPT_STRING,
    TSR_OPT_ENUM,     /* one of `choices` */
    TSR_OPT_INT_LIST, /* written "1,2,3" in text form */
    TSR_OPT_FLOAT_LIST,
    TSR_OPT_STRING_LIST,
} tsr_option_type;

typedef struct tsr_option_spec {
    const char *name; /* lower_snake_case */
    tsr_option_type type;
    const char *default_value; /* text form, parsed like user input; NULL = empty */
    double min, max;           /* numeric range (also list elements); ignored when min > max */
    const char *choices;       /* TSR_OPT_ENUM: "grid|broadcast|balanced" */
    const char *help;          /* one line */
} tsr_option_spec;

/* Validated option values of one SPU instance (opaque). Accessors take the
 * option's declared name; asking for an undeclared name or the wrong type
 * is a programming error and returns 0 / NULL with a logged message. */
typedef struct tsr_options tsr_options;

/* "bool", "int", "float", "string", "enum", "int list", ... */
TSR_API const char *tsr_option_type_name(tsr_option_type type);

/* Checks one text value against one declaration without keeping it
 * (`spu` names the SPU in the message). */
TSR_API int tsr_option_check_value(const char *spu, const tsr_option_spec *spec, const char *text, tsr_error *err);

TSR_API bool tsr_options_bool(const tsr_options *o, const char *name);
TSR_API int64_t tsr_options_int(const tsr_options *o, const char *name);
TSR_API double tsr_options_float(const tsr_options *o, const char *name);
/* TSR_OPT_STRING and TSR_OPT_ENUM. */
TSR_API const char *tsr_options_string(const tsr_options *o, const char *name);
TSR_API size_t tsr_options_count(const tsr_options *o, const char *name);
TSR_API int64_t tsr_options_int_at(const tsr_options *o, const char *name, size_t i);
TSR_API double tsr_options_float_at(const tsr_options *o, const char *name, size_t i);
TSR_API const char *tsr_options_string_at(const tsr_options *o, const char *name, size_t i);

#ifdef __cplusplus
}
#endif
#endif
