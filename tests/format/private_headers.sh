#!/usr/bin/env bash
# tests/format/private_headers.sh ROOT — no folder includes another
# folder's private header. A header used across folders is installed
# (include/tessera/, included as "tessera/...") or moved. Every quoted
# #include of a tracked C source or header outside tests/ and include/ is
# resolved to the tracked headers it can name (generated and system
# headers are not tracked: skipped); it passes when one of them lies in the
# includer's own folder. Folders: core/ is one (libtessera and its graph
# model), spus/NAME each one, every other top-level folder one. The few interfaces of internal static libraries that one program
# links (below, each with its reason) are allowed and listed. Prints every
# offender with the header it names, and how many includes it checked, so
# a run that checked nothing cannot pass.
set -euo pipefail
root=${1:?usage: private_headers.sh ROOT}
cd "$root"
git rev-parse --is-inside-work-tree >/dev/null 2>&1 || {
  echo "private_headers: $root is not a git work tree (the tracked files are read)" >&2; exit 2; }

# header path -> why another folder may include it
declare -A allowed=(
  [mothership/mothership.h]="the mothership's static library, linked into the tessera program (cli/)"
  [mothership/control.h]="the mothership's control messages, spoken by the tessera program's node side (cli/)"
  [mothership/util.h]="the mothership's static library helpers the tessera program shares (cli/)"
  [server/node.h]="the server node's static library, linked into the tessera program and the mothership"
  [spus/display_stream/display_stream.h]="the display stream's static library, linked by readback and binaryswap (it names the pack SPU, so it cannot live in libtessera_client)"
  [spus/capture/capfile.h]="the capture file format's static library, read by tessera replay (cli/)"
  [spus/binaryswap/strategies/strategy.h]="bench/ measures binaryswap's compositing strategies"
  [spus/binaryswap/synthetic.h]="bench/ composites binaryswap's synthetic layers"
)

folder_of() {
  case $1 in
    core/*) echo core ;;
    spus/*/*) echo "spus/$(echo "$1" | cut -d/ -f2)" ;;
    */*) echo "${1%%/*}" ;;
    *) echo . ;;
  esac
}

mapfile -t headers < <(git ls-files -- '*.h' | grep -v -e '^tests/' -e '^include/')
checked=0
offenders=0
used_allowed=0
while IFS= read -r -d '' file; do
  case $file in tests/* | include/*) continue ;; esac
  [ -f "$file" ] || continue
  mine=$(folder_of "$file")
  while IFS= read -r inc; do
    [ -n "$inc" ] || continue
    case $inc in tessera/*) continue ;; esac
    checked=$((checked + 1))
    # What the name can reach: relative to the includer, or any tracked
    # header whose path ends in it (an include directory).
    rel=$(realpath -m --relative-to=. "$(dirname "$file")/$inc")
    found=()
    for h in "${headers[@]}"; do
      if [ "$h" = "$rel" ] || [[ $h == */"$inc" ]] || [ "$h" = "$inc" ]; then found+=("$h"); fi
    done
    [ "${#found[@]}" -gt 0 ] || continue # generated or system
    ok=0
    for h in "${found[@]}"; do
      [ "$(folder_of "$h")" = "$mine" ] && ok=1
    done
    [ "$ok" -eq 1 ] && continue
    for h in "${found[@]}"; do
      if [ -n "${allowed[$h]:-}" ]; then
        ok=1
        used_allowed=$((used_allowed + 1))
      fi
    done
    [ "$ok" -eq 1 ] && continue
    echo "private_headers: $file includes \"$inc\" (${found[*]}), private to another folder: install it under include/tessera/ or move what is shared"
    offenders=$((offenders + 1))
  done < <(sed -nE 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"([^"]+)".*/\1/p' "$file")
done < <(git ls-files -z -- '*.c' '*.h')
if [ "$checked" -eq 0 ]; then
  echo "private_headers: no quoted include checked under $root" >&2; exit 1
fi
echo "private_headers: allowed across folders:"
for h in "${!allowed[@]}"; do echo "  $h: ${allowed[$h]}"; done | sort
echo "private_headers: $checked includes checked, $used_allowed of allowed interfaces, $offenders private headers used across folders"
[ "$offenders" -eq 0 ]
