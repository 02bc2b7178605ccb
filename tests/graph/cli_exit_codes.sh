#!/bin/sh
# tests/graph/cli_exit_codes.sh — exit codes of `tessera check` and
# `tessera dot`: 0 for a valid graph and --help, 2 for an invalid graph, a
# missing file, a missing argument or an unknown option.
# usage: cli_exit_codes.sh TESSERA VALID_GRAPH INVALID_GRAPH
set -u
tessera=$1 valid=$2 invalid=$3
status=0
expect() {
  want=$1
  shift
  "$@" >/dev/null 2>&1
  rc=$?
  if [ "$rc" -ne "$want" ]; then
    echo "FAIL: exit $rc, expected $want: $*" >&2; status=1
  else
    echo "ok: exit $rc: $*"
  fi
}
for command in check dot; do
  expect 0 "$tessera" "$command" "$valid"
  expect 0 "$tessera" "$command" --help
  expect 2 "$tessera" "$command" "$invalid"
  expect 2 "$tessera" "$command" "$valid.does-not-exist"
  expect 2 "$tessera" "$command"
  expect 2 "$tessera" "$command" --no-such-option "$valid"
  expect 2 "$tessera" "$command" "$valid" "$valid"
done
# --help goes to stdout, errors to stderr only.
if [ -z "$("$tessera" check --help 2>/dev/null)" ]; then
  echo "FAIL: tessera check --help prints nothing on stdout" >&2; status=1
fi
if [ -n "$("$tessera" check "$invalid" 2>/dev/null)" ]; then
  echo "FAIL: tessera check prints on stdout for an invalid graph" >&2; status=1
fi
exit $status
