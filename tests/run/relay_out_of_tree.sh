#!/bin/sh
# tests/run/relay_out_of_tree.sh — a third party's network SPU in a graph:
# install this build into a fresh prefix, build tests/run/relay/relay.c (a
# network SPU written only against the installed headers, found with
# pkg-config) from a copy away from the source tree, then run
# tests/run/relay/relay.yaml with `tessera run`: the relay's frames must be
# bit-identical to spheres-native's, and its report must show that it
# carried all 20 frames to the address the run filled into its own option.
# usage: relay_out_of_tree.sh CMAKE BUILD_DIR SOURCE_DIR WORK_DIR CC [EXTRA_CFLAGS]
# (EXTRA_CFLAGS: the sanitizer flags of a sanitized build, else empty).
set -eu
cmake_cmd=$1 build=$2 src=$3 work=$4 cc=$5 extra=${6:-}
fail() { echo "FAIL: $*" >&2; exit 1; }

rm -rf "$work"
mkdir -p "$work/spus" "$work/relay-src"
if ! "$cmake_cmd" --install "$build" --prefix "$work/prefix" >"$work/install.log" 2>&1; then
    cat "$work/install.log"
    fail "cmake --install failed"
fi
pc=$(find "$work/prefix" -name tessera.pc | head -n 1)
[ -n "$pc" ] || fail "no tessera.pc was installed"
export PKG_CONFIG_PATH="$(dirname "$pc")"
libdir=$(dirname "$(dirname "$pc")")
libs=$(pkg-config --libs tessera)
case " $libs " in
*" -ltessera_client "*) ;;
*) fail "pkg-config --libs tessera gives '$libs': no -ltessera_client (the stream client)" ;;
esac

# Only the installed headers can be found from here.
cp "$src/tests/run/relay/relay.c" "$work/relay-src/"
# shellcheck disable=SC2046,SC2086 # pkg-config output is a list of flags
"$cc" -std=c11 -Wall -Wextra -Werror -O1 -g -fPIC -shared -fvisibility=hidden $extra \
    $(pkg-config --cflags tessera) -o "$work/spus/relay_spu.so" "$work/relay-src/relay.c" $libs
echo "built relay_spu.so ($(wc -l <"$work/relay-src/relay.c") lines) with $(pkg-config --cflags tessera) $libs"

export LD_LIBRARY_PATH="$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export TESSERA_SPU_PATH="$work/spus"
tessera="$build/bin/tessera"

# Its role comes from its class alone.
"$tessera" spus relay >"$work/spus.txt" || fail "tessera spus relay exited $?"
cat "$work/spus.txt"
grep -q '^  role: server ' "$work/spus.txt" || fail "tessera spus shows no 'role: server' for relay"
grep -q '^  a graph run fills: upstream (the server.s address), key (the run.s token)$' "$work/spus.txt" \
    || fail "tessera spus does not show the options a run fills"
graph="$src/tests/run/relay/relay.yaml"
"$tessera" check "$graph" || fail "tessera check $graph exited $?"

sh "$src/tests/run/run_graph.sh" "$build/bin" "$graph" "$work/run" 20 spheres-native --size 1024x768 \
    || fail "the relay's frames differ from the reference (or the run failed)"

report="$work/run/run/relay-report.txt"
[ -f "$report" ] || fail "the relay wrote no report ($report)"
cat "$report"
server=$(sed -n 's/.*"name": "server".*"address": "\([^"]*\)".*/\1/p' "$work/run/stats.json")
[ -n "$server" ] || fail "no server address in $work/run/stats.json"
grep -q "^relay#1: upstream=$server key=set frames=20 buffers=[1-9][0-9]* bytes=[1-9][0-9]*\$" "$report" \
    || fail "the report does not say 20 frames went to $server with the run's token"
echo "PASS: an out-of-tree network SPU ran in a graph, to $server, bit-identical"
