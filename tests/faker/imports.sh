#!/usr/bin/env bash
# tests/faker/imports.sh FAKER_DIR — every gl*/glX*/egl* symbol that
# glxgears, glxinfo, libGLU.so.1 and each xscreensaver-gl hack (the
# binaries of /usr/libexec/xscreensaver that link libGL or libEGL) import
# must be defined by the faker's libGL.so.1 / libEGL.so.1 / libOpenGL.so.0:
# the hacks are linked with immediate binding (BIND_NOW), so one missing
# symbol keeps a program from starting at all.
set -euo pipefail
faker=$1
for l in libGL.so.1 libEGL.so.1 libOpenGL.so.0; do
  [ -e "$faker/$l" ] || echo "note: $faker/$l does not exist: its symbols count as missing"
done
libglu=$(ls /usr/lib/*-linux-gnu/libGLU.so.1 /usr/lib/libGLU.so.1 2>/dev/null | head -n1 || true)
bins=()
for b in /usr/bin/glxgears /usr/bin/glxinfo "$libglu"; do
  [ -n "$b" ] && [ -e "$b" ] || { echo "SKIP: $b${b:+ }not installed (scripts/setup-debian: mesa-utils, libglu1-mesa)"; exit 77; }
  bins+=("$b")
done
# One readelf over every file: "File: PATH" headers, then its NEEDED lines.
hacks=0
while read -r b; do
  bins+=("$b")
  hacks=$((hacks + 1))
done < <(readelf -d /usr/libexec/xscreensaver/* 2>/dev/null | awk '
  /^File: / { file = $2 }
  /NEEDED/ && /\[lib(GL|EGL)\.so\.1\]/ && file != "" { print file; file = "" }')
[ "$hacks" -gt 0 ] || { echo "SKIP: no xscreensaver-gl hack in /usr/libexec/xscreensaver (scripts/setup-debian)"; exit 77; }

syms() { { nm -D "$@" 2>/dev/null || true; } | awk '{print $NF}' | sed 's/@.*//' | { grep -E '^(gl|glX|egl)[A-Z]' || true; } | sort -u; }
exports=$(mktemp); imports=$(mktemp); trap 'rm -f "$exports" "$imports"' EXIT
syms --defined-only "$faker/libGL.so.1" "$faker/libEGL.so.1" "$faker/libOpenGL.so.0" > "$exports"
syms --undefined-only "${bins[@]}" > "$imports"
missing=$(comm -23 "$imports" "$exports")
echo "faker exports $(wc -l < "$exports") gl*/glX*/egl* symbols; ${#bins[@]} binaries ($hacks xscreensaver-gl hacks) import $(wc -l < "$imports") distinct ones"
if [ -n "$missing" ]; then
  echo "FAIL: $(echo "$missing" | wc -l) imports the faker does not export:"
  for s in $missing; do
    users=$(for b in "${bins[@]}"; do nm -D --undefined-only "$b" 2>/dev/null | awk '{print $NF}' | sed 's/@.*//' | grep -qx "$s" && basename "$b"; done | head -n3 | tr "\n" " " || true)
    echo "  $s (imported by: $users...)"
  done
  exit 1
fi
echo "OK: 0 missing imports"
