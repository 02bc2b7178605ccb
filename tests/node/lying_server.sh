#!/bin/sh
# tests/node/lying_server.sh — the real pack SPU and stream client against
# tests/node/lying_server (a real socket, a real handshake, lying replies).
#   bad-reply MODE POLICY: node_driver asks glGenLists, glGetIntegerv, ...
#     through "pack on_error=POLICY"; a malformed reply (MODE wrong-size or
#     truncated) is a failure of that server: under exit the application
#     exits non-zero, under drop the server is dropped; both name it.
#   error-text: the server's ERROR text holds ESC[2J and BEL; the line the
#     application prints shows them escaped (\x1b, \x07), never raw.
# usage: lying_server.sh CASE BIN_DIR OUT_DIR LIAR NODE_DRIVER [MODE POLICY]
set -u
case=$1 bin=$2 out=$3 liar=$4 driver=$5
mode=${6:-error-text} policy=${7:-exit}
rm -rf "$out" && mkdir -p "$out" || exit 1
fail() { echo "FAIL: $*"; echo "--- app stderr"; cat "$out/app.err"; echo "--- liar"; cat "$out/liar.out" "$out/liar.err"; exit 1; }
"$liar" "$mode" "unix:$out/liar.sock" >"$out/liar.out" 2>"$out/liar.err" &
liar_pid=$!
i=0
while ! grep -q "^listening on" "$out/liar.out" 2>/dev/null && [ $i -lt 200 ]; do sleep 0.05; i=$((i + 1)); done
addr=$(sed -n 's/^listening on //p' "$out/liar.out")
[ -n "$addr" ] || fail "the lying server did not listen"
if [ "$case" = bad-reply ]; then
  timeout 30 "$driver" replies-chain "pack server=$addr on_error=$policy" >"$out/app.out" 2>"$out/app.err"
  rc=$?
  echo "node_driver through pack on_error=$policy against a $mode liar: exit $rc"
  cat "$out/app.err"
  [ $rc != 0 ] && [ $rc != 124 ] || fail "the application exited $rc after a malformed reply"
  grep -q "server $addr: bad reply: reply to gl[A-Za-z]* (request [0-9]*) is malformed" "$out/app.err" ||
    fail "no line names the server and its malformed reply"
  if [ "$policy" = exit ]; then
    grep -q "ending the application (on_error=exit)" "$out/app.err" || fail "on_error=exit did not end the application"
  else
    grep -Eq "(going on without server $addr|no server left).*\(on_error=drop\)" "$out/app.err" ||
      fail "on_error=drop did not drop the server"
  fi
else
  timeout 30 "$bin/spheres" --frames 2 --chain "pack server=$addr" >"$out/app.out" 2>"$out/app.err"
  rc=$?
  echo "spheres against a server whose ERROR holds ESC[2J and BEL: exit $rc"
  cat -v "$out/app.err"
  [ $rc != 0 ] || fail "the application exited 0 after the server dropped it"
  grep -qF 'the server dropped this client: \x1b[2J\x07you have been pwned' "$out/app.err" ||
    fail "the server's text is not shown escaped"
  if LC_ALL=C grep -q "$(printf '[\033\007]')" "$out/app.err"; then fail "a raw ESC or BEL reached stderr"; fi
fi
kill "$liar_pid" 2>/dev/null
wait "$liar_pid" 2>/dev/null
echo "PASS"
