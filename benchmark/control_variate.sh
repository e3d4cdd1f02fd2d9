#!/bin/bash
# The control variate against the exact Siddon projector and plain point sampling on one view, side by side in one
# run (DESIGN 10; docs/performance.md, "Control variate"). Whole pbdrr processes on the same volume and view; the
# time of a row is pbdrr's own preprocess + render (load and write excluded, the same for every row); NRMSE against
# the exact pixel average (Siddon, 8 x 8 rays per pixel), relative to the reference's range.
#
#   bash benchmark/control_variate.sh [CT] [PBDRR] [RUNS]     (defaults: the LIDC chest, build/apps/pbdrr/pbdrr, 3)
#
# Environment: VIEW (pbdrr view options; default the chest AP view of docs/benchmark/chest_ap_256.md), OUT (a
# directory for the images; default a temporary one), SETTINGS (lines "name|pbdrr options" to run instead of the
# default sweep).
set -euo pipefail
CT=${1:-/work/shared/data/ct/lidc-idri-0314-chest}
PBDRR=${2:-$(dirname "$0")/../build/apps/pbdrr/pbdrr}
RUNS=${3:-3}
VIEW=${VIEW:---gantry 90 --size 256 256 --spacing 2.4 2.4}
OUT=${OUT:-$(mktemp -d)}
mkdir -p "$OUT"
if [ ! -e "$CT" ]; then
  echo "control_variate.sh: $CT not found (give a CT as the first argument)" >&2
  exit 2
fi
DEFAULT_SETTINGS="exact 1x1|--exact siddon --ss 1
exact 2x2|--exact siddon --ss 2
exact 4x4|--exact siddon --ss 4
stratified 1e7|--control-variate off --sampler stratified --samples 1e7
stratified 1e8|--control-variate off --sampler stratified --samples 1e8"
for f in 2 4 8; do
  for n in 1e6 1e7 1e8; do
    DEFAULT_SETTINGS="$DEFAULT_SETTINGS
cv$f stratified $n|--control-variate $f --sampler stratified --samples $n"
  done
  DEFAULT_SETTINGS="$DEFAULT_SETTINGS
cv$f ss2 stratified 1e8|--control-variate $f --ss 2 --sampler stratified --samples 1e8
cv$f level-alias 1e7|--control-variate $f --sampler level-alias --samples 1e7"
done
DEFAULT_SETTINGS="$DEFAULT_SETTINGS
pbdrr defaults|
plain level-alias 1e7|--control-variate off --sampler level-alias --samples 1e7"
SETTINGS=${SETTINGS:-$DEFAULT_SETTINGS}

# shellcheck disable=SC2086
"$PBDRR" "$CT" -o "$OUT/reference.mha" $VIEW --exact siddon --ss 8 -q
echo "| setting | preprocess s | render s | total s (median of $RUNS) | NRMSE | M_r / M |"
echo "|---|---:|---:|---:|---:|---:|"
while IFS='|' read -r name options; do
  [ -z "$name" ] && continue
  image="$OUT/$(echo "$name" | tr ' ' '_').mha"
  times=""
  ratio=""
  for ((r = 0; r < RUNS; ++r)); do
    # shellcheck disable=SC2086
    log=$("$PBDRR" "$CT" -o "$image" $VIEW $options -q -v 2>&1)
    pre=$(echo "$log" | sed -n 's/.*preprocess \([0-9.]*\) s;.*/\1/p')
    ren=$(echo "$log" | sed -n 's/.*\(sample+project\|exact projection\) \([0-9.]*\) s;.*/\2/p')
    times="$times $pre:$ren"
    ratio=$(echo "$log" | sed -n 's/.*M_r \/ M \([0-9.e-]*\),.*/\1/p')
  done
  /usr/bin/python3 - "$name" "$OUT/reference.mha" "$image" "${ratio:--}" $times <<'PY'
import sys, struct, pathlib
def read_mha(path):
    data = pathlib.Path(path).read_bytes()
    header, _, body = data.partition(b"ElementDataFile = LOCAL\n")
    fields = dict(line.split(" = ", 1) for line in header.decode().splitlines() if " = " in line)
    size = [int(v) for v in fields["DimSize"].split()]
    count = size[0] * size[1]
    return struct.unpack("<%df" % count, body[: 4 * count])
name, reference, image, ratio = sys.argv[1:5]
runs = [tuple(float(x) for x in t.split(":")) for t in sys.argv[5:]]
ref, img = read_mha(reference), read_mha(image)
span = max(ref) - min(ref)
nrmse = (sum((a - b) ** 2 for a, b in zip(ref, img)) / len(ref)) ** 0.5 / span
totals = [p + r for p, r in runs]
median = sorted(range(len(totals)), key=lambda i: totals[i])[len(totals) // 2]
p, r = runs[median]
print("| %s | %.3f | %.3f | %.3f | %.5f | %s |" % (name, p, r, p + r, nrmse, ratio))
PY
done <<<"$SETTINGS"
