#!/usr/bin/env bash
# tests/faker/share_client_state.sh — two contexts of one share group with
# different pixel store and client arrays, used in turn on one thread
# (egl_share_client_state_driver.c), through [render], [loopback ! render] and
# [pack -> a shared-mode server render]: each run's read-back blocks and
# frames must be the bytes OSMesa itself gives for the same calls
# (faker_egl_share_client_state_native).
# usage: share_client_state.sh PROGRAM NATIVE TESSERA OUT_DIR
set -u
prog=$1 native=$2 TESSERA=$3 out=$4
. "$(dirname "$0")/../node/node_lib.sh"
rm -rf "$out" && mkdir -p "$out" || exit 1
unset DISPLAY
status=0
fail() { echo "FAIL: $*" >&2; status=1; }
timeout 60 "$native" "$out/native.raw" || fail "native: exit $?"
runs=()
run() { # NAME CHAIN
  echo "--- $1: chain \"$2\""
  runs+=("$1")
  TESSERA_CHAIN=$2 timeout 60 "$prog" "$out/$1.raw" || fail "$1: exit $?"
}
run render "render output="
run loopback "loopback ! render output="
start_node "$out/node" --listen "unix:$out/node.sock" --clients 1 --timeout-ms 30000 --chain "render output=" ||
  fail "no node"
run pack "pack server=unix:$out/node.sock"
wait_exit "$NODE_PID" 15
[ "$EXIT_RC" = 0 ] || { fail "pack: the node exited $EXIT_RC"; cat "$out/node.err"; }
for r in "${runs[@]}"; do
  cmp "$out/native.raw" "$out/$r.raw" || fail "$r: its read-backs and frames differ from OSMesa's"
done
[ $status -eq 0 ] && echo "OK: ${#runs[@]} runs give OSMesa's bytes for two contexts with their own client state"
exit $status
