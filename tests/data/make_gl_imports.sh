#!/bin/sh
# tests/data/make_gl_imports.sh — regenerates gl_imports.txt: every gl*
# function that glxgears, the xscreensaver-gl hacks, and the libGLU they
# load import from libGL (the faker must export all of them).
# Usage: tests/data/make_gl_imports.sh > tests/data/gl_imports.txt
# Needs: mesa-utils, xscreensaver-gl, binutils (nm). glX*/egl*/glu* are
# not GL commands and are left out. Counts per source go to stderr.
set -eu

gl_imports() {
    # Undefined dynamic symbols, version suffix stripped, gl commands only.
    nm -D --undefined-only "$1" | awk '{print $NF}' | sed 's/@.*//' |
        grep '^gl[A-Z]' | grep -v '^glX' || true
}

is_elf() {
    [ -f "$1" ] && [ "$(head -c 4 "$1" | od -An -c | tr -d ' ')" = '177ELF' ]
}

command -v dpkg >/dev/null || { echo "make_gl_imports.sh: needs dpkg" >&2; exit 1; }
dpkg -L xscreensaver-gl >/dev/null 2>&1 || { echo "make_gl_imports.sh: install xscreensaver-gl" >&2; exit 1; }
[ -x /usr/bin/glxgears ] || { echo "make_gl_imports.sh: install mesa-utils (glxgears)" >&2; exit 1; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

gl_imports /usr/bin/glxgears | sort -u > "$tmp/glxgears"

: > "$tmp/hacks.all"
hacks=0
for f in $(dpkg -L xscreensaver-gl | grep '^/usr/libexec/xscreensaver/.'); do
    is_elf "$f" || continue
    hacks=$((hacks + 1))
    gl_imports "$f" >> "$tmp/hacks.all"
done
sort -u "$tmp/hacks.all" > "$tmp/hacks"

# The hacks link libGLU, which calls gl* itself (gluBuild2DMipmaps,
# gluPerspective, ...); those calls also land in the faker.
glu=$(ldconfig -p | awk '/libGLU\.so\.1 /{print $NF; exit}')
if [ -n "$glu" ]; then
    gl_imports "$glu" | sort -u > "$tmp/glu"
else
    echo "make_gl_imports.sh: libGLU.so.1 not found; its imports are not included" >&2
    : > "$tmp/glu"
fi

sort -u "$tmp/glxgears" "$tmp/hacks" "$tmp/glu"
{
    echo "glxgears: $(wc -l < "$tmp/glxgears") gl functions"
    echo "xscreensaver-gl ($hacks programs): $(wc -l < "$tmp/hacks") gl functions"
    echo "glxgears + hacks: $(sort -u "$tmp/glxgears" "$tmp/hacks" | wc -l) gl functions"
    echo "libGLU ($glu): $(wc -l < "$tmp/glu"), not imported by the programs themselves: $(sort -u "$tmp/glxgears" "$tmp/hacks" | comm -13 - "$tmp/glu" | tr '\n' ' ')"
    echo "total: $(sort -u "$tmp/glxgears" "$tmp/hacks" "$tmp/glu" | wc -l)"
} >&2
