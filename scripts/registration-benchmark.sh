#!/usr/bin/env bash
# The registration measurement of issue 6 (README, docs/registration.md): examples/Register2D3D on the LIDC chest and
# the InVesalius head, synthetic AP + lateral X-rays (exact projector) at the true pose, 20 random starts (up to 10 mm
# and 5 degrees), ITK's classic components (--method classic) with PointBasedDRR (the drop-in interpolator, kept
# points) and with ITK's ray caster. One run at a time; resumable (starts already in OUT are skipped). Then
# summarizes into OUT/registration.md.
#
#   bash scripts/registration-benchmark.sh
#
# Environment (defaults in brackets):
#   REG_ONLY     volumes [chest head]          REG_DRRS     methods [pbdrr raycast]
#   REG_STARTS   random starts [20]            REG_SIZE     detector pixels per side [128]
#   REG_SAMPLES  PBDRR points [2e6]            REG_ARGS     extra Register2D3D options
#   CHEST [../shared/data/ct/lidc-idri-0314-chest], BUILD_DIR [build-bench], OUT [out/registration]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
ONLY=${REG_ONLY:-chest head}
DRRS=${REG_DRRS:-pbdrr raycast}
STARTS=${REG_STARTS:-20}
SIZE=${REG_SIZE:-128}
SAMPLES=${REG_SAMPLES:-2e6}
CHEST=${CHEST:-$root/../shared/data/ct/lidc-idri-0314-chest}
BUILD_DIR=${BUILD_DIR:-$root/build-bench}
OUT=${OUT:-$root/out/registration}
mkdir -p "$OUT"

cmake -S "$root" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD_DIR" -j "$(nproc)" --target Register2D3D
EXE=$BUILD_DIR/examples/Register2D3D

volume_path() {
  case $1 in
    chest) [ -d "$CHEST" ] && echo "$CHEST" ;;
    head)
      if [ ! -f "$root/out/demo/head.mha" ]; then bash "$root/scripts/invesalius-head.sh" "$root/out/demo" >&2 || true; fi
      [ -f "$root/out/demo/head.mha" ] && echo "$root/out/demo/head.mha" ;;
  esac
}

for volume in $ONLY; do
  input=$(volume_path "$volume" || true)
  if [ -z "$input" ]; then echo "SKIPPED: no $volume CT"; continue; fi
  for drr in $DRRS; do
    log=$OUT/${volume}_${drr}.txt
    touch "$log"
    for ((seed = 0; seed < STARTS; seed++)); do
      if grep -q " seed=$seed " "$log"; then continue; fi
      echo "== $volume $drr start $seed"
      # shellcheck disable=SC2086
      "$EXE" "$input" --method classic --drr "$drr" --size "$SIZE" --samples "$SAMPLES" --random-start "$seed" ${REG_ARGS:-} | tee -a "$log"
    done
  done
done
/usr/bin/python3 "$root/benchmark/summarize_registration.py" "$OUT" | tee "$OUT/registration.md"
