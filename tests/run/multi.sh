#!/bin/sh
# tests/run/multi.sh — the several-machines set-up on one machine:
# `tessera mothership GRAPH --listen tcp://127.0.0.1:0` plus separately
# started `tessera node --mothership ADDR` processes, as ssh/mpirun/srun
# would start them. Cases:
#   name   the server joins by --name, the app by --rank 0
#   env    both join by rank from OMPI_COMM_WORLD_RANK / PMI_RANK / SLURM_PROCID
#   unknown-name  a node joins with a name the graph lacks: the node is
#          refused (exit 2) and the mothership fails naming it (exit 1)
#   kill-server   (GRAPH = tests/run/long.yaml) the server node is killed
#          with -9 mid-stream: the mothership, which cannot see the exit
#          status of a process it did not start, names the node whose
#          control connection broke and exits 1 (the time it took is
#          printed; 30 s is only a hang guard), and the app node and its
#          application end too.
# Frames are compared with the native reference (0 differing pixels).
# usage: multi.sh CASE BIN_DIR OUT_DIR GRAPH
set -u
case_name=$1 bin=$2 out=$3 graph=$4
TESSERA=$bin/tessera
. "$(dirname "$0")/../node/node_lib.sh"
frames=20
rm -rf "$out" && mkdir -p "$out/ref" "$out/run" || exit 1
out=$(cd "$out" && pwd)
graph=$(cd "$(dirname "$graph")" && pwd)/$(basename "$graph")

"$TESSERA" mothership "$graph" --listen tcp://127.0.0.1:0 --stats "$out/stats.json" \
  --join-timeout-ms 20000 >"$out/ms.out" 2>"$out/ms.err" &
ms_pid=$!
addr= i=0
while [ -z "$addr" ] && [ $i -lt 200 ] && alive $ms_pid; do
  addr=$(sed -n 's/^mothership listening on tcp:\/\///p' "$out/ms.out" | head -n 1)
  sleep 0.05; i=$((i + 1))
done
[ -n "$addr" ] || { echo "FAIL: no 'mothership listening on' line" >&2; cat "$out/ms.err" >&2; kill -KILL $ms_pid; exit 1; }
echo "mothership at $addr (HOST:PORT form, as a launcher would pass it)"

cd "$out/run" || exit 1
case $case_name in
  name)
    "$TESSERA" node --mothership "$addr" --name server >"$out/server.out" 2>"$out/server.err" &
    p1=$!
    "$TESSERA" node --mothership "$addr" --rank 0 >"$out/app.out" 2>"$out/app.err" &
    p2=$! ;;
  env)
    # tcp.yaml lists app (rank 0) then server (rank 1).
    env -u PMI_RANK -u SLURM_PROCID OMPI_COMM_WORLD_RANK=1 \
      "$TESSERA" node --mothership "$addr" >"$out/server.out" 2>"$out/server.err" &
    p1=$!
    env -u OMPI_COMM_WORLD_RANK -u PMI_RANK SLURM_PROCID=0 \
      "$TESSERA" node --mothership "$addr" >"$out/app.out" 2>"$out/app.err" &
    p2=$! ;;
  unknown-name)
    "$TESSERA" node --mothership "$addr" --name nosuchnode >"$out/server.out" 2>"$out/server.err" &
    p1=$!
    wait_exit $p1 15; node_rc=$EXIT_RC
    wait_exit $ms_pid 15; ms_rc=$EXIT_RC
    echo "node exit $node_rc, mothership exit $ms_rc"; cat "$out/server.err" "$out/ms.err"
    status=0
    [ "$node_rc" = 2 ] || { echo "FAIL: refused node exited $node_rc, expected 2" >&2; status=1; }
    [ "$ms_rc" = 1 ] || { echo "FAIL: mothership exited $ms_rc, expected 1" >&2; status=1; }
    grep -q "refused this node: a node joined as 'nosuchnode'" "$out/server.err" || { echo "FAIL: node message" >&2; status=1; }
    grep -q "^tessera mothership: a node joined as 'nosuchnode'" "$out/ms.err" || { echo "FAIL: mothership message" >&2; status=1; }
    [ $status -eq 0 ] && echo "PASS: unknown node name refused on both sides"
    exit $status ;;
  kill-server)
    "$TESSERA" node --mothership "$addr" --name server >"$out/server.out" 2>"$out/server.err" &
    p1=$!
    "$TESSERA" node --mothership "$addr" --name app >"$out/app.out" 2>"$out/app.err" &
    p2=$!
    i=0
    while [ ! -e "$out/run/out/long-000005.png" ] && [ $i -lt 600 ] && alive $ms_pid; do
      sleep 0.05; i=$((i + 1))
    done
    app=$(ps -o pid= --ppid $p2 | tr -d ' ' | head -n 1)
    t0=$(now_ms)
    kill -KILL $p1
    wait_exit $ms_pid 30; ms_rc=$EXIT_RC
    elapsed=$(( $(now_ms) - t0 ))
    wait_exit $p2 10; app_rc=$EXIT_RC
    wait $p1 2>/dev/null
    echo "mothership exit $ms_rc after $elapsed ms, app node exit $app_rc, application pid ${app:-?}"
    cat "$out/ms.err" "$out/app.err"
    status=0
    [ -n "$app" ] || { echo "FAIL: the application never ran" >&2; status=1; }
    [ "$ms_rc" = 1 ] || { echo "FAIL: mothership exited $ms_rc, expected 1" >&2; status=1; }
    case $app_rc in 0|timeout) echo "FAIL: app node exited $app_rc" >&2; status=1 ;; esac
    grep -q "^tessera mothership: node 'server': control connection lost" "$out/ms.err" \
      || { echo "FAIL: the mothership does not name the server" >&2; status=1; }
    # The app node ends its application as it ends: wait for that, bounded.
    i=0
    while [ -n "$app" ] && alive "$app" && [ $i -lt 200 ]; do sleep 0.05; i=$((i + 1)); done
    if [ -n "$app" ] && alive "$app"; then
      echo "FAIL: application $app outlived its node" >&2; kill -KILL "$app"; status=1
    fi
    [ $status -eq 0 ] && echo "PASS: server killed: mothership named it ($elapsed ms), app node and application ended"
    exit $status ;;
  *) echo "multi.sh: unknown case '$case_name'" >&2; kill -KILL $ms_pid; exit 2 ;;
esac
wait_exit $p1 60; r1=$EXIT_RC
wait_exit $p2 60; r2=$EXIT_RC
wait_exit $ms_pid 60; rms=$EXIT_RC
echo "server node exit $r1, app node exit $r2, mothership exit $rms"
cat "$out/ms.out"
status=0
for r in "$r1" "$r2" "$rms"; do
  [ "$r" = 0 ] || status=1
done
[ $status -eq 0 ] || { echo "FAIL: a process failed; stderr:" >&2; cat "$out/ms.err" "$out/server.err" "$out/app.err" >&2; }
"$bin/spheres-native" --frames $frames --size 1024x768 --out "$out/ref/f-%04d.png" || status=1
pattern=$(sed -n 's/.*output: *"\([^"]*\)".*/\1/p' "$graph")
f=0
while [ $f -lt $frames ]; do
  result=$("$TESSERA" imgdiff "$out/ref/$(printf 'f-%04d.png' $f)" "$out/run/$(printf "$pattern" $f)" 2>&1) || status=1
  echo "frame $f: $(echo "$result" | tr '\n' ' ')"
  f=$((f + 1))
done
grep -q '"status": "ok"' "$out/stats.json" || { echo "FAIL: stats JSON not ok" >&2; status=1; }
[ $status -eq 0 ] && echo "PASS: $case_name: mothership + separately started nodes, $frames frames bit-identical"
exit $status
