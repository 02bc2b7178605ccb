#!/bin/sh
# tests/binaryswap/exact.sh — a sort-last graph (binaryswap peers and a
# display node) written for N peers and run with `tessera run`: real
# processes, real sockets, real OSMesa, real PNGs. Every frame the display
# writes is compared with the single-process native render of the whole
# scene: 0 differing pixels, and exactly FRAMES frames.
# usage: exact.sh FORM BIN_DIR OUT_DIR N SCENE [EXTRA [OPTIONS]]
#   FORM   insitu  (N apps, each running the chain `binaryswap`)
#          servers (N apps -> pack -> N render servers ending in binaryswap)
#   SCENE  isosurface | overlap (spheres --overlap: interpenetrating)
#   EXTRA  blank: one more peer, the last rank, that draws nothing (an
#          empty share): its region is empty and it sends no pixel
#          nothing: every peer draws nothing (the display shows background)
#          -: neither
#   OPTIONS binaryswap's options as YAML flow entries ("strategy: bswap")
set -u
. "$(dirname "$0")/lib.sh"
form=$1 bin=$2 out=$3 n=$4 scene=$5 extra=${6:--} options=${7:-}
fail() { echo "FAIL: $*" >&2; bad=1; }
bad=0
rm -rf "$out" && mkdir -p "$out/native" || exit 1
frames=2 size=96x72
case $scene in
isosurface) app=isosurface args="" ;;
overlap) app=spheres args="--overlap" ;;
*) echo "unknown scene $scene" >&2; exit 2 ;;
esac
# Peer i draws share part[i] of parts[i]; the reference draws the whole.
shares=
k=0
while [ $k -lt "$n" ]; do
  if [ "$extra" = nothing ]; then shares="$shares 0/1000000"; else shares="$shares $k/$n"; fi
  k=$((k + 1))
done
[ "$extra" = blank ] && shares="$shares 0/1000000"
if [ "$extra" = nothing ]; then
  "$bin/$app-native" $args --frames $frames --size $size --part 0/1000000 --out "$out/native/f-%04d.png" || exit 1
else
  "$bin/$app-native" $args --frames $frames --size $size --out "$out/native/f-%04d.png" || exit 1
fi
graph=$out/graph.yaml
sl_write_graph "$graph" "$form" unix "$options" "bin/$app $args --frames $frames --size $size" $shares
sl_run "$graph" debug
sl_check_run
sl_compare_frames
[ -e "$out/run/out/$(printf 'f-%04d.png' $frames)" ] && fail "the display wrote more than $frames frames"
if [ "$extra" = blank ] || [ "$extra" = nothing ]; then
  # An empty peer's region is empty and what it sends is headers and one
  # background run (a few dozen bytes), never a frame of background.
  blank=$n
  [ "$extra" = nothing ] && blank=1
  empty=$(grep -c "rank $blank region \[0, 0, 0, 0\] of 96x72" "$out/run.err")
  sent=$(sed -n "s/.*: rank $blank sent \([0-9]*\) bytes to its peers/\1/p" "$out/run.err" | sort -n | tail -n 1)
  echo "empty regions of rank $blank: $empty, at most $sent bytes sent per frame"
  [ "$empty" = $frames ] || fail "rank $blank had $empty empty regions, not $frames"
  [ -n "$sent" ] && [ "$sent" -le 128 ] || fail "the blank rank $blank sent ${sent:-?} bytes in a frame"
fi
grep -o 'strategy [^ ]* for [0-9]* peers.*' "$out/run.err" | head -n 1
[ $bad = 0 ] && echo PASS
exit $bad
