#!/bin/sh
# tests/render/render_options.sh — checks of the render SPU's size and
# window options and of how the examples pick their chain, run through the
# spheres example.
# usage: render_options.sh fixed-size SPHERES IMAGE_TEST OUT_DIR
#        render_options.sh other-window SPHERES OUT_DIR
#        render_options.sh env-chain SPHERES OUT_DIR
#        render_options.sh default-chain SPHERES OUT_DIR
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
  env-chain)
    out=$3
    rm -rf "$out" && mkdir -p "$out" || exit 1
    TESSERA_CHAIN="render output=\"$out/env-%d.png\"" "$spheres" --frames 1 || exit 1
    [ -s "$out/env-0.png" ] || { echo "FAIL: \$TESSERA_CHAIN was not used" >&2; exit 1; }
    # --chain wins over the environment
    TESSERA_CHAIN="render output=\"$out/env-%d.png\"" "$spheres" --frames 1 \
      --chain "render output=\"$out/opt-%d.png\"" || exit 1
    [ -s "$out/opt-0.png" ] || { echo "FAIL: --chain did not win over \$TESSERA_CHAIN" >&2; exit 1; }
    echo "PASS: chain from \$TESSERA_CHAIN, overridden by --chain" ;;
  default-chain)
    out=$3
    rm -rf "$out" && mkdir -p "$out" || exit 1
    (cd "$out" && env -u TESSERA_CHAIN "$spheres" --frames 2) || exit 1
    [ -s "$out/out/spheres-0001.png" ] || { echo "FAIL: no out/spheres-0001.png" >&2; exit 1; }
    echo "PASS: default chain renders to out/spheres-%04d.png" ;;
  *) echo "usage: see header" >&2; exit 2 ;;
esac
