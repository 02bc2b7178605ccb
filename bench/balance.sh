#!/usr/bin/env bash
# bench/balance.sh — sort-first load balancing (issue 13): tilesort's
# bucket=grid, union (GRID_UNION) and kd (KD-SPLIT) on the static
# marching-cubes isosurface (examples/isosurface --static: before, the
# field moved and the camera turned 8 degrees a frame), one real `tessera node`
# render server per region, llvmpipe on the chain's thread
# (LP_NUM_THREADS=0) so the servers' thread CPU time is their render time.
#
# 1. 8x4 (32 servers) at BALANCE_SIZE (default 2048x1536), BALANCE_FRAMES
#    frames (10): per frame
#      imbalance = max / mean of the servers' measured render time (the
#                  thread CPU time each server reports after each swap)
#      overlap   = bytes to all servers / bytes the 1x1 run sent that frame
#    figures balance_METHOD_imbalance_8x4_fN, balance_METHOD_overlap_8x4_fN
#    for N = 3 and 10 (frame N counted from 1), next to the same frame's
#    byte imbalance (balance_METHOD_imbalance_bytes_8x4_fN) and the part
#    of the overlap that is not geometry (balance_METHOD_overlap_commands_8x4_fN:
#    the servers' state diffs, tiles, window and frame commands less the
#    1x1 run's, over the 1x1 run's bytes; tilesort's frames_geometry),
#    and the cost model each balanced run's fit reached at its end
#    (balance_METHOD_fitted_model_8x4: seconds fixed, a byte, a box pixel,
#    a region pixel; tilesort.h's priors are kd's on a quiet machine).
#    union and kd run BALANCE_REPEATS times (default 3; balance_repeats.csv):
#    balance_METHOD_imbalance_8x4_fN_median is the median of frame N over the
#    runs (a single frame holds the machine's noise, part 4), and per run
#    balance_METHOD_after_f3_8x4_runK: the median imbalance of frames 4..N,
#    how many are above 1.2 and how often the split moved after frame 3
#    (the servers' pixel counts changed).
# 2. The frame time of the slowest server against server count (1 .. 32:
#    1x1 2x1 2x2 4x2 4x4 8x4) for grid, union, kd and broadcast at
#    BALANCE_SWEEP_SIZE (default 1024x768), BALANCE_SWEEP_FRAMES (5): on one
#    machine this is the maximum over servers of their measured render CPU
#    time plus their bytes at BALANCE_NET_MBPS (default 1000 Mbit/s),
#    the median over the frames after the first; the 1x1 run's is the
#    reference (one server doing all). Figures balance_slowest_ms_METHOD_32.
# 3. Frames to converge after a camera jump (isosurface --jump
#    BALANCE_JUMP, default 4: the camera turns 90 degrees at that frame),
#    8x4 at BALANCE_SIZE, BALANCE_JUMP_FRAMES (12) frames, for union and
#    kd with the defaults and for kd with the alternatives of damping and
#    hysteresis (BALANCE_ALTS): per frame the imbalance; the figure
#    balance_VARIANT_jump_frames_8x4 is how many frames after the jump the
#    imbalance is first back at or under 1.2 and stays there (the frame
#    of the jump counts 1; "never" if it does not within the run).
#    Also balance_VARIANT_jump_first_8x4: frames from the jump until the
#    imbalance is first at or under 1.2 (the noise of part 4 can lift a
#    later frame above it again), and balance_VARIANT_jump_settled_8x4:
#    frames from the jump to the split's last move in the run (it stays from
#    there on), with the median imbalance of the frames after it.
# 4. The noise floor (a lower bound on the measured imbalance on this
#    machine): kd with its defaults on the static isosurface for
#    BALANCE_FLOOR_FRAMES (20) frames at BALANCE_SIZE; once the split has
#    settled (hysteresis; BALANCE_FLOOR_OPTIONS adds tilesort options,
#    e.g. hysteresis=1 to keep a split on a loaded machine), the servers' times
#    on unchanged regions vary only by measurement noise. Per frame from
#    the split's last move on (at least 5 frames): max / mean over the servers of T / (the server's own mean T
#    over those frames), which even a perfect split would show; figures
#    balance_noise_floor_8x4 (median over the frames, with the smallest
#    and largest) and balance_kd_systematic_8x4 (max / mean of the
#    servers' mean times: the split's own imbalance, with the noise
#    averaged out), balance_noise_floor_over_1_2_8x4 (how many of those
#    frames a perfect split would see above 1.2), balance_noise_sd_8x4 (the servers' median frame-to-frame
#    relative standard deviation) and the load average.
# Writes balance.csv, balance_repeats.csv, balance_servers.csv, balance_jump.csv, balance_floor.csv, balance.png
# (imbalance and overlap per frame), balance_servers.png and
# balance_jump.png. BALANCE_PARTS (default "1 2 3 4") picks the parts.
# usage: bench/balance.sh BIN_DIR OUT_DIR [--quick]
set -euo pipefail
bin=$1 out=$2 quick=${3:-}
size=${BALANCE_SIZE:-2048x1536} frames=${BALANCE_FRAMES:-10} detail=${BALANCE_DETAIL:-2}
ssize=${BALANCE_SWEEP_SIZE:-1024x768} sframes=${BALANCE_SWEEP_FRAMES:-5} mbps=${BALANCE_NET_MBPS:-1000}
wall=8x4 sweep=(1x1 2x1 2x2 4x2 4x4 8x4) parts=${BALANCE_PARTS:-1 2 3 4}
ffloor=${BALANCE_FLOOR_FRAMES:-20} repeats=${BALANCE_REPEATS:-3}
jump=${BALANCE_JUMP:-4} jframes=${BALANCE_JUMP_FRAMES:-12}
alts=${BALANCE_ALTS:-kd:damping=1:hysteresis=0 kd:damping=0.5:hysteresis=0.1 kd:damping=1:hysteresis=0.2 kd:damping=1:hysteresis=0.1:smoothing=1}
if [[ $quick == --quick ]]; then
    size=256x192 frames=10 detail=1 ssize=256x192 sframes=3 wall=2x2 sweep=(1x1 2x1 2x2) ffloor=8 repeats=1
fi
work=$out/balance.work
rm -rf "$work" && mkdir -p "$work"
TESSERA=$bin/tessera
. "$(dirname "$0")/../tests/node/node_lib.sh"

. "$(dirname "$0")/walls.sh"

# awk: med(a, n), the median of a[1..n] (sorts a in place)
awk_median='function med(a, n,   i, j, x) { for (i = 2; i <= n; i++) { x = a[i]; for (j = i - 1; j >= 1 && a[j] > x; j--) a[j + 1] = a[j]; a[j + 1] = x }
    return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2 }
'

# run SIZE FRAMES CONFIG BUCKET STATS [SCENE [OPTIONS]]: servers for CONFIG,
# the isosurface (SCENE: its motion options, default --static) through
# tilesort with OPTIONS, statistics into STATS.
run() {
    local sz=$1 nf=$2 config=$3 bucket=$4 stats=$5 scene=${6:---static} extra=${7:-}
    local cols=${config%x*} rows=${config#*x} n servers= k dir tiles=
    n=$((cols * rows))
    dir=$work/$sz-$config-$bucket${extra:+-${extra// /-}}${scene// /}
    mkdir -p "$dir"
    PIDS=
    for ((k = 0; k < n; k++)); do
        LP_NUM_THREADS=0 start_node "$dir/node$k" --listen tcp://127.0.0.1:0 --clients 1 --timeout-ms 300000 \
            --chain 'render output=""' || { echo "bench/balance: server $k did not start" >&2; exit 1; }
        PIDS="$PIDS $NODE_PID"
        servers="$servers${servers:+,}$NODE_ADDR"
    done
    case $bucket in grid | broadcast) tiles="tiles=$(tiles_for "$cols" "$rows" "${sz%x*}" "${sz#*x}")" ;; esac
    if ! TESSERA_STATS_FILE=$stats LP_NUM_THREADS=0 "$bin/isosurface" $scene --frames "$nf" --detail "$detail" --size "$sz" \
        --chain "tilesort servers=$servers $tiles bucket=$bucket timeout_ms=300000 $extra" \
        >"$dir/app.out" 2>"$dir/app.err"; then
        cat "$dir/app.err" >&2
        echo "bench/balance: isosurface failed ($config, $bucket)" >&2
        exit 1
    fi
    for p in $PIDS; do wait "$p" || { echo "bench/balance: a server failed ($config)" >&2; exit 1; }; done
    PIDS=
}

# rows STATS KEY: the rows of a sort_first array of arrays, one a line.
rows() { sed -n "s/.*\"$2\":\[\[\([^]]*\(\],\[[^]]*\)*\)\]\].*/\1/p" "$1" | sed 's/\],\[/\n/g'; }

# imbalances STATS: the measured imbalance per frame, one a line ("nan" when a report is missing).
imbalances() {
    rows "$1" server_seconds | awk -F, '{ smax = 0; ssum = 0; ok = 1
        for (i = 1; i <= NF; i++) { if ($i == "null") ok = 0; ssum += $i; if ($i + 0 > smax) smax = $i + 0 }
        if (ok && ssum > 0) printf "%.4f\n", smax * NF / ssum; else print "nan" }'
}

load() { echo "bench/balance: part $1, load average $(cut -d' ' -f1-3 /proc/loadavg)"; }

# --- 1. the 8x4 wall, per frame ----------------------------------------------
if [[ " $parts " == *" 1 "* ]]; then
load 1
csv=$out/balance.csv
echo "method,tiles,frame,imbalance,imbalance_bytes,overlap,overlap_commands" >"$csv"
run "$size" "$frames" 1x1 grid "$work/one.json"
rows "$work/one.json" frames >"$work/one.bytes"
rows "$work/one.json" frames_geometry >"$work/one.geo"
for method in grid union kd; do
    st=$work/wall-$method.json
    run "$size" "$frames" "$wall" "$method" "$st"
    rows "$st" server_seconds >"$work/$method.secs"
    rows "$st" frames >"$work/$method.bytes"
    rows "$st" frames_geometry >"$work/$method.geo"
    paste -d';' "$work/$method.secs" "$work/$method.bytes" "$work/one.bytes" "$work/$method.geo" "$work/one.geo" |
        awk -F';' -v m="$method" -v t="$wall" '{
            n = split($1, s, ","); split($2, b, ","); split($3, o, ","); split($4, g, ","); split($5, og, ",")
            smax = 0; ssum = 0; bmax = 0; bsum = 0; gsum = 0; ok = 1
            for (i = 1; i <= n; i++) { if (s[i] == "null") ok = 0; ssum += s[i]; if (s[i] + 0 > smax) smax = s[i] + 0
                                        bsum += b[i]; gsum += g[i]; if (b[i] + 0 > bmax) bmax = b[i] + 0 }
            imb = ok && ssum > 0 ? sprintf("%.4f", smax * n / ssum) : "nan"
            printf "%s,%s,%d,%s,%.4f,%.4f,%.6f\n", m, t, NR, imb, bmax * n / bsum, bsum / o[1],
                   (bsum - gsum - (o[1] - og[1])) / o[1] }' >>"$csv"
done
for method in grid union kd; do
    for f in 3 10; do
        awk -F, -v m="$method" -v f="$f" -v t="$wall" '$1 == m && $3 == f {
            printf "balance_%s_imbalance_%s_f%d: %s\n", m, t, f, $4
            printf "balance_%s_imbalance_bytes_%s_f%d: %s\n", m, t, f, $5
            printf "balance_%s_overlap_%s_f%d: %s\n", m, t, f, $6
            printf "balance_%s_overlap_commands_%s_f%d: %s\n", m, t, f, $7 }' "$csv"
    done
done
# The balanced methods again, BALANCE_REPEATS runs in all: a single frame's
# imbalance holds the machine's noise (part 4: a perfect split's frames
# reach 1.2-1.6 here now and then), so f3 and f10 are the median over the
# runs, each run's value beside it; and per run, what follows frame 3: the
# median imbalance of frames 4..N, how many of them are above 1.2, and how
# often the split moved after frame 3 (an oscillating balancer moves it
# every frame or two).
rcsv=$out/balance_repeats.csv
echo "method,run,frame,imbalance,moved" >"$rcsv"
for method in union kd; do
    for ((r = 1; r <= repeats; r++)); do
        st=$work/wall-$method.json
        ((r > 1)) && st=$work/wall-$method-run$r.json && run "$size" "$frames" "$wall" "$method" "$st"
        rows "$st" server_pixels >"$work/$method.pixels"
        imbalances "$st" | paste -d, - "$work/$method.pixels" | awk -F, -v m="$method" -v r="$r" '{
            key = $0; sub(/^[^,]*,/, "", key); moved = NR > 1 && key != prev; prev = key
            printf "%s,%d,%d,%s,%d\n", m, r, NR, $1, moved }' >>"$rcsv"
    done
    for f in 3 10; do
        awk -F, -v m="$method" -v f="$f" -v t="$wall" "$awk_median"'
            $1 == m && $3 == f { v[++n] = $4; runs = runs (runs == "" ? "" : " ") $4 }
            END { printf "balance_%s_imbalance_%s_f%d_median: %.4f (%d runs: %s)\n", m, t, f, med(v, n), n, runs }' "$rcsv"
    done
    awk -F, -v m="$method" -v t="$wall" "$awk_median"'
        $1 == m && $3 > 3 { k = $2; n[k]++; v[k, n[k]] = $4; over[k] += $4 + 0 > 1.2 || $4 == "nan"; moves[k] += $5; if (k > runs) runs = k }
        END { for (k = 1; k <= runs; k++) { for (i = 1; i <= n[k]; i++) w[i] = v[k, i]
                printf "balance_%s_after_f3_%s_run%d: median %.4f, %d of %d frames above 1.2, the split moved %d times\n", m, t, k, med(w, n[k]), over[k], n[k], moves[k] } }' "$rcsv"
done
# the coefficients each balanced run's fit reached (tilesort.h's priors are this on a quiet machine)
for method in union kd; do
    sed -n 's/.*"cost_model":{\([^}]*\)}.*/\1/p' "$work/wall-$method.json" | tr -d '"' |
        awk -v m="$method" -v t="$wall" '{ printf "balance_%s_fitted_model_%s: %s\n", m, t, $0 }'
done

fi

# --- 2. the slowest server against server count ---------------------------------
if [[ " $parts " == *" 2 "* ]]; then
load 2
scsv=$out/balance_servers.csv
echo "method,tiles,servers,slowest_ms,render_ms,net_ms" >"$scsv"
for config in "${sweep[@]}"; do
    n=$((${config%x*} * ${config#*x}))
    for method in grid union kd broadcast; do
        [[ $config == 1x1 && $method != grid ]] && continue
        st=$work/sweep-$config-$method.json
        run "$ssize" "$sframes" "$config" "$method" "$st"
        rows "$st" server_seconds >"$work/s.secs"
        rows "$st" frames >"$work/s.bytes"
        # per frame after the first: the slowest server's render + bytes at the rate; the median frame
        line=$(paste -d';' "$work/s.secs" "$work/s.bytes" | tail -n +2 | awk -F';' -v r="$mbps" '{
                n = split($1, s, ","); split($2, b, ","); worst = 0
                for (i = 1; i <= n; i++) { t = s[i] + b[i] * 8 / (r * 1e6); if (t > worst) { worst = t; ws = s[i]; wb = b[i] * 8 / (r * 1e6) } }
                printf "%.3f %.3f %.3f\n", 1000 * worst, 1000 * ws, 1000 * wb }' | sort -g | awk '{ v[NR] = $0 } END { print v[int((NR + 1) / 2)] }')
        read -r slowest render net <<<"$line"
        echo "$method,$config,$n,$slowest,$render,$net" >>"$scsv"
        [[ $config == 1x1 ]] && for m in union kd broadcast; do echo "$m,$config,$n,$slowest,$render,$net" >>"$scsv"; done
    done
done
awk -F, 'NR > 1 && $2 == "1x1" && $1 == "grid" { printf "balance_slowest_ms_one_server: %s\n", $4 }' "$scsv"
last=${sweep[${#sweep[@]} - 1]}
awk -F, -v t="$last" 'NR > 1 && $2 == t { printf "balance_slowest_ms_%s_%d: %s (render %s + net %s)\n", $1, $3, $4, $5, $6 }' "$scsv"
fi

# --- 3. frames to converge after a camera jump ----------------------------------
jcsv=$out/balance_jump.csv
if [[ " $parts " == *" 3 "* ]]; then
    load 3
    echo "variant,frame,imbalance,moved" >"$jcsv"
    for v in union kd $alts; do
        method=${v%%:*} extra=
        [[ $v == *:* ]] && extra=${v#*:} && extra=${extra//:/ }
        st=$work/jump-${v//[:=]/_}.json
        run "$size" "$jframes" "$wall" "$method" "$st" "--jump $jump" "$extra"
        rows "$st" server_pixels >"$work/jump.pixels"
        imbalances "$st" | paste -d, - "$work/jump.pixels" | awk -F, -v v="$v" '{
            key = $0; sub(/^[^,]*,/, "", key); moved = NR > 1 && key != prev; prev = key
            printf "%s,%d,%s,%d\n", v, NR, $1, moved }' >>"$jcsv"
    done
    # frames from the jump (frame jump+1 counted from 1) until <= 1.2 for good
    awk -F, -v j="$jump" -v t="$wall" "$awk_median"'NR > 1 { v[$1] = 1; imb[$1, $2] = $3; mv[$1, $2] = $4; if ($2 + 0 > last) last = $2 + 0 }
        END { for (k in v) { conv = "never"
                for (f = last; f > j; f--) { if (imb[k, f] == "nan" || imb[k, f] + 0 > 1.2) break; conv = f - j }
                first = "never"
                for (f = j + 1; f <= last; f++) if (imb[k, f] != "nan" && imb[k, f] + 0 <= 1.2) { first = f - j; break }
                settled = 0; for (f = j + 1; f <= last; f++) if (mv[k, f]) settled = f - j
                cnt = 0; for (f = j + settled + 1; f <= last; f++) if (imb[k, f] != "nan") w[++cnt] = imb[k, f] + 0
                after = cnt ? sprintf("%.4f", med(w, cnt)) : "none"
                n = k; gsub(/[:=]/, "_", n); printf "balance_%s_jump_frames_%s: %s\n", n, t, conv
                printf "balance_%s_jump_settled_%s: %d (the split last moved that many frames after the jump; median imbalance after: %s)\n", n, t, settled, after
                printf "balance_%s_jump_first_%s: %s\n", n, t, first } }' "$jcsv" | sort
fi

# --- 4. the noise floor: a fixed split's frame-to-frame noise ---------------------
fcsv=$out/balance_floor.csv
if [[ " $parts " == *" 4 "* ]]; then
    load 4
    st=$work/floor.json
    run "$size" "$ffloor" "$wall" kd "$st" --static "${BALANCE_FLOOR_OPTIONS:-}"
    rows "$st" server_seconds >"$work/floor.secs"
    rows "$st" server_pixels >"$work/floor.pixels"
    # the frames from the last move of the split on (at least 5 of them)
    total=$(wc -l <"$work/floor.pixels") from=$total
    while ((from > 4)) && [ "$(sed -n "$((from - 1))p" "$work/floor.pixels")" = "$(tail -n 1 "$work/floor.pixels")" ]; do
        from=$((from - 1))
    done
    ((total - from + 1 >= 5)) || echo "bench/balance: the floor run's split moved until frame $from (fewer than 5 frames left)" >&2
    echo "frame,imbalance,noise_only" >"$fcsv"
    tail -n +"$from" "$work/floor.secs" | awk -F, -v first="$from" -v csv="$fcsv" -v t="$wall" '
        function sorted(a, n,   i, j, x) { for (i = 2; i <= n; i++) { x = a[i]; for (j = i - 1; j >= 1 && a[j] > x; j--) a[j + 1] = a[j]; a[j + 1] = x }; return n }
        { nf = NF; for (i = 1; i <= NF; i++) { v[NR, i] = $i; sum[i] += $i } ; rowsn = NR }
        END {
            for (i = 1; i <= nf; i++) { mean[i] = sum[i] / rowsn; all += mean[i]; if (mean[i] > mx) mx = mean[i] }
            for (r = 1; r <= rowsn; r++) {
                zs = 0; zm = 0; ts = 0; tm = 0
                for (i = 1; i <= nf; i++) { z = v[r, i] / mean[i]; zs += z; if (z > zm) zm = z; ts += v[r, i]; if (v[r, i] > tm) tm = v[r, i] }
                fl[r] = zm * nf / zs; printf "%d,%.4f,%.4f\n", r + first - 1, tm * nf / ts, fl[r] >>csv }
            n = sorted(fl, rowsn)
            printf "balance_noise_floor_%s: %.4f (median of frames %d-%d, the split unchanged; smallest %.4f, largest %.4f)\n", t, (n % 2 ? fl[(n + 1) / 2] : (fl[n / 2] + fl[n / 2 + 1]) / 2), first, rowsn + first - 1, fl[1], fl[n]
            for (r = 1; r <= rowsn; r++) over += fl[r] > 1.2
            printf "balance_noise_floor_over_1_2_%s: %d of %d frames (a perfect split'"'"'s imbalance above 1.2 from noise alone)\n", t, over, rowsn
            printf "balance_kd_systematic_%s: %.4f (max / mean of the servers'"'"' mean times, frames %d-%d)\n", t, mx * nf / all, first, rowsn + first - 1
            for (i = 1; i <= nf; i++) { ss = 0; for (r = 1; r <= rowsn; r++) ss += (v[r, i] / mean[i] - 1) ^ 2; sd[i] = sqrt(ss / (rowsn - 1)) }
            m = sorted(sd, nf)
            printf "balance_noise_sd_%s: %.4f (median over the servers of the relative sd of a server'"'"'s time)\n", t, (m % 2 ? sd[(m + 1) / 2] : (sd[m / 2] + sd[m / 2 + 1]) / 2) }'
fi

if command -v gnuplot >/dev/null && [[ $quick != --quick && " $parts " == *" 3 "* ]]; then
    gnuplot <<EOF || echo "bench/balance: gnuplot failed (jump chart skipped)" >&2
set terminal pngcairo size 900,480
set output "$out/balance_jump.png"
set datafile separator ","
set title "Camera turned 90 degrees at frame $((jump + 1)) (isosurface --jump $jump), ${size}, $wall servers\nimbalance = max / mean of the servers' measured render CPU time"
set xlabel "frame"
set ylabel "imbalance"
set key top right
plot for [v in "union kd $alts"] "< grep '^".v.",' $jcsv" using 2:3 with linespoints title v, 1.2 with lines dt 2 title "1.2"
EOF
fi
if command -v gnuplot >/dev/null && [[ $quick != --quick && " $parts " == *" 1 "* && " $parts " == *" 2 "* ]]; then
    gnuplot <<EOF || echo "bench/balance: gnuplot failed (charts skipped)" >&2
set terminal pngcairo size 1000,420
set output "$out/balance.png"
set datafile separator ","
set multiplot layout 1,2 title "Static isosurface (--detail $detail) on a ${size} window, $wall servers"
set xlabel "frame"
set key top right
set ylabel "imbalance (max / mean server render CPU time)"
plot for [m in "grid union kd"] "< grep ^".m.", $csv" using 3:4 with linespoints title m, 1.2 with lines dt 2 title "target 1.2"
set ylabel "overlap (bytes to all servers / 1x1 bytes)"
plot for [m in "grid union kd"] "< grep ^".m.", $csv" using 3:6 with linespoints title m, 1.1 with lines dt 2 title "target 1.1"
unset multiplot
set output "$out/balance_servers.png"
set terminal pngcairo size 900,480
set title "Slowest server per frame (${ssize}): max over servers of render CPU time + bytes at ${mbps} Mbit/s\n(one machine: the servers share its cores; median frame)"
set xlabel "servers"
set logscale x 2
set ylabel "ms"
plot for [m in "grid union kd broadcast"] "< grep ^".m.", $scsv" using 3:4 with linespoints title m
EOF
fi
