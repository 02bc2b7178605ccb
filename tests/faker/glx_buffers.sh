#!/usr/bin/env bash
# tests/faker/glx_buffers.sh — front and back buffers of a double-buffered
# GLX window (glx_buffers_driver.c) through [render], [pack -> tessera node
# render] and a 2x2 tilesort wall of four `tessera node` render servers,
# on a private Xvfb: every labelled line (errors, gets, pixels of each
# buffer) must equal what Mesa's own GLX gives on the same Xvfb
# (faker_glx_buffers_native), save the front read after a swap (below).
# usage: glx_buffers.sh PROGRAM NATIVE TESSERA OUT_DIR
set -u
prog=$1 native=$2 TESSERA=$3 out=$4
. "$(dirname "$0")/../node/node_lib.sh"
. "$(dirname "$0")/xvfb.sh"
rm -rf "$out" && mkdir -p "$out" || exit 1
start_xvfb "$out"
status=0
fail() { echo "FAIL: $*" >&2; status=1; }
PIDS=
kill_all() { for p in $PIDS; do kill -9 "$p" 2>/dev/null; wait "$p" 2>/dev/null; done; PIDS=; }
# the native run is Mesa's own GLX: what it keeps at exit (its DRI driver
# is unloaded by then, so LeakSanitizer cannot name it) is not tessera's
ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0" timeout 60 "$native" "$out/native.txt" || fail "native: exit $?"
runs=()
run() { # NAME CHAIN
  echo "--- $1: chain \"$2\""
  runs+=("$1")
  TESSERA_CHAIN=$2 timeout 60 "$prog" "$out/$1.txt" 2>"$out/$1.err" || { fail "$1: exit $?"; cat "$out/$1.err" >&2; }
}
run render "render output="
start_node "$out/node" --listen "unix:$out/node.sock" --clients 1 --timeout-ms 30000 --chain "render output=" ||
  fail "no node"
PIDS=$NODE_PID
run pack "pack server=unix:$out/node.sock"
wait_exit "$NODE_PID" 15
[ "$EXIT_RC" = 0 ] || { fail "pack: the node exited $EXIT_RC"; cat "$out/node.err"; }
PIDS=
SERVERS= TILES= k=0
for y in 0 24; do
  for x in 0 32; do
    start_node "$out/wall$k" --listen "unix:$out/wall$k.sock" --clients 1 --timeout-ms 30000 \
      --chain "render output=" || fail "no wall node $k"
    PIDS="$PIDS $NODE_PID"
    SERVERS="$SERVERS${SERVERS:+,}unix:$out/wall$k.sock"
    TILES="$TILES${TILES:+,}$k:$x:$y:32:24"
    k=$((k + 1))
  done
done
run wall "tilesort servers=$SERVERS tiles=$TILES"
for p in $PIDS; do
  wait_exit "$p" 15
  [ "$EXIT_RC" = 0 ] || fail "wall: a node exited $EXIT_RC"
done
kill_all
# The front after a swap: Mesa's GLX on Xvfb (drisw) reads a stale copy
# of the front once the program drew into it, where GL (and piglit's
# read-front) wants the frame just swapped; tessera gives the frame, which
# the back keeps: so that line must read as the back's line, in every run.
grep -v '^swapped FRONT:' "$out/native.txt" >"$out/native.cmp"
grep -q '^swapped BACK:' "$out/native.txt" || fail "native: no 'swapped BACK' line"
for r in "${runs[@]}"; do
  grep -v '^swapped FRONT:' "$out/$r.txt" >"$out/$r.cmp"
  diff -u "$out/native.cmp" "$out/$r.cmp" >"$out/$r.diff" || { fail "$r differs from Mesa:"; cat "$out/$r.diff" >&2; }
  front=$(sed -n 's/^swapped FRONT: //p' "$out/$r.txt") back=$(sed -n 's/^swapped BACK: //p' "$out/$r.txt")
  [ -n "$front" ] && [ "$front" = "$back" ] ||
    fail "$r: after the swap the front reads '$front', not the frame swapped '$back'"
done
[ $status -eq 0 ] && echo "OK: ${#runs[@]} runs give Mesa's buffers and answers ($(wc -l <"$out/native.txt") lines)"
exit $status
