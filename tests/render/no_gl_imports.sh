#!/bin/sh
# tests/render/no_gl_imports.sh — a plugin that draws must not import any
# gl* / OSMesa* symbol nor depend on libGL / libOSMesa: it resolves them
# through dlopen + OSMesaGetProcAddress, so it can live next to the faker.
# usage: no_gl_imports.sh PLUGIN.so
set -u
so=$1
[ -f "$so" ] || { echo "FAIL: $so does not exist" >&2; exit 1; }
imports=$(nm -D --undefined-only "$so" | awk '{print $NF}' | grep -E '^(gl|OSMesa)' )
needed=$(readelf -d "$so" | grep NEEDED | grep -Ei 'libGL|OSMesa|glapi')
echo "undefined symbols: $(nm -D --undefined-only "$so" | wc -l)"
status=0
if [ -n "$imports" ]; then echo "FAIL: $so imports: $imports" >&2; status=1; fi
if [ -n "$needed" ]; then echo "FAIL: $so needs: $needed" >&2; status=1; fi
[ $status -eq 0 ] && echo "PASS: no gl*/OSMesa* imports, no GL library dependency"
exit $status
