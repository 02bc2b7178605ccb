/* faker/faker_gl.h — what the faker's libraries share (libGL.so.1 holds the
 * core; libEGL.so.1 calls it). Never installed, never included outside
 * faker/. Owns: streams (one SPU chain each: one for a program drawing
 * from one thread, one more for each thread drawing at the same time into
 * another share group; threads of one share group share its stream
 * through a lock per call),
 * contexts (each one tessera context of one stream, with its share group,
 * ContextCreateTSR/MakeCurrentTSR), surfaces (an X drawable or a pbuffer:
 * a tessera window of each stream that draws into it,
 * WindowCreateTSR/WindowSizeTSR), the
 * calling thread's current context and surface, and the gl* name table.
 * The faker never creates a GL context on the X server: it reads drawable
 * sizes over its own xcb connection and never touches the application's. */
#ifndef TSR_FAKER_GL_H
#define TSR_FAKER_GL_H

#include <stdbool.h>
#include <stddef.h>

#define TSR_FAKER_API __attribute__((visibility("default")))

typedef struct tsr_faker_proc {
    const char *name;
    void (*proc)(void);
} tsr_faker_proc;

/* Generated (faker_stubs_gen.c): every exported gl*, sorted by name. */
extern const tsr_faker_proc tsr_faker_gl_procs[];
extern const size_t tsr_faker_gl_proc_count;
extern const size_t tsr_faker_gl_stub_count;
extern const char tsr_faker_gl_extensions[];
/* What a stream of chain text `chain_text` offers in GL_EXTENSIONS
 * (offered.c): tsr_faker_gl_extensions less what the chain cannot carry. */
const char *tsr_faker_offered_extensions(const char *chain_text);

/* Logs once per function (the generated stubs call it the first time). */
TSR_FAKER_API void tsr_faker_unsupported(const char *name);

/* Exported gl* entry of `name`, or NULL. */
TSR_FAKER_API void (*tsr_faker_gl_proc(const char *name))(void);
/* Sorted-table lookup shared by the GLX and EGL tables. */
TSR_FAKER_API void (*tsr_faker_lookup(const tsr_faker_proc *table, size_t n, const char *name))(void);

typedef struct tsr_faker_context tsr_faker_context;
typedef struct tsr_faker_surface tsr_faker_surface;

/* Logs through libtessera's log with a "faker: " prefix. level: TSR_LOG_*. */
TSR_FAKER_API void tsr_faker_log(int level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* A context sharing objects with `share` (NULL: none; every context of the
 * process is in one share group of the chain's renderer anyway). NULL when
 * the chain cannot be made (logged). */
TSR_FAKER_API tsr_faker_context *tsr_faker_context_create(tsr_faker_context *share);
/* Destroyed now, or when it stops being current (as GLX/EGL say). */
TSR_FAKER_API void tsr_faker_context_destroy(tsr_faker_context *ctx);

/* A surface for X drawable `xid` of the display named `display_name`
 * (the same surface for the same drawable), or a pbuffer (xid 0) of the
 * given size. NULL when the size cannot be read (logged). */
TSR_FAKER_API tsr_faker_surface *tsr_faker_surface_window(const char *display_name, unsigned long xid);
TSR_FAKER_API tsr_faker_surface *tsr_faker_surface_pbuffer(int width, int height);
TSR_FAKER_API void tsr_faker_surface_destroy(tsr_faker_surface *s);
TSR_FAKER_API void tsr_faker_surface_size(const tsr_faker_surface *s, int *width, int *height);
/* The X drawable's size now (a round trip over the faker's connection, as
 * a real glXQueryDrawable makes); a pbuffer's own size. The stream
 * follows a new size at the next swap, glViewport or MakeCurrent. */
TSR_FAKER_API void tsr_faker_surface_x_size(tsr_faker_surface *s, int *width, int *height);
/* Size and depth of X drawable `xid` (a pixmap) of display `display_name`,
 * read over the faker's own connection; false when it cannot be read. */
TSR_FAKER_API bool tsr_faker_drawable_geometry(const char *display_name, unsigned long xid, int *width, int *height,
                                               int *depth);
/* Finds the surface of a drawable without creating it (NULL: none). */
TSR_FAKER_API tsr_faker_surface *tsr_faker_surface_find(unsigned long xid);

/* Whether `s` has a back buffer (its config is double-buffered) and how
 * many samples (0: single-sampled), set before it first becomes current:
 * its tessera windows are then told so (WindowBuffersTSR: GL_BACK and
 * GL_FRONT are two buffers; WindowSamplesTSR: multisample buffers). Later
 * calls change nothing. */
TSR_FAKER_API void tsr_faker_surface_set_config(tsr_faker_surface *s, bool double_buffered, int samples);
/* Makes ctx current on this thread drawing into `draw` (NULL ctx: none
 * current; NULL draw: surfaceless). false: failed (logged). */
TSR_FAKER_API bool tsr_faker_make_current(tsr_faker_context *ctx, tsr_faker_surface *draw);
/* The calling thread's last tsr_faker_make_current failed because the
 * context is current on another thread, or another thread drawing into
 * its share group's stream did not reach a check point in time to share
 * it (core.c; EGL_BAD_ACCESS; logged). */
TSR_FAKER_API bool tsr_faker_make_current_refused_busy(void);
TSR_FAKER_API tsr_faker_context *tsr_faker_current_context(void);
/* End of frame of `s`: SwapBuffersTSR through the current context's
 * table, then the drawable's size is checked (resize: WindowSizeTSR). */
TSR_FAKER_API void tsr_faker_swap(tsr_faker_surface *s);
/* glFinish through the current context (WaitGL). */
TSR_FAKER_API void tsr_faker_finish(void);

#endif
