#!/bin/bash
# A batch killed at random points (SIGKILL, during its renders and writes), each kill followed by --resume (issue 39):
# after every kill, every image under its own name is whole and every view file stands beside its image; the final
# --resume completes the batch, and every file equals a clean run's, bit for bit, with no temporary file left.
#
#   bash KilledBatchResumes.sh PBDRR INPUT WORK
#
# Kills land on the batch's progress (when its count of written views reaches a target), then a few milliseconds on
# (the next view's write), so that they fall inside the batch on a fast or a slow machine alike.
set -u
pbdrr=$1
input=$2
work=$3
views=40
common=(--size 256 256 --samples 1e6 --seed 3 --angles "$views" --angle-step 9 -q --threads 1)
fail() {
  echo "KilledBatchResumes: $*" >&2
  exit 1
}
rm -rf "$work"
mkdir -p "$work/clean" "$work/killed"
"$pbdrr" "$input" "${common[@]}" -o "$work/clean/v_%02d.mha" || fail "the clean run failed"
whole_size=$(stat -c %s "$work/clean/v_00.mha")

# Every image under its name has the clean size, and every view file has its image beside it.
check_whole() {
  local image view
  for image in "$work"/killed/v_*.mha; do
    [ -e "$image" ] || continue
    [ "$(stat -c %s "$image")" = "$whole_size" ] || fail "after $1: $image is cut ($(stat -c %s "$image") bytes)"
  done
  for view in "$work"/killed/v_*.geometry.txt; do
    [ -e "$view" ] || continue
    [ -e "${view%.geometry.txt}.mha" ] || fail "after $1: $view stands without its image"
  done
}

written() {
  ls "$work"/killed/v_*.mha 2> /dev/null | wc -l
}

kills=0
mid_batch=0
partials=0 # kills that landed between a write and its rename
for target in 2 4 7 9 12 15 18 21 24 27 30 33 36 38; do
  "$pbdrr" "$input" "${common[@]}" -o "$work/killed/v_%02d.mha" --resume &
  pid=$!
  while kill -0 "$pid" 2> /dev/null && [ "$(written)" -lt "$target" ]; do
    sleep 0.002
  done
  sleep "0.00$((target % 7))" # a few milliseconds more: into the next view's render or write
  if kill -9 "$pid" 2> /dev/null; then
    kills=$((kills + 1))
  fi
  wait "$pid" 2> /dev/null
  check_whole "the kill at $target views"
  partials=$((partials + $(ls -A "$work/killed" | grep -c partial)))
  n=$(written)
  if [ "$n" -gt 0 ] && [ "$n" -lt "$views" ]; then
    mid_batch=$((mid_batch + 1))
  fi
done
[ "$mid_batch" -ge 8 ] || fail "only $mid_batch of the kills left a batch part done: the test did not test"

"$pbdrr" "$input" "${common[@]}" -o "$work/killed/v_%02d.mha" --resume || fail "the final --resume failed"
check_whole "the final --resume"
for k in $(seq -f %02g 0 $((views - 1))); do
  cmp -s "$work/killed/v_$k.mha" "$work/clean/v_$k.mha" || fail "v_$k.mha differs from the clean run's"
  diff <(tail -n +2 "$work/killed/v_$k.geometry.txt") <(tail -n +2 "$work/clean/v_$k.geometry.txt") > /dev/null ||
    fail "the view of v_$k differs from the clean run's"
done
left=$(ls -A "$work/killed" | grep -c partial)
[ "$left" = 0 ] || fail "$left temporary files left after the final --resume"
echo "KilledBatchResumes: $kills kills ($mid_batch mid-batch, $partials temporary files left by them), then --resume:" \
  "$views views equal to a clean run's"
