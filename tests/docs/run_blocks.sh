#!/usr/bin/env bash
# tests/docs/run_blocks.sh [--xvfb] SRC BUILD PAGE.md... — runs every shell block of
# the given Markdown pages, so the documentation cannot drift from the code.
#
# A shell block is a fenced block opened by ```sh, ```bash or ```console (in
# a console block only the lines starting with "$ " are commands). Each runs
# under `bash -e -o pipefail` in a scratch folder of its own that looks like
# the repository root: every top-level entry of SRC is linked there, and
# `build` links to BUILD, so `build/bin/tessera`, `examples/graphs/tcp.yaml`
# and relative outputs (`out/...`) mean what they mean in a checkout; BUILD/bin
# is also first on PATH. The block must exit 0 within BLOCK_TIMEOUT seconds
# (default 120); then its process group is killed (servers started with `&`
# end with it) and every file the block says it writes must exist: the
# values of output=, assemble=, file=, stats=, --out, --stats, -o and "> F"
# (a %d pattern, {stream}, {client} or $var in a name matches any text; a
# --out of tessera run/exec/replay --graph names a folder).
#
# A block that cannot run here (it needs another host, or builds and tests
# the tree itself) is preceded, on the line just above its fence, by
#     <!-- docs-test: skip REASON -->
# (an HTML comment: Markdown shows nothing of it), and is listed with its
# reason; a docs-test tag anywhere else fails the page; the summary line counts run and skipped
# blocks. Blocks run one after another (a page's blocks may use fixed ports).
# --xvfb: the blocks get a private Xvfb (DISPLAY) for programs that open
# windows (tests/faker/xvfb.sh).
set -uo pipefail
xvfb=0
[ "${1:-}" = --xvfb ] && { xvfb=1; shift; }
src=$(cd "$1" && pwd) build=$(cd "$2" && pwd)
shift 2
timeout_s=${BLOCK_TIMEOUT:-120}
scratch=$(mktemp -d "${TMPDIR:-/tmp}/tsr-docs.XXXXXX")
if [ "$xvfb" = 1 ]; then
  . "$src/tests/faker/xvfb.sh"
  start_xvfb "$scratch"
fi
trap 'stop_xvfb 2>/dev/null; rm -rf "$scratch"' EXIT
ran=0 skipped=0 failed=0
skip_tag='^<!-- docs-test: skip (.+) -->$'
shell_fence='^```(sh|bash|console)[[:space:]]*$'

# expected_outputs BLOCKFILE: one glob per line for each file the block writes.
expected_outputs() {
  grep -v '^[[:space:]]*#' "$1" | sed 's/[[:space:]]#.*$//' | tr ' \t' '\n\n' | awk '
    function emit(p) {
      gsub(/^["\x27]+|["\x27;)]+$/, "", p)
      if (p == "" || p ~ /^-/ || p == "/dev/null" || p ~ /^[0-9]+$/) return
      gsub(/%[0-9]*d/, "*", p); gsub(/\{stream\}|\{client\}/, "*", p)
      gsub(/\$[A-Za-z_][A-Za-z_0-9]*|\$\{[^}]*\}/, "*", p)
      print p
    }
    prev == "--out" || prev == "--stats" || prev == "-o" || prev == ">" { emit($0) }
    /^(output|assemble|file|stats)=/ { sub(/^[a-z]+=/, ""); emit($0) }
    /^>[^>&]/ { emit(substr($0, 2)) }
    { prev = $0 }'
}

run_block() { # PAGE LINE BLOCKFILE TAG-LINE
  local page=$1 line=$2 file=$3 tag=$4 dir reason rc missing=0
  if [[ $tag =~ $skip_tag ]]; then
    reason=${BASH_REMATCH[1]}
    echo "SKIP $page:$line: $reason"
    skipped=$((skipped + 1))
    return
  fi
  if grep -q 'docs-test:' "$file"; then
    echo "FAIL $page:$line: a docs-test tag belongs on the line above the fence, as '<!-- docs-test: skip REASON -->'"
    failed=$((failed + 1))
    return
  fi
  # `build` is the real build tree: a block that configures or builds it
  # (cmake -S/-B, cmake --build, scripts/build) would point it at this
  # scratch folder, gone afterwards, or rebuild it under the running suite.
  if grep -qE '(^|[;&|(`[:space:]])(cmake[[:space:]]+(-S|-B|--build)|(\./)?scripts/(build|test|run-example))' "$file"; then
    echo "FAIL $page:$line: the block configures or builds the tree, which the docs tests run inside: tag it '<!-- docs-test: skip REASON -->'"
    failed=$((failed + 1))
    return
  fi
  dir="$scratch/$(basename "$page" .md)-$line"
  mkdir -p "$dir"
  for e in "$src"/* "$src"/.[!.]*; do
    [ -e "$e" ] || continue
    case $(basename "$e") in build|build-*|out|.git) continue ;; esac
    ln -s "$e" "$dir/$(basename "$e")"
  done
  ln -s "$build" "$dir/build"
  mkdir "$dir/out"
  cp "$file" "$dir.sh"
  cache_before=$(stat -c %Y "$build/CMakeCache.txt" 2>/dev/null)
  # A session of its own, so that whatever the block left running (a server
  # started with &) is found and ended with it.
  (cd "$dir" && PATH="$build/bin:$PATH" setsid -w bash -c \
      'echo $$ >"$1"; exec timeout -k 5 "$2" bash -e -o pipefail "$3"' \
      sh "$dir.sid" "$timeout_s" "$dir.sh" >"$dir.log" 2>&1 </dev/null)
  rc=$?
  pkill -KILL -s "$(cat "$dir.sid")" 2>/dev/null
  # `build` is the real build tree: a block that configures it (cmake -B
  # build) would point it at this scratch folder, which is gone afterwards.
  if [ "$(stat -c %Y "$build/CMakeCache.txt" 2>/dev/null)" != "$cache_before" ]; then
    echo "FAIL $page:$line: the block reconfigured the build tree $build (re-run cmake there); a block that builds the tree must be tagged skip"
    failed=$((failed + 1))
    return
  fi
  if [ "$rc" -ne 0 ]; then
    echo "FAIL $page:$line: exit status $rc; its output:"
    sed 's/^/    /' "$dir.log" | tail -n 30
    failed=$((failed + 1))
    return
  fi
  while IFS= read -r want; do
    (cd "$dir" && compgen -G "$want" >/dev/null) && continue
    echo "FAIL $page:$line: the block says it writes $want, which does not exist"
    missing=1
  done < <(expected_outputs "$file")
  if [ "$missing" -ne 0 ]; then
    sed 's/^/    /' "$dir.log" | tail -n 30
    failed=$((failed + 1))
    return
  fi
  echo "ok   $page:$line"
  ran=$((ran + 1))
}

for page in "$@"; do
  [ -f "$page" ] || { echo "run_blocks: no such page: $page" >&2; exit 2; }
  rel=${page#"$src"/}
  n=0
  # Split the page into blocks: BLOCK<TAB>START-LINE then its lines.
  while IFS= read -r header; do
    n=$((n + 1))
    line=${header#*$'\t'}
    awk -v want="$line" '
      NR == want { inblk = 1; console = ($0 ~ /console/); next }
      inblk && /^```/ { exit }
      inblk { if (!console) print; else if (sub(/^\$ /, "")) print }' \
      "$page" > "$scratch/block"
    tag=""
    [ "$line" -gt 1 ] && tag=$(sed -n "$((line - 1))p" "$page")
    run_block "$rel" "$line" "$scratch/block" "$tag"
  done < <(awk '/^```(sh|bash|console)[[:space:]]*$/ { printf "BLOCK\t%d\n", NR }' "$page")
  [ "$n" -gt 0 ] || echo "note: $rel has no shell block"
  # A tag that is not just above a shell block's fence would silently do
  # nothing: refuse it.
  while IFS=: read -r tagline text; do
    fence=$(sed -n "$((tagline + 1))p" "$page")
    [[ $text =~ $skip_tag && $fence =~ $shell_fence ]] && continue
    echo "FAIL $rel:$tagline: a docs-test tag must read '<!-- docs-test: skip REASON -->' just above a shell block's fence"
    failed=$((failed + 1))
  done < <(grep -n 'docs-test:' "$page")
done
echo "docs blocks: $ran ran, $skipped skipped, $failed failed"
[ "$failed" -eq 0 ]
