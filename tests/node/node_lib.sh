# tests/node/node_lib.sh — shell helpers the node tests source: start a
# `tessera node` in the background and wait (bounded) for its
# "listening on ADDR" line, wait (bounded) for a log line or for a process
# to end, and time commands. Owns nothing but the processes it starts; never waits unbounded.

# now_ms: milliseconds since the epoch.
now_ms() { echo $(( $(date +%s%N) / 1000000 )); }

# alive PID: the process exists and is not a zombie (an ended child stays
# a zombie until waited for, and kill -0 still finds it).
alive() {
  [ -r "/proc/$1/stat" ] || return 1
  state=$(sed 's/.*) //' "/proc/$1/stat" 2>/dev/null | cut -c1)
  [ -n "$state" ] && [ "$state" != Z ]
}

# start_node OUT_PREFIX ARGS...: runs `$TESSERA node ARGS` with stdout in
# OUT_PREFIX.out and stderr in OUT_PREFIX.err; sets NODE_PID and NODE_ADDR.
# Fails (returns 1) when the node does not print its address within 10 s.
start_node() {
  prefix=$1; shift
  # The background job opens its files after the fork: an old .out would
  # still show the previous node's address for a moment.
  rm -f "$prefix.out" "$prefix.err"
  "$TESSERA" node "$@" >"$prefix.out" 2>"$prefix.err" &
  NODE_PID=$!
  NODE_ADDR=
  i=0
  while [ $i -lt 200 ]; do
    NODE_ADDR=$(sed -n 's/^listening on //p' "$prefix.out" 2>/dev/null | head -n 1)
    [ -n "$NODE_ADDR" ] && return 0
    alive "$NODE_PID" || break
    sleep 0.05
    i=$((i + 1))
  done
  echo "FAIL: tessera node $* printed no 'listening on' line; its stderr:" >&2
  cat "$prefix.err" >&2
  kill -9 "$NODE_PID" 2>/dev/null
  return 1
}

# wait_line FILE REGEX SECONDS: waits until a line of FILE matches REGEX
# (grep -E); returns 1 when none does within SECONDS.
wait_line() {
  local file=$1 regex=$2 limit=$(($3 * 20)) i=0
  until grep -Eq "$regex" "$file" 2>/dev/null; do
    [ $i -lt $limit ] || return 1
    sleep 0.05
    i=$((i + 1))
  done
}

# wait_exit PID SECONDS: waits for PID (a child of this shell) to end and
# sets EXIT_RC to its exit status; after SECONDS it kills it and sets
# EXIT_RC=timeout. (Not for $(...): a subshell cannot wait for our child.)
wait_exit() {
  pid=$1 limit=$(( $2 * 20 )) i=0
  while alive "$pid" && [ $i -lt "$limit" ]; do
    sleep 0.05
    i=$((i + 1))
  done
  if alive "$pid"; then
    kill -9 "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    EXIT_RC=timeout
    return
  fi
  wait "$pid"
  EXIT_RC=$?
}

# kill_mid_stream FRAME_FILE VICTIM_PID APP_PID WHO ADDR ERR_FILE: once
# FRAME_FILE exists (mid-stream), kill -9 VICTIM_PID and expect the app
# to exit non-zero (10 s: a hang guard; the time is printed, not judged),
# naming ADDR in ERR_FILE. Calls fail().
kill_mid_stream() {
  local frame=$1 victim=$2 app=$3 who=$4 addr=$5 err=$6 waited=0 start took
  while [ ! -e "$frame" ] && [ $waited -lt 400 ]; do sleep 0.05; waited=$((waited + 1)); done
  [ -e "$frame" ] || fail "$who wrote no frames within 20 s"
  kill -9 "$victim"
  start=$(now_ms)
  wait_exit "$app" 10
  took=$(( $(now_ms) - start ))
  show "$err"
  echo "app exit $EXIT_RC, $took ms after $who was killed"
  [ "$EXIT_RC" != timeout ] || fail "app still running 10 s after $who was killed"
  [ "$EXIT_RC" != 0 ] && [ "$EXIT_RC" != 124 ] || fail "app exited $EXIT_RC after $who was killed"
  grep -q "$addr" "$err" || fail "app's message does not name $who ($addr)"
}

# compare_frames BIN NATIVE_DIR CHAIN_DIR FRAMES LABEL: 0 differing pixels
# in every frame, else returns 1.
compare_frames() {
  cbin=$1 native=$2 chain=$3 frames=$4 label=$5
  status=0 f=0
  while [ "$f" -lt "$frames" ]; do
    name=$(printf 'f-%04d.png' "$f")
    result=$("$cbin/tessera" imgdiff "$native/$name" "$chain/$name" 2>&1)
    rc=$?
    echo "$label frame $f: $(echo "$result" | tr '\n' ' ')"
    [ "$rc" -eq 0 ] || status=1
    f=$((f + 1))
  done
  return $status
}
