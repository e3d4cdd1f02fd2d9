#!/bin/bash
# Two gantry-tilted series of one phantom, rendered in one view, compared on the rays both volumes cover entirely
# (issue 15, item 2: sheared grids). Defaults: the Philips export of ../shared/data (S2010 at -18.5 degrees, S3010 at
# +16.5 degrees), a lateral view at one isocenter, exact Siddon with 2 x 2 rays per pixel.
#
#   bash benchmark/tilted_pair.sh [FIRST_SERIES_DIR] [SECOND_SERIES_DIR] [PBDRR]
#
# Environment: VIEW (pbdrr view options; the view must be lateral, --gantry 0, for the coverage mask), OUT (a
# directory for the images). Prints the number of rays both cover, the mean and RMS difference there, and the best
# integer shift between the two images.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
PHILIPS=$root/../shared/data/ct/philips-s21610-head-phantom
FIRST=${1:-$PHILIPS/S2010}
SECOND=${2:-$PHILIPS/S3010}
PBDRR=${3:-$root/build/apps/pbdrr/pbdrr}
VIEW=${VIEW:---gantry 0 --isocenter 0 104 764 --size 300 300 --spacing 1 1}
OUT=${OUT:-$(mktemp -d)}
mkdir -p "$OUT"
for series in "$FIRST" "$SECOND"; do
  if [ ! -d "$series" ]; then
    echo "tilted_pair.sh: $series not found (give two series directories)" >&2
    exit 2
  fi
done
# shellcheck disable=SC2086
"$PBDRR" "$FIRST" -o "$OUT/first.mha" $VIEW --exact siddon --ss 2 -q -v 2>"$OUT/first.log"
# shellcheck disable=SC2086
"$PBDRR" "$SECOND" -o "$OUT/second.mha" $VIEW --exact siddon --ss 2 -q -v 2>"$OUT/second.log"
/usr/bin/python3 - "$OUT" <<'PY'
import re, sys
import numpy as np

out = sys.argv[1]

def read_mha(path):
    data = open(path, "rb").read()
    header, _, body = data.partition(b"ElementDataFile = LOCAL\n")
    fields = dict(line.split(" = ", 1) for line in header.decode().splitlines() if " = " in line)
    size = [int(v) for v in fields["DimSize"].split()]
    return np.frombuffer(body[: 4 * size[0] * size[1]], "<f4").reshape(size[1], size[0]).astype(float)

def numbers(text):
    return [float(v) for v in re.findall(r"-?[0-9.]+(?:e-?[0-9]+)?", text)]

def read_log(path):
    """The volume's grid and the view, from pbdrr -v."""
    log = open(path).read()
    volume = re.search(r"volume: size (.*?), spacing (.*?) mm, origin \[(.*?)\] mm, direction \[(.*?)\]", log)
    geometry = re.search(r"SID ([0-9.]+) mm.*detector (\d+) cols x (\d+) rows at ([0-9.]+) x ([0-9.]+) mm.*"
                         r"source \[(.*?)\], columns along \[(.*?)\], rows along \[(.*?)\]", log)
    grid = {"size": np.array(numbers(volume.group(1))), "spacing": np.array(numbers(volume.group(2))),
            "origin": np.array(numbers(volume.group(3))),
            "direction": np.array(numbers(volume.group(4))).reshape(3, 3)}
    view = {"sid": float(geometry.group(1)), "cols": int(geometry.group(2)), "rows": int(geometry.group(3)),
            "du": float(geometry.group(4)), "dv": float(geometry.group(5)),
            "source": np.array(numbers(geometry.group(6))), "u": np.array(numbers(geometry.group(7))),
            "v": np.array(numbers(geometry.group(8)))}
    return grid, view

grids, view = [], None
for name in ("first", "second"):
    grid, view = read_log(f"{out}/{name}.log")
    grids.append(grid)
normal = np.cross(view["v"], view["u"])  # detector to source
centre = view["source"] - view["sid"] * normal
cols = (np.arange(view["cols"]) - (view["cols"] - 1) / 2) * view["du"]
rows = (np.arange(view["rows"]) - (view["rows"] - 1) / 2) * view["dv"]
pixels = centre + cols[None, :, None] * view["u"] + rows[:, None, None] * view["v"]
# The depth range both volumes span along the beam (x for a lateral view): a ray is covered by a volume if every
# point of it in that range lies inside the volume's parallelepiped.
lows, highs = [], []
for grid in grids:
    corners = [grid["origin"] + (grid["direction"] * grid["spacing"]) @ (np.array(c) * (grid["size"] - 1))
               for c in np.ndindex(2, 2, 2)]
    depths = [np.dot(c, normal) for c in corners]
    lows.append(min(depths)); highs.append(max(depths))
covered = np.ones(pixels.shape[:2], bool)
for grid in grids:
    inverse = np.linalg.inv(grid["direction"] * grid["spacing"])
    for depth in np.linspace(max(lows), min(highs), 60):
        t = (depth - np.dot(view["source"], normal)) / ((pixels - view["source"]) @ normal)
        points = view["source"] + t[..., None] * (pixels - view["source"])
        index = (points - grid["origin"]) @ inverse.T
        covered &= np.all((index >= -0.5) & (index <= grid["size"] - 0.5), axis=-1)
a, b = read_mha(f"{out}/first.mha"), read_mha(f"{out}/second.mha")
signal = covered & (a > 0.05 * a.max())
d, m = (a - b)[signal], a[signal]
print("rays both volumes cover: %d of %d (%d with signal)" % (covered.sum(), covered.size, signal.sum()))
print("on those: mean L %.4f; mean difference %.4f (%.2f%% of the mean); RMS difference %.4f (%.2f%% of the mean, "
      "%.2f%% of the peak); 99th percentile |difference| %.2f%% of the peak"
      % (m.mean(), d.mean(), 100 * d.mean() / m.mean(), np.sqrt((d ** 2).mean()),
         100 * np.sqrt((d ** 2).mean()) / m.mean(), 100 * np.sqrt((d ** 2).mean()) / a.max(),
         100 * np.percentile(np.abs(d), 99) / a.max()))
rr, cc = np.where(covered)
r0, r1, c0, c1 = rr.min() + 5, rr.max() - 5, cc.min() + 5, cc.max() - 5
best = None
for dy in range(-4, 5):
    for dx in range(-4, 5):
        both = covered[r0:r1, c0:c1] & covered[r0 + dy:r1 + dy, c0 + dx:c1 + dx]
        rms = np.sqrt(((a[r0:r1, c0:c1] - b[r0 + dy:r1 + dy, c0 + dx:c1 + dx])[both] ** 2).mean())
        best = min(best, (rms, dy, dx)) if best else (rms, dy, dx)
print("best integer shift of the second image (rows, columns) in detector pixels: (%d, %d), RMS %.4f"
      % (best[1], best[2], best[0]))
PY
