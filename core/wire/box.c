/* core/wire/box.c — the window-space box of object-space geometry: the
 * packer's box (or any points) under projection * modelview and the
 * viewport, in whole pixels, grown by a margin and clamped to the window.
 * Shared by the SPUs that place geometry by its box: tilesort (which
 * servers a buffer must reach) and binaryswap (the region a peer reads
 * back). Owns nothing; never calls GL (the caller passes the matrices and
 * the viewport it tracks or queried). */
#include <math.h>

#include "tessera/dev/pack.h"

void tsr_box_clip_matrix(const GLfloat *p, const GLfloat *m, double pm[16])
{
    /* in double: the box only has to contain what the renderer draws, and
     * the margin absorbs rounding */
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += (double)p[k * 4 + r] * (double)m[c * 4 + k];
            pm[c * 4 + r] = s;
        }
}

int tsr_box_window(const GLfloat *p, const GLfloat *m, const GLint *vp, const float mn[3], const float mx[3],
                   double margin, int clip, int win_w, int win_h, int box[4])
{
    double pm[16];
    tsr_box_clip_matrix(p, m, pm);
    float corners[8][4];
    for (int corner = 0; corner < 8; corner++) {
        corners[corner][0] = (corner & 1) ? mx[0] : mn[0];
        corners[corner][1] = (corner & 2) ? mx[1] : mn[1];
        corners[corner][2] = (corner & 4) ? mx[2] : mn[2];
        corners[corner][3] = 1.0f;
    }
    return tsr_box_points_window(pm, vp, (const float(*)[4])corners, 8, margin, clip, win_w, win_h, box);
}

/* Clip-space points of a convex hull: at most 8 corners, then what two
 * plane clips of the pair rule below make of them (8 -> 4 + 4x4 = 20 ->
 * 10 + 10x10 = 110). */
#define BOX_MAX_POINTS 128

/* Keeps the part of the hull of pts[0..n) where d(p) = a*z + b*w >= 0:
 * the points inside, and where the segment between every inside and every
 * outside point crosses the plane. Every vertex of hull ∩ half-space is
 * one of those (a hull vertex inside, or where a hull edge, a segment
 * between two hull vertices, crosses), and all of them lie in it, so the
 * hull of the result is exactly hull ∩ half-space. Returns the new n. */
static int clip_plane(double (*pts)[4], int n, double a, double b)
{
    double d[BOX_MAX_POINTS], out[BOX_MAX_POINTS][4];
    int in = 0, m = 0;
    for (int i = 0; i < n; i++) {
        d[i] = a * pts[i][2] + b * pts[i][3];
        if (d[i] >= 0)
            in++;
    }
    if (in == n)
        return n;
    for (int i = 0; i < n; i++)
        if (d[i] >= 0) {
            for (int c = 0; c < 4; c++)
                out[m][c] = pts[i][c];
            m++;
        }
    for (int i = 0; i < n; i++) {
        if (d[i] < 0)
            continue;
        for (int j = 0; j < n && m < BOX_MAX_POINTS; j++) {
            if (d[j] >= 0)
                continue;
            double t = d[i] / (d[i] - d[j]);
            for (int c = 0; c < 4; c++)
                out[m][c] = pts[i][c] + t * (pts[j][c] - pts[i][c]);
            m++;
        }
    }
    for (int i = 0; i < m; i++)
        for (int c = 0; c < 4; c++)
            pts[i][c] = out[i][c];
    return m;
}

int tsr_box_points_window(const double pm[16], const GLint *vp, const float (*pts)[4], int n, double margin, int clip,
                          int win_w, int win_h, int box[4])
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    double c4[BOX_MAX_POINTS][4];
    int behind = 0;
    for (int i = 0; i < n; i++) {
        const float *v = pts[i];
        double cv[4];
        for (int r = 0; r < 4; r++)
            cv[r] = pm[r] * v[0] + pm[4 + r] * v[1] + pm[8 + r] * v[2] + pm[12 + r] * v[3];
        for (int r = 0; r < 4; r++)
            if (!isfinite(cv[r]))
                return 0;
        if (i < 8)
            for (int r = 0; r < 4; r++)
                c4[i][r] = cv[r];
        if (!(cv[3] > 0)) {
            behind = 1;
            continue;
        }
        for (int a = 0; a < 2; a++) {
            double ndc = cv[a] / cv[3];
            if (!isfinite(ndc))
                return 0;
            lo[a] = fmin(lo[a], ndc);
            hi[a] = fmax(hi[a], ndc);
        }
    }
    if (behind && (!clip || n > 8))
        return 0;
    if (behind) {
        /* GL draws only what lies between the near and far planes, -w <= z
         * <= w, where w >= 0 follows: clip the hull there, the planes
         * relaxed a little so that the renderer's own clipping (in float)
         * never keeps a sliver outside. */
        const double slack = 1.0 + 1e-4;
        n = clip_plane(c4, n, 1.0, slack);  /* z + w >= 0 */
        n = clip_plane(c4, n, -1.0, slack); /* w - z >= 0 */
        lo[0] = lo[1] = INFINITY;
        hi[0] = hi[1] = -INFINITY;
        for (int i = 0; i < n; i++) {
            if (!(c4[i][3] > 0)) {
                /* where the clipped hull touches the eye (z = w = 0) its
                 * direction on the screen is unbounded */
                lo[0] = lo[1] = -1.0;
                hi[0] = hi[1] = 1.0;
                break;
            }
            for (int a = 0; a < 2; a++) {
                double ndc = c4[i][a] / c4[i][3];
                if (!isfinite(ndc))
                    return 0;
                lo[a] = fmin(lo[a], ndc);
                hi[a] = fmax(hi[a], ndc);
            }
        }
        if (n == 0) {
            box[0] = box[1] = box[2] = box[3] = 0;
            return 1;
        }
    }
    /* Only what lies inside the clip volume is drawn (wide points and
     * lines reach out of it by the margin, added below). */
    for (int a = 0; a < 2; a++) {
        lo[a] = fmax(lo[a], -1.0);
        hi[a] = fmin(hi[a], 1.0);
        if (lo[a] > hi[a]) {
            box[0] = box[1] = box[2] = box[3] = 0;
            return 1;
        }
    }
    double wx0 = vp[0] + (lo[0] + 1.0) * 0.5 * vp[2], wx1 = vp[0] + (hi[0] + 1.0) * 0.5 * vp[2];
    double wy0 = vp[1] + (lo[1] + 1.0) * 0.5 * vp[3], wy1 = vp[1] + (hi[1] + 1.0) * 0.5 * vp[3];
    double fx0 = floor(wx0 - margin), fy0 = floor(wy0 - margin);
    double fx1 = ceil(wx1 + margin) + 1, fy1 = ceil(wy1 + margin) + 1;
    box[0] = fx0 < 0 ? 0 : fx0 > win_w ? win_w : (int)fx0;
    box[1] = fy0 < 0 ? 0 : fy0 > win_h ? win_h : (int)fy0;
    box[2] = fx1 < 0 ? 0 : fx1 > win_w ? win_w : (int)fx1;
    box[3] = fy1 < 0 ? 0 : fy1 > win_h ? win_h : (int)fy1;
    return 1;
}
