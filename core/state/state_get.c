/* core/state/state_get.c — glGet*, glIsEnabled and the object queries answered
 * from the tracker. One lookup (pname -> values + kind) serves every type;
 * conversions follow the GL rules with Mesa's rounding, so an answer is the
 * one the renderer would give. Implementation limits, strings, errors and
 * anything the window system decides are not answered (return 0). */
#include "state_internal.h"
#include "tessera/dev/pack.h"

#include <math.h>
#include <string.h>

typedef enum kind {
    K_FLOAT, /* plain number: ints round to nearest */
    K_NORM,  /* normalized [0,1] / [-1,1] value: ints scale to the full range */
    K_INT,   /* integer or enum */
    K_BOOL,
} kind;

typedef struct answer {
    double v[16];
    int n;
    kind k;
} answer;

static void putf(answer *a, kind k, const GLfloat *v, int n)
{
    a->k = k;
    a->n = n;
    for (int i = 0; i < n; i++)
        a->v[i] = v[i];
}

static void puti(answer *a, double v)
{
    a->k = K_INT;
    a->n = 1;
    a->v[0] = v;
}

static void putb(answer *a, int v)
{
    a->k = K_BOOL;
    a->n = 1;
    a->v[0] = v ? 1.0 : 0.0;
}

static void put1(answer *a, kind k, double v)
{
    a->k = k;
    a->n = 1;
    a->v[0] = v;
}


static int lookup(const tsr_state_ctx *c, GLenum pname, answer *a)
{
    const tsr_state_values *v = &c->v;
    GLuint au = v->active_texture;
    const tsr_state_imageunit *iu = &v->image[au];
    /* past the coordinate units GL refuses the coordinate unit's gets
     * (GL_INVALID_OPERATION): the renderer answers them */
    if (au >= TSR_STATE_UNITS &&
        (pname == GL_CURRENT_TEXTURE_COORDS || pname == GL_TEXTURE_MATRIX || pname == GL_TEXTURE_STACK_DEPTH))
        return 0;
    switch (pname) {
    /* current */
    case GL_CURRENT_COLOR: putf(a, K_NORM, v->color, 4); return 1;
    case GL_CURRENT_NORMAL: putf(a, K_NORM, v->normal, 3); return 1;
    case GL_CURRENT_TEXTURE_COORDS: putf(a, K_FLOAT, v->texcoord[au], 4); return 1;
    case GL_EDGE_FLAG: putb(a, v->edge_flag); return 1;
    /* the stream's name (a renderer maps it: tessera/glsl_names.h) */
    case GL_CURRENT_PROGRAM: puti(a, c->program); return 1;
    /* transform */
    /* Mesa converts matrices to integers like normalized values. */
    case GL_MODELVIEW_MATRIX: putf(a, K_NORM, c->s.modelview[c->s.modelview_depth - 1], 16); return 1;
    case GL_PROJECTION_MATRIX: putf(a, K_NORM, c->s.projection[c->s.projection_depth - 1], 16); return 1;
    case GL_TEXTURE_MATRIX: putf(a, K_NORM, c->s.texture[au][c->s.texture_depth[au] - 1], 16); return 1;
    /* GL_TRANSPOSE_TEXTURE_MATRIX is left to the renderer: Mesa (22.3)
     * answers it with a matrix other than the active unit's transposed
     * texture matrix, and the renderer's answer is the one that counts. */
    case GL_TRANSPOSE_MODELVIEW_MATRIX:
    case GL_TRANSPOSE_PROJECTION_MATRIX: {
        GLenum base = pname == GL_TRANSPOSE_MODELVIEW_MATRIX ? GL_MODELVIEW_MATRIX : GL_PROJECTION_MATRIX;
        answer m;
        lookup(c, base, &m);
        a->k = K_NORM;
        a->n = 16;
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 4; j++)
                a->v[i * 4 + j] = m.v[j * 4 + i];
        return 1;
    }
    case GL_MODELVIEW_STACK_DEPTH: puti(a, c->s.modelview_depth); return 1;
    case GL_PROJECTION_STACK_DEPTH: puti(a, c->s.projection_depth); return 1;
    case GL_TEXTURE_STACK_DEPTH: puti(a, c->s.texture_depth[au]); return 1;
    case GL_MATRIX_MODE: puti(a, v->matrix_mode); return 1;
    /* viewport */
    case GL_VIEWPORT:
    case GL_SCISSOR_BOX: {
        const GLint *r = pname == GL_VIEWPORT ? v->viewport : v->scissor;
        if (r[2] < 0)
            return 0;
        a->k = K_INT;
        a->n = 4;
        for (int i = 0; i < 4; i++)
            a->v[i] = r[i];
        return 1;
    }
    case GL_DEPTH_RANGE:
        a->k = K_NORM;
        a->n = 2;
        a->v[0] = v->depth_range[0];
        a->v[1] = v->depth_range[1];
        return 1;
    /* color buffer */
    case GL_BLEND_SRC_RGB: puti(a, v->blend_src_rgb); return 1;
    case GL_BLEND_DST_RGB: puti(a, v->blend_dst_rgb); return 1;
    case GL_BLEND_SRC_ALPHA: puti(a, v->blend_src_alpha); return 1;
    case GL_BLEND_DST_ALPHA: puti(a, v->blend_dst_alpha); return 1;
    case GL_BLEND_EQUATION_RGB: puti(a, v->blend_eq_rgb); return 1;
    case GL_BLEND_EQUATION_ALPHA: puti(a, v->blend_eq_alpha); return 1;
    case GL_BLEND_COLOR: putf(a, K_NORM, v->blend_color, 4); return 1;
    case GL_ALPHA_TEST_FUNC: puti(a, v->alpha_func); return 1;
    case GL_ALPHA_TEST_REF: put1(a, K_NORM, v->alpha_ref); return 1;
    case GL_LOGIC_OP_MODE: puti(a, v->logic_op); return 1;
    case GL_COLOR_WRITEMASK:
        a->k = K_BOOL;
        a->n = 4;
        for (int i = 0; i < 4; i++)
            a->v[i] = v->color_mask[i];
        return 1;
    case GL_COLOR_CLEAR_VALUE:
        if (v->clear_color_type)
            return 0; /* an integer clear colour read as floats: the renderer's affair */
        putf(a, K_NORM, v->clear_color, 4);
        return 1;
    case GL_ACCUM_CLEAR_VALUE: putf(a, K_NORM, v->clear_accum, 4); return 1;
    case GL_DRAW_BUFFER:
        if (!v->draw_buffer)
            return 0;
        puti(a, (GLint)ST_BUFFER_OF(v->draw_buffer));
        return 1;
    case GL_READ_BUFFER:
        if (!v->read_buffer)
            return 0;
        puti(a, (GLint)ST_BUFFER_OF(v->read_buffer));
        return 1;
    /* depth, stencil */
    case GL_DEPTH_FUNC: puti(a, v->depth_func); return 1;
    case GL_DEPTH_WRITEMASK: putb(a, v->depth_mask); return 1;
    case GL_DEPTH_CLEAR_VALUE: put1(a, K_NORM, v->clear_depth); return 1;
    case GL_STENCIL_FUNC: puti(a, v->stencil_func[0]); return 1;
    case GL_STENCIL_REF: puti(a, v->stencil_ref[0]); return 1;
    case GL_STENCIL_FAIL: puti(a, v->stencil_fail[0]); return 1;
    case GL_STENCIL_PASS_DEPTH_FAIL: puti(a, v->stencil_zfail[0]); return 1;
    case GL_STENCIL_PASS_DEPTH_PASS: puti(a, v->stencil_zpass[0]); return 1;
    case GL_STENCIL_BACK_FUNC: puti(a, v->stencil_func[1]); return 1;
    case GL_STENCIL_BACK_REF: puti(a, v->stencil_ref[1]); return 1;
    case GL_STENCIL_BACK_FAIL: puti(a, v->stencil_fail[1]); return 1;
    case GL_STENCIL_BACK_PASS_DEPTH_FAIL: puti(a, v->stencil_zfail[1]); return 1;
    case GL_STENCIL_BACK_PASS_DEPTH_PASS: puti(a, v->stencil_zpass[1]); return 1;
    /* Stencil masks are answered by the renderer: GL reports them cut to
     * its stencil bits, which only the renderer knows. */
    case GL_STENCIL_CLEAR_VALUE: puti(a, v->clear_stencil); return 1;
    /* fog */
    case GL_FOG_MODE: puti(a, v->fog_mode); return 1;
    case GL_FOG_COORD_SRC: puti(a, v->fog_coord_src); return 1;
    case GL_FOG_DENSITY: put1(a, K_FLOAT, v->fog_density); return 1;
    case GL_FOG_START: put1(a, K_FLOAT, v->fog_start); return 1;
    case GL_FOG_END: put1(a, K_FLOAT, v->fog_end); return 1;
    case GL_FOG_INDEX: put1(a, K_FLOAT, v->fog_index); return 1;
    case GL_FOG_COLOR: putf(a, K_NORM, v->fog_color, 4); return 1;
    /* lighting */
    case GL_LIGHT_MODEL_AMBIENT: putf(a, K_NORM, v->model_ambient, 4); return 1;
    case GL_LIGHT_MODEL_LOCAL_VIEWER: putb(a, v->model_local_viewer); return 1;
    case GL_LIGHT_MODEL_TWO_SIDE: putb(a, v->model_two_side); return 1;
    case GL_LIGHT_MODEL_COLOR_CONTROL: puti(a, v->model_color_control); return 1;
    case GL_COLOR_MATERIAL_FACE: puti(a, v->color_material_face); return 1;
    case GL_COLOR_MATERIAL_PARAMETER: puti(a, v->color_material_mode); return 1;
    case GL_SHADE_MODEL: puti(a, v->shade_model); return 1;
    /* polygon, line, point */
    case GL_POLYGON_MODE:
        a->k = K_INT;
        a->n = 2;
        a->v[0] = v->polygon_mode[0];
        a->v[1] = v->polygon_mode[1];
        return 1;
    case GL_CULL_FACE_MODE: puti(a, v->cull_face_mode); return 1;
    case GL_FRONT_FACE: puti(a, v->front_face); return 1;
    case GL_POLYGON_OFFSET_FACTOR: put1(a, K_FLOAT, v->offset_factor); return 1;
    case GL_POLYGON_OFFSET_UNITS: put1(a, K_FLOAT, v->offset_units); return 1;
    case GL_LINE_WIDTH: put1(a, K_FLOAT, v->line_width); return 1;
    case GL_LINE_STIPPLE_PATTERN: puti(a, v->line_stipple_pattern); return 1;
    case GL_LINE_STIPPLE_REPEAT: puti(a, v->line_stipple_factor); return 1;
    case GL_POINT_SIZE: put1(a, K_FLOAT, v->point_size); return 1;
    case GL_POINT_SIZE_MIN: put1(a, K_FLOAT, v->point_min); return 1;
    case GL_POINT_SIZE_MAX:
        if (v->point_max < 0)
            return 0;
        put1(a, K_FLOAT, v->point_max);
        return 1;
    case GL_POINT_FADE_THRESHOLD_SIZE: put1(a, K_FLOAT, v->point_fade); return 1;
    case GL_POINT_DISTANCE_ATTENUATION: putf(a, K_FLOAT, v->point_attenuation, 3); return 1;
    case GL_POINT_SPRITE_COORD_ORIGIN: puti(a, v->point_sprite_origin); return 1;
    /* hints */
    case GL_PERSPECTIVE_CORRECTION_HINT: puti(a, v->hint[0]); return 1;
    case GL_POINT_SMOOTH_HINT: puti(a, v->hint[1]); return 1;
    case GL_LINE_SMOOTH_HINT: puti(a, v->hint[2]); return 1;
    case GL_POLYGON_SMOOTH_HINT: puti(a, v->hint[3]); return 1;
    case GL_FOG_HINT: puti(a, v->hint[4]); return 1;
    case GL_GENERATE_MIPMAP_HINT: puti(a, v->hint[5]); return 1;
    case GL_TEXTURE_COMPRESSION_HINT: puti(a, v->hint[6]); return 1;
    case GL_FRAGMENT_SHADER_DERIVATIVE_HINT: puti(a, v->hint[7]); return 1;
    /* pixel */
    case GL_PACK_SWAP_BYTES:
    case GL_PACK_LSB_FIRST:
    case GL_UNPACK_SWAP_BYTES:
    case GL_UNPACK_LSB_FIRST: putb(a, tsr_pixel_store_get(&v->pixel_store, pname)); return 1;
    case GL_PACK_ROW_LENGTH:
    case GL_PACK_IMAGE_HEIGHT:
    case GL_PACK_SKIP_ROWS:
    case GL_PACK_SKIP_PIXELS:
    case GL_PACK_SKIP_IMAGES:
    case GL_PACK_ALIGNMENT:
    case GL_UNPACK_ROW_LENGTH:
    case GL_UNPACK_IMAGE_HEIGHT:
    case GL_UNPACK_SKIP_ROWS:
    case GL_UNPACK_SKIP_PIXELS:
    case GL_UNPACK_SKIP_IMAGES:
    case GL_UNPACK_ALIGNMENT: puti(a, tsr_pixel_store_get(&v->pixel_store, pname)); return 1;
    case GL_ZOOM_X: put1(a, K_FLOAT, v->zoom[0]); return 1;
    case GL_ZOOM_Y: put1(a, K_FLOAT, v->zoom[1]); return 1;
    case GL_RED_SCALE: put1(a, K_FLOAT, v->transfer_scale[0]); return 1;
    case GL_GREEN_SCALE: put1(a, K_FLOAT, v->transfer_scale[1]); return 1;
    case GL_BLUE_SCALE: put1(a, K_FLOAT, v->transfer_scale[2]); return 1;
    case GL_ALPHA_SCALE: put1(a, K_FLOAT, v->transfer_scale[3]); return 1;
    case GL_DEPTH_SCALE: put1(a, K_FLOAT, v->transfer_scale[4]); return 1;
    case GL_RED_BIAS: put1(a, K_FLOAT, v->transfer_bias[0]); return 1;
    case GL_GREEN_BIAS: put1(a, K_FLOAT, v->transfer_bias[1]); return 1;
    case GL_BLUE_BIAS: put1(a, K_FLOAT, v->transfer_bias[2]); return 1;
    case GL_ALPHA_BIAS: put1(a, K_FLOAT, v->transfer_bias[3]); return 1;
    case GL_DEPTH_BIAS: put1(a, K_FLOAT, v->transfer_bias[4]); return 1;
    case GL_INDEX_SHIFT: puti(a, v->index_shift); return 1;
    case GL_INDEX_OFFSET: puti(a, v->index_offset); return 1;
    case GL_MAP_COLOR: putb(a, v->map_color); return 1;
    case GL_MAP_STENCIL: putb(a, v->map_stencil); return 1;
    /* texture */
    case GL_ACTIVE_TEXTURE: puti(a, GL_TEXTURE0 + au); return 1;
    case GL_CLIENT_ACTIVE_TEXTURE: puti(a, GL_TEXTURE0 + c->client.client_active_texture); return 1;
    case GL_TEXTURE_BINDING_1D: puti(a, iu->binding[TSR_TEX_1D]); return 1;
    case GL_TEXTURE_BINDING_2D: puti(a, iu->binding[TSR_TEX_2D]); return 1;
    case GL_TEXTURE_BINDING_3D: puti(a, iu->binding[TSR_TEX_3D]); return 1;
    case GL_TEXTURE_BINDING_CUBE_MAP: puti(a, iu->binding[TSR_TEX_CUBE]); return 1;
    /* buffers, lists, misc */
    case GL_ARRAY_BUFFER_BINDING: puti(a, v->array_buffer); return 1;
    case GL_ELEMENT_ARRAY_BUFFER_BINDING: puti(a, v->element_buffer); return 1;
    case GL_PIXEL_PACK_BUFFER_BINDING: puti(a, v->pixel_pack_buffer); return 1;
    case GL_PIXEL_UNPACK_BUFFER_BINDING: puti(a, v->pixel_unpack_buffer); return 1;
    case GL_LIST_BASE: puti(a, v->list_base); return 1;
    case GL_LIST_INDEX: puti(a, c->list_name); return 1;
    case GL_LIST_MODE: puti(a, c->list_mode); return 1;
    case GL_SAMPLE_COVERAGE_VALUE: put1(a, K_FLOAT, v->sample_coverage_value); return 1;
    case GL_SAMPLE_COVERAGE_INVERT: putb(a, v->sample_coverage_invert); return 1;
    case GL_ATTRIB_STACK_DEPTH: puti(a, c->attrib_depth); return 1;
    case GL_CLIENT_ATTRIB_STACK_DEPTH: puti(a, c->client_depth); return 1;
    /* client arrays */
    case GL_VERTEX_ARRAY_SIZE: puti(a, c->client.vertex.size); return 1;
    case GL_VERTEX_ARRAY_TYPE: puti(a, c->client.vertex.type); return 1;
    case GL_VERTEX_ARRAY_STRIDE: puti(a, c->client.vertex.stride); return 1;
    case GL_NORMAL_ARRAY_TYPE: puti(a, c->client.normal.type); return 1;
    case GL_NORMAL_ARRAY_STRIDE: puti(a, c->client.normal.stride); return 1;
    case GL_COLOR_ARRAY_SIZE: puti(a, c->client.color.size); return 1;
    case GL_COLOR_ARRAY_TYPE: puti(a, c->client.color.type); return 1;
    case GL_COLOR_ARRAY_STRIDE: puti(a, c->client.color.stride); return 1;
    case GL_EDGE_FLAG_ARRAY_STRIDE: puti(a, c->client.edge_flag.stride); return 1;
    case GL_SECONDARY_COLOR_ARRAY_SIZE: puti(a, c->client.secondary_color.size); return 1;
    case GL_SECONDARY_COLOR_ARRAY_TYPE: puti(a, c->client.secondary_color.type); return 1;
    case GL_SECONDARY_COLOR_ARRAY_STRIDE: puti(a, c->client.secondary_color.stride); return 1;
    case GL_FOG_COORD_ARRAY_TYPE: puti(a, c->client.fog_coord.type); return 1;
    case GL_FOG_COORD_ARRAY_STRIDE: puti(a, c->client.fog_coord.stride); return 1;
    case GL_INDEX_ARRAY_TYPE: puti(a, c->client.index.type); return 1;
    case GL_INDEX_ARRAY_STRIDE: puti(a, c->client.index.stride); return 1;
    case GL_SECONDARY_COLOR_ARRAY_BUFFER_BINDING: puti(a, c->client.secondary_color.buffer); return 1;
    case GL_FOG_COORD_ARRAY_BUFFER_BINDING: puti(a, c->client.fog_coord.buffer); return 1;
    case GL_INDEX_ARRAY_BUFFER_BINDING: puti(a, c->client.index.buffer); return 1;
    case GL_TEXTURE_COORD_ARRAY_SIZE: puti(a, st_client_array(c, GL_TEXTURE_COORD_ARRAY)->size); return 1;
    case GL_TEXTURE_COORD_ARRAY_TYPE: puti(a, st_client_array(c, GL_TEXTURE_COORD_ARRAY)->type); return 1;
    case GL_TEXTURE_COORD_ARRAY_STRIDE: puti(a, st_client_array(c, GL_TEXTURE_COORD_ARRAY)->stride); return 1;
    case GL_VERTEX_ARRAY_BUFFER_BINDING: puti(a, c->client.vertex.buffer); return 1;
    case GL_NORMAL_ARRAY_BUFFER_BINDING: puti(a, c->client.normal.buffer); return 1;
    case GL_COLOR_ARRAY_BUFFER_BINDING: puti(a, c->client.color.buffer); return 1;
    case GL_EDGE_FLAG_ARRAY_BUFFER_BINDING: puti(a, c->client.edge_flag.buffer); return 1;
    case GL_TEXTURE_COORD_ARRAY_BUFFER_BINDING: puti(a, st_client_array(c, GL_TEXTURE_COORD_ARRAY)->buffer); return 1;
    case GL_VERTEX_ARRAY:
    case GL_NORMAL_ARRAY:
    case GL_COLOR_ARRAY:
    case GL_EDGE_FLAG_ARRAY:
    case GL_SECONDARY_COLOR_ARRAY:
    case GL_FOG_COORD_ARRAY:
    case GL_INDEX_ARRAY:
    case GL_TEXTURE_COORD_ARRAY: putb(a, st_client_array(c, pname)->enabled); return 1;
    default: break;
    }
    int idx = st_enable_index(pname, au);
    if (idx >= 0) {
        putb(a, st_enabled(v, idx));
        return 1;
    }
    return 0;
}

/* The table of value counts: how many values glGet* writes for each pname
 * lookup() answers, one case per pname (the state test get_count_table
 * fails when this table and lookup() part). A count does not depend on the
 * values, so it is known even while lookup() declines a pname whose value
 * only the window system knows yet (the viewport, the draw buffer, ...). */
int tsr_state_get_count(GLenum pname)
{
    switch (pname) {
    case GL_MODELVIEW_MATRIX:
    case GL_PROJECTION_MATRIX:
    case GL_TEXTURE_MATRIX:
    case GL_TRANSPOSE_MODELVIEW_MATRIX:
    case GL_TRANSPOSE_PROJECTION_MATRIX: return 16;
    case GL_CURRENT_COLOR:
    case GL_CURRENT_TEXTURE_COORDS:
    case GL_VIEWPORT:
    case GL_SCISSOR_BOX:
    case GL_BLEND_COLOR:
    case GL_COLOR_WRITEMASK:
    case GL_COLOR_CLEAR_VALUE:
    case GL_ACCUM_CLEAR_VALUE:
    case GL_FOG_COLOR:
    case GL_LIGHT_MODEL_AMBIENT: return 4;
    case GL_CURRENT_NORMAL:
    case GL_POINT_DISTANCE_ATTENUATION: return 3;
    case GL_DEPTH_RANGE:
    case GL_POLYGON_MODE: return 2;
    case GL_EDGE_FLAG:
    case GL_CURRENT_PROGRAM:
    case GL_MODELVIEW_STACK_DEPTH:
    case GL_PROJECTION_STACK_DEPTH:
    case GL_TEXTURE_STACK_DEPTH:
    case GL_MATRIX_MODE:
    case GL_BLEND_SRC_RGB:
    case GL_BLEND_DST_RGB:
    case GL_BLEND_SRC_ALPHA:
    case GL_BLEND_DST_ALPHA:
    case GL_BLEND_EQUATION_RGB:
    case GL_BLEND_EQUATION_ALPHA:
    case GL_ALPHA_TEST_FUNC:
    case GL_ALPHA_TEST_REF:
    case GL_LOGIC_OP_MODE:
    case GL_DRAW_BUFFER:
    case GL_READ_BUFFER:
    case GL_DEPTH_FUNC:
    case GL_DEPTH_WRITEMASK:
    case GL_DEPTH_CLEAR_VALUE:
    case GL_STENCIL_FUNC:
    case GL_STENCIL_REF:
    case GL_STENCIL_FAIL:
    case GL_STENCIL_PASS_DEPTH_FAIL:
    case GL_STENCIL_PASS_DEPTH_PASS:
    case GL_STENCIL_BACK_FUNC:
    case GL_STENCIL_BACK_REF:
    case GL_STENCIL_BACK_FAIL:
    case GL_STENCIL_BACK_PASS_DEPTH_FAIL:
    case GL_STENCIL_BACK_PASS_DEPTH_PASS:
    case GL_STENCIL_CLEAR_VALUE:
    case GL_FOG_MODE:
    case GL_FOG_COORD_SRC:
    case GL_FOG_DENSITY:
    case GL_FOG_START:
    case GL_FOG_END:
    case GL_FOG_INDEX:
    case GL_LIGHT_MODEL_LOCAL_VIEWER:
    case GL_LIGHT_MODEL_TWO_SIDE:
    case GL_LIGHT_MODEL_COLOR_CONTROL:
    case GL_COLOR_MATERIAL_FACE:
    case GL_COLOR_MATERIAL_PARAMETER:
    case GL_SHADE_MODEL:
    case GL_CULL_FACE_MODE:
    case GL_FRONT_FACE:
    case GL_POLYGON_OFFSET_FACTOR:
    case GL_POLYGON_OFFSET_UNITS:
    case GL_LINE_WIDTH:
    case GL_LINE_STIPPLE_PATTERN:
    case GL_LINE_STIPPLE_REPEAT:
    case GL_POINT_SIZE:
    case GL_POINT_SIZE_MIN:
    case GL_POINT_SIZE_MAX:
    case GL_POINT_FADE_THRESHOLD_SIZE:
    case GL_POINT_SPRITE_COORD_ORIGIN:
    case GL_PERSPECTIVE_CORRECTION_HINT:
    case GL_POINT_SMOOTH_HINT:
    case GL_LINE_SMOOTH_HINT:
    case GL_POLYGON_SMOOTH_HINT:
    case GL_FOG_HINT:
    case GL_GENERATE_MIPMAP_HINT:
    case GL_TEXTURE_COMPRESSION_HINT:
    case GL_FRAGMENT_SHADER_DERIVATIVE_HINT:
    case GL_PACK_SWAP_BYTES:
    case GL_PACK_LSB_FIRST:
    case GL_UNPACK_SWAP_BYTES:
    case GL_UNPACK_LSB_FIRST:
    case GL_PACK_ROW_LENGTH:
    case GL_PACK_IMAGE_HEIGHT:
    case GL_PACK_SKIP_ROWS:
    case GL_PACK_SKIP_PIXELS:
    case GL_PACK_SKIP_IMAGES:
    case GL_PACK_ALIGNMENT:
    case GL_UNPACK_ROW_LENGTH:
    case GL_UNPACK_IMAGE_HEIGHT:
    case GL_UNPACK_SKIP_ROWS:
    case GL_UNPACK_SKIP_PIXELS:
    case GL_UNPACK_SKIP_IMAGES:
    case GL_UNPACK_ALIGNMENT:
    case GL_ZOOM_X:
    case GL_ZOOM_Y:
    case GL_RED_SCALE:
    case GL_GREEN_SCALE:
    case GL_BLUE_SCALE:
    case GL_ALPHA_SCALE:
    case GL_DEPTH_SCALE:
    case GL_RED_BIAS:
    case GL_GREEN_BIAS:
    case GL_BLUE_BIAS:
    case GL_ALPHA_BIAS:
    case GL_DEPTH_BIAS:
    case GL_INDEX_SHIFT:
    case GL_INDEX_OFFSET:
    case GL_MAP_COLOR:
    case GL_MAP_STENCIL:
    case GL_ACTIVE_TEXTURE:
    case GL_CLIENT_ACTIVE_TEXTURE:
    case GL_TEXTURE_BINDING_1D:
    case GL_TEXTURE_BINDING_2D:
    case GL_TEXTURE_BINDING_3D:
    case GL_TEXTURE_BINDING_CUBE_MAP:
    case GL_ARRAY_BUFFER_BINDING:
    case GL_ELEMENT_ARRAY_BUFFER_BINDING:
    case GL_PIXEL_PACK_BUFFER_BINDING:
    case GL_PIXEL_UNPACK_BUFFER_BINDING:
    case GL_LIST_BASE:
    case GL_LIST_INDEX:
    case GL_LIST_MODE:
    case GL_SAMPLE_COVERAGE_VALUE:
    case GL_SAMPLE_COVERAGE_INVERT:
    case GL_ATTRIB_STACK_DEPTH:
    case GL_CLIENT_ATTRIB_STACK_DEPTH:
    case GL_VERTEX_ARRAY_SIZE:
    case GL_VERTEX_ARRAY_TYPE:
    case GL_VERTEX_ARRAY_STRIDE:
    case GL_NORMAL_ARRAY_TYPE:
    case GL_NORMAL_ARRAY_STRIDE:
    case GL_COLOR_ARRAY_SIZE:
    case GL_COLOR_ARRAY_TYPE:
    case GL_COLOR_ARRAY_STRIDE:
    case GL_EDGE_FLAG_ARRAY_STRIDE:
    case GL_SECONDARY_COLOR_ARRAY_SIZE:
    case GL_SECONDARY_COLOR_ARRAY_TYPE:
    case GL_SECONDARY_COLOR_ARRAY_STRIDE:
    case GL_FOG_COORD_ARRAY_TYPE:
    case GL_FOG_COORD_ARRAY_STRIDE:
    case GL_INDEX_ARRAY_TYPE:
    case GL_INDEX_ARRAY_STRIDE:
    case GL_SECONDARY_COLOR_ARRAY_BUFFER_BINDING:
    case GL_FOG_COORD_ARRAY_BUFFER_BINDING:
    case GL_INDEX_ARRAY_BUFFER_BINDING:
    case GL_SECONDARY_COLOR_ARRAY:
    case GL_FOG_COORD_ARRAY:
    case GL_INDEX_ARRAY:
    case GL_TEXTURE_COORD_ARRAY_SIZE:
    case GL_TEXTURE_COORD_ARRAY_TYPE:
    case GL_TEXTURE_COORD_ARRAY_STRIDE:
    case GL_VERTEX_ARRAY_BUFFER_BINDING:
    case GL_NORMAL_ARRAY_BUFFER_BINDING:
    case GL_COLOR_ARRAY_BUFFER_BINDING:
    case GL_EDGE_FLAG_ARRAY_BUFFER_BINDING:
    case GL_TEXTURE_COORD_ARRAY_BUFFER_BINDING:
    case GL_VERTEX_ARRAY:
    case GL_NORMAL_ARRAY:
    case GL_COLOR_ARRAY:
    case GL_EDGE_FLAG_ARRAY:
    case GL_TEXTURE_COORD_ARRAY: return 1;
    default: return st_enable_index(pname, 0) >= 0 ? 1 : 0; /* a cap: one boolean */
    }
}

/* Mesa's conversions (main/macros.h): FLOAT_TO_INT for normalized values,
 * IROUND for the rest. Out of range, Mesa's cast gives what x86-64's
 * conversion instruction gives, INT_MIN; so do we (without the undefined
 * behaviour of the C cast). */
static GLint to_int(double v, kind k)
{
    if (k == K_NORM) {
        double r = 2147483647.0 * (double)(float)v;
        if (!(r < 2147483648.0 && r > -2147483649.0))
            return (GLint)-2147483647 - 1;
        return (GLint)r;
    }
    if (k == K_FLOAT) {
        float f = (float)v;
        return (GLint)(f >= 0.0f ? f + 0.5f : f - 0.5f);
    }
    return (GLint)(int64_t)v;
}

int tsr_state_get_doublev(const tsr_state_ctx *c, GLenum pname, GLdouble *out)
{
    answer a;
    if (!lookup(c, pname, &a))
        return 0;
    for (int i = 0; i < a.n; i++)
        out[i] = a.v[i];
    return 1;
}

int tsr_state_get_floatv(const tsr_state_ctx *c, GLenum pname, GLfloat *out)
{
    answer a;
    if (!lookup(c, pname, &a))
        return 0;
    for (int i = 0; i < a.n; i++)
        out[i] = (GLfloat)a.v[i];
    return 1;
}

int tsr_state_get_integerv(const tsr_state_ctx *c, GLenum pname, GLint *out)
{
    answer a;
    if (!lookup(c, pname, &a))
        return 0;
    for (int i = 0; i < a.n; i++)
        out[i] = to_int(a.v[i], a.k);
    return 1;
}

int tsr_state_get_booleanv(const tsr_state_ctx *c, GLenum pname, GLboolean *out)
{
    answer a;
    if (!lookup(c, pname, &a))
        return 0;
    for (int i = 0; i < a.n; i++)
        out[i] = a.v[i] != 0.0 ? GL_TRUE : GL_FALSE;
    return 1;
}

int tsr_state_is_enabled(const tsr_state_ctx *c, GLenum cap, GLboolean *out)
{
    const tsr_state_array *arr = st_client_array(c, cap);
    if (arr) {
        *out = arr->enabled;
        return 1;
    }
    int idx = st_enable_index(cap, c->v.active_texture);
    if (idx < 0)
        return 0;
    *out = (GLboolean)st_enabled(&c->v, idx);
    return 1;
}

int tsr_state_get_lightfv(const tsr_state_ctx *c, GLenum which, GLenum pname, GLfloat *out)
{
    if (which < GL_LIGHT0 || which >= GL_LIGHT0 + TSR_STATE_LIGHTS)
        return 0;
    const tsr_state_light *l = &c->v.light[which - GL_LIGHT0];
    switch (pname) {
    case GL_AMBIENT: memcpy(out, l->ambient, 16); return 1;
    case GL_DIFFUSE: memcpy(out, l->diffuse, 16); return 1;
    case GL_SPECULAR: memcpy(out, l->specular, 16); return 1;
    case GL_POSITION: memcpy(out, l->position, 16); return 1;
    case GL_SPOT_DIRECTION: memcpy(out, l->spot_direction, 12); return 1;
    case GL_SPOT_EXPONENT: *out = l->spot_exponent; return 1;
    case GL_SPOT_CUTOFF: *out = l->spot_cutoff; return 1;
    case GL_CONSTANT_ATTENUATION: *out = l->attenuation[0]; return 1;
    case GL_LINEAR_ATTENUATION: *out = l->attenuation[1]; return 1;
    case GL_QUADRATIC_ATTENUATION: *out = l->attenuation[2]; return 1;
    default: return 0;
    }
}

int tsr_state_get_materialfv(const tsr_state_ctx *c, GLenum face, GLenum pname, GLfloat *out)
{
    if (face != GL_FRONT && face != GL_BACK)
        return 0;
    const tsr_state_material *m = &c->v.material[face == GL_BACK];
    switch (pname) {
    case GL_AMBIENT: memcpy(out, m->ambient, 16); return 1;
    case GL_DIFFUSE: memcpy(out, m->diffuse, 16); return 1;
    case GL_SPECULAR: memcpy(out, m->specular, 16); return 1;
    case GL_EMISSION: memcpy(out, m->emission, 16); return 1;
    case GL_SHININESS: *out = m->shininess; return 1;
    default: return 0;
    }
}

int tsr_state_get_tex_envfv(const tsr_state_ctx *c, GLenum target, GLenum pname, GLfloat *out)
{
    GLuint u = c->v.active_texture;
    if (target == GL_TEXTURE_FILTER_CONTROL && pname == GL_TEXTURE_LOD_BIAS) {
        *out = c->v.image[u].lod_bias;
        return 1;
    }
    if (u >= TSR_STATE_UNITS)
        return 0; /* no coordinate unit: the renderer's answer (or error) */
    const tsr_state_texunit *t = &c->v.unit[u];
    if (target == GL_POINT_SPRITE && pname == GL_COORD_REPLACE) {
        *out = t->coord_replace;
        return 1;
    }
    if (target != GL_TEXTURE_ENV)
        return 0;
    switch (pname) {
    case GL_TEXTURE_ENV_MODE: *out = (GLfloat)t->env_mode; return 1;
    case GL_TEXTURE_ENV_COLOR: memcpy(out, t->env_color, 16); return 1;
    case GL_COMBINE_RGB: *out = (GLfloat)t->combine_rgb; return 1;
    case GL_COMBINE_ALPHA: *out = (GLfloat)t->combine_alpha; return 1;
    case GL_SRC0_RGB:
    case GL_SRC1_RGB:
    case GL_SRC2_RGB: *out = (GLfloat)t->src_rgb[pname - GL_SRC0_RGB]; return 1;
    case GL_SRC0_ALPHA:
    case GL_SRC1_ALPHA:
    case GL_SRC2_ALPHA: *out = (GLfloat)t->src_alpha[pname - GL_SRC0_ALPHA]; return 1;
    case GL_OPERAND0_RGB:
    case GL_OPERAND1_RGB:
    case GL_OPERAND2_RGB: *out = (GLfloat)t->operand_rgb[pname - GL_OPERAND0_RGB]; return 1;
    case GL_OPERAND0_ALPHA:
    case GL_OPERAND1_ALPHA:
    case GL_OPERAND2_ALPHA: *out = (GLfloat)t->operand_alpha[pname - GL_OPERAND0_ALPHA]; return 1;
    case GL_RGB_SCALE: *out = t->rgb_scale; return 1;
    case GL_ALPHA_SCALE: *out = t->alpha_scale; return 1;
    default: return 0;
    }
}

int tsr_state_get_tex_genfv(const tsr_state_ctx *c, GLenum coord, GLenum pname, GLfloat *out)
{
    if (coord < GL_S || coord > GL_Q || c->v.active_texture >= TSR_STATE_UNITS)
        return 0;
    const tsr_state_texgen *g = &c->v.unit[c->v.active_texture].gen[coord - GL_S];
    switch (pname) {
    case GL_TEXTURE_GEN_MODE: *out = (GLfloat)g->mode; return 1;
    case GL_OBJECT_PLANE: memcpy(out, g->object_plane, 16); return 1;
    case GL_EYE_PLANE: memcpy(out, g->eye_plane, 16); return 1;
    default: return 0;
    }
}

static const st_texobj *bound(const tsr_state_ctx *c, GLenum target)
{
    int ti = st_tex_target_index(target);
    if (ti < 0)
        return NULL;
    return st_tex_lookup((tsr_state_ctx *)c, c->v.image[c->v.active_texture].binding[ti], ti);
}

int tsr_state_get_tex_parameterfv(const tsr_state_ctx *c, GLenum target, GLenum pname, GLfloat *out)
{
    if (target != GL_TEXTURE_1D && target != GL_TEXTURE_2D && target != GL_TEXTURE_3D && target != GL_TEXTURE_CUBE_MAP)
        return 0;
    const st_texobj *o = bound(c, target);
    if (!o)
        return 0;
    const st_texparams *p = &o->params;
    switch (pname) {
    case GL_TEXTURE_MIN_FILTER: *out = (GLfloat)p->min_filter; return 1;
    case GL_TEXTURE_MAG_FILTER: *out = (GLfloat)p->mag_filter; return 1;
    case GL_TEXTURE_WRAP_S: *out = (GLfloat)p->wrap_s; return 1;
    case GL_TEXTURE_WRAP_T: *out = (GLfloat)p->wrap_t; return 1;
    case GL_TEXTURE_WRAP_R: *out = (GLfloat)p->wrap_r; return 1;
    case GL_TEXTURE_BORDER_COLOR:
        if (p->border_type)
            return 0; /* integers read as floats: the renderer's affair */
        memcpy(out, p->border_color, 16);
        return 1;
    case GL_TEXTURE_PRIORITY: *out = p->priority; return 1;
    case GL_TEXTURE_MIN_LOD: *out = p->min_lod; return 1;
    case GL_TEXTURE_MAX_LOD: *out = p->max_lod; return 1;
    case GL_TEXTURE_LOD_BIAS: *out = p->lod_bias; return 1;
    case GL_TEXTURE_BASE_LEVEL: *out = (GLfloat)p->base_level; return 1;
    case GL_TEXTURE_MAX_LEVEL: *out = (GLfloat)p->max_level; return 1;
    case GL_GENERATE_MIPMAP: *out = p->generate_mipmap; return 1;
    case GL_TEXTURE_COMPARE_MODE: *out = (GLfloat)p->compare_mode; return 1;
    case GL_TEXTURE_COMPARE_FUNC: *out = (GLfloat)p->compare_func; return 1;
    case GL_DEPTH_TEXTURE_MODE: *out = (GLfloat)p->depth_mode; return 1;
    case GL_TEXTURE_SWIZZLE_R:
    case GL_TEXTURE_SWIZZLE_G:
    case GL_TEXTURE_SWIZZLE_B:
    case GL_TEXTURE_SWIZZLE_A: *out = (GLfloat)p->swizzle[pname - GL_TEXTURE_SWIZZLE_R]; return 1;
    case GL_TEXTURE_SWIZZLE_RGBA:
        for (int i = 0; i < 4; i++)
            out[i] = (GLfloat)p->swizzle[i];
        return 1;
    default: return 0;
    }
}

int tsr_state_get_tex_parameter_int(const tsr_state_ctx *c, GLenum target, GLenum pname, GLenum type, GLint *out)
{
    if (pname != GL_TEXTURE_BORDER_COLOR || (target != GL_TEXTURE_1D && target != GL_TEXTURE_2D &&
                                             target != GL_TEXTURE_3D && target != GL_TEXTURE_CUBE_MAP))
        return 0;
    const st_texobj *o = bound(c, target);
    if (!o || o->params.border_type != type)
        return 0;
    memcpy(out, o->params.border_int, sizeof o->params.border_int);
    return 1;
}

/* The image the tracker holds for (target, level) of the bound texture,
 * or NULL (none, or levels made by the renderer's mipmap generation). */
static const st_upload *held_level(const tsr_state_ctx *c, GLenum target, GLint level)
{
    const st_texobj *o = bound(c, target);
    if (!o)
        return NULL;
    for (size_t i = o->nup; i-- > 0;) {
        if (o->up[i].kind == ST_UP_MIPMAP || o->up[i].gen_mipmap)
            return NULL; /* levels made by the renderer: ask it */
        if (o->up[i].kind == ST_UP_IMAGE && o->up[i].target == target && o->up[i].level == level)
            return &o->up[i];
    }
    return NULL;
}

int tsr_state_get_tex_level_parameteriv(const tsr_state_ctx *c, GLenum target, GLint level, GLenum pname, GLint *out)
{
    const st_upload *img = held_level(c, target, level);
    if (!img)
        return 0;
    switch (pname) {
    case GL_TEXTURE_WIDTH: *out = img->w; return 1;
    case GL_TEXTURE_HEIGHT: *out = img->dims >= 2 ? img->h : 1; return 1;
    case GL_TEXTURE_DEPTH: *out = img->dims == 3 ? img->d : 1; return 1;
    case GL_TEXTURE_BORDER: *out = img->border; return 1;
    default: return 0; /* internal format and sizes: the renderer decides */
    }
}

int tsr_state_tex_level_requested_format(const tsr_state_ctx *c, GLenum target, GLint level, GLint *out)
{
    const st_upload *img = held_level(c, target, level);
    if (!img)
        return 0;
    *out = img->internalformat;
    return 1;
}

int tsr_state_get_clip_plane(const tsr_state_ctx *c, GLenum plane, GLdouble *out)
{
    if (plane < GL_CLIP_PLANE0 || plane >= GL_CLIP_PLANE0 + TSR_STATE_CLIP_PLANES)
        return 0;
    for (int i = 0; i < 4; i++)
        out[i] = c->v.clip_plane[plane - GL_CLIP_PLANE0][i];
    return 1;
}

/* Writes the stipple as GL does: a 32x32 bitmap under the pack modes. */
int tsr_state_get_polygon_stipple(const tsr_state_ctx *c, GLubyte *out)
{
    tsr_pixel_layout l;
    const tsr_pixel_modes *m = &c->v.pixel_store.pack;
    /* With a GL_PIXEL_PACK_BUFFER bound `out` is an offset into the
     * renderer's buffer: the renderer's to write. */
    if (c->v.pixel_pack_buffer)
        return 0;
    /* Bit-shifted output (SKIP_PIXELS not a multiple of 8) is left to the
     * renderer: what lands in the partial bytes around it is its affair. */
    if (m->skip_pixels % 8 != 0 || tsr_pixel_layout_of(m, 2, 32, 32, 1, GL_COLOR_INDEX, GL_BITMAP, &l) != 0)
        return 0;
    for (int row = 0; row < 32; row++)
        for (int i = 0; i < 4; i++) {
            GLubyte b = c->v.polygon_stipple[row * 4 + i];
            if (m->lsb_first)
                b = (GLubyte)(((b * 0x0802u & 0x22110u) | (b * 0x8020u & 0x88440u)) * 0x10101u >> 16);
            out[l.first + (uint64_t)row * l.row_bytes + (uint64_t)i] = b;
        }
    return 1;
}

int tsr_state_get_buffer_parameteriv(const tsr_state_ctx *c, GLenum target, GLenum pname, GLint *out)
{
    const st_bufobj *b = st_bound_buffer(c, target);
    if (!b)
        return 0;
    /* a buffer not mapped answers GL's defaults (Mesa's access is
     * GL_READ_WRITE, the flags, offset and length 0) */
    GLbitfield access = b->mapped ? b->map_access : 0;
    switch (pname) {
    case GL_BUFFER_SIZE: *out = (GLint)b->size; return 1;
    case GL_BUFFER_USAGE: *out = (GLint)b->usage; return 1;
    case GL_BUFFER_ACCESS: *out = (GLint)tsr_map_access_enum(access); return 1;
    case GL_BUFFER_MAPPED: *out = b->mapped ? GL_TRUE : GL_FALSE; return 1;
    case GL_BUFFER_ACCESS_FLAGS: *out = (GLint)access; return 1;
    case GL_BUFFER_MAP_OFFSET: *out = b->mapped ? (GLint)b->map_offset : 0; return 1;
    case GL_BUFFER_MAP_LENGTH: *out = b->mapped ? (GLint)b->map_length : 0; return 1;
    default: return 0;
    }
}

const void *tsr_state_buffer_bytes(const tsr_state_ctx *c, GLenum target, GLsizeiptr *size)
{
    const st_bufobj *b = st_bound_buffer(c, target);
    if (!b || !b->data || b->mapped)
        return NULL;
    *size = b->size;
    return b->data;
}

GLboolean tsr_state_is_texture(const tsr_state_ctx *c, GLuint name)
{
    const st_texobj *o = name ? tsr_name_map_get(&c->textures, name) : NULL;
    return o && o->target >= 0;
}

GLboolean tsr_state_is_list(const tsr_state_ctx *c, GLuint name) { return tsr_name_map_get(&c->lists, name) != NULL; }

GLboolean tsr_state_is_buffer(const tsr_state_ctx *c, GLuint name)
{
    const st_bufobj *b = name ? st_buf_lookup(c, name) : NULL;
    return b && b->bound;
}

/* --- table entries: answer when known, else leave the outputs alone ------------ */
static void g_GetBooleanv(void *self, GLenum p, GLboolean *o) { tsr_state_get_booleanv(self, p, o); }
static void g_GetDoublev(void *self, GLenum p, GLdouble *o) { tsr_state_get_doublev(self, p, o); }
static void g_GetFloatv(void *self, GLenum p, GLfloat *o) { tsr_state_get_floatv(self, p, o); }
static void g_GetIntegerv(void *self, GLenum p, GLint *o) { tsr_state_get_integerv(self, p, o); }
static GLboolean g_IsEnabled(void *self, GLenum cap)
{
    GLboolean b = GL_FALSE;
    tsr_state_is_enabled(self, cap, &b);
    return b;
}
static void g_GetLightfv(void *self, GLenum l, GLenum p, GLfloat *o) { tsr_state_get_lightfv(self, l, p, o); }
static void g_GetMaterialfv(void *self, GLenum f, GLenum p, GLfloat *o) { tsr_state_get_materialfv(self, f, p, o); }
static void g_GetTexEnvfv(void *self, GLenum t, GLenum p, GLfloat *o) { tsr_state_get_tex_envfv(self, t, p, o); }
static void g_GetTexGenfv(void *self, GLenum t, GLenum p, GLfloat *o) { tsr_state_get_tex_genfv(self, t, p, o); }
static void g_GetTexParameterfv(void *self, GLenum t, GLenum p, GLfloat *o)
{
    tsr_state_get_tex_parameterfv(self, t, p, o);
}
static void g_GetTexParameterIivEXT(void *self, GLenum t, GLenum p, GLint *o)
{
    tsr_state_get_tex_parameter_int(self, t, p, GL_INT, o);
}
static void g_GetTexParameterIuivEXT(void *self, GLenum t, GLenum p, GLuint *o)
{
    tsr_state_get_tex_parameter_int(self, t, p, GL_UNSIGNED_INT, (GLint *)o);
}
static void g_GetTexLevelParameteriv(void *self, GLenum t, GLint l, GLenum p, GLint *o)
{
    tsr_state_get_tex_level_parameteriv(self, t, l, p, o);
}
static void g_GetClipPlane(void *self, GLenum p, GLdouble *o) { tsr_state_get_clip_plane(self, p, o); }
static void g_GetPolygonStipple(void *self, GLubyte *o) { tsr_state_get_polygon_stipple(self, o); }
static void g_GetBufferParameteriv(void *self, GLenum t, GLenum p, GLint *o)
{
    tsr_state_get_buffer_parameteriv(self, t, p, o);
}
static void g_GetPointerv(void *self, GLenum pname, void **out)
{
    const tsr_state_ctx *c = self;
    const tsr_state_array *a = pname == GL_VERTEX_ARRAY_POINTER            ? &c->client.vertex
                               : pname == GL_NORMAL_ARRAY_POINTER          ? &c->client.normal
                               : pname == GL_COLOR_ARRAY_POINTER           ? &c->client.color
                               : pname == GL_EDGE_FLAG_ARRAY_POINTER       ? &c->client.edge_flag
                               : pname == GL_SECONDARY_COLOR_ARRAY_POINTER ? &c->client.secondary_color
                               : pname == GL_FOG_COORD_ARRAY_POINTER       ? &c->client.fog_coord
                               : pname == GL_INDEX_ARRAY_POINTER           ? &c->client.index
                               : pname == GL_TEXTURE_COORD_ARRAY_POINTER
                                   ? &c->client.texcoord[c->client.client_active_texture]
                                   : NULL;
    if (a)
        *out = (void *)a->pointer;
}
/* The program's own pointer; a call GL refuses leaves `out` alone (the
 * packer beside the tracker raises its error). */
static void g_GetVertexAttribPointerv(void *self, GLuint index, GLenum pname, void **out)
{
    const tsr_state_ctx *c = self;
    if (index < TSR_STATE_ATTRIBS && pname == GL_VERTEX_ATTRIB_ARRAY_POINTER && out)
        *out = (void *)c->client.attrib[index].pointer;
}
static GLboolean g_IsTexture(void *self, GLuint n) { return tsr_state_is_texture(self, n); }
/* Mesa keeps every texture resident: GL_TRUE when every name is a texture
 * object (glGenTextures makes them), and `residences` untouched. */
static GLboolean g_AreTexturesResident(void *self, GLsizei n, const GLuint *names, GLboolean *residences)
{
    const tsr_state_ctx *c = self;
    (void)residences;
    for (GLsizei i = 0; i < n && names; i++)
        if (!names[i] || !tsr_name_map_get(&c->textures, names[i]))
            return GL_FALSE;
    return n >= 0 && names ? GL_TRUE : GL_FALSE;
}
static GLboolean g_IsList(void *self, GLuint n) { return tsr_state_is_list(self, n); }
static GLboolean g_IsBuffer(void *self, GLuint n) { return tsr_state_is_buffer(self, n); }

void st_get_fill_dispatch(tsr_state_ctx *c, tsr_dispatch *d)
{
#define SET(name) tsr_set_##name(d, g_##name, c)
    SET(GetBooleanv);
    SET(GetDoublev);
    SET(GetFloatv);
    SET(GetIntegerv);
    SET(IsEnabled);
    SET(GetLightfv);
    SET(GetMaterialfv);
    SET(GetTexEnvfv);
    SET(GetTexGenfv);
    SET(GetTexParameterfv);
    SET(GetTexParameterIivEXT);
    SET(GetTexParameterIuivEXT);
    SET(GetTexLevelParameteriv);
    SET(GetClipPlane);
    SET(GetPolygonStipple);
    SET(GetBufferParameteriv);
    SET(IsTexture);
    SET(AreTexturesResident);
    SET(IsList);
    SET(IsBuffer);
    SET(GetPointerv);
    SET(GetVertexAttribPointerv);
#undef SET
}

/* --- shaders and programs (the objects are core/state/state_glsl.c's) -------- */
int tsr_state_get_shaderiv(const tsr_state_ctx *c, GLuint shader, GLenum pname, GLint *out)
{
    const st_shader *o = tsr_name_map_get(&c->shaders, shader);
    if (!o)
        return 0;
    switch (pname) {
    case GL_SHADER_TYPE: *out = (GLint)o->type; return 1;
    case GL_DELETE_STATUS: *out = o->delete_pending; return 1;
    case GL_SHADER_SOURCE_LENGTH: *out = o->source ? o->source->len + 1 : 0; return 1;
    default: return 0;
    }
}

int tsr_state_get_programiv(const tsr_state_ctx *c, GLuint program, GLenum pname, GLint *out)
{
    const st_program *p = tsr_name_map_get(&c->programs, program);
    if (!p)
        return 0;
    switch (pname) {
    case GL_DELETE_STATUS: *out = p->delete_pending; return 1;
    case GL_ATTACHED_SHADERS: *out = (GLint)p->nattached; return 1;
    default: return 0;
    }
}
