#!/bin/sh
# tests/binaryswap/roi.sh — binaryswap's region of interest from the
# geometry's boxes (issue 11, item 2; spus/binaryswap/roi.c). A graph of N
# peers (FORM insitu: each application runs binaryswap; servers: app ->
# pack -> a binaryswap server), small window, 2 frames, under `tessera
# run` with TESSERA_LOG=debug (each peer logs the region it read per
# frame and where it came from). Every frame the display writes is compared
# with the native render of the whole scene (0 differing pixels), and:
#   behind  APP is behind_viewer with N = 8: one triangle per peer, some
#           straddling the eye plane, one wholly behind the viewer. Every
#           region came from the geometry's box (none from the depth
#           buffer), and rank 4 (its triangle is behind the viewer) read
#           nothing: an empty region, a header only.
#   bounds  APP is behind_viewer --bounds with N = 2: rank 1 sends a
#           BoundsInfoTSR box around the eye, so its region is the whole
#           window (the box is united with its geometry's, the part behind
#           the eye clipped conservatively), in every frame.
#   box     every region came from the geometry's box and each peer read
#           fewer pixels than the window (colour and depth: no
#           full-window depth read); the pixels read per frame are printed.
# usage: roi.sh FORM BIN_DIR OUT_DIR N APP CHECK [ARGS for the peers' APP]
set -u
. "$(dirname "$0")/lib.sh"
form=$1 bin=$2 out=$3 n=$4 app=$5 check=$6 args=${7:-}
bad=0
fail() { echo "FAIL: $*" >&2; bad=1; }
rm -rf "$out" && mkdir -p "$out/native" || exit 1
frames=2 size=96x72
"$bin/$app-native" --frames $frames --size $size --out "$out/native/f-%04d.png" || exit 1
graph=$out/graph.yaml
shares= k=0
while [ $k -lt "$n" ]; do shares="$shares $k/$n"; k=$((k + 1)); done
sl_write_graph "$graph" "$form" unix "" "bin/$app $args --frames $frames --size $size" $shares
sl_run "$graph" debug
sl_check_run
sl_compare_frames
regions=$out/regions.txt
sed -n 's/.*binaryswap#[0-9]*: \(frame [0-9]*: rank [0-9]* region .*\)/\1/p' "$out/run.err" | sort >"$regions"
cat "$regions"
total=$(wc -l <"$regions")
boxed=$(grep -c "from the geometry's box" "$regions")
[ "$total" = $((n * frames)) ] || fail "$total region lines, expected $((n * frames)) ($n peers, $frames frames)"
[ "$boxed" = "$total" ] || fail "$((total - boxed)) of $total regions did not come from the geometry's box"
case $check in
behind)
  empty=$(grep -c "rank 4 region \[0, 0, 0, 0\] of 96x72 from the geometry's box; read 0x0 depth, 0x0 colour" "$regions")
  [ "$empty" = $frames ] || fail "rank 4 (behind the viewer) read something in $((frames - empty)) of $frames frames"
  ;;
bounds)
  whole=$(grep -c "rank 1 region \[0, 0, 96, 72\] of 96x72 from the geometry's box" "$regions")
  [ "$whole" = $frames ] || fail "rank 1's BoundsInfoTSR box made its region the window in $whole of $frames frames"
  ;;
box)
  # read WxH depth, WxH colour: both smaller than the 96x72 window
  big=$(sed -n 's/.*read \([0-9]*\)x\([0-9]*\) depth, \([0-9]*\)x\([0-9]*\) colour/\1 \2 \3 \4/p' "$regions" |
    awk '$1 * $2 >= 96 * 72 || $3 * $4 >= 96 * 72 { n++ } END { print n + 0 }')
  sum=$(sed -n 's/.*read \([0-9]*\)x\([0-9]*\) depth.*/\1 \2/p' "$regions" | awk '{ s += $1 * $2 } END { print s + 0 }')
  echo "pixels read per frame (all peers, depth): $((sum / frames)); a full-window read would be $((n * 96 * 72))"
  [ "$big" = 0 ] || fail "$big regions read the whole window"
  [ "$sum" -gt 0 ] || fail "no peer read anything"
  ;;
*) echo "roi.sh: unknown check '$check'" >&2; exit 2 ;;
esac
[ $bad = 0 ] && echo PASS
exit $bad
