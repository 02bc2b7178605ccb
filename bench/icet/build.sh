#!/usr/bin/env bash
# bench/icet/build.sh — builds IceT (Kitware's MPI compositing library) out of
# the tessera tree and our harness icet_composite.c against it, for
# `bench/run icet` (bench/icet/README.md says where to get IceT).
#
#   bench/icet/build.sh ICET_SOURCE_DIR   configure, build and install IceT
#                                         (Release, no OpenGL, no tests), then
#                                         the harness
#   bench/icet/build.sh --harness         the harness only, against an
#                                         existing install
#
# Everything goes under the bench build tree (TESSERA_BENCH_BUILD, default
# build-bench): IceT's build in icet/build, its install in icet/install
# (TESSERA_ICET_PREFIX overrides the install), the harness in
# icet/icet_composite. The harness links libtessera from the same bench tree
# (configured here as bench/run does when it is missing) and compiles the
# very generator the binaryswap bench hands its peers, spus/binaryswap/synthetic.c.
# Needs mpicc (Debian: apt-get install libopenmpi-dev openmpi-bin) and cmake.
set -euo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
build=${TESSERA_BENCH_BUILD:-$root/build-bench}
jobs=${TESSERA_BENCH_JOBS:-2}
prefix=${TESSERA_ICET_PREFIX:-$build/icet/install}

usage() { echo "usage: bench/icet/build.sh ICET_SOURCE_DIR | --harness" >&2; exit 2; }
(($# == 1)) || usage
command -v mpicc >/dev/null || { echo "bench/icet/build.sh: mpicc not found (apt-get install libopenmpi-dev openmpi-bin)" >&2; exit 1; }

if [[ $1 != --harness ]]; then
    src=$(cd "$1" && pwd)
    [[ -f $src/src/include/IceT.h ]] || { echo "bench/icet/build.sh: $src is not an IceT source tree (no src/include/IceT.h)" >&2; exit 1; }
    mkdir -p "$build/icet/build"
    # -O2 like the bench tree; IceT's own defaults otherwise (magic k 8,
    # max image split 512), so the figures are IceT as shipped.
    cmake -S "$src" -B "$build/icet/build" -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_C_FLAGS_RELEASE="-O2 -DNDEBUG" -DCMAKE_INSTALL_PREFIX="$prefix" \
        -DCMAKE_C_COMPILER=mpicc -DBUILD_SHARED_LIBS=OFF \
        -DICET_USE_OPENGL=OFF -DICET_USE_OPENGL3=OFF -DICET_USE_MPI=ON -DICET_BUILD_TESTING=OFF \
        >"$build/icet/configure.log" 2>&1 ||
        { tail -30 "$build/icet/configure.log" >&2; echo "bench/icet/build.sh: IceT configure failed" >&2; exit 1; }
    cmake --build "$build/icet/build" -j"$jobs" >"$build/icet/build.log" 2>&1 ||
        { tail -30 "$build/icet/build.log" >&2; echo "bench/icet/build.sh: IceT build failed" >&2; exit 1; }
    cmake --install "$build/icet/build" >"$build/icet/install.log" 2>&1 ||
        { tail -30 "$build/icet/install.log" >&2; echo "bench/icet/build.sh: IceT install failed" >&2; exit 1; }
    # Which IceT this is, for the results: the version IceT's build states
    # and, when the source is a git checkout, its commit.
    {
        sed -n 's/^#define ICET_VERSION[[:space:]]*"\(.*\)"/version \1/p' "$prefix/include/IceTConfig.h"
        if git -C "$src" rev-parse HEAD >/dev/null 2>&1; then echo "commit $(git -C "$src" rev-parse HEAD)"; fi
        [[ -f $src/.icet-commit ]] && echo "commit $(cat "$src/.icet-commit")"
        echo "source $src"
    } >"$prefix/tessera-icet-version.txt"
fi

[[ -f $prefix/include/IceT.h ]] || { echo "bench/icet/build.sh: no IceT install in $prefix (run bench/icet/build.sh ICET_SOURCE_DIR)" >&2; exit 1; }

if [[ ! -f $build/CMakeCache.txt ]]; then
    mkdir -p "$build"
    cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_FLAGS_RELEASE="-O2 -DNDEBUG" \
        -DTESSERA_SANITIZE=OFF -DTESSERA_FUZZ=OFF >"$build/bench-configure.log" 2>&1 ||
        { cat "$build/bench-configure.log" >&2; echo "bench/icet/build.sh: configure failed" >&2; exit 1; }
fi
mkdir -p "$build/icet"
cmake --build "$build" -j"$jobs" --target tessera >"$build/icet/tessera-build.log" 2>&1 ||
    { tail -30 "$build/icet/tessera-build.log" >&2; echo "bench/icet/build.sh: libtessera build failed" >&2; exit 1; }

libdir=$prefix/lib
[[ -d $libdir ]] || libdir=$prefix/lib64
mpicc -std=c11 -O2 -DNDEBUG -Wall -Wextra -Werror -D_GNU_SOURCE \
    -I"$prefix/include" -I"$root/include" -I"$build/generated/include" -I"$root/spus/binaryswap" \
    "$root/bench/icet/icet_composite.c" "$root/spus/binaryswap/synthetic.c" \
    -o "$build/icet/icet_composite" \
    -L"$libdir" -lIceTMPI -lIceTCore -L"$build/lib" -Wl,-rpath,"$build/lib" -ltessera -lm
echo "bench/icet/build.sh: built $build/icet/icet_composite against IceT in $prefix"
