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
. "$(dirname "$0")/xvfb.sh"
rm -rf "$out" && mkdir -p "$out" || exit 1
start_xvfb "$out"
. "$(dirname "$0")/graphs_lib.sh"
run_native
run_graphs "" ""
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
