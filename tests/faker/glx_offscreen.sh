#!/usr/bin/env bash
# tests/faker/glx_offscreen.sh PROGRAM OUTDIR — runs faker_glx_offscreen
# under a private Xvfb for a GLX pbuffer, a GLX 1.3 pixmap and a GLX 1.2
# pixmap, each in a process of its own (the drawable is its stream's first
# window), with the chain "render output=OUTDIR/MODE/r-%04d.png".
set -euo pipefail
prog=$1 out=$2
rm -rf "$out"; mkdir -p "$out"
. "$(dirname "$0")/xvfb.sh"
start_xvfb "$out"
status=0
for mode in pbuffer pixmap glxpixmap; do
  mkdir -p "$out/$mode"
  echo "--- $mode"
  TESSERA_CHAIN="render output=$out/$mode/r-%04d.png" timeout 60 "$prog" "$mode" "$out/$mode" || status=1
done
exit $status
