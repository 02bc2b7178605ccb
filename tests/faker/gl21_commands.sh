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
rm -rf "$out" && mkdir -p "$out" || exit 1
unset DISPLAY
. "$(dirname "$0")/graphs_lib.sh"
run_native
run_graphs "" ""
run_graph capture "capture file=$out/capture.tsrcap ! render output="
timeout 120 "$TESSERA" replay "$out/capture.tsrcap" --exact-answers --chain "render output=" >"$out/replay.out" 2>&1 ||
  { fail "replay of the capture: exit $?"; cat "$out/replay.out" >&2; }
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
