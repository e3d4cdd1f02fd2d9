#!/usr/bin/env bash
# Does `pbdrr --control-variate auto` land within 20% of the fastest setting AT EQUAL ERROR? (issue 27, item 5;
# docs/benchmark/auto_choice.md)
#
#   bash benchmark/auto_choice.sh [CASES...]      (default: chest head x2 batch; about 40 min on 2 busy cores)
#   bash benchmark/auto_choice.sh calibrate       (the cost model's constants; then: auto_choice.py calreport OUT)
#   /usr/bin/python3 benchmark/auto_choice.py report OUT    (the sections again, from OUT/CASE/result.json)
#
# Cases: chest  the LIDC chest (DICOM, 512 x 512 x 275), AP (--gantry 90), 256 x 256 pixels of 2.4 mm, SAD 1000, SID 1500
#        head   the InVesalius head (scripts/invesalius-head.sh), demo.sh's lateral view: --gantry 0 --spacing 0.8 0.8,
#               512 x 512 pixels
#        x2     scripts/make_large_ct.py's 2x chest (1024 x 1024 x 550 int16 .mha), the chest's view
#        batch  the chest, a 360-view sweep (--angles 360 from gantry 90, 1 degree apart) in one process, the chest's
#               detector, BATCH_N points per view; BATCH_SCORED views (every 10th) scored against their references
# Per case, benchmark/auto_choice.py: the reference `pbdrr --exact siddon --ss 4`; the target = auto's NRMSE at N0
# (10M, or BATCH_N for the batch; the mean of NRMSE^2 over SEEDS seeds); for --control-variate off, 2, 4, 8, 16 the
# NRMSE at two or three N, the fit NRMSE^2 = a / N + b and the N at auto's NRMSE; then RUNS interleaved rounds of
# every setting at its N, whole processes under /usr/bin/time -f '%e s %M KB %U %S' (wall, peak RSS, user, system);
# medians. NRMSE = RMSE / (max - min of the reference), as benchmark/scale.sh computes it.
# calibrate: the chest, every setting but auto at CAL_N (default "1e6 2e7") points, a single view and a
# CAL_VIEWS-view batch (default 36, every 10 degrees), RUNS interleaved rounds: CPU and wall times, -v stage times.
# Markdown sections on stdout and in OUT/CASE/section.md; OUT/CASE/result.json holds every number. Finished
# measurements are cached in OUT (err_*.json, the references): delete OUT/CASE to measure a case again.
#
# Environment: PBDRR (default /work/auto_bench/pbdrr), CHEST (default ../shared/data/ct/lidc-idri-0314-chest),
# HEAD (default: extracted by scripts/invesalius-head.sh into OUT/head_ct), X2 (default ../scale_data/chest_x2.mha),
# OUT (default /work/auto_bench/out), RUNS (timed rounds, default 3), SEEDS (default "1 2"), BATCH_SEEDS (default "1"),
# BATCH_VIEWS (default 360), BATCH_SCORED (default 36), BATCH_N (points per batch view, default 2e6), NMAX (the most
# points of any timed run, default 200 x N0 for a single view, 10 x for the batch: a setting that needs more is timed at
# NMAX and its time is a lower bound; the error runs stop at the smaller of NMAX and 100 x N0), CAL_N, CAL_VIEWS.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
export PBDRR=${PBDRR:-/work/auto_bench/pbdrr}
export CHEST=${CHEST:-$(realpath -m "$root/../shared/data/ct/lidc-idri-0314-chest")}
export X2=${X2:-$(realpath -m "$root/../scale_data/chest_x2.mha")}
OUT=${OUT:-/work/auto_bench/out}
export RUNS=${RUNS:-3} SEEDS=${SEEDS:-1 2} BATCH_SEEDS=${BATCH_SEEDS:-1}
export BATCH_VIEWS=${BATCH_VIEWS:-360} BATCH_SCORED=${BATCH_SCORED:-36} BATCH_N=${BATCH_N:-2e6}
PY=/usr/bin/python3

[ -x "$PBDRR" ] || { echo "auto_choice.sh: no pbdrr binary at $PBDRR" >&2; exit 1; }
"$PY" -c "import numpy" 2>/dev/null || { echo "auto_choice.sh: $PY needs numpy (apt-get install python3-numpy)" >&2; exit 1; }
mkdir -p "$OUT"
cases=("$@")
[ ${#cases[@]} -gt 0 ] || cases=(chest head x2 batch)
if [[ " ${cases[*]} " == *" head "* ]] && [ -z "${HEAD:-}" ]; then
  HEAD=$(bash "$root/scripts/invesalius-head.sh" "$OUT/head_ct")
fi
export HEAD=${HEAD:-}

echo "# auto_choice: $("$PBDRR" --version 2>&1 | head -1) ($PBDRR); $(nproc) cores; $(date -u +%Y-%m-%dT%H:%MZ);" \
     "load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo
for c in "${cases[@]}"; do
  "$PY" "$root/benchmark/auto_choice.py" "$c" "$OUT"
done
echo "load average at the end: $(cut -d' ' -f1-3 /proc/loadavg); $(date -u +%Y-%m-%dT%H:%MZ)"
