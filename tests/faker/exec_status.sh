#!/usr/bin/env bash
# tests/faker/exec_status.sh TESSERA OUTDIR — `tessera exec` passes the
# program's exit status, its death by a signal, and its standard output
# and error through unchanged, sets TESSERA_CHAIN (default: render to
# out/PROGRAM-%04d.png, out/ created) and puts the faker first in
# LD_LIBRARY_PATH; usage errors exit 2.
set -uo pipefail
tessera=$1 out=$2
rm -rf "$out"; mkdir -p "$out"; cd "$out"
fail() { echo "FAIL: $*"; exit 1; }
"$tessera" exec -- sh -c 'exit 7'; s=$?
[ $s -eq 7 ] || fail "exit 7 came back as $s"
"$tessera" exec -- sh -c 'kill -TERM $$'; s=$?
[ $s -eq 143 ] || fail "death by SIGTERM came back as $s (expected 143)"
o=$("$tessera" exec -- sh -c 'printf "a\nb"; printf "err" >&2' 2>"$out/err.txt")
[ "$o" = "$(printf 'a\nb')" ] || fail "stdout changed: '$o'"
[ "$(cat "$out/err.txt")" = err ] || fail "stderr changed: '$(cat "$out/err.txt")'"
c=$(env -u TESSERA_CHAIN "$tessera" exec -- sh -c 'echo "$TESSERA_CHAIN"')
[ "$c" = 'render output="out/sh-%04d.png"' ] || fail "default chain is '$c'"
[ -d out ] || fail "out/ was not created for the default chain"
c=$("$tessera" exec --chain "print ! render" -- sh -c 'echo "$TESSERA_CHAIN"')
[ "$c" = "print ! render" ] || fail "--chain gave '$c'"
l=$("$tessera" exec -- sh -c 'echo "$LD_LIBRARY_PATH"')
[ -e "${l%%:*}/libGL.so.1" ] || fail "LD_LIBRARY_PATH '$l' does not start with the faker's directory"
"$tessera" exec --help | grep -q "usage: tessera exec" || fail "--help has no usage line"
"$tessera" exec 2>/dev/null; s=$?
[ $s -eq 2 ] || fail "no program: status $s (expected 2)"
"$tessera" exec --bogus -- true 2>/dev/null; s=$?
[ $s -eq 2 ] || fail "unknown option: status $s (expected 2)"
"$tessera" exec -- /nonexistent/program 2>/dev/null; s=$?
[ $s -eq 127 ] || fail "missing program: status $s (expected 127)"
echo "OK: status, signal, stdout/stderr, chain, LD_LIBRARY_PATH, usage"
