# tests/faker/xvfb.sh — sourced by the faker tests: start_xvfb starts a
# private Xvfb on a display number the server picks itself (-displayfd, so
# parallel tests never collide) and exports DISPLAY; it is stopped by the
# EXIT trap (stop_xvfb), killed by its own pid only. -noreset: by default
# the server resets when its last client leaves, and a program started in
# that moment cannot connect ("no X display": seen when a script runs
# programs one after the other).
XVFB_PID=""
stop_xvfb() {
  if [ -n "$XVFB_PID" ]; then
    kill "$XVFB_PID" 2>/dev/null || true
    wait "$XVFB_PID" 2>/dev/null || true
    XVFB_PID=""
  fi
}
start_xvfb() {  # start_xvfb WORKDIR [XVFB OPTIONS...] (e.g. -extension GLX)
  command -v Xvfb >/dev/null || { echo "SKIP: Xvfb is not installed (scripts/setup-debian installs xvfb)"; exit 77; }
  local dir="$1" fdfile="$1/xvfb.display"
  shift
  : > "$fdfile"
  Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp -noreset "$@" 3>"$fdfile" 2>"$dir/xvfb.log" &
  XVFB_PID=$!
  trap stop_xvfb EXIT
  for _ in $(seq 100); do
    [ -s "$fdfile" ] && break
    kill -0 "$XVFB_PID" 2>/dev/null || { echo "FAIL: Xvfb exited:"; cat "$dir/xvfb.log"; exit 1; }
    sleep 0.1
  done
  [ -s "$fdfile" ] || { echo "FAIL: Xvfb did not report a display in 10 s"; exit 1; }
  export DISPLAY=":$(head -n1 "$fdfile")"
}
