#!/usr/bin/env bash
# tests/faker/only_faker.sh TESSERA MAPS_PRELOAD OUTDIR — under `tessera
# exec`, programs map the faker's GL libraries and no system GL library
# (faker/README.md): glxgears (its /proc/PID/maps read while it draws),
# glxinfo, a piglit test through waffle on GLX and on EGL, and apitrace's
# glretrace and eglretrace replaying traces recorded here natively, and a
# VTK 9 program (vtk_cone.py: VTK's rendering library links glvnd's
# libGLX.so.0 and libOpenGL.so.0 through GLEW) (their /proc/self/maps
# copied at exit by MAPS_PRELOAD, since they end by themselves;
# $FAKER_PRELOAD, the sanitizer runtimes of a sanitized build, goes
# first). VTK 9.1 needs OpenGL 3.2, which tessera does not offer: natively
# the program draws its cone; under `tessera exec` VTK must say it found no
# OpenGL 3.2 and the program exit 1 with no frame written. A system GL library is any libGL, libGLX, libGLX_*,
# libOpenGL, libEGL, libEGL_*, libGLdispatch, libGLESv1_CM, libGLESv2 or
# *_dri.so outside the faker's directory (Mesa's libglapi and libgallium,
# which render's OSMesa uses, are not). Private default Xvfb (GLX on).
set -euo pipefail
# the programs here are Debian's (glxinfo, python3, piglit, the replayers):
# what they keep at exit is theirs, not the sanitized faker's
export ASAN_OPTIONS="${ASAN_OPTIONS:-}:detect_leaks=0"
tessera=$1 preload=$2 out=$3
rm -rf "$out"; mkdir -p "$out/frames" "$out/maps"
. "$(dirname "$0")/xvfb.sh"
piglit_bin=/usr/lib/x86_64-linux-gnu/piglit/bin
piglit_test=$piglit_bin/gl-1.0-dlist-bitmap
for need in glxgears glxinfo apitrace glretrace eglretrace; do
  command -v "$need" >/dev/null || { echo "SKIP: $need is not installed (scripts/setup-debian installs mesa-utils, apitrace)"; exit 77; }
done
[ -x "$piglit_test" ] || { echo "SKIP: piglit is not installed (scripts/setup-debian installs it)"; exit 77; }
vtk_python=/usr/bin/python3 # Debian's, where python3-vtk9 installs vtkmodules
"$vtk_python" -c 'import vtkmodules.vtkRenderingOpenGL2' 2>/dev/null ||
  { echo "SKIP: python3-vtk9 is not installed (scripts/setup-debian installs it)"; exit 77; }
vtk_cone=$(dirname "$0")/vtk_cone.py
faker_dir=$(cd "$(dirname "$tessera")/../lib/faker" && pwd)
start_xvfb "$out"
fail=0 last_status=0

# check NAME MAPSFILE: the faker's libGL is mapped, no system GL library is.
check() {
  local name=$1 maps=$2
  local system
  system=$(awk '{print $6}' "$maps" | sort -u | grep -E '/(libGL|libGLX|libGLX_[a-z]+|libOpenGL|libEGL|libEGL_[a-z]+|libGLdispatch|libGLESv1_CM|libGLESv2)\.so|_dri\.so' | grep -v "^$faker_dir/" || true)
  if ! grep -q "$faker_dir/libGL.so.1" "$maps"; then
    echo "FAIL $name: the faker's libGL.so.1 is not mapped"; fail=1
  elif [ -n "$system" ]; then
    echo "FAIL $name maps system GL libraries:"; echo "$system" | sed 's/^/    /'; fail=1
  else
    echo "ok   $name: $(awk '{print $6}' "$maps" | sort -u | grep -c "^$faker_dir/") faker libraries ($(awk '{print $6}' "$maps" | sort -u | grep "^$faker_dir/" | xargs -n1 basename | tr '\n' ' ')), no system GL library"
  fi
}

# run_to_end NAME CMD...: under tessera exec with the maps copied at exit.
run_to_end() {
  local name=$1; shift
  rm -f "$out/maps/"maps.*
  local status=0
  FAKER_MAPS_DIR="$out/maps" LD_PRELOAD="${FAKER_PRELOAD:+$FAKER_PRELOAD }$preload" timeout 120 \
    "$tessera" exec --out "$out/frames/$name-%04d.png" -- "$@" > "$out/$name.log" 2>&1 || status=$?
  last_status=$status
  local maps
  maps=$(ls -S "$out/maps/"maps.* 2>/dev/null | head -n1 || true)
  if [ -z "$maps" ]; then
    echo "FAIL $name: no maps copied (status $status)"; tail -n5 "$out/$name.log"; fail=1; return
  fi
  cp "$maps" "$out/$name.maps"
  check "$name (status $status)" "$out/$name.maps"
}

# Traces recorded natively (Mesa) on the same server.
apitrace trace -o "$out/glx.trace" "$piglit_test" -auto > "$out/trace-glx.log" 2>&1
PIGLIT_PLATFORM=x11_egl apitrace trace --api egl -o "$out/egl.trace" "$piglit_test" -auto > "$out/trace-egl.log" 2>&1
[ -s "$out/glx.trace" ] && [ -s "$out/egl.trace" ] || { echo "FAIL: apitrace recorded no trace"; cat "$out"/trace-*.log; exit 1; }

# glxgears: runs until killed; its maps are read while it draws.
LD_PRELOAD="${FAKER_PRELOAD:-}" "$tessera" exec --out "$out/frames/glxgears-%04d.png" -- glxgears > "$out/glxgears.log" 2>&1 &
gears=$!
for _ in $(seq 300); do
  ls "$out/frames/"glxgears-0002.png > /dev/null 2>&1 && break
  kill -0 "$gears" 2>/dev/null || break
  sleep 0.1
done
if kill -0 "$gears" 2>/dev/null && ls "$out/frames/"glxgears-0002.png > /dev/null 2>&1; then
  cp "/proc/$gears/maps" "$out/glxgears.maps"
  check "glxgears (running, pid $gears)" "$out/glxgears.maps"
else
  echo "FAIL glxgears: no frame in 30 s"; tail -n5 "$out/glxgears.log"; fail=1
fi
kill "$gears" 2>/dev/null || true
wait "$gears" 2>/dev/null || true

# each of these ends by itself with status 0, as it does natively
succeeds() { # NAME CMD...
  run_to_end "$@"
  [ "$last_status" = 0 ] || { echo "FAIL $1: exit status $last_status under tessera exec"; tail -n5 "$out/$1.log"; fail=1; }
}
succeeds glxinfo glxinfo -B
succeeds piglit_glx env PIGLIT_PLATFORM=glx "$piglit_test" -auto
succeeds piglit_egl env PIGLIT_PLATFORM=x11_egl "$piglit_test" -auto
succeeds glretrace glretrace "$out/glx.trace"
succeeds eglretrace eglretrace "$out/egl.trace"

# VTK: the program itself works natively on this server (draws its cone);
# under tessera exec only the faker is mapped and VTK refuses cleanly.
if "$vtk_python" "$vtk_cone" > "$out/vtk-native.log" 2>&1 && grep -qE 'vtk_cone: [1-9][0-9]* of [0-9]+ pixels differ' "$out/vtk-native.log"; then
  echo "ok   vtk natively: $(grep -h 'vtk_cone:' "$out/vtk-native.log" | cut -d' ' -f2- | paste -sd';' -)"
else
  echo "FAIL vtk natively: the cone was not drawn"; tail -n5 "$out/vtk-native.log"; fail=1
fi
run_to_end vtk "$vtk_python" "$vtk_cone"
if [ "$last_status" != 1 ] || ! grep -q 'Unable to find a valid OpenGL 3.2 or later implementation' "$out/vtk.log" ||
  ! grep -q 'vtk_cone: VTK finds no OpenGL 3.2' "$out/vtk.log" || ls "$out/frames/"vtk-* > /dev/null 2>&1; then
  echo "FAIL vtk under tessera exec: not VTK's clean refusal of OpenGL below 3.2 (exit 1) with no frame written (status $last_status)"; tail -n5 "$out/vtk.log"; fail=1
else
  echo "ok   vtk under tessera exec: VTK reports no OpenGL 3.2 it can use, exits 1, no frame written"
fi
grep -h "PIGLIT: {\"result\"" "$out/piglit_glx.log" "$out/piglit_egl.log" | sed 's/^/piglit under tessera exec: /' || true
exit $fail
