#!/usr/bin/env bash
# tests/window/exec_grid_resize.sh BIN PROGRAM GRAPH OUTDIR
# PROGRAM (window_exec_resize: an ordinary GLX program whose frames depend
# only on the frame number) opens 320x240 and resizes its own window to
# 240x200 before frame 4 of 8. Run once under `tessera exec` with the
# render chain (its own render: the reference) and once as the app of
# GRAPH (tests/window/grid_wall.yaml: tilesort grid=2,2, so the four
# servers' tiles divide whatever window the program has, re-divided at
# the resize). Every frame the wall assembles must equal the reference,
# 0 differing pixels, at both sizes, and the tiles must have followed the
# resize (160x120 before, 120x100 after).
set -uo pipefail
bin=$1 prog=$2 graph=$3 out=$4
rm -rf "$out"; mkdir -p "$out/ref"
. "$(dirname "$0")/../faker/xvfb.sh"
start_xvfb "$out"
export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0"
bad=0
fail() { echo "FAIL: $*"; bad=1; }
LD_PRELOAD="${FAKER_PRELOAD:-}" timeout 60 "$bin/tessera" exec --chain "render output=$out/ref/f-%04d.png" -- \
  "$prog" 8 4 240 200 || fail "the reference run exited $?"
LD_PRELOAD="${FAKER_PRELOAD:-}" timeout 90 "$bin/tessera" exec --graph "$graph" --out "$out/run" -- \
  "$prog" 8 4 240 200 > "$out/run.out" 2> "$out/run.err" || { cat "$out/run.err"; fail "the grid wall run exited $?"; }

for f in 0 1 2 3 4 5 6 7; do
  n=$(printf %04d $f)
  d=$("$bin/tessera" imgdiff "$out/ref/f-$n.png" "$out/run/out/wall-$n.png" | sed -n 's/^differing_pixels: //p')
  [ "$d" = 0 ] || fail "frame $f: '$d' pixels of the wall differ from the program's own render"
done
for f in 0 4; do
  n=$(printf %04d $f)
  echo "frame $f: reference $(head -c 24 "$out/ref/f-$n.png" | tail -c 8 | od -An -tx1 | tr -d ' '), tile w00 $(head -c 24 "$out/run/out/w00-$n.png" | tail -c 8 | od -An -tx1 | tr -d ' ')"
done
# PNG IHDR width and height: 320x240 then 240x200; tiles 160x120 then 120x100
[ "$(head -c 24 "$out/ref/f-0000.png" | tail -c 8 | od -An -tx1 | tr -d ' ')" = 00000140000000f0 ] || fail "frame 0 is not 320x240"
[ "$(head -c 24 "$out/ref/f-0004.png" | tail -c 8 | od -An -tx1 | tr -d ' ')" = 000000f0000000c8 ] || fail "frame 4 is not 240x200"
[ "$(head -c 24 "$out/run/out/w00-0000.png" | tail -c 8 | od -An -tx1 | tr -d ' ')" = 000000a000000078 ] || fail "tile w00 of frame 0 is not 160x120"
[ "$(head -c 24 "$out/run/out/w00-0004.png" | tail -c 8 | od -An -tx1 | tr -d ' ')" = 0000007800000064 ] || fail "tile w00 of frame 4 is not 120x100"
[ $bad = 0 ] && echo "8 frames (320x240, then 240x200 from frame 4): the grid wall equals the program's own render, 0 differing pixels" && echo PASS
exit $bad
