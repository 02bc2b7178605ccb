#!/bin/sh
# tests/faker/share_threads.sh — share-list contexts on two threads drawing
# at once (faker_egl_share_threads): both orders of making the contexts
# through [render], the loader joining a drawing thread through
# [loopback ! render] (the wire format in process) and through [pack ->
# server render] (a `tessera node` on a Unix socket), with no X server.
# Each run compares its frames with one thread's (0 differing pixels);
# then the frames of every run must be the same bytes as the same frames
# drawn natively, by OSMesa in this process (faker_egl_share_threads_native).
# usage: share_threads.sh FAKER_EGL_SHARE_THREADS NATIVE TESSERA OUT_DIR
set -u
prog=$1 native=$2 TESSERA=$3 out=$4
. "$(dirname "$0")/../node/node_lib.sh"
rm -rf "$out" && mkdir -p "$out" || exit 1
status=0
fail() { echo "FAIL: $*" >&2; status=1; }
frames=8
unset DISPLAY

run() { # NAME MODE CHAIN
  echo "--- $1: $2, chain \"$3\""
  TESSERA_CHAIN=$3 timeout 60 "$prog" "$2" $frames "$out/$1.raw" || fail "$1: exit $?"
}

run render-created created "render output="
run render-joined joined "render output="
run loopback-joined joined "loopback ! render output="
for mode in created joined; do
  start_node "$out/node-$mode" --listen "unix:$out/$mode.sock" --clients 1 --timeout-ms 30000 \
    --chain "render output=" || { fail "no node"; continue; }
  run "pack-$mode" $mode "pack server=unix:$out/$mode.sock"
  wait_exit "$NODE_PID" 15
  [ "$EXIT_RC" = 0 ] || { fail "pack-$mode: the node exited $EXIT_RC"; cat "$out/node-$mode.err"; }
done
echo "--- native: OSMesa, one thread"
timeout 60 "$native" native $frames "$out/native.raw" || fail "native: exit $?"
for r in render-created render-joined loopback-joined pack-created pack-joined; do
  cmp "$out/native.raw" "$out/$r.raw" || fail "$r: its frames differ from the native render's"
done
[ $status -eq 0 ] && echo "OK: the frames of all 5 runs are the native render's bytes"
exit $status
