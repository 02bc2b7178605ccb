#!/usr/bin/env bash
# tests/docs/no_outside_pointers.sh SRC — fails, naming file:line, when a
# tracked file points outside the repository: a path into the developers'
# machines (/work/..., /home/NAME, /root/, /Users/), the sibling folder
# ../shared that a clone does not have, or a Markdown link whose relative
# target is not a file or folder of the repository. A clone must stand on
# its own. Fuzz corpora (tests/fuzz/corpus-*) are inputs, not pointers, and
# are not read; binary files neither, nor this folder (tests/docs), whose
# script and README spell the patterns out.
set -uo pipefail
src=$(cd "$1" && pwd)
cd "$src"
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files)
else
  mapfile -t files < <(find . -path ./build -prune -o -path ./.git -prune -o -type f -print | sed 's#^\./##')
fi
self=tests/docs/no_outside_pointers.sh
bad=0 checked=0
pattern='\.\./shared|(^|[^A-Za-z0-9_.~-])/(work|home/[a-z][a-z0-9_-]*|root|Users)/'
for f in "${files[@]}"; do
  case $f in tests/fuzz/corpus-*|"$self") continue ;; esac
  [ -f "$f" ] || continue
  checked=$((checked + 1))
  case $f in *.md) ;; *) continue ;; esac
  dir=$(dirname "$f")
  while IFS=: read -r line target; do
    target=${target%%#*}
    [ -n "$target" ] || continue
    case $target in http:*|https:*|mailto:*|/*) continue ;; esac
    resolved=$(realpath -m "$dir/$target")
    case $resolved in "$src"|"$src"/*) ;; *)
      echo "$f:$line: link to $target leaves the repository"; bad=$((bad + 1)); continue ;; esac
    [ -e "$resolved" ] && continue
    echo "$f:$line: link to $target: no such file in the repository"
    bad=$((bad + 1))
  done < <(grep -noE '\]\([^) ]+\)' "$f" | sed -E 's/^([0-9]+):\]\((.*)\)$/\1:\2/')
done
# Paths into the developers' machines, in every text file at once (grep -I
# passes over binary files).
while IFS= read -r hit; do
  echo "$hit"
  bad=$((bad + 1))
done < <(printf '%s\0' "${files[@]}" | grep -zvE "^(tests/fuzz/corpus-|tests/docs/)" |
         xargs -0 grep -nIHE "$pattern" 2>/dev/null)
echo "outside pointers: $bad in $checked files"
[ "$bad" -eq 0 ]
