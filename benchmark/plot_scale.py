#!/usr/bin/python3
"""Time and peak memory against the CT's voxels, log-log, from benchmark/scale.sh's scale.csv (issue 27).

    /usr/bin/python3 benchmark/plot_scale.py OUT.png SCALE.csv [LABEL=]SCALE.csv ...

One colour per tool (pbdrr's defaults, pbdrr --exact siddon, plastimatch drr -i exact), one line style per CSV
(e.g. before=scale_before/scale.csv after=scale_after/scale.csv to compare two builds). A tool whose runs all
failed on a volume (the 4x chest under its memory cap) is drawn as an x at what it reached.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {"pbdrr (defaults)": "tab:blue", "pbdrr --exact siddon": "tab:orange",
           "plastimatch drr -i exact": "tab:green"}
STYLES = ["-", "--", ":", "-."]


def main(png, inputs):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for n, arg in enumerate(inputs):
        label, path = arg.split("=", 1) if "=" in arg else (os.path.basename(os.path.dirname(os.path.abspath(arg))), arg)
        rows = list(csv.DictReader(open(path)))
        for tool in dict.fromkeys(r["tool"] for r in rows):
            rs = sorted((r for r in rows if r["tool"] == tool), key=lambda r: int(r["voxels"]))
            for ax, key, scale in ((axes[0], "median_s", 1.0), (axes[1], "peak_mib", 1 / 1024)):
                ok = [r for r in rs if int(r["ok_runs"]) > 0]
                ax.plot([int(r["voxels"]) for r in ok], [float(r[key]) * scale for r in ok], STYLES[n % 4] + "o",
                        color=COLOURS.get(tool), label="%s (%s)" % (tool, label), ms=4)
                bad = [r for r in rs if int(r["ok_runs"]) == 0]
                ax.plot([int(r["voxels"]) for r in bad], [float(r[key]) * scale for r in bad], "x",
                        color=COLOURS.get(tool), ms=9, mew=2)
    ram = [int(l.split()[1]) / 2 ** 20 for l in open("/proc/meminfo") if l.startswith("MemTotal")]
    if ram:
        axes[1].axhline(ram[0], color="grey", ls="--", lw=1)
        axes[1].text(0.02, ram[0], "this machine's RAM", transform=axes[1].get_yaxis_transform(), fontsize=7,
                     color="grey", va="bottom")
    for ax, title in ((axes[0], "time, whole process (s)"), (axes[1], "peak RSS (GiB)")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("CT voxels")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle("Chest CT upsampled 1x, 2x, 4x per axis; AP view 256 x 256 (benchmark/scale.sh); x: failed")
    fig.tight_layout()
    fig.savefig(png, dpi=120)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2:])
