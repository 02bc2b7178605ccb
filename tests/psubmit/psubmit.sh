#!/bin/sh
# tests/psubmit/psubmit.sh — parallel submission into one shared-mode
# server node (server/node.h), with real processes over real sockets:
#   accuracy BIN OUT N FRAMES   N psubmit ranks -> one node (render):
#                               every frame bit-identical to psubmit-native
#   semaphore BIN OUT DRIVER    V from one client lets another's P go on:
#                               the drawing order (and so the picture) is
#                               the semaphore's, equal to the reference
#   deadlock BIN OUT DRIVER     one client waits on a semaphore nobody
#                               posts, the other at a barrier for two: the
#                               node fails within the bound, naming both
#   barrier-left BIN OUT DRIVER one client waits at a barrier for two, the
#                               other ends without reaching it: clear error
#   barrier-cut BIN OUT DRIVER  one client waits at a barrier for two and
#                               is killed there (the node does not read a
#                               waiter's stream), then the other is killed:
#                               both get a line saying they went away
#   one-swapper BIN OUT DRIVER  two clients swap; only the first to swap
#                               ends frames, the other's swap is ignored
#   graph BIN OUT GRAPH         `tessera run GRAPH` (examples/graphs/
#                               psubmit.yaml: 4 ranks, 10 frames, 1024x768)
#                               from the build directory: every frame
#                               bit-identical to psubmit-native
# Every wait is bounded (node_lib.sh).
set -u
mode=$1 bin=$2 out=$3
TESSERA=$bin/tessera
. "$(dirname "$0")/../node/node_lib.sh"
rm -rf "$out" && mkdir -p "$out/native" "$out/chain" || exit 1
status=0
fail() { echo "FAIL: $*"; status=1; }
show() { [ -s "$1" ] && sed 's/^/  | /' "$1"; }
# A shared-mode node for two driver clients, logging at debug level (the
# tests wait for its "connected" and "waits" lines), rendering into
# $out/chain.
start_pair_node() {
  TESSERA_LOG=debug start_node "$out/node" --listen tcp://127.0.0.1:0 --clients 2 --timeout-ms 20000 \
    --chain "render output=\"$out/chain/f-%04d.png\""
}

case "$mode" in
accuracy)
  ranks=$4 frames=$5
  size=320x240
  "$bin/psubmit-native" --frames "$frames" --size $size --out "$out/native/f-%04d.png" || exit 1
  start_node "$out/node" --listen tcp://127.0.0.1:0 --clients "$ranks" --timeout-ms 20000 \
    --chain "render output=\"$out/chain/f-%04d.png\"" || exit 1
  pids=""
  r=0
  while [ $r -lt "$ranks" ]; do
    "$bin/psubmit" --rank $r --ranks "$ranks" --frames "$frames" --size $size \
      --chain "pack server=$NODE_ADDR" 2>"$out/rank$r.err" &
    pids="$pids $!"
    r=$((r + 1))
  done
  r=0
  for pid in $pids; do
    wait_exit "$pid" 90
    [ "$EXIT_RC" = 0 ] || { fail "rank $r exited $EXIT_RC"; show "$out/rank$r.err"; }
    r=$((r + 1))
  done
  wait_exit "$NODE_PID" 20
  [ "$EXIT_RC" = 0 ] || { fail "node exited $EXIT_RC"; show "$out/node.err"; }
  compare_frames "$bin" "$out/native" "$out/chain" "$frames" "psubmit $ranks ranks" || status=1
  extra=$(printf 'f-%04d.png' "$frames")
  [ ! -e "$out/chain/$extra" ] || fail "the node wrote more than $frames frames"
  ;;
semaphore)
  driver=$4
  timeout 30 "$driver" sem-reference "render output=\"$out/native/f-%04d.png\"" || exit 1
  start_pair_node || exit 1
  # The waiting client connects first and is blocked on P before the other
  # even starts: the node says so (debug), and the script waits for that.
  "$driver" sem-second "pack server=$NODE_ADDR" 2>"$out/second.err" &
  second=$!
  wait_line "$out/node.err" "client 0 .* waits on semaphore 5" 20 || fail "sem-second never blocked on P(5)"
  timeout 30 "$driver" sem-first "pack server=$NODE_ADDR" 2>"$out/first.err" || fail "sem-first exited $?"
  wait_exit "$second" 30
  [ "$EXIT_RC" = 0 ] || { fail "sem-second exited $EXIT_RC"; show "$out/second.err"; }
  wait_exit "$NODE_PID" 20
  [ "$EXIT_RC" = 0 ] || { fail "node exited $EXIT_RC"; show "$out/node.err"; }
  grep -q "blocked\|dropped" "$out/node.err" && show "$out/node.err"
  compare_frames "$bin" "$out/native" "$out/chain" 1 "semaphore order" || status=1
  ;;
graph)
  graph=$4
  "$bin/psubmit-native" --frames 10 --size 1024x768 --out "$out/native/f-%04d.png" || exit 1
  (cd "$bin/.." && timeout 120 "$TESSERA" run "$graph" --out "$out/run") >"$out/run.log" 2>&1
  rc=$?
  [ $rc -eq 0 ] || { fail "tessera run exited $rc"; show "$out/run.log"; }
  f=0
  while [ $f -lt 10 ]; do
    n=$(printf '%04d' $f)
    [ -e "$out/run/out/psubmit-$n.png" ] && mv "$out/run/out/psubmit-$n.png" "$out/chain/f-$n.png"
    f=$((f + 1))
  done
  compare_frames "$bin" "$out/native" "$out/chain" 10 "psubmit graph" || status=1
  ;;
barrier-cut)
  driver=$4
  start_pair_node || exit 1
  "$driver" barrier-wait "pack server=$NODE_ADDR" 2>"$out/wait.err" &
  waiter=$!
  wait_line "$out/node.err" "client 0 .* waits at barrier 3" 20 || fail "barrier-wait never reached barrier 3"
  "$driver" barrier-hold "pack server=$NODE_ADDR" 2>"$out/hold.err" &
  holder=$!
  wait_line "$out/hold.err" "barrier-hold: held" 20 || fail "the node never ran barrier-hold's stream"
  kill -9 $waiter
  wait $waiter 2>/dev/null
  # The waiter's end is gone, unread: the node still serves the holder.
  kill -USR1 $holder
  wait_line "$out/hold.err" "barrier-hold: served again" 20 || fail "the node stopped serving after the waiter went away"
  alive "$NODE_PID" || fail "the node ended before the second client went away"
  kill -9 $holder
  wait $holder 2>/dev/null
  wait_exit "$NODE_PID" 20
  node_rc=$EXIT_RC
  show "$out/node.err"
  [ "$node_rc" = 1 ] || fail "node exited $node_rc; expected 1"
  for k in 0 1; do
    grep -q "node: client $k 'pack[^']*' at [^ ]* dropped: .*went away without closing" "$out/node.err" \
      || fail "no line says client $k went away"
  done
  grep -q "barrier 3 can never be reached: it counts 2 clients, 0 left; gone: client 0 .*(dropped), client 1 .*(dropped)" \
    "$out/node.err" || fail "the verdict does not name both clients as gone"
  ;;
one-swapper)
  driver=$4
  start_pair_node || exit 1
  "$driver" swap-other "pack server=$NODE_ADDR" 2>"$out/other.err" &
  other=$!
  timeout 30 "$driver" swap-owner "pack server=$NODE_ADDR" 2>"$out/owner.err" || fail "swap-owner exited $?"
  wait_exit "$other" 30
  [ "$EXIT_RC" = 0 ] || { fail "swap-other exited $EXIT_RC"; show "$out/other.err"; }
  wait_exit "$NODE_PID" 20
  [ "$EXIT_RC" = 0 ] || fail "node exited $EXIT_RC"
  show "$out/node.err"
  frames=$(ls "$out/chain" | grep -c '^f-.*png$')
  [ "$frames" = 2 ] || fail "the node wrote $frames frames; expected 2 (swap-owner's swaps only)"
  grep -q "node: 2 frames; 1 swaps of other clients ignored" "$out/node.err" \
    || fail "the node did not count 2 frames and 1 ignored swap"
  ;;
deadlock|barrier-left)
  driver=$4
  start_node "$out/node" --listen tcp://127.0.0.1:0 --clients 2 --timeout-ms 20000 \
    --chain "render output=\"$out/chain/f-%04d.png\"" || exit 1
  start=$(now_ms)
  if [ "$mode" = deadlock ]; then roles="p-forever barrier-wait"; else roles="barrier-wait barrier-leave"; fi
  pids=""
  for role in $roles; do
    "$driver" $role "pack server=$NODE_ADDR" 2>"$out/$role.err" &
    pids="$pids $!"
  done
  wait_exit "$NODE_PID" 20
  took=$(( $(now_ms) - start ))
  node_rc=$EXIT_RC
  show "$out/node.err"
  echo "node exit $node_rc after $took ms"
  [ "$node_rc" = 1 ] || fail "node exited $node_rc; expected 1"
  if [ "$mode" = deadlock ]; then
    word=deadlock
    line=$(grep "$word" "$out/node.err")
    echo "$line" | grep -q "barrier 3 (count 2, 1 arrived) holds client [01] 'pack" \
      || fail "the message does not name barrier 3 and its waiting client"
    echo "$line" | grep -q "semaphore 7 (value 0) holds client [01] 'pack" \
      || fail "the message does not name semaphore 7 and its waiting client"
  else
    word="can never be reached"
    line=$(grep "$word" "$out/node.err")
    echo "$line" | grep -q "barrier 3 can never be reached: it counts 2 clients, 1 left; waiting: client [01] 'pack" \
      || fail "the message does not name barrier 3 and its waiting client"
    echo "$line" | grep -q "gone: client [01] 'pack.* (disconnected)" \
      || fail "the message does not name the client that left"
  fi
  for pid in $pids; do
    wait_exit "$pid" 15
    [ "$EXIT_RC" != timeout ] || fail "a client was still running 15 s after the node ended"
  done
  # The blocked clients learn why.
  for role in $roles; do
    [ "$role" = barrier-leave ] && continue
    show "$out/$role.err"
    grep -q "$word" "$out/$role.err" || fail "$role was not told why"
  done
  ;;
*)
  echo "psubmit.sh: unknown mode $mode" >&2
  exit 2
  ;;
esac
[ $status -eq 0 ] && echo "PASS: psubmit $mode"
exit $status
