#!/bin/sh
# tests/node/budget.sh — one hostile client of a shared node goes over its
# budget (issue 10, defects 5 and 6): budget_driver CASE connects first
# and must be refused with one line naming it, the budget and its value;
# the node's peak memory (VmHWM) must stay under 1 GiB, a memory bound,
# not a time; and a second client (spheres through pack) connecting after
# it to the same node must get frames bit-identical to OSMesa.
# (NODE ARGS may make the node --independent: the same holds there.)
# usage: budget.sh CASE BIN_DIR OUT_DIR DRIVER BUDGET_RE [NODE ARGS...]
set -u
case=$1 bin=$2 out=$3 driver=$4 budget_re=$5
shift 5
TESSERA=$bin/tessera
. "$(dirname "$0")/node_lib.sh"
frames=3
rm -rf "$out" && mkdir -p "$out/native" "$out/chain" || exit 1
"$bin/spheres-native" --frames $frames --out "$out/native/f-%04d.png" || exit 1
fail() { echo "FAIL: $*"; echo "--- node stderr:"; cat "$out/node.err"; exit 1; }

start_node "$out/node" --listen tcp://127.0.0.1:0 --clients 2 --timeout-ms 30000 \
  --chain "render output=\"$out/chain/f-%04d.png\"" "$@" || exit 1
"$driver" "$case" "$NODE_ADDR" >"$out/driver.out" 2>&1 &
drv=$!
wait_exit "$drv" 90
cat "$out/driver.out"
[ "$EXIT_RC" = 0 ] || fail "budget_driver $case got no error from the node (exit $EXIT_RC)"
grep -q "client 0 'budget-driver' at .*dropped: .*$budget_re" "$out/node.err" ||
  fail "the node's line does not name client 0 'budget-driver' and the budget /$budget_re/"
[ "$(grep -c "dropped:" "$out/node.err")" = 1 ] || fail "expected exactly one 'dropped:' line"
hwm=$(sed -n 's/^VmHWM:[[:space:]]*\([0-9]*\) kB/\1/p' "/proc/$NODE_PID/status")
echo "node VmHWM after '$case': ${hwm} kB"
[ -n "$hwm" ] && [ "$hwm" -lt 1048576 ] || fail "node peak memory ${hwm} kB is not under 1 GiB"

# The node still serves: a second client's frames are exact.
timeout 60 "$bin/spheres" --frames $frames --chain "pack server=$NODE_ADDR"
app=$?
wait_exit "$NODE_PID" 20
echo "spheres exit $app, node exit $EXIT_RC"
[ "$app" = 0 ] || fail "spheres (client 1) exit $app"
[ "$EXIT_RC" = 1 ] || fail "node exit $EXIT_RC (expected 1: a client was dropped)"
compare_frames "$bin" "$out/native" "$out/chain" $frames "spheres (client 1)" || fail "client 1's frames differ"
echo "PASS: $case refused, node under 1 GiB, the next client's frames exact"
