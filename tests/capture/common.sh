# tests/capture/common.sh — sourced by the capture tests: same_frames
# compares two frame series with tessera imgdiff (0 differing pixels,
# every frame, the same number of frames).
same_frames() {  # same_frames TESSERA A_PATTERN B_PATTERN COUNT [A_FIRST]
  local tessera=$1 a=$2 b=$3 count=$4 first=${5:-0} i
  for ((i = 0; i < count; i++)); do
    local fa fb
    fa=$(printf "$a" $((first + i))) fb=$(printf "$b" "$i")
    [ -e "$fa" ] || { echo "FAIL: $fa is missing"; exit 1; }
    [ -e "$fb" ] || { echo "FAIL: $fb is missing"; exit 1; }
    local d
    d=$("$tessera" imgdiff "$fa" "$fb" | sed -n 's/^differing_pixels: //p')
    [ "$d" = 0 ] || { echo "FAIL: $fa vs $fb: ${d:-no answer} differing pixels"; exit 1; }
  done
  # Nothing beyond the frames asked for.
  local extra
  extra=$(printf "$b" "$count")
  [ ! -e "$extra" ] || { echo "FAIL: $extra exists: more frames than $count"; exit 1; }
  echo "ok: $count frames of $b equal $a (0 differing pixels each)"
}
# The frames compared are not all the same picture (the scene moves).
frames_move() {  # frames_move TESSERA A.png B.png
  if "$1" imgdiff "$2" "$3" > /dev/null; then echo "FAIL: $2 and $3 are the same picture"; exit 1; fi
}
