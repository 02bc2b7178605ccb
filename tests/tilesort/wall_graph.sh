#!/bin/sh
# tests/tilesort/wall_graph.sh — examples/graphs/wall.yaml through
# `tessera run`: the app's tilesort gets its servers' addresses and tiles
# from the mothership; every tile PNG a server writes equals the same
# rectangle of the native reference, every assembled whole-window PNG
# equals the reference (0 differing pixels), and the --stats JSON carries
# the sort-first statistics (bytes per server per frame, overlap,
# imbalance).
# A graph with a node named `display` (examples/graphs/wall_display.yaml)
# assembles the window on that display node instead (spus/readback: the
# tile servers stream their tile images to it): then the app's tilesort
# must not assemble, and the display must have served the four tile
# servers, ended every frame and received every tile image of every frame.
# With BUCKET (kd, union: the load-balanced modes) the graph's tilesort
# runs with that bucket= instead and FRAMES frames: the servers' regions
# change every frame, so only the assembled window (and the display) is
# checked, with every server's region reported in the statistics.
# usage: wall_graph.sh BIN_DIR GRAPH OUT_DIR TILES_DRIVER [BUCKET FRAMES]
set -u
bin=$1 graph=$2 out=$3 driver=$4 bucket=${5:-} frames=${6:-20}
rm -rf "$out" && mkdir -p "$out/ref" "$out/run" || exit 1
if [ -n "$bucket" ]; then
  sed -e "s/tilesort: {bucket: grid/tilesort: {bucket: $bucket/" -e "s/--frames 20/--frames $frames/" \
    "$graph" >"$out/graph.yaml" || exit 1
  grep -q "bucket: $bucket" "$out/graph.yaml" || { echo "FAIL: $graph has no tilesort: {bucket: grid ...}" >&2; exit 1; }
  graph=$out/graph.yaml
fi
bad=0
fail() { echo "FAIL: $*" >&2; bad=1; }
"$bin/spheres-native" --size 1024x768 --frames $frames --out "$out/ref/f-%04d.png" >/dev/null ||
  { echo "FAIL: reference exited $?" >&2; exit 1; }
timeout 120 "$bin/tessera" run "$graph" --out "$out/run" --stats "$out/stats.json" --no-progress \
  >"$out/run.out" 2>"$out/run.err" || { echo "FAIL: tessera run exited $?:" >&2; cat "$out/run.err" >&2; exit 1; }
cat "$out/run.out"
f=0
while [ $f -lt $frames ]; do
  n=$(printf %04d $f)
  d=$("$bin/tessera" imgdiff "$out/ref/f-$n.png" "$out/run/out/wall-$n.png" | sed -n 's/^differing_pixels: //p')
  [ "$d" = 0 ] || fail "assembled frame $f: '$d' pixels differ from spheres-native"
  [ -n "$bucket" ] && { f=$((f + 1)); continue; }
  for tile in "wall00 0 0" "wall10 512 0" "wall01 0 384" "wall11 512 384"; do
    set -- $tile
    "$driver" crop "$out/ref/f-$n.png" "$2" "$3" 512 384 "$out/ref/$1-$n.png" || exit 1
    d=$("$bin/tessera" imgdiff "$out/ref/$1-$n.png" "$out/run/out/$1-$n.png" | sed -n 's/^differing_pixels: //p')
    [ "$d" = 0 ] || fail "tile $1 frame $f: '$d' pixels differ from the reference's rectangle"
  done
  f=$((f + 1))
done
echo "$frames frames: the assembled window and the four tiles equal the reference"
grep -q '"sort_first": {"bucket":"'"${bucket:-grid}"'","servers":4' "$out/stats.json" ||
  fail "no sort_first statistics in --stats"
if [ -n "$bucket" ]; then
  regions=$(grep -o '"server_pixels":\[\[[^]]*\],\[[^]]*\],\[[^]]*\]' "$out/stats.json")
  echo "$bucket: $regions"
  [ -n "$regions" ] || fail "no server_pixels in the statistics"
fi
rows=$(sed -e 's/.*"frames":\[\[//' -e 's/\]\].*//' "$out/stats.json" | grep -o '\],\[' | wc -l)
[ "$rows" -eq $((frames - 1)) ] || fail "sort_first.frames has $((rows + 1)) rows, expected $frames"
grep -q "sort-first: overlap" "$out/run.out" || fail "the summary has no sort-first line"
if grep -q '^  display:' "$graph"; then
  ! grep -q 'assemble' "$graph" || fail "$graph: tilesort assembles, the display node should"
  d=$(grep -o '"name": "display"[^}]*' "$out/stats.json")
  echo "display: $d"
  case "$d" in *'"frames": '$frames,*) ;; *) fail "the display ended no $frames frames" ;; esac
  case "$d" in *'"clients": 4'*) ;; *) fail "the display did not serve 4 tile servers" ;; esac
  bytes=$(echo "$d" | sed -n 's/.*"bytes_in": \([0-9]*\).*/\1/p')
  [ "${bytes:-0}" -ge $((frames * 1024 * 768 * 4)) ] ||
    fail "the display received $bytes bytes, less than $frames frames of 1024x768 RGBA tiles"
fi
[ $bad = 0 ] && echo PASS
exit $bad
