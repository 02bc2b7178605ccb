#!/bin/sh
# tests/render/two_chains.sh — two render instances in one process (two
# chains on two threads) must each produce exactly the frames the same
# scene gives when rendered alone, and the two scenes must differ.
# usage: two_chains.sh RENDER_DRIVER TESSERA_BIN OUT_DIR FRAMES
set -u
prog=$1 tessera=$2 out=$3 frames=$4
rm -rf "$out" && mkdir -p "$out/both" "$out/alone" || exit 1
"$prog" both "$out/both" "$frames" || { echo "FAIL: both run exited $?" >&2; exit 1; }
"$prog" single A "$out/alone/a-%d.png" "$frames" || exit 1
"$prog" single B "$out/alone/b-%d.png" "$frames" || exit 1
status=0
f=0
while [ "$f" -lt "$frames" ]; do
  for s in a b; do
    r=$("$tessera" imgdiff "$out/both/$s-$f.png" "$out/alone/$s-$f.png")
    rc=$?
    echo "scene $s frame $f (together vs alone): $(echo "$r" | tr '\n' ' ')"
    [ $rc -eq 0 ] || status=1
  done
  f=$((f + 1))
done
# The scenes have different sizes: imgdiff must refuse to call them equal.
"$tessera" imgdiff "$out/both/a-0.png" "$out/both/b-0.png" >/dev/null 2>&1
[ $? -eq 0 ] && { echo "FAIL: scenes A and B are identical" >&2; status=1; }
exit $status
