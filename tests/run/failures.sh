#!/bin/sh
# tests/run/failures.sh — `tessera run` must end a run whose node fails:
# kill -9 the server node mid-stream, kill -9 the application mid-stream,
# SIGSTOP the server node, the app node or the application itself (whose
# silent stream its server drops after --timeout-ms, which ends the run).
# Each case asserts: non-zero exit,
# one line naming the node and what happened (so the run ended because of
# the fault, not because some time-out fired), and no process of the run
# left (every process group the run started, and the application's pid,
# are gone). The time from the fault to the end is printed, not judged:
# the waits' bounds (30 s for the run, 10 s for its processes) only keep a
# broken build from hanging.
# usage: failures.sh CASE BIN_DIR OUT_DIR
#   CASE: kill-server | kill-app | stop-server | stop-app-node | stop-app, or
#         interrupt (SIGTERM to tessera run: it stops the run the same way),
#         kill-mothership (kill -9 tessera run: its nodes notice the lost
#         control connection, kill their application and end by themselves)
set -u
case_name=$1 bin=$2 out=$3
TESSERA=$bin/tessera
. "$(dirname "$0")/../node/node_lib.sh"
graph=$(dirname "$0")/long.yaml
timeout_ms=1500
rm -rf "$out" && mkdir -p "$out/tmp" || exit 1
# The run's temporary files (a killed mothership cannot remove its own).
TMPDIR=$(cd "$out/tmp" && pwd); export TMPDIR

"$TESSERA" run "$graph" --out "$out" --timeout-ms $timeout_ms --no-progress \
  >"$out/run.out" 2>"$out/run.err" &
run_pid=$!

# Wait (bounded) until the server has drawn a few frames: mid-stream.
i=0
while [ ! -e "$out/out/long-000005.png" ] && [ $i -lt 600 ] && alive $run_pid; do
  sleep 0.05; i=$((i + 1))
done
if [ ! -e "$out/out/long-000005.png" ]; then
  echo "FAIL: the run drew no 6 frames in 30 s; its stderr:" >&2; cat "$out/run.err" >&2
  kill -TERM $run_pid 2>/dev/null; wait_exit $run_pid 10; exit 1
fi

node_pid() { ps -o pid=,args= --ppid "$run_pid" | awk -v n="$1" '$0 ~ "--name " n "( |$)" {print $1}'; }
server=$(node_pid server)
appnode=$(node_pid app)
app=$(ps -o pid= --ppid "$appnode" | tr -d ' ' | head -n 1)
echo "run $run_pid, server node $server, app node $appnode, application $app"
[ -n "$server" ] && [ -n "$appnode" ] && [ -n "$app" ] \
  || { echo "FAIL: could not find the run's processes" >&2; ps -ef >&2; kill -TERM $run_pid; wait_exit $run_pid 10; exit 1; }
groups="$server $appnode"

case $case_name in
  kill-server)   victim=$server  sig=KILL want="node 'server' \\(pid $server\\) killed by signal 9" ;;
  kill-app)      victim=$app     sig=KILL want="node 'app': application .*spheres killed by signal 9" ;;
  stop-server)   victim=$server  sig=STOP want="node 'server' sent no heartbeat for [0-9]+ ms" ;;
  stop-app-node) victim=$appnode sig=STOP want="node 'app' sent no heartbeat for [0-9]+ ms" ;;
  stop-app)      victim=$app     sig=STOP
                 want="node 'server': client 0 'pack[^']*-pid$app' at .* dropped: .*sent nothing for $timeout_ms ms" ;;
  interrupt)     victim=$run_pid sig=TERM want="interrupted by signal 15" ;;
  kill-mothership) victim=$run_pid sig=KILL want= ;;
  *) echo "failures.sh: unknown case '$case_name'" >&2; kill -TERM $run_pid; exit 2 ;;
esac

# left: the processes of the run still there (group members, the application).
left() {
  ps -e -o pid=,pgid=,stat=,args= | awk -v g=" $groups " -v a="$app" 'index(g, " " $2 " ") || $1 == a {print}'
}
t0=$(now_ms)
kill -$sig "$victim"
wait_exit $run_pid 30
if [ "$case_name" = kill-mothership ]; then
  # Nobody is left to reap the nodes' zombies but init; count the living.
  i=0
  while [ -n "$(left | awk '$3 !~ /^Z/')" ] && [ $i -lt 200 ]; do sleep 0.05; i=$((i + 1)); done
  elapsed=$(( $(now_ms) - t0 ))
  echo "nodes gone ${elapsed} ms after the mothership was killed"
  cat "$out/run.err"
  status=0
  grep -q "lost the mothership" "$out/run.err" || { echo "FAIL: no node said it lost the mothership" >&2; status=1; }
  alive_left=$(left | awk '$3 !~ /^Z/')
  if [ -n "$alive_left" ]; then
    echo "FAIL: processes of the run are left:" >&2; echo "$alive_left" >&2
    for p in $groups; do kill -KILL -- -"$p" 2>/dev/null; done; kill -KILL "$app" 2>/dev/null
    status=1
  fi
  [ $status -eq 0 ] && echo "PASS: kill-mothership: every node ended by itself (${elapsed} ms)"
  exit $status
fi
elapsed=$(( $(now_ms) - t0 ))
echo "tessera run exit $EXIT_RC after ${elapsed} ms; stderr:"
cat "$out/run.err"
status=0
case $EXIT_RC in
  timeout) echo "FAIL: tessera run did not end within 30 s" >&2; status=1 ;;
  0) echo "FAIL: tessera run exited 0 after a failure" >&2; status=1 ;;
esac
grep -Eq "^tessera run: $want" "$out/run.err" || { echo "FAIL: stderr does not name the node: /$want/" >&2; status=1; }
# Nothing of the run may be left: not a group member, not the application
# (the application's node ends it as it ends: wait for that, bounded).
i=0
while [ -n "$(left)" ] && [ $i -lt 200 ]; do sleep 0.05; i=$((i + 1)); done
still=$(left)
if [ -n "$still" ]; then
  echo "FAIL: processes of the run are left:" >&2; echo "$still" >&2
  for p in $groups; do kill -KILL -- -"$p" 2>/dev/null; done; kill -KILL "$app" 2>/dev/null
  status=1
fi
[ $status -eq 0 ] && echo "PASS: $case_name: exit $EXIT_RC after ${elapsed} ms, node named, no process left"
exit $status
