#!/bin/sh
# tests/render/expect.sh — runs a command and checks its exit code and that
# stdout / stderr match extended regular expressions ('' = anything).
# usage: expect.sh EXIT_CODE STDOUT_REGEX STDERR_REGEX COMMAND [ARGS...]
set -u
want_rc=$1 out_re=$2 err_re=$3
shift 3
tmp=$(mktemp -d) || exit 1
"$@" >"$tmp/out" 2>"$tmp/err"
rc=$?
status=0
if [ "$rc" -ne "$want_rc" ]; then
  echo "FAIL: exit code $rc, expected $want_rc: $*" >&2; status=1
fi
if [ -n "$out_re" ] && ! grep -Eq -- "$out_re" "$tmp/out"; then
  echo "FAIL: stdout does not match /$out_re/" >&2; status=1
fi
if [ -n "$err_re" ] && ! grep -Eq -- "$err_re" "$tmp/err"; then
  echo "FAIL: stderr does not match /$err_re/" >&2; status=1
fi
echo "--- stdout"; cat "$tmp/out"; echo "--- stderr"; cat "$tmp/err"
rm -rf "$tmp"
exit $status
