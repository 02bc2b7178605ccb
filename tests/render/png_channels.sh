#!/bin/sh
# tests/render/png_channels.sh — render writes what a window shows: RGB
# PNGs, the framebuffer's alpha dropped, unless output_alpha=1 asks for
# RGBA; the examples' native builds follow the same rule (--out-alpha).
# The scene (spheres --alpha) clears to transparent black, so an RGBA file
# must hold alpha 0 somewhere; either way the picture equals the native
# one, 0 differing pixels.
# usage: png_channels.sh BIN_DIR IMAGE_TEST OUT_DIR
set -u
bin=$1 image_test=$2 out=$3
bad=0
fail() { echo "FAIL: $*" >&2; bad=1; }
rm -rf "$out" && mkdir -p "$out" || exit 1
args="--alpha 0.5 --frames 1 --size 64x48"
# shellcheck disable=SC2086
"$bin/spheres" $args --chain "render output=$out/rgb-%04d.png" || fail "spheres through render"
# shellcheck disable=SC2086
"$bin/spheres" $args --chain "render output=$out/rgba-%04d.png output_alpha=1" || fail "spheres, output_alpha=1"
# shellcheck disable=SC2086
"$bin/spheres-native" $args --out "$out/native-rgb-%04d.png" || fail "spheres-native"
# shellcheck disable=SC2086
"$bin/spheres-native" $args --out-alpha --out "$out/native-rgba-%04d.png" || fail "spheres-native --out-alpha"
expect() { # FILE WANT
  got=$("$image_test" channels "$1" 2>&1)
  echo "$got"
  [ "$got" = "$1: $2" ] || fail "$1: expected $2"
}
expect "$out/rgb-0000.png" "RGB"
expect "$out/native-rgb-0000.png" "RGB"
expect "$out/rgba-0000.png" "RGBA min_alpha 0"
expect "$out/native-rgba-0000.png" "RGBA min_alpha 0"
for kind in rgb rgba; do
  d=$("$bin/tessera" imgdiff "$out/$kind-0000.png" "$out/native-$kind-0000.png" 2>&1 | head -n 1)
  echo "$kind against native: $d"
  [ "$d" = "differing_pixels: 0" ] || fail "$kind differs from the native render"
done
[ $bad = 0 ] && echo PASS
exit $bad
