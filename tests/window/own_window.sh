#!/usr/bin/env bash
# tests/window/own_window.sh TESSERA SPHERES XGRAB OUTDIR
# A two-server wall (tilesort, left and right halves of 320x240) whose tile
# servers run "render ... window_output=x11": each shows its tile in an X
# window of its own on a private Xvfb. Once 6 frames exist the application
# is stopped (SIGSTOP), the servers finish what they hold, and each
# server's window (XGetImage) must come to equal its newest tile PNG: 0
# differing pixels (polled, bounded: no wait assumes how long they take). Server a sends with MIT-SHM (XShmPutImage), server b with
# x_shm=false (XPutImage).
set -euo pipefail
tessera=$1 spheres=$2 xgrab=$3 out=$4
rm -rf "$out"; mkdir -p "$out"
. "$(dirname "$0")/../faker/xvfb.sh"
start_xvfb "$out"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill -CONT "$p" 2>/dev/null || true; kill "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  stop_xvfb
}
trap cleanup EXIT
for s in a b; do
  TESSERA_LOG=info "$tessera" node --listen "unix:$out/$s.sock" \
    --chain "render output=$out/$s-%04d.png window_output=x11 x_title=wall-$s x_position=$([ $s = a ] && echo 0,0 || echo 200,0 x_shm=false)" \
    > "$out/node-$s.log" 2>&1 &
  pids+=($!)
done
for _ in $(seq 100); do [ -S "$out/a.sock" ] && [ -S "$out/b.sock" ] && break; sleep 0.1; done
"$spheres" --frames 2000 --size 320x240 \
  --chain "tilesort servers=unix:$out/a.sock,unix:$out/b.sock tiles=0:0:0:160:240,1:160:0:160:240" \
  > "$out/app.log" 2>&1 &
app=$!; pids+=($app)
for _ in $(seq 300); do [ -e "$out/b-0006.png" ] && [ -e "$out/a-0006.png" ] && break; kill -0 $app || break; sleep 0.1; done
kill -STOP $app
# The servers draw what they already received, then stay still. Wait for
# that event itself: both windows equal their server's newest PNG (each
# tried with the newest PNG as it is at the time, since a server may still
# be writing), polled for at most 30 s; the last attempt is printed.
status=1
for _ in $(seq 150); do
  report="" ok=1
  for s in a b; do
    newest=$(ls "$out" | grep "^$s-[0-9]*\.png$" | sort | tail -n1)
    report+="server $s: newest frame $newest"$'\n'
    report+=$("$xgrab" "wall-$s" "$out/$newest" 2>&1)$'\n' || ok=0
  done
  [ $ok = 1 ] && { status=0; break; }
  sleep 0.2
done
printf '%s' "$report"
[ $status = 0 ] || echo "FAIL: the windows did not settle on their newest PNGs within 30 s"
cat "$out/node-a.log" "$out/node-b.log"
grep -q "with XShmPutImage" "$out/node-a.log" || { echo "FAIL: server a did not use MIT-SHM"; status=1; }
grep -q "with XPutImage" "$out/node-b.log" || { echo "FAIL: server b did not use XPutImage"; status=1; }
exit $status
