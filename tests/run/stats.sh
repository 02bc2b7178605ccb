#!/bin/sh
# tests/run/stats.sh — what `tessera run` reports: the progress line
# (--progress forces it without a terminal), the summary, and the
# statistics JSON, checked against each other: the server drew every frame,
# the bytes the app's pack SPU sent (its TESSERA_STATS_FILE) are the bytes
# the server received, and the server's render time is measured.
# usage: stats.sh BIN_DIR OUT_DIR GRAPH FRAMES
set -u
bin=$1 out=$2 graph=$3 frames=$4
rm -rf "$out" && mkdir -p "$out" || exit 1
timeout 120 "$bin/tessera" run "$graph" --out "$out" --stats "$out/stats.json" --progress \
  >"$out/run.out" 2>"$out/run.err"
rc=$?
echo "--- stdout"; cat "$out/run.out"; echo "--- stderr"; tr '\r' '\n' <"$out/run.err" | tail -n 3
echo "--- stats.json"; cat "$out/stats.json"
status=0
[ $rc -eq 0 ] || { echo "FAIL: tessera run exited $rc" >&2; status=1; }
grep -Eq "server [0-9]+ fr [0-9.]+ fr/s [0-9.]+ MB/s|server done" "$out/run.err" \
  || { echo "FAIL: no progress line on stderr" >&2; status=1; }
grep -Eq "server +server: $frames frames, [0-9.]+ frames/s" "$out/run.out" \
  || { echo "FAIL: summary lacks the server's $frames frames" >&2; status=1; }
# field NODE KEY: the value of KEY in NODE's line of the JSON.
field() { grep "\"name\": \"$1\"" "$out/stats.json" | sed -n "s/.*\"$2\": \([^,}]*\).*/\1/p"; }
server_frames=$(field server frames) server_in=$(field server bytes_in)
app_out=$(field app bytes_out) app_frames=$(field app frames)
render=$(field server render_seconds) blocked=$(field app blocked_seconds)
echo "server frames $server_frames, bytes_in $server_in, render_seconds $render;" \
     "app frames $app_frames, bytes_out $app_out, blocked_seconds $blocked"
[ "$server_frames" = "$frames" ] || { echo "FAIL: server frames $server_frames, expected $frames" >&2; status=1; }
[ "$app_frames" = "$frames" ] || { echo "FAIL: app frames '$app_frames', expected $frames (TESSERA_STATS_FILE)" >&2; status=1; }
[ -n "$server_in" ] && [ "$server_in" -gt 0 ] && [ "$server_in" = "$app_out" ] \
  || { echo "FAIL: app sent '$app_out' bytes, server received '$server_in'" >&2; status=1; }
case $render in ''|null|0.000000) echo "FAIL: no render time" >&2; status=1 ;; esac
case $blocked in ''|null) echo "FAIL: no blocked_seconds for the app" >&2; status=1 ;; esac
[ $status -eq 0 ] && echo "PASS: progress, summary and statistics agree"
exit $status
