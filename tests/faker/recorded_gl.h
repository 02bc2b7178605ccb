/* tests/faker/recorded_gl.h — what the drivers that hold tessera's answers
 * next to OSMesa's share (gl21_commands_driver.c, extensions_driver.c,
 * client_arrays_driver.c; gl21_commands.sh runs each twice and compares
 * the files they write): one GL context current on a RECORDED_GL_W x
 * RECORDED_GL_H surface with depth 24 and stencil 8 (OSMesa's own when
 * built with RECORDED_GL_NATIVE, else an EGL pbuffer through the faker),
 * and the checksummed lines of what a driver reads back.
 *
 * Owns: the context and surface it opens (one per process).
 * Never: judges a result; the runner compares the files. */
#ifndef TESTS_FAKER_RECORDED_GL_H
#define TESTS_FAKER_RECORDED_GL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define RECORDED_GL_W 64
#define RECORDED_GL_H 48

/* FNV-1a of n bytes: the checksum of every read-back line. */
uint32_t recorded_gl_fnv(const void *data, size_t n);

/* The start of a driver's main: takes its one argument, the file to
 * write, opens it and makes the context current on its surface with the
 * viewport on the whole of it; prints the usage and exits 2 without the
 * argument, exits 1 with a message when it cannot. Returns the file. */
FILE *recorded_gl_start(int argc, char **argv);

/* The end: writes the last glGetError, closes the file (exits 1 when it
 * cannot), releases and destroys the context and surface. */
void recorded_gl_end(FILE *out, const char *path);

/* 1 when the current context's GL_EXTENSIONS names `name` whole. */
int recorded_gl_has_extension(const char *name);

/* One line to out: label and glGetError's answer (which it clears). */
void recorded_gl_error_line(FILE *out, const char *label);

/* glGetIntegerv's first value of GLenum `pname`; -7 when GL wrote none. */
int recorded_gl_int(unsigned pname);

/* One line to out: label, the checksum of the whole RGBA colour buffer
 * and its centre pixel. */
void recorded_gl_frame(FILE *out, const char *label);

#endif
