/* spus/tilesort/instance.h — one tilesort instance, and what its files
 * (tilesort.c, send.c, lists.c, arrays.c, frame.c, gets.c, fbo.c, copy.c) call
 * across one another. Private to the SPU; bucket.c, batch.c and split.c do not see
 * the instance (tilesort.h). */
#ifndef TSR_TILESORT_INSTANCE_H
#define TSR_TILESORT_INSTANCE_H

#include "tessera/dev/client.h"
#include "tessera/dev/pack.h"
#include "tessera/dev/state.h"
#include "tessera/dev/unpack.h"
#include "tilesort.h"

#ifndef GL_FRAMEBUFFER_EXT
#define GL_FRAMEBUFFER_EXT 0x8D40
#endif

/* ts_current (the current attributes): tilesort.h, shared with split.c */

typedef struct ts_chunk {
    uint8_t *data;
    size_t size;
} ts_chunk;

typedef struct ts_list {
    GLuint name;
    uint32_t version; /* 0: slot free */
    ts_chunk *chunks;
    size_t nchunks, cap;
    float mn[3], mx[3];
    int boxed;              /* mn/mx hold the box of its vertices */
    int unknown;            /* holds commands a box cannot place: every server gets its calls */
    int has_state;          /* its calls change state: replayed into the tracker */
    int calls;              /* it calls lists */
    int geometry;           /* it draws itself (not only through the lists it calls) */
    int unexpandable;       /* holds commands a call cannot be expanded into (lists.c: expand_list) */
    tsr_pixel_modes unpack; /* unpack modes it was compiled under */
    struct {
        GLenum target;
        GLuint name;
    } * textures; /* the textures it binds (sent before it runs) */
    size_t ntextures;
} ts_list;

typedef struct ts_server {
    struct tilesort *ts;
    size_t index;
    tsr_state_shadow *shadow;
    tsr_packer *packer;
    tsr_dispatch table;     /* the packer's functions */
    tsr_pack_sink inner;    /* the client's sink for this server */
    uint32_t tiles_version; /* of the tiling last sent (0: none) */
    uint32_t *lists;        /* per list slot: version the server has */
    size_t lists_cap;
    uint64_t frame_bytes, bytes;
    ts_batch sorted; /* primitives of a sorted array draw waiting for this server */
} ts_server;

/* No single target: the geometry buffer goes where its box says. */
#define TS_ANY_TARGET SIZE_MAX

/* A glMaterial call made inside glBegin/glEnd (send.c). */
typedef struct ts_material {
    int slot; /* which of Materialf, fv, i, iv */
    GLenum face, pname;
    union {
        GLfloat f[4];
        GLint i[4];
    } v;
} ts_material;

typedef struct tilesort {
    char name[96];
    tsr_stream_client *client;
    size_t nservers;
    ts_server *srv;
    uint64_t *frame_geometry; /* per server: of its frame_bytes, geometry buffers and display lists */
    ts_tiling tiling;
    uint32_t tiling_version;
    char *assemble;      /* PNG pattern of the gathered window, or NULL */
    bool assemble_alpha; /* assemble= PNGs keep the alpha (else RGB) */
    size_t batch_bytes;  /* geometry is bucketed in batches of about this size */
    tsr_state_tracker *tracker;
    bool texture_limits_known; /* the tracker has the servers' texture limits (gets.c) */
    GLint copy_max_size[3]; /* copy.c: the first server's GL_MAX_TEXTURE_SIZE, _CUBE_MAP_, _RECTANGLE_ (0: not asked) */
    tsr_state_ctx *ctx;
    tsr_packer *geo;
    tsr_dispatch geo_table, track_table, normal, record;
    tsr_dispatch *live;
    unsigned char route[TSR_DISPATCH_COUNT];
    tsr_hook hooks[TSR_DISPATCH_COUNT];
    tsr_tee tees[TSR_DISPATCH_COUNT];
    tsr_hook rec_hooks[TSR_DISPATCH_COUNT];
    tsr_tee rec_tees[TSR_DISPATCH_COUNT];
    /* the geometry buffer */
    int in_begin, split_primitive, broadcast_next, program;
    /* GL_SELECT or GL_FEEDBACK: the pass runs on render_server alone, whole
     * (gets.c's ts_RenderMode says why); GL_RENDER otherwise */
    GLenum render_mode;
    size_t render_server;
    /* the program's bound draw framebuffer object (fbo.c), 0: the window.
     * While one is bound, everything drawn goes to every server whole. */
    GLuint app_fb;
    /* its bound read framebuffer object, 0: the window (reads and blits
     * from it gather the tiles: frame.c, copy.c, blit.c) */
    GLuint app_read_fb;
    /* occlusion queries (queries.c): the one being counted (0: none) and
     * those that counted drawing into an FBO, which every server drew */
    GLuint query_active;
    GLuint *fbo_queries;
    size_t nfbo_queries, fbo_queries_cap;
    tsr_tee query_tees[2];
    GLenum gl_error;        /* made here (ts_gl_error): answered first */
    ts_material *materials; /* glMaterial inside glBegin/glEnd, in this buffer (send.c) */
    size_t nmaterials, materials_cap;
    ts_split *split;      /* split.c: a primitive cut across buffers */
    ts_current start;     /* current attributes when this buffer started */
    size_t *buffer_lists; /* list slots called by this buffer */
    size_t nbuffer_lists, buffer_lists_cap;
    int buffer_calls_any; /* glCallLists: every list may be called */
    uint8_t *hit;
    size_t *targets;
    size_t last_targets;  /* how many of targets[] the last flushed buffer went to */
    tsr_dispatch discard; /* no-ops: diffs that only update a shadow */
    /* array draws sorted primitive by primitive */
    size_t only_target; /* TS_ANY_TARGET, or the one server the buffer is for */
    ts_batch compact;   /* scratch: a sorted draw as one server would get it (statistics), or
                               one batch of a glDrawElements that is not sorted */
    uint8_t *gathered;  /* scratch: gathered arrays and 16-bit indices */
    size_t gathered_cap;
    /* display lists */
    ts_list *lists;
    size_t nlists;
    uint32_t list_versions;
    tsr_packer *list_packer;
    tsr_dispatch list_table;
    ts_list *recording;
    int recording_execute;
    tsr_unpacker *replay;
    int replay_depth;
    tsr_unpacker *expand; /* runs an expanded list's commands through the normal routes */
    /* window and frames */
    int win_w, win_h;
    int grid_cols, grid_rows; /* option grid: tiles follow the window; 0: fixed tiles */
    /* fixed tiles reaching outside the window: why (empty: they fit). The
     * application ends at the next swap or read of pixels if the window
     * has not grown to them by then (frame.c). */
    char tiles_misfit[400];
    uint64_t frames;
    /* statistics: the stream packed once, and bytes per server per frame */
    uint64_t stream_bytes;
    /* what one server of a 1x1 configuration would get besides the stream:
     * its diffs, taken into a shadow of its own and counted, never sent */
    tsr_state_shadow *solo;
    tsr_packer *solo_packer;
    tsr_dispatch solo_table;
    uint64_t *frame_rows;          /* frames_kept rows of nservers counts */
    uint64_t *frame_geometry_rows; /* frames_kept rows of nservers: their geometry part */
    double *frame_seconds;         /* application time of each kept frame (swap to swap) */
    double *frame_costs;           /* frames_kept rows of nservers: seconds each server reported (< 0: none) */
    double *frame_fault_costs;     /* the same rows: the part of those seconds that were page faults */
    uint64_t *frame_pixels;        /* frames_kept rows of nservers: pixels of each server's tiles that frame */
    double last_swap;              /* monotonic seconds of the last swap (or of creation) */
    size_t frames_kept, frames_cap;
    tsr_error error; /* first failure, reported once */
} tilesort;

/* --- tilesort.c --------------------------------------------------------------- */
/* Keeps the first failure and logs it (later ones are dropped). */
void ts_report(tilesort *t, const tsr_error *e);
void ts_keep_frame_row(tilesort *t);

/* --- send.c: the geometry buffer and its servers ------------------------------ */
/* The current attributes now become the start of the next buffer. */
void ts_snapshot(tilesort *t);
void ts_prepare_server(tilesort *t, ts_server *s, int geometry);
void ts_flush_geometry(tilesort *t);
void ts_flush_before_state(tilesort *t);
void ts_broadcast_next(tilesort *t);
void ts_Materialf(void *self, GLenum face, GLenum pname, GLfloat param);
void ts_Materialfv(void *self, GLenum face, GLenum pname, const GLfloat *params);
void ts_Materiali(void *self, GLenum face, GLenum pname, GLint param);
void ts_Materialiv(void *self, GLenum face, GLenum pname, const GLint *params);
ts_server *ts_to_server(tilesort *t);
/* --- gets.c ----------------------------------------------------------------- */
/* A GL error made here, as GL keeps one: the first, until glGetError. */
void ts_gl_error(tilesort *t, GLenum error);
double ts_box_margin(const tilesort *t);
/* The same for a box of filled polygons only (triangles, quads). */
double ts_polygon_margin(const tilesort *t);
/* The application's viewport, or the window's while it never set one. */
const GLint *ts_viewport(const tilesort *t, GLint out[4]);
void ts_count_solo_diff(tilesort *t);
int ts_geo_sink_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err);
int ts_server_sink_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err);
int ts_server_sink_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err);
void ts_Begin(void *self, GLenum mode);
void ts_End(void *self);

/* --- lists.c: display lists --------------------------------------------------- */
void ts_list_clear(ts_list *l);
int ts_list_sink_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err);
void ts_send_buffer_lists(tilesort *t, ts_server *s);
void ts_CallList(void *self, GLuint name);
void ts_CallLists(void *self, GLsizei n, GLenum type, const GLvoid *lists);
void ts_NewList(void *self, GLuint name, GLenum mode);
void ts_EndList(void *self);
void ts_DeleteLists(void *self, GLuint first, GLsizei range);
/* in the tracker's table: a called list's state calls replayed */
void ts_replay_CallList(void *self, GLuint name);
void ts_replay_CallLists(void *self, GLsizei n, GLenum type, const GLvoid *lists);
/* in the table used while compiling a list */
void ts_rec_CallList(void *self, GLuint name);
void ts_rec_CallLists(void *self, GLsizei n, GLenum type, const GLvoid *lists);
void ts_rec_BindTexture(void *self, GLenum target, GLuint name);

/* --- arrays.c: array draws ---------------------------------------------------- */
void ts_DrawArrays(void *self, GLenum mode, GLint first, GLsizei count);
void ts_DrawElements(void *self, GLenum mode, GLsizei count, GLenum type, const void *indices);
void ts_DrawRangeElements(void *self, GLenum mode, GLuint start, GLuint end, GLsizei count, GLenum type,
                          const void *indices);
void ts_MultiDrawArrays(void *self, GLenum mode, const GLint *first, const GLsizei *count, GLsizei drawcount);
void ts_MultiDrawElements(void *self, GLenum mode, const GLsizei *count, GLenum type, const void *const *indices,
                          GLsizei drawcount);

/* --- frame.c: frames, the window, gathered pixels ----------------------------- */
void ts_WindowCreateTSR(void *self, GLint window, GLsizei w, GLsizei h);
void ts_WindowSizeTSR(void *self, GLint window, GLsizei w, GLsizei h);
void ts_SwapBuffersTSR(void *self, GLint window, GLbitfield flags);
void ts_ReadPixels(void *self, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type, void *pixels);

/* --- pack_buffer.c: gets into the program's pixel pack buffer ---------------- */
/* 1 when a pack buffer is bound and the call was made (into it); 0: not
 * bound, the caller answers as usual. */
int ts_pack_buffer_read_pixels(tilesort *t, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type,
                               void *pixels);
int ts_pack_buffer_stipple(tilesort *t, GLubyte *mask);
void ts_GetTexImage(void *self, GLenum target, GLint level, GLenum format, GLenum type, void *pixels);
void ts_GetCompressedTexImage(void *self, GLenum target, GLint level, void *img);
void ts_GetPixelMapfv(void *self, GLenum map, GLfloat *values);
void ts_GetPixelMapuiv(void *self, GLenum map, GLuint *values);
void ts_GetPixelMapusv(void *self, GLenum map, GLushort *values);

/* --- gets.c ------------------------------------------------------------------- */
void ts_GetBooleanv(void *self, GLenum p, GLboolean *o);
void ts_GetIntegerv(void *self, GLenum p, GLint *o);
GLint ts_RenderMode(void *self, GLenum mode);
void ts_GetFloatv(void *self, GLenum p, GLfloat *o);
void ts_GetDoublev(void *self, GLenum p, GLdouble *o);
void ts_GetLightfv(void *self, GLenum l, GLenum p, GLfloat *o);
void ts_GetMaterialfv(void *self, GLenum f, GLenum p, GLfloat *o);
void ts_GetTexEnvfv(void *self, GLenum tg, GLenum p, GLfloat *o);
void ts_GetTexGenfv(void *self, GLenum c, GLenum p, GLfloat *o);
void ts_GetTexParameterfv(void *self, GLenum tg, GLenum p, GLfloat *o);
void ts_GetTexParameterIivEXT(void *self, GLenum tg, GLenum p, GLint *o);
void ts_GetTexParameterIuivEXT(void *self, GLenum tg, GLenum p, GLuint *o);
void ts_GetTexLevelParameteriv(void *self, GLenum tg, GLint lv, GLenum p, GLint *o);
void ts_GetClipPlane(void *self, GLenum p, GLdouble *o);
void ts_GetPolygonStipple(void *self, GLubyte *o);
void ts_GetBufferParameteriv(void *self, GLenum tg, GLenum p, GLint *o);
GLboolean ts_IsEnabled(void *self, GLenum cap);
GLenum ts_GetError(void *self);
void ts_GetShaderiv(void *self, GLuint shader, GLenum pname, GLint *out);
void ts_GetProgramiv(void *self, GLuint program, GLenum pname, GLint *out);
void ts_GetShaderInfoLog(void *self, GLuint shader, GLsizei size, GLsizei *length, GLchar *log);
void ts_GetProgramInfoLog(void *self, GLuint program, GLsizei size, GLsizei *length, GLchar *log);
GLint ts_GetUniformLocation(void *self, GLuint program, const GLchar *name);
void ts_GetUniformfv(void *self, GLuint program, GLint location, GLfloat *out);
void ts_GetUniformiv(void *self, GLuint program, GLint location, GLint *out);
GLint ts_GetAttribLocation(void *self, GLuint program, const GLchar *name);
void ts_GetActiveAttrib(void *self, GLuint program, GLuint index, GLsizei size, GLsizei *length, GLint *n, GLenum *type,
                        GLchar *name);
void ts_GetActiveUniform(void *self, GLuint program, GLuint index, GLsizei size, GLsizei *length, GLint *n,
                         GLenum *type, GLchar *name);
void ts_GetAttachedShaders(void *self, GLuint program, GLsizei max, GLsizei *count, GLuint *shaders);
void ts_GetShaderSource(void *self, GLuint shader, GLsizei size, GLsizei *length, GLchar *source);
GLboolean ts_IsShader(void *self, GLuint shader);
GLboolean ts_IsProgram(void *self, GLuint program);
void ts_ActiveTexture(void *self, GLenum texture);
void ts_TexImage1D(void *self, GLenum target, GLint level, GLint internalformat, GLsizei width, GLint border,
                   GLenum format, GLenum type, const void *pixels);
void ts_TexImage2D(void *self, GLenum target, GLint level, GLint internalformat, GLsizei width, GLsizei height,
                   GLint border, GLenum format, GLenum type, const void *pixels);
void ts_TexImage3D(void *self, GLenum target, GLint level, GLint internalformat, GLsizei width, GLsizei height,
                   GLsizei depth, GLint border, GLenum format, GLenum type, const void *pixels);
/* fbo.c: the program's framebuffer objects, replicated on every server */
int ts_fbo_command(const char *name); /* an FBO command every server gets at once */
/* a get GL answers from the bound framebuffer (its draw and read buffers)
 * while a program FBO is bound: the first server answers, not the tracker */
int ts_fbo_get_asks_server(const tilesort *t, GLenum pname);
void ts_BindFramebufferEXT(void *self, GLenum target, GLuint framebuffer);
void ts_BindFramebuffer(void *self, GLenum target, GLuint framebuffer);
void ts_DeleteFramebuffersEXT(void *self, GLsizei n, const GLuint *framebuffers);
void ts_DeleteFramebuffers(void *self, GLsizei n, const GLuint *framebuffers);
void ts_fbo_send_texture(tilesort *t, GLenum textarget, GLuint texture);
void ts_FramebufferTexture1D(void *self, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                             GLint level);
void ts_FramebufferTexture2D(void *self, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                             GLint level);
void ts_FramebufferTexture3D(void *self, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                             GLint level, GLint zoffset);
void ts_FramebufferTextureLayer(void *self, GLenum target, GLenum attachment, GLuint texture, GLint level, GLint layer);
void ts_FramebufferTexture1DEXT(void *self, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                                GLint level);
void ts_FramebufferTexture2DEXT(void *self, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                                GLint level);
void ts_FramebufferTexture3DEXT(void *self, GLenum target, GLenum attachment, GLenum textarget, GLuint texture,
                                GLint level, GLint zoffset);
void ts_GenerateMipmapEXT(void *self, GLenum target);
void ts_GenerateMipmap(void *self, GLenum target);
void ts_DrawBuffer(void *self, GLenum buf);
void ts_DrawBuffers(void *self, GLsizei n, const GLenum *bufs);
void ts_ReadBuffer(void *self, GLenum buf);
/* --- copy.c: copies of the window's pixels, gathered ---------------------------- */
void ts_CopyPixels(void *self, GLint x, GLint y, GLsizei w, GLsizei h, GLenum type);
void ts_CopyTexImage1D(void *self, GLenum target, GLint level, GLenum ifmt, GLint x, GLint y, GLsizei w, GLint border);
void ts_CopyTexImage2D(void *self, GLenum target, GLint level, GLenum ifmt, GLint x, GLint y, GLsizei w, GLsizei h,
                       GLint border);
void ts_CopyTexSubImage1D(void *self, GLenum target, GLint level, GLint xo, GLint x, GLint y, GLsizei w);
void ts_CopyTexSubImage2D(void *self, GLenum target, GLint level, GLint xo, GLint yo, GLint x, GLint y, GLsizei w,
                          GLsizei h);
void ts_CopyTexSubImage3D(void *self, GLenum target, GLint level, GLint xo, GLint yo, GLint zo, GLint x, GLint y,
                          GLsizei w, GLsizei h);
void *ts_copy_gather(tilesort *t, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type);
void ts_copy_upload_2d(tilesort *t, GLenum ifmt, GLsizei w, GLsizei h, GLint x, GLint y, GLsizei sw, GLsizei sh,
                       GLenum format, GLenum type, const void *pixels);
/* --- blit.c: glBlitFramebuffer, its window source gathered ----------------------- */
void ts_BlitFramebuffer(void *self, GLint sx0, GLint sy0, GLint sx1, GLint sy1, GLint dx0, GLint dy0, GLint dx1,
                        GLint dy1, GLbitfield mask, GLenum filter);
/* queries.c */
void ts_queries_install(tilesort *t);
void ts_queries_fbo_bound(tilesort *t);
void ts_GetQueryObjectuiv(void *self, GLuint id, GLenum pname, GLuint *params);
void ts_GetQueryObjectiv(void *self, GLuint id, GLenum pname, GLint *params);

#endif
