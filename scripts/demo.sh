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
# Cranium.inv3 is a gzip'd tar: matrix.dat holds int16 HU, C order (z, y, x) = 108 x 256 x 256, rows
# posterior-first (hence the y flip to LPS), slice 0 at the skull base.
inv3=/usr/share/doc/invesalius-examples/examples/Cranium.inv3
tar -xzf "$inv3" -C "$out" --wildcards '*matrix.dat' --transform 's|.*/||'
cat > "$out/head.mha" <<'HEADER'
ObjectType = Image
NDims = 3
BinaryData = True
BinaryDataByteOrderMSB = False
TransformMatrix = 1 0 0 0 -1 0 0 0 1
Offset = 0 0 0
ElementSpacing = 0.9570312 0.9570312 1.5
DimSize = 256 256 108
ElementType = MET_SHORT
ElementDataFile = matrix.dat
HEADER

pbdrr=build/apps/pbdrr/pbdrr
"$pbdrr" "$out/head.mha" -o "$out/head_lateral.png" --gantry 0 --size 512 512 --spacing 0.8 0.8 --samples 50M \
  --kernel tent --seed 1 --verbose
"$pbdrr" "$out/head.mha" -o "$out/head_ap.png" --gantry 90 --size 512 512 --spacing 0.8 0.8 --samples 50M \
  --kernel tent --seed 1
echo
echo "Head DRRs (50 million points each, unbiased line integrals windowed to 8 bits):"
echo "  lateral: $out/head_lateral.png"
echo "  AP:      $out/head_ap.png"
