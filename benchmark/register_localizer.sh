#!/bin/bash
# Registers both gantry-tilted series of the Philips head phantom (../shared/data) to the real lateral localizer from
# 20 random starts each (translation up to 10 mm in a uniform direction, rotation up to 5 degrees about a uniform axis,
# as small Euler angles), with kept points and with the exact Siddon projector; one CSV row per registration, then
# benchmark/summarize_register.py: how many starts reach the same pose (within 1 mm and 0.5 degrees of the median),
# the median pose and the wall time. Issue 15's "done means".
#
#   bash benchmark/register_localizer.sh [BUILD_DIR] [OUT_DIR]
#        (STARTS=20 EXACT_STARTS=5 METHODS="points exact" METRIC=gc THREADS=2; the exact projector takes ~4x longer)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$here/build}
out=${2:-$here/out/register}
data=$here/../shared/data/ct/philips-s21610-head-phantom
starts=${STARTS:-20}
methods=${METHODS:-points exact}
threads=${THREADS:-2}
pbdrr=$build/apps/pbdrr/pbdrr
if [ ! -e "$data/S1000/I10" ]; then
  echo "SKIPPED: $data is absent (real data from ../shared/data)"
  exit 0
fi
mkdir -p "$out"
csv=$out/register_localizer.csv
echo "series,method,start,tx0,ty0,tz0,rx0,ry0,rz0,tx,ty,tz,rx,ry,rz,similarity,seconds,drrs" > "$csv"
/usr/bin/python3 - "$starts" > "$out/starts.txt" <<'PY'
import numpy as np, sys
rng = np.random.default_rng(20261124)
for k in range(int(sys.argv[1])):
    d = rng.normal(size=3); d /= np.linalg.norm(d)
    a = rng.normal(size=3); a /= np.linalg.norm(a)
    t = d * 10.0 * rng.uniform()
    r = a * 5.0 * rng.uniform()
    print(" ".join("%.3f" % v for v in list(t) + list(r)))
PY
for series in S2010 S3010; do
  for method in $methods; do
    k=0
    count=$starts
    [ "$method" = exact ] && count=${EXACT_STARTS:-5}
    head -n "$count" "$out/starts.txt" | while read -r start; do
      k=$((k + 1))
      extra=""
      [ "$method" = exact ] && extra="--exact siddon"
      result=$("$pbdrr" register "$data/$series" --xray "$data/S1000/I10" -o "$out/${series}_${method}_$k.png" \
        --start $start --threads "$threads" --metric "${METRIC:-gc}" -q $extra)
      pose=$(echo "$result" | sed -n 's/^pose: //p' | tr ' ' ',')
      similarity=$(echo "$result" | sed -n 's/^similarity: \([0-9.-]*\).*/\1/p')
      seconds=$(echo "$result" | sed -n 's/^time: \([0-9.]*\) s, \([0-9]*\) DRRs.*/\1/p')
      drrs=$(echo "$result" | sed -n 's/^time: [0-9.]* s, \([0-9]*\) DRRs.*/\1/p')
      echo "$series,$method,$k,$(echo $start | tr ' ' ','),$pose,$similarity,$seconds,$drrs" | tee -a "$csv"
    done
  done
done
/usr/bin/python3 "$here/benchmark/summarize_register.py" "$csv"
