#!/bin/sh
# tests/run/fake_node.sh — text from a hostile node reaches the terminal
# escaped (issue 10, defect 10): a real `tessera mothership` runs GRAPH,
# fake_node joins it as node NAME over a real socket and reports DONE
# status=1 with ESC[2J, BEL and a C1 CSI in its message (and an OSC in its
# host name). The mothership must exit 1 within its time-outs with one
# line naming the node and the message in its escaped form (\x1b[2J\x07),
# and nothing it prints may hold a raw control byte.
# usage: fake_node.sh BIN_DIR FAKE_NODE OUT_DIR GRAPH NAME
set -u
bin=$1 fake=$2 out=$3 graph=$4 name=$5
TESSERA=$bin/tessera
. "$(dirname "$0")/../node/node_lib.sh"
rm -rf "$out" && mkdir -p "$out" || exit 1
fail() { echo "FAIL: $*"; echo "--- mothership stderr:"; cat "$out/ms.err"; exit 1; }

"$TESSERA" mothership "$graph" --listen tcp://127.0.0.1:0 --join-timeout-ms 20000 \
  >"$out/ms.out" 2>"$out/ms.err" &
ms=$!
addr= i=0
while [ -z "$addr" ] && [ $i -lt 200 ] && alive $ms; do
  addr=$(sed -n 's/^mothership listening on //p' "$out/ms.out" | head -n 1)
  sleep 0.05; i=$((i + 1))
done
[ -n "$addr" ] || { kill -KILL $ms 2>/dev/null; fail "no 'mothership listening on' line"; }

"$fake" "$addr" "$name" >"$out/fake.out" 2>&1 &
fake_pid=$!
wait_exit $fake_pid 40; fake_rc=$EXIT_RC
wait_exit $ms 20; ms_rc=$EXIT_RC
cat "$out/fake.out"
echo "fake_node exit $fake_rc, mothership exit $ms_rc; its stderr:"
cat -v "$out/ms.err"
[ "$fake_rc" = 0 ] || fail "fake_node exit $fake_rc"
[ "$ms_rc" = 1 ] || fail "mothership exit $ms_rc, expected 1"
grep -F "node '$name': render failed\\x1b[2J\\x07\\xc2\\x9b31mgotcha" "$out/ms.err" >/dev/null ||
  fail "no line naming node '$name' with the message escaped"
# Any C0 control but newline, DEL, or a C1 control (UTF-8 C2 80..C2 9F).
if LC_ALL=C grep -n "$(printf '[\001-\011\013-\037\177]')" "$out/ms.err" "$out/ms.out" ||
   LC_ALL=C grep -n "$(printf '\302[\200-\237]')" "$out/ms.err" "$out/ms.out"; then
  fail "the mothership printed a raw control byte (lines above)"
fi
echo "PASS: the node's DONE message printed escaped, no raw control byte"
