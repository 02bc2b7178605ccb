#!/bin/sh
# tests/tilesort/tilesort.sh — the tilesort SPU with real `tessera node`
# tile servers (render SPU, OSMesa), real example programs and real PNGs.
# usage: tilesort.sh MODE BIN_DIR OUT_DIR ARGS...
#   exact APP FRAMES CONFIG [OPTION...]
#       tilesort gathers every frame from the servers (assemble=) and each
#       one must equal APP-native's frame: 0 differing pixels.
#   split APP FRAMES FRAME MAX [OPTION...]
#       APP through tilesort on 1x1 and on 4x4 tiles, every frame exact as
#       in `exact`; then frame FRAME (long primitives crossing the wall,
#       cut into pieces by small batches) must reach the 16 servers with
#       an overlap (bytes to all servers / bytes of the 1x1 run, from the
#       sort_first statistics) below MAX: a primitive sent whole to every
#       server would give about 16.
#   stable CONFIG STALL
#       balance_scenes (tests/tilesort/balance_scenes_driver.c: the whole cost in
#       one pixel, one window-sized primitive, an empty frame, an ordinary
#       scene; 16 frames, 256x192) on a balanced CONFIG, every frame exact;
#       every frame every server has a region of at least one pixel, the
#       regions add up to the window, no NaN or Inf in the statistics. STALL
#       1: server 1's first frame takes 1.5 s more (it reports late).
#   converge CONFIG FRAMES FROM MAX SLOW [OPTION...]
#       balance_scenes --static (a static scene) with deterministic costs
#       (each server reports 1 ns per byte received, tessera node --cost bytes),
#       every frame exact: from frame FROM on (counted from 0) the measured imbalance (max /
#       mean of the servers' reported times) is at most MAX every frame,
#       and the regions settle (no oscillation: the last four frames keep
#       one split). SLOW (1: none): server 0's reported time is multiplied by SLOW
#       (a server SLOW times as slow): its share of the bytes (its bytes
#       over the mean of the others') over the last frames must be within
#       0.3 of 1/SLOW.
#   track CONFIG FRAMES ORBIT MAX [OPTION...]
#       isosurface --orbit ORBIT (a still field, the camera orbiting ORBIT
#       degrees a frame) at 512x384 with deterministic costs, every frame
#       exact: from frame 2 on (the first split from a frame's cost is
#       frame 1's) the measured imbalance is at most MAX every frame, so
#       the split follows the motion.
#   records APP FRAMES CONFIG [OPTION...]
#       APP prints records (selection, feedback): its output and every frame
#       equal APP-native's through render, pack -> node -> render and
#       tilesort on CONFIG (frames gathered as in `exact`).
#   bad TILES BUCKET WORD
#       a tilesort with this tiles option fails at start, exit status
#       non-zero, one message naming WORD.
# CONFIG (window 1024x768): 1x1 2x1 2x2 3x3 4x4 irregular multi broadcast,
#   and the load-balanced kd, union, balance (kd's alias) on 4 servers,
#   kd8 and union8 on 8; OPTIONs are extra tilesort options (batch_bytes=4096 makes
#   primitives span buffers).
set -u
mode=$1 bin=$2 out=$3
SIZE=1024x768 APP_ARGS= TILESORT_NODE_ARGS=
shift 3
TESSERA=$bin/tessera
. "$(dirname "$0")/../node/node_lib.sh"
rm -rf "$out" && mkdir -p "$out" || exit 1
bad=0
fail() { echo "FAIL: $*" >&2; bad=1; }

# tiles_of CONFIG: sets SERVERS_N, TILES and BUCKET.
tiles_of() {
  BUCKET=grid
  case $1 in
    1x1) SERVERS_N=1 TILES=0:0:0:1024:768 ;;
    2x1) SERVERS_N=2 TILES=0:0:0:512:768,1:512:0:512:768 ;;
    2x2) SERVERS_N=4 TILES=0:0:0:512:384,1:512:0:512:384,2:0:384:512:384,3:512:384:512:384 ;;
    3x3) SERVERS_N=9 TILES=
         k=0
         for y in 0:256 256:256 512:256; do
           for x in 0:342 342:341 683:341; do
             TILES="$TILES${TILES:+,}$k:${x%%:*}:${y%%:*}:${x##*:}:${y##*:}"
             k=$((k + 1))
           done
         done ;;
    4x4) SERVERS_N=16 TILES=
         k=0
         for y in 0 192 384 576; do
           for x in 0 256 512 768; do
             TILES="$TILES${TILES:+,}$k:$x:$y:256:192"
             k=$((k + 1))
           done
         done ;;
    irregular) SERVERS_N=3 BUCKET=tiles TILES=0:0:0:700:768,1:700:0:324:300,2:700:300:324:468 ;;
    multi) SERVERS_N=2 TILES=0:0:0:512:384,1:512:0:512:384,1:0:384:512:384,0:512:384:512:384 ;;
    small2x2) SERVERS_N=4 TILES=0:0:0:128:96,1:128:0:128:96,2:0:96:128:96,3:128:96:128:96 ;;
    balance) SERVERS_N=4 BUCKET=balance TILES= ;;
    kd) SERVERS_N=4 BUCKET=kd TILES= ;;
    union) SERVERS_N=4 BUCKET=union TILES= ;;
    kd8|union8) SERVERS_N=8 BUCKET=${1%8} TILES= ;;
    broadcast) SERVERS_N=3 BUCKET=broadcast TILES=0:0:0:1024:256,1:0:256:1024:256,2:0:512:1024:256 ;;
    *) echo "unknown CONFIG $1" >&2; exit 2 ;;
  esac
}

PIDS=
kill_all() { for p in $PIDS; do kill -9 "$p" 2>/dev/null; wait "$p" 2>/dev/null; done; PIDS=; }

# run_tilesort DIR APP FRAMES CONFIG OPTIONS...: N servers, the app through
# tilesort assembling DIR/as-%04d.png; every process must exit 0.
run_tilesort() {
  dir=$1 app=$2 frames=$3 cfg=$4
  shift 4
  tiles_of "$cfg"
  mkdir -p "$dir"
  SERVERS= PIDS=
  k=0
  while [ $k -lt "$SERVERS_N" ]; do
    mkdir -p "$dir/s$k"
    # test settings (tessera node --cost ...) for every server and for
    # server k (TILESORT_NODE_ARGS, TILESORT_NODE_ARGS_k)
    eval "one=\${TILESORT_NODE_ARGS_$k:-}"
    start_node "$dir/node$k" --listen tcp://127.0.0.1:0 --clients 1 --timeout-ms 120000 $TILESORT_NODE_ARGS $one \
      --chain "render output=\"$dir/s$k/f-%04d.png\"" || { kill_all; exit 1; }
    PIDS="$PIDS $NODE_PID"
    SERVERS="$SERVERS${SERVERS:+,}$NODE_ADDR"
    k=$((k + 1))
  done
  chain="tilesort servers=$SERVERS bucket=$BUCKET assemble=\"$dir/as-%04d.png\""
  [ -n "$TILES" ] && chain="$chain tiles=$TILES"
  for o in "$@"; do chain="$chain $o"; done
  TESSERA_STATS_FILE="$dir/stats.json" "$bin/$app" $APP_ARGS --frames "$frames" --size $SIZE --chain "$chain" \
    >"$dir/app.out" 2>"$dir/app.err" &
  apid=$!
  wait_exit "$apid" 120
  [ "$EXIT_RC" = 0 ] || { fail "$app through tilesort ($cfg) exited $EXIT_RC"; cat "$dir/app.err" >&2; }
  k=0
  for p in $PIDS; do
    wait_exit "$p" 30
    [ "$EXIT_RC" = 0 ] || { fail "server $k ($cfg) exited $EXIT_RC"; cat "$dir/node$k.err" >&2; }
    k=$((k + 1))
  done
  PIDS=
}

# pixels A B: differing pixels between two PNGs (or "missing").
pixels() {
  [ -f "$1" ] && [ -f "$2" ] || { echo missing; return; }
  "$TESSERA" imgdiff "$1" "$2" | sed -n 's/^differing_pixels: //p'
}

# exact_frames DIR APP FRAMES CONFIG: every assembled frame equals the native one.
exact_frames() {
  f=0
  while [ $f -lt "$3" ]; do
    n=$(printf %04d $f)
    native=$(pixels "$out/ref-$n.png" "$1/as-$n.png")
    echo "frame $f ($4): $native pixels differ from $2-native"
    [ "$native" = 0 ] || fail "frame $f ($4): $native pixels differ from $2-native"
    f=$((f + 1))
  done
}

# frame_bytes STATS FRAME: bytes sent to all servers in that frame.
frame_bytes() {
  sed -e 's/.*"frames":\[\[//' -e 's/\]\].*//' "$1" | sed 's/\],\[/\n/g' | sed -n "$(($2 + 1))p" |
    tr ',' '\n' | awk '{ s += $1 } END { print s + 0 }'
}

# rows STATS KEY: the rows of a sort_first array of arrays, one a line.
rows() {
  sed -n "s/.*\"$2\":\[\[\([^]]*\(\],\[[^]]*\)*\)\]\].*/\1/p" "$1" | sed 's/\],\[/\n/g'
}

case $mode in
stable)
  config=$1 stall=$2
  SIZE=256x192
  [ "$stall" = 1 ] && TILESORT_NODE_ARGS_1="--stall-first-frame-ms 1500"
  "$bin/balance_scenes-native" --frames 16 --size $SIZE --out "$out/ref-%04d.png" >/dev/null ||
    fail "balance_scenes-native failed"
  run_tilesort "$out/tiled" balance_scenes 16 "$config"
  exact_frames "$out/tiled" balance_scenes 16 "$config"
  rows "$out/tiled/stats.json" server_pixels >"$out/pixels"
  [ "$(wc -l <"$out/pixels")" = 16 ] || fail "server_pixels has $(wc -l <"$out/pixels") rows, not 16"
  awk -F, -v n="$SERVERS_N" '{ s = 0; for (i = 1; i <= NF; i++) { s += $i; if ($i < 1) print "frame " NR - 1 ": server " i - 1 " has no pixel" }
       if (NF != n) print "frame " NR - 1 ": " NF " servers"; if (s != 256 * 192) print "frame " NR - 1 ": regions cover " s " pixels" }' \
    "$out/pixels" >"$out/bad"
  sed 's/^/FAIL: /' "$out/bad" >&2
  [ -s "$out/bad" ] && bad=1
  echo "regions (pixels per server) per frame:"; cat "$out/pixels"
  grep -i -q 'nan\|inf' "$out/tiled/stats.json" && fail "NaN or Inf in the statistics"
  # frames_geometry: each server's geometry part of its frame's bytes
  rows "$out/tiled/stats.json" frames >"$out/bytes"
  rows "$out/tiled/stats.json" frames_geometry >"$out/geometry"
  [ "$(wc -l <"$out/geometry")" = 16 ] || fail "frames_geometry has $(wc -l <"$out/geometry") rows, not 16"
  paste -d';' "$out/bytes" "$out/geometry" | awk -F';' '{ n = split($1, b, ","); m = split($2, g, ",")
      if (n != m) print "frame " NR - 1 ": " m " geometry counts for " n " servers"
      for (i = 1; i <= n; i++) if (g[i] + 0 > b[i] + 0) print "frame " NR - 1 ": server " i - 1 " geometry " g[i] " above its bytes " b[i] }' >"$out/badgeo"
  sed 's/^/FAIL: /' "$out/badgeo" >&2
  [ -s "$out/badgeo" ] && bad=1
  if [ "$stall" = 1 ]; then
    grep -q "first frame takes 1500 ms more" "$out/tiled/node1.err" || fail "server 1 did not stall"
  fi ;;
converge)
  config=$1 frames=$2 from=$3 max=$4 slow=$5
  shift 5
  SIZE=256x192 APP_ARGS=--static TILESORT_NODE_ARGS="--cost bytes"
  [ "$slow" != 1 ] && TILESORT_NODE_ARGS_0="--cost-scale $slow"
  "$bin/balance_scenes-native" --static --frames "$frames" --size $SIZE --out "$out/ref-%04d.png" >/dev/null ||
    fail "balance_scenes-native failed"
  run_tilesort "$out/tiled" balance_scenes "$frames" "$config" "$@"
  exact_frames "$out/tiled" balance_scenes "$frames" "$config"
  st=$out/tiled/stats.json
  imb=$(sed -n 's/.*"time_imbalance":\[\([^]]*\)\].*/\1/p' "$st")
  echo "imbalance (max/mean of reported time) per frame: $imb"
  echo "$imb" | tr ',' '\n' | awk -v m="$max" -v f="$from" 'NR > f { if ($1 == "null" || $1 + 0 > m + 0) { print "frame " NR - 1 ": imbalance " $1 " above " m; b = 1 } } END { exit b }' >&2 ||
    bad=1
  rows "$st" server_pixels >"$out/pixels"
  echo "regions (pixels per server) per frame:"; cat "$out/pixels"
  [ "$(tail -n 4 "$out/pixels" | sort -u | wc -l)" = 1 ] || fail "the regions still move in the last four frames"
  if [ "$slow" != 1 ]; then
    rows "$st" frames | tail -n 3 | awk -F, -v s="$slow" '{ o = 0; for (i = 2; i <= NF; i++) o += $i; a += $1; m += o / (NF - 1) }
      END { r = a / m; printf "server 0 (%s times as slow) got %.3f of the others'"'"' mean bytes (1/%s = %.3f)\n", s, r, s, 1 / s
            exit !(r > 1 / s - 0.3 && r < 1 / s + 0.3) }' || fail "the slow server's share is not near 1/$slow"
  fi ;;
track)
  config=$1 frames=$2 orbit=$3 max=$4
  shift 4
  SIZE=512x384 APP_ARGS="--orbit $orbit" TILESORT_NODE_ARGS="--cost bytes"
  "$bin/isosurface-native" $APP_ARGS --frames "$frames" --size $SIZE --out "$out/ref-%04d.png" >/dev/null ||
    fail "isosurface-native failed"
  run_tilesort "$out/tiled" isosurface "$frames" "$config" "$@"
  exact_frames "$out/tiled" isosurface "$frames" "$config"
  imb=$(sed -n 's/.*"time_imbalance":\[\([^]]*\)\].*/\1/p' "$out/tiled/stats.json")
  echo "imbalance (max/mean of reported time) per frame, camera orbiting $orbit degrees a frame: $imb"
  echo "$imb" | tr ',' '\n' | awk -v m="$max" 'NR > 2 { if ($1 == "null" || $1 + 0 > m + 0) { print "frame " NR - 1 ": imbalance " $1 " above " m; b = 1 } } END { exit b }' >&2 ||
    bad=1
  rows "$out/tiled/stats.json" server_pixels >"$out/pixels"
  echo "regions (pixels per server) per frame:"; cat "$out/pixels" ;;
records)
  # what the program prints (selection and feedback records) and every
  # frame: the same as APP-native's through render, pack -> node -> render
  # and tilesort on CONFIG
  app=$1 frames=$2 config=$3
  shift 3
  "$bin/$app-native" --frames "$frames" --size $SIZE --out "$out/ref-%04d.png" >"$out/ref.out" ||
    fail "$app-native failed"
  same_output() { # WHAT FILE
    if cmp -s "$out/ref.out" "$2"; then
      echo "$1: the same $(wc -l <"$2") lines as $app-native"
    else
      fail "$1: the output differs from $app-native's:"
      diff "$out/ref.out" "$2" | head -n 20 | cut -c1-300 >&2
    fi
  }
  same_frames() { # WHAT PATTERN_PREFIX
    f=0
    while [ $f -lt "$frames" ]; do
      n=$(printf %04d $f)
      d=$(pixels "$out/ref-$n.png" "$2-$n.png")
      echo "$1 frame $f: $d pixels differ from $app-native"
      [ "$d" = 0 ] || fail "$1 frame $f: $d pixels differ from $app-native"
      f=$((f + 1))
    done
  }
  mkdir -p "$out/render" "$out/pack"
  timeout 120 "$bin/$app" --frames "$frames" --size $SIZE --chain "render output=\"$out/render/f-%04d.png\"" \
    >"$out/render/app.out" 2>"$out/render/app.err" || { fail "$app through render failed"; cat "$out/render/app.err" >&2; }
  same_output render "$out/render/app.out"
  same_frames render "$out/render/f"
  start_node "$out/pack/node" --listen tcp://127.0.0.1:0 --clients 1 --timeout-ms 120000 \
    --chain "render output=\"$out/pack/f-%04d.png\"" || exit 1
  PIDS=$NODE_PID
  timeout 120 "$bin/$app" --frames "$frames" --size $SIZE --chain "pack server=\"$NODE_ADDR\"" \
    >"$out/pack/app.out" 2>"$out/pack/app.err" || { fail "$app through pack failed"; cat "$out/pack/app.err" >&2; }
  wait_exit "$NODE_PID" 30
  [ "$EXIT_RC" = 0 ] || { fail "the node exited $EXIT_RC"; cat "$out/pack/node.err" >&2; }
  PIDS=
  same_output "pack -> node" "$out/pack/app.out"
  same_frames "pack -> node" "$out/pack/f"
  run_tilesort "$out/tiled" "$app" "$frames" "$config" "$@"
  same_output "tilesort $config" "$out/tiled/app.out"
  exact_frames "$out/tiled" "$app" "$frames" "$config" ;;
exact)
  app=$1 frames=$2 config=$3
  shift 3
  "$bin/$app-native" --frames "$frames" --size 1024x768 --out "$out/ref-%04d.png" >/dev/null ||
    fail "$app-native failed"
  run_tilesort "$out/tiled" "$app" "$frames" "$config" "$@"
  exact_frames "$out/tiled" "$app" "$frames" "$config"
  case $config in kd | union | balance)
    # the servers' real costs: a fresh window's pages fault in during the
    # first frame, so some server puts a part of its time down to faults
    # (the node measures a fault's cost at its first report with faults),
    # never more than the time itself
    rows "$out/tiled/stats.json" server_seconds >"$out/seconds"
    rows "$out/tiled/stats.json" server_fault_seconds >"$out/faults"
    paste -d';' "$out/seconds" "$out/faults" | awk -F';' '{ n = split($1, s, ","); m = split($2, f, ",")
        if (n != m) print "frame " NR - 1 ": " m " fault times for " n " servers"
        for (i = 1; i <= n; i++) {
          if (f[i] == "null") continue
          if (f[i] + 0 < 0 || f[i] + 0 > s[i] + 0) print "frame " NR - 1 ": server " i - 1 " fault seconds " f[i] " outside 0.." s[i]
          if (f[i] + 0 > 0) any = 1 } }
      END { if (!any) print "no server reported any fault seconds (their first frames touch fresh pages)" }' >"$out/badfaults"
    sed 's/^/FAIL: /' "$out/badfaults" >&2
    [ -s "$out/badfaults" ] && bad=1 ;;
  esac ;;
split)
  app=$1 frames=$2 frame=$3 max=$4
  shift 4
  "$bin/$app-native" --frames "$frames" --size 1024x768 --out "$out/ref-%04d.png" >/dev/null ||
    fail "$app-native failed"
  run_tilesort "$out/one" "$app" "$frames" 1x1 "$@"
  exact_frames "$out/one" "$app" "$frames" 1x1
  run_tilesort "$out/wall" "$app" "$frames" 4x4 "$@"
  exact_frames "$out/wall" "$app" "$frames" 4x4
  one=$(frame_bytes "$out/one/stats.json" "$frame")
  wall=$(frame_bytes "$out/wall/stats.json" "$frame")
  overlap=$(awk -v a="$wall" -v b="$one" 'BEGIN { if (b > 0) printf "%.3f", a / b; else print "none" }')
  echo "frame $frame on 4x4: $wall bytes to the servers, $one on 1x1: overlap $overlap (must be below $max)"
  awk -v o="$overlap" -v m="$max" 'BEGIN { exit !(o != "none" && o + 0 < m + 0) }' ||
    fail "frame $frame: overlap $overlap is not below $max (the long primitives reached too many servers)" ;;
bad)
  tiles=$1 bucket=$2 word=$3
  start_node "$out/node" --listen tcp://127.0.0.1:0 --clients 1 --timeout-ms 5000 \
    --chain "render output=\"$out/f-%04d.png\"" || exit 1
  PIDS=$NODE_PID
  "$bin/texquads" --frames 1 --size 1024x768 \
    --chain "tilesort servers=$NODE_ADDR bucket=$bucket tiles=$tiles" >"$out/app.out" 2>"$out/app.err" &
  apid=$!
  wait_exit "$apid" 10
  cat "$out/app.err"
  case $EXIT_RC in 0|timeout) fail "tilesort with tiles=$tiles exited $EXIT_RC" ;; esac
  grep -q -- "$word" "$out/app.err" || fail "the message does not name '$word'"
  [ "$(wc -l <"$out/app.err")" -le 2 ] || fail "more than two lines of errors"
  kill_all ;;
*) echo "unknown mode $mode" >&2; exit 2 ;;
esac
kill_all
[ $bad = 0 ] && echo PASS
exit $bad
