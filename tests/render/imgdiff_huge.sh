#!/bin/sh
# tests/render/imgdiff_huge.sh — imgdiff reads both headers before it
# decodes either image: a small file claiming 16384x16384 against a 64x64
# image is a size mismatch refused at once, in bounded memory; the same
# file against itself is refused by --max-pixels (default 8192x8192), and
# a file over the per-side limit names that limit. Each is one line, exit 2.
# usage: imgdiff_huge.sh TESSERA PNG_CLAIMS OUT_DIR LIMIT_KB (0: no ulimit,
# for sanitizer builds, whose shadow memory needs the address space)
set -u
tessera=$1 claims=$2 out=$3 limit_kb=$4
rm -rf "$out" && mkdir -p "$out" || exit 1
"$claims" "$out/huge.png" 16384 16384 || exit 1
"$claims" "$out/small.png" 64 64 || exit 1
"$claims" "$out/wide.png" 40000 1 || exit 1
status=0
# expect RC REGEX ARGS...: runs imgdiff (under the memory limit) and checks
# its exit code, that stderr matches and is one line.
expect() {
  want=$1 re=$2
  shift 2
  if [ "$limit_kb" != 0 ]; then
    (ulimit -v "$limit_kb" && exec "$tessera" imgdiff "$@") >"$out/out" 2>"$out/err"
  else
    "$tessera" imgdiff "$@" >"$out/out" 2>"$out/err"
  fi
  rc=$?
  echo "imgdiff $*: exit $rc: $(cat "$out/err")"
  [ "$rc" = "$want" ] || { echo "FAIL: exit $rc, expected $want"; status=1; }
  grep -Eq -- "$re" "$out/err" || { echo "FAIL: stderr does not match /$re/"; status=1; }
  [ "$(wc -l <"$out/err")" = 1 ] || { echo "FAIL: not one line"; status=1; }
}
expect 2 "size mismatch: .*huge.png is 16384x16384, .*small.png is 64x64" "$out/huge.png" "$out/small.png"
expect 2 "size mismatch: .*small.png is 64x64, .*huge.png is 16384x16384" "$out/small.png" "$out/huge.png"
expect 2 "huge.png claims 16384x16384 = 268435456 pixels, more than --max-pixels 67108864" \
  "$out/huge.png" "$out/huge.png"
expect 2 "huge.png claims 16384x16384 = 268435456 pixels, more than --max-pixels 1000" \
  --max-pixels 1000 "$out/huge.png" "$out/huge.png"
expect 2 "wide.png: claims 40000x1 pixels, more than the limit of 32768 per side" "$out/wide.png" "$out/small.png"
expect 2 "bad --max-pixels '0'" --max-pixels 0 "$out/small.png" "$out/small.png"
[ $status = 0 ] && echo "PASS: headers first, sizes bounded"
exit $status
