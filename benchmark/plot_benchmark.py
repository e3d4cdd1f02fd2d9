#!/usr/bin/python3
"""Plots of PointBasedDRRBenchmark's CSV files (run with Debian's /usr/bin/python3: numpy, matplotlib).

  plot_benchmark.py [--out-dir DIR] [--title-suffix TEXT] CSV...

Each CSV becomes DIR/benchmark_NAME.png (NAME: the CSV's config column), drawn by what it holds:

- trade (sweep 'trade'): log-log NRMSE against wall time, one curve per point-based method (sampler: colour,
  kernel: line style, splat: marker) over its sample ladder; the exact projectors (1, 2, 4 ... rays per side) as a
  black line of points; ITK's ray caster and plastimatch as single points. Left: against the reference of the
  method's own voxel model (box: Siddon, tent: trilinear); right: every method against the box reference.
- scaling (sweeps 'samples', 'volume', 'detector'): wall time against samples, number of voxels and detector
  columns, with the preprocessing (HU->mu + sampling tables) against the number of voxels.
- collimated (sweeps 'collimated', 'crop'): NRMSE against wall time of the small detector and of the same crop of
  the full render; right: wall x NRMSE^2 (time to reach a given error, up to a constant) of both.

Default DIR: docs/images next to this script's directory. TEXT is appended to every title (e.g. "quick mode").
"""
import csv
import io
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

COLOURS = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown", "tab:pink", "tab:olive",
           "tab:cyan", "tab:gray"]
LINESTYLE = {"box": "-", "tent": "--"}
SUFFIX = [""]
MARKER = {"nearest": "o", "bilinear": "s"}


def num(x):
    try:
        v = float(x)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def ok(rows, **match):
    return [r for r in rows if r["status"] == "ok" and all(r[k] == v for k, v in match.items())]


def positive(xs, ys):
    pts = [(x, y) for x, y in zip(xs, ys) if x is not None and y is not None and x > 0 and y > 0]
    return [p[0] for p in pts], [p[1] for p in pts]


def sampler_colours(rows):
    names = []
    for r in rows:
        if r["sampler"] and r["sampler"] not in names:
            names.append(r["sampler"])
    return {n: COLOURS[i % len(COLOURS)] for i, n in enumerate(names)}


def with_suffix(text):
    return text + (" (%s)" % SUFFIX[0] if SUFFIX[0] else "")


def save(fig, path):
    buf = io.BytesIO()
    fig.savefig(buf, dpi=80)
    plt.close(fig)
    try:  # 256-colour palette: a third of the bytes, no visible change
        from PIL import Image
        Image.open(buf).convert("RGB").quantize(colors=256).save(path, optimize=True)
    except ImportError:
        with open(path, "wb") as f:
            f.write(buf.getvalue())
    print("wrote %s (%d KB)" % (path, os.path.getsize(path) // 1024))


def header(rows):
    r = rows[0]
    return "%s: %s x %s pixels, %s voxels" % (r["config"], r["cols"], r["rows"], r["voxels"])


# ------------------------------------------------------------------------------------------------- trade
def plot_trade(rows, path):
    colours = sampler_colours(ok(rows, method="points"))
    fig, axes = plt.subplots(1, 2, figsize=(14, 6.2), sharey=True)
    for ax, column, title in ((axes[0], "nrmse", "against the reference of the method's own voxel model"),
                              (axes[1], "nrmse_box", "against the box (Siddon) reference")):
        curves = {}
        for r in ok(rows, method="points"):
            curves.setdefault((r["sampler"], r["kernel"], r["splat"]), []).append(r)
        for (sampler, kernel, splat), rs in curves.items():
            rs.sort(key=lambda r: int(r["samples"]))
            x, y = positive([num(r["wall_s"]) for r in rs], [num(r[column]) for r in rs])
            ax.plot(x, y, color=colours[sampler], linestyle=LINESTYLE.get(kernel, ":"),
                    marker=MARKER.get(splat, "^"), markersize=4, linewidth=1.2, alpha=0.85)
        for method, style in (("exact-siddon", "k-"), ("exact-trilinear", "k--")):
            rs = sorted(ok(rows, method=method), key=lambda r: int(r["rays_per_pixel"]))
            x, y = positive([num(r["wall_s"]) for r in rs], [num(r[column]) for r in rs])
            ax.plot(x, y, style, marker="D", markersize=6, linewidth=1.5)
            for xi, yi, r in zip(x, y, [r for r in rs if num(r[column]) and num(r[column]) > 0]):
                ax.annotate(r["rays_per_pixel"], (xi, yi), textcoords="offset points", xytext=(5, 4), fontsize=7)
        for method, marker, colour in (("itk-raycast", "*", "crimson"), ("plastimatch-exact", "P", "teal"),
                                       ("plastimatch-uniform", "X", "teal")):
            rs = ok(rows, method=method)
            x, y = positive([num(r["wall_s"]) for r in rs], [num(r[column]) for r in rs])
            ax.plot(x, y, linestyle="none", marker=marker, markersize=12, color=colour)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
        ax.set_xlabel("wall time (s), median of runs")
        ax.set_title(title, fontsize=10)
    axes[0].set_ylabel("NRMSE (RMSE / range of the reference)")
    handles = [Line2D([], [], color=c, label=s) for s, c in colours.items()]
    handles += [Line2D([], [], color="gray", linestyle=LINESTYLE[k], label="kernel %s" % k) for k in LINESTYLE]
    handles += [Line2D([], [], color="gray", linestyle="none", marker=MARKER[s], label="splat %s" % s)
                for s in MARKER]
    handles += [Line2D([], [], color="k", linestyle="-", marker="D", label="exact Siddon (label: rays/pixel)"),
                Line2D([], [], color="k", linestyle="--", marker="D", label="exact trilinear"),
                Line2D([], [], color="crimson", linestyle="none", marker="*", markersize=12,
                       label="ITK ray caster"),
                Line2D([], [], color="teal", linestyle="none", marker="P", markersize=10,
                       label="plastimatch -i exact"),
                Line2D([], [], color="teal", linestyle="none", marker="X", markersize=10,
                       label="plastimatch -i uniform")]
    fig.legend(handles=handles, loc="center right", fontsize=8, frameon=False)
    fig.suptitle(with_suffix("Speed / accuracy, " + header(rows)), fontsize=11)
    fig.tight_layout(rect=(0, 0, 0.83, 0.95))
    save(fig, path)


# ----------------------------------------------------------------------------------------------- scaling
def plot_scaling(rows, path):
    colours = sampler_colours(ok(rows, method="points"))
    fig, axes = plt.subplots(1, 3, figsize=(16, 5.2))
    # samples
    ax = axes[0]
    for sampler, c in colours.items():
        rs = sorted(ok(rows, sweep="samples", method="points", sampler=sampler), key=lambda r: int(r["samples"]))
        x, y = positive([num(r["samples"]) for r in rs], [num(r["wall_s"]) for r in rs])
        ax.plot(x, y, color=c, marker="o", markersize=4, label=sampler)
    xs = [num(r["samples"]) for r in ok(rows, sweep="samples", method="points")]
    ys = [num(r["wall_s"]) for r in ok(rows, sweep="samples", method="points")]
    if xs:
        top = max(xs)
        y_top = max(y for x, y in zip(xs, ys) if x == top)
        ax.plot([top / 1000, top], [y_top / 1000, y_top], "k:", label="proportional to N")
    ax.set_xlabel("samples N")
    ax.set_ylabel("wall time (s)")
    ax.set_title("render time against samples", fontsize=10)
    # volume
    ax = axes[1]
    for sampler, c in colours.items():
        for method, style, label in (("points", "-", "render"), ("preprocess", "--", "preprocess")):
            rs = sorted(ok(rows, sweep="volume", method=method, sampler=sampler), key=lambda r: num(r["x"]))
            x, y = positive([num(r["x"]) for r in rs], [num(r["wall_s"]) for r in rs])
            ax.plot(x, y, color=c, linestyle=style, marker="o", markersize=4,
                    label="%s %s" % (sampler, label) if sampler == list(colours)[0] else None)
    for method, style in (("exact-siddon", "k-"), ("exact-trilinear", "k--"), ("itk-raycast", "r-")):
        rs = sorted(ok(rows, sweep="volume", method=method), key=lambda r: num(r["x"]))
        x, y = positive([num(r["x"]) for r in rs], [num(r["wall_s"]) for r in rs])
        ax.plot(x, y, style, marker="D", markersize=5, label=method + " (1 ray)")
    samples = [r["samples"] for r in ok(rows, sweep="volume", method="points")]
    ax.set_xlabel("voxels (the volume resampled over the same box)")
    ax.set_title("time against volume size (points: %s samples; dashed: preprocess)"
                 % ("%.3g" % float(samples[0]) if samples else "?"), fontsize=10)
    # detector
    ax = axes[2]
    for sampler, c in colours.items():
        rs = sorted(ok(rows, sweep="detector", method="points", sampler=sampler), key=lambda r: num(r["x"]))
        x, y = positive([num(r["x"]) for r in rs], [num(r["wall_s"]) for r in rs])
        ax.plot(x, y, color=c, marker="o", markersize=4)
    for method, style in (("exact-siddon", "k-"), ("itk-raycast", "r-")):
        rs = sorted(ok(rows, sweep="detector", method=method), key=lambda r: num(r["x"]))
        x, y = positive([num(r["x"]) for r in rs], [num(r["wall_s"]) for r in rs])
        ax.plot(x, y, style, marker="D", markersize=5, label=method + " (1 ray)")
    ax.set_xlabel("detector columns (= rows), same field of view")
    ax.set_title("time against detector size", fontsize=10)
    for ax in axes:
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
    handles = [Line2D([], [], color=c, label=s) for s, c in colours.items()]
    handles += [Line2D([], [], color="gray", linestyle="--", label="preprocess (HU->mu + tables)"),
                Line2D([], [], color="k", marker="D", label="exact Siddon, 1 ray/pixel"),
                Line2D([], [], color="k", linestyle="--", marker="D", label="exact trilinear, 1 ray/pixel"),
                Line2D([], [], color="r", marker="D", label="ITK ray caster"),
                Line2D([], [], color="k", linestyle=":", label="proportional to N")]
    fig.legend(handles=handles, loc="center right", fontsize=8, frameon=False)
    fig.suptitle(with_suffix("Scaling, " + rows[0]["config"]), fontsize=11)
    fig.tight_layout(rect=(0, 0, 0.86, 0.95))
    save(fig, path)


# -------------------------------------------------------------------------------------------- collimated
def plot_collimated(rows, path):
    colours = sampler_colours(ok(rows, method="points"))
    fig, axes = plt.subplots(1, 2, figsize=(14, 5.8))
    ax = axes[0]
    combos = []
    for r in ok(rows, method="points"):
        key = (r["sampler"], r["kernel"], r["splat"])
        if key not in combos:
            combos.append(key)
    for sampler, kernel, splat in combos:
        for view, style in (("collimated", "-"), ("crop", ":")):
            rs = sorted(ok(rows, sweep=view, method="points", sampler=sampler, kernel=kernel, splat=splat),
                        key=lambda r: int(r["samples"]))
            x, y = positive([num(r["wall_s"]) for r in rs], [num(r["nrmse"]) for r in rs])
            ax.plot(x, y, color=colours[sampler], linestyle=style, marker=MARKER.get(splat, "^"), markersize=4,
                    alpha=0.9 if kernel == "box" else 0.5)
    for view, style in (("collimated", "k-"), ("crop", "k:")):
        rs = sorted(ok(rows, sweep=view, method="exact-siddon"), key=lambda r: int(r["rays_per_pixel"]))
        x, y = positive([num(r["wall_s"]) for r in rs], [num(r["nrmse"]) for r in rs])
        ax.plot(x, y, style, marker="D", markersize=6)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.grid(True, which="both", alpha=0.3)
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("NRMSE over the collimated pixels")
    ax.set_title("solid: collimated detector; dotted: crop of the full render", fontsize=10)
    # efficiency: median over the ladder's largest three rungs of wall x NRMSE^2, per method and view
    ax = axes[1]
    labels, coll, crop = [], [], []
    for sampler, kernel, splat in combos:
        vals = {}
        for view in ("collimated", "crop"):
            rs = sorted(ok(rows, sweep=view, method="points", sampler=sampler, kernel=kernel, splat=splat),
                        key=lambda r: int(r["samples"]))[-3:]
            e = sorted(num(r["wall_x_nrmse2"]) for r in rs if num(r["wall_x_nrmse2"]))
            vals[view] = e[len(e) // 2] if e else float("nan")
        labels.append("%s\n%s %s" % (sampler, kernel, splat))
        coll.append(vals["collimated"])
        crop.append(vals["crop"])
    idx = range(len(labels))
    ax.bar([i - 0.2 for i in idx], coll, width=0.4, label="collimated detector", color="tab:blue")
    ax.bar([i + 0.2 for i in idx], crop, width=0.4, label="crop of the full render", color="tab:gray")
    ax.set_xticks(list(idx))
    ax.set_xticklabels(labels, fontsize=6, rotation=90)
    ax.set_yscale("log")
    ax.set_ylabel("wall x NRMSE^2 (s): lower is faster at equal error")
    ax.set_title("time per achieved NRMSE (median of the 3 largest rungs)", fontsize=10)
    ax.legend(fontsize=8)
    handles = [Line2D([], [], color=c, label=s) for s, c in colours.items()]
    handles += [Line2D([], [], color="gray", linestyle="none", marker=MARKER[s], label="splat %s" % s)
                for s in MARKER]
    handles += [Line2D([], [], color="k", marker="D", label="exact Siddon")]
    axes[0].legend(handles=handles, fontsize=7, loc="lower left")
    r = ok(rows, sweep="collimated")[0]
    fig.suptitle(with_suffix("Collimated view, %s: %s x %s detector against the same pixels of the full render"
                       % (r["config"], r["cols"], r["rows"])), fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    save(fig, path)


def main(argv):
    out = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "docs", "images")
    paths = []
    i = 1
    while i < len(argv):
        if argv[i] == "--out-dir":
            out = argv[i + 1]
            i += 2
        elif argv[i] == "--title-suffix":
            SUFFIX[0] = argv[i + 1]
            i += 2
        elif argv[i] in ("-h", "--help"):
            print(__doc__)
            return 0
        else:
            paths.append(argv[i])
            i += 1
    if not paths:
        print(__doc__)
        return 1
    os.makedirs(out, exist_ok=True)
    for path in paths:
        rows = read(path)
        if not rows:
            print("%s: empty, skipped" % path)
            continue
        sweeps = {r["sweep"] for r in rows}
        name = rows[0]["config"]
        target = os.path.join(out, "benchmark_%s.png" % name)
        if "trade" in sweeps:
            plot_trade(rows, target)
        elif "samples" in sweeps or "volume" in sweeps or "detector" in sweeps:
            plot_scaling(rows, target)
        elif "collimated" in sweeps:
            plot_collimated(rows, target)
        else:
            print("%s: no sweep recognised, skipped" % path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
