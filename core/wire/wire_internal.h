/* core/wire/wire_internal.h — the packer and unpacker runtime functions that
 * only the generated packers and decoders (pack_gen.c, unpack_gen.c) call:
 * variable-size commands, replies, dropped commands. Shared by core/wire/
 * pack.c and unpack.c, which define them, and the generated code of
 * libtessera. Not exported and never installed: an SPU packs through the
 * dispatch table (tessera/dev/pack.h) and decodes with tsr_unpacker_run
 * (tessera/dev/unpack.h). */
#ifndef TSR_CORE_WIRE_INTERNAL_H
#define TSR_CORE_WIRE_INTERNAL_H

#include <stddef.h>
#include <stdint.h>
#include <GL/gl.h>
#include "tessera/dispatch.h"
#include "tessera/error.h"
#include "tessera/dev/pack.h"
#include "tessera/dev/unpack.h"

/* --- per-context client state (contexts.c) ------------------------------------ */

/* Records of one size, each beginning with its GLint context number: the
 * mirrors of a stream's contexts other than the current one. */
typedef struct tsr_wire_contexts tsr_wire_contexts;
void *tsr_wire_contexts_find(tsr_wire_contexts *t, GLint context);
/* A zeroed record of `size` bytes for `context` (the table made at the
 * first); NULL when out of memory. */
void *tsr_wire_contexts_add(tsr_wire_contexts **t, GLint context, size_t size);
void tsr_wire_contexts_remove(tsr_wire_contexts *t, GLint context);
void tsr_wire_contexts_free(tsr_wire_contexts *t);

/* --- selection and feedback (select.c) ---------------------------------------- */

/* Per context: the program's buffers (packer) or the ones given to GL
 * (unpacker, owned), and the render mode the receiver reported. */
typedef struct tsr_wire_selection tsr_wire_selection;
void tsr_wire_selection_free(tsr_wire_selection *s);
/* `context` is gone: its record and buffers are dropped. */
void tsr_wire_selection_forget(tsr_wire_selection *s, GLint context);
/* glGetPointerv of GL_SELECTION_BUFFER_POINTER / GL_FEEDBACK_BUFFER_POINTER:
 * the program's buffer (returns 1); other pnames return 0. */
int tsr_packer_answer_GetPointerv(tsr_packer *p, GLenum pname, void **params);

/* --- packer ------------------------------------------------------------------ */

/* Reserves `size` data bytes (aligned) for opcode and records the opcode;
 * the caller fills the bytes. Handles extended opcodes and any size. */
uint8_t *tsr_packer_cmd_var(tsr_packer *p, uint32_t opcode, uint64_t size, size_t align);
/* Records an error for a command that cannot be packed and drops it. */
void tsr_packer_drop(tsr_packer *p, const char *command, const char *why);
/* Flushes and fetches the reply to request `id`; NULL on failure (error
 * recorded). */
const uint8_t *tsr_packer_request(tsr_packer *p, uint32_t id, size_t *size);
/* The reply being decoded is malformed (`why`): recorded, and the sink's
 * reply_failed told, since the answering side is at fault. */
void tsr_packer_reply_bad(tsr_packer *p, const char *command, const char *why);
/* Reads reply item `*pos` (advancing it): returns the bytes and sets *len;
 * NULL when the reply is malformed (tsr_packer_reply_bad). */
const uint8_t *tsr_packer_reply_item(tsr_packer *p, const uint8_t *r, size_t rsize, size_t *pos, uint64_t *len,
                                     const char *command);
/* Keeps a copy of a returned string for the packer's lifetime. */
const GLubyte *tsr_packer_keep_string(tsr_packer *p, const uint8_t *s, uint64_t len);
/* glIsEnabled of a client array (GL_VERTEX_ARRAY, ...): answered from the
 * mirror (returns 1); other caps go to the receiver (returns 0). */
int tsr_packer_answer_IsEnabled(tsr_packer *p, GLenum cap, GLboolean *out);
/* glGet{Boolean,Integer,Float,Double}v (as: GL_BOOL, GL_INT, GL_FLOAT,
 * GL_DOUBLE) of client-array state the receiver never sees (sizes, types,
 * strides, per-array buffer bindings, enables, the client active texture):
 * answered from the mirror (returns 1); other pnames return 0. */
int tsr_packer_answer_client_get(tsr_packer *p, GLenum pname, GLenum as, void *data);
/* glEnable/glDisable (on 1/0) of a client array: the mirror's enable set,
 * returns 1 (nothing is sent); other caps return 0. */
int tsr_packer_local_enable_array(tsr_packer *p, GLenum cap, int on);
/* A GL error the packer found without the receiver (a query whose pname
 * the wire cannot size): kept until glGetError takes it (the first one
 * stays, as GL keeps its error flag); take returns it once, then 0. */
void tsr_packer_local_error(tsr_packer *p, GLenum error);
/* With a GL_PIXEL_PACK_BUFFER bound (returns 1; 0 otherwise, nothing
 * done): the get `command` (its opcode) with its `nargs` arguments before
 * the pointer, whose pointer `offset` is an offset into that buffer, is
 * sent as a PackBufferGetTSR: the answer stays in the receiver's buffer
 * (pack_buffer_get.c). */
int tsr_packer_get_into_pack_buffer(tsr_packer *p, uint32_t command, const GLint *args, int nargs, const void *offset);
/* The stream's GLSL object names (generated hooks of glCreateShader,
 * glCreateProgram and their TSR forms): `name` is a shader (is_program 0)
 * or a program (1). Names stay known after glDelete*: a deleted shader
 * still attached to a program keeps its name, and the receiver answers a
 * call on one that is gone. */
/* Buffers deleted: their mappings (glMapBuffer's client copies) go, as GL
 * unmaps a deleted buffer (pack_map.c). */
void tsr_packer_forget_mappings(tsr_packer *p, GLsizei n, const GLuint *buffers);
/* glGetBufferParameteriv of GL_BUFFER_MAPPED, GL_BUFFER_ACCESS,
 * GL_BUFFER_ACCESS_FLAGS, GL_BUFFER_MAP_OFFSET or GL_BUFFER_MAP_LENGTH
 * while the buffer bound to `target` is mapped here: answered from the
 * mapping (returns 1); otherwise 0 and the receiver answers (its buffer,
 * never mapped, answers as GL does for one that is not). */
int tsr_packer_answer_buffer_mapping(tsr_packer *p, GLenum target, GLenum pname, GLint *params);
/* 1 while the buffer bound to `target` is mapped (glMapBuffer's client
 * copy, pack_map.c). */
int tsr_packer_buffer_mapped(tsr_packer *p, GLenum target);
void tsr_packer_note_glsl_name(tsr_packer *p, GLuint name, int is_program);
/* The error GL raises for a shader call (glShaderSource) on `name` before
 * it reads the call's pointers: GL_INVALID_OPERATION for a program's name,
 * GL_INVALID_VALUE for a name the stream never created; 0 for a shader,
 * or when the packer cannot tell (it lost a name to a failed allocation). */
GLenum tsr_packer_shader_name_error(const tsr_packer *p, GLuint name);
void tsr_packer_glsl_names_free(struct tsr_packer_glsl_names *n);

/* --- unpacker ---------------------------------------------------------------- */

/* Decodes `nops` commands of `data` (`len` bytes) into `d` (generated). */
int tsr_unpack_commands(tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *data, uint32_t nops, size_t len,
                        tsr_error *err);
/* Zero-filled, 8-aligned space for `n` outputs of the given sizes; -1 when
 * their total exceeds max_output or memory runs out. */
int tsr_unpacker_outputs(tsr_unpacker *u, int n, const uint64_t *sizes, uint8_t **ptrs);
/* Builds the reply (tessera/dev/wire.h section 5) and hands it to the callback.
 * ret_len TSR_WIRE_NULL: the command returns nothing. */
int tsr_unpacker_reply(tsr_unpacker *u, uint32_t id, const void *ret, uint64_t ret_len, int n, const uint64_t *sizes,
                       uint8_t *const *ptrs, tsr_error *err);

/* Budgeted streams (tsr_unpacker_set_limits): the buffer objects the
 * stream binds, sizes and deletes, followed before each is dispatched
 * (generated hooks). check_BufferData fails (TSR_EPROTO, `err` naming the
 * budget) when the new size would pass max_buffer_bytes; the command is
 * then not dispatched. All do nothing while limits are off. */
void tsr_unpacker_note_BindBuffer(tsr_unpacker *u, GLenum target, GLuint buffer);
void tsr_unpacker_note_DeleteBuffers(tsr_unpacker *u, GLsizei n, const GLuint *buffers);
int tsr_unpacker_check_BufferData(tsr_unpacker *u, GLenum target, GLsizeiptr size, tsr_error *err);
/* Pixel store and buffer bindings are per context (tessera/dev/unpack.h):
 * MakeCurrentTSR swaps them in, ContextDestroyTSR drops a context's. */
void tsr_unpacker_note_MakeCurrent(tsr_unpacker *u, GLint context);
void tsr_unpacker_note_ContextDestroy(tsr_unpacker *u, GLint context);

#endif
