#!/usr/bin/env bash
# tests/format/file_sizes.sh ROOT — a file per job: no tracked C source or
# header has more than 1,000 lines, outside tests/, bench/, examples/ and
# generated code (*_gen.c, *_gen.h; none is tracked today). Prints every
# offender with its line count and fails if there is one; prints how many
# files it counted, so a test that counted nothing cannot pass.
set -euo pipefail
root=${1:?usage: file_sizes.sh ROOT}
limit=1000
cd "$root"
git rev-parse --is-inside-work-tree >/dev/null 2>&1 || {
  echo "file_sizes: $root is not a git work tree (the tracked files are counted)" >&2; exit 2; }
counted=0
offenders=0
while IFS= read -r -d '' file; do
  case $file in
    tests/* | bench/* | examples/* | *_gen.c | *_gen.h) continue ;;
  esac
  [ -f "$file" ] || continue
  lines=$(wc -l <"$file")
  counted=$((counted + 1))
  if [ "$lines" -gt "$limit" ]; then
    echo "file_sizes: $file: $lines lines (limit $limit): cut it along its seams"
    offenders=$((offenders + 1))
  fi
done < <(git ls-files -z -- '*.c' '*.h')
if [ "$counted" -eq 0 ]; then
  echo "file_sizes: no tracked *.c or *.h counted under $root" >&2; exit 1
fi
echo "file_sizes: $counted files counted, $offenders over $limit lines"
[ "$offenders" -eq 0 ]
