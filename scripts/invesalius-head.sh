#!/usr/bin/env bash
# Extracts the InVesalius head CT that Debian's invesalius-examples ships into DIR as a MetaImage, DIR/head.mha, and
# prints its path. Cranium.inv3 is a gzip'd tar: matrix.dat holds int16 HU, C order (z, y, x) = 108 x 256 x 256, rows
# posterior-first (hence the y flip to LPS in the direction matrix), slice 0 at the skull base.
#   bash scripts/invesalius-head.sh DIR
set -euo pipefail
dir=${1:?usage: invesalius-head.sh DIR}
inv3=/usr/share/doc/invesalius-examples/examples/Cranium.inv3
if [ ! -f "$inv3" ]; then
  echo "invesalius-head.sh: $inv3 not found (apt-get install invesalius-examples)" >&2
  exit 1
fi
mkdir -p "$dir"
tar -xzf "$inv3" -C "$dir" --wildcards '*matrix.dat' --transform 's|.*/||'
cat >"$dir/head.mha" <<'HEADER'
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
echo "$dir/head.mha"
