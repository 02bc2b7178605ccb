#!/usr/bin/env bash
# tests/faker/gl21_commands.sh — the GL 1.0-2.1 commands added to complete
# the spec (gl21_commands_driver.c), or the offered extensions without
# commands (extensions_driver.c), through [render], [capture ! render],
# [pack -> tessera node render] and a 2x2 tilesort wall of four `tessera
# node` render servers: every labelled line (pixels drawn, answers of gets)
# must equal what OSMesa gives for the same calls (the driver built with
# RECORDED_GL_NATIVE), and the capture replayed into render must give
# every recorded answer again (tessera replay --exact-answers). With
# RECORDED_GL_WALL_ABSENT set, the wall does not offer what the driver
# shows (faker/offered.c): the wall's first line must be that text instead.
# usage: gl21_commands.sh PROGRAM NATIVE TESSERA OUT_DIR
set -u
prog=$1 native=$2 TESSERA=$3 out=$4
. "$(dirname "$0")/../node/node_lib.sh"
rm -rf "$out" && mkdir -p "$out" || exit 1
unset DISPLAY
status=0
fail() { echo "FAIL: $*" >&2; status=1; }
PIDS=
kill_all() { for p in $PIDS; do kill -9 "$p" 2>/dev/null; wait "$p" 2>/dev/null; done; PIDS=; }
timeout 60 "$native" "$out/native.txt" || fail "native: exit $?"
runs=()
run() { # NAME CHAIN
  echo "--- $1: chain \"$2\""
  runs+=("$1")
  TESSERA_CHAIN=$2 timeout 60 "$prog" "$out/$1.txt" 2>"$out/$1.err" || { fail "$1: exit $?"; cat "$out/$1.err" >&2; }
}
run render "render output="
run capture "capture file=$out/capture.tsrcap ! render output="
timeout 120 "$TESSERA" replay "$out/capture.tsrcap" --exact-answers --chain "render output=" >"$out/replay.out" 2>&1 ||
  { fail "replay of the capture: exit $?"; cat "$out/replay.out" >&2; }
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
if [ -n "${RECORDED_GL_WALL_ABSENT:-}" ]; then
  [ "$(head -n 1 "$out/wall.txt")" = "$RECORDED_GL_WALL_ABSENT" ] ||
    fail "wall: first line \"$(head -n 1 "$out/wall.txt")\", not \"$RECORDED_GL_WALL_ABSENT\""
  runs=("${runs[@]/wall/}")
fi
for r in "${runs[@]}"; do
  [ -n "$r" ] || continue
  diff -u "$out/native.txt" "$out/$r.txt" >"$out/$r.diff" || { fail "$r differs from OSMesa:"; cat "$out/$r.diff" >&2; }
done
[ $status -eq 0 ] && echo "OK: ${#runs[@]} runs give OSMesa's pixels and answers ($(wc -l <"$out/native.txt") lines)," \
  "the capture's replay every recorded answer: $(tail -n 1 "$out/replay.out")"
exit $status
