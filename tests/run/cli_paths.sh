#!/bin/sh
# tests/run/cli_paths.sh — `tessera run` refuses an --out or --stats path
# it cannot use before it starts anything: exit 2, one line on stderr
# naming the option, the path and what is wrong, nothing on stdout.
# usage: cli_paths.sh CASE TESSERA GRAPH OUT
#   out-is-a-file       --out names an existing file
#   out-under-a-file    --out names a folder inside a file
#   stats-no-folder     --stats in a folder that does not exist
#   stats-is-a-folder   --stats names a folder
set -u
case_=$1 tessera=$2 graph=$3 out=$4
rm -rf "$out" && mkdir -p "$out" || exit 1
echo "not a folder" >"$out/file"
case $case_ in
  out-is-a-file) args="--out $out/file" want="--out $out/file: not a directory" ;;
  out-under-a-file) args="--out $out/file/sub" want="--out $out/file/sub: cannot create the directory: Not a directory" ;;
  stats-no-folder) args="--out $out/run --stats $out/missing/stats.json"
    want="--stats $out/missing/stats.json: cannot write it: No such file or directory" ;;
  stats-is-a-folder) args="--out $out/run --stats $out" want="--stats $out: cannot write it: Is a directory" ;;
  *) echo "unknown case $case_" >&2; exit 2 ;;
esac
# $args is a list of words on purpose.
# shellcheck disable=SC2086
timeout 60 "$tessera" run "$graph" $args --no-progress >"$out/stdout" 2>"$out/stderr"
rc=$?
status=0
echo "--- stderr"; cat "$out/stderr"
[ "$rc" -eq 2 ] || { echo "FAIL: exit $rc, expected 2" >&2; status=1; }
[ "$(wc -l <"$out/stderr")" -eq 1 ] || { echo "FAIL: expected one line on stderr" >&2; status=1; }
[ "$(cat "$out/stderr")" = "tessera run: $want" ] || { echo "FAIL: expected: tessera run: $want" >&2; status=1; }
[ -s "$out/stdout" ] && { echo "FAIL: output on stdout (the run started)" >&2; status=1; }
# Nothing ran: no node wrote into the run's folder.
if [ -d "$out/run" ] && [ -n "$(ls -A "$out/run")" ]; then
  echo "FAIL: the run's folder is not empty: $(ls -A "$out/run")" >&2; status=1
fi
exit $status
