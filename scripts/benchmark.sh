#!/usr/bin/env bash
# The speed/accuracy benchmark of issue 5 (docs/benchmark.md): builds PointBasedDRRBenchmark in Release and runs, one
# after the other (never two heavy processes at once),
#
#   chest_ap_256      LIDC-IDRI-0314 chest, AP (gantry 90), 256 x 256 pixels of 2.4 mm
#   chest_ap_512      the same view, 512 x 512 pixels of 1.2 mm
#   head_lateral      InVesalius head CT (Debian invesalius-examples), lateral (gantry 0), 512 x 512 pixels of 0.8 mm
#   chest_scaling     time against samples, volume size (1/8 .. 1 of the voxels) and detector size (64 .. 1024)
#   chest_collimated  a 64 x 64 detector centred on the chest against the same crop of the 256 x 256 render
#
# writing OUT/NAME.{csv,md,log} and NAME_agreement.csv, then plots IMAGES/benchmark_NAME.png.
#
#   bash scripts/benchmark.sh                  # the full run: samples up to 1e9, 3 runs (hours on 2 cores)
#   BENCH_QUICK=1 bash scripts/benchmark.sh    # quick check: samples up to 1e7, 1 run (about 20 minutes)
#
# Environment (defaults in brackets; BENCH_QUICK=1 changes the ones marked *):
#   BENCH_ONLY         names of the configurations to run [all five]
#   BENCH_MAX_SAMPLES  top of the sample ladder 1e5, 3e5, 1e6, ... [1e9; *1e7]
#   BENCH_RUNS         timing runs per setting, median reported [3; *1]
#   BENCH_BUDGET       skip a setting predicted to run longer than this many seconds [60]
#   BENCH_REF_RAYS     rays per pixel side of the exact references [8; *8 for chest_ap_256, 4 elsewhere]
#   BENCH_SAMPLERS     comma-separated samplers [every registered one]
#   BENCH_THREADS      ITK threads and plastimatch's OMP_NUM_THREADS [ITK's default: the number of cores]
#   BENCH_ARGS         extra PointBasedDRRBenchmark options for every configuration
#   CHEST              the chest DICOM directory [../shared/data/ct/lidc-idri-0314-chest]; absent: chest skipped
#   BUILD_DIR [build-bench], OUT [out/benchmark], IMAGES [docs/images]
# plastimatch is measured when it is on PATH (Debian package plastimatch); the plots need /usr/bin/python3 with
# numpy and matplotlib.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

QUICK=${BENCH_QUICK:-0}
ONLY=${BENCH_ONLY:-chest_ap_256 chest_ap_512 head_lateral chest_scaling chest_collimated}
if [ "$QUICK" = 1 ]; then
  MAX=${BENCH_MAX_SAMPLES:-1e7} RUNS=${BENCH_RUNS:-1}
else
  MAX=${BENCH_MAX_SAMPLES:-1e9} RUNS=${BENCH_RUNS:-3}
fi
BUDGET=${BENCH_BUDGET:-60}
CHEST=${CHEST:-$root/../shared/data/ct/lidc-idri-0314-chest}
BUILD_DIR=${BUILD_DIR:-$root/build-bench}
OUT=${OUT:-$root/out/benchmark}
IMAGES=${IMAGES:-$root/docs/images}
PY=/usr/bin/python3

# rays per pixel side of the reference of a configuration; quick mode keeps 8 for the headline view only
ref_rays() {
  if [ -n "${BENCH_REF_RAYS:-}" ]; then echo "$BENCH_REF_RAYS"
  elif [ "$QUICK" = 1 ] && [ "$1" != chest_ap_256 ]; then echo 4
  else echo 8; fi
}
# exact projector rows: 1, 2, 4 rays per side, those below the reference's
exact_rays() {
  local k=$1 list="" r
  for r in 1 2 4; do [ "$r" -lt "$k" ] && list+="${list:+,}$r"; done
  echo "${list:-1}"
}

echo "== build ($BUILD_DIR, Release)"
cmake -S "$root" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD_DIR" -j "$(nproc)" --target PointBasedDRRBenchmark
BENCH=$BUILD_DIR/benchmark/PointBasedDRRBenchmark
mkdir -p "$OUT"

commit=$(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo '?')
dirty=$(git -C "$root" status --porcelain -- src include 2>/dev/null | head -1)
mode=$([ "$QUICK" = 1 ] && echo "quick mode" || echo "full run")
DESCRIPTION="Commit $commit${dirty:+ (with uncommitted changes in src/ or include/)}, $mode: samples up to $MAX, $RUNS run(s), budget $BUDGET s; $(date -u +%Y-%m-%dT%H:%MZ)."
COMMON=(--max-samples "$MAX" --runs "$RUNS" --budget "$BUDGET" --description "$DESCRIPTION")
[ -n "${BENCH_SAMPLERS:-}" ] && COMMON+=(--samplers "$BENCH_SAMPLERS")
[ -n "${BENCH_THREADS:-}" ] && COMMON+=(--threads "$BENCH_THREADS")
# shellcheck disable=SC2206
[ -n "${BENCH_ARGS:-}" ] && COMMON+=($BENCH_ARGS)

# The InVesalius head as scripts/demo.sh extracts it (scripts/invesalius-head.sh).
head_volume() {
  local dir=$root/out/demo
  if [ -f "$dir/head.mha" ] && [ -f "$dir/matrix.dat" ]; then echo "$dir/head.mha"; return; fi
  bash "$root/scripts/invesalius-head.sh" "$dir"
}

ran=() failed=()
run() {  # NAME INPUT [options...]
  local name=$1 input=$2; shift 2
  echo
  echo "== $name: $*"
  local start=$SECONDS
  if "$BENCH" "$input" "$OUT" --name "$name" "${COMMON[@]}" "$@" 2>&1 | tee "$OUT/$name.log"; then
    echo "== $name: $((SECONDS - start)) s, $OUT/$name.md"
    ran+=("$name")
  else
    echo "== $name FAILED after $((SECONDS - start)) s (log: $OUT/$name.log)"
    failed+=("$name")
  fi
}

want() { case " $ONLY " in *" $1 "*) return 0 ;; *) return 1 ;; esac; }

if [ -e "$CHEST" ]; then
  if want chest_ap_256; then
    k=$(ref_rays chest_ap_256)
    run chest_ap_256 "$CHEST" --gantry 90 --cols 256 --spacing 2.4 --reference-rays "$k" --exact-rays "$(exact_rays "$k")"
  fi
  if want chest_ap_512; then
    k=$(ref_rays chest_ap_512)
    run chest_ap_512 "$CHEST" --gantry 90 --cols 512 --spacing 1.2 --reference-rays "$k" --exact-rays "$(exact_rays "$k")"
  fi
else
  echo "SKIP chest configurations: no CT at $CHEST (set CHEST=DICOM_DIR)"
fi

if want head_lateral; then
  if head=$(head_volume); then
    k=$(ref_rays head_lateral)
    run head_lateral "$head" --gantry 0 --cols 512 --spacing 0.8 --reference-rays "$k" --exact-rays "$(exact_rays "$k")"
  else
    echo "SKIP head_lateral: no /usr/share/doc/invesalius-examples/examples/Cranium.inv3 (apt-get install invesalius-examples)"
  fi
fi

if [ -e "$CHEST" ]; then
  want chest_scaling && run chest_scaling "$CHEST" --mode scaling --gantry 90 --cols 256 --spacing 2.4 \
    --kernels box --splats nearest --scaling-samples 1e7 --no-plastimatch
  if want chest_collimated; then
    k=$(ref_rays chest_collimated)
    run chest_collimated "$CHEST" --mode collimated --gantry 90 --cols 256 --spacing 2.4 --collimated-cols 64 \
      --reference-rays "$k" --exact-rays "$(exact_rays "$k")" --no-itk --no-plastimatch
  fi
fi

echo
if [ ${#ran[@]} -eq 0 ]; then
  echo "nothing was run"
  exit 0
fi
if [ -x "$PY" ] && "$PY" -c "import numpy, matplotlib" 2>/dev/null; then
  csvs=()
  for name in "${ran[@]}"; do csvs+=("$OUT/$name.csv"); done
  suffix=""
  [ "$QUICK" = 1 ] && suffix="quick mode: samples up to $MAX, $RUNS run(s)"
  "$PY" "$root/benchmark/plot_benchmark.py" --out-dir "$IMAGES" --title-suffix "$suffix" "${csvs[@]}"
else
  echo "SKIP plots: $PY with numpy and matplotlib is needed"
fi
echo "Tables: $(for name in "${ran[@]}"; do printf '%s ' "$OUT/$name.md"; done)"
if [ ${#failed[@]} -gt 0 ]; then
  echo "FAILED: ${failed[*]}"
  exit 1
fi
