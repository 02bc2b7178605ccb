/* examples/isosurface.c — marching-cubes isosurfaces of analytic fields,
 * drawn with client vertex arrays: moving metaballs (shared vertices,
 * glDrawElements) and a slab of a gyroid (flat triangle list with a colour
 * array, glDrawArrays). Ordinary GL 1.x code; owns the field, the mesh and
 * its drawing. Deterministic per frame (the field depends only on it).
 *
 * --part K/N (sort-last): the primitives are the triangles, numbered in
 * draw order (the metaballs' then the gyroid's); share K draws the run
 * exapp_part_range gives it, from whichever of the two meshes it covers,
 * so a share may end in the middle of a surface.
 *
 * --static, --orbit DEG, --jump K (the load balancers' scenes, issue 13):
 * the field is frame 0's in every frame; the camera stays (--static),
 * orbits DEG degrees a frame about the vertical axis (--orbit), and/or
 * turns 90 degrees at once at frame K and stays there (--jump). Without
 * them the field moves and the camera turns 8 degrees a frame. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>

#include "common/exapp.h"

/* --- marching-cubes case table, derived at start-up ----------------------
 * Instead of a hand-typed 256-case table, each case is built from the cube
 * faces: on every face the surface crosses 0, 2 or 4 edges; crossings are
 * joined into segments (with 4, the inside corners are cut off separately,
 * a rule that depends only on the face, so neighbouring cells agree and the
 * surface is closed). Each crossed edge lies on two faces, so the segments
 * form closed loops; every loop is fanned into triangles. */

#define MC_MAX_TRIS 12

typedef struct mc_case {
    int tri_count;
    unsigned char edges[MC_MAX_TRIS * 3]; /* cube edge index per triangle corner */
} mc_case;

/* Corner c sits at (c & 1, c >> 1 & 1, c >> 2 & 1). Edge e joins corners
 * edge_corner[e][0] -> [1], which differ in bit edge_axis[e]. */
static int edge_corner[12][2];
static int edge_axis[12];

static int find_edge(int a, int b)
{
    for (int e = 0; e < 12; e++)
        if ((edge_corner[e][0] == a && edge_corner[e][1] == b) || (edge_corner[e][0] == b && edge_corner[e][1] == a))
            return e;
    return -1;
}

static void build_mc_table(mc_case table[256])
{
    int n = 0;
    for (int c = 0; c < 8; c++)
        for (int axis = 0; axis < 3; axis++)
            if (!(c & (1 << axis))) {
                edge_corner[n][0] = c;
                edge_corner[n][1] = c | (1 << axis);
                edge_axis[n] = axis;
                n++;
            }
    /* Faces: axis a fixed at value v; corners in cyclic order. */
    int faces[6][4];
    for (int a = 0, f = 0; a < 3; a++)
        for (int v = 0; v < 2; v++, f++) {
            int u = (a + 1) % 3, w = (a + 2) % 3;
            int base = v << a;
            faces[f][0] = base;
            faces[f][1] = base | 1 << u;
            faces[f][2] = base | 1 << u | 1 << w;
            faces[f][3] = base | 1 << w;
        }
    for (int config = 0; config < 256; config++) {
        int link[12][2]; /* each crossed edge's two neighbours in its loop */
        int link_count[12] = {0};
        for (int f = 0; f < 6; f++) {
            int crossed[4], inside_first[4], k = 0;
            for (int i = 0; i < 4; i++) {
                int a = faces[f][i], b = faces[f][(i + 1) % 4];
                int ina = config >> a & 1, inb = config >> b & 1;
                if (ina != inb) {
                    crossed[k] = find_edge(a, b);
                    inside_first[k] = ina;
                    k++;
                }
            }
            /* Join crossings pairwise: with 4, pair each crossing that
             * leaves an inside corner with the one entering it before. */
            int pairs[2][2], pair_count = 0;
            if (k == 2) {
                pairs[0][0] = crossed[0];
                pairs[0][1] = crossed[1];
                pair_count = 1;
            } else if (k == 4) {
                for (int i = 0; i < 4; i++)
                    if (inside_first[i]) {
                        pairs[pair_count][0] = crossed[(i + 3) % 4];
                        pairs[pair_count][1] = crossed[i];
                        pair_count++;
                    }
            }
            for (int p = 0; p < pair_count; p++) {
                int a = pairs[p][0], b = pairs[p][1];
                link[a][link_count[a]++] = b;
                link[b][link_count[b]++] = a;
            }
        }
        mc_case *mc = &table[config];
        mc->tri_count = 0;
        int visited[12] = {0};
        for (int start = 0; start < 12; start++) {
            if (link_count[start] != 2 || visited[start])
                continue;
            int loop[12], len = 0, prev = -1, cur = start;
            while (!visited[cur]) {
                visited[cur] = 1;
                loop[len++] = cur;
                int next = link[cur][0] != prev ? link[cur][0] : link[cur][1];
                prev = cur;
                cur = next;
            }
            for (int i = 1; i + 1 < len; i++) {
                unsigned char *t = &mc->edges[mc->tri_count * 3];
                t[0] = (unsigned char)loop[0];
                t[1] = (unsigned char)loop[i];
                t[2] = (unsigned char)loop[i + 1];
                mc->tri_count++;
            }
        }
    }
}

/* --- meshes ---------------------------------------------------------------- */

typedef struct mesh {
    float *positions, *normals; /* xyz per vertex */
    unsigned *indices;
    size_t vertex_count, vertex_cap;
    size_t index_count, index_cap;
} mesh;

static void *xrealloc(void *p, size_t bytes)
{
    void *q = realloc(p, bytes);
    if (!q) {
        fprintf(stderr, "isosurface: out of memory\n");
        exit(1);
    }
    return q;
}

static size_t mesh_add_vertex(mesh *m, const float p[3], const float n[3])
{
    if (m->vertex_count == m->vertex_cap) {
        m->vertex_cap = m->vertex_cap ? 2 * m->vertex_cap : 4096;
        m->positions = xrealloc(m->positions, m->vertex_cap * 3 * sizeof(float));
        m->normals = xrealloc(m->normals, m->vertex_cap * 3 * sizeof(float));
    }
    memcpy(m->positions + 3 * m->vertex_count, p, 3 * sizeof(float));
    memcpy(m->normals + 3 * m->vertex_count, n, 3 * sizeof(float));
    return m->vertex_count++;
}

static void mesh_add_index(mesh *m, size_t v)
{
    if (m->index_count == m->index_cap) {
        m->index_cap = m->index_cap ? 2 * m->index_cap : 4096;
        m->indices = xrealloc(m->indices, m->index_cap * sizeof(unsigned));
    }
    m->indices[m->index_count++] = (unsigned)v;
}

static void mesh_free(mesh *m)
{
    free(m->positions);
    free(m->normals);
    free(m->indices);
    memset(m, 0, sizeof *m);
}

/* --- fields --------------------------------------------------------------- */

typedef float (*field_fn)(const float p[3], const void *params);

typedef struct metaballs {
    float centres[5][3];
    float radii[5];
} metaballs;

static float metaball_field(const float p[3], const void *params)
{
    const metaballs *mb = params;
    float sum = 0;
    for (int i = 0; i < 5; i++) {
        float dx = p[0] - mb->centres[i][0], dy = p[1] - mb->centres[i][1], dz = p[2] - mb->centres[i][2];
        sum += mb->radii[i] * mb->radii[i] / (dx * dx + dy * dy + dz * dz + 1e-6f);
    }
    return sum - 1.0f;
}

static float gyroid_field(const float p[3], const void *params)
{
    const float *scale = params;
    float x = p[0] * *scale, y = p[1] * *scale, z = p[2] * *scale;
    return sinf(x) * cosf(y) + sinf(y) * cosf(z) + sinf(z) * cosf(x);
}

/* Outward normal: minus the gradient for metaballs (field grows inwards). */
static void field_normal(field_fn f, const void *params, const float p[3], float sign, float n[3])
{
    const float h = 1e-3f;
    for (int a = 0; a < 3; a++) {
        float q0[3] = {p[0], p[1], p[2]}, q1[3] = {p[0], p[1], p[2]};
        q0[a] -= h;
        q1[a] += h;
        n[a] = sign * (f(q1, params) - f(q0, params));
    }
    float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (len > 0)
        for (int a = 0; a < 3; a++)
            n[a] /= len;
}

/* The case table's fans have arbitrary winding; make each triangle
 * counter-clockwise seen from where its vertex normals point, so front
 * faces (and two-sided lighting) are right. */
static void orient_triangles(mesh *m, size_t first_index)
{
    for (size_t i = first_index; i + 2 < m->index_count; i += 3) {
        const float *a = m->positions + 3 * m->indices[i];
        const float *b = m->positions + 3 * m->indices[i + 1];
        const float *c = m->positions + 3 * m->indices[i + 2];
        float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        float face[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        float dot = 0;
        for (int k = 0; k < 3; k++)
            for (int a3 = 0; a3 < 3; a3++)
                dot += face[a3] * m->normals[3 * m->indices[i + (size_t)k] + (size_t)a3];
        if (dot < 0) {
            unsigned t = m->indices[i + 1];
            m->indices[i + 1] = m->indices[i + 2];
            m->indices[i + 2] = t;
        }
    }
}

/* Polygonises f > 0 on an n^3 grid over [lo, hi]^3 into an indexed mesh:
 * a vertex per crossed grid edge, shared by every cell that touches it. */
static void polygonise(const mc_case table[256], field_fn f, const void *params, float sign, int n, float lo, float hi,
                       mesh *out)
{
    int np = n + 1;
    float step = (hi - lo) / (float)n;
    float *values = xrealloc(NULL, (size_t)np * np * np * sizeof(float));
    int *edge_vertex = xrealloc(NULL, (size_t)np * np * np * 3 * sizeof(int));
    for (int z = 0; z < np; z++)
        for (int y = 0; y < np; y++)
            for (int x = 0; x < np; x++) {
                float p[3] = {lo + step * (float)x, lo + step * (float)y, lo + step * (float)z};
                values[((size_t)z * np + y) * np + x] = f(p, params);
            }
    for (size_t i = 0; i < (size_t)np * np * np * 3; i++)
        edge_vertex[i] = -1;

    /* Cells go brick by brick (BRICK^3 cells), as cache-friendly marching
     * cubes does: consecutive triangles stay close together on screen. */
    enum { BRICK = 8 };
    for (int bz = 0; bz < n; bz += BRICK)
        for (int by = 0; by < n; by += BRICK)
            for (int bx = 0; bx < n; bx += BRICK)
                for (int z = bz; z < n && z < bz + BRICK; z++)
                    for (int y = by; y < n && y < by + BRICK; y++)
                        for (int x = bx; x < n && x < bx + BRICK; x++) {
                            int config = 0;
                            for (int c = 0; c < 8; c++) {
                                size_t gi = ((size_t)(z + (c >> 2 & 1)) * np + (y + (c >> 1 & 1))) * np + (x + (c & 1));
                                if (values[gi] > 0)
                                    config |= 1 << c;
                            }
                            const mc_case *mc = &table[config];
                            size_t first_index = out->index_count;
                            for (int t = 0; t < mc->tri_count * 3; t++) {
                                int e = mc->edges[t];
                                int c0 = edge_corner[e][0], c1 = edge_corner[e][1];
                                int gx = x + (c0 & 1), gy = y + (c0 >> 1 & 1), gz = z + (c0 >> 2 & 1);
                                size_t g0 = ((size_t)gz * np + gy) * np + gx;
                                size_t key = g0 * 3 + (size_t)edge_axis[e];
                                if (edge_vertex[key] < 0) {
                                    size_t g1 =
                                        ((size_t)(z + (c1 >> 2 & 1)) * np + (y + (c1 >> 1 & 1))) * np + (x + (c1 & 1));
                                    float v0 = values[g0], v1 = values[g1];
                                    float s = v0 / (v0 - v1);
                                    float p[3] = {lo + step * (float)gx, lo + step * (float)gy, lo + step * (float)gz};
                                    p[edge_axis[e]] += s * step;
                                    float nrm[3];
                                    field_normal(f, params, p, sign, nrm);
                                    edge_vertex[key] = (int)mesh_add_vertex(out, p, nrm);
                                }
                                mesh_add_index(out, (size_t)edge_vertex[key]);
                            }
                            orient_triangles(out, first_index);
                        }
    free(values);
    free(edge_vertex);
}

/* --- drawing -------------------------------------------------------------- */

static void setup(const exapp *app)
{
    glViewport(0, 0, app->width, app->height);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    double aspect = (double)app->width / (double)app->height;
    glFrustum(-0.4 * aspect, 0.4 * aspect, -0.4, 0.4, 1.0, 20.0);
    glMatrixMode(GL_MODELVIEW);
    glClearColor(0.1f, 0.1f, 0.1f, 1.0f);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glEnable(GL_LIGHT1);
    GLfloat white[4] = {0.7f, 0.7f, 0.65f, 1}, blue[4] = {0.3f, 0.35f, 0.6f, 1};
    glLightfv(GL_LIGHT0, GL_DIFFUSE, white);
    glLightfv(GL_LIGHT1, GL_DIFFUSE, blue);
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
    glEnable(GL_COLOR_MATERIAL);
    glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
    GLfloat spec[4] = {0.5f, 0.5f, 0.5f, 1};
    glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, spec);
    glMaterialf(GL_FRONT_AND_BACK, GL_SHININESS, 32.0f);
}

/* What moves: the field's time and the camera's angle per frame. */
typedef struct motion {
    bool still_field; /* --static, --orbit or --jump: frame 0's field */
    double orbit;     /* degrees a frame */
    double jump;      /* the frame from which the camera is turned 90 degrees; < 0: none */
} motion;

static void draw(const exapp *app, const mc_case table[256], int frame, int detail, const motion *mo)
{
    float t = mo->still_field ? 0.0f : 0.25f * (float)frame;
    float angle = (float)(mo->orbit * frame + (mo->jump >= 0 && frame >= mo->jump ? 90.0 : 0.0));
    metaballs mb;
    for (int i = 0; i < 5; i++) {
        float phase = (float)i * 1.3f;
        mb.centres[i][0] = 0.55f * sinf(t + phase);
        mb.centres[i][1] = 0.45f * cosf(0.7f * t + 2.0f * phase);
        mb.centres[i][2] = 0.5f * sinf(1.3f * t + 0.5f * phase);
        mb.radii[i] = 0.2f + 0.03f * (float)i;
    }
    mesh balls = {0};
    polygonise(table, metaball_field, &mb, -1.0f, 80 * detail, -1.2f, 1.2f, &balls);

    float gyroid_scale = 6.0f;
    mesh gyroid = {0};
    polygonise(table, gyroid_field, &gyroid_scale, 1.0f, 64 * detail, -1.0f, 1.0f, &gyroid);
    /* Flatten the gyroid into a plain triangle list with per-vertex colour,
     * to be drawn with glDrawArrays. */
    size_t flat_count = gyroid.index_count;
    float *flat_pos = xrealloc(NULL, (flat_count + 1) * 3 * sizeof(float));
    float *flat_nrm = xrealloc(NULL, (flat_count + 1) * 3 * sizeof(float));
    float *flat_col = xrealloc(NULL, (flat_count + 1) * 4 * sizeof(float));
    for (size_t i = 0; i < flat_count; i++) {
        size_t v = gyroid.indices[i];
        memcpy(flat_pos + 3 * i, gyroid.positions + 3 * v, 3 * sizeof(float));
        memcpy(flat_nrm + 3 * i, gyroid.normals + 3 * v, 3 * sizeof(float));
        const float *p = gyroid.positions + 3 * v;
        flat_col[4 * i + 0] = 0.5f + 0.5f * p[0];
        flat_col[4 * i + 1] = 0.6f;
        flat_col[4 * i + 2] = 0.5f - 0.5f * p[0];
        flat_col[4 * i + 3] = 1.0f;
    }

    /* This process's share of the triangles (header comment). */
    long ball_tris = (long)balls.index_count / 3, first = 0;
    long count = exapp_part_range(app, ball_tris + (long)flat_count / 3, &first);
    long ball_first = first < ball_tris ? first : ball_tris;
    long ball_count = (first + count < ball_tris ? first + count : ball_tris) - ball_first;
    long flat_first = (first > ball_tris ? first : ball_tris) - ball_tris;
    long flat_tris = first + count - ball_tris - flat_first;
    if (flat_tris < 0)
        flat_tris = 0;

    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glLoadIdentity();
    GLfloat l0[4] = {2, 3, 4, 0}, l1[4] = {-3, -1, 1, 0};
    glLightfv(GL_LIGHT0, GL_POSITION, l0);
    glLightfv(GL_LIGHT1, GL_POSITION, l1);
    glTranslatef(0, 0, -4.2f);
    glRotatef(25.0f, 1, 0, 0);
    glRotatef(angle, 0, 1, 0);

    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_NORMAL_ARRAY);

    /* Metaballs: indexed, shared vertices. */
    glPushMatrix();
    glTranslatef(-0.75f, 0, 0);
    glScalef(0.8f, 0.8f, 0.8f);
    glColor3f(0.95f, 0.55f, 0.2f);
    glVertexPointer(3, GL_FLOAT, 0, balls.positions);
    glNormalPointer(GL_FLOAT, 0, balls.normals);
    if (ball_count > 0)
        glDrawElements(GL_TRIANGLES, (GLsizei)(3 * ball_count), GL_UNSIGNED_INT, balls.indices + 3 * ball_first);
    glPopMatrix();

    /* Gyroid slab: flat triangle list with a colour array. */
    glPushMatrix();
    glTranslatef(0.85f, 0, 0);
    glScalef(0.6f, 0.6f, 0.6f);
    glEnableClientState(GL_COLOR_ARRAY);
    glVertexPointer(3, GL_FLOAT, 0, flat_pos);
    glNormalPointer(GL_FLOAT, 0, flat_nrm);
    glColorPointer(4, GL_FLOAT, 0, flat_col);
    if (flat_tris > 0)
        glDrawArrays(GL_TRIANGLES, (GLint)(3 * flat_first), (GLsizei)(3 * flat_tris));
    glDisableClientState(GL_COLOR_ARRAY);
    glPopMatrix();

    glDisableClientState(GL_NORMAL_ARRAY);
    glDisableClientState(GL_VERTEX_ARRAY);

    /* GL reads client arrays during the draw call: freeing them now is fine. */
    free(flat_pos);
    free(flat_nrm);
    free(flat_col);
    mesh_free(&balls);
    mesh_free(&gyroid);
}

int main(int argc, char **argv)
{
    exapp app;
    motion mo = {false, 8.0, -1};
    double orbit = 0, jump = -1;
    bool still = false, orbits = false, jumps = false;
    const exapp_option options[] = {
        {"--static", "  --static        nothing moves: frame 0's field and camera in every frame", 0, 0, NULL, &still},
        {"--orbit", "  --orbit DEG     frame 0's field, the camera orbiting DEG degrees a frame", -360, 360, &orbit,
         &orbits},
        {"--jump", "  --jump K        frame 0's field, the camera turned 90 degrees from frame K on", 0, 1000000, &jump,
         &jumps},
    };
    if (!exapp_init_options(&app, "isosurface", argc, argv, 640, 480, options, 3))
        return exapp_finish(&app);
    if (still || orbits || jumps) {
        mo.still_field = true;
        mo.orbit = orbits ? orbit : 0;
        mo.jump = jumps ? floor(jump) : -1;
    }
    static mc_case table[256];
    build_mc_table(table);
    setup(&app);
    for (int f = 0; f < app.frames; f++) {
        draw(&app, table, f, app.detail, &mo);
        if (!exapp_swap(&app))
            break;
    }
    return exapp_finish(&app);
}
