#!/bin/sh
# tests/render/render_options.sh — checks of the render SPU's size and
# window options, run through the spheres example.
# usage: render_options.sh fixed-size SPHERES IMAGE_TEST OUT_DIR
#        render_options.sh other-window SPHERES OUT_DIR
set -u
mode=$1 spheres=$2
case $mode in
  fixed-size)
    image_test=$3 out=$4
    rm -rf "$out" && mkdir -p "$out" || exit 1
    # the window is 640x480; the options say 200x100
    "$spheres" --frames 1 --size 640x480 \
      --chain "render width=200 height=100 output=\"$out/f-%d.png\"" || exit 1
    "$image_test" expect-size "$out/f-0.png" 200 100 || exit 1
    echo "PASS: framebuffer follows width/height options" ;;
  other-window)
    out=$3
    rm -rf "$out" && mkdir -p "$out" || exit 1
    "$spheres" --frames 2 --chain "render window=0 output=\"$out/w0-%d.png\"" || exit 1
    "$spheres" --frames 2 --chain "render window=3 output=\"$out/w3-%d.png\"" || exit 1
    [ -s "$out/w0-1.png" ] || { echo "FAIL: window=0 wrote no frame" >&2; exit 1; }
    [ ! -e "$out/w3-0.png" ] || { echo "FAIL: window=3 wrote frames for window 0" >&2; exit 1; }
    echo "PASS: only swaps of the instance's own window write frames" ;;
  *) echo "usage: see header" >&2; exit 2 ;;
esac
