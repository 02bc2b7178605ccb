#!/bin/sh
# tests/graph/expect_error.sh — runs `tessera check` on a graph file that
# must be rejected, and checks the error against the file's own header:
#   # expect: LINE:COL: TEXT     the one stderr line is FILE:LINE:COL: ...TEXT...
#   # flags: ARGS                extra arguments for tessera check (optional)
# and that the exit code is 2 (bad input) with nothing on stdout.
# usage: expect_error.sh TESSERA GRAPH
set -u
tessera=$1 graph=$2
expect=$(sed -n 's/^# expect: //p' "$graph")
flags=$(sed -n 's/^# flags: //p' "$graph")
if [ -z "$expect" ]; then
  echo "FAIL: $graph has no '# expect: LINE:COL: TEXT' line" >&2; exit 1
fi
where=${expect%%: *}
text=${expect#*: }
tmp=$(mktemp -d) || exit 1
# $flags is a list of words on purpose.
# shellcheck disable=SC2086
"$tessera" check $flags "$graph" >"$tmp/out" 2>"$tmp/err"
rc=$?
status=0
lines=$(wc -l <"$tmp/err")
message=$(cat "$tmp/err")
if [ "$rc" -ne 2 ]; then
  echo "FAIL: exit code $rc, expected 2" >&2; status=1
fi
if [ "$lines" -ne 1 ]; then
  echo "FAIL: $lines lines on stderr, expected one" >&2; status=1
fi
if [ -s "$tmp/out" ]; then
  echo "FAIL: output on stdout" >&2; status=1
fi
case $message in
  "$graph:$where: "*) ;;
  *) echo "FAIL: message does not start with '$graph:$where: '" >&2; status=1 ;;
esac
case $message in
  *"$text"*) ;;
  *) echo "FAIL: message does not contain: $text" >&2; status=1 ;;
esac
echo "--- stderr"; cat "$tmp/err"
rm -rf "$tmp"
exit $status
