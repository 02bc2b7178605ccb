#!/usr/bin/env bash
# tests/capture/replay.sh MODE TESSERA SPHERES GRAPH_DIR OUTDIR
# Captures spheres (64x48, 5 frames) with the chain
# "capture file=sp.tsrcap ! render" (the original run's frames) and then:
#   chain   replays it through "render": every frame bit-identical; the
#           default chain (render to out/sp-%04d.png) likewise
#   graphs  replays it as the app node of tcp.yaml (pack -> server render),
#           wall.yaml (tilesort 2x2, assembled) and replicate.yaml (two
#           servers): every frame of every output bit-identical
#   ranges  --frames 1-3 (frames 1..3 as the chain's 0..2), --frames 4,
#           --loop 3 (15 frames: the 5 three times) and --frames 2-3
#           --loop 2 (2,3,2,3); a range past the end and a graph with two
#           app nodes refused before anything runs
#   info    --info: frames, buffers, replies, and every command count equal
#           to a print trace of the same run (print after capture)
#   hexfloats  the replay traced by print floats=hex: each %a float read
#           back and written with %g gives the default trace line for line,
#           every float is written exactly (%a of its value is the token),
#           and some float of the stream is not what its %g text reads as
#           (the bits the default trace loses)
set -euo pipefail
mode=$1 tessera=$2 spheres=$3 graphs=$4 out=$5
. "$(dirname "$0")/common.sh"
rm -rf "$out"; mkdir -p "$out"; cd "$out"
"$spheres" --frames 5 --size 64x48 \
  --chain "capture file=sp.tsrcap ! print file=trace.txt ! render output=orig-%04d.png" > /dev/null
[ -s sp.tsrcap ] || { echo "FAIL: no capture file"; exit 1; }
frames_move "$tessera" orig-0000.png orig-0004.png
ls -a | grep -q '\.tmp-' && { echo "FAIL: a temporary file was left"; exit 1; }
case $mode in
chain)
  "$tessera" replay sp.tsrcap --chain "render output=rep-%04d.png"
  same_frames "$tessera" orig-%04d.png rep-%04d.png 5
  "$tessera" replay sp.tsrcap
  same_frames "$tessera" orig-%04d.png out/sp-%04d.png 5
  ;;
graphs)
  for g in tcp wall replicate; do
    "$tessera" replay sp.tsrcap --graph "$graphs/$g.yaml" --out "$out/$g" --no-progress
  done
  same_frames "$tessera" orig-%04d.png tcp/out/tcp-%04d.png 5
  same_frames "$tessera" orig-%04d.png wall/out/wall-%04d.png 5
  same_frames "$tessera" orig-%04d.png replicate/out/rep-s0-%04d.png 5
  same_frames "$tessera" orig-%04d.png replicate/out/rep-s1-%04d.png 5
  ;;
ranges)
  "$tessera" replay sp.tsrcap --frames 1-3 --chain "render output=a-%04d.png"
  same_frames "$tessera" orig-%04d.png a-%04d.png 3 1
  "$tessera" replay sp.tsrcap --frames 4 --chain "render output=b-%04d.png"
  same_frames "$tessera" orig-%04d.png b-%04d.png 1 4
  "$tessera" replay sp.tsrcap --loop 3 --chain "render output=c-%04d.png" | tee c.txt
  grep -q "15 frames fed (3 passes)" c.txt || { echo "FAIL: --loop 3 did not feed 15 frames"; exit 1; }
  for k in 0 1 2; do
    for i in 0 1 2 3 4; do cp "c-$(printf %04d $((k * 5 + i))).png" "c$k-$(printf %04d $i).png"; done
    same_frames "$tessera" orig-%04d.png "c$k-%04d.png" 5
  done
  "$tessera" replay sp.tsrcap --frames 2-3 --loop 2 --chain "render output=d-%04d.png"
  for i in 0 1 2 3; do cp "d-$(printf %04d $i).png" "e-$(printf %04d $i).png"; done
  cp orig-0002.png f-0000.png; cp orig-0003.png f-0001.png; cp orig-0002.png f-0002.png; cp orig-0003.png f-0003.png
  same_frames "$tessera" f-%04d.png e-%04d.png 4
  # A range past the end is refused before anything runs.
  s=0; "$tessera" replay sp.tsrcap --frames 3-5 --chain "render output=g-%04d.png" 2> g.err || s=$?
  cat g.err
  [ "$s" -eq 2 ] && grep -q "has 5 frames" g.err && [ ! -e g-0000.png ] || { echo "FAIL: --frames 3-5 not refused"; exit 1; }
  # In graph mode too, before any node starts; and a graph whose app
  # nodes are several is refused (a replay is one application).
  s=0; "$tessera" replay sp.tsrcap --frames 3-5 --graph "$graphs/tcp.yaml" --out "$out/gr" 2> gr.err || s=$?
  cat gr.err
  [ "$s" -eq 2 ] && grep -q "has 5 frames" gr.err && [ ! -e gr ] || { echo "FAIL: --graph --frames 3-5 not refused"; exit 1; }
  printf 'version: 1\nnodes:\n  a: {exec: x, chain: [pack], to: s}\n  b: {exec: y, chain: [pack], to: s}\n  s: {chain: [render]}\n' > two.yaml
  s=0; "$tessera" replay sp.tsrcap --graph two.yaml 2> two.err || s=$?
  cat two.err
  [ "$s" -eq 2 ] && grep -q "has 2 app nodes" two.err || { echo "FAIL: a graph with two app nodes not refused"; exit 1; }
  ;;
info)
  "$tessera" replay --info sp.tsrcap | tee info.txt
  grep -qx "frames: 5" info.txt && grep -qx "window: 64x48" info.txt && grep -qx "replies: 1" info.txt \
    || { echo "FAIL: header lines"; exit 1; }
  grep -qx "bytes: $(stat -c %s sp.tsrcap) .*" info.txt 2>/dev/null || grep -q "^bytes: $(stat -c %s sp.tsrcap) " info.txt \
    || { echo "FAIL: bytes is not the file size"; exit 1; }
  # Per command: the print trace of the same run saw the same calls.
  sed -n 's/^  \(gl[A-Za-z0-9]*\) *\([0-9]*\)$/\1 \2/p' info.txt | sort > info-counts.txt
  sed 's/(.*//' trace.txt | sort | uniq -c | awk '{print $2, $1}' | sort > trace-counts.txt
  diff trace-counts.txt info-counts.txt || { echo "FAIL: --info counts differ from the print trace"; exit 1; }
  echo "ok: $(wc -l < info-counts.txt) commands counted as the trace has them"
  calls=$(sed -n 's/^calls: //p' info.txt)
  [ "$calls" -eq "$(wc -l < trace.txt)" ] || { echo "FAIL: calls $calls, trace has $(wc -l < trace.txt)"; exit 1; }
  ;;
hexfloats)
  "$tessera" replay sp.tsrcap --chain "print file=g.txt ! render output=g-%04d.png" > /dev/null
  "$tessera" replay sp.tsrcap --chain "print file=hex.txt floats=hex ! render output=hex-%04d.png" > /dev/null
  same_frames "$tessera" orig-%04d.png hex-%04d.png 5
  cmp -s g.txt hex.txt && { echo "FAIL: floats=hex wrote the %g trace"; exit 1; }
  # shellcheck disable=SC2016
  perl -MPOSIX=strtod -ne '
    BEGIN { $floats = $inexact = $bad = 0 }
    s{(-?0x[0-9a-f]+(?:\.[0-9a-f]*)?p[-+][0-9]+)}{
      my ($v) = strtod($1); $floats++;
      $bad++ if sprintf("%a", $v) ne $1;
      my $g = sprintf("%g", $v); $inexact++ if $g + 0 != $v; $g
    }ge;
    print;
    END { print STDERR "floats=$floats inexact_as_g=$inexact not_exact=$bad\n" }' hex.txt > hex-as-g.txt 2> counts.txt
  cat counts.txt
  diff -q g.txt hex-as-g.txt > /dev/null || { echo "FAIL: the hex trace read back with %g differs from the default trace"; diff g.txt hex-as-g.txt | head -5; exit 1; }
  grep -q ' not_exact=0$' counts.txt || { echo "FAIL: a hex float does not hold its value exactly"; exit 1; }
  grep -q ' inexact_as_g=0 ' counts.txt && { echo "FAIL: no float of the stream needs more than %g (the test proves nothing)"; exit 1; }
  grep -q '^floats=0 ' counts.txt && { echo "FAIL: no floats in the trace"; exit 1; }
  echo "ok: hex trace = the %g trace when read back; $(cat counts.txt)"
  ;;
*) echo "unknown mode $mode"; exit 2 ;;
esac
