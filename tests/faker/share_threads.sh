#!/usr/bin/env bash
# tests/faker/share_threads.sh — share-list contexts on two threads drawing
# at once (egl_share_threads_driver.c). egl: faker_egl_share_threads with no X
# server, both orders of making the contexts through [render], the loader
# joining a drawing thread through [loopback ! render] (the wire format in
# process), and both through [pack -> server render] (a shared-mode
# `tessera node` on a Unix socket). glx: faker_glx_share_threads under a private Xvfb (the
# drawing thread in an X window, the loader on a GLX pbuffer), both orders
# through [render] and [pack -> server render]. Each run compares its
# frames with one thread's (0 differing pixels); then the frames of every
# run must be the same bytes as the same frames drawn natively, by OSMesa
# in this process (faker_egl_share_threads_native).
# usage: share_threads.sh egl|glx PROGRAM NATIVE TESSERA OUT_DIR
set -u
api=$1 prog=$2 native=$3 TESSERA=$4 out=$5
. "$(dirname "$0")/../node/node_lib.sh"
rm -rf "$out" && mkdir -p "$out" || exit 1
status=0
fail() { echo "FAIL: $*" >&2; status=1; }
frames=8
if [ "$api" = glx ]; then
  . "$(dirname "$0")/xvfb.sh"
  start_xvfb "$out"
else
  unset DISPLAY
fi

runs=()
run() { # NAME MODE CHAIN
  echo "--- $1: $2, chain \"$3\""
  runs+=("$1")
  TESSERA_CHAIN=$3 timeout 60 "$prog" "$2" $frames "$out/$1.raw" || fail "$1: exit $?"
}

run render-created created "render output="
run render-joined joined "render output="
[ "$api" = egl ] && run loopback-joined joined "loopback ! render output="
for mode in created joined; do
  # A shared-mode node: the client's further contexts get chain contexts
  # of their own (server/node.h); when it folded them into one, the
  # drawing thread's calls could land in the loader's open display list.
  start_node "$out/node-$mode" --listen "unix:$out/$mode.sock" --clients 1 --timeout-ms 30000 \
    --chain "render output=" || { fail "no node"; continue; }
  run "pack-$mode" $mode "pack server=unix:$out/$mode.sock"
  wait_exit "$NODE_PID" 15
  [ "$EXIT_RC" = 0 ] || { fail "pack-$mode: the node exited $EXIT_RC"; cat "$out/node-$mode.err"; }
done
echo "--- native: OSMesa, one thread"
timeout 60 "$native" native $frames "$out/native.raw" || fail "native: exit $?"
for r in "${runs[@]}"; do
  cmp "$out/native.raw" "$out/$r.raw" || fail "$r: its frames differ from the native render's"
done
[ $status -eq 0 ] && echo "OK: the frames of all ${#runs[@]} $api runs are the native render's bytes"
exit $status
