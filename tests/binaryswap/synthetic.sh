#!/bin/sh
# tests/binaryswap/synthetic.sh — N in-situ binaryswap peers with
# synthetic=MODE (generated layers instead of the read-back, the
# benchmarks' input) under `tessera run`, with stats= on: every frame the
# display writes must equal the composite of those layers computed by
# synthetic_check, and every peer must have written a timing line per frame.
# With FILLED=1 some peer must also have drawn a final piece filled with
# background (final_filled 1: a strip folded from many pieces, drawn as it
# is rather than gathered).
# usage: synthetic.sh BIN_DIR OUT_DIR N full|ellipse [WxH (96x72)]
set -u
bin=$1 out=$2 n=$3 mode=$4 size=${5:-96x72}
frames=2 w=${size%x*} h=${size#*x}
bad=0
fail() { echo "FAIL: $*" >&2; bad=1; }
rm -rf "$out" && mkdir -p "$out" || exit 1
graph=$out/graph.yaml
{
  echo "version: 1"
  echo "window: {width: $w, height: $h}"
  echo "defaults: {transport: unix}"
  echo "nodes:"
  i=0
  while [ $i -lt "$n" ]; do
    # The application draws nothing: the layer is generated.
    echo "  app$i:"
    echo "    exec: bin/spheres --frames $frames --size ${w}x$h --part 0/1000000"
    echo "    chain: [{binaryswap: {synthetic: $mode, stats: \"$out/stats.txt\"}}]"
    echo "    to: display"
    i=$((i + 1))
  done
  echo "  display:"
  echo "    chain:"
  echo "      - render: {output: \"out/f-%04d.png\"}"
} >"$graph"
timeout 60 "$bin/tessera" run "$graph" --out "$out/run" --no-progress >"$out/run.out" 2>"$out/run.err"
rc=$?
[ $rc = 0 ] || { fail "tessera run exited $rc"; tail -n 20 "$out/run.err"; }
f=0
while [ $f -lt $frames ]; do
  "$bin/synthetic_check" "$mode" $w $h "$n" "$out/run/out/$(printf 'f-%04d.png' $f)" || bad=1
  f=$((f + 1))
done
lines=$(grep -c '^frame [0-9]* rank [0-9]* nranks '"$n"' swap_ns [0-9]* ready_ns' "$out/stats.txt" 2>/dev/null)
[ "${lines:-0}" = $((n * frames)) ] || fail "stats.txt has ${lines:-0} frame lines, not $((n * frames))"
grep -Eq '^frame 1 rank 0 .* displayed_ns [1-9]' "$out/stats.txt" || fail "rank 0 wrote no displayed_ns"
if [ "${FILLED:-0}" = 1 ]; then
  grep -Eq ' final_filled 1$' "$out/stats.txt" || fail "no peer drew a final piece filled with background"
fi
exit $bad
