#!/usr/bin/env bash
# tests/faker/glx_multisample.sh — a window of a multisample GLX config
# (glx_multisample_driver.c) through [render], [pack -> tessera node
# render] and a 2x2 tilesort wall of four `tessera node` render servers, on
# a private Xvfb: every labelled line (the config's and GL's sample sizes,
# hashes of the colour, depth and stencil read back each way) and every
# colour pixel of the first read must equal what Mesa's own GLX gives with
# the same 4 samples on the same Xvfb (faker_glx_multisample_native), and
# the frame render writes at the swap (under [render] and on pack's node)
# what Mesa's swap puts in the X window, pixel for pixel.
# usage: glx_multisample.sh PROGRAM NATIVE TESSERA OUT_DIR
set -u
prog=$1 native=$2 TESSERA=$3 out=$4
. "$(dirname "$0")/xvfb.sh"
rm -rf "$out" && mkdir -p "$out" "$out/render-frames" "$out/pack-frames" || exit 1
start_xvfb "$out"
. "$(dirname "$0")/graphs_lib.sh"
run_native
run_graphs "$out/render-frames/f-%04d.png" "$out/pack-frames/f-%04d.png"
# What is compared. Mesa's own glReadPixels and glCopyPixels of a
# multisample window read one sample of each pixel, not the resolved
# colour (its "drawn colour" line blends no pixel, while its glCopyTexImage2D
# of the same window and the picture its swap puts in the X window are
# resolved and equal): ARB_multisample has the colour buffer hold the
# resolved colour, which tessera reads, so tessera's colour reads must
# equal Mesa's displayed picture, pixel for pixel, and its glCopyPixels
# copies resolved colours (that line is not compared). Depth and stencil
# (one sample, as Mesa) and every other line must equal Mesa's. On the wall
# the glCopyTex(Sub)Image lines are left out: a copy across tiles reads
# pixels another server has (tests/piglit/open.tsv, "cross-tile copy").
line() { sed -n "s/^$2: //p" "$out/$1.txt" | awk '{print $1}'; }
picture=$(line native displayed)
[ -n "$picture" ] && [ "$picture" = "$(line native resolved)" ] && [ "$picture" = "$(line native frame)" ] ||
  fail "native: the picture shown ($picture) is not the window resolved ($(line native resolved))"
grep -q '^resolved: .* blended [1-9]' "$out/native.txt" || fail "native: no pixel blended by the samples"
compared='^(config|gets|drawn|copypixels|swapped|resolved|copyteximage|copytexsubimage|frame):'
for r in "${runs[@]}"; do
  keep=$compared
  [ "$r" = wall ] && keep='^(config|gets|drawn|copypixels|swapped):'
  grep -E "$keep" "$out/native.txt" >"$out/native.$r.cmp"
  grep -E "$keep" "$out/$r.txt" >"$out/$r.cmp"
  diff -u "$out/native.$r.cmp" "$out/$r.cmp" >"$out/$r.diff" || { fail "$r differs from Mesa:"; cat "$out/$r.diff" >&2; }
  for read in "drawn colour" "swapped colour"; do
    [ "$(line "$r" "$read")" = "$picture" ] || fail "$r: $read $(line "$r" "$read") is not Mesa's picture $picture"
  done
  # the first colour read, pixel by pixel, against Mesa's resolved window
  python3 - "$out/native.txt.resolved.rgba" "$out/$r.txt.rgba" "$r" <<'PY' || status=1
import sys
a, b = open(sys.argv[1], 'rb').read(), open(sys.argv[2], 'rb').read()
px = [i for i in range(0, len(a), 4) if a[i:i + 4] != b[i:i + 4]]
print(f"{sys.argv[3]}: {len(px)} of {len(a) // 4} colour pixels differ from Mesa's resolved window")
sys.exit(1 if px or len(a) != len(b) else 0)
PY
done
# The frame written at the swap (render's PNG, bottom-up here as glReadPixels
# rows) against the picture Mesa's swap put in the X window, in R, G, B.
for r in render pack; do
  python3 - "$out/native.txt.displayed.rgba" "$out/$r-frames/f-0000.png" "$r" <<'PY' || status=1
import struct, sys, zlib
shown = open(sys.argv[1], 'rb').read()
data = open(sys.argv[2], 'rb').read()
assert data[:8] == b'\x89PNG\r\n\x1a\n', 'not a PNG'
pos, idat = 8, b''
while pos < len(data):
    n, kind = struct.unpack('>I4s', data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    if kind == b'IHDR':
        w, h, depth, colour = struct.unpack('>IIBB', body[:10])
    elif kind == b'IDAT':
        idat += body
    pos += 12 + n
assert depth == 8 and colour in (2, 6) and body is not None, 'an 8-bit RGB(A) PNG'
bpp = 3 if colour == 2 else 4
raw, rows, prev = zlib.decompress(idat), [], bytearray(w * bpp)
for y in range(h):
    f, line = raw[y * (w * bpp + 1)], bytearray(raw[y * (w * bpp + 1) + 1:(y + 1) * (w * bpp + 1)])
    for i in range(len(line)):
        a = line[i - bpp] if i >= bpp else 0
        b, c = prev[i], prev[i - bpp] if i >= bpp else 0
        p = a + b - c
        pred = [0, a, b, (a + b) // 2, a if abs(p - a) <= abs(p - b) and abs(p - a) <= abs(p - c) else b if abs(p - b) <= abs(p - c) else c][f]
        line[i] = (line[i] + pred) & 255
    rows.append(line)
    prev = line
differ = 0
for y in range(h):
    for x in range(w):
        png = rows[h - 1 - y][x * bpp:x * bpp + 3]
        differ += bytes(png) != shown[4 * (y * w + x):4 * (y * w + x) + 3]
print(f"{sys.argv[3]}: frame 0: {differ} of {w * h} pixels differ from what Mesa's swap shows")
sys.exit(1 if differ or w * h * 4 != len(shown) else 0)
PY
done
python3 - "$out/native.txt.resolved.rgba" "$out/native.txt.rgba" <<'PY'
import sys
a, b = open(sys.argv[1], 'rb').read(), open(sys.argv[2], 'rb').read()
n = sum(a[i:i + 4] != b[i:i + 4] for i in range(0, len(a), 4))
print(f"(Mesa's own glReadPixels: {n} of {len(a) // 4} pixels are one sample's colour, not the resolved one)")
PY
[ $status -eq 0 ] && echo "OK: ${#runs[@]} runs draw Mesa's multisample picture and answer as Mesa ($(wc -l <"$out/native.txt") lines)"
exit $status
