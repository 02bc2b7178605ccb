#!/bin/sh
# tests/render/accuracy.sh — renders an example natively (OSMesa, the
# reference) and through a tessera chain, then compares every frame with
# `tessera imgdiff`; fails unless all frames are bit-identical.
# usage: accuracy.sh BIN_DIR EXAMPLE OUT_DIR FRAMES KIND [SIZE]
#   KIND: render | print | loopback   (chain: [KIND !] render)
# ACCURACY_NATIVE_THREADS / ACCURACY_CHAIN_THREADS, when set, become
# LP_NUM_THREADS (llvmpipe's rasterizer threads) of the two runs.
set -u
bin=$1 example=$2 out=$3 frames=$4 kind=$5 size=${6:-640x480}
rm -rf "$out" && mkdir -p "$out/native" "$out/chain" || exit 1

case $kind in
  render)   chain="render output=\"$out/chain/f-%04d.png\"" ;;
  print)    chain="print file=\"$out/trace.txt\" ! render output=\"$out/chain/f-%04d.png\"" ;;
  loopback) chain="loopback ! render output=\"$out/chain/f-%04d.png\"" ;;
  *) echo "accuracy.sh: unknown kind '$kind'" >&2; exit 2 ;;
esac

run_with_threads() { # THREADS COMMAND...: LP_NUM_THREADS=THREADS unless empty
  t=$1; shift
  if [ -n "$t" ]; then LP_NUM_THREADS=$t "$@"; else "$@"; fi
}
run_with_threads "${ACCURACY_NATIVE_THREADS:-}" "$bin/$example-native" --frames "$frames" --size "$size" --out "$out/native/f-%04d.png" \
  || { echo "FAIL: $example-native exited $?" >&2; exit 1; }
run_with_threads "${ACCURACY_CHAIN_THREADS:-}" \
  "$bin/$example" --frames "$frames" --size "$size" --chain "$chain" \
  || { echo "FAIL: $example --chain '$chain' exited $?" >&2; exit 1; }

status=0
f=0
while [ "$f" -lt "$frames" ]; do
  name=$(printf 'f-%04d.png' "$f")
  result=$("$bin/tessera" imgdiff "$out/native/$name" "$out/chain/$name")
  rc=$?
  echo "$example [$kind] frame $f: $(echo "$result" | tr '\n' ' ')"
  [ "$rc" -eq 0 ] || status=1
  f=$((f + 1))
done
if [ "$kind" = print ] && [ ! -s "$out/trace.txt" ]; then
  echo "FAIL: print wrote no trace to $out/trace.txt" >&2
  status=1
fi
[ "$status" -eq 0 ] && echo "PASS: $frames frames of $example through [$chain] are bit-identical to OSMesa"
exit $status
