#!/bin/sh
# tests/run/peers/peers.sh — a graph run tells a group of peers (servers
# whose network SPU declares TSR_SPU_ROLE_PEERS and sends to one display)
# their ranks and every peer's address: each peer's chain is built only
# once all of them listen. Checks what the test SPU peerprobe reports
# against the addresses in the run's statistics.
# usage: peers.sh BIN_DIR PLUGIN_DIR OUT_DIR
set -u
bin=$1 plugins=$2 out=$3
fail() { echo "FAIL: $*" >&2; exit 1; }
graph=$(dirname "$0")/peers.yaml
rm -rf "$out" && mkdir -p "$out" || exit 1
TESSERA_SPU_PATH="$plugins" timeout 120 "$bin/tessera" run "$graph" --out "$out/run" \
    --stats "$out/stats.json" --no-progress >"$out/run.out" 2>"$out/run.err"
rc=$?
cat "$out/run.out" "$out/run.err"
[ "$rc" -eq 0 ] || fail "tessera run exited $rc"
address() { sed -n "s/.*\"name\": \"$1\".*\"address\": \"\([^\"]*\)\".*/\1/p" "$out/stats.json"; }
p0=$(address p0) p1=$(address p1) display=$(address display)
[ -n "$p0" ] && [ -n "$p1" ] && [ -n "$display" ] || fail "addresses missing from stats.json"
for peer in p0 p1; do
    echo "$peer: $(cat "$out/run/peer-$peer.txt")"
done
[ "$(cat "$out/run/peer-p0.txt")" = "rank=0 display=$display peers=$p0,$p1" ] || fail "p0 was told otherwise"
[ "$(cat "$out/run/peer-p1.txt")" = "rank=1 display=$display peers=$p0,$p1" ] || fail "p1 was told otherwise"
echo "PASS: both peers know their rank, the display and every peer's address"
