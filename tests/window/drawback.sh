#!/usr/bin/env bash
# tests/window/drawback.sh TESSERA XGRAB OUTDIR
# An unmodified glxgears (320x240) under `tessera exec` with the chain
# "render output=... window_output=app" on a private Xvfb: each frame is
# drawn back into glxgears' own window (the drawable the faker recorded),
# as remote-rendering tools do. Once 8 frames exist glxgears is stopped
# (SIGSTOP); its window (XGetImage) must equal the PNG of the same frame
# with 0 differing pixels. That frame is the newest PNG, or the one before
# it when the stop fell between writing the PNG and drawing the window
# (render writes the PNG first); the match names which. Without MIT-SHM,
# Xlib sends a 320x240 image as two PutImage requests of at most 256 KiB,
# so a stop can also fall between them and leave the window half one frame
# and half the next: then neither PNG matches, and the program is resumed
# and stopped again, at most 5 times, each attempt printed. Run twice:
# with MIT-SHM and with x_shm=false.
set -euo pipefail
tessera=$1 xgrab=$2 out=$3
command -v glxgears >/dev/null || { echo "SKIP: glxgears is not installed (scripts/setup-debian: mesa-utils)"; exit 77; }
rm -rf "$out"; mkdir -p "$out"
. "$(dirname "$0")/../faker/xvfb.sh"
start_xvfb "$out"
export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0"
pid=""
cleanup() { if [ -n "$pid" ]; then kill -CONT "$pid" 2>/dev/null || true; kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true; fi; stop_xvfb; }
trap cleanup EXIT
status=0
for mode in shm plain; do
  d=$out/$mode; mkdir -p "$d"
  opt=""; [ $mode = plain ] && opt="x_shm=false"
  TESSERA_LOG=info LD_PRELOAD="${FAKER_PRELOAD:-}" "$tessera" exec \
    --chain "render output=$d/g-%04d.png window_output=app $opt" -- glxgears -geometry 320x240 \
    > "$d/stdout.txt" 2> "$d/stderr.txt" &
  pid=$!
  for _ in $(seq 300); do [ -e "$d/g-0008.png" ] && break; kill -0 $pid 2>/dev/null || break; sleep 0.1; done
  matched=0
  for attempt in 1 2 3 4 5; do
    kill -STOP $pid
    newest=$(ls "$d" | grep '^g-[0-9]*\.png$' | sort | tail -n1)
    before=$(ls "$d" | grep '^g-[0-9]*\.png$' | sort | tail -n2 | head -n1)
    echo "$mode: attempt $attempt: newest frame $newest"
    # The X server may still hold the last PutImage: poll the window for
    # at most 2 s before taking this stop for one between two requests.
    for _ in $(seq 20); do
      if "$xgrab" glxgears "$d/$newest" "$d/$before" > "$d/xgrab.txt" 2>&1; then matched=1; break; fi
      sleep 0.1
    done
    cat "$d/xgrab.txt"
    [ $matched = 1 ] && break
    # Resume until the program has written a newer frame, then stop again.
    kill -CONT $pid
    for _ in $(seq 100); do
      [ "$(ls "$d" | grep '^g-[0-9]*\.png$' | sort | tail -n1)" != "$newest" ] && break
      sleep 0.1
    done
  done
  [ $matched = 1 ] || { echo "FAIL: $mode: the window equalled neither of the two newest PNGs in 5 stops"; status=1; }
  kill -CONT $pid; kill -TERM $pid; wait $pid || true; pid=""
  want=XShmPutImage; [ $mode = plain ] && want=XPutImage
  grep -q "window output to the program's window .* with $want" "$d/stderr.txt" ||
    { echo "FAIL: $mode: no line saying the frames went to glxgears' window with $want"; cat "$d/stderr.txt"; status=1; }
done
exit $status
