#!/bin/sh
# tests/binaryswap/parts.sh — an example's --part K/N shares (native build):
# each of 3 shares draws something and less than the whole scene (its
# frame differs from the whole), and the whole is drawn without --part
# exactly as with --part 0/1. That the shares' union with the depth test
# IS the whole scene is what the binaryswap accuracy tests check.
# usage: parts.sh BIN_DIR APP OUT_DIR
set -u
bin=$1 app=$2 out=$3
rm -rf "$out" && mkdir -p "$out" || exit 1
bad=0
fail() { echo "FAIL: $*" >&2; bad=1; }
size=96x72
"$bin/$app-native" --frames 1 --size $size --out "$out/whole-%d.png" || exit 1
"$bin/$app-native" --frames 1 --size $size --part 0/1 --out "$out/one-%d.png" || exit 1
"$bin/$app-native" --frames 1 --size $size --part 0/1000 --out "$out/empty-%d.png" || exit 1
"$bin/tessera" imgdiff "$out/whole-0.png" "$out/one-0.png" | grep -q '^differing_pixels: 0$' ||
  fail "--part 0/1 differs from the whole scene"
for k in 0 1 2; do
  "$bin/$app-native" --frames 1 --size $size --part $k/3 --out "$out/part$k-%d.png" || exit 1
  "$bin/tessera" imgdiff "$out/whole-0.png" "$out/part$k-0.png" | grep -q '^differing_pixels: 0$' &&
    fail "part $k/3 draws the whole scene"
  "$bin/tessera" imgdiff "$out/empty-0.png" "$out/part$k-0.png" | grep -q '^differing_pixels: 0$' &&
    fail "part $k/3 draws nothing"
done
[ $bad = 0 ] && echo PASS
exit $bad
