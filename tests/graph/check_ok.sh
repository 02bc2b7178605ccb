#!/bin/sh
# tests/graph/check_ok.sh — `tessera check [FLAGS] GRAPH` accepts GRAPH:
# exit 0, one summary line "ok: N nodes, E edges, window WxH", no stderr.
# usage: check_ok.sh TESSERA GRAPH [FLAGS...]
set -u
tessera=$1 graph=$2
shift 2
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
"$tessera" check "$@" "$graph" >"$tmp/out" 2>"$tmp/err"
rc=$?
cat "$tmp/out" "$tmp/err"
if [ "$rc" -ne 0 ]; then
  echo "FAIL: exit $rc" >&2; exit 1
fi
if [ -s "$tmp/err" ]; then
  echo "FAIL: stderr is not empty" >&2; exit 1
fi
if [ "$(wc -l <"$tmp/out")" -ne 1 ] ||
   ! grep -Eq '^ok: [1-9][0-9]* nodes?, [0-9]+ edges?, window [1-9][0-9]*x[1-9][0-9]*' "$tmp/out"; then
  echo "FAIL: not a one-line summary" >&2; exit 1
fi
