#!/bin/sh
# tests/run/netns.sh — several hosts for real: four network namespaces
# (ip netns, from iproute2) joined by veth pairs to a bridge that lives in a
# fifth namespace, so the host's own network is never touched. The
# mothership (10.213.0.1), two servers (.2, .3) and an app (.4) each run in
# their own namespace and talk over TCP on those addresses only; both
# servers' frames must be bit-identical to the native reference.
# Then a sort-last graph (netns_sortlast.yaml) across the same hosts: two
# apps on .4 stream to two binaryswap render servers on .2 and .3, which
# composite between their hosts over TCP (their own per-pair lines say
# "tcp"), and a display on .1: every frame bit-identical to the native
# render of the whole isosurface.
# Without root or namespace support it prints why and exits 77 (ctest's
# SKIP_RETURN_CODE for this test); as root (CI) it runs. Namespaces and
# processes are removed on every exit path (trap).
# usage: netns.sh BIN_DIR OUT_DIR
set -u
bin=$1 out=$2
TESSERA=$bin/tessera
here=$(cd "$(dirname "$0")" && pwd)
. "$here/../node/node_lib.sh"
graph=$here/netns.yaml
frames=5
tag=t$$
hub=tsr-$tag-hub
pids=

skip() { echo "SKIP: $*"; exit 77; }
[ "$(id -u)" = 0 ] || skip "needs root to create network namespaces (uid $(id -u))"
command -v ip >/dev/null 2>&1 || skip "ip (Debian package iproute2) is not installed"
ip netns add "tsr-$tag-probe" 2>/dev/null || skip "cannot create a network namespace here (ip netns add failed)"
ip netns del "tsr-$tag-probe"

cleanup() {
  for p in $pids; do kill -KILL "$p" 2>/dev/null; done
  for ns in ms s0 s1 app hub; do ip netns del "tsr-$tag-$ns" 2>/dev/null; done
}
trap cleanup EXIT
trap 'exit 1' INT TERM HUP

rm -rf "$out" && mkdir -p "$out/ref" "$out/run" || exit 1
out=$(cd "$out" && pwd)

ip netns add "$hub" || exit 1
ip -n "$hub" link add br0 type bridge && ip -n "$hub" link set br0 up || exit 1
i=1
for host in ms s0 s1 app; do
  ns=tsr-$tag-$host
  ip netns add "$ns" || exit 1
  ip -n "$hub" link add "v$i" type veth peer name "b$i" || exit 1
  ip -n "$hub" link set "v$i" netns "$ns" || exit 1
  ip -n "$hub" link set "b$i" master br0 && ip -n "$hub" link set "b$i" up || exit 1
  ip -n "$ns" addr add "10.213.0.$i/24" dev "v$i" || exit 1
  ip -n "$ns" link set "v$i" up && ip -n "$ns" link set lo up || exit 1
  i=$((i + 1))
done
echo "namespaces: mothership 10.213.0.1, s0 10.213.0.2, s1 10.213.0.3, app 10.213.0.4 (bridge in $hub)"

ip netns exec "tsr-$tag-ms" "$TESSERA" mothership "$graph" --listen tcp://10.213.0.1:0 \
  --stats "$out/stats.json" --join-timeout-ms 30000 --no-progress >"$out/ms.out" 2>"$out/ms.err" &
ms_pid=$!
pids="$ms_pid"
addr= n=0
while [ -z "$addr" ] && [ $n -lt 200 ] && alive $ms_pid; do
  addr=$(sed -n 's/^mothership listening on tcp:\/\///p' "$out/ms.out" | head -n 1)
  sleep 0.05; n=$((n + 1))
done
[ -n "$addr" ] || { echo "FAIL: mothership printed no address" >&2; cat "$out/ms.err" >&2; exit 1; }
case $addr in 10.213.0.1:*) ;; *) echo "FAIL: mothership listens on $addr, not 10.213.0.1" >&2; exit 1 ;; esac
echo "mothership listening on $addr"

cd "$out/run" || exit 1
i=2
for host in s0 s1 app; do
  ip netns exec "tsr-$tag-$host" "$TESSERA" node --mothership "$addr" --name "$host" \
    --bind "10.213.0.$i" >"$out/$host.out" 2>"$out/$host.err" &
  i=$((i + 1))
  pids="$pids $!"
  eval "pid_$host=\$!"
done
status=0
for host in s0 s1 app; do
  eval "p=\$pid_$host"
  wait_exit "$p" 90
  echo "node $host exit $EXIT_RC"
  [ "$EXIT_RC" = 0 ] || { echo "FAIL: node $host exited $EXIT_RC:" >&2; cat "$out/$host.err" >&2; status=1; }
done
wait_exit $ms_pid 30
echo "mothership exit $EXIT_RC"; cat "$out/ms.out"
[ "$EXIT_RC" = 0 ] || { echo "FAIL: mothership exited $EXIT_RC:" >&2; cat "$out/ms.err" >&2; status=1; }
# The servers really listened on their own namespace's address.
cat "$out/stats.json"
grep -q '"status": "ok"' "$out/stats.json" || { echo "FAIL: stats JSON not ok" >&2; status=1; }
for s in 2 3; do
  grep -Eq "\"address\": \"tcp://10\.213\.0\.$s:[1-9][0-9]*\"" "$out/stats.json" \
    || { echo "FAIL: no server listened on 10.213.0.$s" >&2; status=1; }
done

"$bin/spheres-native" --frames $frames --size 320x240 --out "$out/ref/f-%04d.png" || status=1
for s in s0 s1; do
  f=0
  while [ $f -lt $frames ]; do
    result=$("$TESSERA" imgdiff "$out/ref/$(printf 'f-%04d.png' $f)" \
             "$out/run/out/$(printf "netns-$s-%04d.png" $f)" 2>&1) || status=1
    echo "$s frame $f: $(echo "$result" | tr '\n' ' ')"
    f=$((f + 1))
  done
done
[ $status -eq 0 ] && echo "PASS: mothership, two servers and an app in four namespaces over TCP; $frames frames per server bit-identical"

# ---- sort-last across the namespaces -----------------------------------------
sl=$out/sortlast sl_frames=3
mkdir -p "$sl/ref" "$sl/run" || exit 1
ip netns exec "tsr-$tag-ms" "$TESSERA" mothership "$here/netns_sortlast.yaml" --listen tcp://10.213.0.1:0 \
  --stats "$sl/stats.json" --join-timeout-ms 30000 --no-progress >"$sl/ms.out" 2>"$sl/ms.err" &
ms_pid=$!
pids="$pids $ms_pid"
addr= n=0
while [ -z "$addr" ] && [ $n -lt 200 ] && alive $ms_pid; do
  addr=$(sed -n 's/^mothership listening on tcp:\/\///p' "$sl/ms.out" | head -n 1)
  sleep 0.05; n=$((n + 1))
done
[ -n "$addr" ] || { echo "FAIL: the sort-last mothership printed no address" >&2; cat "$sl/ms.err" >&2; exit 1; }
cd "$sl/run" || exit 1
for pair in display:ms:1 peer0:s0:2 peer1:s1:3 app0:app:4 app1:app:4; do
  name=${pair%%:*} rest=${pair#*:}
  host=${rest%%:*} ip=10.213.0.${rest#*:}
  TESSERA_LOG=info ip netns exec "tsr-$tag-$host" "$TESSERA" node --mothership "$addr" --name "$name" \
    --bind "$ip" >"$sl/$name.out" 2>"$sl/$name.err" &
  pids="$pids $!"
  eval "pid_$name=\$!"
done
for name in app0 app1 peer0 peer1 display; do
  eval "p=\$pid_$name"
  wait_exit "$p" 90
  echo "sort-last node $name exit $EXIT_RC"
  [ "$EXIT_RC" = 0 ] || { echo "FAIL: sort-last node $name exited $EXIT_RC:" >&2; tail -n 20 "$sl/$name.err" >&2; status=1; }
done
wait_exit $ms_pid 30
echo "sort-last mothership exit $EXIT_RC"
[ "$EXIT_RC" = 0 ] || { echo "FAIL: the sort-last mothership exited $EXIT_RC:" >&2; cat "$sl/ms.err" >&2; status=1; }
# The two peers composited with each other over TCP between their hosts.
for r in 0 1; do
  o=$((1 - r)) ip=$((3 - r))
  line=$(grep "transport rank $r <-> rank $o " "$sl/peer$r.err" | sed 's/^tessera: //')
  echo "peer$r: $line"
  case $line in
  *"(tcp://10.213.0.$ip:7102): tcp") ;;
  *) echo "FAIL: peer$r did not reach rank $o over TCP at 10.213.0.$ip:7102" >&2; status=1 ;;
  esac
  stats=$(grep "transport stats rank $r -> rank $o: tcp; sent [1-9]" "$sl/peer$r.err" | sed 's/^tessera: //')
  [ -n "$stats" ] || { echo "FAIL: peer$r sent rank $o no image over TCP" >&2; status=1; }
  echo "peer$r: $stats"
done
"$bin/isosurface-native" --frames $sl_frames --size 160x120 --out "$sl/ref/f-%04d.png" || status=1
f=0
while [ $f -lt $sl_frames ]; do
  name=$(printf 'f-%04d.png' $f)
  result=$("$TESSERA" imgdiff "$sl/ref/$name" "$sl/run/out/$(printf 'netns-sortlast-%04d.png' $f)" 2>&1 | head -n 1)
  echo "sort-last frame $f: $result"
  [ "$result" = "differing_pixels: 0" ] || { echo "FAIL: sort-last frame $f differs from the native render ($result)" >&2; status=1; }
  f=$((f + 1))
done
[ -e "$sl/run/out/$(printf 'netns-sortlast-%04d.png' $sl_frames)" ] && { echo "FAIL: the display wrote more than $sl_frames frames" >&2; status=1; }
[ $status -eq 0 ] && echo "PASS: sort-last across namespaces: two binaryswap peers on two hosts over TCP, $sl_frames frames bit-identical"
exit $status
