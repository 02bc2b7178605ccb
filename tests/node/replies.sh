#!/bin/sh
# tests/node/replies.sh — gets, GenLists, GetString and ReadPixels sent
# through the pack SPU to a node must answer exactly what a local render
# chain answers (node_driver replies compares them).
# usage: replies.sh BIN_DIR OUT_DIR NODE_DRIVER
set -u
bin=$1 out=$2 driver=$3
TESSERA=$bin/tessera
. "$(dirname "$0")/node_lib.sh"
rm -rf "$out" && mkdir -p "$out" || exit 1
start_node "$out/node" --listen tcp://127.0.0.1:0 --clients 1 --timeout-ms 10000 --chain render || exit 1
timeout 30 "$driver" replies "$NODE_ADDR"
rc=$?
wait_exit "$NODE_PID" 15
echo "driver exit $rc, node exit $EXIT_RC"
cat "$out/node.err"
[ $rc -eq 0 ] && [ "$EXIT_RC" = 0 ] && echo "PASS: replies through the node equal local ones"
[ $rc -eq 0 ] && [ "$EXIT_RC" = 0 ]
