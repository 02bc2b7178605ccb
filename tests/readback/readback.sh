#!/bin/sh
# tests/readback/readback.sh — the readback SPU (spus/readback) with a real
# `tessera node` display server, a real example program and real PNGs.
# usage: readback.sh MODE BIN_DIR OUT_DIR
#   window  readback without tiles, in the application's own chain: it
#           renders the whole window, writes it, and streams it to the
#           display node, whose render writes it again. Every frame of
#           both is bit-identical to the native reference; app and display
#           exit 0, and the display ended every frame.
set -u
mode=$1 bin=$2 out=$3
TESSERA=$bin/tessera
. "$(dirname "$0")/../node/node_lib.sh"
rm -rf "$out" && mkdir -p "$out/native" "$out/tile" "$out/display" || exit 1
bad=0
fail() { echo "FAIL: $*" >&2; bad=1; }
case $mode in
window)
  frames=6 size=320x240
  "$bin/spheres-native" --frames $frames --size $size --out "$out/native/f-%04d.png" >/dev/null ||
    { echo "FAIL: spheres-native exited $?" >&2; exit 1; }
  start_node "$out/display" --listen tcp://127.0.0.1:0 --clients 1 --timeout-ms 30000 \
    --chain "render output=\"$out/display/f-%04d.png\"" || exit 1
  display=$NODE_PID
  "$bin/spheres" --frames $frames --size $size \
    --chain "readback server=\"$NODE_ADDR\" output=\"$out/tile/f-%04d.png\"" 2>"$out/app.err" &
  app=$!
  wait_exit $app 60
  [ "$EXIT_RC" = 0 ] || { fail "spheres with readback exited $EXIT_RC"; cat "$out/app.err" >&2; }
  wait_exit $display 30
  [ "$EXIT_RC" = 0 ] || { fail "the display node exited $EXIT_RC"; cat "$out/display.err" >&2; }
  compare_frames "$bin" "$out/native" "$out/tile" $frames "readback's own" || fail "readback's own frames differ"
  compare_frames "$bin" "$out/native" "$out/display" $frames "display" || fail "the display's frames differ"
  [ -e "$out/display/$(printf 'f-%04d.png' $frames)" ] && fail "the display wrote more than $frames frames"
  ;;
*)
  echo "usage: readback.sh window BIN_DIR OUT_DIR" >&2; exit 2 ;;
esac
[ $bad = 0 ] && echo PASS
exit $bad
