#!/usr/bin/env bash
# tests/capture/glxgears.sh TESSERA GRAPH_DIR OUTDIR
# An unmodified glxgears (64x48) under a private Xvfb, run by `tessera exec`
# with the chain "capture frames=6 ! render": the capture ends after 6
# frames (glxgears ends only by a signal; it then gets SIGTERM), and its
# frames are the original run's PNGs. The capture must then replay bit-
# identically, every frame, through "render" and as the app node of the
# pack, 2x2 tilesort wall and replicate graphs, with no X server at all.
set -euo pipefail
tessera=$1 graphs=$2 out=$3
command -v glxgears >/dev/null || { echo "SKIP: glxgears is not installed (scripts/setup-debian: mesa-utils)"; exit 77; }
here=$(cd "$(dirname "$0")" && pwd)
. "$here/common.sh"
rm -rf "$out"; mkdir -p "$out"; cd "$out"
. "$here/../faker/xvfb.sh"
start_xvfb "$out"
export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0"
LD_PRELOAD="${FAKER_PRELOAD:-}" "$tessera" exec \
  --chain "capture file=gears.tsrcap frames=6 ! render output=orig-%04d.png" -- glxgears -geometry 64x48 \
  > stdout.txt 2> stderr.txt &
pid=$!
for _ in $(seq 300); do
  [ -e gears.tsrcap ] && break
  kill -0 "$pid" 2>/dev/null || break
  sleep 0.1
done
kill -TERM "$pid" 2>/dev/null || true
status=0; wait "$pid" || status=$?
stop_xvfb
echo "glxgears: exit status $status"; cat stderr.txt
[ -e gears.tsrcap ] || { echo "FAIL: no capture was written"; exit 1; }
ls -a | grep -q '\.tmp-' && { echo "FAIL: a temporary file was left"; exit 1; }
frames_move "$tessera" orig-0000.png orig-0005.png
unset DISPLAY
"$tessera" replay --info gears.tsrcap | tee info.txt
grep -qx "frames: 6" info.txt || { echo "FAIL: expected 6 frames"; exit 1; }
"$tessera" replay gears.tsrcap --chain "render output=rep-%04d.png"
same_frames "$tessera" orig-%04d.png rep-%04d.png 6
# The graphs' window is 64x48, as this capture's.
for g in tcp wall replicate; do
  "$tessera" replay gears.tsrcap --graph "$graphs/$g.yaml" --out "$out/$g" --no-progress > "$g.txt"
done
same_frames "$tessera" orig-%04d.png tcp/out/tcp-%04d.png 6
same_frames "$tessera" orig-%04d.png wall/out/wall-%04d.png 6
same_frames "$tessera" orig-%04d.png replicate/out/rep-s0-%04d.png 6
same_frames "$tessera" orig-%04d.png replicate/out/rep-s1-%04d.png 6
