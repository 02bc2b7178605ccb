#!/bin/sh
# tests/replicate/late.sh — replicate's late joiners (client/join.h) with real
# `tessera node` servers, real example programs and real PNGs.
# usage: late.sh MODE BIN_DIR OUT_DIR [EXAMPLE]
#   join EXAMPLE  server A (TCP) gets the stream from the start; the app
#                 lists server B (Unix socket) as late. Once A wrote frame
#                 3 the app is stopped (SIGSTOP), B is started, and the app
#                 goes on (SIGCONT): B joins at a frame boundary N, which
#                 the app names in its "joined at frame N" line. Every
#                 frame of A is bit-identical to the native reference, B
#                 writes exactly the frames N.. and each one is
#                 bit-identical to the native frame of the same number;
#                 app, A and B exit 0; the statistics list B.
#   never         the late server never comes: the app still draws every
#                 frame on A, exits 0, and says so in one line naming the
#                 late address.
set -u
mode=$1 bin=$2 out=$3 arg=${4:-}
TESSERA=$bin/tessera
. "$(dirname "$0")/../node/node_lib.sh"
rm -rf "$out" && mkdir -p "$out/native" "$out/a" "$out/b" "$out/b-as-app" "$out/native-from-n" || exit 1
bad=0 PIDS=
fail() { echo "FAIL: $*" >&2; bad=1; }
show() { echo "--- $1"; cat "$1"; }
kill_all() { for p in $PIDS; do kill -9 "$p" 2>/dev/null; wait "$p" 2>/dev/null; done; }

start_a() {
  start_node "$out/nodeA" --listen tcp://127.0.0.1:0 --clients 1 --timeout-ms 30000 \
    --chain "render output=\"$out/a/f-%04d.png\"" || exit 1
  PIDS=$NODE_PID A_PID=$NODE_PID A_ADDR=$NODE_ADDR
}

case $mode in
join)
  # isosurface computes its surfaces in the app: fewer frames keep the
  # sanitizer build within the time limit (B still joins mid-stream).
  example=$arg frames=40
  [ "$example" = isosurface ] && frames=16
  [ "$example" = shaders ] && frames=24
  size=320x240
  "$bin/$example-native" --frames $frames --size $size --out "$out/native/f-%04d.png" \
    || { echo "FAIL: $example-native exited $?" >&2; exit 1; }
  start_a
  late="unix:$out/b.sock"
  # Info logging: the app's "joined at frame N" line. No `timeout` in front:
  # SIGSTOP must reach the app itself (wait_exit bounds it).
  TESSERA_LOG=info TESSERA_STATS_FILE=$out/stats.json "$bin/$example" --frames $frames --size $size \
    --chain "replicate servers=\"$A_ADDR\" late=\"$late\" late_retry_ms=20" 2>"$out/app.err" &
  app=$!
  PIDS="$PIDS $app"
  n=0
  while [ ! -e "$out/a/f-0003.png" ] && [ $n -lt 400 ]; do sleep 0.05; n=$((n + 1)); done
  [ -e "$out/a/f-0003.png" ] || { fail "server A wrote no frame 3 within 20 s"; show "$out/app.err"; kill_all; exit 1; }
  kill -STOP "$app"
  start_node "$out/nodeB" --listen "$late" --clients 1 --timeout-ms 30000 \
    --chain "render output=\"$out/b/f-%04d.png\"" || { kill -CONT "$app"; kill_all; exit 1; }
  PIDS="$PIDS $NODE_PID" B_PID=$NODE_PID
  kill -CONT "$app"
  wait_exit "$app" 90
  show "$out/app.err"
  [ "$EXIT_RC" = 0 ] || fail "$example through replicate (late B) exited $EXIT_RC"
  wait_exit "$A_PID" 15
  [ "$EXIT_RC" = 0 ] || { fail "server A exited $EXIT_RC"; show "$out/nodeA.err"; }
  wait_exit "$B_PID" 15
  [ "$EXIT_RC" = 0 ] || { fail "server B exited $EXIT_RC"; show "$out/nodeB.err"; }
  compare_frames "$bin" "$out/native" "$out/a" $frames "$example [replicate, server A from the start]" || bad=1
  joined=$(sed -n "s/.*server $(echo "$late" | sed 's/[\/.]/\\&/g') joined at frame \([0-9]*\).*/\1/p" "$out/app.err")
  if [ -z "$joined" ]; then
    fail "the app did not say B joined"
  else
    echo "B joined at frame $joined of $frames"
    [ "$joined" -ge 3 ] && [ "$joined" -lt "$frames" ] || fail "B joined at frame $joined, not within 3..$((frames - 1))"
    count=$(ls "$out/b" | grep -c '^f-.*\.png$')
    [ "$count" -eq $((frames - joined)) ] || fail "B wrote $count frames, not $((frames - joined)) (frames $joined..$((frames - 1)))"
    # B's frame k is the app's frame joined + k: compare under the app's numbers.
    k=0
    while [ $k -lt "$count" ]; do
      cp "$out/b/$(printf 'f-%04d.png' $k)" "$out/b-as-app/$(printf 'f-%04d.png' $k)"
      cp "$out/native/$(printf 'f-%04d.png' $((joined + k)))" "$out/native-from-n/$(printf 'f-%04d.png' $k)"
      k=$((k + 1))
    done
    compare_frames "$bin" "$out/native-from-n" "$out/b-as-app" "$count" \
      "$example [replicate, server B joined at frame $joined; native frame = $joined + k]" || bad=1
  fi
  show "$out/stats.json"
  grep -q "\"address\":\"$late\",[^}]*\"failed\":false" "$out/stats.json" || fail "the statistics do not list B"
  ;;
never)
  frames=30 size=160x120
  "$bin/spheres-native" --frames $frames --size $size --out "$out/native/f-%04d.png" || exit 1
  start_a
  late="unix:$out/nobody.sock"
  start=$(now_ms)
  timeout 60 "$bin/spheres" --frames $frames --size $size \
    --chain "replicate servers=\"$A_ADDR\" late=\"$late\" late_retry_ms=20" 2>"$out/app.err"
  rc=$?
  took=$(( $(now_ms) - start ))
  show "$out/app.err"
  echo "app exit $rc after $took ms"
  [ $rc -eq 0 ] || fail "app exited $rc although only a late server was missing"
  [ "$(grep -c . "$out/app.err")" -eq 1 ] || fail "the app printed $(grep -c . "$out/app.err") lines, not one"
  grep -q "late server $late never joined" "$out/app.err" || fail "the app's line does not name $late"
  wait_exit "$A_PID" 15
  [ "$EXIT_RC" = 0 ] || { fail "server A exited $EXIT_RC"; show "$out/nodeA.err"; }
  compare_frames "$bin" "$out/native" "$out/a" $frames "spheres [replicate, late server never came, server A]" || bad=1
  ;;
*) echo "late.sh: unknown mode '$mode'" >&2; exit 2 ;;
esac
kill_all
[ $bad -eq 0 ] && echo "PASS: replicate late $mode $arg"
exit $bad
