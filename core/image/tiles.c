/* core/image/tiles.c — parses the text form of tile lists (tessera/tiles.h).
 * Owns nothing (the caller frees the list). Never: accepts a field it
 * cannot represent, or a tile with a non-positive size. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/tiles.h"

/* One decimal field ending at ':' (or at the end of the tile when `last`).
 * Returns false on anything else. */
static bool parse_field(const char **p, const char *end, bool last, long *out)
{
    const char *s = *p;
    if (s >= end || !((*s >= '0' && *s <= '9') || *s == '-'))
        return false;
    errno = 0;
    char *stop;
    long v = strtol(s, &stop, 10);
    if (errno || stop == s || stop > end)
        return false;
    if (last ? stop != end : (stop >= end || *stop != ':'))
        return false;
    *out = v;
    *p = last ? stop : stop + 1;
    return true;
}

int tsr_tiles_parse(const char *text, bool with_server, tsr_tile **tiles, size_t *count, tsr_error *err)
{
    *tiles = NULL;
    *count = 0;
    if (!text || !text[0])
        return TSR_OK;
    size_t n = 1;
    for (const char *c = text; *c; c++)
        n += *c == ',';
    tsr_tile *out = calloc(n, sizeof *out);
    if (!out)
        return tsr_error_set(err, TSR_ENOMEM, "tiles: out of memory");
    const char *form = with_server ? "S:X:Y:W:H" : "X:Y:W:H";
    const char *p = text;
    for (size_t i = 0; i < n; i++) {
        const char *end = strchr(p, ',');
        if (!end)
            end = p + strlen(p);
        int len = (int)(end - p);
        long v[5];
        size_t fields = with_server ? 5 : 4;
        const char *q = p;
        for (size_t f = 0; f < fields; f++)
            if (!parse_field(&q, end, f + 1 == fields, &v[f])) {
                free(out);
                return tsr_error_set(err, TSR_EINVAL, "tile %zu '%.*s': expected %s", i + 1, len > 60 ? 60 : len, p,
                                     form);
            }
        const long *r = with_server ? v + 1 : v;
        static const char *const name[] = {"x", "y", "width", "height"};
        for (size_t f = 0; f < 4; f++) {
            long lo = f < 2 ? 0 : 1;
            long hi = f < 2 ? TSR_TILES_MAX_SIDE - 1 : TSR_TILES_MAX_SIDE;
            if (r[f] < lo || r[f] > hi) {
                free(out);
                return tsr_error_set(err, TSR_EINVAL, "tile %zu '%.*s': %s must be %ld..%ld", i + 1,
                                     len > 60 ? 60 : len, p, name[f], lo, hi);
            }
        }
        if (with_server && (v[0] < 0 || v[0] > 1000000)) {
            free(out);
            return tsr_error_set(err, TSR_EINVAL, "tile %zu '%.*s': server index must be >= 0", i + 1,
                                 len > 60 ? 60 : len, p);
        }
        out[i] = (tsr_tile){.server = with_server ? (int)v[0] : 0,
                            .x = (int)r[0],
                            .y = (int)r[1],
                            .width = (int)r[2],
                            .height = (int)r[3]};
        p = *end ? end + 1 : end;
    }
    *tiles = out;
    *count = n;
    return TSR_OK;
}
