/* spus/binaryswap/order.c — the compositing order of a group. Depth mode
 * composites in rank order (equal depth to the lower rank). Alpha mode
 * blends the peers' premultiplied layers in view order, front first, and
 * that order is the graph's: `view_order: [2, 0, 1]` lists the ranks from
 * the front. The executor's participants are positions in this order; the
 * SPU maps them to ranks (view[], pos[]) when it sends and receives. Every
 * peer reads the same option, so they agree without a message.
 *
 * Why the graph gives it: each peer's part must be convex (or a set of
 * layers already sorted) and the parts separable along the view direction,
 * which the application that split the scene knows; the order the boxes of
 * the parts would give under a moving camera is not computed here yet. */
#include <stdlib.h>
#include <string.h>

#include "layers.h"

int bswap_view_order(const tsr_options *o, int alpha, int nranks, int *view, int *pos, tsr_error *err)
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
