# bench/walls.sh — what the sort-first benchmarks (march.sh, balance.sh)
# share, sourced after tests/node/node_lib.sh: the servers they start
# (PIDS, killed on exit) and an even split of a window into tiles.
# Never starts anything itself.
PIDS=
kill_all() { for p in $PIDS; do kill -9 "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done; PIDS=; }
trap kill_all EXIT

# tiles_for COLS ROWS W H: "S:X:Y:W:H,..." splitting WxH evenly.
tiles_for() {
    local cols=$1 rows=$2 width=$3 height=$4 c r s=0 list=
    for ((r = 0; r < rows; r++)); do
        for ((c = 0; c < cols; c++)); do
            local x0=$((c * width / cols)) x1=$(((c + 1) * width / cols))
            local y0=$((r * height / rows)) y1=$(((r + 1) * height / rows))
            list="$list${list:+,}$s:$x0:$y0:$((x1 - x0)):$((y1 - y0))"
            s=$((s + 1))
        done
    done
    echo "$list"
}
