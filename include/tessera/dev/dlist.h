/* tessera/dev/dlist.h — the display-list recorder: keeps the contents of
 * every display list a GL stream defines, so a sender can replay a list's
 * state calls into its state tracker when the application calls it
 * (tessera/dev/state.h tracks list names only) and define every list again
 * on a renderer that joins late (replicate) or needs it lazily (tilesort).
 * Part of libtessera (pkg-config tessera).
 *
 * Owns: one body per list name (the commands between glNewList and
 * glEndList, packed into wire buffers by its own packer:
 * tessera/dev/pack.h), the packer and unpackers that write and read them,
 * and a copy of the table calls go on to (`next`). Never: executes a
 * compiled command itself, or keeps a host pointer (bodies hold bytes
 * only).
 *
 *   tsr_dispatch next;                       // e.g. a state tracker's table
 *   tsr_dispatch_fill_nop(&next);
 *   tsr_state_fill_dispatch(ctx, &next);
 *   tsr_dlist_store *lists = tsr_dlist_create(&next, &err);
 *   const tsr_dispatch *in = tsr_dlist_table(lists);   // give the stream to `in`
 *   ... on glCallList(n): tsr_dlist_call(lists, n, &next, &err);
 *   ... a renderer joins: tsr_dlist_define_all(lists, its_packer_table, &err);
 *   tsr_dlist_destroy(lists);
 *
 * Use: build `next` first (e.g. a state tracker's table), create the store
 * with it, and give every call of the stream to tsr_dlist_table(). Outside
 * a list every call goes straight on to `next`. Between glNewList and
 * glEndList the calls GL compiles go into the body, and the calls GL runs
 * at once even while compiling (OpenGL 2.1 section 5.4: client state,
 * pixel store, object creation/deletion, buffer objects, queries, Flush,
 * Finish, and tessera's *TSR frame and window commands) go on to `next`.
 * NewList, EndList and DeleteLists reach `next` too (the tracker keeps the
 * names). GL_COMPILE_AND_EXECUTE is recorded like GL_COMPILE and the list
 * is then called into `next` (tsr_dlist_call) at glEndList: the same
 * result, except that an immediate command inside such a list reaches
 * `next` before the list's other commands instead of among them.
 *
 * A body is self-contained: it starts with the unpack pixel-store values
 * in force at glNewList (when not GL's defaults), so images inside it
 * decode the same whenever it is replayed; the vertex-array pointers and
 * buffer bindings a recorded glDrawArrays/glDrawElements needs are in the
 * body too. Those immediate commands are recording artefacts: the call
 * replay (tsr_dlist_call) filters them out, and tsr_dlist_define_all puts
 * the renderer's pixel store and buffer bindings back to GL's defaults
 * after sending the bodies.
 *
 * Not thread-safe: one store per stream, used by one thread. */
#ifndef TESSERA_DEV_DLIST_H
#define TESSERA_DEV_DLIST_H

#include <stddef.h>
#include <stdint.h>
#include <GL/gl.h>
#include "tessera/dispatch.h"
#include "tessera/error.h"
#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* GL's limit on nested glCallList (GL_MAX_LIST_NESTING is at least 64);
 * deeper calls are ignored, as GL ignores them. */
#define TSR_DLIST_MAX_NESTING 64

typedef struct tsr_dlist_store tsr_dlist_store;

/* `next`'s slots are copied now (set them up first). */
TSR_API tsr_dlist_store *tsr_dlist_create(const tsr_dispatch *next, tsr_error *err);
TSR_API void tsr_dlist_destroy(tsr_dlist_store *s);

/* The table to give the stream to (stable for the store's lifetime; its
 * contents switch between "pass on" and "record" at NewList/EndList). */
TSR_API const tsr_dispatch *tsr_dlist_table(tsr_dlist_store *s);

/* 0 outside a list, else GL_COMPILE or GL_COMPILE_AND_EXECUTE. */
TSR_API GLenum tsr_dlist_recording(const tsr_dlist_store *s);
/* Number of lists with a body, and whether `list` has one. */
TSR_API size_t tsr_dlist_count(const tsr_dlist_store *s);
TSR_API int tsr_dlist_has(const tsr_dlist_store *s, GLuint list);
/* Bytes held in bodies (statistics). */
TSR_API uint64_t tsr_dlist_bytes(const tsr_dlist_store *s);

/* Calls `out` with the commands GL runs when list `list` is called (the
 * recording artefacts filtered out). A glCallList/glCallLists inside the
 * body reaches out's CallList/CallLists slot: a caller that wants nested
 * lists followed calls tsr_dlist_call from there (nesting is bounded by
 * TSR_DLIST_MAX_NESTING). `out`'s slots are copied the first time a
 * table is passed (per nesting level): pass another table, not the same
 * one changed. An unknown list does nothing. Returns TSR_OK or
 * the unpacker's error (a body is our own bytes: never expected). */
TSR_API int tsr_dlist_call(tsr_dlist_store *s, GLuint list, const tsr_dispatch *out, tsr_error *err);

/* Defines every list again through `out` (a renderer's packer table):
 * NewList(name, GL_COMPILE), the body, EndList; then sets the unpack and
 * pack pixel store and the array and element buffer bindings back to GL's
 * defaults if a body changed them, so the renderer's state is GL's initial
 * state apart from the lists (a state diff from a fresh shadow follows).
 * Returns the number of lists defined, or -1 with `err` filled. */
TSR_API long tsr_dlist_define_all(tsr_dlist_store *s, const tsr_dispatch *out, tsr_error *err);

#ifdef __cplusplus
}
#endif
#endif
