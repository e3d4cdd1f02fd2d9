#!/usr/bin/env bash
# Installs what PointBasedDRR needs (Debian packages), builds pbdrr in Release, and renders a lateral and an AP
# radiograph of the InVesalius head CT that Debian's invesalius-examples ships. Prints where the PNGs are.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-dependencies.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build -j "$(nproc)" --target pbdrr

out="$PWD/out/demo"
mkdir -p "$out"
head=$(bash scripts/invesalius-head.sh "$out")

pbdrr=build/apps/pbdrr/pbdrr
# pbdrr's default (--accuracy 0.5: the estimator predicted fastest to 0.5% error, -v says which); only the view is
# given.
"$pbdrr" "$head" -o "$out/head_lateral.png" --gantry 0 --spacing 0.8 0.8 --seed 1 --verbose
"$pbdrr" "$head" -o "$out/head_ap.png" --gantry 90 --spacing 0.8 0.8 --seed 1
echo
echo "Head DRRs (pbdrr's default, --accuracy 0.5: line integrals to 0.5% error, windowed to 8 bits):"
echo "  lateral: $out/head_lateral.png"
echo "  AP:      $out/head_ap.png"
