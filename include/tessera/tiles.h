/* tessera/tiles.h — the text form of tile lists, as the mothership hands
 * a graph's `tiles:` to SPUs in options (one format everywhere):
 *   "X:Y:W:H,X:Y:W:H"        rectangles of the window a renderer owns
 *                            (the render SPU's `tiles`)
 *   "S:X:Y:W:H,S:X:Y:W:H"    the same per server, S = the server's 0-based
 *                            index in the node's `to:` list (a sort-first
 *                            SPU's `tiles`)
 * Window pixels, origin bottom-left as in GL; X, Y >= 0, W, H >= 1, none
 * above TSR_TILES_MAX_SIDE. Parsing only: owns nothing but the array it
 * returns, and never checks tiles against a window (its size may change). */
#ifndef TESSERA_TILES_H
#define TESSERA_TILES_H

#include <stdbool.h>
#include <stddef.h>

#include "tessera/error.h"
#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TSR_TILES_MAX_SIDE 16384

typedef struct tsr_tile {
    int server; /* index in `to:` ("S:..." form); 0 in the plain form */
    int x, y, width, height;
} tsr_tile;

/* Parses `text` ("" gives 0 tiles and *tiles == NULL). `with_server`
 * selects the "S:X:Y:W:H" form. On success *tiles is malloc'ed (free()
 * it). On error returns TSR_EINVAL with a message naming the bad tile,
 * e.g. "tile 2 '0:0:-4:8': width must be 1..16384". */
TSR_API int tsr_tiles_parse(const char *text, bool with_server, tsr_tile **tiles, size_t *count, tsr_error *err);

#ifdef __cplusplus
}
#endif
#endif
