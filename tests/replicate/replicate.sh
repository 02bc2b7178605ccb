#!/bin/sh
# tests/replicate/replicate.sh — the replicate SPU with real `tessera node`
# servers (two over TCP, one over a Unix socket) and real example programs,
# and the statistics file the stream clients (pack, replicate) write.
# usage: replicate.sh MODE BIN_DIR OUT_DIR [ARG]
#   accuracy EXAMPLE  every frame each of the three servers writes is
#                     bit-identical to the example drawn by OSMesa directly;
#                     app and servers exit 0; TESSERA_STATS_FILE holds the
#                     app's statistics (frames, buffers, bytes = 3 x stream)
#   refused           the second server requires another token: the app
#                     exits non-zero within 5 s naming that server and the
#                     token; the server reports the refusal
#   absent            the third server's Unix socket does not exist: the app
#                     exits non-zero within 5 s naming that address
#   killed            kill -9 the second server mid-stream: the app exits
#                     non-zero within 5 s naming that server (and writes
#                     the failure into its statistics file)
#   stopped-drop      with on_error=drop and timeout_ms=3000, SIGSTOP the
#                     second server mid-stream: the app says it goes on
#                     without that server, finishes and exits 0, the other
#                     two servers' frames are bit-identical to the
#                     reference, and the statistics mark only it failed
#   replies NODE_DRIVER  gets, GenLists, GetString, ReadPixels through
#                     replicate equal a local render chain's; all three
#                     servers stay in step and exit 0
#   pack-blocked      pack to one server that is stopped (SIGSTOP)
#                     mid-stream until the app is seen blocked on it: the
#                     statistics file shows the frames, buffers and bytes
#                     sent and time blocked on send credits
set -u
mode=$1 bin=$2 out=$3 arg=${4:-}
TESSERA=$bin/tessera
. "$(dirname "$0")/../node/node_lib.sh"
rm -rf "$out" && mkdir -p "$out/native" "$out/s0" "$out/s1" "$out/s2" || exit 1
bad=0
fail() { echo "FAIL: $*" >&2; bad=1; }
show() { echo "--- $1"; cat "$1"; }

# json_field FILE NAME: the number after top-level "NAME": in the one-line
# JSON FILE (the "servers" array, which repeats names, is cut off first).
json_field() { sed -e 's/,"servers":.*//' -n -e "s/.*\"$2\":\([-0-9.e+]*\).*/\1/p" "$1" | head -n 1; }

# (node_lib.sh's functions use the globals i, f, pid, status, frames: this
# script keeps its own in k, n, total and bad.)

# start_three [TOKEN0 TOKEN1 TOKEN2]: servers s0 (tcp), s1 (tcp), s2 (unix),
# each serving one client and requiring its token when given; sets PIDS,
# SERVERS (comma-separated) and ADDR0..ADDR2.
start_three() {
  PIDS= SERVERS=
  k=0
  for listen in tcp://127.0.0.1:0 tcp://127.0.0.1:0 "unix:$out/s2.sock"; do
    token=
    [ $# -ge 3 ] && eval "token=\${$((k + 1))}"
    start_node "$out/node$k" --listen "$listen" --clients 1 --timeout-ms 15000 ${token:+--token "$token"} \
      --chain "render output=\"$out/s$k/f-%04d.png\"" || { kill_all; exit 1; }
    PIDS="$PIDS $NODE_PID"
    SERVERS="$SERVERS${SERVERS:+,}$NODE_ADDR"
    eval "ADDR$k=\$NODE_ADDR"
    k=$((k + 1))
  done
  echo "servers: $SERVERS"
}

kill_all() { for p in $PIDS; do kill -9 "$p" 2>/dev/null; wait "$p" 2>/dev/null; done; }

# wait_servers: each server must exit 0 within 15 s.
wait_servers() {
  k=0
  for p in $PIDS; do
    wait_exit "$p" 15
    [ "$EXIT_RC" = 0 ] || { fail "server s$k exited $EXIT_RC"; show "$out/node$k.err"; }
    k=$((k + 1))
  done
}

# app_fails_naming ADDRESS WORD CMD...: CMD exits non-zero (not by the 30 s
# timeout, a hang guard) and its stderr names ADDRESS (and WORD when given);
# the time it took is printed, not judged.
app_fails_naming() {
  address=$1 word=$2; shift 2
  start=$(now_ms)
  timeout 30 "$@" 2>"$out/app.err"
  rc=$?
  took=$(( $(now_ms) - start ))
  show "$out/app.err"
  echo "app exit $rc after $took ms"
  [ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "app exited $rc"
  grep -q "$address" "$out/app.err" || fail "app's message does not name $address"
  [ -z "$word" ] || grep -qi "$word" "$out/app.err" || fail "app's message does not say '$word'"
}

case $mode in
accuracy)
  example=$arg frames=3
  "$bin/$example-native" --frames $frames --out "$out/native/f-%04d.png" \
    || { echo "FAIL: $example-native exited $?" >&2; exit 1; }
  start_three
  TESSERA_STATS_FILE=$out/stats.json timeout 60 "$bin/$example" --frames $frames \
    --chain "replicate servers=\"$SERVERS\""
  rc=$?
  [ $rc -eq 0 ] || fail "$example through replicate exited $rc"
  wait_servers
  for k in 0 1 2; do
    compare_frames "$bin" "$out/native" "$out/s$k" $frames "$example [replicate, server s$k]" || bad=1
  done
  show "$out/stats.json"
  frames_seen=$(json_field "$out/stats.json" frames)
  buffers=$(json_field "$out/stats.json" buffers)
  stream=$(json_field "$out/stats.json" stream_bytes)
  bytes=$(json_field "$out/stats.json" bytes_out)
  [ "$frames_seen" = "$frames" ] || fail "statistics count $frames_seen frames, not $frames"
  [ "${buffers:-0}" -ge "$frames" ] || fail "statistics count ${buffers:-?} buffers for $frames frames"
  [ "${stream:-0}" -gt 0 ] && [ "${bytes:-0}" -eq $((stream * 3)) ] \
    || fail "bytes_out ${bytes:-?} is not 3 x stream_bytes ${stream:-?}"
  grep -q '"spu":"replicate"' "$out/stats.json" || fail "statistics do not name the SPU"
  grep -q '"error":null' "$out/stats.json" || fail "statistics report an error"
  [ "$(grep -o '"failed":false' "$out/stats.json" | wc -l)" -eq 3 ] || fail "statistics do not list 3 servers"
  for a in $(echo "$SERVERS" | tr , ' '); do
    grep -q "\"address\":\"$a\"" "$out/stats.json" || fail "statistics do not list $a"
  done
  ;;
refused)
  # Info logging makes the servers log each refusal as it happens.
  export TESSERA_LOG=info
  start_three sesame other sesame
  app_fails_naming "$ADDR1" token "$bin/spheres" --frames 2 --chain "replicate servers=\"$SERVERS\" token=sesame"
  wait_exit "$(echo $PIDS | cut -d' ' -f2)" 1
  grep -q "refused" "$out/node1.err" || { fail "server s1 did not report the refusal"; show "$out/node1.err"; }
  kill_all
  ;;
absent)
  start_three
  PIDS="$(echo $PIDS | cut -d' ' -f1-2)"
  kill -9 "$(echo $PIDS | cut -d' ' -f2)" 2>/dev/null
  missing="unix:$out/nobody.sock"
  app_fails_naming "$missing" "" "$bin/spheres" --frames 2 \
    --chain "replicate servers=\"$ADDR0,$missing\""
  kill_all
  ;;
killed)
  start_three
  TESSERA_STATS_FILE=$out/stats.json "$bin/spheres" --frames 100000 --size 320x240 \
    --chain "replicate servers=\"$SERVERS\"" 2>"$out/app.err" &
  app=$!
  victim=$(echo $PIDS | cut -d' ' -f2)
  kill_mid_stream "$out/s1/f-0002.png" "$victim" "$app" "server s1" "server $ADDR1" "$out/app.err"
  if grep -q "server $ADDR0\|server $ADDR2" "$out/app.err"; then fail "app blames a server that is alive"; fi
  show "$out/stats.json"
  grep -q "\"error\":\".*$ADDR1" "$out/stats.json" || fail "the statistics file does not record the failure"
  kill_all
  ;;
stopped-drop)
  total=300
  "$bin/spheres-native" --frames $total --size 160x120 --out "$out/native/f-%04d.png" || exit 1
  start_three
  TESSERA_STATS_FILE=$out/stats.json "$bin/spheres" --frames $total --size 160x120 \
    --chain "replicate servers=\"$SERVERS\" on_error=drop timeout_ms=3000" 2>"$out/app.err" &
  app=$!
  n=0
  while [ ! -e "$out/s1/f-0003.png" ] && [ $n -lt 400 ]; do sleep 0.05; n=$((n + 1)); done
  victim=$(echo $PIDS | cut -d' ' -f2)
  kill -STOP "$victim"
  wait_exit "$app" 60
  show "$out/app.err"
  [ "$EXIT_RC" = 0 ] || fail "app exited $EXIT_RC (on_error=drop must go on without the stopped server)"
  grep -q "server $ADDR1: .*going on without\|going on without server $ADDR1" "$out/app.err" \
    || fail "app did not say it goes on without $ADDR1"
  last=$(printf 'f-%04d.png' $((total - 1)))
  [ ! -e "$out/s1/$last" ] || fail "server s1 drew the last frame: it was not stopped mid-stream"
  kill -9 "$victim" 2>/dev/null
  wait "$victim" 2>/dev/null
  PIDS="$(echo $PIDS | cut -d' ' -f1) $(echo $PIDS | cut -d' ' -f3)"
  k=0
  for p in $PIDS; do
    wait_exit "$p" 15
    [ "$EXIT_RC" = 0 ] || fail "a live server exited $EXIT_RC"
  done
  # Every 25th frame and the last, on both live servers.
  mkdir -p "$out/pick-native" "$out/pick-s0" "$out/pick-s2"
  n=0 picked=0
  while [ $n -lt $total ]; do
    if [ $((n % 25)) -eq 0 ] || [ $n -eq $((total - 1)) ]; then
      name=$(printf 'f-%04d.png' $n) pick=$(printf 'f-%04d.png' $picked)
      for d in native s0 s2; do cp "$out/$d/$name" "$out/pick-$d/$pick" 2>/dev/null || fail "$d has no $name"; done
      picked=$((picked + 1))
    fi
    n=$((n + 1))
  done
  for k in 0 2; do
    compare_frames "$bin" "$out/pick-native" "$out/pick-s$k" $picked "spheres [replicate, s1 dropped, server s$k]" || bad=1
  done
  show "$out/stats.json"
  [ "$(grep -o '"failed":true' "$out/stats.json" | wc -l)" -eq 1 ] || fail "statistics do not mark exactly one server failed"
  grep -q "\"address\":\"$ADDR1\",[^}]*\"failed\":true" "$out/stats.json" || fail "statistics do not mark $ADDR1 failed"
  [ "$(json_field "$out/stats.json" frames)" = $total ] || fail "statistics do not count $total frames"
  ;;
replies)
  [ -n "$arg" ] || { echo "replicate.sh: replies needs NODE_DRIVER" >&2; exit 2; }
  start_three
  timeout 30 "$arg" replies-chain "replicate servers=\"$SERVERS\"" || fail "answers through replicate differ (exit $?)"
  wait_servers
  ;;
pack-blocked)
  frames=400
  start_node "$out/node0" --listen tcp://127.0.0.1:0 --clients 1 --timeout-ms 15000 \
    --chain "render output=\"$out/s0/f-%04d.png\"" || exit 1
  PIDS=$NODE_PID
  # Small buffers and frames: the app runs far ahead of the stopped server.
  TESSERA_STATS_FILE=$out/stats.json "$bin/spheres" --frames $frames --size 160x120 \
    --chain "pack server=$NODE_ADDR buffer_size=65536" 2>"$out/app.err" &
  app=$!
  n=0
  while [ ! -e "$out/s0/f-0001.png" ] && [ $n -lt 400 ]; do sleep 0.05; n=$((n + 1)); done
  kill -STOP "$NODE_PID"
  # Resume the server once the app is blocked on it: asleep, and its bytes
  # written (/proc/PID/io wchar, every thread) unchanged over 5 polls in a
  # row. Bounded (20 s): an app that never blocks fails below.
  last="" still=0 n=0
  while [ $still -lt 5 ] && [ $n -lt 400 ] && alive "$app"; do
    now=$(sed -n 's/^wchar: //p' "/proc/$app/io" 2>/dev/null)
    state=$(sed 's/.*) //' "/proc/$app/stat" 2>/dev/null | cut -c1)
    if [ -n "$now" ] && [ "$now" = "$last" ] && [ "$state" = S ]; then still=$((still + 1)); else still=0; fi
    last=$now
    sleep 0.05; n=$((n + 1))
  done
  [ $still -ge 5 ] || fail "the app never blocked on the stopped server"
  kill -CONT "$NODE_PID"
  wait_exit "$app" 60
  [ "$EXIT_RC" = 0 ] || { fail "app exited $EXIT_RC"; show "$out/app.err"; }
  wait_servers
  show "$out/stats.json"
  blocked=$(json_field "$out/stats.json" blocked_seconds)
  [ "$(json_field "$out/stats.json" frames)" = $frames ] || fail "statistics do not count $frames frames"
  [ "$(json_field "$out/stats.json" bytes_out)" -gt 0 ] || fail "statistics count no bytes"
  grep -q '"spu":"pack"' "$out/stats.json" || fail "statistics do not name the SPU"
  awk -v b="${blocked:-0}" 'BEGIN { exit !(b > 0) }' \
    || fail "blocked_seconds ${blocked:-?} although the app was seen blocked on the stopped server"
  [ -s "$out/s0/f-$(printf %04d $((frames - 1))).png" ] || fail "the last frame was not drawn"
  ;;
*) echo "replicate.sh: unknown mode '$mode'" >&2; exit 2 ;;
esac
[ $bad -eq 0 ] && echo "PASS: replicate $mode $arg"
exit $bad
