#!/usr/bin/env bash
# tests/faker/xscreensaver.sh TESSERA FRAMES_CHECK SPEC_YAML OUTDIR [MODE]
# The real-program sweep (issue 12, item 6): EVERY GL hack of Debian's
# xscreensaver-gl package (the programs with a config/NAME.xml in
# `dpkg -L xscreensaver-gl`), and glxgears, run unmodified under a private
# Xvfb through `tessera exec` with the default chain ([render] 1x1 to PNG
# files), $FAKER_SWEEP_JOBS (default 2) at a time, each in its own session.
# MODE pack or wall: glxgears and 25 of the hacks (the five GLSL ones and
# 20 others, $graph_hacks below) as the app node of a graph instead,
# `tessera exec --graph tests/faker/sweep_MODE.yaml`: pack ->
# server render over TCP, or tilesort grid=2,2 over four servers with the
# tiles assembled; the frames judged are the server's, or the assembled
# ones. Same verdicts, at least 25 must run.
#
# A program passes ("ran") when, within $FAKER_SWEEP_SECONDS (default 30),
# it has written at least 10 frames that are not all one colour, not all
# the same picture (FRAMES_CHECK --some-blank: hacks fade in from black),
# then dies of the SIGTERM it is sent (status 143; with a graph, the run
# stops every node and tessera exec dies of the SIGTERM too, 143, with
# "tessera exec: interrupted by signal 15", no node
# dead of another signal) within 5 s, leaving no
# process of its session behind, having logged no "not supported by
# tessera" warning for a function spec/gl.yaml has. Anything else fails —
# crashed (exited or died of another signal), hung (no frames, or still
# alive 5 s after SIGTERM), drew only blank frames, too few frames, left
# processes — unless the program, run natively (Mesa's EGL/GLX on the
# same Xvfb, no faker, for as long), fails the same way: it ends by itself
# before the time is up, or SIGTERM does not end it, or it leaves
# processes behind too. Then it is reported, not failed. The hacks that use
# GLSL shaders and buffer objects (the ones that ask for a GLSL context:
# "prefersGLSL") must be among those that ran, and at least 25 must run.
# Prints one line per program and the counts; exits 1 naming each failure.
set -uo pipefail
tessera=$1 frames=$2 spec=$3 out=$4 mode=${5:-render}
jobs_max=${FAKER_SWEEP_JOBS:-2}
limit=${FAKER_SWEEP_SECONDS:-30}
want=10
hackdir=/usr/libexec/xscreensaver
# glsl_hacks, graph_hacks, check_glsl_hacks
. "$(dirname "$0")/sweep_programs.sh"
case $mode in
  render) graph="" ;;
  pack | wall) graph=$(cd "$(dirname "$0")" && pwd)/sweep_$mode.yaml ;;
  *) echo "FAIL: mode '$mode' is not render, pack or wall"; exit 2 ;;
esac

command -v dpkg >/dev/null && dpkg -s xscreensaver-gl >/dev/null 2>&1 ||
  { echo "SKIP: xscreensaver-gl is not installed (scripts/setup-debian installs it)"; exit 77; }
mapfile -t hacks < <(dpkg -L xscreensaver-gl | sed -n 's|.*/config/\([^/]*\)\.xml$|\1|p' | sort -u)
[ "${#hacks[@]}" -gt 0 ] || { echo "FAIL: dpkg -L xscreensaver-gl lists no config/*.xml"; exit 1; }
check_glsl_hacks "$hackdir" "${hacks[@]}" || exit 1
if [ -n "$graph" ]; then
  for h in $graph_hacks; do
    [[ " ${hacks[*]} " == *" $h "* ]] || { echo "FAIL: $h is not a hack of xscreensaver-gl"; exit 1; }
  done
  read -ra hacks <<< "$(echo $graph_hacks)"
fi
# $FAKER_SWEEP_ONLY="NAME ...": only those hacks (to look at one by hand).
if [ -n "${FAKER_SWEEP_ONLY:-}" ]; then
  read -ra hacks <<< "$FAKER_SWEEP_ONLY"
  glsl_hacks=$(for g in $glsl_hacks; do [[ " $FAKER_SWEEP_ONLY " == *" $g "* ]] && echo "$g"; done)
fi
rm -rf "$out"; mkdir -p "$out"
. "$(dirname "$0")/xvfb.sh"
start_xvfb "$out"

# gl commands the spec has: "- name: Foo" is glFoo.
sed -n 's/^  - name: \([A-Za-z0-9_]*\).*/gl\1/p' "$spec" | sort -u > "$out/spec_names.txt"

alive() {  # alive PID: running, not a zombie
  local st
  st=$(awk '{print $3}' "/proc/$1/stat" 2>/dev/null) || return 1
  [ -n "$st" ] && [ "$st" != Z ]
}

# run DIR MODE PROGRAM ARGS...: MODE faker or native. Writes DIR/result:
# "STATUS FRAMES GOOD TERMED HUNG LEFT" (GOOD: FRAMES_CHECK passed).
run() {
  local d=$1 mode=$2; shift 2
  mkdir -p "$d"
  if [ "$mode" = faker ] && [ -n "$graph" ]; then
    # The graph's outputs (f-NNNN.png, tiles/) are relative to --out.
    setsid "$tessera" exec --graph "$graph" --out "$d" -- "$@" > "$d/stdout.txt" 2> "$d/stderr.txt" &
  elif [ "$mode" = faker ]; then
    setsid "$tessera" exec --out "$d/f-%04d.png" -- "$@" > "$d/stdout.txt" 2> "$d/stderr.txt" &
  else
    setsid "$@" > "$d/stdout.txt" 2> "$d/stderr.txt" &
  fi
  local pid=$! start=$SECONDS good=0 n=0 checked=-1 termed=0 hung=0 left=0 status
  while alive "$pid" && [ $((SECONDS - start)) -lt "$limit" ]; do
    if [ "$mode" = faker ]; then
      n=$(find "$d" -maxdepth 1 -name 'f-*.png' | wc -l)
      # The check decodes every frame written so far, so it runs each
      # time their number has doubled: the decoding stays within twice
      # the frames a program writes. (Checked every 4 new frames, a hack
      # that writes hundreds of frames a second, atunnel, had the check
      # decode O(frames^2) PNGs: under load the pack sweep ran past its
      # 300 s in the flake hunt.)
      if [ "$n" -ge $((want + 2)) ] && [ "$n" -ge $((checked * 2)) ]; then
        checked=$n
        if "$frames" --some-blank "$d" f- "$want" > "$d/frames.txt" 2>&1; then good=1; break; fi
      fi
    fi
    sleep 0.2
  done
  if alive "$pid"; then
    termed=1
    kill -TERM "$pid" 2>/dev/null
    for _ in $(seq 50); do alive "$pid" || break; sleep 0.1; done
    if alive "$pid"; then hung=1; kill -KILL "$pid" 2>/dev/null; fi
  fi
  wait "$pid"; status=$?
  # Children (the image hacks' xscreensaver-getimage) end after their
  # parent; on a loaded machine that takes a moment: 3 s before "left".
  for _ in $(seq 30); do [ -n "$(ps -o pid= -s "$pid" 2>/dev/null)" ] || break; sleep 0.1; done
  if [ -n "$(ps -o pid= -s "$pid" 2>/dev/null)" ]; then
    left=1
    ps -o pid=,comm= -s "$pid" > "$d/left.txt"
    kill -KILL -- "-$pid" 2>/dev/null
  fi
  if [ "$mode" = faker ]; then
    n=$(find "$d" -maxdepth 1 -name 'f-*.png' | wc -l)
    [ "$good" = 1 ] || { "$frames" --some-blank "$d" f- "$want" > "$d/frames.txt" 2>&1 && good=1; }
  fi
  echo "$status $n $good $termed $hung $left" > "$d/result"
}

# judge NAME: one line; the verdict word first (ran, native, FAIL).
judge() {
  local name=$1 d=$out/$1/faker status n good termed hung left why="" warned spec_warned
  read -r status n good termed hung left < "$d/result"
  warned=$(sed -n 's/.*faker: \(gl[A-Za-z0-9_]*\) is not supported by tessera.*/\1/p' "$d/stderr.txt" | sort -u | tr '\n' ' ')
  spec_warned=$(for f in $warned; do grep -qx "$f" "$out/spec_names.txt" && printf '%s ' "$f"; done)
  # kind: what natively would be the same failure (self: the program ends
  # by itself; hung: not ended by SIGTERM; left: processes left behind).
  local kind=self
  if [ "$hung" = 1 ]; then why="hung: still running 5 s after SIGTERM" kind=hung
  elif [ "$termed" = 0 ]; then why="crashed: ended by itself (status $status) after $n frames"
  elif [ "$n" = 0 ]; then why="hung: no frame in ${limit} s"
  elif [ "$good" != 1 ]; then why="$(tail -n 1 "$d/frames.txt" | sed 's/.*check failed: //') ($(head -n 1 "$d/frames.txt"))"
  elif [ -z "$graph" ] && [ "$status" != 143 ]; then why="status $status after SIGTERM, not 143" kind=status
  # A graph run stops every node on SIGTERM, says so, then ends by the
  # same signal (cli/cmd_run.c): 143.
  elif [ -n "$graph" ] && { [ "$status" != 143 ] || ! grep -qx "tessera exec: interrupted by signal 15" "$d/stderr.txt"; }; then
    why="status $status after SIGTERM, not 143 with 'tessera exec: interrupted by signal 15'" kind=status
  # The run's reason is the first failure, so that line says the SIGTERM
  # came first; a server may then see the app go before its own SIGTERM
  # ("dropped"), but no node may die of another signal.
  elif [ -n "$graph" ] && grep '^tessera node: ' "$d/stderr.txt" | grep 'signal' | grep -qv 'signal 15'; then
    why="a node died of a signal: $(grep '^tessera node: ' "$d/stderr.txt" | grep signal | grep -v 'signal 15' | head -n 2 | tr '\n' ' ')"
  elif [ "$left" = 1 ]; then why="left processes behind: $(tr '\n' ' ' < "$d/left.txt")" kind=left
  elif [ -n "$spec_warned" ]; then why="warned for functions the spec has: $spec_warned" kind=faker
  fi
  if [ -z "$why" ]; then
    echo "ran $name: $(head -n 1 "$d/frames.txt")${warned:+; not in the spec, warned: $warned}"
    return
  fi
  # The same program natively, for as long: does it fail that way too?
  local nd=$out/$name/native nstatus nhung nleft ntermed same=""
  run "$nd" native "${cmd[@]}"
  read -r nstatus _ _ ntermed nhung nleft < "$nd/result"
  if [ "$kind" = self ] && [ "$ntermed" = 0 ]; then
    same="natively it also ends by itself (status $nstatus): $(head -c 200 "$nd/stderr.txt" | tr '\n' ' ')"
  elif [ "$kind" = hung ] && [ "$nhung" = 1 ]; then same="natively SIGTERM does not end it either"
  elif [ "$kind" = status ] && [ "$nstatus" = "$status" ]; then same="natively SIGTERM gives status $nstatus too"
  elif [ "$kind" = left ] && [ "$nleft" = 1 ]; then
    same="natively it leaves $(tr '\n' ' ' < "$nd/left.txt")behind too"
  fi
  if [ -n "$same" ]; then
    echo "native $name: $why; $same"
  else
    echo "FAIL $name: $why; $(head -c 300 "$d/stderr.txt" | tr '\n' ' ')"
  fi
}

one() {  # one NAME PROGRAM ARGS...
  local name=$1; shift
  cmd=("$@")
  run "$out/$name/faker" faker "${cmd[@]}"
  judge "$name" > "$out/$name/verdict"
  # A failure is tried once more: a program that crashes, hangs or draws
  # nothing does so again, while one that only met the machine's load
  # (image hacks forking xscreensaver-getimage, start-up over the limit)
  # runs the second time. Both verdicts are printed.
  if grep -q '^FAIL ' "$out/$name/verdict"; then
    mv "$out/$name/verdict" "$out/$name/verdict.first"
    rm -rf "$out/$name/faker"
    run "$out/$name/faker" faker "${cmd[@]}"
    judge "$name" > "$out/$name/verdict"
    echo "retried $name: first $(cat "$out/$name/verdict.first")"
  fi
  cat "$out/$name/verdict"
  # A program that ran keeps its last two frames (80 runs: 30 MB otherwise).
  if grep -q '^ran ' "$out/$name/verdict"; then
    find "$out/$name/faker" -maxdepth 1 -name 'f-*.png' | sort | head -n -2 | xargs -r rm -f
    rm -rf "$out/$name/faker/tiles"
  fi
}

names=()
begin=$SECONDS
if [ -z "${FAKER_SWEEP_ONLY:-}" ] && command -v glxgears >/dev/null; then
  names+=(glxgears)
  one glxgears glxgears -geometry 320x240 &
fi
for h in "${hacks[@]}"; do
  # Xvfb is a job too: only the programs' runs count.
  while [ "$(jobs -rp | grep -cvx "$XVFB_PID")" -ge "$jobs_max" ]; do wait -n; done
  names+=("$h")
  if [ -x "$hackdir/$h" ]; then
    one "$h" "$hackdir/$h" -geometry 320x240 &
  else
    mkdir -p "$out/$h"; echo "FAIL $h: $hackdir/$h is not an executable" | tee "$out/$h/verdict" &
  fi
done
while [ "$(jobs -rp | grep -cvx "$XVFB_PID")" -gt 0 ]; do wait -n; done

ran=0 native=0 failed=() retried=0
for n in "${names[@]}"; do
  case $(cut -d' ' -f1 "$out/$n/verdict") in
    ran) ran=$((ran + 1)); [ -e "$out/$n/verdict.first" ] && retried=$((retried + 1)) ;;
    native) native=$((native + 1)) ;;
    *) failed+=("$n") ;;
  esac
done
for g in $glsl_hacks; do
  if ! grep -q '^ran ' "$out/$g/verdict" 2>/dev/null && [[ " ${failed[*]} " != *" $g "* ]]; then
    failed+=("$g")
    echo "FAIL $g: a GLSL and buffer-object hack must run, not only fail natively too"
  fi
done
echo "xscreensaver-gl sweep ($([ -n "$graph" ] && echo "graph $(basename "$graph")" || echo "[render] 1x1")): ${#names[@]} programs (${#hacks[@]} hacks of xscreensaver-gl$([ "${names[0]}" = glxgears ] && echo ' and glxgears')) in $((SECONDS - begin)) s, $jobs_max at a time: $ran ran (>= $want frames not of one colour, ended by SIGTERM, nothing left; $retried of them on a second try), $native fail natively too (reported), ${#failed[@]} failed"
[ -n "${FAKER_SWEEP_ONLY:-}" ] || [ "$ran" -ge 25 ] || { echo "FAIL: only $ran programs ran, at least 25 must"; exit 1; }
if [ "${#failed[@]}" -gt 0 ]; then
  echo "FAIL: ${failed[*]}"
  exit 1
fi
