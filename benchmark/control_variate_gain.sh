#!/bin/bash
# The control variate's gain at equal N against DESIGN 10's prediction (docs/performance.md, "Control variate"): for
# F = 2, 4, 8, the NRMSE of `--control-variate F` over the NRMSE of plain sampling (`--control-variate off`), same
# sampler, seed and N, beside M_r / M. Accuracy only (no timing). Both against the exact pixel average (Siddon, 8 x 8
# rays per pixel).
#
#   bash benchmark/control_variate_gain.sh [CT] [PBDRR]   (defaults: the LIDC chest, build/apps/pbdrr/pbdrr)
#
# Environment: VIEW (pbdrr view options; default the chest AP view of docs/benchmark/chest_ap_256.md), SAMPLES (the
# N to compare at, default "1e6 1e7"), SAMPLER (default stratified), OUT (a directory for the images).
#
# The image's error is the coarse image's (antithetic rays, no points) plus the residual's in quadrature; the ratio
# approaches M_r / M where the residual's part dominates (small N), and rises above it where the coarse image's floor
# shows (large N).
set -euo pipefail
CT=${1:-/work/shared/data/ct/lidc-idri-0314-chest}
PBDRR=${2:-$(dirname "$0")/../build/apps/pbdrr/pbdrr}
VIEW=${VIEW:---gantry 90 --size 256 256 --spacing 2.4 2.4}
SAMPLES=${SAMPLES:-1e6 1e7}
SAMPLER=${SAMPLER:-stratified}
OUT=${OUT:-$(mktemp -d)}
mkdir -p "$OUT"
if [ ! -e "$CT" ]; then
  echo "control_variate_gain.sh: $CT not found (give a CT as the first argument)" >&2
  exit 2
fi
nrmse() {
  /usr/bin/python3 - "$OUT/reference.mha" "$1" <<'PY'
import sys, struct, pathlib
def read_mha(path):
    data = pathlib.Path(path).read_bytes()
    header, _, body = data.partition(b"ElementDataFile = LOCAL\n")
    fields = dict(line.split(" = ", 1) for line in header.decode().splitlines() if " = " in line)
    size = [int(v) for v in fields["DimSize"].split()]
    return struct.unpack("<%df" % (size[0] * size[1]), body[: 4 * size[0] * size[1]])
ref, img = read_mha(sys.argv[1]), read_mha(sys.argv[2])
print("%.6f" % ((sum((a - b) ** 2 for a, b in zip(ref, img)) / len(ref)) ** 0.5 / (max(ref) - min(ref))))
PY
}
# shellcheck disable=SC2086
"$PBDRR" "$CT" -o "$OUT/reference.mha" $VIEW --exact siddon --ss 8 -q
echo "| N | F | M_r / M | NRMSE plain | NRMSE control variate | ratio |"
echo "|---:|---:|---:|---:|---:|---:|"
for n in $SAMPLES; do
  # shellcheck disable=SC2086
  "$PBDRR" "$CT" -o "$OUT/plain.mha" $VIEW --sampler "$SAMPLER" --samples "$n" --control-variate off -q
  plain=$(nrmse "$OUT/plain.mha")
  for f in 2 4 8; do
    # shellcheck disable=SC2086
    log=$("$PBDRR" "$CT" -o "$OUT/cv.mha" $VIEW --sampler "$SAMPLER" --samples "$n" --control-variate "$f" -q -v 2>&1)
    ratio=$(echo "$log" | sed -n 's/.*M_r \/ M \([0-9.e-]*\),.*/\1/p')
    cv=$(nrmse "$OUT/cv.mha")
    printf "| %s | %s | %.3f | %.4f | %.4f | %.3f |\n" "$n" "$f" "$ratio" "$plain" "$cv" \
      "$(/usr/bin/python3 -c "print($cv / $plain)")"
  done
done
