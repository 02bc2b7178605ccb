#!/bin/sh
# tests/spu/template_out_of_tree.sh — what a third party does: install this
# build into a fresh prefix, build spus/template and a small driver against
# that prefix only (pkg-config), then run the SPU in a chain and check its
# counts. Usage: template_out_of_tree.sh CMAKE BUILD_DIR SOURCE_DIR WORK_DIR CC [EXTRA_CFLAGS]
# (EXTRA_CFLAGS: the sanitizer flags of a sanitized build, else empty).
set -eu
cmake_cmd=$1 build=$2 src=$3 work=$4 cc=$5 extra=${6:-}

rm -rf "$work"
mkdir -p "$work"
if ! "$cmake_cmd" --install "$build" --prefix "$work/prefix" >"$work/install.log" 2>&1; then
    cat "$work/install.log"
    echo "template_out_of_tree: cmake --install failed" >&2
    exit 1
fi
pcdir="$work/prefix/lib/pkgconfig"
if [ ! -f "$pcdir/tessera.pc" ]; then
    pc=$(find "$work/prefix" -name tessera.pc | head -n 1)
    [ -n "$pc" ] || { echo "template_out_of_tree: no tessera.pc was installed" >&2; exit 1; }
    pcdir=$(dirname "$pc")
fi
export PKG_CONFIG_PATH="$pcdir"
libdir=$(dirname "$pcdir")
echo "installed: $(pkg-config --modversion tessera); cflags: $(pkg-config --cflags tessera)"

# Build from copies, away from the source tree, so only installed headers
# can be found.
cp -R "$src/spus/template" "$work/template-src"
mkdir -p "$work/driver-src"
cp "$src/tests/spu/template_driver.c" "$src/tests/spu/template_counts.h" "$work/driver-src/"
make -s -C "$work/template-src" BUILD_DIR="$work/spus" CC="$cc" CFLAGS="-O1 -g -Werror $extra"
# shellcheck disable=SC2046,SC2086 # pkg-config output is a list of flags
"$cc" -std=c11 -Wall -Wextra -Werror $extra $(pkg-config --cflags tessera) \
    -o "$work/template_driver" "$work/driver-src/template_driver.c" $(pkg-config --libs tessera)

LD_LIBRARY_PATH="$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" TESSERA_SPU_PATH="$work/spus" \
    "$work/template_driver" "$work/counts.txt"
cat "$work/counts.txt"
