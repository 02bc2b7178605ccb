#!/usr/bin/env bash
# tests/faker/sweep_exact.sh TESSERA OUTDIR [PROGRAM...]
# Exactness of the real-program sweep (issue 12, item 6): each PROGRAM
# (glxgears, or the name of an xscreensaver-gl hack) runs unmodified at
# 320x240 under a private Xvfb through `tessera exec --chain "capture
# frames=10 ! render"`, so its stream is captured once; the capture is then
# replayed with no X server through [render] 1x1 (--chain) and through the
# 2x2 grid wall tests/faker/sweep_wall.yaml (tilesort grid=2,2, assembled):
# 0 differing pixels (tessera imgdiff) between the two, every frame, and
# each equal to the live run's frame (that they move and are not blank is
# xscreensaver.sh's check). Two programs at a time. No PROGRAM: glxgears
# and the graph sweeps' 25 hacks (sweep_programs.sh), every GLSL and
# buffer-object hack among them. In the suite (tests/faker.cmake, plain
# builds). Prints one line per program and the counts; exits 1 naming
# each that differs.
set -uo pipefail
tessera=$(cd "$(dirname "$1")" && pwd)/$(basename "$1") out=$2; shift 2
here=$(cd "$(dirname "$0")" && pwd)
. "$here/sweep_programs.sh"
if [ $# = 0 ]; then
  command -v dpkg >/dev/null && dpkg -s xscreensaver-gl >/dev/null 2>&1 ||
    { echo "SKIP: xscreensaver-gl is not installed (scripts/setup-debian installs it)"; exit 77; }
  command -v glxgears >/dev/null || { echo "SKIP: glxgears is not installed (mesa-utils)"; exit 77; }
  mapfile -t all < <(dpkg -L xscreensaver-gl | sed -n 's|.*/config/\([^/]*\)\.xml$|\1|p' | sort -u)
  check_glsl_hacks /usr/libexec/xscreensaver "${all[@]}" || exit 1
  set -- glxgears $graph_hacks
fi
frames=10
rm -rf "$out"; mkdir -p "$out"
. "$here/xvfb.sh"
start_xvfb "$out"

# A KNOWN defect, its cause inside Mesa (llvmpipe), not fixed: a capture of
# engine replayed through the 2x2 wall can differ from its 1x1 replay in a
# frame by pixels 1-3 levels apart (measured twice: 3 of 20 captures, up
# to 764 pixels within 2 levels; 4 of 60, 8-172 pixels, one with 111
# pixels within 3 levels; the two looked at in the top-right and the
# top-left server's tiles). The cause, shown with OSMesa alone
# (tests/render/quad_diagonal_test.c, in the suite): llvmpipe cuts a GL_QUADS
# quad into triangles along its 0-2 diagonal, but along 1-3 when the draw
# Mesa makes of it holds a vertex that needs clipping, and lit quads have
# other colours along the other diagonal. Mesa makes one draw of consecutive
# glBegin/glEnd pairs up to a state change or the end of its immediate-mode
# buffer; a server gets only the pairs near its tile, with state diffs
# between them, so its draws are not the whole window's: engine's
# translucent lit housing is 16 such pairs, three of which cross the
# window's top edge. Both failing captures kept were exact (0 differing
# pixels in every tile) with every glBegin/glEnd made its own draw on both
# sides (the servers' streams recorded with print floats=hex and replayed
# into OSMesa directly), so the light positions, the matrices and the
# scissor play no part. Even the 1x1 render depends on it: 16 points added
# at the end of frame 7 changed 7 pixels of frame 8. Only GL_QUADS does it
# (the same check with GL_QUAD_STRIP, GL_POLYGON, GL_TRIANGLE_FAN and
# GL_TRIANGLE_STRIP pairs changed no pixel). Avoiding it needs the render
# SPU to draw every GL_QUADS quad as two triangles along 0-2 itself
# (immediate mode, display lists and arrays), which would also part it from
# a native OSMesa render wherever llvmpipe itself cut along 1-3. For
# engine's 1x1-against-2x2 comparison only, up to KNOWN_ENGINE_PIXELS pixels
# (2 % of the 320x240 frame) within KNOWN_ENGINE_LEVELS are reported as
# "known" (counted apart) instead of failing; anything more, any other
# program, and every live-against-replay comparison stay exact.
KNOWN_ENGINE_PIXELS=1536 KNOWN_ENGINE_LEVELS=3
# (glsnake used to differ by one pixel one level apart in about 1 capture
# in 18: its modelview history reaches 124 operations since the last load,
# beyond the state tracker's recipe of 64, so tilesort sent its servers
# glLoadMatrixf of the same bits and Mesa lit them along another rounding
# path. Recipes now hold 255 operations; tests/state covers it.)
diff_frames() {  # diff_frames A_PATTERN B_PATTERN [PIXELS LEVELS]: "" when all equal (or, given PIXELS and LEVELS, each frame's difference within them: "known:..."), else the first difference
  local i a b r d e known=""
  for ((i = 0; i < frames; i++)); do
    a=$(printf "$1" "$i") b=$(printf "$2" "$i")
    [ -e "$a" ] || { echo "$a is missing"; return; }
    [ -e "$b" ] || { echo "$b is missing"; return; }
    r=$("$tessera" imgdiff "$a" "$b")
    d=$(sed -n 's/^differing_pixels: //p' <<<"$r")
    [ "$d" = 0 ] && continue
    e=$(sed -n 's/^max_channel_error: //p' <<<"$r")
    if [ -n "${3:-}" ] && [ -n "$d" ] && [ "$d" -le "$3" ] && [ "${e:-9}" -le "$4" ]; then
      known="$known frame $i: $d pixels within $e level(s);"
      continue
    fi
    echo "frame $i: ${d:-no answer} pixels of $b differ from $a"; return
  done
  [ -z "$known" ] || echo "known:$known"
}

one() {  # one NAME: writes DIR/verdict
  local name=$1 d=$out/$1 prog=$1
  [ "$name" = glxgears ] || prog=/usr/libexec/xscreensaver/$name
  mkdir -p "$d"
  (
    cd "$d" || exit 1
    setsid "$tessera" exec --chain "capture file=$d/s.tsrcap frames=$frames ! render output=$d/orig-%04d.png" \
      -- "$prog" -geometry 320x240 > stdout.txt 2> stderr.txt &
    pid=$!
    for _ in $(seq 300); do [ -e s.tsrcap ] && break; kill -0 $pid 2>/dev/null || break; sleep 0.1; done
    kill -TERM $pid 2>/dev/null
    for _ in $(seq 50); do kill -0 $pid 2>/dev/null || break; sleep 0.1; done
    kill -KILL -- -$pid 2>/dev/null
    wait $pid 2>/dev/null
    [ -e s.tsrcap ] || { echo "FAIL $name: no capture written; $(head -c 200 stderr.txt | tr '\n' ' ')"; exit; }
    env -u DISPLAY "$tessera" replay s.tsrcap --chain "render output=$d/one-%04d.png" > replay1.txt 2>&1 ||
      { echo "FAIL $name: replay through [render] failed: $(tail -n 1 replay1.txt)"; exit; }
    env -u DISPLAY "$tessera" replay s.tsrcap --graph "$here/sweep_wall.yaml" --out "$d/wall" --no-progress \
      > replay4.txt 2>&1 || { echo "FAIL $name: replay through the 2x2 wall failed: $(tail -n 1 replay4.txt)"; exit; }
    local tolerate=()
    [ "$name" = engine ] && tolerate=($KNOWN_ENGINE_PIXELS $KNOWN_ENGINE_LEVELS)
    why=$(diff_frames "$d/one-%04d.png" "$d/wall/f-%04d.png" "${tolerate[@]}")
    known=""
    case $why in
      "") ;;
      known:*) known=${why#known:} ;;
      *) echo "FAIL $name: 1x1 against 2x2: $why"; exit ;;
    esac
    why=$(diff_frames "$d/orig-%04d.png" "$d/one-%04d.png")
    [ -z "$why" ] || { echo "FAIL $name: the live run against its replay: $why"; exit; }
    if [ -n "$known" ]; then
      echo "known $name: inexact by the known defect (see above): 1x1 against 2x2:$known; the live run = its replay"
    else
      echo "exact $name: $frames frames, 1x1 = 2x2 = the live run (0 differing pixels each)"
    fi
    rm -rf "$d/wall/tiles"
  ) > "$d/verdict"
  cat "$d/verdict"
}

begin=$SECONDS
for p in "$@"; do
  while [ "$(jobs -rp | grep -cvx "$XVFB_PID")" -ge 2 ]; do wait -n; done
  one "$p" &
done
while [ "$(jobs -rp | grep -cvx "$XVFB_PID")" -gt 0 ]; do wait -n; done
exact=0 known=0 failed=()
for p in "$@"; do
  if grep -q '^exact ' "$out/$p/verdict"; then exact=$((exact + 1))
  elif grep -q '^known ' "$out/$p/verdict"; then known=$((known + 1))
  else failed+=("$p"); fi
done
echo "sweep exactness: $# programs in $((SECONDS - begin)) s: $exact exact (1x1 = 2x2 wall, every frame), $known within a known defect (engine), ${#failed[@]} failed"
[ "${#failed[@]}" = 0 ] || { echo "FAIL: ${failed[*]}"; exit 1; }
