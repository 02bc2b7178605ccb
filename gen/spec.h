/* gen/spec.h — the parsed GL command spec (spec/gl.yaml, format in
 * spec/README.md). Owns: loading and validating the spec into plain
 * structs. Used by the generator and by tests; never by the runtime (the
 * runtime only sees generated tables). */
#ifndef TSR_GEN_SPEC_H
#define TSR_GEN_SPEC_H

#include <stddef.h>

typedef enum spec_count_kind {
    SPEC_COUNT_NONE,   /* not a pointer */
    SPEC_COUNT_FIXED,  /* fixed: `n` elements */
    SPEC_COUNT_EXPR,   /* product of params and integers: factors[] */
    SPEC_COUNT_PNAME,  /* pname_counts[value of param args[0]] */
    SPEC_COUNT_IMAGE,  /* args: w, h, d, format, type (d may be "1") */
    SPEC_COUNT_BITMAP, /* args: w, h */
    SPEC_COUNT_TYPED,  /* args: n, typeparam */
    SPEC_COUNT_BYTES,  /* args: size param (or integer) */
    SPEC_COUNT_STRING, /* NUL-terminated */
    /* Evaluator control points (glMap1f/glMap2f). args: target, stride,
     * order [, vstride, vorder]; elements addressed =
     * (order-1)*stride [+ (vorder-1)*vstride] + map_components[target]
     * (a separate table: GL_MAP1_VERTEX_3 means 1 value to glGet*). */
    SPEC_COUNT_MAP,
} spec_count_kind;

typedef struct spec_count {
    spec_count_kind kind;
    long fixed;  /* SPEC_COUNT_FIXED */
    char **args; /* names (or integer literals as text) */
    size_t nargs;
} spec_count;

typedef struct spec_param {
    char *name;
    char *type;        /* C type as written: "const GLfloat *" */
    char *base_type;   /* pointee or value type without const/pointer: "GLfloat" */
    int pointer_depth; /* 0 value, 1 pointer, 2 pointer to pointer */
    int is_const;      /* the pointee is const */
    int dir_out;       /* pointer written by the command */
    int nullable;
    spec_count count;
} spec_param;

typedef enum spec_wire { SPEC_WIRE_PACK, SPEC_WIRE_REPLY, SPEC_WIRE_LOCAL, SPEC_WIRE_CUSTOM } spec_wire;

typedef struct spec_command {
    char *name; /* without "gl" */
    int opcode;
    char *category; /* geometry|state|frame|get|object|client|special */
    char *ret;      /* "void", "GLuint", "const GLubyte *" */
    spec_param *params;
    size_t nparams;
    spec_wire wire;
    char *vertex; /* "position" or NULL */
    int khronos;  /* checked against gl.xml */
    int line;     /* line in the YAML file, for messages */
} spec_command;

typedef struct spec_pname_count {
    char *name; /* "GL_AMBIENT" */
    int count;
} spec_pname_count;

typedef struct spec {
    spec_command *cmds; /* in file order */
    size_t ncmds;
    spec_pname_count *pnames;
    size_t npnames;
    spec_pname_count *map_components; /* GL_MAP1_VERTEX_3 -> 3, for SPEC_COUNT_MAP */
    size_t nmap_components;
} spec;

/* Loads and validates `path`. On failure returns -1 and writes one line
 * "FILE:LINE:COL: message" into err. Validation: unique names and opcodes,
 * opcode range, known categories/wire kinds, counts that name existing
 * parameters, pointer params with a count (or wire local/custom). */
int spec_load(const char *path, spec *out, char *err, size_t errsz);
void spec_free(spec *s);
const spec_command *spec_find(const spec *s, const char *name);
/* pname_counts[enum_name] ("GL_AMBIENT" -> 4), or -1 when not listed. */
int spec_pname_count_of(const spec *s, const char *enum_name);
/* map_components[enum_name] ("GL_MAP2_VERTEX_3" -> 3), or -1. */
int spec_map_components_of(const spec *s, const char *enum_name);

#endif
