#!/usr/bin/env bash
# bench/composite_charts.sh — the charts of bench_composite's in-process
# sweeps (composite-codecs.csv, composite-strategies.csv): a thread per
# peer and the display in ONE process over the in-memory transport, CPU ms
# of all threads per frame. Every chart says so in its title; the
# multi-process figures are bench/binaryswap.sh's.
# usage: bench/composite_charts.sh OUT_DIR
set -euo pipefail
out=$1
c=$out/composite-codecs.csv s=$out/composite-strategies.csv
plot="" sep=""
for size in 1024x768 1920x1080; do
    for n in 2 4 8; do
        plot+="$sep\"< grep ',$size,$n,' $c\" using 4:7 with points ps 1.5 title \"$size N=$n\""
        sep=", "
    done
done
plot+=", \"< grep ',1920x1080,8,' $c\" using 4:7:1 with labels offset 0,1 notitle"
gnuplot <<EOF
set terminal pngcairo size 900,540
set output "$out/composite_codecs.png"
set datafile separator ","
set title "IN-PROCESS (threads, in-memory transport): composite time per frame against accuracy\nevery codec, strategy auto, synthetic full layers; PSNR of the final frame against codec none (99 = exact)"
set xlabel "CPU ms per frame (all peer threads + display)"
set ylabel "colour PSNR dB"
set key bottom right
set yrange [0:105]
plot $plot
EOF
plot="" sep=""
for st in gather direct bswap radixk-4 auto; do
    plot+="$sep\"< grep '^$st,full,' $s\" using 3:4 with linespoints title \"$st\""
    sep=", "
done
gnuplot <<EOF
set terminal pngcairo size 800,480
set output "$out/composite_strategies.png"
set datafile separator ","
set title "IN-PROCESS (threads, in-memory transport): composite time against N\n1920x1080 synthetic full layers, codec rle"
set xlabel "peers N"
set ylabel "CPU ms per frame (all threads)"
set logscale x 2
set key top left
plot $plot
EOF
plot="" sep=""
for st in gather direct bswap radixk-4; do
    plot+="$sep\"< grep '^$st,full,' $s\" using 3:(column(6)/1e6) with linespoints title \"$st full\""
    plot+=", \"< grep '^$st,partial,' $s\" using 3:(column(6)/1e6) with linespoints dt 2 title \"$st ellipse 40%\""
    sep=", "
done
gnuplot <<EOF
set terminal pngcairo size 800,480
set output "$out/composite_bytes.png"
set datafile separator ","
set title "IN-PROCESS (threads, in-memory transport): bytes all peers send per frame against N\n1920x1080, codec rle"
set xlabel "peers N"
set ylabel "MB per frame"
set logscale x 2
set key top left
plot $plot
EOF
