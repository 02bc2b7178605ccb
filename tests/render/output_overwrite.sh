#!/bin/sh
# tests/render/output_overwrite.sh — render output_overwrite=1 is the
# explicit form of one file for every frame: the run succeeds and the file
# holds the last frame (bit-identical to OSMesa's last frame), with no
# temporary left beside it.
# usage: output_overwrite.sh BIN_DIR OUT_DIR
set -u
bin=$1 out=$2
rm -rf "$out" && mkdir -p "$out/native" || exit 1
"$bin/spheres-native" --frames 3 --out "$out/native/f-%04d.png" || exit 1
"$bin/spheres" --frames 3 --chain "render output=$out/last.png output_overwrite=1" || {
  echo "FAIL: render output_overwrite=1 was refused"; exit 1; }
"$bin/tessera" imgdiff "$out/native/f-0002.png" "$out/last.png" || {
  echo "FAIL: last.png is not the last frame"; exit 1; }
left=$(ls -A "$out" | grep -v '^native$' | grep -v '^last.png$')
[ -z "$left" ] || { echo "FAIL: files left beside last.png: $left"; exit 1; }
echo "PASS: output_overwrite=1 keeps the last frame in one file"
