"""Issue 38's registration benchmark (benchmark/registration.sh): the random starts, and the summary.

  registration.py starts N SEED            N starts within 10 mm / 5 degrees, then N within 20 mm / 10 degrees
  registration.py summarize OUT_DIR        OUT_DIR/registration.csv -> OUT_DIR/registration.md (every case, method and
                                           range), registration_overview.md (one line per case and method) and
                                           registration.png
  registration.py reference SCORED.txt     the reference pose of the exact runs (pose and similarity a line)

A start is a translation of uniform direction and a length uniform up to the range's millimetres, and a rotation about
a uniform axis by an angle uniform up to its degrees, written as pbdrr register's pose (tx ty tz mm, rx ry rz degrees
of itk::Euler3DTransform: R = Rz Rx Ry, about the CT's centre).

The target registration error of a pose is the mean distance between where it and the true pose put the case's bone
points (voxels of 300 HU or more, drawn by PointBasedDRRRegistrationClassic --bone-points): success is an mTRE of 2 mm
or less. The true pose of a synthetic case is the identity (its X-rays were rendered there); a real localizer has no
truth, and its reference is the exact projector's registration: the mean pose of those of five runs whose exact
similarity is within 0.005 of the best (reference_scored.txt; `reference`).
"""
import csv
import math
import os
import sys
from collections import defaultdict

import numpy as np


def euler_matrix(rx, ry, rz):
    """itk::Euler3DTransform's rotation (ComputeZYX off): Rz Rx Ry, angles in radians."""
    cx, sx, cy, sy, cz, sz = math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry), math.cos(rz), math.sin(rz)
    Rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    Ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    Rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return Rz @ Rx @ Ry


def euler_angles(R):
    """The angles (radians) of Rz Rx Ry = R, as itk::Euler3DTransform::ComputeMatrixParameters finds them."""
    rx = math.asin(max(-1.0, min(1.0, R[2, 1])))
    A = math.cos(rx)
    if abs(A) > 1e-5:
        ry = math.atan2(-R[2, 0] / A, R[2, 2] / A)
        rz = math.atan2(-R[0, 1] / A, R[1, 1] / A)
    else:
        ry, rz = 0.0, math.atan2(R[1, 0], R[0, 0])
    return rx, ry, rz


def apply_pose(pose, centre, points):
    """x -> R (x - c) + c + t for pose tx ty tz (mm) rx ry rz (degrees)."""
    R = euler_matrix(*(math.radians(a) for a in pose[3:]))
    return (points - centre) @ R.T + centre + np.asarray(pose[:3])


def starts(n, seed):
    rng = np.random.default_rng(seed)
    for millimetres, degrees in ((10.0, 5.0), (20.0, 10.0)):
        for _ in range(n):
            d = rng.normal(size=3)
            d /= np.linalg.norm(d)
            a = rng.normal(size=3)
            a /= np.linalg.norm(a)
            t = d * millimetres * rng.uniform()
            angle = math.radians(degrees * rng.uniform())
            # The rotation about axis a by angle (Rodrigues), as Euler angles.
            K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
            R = np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K
            angles = [math.degrees(v) for v in euler_angles(R)]
            print("%d %s" % (millimetres, " ".join("%.4f" % v for v in list(t) + angles)))


def read_points(path):
    """The bone points file: '# centre x y z' then 'x y z' lines."""
    centre, points = None, []
    with open(path) as f:
        for line in f:
            if line.startswith("# centre"):
                centre = np.array([float(v) for v in line.split()[2:5]])
            elif line.strip() and not line.startswith("#"):
                points.append([float(v) for v in line.split()])
    return centre, np.array(points)


def mtre(pose, truth, centre, points):
    return float(np.mean(np.linalg.norm(apply_pose(pose, centre, points) - apply_pose(truth, centre, points), axis=1)))


METHOD_NAMES = {
    "new": "PointBasedDRRMetricv4 + v4 optimizer (pbdrr register)",
    "global": "the same with the global stage (4 starts on the first level)",
    "powell": "today's Powell method (pbdrr register at 159ec84)",
    "classic": "ITK classic: ray caster + NormalizedCorrelation + Powell",
}


def summarize(out):
    rows = list(csv.DictReader(open(os.path.join(out, "registration.csv"))))
    groups = defaultdict(list)
    records = []
    for r in rows:
        case = r["case"]
        centre, points = read_points(os.path.join(out, case, "bone_points.txt"))
        truth = [float(v) for v in open(os.path.join(out, case, "truth.txt")).read().split()]
        start = [float(r[k]) for k in ("tx0", "ty0", "tz0", "rx0", "ry0", "rz0")]
        pose = [float(r[k]) for k in ("tx", "ty", "tz", "rx", "ry", "rz")]
        shift = apply_pose(pose, centre, centre[None, :])[0] - apply_pose(truth, centre, centre[None, :])[0]
        record = dict(case=case, method=r["method"], range=int(r["range"]), start_tre=mtre(start, truth, centre, points),
                      tre=mtre(pose, truth, centre, points), seconds=float(r["seconds"]), wall=float(r["wall"]),
                      rss=float(r["rss_kb"]) / 1024.0, drrs=float(r["drrs"]), shift=shift, pose=np.array(pose),
                      truth=np.array(truth))
        records.append(record)
        groups[(case, r["method"], record["range"])].append(record)

    lines = ["| case | method | range (mm / deg) | starts | success (mTRE <= 2 mm) | start mTRE median (mm) |"
             " final mTRE median / 90th pct (mm) | registration s median (min-max) | process s median | peak RSS MB |"
             " DRRs median | centre error |x| |y| |z| median (mm) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for (case, method, rng), rs in sorted(groups.items(), key=lambda kv: (kv[0][0], kv[0][2], kv[0][1])):
        tre = np.array([r["tre"] for r in rs])
        seconds = np.array([r["seconds"] for r in rs])
        shifts = np.abs(np.array([r["shift"] for r in rs]))
        lines.append("| %s | %s | %d / %d | %d | %d / %d (%.0f%%) | %.1f | %.2f / %.2f | %.2f (%.2f-%.2f) | %.2f | %.0f |"
                     " %.0f | %.2f %.2f %.2f |" % (
                         case, method, rng, rng // 2, len(rs), (tre <= 2.0).sum(), len(rs), 100.0 * (tre <= 2.0).mean(),
                         np.median([r["start_tre"] for r in rs]), np.median(tre), np.percentile(tre, 90),
                         np.median(seconds), seconds.min(), seconds.max(), np.median([r["wall"] for r in rs]),
                         np.median([r["rss"] for r in rs]), np.median([r["drrs"] for r in rs]),
                         *np.median(shifts, axis=0)))
    # Ratios in one run, per case and range: the other methods' median time over the new method's.
    lines += ["", "| case | range | global / new (median registration time) | powell / new | classic / new |",
              "|---|---|---|---|---|"]
    for case in sorted({k[0] for k in groups}):
        for rng in (10, 20):
            new = groups.get((case, "new", rng))
            if not new:
                continue
            base = np.median([r["seconds"] for r in new])
            ratio = lambda m: ("%.1f" % (np.median([r["seconds"] for r in groups[(case, m, rng)]]) / base)
                               if (case, m, rng) in groups else "-")
            lines.append("| %s | %d / %d | %s | %s | %s |" % (case, rng, rng // 2, ratio("global"), ratio("powell"),
                                                             ratio("classic")))
    # The real localizer: in-plane agreement (the lateral view's plane: y, z, and rx about its beam) with the reference.
    loc = [r for r in records if r["case"].startswith("localizer")]
    if loc:
        lines += ["", "| case | method | converged | in-plane |ty| |tz| (mm), |rx| (deg) vs the reference, median |"
                  " the same, 90th percentile |", "|---|---|---|---|---|"]
        for key in sorted({(r["case"], r["method"]) for r in loc}):
            rs = [r for r in loc if (r["case"], r["method"]) == key and r["tre"] <= 2.0]
            n = len([r for r in loc if (r["case"], r["method"]) == key])
            d = np.abs(np.array([r["pose"] - r["truth"] for r in rs])) if rs else np.zeros((1, 6))
            lines.append("| %s | %s | %d / %d | %.2f %.2f, %.3f | %.2f %.2f, %.3f |" % (
                key[0], key[1], len(rs), n, *np.median(d[:, 1:4], axis=0), *np.percentile(d[:, 1:4], 90, axis=0)))
    text = "\n".join(lines) + "\n"
    open(os.path.join(out, "registration.md"), "w").write(text)
    overview_text = overview(groups)
    open(os.path.join(out, "registration_overview.md"), "w").write(overview_text)
    print(overview_text)
    print(text)
    plot(records, out)


def overview(groups):
    """One line per case and method: success per range, and the final mTRE, time, DRRs and memory of both ranges."""
    names = {"new": "this module (LBFGSB, analytic derivative)", "global": "the same, 4 starts on the first level",
             "powell": "the earlier Powell method (159ec84)", "classic": "ITK classic (ray caster, NCC, Powell)"}
    lines = ["| case | method | success 10 mm / 5 deg | success 20 mm / 10 deg | final mTRE median (mm) |"
             " registration s median | DRRs median | peak RSS MB |", "|---|---|---|---|---|---|---|---|"]
    for case in sorted({k[0] for k in groups}):
        for method in ("new", "global", "powell", "classic"):
            near, far = groups.get((case, method, 10), []), groups.get((case, method, 20), [])
            both = near + far
            if not both:
                continue
            rate = lambda rs: "%d / %d" % (sum(r["tre"] <= 2.0 for r in rs), len(rs)) if rs else "-"
            lines.append("| %s | %s | %s | %s | %.2f | %.2f | %.0f | %.0f |" % (
                case, names[method], rate(near), rate(far), np.median([r["tre"] for r in both]),
                np.median([r["seconds"] for r in both]), np.median([r["drrs"] for r in both]),
                np.median([r["rss"] for r in both])))
    return "\n".join(lines) + "\n"


def plot(records, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    methods = [m for m in ("new", "global", "powell", "classic") if any(r["method"] == m for r in records)]
    colours = {"new": "tab:blue", "global": "tab:purple", "powell": "tab:orange", "classic": "tab:green"}
    # Lines that coincide (100% for new and global) stay visible: wide markers under narrow, dashed over solid.
    styles = {"new": ("o-", 10), "global": ("s--", 5), "powell": ("o-", 7), "classic": ("D-", 7)}
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    edges = np.array([0, 4, 8, 12, 16, 24, 40])
    for m in methods:
        rs = [r for r in records if r["method"] == m]
        start = np.array([r["start_tre"] for r in rs])
        ok = np.array([r["tre"] <= 2.0 for r in rs])
        centres, rates = [], []
        for lo, hi in zip(edges[:-1], edges[1:]):
            inside = (start >= lo) & (start < hi)
            if inside.sum() >= 3:
                centres.append(0.5 * (lo + hi))
                rates.append(100.0 * ok[inside].mean())
        style, size = styles[m]
        axes[0].plot(centres, rates, style, markersize=size, color=colours[m], label="%s (%d runs)" % (m, len(rs)))
    axes[0].set_xlabel("start mTRE (mm)")
    axes[0].set_ylabel("success (final mTRE <= 2 mm), %")
    axes[0].set_ylim(-5, 105)
    axes[0].legend()
    axes[0].set_title("Success rate against start distance (all cases)")
    cases = sorted({r["case"] for r in records})
    width = 0.8 / max(1, len(methods))
    for k, m in enumerate(methods):
        data = [[r["seconds"] for r in records if r["method"] == m and r["case"] == c] or [np.nan] for c in cases]
        positions = np.arange(len(cases)) + (k - (len(methods) - 1) / 2) * width
        # The median in the method's colour: a method with one run on a case is a box of no height.
        box = axes[1].boxplot(data, positions=positions, widths=width * 0.9, patch_artist=True, showfliers=False,
                              medianprops={"color": colours[m], "linewidth": 2.5})
        for patch in box["boxes"]:
            patch.set_facecolor(colours[m])
    axes[1].set_yscale("log")
    axes[1].set_xticks(np.arange(len(cases)))
    axes[1].set_xticklabels(cases, rotation=20)
    axes[1].set_ylabel("registration time, s (log)")
    axes[1].set_title("Time per registration (2 cores)")
    axes[1].legend([plt.Rectangle((0, 0), 1, 1, color=colours[m]) for m in methods], methods)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "registration.png"), dpi=110)


def reference(path):
    rows = np.loadtxt(path)
    best = rows[:, 6].max()
    kept = rows[rows[:, 6] >= best - 0.005]
    print(" ".join("%.4f" % v for v in kept[:, :6].mean(axis=0)))
    sys.stderr.write("reference: %d of %d exact runs, spread (max - min) %s\n"
                     % (len(kept), len(rows), " ".join("%.3f" % v for v in np.ptp(kept[:, :6], axis=0))))


if __name__ == "__main__":
    if sys.argv[1] == "reference":
        reference(sys.argv[2])
    elif sys.argv[1] == "starts":
        starts(int(sys.argv[2]), int(sys.argv[3]))
    elif sys.argv[1] == "summarize":
        summarize(sys.argv[2])
    else:
        sys.exit(__doc__)
