#!/usr/bin/env bash
# tests/capture/answers.sh TESSERA ASKS OUTDIR
# The capture of a program whose stream depends on the answers it gets
# (asks: glGenLists, glGetIntegerv, glGetFloatv, glReadPixels each frame)
# is made in a graph, chain "capture ! pack" to a server that renders, so
# every answer comes from that server. The replay then runs with no
# server: through "render" it must draw the server's frames exactly and
# give every answer the server gave (counted by the request that asked);
# through "passthrough" (which answers every request with zeros) it must
# still feed the whole stream, end cleanly and say how many answers
# differed, and --exact-answers makes that a failure.
set -euo pipefail
tessera=$1 asks=$2 out=$3
. "$(dirname "$0")/common.sh"
rm -rf "$out"; mkdir -p "$out"; cd "$out"
cat > asks.yaml <<YAML
version: 1
window: {width: 64, height: 48}
nodes:
  app:
    exec: ["$asks", "-", "4"]
    chain:
      - capture: {file: asks.tsrcap}
      - pack
    to: server
  server:
    chain:
      - render: {output: "srv-%04d.png"}
YAML
"$tessera" run asks.yaml --out "$out/run" --no-progress | tee run.txt
grep -q "^glGenLists: 1$" run.txt || { echo "FAIL: asks did not get its list names from the server"; exit 1; }
# frame 3 reads the modelview of frame 2: three 17-degree turns, cos(51) = 0.6293
grep -q "^frame 3: viewport 0 0 64 48, m\[0\] 0.6293[0-9]*, pixel [1-9]" run.txt || { echo "FAIL: asks did not get its answers"; exit 1; }
"$tessera" replay --info run/asks.tsrcap | tee info.txt
# 1 glGenLists + 4 frames x (glGetIntegerv, glGetFloatv, glReadPixels)
grep -qx "replies: 13" info.txt || { echo "FAIL: expected 13 replies in the capture"; exit 1; }
grep -qx "replies by request: glGetFloatv 4, glGetIntegerv 4, glReadPixels 4, glGenLists 1" info.txt ||
  { echo "FAIL: --info should count the replies by the request that asked"; exit 1; }
"$tessera" replay run/asks.tsrcap --exact-answers --chain "render output=rp-%04d.png" 2> rp.err | tee rp.txt
cat rp.err
[ ! -s rp.err ] || { echo "FAIL: render's answers should all equal the server's"; exit 1; }
grep -qx "tessera replay: run/asks.tsrcap: answers: 13 compared, 0 differ; by request: glGetFloatv 4, glGetIntegerv 4, glReadPixels 4, glGenLists 1" rp.txt ||
  { echo "FAIL: the replay should print its 13 answers, 0 differing, by request"; exit 1; }
same_frames "$tessera" run/srv-%04d.png rp-%04d.png 4
timeout 20 "$tessera" replay run/asks.tsrcap --chain passthrough 2> pt.err | tee pt.txt
cat pt.err
grep -q "4 frames fed" pt.txt || { echo "FAIL: the passthrough replay did not feed every frame"; exit 1; }
grep -q "note: 13 of 13 answers of this chain differ" pt.err || { echo "FAIL: the differing answers were not counted"; exit 1; }
grep -q "answers: 13 compared, 13 differ; by request: glGetFloatv 4 (4 differ), glGetIntegerv 4 (4 differ), glReadPixels 4 (4 differ), glGenLists 1 (1 differs)$" pt.txt ||
  { echo "FAIL: the differing answers were not counted by request"; exit 1; }
set +e
timeout 20 "$tessera" replay run/asks.tsrcap --exact-answers --chain passthrough > ptx.txt 2> ptx.err
status=$?
set -e
cat ptx.err
[ "$status" = 1 ] && grep -q -- "--exact-answers: 13 answers differ" ptx.err ||
  { echo "FAIL: --exact-answers should end a replay with differing answers with status 1 (got $status)"; exit 1; }
# max_bytes: a capture that would grow past it is abandoned (no file, no
# temporary, one line) and every call still passes on: the replay through
# "capture max_bytes=2000 ! render" gets all 13 answers right
"$tessera" replay run/asks.tsrcap --exact-answers --chain "capture file=big.tsrcap max_bytes=2000 ! render output=" \
  > big.txt 2> big.err
cat big.txt big.err
grep -q "answers: 13 compared, 0 differ" big.txt || { echo "FAIL: a capture past max_bytes changed the stream"; exit 1; }
[ "$(grep -c "would pass max_bytes=2000; the capture is abandoned" big.err)" = 1 ] ||
  { echo "FAIL: expected one line saying the capture was abandoned at max_bytes"; exit 1; }
[ -z "$(ls -A . | grep big.tsrcap)" ] || { echo "FAIL: a capture past max_bytes left a file"; exit 1; }
echo "PASS: answers recorded, replayed and compared by request; max_bytes abandons a capture whole"
