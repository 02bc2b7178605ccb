/* gen/gen.h — shared pieces of the code generator tsr-gen (a host tool).
 * Owns: the output-file helpers, the C type table (wire sizes and
 * alignments of GL types), the GL enum name table parsed from the GL
 * headers, and the per-command wire layout every emitter agrees on.
 * Never used by the runtime: the runtime sees only the generated code. */
#ifndef TSR_GEN_GEN_H
#define TSR_GEN_GEN_H

#include <stdio.h>
#include <stddef.h>
#include "spec.h"

/* Wire size/alignment of a GL scalar type; 0 size when unknown. */
typedef struct gen_type {
    const char *name; /* "GLfloat" */
    size_t size;      /* bytes on the wire (GLintptr/GLsizeiptr: 8) */
    int is_float;     /* printed with %g */
    int is_signed;
    int is_enum; /* GLenum: printed by name */
} gen_type;

const gen_type *gen_type_find(const char *base);

/* One GL enum from the headers (first name wins for a value). */
typedef struct gen_enum {
    char *name;
    unsigned long long value;
    size_t seq; /* order of appearance: the first name of a value wins */
} gen_enum;

typedef struct gen_enums {
    gen_enum *v;
    size_t n;
} gen_enums;

int gen_enums_parse(gen_enums *e, const char *header_path, char *err, size_t errsz);
void gen_enums_finish(gen_enums *e);
/* Value of a named enum; returns 0 and sets *found=0 when unknown. */
unsigned long long gen_enum_value(const gen_enums *e, const char *name, int *found);

/* How one parameter travels on the wire. */
typedef enum gen_pkind {
    GEN_P_SCALAR, /* value in the fixed part */
    GEN_P_FIXED,  /* pointer with a constant count: inline in the fixed part */
    GEN_P_VAR,    /* input pointer of variable size: u64 length + payload */
    GEN_P_OUT,    /* output pointer: not sent; comes back in the reply */
    GEN_P_NONE,   /* not on the wire (local/custom commands) */
} gen_pkind;

typedef struct gen_param {
    const spec_param *sp;
    gen_pkind kind;
    const gen_type *type; /* value type, or pointee type for pointers (NULL for void) */
    size_t elem_size;     /* pointee element size (1 for void/bytes) */
    size_t offset;        /* GEN_P_SCALAR/GEN_P_FIXED: offset in the fixed part */
    size_t size;          /* GEN_P_SCALAR/GEN_P_FIXED: bytes */
} gen_param;

typedef struct gen_cmd {
    const spec_command *sc;
    int slot; /* index in the dispatch table (spec order) */
    gen_param *params;
    size_t align;        /* alignment of the command's data start */
    size_t fixed_size;   /* bytes of the fixed part (incl. request id) */
    size_t reqid_offset; /* reply commands: offset of the u32 request id */
    int nvar;            /* GEN_P_VAR params */
    int nout;            /* GEN_P_OUT params */
    int is_reply;
    int packable; /* wire pack or reply (generated packer/unpacker) */
    int is_custom, is_local;
    int is_void;
    const gen_type *ret_type; /* NULL for void or pointer returns */
    int ret_is_string;        /* const GLubyte * return */
} gen_cmd;

typedef struct gen {
    const spec *s;
    gen_cmd *cmds; /* same order as s->cmds */
    size_t ncmds;
    gen_enums enums;
    const char *outdir;
} gen;

/* Opens OUTDIR/rel for writing (creating directories); exits the tool on
 * failure (a host tool, not library code). */
FILE *gen_open(const gen *g, const char *rel);
void gen_close(FILE *f);

/* "GLfloat x, GLfloat y" (or "void" when empty and with_void). */
void gen_print_params(FILE *f, const spec_command *c, int with_self, int with_void);
/* "x, y, z" */
void gen_print_args(FILE *f, const spec_command *c, int leading_comma);
/* "GLfloat *" -> "GLfloat *x" formatting of one declaration */
void gen_print_decl(FILE *f, const char *type, const char *name);
int gen_is_void(const char *type);

/* Emits code computing uint64_t tsr_len_NAME (bytes a pointer parameter
 * addresses); jumps to tsr_invalid with tsr_why set when invalid. */
void gen_emit_count(FILE *f, const gen_cmd *gc, const gen_param *gp, const char *modes);
void gen_emit_dispatch(const gen *g);
void gen_emit_wire(const gen *g);
void gen_emit_trace(const gen *g);
void gen_emit_test_support(const gen *g);
void gen_emit_state(const gen *g);

#endif
