#!/bin/sh
# tests/tilesort/overlap.sh — tilesort sends each server only what touches
# its tiles: examples/isosurface (large glDrawElements and glDrawArrays of
# triangles, which tilesort sorts primitive by primitive) on a 4x4 wall of
# real `tessera node` render servers; the sort_first statistics
# (TESSERA_STATS_FILE) must show an overlap (bytes sent / bytes one
# server would get) below MAX, where broadcast's would be 16, and every
# server must have received something it draws.
# usage: overlap.sh BIN_DIR OUT_DIR MAX [TILESORT_OPTION...]
set -u
bin=$1 out=$2 max=$3
shift 3
TESSERA=$bin/tessera
. "$(dirname "$0")/../node/node_lib.sh"
rm -rf "$out" && mkdir -p "$out" || exit 1
PIDS= SERVERS= TILES= k=0
kill_all() { for p in $PIDS; do kill -9 "$p" 2>/dev/null; wait "$p" 2>/dev/null; done; PIDS=; }
for y in 0 192 384 576; do
  for x in 0 256 512 768; do
    start_node "$out/node$k" --listen tcp://127.0.0.1:0 --clients 1 --timeout-ms 120000 \
      --chain 'render output=""' || { kill_all; exit 1; }
    PIDS="$PIDS $NODE_PID"
    SERVERS="$SERVERS${SERVERS:+,}$NODE_ADDR"
    TILES="$TILES${TILES:+,}$k:$x:$y:256:192"
    k=$((k + 1))
  done
done
TESSERA_STATS_FILE=$out/stats.json "$bin/isosurface" --frames 1 --size 1024x768 \
  --chain "tilesort servers=$SERVERS tiles=$TILES $*" >"$out/app.out" 2>"$out/app.err" &
wait_exit $! 120
rc=$EXIT_RC
kill_all
[ "$rc" = 0 ] || { cat "$out/app.err" >&2; echo "FAIL: isosurface through tilesort exited $rc" >&2; exit 1; }
overlap=$(sed -n 's/.*"sort_first":{[^}]*"overlap":\([0-9.]*\).*/\1/p' "$out/stats.json")
echo "overlap on 4x4 tiles: $overlap (must be below $max; broadcast: 16)"
[ -n "$overlap" ] || { echo "FAIL: no overlap in $out/stats.json" >&2; exit 1; }
awk -v o="$overlap" -v m="$max" 'BEGIN { exit !(o > 0 && o < m) }' || { echo "FAIL: overlap $overlap" >&2; exit 1; }
echo PASS
