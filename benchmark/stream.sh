#!/usr/bin/env bash
# CTs larger than memory (issue 30): a CT rendered streamed in slabs and read whole, side by side, one run each.
#
#   bash benchmark/stream.sh CT.mha [SLABS]
#
# CT.mha: an uncompressed MetaImage of int16 HU (scripts/make_large_ct.py CHEST chest_x4.mha --factor 4 makes the
# chest x4, 2048 x 2048 x 1100, 9.2 GB; never committed). SLABS: default 32.
# Environment: PBDRR (default build/apps/pbdrr/pbdrr), OUT (default DATA/stream_<CT name>), WHOLE=0 skips the renders
# read whole (a CT larger than memory: they cannot run), DROP_CACHES=1 drops the page cache before each run (root).
# Each run is one whole process under /usr/bin/time -f '%e s %M KB' (elapsed, peak RSS), on pbdrr's default view
# (512 x 512 at 1.2 mm, the isocenter at the CT's centre):
#   stream_default   pbdrr defaults, --stream SLABS            (`auto` control variate: F >= 4 when streamed)
#   stream_exact     --exact siddon --stream SLABS
#   stream_cv4       --control-variate 4 --stream SLABS         (to compare with whole_cv4 bit for bit)
#   whole_cv4        --control-variate 4 --memory-budget 0
#   whole_default    pbdrr defaults, --memory-budget 0          (`auto` F as unstreamed: 2 on the x4)
#   budget_default   pbdrr defaults (the default budget, half the memory, decides the slabs)
# Then: whether stream_cv4 and whole_cv4 are the same bytes, and the NRMSE (RMSE / range) of every image against
# stream_exact. Output: lines "NAME SECONDS s PEAK KB" and the comparisons, on stdout and OUT/stream.txt.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
ct=${1:?usage: stream.sh CT.mha [SLABS]}
slabs=${2:-32}
pbdrr=${PBDRR:-$root/build/apps/pbdrr/pbdrr}
name=$(basename "$ct" .mha)
out=${OUT:-$(dirname "$ct")/stream_$name}
mkdir -p "$out"
exec > >(tee "$out/stream.txt") 2>&1

run() {
  local label=$1
  shift
  if [ "${DROP_CACHES:-0}" = 1 ]; then
    sync
    echo 3 >/proc/sys/vm/drop_caches
  fi
  /usr/bin/time -f "$label %e s %M KB" "$pbdrr" "$ct" -o "$out/$label.mha" -q "$@" 2>&1 | tail -1
}

run stream_default --stream "$slabs"
run stream_exact --stream "$slabs" --exact siddon
run stream_cv4 --stream "$slabs" --control-variate 4
if [ "${WHOLE:-1}" = 1 ]; then
  run whole_cv4 --memory-budget 0 --control-variate 4
  run whole_default --memory-budget 0
  run budget_default
  if cmp -s "$out/stream_cv4.mha" "$out/whole_cv4.mha"; then
    echo "stream_cv4 and whole_cv4: the same bytes"
  else
    echo "stream_cv4 and whole_cv4: DIFFERENT"
  fi
fi
/usr/bin/python3 - "$out" <<'PY'
import glob, os, sys
import numpy as np

def read(path):
    data = open(path, "rb").read()
    end = data.index(b"ElementDataFile = LOCAL\n") + len(b"ElementDataFile = LOCAL\n")
    header = dict(line.split(" = ", 1) for line in data[:end].decode().splitlines())
    return np.frombuffer(data[end:], dtype={"MET_FLOAT": "<f4", "MET_DOUBLE": "<f8"}[header["ElementType"]]).astype(float)

out = sys.argv[1]
reference = read(os.path.join(out, "stream_exact.mha"))
for path in sorted(glob.glob(os.path.join(out, "*.mha"))):
    image = read(path)
    nrmse = np.sqrt(np.mean((image - reference) ** 2)) / (reference.max() - reference.min())
    print("%s NRMSE %.3e against stream_exact" % (os.path.basename(path)[:-4], nrmse))
PY
