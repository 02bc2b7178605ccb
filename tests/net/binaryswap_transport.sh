#!/bin/sh
# tests/net/binaryswap_transport.sh — which transport sort-last peers on one
# host use, proven from their own statistics: a sort-last graph (N in-situ
# binaryswap peers, direct send, so every pair of peers exchanges images
# both ways, and a display node) under `tessera run`, every frame exactly
# the native render of the whole scene, and every peer's per-pair lines
# (binaryswap logs them at info level: "transport rank I <-> rank J" at
# the first frame, "transport stats rank I -> rank J" at the end):
#   unix  every pair "unix+shm", and every byte each peer sent and received
#         went through shared memory (only descriptors crossed the sockets)
#   noshm the same graph with shm=0: every pair "unix", nothing through
#         shared memory
#   tcp   defaults transport tcp: every pair "tcp", nothing through it
#         (explicit exchange ports below Linux's ephemeral range, 32768..,
#         so no client's port can hold one; a run that still finds one
#         taken by another program is run again on other ports, twice at
#         most)
# usage: binaryswap_transport.sh MODE BIN_DIR OUT_DIR [N]
set -u
. "$(dirname "$0")/../binaryswap/lib.sh"
mode=$1 bin=$2 out=$3 n=${4:-3}
fail() { echo "FAIL: $*" >&2; bad=1; }
bad=0
rm -rf "$out" && mkdir -p "$out/native" || exit 1
frames=2 size=96x72
case $mode in
unix) transport=unix options="strategy: direct" want=unix+shm ;;
noshm) transport=unix options="strategy: direct, shm: 0" want=unix ;;
tcp) transport=tcp options="strategy: direct" want=tcp ;;
*) echo "unknown mode $mode" >&2; exit 2 ;;
esac
"$bin/spheres-native" --overlap --frames $frames --size $size --out "$out/native/f-%04d.png" || exit 1
graph=$out/graph.yaml
shares= i=0
while [ $i -lt "$n" ]; do shares="$shares $i/$n"; i=$((i + 1)); done
try=0
while :; do
  if [ "$mode" = tcp ]; then
    base=$((20000 + ($$ * 7 + try * 1009) % 12000))
    ex= i=0
    while [ $i -lt "$n" ]; do ex="$ex${ex:+, }tcp://127.0.0.1:$((base + i))"; i=$((i + 1)); done
    options="strategy: direct, exchange: [$ex]"
  fi
  sl_write_graph "$graph" insitu "$transport" "$options" "bin/spheres --overlap --frames $frames --size $size" $shares
  rm -rf "$out/run"
  sl_run "$graph" info
  try=$((try + 1))
  [ $rc != 0 ] && [ $try -lt 3 ] && grep -q "cannot listen for its peers.*address already in use" "$out/run.err" || break
  echo "an exchange port was taken by another program: again on other ports"
done
sl_check_run
sl_compare_frames
grep 'transport ' "$out/run.err" | sed 's/^tessera: //'
i=0
while [ $i -lt "$n" ]; do
  j=0
  while [ $j -lt "$n" ]; do
    if [ $i != $j ]; then
      link=$(grep -c "transport rank $i <-> rank $j (.*): $want\$" "$out/run.err")
      [ "$link" = 1 ] || fail "rank $i did not log its link to rank $j as $want ($link lines)"
      line=$(grep "transport stats rank $i -> rank $j: " "$out/run.err")
      [ -n "$line" ] || { fail "rank $i wrote no statistics for rank $j"; j=$((j + 1)); continue; }
      echo "$line" | grep -q "rank $j: $want;" || fail "rank $i -> rank $j: not $want: $line"
      # sent A messages B bytes (C messages D bytes through shared memory); received E F (G H ...)
      set -- $(echo "$line" | sed 's/.*; sent \([0-9]*\) messages \([0-9]*\) bytes (\([0-9]*\) messages \([0-9]*\) bytes through shared memory); received \([0-9]*\) messages \([0-9]*\) bytes (\([0-9]*\) messages \([0-9]*\) bytes.*/\1 \2 \3 \4 \5 \6 \7 \8/')
      [ $# = 8 ] || { fail "rank $i -> rank $j: unreadable statistics: $line"; j=$((j + 1)); continue; }
      # direct send: each pair exchanges a strip every frame, both ways
      [ "$1" -ge $frames ] && [ "$5" -ge $frames ] || fail "rank $i -> rank $j: $1 sent, $5 received (< $frames frames)"
      if [ "$want" = unix+shm ]; then
        [ "$3" = "$1" ] && [ "$4" = "$2" ] || fail "rank $i -> rank $j: $3 of $1 messages, $4 of $2 bytes through shared memory"
        [ "$7" = "$5" ] && [ "$8" = "$6" ] || fail "rank $i <- rank $j: $7 of $5 messages, $8 of $6 bytes through shared memory"
      else
        [ "$3" = 0 ] && [ "$7" = 0 ] || fail "rank $i -> rank $j: $3 sent and $7 received through shared memory over $want"
      fi
    fi
    j=$((j + 1))
  done
  i=$((i + 1))
done
[ $bad = 0 ] && echo "PASS: $n peers on one host, every pair over $want, $frames frames exact"
exit $bad
