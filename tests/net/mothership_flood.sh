#!/bin/sh
# tests/net/mothership_flood.sh — the mothership's control listener under
# the idle-connection flood of issue 10, defect 7: 200 connections that
# never send a byte (reopened as the mothership closes them) are held on
# its port while the graph's two nodes join with the run's token. Before
# the fix they filled the pending-accept limit and the nodes were locked
# out; now each node must join within a 3 s connect time-out and the run
# end with every process exiting 0.
# usage: mothership_flood.sh BIN_DIR OUT_DIR GRAPH NET_AUTH_TEST
set -u
bin=$1 out=$2 graph=$3 flood=$4
TESSERA=$bin/tessera
. "$(dirname "$0")/../node/node_lib.sh"
rm -rf "$out" && mkdir -p "$out/run" || exit 1
out=$(cd "$out" && pwd)
graph=$(cd "$(dirname "$graph")" && pwd)/$(basename "$graph")
token=flood-test-token-5d1e

"$TESSERA" mothership "$graph" --listen tcp://127.0.0.1:0 --token $token \
  --join-timeout-ms 20000 >"$out/ms.out" 2>"$out/ms.err" &
ms_pid=$!
addr= i=0
while [ -z "$addr" ] && [ $i -lt 200 ] && alive $ms_pid; do
  addr=$(sed -n 's/^mothership listening on tcp:\/\///p' "$out/ms.out" | head -n 1)
  sleep 0.05; i=$((i + 1))
done
[ -n "$addr" ] || { echo "FAIL: no 'mothership listening on' line" >&2; cat "$out/ms.err" >&2; kill -KILL $ms_pid; exit 1; }
port=${addr##*:}

"$flood" hold_idle "$port" 200 20000 >"$out/flood.out" 2>"$out/flood.err" &
flood_pid=$!
i=0
while ! grep -q '^holding' "$out/flood.out" && [ $i -lt 200 ] && alive $flood_pid; do
  sleep 0.05; i=$((i + 1))
done
grep -q '^holding 200' "$out/flood.out" || { echo "FAIL: the flood did not start" >&2; cat "$out/flood.err" >&2; kill -KILL $ms_pid $flood_pid; exit 1; }
echo "mothership at $addr, 200 idle connections held on it"

cd "$out/run" || exit 1
"$TESSERA" node --mothership "$addr" --name server --token $token --connect-timeout-ms 3000 \
  >"$out/server.out" 2>"$out/server.err" &
p1=$!
"$TESSERA" node --mothership "$addr" --name app --token $token --connect-timeout-ms 3000 \
  >"$out/app.out" 2>"$out/app.err" &
p2=$!
wait_exit $p1 60; r1=$EXIT_RC
wait_exit $p2 60; r2=$EXIT_RC
wait_exit $ms_pid 60; rms=$EXIT_RC
kill $flood_pid 2>/dev/null; wait $flood_pid 2>/dev/null
echo "server node exit $r1, app node exit $r2, mothership exit $rms"
status=0
for r in "$r1" "$r2" "$rms"; do
  [ "$r" = 0 ] || status=1
done
if [ $status -ne 0 ]; then
  echo "FAIL: a process failed under the flood; stderr:" >&2
  cat "$out/ms.err" "$out/server.err" "$out/app.err" >&2
fi
[ $status -eq 0 ] && echo "PASS: both nodes joined the mothership through 200 idle connections; the run ended cleanly"
exit $status
