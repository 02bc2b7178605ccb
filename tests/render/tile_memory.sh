#!/bin/sh
# tests/render/tile_memory.sh — a render SPU that owns one 1024x768 tile of
# a 4096x3072 window must not make the pages outside its tile resident:
# it must stay at least 60 MiB below a full-window instance (the colour
# and depth renderbuffers outside the tile are 15/16 of 96 MiB = 90 MiB;
# neither instance writes PNGs, so OSMesa's 48 MiB window buffer stays
# untouched in both: render finishes such frames without its copy;
# measured: 74-80 MiB below; with the zero pages llvmpipe writes kept,
# the tile instance would hold most of those 90 MiB). Resident memory
# after the last frame (VmRSS, tiles_driver rss); the figures go to bench/
# (bench/run tiles).
# usage: tile_memory.sh TILES_DRIVER
set -u
driver=$1
# AddressSanitizer keeps freed memory resident in its quarantine (256 MiB
# by default): with it, the window buffers freed when the tiles arrive
# would count. Ignored by builds without it.
ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}quarantine_size_mb=0"
export ASAN_OPTIONS
rss() { "$driver" rss "$@" | sed -n 's/^vmrss_mb: //p'; }
small=$(rss 64x48 3 -) && full=$(rss 4096x3072 3 -) || { echo "FAIL: tiles_driver rss failed" >&2; exit 1; }
status=0
# A whole-window instance that writes no PNG has its colour and depth
# renderbuffers (96 MiB) resident, not OSMesa's window buffer (48 MiB more,
# which glFinish would fill): render finishes such frames with a one-pixel
# read instead (spus/render/render.c, finish_frame).
awk -v s="$small" -v f="$full" 'BEGIN {
  if (f - s > 120) { printf "FAIL: a whole 4096x3072 window without PNGs keeps %.1f MiB above idle: OSMesa filled its window buffer\n", f - s; exit 1 }
}' || status=1
# The tile as the `tiles` option (from the start); as TilesTSR after the
# window exists; and after two contexts put the server in shared mode with
# full-window renderbuffers already allocated (they are allocated again).
for how in "option" "--tilestsr" "--tilestsr --contexts"; do
  [ "$how" = option ] && how=""
  # shellcheck disable=SC2086
  tile=$(rss 4096x3072 3 1024:768:1024:768 $how) || { echo "FAIL: tiles_driver rss failed" >&2; exit 1; }
  [ -n "$small" ] && [ -n "$tile" ] && [ -n "$full" ] || { echo "FAIL: no vmrss_mb figure" >&2; exit 1; }
  echo "resident MiB (${how:-option}): idle 64x48 $small, one 1024x768 tile of 4096x3072 $tile, whole 4096x3072 $full"
  awk -v s="$small" -v t="$tile" -v f="$full" 'BEGIN {
    printf "above idle: tile %.1f MiB, full window %.1f MiB\n", t - s, f - s
    if (f - t < 60) { printf "FAIL: the tile server is only %.1f MiB below the full window: it keeps pages outside its tile\n", f - t; exit 1 }
  }' || status=1
done
exit $status
