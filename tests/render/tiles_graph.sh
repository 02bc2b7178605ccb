#!/bin/sh
# tests/render/tiles_graph.sh — runs tests/render/tiles_graph.yaml with
# `tessera run` (the mothership hands each server node's `tiles:` to its
# render SPU) and compares every tile PNG with the same rectangle of the
# native reference: 0 differing pixels, exactly FRAMES frames.
# usage: tiles_graph.sh BIN_DIR GRAPH OUT_DIR TILES_DRIVER
set -u
bin=$1 graph=$2 out=$3 driver=$4 frames=3
rm -rf "$out" && mkdir -p "$out/ref" "$out/run" || exit 1
"$bin/spheres-native" --size 320x240 --frames $frames --out "$out/ref/f-%04d.png" ||
  { echo "FAIL: reference exited $?" >&2; exit 1; }
timeout 120 "$bin/tessera" run "$graph" --out "$out/run" --no-progress >"$out/run.out" 2>"$out/run.err" ||
  { echo "FAIL: tessera run exited $?:" >&2; cat "$out/run.err" >&2; exit 1; }
status=0
# file suffix, then the tile X Y W H (tessera/tiles.h order)
for tile in "left-%04d.png 0 0 161 240" "right-%04d-t0.png 161 0 159 117" \
            "right-%04d-t1.png 161 117 159 123"; do
  set -- $tile
  f=0
  while [ "$f" -lt "$frames" ]; do
    got="$out/run/$(printf "$1" "$f")"
    want="$out/ref/crop-$f-$2-$3.png"
    "$driver" crop "$out/ref/$(printf 'f-%04d.png' "$f")" "$2" "$3" "$4" "$5" "$want" || exit 1
    result=$("$bin/tessera" imgdiff "$want" "$got" 2>&1)
    rc=$?
    echo "$1 frame $f tile [$2, $3, $4, $5]: $(echo "$result" | tr '\n' ' ')"
    [ "$rc" -eq 0 ] || status=1
    f=$((f + 1))
  done
  [ -e "$out/run/$(printf "$1" "$frames")" ] && { echo "FAIL: more than $frames frames" >&2; status=1; }
done
# A one-tile server's PNG is the tile, not the window.
[ -e "$out/run/right-0000.png" ] && { echo "FAIL: right wrote a window-named PNG" >&2; status=1; }
exit $status
