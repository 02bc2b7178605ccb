#!/usr/bin/env bash
# tests/faker/exec_tiles_mismatch.sh BIN GRAPH OUTDIR
# examples/graphs/wall.yaml's pixel tiles cover a 1024x768 window; glxgears
# run as its app with -geometry 320x240 (`tessera exec --graph`) opens a
# smaller one. The run must fail (non-zero, within 60 s) with one line
# naming both sizes, before any tile or assembled PNG is written: never a
# silently cropped or misplaced wall.
set -uo pipefail
bin=$1 graph=$2 out=$3
command -v glxgears >/dev/null || { echo "SKIP: glxgears is not installed (scripts/setup-debian: mesa-utils)"; exit 77; }
rm -rf "$out"; mkdir -p "$out"
. "$(dirname "$0")/xvfb.sh"
start_xvfb "$out"
export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0"
status=0
LD_PRELOAD="${FAKER_PRELOAD:-}" timeout 60 "$bin/tessera" exec --graph "$graph" --out "$out/run" -- \
  glxgears -geometry 320x240 > "$out/stdout.txt" 2> "$out/stderr.txt" || status=$?
echo "tessera exec --graph exited $status"
cat "$out/stderr.txt"
bad=0
[ $status -ne 0 ] && [ $status -ne 124 ] || { echo "FAIL: expected a failed run, not status $status"; bad=1; }
grep -q "the program's window is 320x240 but the tiles cover 1024x768" "$out/stderr.txt" ||
  { echo "FAIL: no line naming both sizes"; bad=1; }
# The verdict (the last line) names the cause, the app's exit, not a
# server's dropped client, which only echoes it.
tail -n 1 "$out/stderr.txt" | grep -q "^tessera exec: node 'app': application glxgears exited with status 1" ||
  { echo "FAIL: the verdict does not name the application: $(tail -n 1 "$out/stderr.txt")"; bad=1; }
pngs=$(find "$out/run" -name '*.png' | wc -l)
[ "$pngs" -eq 0 ] || { echo "FAIL: $pngs PNGs were written for a wall that does not fit"; bad=1; }
[ $bad = 0 ] && echo PASS
exit $bad
