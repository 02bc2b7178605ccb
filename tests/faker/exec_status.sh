#!/usr/bin/env bash
# tests/faker/exec_status.sh TESSERA OUTDIR — `tessera exec` passes the
# program's exit status, its death by a signal, and its standard output
# and error through unchanged, sets TESSERA_CHAIN (default: render to
# out/PROGRAM-%04d.png, out/ created) and puts the faker first in
# LD_LIBRARY_PATH; usage errors exit 2. Under --graph GRAPH the same
# program's exit status and death by a signal pass through (the run's
# verdict is the program's own end), while a failing server gives 1 and one
# line naming it, not the program's status.
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

# --graph: the program is the app node's exec (run under the faker).
cat > local.yaml <<'EOF'
version: 1
window: {width: 64, height: 48}
nodes:
  app:
    exec: bin/spheres
    chain: [render: {output: "out/local-%04d.png"}]
EOF
cat > server_fails.yaml <<'EOF'
version: 1
window: {width: 64, height: 48}
nodes:
  app:
    exec: bin/spheres
    chain: [pack]
    to: server
  server:
    chain: [render: {output: "/proc/tessera-none/f-%04d.png"}]
EOF
g() { "$tessera" exec --graph "$@"; }
o=$(g local.yaml --out g1 -- sh -c 'echo out; exit 7' 2>"$out/g1.err"); s=$?
[ $s -eq 7 ] || fail "--graph: exit 7 came back as $s"
[ "$o" = out ] || fail "--graph: stdout changed: '$o'"
grep -q "^tessera exec: node 'app': application sh exited with status 7$" "$out/g1.err" ||
  fail "--graph: no line naming the program's status: $(cat "$out/g1.err")"
g local.yaml --out g2 -- sh -c 'kill -TERM $$' 2>/dev/null; s=$?
[ $s -eq 143 ] || fail "--graph: death by SIGTERM came back as $s (expected 143)"
# Death by the signal itself, not an exit 139: bash reports a child that
# a SIGSEGV killed (and says nothing of an exit status).
bash -c "'$tessera' exec --graph local.yaml --out g3 -- sh -c 'kill -SEGV \$\$' 2>/dev/null; echo \$? > g3.status" 2>"$out/g3.err"
[ "$(cat g3.status)" = 139 ] || fail "--graph: death by SIGSEGV came back as $(cat g3.status) (expected 139)"
grep -q "Segmentation fault" "$out/g3.err" || fail "--graph: exit 139 but no death by SIGSEGV: $(cat "$out/g3.err")"
g local.yaml --out g4 -- true >/dev/null 2>&1; s=$?
[ $s -eq 0 ] || fail "--graph: a clean program and run gave $s"
start=$(date +%s)
g server_fails.yaml --out g5 -- sh -c 'sleep 30; exit 7' 2>"$out/g5.err"; s=$?
[ $s -eq 1 ] || fail "--graph: a failing server gave $s (expected 1, the run's verdict)"
[ $(($(date +%s) - start)) -lt 20 ] || fail "--graph: the failing server's run did not end before the program"
n=$(grep -c "^tessera exec: " "$out/g5.err")
[ "$n" = 1 ] && grep -q "^tessera exec: node 'server': cannot create output directory '/proc/tessera-none'" "$out/g5.err" ||
  fail "--graph: the failing server is not named in one line: $(cat "$out/g5.err")"
echo "OK: status, signal, stdout/stderr, chain, LD_LIBRARY_PATH, usage; --graph: status and signals pass through, a failing server gives 1 and its line"
