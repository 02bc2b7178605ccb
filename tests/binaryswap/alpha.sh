#!/bin/sh
# tests/binaryswap/alpha.sh — binaryswap's alpha mode under `tessera run`:
# N peers each draw a share of `spheres --alpha` (whole translucent
# spheres, back to front, premultiplied, cleared to transparent black);
# every frame the display writes must equal, with 0 differing pixels, the
# serial back-to-front blend of the same layers that alpha_blend computes
# from each share rendered natively (spheres-native --part K/N), with the
# background added once. Real processes, sockets, OSMesa and PNGs.
# usage: alpha.sh FORM BIN_DIR BLEND OUT_DIR N [OPTIONS [CASE]]
#   FORM    insitu | servers (as exact.sh)
#   BLEND   the alpha_blend tool
#   OPTIONS binaryswap's options as YAML flow entries ("strategy: direct")
#   CASE    -: rank r draws share r, rank order is view order
#           background: the applications clear to an opaque colour
#           reversed: rank r draws share N-1-r, view_order lists N-1..0
#           boxes: rank r draws share N-1-r, each peer has the `box` of
#                    its share's spheres and no view_order: the order is
#                    computed from the boxes every frame
#           refused: the options must be refused with one line naming the
#                    regrouped blend (exit non-zero, no frame)
set -u
. "$(dirname "$0")/lib.sh"
form=$1 bin=$2 blend=$3 out=$4 n=$5 options=${6:-} case=${7:--}
fail() { echo "FAIL: $*" >&2; bad=1; }
bad=0
rm -rf "$out" && mkdir -p "$out/native" || exit 1
frames=2 size=96x72 alpha=0.55 colour=rgba8
case $options in *rgba32f*) colour=rgba32f ;; esac
bgargs= bgpng=none
if [ "$case" = background ]; then
  bgargs="--background 0.2,0.35,0.6"
  "$bin/spheres-native" --out-alpha --alpha $alpha $bgargs --frames 1 --size $size --part 0/1000000 \
    --out "$out/native/bg-%04d.png" || exit 1
  bgpng=$out/native/bg-0000.png
fi
# the layers, in view order (front first): share k is layer k
k=0
while [ $k -lt "$n" ]; do
  "$bin/spheres-native" --out-alpha --alpha $alpha --frames $frames --size $size --part $k/$n \
    --out "$out/native/layer$k-%04d.png" || exit 1
  k=$((k + 1))
done
order=
if [ "$case" = reversed ]; then
  r=$((n - 1))
  while [ $r -ge 0 ]; do order="$order${order:+, }$r"; r=$((r - 1)); done
  options="$options${options:+, }view_order: [$order]"
fi
entries="mode: alpha${options:+, }$options"
graph=$out/graph.yaml
set --
i=0
while [ $i -lt "$n" ]; do
  share=$i
  [ "$case" = reversed ] || [ "$case" = boxes ] && share=$((n - 1 - i))
  peer_entries=$entries
  if [ "$case" = boxes ]; then
    # spheres.c's alpha scene: sphere s at (-0.9 + 0.22 s, 0.5 - 0.12 s,
    # 1.6 - 1.1 s), radius 0.55; share K has spheres [8K/N, 8(K+1)/N)
    box=$(awk -v k=$share -v n="$n" 'BEGIN {
      a = int(8 * k / n); b = int(8 * (k + 1) / n) - 1
      printf "%g, %g, %g, %g, %g, %g", -0.9 + 0.22 * a - 0.55, 0.5 - 0.12 * b - 0.55, 1.6 - 1.1 * b - 0.55,
             -0.9 + 0.22 * b + 0.55, 0.5 - 0.12 * a + 0.55, 1.6 - 1.1 * a + 0.55 }')
    peer_entries="$entries, box: [$box]"
  fi
  set -- "$@" "$share/$n;$peer_entries"
  i=$((i + 1))
done
# the blend is checked in all four channels: the display keeps the alpha
SL_OUTPUT_ALPHA=true sl_write_graph "$graph" "$form" unix "$entries" "bin/spheres --alpha $alpha $bgargs --frames $frames --size $size" "$@"
sl_run "$graph" debug
if [ "$case" = refused ]; then
  line=$(grep -m 1 "mode=alpha with strategy" "$out/run.err")
  echo "exit $rc: $line"
  [ $rc != 0 ] || fail "tessera run exited 0 with a strategy that regroups the blend"
  case $line in
  *"blended, in front of others"*"use direct, gather or auto"*) ;;
  *) fail "no line naming the regrouped blend"; tail -n 20 "$out/run.err" ;;
  esac
  [ -e "$out/run/out/f-0000.png" ] && fail "a frame was written"
  [ $bad = 0 ] && echo PASS
  exit $bad
fi
sl_check_run
f=0
while [ $f -lt $frames ]; do
  name=$(printf '%04d.png' $f)
  layers=
  k=0
  while [ $k -lt "$n" ]; do layers="$layers $out/native/layer$k-$name"; k=$((k + 1)); done
  # shellcheck disable=SC2086
  diff=$("$blend" $colour "$out/run/out/f-$name" "$bgpng" $layers 2>&1)
  echo "frame $f: $diff"
  case $diff in "differing_pixels: 0") ;; *) fail "frame $f differs from the serial back-to-front blend" ;; esac
  f=$((f + 1))
done
[ -e "$out/run/out/$(printf 'f-%04d.png' $frames)" ] && fail "the display wrote more than $frames frames"
# $layers and $name are the last frame's now.
# not vacuous: the layers overlap (two or more peers drew translucent
# pixels somewhere), and the background, when given, shows once
if [ "$n" -gt 1 ]; then
  # shellcheck disable=SC2086
  over=$("$blend" rgba8 "$out/native/layer0-$name" none $layers 2>&1 | head -n 1)
  echo "blending the layers changes layer 0 at: $over"
  [ "$over" != "differing_pixels: 0" ] || fail "the layers do not overlap: the test shows nothing"
fi
# and where three or more layers meet, the grouping of the 8-bit blend
# shows: the same steps front to back give another frame
if [ "$n" -ge 4 ] && [ $colour = rgba8 ]; then
  # shellcheck disable=SC2086
  regrouped=$("$blend" rgba8-front-to-back "$out/run/out/f-$name" "$bgpng" $layers 2>&1 | head -n 1)
  echo "the front-to-back grouping would differ at: $regrouped"
  [ "$regrouped" != "differing_pixels: 0" ] || fail "the scene does not tell the blend's groupings apart"
fi
if [ "$case" = boxes ]; then
  # rank r drew the share at position N-1-r: the computed order says so
  r=0
  while [ $r -lt "$n" ]; do
    want="rank $r is at position $((n - 1 - r)) of the view order"
    got=$(grep -c "$want" "$out/run.err")
    echo "$want: $got frames"
    [ "$got" = $frames ] || fail "rank $r was not at position $((n - 1 - r)) in every frame"
    r=$((r + 1))
  done
fi
grep -o 'strategy [^ ]* for [0-9]* peers.*' "$out/run.err" | head -n 1
[ $bad = 0 ] && echo PASS
exit $bad
