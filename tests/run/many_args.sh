#!/bin/sh
# tests/run/many_args.sh — an exec with 1200 arguments, which `tessera
# check` accepts, runs: every argument reaches the application (a shell
# that counts them), none is lost to a limit of the control messages.
# usage: many_args.sh TESSERA OUT
set -u
tessera=$1 out=$2
rm -rf "$out" && mkdir -p "$out" || exit 1
{
  echo "version: 1"
  echo "nodes:"
  echo "  app:"
  printf "    exec: [/bin/sh, -c, 'test \"\$#\" -eq 1200 && test \"\$1\" = a1 && test \"\$1200\" = a1200', sh"
  i=1
  while [ $i -le 1200 ]; do printf ", a%d" $i; i=$((i + 1)); done
  echo "]"
  echo "    chain: [render]"
} >"$out/args.yaml"
"$tessera" check "$out/args.yaml" || { echo "FAIL: tessera check refused the graph" >&2; exit 1; }
timeout 60 "$tessera" run "$out/args.yaml" --out "$out/run" --no-progress
rc=$?
[ "$rc" -eq 0 ] || { echo "FAIL: tessera run exited $rc" >&2; exit 1; }
