#!/bin/sh
# tests/node/accuracy.sh — an example sends its stream through the pack SPU
# to a `tessera node` (render chain) over TCP or a Unix socket; every frame
# the node writes must be bit-identical to the example drawn by OSMesa
# directly, and node and app must both exit 0.
# usage: accuracy.sh BIN_DIR EXAMPLE OUT_DIR FRAMES tcp|unix
set -u
bin=$1 example=$2 out=$3 frames=$4 transport=$5
TESSERA=$bin/tessera
. "$(dirname "$0")/node_lib.sh"
rm -rf "$out" && mkdir -p "$out/native" "$out/chain" || exit 1
case $transport in
  tcp)  listen=tcp://127.0.0.1:0 ;;
  unix) listen=unix:$out/node.sock ;;
  *) echo "accuracy.sh: unknown transport '$transport'" >&2; exit 2 ;;
esac

"$bin/$example-native" --frames "$frames" --out "$out/native/f-%04d.png" \
  || { echo "FAIL: $example-native exited $?" >&2; exit 1; }

start_node "$out/node" --listen "$listen" --clients 1 --timeout-ms 10000 \
  --chain "render output=\"$out/chain/f-%04d.png\"" || exit 1
echo "node listening on $NODE_ADDR"
case $transport in
  tcp) echo "$NODE_ADDR" | grep -Eq '^tcp://127\.0\.0\.1:[1-9][0-9]*$' \
         || { echo "FAIL: node printed '$NODE_ADDR', not its real port" >&2; kill -9 $NODE_PID; exit 1; } ;;
esac

timeout 60 "$bin/$example" --frames "$frames" --chain "pack server=\"$NODE_ADDR\""
app_rc=$?
wait_exit "$NODE_PID" 15; node_rc=$EXIT_RC
echo "app exit $app_rc, node exit $node_rc"
status=0
[ "$app_rc" -eq 0 ] || { echo "FAIL: $example exited $app_rc" >&2; status=1; }
[ "$node_rc" = 0 ] || { echo "FAIL: node exited $node_rc; its stderr:" >&2; cat "$out/node.err" >&2; status=1; }
compare_frames "$bin" "$out/native" "$out/chain" "$frames" "$example [pack $transport]" || status=1
[ $status -eq 0 ] && echo "PASS: $frames frames of $example through pack -> $transport -> node render are bit-identical to OSMesa"
exit $status
