#!/usr/bin/env bash
# tests/capture/bad.sh TESSERA ASKS OUTDIR [CORPUS_DIR]
# Malformed capture files, made from a real capture of asks (64x48, 2
# frames, with replies): each must be refused by `tessera replay --info` and by `tessera
# replay` with exit status 2 and exactly one line on stderr that names the
# file and the byte offset ("FILE: byte N: ..."), before any frame is
# written (--info checks every buffer; replay checks the header first).
# With CORPUS_DIR the files are also copied there as bad-*.tsrcap and the
# good capture as ok-asks.tsrcap (the fuzz corpus, tests/fuzz/README.md).
set -euo pipefail
tessera=$1 asks=$2 out=$3 corpus=${4:-}
rm -rf "$out"; mkdir -p "$out"; cd "$out"
"$asks" "capture file=good.tsrcap ! render output=orig-%04d.png" 2 > /dev/null
size=$(stat -c %s good.tsrcap)
put() {  # put FILE OFFSET HEXBYTES: overwrite bytes in place
  printf "$(echo "$3" | sed 's/../\\x&/g')" | dd of="$1" bs=1 seek="$2" conv=notrunc status=none
}
mk() { cp good.tsrcap "$1.tsrcap"; }
mk truncated-record; truncate -s $((size - 100)) truncated-record.tsrcap
head -c 40 good.tsrcap > truncated-header.tsrcap
mk version-2; put version-2.tsrcap 8 02000000
mk wire-magic; put wire-magic.tsrcap 12 54535732
mk header-bytes-lie; put header-bytes-lie.tsrcap 48 ffffff0000000000
mk frames-lie; put frames-lie.tsrcap 24 09000000
mk record-length-lie; put record-length-lie.tsrcap 72 ffffffffffffff7f
mk record-kind; put record-kind.tsrcap 64 07000000
mk buffer-magic; put buffer-magic.tsrcap 80 00000000
mk buffer-opcodes-lie; put buffer-opcodes-lie.tsrcap 84 ffff0000
# An opcode no command has (0 is never valid), in the first buffer: the
# last byte before its data is its first command's opcode.
mk opcode-zero
n=$(od -An -tu4 -j84 -N4 good.tsrcap | tr -d ' ')
put opcode-zero.tsrcap $((80 + 16 + (n + 7) / 8 * 8 - 1)) 00
# Random bytes, with and without the magic in front.
awk 'BEGIN { srand(12); for (i = 0; i < 4096; i++) printf "%c", int(rand() * 256) }' LC_ALL=C > random.tsrcap
{ printf 'TSRCAP\r\n'; head -c 2000 random.tsrcap; } > random-after-magic.tsrcap
: > empty.tsrcap
fails=0
for f in *.tsrcap; do
  [ "$f" = good.tsrcap ] && continue
  for how in info replay; do
    s=0
    if [ $how = info ]; then
      "$tessera" replay --info "$f" > out.txt 2> err.txt || s=$?
    else
      "$tessera" replay "$f" --chain "render output=$f-%04d.png" > out.txt 2> err.txt || s=$?
    fi
    lines=$(wc -l < err.txt)
    if [ "$s" -ne 2 ] || [ "$lines" -ne 1 ] || ! grep -q "^tessera replay: $f: byte [0-9]*: " err.txt; then
      echo "FAIL: $how $f: status $s, $lines lines:"; cat err.txt; fails=1
    else
      echo "ok: $how $f: $(cat err.txt)"
    fi
  done
done
# The header checks come before any frame is fed; a bad buffer inside the
# stream is found when it is reached, after the frames before it.
for f in truncated-header version-2 wire-magic header-bytes-lie record-length-lie; do
  if ls "$f".tsrcap-*.png > /dev/null 2>&1; then echo "FAIL: $f: frames were written"; fails=1; fi
done
"$tessera" replay --info good.tsrcap > /dev/null || { echo "FAIL: the good capture was refused"; fails=1; }
if [ -n "$corpus" ]; then
  mkdir -p "$corpus"
  cp good.tsrcap "$corpus/ok-asks.tsrcap"
  for f in *.tsrcap; do [ "$f" = good.tsrcap ] || cp "$f" "$corpus/bad-$f"; done
fi
exit $fails
