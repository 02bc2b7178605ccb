/* tessera/dev/state.h — the GL state tracker (docs/architecture.md). Part
 * of libtessera (pkg-config tessera).
 *
 * What it is for: an SPU that sends one stream to several renderers
 * (tilesort, replicate's late joiners) keeps the application's GL state
 * here instead of broadcasting state calls, and before it sends geometry to
 * a renderer it asks for a *diff*: the GL calls that turn what that
 * renderer has into what the application has, and nothing else.
 *
 * Owns: the tracked contexts, the renderers' shadows, copies of the
 * objects' contents (texture images, buffer data, shader sources) and the
 * dirty bits between them. Never: calls GL, or calls on from a tracking
 * slot (the tracker's table only records); a diff emits only through the
 * table it is given, and never a get (no reply is needed).
 *
 * Use (one renderer behind a packer):
 *
 *   tsr_state_tracker *t = tsr_state_tracker_create(&err);
 *   tsr_state_ctx *c = tsr_state_ctx_create(t, &err);     // the application's context
 *   tsr_state_shadow *r = tsr_state_shadow_create(t, &err); // one per renderer
 *   tsr_dispatch track;
 *   tsr_dispatch_fill_nop(&track);
 *   tsr_state_fill_dispatch(c, &track);    // give the stream's calls to `track` too
 *   ... before geometry goes to the renderer:
 *   tsr_state_diff(c, r, packer_table, NULL);  // only what the renderer lacks
 *   tsr_state_tracker_destroy(t);          // and every context and shadow
 *
 * Objects (all caller-owned, no globals):
 *   tsr_state_tracker  one per sending SPU instance: the set of tracked
 *                      contexts and renderers that can meet each other.
 *   tsr_state_ctx      one per application GL context: every value the
 *                      spec's state commands set, texture, buffer,
 *                      shader and program objects, list names, client
 *                      arrays.
 *   tsr_state_shadow   one per remote renderer: the tracker's model of the
 *                      values that renderer holds right now.
 *
 * Dirty bits are hierarchical and per renderer: every context keeps one bit
 * per (node, renderer) where the nodes are a root, ~15 groups (lighting,
 * texture, ...) and ~90 members (light 3, texture unit 2's env, ...); a
 * group's bit is the OR of its members', the root's the OR of the groups'.
 * Bit vectors grow with the renderer ids (no fixed maximum of renderers or
 * contexts). Invariant: when bit (ctx, member, r) is clear, that member of
 * ctx equals the shadow of r. So:
 *   - a setter sets the member, group and root bits for every renderer;
 *   - a diff visits only dirty groups, then dirty members, compares values,
 *     emits only what differs, updates the shadow and clears r's bits; an
 *     unchanged context costs one word test;
 *   - a member the diff changed on renderer r is marked dirty for r in
 *     every *other* context, so a context switch on one renderer (diff ctx
 *     A, then ctx B into the same shadow) emits only where A and B differ.
 *
 * Diffs emit through a tsr_dispatch: a packer's table (to pack the diff
 * for one server), the render SPU's table (apply it directly), or any SPU.
 * Objects travel lazily: a diff uploads only the texture objects bound in
 * some unit (parameters, then the log of image calls replayed in order from
 * the tracker's own tightly packed copy of the pixels, each under the
 * pixel-transfer and GL_GENERATE_MIPMAP settings it was made with) and the
 * buffer objects bound or sourced by enabled arrays, and remembers per
 * renderer which version of each object it has. Objects are per context;
 * when two contexts meet on one renderer, an object under the same name
 * with the same content (64-bit content hash) is recognised, not resent.
 *
 * Shaders and programs are objects too: names are
 * allocated here in one namespace (max used + 1, never reused), so
 * glCreateShader/glCreateProgram need no round trip; renderers create them
 * with CreateShaderTSR/CreateProgramTSR under these names and map them to
 * their driver's (tessera/glsl_names.h). The tracker keeps each shader's
 * source and last compiled source, each program's attachments, attribute
 * bindings, what its last glLinkProgram linked (shader sources and
 * bindings at that moment, kept even when the shaders are deleted) and a
 * log of the uniform calls made since, compacted as later calls cover
 * earlier ones. A diff gives a renderer the current program (created,
 * compiled and linked from those inputs, then the uniform calls it lacks);
 * tsr_state_send_shader/_program give it any other one (before a get the
 * renderer must answer), tsr_state_send_glsl_all every one (late joiners).
 * Uniform locations come from a renderer (glGetUniformLocation): the same
 * link inputs on the same Mesa give the same locations on every renderer
 * (tests/state: glsl_* tests).
 *
 * Display lists: only their names are tracked here, and state calls made
 * inside glNewList(GL_COMPILE) are not applied (GL records them). What a
 * glCallList does to the state is not known to the tracker: the sender,
 * which keeps the list contents (tilesort, next), replays the list's state
 * calls into the tracker's table when the application calls the list.
 *
 * Getting: tsr_state_get_* answer glGet*, glIsEnabled, glGetLight*, ... from
 * the tracker (return 1) when the value is client-known; 0 means "ask the
 * renderer" (implementation limits, strings, GL errors, ...).
 *
 * What is not tracked, and why, is listed in tsr_state_untracked[]; the
 * test state_covers_spec checks that every `state`,
 * `object` and `client` command of spec/gl.yaml is either implemented by
 * tsr_state_fill_dispatch or listed there.
 *
 * The value structs below still grow with the spec: code built against one
 * version of this header must not assume their layout in another (read
 * them through this header, rebuild with the library). */
#ifndef TESSERA_DEV_STATE_H
#define TESSERA_DEV_STATE_H

#include <stddef.h>
#include <stdint.h>
#include <GL/gl.h>
#include <GL/glext.h>
#include "tessera/dispatch.h"
#include "tessera/error.h"
#include "tessera/export.h"
#include "tessera/dev/pixel.h"

#ifdef __cplusplus
extern "C" {
#endif

/* GL implementation limits the tracker models (Mesa's fixed-function
 * values; a call beyond them is ignored, as GL ignores it with an error).
 * Texture units come in two kinds: the first TSR_STATE_UNITS are
 * coordinate units (GL_MAX_TEXTURE_COORDS: texture environment, coordinate
 * generation, enables, matrices, current coordinates, client arrays), and
 * every unit up to GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS is an image unit
 * (a binding per target and a LOD bias: what shaders sample). The tracker
 * holds TSR_STATE_IMAGE_UNITS image units, Mesa's combined count (llvmpipe:
 * 32 per shader stage, 6 stages); tsr_state_tracker_set_image_units
 * narrows them to the renderers'. */
#define TSR_STATE_UNITS 8
#define TSR_STATE_IMAGE_UNITS 192
#define TSR_STATE_LIGHTS 8
#define TSR_STATE_CLIP_PLANES 8 /* GL_MAX_CLIP_PLANES of Mesa (the spec asks at least 6) */
#define TSR_STATE_ATTRIBS 16
#define TSR_STATE_MODELVIEW_DEPTH 32
#define TSR_STATE_PROJECTION_DEPTH 32
#define TSR_STATE_TEXTURE_DEPTH 10
#define TSR_STATE_ATTRIB_DEPTH 16

/* Texture targets, index of tsr_state_texunit.binding[]. */
enum { TSR_TEX_1D, TSR_TEX_2D, TSR_TEX_3D, TSR_TEX_CUBE, TSR_TEX_TARGETS };

/* --- groups and members of the dirty-bit tree ------------------------------ */
typedef enum tsr_state_group {
    TSR_SG_ENABLE,
    TSR_SG_CURRENT,
    TSR_SG_VIEWPORT,
    TSR_SG_COLORBUF,
    TSR_SG_DEPTH,
    TSR_SG_STENCIL,
    TSR_SG_FOG,
    TSR_SG_LIGHTING,
    TSR_SG_RASTER,
    TSR_SG_HINT,
    TSR_SG_TEXTURE,
    TSR_SG_BUFFER,
    TSR_SG_MISC,
    TSR_SG_PIXEL,
    TSR_SG_TRANSFORM,
    TSR_SG_PROGRAM,
    TSR_SG_COUNT
} tsr_state_group;

typedef enum tsr_state_member {
    /* ENABLE: the two words of the enable bitmap */
    TSR_SM_ENABLE0,
    TSR_SM_ENABLE1,
    /* CURRENT */
    TSR_SM_COLOR,
    TSR_SM_NORMAL,
    TSR_SM_TEXCOORD0,
    TSR_SM_EDGEFLAG = TSR_SM_TEXCOORD0 + TSR_STATE_UNITS,
    TSR_SM_ATTRIBS,
    /* VIEWPORT */
    TSR_SM_VIEWPORT,
    TSR_SM_DEPTHRANGE,
    TSR_SM_SCISSOR,
    /* COLORBUF */
    TSR_SM_BLEND,
    TSR_SM_ALPHAFUNC,
    TSR_SM_LOGICOP,
    TSR_SM_COLORMASK,
    TSR_SM_CLEARCOLOR,
    TSR_SM_DRAWBUFFER,
    TSR_SM_CLEARACCUM,
    /* DEPTH, STENCIL, FOG */
    TSR_SM_DEPTH,
    TSR_SM_STENCIL,
    TSR_SM_FOG,
    /* LIGHTING */
    TSR_SM_LIGHT0,
    TSR_SM_LIGHTMODEL = TSR_SM_LIGHT0 + TSR_STATE_LIGHTS,
    TSR_SM_COLORMATERIAL,
    TSR_SM_MATERIAL,
    TSR_SM_SHADEMODEL,
    /* RASTER */
    TSR_SM_POLYGON,
    TSR_SM_STIPPLE,
    TSR_SM_LINE,
    TSR_SM_POINT,
    /* HINT */
    TSR_SM_HINT,
    /* TEXTURE: per coordinate unit its image unit's bindings (+ the bound
     * objects) and LOD bias; the image units past them in one member (the
     * diff looks only at the units ever set: image_units_set); per
     * coordinate unit env, texgen */
    TSR_SM_TEXBIND0,
    TSR_SM_TEXBIND_IMAGE = TSR_SM_TEXBIND0 + TSR_STATE_UNITS,
    TSR_SM_TEXENV0,
    TSR_SM_TEXGEN0 = TSR_SM_TEXENV0 + TSR_STATE_UNITS,
    /* BUFFER: bindings (+ the bound objects) */
    TSR_SM_BUFBIND = TSR_SM_TEXGEN0 + TSR_STATE_UNITS,
    /* MISC */
    TSR_SM_LISTBASE,
    TSR_SM_MULTISAMPLE,
    /* PIXEL */
    TSR_SM_PIXELSTORE,
    TSR_SM_PIXELMODE,
    /* TRANSFORM: matrix stacks, clip planes */
    TSR_SM_MODELVIEW,
    TSR_SM_PROJECTION,
    TSR_SM_TEXMAT0,
    TSR_SM_CLIP = TSR_SM_TEXMAT0 + TSR_STATE_UNITS,
    /* PROGRAM: the current program (+ the program objects) */
    TSR_SM_PROGRAM,
    TSR_SM_COUNT
} tsr_state_member;

/* Name of a group ("lighting"), for tests and statistics. */
TSR_API const char *tsr_state_group_name(int group);
/* Group of a member. */
TSR_API int tsr_state_member_group(int member);

/* --- the values ------------------------------------------------------------ */
typedef struct tsr_state_light {
    GLfloat ambient[4], diffuse[4], specular[4];
    GLfloat position[4];       /* eye coordinates (transformed when set) */
    GLfloat spot_direction[3]; /* eye coordinates */
    GLfloat spot_exponent, spot_cutoff, attenuation[3];
} tsr_state_light;

typedef struct tsr_state_material {
    GLfloat ambient[4], diffuse[4], specular[4], emission[4], shininess;
} tsr_state_material;

typedef struct tsr_state_texgen {
    GLenum mode;
    GLfloat object_plane[4];
    GLfloat eye_plane[4]; /* eye coordinates */
} tsr_state_texgen;

/* A texture image unit: what glBindTexture and
 * glTexEnv(GL_TEXTURE_FILTER_CONTROL) set there. */
typedef struct tsr_state_imageunit {
    GLuint binding[TSR_TEX_TARGETS];
    GLfloat lod_bias; /* GL_TEXTURE_FILTER_CONTROL */
} tsr_state_imageunit;

/* A coordinate unit's fixed-function state. */
typedef struct tsr_state_texunit {
    /* glTexEnv */
    GLenum env_mode;
    GLfloat env_color[4];
    GLenum combine_rgb, combine_alpha, src_rgb[3], src_alpha[3], operand_rgb[3], operand_alpha[3];
    GLfloat rgb_scale, alpha_scale;
    GLboolean coord_replace; /* GL_POINT_SPRITE */
    tsr_state_texgen gen[4]; /* S, T, R, Q */
} tsr_state_texunit;

typedef struct tsr_state_array {
    GLboolean enabled, normalized;
    GLint size;
    GLenum type;
    GLsizei stride;
    GLuint buffer;
    const void *pointer;
} tsr_state_array;

/* Client state (never diffed: client arrays travel as draw payloads). */
typedef struct tsr_state_client {
    tsr_state_array vertex, normal, color, edge_flag;
    tsr_state_array secondary_color, fog_coord, index;
    tsr_state_array texcoord[TSR_STATE_UNITS];
    tsr_state_array attrib[TSR_STATE_ATTRIBS];
    GLuint client_active_texture; /* unit index */
    tsr_pixel_store pixel_store;  /* saved by PushClientAttrib only */
} tsr_state_client;

/* Everything PushAttrib can save, and more: one flat struct so a shadow is
 * the same struct and a diff compares field by field. */
typedef struct tsr_state_values {
    /* current */
    GLfloat color[4], normal[3], texcoord[TSR_STATE_UNITS][4];
    GLboolean edge_flag;
    GLfloat attrib[TSR_STATE_ATTRIBS][4];
    /* enables: bit i = cap index i (state_enable_index) */
    uint64_t enables[2];
    /* viewport */
    GLint viewport[4];
    GLdouble depth_range[2];
    GLint scissor[4];
    /* color buffer */
    GLenum blend_src_rgb, blend_dst_rgb, blend_src_alpha, blend_dst_alpha;
    GLenum blend_eq_rgb, blend_eq_alpha;
    GLfloat blend_color[4];
    GLenum alpha_func;
    GLfloat alpha_ref;
    GLenum logic_op;
    GLboolean color_mask[4];
    GLfloat clear_color[4], clear_accum[4];
    /* Which call set the clear colour last: 0 glClearColor (clear_color),
     * GL_INT glClearColorIiEXT or GL_UNSIGNED_INT glClearColorIuiEXT
     * (clear_color_int, the integers' bits). GL keeps one clear colour;
     * the diff sends it with the call that set it. */
    GLenum clear_color_type;
    GLuint clear_color_int[4];
    GLenum draw_buffer, read_buffer;
    /* depth */
    GLenum depth_func;
    GLboolean depth_mask;
    GLdouble clear_depth;
    /* stencil: [0] front, [1] back */
    GLenum stencil_func[2];
    GLint stencil_ref[2];
    GLuint stencil_value_mask[2], stencil_writemask[2];
    GLenum stencil_fail[2], stencil_zfail[2], stencil_zpass[2];
    GLint clear_stencil;
    /* fog */
    GLenum fog_mode, fog_coord_src;
    GLfloat fog_density, fog_start, fog_end, fog_index, fog_color[4];
    /* lighting */
    tsr_state_light light[TSR_STATE_LIGHTS];
    GLfloat model_ambient[4];
    GLboolean model_local_viewer, model_two_side;
    GLenum model_color_control;
    tsr_state_material material[2]; /* front, back */
    GLenum color_material_face, color_material_mode;
    GLenum shade_model;
    /* polygon, line, point */
    GLenum polygon_mode[2]; /* front, back */
    GLenum cull_face_mode, front_face;
    GLfloat offset_factor, offset_units;
    GLubyte polygon_stipple[128];
    GLfloat line_width;
    GLint line_stipple_factor;
    GLushort line_stipple_pattern;
    GLfloat point_size, point_min, point_max, point_fade, point_attenuation[3];
    GLenum point_sprite_origin;
    /* hints: perspective, point, line, polygon, fog, mipmap, texture
     * compression, fragment shader derivative */
    GLenum hint[8];
    /* pixel */
    tsr_pixel_store pixel_store;
    GLfloat zoom[2];
    GLfloat transfer_scale[5], transfer_bias[5]; /* R, G, B, A, depth */
    GLint index_shift, index_offset;
    GLboolean map_color, map_stencil;
    /* texture */
    GLuint active_texture; /* unit index */
    tsr_state_texunit unit[TSR_STATE_UNITS];
    tsr_state_imageunit image[TSR_STATE_IMAGE_UNITS];
    /* Bit u: image unit u (past the coordinate units) was ever given a
     * binding or a LOD bias; never cleared. The diff of
     * TSR_SM_TEXBIND_IMAGE walks the units set here or in the shadow's,
     * not all of them. */
    uint64_t image_units_set[TSR_STATE_IMAGE_UNITS / 64];
    /* buffers */
    GLuint array_buffer, element_buffer;
    GLuint pixel_pack_buffer, pixel_unpack_buffer; /* GL 2.1 pixel buffer objects */
    /* misc */
    GLuint list_base;
    GLfloat sample_coverage_value;
    GLboolean sample_coverage_invert;
    /* transform (the stacks live in tsr_state_stacks) */
    GLenum matrix_mode;
    GLfloat clip_plane[TSR_STATE_CLIP_PLANES][4]; /* eye coordinates */
} tsr_state_values;

/* How a matrix was built since its last load: what a renderer replays so
 * it holds not only the same bits but the same matrix *history* (Mesa
 * classifies a matrix built by glRotate/glTranslate/... from the
 * operations, and one given by glLoadMatrix from its values; lighting
 * then takes different, equally valid, rounding paths). A diff emits the
 * operations the renderer lacks; after more than TSR_STATE_RECIPE_OPS
 * operations the matrix counts as loaded (`base` = the product), which
 * Mesa may classify otherwise (no operation gives a loaded matrix a
 * general class back). The longest histories of the 26 programs of the
 * exactness sweep: glsnake 124, blinkbox 105, queens 79, antinspect 31
 * (with 16 antinspect differed on a wall, with 64 glsnake did); 255 is
 * what `count` holds. A recipe is about 6 KB at its longest, copied only
 * as far as it is used (st_recipe_copy). */
#define TSR_STATE_RECIPE_OPS 255
enum { TSR_RECIPE_TRANSLATE, TSR_RECIPE_SCALE, TSR_RECIPE_ROTATE, TSR_RECIPE_FRUSTUM, TSR_RECIPE_ORTHO };
/* Mesa also keeps a matrix's classification across glLoadIdentity: the
 * kinds of operation applied since the last glLoadMatrix stick to it.
 * `sticky` holds them (bit 1 << TSR_RECIPE_*, and TSR_STICKY_* below), and
 * a diff reproduces them on the renderer. */
#define TSR_STICKY_GENERAL_SCALE (1u << 5)
#define TSR_STICKY_GENERAL (1u << 6)
typedef struct tsr_state_recipe {
    GLfloat base[16];         /* the loaded matrix the operations start from */
    uint8_t base_is_identity; /* base came from glLoadIdentity (or the initial state) */
    uint8_t sticky;           /* classification bits from before the last glLoadIdentity */
    uint8_t count;            /* operations after the base */
    uint8_t kind[TSR_STATE_RECIPE_OPS];
    GLfloat arg[TSR_STATE_RECIPE_OPS][6];
} tsr_state_recipe;

typedef struct tsr_state_stacks {
    tsr_state_recipe modelview_recipe[TSR_STATE_MODELVIEW_DEPTH];
    tsr_state_recipe projection_recipe[TSR_STATE_PROJECTION_DEPTH];
    tsr_state_recipe texture_recipe[TSR_STATE_UNITS][TSR_STATE_TEXTURE_DEPTH];
    GLfloat modelview[TSR_STATE_MODELVIEW_DEPTH][16];
    GLfloat projection[TSR_STATE_PROJECTION_DEPTH][16];
    GLfloat texture[TSR_STATE_UNITS][TSR_STATE_TEXTURE_DEPTH][16];
    uint32_t modelview_depth, projection_depth, texture_depth[TSR_STATE_UNITS];
} tsr_state_stacks;

typedef struct tsr_state_tracker tsr_state_tracker;
typedef struct tsr_state_ctx tsr_state_ctx;
typedef struct tsr_state_shadow tsr_state_shadow;

/* --- life cycle ------------------------------------------------------------ */
TSR_API tsr_state_tracker *tsr_state_tracker_create(tsr_error *err);
/* Destroys every context and shadow still attached. */
TSR_API void tsr_state_tracker_destroy(tsr_state_tracker *t);
/* The renderers' texture size limits (glGetIntegerv of GL_MAX_TEXTURE_SIZE,
 * GL_MAX_3D_TEXTURE_SIZE and GL_MAX_CUBE_MAP_TEXTURE_SIZE): a glTexImage*
 * whose level or size is past them is GL_INVALID_VALUE, refused here as GL
 * does, so that it is never kept and sent again with every later state
 * sent. 0 (the default) leaves a limit unchecked. */
TSR_API void tsr_state_tracker_set_texture_limits(tsr_state_tracker *t, GLint max_size, GLint max_3d_size,
                                                  GLint max_cube_size);
/* The renderers' GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS: glActiveTexture of a
 * unit past it (or past TSR_STATE_IMAGE_UNITS) is GL_INVALID_ENUM, refused
 * here as GL does. Until it is given, TSR_STATE_IMAGE_UNITS units. */
TSR_API void tsr_state_tracker_set_image_units(tsr_state_tracker *t, GLint units);

/* A new context holds GL's initial state and is dirty for every renderer. */
TSR_API tsr_state_ctx *tsr_state_ctx_create(tsr_state_tracker *t, tsr_error *err);

/* The GL error of the first call the tracker refused since the last take
 * (an unknown enum or pname, a value out of range, a stack overflow or
 * underflow: such a call changes nothing and is never sent, so no
 * renderer raises it), and clears it; GL_NO_ERROR when none. */
TSR_API GLenum tsr_state_take_error(tsr_state_ctx *c);
TSR_API void tsr_state_ctx_destroy(tsr_state_ctx *c);

/* A new renderer: its shadow holds GL's initial state (a fresh context),
 * and every context is dirty for it. Ids are small integers, reused after
 * destroy; bit vectors grow as needed. */
TSR_API tsr_state_shadow *tsr_state_shadow_create(tsr_state_tracker *t, tsr_error *err);
TSR_API void tsr_state_shadow_destroy(tsr_state_shadow *s);
TSR_API int tsr_state_shadow_id(const tsr_state_shadow *s);
/* Forget what the renderer has (it was reset or replaced): GL's initial
 * state, no objects, dirty in every context. */
TSR_API void tsr_state_shadow_reset(tsr_state_shadow *s);

/* --- tracking ---------------------------------------------------------------
 * Sets the slots of every command the tracker implements (state, current
 * attributes, objects, client state, gets it can answer; the commands it
 * leaves out are in tsr_state_untracked[]) to functions
 * updating `c` (self = c). Other slots are left untouched, so a caller can
 * fill its child's table first and let the tracker override. The tracker's
 * functions never call further: an SPU that also forwards a call calls both
 * (e.g. tilesort: tracker for state, packer for geometry). Get functions in
 * the table answer from the tracker; for values it cannot answer they leave
 * the outputs untouched (call tsr_state_get_* to know). */
TSR_API void tsr_state_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d);

/* The tracked values, read-only (tilesort reads viewport and matrices to
 * place bounding boxes). */
TSR_API const tsr_state_values *tsr_state_values_of(const tsr_state_ctx *c);
TSR_API const tsr_state_stacks *tsr_state_stacks_of(const tsr_state_ctx *c);
TSR_API const tsr_state_client *tsr_state_client_of(const tsr_state_ctx *c);
/* Top of the modelview / projection stack (column-major). */
TSR_API const GLfloat *tsr_state_modelview(const tsr_state_ctx *c);
TSR_API const GLfloat *tsr_state_projection(const tsr_state_ctx *c);

/* --- diffing --------------------------------------------------------------- */
typedef struct tsr_state_diff_stats {
    uint32_t groups_visited;  /* dirty groups looked at */
    uint32_t members_visited; /* dirty members compared */
    uint32_t commands;        /* GL calls emitted */
    uint32_t group_mask;      /* bit g: group g emitted something */
} tsr_state_diff_stats;

/* Emits through `out` the calls that make renderer `s` hold the state of
 * `c` (bound objects included), updates the shadow and marks s clean in c.
 * Returns the number of GL calls emitted (0: nothing differed). `stats`
 * may be NULL. Replies are never needed (no get is emitted). */
TSR_API uint32_t tsr_state_diff(tsr_state_ctx *c, tsr_state_shadow *s, const tsr_dispatch *out,
                                tsr_state_diff_stats *stats);
/* Makes renderer s hold texture object `name` of c (target GL_TEXTURE_2D,
 * ...) as it is now, uploading only what it lacks, and leaves the
 * renderer's bindings as they were. For objects a diff cannot see: those a
 * display list binds (its sender calls this before the list runs). Returns
 * the number of GL calls emitted. */
TSR_API uint32_t tsr_state_send_texture(tsr_state_ctx *c, tsr_state_shadow *s, GLenum target, GLuint name,
                                        const tsr_dispatch *out);
/* Makes renderer s hold shader / program `name` of c as it is now: created
 * under that name, sources, compile, attachments, attribute bindings, the
 * program linked from its last link's inputs and every uniform call since,
 * emitting only what s lacks; the renderer's current program is left as
 * it was. For gets only a renderer answers (compile/link status, info
 * logs, uniform and attribute locations). Returns GL calls emitted. */
TSR_API uint32_t tsr_state_send_shader(tsr_state_ctx *c, tsr_state_shadow *s, GLuint name, const tsr_dispatch *out);
TSR_API uint32_t tsr_state_send_program(tsr_state_ctx *c, tsr_state_shadow *s, GLuint name, const tsr_dispatch *out);
/* Every shader and program of c (a late joiner: the stream may use any of
 * them later), including deletions that wait for a detach or a
 * glUseProgram, as on the other renderers. */
TSR_API uint32_t tsr_state_send_glsl_all(tsr_state_ctx *c, tsr_state_shadow *s, const tsr_dispatch *out);
/* Whether a diff of c into s would look at anything (the root bit). */
TSR_API int tsr_state_is_dirty(const tsr_state_ctx *c, const tsr_state_shadow *s);
/* The renderer received commands (in a geometry stream) that made the
 * current-attribute `member` (TSR_SM_COLOR, _NORMAL, _TEXCOORD0 + u,
 * _EDGEFLAG, _ATTRIBS), or the material (TSR_SM_MATERIAL: glMaterial is
 * allowed inside glBegin/glEnd), equal to c's value: copy it into the
 * shadow without emitting. Tilesort calls it for what its geometry carried.
 * Other members are ignored. */
TSR_API void tsr_state_shadow_assume(tsr_state_ctx *c, tsr_state_shadow *s, int member);

/* --- getting ----------------------------------------------------------------
 * Each returns 1 and fills `out` when the tracker knows the answer, 0 when
 * the value must come from the renderer (outputs untouched). Conversions
 * follow the GL rules (and Mesa's rounding) for the type asked. */
TSR_API int tsr_state_get_doublev(const tsr_state_ctx *c, GLenum pname, GLdouble *out);
TSR_API int tsr_state_get_floatv(const tsr_state_ctx *c, GLenum pname, GLfloat *out);
TSR_API int tsr_state_get_integerv(const tsr_state_ctx *c, GLenum pname, GLint *out);
TSR_API int tsr_state_get_booleanv(const tsr_state_ctx *c, GLenum pname, GLboolean *out);
TSR_API int tsr_state_is_enabled(const tsr_state_ctx *c, GLenum cap, GLboolean *out);
TSR_API int tsr_state_get_lightfv(const tsr_state_ctx *c, GLenum light, GLenum pname, GLfloat *out);
TSR_API int tsr_state_get_materialfv(const tsr_state_ctx *c, GLenum face, GLenum pname, GLfloat *out);
TSR_API int tsr_state_get_tex_envfv(const tsr_state_ctx *c, GLenum target, GLenum pname, GLfloat *out);
TSR_API int tsr_state_get_tex_genfv(const tsr_state_ctx *c, GLenum coord, GLenum pname, GLfloat *out);
TSR_API int tsr_state_get_tex_parameterfv(const tsr_state_ctx *c, GLenum target, GLenum pname, GLfloat *out);
/* glGetTexParameterIivEXT (type GL_INT) or glGetTexParameterIuivEXT
 * (GL_UNSIGNED_INT, `out` then holds GLuints): the border colour when the
 * call of the same type set it; anything else is the renderer's to answer. */
TSR_API int tsr_state_get_tex_parameter_int(const tsr_state_ctx *c, GLenum target, GLenum pname, GLenum type,
                                            GLint *out);
TSR_API int tsr_state_get_tex_level_parameteriv(const tsr_state_ctx *c, GLenum target, GLint level, GLenum pname,
                                                GLint *out);
/* The internal format the program gave for the image the tracker holds
 * for (target, level) of the bound texture (as given: 3, GL_COMPRESSED_RGB,
 * not what the renderer made of it, which glGetTexLevelParameteriv
 * answers); 0 when the tracker holds none (mipmap generation's levels). A
 * wall's copy into the level reads its source in a form that suits it. */
TSR_API int tsr_state_tex_level_requested_format(const tsr_state_ctx *c, GLenum target, GLint level, GLint *out);
TSR_API int tsr_state_get_clip_plane(const tsr_state_ctx *c, GLenum plane, GLdouble *out);
TSR_API int tsr_state_get_polygon_stipple(const tsr_state_ctx *c, GLubyte *out);
TSR_API int tsr_state_get_buffer_parameteriv(const tsr_state_ctx *c, GLenum target, GLenum pname, GLint *out);
/* The bytes of the buffer bound to `target` as the tracker keeps them and
 * their count in *size, or NULL (no buffer bound, none kept, or mapped:
 * the program may be writing them). */
TSR_API const void *tsr_state_buffer_bytes(const tsr_state_ctx *c, GLenum target, GLsizeiptr *size);
/* glGetShaderiv / glGetProgramiv: answered for what the client knows
 * (GL_SHADER_TYPE, GL_DELETE_STATUS, GL_SHADER_SOURCE_LENGTH,
 * GL_ATTACHED_SHADERS); compile, link and validate status, info logs and
 * active uniforms/attributes come from a renderer (0: send the object
 * there first with tsr_state_send_shader/_program, then ask it). Unknown
 * names are left to the renderer too (its GL error). */
TSR_API int tsr_state_get_shaderiv(const tsr_state_ctx *c, GLuint shader, GLenum pname, GLint *out);
TSR_API int tsr_state_get_programiv(const tsr_state_ctx *c, GLuint program, GLenum pname, GLint *out);
/* Whether the current program's last link had a vertex shader: vertex
 * positions are then computed by the shader (a bounding box from the
 * application's matrices does not hold). */
TSR_API int tsr_state_program_has_vertex_shader(const tsr_state_ctx *c);
/* glIsTexture / glIsList / glIsBuffer: always answered. */
TSR_API GLboolean tsr_state_is_texture(const tsr_state_ctx *c, GLuint name);
TSR_API GLboolean tsr_state_is_list(const tsr_state_ctx *c, GLuint name);
TSR_API GLboolean tsr_state_is_buffer(const tsr_state_ctx *c, GLuint name);
/* Number of values glGet* writes for pname when the tracker answers it (0:
 * not answered here). */
TSR_API int tsr_state_get_count(GLenum pname);

/* --- coverage -------------------------------------------------------------- */
typedef struct tsr_state_untracked_cmd {
    const char *name; /* spec name without "gl" */
    const char *why;
} tsr_state_untracked_cmd;
/* Spec commands of category state/object/client the tracker does not
 * implement, each with the reason; terminated by {NULL, NULL}. */
TSR_API extern const tsr_state_untracked_cmd tsr_state_untracked[];
/* Command i (from 0) of the spec the tracker must cover (categories state,
 * object, client, and the current-attribute commands): its name and
 * category ("current" for those). Returns 0 past the end. Generated from
 * the spec. */
TSR_API int tsr_state_spec_command(size_t i, const char **name, const char **category);

#ifdef __cplusplus
}
#endif
#endif
