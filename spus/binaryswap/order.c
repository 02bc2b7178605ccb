/* spus/binaryswap/order.c — the compositing order of a group. Depth mode
 * composites in rank order (equal depth to the lower rank). Alpha mode
 * blends the peers' premultiplied layers in view order, front first, and
 * that order is the graph's: `view_order: [2, 0, 1]` lists the ranks from
 * the front. The executor's participants are positions in this order; the
 * SPU maps them to ranks (view[], pos[]) when it sends and receives. Every
 * peer reads the same option, so they agree without a message.
 *
 * Or, when every peer has a `box` (its part's object-space bounding box)
 * and view_order is empty, the order is computed at every frame from the
 * boxes and the modelview current at SwapBuffers: each peer's centre
 * distance in front of the eye, exchanged among the peers (layers.h), so
 * the order follows a moving camera. Either way each part must be convex
 * (or drawn sorted) and the parts separable along the view direction. */
#include <stdlib.h>
#include <string.h>

#include "layers.h"

int binaryswap_view_order(const tsr_options *o, int alpha, int nranks, int *view, int *pos, tsr_error *err)
{
    size_t n = tsr_options_count(o, "view_order");
    for (int r = 0; r < nranks; r++)
        view[r] = pos[r] = r;
    if (!n)
        return TSR_OK;
    if (!alpha)
        return tsr_error_set(err, TSR_EINVAL, "view_order is for mode=alpha (depth mode composites in rank order)");
    if (n != (size_t)nranks)
        return tsr_error_set(err, TSR_EINVAL, "view_order lists %zu ranks, the group has %d", n, nranks);
    for (int r = 0; r < nranks; r++)
        pos[r] = -1;
    for (size_t p = 0; p < n; p++) {
        const char *text = tsr_options_string_at(o, "view_order", p);
        char *end;
        long r = strtol(text, &end, 10);
        if (!text[0] || *end || r < 0 || r >= nranks)
            return tsr_error_set(err, TSR_EINVAL, "view_order entry %zu is '%s', not a rank 0..%d", p + 1, text,
                                 nranks - 1);
        if (pos[r] >= 0)
            return tsr_error_set(err, TSR_EINVAL, "view_order lists rank %ld twice (entries %d and %zu)", r, pos[r] + 1,
                                 p + 1);
        pos[r] = (int)p;
        view[p] = (int)r;
    }
    return TSR_OK;
}

int binaryswap_box_parse(const tsr_options *o, float box[6], int *has, tsr_error *err)
{
    size_t n = tsr_options_count(o, "box");
    *has = n > 0;
    if (!n)
        return TSR_OK;
    if (n != 6)
        return tsr_error_set(err, TSR_EINVAL, "box has %zu numbers, not 6 (xmin, ymin, zmin, xmax, ymax, zmax)", n);
    for (size_t i = 0; i < 6; i++) {
        const char *text = tsr_options_string_at(o, "box", i);
        char *end;
        box[i] = strtof(text, &end);
        if (!text[0] || *end || box[i] != box[i])
            return tsr_error_set(err, TSR_EINVAL, "box entry %zu is '%s', not a number", i + 1, text);
    }
    for (int i = 0; i < 3; i++)
        if (box[i] > box[i + 3])
            return tsr_error_set(err, TSR_EINVAL, "box: its minimum %c (%g) is above its maximum (%g)", "xyz"[i],
                                 (double)box[i], (double)box[i + 3]);
    return TSR_OK;
}

float binaryswap_box_distance(const float box[6], const float modelview[16])
{
    float c[3] = {0.5f * (box[0] + box[3]), 0.5f * (box[1] + box[4]), 0.5f * (box[2] + box[5])};
    /* column-major, as GL returns it: eye z is row 2 */
    float z = modelview[2] * c[0] + modelview[6] * c[1] + modelview[10] * c[2] + modelview[14];
    return -z;
}

void binaryswap_order_by_distance(const float *distance, int nranks, int *view, int *pos)
{
    for (int r = 0; r < nranks; r++)
        view[r] = r;
    /* insertion sort: at most 64 peers; equal distance keeps rank order */
    for (int i = 1; i < nranks; i++) {
        int r = view[i], j = i;
        while (j > 0 && distance[view[j - 1]] > distance[r]) {
            view[j] = view[j - 1];
            j--;
        }
        view[j] = r;
    }
    for (int p = 0; p < nranks; p++)
        pos[view[p]] = p;
}
