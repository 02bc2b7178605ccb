#!/usr/bin/env bash
# bench/march.sh — sort-first in the shape of WireGL's "March" experiment:
# a marching-cubes isosurface (examples/isosurface --detail 2, about
# 400,000 triangles a frame) on a wall of WxH (default 4096x3072) split
# into 1x1, 2x1, 2x2, 4x2, 4x4 and 8x4 tiles, one real `tessera node`
# render server per tile, through tilesort with bucket=grid and with
# bucket=broadcast. From each run's statistics (TESSERA_STATS_FILE,
# "sort_first": bytes per server per frame, application frame times):
#   efficiency  = bytes sent in the 1x1 configuration / bytes sent in this
#                 one, as a percentage (100: no overlap at all)
#   overlap     = bytes sent / stream bytes packed once
#   imbalance   = max / mean of the servers' bytes (the CSV's column; the
#                 figure is march_imbalance_bytes_*)
#   frame_ms    = median application time per frame (frames after the first)
# Then the stability scenes of examples/tilescenes (frame 8: every
# primitive covers the window; frame 9: a state change between every
# primitive) on 4x4 tiles: their overlap with tilesort next to broadcast.
# Figures: march_efficiency_2x2 march_efficiency_4x4 march_efficiency_8x4
# broadcast_efficiency_8x4 (+ march_overlap_8x4, march_imbalance_bytes_8x4 (max / mean
# of the servers' bytes; bench/balance.sh measures render time),
# stability_all_tiles_overlap_4x4, stability_tiny_batches_overlap_4x4,
# stability_broadcast_overlap_4x4). Writes march.csv, march.png (frame time
# and overlap, tilesort vs broadcast), march_imbalance.png (overlap vs load
# imbalance as tiles shrink) and stability.csv.
# usage: bench/march.sh BIN_DIR OUT_DIR [--quick]
# Environment: MARCH_SIZE (default 4096x3072), MARCH_DETAIL (2),
# MARCH_FRAMES (3), MARCH_BATCH (tilesort batch_bytes; default: tilesort's),
# MARCH_CONFIGS (default "1x1 2x1 2x2 4x2 4x4 8x4"; 1x1 must come first),
# MARCH_BUCKETS (default "grid broadcast").
set -euo pipefail
bin=$1 out=$2 quick=${3:-}
size=${MARCH_SIZE:-4096x3072} detail=${MARCH_DETAIL:-2} frames=${MARCH_FRAMES:-3}
batch=${MARCH_BATCH:+batch_bytes=$MARCH_BATCH}
read -r -a configs <<<"${MARCH_CONFIGS:-1x1 2x1 2x2 4x2 4x4 8x4}"
if [[ $quick == --quick ]]; then
    size=512x384 detail=1 frames=2 configs=(1x1 2x1 2x2)
fi
width=${size%x*} height=${size#*x}
work=$out/march.work
rm -rf "$work" && mkdir -p "$work"
TESSERA=$bin/tessera
. "$(dirname "$0")/../tests/node/node_lib.sh"

. "$(dirname "$0")/walls.sh"

# run APP ARGS CONFIG BUCKET STATS: servers for CONFIG, the app through
# tilesort, statistics into STATS. Fails loudly when a process fails.
run() {
    local app=$1 args=$2 config=$3 bucket=$4 stats=$5
    local cols=${config%x*} rows=${config#*x} n servers= k dir
    n=$((cols * rows))
    dir=$work/$app-$config-$bucket   # fresh files: start_node reads the address a node prints
    mkdir -p "$dir"
    PIDS=
    for ((k = 0; k < n; k++)); do
        start_node "$dir/node$k" --listen tcp://127.0.0.1:0 --clients 1 --timeout-ms 120000 \
            --chain 'render output=""' || { echo "bench/march: server $k did not start" >&2; exit 1; }
        PIDS="$PIDS $NODE_PID"
        servers="$servers${servers:+,}$NODE_ADDR"
    done
    # shellcheck disable=SC2086
    if ! TESSERA_STATS_FILE=$stats LP_NUM_THREADS=${LP_NUM_THREADS:-1} "$bin/$app" $args --size "$size" \
        --chain "tilesort servers=$servers tiles=$(tiles_for "$cols" "$rows" "$width" "$height") bucket=$bucket $batch timeout_ms=120000" \
        >"$dir/app.out" 2>"$dir/app.err"; then
        cat "$dir/app.err" >&2
        echo "bench/march: $app failed ($config, $bucket)" >&2
        exit 1
    fi
    for p in $PIDS; do wait "$p" || { echo "bench/march: a server failed ($config)" >&2; exit 1; }; done
    PIDS=
}

# field STATS KEY: a number of the "sort_first" object.
field() { sed -e 's/.*"sort_first"://' -n -e "s/.*\"$2\":\([-0-9.e+]*\).*/\1/p" "$1" | head -n 1; }
# median_ms STATS: median frame time (ms) over frames after the first.
median_ms() {
    sed -e 's/.*"frame_seconds":\[\([^]]*\)\].*/\1/' "$1" | tr ',' '\n' | tail -n +2 | sort -g |
        awk '{ v[NR] = $1 } END { if (NR == 0) print 0; else printf "%.1f", 1000 * v[int((NR + 1) / 2)] }'
}
# frame_bytes STATS FRAME: bytes sent to all servers in that frame.
frame_bytes() {
    sed -e 's/.*"frames":\[\[//' -e 's/\]\].*//' "$1" | sed 's/\],\[/\n/g' | sed -n "$(($2 + 1))p" |
        tr ',' '\n' | awk '{ s += $1 } END { print s + 0 }'
}

csv=$out/march.csv
echo "tiles,servers,bucket,bytes,efficiency_pct,overlap,imbalance,frame_ms" >"$csv"
base=0
for config in "${configs[@]}"; do
    n=$((${config%x*} * ${config#*x}))
    for bucket in ${MARCH_BUCKETS:-grid broadcast}; do
        [[ $config == 1x1 && $bucket == broadcast ]] && continue
        stats=$work/$config-$bucket.json
        run isosurface "--frames $frames --detail $detail" "$config" "$bucket" "$stats"
        bytes=$(field "$stats" bytes_out)
        [[ $config == 1x1 ]] && base=$bytes
        line=$(awk -v c="$config" -v n="$n" -v b="$bucket" -v bytes="$bytes" -v base="$base" \
            -v o="$(field "$stats" overlap)" -v i="$(field "$stats" imbalance)" -v ms="$(median_ms "$stats")" \
            'BEGIN { printf "%s,%d,%s,%.0f,%.2f,%.4f,%.4f,%s", c, n, b, bytes, 100 * base / bytes, o, i, ms }')
        echo "$line" >>"$csv"
        # one server: broadcast is the same run (the charts start there)
        [[ $config == 1x1 ]] && echo "${line/,grid,/,broadcast,}" >>"$csv"
    done
done
for config in 2x2 4x4 8x4; do
    v=$(awk -F, -v c="$config" '$1 == c && $3 == "grid" { print $5 }' "$csv")
    [[ -n $v ]] && echo "march_efficiency_$config: $v"
done
v=$(awk -F, '$1 == "8x4" && $3 == "broadcast" { print $5 }' "$csv")
[[ -n $v ]] && echo "broadcast_efficiency_8x4: $v"
v=$(awk -F, '$1 == "8x4" && $3 == "grid" { print $6 " " $7 }' "$csv")
[[ -n $v ]] && echo "march_overlap_8x4: ${v% *}" && echo "march_imbalance_bytes_8x4: ${v#* }"

# --- stability: the scenes where sort-first degrades ------------------------
scfg=4x4
[[ $quick == --quick ]] && scfg=2x2
scsv=$out/stability.csv
echo "scene,bucket,tiles,bytes,bytes_1x1,overlap" >"$scsv"
run tilescenes "--frames 10" 1x1 grid "$work/scenes-1x1.json"
for bucket in grid broadcast; do
    run tilescenes "--frames 10" "$scfg" "$bucket" "$work/scenes-$bucket.json"
    for f in 8 9; do
        one=$(frame_bytes "$work/scenes-1x1.json" $f)
        b=$(frame_bytes "$work/scenes-$bucket.json" $f)
        scene=$([[ $f == 8 ]] && echo all_tiles || echo tiny_batches)
        awk -v s="$scene" -v k="$bucket" -v t="$scfg" -v b="$b" -v one="$one" \
            'BEGIN { printf "%s,%s,%s,%.0f,%.0f,%.4f\n", s, k, t, b, one, b / one }' >>"$scsv"
    done
done
awk -F, -v t="$scfg" 'NR > 1 && $2 == "grid" { printf "stability_%s_overlap_%s: %s\n", $1, t, $6 }
    NR > 1 && $2 == "broadcast" && $1 == "tiny_batches" { printf "stability_broadcast_overlap_%s: %s\n", t, $6 }' "$scsv"

if command -v gnuplot >/dev/null && [[ $quick != --quick ]]; then
    gnuplot <<EOF || echo "bench/march: gnuplot failed (charts skipped)" >&2
set terminal pngcairo size 1000,420
set output "$out/march.png"
set datafile separator ","
set multiplot layout 1,2 title "Marching-cubes isosurface (--detail $detail) on a ${size} wall"
set xlabel "servers (tiles)"
set logscale x 2
set key top left
set ylabel "ms per frame (application)"
plot "< grep ',grid,' $csv" using 2:8 with linespoints title "tilesort (grid)", \
     "< grep ',broadcast,' $csv" using 2:8 with linespoints title "broadcast"
set ylabel "overlap (bytes sent / stream)"
set logscale y 2
plot "< grep ',grid,' $csv" using 2:6 with linespoints title "tilesort (grid)", \
     "< grep ',broadcast,' $csv" using 2:6 with linespoints title "broadcast"
unset multiplot
set output "$out/march_imbalance.png"
set terminal pngcairo size 640,420
unset logscale
set title "tilesort: overlap against load imbalance as tiles shrink"
set xlabel "overlap factor"
set ylabel "load imbalance (max / mean server bytes)"
plot "< grep ',grid,' $csv" using 6:7:1 with labels offset 1,1 notitle, "" using 6:7 with linespoints notitle
EOF
fi
