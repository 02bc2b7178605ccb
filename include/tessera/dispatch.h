/* tessera/dispatch.h — the dispatch table: one entry per GL command of the
 * spec, each a (function, instance) pair, so every slot can come from a
 * different SPU instance (own code, super SPU, or child) without globals.
 *
 * The table type itself is generated from spec/gl.yaml into
 * tessera/dispatch_gen.h (build tree, installed with the headers):
 *
 *   typedef void (*tsr_fn_Vertex3f)(void *self, GLfloat x, GLfloat y, GLfloat z);
 *   typedef struct tsr_dispatch {
 *       union {
 *           struct { tsr_entry Accum; ...; tsr_entry Vertex3f; ... };
 *           tsr_entry slots[TSR_DISPATCH_COUNT];
 *       };
 *   } tsr_dispatch;
 *   static inline void tsr_call_Vertex3f(const tsr_dispatch *d, GLfloat x, ...);
 *   static inline void tsr_set_Vertex3f(tsr_dispatch *d, tsr_fn_Vertex3f fn, void *self);
 *
 * Use the typed tsr_set_* / tsr_call_* helpers: they check signatures at
 * compile time. The slots[] view is for generic code (loader, recorders). */
#ifndef TESSERA_DISPATCH_H
#define TESSERA_DISPATCH_H

#include <stddef.h>
#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef void (*tsr_proc)(void);

typedef struct tsr_entry {
    tsr_proc fn; /* cast to the slot's tsr_fn_NAME type before calling */
    void *self;  /* the instance the function belongs to */
} tsr_entry;

#ifdef __cplusplus
}
#endif

#include "tessera/dispatch_gen.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Slot index of a command by name ("Vertex3f" or "glVertex3f"), -1 if the
 * spec has no such command. */
TSR_API int tsr_dispatch_slot(const char *name);
/* Name of a slot without the "gl" prefix, NULL when out of range. */
TSR_API const char *tsr_dispatch_name(int slot);
/* Fills every slot with a function that does nothing and returns zero
 * (outputs are left untouched); `self` is ignored. The end of every chain. */
TSR_API void tsr_dispatch_fill_nop(tsr_dispatch *d);

/* What the spec says of a slot's command: its category, and flags. */
typedef enum tsr_cmd_category {
    TSR_CAT_GEOMETRY,
    TSR_CAT_STATE,
    TSR_CAT_FRAME,
    TSR_CAT_GET,
    TSR_CAT_OBJECT,
    TSR_CAT_CLIENT,
    TSR_CAT_SPECIAL
} tsr_cmd_category;
#define TSR_CMD_OUTPUT 1u   /* returns a value or writes through a pointer */
#define TSR_CMD_LOCAL 2u    /* wire: local (client state, never sent) */
#define TSR_CMD_POSITION 4u /* vertex: position (glVertex*) */
/* Category of a slot (tsr_cmd_category), -1 when out of range. */
TSR_API int tsr_dispatch_category(int slot);
TSR_API unsigned tsr_dispatch_flags(int slot);

/* Hooks and tees: generic per-slot wrappers for SPUs that must act around
 * whole classes of commands without writing one function per command.
 * A hook calls before(ctx, slot), then the slot's previous entry (saved in
 * `next` by tsr_dispatch_hook), then after(ctx, slot); either may be NULL.
 * A tee calls `first`, then `second` (whose result it returns). The hook or
 * tee struct is the slot's `self`: it must outlive the table's use. */
typedef struct tsr_hook {
    void (*before)(void *ctx, int slot);
    void (*after)(void *ctx, int slot);
    void *ctx;
    tsr_entry next;
} tsr_hook;
TSR_API void tsr_dispatch_hook(tsr_dispatch *d, int slot, tsr_hook *hook);
typedef struct tsr_tee {
    tsr_entry first, second;
} tsr_tee;
TSR_API void tsr_dispatch_tee(tsr_dispatch *d, int slot, tsr_tee *tee);

#ifdef __cplusplus
}
#endif
#endif
