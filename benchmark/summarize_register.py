"""Summary of benchmark/register_localizer.sh: per series and method, the median pose, how many starts reach it
(within 1 mm in translation and 0.5 degrees in each rotation), and the wall time per registration (median)."""
import csv
import sys
from collections import defaultdict

import numpy as np

rows = defaultdict(list)
with open(sys.argv[1]) as f:
    for r in csv.DictReader(f):
        rows[(r["series"], r["method"])].append(r)
print("| series | method | converged (1 mm, 0.5 deg) | median pose tx ty tz (mm) rx ry rz (deg) | spread of the converged (mm, deg) | similarity median (GC, full resolution) | s per registration (median) | DRRs |")
print("|---|---|---|---|---|---|---|---|")
for (series, method), rs in sorted(rows.items()):
    pose = np.array([[float(r[k]) for k in ("tx", "ty", "tz", "rx", "ry", "rz")] for r in rs])
    median = np.median(pose, axis=0)
    close = (np.linalg.norm(pose[:, :3] - median[:3], axis=1) <= 1.0) & (np.abs(pose[:, 3:] - median[3:]) <= 0.5).all(axis=1)
    spread = pose[close].std(axis=0) if close.any() else np.zeros(6)
    seconds = np.median([float(r["seconds"]) for r in rs])
    ncc = np.median([float(r["similarity"]) for r in rs])
    drrs = np.median([float(r["drrs"]) for r in rs])
    print("| %s | %s | %d of %d | %s | %s | %.4f | %.1f | %.0f |" % (
        series, method, close.sum(), len(rs), " ".join("%.2f" % v for v in median),
        " ".join("%.2f" % v for v in spread), ncc, seconds, drrs))
