/* tests/spec/glxml.h — a small reader for the Khronos registry gl.xml,
 * just enough for the spec tests: command signatures and enum values.
 * Owns: the parsed tables (glxml_free). Never used outside tests; never
 * trusts the file: malformed XML is an error, not a crash. */
#ifndef TSR_TESTS_GLXML_H
#define TSR_TESTS_GLXML_H

#include <stddef.h>

typedef struct glxml_param {
    char *name;
    char *type;  /* C type text with the name removed: "const GLchar *const*" */
    char *group; /* enum group of a GLenum parameter ("LightParameter") or NULL */
} glxml_param;

typedef struct glxml_command {
    char *name; /* "glLightfv" */
    char *ret;  /* "void", "const GLubyte *" */
    glxml_param *params;
    size_t nparams;
    int line;       /* line of <command> in gl.xml */
    int gl_version; /* first GL version requiring it, major*10+minor; 0 if none */
} glxml_command;

typedef struct glxml_enum {
    char *name; /* "GL_AMBIENT" */
    unsigned long long value;
    char *groups;   /* comma-separated group list ("GetPName,LightParameter") or NULL */
    int gl_version; /* first GL version requiring it, major*10+minor (21 = 2.1); 0 if none */
} glxml_enum;

typedef struct glxml {
    glxml_command *cmds;
    size_t ncmds;
    glxml_enum *enums;
    size_t nenums;
} glxml;

/* Reads `path`; on failure returns -1 with "PATH:LINE: message" in err. */
int glxml_load(const char *path, glxml *out, char *err, size_t errsz);
void glxml_free(glxml *x);
const glxml_command *glxml_find_command(const glxml *x, const char *name);
const glxml_enum *glxml_find_enum(const glxml *x, const char *name);
/* Whether enum `e` belongs to group `group` (exact name in e->groups). */
int glxml_enum_in_group(const glxml_enum *e, const char *group);

/* Canonical form of a C type for comparison: identifiers and '*' separated
 * by single spaces, "GLvoid" read as "void" ("const GLchar *const*" ->
 * "const GLchar * const *"). Writes into buf; returns buf. */
char *glxml_normalise_type(const char *type, char *buf, size_t bufsz);

#endif
