#!/usr/bin/env bash
# tests/faker/glx_configs.sh PROGRAM FAKER_DIR OUTDIR — the faker's GLX
# configs next to Mesa's (tests/faker/glx_configs_driver.c): on a private default
# Xvfb (GLX enabled, about 180 TrueColor visuals) the system's libGL.so.1
# (Mesa) and the faker's answer the same attribute lists, each in its own
# process, and the faker's answers must hold to Mesa's; then on an Xvfb
# with -extension GLX (a depth-24 and a depth-32 TrueColor visual) and on
# one also without Composite (one depth-24 TrueColor visual), where no Mesa
# GLX can answer, the faker's answers must hold to the same Mesa answers.
set -euo pipefail
prog=$1 faker=$2 out=$3
rm -rf "$out"; mkdir -p "$out"
. "$(dirname "$0")/xvfb.sh"
mesa=$(ldconfig -p | awk '/libGL\.so\.1 .*x86-64/ {print $NF; exit}')
[ -n "$mesa" ] && [ -e "$mesa" ] || { echo "SKIP: no system libGL.so.1 (libgl1 with Mesa's GLX)"; exit 77; }
status=0
start_xvfb "$out"
echo "== default Xvfb ($DISPLAY): Mesa ($mesa) against the faker"
"$prog" ask "$mesa" > "$out/mesa.txt"
"$prog" ask "$faker/libGL.so.1" > "$out/faker.txt"
"$prog" compare "$out/mesa.txt" "$out/faker.txt" || status=1
stop_xvfb
for server in "-extension GLX" "-extension GLX -extension Composite"; do
  start_xvfb "$out" $server
  tag=${server// /_}
  echo "== Xvfb $server ($DISPLAY, TrueColor visuals of depth: $(xdpyinfo 2>/dev/null | awk '/class:/ {c=$2} /depth:/ && c=="TrueColor" {printf "%s ", $2}')): the faker against Mesa's answers above"
  "$prog" ask "$faker/libGL.so.1" > "$out/faker$tag.txt"
  "$prog" compare "$out/mesa.txt" "$out/faker$tag.txt" || status=1
  stop_xvfb
done
exit $status
