#!/usr/bin/env bash
# Does `pbdrr --accuracy PCT` reach the asked error, as fast as the fastest setting that does? (issue 41;
# docs/benchmark/accuracy_target.md)
#
#   bash benchmark/accuracy_target.sh [CASES...]      (default: chest head batch; x2 when X2 names the 2x chest)
#
# Cases: chest  the LIDC chest (DICOM, 512 x 512 x 275), AP (--gantry 90), 256 x 256 pixels of 2.4 mm
#        head   the InVesalius head (scripts/invesalius-head.sh), lateral (--gantry 0), 512 x 512 pixels of 0.8 mm
#        x2     scripts/make_large_ct.py's 2x chest (1024 x 1024 x 550), the chest's view
#        batch  the chest's view swept over 360 views 1 degree apart in one process (kept points), scored at 8 views
# Targets 2, 1, 0.5 and 0.25%, medians of RUNS (default 3) whole processes; benchmark/accuracy_target.py says how.
# Environment: PBDRR (default build/apps/pbdrr/pbdrr), CHEST (default ../shared/data/ct/lidc-idri-0314-chest),
# X2 (the 2x chest .mha), OUT (default /tmp/accuracy_target), RUNS, TARGETS (default 2,1,0.5,0.25), FACTORS
# (default off,2,8: the search's control variates, off for plain points), BATCH_VIEWS
# (default 360) and SCORED (default 8) for the batch.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
PBDRR=${PBDRR:-$root/build/apps/pbdrr/pbdrr}
CHEST=${CHEST:-$root/../shared/data/ct/lidc-idri-0314-chest}
OUT=${OUT:-/tmp/accuracy_target}
RUNS=${RUNS:-3}
TARGETS=${TARGETS:-2,1,0.5,0.25}
cases=("$@")
if [ ${#cases[@]} -eq 0 ]; then
  cases=(chest head batch)
  [ -n "${X2:-}" ] && cases+=(x2)
fi
mkdir -p "$OUT"
args=()
for c in "${cases[@]}"; do
  case $c in
    chest) args+=("chest=$CHEST") ;;
    batch) args+=("batch=$CHEST") ;;
    head) args+=("head=$(bash "$root/scripts/invesalius-head.sh" "$OUT/head_ct")") ;;
    x2) args+=("x2=${X2:?X2: the 2x chest, made by scripts/make_large_ct.py --factor 2}") ;;
    *) echo "accuracy_target.sh: unknown case $c (chest, head, x2, batch)" >&2; exit 2 ;;
  esac
done
echo "# accuracy_target: $("$PBDRR" --version 2>&1 | head -1); $(nproc) cores; $(date -u +%Y-%m-%dT%H:%MZ)"
/usr/bin/python3 "$root/benchmark/accuracy_target.py" "$PBDRR" "$OUT" "${args[@]}" --targets "$TARGETS" --runs "$RUNS"
