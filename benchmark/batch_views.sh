#!/bin/bash
# Many views in one run against one run per view (issue 17; docs/benchmark/batch_chest_360.md): a 360-view gantry sweep
# of the chest at 256 x 256, as one `pbdrr --angles 360` batch and as 360 separate `pbdrr --view-index K` runs (each
# loads the CT, preprocesses it and draws its points). Wall times of whole processes, measured in one run, side by side;
# every view's NRMSE against the exact pixel average (Siddon, 2 x 2 rays per pixel), relative to the reference's range;
# and every separate run's image compared bit for bit with the batch's view.
#
#   bash benchmark/batch_views.sh [CT] [PBDRR] [OUT]    (defaults: the LIDC chest, build/apps/pbdrr/pbdrr, a temp dir)
#
# Environment: VIEWS (default 360), SEPARATE (how many of the separate runs to time, every VIEWS/SEPARATE-th view;
# default all), SETTINGS (pbdrr's sampling options for the batch; default below), VIEW (the detector).
set -euo pipefail
CT=${1:-/work/shared/data/ct/lidc-idri-0314-chest}
PBDRR=${2:-$(dirname "$0")/../build/apps/pbdrr/pbdrr}
OUT=${3:-$(mktemp -d)}
VIEWS=${VIEWS:-360}
SEPARATE=${SEPARATE:-$VIEWS}
SETTINGS=${SETTINGS:---control-variate 8 --samples 2M}
VIEW=${VIEW:---size 256 256 --spacing 2.4 2.4}
STEP=$(/usr/bin/python3 -c "print(360.0 / $VIEWS)")
if [ ! -e "$CT" ]; then
  echo "batch_views.sh: $CT not found (give a CT as the first argument)" >&2
  exit 2
fi
rm -rf "$OUT/batch" "$OUT/separate"
mkdir -p "$OUT/reference" "$OUT/batch" "$OUT/separate"
sweep="--angles $VIEWS --angle-step $STEP"
seconds() { /usr/bin/python3 -c "import time; print(time.monotonic())"; }

# The exact references (kept in OUT: a second run with other SETTINGS reuses them).
# shellcheck disable=SC2086
"$PBDRR" "$CT" $sweep $VIEW --exact siddon --ss 2 -o "$OUT/reference/v_%04d.mha" -q --resume

start=$(seconds)
# shellcheck disable=SC2086
"$PBDRR" "$CT" $sweep $VIEW $SETTINGS -o "$OUT/batch/v_%04d.mha" -q -v 2>"$OUT/batch.log"
batch=$(/usr/bin/python3 -c "print($(seconds) - $start)")

stride=$((VIEWS / SEPARATE))
start=$(seconds)
for ((k = 0; k < VIEWS; k += stride)); do
  # shellcheck disable=SC2086
  "$PBDRR" "$CT" $sweep $VIEW $SETTINGS --view-index "$k" -o "$OUT/separate/v_$(printf %04d "$k").mha" -q
done
separate=$(/usr/bin/python3 -c "print($(seconds) - $start)")
same=0
for ((k = 0; k < VIEWS; k += stride)); do
  name=v_$(printf %04d "$k").mha
  cmp -s "$OUT/batch/$name" "$OUT/separate/$name" && same=$((same + 1))
done

accuracy=$(/usr/bin/python3 "$(dirname "$0")/batch_nrmse.py" "$OUT/reference/v_%04d.mha" "$OUT/batch/v_%04d.mha" "$VIEWS")
/usr/bin/python3 - "$VIEWS" "$SEPARATE" "$batch" "$separate" "$same" "$SETTINGS" "$accuracy" "$(grep "time:" "$OUT/batch.log")" <<'PY'
import sys
views, separate_runs, batch, separate, same, settings, accuracy, timing = sys.argv[1:]
views, separate_runs, batch, separate, same = int(views), int(separate_runs), float(batch), float(separate), int(same)
per_separate = separate / separate_runs
all_separate = per_separate * views
print("| run | views | wall s | views/s | s per view |")
print("|---|---:|---:|---:|---:|")
print("| one batch (`--angles %d`, %s) | %d | %.1f | %.1f | %.3f |" % (views, settings, views, batch, views / batch, batch / views))
print("| separate runs (`--view-index K`)%s | %d | %.1f | %.2f | %.3f |" % (
    "" if separate_runs == views else ", %d timed, scaled to %d" % (separate_runs, views),
    views, all_separate, views / all_separate, per_separate))
print()
print("Batch against separate runs: **%.1fx** the views per second. Separate runs' images equal to the batch's view, "
      "bit for bit: %d of %d." % (all_separate / batch, same, separate_runs))
print()
print("Accuracy of the batch's views (NRMSE against Siddon 2 x 2 rays per pixel): " + accuracy + ".")
print()
print("Batch stages (pbdrr -v): " + timing.replace("pbdrr: time: ", ""))
PY
