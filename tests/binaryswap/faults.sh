#!/bin/sh
# tests/binaryswap/faults.sh — a sort-last group whose peer fails mid-run:
# three in-situ peers (spheres --part K/3, chain binaryswap with explicit
# exchange addresses) and a `tessera node` display, started here (real
# processes, real sockets). Once the display wrote frames, peer rank 1 is
# killed (kill -9) or stopped (SIGSTOP: it never sends again). Asserts:
# rank 0 exits non-zero with one line naming rank 1 and its address, rank
# 2 and the display exit non-zero too (the display drops a stopped peer's
# stream after its --idle-timeout-ms), and no process of the group is
# left. The times are printed; each wait's 30 s is only a hang guard.
# sizes: rank 1 draws a 64x40 window, the others 64x48: rank 0 names it
# ("window sizes differ") at the first frame, and the same assertions hold.
# absent: rank 2 never starts: ranks 0 and 1 wait link_timeout_ms (2 s)
# for it at the first frame, then rank 0 names it.
# usage: faults.sh kill|stop|sizes|absent BIN_DIR OUT_DIR
set -u
case_name=$1 bin=$2 out=$3
TESSERA=$bin/tessera
. "$(dirname "$0")/../node/node_lib.sh"
bad=0
fail() { echo "FAIL: $*" >&2; bad=1; }
rm -rf "$out" && mkdir -p "$out/d" || exit 1
timeout_ms=1500 link_ms=20000
# A failure while the mesh forms (the first frame) reaches the peers still
# waiting for it only after link_timeout_ms (a graph run's mothership ends
# them at once): absent and sizes keep it short.
[ "$1" = absent ] || [ "$1" = sizes ] && link_ms=2000
start_node "$out/display" --listen "unix:$out/display.sock" --clients 3 --timeout-ms 5000 --idle-timeout-ms 2000 \
  --chain "render output=\"$out/d/f-%04d.png\"" || exit 1
display=$NODE_PID
x="unix:$out/x0,unix:$out/x1,unix:$out/x2"
pids=
for k in 0 1 2; do
  size=64x48
  [ "$case_name" = sizes ] && [ $k = 1 ] && size=64x40
  "$bin/spheres" --overlap --frames 100000 --size $size --part $k/3 \
    --chain "binaryswap display=\"$NODE_ADDR\" rank=$k exchange=\"$x\" timeout_ms=$timeout_ms link_timeout_ms=$link_ms" \
    2>"$out/peer$k.err" &
  pids="$pids $!"
  [ "$case_name" = absent ] && [ $k = 1 ] && break
done
set -- $pids
p0=$1 p1=$2 p2=${3:-}
if [ "$case_name" = absent ]; then
  # rank 1 stands in for rank 2 below: it, too, must end non-zero.
  p2=$p1
  echo > "$out/peer2.err"
fi
i=0
while [ "$case_name" != sizes ] && [ "$case_name" != absent ] && [ ! -e "$out/d/f-0003.png" ] && [ $i -lt 600 ]; do sleep 0.05; i=$((i + 1)); done
[ "$case_name" = sizes ] || [ "$case_name" = absent ] || [ -e "$out/d/f-0003.png" ] || fail "the display wrote no 4 frames in 30 s"
case $case_name in
  sizes | absent) sig=CONT ;;
  kill) sig=KILL ;;
  stop) sig=STOP ;;
  *) echo "faults.sh: unknown case '$case_name'" >&2; kill -9 $p0 $p1 $p2 $display; exit 2 ;;
esac
t0=$(now_ms)
kill -$sig $p1
wait_exit $p0 30
rc0=$EXIT_RC
took=$(( $(now_ms) - t0 ))
wait_exit $p2 30
rc2=$EXIT_RC
wait_exit $display 30
rcd=$EXIT_RC
took_all=$(( $(now_ms) - t0 ))
echo "rank 0 exit $rc0 after $took ms, rank 2 exit $rc2, display exit $rcd; all ended after $took_all ms"
echo "--- rank 0:"; cat "$out/peer0.err"
echo "--- rank 2:"; cat "$out/peer2.err"
echo "--- display:"; cat "$out/display.err"
[ "$rc0" != timeout ] && [ "$rc0" != 0 ] || fail "rank 0 exited $rc0"
[ "$rc2" != timeout ] && [ "$rc2" != 0 ] || fail "rank 2 exited $rc2"
[ "$rcd" != timeout ] && [ "$rcd" != 0 ] || fail "the display exited $rcd"
# The times are printed, not judged (the waits' 30 s are hang guards): the
# display drops a stopped peer after its --idle-timeout-ms (2 s) and stops
# waiting for a peer that never connected after --timeout-ms (5 s); the
# messages below say which cause ended each.
[ "$case_name" != sizes ] || grep -q "binaryswap#1: frame 0: peer rank 1 (unix:$out/x1) draws a 64x40 window, not 64x48 (window sizes differ)" "$out/peer0.err" ||
  fail "rank 0 does not say that rank 1's window size differs"
[ "$case_name" != absent ] || grep -q "binaryswap#1: peer rank 2 (unix:$out/x2) did not connect within $link_ms ms" "$out/peer0.err" ||
  fail "rank 0 does not name the absent rank 2"
[ "$case_name" = absent ] || grep -Eq "binaryswap#1: frame [0-9]+: peer rank 1 \\(unix:$out/x1\\)" "$out/peer0.err" ||
  fail "rank 0's message does not name rank 1 and its address"
[ "$(grep -c 'binaryswap#1: .*peer rank' "$out/peer0.err")" = 1 ] || fail "rank 0 said more than one line about it"
# The stopped (or killed) peer is ours to end; then nothing may be left.
kill -9 $p1 2>/dev/null
wait $p1 2>/dev/null
for p in $p0 $p1 $p2 $display; do
  alive $p && fail "process $p is left"
done
[ $bad = 0 ] && echo PASS
exit $bad
