#!/bin/sh
# tests/render/drawpixels.sh — render's fast DrawPixels and scissored
# colour Clear (texture upload and blit, spus/render/drawpixels.c) must
# give every frame byte for byte what glDrawPixels and glClear give
# (fast_drawpixels=false), and must be the path taken exactly in the cases
# the driver says allow it.
# usage: drawpixels.sh DRIVER TESSERA_BIN OUT_DIR solo|shared
set -u
driver=$1 tessera=$2 out=$3 mode=$4
rm -rf "$out" && mkdir -p "$out/fast" "$out/plain" || exit 1
TESSERA_LOG=info "$driver" "$mode" true "$out/fast/f-%d.png" >"$out/fast.out" 2>"$out/fast.err" ||
  { echo "FAIL: fast run exited $?" >&2; cat "$out/fast.err" >&2; exit 1; }
TESSERA_LOG=info "$driver" "$mode" false "$out/plain/f-%d.png" >"$out/plain.out" 2>"$out/plain.err" ||
  { echo "FAIL: plain run exited $?" >&2; cat "$out/plain.err" >&2; exit 1; }
status=0
n=0
for f in "$out/plain"/f-*.png; do
  b=$(basename "$f")
  r=$("$tessera" imgdiff "$out/fast/$b" "$f")
  rc=$?
  echo "$b (fast vs glDrawPixels): $(echo "$r" | grep differing_pixels)"
  [ $rc -eq 0 ] || status=1
  n=$((n + 1))
done
[ "$n" -eq 32 ] || { echo "FAIL: $n frames, expected 32" >&2; status=1; }
# fast_path_counts KEY WHAT: the fast run took the texture-blit path for
# WHAT as often as the driver's "KEY: N of M" line expects, the plain run never
fast_path_counts() {
  local want total
  want=$(sed -n "s/^$1: \([0-9]*\) of \([0-9]*\)\$/\1 of \2/p" "$out/fast.out")
  echo "expected $1: $want"
  grep "$2: .* calls took the texture-blit path" "$out/fast.err" "$out/plain.err"
  grep -q "$2: $want calls took the texture-blit path" "$out/fast.err" ||
    { echo "FAIL: the fast run did not take the fast path for $2 $want times" >&2; status=1; }
  total=${want#* of }
  grep -q "$2: 0 of $total calls took the texture-blit path" "$out/plain.err" ||
    { echo "FAIL: fast_drawpixels=false still took the fast path for $2" >&2; status=1; }
}
fast_path_counts expect_fast DrawPixels
fast_path_counts expect_fast_clear "scissored colour Clear"
exit $status
