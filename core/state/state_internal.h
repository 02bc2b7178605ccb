/* core/state/state_internal.h — what the state tracker's files share: the
 * structs behind the opaque types of tessera/dev/state.h, the dirty-bit
 * nodes, and the helpers more than one file calls (state.c lists the
 * files). Not for SPUs: they use tessera/dev/state.h. */
#ifndef TSR_CORE_STATE_INTERNAL_H
#define TSR_CORE_STATE_INTERNAL_H

#include "tessera/dev/state.h"
#include "util/map.h"

/* glDrawBuffer/glReadBuffer(GL_NONE) as tracked: draw_buffer and
 * read_buffer 0 mean "never set" (the renderer's default applies), and
 * GL_NONE is 0 too. ST_BUFFER_OF turns a tracked value back into GL's. */
#define ST_BUFFER_NONE 0xffffffffu
#define ST_BUFFER_OF(v) ((v) == ST_BUFFER_NONE ? (GLenum)GL_NONE : (GLenum)(v))
#define ST_BUFFER_TRACKED(buf) ((buf) == GL_NONE ? (GLenum)ST_BUFFER_NONE : (GLenum)(buf))

/* --- texture objects -------------------------------------------------------- */
typedef struct st_texparams {
    GLenum min_filter, mag_filter, wrap_s, wrap_t, wrap_r;
    GLfloat border_color[4], priority, min_lod, max_lod, lod_bias;
    /* Which call set the border colour last: 0 the float and fixed-point
     * ones (border_color), GL_INT glTexParameterIivEXT or GL_UNSIGNED_INT
     * glTexParameterIuivEXT (border_int, the integers' bits). */
    GLenum border_type;
    GLuint border_int[4];
    GLint base_level, max_level;
    GLboolean generate_mipmap;
    GLenum compare_mode, compare_func, depth_mode;
    GLenum swizzle[4]; /* GL_TEXTURE_SWIZZLE_R..A (GL_EXT_texture_swizzle) */
} st_texparams;

/* One image call, replayed in order on a renderer that lacks it. Pixels
 * are kept tightly packed (alignment 1, no skips) in the tracker's memory;
 * swap_bytes/lsb_first are kept as the application gave them. */
/* Pixel-transfer modes that applied to an upload (they change the texels). */
typedef struct st_transfer {
    GLfloat scale[5], bias[5];
    GLint index_shift, index_offset;
    GLboolean map_color, map_stencil;
} st_transfer;

typedef enum st_upload_kind { ST_UP_IMAGE, ST_UP_SUBIMAGE, ST_UP_MIPMAP } st_upload_kind;
typedef struct st_upload {
    st_upload_kind kind;
    int dims;      /* 1, 2, 3 */
    GLenum target; /* the face for cube maps */
    GLint level, internalformat, border, x, y, z;
    GLsizei w, h, d;
    GLenum format, type;
    uint8_t *data; /* NULL: no pixels (undefined contents) */
    size_t size;
    uint8_t swap_bytes, lsb_first;
    uint8_t gen_mipmap; /* GL_GENERATE_MIPMAP was on: the upload regenerated levels */
    st_transfer transfer;
} st_upload;

typedef struct st_texobj {
    GLuint name;
    int target;       /* TSR_TEX_*, -1 while only generated */
    uint64_t uid;     /* unique in the tracker: a new object = a new uid */
    uint64_t version; /* bumped by every change */
    uint64_t epoch;   /* bumped when uploads[] is rewritten (not appended) */
    st_texparams params;
    st_upload *up;
    size_t nup, capup;
} st_texobj;

/* What a renderer has of one texture object. */
typedef struct st_shadow_tex {
    uint64_t uid, version, epoch;
    uint64_t hash; /* content hash of what the renderer has */
    size_t nup;    /* uploads replayed */
    st_texparams params;
} st_shadow_tex;

typedef struct st_bufobj {
    GLuint name;
    int bound; /* ever bound: IsBuffer is true */
    uint64_t uid, version;
    GLsizeiptr size;
    GLenum usage;
    uint8_t *data;
    int mapped;            /* glMapBuffer(Range) handed out `data` + map_offset (state_map.c) */
    GLbitfield map_access; /* its access, as GL_MAP_*_BIT */
    GLintptr map_offset;   /* the range mapped */
    GLsizeiptr map_length;
} st_bufobj;

typedef struct st_shadow_buf {
    uint64_t uid, version, hash;
} st_shadow_buf;

/* --- shaders and programs (state_glsl.c) ----------------------------------- */
/* A source text, immutable once made and shared (refcounted) between a
 * shader and the link snapshots that compiled it. id: unique in the
 * tracker (what a renderer's shadow compares). */
typedef struct st_source {
    uint32_t refs;
    uint64_t id;
    GLint len;
    char text[];
} st_source;

typedef struct st_shader {
    GLuint name;
    GLenum type;
    st_source *source;   /* glShaderSource's text (NULL: none yet) */
    st_source *compiled; /* the text of the last glCompileShader (NULL: never) */
    uint32_t attached;   /* programs it is attached to */
    int delete_pending;  /* glDeleteShader while attached */
} st_shader;

typedef struct st_binding {
    char *name;
    GLuint index;
} st_binding;

typedef struct st_link_shader {
    GLuint name;
    GLenum type;
    st_source *src; /* compiled text at link time (NULL: was never compiled) */
} st_link_shader;

/* One uniform call, kept as its vector form (Uniform3f = Uniform3fv with
 * count 1: Mesa treats them alike). It covers locations [loc, loc+count). */
enum { ST_U_F, ST_U_I, ST_U_M, ST_U_MX };
typedef struct st_uniform {
    uint64_t seq;
    GLint loc;
    GLsizei count;
    uint8_t base; /* ST_U_F, ST_U_I, ST_U_M, ST_U_MX (non-square matrix) */
    uint8_t size; /* components (1..4), matrix side (2..4), or columns << 4 | rows (ST_U_MX) */
    GLboolean transpose;
    void *data; /* count * values floats or ints */
} st_uniform;

typedef struct st_program {
    GLuint name;
    uint64_t uid;
    GLuint *attached;
    size_t nattached, capattached;
    st_binding *bind; /* glBindAttribLocation so far (a name bound again moves) */
    size_t nbind;
    uint64_t bind_version;
    uint64_t link_id; /* 0: never linked; unique per glLinkProgram */
    st_link_shader *link;
    size_t nlink;
    st_binding *link_bind;
    size_t nlink_bind;
    st_uniform *uni; /* uniform calls since the last link, oldest first */
    size_t nuni, capuni;
    uint64_t next_seq;
    uint64_t validations; /* glValidateProgram calls */
    int delete_pending;   /* glDeleteProgram while current */
} st_program;

/* What a renderer has of a shader / a program. */
typedef struct st_shadow_shader {
    GLenum type;
    uint64_t source, compiled; /* st_source ids (0: none) */
    int deleted;               /* glDeleteShader sent (waits for a detach there) */
} st_shadow_shader;

typedef struct st_shadow_program {
    uint64_t uid, link_id, uni_seq, bind_version, validations;
    GLuint *attached;
    size_t nattached;
    int deleted;
} st_shadow_program;

/* --- attribute stacks --------------------------------------------------------- */
typedef struct st_attrib_entry {
    GLbitfield mask;
    tsr_state_values v;
    /* GL_TEXTURE_BIT also saves the parameters of the bound textures (of
     * the units st_for_image_units walks; the rest are never written). */
    st_texparams tex_params[TSR_STATE_IMAGE_UNITS][TSR_TEX_TARGETS];
} st_attrib_entry;

typedef struct st_client_entry {
    GLbitfield mask;
    tsr_state_client c;
    GLuint array_buffer, element_buffer;
} st_client_entry;

/* --- the objects of state.h ------------------------------------------------- */
struct tsr_state_tracker {
    tsr_state_ctx **ctxs;
    size_t nctxs, capctxs;
    tsr_state_shadow **shadows;            /* indexed by id; NULL = free id */
    size_t nshadows;                       /* ids in use are < nshadows */
    size_t words;                          /* bit-vector words per node (64 renderers each) */
    uint8_t group_first[TSR_SG_COUNT + 1]; /* members of group g: [first[g], first[g+1]) */
    uint64_t next_uid;
    GLint max_tex_size[TSR_TEX_TARGETS]; /* by TSR_TEX_*; 0: unknown (tsr_state_tracker_set_texture_limits) */
    GLuint image_units;                  /* glActiveTexture's limit (tsr_state_tracker_set_image_units) */
};

/* Dirty-bit nodes: root, groups, members. */
enum {
    ST_NODE_ROOT = 0,
    ST_NODE_GROUP0 = 1,
    ST_NODE_MEMBER0 = 1 + TSR_SG_COUNT,
    ST_NODES = 1 + TSR_SG_COUNT + TSR_SM_COUNT
};

struct tsr_state_ctx {
    tsr_state_tracker *t;
    GLenum gl_error; /* of a call refused here, not yet taken (st_error) */
    uint64_t *dirty; /* [ST_NODES][t->words] */
    tsr_state_values v;
    tsr_state_stacks s;
    tsr_state_client client;
    tsr_name_map textures; /* name -> st_texobj */
    st_texobj default_tex[TSR_TEX_TARGETS];
    tsr_name_map buffers;          /* name -> st_bufobj */
    tsr_name_map lists;            /* name -> (void *)1 */
    st_attrib_entry *attrib_stack; /* TSR_STATE_ATTRIB_DEPTH entries */
    uint32_t attrib_depth;
    st_client_entry *client_stack;
    uint32_t client_depth;
    tsr_name_map shaders;  /* name -> st_shader */
    tsr_name_map programs; /* name -> st_program */
    GLuint program;        /* glUseProgram */
    GLenum list_mode;      /* 0, GL_COMPILE, GL_COMPILE_AND_EXECUTE */
    GLuint list_name;
};

struct tsr_state_shadow {
    tsr_state_tracker *t;
    int id;
    tsr_state_values v;
    tsr_state_stacks s;
    tsr_name_map textures; /* name -> st_shadow_tex */
    st_shadow_tex default_tex[TSR_TEX_TARGETS];
    tsr_name_map buffers;  /* name -> st_shadow_buf */
    tsr_name_map shaders;  /* name -> st_shadow_shader */
    tsr_name_map programs; /* name -> st_shadow_program */
    GLuint program;        /* current program there */
};

/* --- shared helpers ------------------------------------------------------------ */
extern const uint8_t st_member_group[TSR_SM_COUNT];
extern const GLenum st_enable_caps[128]; /* cap of each enable index (0: unused) */
/* Indices in st_enable_caps of the caps other files test by index. */
enum { ST_EN_COLOR_MATERIAL = 10, ST_EN_DITHER = 13, ST_EN_MULTISAMPLE = 36, ST_EN_COLOR_SUM = 43 };

/* Fresh matrix stacks: one identity level each, with no history
 * (state_matrix.c). */
void st_stacks_init(tsr_state_stacks *s);
/* Classification bits (tsr_state_recipe.sticky's kind) recipe r leaves on
 * a Mesa matrix: its sticky bits, its base, its operations. */
unsigned st_recipe_bits(const tsr_state_recipe *r);
/* dst = src, copying only the operations src holds (a recipe is some
 * 6 KB at its longest; a push copies one). */
void st_recipe_copy(tsr_state_recipe *dst, const tsr_state_recipe *src);
void st_texparams_init(st_texparams *p, int target);
/* Enable index of cap for the active unit (-1: not a tracked cap; -2: a
 * texture or texgen cap while a unit past the coordinate units is active). */
int st_enable_index(GLenum cap, GLuint unit);
static inline int st_enabled(const tsr_state_values *v, int idx)
{
    return (int)((v->enables[idx >> 6] >> (idx & 63)) & 1u);
}
/* Enable indices of the per-unit caps: 64 + unit * 8 + k. */
enum { ST_EN_UNIT0 = 64, ST_EN_TEX1D = 0, ST_EN_TEX2D, ST_EN_TEX3D, ST_EN_TEXCUBE, ST_EN_GEN_S };

/* Marks a member dirty for every renderer (and its group and the root). */
static inline void st_mark(tsr_state_ctx *c, int member)
{
    size_t w = c->t->words;
    uint64_t *m = c->dirty + (size_t)(ST_NODE_MEMBER0 + member) * w;
    uint64_t *g = c->dirty + (size_t)(ST_NODE_GROUP0 + st_member_group[member]) * w;
    for (size_t i = 0; i < w; i++) {
        m[i] = ~0ull;
        g[i] = ~0ull;
        c->dirty[i] = ~0ull;
    }
}
void st_mark_all(tsr_state_ctx *c);

/* The context of a tracker function (self), or NULL when the call must
 * not change it: inside glNewList(GL_COMPILE) GL records state calls into
 * the list instead of executing them, so the tracker ignores them (what the
 * list does when called is a known gap, see tsr_state_untracked). Commands
 * GL executes at once even while compiling a list (client state, pixel
 * store, object creation and deletion, buffer objects) use self as it is. */
static inline tsr_state_ctx *st_exec_ctx(void *self)
{
    tsr_state_ctx *c = self;
    return __builtin_expect(c->list_mode == GL_COMPILE, 0) ? NULL : c;
}
/* The GL error a call the tracker refuses raises (Mesa keeps one: the
 * first, until glGetError takes it; tsr_state_take_error). */
static inline void st_error(tsr_state_ctx *c, GLenum error)
{
    if (!c->gl_error)
        c->gl_error = error;
}
/* The dirty member of image unit u's bindings and LOD bias. */
static inline int st_image_member(GLuint u)
{
    return u < TSR_STATE_UNITS ? TSR_SM_TEXBIND0 + (int)u : TSR_SM_TEXBIND_IMAGE;
}
/* Image unit u of c changed: marked, and past the coordinate units
 * remembered in image_units_set (what the diff walks). */
static inline void st_image_changed(tsr_state_ctx *c, GLuint u)
{
    if (u >= TSR_STATE_UNITS)
        c->v.image_units_set[u >> 6] |= 1ull << (u & 63);
    st_mark(c, st_image_member(u));
}
/* The next image unit from u on (u included) that can hold a binding in
 * v: every coordinate unit, past them those of image_units_set;
 * TSR_STATE_IMAGE_UNITS when none. `also` (may be NULL) adds another
 * values' set (a shadow's). Walks words, not units. */
static inline GLuint st_next_image_unit(const tsr_state_values *v, const tsr_state_values *also, GLuint u)
{
    if (u < TSR_STATE_UNITS)
        return u;
    while (u < TSR_STATE_IMAGE_UNITS) {
        uint64_t w = v->image_units_set[u >> 6] | (also ? also->image_units_set[u >> 6] : 0);
        w &= ~0ull << (u & 63);
        if (w)
            return (u & ~63u) + (GLuint)__builtin_ctzll(w);
        u = (u | 63u) + 1;
    }
    return TSR_STATE_IMAGE_UNITS;
}
#define st_for_image_units(u, v, also)                                             \
    for (GLuint u = st_next_image_unit((v), (also), 0); u < TSR_STATE_IMAGE_UNITS; \
         u = st_next_image_unit((v), (also), u + 1))
/* A matrix setter's context: NULL too while the current matrix is the
 * texture matrix of a unit past the coordinate units (Mesa takes such
 * calls without an error, and no get or drawing sees that matrix). */
static inline tsr_state_ctx *st_matrix_ctx(void *self)
{
    tsr_state_ctx *c = st_exec_ctx(self);
    return c && c->v.matrix_mode == GL_TEXTURE && c->v.active_texture >= TSR_STATE_UNITS ? NULL : c;
}

/* Marks member dirty for one renderer id only. */
void st_mark_one(tsr_state_ctx *c, int member, int id);

/* Conversions and checks every group of setters needs. */
static inline void st_set4(GLfloat *d, GLfloat a, GLfloat b, GLfloat c, GLfloat e)
{
    d[0] = a;
    d[1] = b;
    d[2] = c;
    d[3] = e;
}
static inline GLfloat st_clampf(GLfloat x) { return x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x; }
static inline double st_clampd(double x) { return x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x; }
/* An integer given for a color: Mesa's INT_TO_FLOAT, in double like Mesa,
 * so the float the renderer stores is the one the tracker stores. */
static inline GLfloat st_int_to_float(GLint i) { return (GLfloat)((2.0 * i + 1.0) / 4294967295.0); }
/* The n values of a glFoo*iv as its float form takes them: colors
 * normalized, anything else converted as a number. */
static inline void st_ints_to_floats(GLfloat *out, const GLint *in, int n, int color)
{
    for (int i = 0; i < n; i++)
        out[i] = color ? st_int_to_float(in[i]) : (GLfloat)in[i];
}
/* The faces (0 front, 1 back) a face enum names; 0 for an invalid enum. */
static inline int st_faces(GLenum face, int *first, int *last)
{
    *first = face == GL_BACK ? 1 : 0;
    *last = face == GL_FRONT ? 0 : 1;
    return face == GL_FRONT || face == GL_BACK || face == GL_FRONT_AND_BACK;
}

/* glColor -> material while GL_COLOR_MATERIAL is on (returns 1 when it
 * applied); whether glColor drives material property pname of face
 * (state_light.c). _update applies it to c and marks the material. */
int st_color_material_apply(tsr_state_values *v);
void st_color_material_update(tsr_state_ctx *c);
int st_tracked_by_color(const tsr_state_values *v, int face, GLenum pname);
void st_cur_color(void *self, GLfloat r, GLfloat g, GLfloat b, GLfloat a);
void st_cur_normal(void *self, GLfloat x, GLfloat y, GLfloat z);
void st_cur_texcoord(void *self, GLenum unit, GLfloat s, GLfloat t, GLfloat r, GLfloat q);
void st_cur_edgeflag(void *self, GLboolean flag);
void st_cur_attrib(void *self, GLuint index, GLfloat x, GLfloat y, GLfloat z, GLfloat w);

/* A plane given in object coordinates, in eye coordinates: GL transforms
 * clip planes and eye-linear texgen planes by the inverse modelview
 * (state_matrix.c). */
void st_plane_to_eye(const tsr_state_ctx *c, GLfloat out[4], const GLfloat in[4]);

/* Each file of setters puts its functions in the table
 * (tsr_state_fill_dispatch calls them all). */
void st_matrix_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d);
void st_light_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d);
void st_fragment_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d);
void st_raster_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d);
void st_texenv_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d);
void st_attrib_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d);
void st_client_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d);
void st_map_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d);

/* Objects (state_obj.c). */
st_texobj *st_tex_lookup(tsr_state_ctx *c, GLuint name, int target);
st_bufobj *st_buf_lookup(const tsr_state_ctx *c, GLuint name);
/* The buffer object bound to `target` (vertex, index, pixel pack or
 * unpack buffer), or NULL. */
static inline st_bufobj *st_bound_buffer(const tsr_state_ctx *c, GLenum target)
{
    GLuint name = target == GL_ARRAY_BUFFER           ? c->v.array_buffer
                  : target == GL_ELEMENT_ARRAY_BUFFER ? c->v.element_buffer
                  : target == GL_PIXEL_PACK_BUFFER    ? c->v.pixel_pack_buffer
                  : target == GL_PIXEL_UNPACK_BUFFER  ? c->v.pixel_unpack_buffer
                                                      : 0;
    return name ? st_buf_lookup(c, name) : NULL;
}
/* The bytes of an image call's `pixels` (client memory, or an offset into
 * the bound GL_PIXEL_UNPACK_BUFFER's tracked data), or NULL (state_obj.c). */
const uint8_t *st_unpack_source(const tsr_state_ctx *c, const void *pixels, uint64_t extent);
void st_tex_changed(tsr_state_ctx *c, st_texobj *o);
void st_objects_free(tsr_state_ctx *c);
void st_shadow_objects_free(tsr_state_shadow *s);
int st_tex_target_index(GLenum target); /* -1 when not a texture target */
void st_obj_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d);

/* Shaders and programs (state_glsl.c). */
void st_glsl_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d);
void st_glsl_free(tsr_state_ctx *c);
void st_glsl_shadow_free(tsr_state_shadow *s);
/* The diff of TSR_SM_PROGRAM: emits through out, returns the calls. */
uint32_t st_glsl_diff(tsr_state_ctx *c, tsr_state_shadow *s, const tsr_dispatch *out);

/* Gets (state_get.c) fill the get slots of the table. */
void st_get_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d);

/* The client array `which` names (GL_VERTEX_ARRAY, ...; texture coordinates
 * of the client-active unit), or NULL for anything else. Used by the
 * setters (state_client.c) and the gets (state_get.c). */
static inline tsr_state_array *st_client_array(const tsr_state_ctx *c, GLenum which)
{
    tsr_state_ctx *m = (tsr_state_ctx *)c; /* the caller decides whether it writes */
    switch (which) {
    case GL_VERTEX_ARRAY: return &m->client.vertex;
    case GL_NORMAL_ARRAY: return &m->client.normal;
    case GL_COLOR_ARRAY: return &m->client.color;
    case GL_EDGE_FLAG_ARRAY: return &m->client.edge_flag;
    case GL_SECONDARY_COLOR_ARRAY: return &m->client.secondary_color;
    case GL_FOG_COORD_ARRAY: return &m->client.fog_coord;
    case GL_INDEX_ARRAY: return &m->client.index;
    case GL_TEXTURE_COORD_ARRAY: return &m->client.texcoord[m->client.client_active_texture];
    default: return NULL;
    }
}

#endif
