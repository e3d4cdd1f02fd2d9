#!/bin/bash
# What each model of issue 16 costs on one view (docs/design.md sections 12 to 14): whole pbdrr processes on the same
# CT and view, the rows interleaved run by run (a drift of the machine's speed touches every row alike), and for each
# row the median over the runs of pbdrr's own stages (-v): preprocess (attenuation volume, labels, sampler tables),
# render (sample + project, or the exact projection) and write (for --kvp the polychromatic image, for --photons the
# noise, then the files). Ratios are against the plain row of the same projector.
#
#   bash benchmark/scene_models.sh [CT] [LABELS] [PBDRR] [RUNS]
#     defaults: the LIDC chest, a label image from examples/RenderScene (HU thresholds: 0 air, 1 soft tissue,
#     2 bone; made if absent), build/apps/pbdrr/pbdrr, 5
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
CT=${1:-/work/shared/data/ct/lidc-idri-0314-chest}
LABELS=${2:-}
PBDRR=${3:-$HERE/../build/apps/pbdrr/pbdrr}
RUNS=${4:-5}
VIEW=${VIEW:---gantry 90 --size 256 256 --spacing 2.4 2.4 --samples 1e7 --seed 1}
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
if [ ! -e "$CT" ]; then
  echo "scene_models.sh: $CT not found (give a CT as the first argument)" >&2
  exit 2
fi
if [ -z "$LABELS" ]; then
  "$HERE/../build/examples/RenderScene" "$CT" "$OUT/scene" 100000 >/dev/null
  LABELS=$OUT/scene_labels.mha
fi
SETTINGS="points, plain|--control-variate off
points, --keep-labels 2 (bone only)|--control-variate off --labels $LABELS --keep-labels 2
points, --label-channels (3 labels)|--control-variate off --labels $LABELS --label-channels $OUT/channels.mha
points, --kvp 120 (3 materials)|--control-variate off --kvp 120
points, --kvp 120 --jensen-correction|--control-variate off --kvp 120 --jensen-correction
points, --photons 1e4|--control-variate off --photons 1e4
exact, plain|--exact siddon
exact, --label-channels (3 labels)|--exact siddon --labels $LABELS --label-channels $OUT/channels.mha
exact, --kvp 120 (3 materials)|--exact siddon --kvp 120"
mapfile -t ROWS <<<"$SETTINGS"
for ((run = 0; run < RUNS; ++run)); do
  for ((r = 0; r < ${#ROWS[@]}; ++r)); do
    # shellcheck disable=SC2086
    "$PBDRR" "$CT" -o "$OUT/image.mha" $VIEW ${ROWS[r]#*|} -v 2>&1 | grep '^pbdrr: time:' >>"$OUT/times_$r.txt"
  done
done
/usr/bin/python3 - "$OUT" "${#ROWS[@]}" "$SETTINGS" <<'PY'
import re
import statistics
import sys

out, count, settings = sys.argv[1], int(sys.argv[2]), sys.argv[3].splitlines()
rows = []
for r in range(count):
    stages = {}
    for line in open(f"{out}/times_{r}.txt"):
        for name, seconds in re.findall(r" ([a-z+ ]+?) ([0-9.]+) s;", line):
            stages.setdefault(name.strip(), []).append(float(seconds))
    median = {name: statistics.median(values) for name, values in stages.items()}
    render = median.get("sample+project", median.get("exact projection", 0.0))
    rows.append((settings[r].split("|")[0], median.get("preprocess", 0.0), render, median.get("write", 0.0)))
print("| model | preprocess (s) | render (s) | write (s) | render + write vs plain |")
print("|---|---:|---:|---:|---:|")
plain = {}
for name, pre, render, write in rows:
    projector = name.split(",")[0]
    plain.setdefault(projector, render + write)
    print(f"| {name} | {pre:.3f} | {render:.3f} | {write:.3f} | {(render + write) / plain[projector]:.2f} |")
PY
