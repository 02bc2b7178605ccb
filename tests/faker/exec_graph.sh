#!/usr/bin/env bash
# tests/faker/exec_graph.sh BIN GRAPH KIND OUTDIR TILES_DRIVER FRAMES_CHECK
# An unmodified glxgears as the app node of an existing example graph,
# through `tessera exec --graph GRAPH -- glxgears ...` on a private Xvfb:
# the node sees glxgears is not linked to libtessera_gl and runs it under
# the faker (mothership/faker.h), and the rest of the graph runs as with
# `tessera run`. KIND tcp: the server's PNGs (tcp-NNNN.png) are >= 5
# frames of glxgears' 320x240 window, moving, not one colour. KIND
# wall_display: glxgears opens the graph's 1024x768 window; for frames 0..4
# each of the four tile servers' PNGs equals the same rectangle of the
# display node's assembled window, 0 differing pixels. Then SIGTERM ends
# the run and no process is left behind; with tcp, after glxgears' first
# 5 s, its own standard output ("N frames in 5.0 seconds") reached ours.
set -uo pipefail
bin=$1 graph=$2 kind=$3 out=$4 driver=$5 frames=$6
command -v glxgears >/dev/null || { echo "SKIP: glxgears is not installed (scripts/setup-debian: mesa-utils)"; exit 77; }
rm -rf "$out"; mkdir -p "$out"
. "$(dirname "$0")/xvfb.sh"
start_xvfb "$out"
export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0"
if [ "$kind" = tcp ]; then geometry=320x240 last=tcp-0005.png; else geometry=1024x768 last=wall-0005.png; fi
LD_PRELOAD="${FAKER_PRELOAD:-}" TESSERA_LOG=info "$bin/tessera" exec --graph "$graph" --out "$out/run" -- \
  glxgears -geometry $geometry > "$out/stdout.txt" 2> "$out/stderr.txt" &
pid=$!
for _ in $(seq 600); do [ -e "$out/run/out/$last" ] && break; kill -0 $pid 2>/dev/null || break; sleep 0.1; done
# glxgears prints its frame rate every 5 s: wait for that line (bounded).
if [ "$kind" = tcp ]; then
  for _ in $(seq 300); do grep -q "frames in" "$out/stdout.txt" && break; kill -0 $pid 2>/dev/null || break; sleep 0.1; done
fi
kill -TERM $pid 2>/dev/null
status=0; wait $pid || status=$?
echo "tessera exec --graph exited $status"
bad=0
fail() { echo "FAIL: $*"; bad=1; }
# The run's children end after it: wait (bounded) until none but Xvfb is left.
for _ in $(seq 50); do
  ps -o pid=,comm= --ppid $$ > "$out/children.txt"   # direct children only: no subshell in the list
  grep -q -v -e " ps$" -e " Xvfb$" "$out/children.txt" || break
  sleep 0.1
done
left=$(grep -v -e " ps$" -e " Xvfb$" "$out/children.txt" || true)
[ -z "$left" ] || fail "processes left behind: $left"
grep -q "glxgears is not linked to libtessera_gl: it runs under the faker" "$out/stderr.txt" ||
  fail "the app node did not say it runs glxgears under the faker"
[ "$kind" != tcp ] || grep -q "frames in" "$out/stdout.txt" || fail "glxgears' own output did not reach stdout"
grep -q "interrupted by signal 15" "$out/stderr.txt" || fail "the run did not end on SIGTERM"
[ "$status" = 143 ] || fail "tessera exec --graph ended with status $status after SIGTERM, not 143 (death by it)"
[ -e "$out/run/out/$last" ] || { tail -n 20 "$out/stderr.txt"; fail "no $last"; }
if [ "$kind" = tcp ]; then
  "$frames" "$out/run/out" tcp- 5 || bad=1
else
  for f in 0 1 2 3 4; do
    n=$(printf %04d $f)
    for tile in "wall00 0 0" "wall10 512 0" "wall01 0 384" "wall11 512 384"; do
      set -- $tile
      "$driver" crop "$out/run/out/wall-$n.png" "$2" "$3" 512 384 "$out/$1-$n.png" || exit 1
      d=$("$bin/tessera" imgdiff "$out/$1-$n.png" "$out/run/out/$1-$n.png" | sed -n 's/^differing_pixels: //p')
      [ "$d" = 0 ] || fail "frame $f tile $1: '$d' pixels differ from the display's window"
    done
  done
  "$frames" "$out/run/out" wall- 5 || bad=1
  [ $bad = 0 ] && echo "frames 0..4: the four tiles equal the display's assembled window (0 differing pixels)"
fi
[ $bad = 0 ] && echo PASS
exit $bad
