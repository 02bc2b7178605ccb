/* core/state/state.c — the state tracker's map: the groups and members of
 * the dirty-bit tree and how a member is marked, the enable indices, and
 * tsr_state_fill_dispatch, which puts every tracker function in a table.
 *
 * The tracker's files: state_init.c (life cycle, initial values),
 * state_matrix.c, the setters by group (state_light.c, state_fragment.c,
 * state_raster.c, state_texenv.c), state_attrib.c (push/pop attributes),
 * state_client.c (client state), state_obj.c (objects), state_glsl.c
 * (shaders and programs), state_diff.c (with state_diff_members.c and
 * state_diff_objects.c), state_get.c; state_internal.h is
 * what they share. Setters follow GL (and Mesa where GL leaves room): an
 * invalid enum or a value out of range changes nothing, as GL ignores it
 * with an error.
 *
 * Owns: the layout of the dirty bits (member -> group), which every
 * setter and the diff rely on.
 *
 * Never: sets a slot for a command the tracker does not implement: those
 * stay the caller's (tsr_state_untracked lists them with the reason). */
#include "state_internal.h"

#include <string.h>

/* --- groups and members ---------------------------------------------------- */
static const char *const group_names[TSR_SG_COUNT] = {
    "enable", "current", "viewport", "colorbuf", "depth", "stencil", "fog",       "lighting",
    "raster", "hint",    "texture",  "buffer",   "misc",  "pixel",   "transform", "program",
};

const char *tsr_state_group_name(int group) { return group >= 0 && group < TSR_SG_COUNT ? group_names[group] : "?"; }

#define U8 TSR_STATE_UNITS
const uint8_t st_member_group[TSR_SM_COUNT] = {
    [TSR_SM_ENABLE0] = TSR_SG_ENABLE,
    [TSR_SM_ENABLE1] = TSR_SG_ENABLE,
    [TSR_SM_COLOR] = TSR_SG_CURRENT,
    [TSR_SM_NORMAL] = TSR_SG_CURRENT,
    [TSR_SM_TEXCOORD0... TSR_SM_TEXCOORD0 + U8 - 1] = TSR_SG_CURRENT,
    [TSR_SM_EDGEFLAG] = TSR_SG_CURRENT,
    [TSR_SM_ATTRIBS] = TSR_SG_CURRENT,
    [TSR_SM_VIEWPORT] = TSR_SG_VIEWPORT,
    [TSR_SM_DEPTHRANGE] = TSR_SG_VIEWPORT,
    [TSR_SM_SCISSOR] = TSR_SG_VIEWPORT,
    [TSR_SM_BLEND] = TSR_SG_COLORBUF,
    [TSR_SM_ALPHAFUNC] = TSR_SG_COLORBUF,
    [TSR_SM_LOGICOP] = TSR_SG_COLORBUF,
    [TSR_SM_COLORMASK] = TSR_SG_COLORBUF,
    [TSR_SM_CLEARCOLOR] = TSR_SG_COLORBUF,
    [TSR_SM_DRAWBUFFER] = TSR_SG_COLORBUF,
    [TSR_SM_CLEARACCUM] = TSR_SG_COLORBUF,
    [TSR_SM_DEPTH] = TSR_SG_DEPTH,
    [TSR_SM_STENCIL] = TSR_SG_STENCIL,
    [TSR_SM_FOG] = TSR_SG_FOG,
    [TSR_SM_LIGHT0... TSR_SM_LIGHT0 + TSR_STATE_LIGHTS - 1] = TSR_SG_LIGHTING,
    [TSR_SM_LIGHTMODEL] = TSR_SG_LIGHTING,
    [TSR_SM_MATERIAL] = TSR_SG_LIGHTING,
    [TSR_SM_COLORMATERIAL] = TSR_SG_LIGHTING,
    [TSR_SM_SHADEMODEL] = TSR_SG_LIGHTING,
    [TSR_SM_POLYGON] = TSR_SG_RASTER,
    [TSR_SM_STIPPLE] = TSR_SG_RASTER,
    [TSR_SM_LINE] = TSR_SG_RASTER,
    [TSR_SM_POINT] = TSR_SG_RASTER,
    [TSR_SM_HINT] = TSR_SG_HINT,
    [TSR_SM_TEXBIND0... TSR_SM_TEXBIND0 + U8 - 1] = TSR_SG_TEXTURE,
    [TSR_SM_TEXBIND_IMAGE] = TSR_SG_TEXTURE,
    [TSR_SM_TEXENV0... TSR_SM_TEXENV0 + U8 - 1] = TSR_SG_TEXTURE,
    [TSR_SM_TEXGEN0... TSR_SM_TEXGEN0 + U8 - 1] = TSR_SG_TEXTURE,
    [TSR_SM_BUFBIND] = TSR_SG_BUFFER,
    [TSR_SM_LISTBASE] = TSR_SG_MISC,
    [TSR_SM_MULTISAMPLE] = TSR_SG_MISC,
    [TSR_SM_PIXELSTORE] = TSR_SG_PIXEL,
    [TSR_SM_PIXELMODE] = TSR_SG_PIXEL,
    [TSR_SM_MODELVIEW] = TSR_SG_TRANSFORM,
    [TSR_SM_PROJECTION] = TSR_SG_TRANSFORM,
    [TSR_SM_TEXMAT0... TSR_SM_TEXMAT0 + U8 - 1] = TSR_SG_TRANSFORM,
    [TSR_SM_CLIP] = TSR_SG_TRANSFORM,
    [TSR_SM_PROGRAM] = TSR_SG_PROGRAM,
};

int tsr_state_member_group(int member) { return member >= 0 && member < TSR_SM_COUNT ? st_member_group[member] : -1; }

/* --- enables ---------------------------------------------------------------- */
#define EN_UNIT(u, k)                                                                                                  \
    [ST_EN_UNIT0 + (u)*8 + 0] = GL_TEXTURE_1D, [ST_EN_UNIT0 + (u)*8 + 1] = GL_TEXTURE_2D,                              \
                           [ST_EN_UNIT0 + (u)*8 + 2] = GL_TEXTURE_3D, [ST_EN_UNIT0 + (u)*8 + 3] = GL_TEXTURE_CUBE_MAP, \
                           [ST_EN_UNIT0 + (u)*8 + 4] = GL_TEXTURE_GEN_S, [ST_EN_UNIT0 + (u)*8 + 5] = GL_TEXTURE_GEN_T, \
                           [ST_EN_UNIT0 + (u)*8 + 6] = GL_TEXTURE_GEN_R, [ST_EN_UNIT0 + (u)*8 + 7] = GL_TEXTURE_GEN_Q
const GLenum st_enable_caps[128] = {
    GL_ALPHA_TEST,
    GL_AUTO_NORMAL,
    GL_BLEND,
    GL_CLIP_PLANE0,
    GL_CLIP_PLANE1,
    GL_CLIP_PLANE2,
    GL_CLIP_PLANE3,
    GL_CLIP_PLANE4,
    GL_CLIP_PLANE5,
    GL_COLOR_LOGIC_OP,
    GL_COLOR_MATERIAL,
    GL_CULL_FACE,
    GL_DEPTH_TEST,
    GL_DITHER,
    GL_FOG,
    GL_LIGHT0,
    GL_LIGHT1,
    GL_LIGHT2,
    GL_LIGHT3,
    GL_LIGHT4,
    GL_LIGHT5,
    GL_LIGHT6,
    GL_LIGHT7,
    GL_LIGHTING,
    GL_LINE_SMOOTH,
    GL_LINE_STIPPLE,
    GL_NORMALIZE,
    GL_POINT_SMOOTH,
    GL_POLYGON_OFFSET_FILL,
    GL_POLYGON_OFFSET_LINE,
    GL_POLYGON_OFFSET_POINT,
    GL_POLYGON_SMOOTH,
    GL_POLYGON_STIPPLE,
    GL_RESCALE_NORMAL,
    GL_SCISSOR_TEST,
    GL_STENCIL_TEST,
    GL_MULTISAMPLE,
    GL_SAMPLE_ALPHA_TO_COVERAGE,
    GL_SAMPLE_ALPHA_TO_ONE,
    GL_SAMPLE_COVERAGE,
    GL_POINT_SPRITE,
    GL_VERTEX_PROGRAM_POINT_SIZE,
    GL_VERTEX_PROGRAM_TWO_SIDE,
    GL_COLOR_SUM,
    GL_MAP1_COLOR_4,
    GL_MAP1_INDEX,
    GL_MAP1_NORMAL,
    GL_MAP1_TEXTURE_COORD_1,
    GL_MAP1_TEXTURE_COORD_2,
    GL_MAP1_TEXTURE_COORD_3,
    GL_MAP1_TEXTURE_COORD_4,
    GL_MAP1_VERTEX_3,
    GL_MAP1_VERTEX_4,
    GL_MAP2_COLOR_4,
    GL_MAP2_INDEX,
    GL_MAP2_NORMAL,
    GL_MAP2_TEXTURE_COORD_1,
    GL_MAP2_TEXTURE_COORD_2,
    GL_MAP2_TEXTURE_COORD_3,
    GL_MAP2_TEXTURE_COORD_4,
    GL_MAP2_VERTEX_3,
    GL_MAP2_VERTEX_4,
    /* Mesa's GL_MAX_CLIP_PLANES is 8 (after the 62 above, so their
     * indices stay) */
    GL_CLIP_PLANE0 + 6,
    GL_CLIP_PLANE0 + 7,
    EN_UNIT(0, 0),
    EN_UNIT(1, 0),
    EN_UNIT(2, 0),
    EN_UNIT(3, 0),
    EN_UNIT(4, 0),
    EN_UNIT(5, 0),
    EN_UNIT(6, 0),
    EN_UNIT(7, 0),
};

int st_enable_index(GLenum cap, GLuint unit)
{
    if (unit >= TSR_STATE_UNITS && ((cap >= GL_TEXTURE_GEN_S && cap <= GL_TEXTURE_GEN_Q) || cap == GL_TEXTURE_1D ||
                                    cap == GL_TEXTURE_2D || cap == GL_TEXTURE_3D || cap == GL_TEXTURE_CUBE_MAP))
        return -2;
    switch (cap) {
    case GL_TEXTURE_1D: return ST_EN_UNIT0 + (int)unit * 8 + 0;
    case GL_TEXTURE_2D: return ST_EN_UNIT0 + (int)unit * 8 + 1;
    case GL_TEXTURE_3D: return ST_EN_UNIT0 + (int)unit * 8 + 2;
    case GL_TEXTURE_CUBE_MAP: return ST_EN_UNIT0 + (int)unit * 8 + 3;
    case GL_TEXTURE_GEN_S: return ST_EN_UNIT0 + (int)unit * 8 + 4;
    case GL_TEXTURE_GEN_T: return ST_EN_UNIT0 + (int)unit * 8 + 5;
    case GL_TEXTURE_GEN_R: return ST_EN_UNIT0 + (int)unit * 8 + 6;
    case GL_TEXTURE_GEN_Q: return ST_EN_UNIT0 + (int)unit * 8 + 7;
    default: break;
    }
    for (int i = 0; i < ST_EN_UNIT0; i++)
        if (st_enable_caps[i] == cap)
            return i;
    return -1;
}

/* --- bits ------------------------------------------------------------------------ */
void st_mark_all(tsr_state_ctx *c) { memset(c->dirty, 0xff, (size_t)ST_NODES * c->t->words * sizeof *c->dirty); }

void st_mark_one(tsr_state_ctx *c, int member, int id)
{
    size_t w = c->t->words, word = (size_t)id >> 6;
    uint64_t bit = 1ull << (id & 63);
    c->dirty[(size_t)(ST_NODE_MEMBER0 + member) * w + word] |= bit;
    c->dirty[(size_t)(ST_NODE_GROUP0 + st_member_group[member]) * w + word] |= bit;
    c->dirty[word] |= bit;
}

/* --- the table ------------------------------------------------------------------- */
void st_gen_fill_current(tsr_state_ctx *c, tsr_dispatch *d); /* state_gen.c (generated) */

void tsr_state_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d)
{
    st_matrix_fill_dispatch(c, d);
    st_light_fill_dispatch(c, d);
    st_fragment_fill_dispatch(c, d);
    st_raster_fill_dispatch(c, d);
    st_texenv_fill_dispatch(c, d);
    st_attrib_fill_dispatch(c, d);
    st_client_fill_dispatch(c, d);
    st_gen_fill_current(c, d);
    st_obj_fill_dispatch(c, d);
    st_map_fill_dispatch(c, d);
    st_glsl_fill_dispatch(c, d);
    st_get_fill_dispatch(c, d);
}
