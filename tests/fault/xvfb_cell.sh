#!/usr/bin/env bash
# tests/fault/xvfb_cell.sh OUT_DIR FAULT_CELL ARGS... — one cell of the
# fault matrix whose app is an unmodified X program (tests/fault/faker_*.yaml:
# glxgears): starts a private Xvfb for it (tests/faker/xvfb.sh; exit 77
# without Xvfb or glxgears), runs FAULT_CELL ARGS... and stops the Xvfb.
# The Xvfb does not carry the cell's marker, so fault_cell never counts it
# as a process of the run. Sanitizer builds: $FAKER_PRELOAD (the sanitizer
# runtimes) is preloaded into the run, since glxgears is not instrumented
# but loads the instrumented faker; leak checks are off there, as in
# tests/faker/exec_graph.sh (glxgears' and Xlib's own allocations at exit).
set -u
out=$1; shift
command -v glxgears >/dev/null || { echo "SKIP: glxgears is not installed (scripts/setup-debian: mesa-utils)"; exit 77; }
xdir=$out-xvfb   # fault_cell empties OUT_DIR first
mkdir -p "$xdir"
. "$(dirname "$0")/../faker/xvfb.sh"
start_xvfb "$xdir"
if [ -n "${FAKER_PRELOAD:-}" ]; then
  export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0"
  LD_PRELOAD="$FAKER_PRELOAD" "$@"
else
  "$@"
fi
