#!/bin/sh
# tests/node/two_clients.sh — two applications stream to one node at the
# same time; each gets its own chain ({client} in the chain text keeps
# their frames apart) and its own GL context, so each one's frames are
# bit-identical to that example drawn by OSMesa directly.
# usage: two_clients.sh BIN_DIR OUT_DIR FRAMES
set -u
bin=$1 out=$2 frames=$3
TESSERA=$bin/tessera
. "$(dirname "$0")/node_lib.sh"
rm -rf "$out" && mkdir -p "$out/spheres-native" "$out/texquads-native" "$out/spheres-chain" \
  "$out/texquads-chain" || exit 1
"$bin/spheres-native" --frames "$frames" --out "$out/spheres-native/f-%04d.png" || exit 1
"$bin/texquads-native" --frames "$frames" --out "$out/texquads-native/f-%04d.png" || exit 1

TESSERA_LOG=info start_node "$out/node" --listen tcp://127.0.0.1:0 --clients 2 --timeout-ms 10000 --independent \
  --chain "render output=\"$out/c{client}-f-%04d.png\"" || exit 1
"$bin/spheres" --frames "$frames" --chain "pack server=$NODE_ADDR" &
first=$!
i=0
while ! grep -q "client 0 .* connected" "$out/node.err" && [ $i -lt 200 ]; do sleep 0.05; i=$((i + 1)); done
timeout 60 "$bin/texquads" --frames "$frames" --chain "pack server=$NODE_ADDR"
second_rc=$?
wait_exit "$first" 60
first_rc=$EXIT_RC
wait_exit "$NODE_PID" 15
echo "spheres exit $first_rc, texquads exit $second_rc, node exit $EXIT_RC"
status=0
[ "$first_rc" = 0 ] && [ "$second_rc" = 0 ] && [ "$EXIT_RC" = 0 ] || { cat "$out/node.err"; status=1; }
f=0
while [ $f -lt "$frames" ]; do
  n=$(printf '%04d' $f)
  mv "$out/c0-f-$n.png" "$out/spheres-chain/f-$n.png" 2>/dev/null
  mv "$out/c1-f-$n.png" "$out/texquads-chain/f-$n.png" 2>/dev/null
  f=$((f + 1))
done
compare_frames "$bin" "$out/spheres-native" "$out/spheres-chain" "$frames" "spheres (client 0)" || status=1
compare_frames "$bin" "$out/texquads-native" "$out/texquads-chain" "$frames" "texquads (client 1)" || status=1
[ $status -eq 0 ] && echo "PASS: two concurrent clients, each bit-identical to OSMesa"
exit $status
