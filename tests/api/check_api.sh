#!/bin/sh
# tests/api/check_api.sh — the installed developer API as a third party
# sees it: `cmake --install` of this build into a prefix, then checks made
# with that prefix alone.
#
#   check_api.sh install  CMAKE BUILD_DIR PREFIX
#   check_api.sh headers  PREFIX CC
#   check_api.sh exports  PREFIX GCC
#   check_api.sh pkgconfig PREFIX CC [EXTRA_CFLAGS]
#
# install    installs the build into PREFIX (the other modes read it).
# headers    every installed header compiles alone (twice, -Wall -Wextra
#            -Werror) with -I PREFIX/include only, includes others by path
#            ("tessera/..."), and names no internal source folder.
# exports    the dynamic symbols each installed library exports (nm -D
#            --defined-only) are exactly the functions and variables the
#            installed headers declare for it: an exported symbol no
#            header declares is an internal that leaked, a declared one
#            the library does not export is a header that lies. Needs GCC
#            (the declarations are read with -aux-info).
# pkgconfig  tessera.pc links libtessera and libtessera_client (as needed:
#            an SPU that never sends depends on libtessera alone),
#            tessera-graph.pc adds libtessera_graph, and only
#            libtessera_graph depends on libyaml.
set -eu
mode=$1
shift
LC_ALL=C
export LC_ALL

fail() {
    echo "check_api $mode: $*" >&2
    exit 1
}

# The library each installed header's functions belong to. Every other
# header is libtessera's.
lib_of_header() {
    case $1 in
    tessera/graph.h) echo tessera_graph ;;
    tessera/dev/client.h) echo tessera_client ;;
    tessera/dev/net.h) echo tessera_net ;;
    tessera/glapi.h | tessera/gltsr_gen.h) echo tessera_gl ;;
    *) echo tessera ;;
    esac
}
# The installed libraries checked. libtessera_net (tessera/dev/net.h) is
# the network under libtessera_client, the tessera program and SPUs that
# talk to their peers themselves.
checked_libs="tessera tessera_client tessera_graph tessera_gl tessera_net"

headers_of() { (cd "$1/include" && find tessera -name '*.h' | sort); }

case $mode in
install)
    cmake_cmd=$1 build=$2 prefix=$3
    rm -rf "$prefix"
    if ! "$cmake_cmd" --install "$build" --prefix "$prefix" >"$prefix.log" 2>&1; then
        cat "$prefix.log"
        fail "cmake --install failed"
    fi
    [ -f "$prefix/include/tessera/spu.h" ] || fail "no headers under $prefix/include"
    echo "installed into $prefix"
    ;;

headers)
    prefix=$1 cc=$2
    work=$prefix.headers
    rm -rf "$work" && mkdir -p "$work"
    n=0
    for h in $(headers_of "$prefix"); do
        n=$((n + 1))
        # By path: every quoted include is one of ours, under tessera/.
        bad=$(grep -n '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$prefix/include/$h" |
            grep -v '"tessera/' || true)
        [ -z "$bad" ] || fail "$h includes a header by bare name: $bad"
        bad=$(grep -nE '(^|[^a-z_])(core|node|netlib)/[a-z_]' "$prefix/include/$h" || true)
        [ -z "$bad" ] || fail "$h names an internal source folder: $bad"
        printf '#include "%s"\n#include "%s"\n' "$h" "$h" >"$work/one.c"
        "$cc" -std=c11 -Wall -Wextra -Werror -fsyntax-only -I "$prefix/include" "$work/one.c" \
            >"$work/cc.log" 2>&1 || { cat "$work/cc.log"; fail "$h does not compile alone"; }
    done
    [ "$n" -gt 10 ] || fail "only $n headers installed"
    echo "$n installed headers compile alone"
    ;;

exports)
    prefix=$1 gcc=$2
    work=$prefix.exports
    rm -rf "$work" && mkdir -p "$work"
    # Every installed header in one translation unit, the GL headers with
    # their prototypes (libtessera_gl exports the spec's gl* functions).
    {
        echo '#define GL_GLEXT_PROTOTYPES 1'
        echo '#include <GL/gl.h>'
        echo '#include <GL/glext.h>'
        for h in $(headers_of "$prefix"); do echo "#include \"$h\""; done
    } >"$work/all.c"
    "$gcc" -std=c11 -fsyntax-only -aux-info "$work/aux.txt" -I "$prefix/include" "$work/all.c" \
        >"$work/cc.log" 2>&1 || { cat "$work/cc.log"; fail "the headers do not compile together"; }
    # aux-info lines: /* FILE:LINE:NC */ extern RET NAME (PARAMS); NC =
    # prototype, declaration (F: definition, i.e. static inline). The name
    # is the last word before the first " (".
    awk -v inc="$prefix/include/" '
        /^\/\* / && $2 ~ /:NC$/ {
            file = $2; sub(/:[0-9]+:NC$/, "", file)
            decl = $0; sub(/^\/\* [^ ]* \*\/ /, "", decl)
            if (decl ~ /^static /) next
            head = decl; sub(/ \(.*/, "", head)
            n = split(head, w, /[ *]+/); name = w[n]
            if (index(file, inc) == 1) {
                print "T", substr(file, length(inc) + 1), name
            } else if (file ~ /\/GL\/gl(ext)?\.h$/) {
                print "G", file, name
            }
        }' "$work/aux.txt" >"$work/decls.txt"
    # Variables: one `extern` declaration per line in our headers.
    for h in $(headers_of "$prefix"); do
        grep -n 'extern' "$prefix/include/$h" | grep -v 'extern "C"' | while IFS= read -r line; do
            name=$(printf '%s\n' "$line" |
                sed -nE 's/.*extern[^(]*[ *]([A-Za-z_][A-Za-z0-9_]*)[[:space:]]*(\[[^]]*\])?[[:space:]]*;.*/\1/p')
            [ -n "$name" ] || fail "$h: cannot read the extern declaration (keep it on one line): $line"
            echo "T $h $name"
        done
    done >>"$work/decls.txt"
    bad=$(awk '$3 !~ /^[A-Za-z_][A-Za-z0-9_]*$/' "$work/decls.txt")
    [ -z "$bad" ] || fail "cannot read these declarations: $bad"
    awk '$1 == "G" {print $3}' "$work/decls.txt" | sort -u >"$work/gl_decls.txt"
    awk '$1 == "T"' "$work/decls.txt" | while read -r _ h name; do
        echo "$(lib_of_header "$h") $name $h"
    done | sort -u >"$work/declared.txt"
    ndecl=$(wc -l <"$work/declared.txt")
    [ "$ndecl" -gt 100 ] || fail "only $ndecl declarations found in the installed headers"

    status=0
    summary=""
    for lib in $checked_libs; do
        so="$prefix/lib/lib$lib.so"
        [ -f "$so" ] || so=$(find "$prefix" -name "lib$lib.so" | head -n 1)
        if [ -z "$so" ] || [ ! -f "$so" ]; then fail "lib$lib.so is not installed"; fi
        # Names starting with _ are the toolchain's (_init, __bss_start,
        # sanitizer runtimes), never ours.
        nm -D --defined-only "$so" | awk 'NF >= 3 && $3 !~ /^_/ {print $3}' | sed 's/@.*//' |
            sort -u >"$work/exported-$lib.txt"
        awk -v l="$lib" '$1 == l {print $2}' "$work/declared.txt" | sort -u >"$work/declared-$lib.txt"
        allowed="$work/declared-$lib.txt"
        if [ "$lib" = tessera_gl ]; then
            sort -u "$work/declared-$lib.txt" "$work/gl_decls.txt" >"$work/allowed-$lib.txt"
            allowed="$work/allowed-$lib.txt"
        fi
        leaked=$(comm -23 "$work/exported-$lib.txt" "$allowed")
        if [ -n "$leaked" ]; then
            echo "lib$lib.so exports symbols no installed header declares (hide them, or declare them in an installed header):" >&2
            printf '%s\n' "$leaked" | sed 's/^/  /' >&2
            status=1
        fi
        missing=$(comm -13 "$work/exported-$lib.txt" "$work/declared-$lib.txt")
        if [ -n "$missing" ]; then
            echo "installed headers declare for lib$lib.so what it does not export:" >&2
            for s in $missing; do
                echo "  $s ($(awk -v l="$lib" -v s="$s" '$1 == l && $2 == s {print $3}' "$work/declared.txt"))" >&2
            done
            status=1
        fi
        summary="$summary lib$lib.so $(wc -l <"$work/exported-$lib.txt");"
    done
    echo "exported symbols:$summary"
    [ "$status" -eq 0 ] || fail "exports and installed headers differ"
    ;;

pkgconfig)
    prefix=$1 cc=$2 extra=${3:-}
    work=$prefix.pkgconfig
    rm -rf "$work" && mkdir -p "$work"
    pcdir=$(dirname "$(find "$prefix" -name tessera.pc | head -n 1)")
    [ -f "$pcdir/tessera.pc" ] || fail "no tessera.pc installed"
    [ -f "$pcdir/tessera-graph.pc" ] || fail "no tessera-graph.pc installed"
    libdir=$(dirname "$pcdir")
    PKG_CONFIG_PATH=$pcdir
    export PKG_CONFIG_PATH
    libs=$(pkg-config --libs tessera)
    glibs=$(pkg-config --libs tessera-graph)
    echo "tessera: $libs"
    echo "tessera-graph: $glibs"
    case " $libs " in *" -ltessera "*) ;; *) fail "tessera.pc does not link -ltessera" ;; esac
    case "$libs" in *-ltessera_client*) ;; *) fail "tessera.pc does not list libtessera_client" ;; esac
    case "$glibs" in *-ltessera_graph*) ;; *) fail "tessera-graph.pc does not link -ltessera_graph" ;; esac
    case " $glibs " in *" -ltessera "*) ;; *) fail "tessera-graph.pc does not require tessera" ;; esac
    case "$libs $glibs" in *yaml*) fail "pkg-config links libyaml into its users" ;; esac

    # A filter SPU, a sending SPU and a graph reader, built with pkg-config only.
    cat >"$work/filter.c" <<'EOF'
#include "tessera/spu.h"
#include "tessera/dev/pack.h"
int filter_probe(void);
int filter_probe(void) { return tsr_packer_pending(NULL) == 0 && tsr_dispatch_slot("Vertex3f") >= 0; }
EOF
    cat >"$work/sender.c" <<'EOF'
#include "tessera/dev/client.h"
void sender_probe(const tsr_options *o);
void sender_probe(const tsr_options *o)
{
    tsr_stream_client_config cfg = {0};
    tsr_stream_client_config_from_options(&cfg, o);
}
EOF
    cat >"$work/graph.c" <<'EOF'
#include <stdio.h>
#include "tessera/graph.h"
int main(void) { return printf("%p\n", (void *)&tsr_graph_free) < 0; }
EOF
    # shellcheck disable=SC2046,SC2086 # pkg-config output is a list of flags
    {
        "$cc" -std=c11 -Wall -Wextra -Werror -fPIC -shared -Wl,-z,defs $extra $(pkg-config --cflags tessera) \
            -o "$work/filter.so" "$work/filter.c" $(pkg-config --libs tessera) &&
        "$cc" -std=c11 -Wall -Wextra -Werror -fPIC -shared -Wl,-z,defs $extra $(pkg-config --cflags tessera) \
            -o "$work/sender.so" "$work/sender.c" $(pkg-config --libs tessera) &&
        "$cc" -std=c11 -Wall -Wextra -Werror $extra $(pkg-config --cflags tessera-graph) \
            -o "$work/graph" "$work/graph.c" $(pkg-config --libs tessera-graph)
    } >"$work/cc.log" 2>&1 || { cat "$work/cc.log"; fail "building against pkg-config failed"; }
    needed() { readelf -d "$1" | sed -n 's/.*(NEEDED).*\[\(.*\)\].*/\1/p' | tr '\n' ' '; }
    f=$(needed "$work/filter.so") s=$(needed "$work/sender.so") g=$(needed "$work/graph")
    echo "filter SPU needs: $f"
    echo "sending SPU needs: $s"
    echo "graph reader needs: $g"
    case "$f" in *libtessera.so*) ;; *) fail "the filter SPU does not depend on libtessera" ;; esac
    case "$f" in *libtessera_client*) fail "the filter SPU depends on libtessera_client" ;; esac
    case "$s" in *libtessera_client.so*) ;; *) fail "the sending SPU does not depend on libtessera_client" ;; esac
    case "$g" in *libtessera_graph.so*) ;; *) fail "the graph reader does not depend on libtessera_graph" ;; esac
    for lib in tessera tessera_client; do
        case $(needed "$libdir/lib$lib.so") in
        *yaml*) fail "lib$lib.so depends on libyaml" ;;
        esac
    done
    case $(needed "$libdir/libtessera_graph.so") in
    *yaml*) ;;
    *) fail "libtessera_graph.so does not depend on libyaml (is the graph model elsewhere?)" ;;
    esac
    echo "pkg-config: SPUs link libtessera (and libtessera_client when they send), never libyaml"
    ;;

*)
    fail "unknown mode (install, headers, exports, pkgconfig)"
    ;;
esac
