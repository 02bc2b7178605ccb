#!/bin/sh
# tests/node/failures.sh — what happens when something goes wrong between
# an application (pack SPU) and a server node: each must end with a clear
# one-line message naming the culprit, the right exit codes, and no hang.
# usage: failures.sh MODE BIN_DIR OUT_DIR [NODE_DRIVER]
#   bad-token       node requires a token; a client with a wrong one is
#                   refused (both sides say so), then a right one is served
#   server-missing  nothing listens (TCP port, Unix path): the app exits
#                   non-zero, refused (not timed out), naming the address
#   garbage-client  a client sending a malformed buffer while another one
#                   streams is dropped (node names it); the other client's
#                   frames are still exact
#   node-killed     kill -9 the node mid-stream: the app exits non-zero
#                   naming the server
#   client-chain-fails  the node cannot build one client's chain: that
#                   app exits non-zero with the server's reason
#   node-stopped    SIGSTOP the node mid-stream: the app (pack
#                   timeout_ms=1500) exits non-zero naming the node
#   client-stopped  SIGSTOP one of two clients of a shared node mid-stream:
#                   after --idle-timeout-ms it is dropped and named, the
#                   other is served to its end, and the node exits 1 (it
#                   must not poll the dead connection forever)
#   server-slow     two psubmit ranks (pack timeout_ms=1000) into a shared
#                   node whose chain takes 3 s over its first frame
#                   (--stall-first-frame-ms): meanwhile both fill their credit
#                   windows, rank 1 only waiting for rank 0's slow frame;
#                   neither may be taken for dead: both exit 0, every frame
#                   is drawn
#   client-busy     a client that computes for 3.5 s between frames (no GL
#                   call) beside a node whose --idle-timeout-ms is 1 s is
#                   not dropped: its I/O thread answers the heartbeats
set -u
mode=$1 bin=$2 out=$3 driver=${4:-}
TESSERA=$bin/tessera
. "$(dirname "$0")/node_lib.sh"
rm -rf "$out" && mkdir -p "$out/native" "$out/chain" || exit 1
status=0
fail() { echo "FAIL: $*" >&2; status=1; }
show() { echo "--- $1"; cat "$1"; }

case $mode in
bad-token)
  start_node "$out/node" --listen tcp://127.0.0.1:0 --token sesame --clients 1 \
    --timeout-ms 10000 --chain "render output=\"$out/chain/f-%04d.png\"" || exit 1
  timeout 20 "$bin/spheres" --frames 1 --chain "pack server=$NODE_ADDR token=wrong" 2>"$out/app-bad.err"
  rc=$?
  show "$out/app-bad.err"
  [ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "app with a wrong token exited $rc"
  grep -q "$NODE_ADDR" "$out/app-bad.err" || fail "app's message does not name $NODE_ADDR"
  grep -qi "token" "$out/app-bad.err" || fail "app's message does not say the token was wrong"
  timeout 20 "$bin/spheres" --frames 1 --chain "pack server=$NODE_ADDR token=sesame"
  rc=$?
  [ $rc -eq 0 ] || fail "app with the right token exited $rc"
  wait_exit "$NODE_PID" 15
  show "$out/node.err"
  [ "$EXIT_RC" = 0 ] || fail "node exited $EXIT_RC after serving the right client"
  grep -q "refused" "$out/node.err" || fail "node did not report the refusal"
  [ -s "$out/chain/f-0000.png" ] || fail "the client with the right token drew no frame"
  ;;
server-missing)
  # Port 1 (tcpmux) is privileged and unused here: connecting is refused.
  for address in tcp://127.0.0.1:1 "unix:$out/nobody.sock"; do
    start=$(now_ms)
    timeout 30 "$bin/spheres" --frames 1 --chain "pack server=$address" 2>"$out/app.err"
    rc=$?
    took=$(( $(now_ms) - start ))
    show "$out/app.err"
    echo "$address: exit $rc after $took ms"
    [ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "app exited $rc with no server at $address"
    # Refused, not timed out: the cause, not the time, is the verdict.
    ! grep -qi "timed out" "$out/app.err" || fail "app timed out on $address instead of being refused"
    grep -q "$address" "$out/app.err" || fail "app's message does not name $address"
    [ "$(grep -c . "$out/app.err")" -le 2 ] || fail "more than a short message for $address"
  done
  ;;
garbage-client)
  [ -n "$driver" ] || { echo "failures.sh: garbage-client needs NODE_DRIVER" >&2; exit 2; }
  frames=12
  "$bin/spheres-native" --frames $frames --out "$out/native/f-%04d.png" || exit 1
  # Info logging makes the node print "client N ... connected", so the good
  # client is known to be client 0 and mid-stream when the garbage arrives.
  TESSERA_LOG=info start_node "$out/node" --listen tcp://127.0.0.1:0 --clients 2 --timeout-ms 10000 --independent \
    --chain "render output=\"$out/chain/c{client}-f-%04d.png\"" || exit 1
  "$bin/spheres" --frames $frames --chain "pack server=$NODE_ADDR" 2>"$out/app.err" &
  app=$!
  i=0
  while ! grep -q "client 0 .* connected" "$out/node.err" && [ $i -lt 200 ]; do sleep 0.05; i=$((i + 1)); done
  timeout 20 "$driver" garbage "$NODE_ADDR" >"$out/garbage.out" 2>&1
  rc=$?
  show "$out/garbage.out"
  [ $rc -eq 0 ] || fail "the garbage client got no error message back (exit $rc)"
  wait_exit "$app" 60
  [ "$EXIT_RC" = 0 ] || { fail "the good client exited $EXIT_RC while a garbage client was dropped"; show "$out/app.err"; }
  wait_exit "$NODE_PID" 15
  show "$out/node.err"
  [ "$EXIT_RC" = 1 ] || fail "node exited $EXIT_RC; expected 1 (a client was dropped)"
  grep -q "client 1 'garbage-client' at .* dropped" "$out/node.err" \
    || fail "node's message does not name the garbage client"
  f=0
  while [ $f -lt $frames ]; do
    n=$(printf '%04d' $f)
    [ -e "$out/chain/c0-f-$n.png" ] && mv "$out/chain/c0-f-$n.png" "$out/chain/f-$n.png"
    f=$((f + 1))
  done
  compare_frames "$bin" "$out/native" "$out/chain" $frames "spheres beside a garbage client" || status=1
  ;;
node-killed)
  start_node "$out/node" --listen tcp://127.0.0.1:0 --clients 1 --timeout-ms 10000 \
    --chain "render output=\"$out/chain/f-%04d.png\"" || exit 1
  "$bin/spheres" --frames 100000 --size 320x240 --chain "pack server=$NODE_ADDR" \
    2>"$out/app.err" &
  app=$!
  kill_mid_stream "$out/chain/f-0002.png" "$NODE_PID" "$app" "the node" "$NODE_ADDR" "$out/app.err"
  wait "$NODE_PID" 2>/dev/null
  ;;
client-chain-fails)
  # Client 1's output directory does not exist, so only its chain fails
  # (the node's start-up check builds client 0's). The app must not exit 0
  # as if its frames were drawn.
  mkdir -p "$out/c0"
  start_node "$out/node" --listen tcp://127.0.0.1:0 --clients 2 --timeout-ms 10000 --independent \
    --chain "render output=\"$out/c{client}/f-%04d.png\"" || exit 1
  timeout 30 "$bin/spheres" --frames 2 --chain "pack server=$NODE_ADDR" || fail "client 0 exited $?"
  timeout 30 "$bin/spheres" --frames 2 --chain "pack server=$NODE_ADDR" 2>"$out/app.err"
  rc=$?
  wait_exit "$NODE_PID" 15
  show "$out/app.err"
  show "$out/node.err"
  echo "client 1 exit $rc, node exit $EXIT_RC"
  [ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "client 1 exited $rc although the server could not draw its stream"
  grep -q "$NODE_ADDR.*dropped this client: .*c1" "$out/app.err" \
    || fail "client 1's message does not give the server's reason"
  [ "$EXIT_RC" = 1 ] || fail "node exited $EXIT_RC; expected 1 (a client was dropped)"
  [ -s "$out/c0/f-0001.png" ] || fail "client 0's frames are missing"
  ;;
node-stopped)
  # SIGSTOP freezes the node, I/O thread included: it answers nothing, so
  # only the pack SPU's silence limit (timeout_ms) can end the wait.
  start_node "$out/node" --listen tcp://127.0.0.1:0 --clients 1 --timeout-ms 10000 \
    --chain "render output=\"$out/chain/f-%04d.png\"" || exit 1
  "$bin/spheres" --frames 100000 --size 320x240 \
    --chain "pack server=$NODE_ADDR timeout_ms=1500" 2>"$out/app.err" &
  app=$!
  i=0
  while [ ! -e "$out/chain/f-0002.png" ] && [ $i -lt 400 ]; do sleep 0.05; i=$((i + 1)); done
  [ -e "$out/chain/f-0002.png" ] || fail "the node wrote no frames within 20 s"
  kill -STOP "$NODE_PID"
  start=$(now_ms)
  wait_exit "$app" 10
  took=$(( $(now_ms) - start ))
  kill -9 "$NODE_PID"
  wait "$NODE_PID" 2>/dev/null
  show "$out/app.err"
  echo "app exit $EXIT_RC, $took ms after the node was stopped"
  [ "$EXIT_RC" != timeout ] || fail "app still running 10 s after the node was stopped"
  [ "$EXIT_RC" != 0 ] || fail "app exited 0 although the node stopped mid-stream"
  grep -q "$NODE_ADDR" "$out/app.err" || fail "app's message does not name $NODE_ADDR"
  ;;
client-stopped)
  idle=1500
  start_node "$out/node" --listen tcp://127.0.0.1:0 --clients 2 --timeout-ms 30000 \
    --idle-timeout-ms $idle --chain "render output=\"$out/chain/f-%04d.png\"" || exit 1
  "$bin/spheres" --frames 100000 --size 160x120 --chain "pack server=$NODE_ADDR" \
    2>"$out/stopped.err" &
  victim=$!
  i=0
  while [ ! -e "$out/chain/f-0002.png" ] && [ $i -lt 400 ]; do sleep 0.05; i=$((i + 1)); done
  [ -e "$out/chain/f-0002.png" ] || fail "the node wrote no frames within 20 s"
  kill -STOP "$victim"
  start=$(now_ms)
  timeout 30 "$bin/spheres" --frames 5 --size 160x120 --chain "pack server=$NODE_ADDR" \
    2>"$out/other.err"
  rc=$?
  [ $rc -eq 0 ] || { fail "the other client exited $rc while one was stopped"; show "$out/other.err"; }
  wait_exit "$NODE_PID" $(( idle / 1000 + 15 ))
  took=$(( $(now_ms) - start ))
  kill -9 "$victim"
  wait "$victim" 2>/dev/null
  show "$out/node.err"
  echo "node exit $EXIT_RC, $took ms after client 0 was stopped (--idle-timeout-ms $idle)"
  [ "$EXIT_RC" != timeout ] || fail "node still running $(( idle / 1000 + 15 )) s after a client was stopped"
  [ "$EXIT_RC" = 1 ] || fail "node exited $EXIT_RC; expected 1 (a client was dropped)"
  grep -q "client 0 'pack[^']*-pid$victim' at .* dropped: .*sent nothing for $idle ms" "$out/node.err" \
    || fail "node's message does not name the stopped client (pack-pid$victim) and its silence"
  ;;
server-slow)
  frames=8
  start_node "$out/node" --listen tcp://127.0.0.1:0 --clients 2 --stall-first-frame-ms 3000 \
    --timeout-ms 20000 --chain "render output=\"$out/chain/f-%04d.png\"" || exit 1
  start=$(now_ms)
  pids=""
  for r in 0 1; do
    "$bin/psubmit" --rank $r --ranks 2 --frames $frames --size 160x120 \
      --chain "pack server=$NODE_ADDR timeout_ms=1000 buffer_size=16384" 2>"$out/rank$r.err" &
    pids="$pids $!"
  done
  r=0
  for pid in $pids; do
    wait_exit "$pid" 30
    show "$out/rank$r.err"
    [ "$EXIT_RC" = 0 ] || fail "rank $r exited $EXIT_RC: a live server busy for 3 s was taken for dead"
    r=$((r + 1))
  done
  took=$(( $(now_ms) - start ))
  wait_exit "$NODE_PID" 15
  show "$out/node.err"
  echo "node exit $EXIT_RC; $took ms for both ranks"
  [ "$EXIT_RC" = 0 ] || fail "node exited $EXIT_RC"
  [ $took -ge 3000 ] || fail "both ranks ended within $took ms: the chain did not stall (test setting ignored?)"
  last=$(printf '%04d' $((frames - 1)))
  [ -s "$out/chain/f-$last.png" ] || fail "frame $last is missing"
  ;;
client-busy)
  [ -n "$driver" ] || { echo "failures.sh: client-busy needs NODE_DRIVER" >&2; exit 2; }
  start_node "$out/node" --listen tcp://127.0.0.1:0 --clients 1 --timeout-ms 20000 \
    --idle-timeout-ms 1000 --chain "render output=\"$out/chain/f-%04d.png\"" || exit 1
  timeout 30 "$driver" busy "$NODE_ADDR" 3500 >"$out/busy.out" 2>"$out/busy.err"
  rc=$?
  show "$out/busy.out"
  show "$out/busy.err"
  [ $rc -eq 0 ] || fail "the busy client exited $rc (taken for dead while computing)"
  wait_exit "$NODE_PID" 15
  show "$out/node.err"
  [ "$EXIT_RC" = 0 ] || fail "node exited $EXIT_RC; a busy client is not a dead one"
  [ -s "$out/chain/f-0001.png" ] || fail "the frame after the busy time is missing"
  ;;
*) echo "failures.sh: unknown mode '$mode'" >&2; exit 2 ;;
esac
[ $status -eq 0 ] && echo "PASS: $mode"
exit $status
