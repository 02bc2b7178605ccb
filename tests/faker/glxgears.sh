#!/usr/bin/env bash
# tests/faker/glxgears.sh MODE FAKER_DIR TESSERA FRAMES_CHECK OUTDIR
# An unmodified glxgears (320x240) under a private Xvfb with the faker and
# the chain "render output=...": MODE direct sets LD_LIBRARY_PATH and
# TESSERA_CHAIN itself, MODE exec runs `tessera exec -- glxgears` (default
# chain: out/glxgears-%04d.png in OUTDIR). Once 12 frames exist (at most
# 30 s) the program gets SIGTERM; it must die of that signal (status 143),
# leave no process behind, log no unsupported-function warning, and its
# frames must pass faker_frames (>= 10 frames, none of one colour, moving).
# $FAKER_PRELOAD (sanitized builds: the ASan/UBSan runtimes) is preloaded
# into the uninstrumented program, which then loads the instrumented faker.
set -euo pipefail
mode=$1 faker=$2 tessera=$3 frames=$4 out=$5
command -v glxgears >/dev/null || { echo "SKIP: glxgears is not installed (scripts/setup-debian: mesa-utils)"; exit 77; }
rm -rf "$out"; mkdir -p "$out"
. "$(dirname "$0")/xvfb.sh"
start_xvfb "$out"
export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0"
cd "$out"
if [ "$mode" = direct ]; then
  dir=$out prefix=g-
  LD_PRELOAD="${FAKER_PRELOAD:-}" LD_LIBRARY_PATH="$faker" TESSERA_CHAIN="render output=$out/g-%04d.png" \
    glxgears -geometry 320x240 > "$out/stdout.txt" 2> "$out/stderr.txt" &
else
  dir=$out/out prefix=glxgears-
  LD_PRELOAD="${FAKER_PRELOAD:-}" "$tessera" exec -- glxgears -geometry 320x240 \
    > "$out/stdout.txt" 2> "$out/stderr.txt" &
fi
pid=$!
start=$(date +%s%N)
for _ in $(seq 300); do
  [ -e "$dir/${prefix}0012.png" ] && break
  kill -0 "$pid" 2>/dev/null || break
  sleep 0.1
done
kill -TERM "$pid" 2>/dev/null || true
status=0; wait "$pid" || status=$?
echo "glxgears ran $(( ($(date +%s%N) - start) / 1000000 )) ms; exit status $status"
if kill -0 "$pid" 2>/dev/null; then echo "FAIL: glxgears (pid $pid) is still running"; kill -KILL "$pid"; exit 1; fi
ps -o pid=,comm= --ppid $$ > "$out/children.txt"   # direct child: no subshell in the list
left=$(grep -v -e " ps$" -e " Xvfb$" "$out/children.txt" || true)
[ -z "$left" ] || { echo "FAIL: processes left behind: $left"; exit 1; }
echo "--- stderr"; cat "$out/stderr.txt"; echo "---"
[ "$status" -eq 143 ] || { echo "FAIL: expected death by SIGTERM (143), got $status"; exit 1; }
if grep -q "is not supported by tessera" "$out/stderr.txt"; then
  echo "FAIL: glxgears called functions the faker does not support"; exit 1
fi
"$frames" "$dir" "$prefix" 10
