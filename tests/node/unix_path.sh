#!/bin/sh
# tests/node/unix_path.sh — `tessera node --listen unix:PATH` replaces only a
# stale socket (a socket file nobody listens on) and refuses everything else
# at PATH with one line naming it, leaving it as it was: a regular file, a
# folder, a symbolic link, a live socket (whose node must go on serving). A
# socket in a missing folder says so (not "permission denied"); a folder
# does not say "address already in use" (issue 10, defects 1 and 11).
# usage: unix_path.sh BIN_DIR OUT_DIR
set -u
bin=$(cd "$1" && pwd) out=$2
TESSERA=$bin/tessera
. "$(dirname "$0")/node_lib.sh"
rm -rf "$out" && mkdir -p "$out" || exit 1
cd "$out" || exit 1
status=0
fail() { echo "FAIL: $*" >&2; status=1; }

# refused NAME PATH WANT_RE [NOT_RE]: the node must exit 2 at once with one
# line naming PATH that matches WANT_RE (and not NOT_RE).
refused() {
  name=$1 path=$2 want=$3 not=${4:-}
  timeout 10 "$TESSERA" node --listen "unix:$path" --chain render --timeout-ms 2000 \
    >"$name.out" 2>"$name.err"
  rc=$?
  echo "--- $name: exit $rc"; cat "$name.err"
  [ $rc -eq 2 ] || fail "$name: exit $rc, expected 2"
  [ "$(grep -c . "$name.err")" -eq 1 ] || fail "$name: not one line on stderr"
  grep -qF "$path" "$name.err" || fail "$name: the message does not name $path"
  grep -Eq "$want" "$name.err" || fail "$name: the message does not match /$want/"
  if [ -n "$not" ] && grep -Eqi "$not" "$name.err"; then fail "$name: the message says /$not/"; fi
  ! grep -q "^listening on" "$name.out" || fail "$name: the node listened on $path"
}

echo precious >f.txt
refused file f.txt "not a socket" "in use"
[ "$(cat f.txt 2>/dev/null)" = precious ] || fail "f.txt was removed or changed"

mkdir adir && echo inside >adir/keep
refused folder adir "is a folder" "already in use"
[ "$(cat adir/keep 2>/dev/null)" = inside ] || fail "the folder or its content was removed"

echo target >target.txt && ln -s target.txt link
refused symlink link "symbolic link"
[ -L link ] && [ "$(cat target.txt 2>/dev/null)" = target ] || fail "the link or its target was removed"

ln -s nowhere dangling
refused dangling dangling "symbolic link"
[ -L dangling ] || fail "the dangling link was removed"

refused missing-folder no-such-folder/x.sock "folder .*no-such-folder.* does not exist" "permission denied"

# A live socket: refused, and its node still serves a client afterwards.
start_node live --listen unix:live.sock --clients 1 --timeout-ms 20000 \
  --chain "render output=\"live-%04d.png\"" || exit 1
refused live-socket live.sock "in use"
[ -S live.sock ] || fail "the live socket was removed"
timeout 30 "$bin/spheres" --frames 1 --size 64x48 --chain "pack server=unix:live.sock" 2>live-app.err \
  || { fail "the live node could not serve a client after the refusal"; cat live-app.err; }
wait_exit "$NODE_PID" 15
[ "$EXIT_RC" = 0 ] || fail "the live node exited $EXIT_RC"
[ -s live-0000.png ] || fail "the live node drew no frame"
[ ! -e live.sock ] || fail "the node left its socket behind after a clean end"

# A stale socket (its node was killed): replaced, and the new node serves.
start_node stale1 --listen unix:stale.sock --clients 1 --timeout-ms 20000 --chain render || exit 1
kill -9 "$NODE_PID"; wait "$NODE_PID" 2>/dev/null
[ -S stale.sock ] || fail "a killed node left no socket file (the test needs one)"
start_node stale2 --listen unix:stale.sock --clients 1 --timeout-ms 20000 \
  --chain "render output=\"stale-%04d.png\"" || { fail "a stale socket was not replaced"; exit 1; }
timeout 30 "$bin/spheres" --frames 1 --size 64x48 --chain "pack server=unix:stale.sock" 2>stale-app.err \
  || { fail "the node on the replaced socket could not serve"; cat stale-app.err; }
wait_exit "$NODE_PID" 15
[ "$EXIT_RC" = 0 ] || fail "the node on the replaced stale socket exited $EXIT_RC"

[ $status -eq 0 ] && echo "PASS: only a stale socket is replaced; everything else is refused and kept"
exit $status
