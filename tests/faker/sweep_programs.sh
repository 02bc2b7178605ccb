# tests/faker/sweep_programs.sh — sourced by xscreensaver.sh and
# sweep_exact.sh: the programs of the graph sweeps (issue 12, item 6).
#
# glsl_hacks: the hacks that draw with GLSL programs and buffer objects.
# Every hack imports glCreateShader and glUseProgram (xscreensaver's shared
# code, used when the context offers GLSL), so those imports do not tell;
# tracing every hack through `print` showed these five, and only these,
# call glCreateShader, glBindBuffer and glBufferData (GLSL 1.20 programs,
# vertex and index buffers, on tessera's OpenGL 2.1), and they are exactly
# the hacks that import the buffer-object functions: check_glsl_hacks
# fails naming any other hack that does.
glsl_hacks="etruscanvenus hypertorus projectiveplane romanboy sphereeversion"
# graph_hacks: the five and 20 others of different kinds (display lists,
# textures, lighting, glMaterial inside glBegin, many small draws): 26
# programs with glxgears.
graph_hacks="$glsl_hacks antinspect atunnel blinkbox bubble3d cubestorm discoball engine gears
  geodesic gflux glknots glmatrix glsnake hexstrut moebius molecule pipes polytopes queens superquadrics"
# check_glsl_hacks HACKDIR NAME...: every NAME whose binary imports a
# buffer-object function (nm -D) is in $glsl_hacks; else one FAIL line per
# such hack and status 1.
check_glsl_hacks() {
  local dir=$1 h bad=0; shift
  command -v nm >/dev/null || { echo "FAIL: nm (binutils) is needed to find the buffer-object hacks"; return 1; }
  for h in "$@"; do
    [ -x "$dir/$h" ] || continue
    if nm -D --undefined-only "$dir/$h" 2>/dev/null | grep -qwE 'gl(BindBuffer|BufferData|GenBuffers)(ARB)?' &&
      [[ " $glsl_hacks " != *" $h "* ]]; then
      echo "FAIL $h: imports buffer-object functions but is not among the GLSL hacks every graph sweep runs ($glsl_hacks)"
      bad=1
    fi
  done
  return $bad
}
