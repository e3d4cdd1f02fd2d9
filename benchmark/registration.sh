#!/bin/bash
# Issue 38's registration benchmark: three methods side by side on the same cases, from the same random starts.
#
#   bash benchmark/registration.sh [BUILD_DIR] [OUT_DIR]
#
# Methods (METHODS, default "new global powell classic"):
#   new      pbdrr register as built here: PointBasedDRRMetricv4 (analytic derivative of kept points) and its default
#            v4 optimizer and schedule (NEW_ARGS adds options, e.g. "--optimizer rsgd")
#   global   the same with the global stage: the first level from GLOBAL_ARGS' starts ("--starts 4 --start-radius 10")
#   powell   today's Powell method: pbdrr register built from OLD_COMMIT (default 159ec84, the code before issue 38) in
#            a git worktree beside BUILD_DIR, run with its defaults (Powell, levels 2,1, 4M kept points)
#   classic  ITK's classic framework: benchmark/PointBasedDRRRegistrationClassic (RayCastInterpolateImageFunction,
#            NormalizedCorrelationImageToImageMetric, PowellOptimizer); ITK's ray caster has no localizer beam, so it
#            runs on the synthetic cases only, and on the first CLASSIC_STARTS starts of each range (a run takes minutes)
# Cases (CASES, default all): the shared real localizer (S21610: the lateral CT localizer S1000 against the series
# S2010 and S3010), and synthetic X-rays of the shared LIDC chest and TotalSegmentator abdomen-pelvis CTs at the
# identity pose, 256 x 256 pixels of 2.4 mm at SID 1500 / SAD 1000, rendered by another projector than the one that
# registers (pbdrr --exact trilinear, 2 x 2 rays per pixel, quantum noise of 1e5 photons per pixel), one view (AP) and
# two (AP and lateral).
# Starts: STARTS (20) within 10 mm / 5 degrees and STARTS within 20 mm / 10 degrees (benchmark/registration.py).
# Every run is one process at a time on THREADS (2) threads, timed by /usr/bin/time (wall, peak RSS) besides the
# registration's own time; one CSV row per run in OUT_DIR/registration.csv, skipped when already there (resumable).
# Then benchmark/registration.py summarizes: OUT_DIR/registration.md and OUT_DIR/registration.png.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$here/build}
out=${2:-$here/out/registration}
data=$here/../shared/data/ct
starts=${STARTS:-20}
classic_starts=${CLASSIC_STARTS:-4}
methods=${METHODS:-new global powell classic}
cases=${CASES:-localizer-S2010 localizer-S3010 chest-ap chest-biplane pelvis-ap pelvis-biplane}
threads=${THREADS:-2}
old_commit=${OLD_COMMIT:-159ec84}
if [ ! -d "$data/philips-s21610-head-phantom" ] || [ ! -d "$data/lidc-idri-0314-chest" ]; then
  echo "SKIPPED: $data is absent (real data from ../shared/data)"
  exit 0
fi
mkdir -p "$out"
out=$(cd "$out" && pwd)
pbdrr=$build/apps/pbdrr/pbdrr
classic=$build/benchmark/PointBasedDRRRegistrationClassic
cmake --build "$build" --target pbdrr PointBasedDRRRegistrationClassic -j "$threads" > /dev/null

old_pbdrr=""
if [[ " $methods " == *" powell "* ]]; then
  old_src=$build-old-src
  old_build=$build-old
  if [ ! -d "$old_src" ]; then
    git -C "$here" worktree add --detach "$old_src" "$old_commit" > /dev/null
  fi
  cmake -S "$old_src" -B "$old_build" -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF > /dev/null
  cmake --build "$old_build" --target pbdrr -j "$threads" > /dev/null
  old_pbdrr=$old_build/apps/pbdrr/pbdrr
fi

/usr/bin/python3 "$here/benchmark/registration.py" starts "$starts" 20261128 > "$out/starts.txt"

# The cases: CT, X-rays (--xray X [--geometry G] ...), bone points and the truth.
case_ct() {
  case $1 in
    localizer-S2010) echo "$data/philips-s21610-head-phantom/S2010" ;;
    localizer-S3010) echo "$data/philips-s21610-head-phantom/S3010" ;;
    chest-*) echo "$data/lidc-idri-0314-chest" ;;
    pelvis-*) echo "$data/totalsegmentator/example_ct.nii.gz" ;;
  esac
}
case_xrays() {
  local dir=$out/$1
  case $1 in
    localizer-*) echo "--xray $data/philips-s21610-head-phantom/S1000/I10" ;;
    *-ap) echo "--xray $dir/ap.mha --geometry $dir/ap.geometry.txt" ;;
    *-biplane) echo "--xray $dir/ap.mha --geometry $dir/ap.geometry.txt --xray $dir/lateral.mha --geometry $dir/lateral.geometry.txt" ;;
  esac
}
prepare_case() {
  local name=$1 dir=$out/$1 ct
  ct=$(case_ct "$name")
  mkdir -p "$dir"
  [ -s "$dir/bone_points.txt" ] || "$classic" "$ct" --bone-points 500 --bone-hu 300 --seed 1 -o "$dir/bone_points.txt"
  case $name in
    localizer-*)
      # No truth: the reference is the exact projector's registration (Powell, no noise, levels 2 and 1) from the
      # scanner's frame and from the first four starts of the 10 mm range: the mean pose of the runs whose exact
      # similarity at full resolution is within 0.005 of the best (the others stopped in other optima; the kept ones
      # spread by about 0.1 degree and 0.15 mm: the reference's own uncertainty, in reference_scored.txt).
      if [ ! -s "$dir/truth.txt" ]; then
        : > "$dir/reference_scored.txt"
        { echo "0 0 0 0 0 0"; head -n 4 "$out/starts.txt" | cut -d' ' -f2-; } | while read -r start; do
          local pose similarity
          pose=$("$pbdrr" register "$ct" $(case_xrays "$name") -o "$dir/reference.png" --exact siddon \
            --optimizer powell --levels 2,1 --start $start --threads "$threads" -q | sed -n 's/^pose: //p')
          # The exact similarity at that pose, full resolution: the start's of a run stopped before its search.
          similarity=$("$pbdrr" register "$ct" $(case_xrays "$name") -o "$dir/reference.png" --exact siddon \
            --levels 1 --start $pose --max-seconds 1e-9 --threads "$threads" -q |
            sed -n 's/.*at the start \([0-9.-]*\).*/\1/p')
          echo "$pose $similarity" >> "$dir/reference_scored.txt"
        done
        /usr/bin/python3 "$here/benchmark/registration.py" reference "$dir/reference_scored.txt" > "$dir/truth.txt"
      fi
      ;;
    *)
      echo "0 0 0 0 0 0" > "$dir/truth.txt"
      for view in ap:90 lateral:0; do
        local file=${view%%:*} gantry=${view##*:}
        [[ $name == *-ap && $file == lateral ]] && continue
        if [ ! -s "$dir/$file.mha" ]; then
          printf 'gantry %s\nsad 1000\nsid 1500\ncols 256\nrows 256\nspacing 2.4 2.4\n' "$gantry" > "$dir/$file.view.txt"
          "$pbdrr" "$ct" --exact trilinear --ss 2 --photons 1e5 --seed "$gantry" --geometry "$dir/$file.view.txt" \
            -o "$dir/$file.mha" -q
        fi
      done
      ;;
  esac
}

csv=$out/registration.csv
[ -s "$csv" ] || echo "case,method,range,start,tx0,ty0,tz0,rx0,ry0,rz0,tx,ty,tz,rx,ry,rz,similarity,seconds,drrs,wall,rss_kb" > "$csv"

run_one() {
  local name=$1 method=$2 range=$3 k=$4 start=$5 ct log
  ct=$(case_ct "$name")
  log=$out/$name/run.log
  local timing=$out/$name/time.txt
  case $method in
    new) /usr/bin/time -f '%e %M' -o "$timing" "$pbdrr" register "$ct" $(case_xrays "$name") -o "$out/$name/new.png" \
      --start $start --threads "$threads" -q ${NEW_ARGS:-} > "$log" ;;
    global) /usr/bin/time -f '%e %M' -o "$timing" "$pbdrr" register "$ct" $(case_xrays "$name") \
      -o "$out/$name/global.png" --start $start --threads "$threads" -q ${NEW_ARGS:-} \
      ${GLOBAL_ARGS:---starts 4 --start-radius 10} > "$log" ;;
    powell) /usr/bin/time -f '%e %M' -o "$timing" "$old_pbdrr" register "$ct" $(case_xrays "$name") \
      -o "$out/$name/powell.png" --start $start --threads "$threads" -q > "$log" ;;
    classic) /usr/bin/time -f '%e %M' -o "$timing" "$classic" "$ct" $(case_xrays "$name") --start $start \
      --threads "$threads" > "$log" ;;
  esac
  local pose similarity seconds drrs
  pose=$(sed -n 's/^pose: //p' "$log" | tr ' ' ',')
  similarity=$(sed -n 's/^similarity: \([0-9.-]*\).*/\1/p' "$log")
  seconds=$(sed -n 's/^time: \([0-9.]*\) s.*/\1/p' "$log")
  drrs=$(sed -n 's/.* \([0-9]*\) DRRs.*/\1/p' "$log")
  echo "$name,$method,$range,$k,$(echo $start | tr ' ' ','),$pose,${similarity:-nan},$seconds,$drrs,$(tr ' ' ',' < "$timing")" >> "$csv"
}

for name in $cases; do
  prepare_case "$name"
done
# Method by method (the order of METHODS), so that a method's runs share the machine's state.
for method in $methods; do
  for name in $cases; do
    [[ $method == classic && $name == localizer-* ]] && continue
    k=0
    while read -r range start; do
      k=$((k + 1))
      index=$(( (k - 1) % starts + 1 ))
      [[ $method == classic && $index -gt $classic_starts ]] && continue
      grep -q "^$name,$method,$range,$index," "$csv" && continue
      echo "== $name $method range $range start $index: $start"
      run_one "$name" "$method" "$range" "$index" "$start"
      tail -n 1 "$csv"
    done < "$out/starts.txt"
  done
done
/usr/bin/python3 "$here/benchmark/registration.py" summarize "$out"
