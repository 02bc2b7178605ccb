#!/bin/sh
# tests/fault/small_tiles.sh — a wall with a display node whose tiles are
# small (tests/fault/wall_display.yaml: 64x48 tiles) must run to its end
# with every assembled window bit-identical to the native render. The tile
# servers other than rank 0 send no swap, and a tile is far less than a
# wire buffer: their frame barrier must be flushed to the display at once,
# or the display waits on it for ever (the fault matrix's wall_display
# graph hung that way before its first frame).
# usage: small_tiles.sh BIN_DIR GRAPH OUT_DIR FRAMES
set -u
bin=$1 graph=$2 out=$3 frames=$4
rm -rf "$out" && mkdir -p "$out/ref" "$out/g" || exit 1
sed "s/--frames [0-9]*/--frames $frames/" "$graph" >"$out/g/wall_display.yaml" || exit 1
"$bin/spheres-native" --size 128x96 --frames "$frames" --out "$out/ref/f-%04d.png" || exit 1
timeout 30 "$bin/tessera" run "$out/g/wall_display.yaml" --out "$out/run" --no-progress \
  >"$out/run.out" 2>"$out/run.err"
rc=$?
[ $rc -eq 0 ] || { echo "FAIL: tessera run exited $rc (124: it hung); its stderr:" >&2; cat "$out/run.err" >&2; exit 1; }
f=0
while [ $f -lt "$frames" ]; do
  got=$(printf "%s/run/out/wall-%06d.png" "$out" $f) ref=$(printf "%s/ref/f-%04d.png" "$out" $f)
  "$bin/tessera" imgdiff "$got" "$ref" >/dev/null || { echo "FAIL: frame $f: $got differs from $ref" >&2; exit 1; }
  f=$((f + 1))
done
echo "PASS: $frames assembled windows of 64x48 tiles, each bit-identical to the native render"
