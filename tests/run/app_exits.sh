#!/bin/sh
# tests/run/app_exits.sh — an application that exits without ever
# connecting to its server ends `tessera run` at once (not after the
# server's 60 s join wait), non-zero, naming the application and its exit
# status: /bin/true (status 0) and sh -c 'exit 3'.
# usage: app_exits.sh TESSERA OUT_DIR
set -u
tessera=$1 out=$2
rm -rf "$out" && mkdir -p "$out" || exit 1
status=0
for app in true exit3; do
  if [ $app = true ]; then exec_line='exec: /bin/true'; want='application /bin/true exited with status 0 without connecting'
  else exec_line='exec: /bin/sh -c "exit 3"'; want='application /bin/sh exited with status 3'; fi
  cat >"$out/$app.yaml" <<YAML
version: 1
window: {width: 64, height: 64}
nodes:
  app:
    $exec_line
    chain:
      - pack
    to: server
  server:
    transport: tcp
    listen: 127.0.0.1:0
    chain:
      - render: {output: "out/f-%04d.png"}
YAML
  start=$(date +%s)
  # bounded: the run's own time-out (5 s) plus a margin, far below the 60 s join wait
  timeout 20 "$tessera" run --timeout-ms 5000 "$out/$app.yaml" >"$out/$app.out" 2>"$out/$app.err"
  rc=$?
  took=$(( $(date +%s) - start ))
  echo "$app: exit $rc after ${took} s: $(tail -n 1 "$out/$app.err")"
  [ $rc != 0 ] && [ $rc != 124 ] || { echo "FAIL: $app: exit $rc"; status=1; }
  grep -q "tessera run: node 'app': $want" "$out/$app.err" || { echo "FAIL: $app: no line names the application and its status"; cat "$out/$app.err"; status=1; }
done
[ $status = 0 ] && echo "PASS"
exit $status
