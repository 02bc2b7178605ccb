#!/bin/sh
# tests/run/run_graph.sh — runs a graph file with `tessera run` and compares
# every frame of every output the graph names (its `output: "..."`
# patterns) with a native reference render: 0 differing pixels, exactly
# FRAMES frames each, exit 0 and a statistics JSON that says "ok".
# usage: run_graph.sh BIN_DIR GRAPH OUT_DIR FRAMES REFERENCE_PROGRAM [REFERENCE_ARGS...]
#   e.g. run_graph.sh build/bin examples/graphs/tcp.yaml /tmp/t 20 spheres-native --size 1024x768
# The reference runs as BIN_DIR/REFERENCE_PROGRAM REFERENCE_ARGS --frames FRAMES
# --out OUT_DIR/ref/f-%04d.png. Adding a graph test is one line in tests/run.cmake.
set -u
bin=$1 graph=$2 out=$3 frames=$4 ref=$5
shift 5
rm -rf "$out" && mkdir -p "$out/ref" "$out/run" || exit 1

patterns=$(sed -n 's/.*output: *"\([^"]*\)".*/\1/p' "$graph")
[ -n "$patterns" ] || { echo "FAIL: $graph names no output: \"...\" pattern" >&2; exit 1; }

"$bin/$ref" "$@" --frames "$frames" --out "$out/ref/f-%04d.png" \
  || { echo "FAIL: reference $ref exited $?" >&2; exit 1; }

timeout 120 "$bin/tessera" run "$graph" --out "$out/run" --stats "$out/stats.json" --no-progress \
  >"$out/run.out" 2>"$out/run.err"
rc=$?
cat "$out/run.out"
if [ "$rc" -ne 0 ]; then
  echo "FAIL: tessera run $graph exited $rc; its stderr:" >&2
  cat "$out/run.err" >&2
  exit 1
fi
grep -q '"status": "ok"' "$out/stats.json" || { echo "FAIL: stats JSON does not say ok" >&2; cat "$out/stats.json" >&2; exit 1; }

status=0
for pattern in $patterns; do
  f=0
  while [ "$f" -lt "$frames" ]; do
    got="$out/run/$(printf "$pattern" "$f")"
    want="$out/ref/$(printf 'f-%04d.png' "$f")"
    result=$("$bin/tessera" imgdiff "$want" "$got" 2>&1)
    rc=$?
    echo "$pattern frame $f: $(echo "$result" | tr '\n' ' ')"
    [ "$rc" -eq 0 ] || status=1
    f=$((f + 1))
  done
  extra="$out/run/$(printf "$pattern" "$frames")"
  [ -e "$extra" ] && { echo "FAIL: $extra exists: more than $frames frames" >&2; status=1; }
done
[ $status -eq 0 ] && echo "PASS: $graph: every frame of $(echo $patterns | wc -w) output(s) is bit-identical to $ref"
exit $status
