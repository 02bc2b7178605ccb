#!/usr/bin/env bash
# bench/binaryswap.sh — sort-last compositing timed across real processes:
# N in-situ binaryswap peers (each its own process, an application that
# draws nothing, `synthetic=full|ellipse` handing the compositor a generated
# 1920x1080 colour+depth layer instead of the read-back, and skipping the
# application's clears, which the layer replaces) and a separate
# display process (`tessera node`, render writing no PNG), launched by
# `tessera run` over Unix sockets; depth mode, the default lossless codec
# (rle) and strategy (auto). Every peer writes a `stats=` line per frame
# (CLOCK_MONOTONIC, one clock for all processes here): the figure of a
# frame is the time from the LAST peer's layer being handed to the
# compositor (right after its SwapBuffers; the read-back is what synthetic
# replaces) to rank 0's answer from the display node after that node drew
# the assembled frame (one round trip per frame). Median over the frames
# after the first two (the first links the mesh).
# Figures: composite_8x1080p_ms composite_8x1080p_partial_ms
# composite_scaling_nN composite_vs_memcpy composite_peer_rss_mb
# (+ composite_8x1080p_assembled_ms: up to the last peer's final piece
# being final (all compositing done; under gather, the frame assembled on
# rank 0), before the display path; composite_8x1080p_display_path_ms: from
# there to the display's answer (each peer's piece as DrawPixels through its
# own pack stream straight to the display, the display's render drawing the
# pieces between two barriers, rank 0's swap, the round trip);
# composite_8x1080p_peers_cpu_ms: CPU ms per frame of all peer processes
# together (their applications' empty frames included, the display's not),
# which other load on the machine does not inflate, and
# composite_8x1080p_compositing_cpu_ms: that minus 8 x the render-only
# application's CPU per frame (render_only_cpu_ms_per_frame, measured
# alone, with the full-window clears that synthetic peers skip, so it
# understates the compositing: the measured figure is the next one);
# composite_8x1080p_hook_cpu_ms: the
# peers' CPU from the start of binaryswap's frame hook to the frame's
# stats line, measured in the same run, and composite_8x1080p_app_cpu_ms:
# the rest of peers_cpu (the applications' frames and the render's
# one-pixel finish; their clears are skipped; a stats line without
# hook_cpu_ns, from an older build, leaves both unmeasured);
# memcpy_frame_ms, the reference, measured before
# and after the runs, best of both). Writes binaryswap.csv (one row per
# frame), binaryswap-summary.csv and binaryswap.png.
# usage: bench/binaryswap.sh BIN_DIR OUT_DIR [--quick]
# The 8-peer cases (the figures) run BINARYSWAP_REPEATS times (default 3)
# and their medians are over the frames of all those runs: one run's
# median moves by 1-2 ms from run to run here (how the scheduler places
# nine processes on two cores), more than within a run.
# Environment: BINARYSWAP_SIZE (default 1920x1080), BINARYSWAP_FRAMES (24),
# BINARYSWAP_COUNTS (default "2 4 8 16"; 8 is the figure), BINARYSWAP_STRATEGY (auto),
# BINARYSWAP_OPTIONS (more binaryswap options as YAML flow entries: "codec: erle"),
# BINARYSWAP_DISPLAY_OPTIONS (more options of the display's render, the same
# way: "fast_drawpixels: false" times glDrawPixels instead of the blit).
set -euo pipefail
bin=$1 out=$2 quick=${3:-}
size=${BINARYSWAP_SIZE:-1920x1080} frames=${BINARYSWAP_FRAMES:-24} strategy=${BINARYSWAP_STRATEGY:-auto}
repeats=${BINARYSWAP_REPEATS:-3}
extra=${BINARYSWAP_OPTIONS:+, $BINARYSWAP_OPTIONS}
display_extra=${BINARYSWAP_DISPLAY_OPTIONS:+, $BINARYSWAP_DISPLAY_OPTIONS}
read -r -a counts <<<"${BINARYSWAP_COUNTS:-2 4 8 16}"
memcpy_args=()
if [[ $quick == --quick ]]; then
    size=128x72 frames=4 counts=(2 8) memcpy_args=(--quick) repeats=${BINARYSWAP_REPEATS:-1}
fi
width=${size%x*} height=${size#*x}
work=$out/binaryswap.work
rm -rf "$work" && mkdir -p "$work"
csv=$out/binaryswap.csv summary=$out/binaryswap-summary.csv
echo "peers,coverage,frame,ready_to_displayed_ms,ready_to_assembled_ms,swap_to_displayed_ms,bytes_sent,assembled_to_sent_ms,sent_to_displayed_ms" >"$csv"
echo "peers,coverage,frames,median_ms,median_assembled_ms,median_bytes_sent,peer_hwm_mib_max,peer_hwm_mib_rank1,median_display_path_ms,median_peers_cpu_ms,median_hook_cpu_ms" >"$summary"

memcpy_ms() { "$bin/bench_memcpy" "${memcpy_args[@]}" | sed -n 's/^memcpy_frame_ms: //p'; }
cpy0=$(memcpy_ms)

# N peers, coverage full|ellipse, run REPEATS times (the frames of all
# runs pooled). Prints "median assembled bytes hwm_max hwm_rank1 frames
# display_path peers_cpu hook_cpu" (hook_cpu "-" when the lines have no hook_cpu_ns).
run_group() {
    local n=$1 cov=$2 repeats=$3 dir=$work/$1-$2 i k
    mkdir -p "$dir"
    {
        echo "version: 1"
        echo "window: {width: $width, height: $height}"
        echo "defaults: {transport: unix}"
        echo "nodes:"
        for ((i = 0; i < n; i++)); do
            echo "  app$i:"
            echo "    exec: bin/spheres --frames $frames --size $size --part 0/1000000"
            echo "    chain: [{binaryswap: {synthetic: $cov, strategy: $strategy, stats: \"$dir/stats.txt\"$extra}}]"
            echo "    to: display"
        done
        echo "  display:"
        echo "    chain: [{render: {output: \"\"$display_extra}}]"
    } >"$dir/graph.yaml"
    local files=()
    for ((k = 1; k <= repeats; k++)); do
        rm -f "$dir/stats.txt"
        if ! LP_NUM_THREADS=0 timeout 600 "$bin/tessera" run "$dir/graph.yaml" --out "$dir/run" --no-progress \
            >"$dir/run.out" 2>"$dir/run.err"; then
            echo "bench/binaryswap.sh: tessera run of $n peers ($cov) failed" >&2
            tail -n 20 "$dir/run.err" >&2
            return 1
        fi
        mv "$dir/stats.txt" "$dir/stats-$k.txt"
        files+=("$dir/stats-$k.txt")
    done
    awk -v n="$n" -v cov="$cov" -v csv="$csv" '
        FNR == 1 { run++; delete lastcpu }
        { for (i = 1; i < NF; i += 2) v[$i] = $(i + 1)
          r = v["rank"]; if (v["frame"] > lastf[run]) lastf[run] = v["frame"]
          f = run SUBSEP v["frame"]
          if (!(f in ready) || v["ready_ns"] > ready[f]) ready[f] = v["ready_ns"]
          if (!(f in swap) || v["swap_ns"] > swap[f]) swap[f] = v["swap_ns"]
          bytes[f] += v["bytes_sent"]
          if (r in lastcpu) cpu[f] += v["cpu_ns"] - lastcpu[r]
          lastcpu[r] = v["cpu_ns"]
          if ("hook_cpu_ns" in v) hook[f] += v["cpu_ns"] - v["hook_cpu_ns"]; else nohook = 1
          # assembled: the last final piece is final (every peer places its
          # own on the display; under gather rank 0 assembles the frame)
          if (v["assembled_ns"] > asm[f]) asm[f] = v["assembled_ns"]
          if (r == 0) { shown[f] = v["displayed_ns"]; sent[f] = v["sent_ns"] }
          if (v["vmhwm_kb"] > hwm) hwm = v["vmhwm_kb"]
          if (r == 1 && v["vmhwm_kb"] > hwm1) hwm1 = v["vmhwm_kb"]
        }
        END {
          m = 0
          for (k = 1; k <= run; k++) for (fr = 2; fr <= lastf[k]; fr++) {
              f = k SUBSEP fr
              if (!(f in shown)) continue
              d = (shown[f] - ready[f]) / 1e6; a = (asm[f] - ready[f]) / 1e6
              printf "%d,%s,%d,%.3f,%.3f,%.3f,%d,%.3f,%.3f\n", n, cov, fr, d, a, (shown[f] - swap[f]) / 1e6, bytes[f], (sent[f] - asm[f]) / 1e6, (shown[f] - sent[f]) / 1e6 >> csv
              ds[m] = d; as[m] = a; bs[m] = bytes[f]; ps[m] = (shown[f] - asm[f]) / 1e6; cs[m] = cpu[f] / 1e6; hs[m] = hook[f] / 1e6; m++
          }
          # medians (insertion sort: a few dozen frames)
          for (i = 1; i < m; i++) for (j = i; j > 0 && ds[j - 1] > ds[j]; j--) { t = ds[j]; ds[j] = ds[j - 1]; ds[j - 1] = t }
          for (i = 1; i < m; i++) for (j = i; j > 0 && as[j - 1] > as[j]; j--) { t = as[j]; as[j] = as[j - 1]; as[j - 1] = t }
          for (i = 1; i < m; i++) for (j = i; j > 0 && bs[j - 1] > bs[j]; j--) { t = bs[j]; bs[j] = bs[j - 1]; bs[j - 1] = t }
          for (i = 1; i < m; i++) for (j = i; j > 0 && ps[j - 1] > ps[j]; j--) { t = ps[j]; ps[j] = ps[j - 1]; ps[j - 1] = t }
          for (i = 1; i < m; i++) for (j = i; j > 0 && cs[j - 1] > cs[j]; j--) { t = cs[j]; cs[j] = cs[j - 1]; cs[j - 1] = t }
          for (i = 1; i < m; i++) for (j = i; j > 0 && hs[j - 1] > hs[j]; j--) { t = hs[j]; hs[j] = hs[j - 1]; hs[j - 1] = t }
          med = m % 2 ? ds[int(m / 2)] : (ds[m / 2 - 1] + ds[m / 2]) / 2
          amed = m % 2 ? as[int(m / 2)] : (as[m / 2 - 1] + as[m / 2]) / 2
          pmed = m % 2 ? ps[int(m / 2)] : (ps[m / 2 - 1] + ps[m / 2]) / 2
          cmed = m % 2 ? cs[int(m / 2)] : (cs[m / 2 - 1] + cs[m / 2]) / 2
          hmed = m % 2 ? hs[int(m / 2)] : (hs[m / 2 - 1] + hs[m / 2]) / 2
          printf "%.3f %.3f %d %.1f %.1f %d %.3f %.3f %s\n", med, amed, bs[int(m / 2)], hwm / 1024, hwm1 / 1024, m, pmed, cmed, nohook ? "-" : sprintf("%.3f", hmed)
        }' "${files[@]}"
}

# The render SPU's own memory for the same application and window: VmHWM
# (ru_maxrss) of the process with the chain `render` alone.
# Its CPU per frame (runs of F and 2F frames: start-up cancels) is what
# each peer's application spends outside compositing.
render_only() { # FRAMES: "maxrss_kb cpu_s"
    LP_NUM_THREADS=0 /usr/bin/time -f '%M %U %S' "$bin/spheres" --frames "$1" --size "$size" \
        --part 0/1000000 --chain 'render output=""' 2>&1 >/dev/null | tail -n 1 | awk '{ print $1, $2 + $3 }'
}
read -r render_hwm_kb render_cpu1 < <(render_only "$frames")
read -r _ render_cpu2 < <(render_only $((2 * frames)))
render_cpu_ms=$(awk -v a="$render_cpu1" -v b="$render_cpu2" -v f="$frames" 'BEGIN { d = (b - a) / f * 1e3; printf "%.3f", d < 0 ? 0 : d }')

declare -A med asm_med path_med cpu_med hook_med
for cov in full ellipse; do
    for n in "${counts[@]}"; do
        [[ $cov == ellipse && $n != 8 ]] && continue
        reps=1
        [[ $n == 8 ]] && reps=$repeats
        read -r m a b hmax h1 count p c hk < <(run_group "$n" "$cov" "$reps") || exit 1
        med[$n-$cov]=$m asm_med[$n-$cov]=$a path_med[$n-$cov]=$p cpu_med[$n-$cov]=$c hook_med[$n-$cov]=$hk
        echo "$n,$cov,$count,$m,$a,$b,$hmax,$h1,$p,$c,$hk" >>"$summary"
        if [[ $cov == full ]]; then
            echo "composite_scaling_n$n: $m"
        fi
        if [[ $n == 8 && $cov == full ]]; then hwm_max=$hmax hwm_1=$h1; fi
    done
done
cpy1=$(memcpy_ms)
cpy=$(awk -v a="$cpy0" -v b="$cpy1" 'BEGIN { print (a < b) ? a : b }')
render_mib=$(awk -v k="$render_hwm_kb" 'BEGIN { printf "%.1f", k / 1024 }')
frame_mib=$(awk -v w="$width" -v h="$height" 'BEGIN { printf "%.1f", w * h * 8 / 1048576 }')
echo "composite_8x1080p_ms: ${med[8-full]}"
echo "composite_8x1080p_assembled_ms: ${asm_med[8-full]}"
echo "composite_8x1080p_display_path_ms: ${path_med[8-full]}"
echo "composite_8x1080p_peers_cpu_ms: ${cpu_med[8-full]}"
echo "render_only_cpu_ms_per_frame: $render_cpu_ms"
awk -v c="${cpu_med[8-full]}" -v r="$render_cpu_ms" 'BEGIN { printf "composite_8x1080p_compositing_cpu_ms: %.3f\n", c - 8 * r }'
for cov in full ellipse; do
    key=composite_8x1080p; [[ $cov == ellipse ]] && key=composite_8x1080p_partial
    if [[ ${hook_med[8-$cov]} == - ]]; then
        echo "${key}_hook_cpu_ms: unmeasured (stats lines without hook_cpu_ns)"
        echo "${key}_app_cpu_ms: unmeasured (stats lines without hook_cpu_ns)"
    else
        echo "${key}_hook_cpu_ms: ${hook_med[8-$cov]}"
        awk -v c="${cpu_med[8-$cov]}" -v h="${hook_med[8-$cov]}" -v k="$key" 'BEGIN { printf "%s_app_cpu_ms: %.3f\n", k, c - h }'
    fi
done
echo "composite_8x1080p_partial_ms: ${med[8-ellipse]}"
echo "composite_8x1080p_partial_assembled_ms: ${asm_med[8-ellipse]}"
echo "memcpy_frame_ms: $cpy"
awk -v c="${med[8-full]}" -v m="$cpy" 'BEGIN { if (m > 0) printf "composite_vs_memcpy: %.3f\n", c / (8 * m); else print "composite_vs_memcpy: unmeasured (memcpy_frame_ms is 0)" }'
awk -v p="$hwm_max" -v r="$render_mib" -v f="$frame_mib" -v p1="$hwm_1" 'BEGIN {
    printf "composite_peer_rss_mb: %.1f\n", p - r
    printf "composite_peer_rss_mb_rank1: %.1f\n", p1 - r
    printf "render_only_hwm_mb: %.1f\n", r
    printf "composite_peer_rss_limit_mb: %.1f\n", 3 * f }'
if command -v gnuplot >/dev/null && [[ $quick != --quick ]]; then
    gnuplot <<EOF || echo "bench/binaryswap.sh: gnuplot failed (chart skipped)" >&2
set terminal pngcairo size 800,480
set output "$out/binaryswap.png"
set datafile separator ","
set title "MULTI-PROCESS (real processes, Unix sockets) sort-last ($size, synthetic layers, strategy $strategy, rle):\nlast peer's layer ready -> frame drawn on the display node (median)"
set xlabel "peer processes (plus one display process; 2 vCPUs)"
set ylabel "ms per frame"
set logscale x 2
set key top left
set yrange [0:*]
plot "< grep ',full,' $summary" using 1:4 with linespoints pt 7 title "full layers", \
     "< grep ',full,' $summary" using 1:5 with linespoints pt 5 title "full, last final piece composited (before the display path)", \
     "< grep ',ellipse,' $summary" using 1:4 with points pt 9 ps 2 title "ellipse 40% layers", \
     "< grep ',full,' $summary" using 1:10 with linespoints dt 4 pt 6 title "full, CPU ms of all peer processes per frame", \
     30 with lines dt 2 title "target N=8 full (30 ms)", 15 with lines dt 3 title "target N=8 ellipse (15 ms)"
EOF
fi
