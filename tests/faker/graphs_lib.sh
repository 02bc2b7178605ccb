# tests/faker/graphs_lib.sh — sourced by the scripts that run one driver
# program natively and through tessera's three graphs (glx_buffers.sh,
# glx_multisample.sh, gl21_commands.sh), so that all run them alike.
# The caller sets prog (the driver built on the faker), native (the same
# source built on Mesa's own GLX or OSMesa), TESSERA and out.
# Defines status and fail (a failure is reported, the script goes on),
# run_native and run_graphs; each run writes $out/NAME.txt, which the
# caller compares with $out/native.txt.
. "$(dirname "${BASH_SOURCE[0]}")/../node/node_lib.sh"
status=0
fail() { echo "FAIL: $*" >&2; status=1; }
PIDS=
kill_all() { for p in $PIDS; do kill -9 "$p" 2>/dev/null; wait "$p" 2>/dev/null; done; PIDS=; }
runs=()

# The native run is Mesa's own: what it keeps at exit (Mesa's GLX unloads
# its DRI driver by then, so LeakSanitizer cannot name it) is not tessera's.
run_native() {
  ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0" timeout 60 "$native" "$out/native.txt" || fail "native: exit $?"
}

run_graph() { # NAME CHAIN
  echo "--- $1: chain \"$2\""
  runs+=("$1")
  TESSERA_CHAIN=$2 timeout 60 "$prog" "$out/$1.txt" 2>"$out/$1.err" || { fail "$1: exit $?"; cat "$out/$1.err" >&2; }
}

# run_graphs RENDER_OUTPUT PACK_OUTPUT: [render output=RENDER_OUTPUT],
# [pack -> a `tessera node` whose render writes PACK_OUTPUT], and a 2x2
# tilesort wall of four `tessera node` render servers (64x48 in 32x24
# tiles); each node must end with status 0.
run_graphs() {
  run_graph render "render output=$1"
  start_node "$out/node" --listen "unix:$out/node.sock" --clients 1 --timeout-ms 30000 --chain "render output=$2" ||
    fail "no node"
  PIDS=$NODE_PID
  run_graph pack "pack server=unix:$out/node.sock"
  wait_exit "$NODE_PID" 15
  [ "$EXIT_RC" = 0 ] || { fail "pack: the node exited $EXIT_RC"; cat "$out/node.err"; }
  PIDS=
  local servers="" tiles="" k=0 x y p
  for y in 0 24; do
    for x in 0 32; do
      start_node "$out/wall$k" --listen "unix:$out/wall$k.sock" --clients 1 --timeout-ms 30000 \
        --chain "render output=" || fail "no wall node $k"
      PIDS="$PIDS $NODE_PID"
      servers="$servers${servers:+,}unix:$out/wall$k.sock"
      tiles="$tiles${tiles:+,}$k:$x:$y:32:24"
      k=$((k + 1))
    done
  done
  run_graph wall "tilesort servers=$servers tiles=$tiles"
  for p in $PIDS; do
    wait_exit "$p" 15
    [ "$EXIT_RC" = 0 ] || fail "wall: a node exited $EXIT_RC"
  done
  kill_all
}
