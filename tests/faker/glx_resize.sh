#!/usr/bin/env bash
# tests/faker/glx_resize.sh PROGRAM OUTDIR — runs faker_glx_resize (or
# faker_glx_share) under a private Xvfb with the chain
# "render output=OUTDIR/r-%04d.png".
set -euo pipefail
prog=$1 out=$2
rm -rf "$out"; mkdir -p "$out"
. "$(dirname "$0")/xvfb.sh"
start_xvfb "$out"
TESSERA_CHAIN="render output=$out/r-%04d.png" "$prog" "$out"
