#!/usr/bin/env python3
"""Error against time for the control variate, from the table benchmark/control_variate.sh prints.

    bash benchmark/control_variate.sh > cv.md
    /usr/bin/python3 benchmark/plot_control_variate.py cv.md docs/images/control_variate_chest_ap_256.png

One series per family of rows: the exact Siddon projector (k x k rays), plain stratified sampling and the control
variate with F = 2, 4, 8 (points at 10^6, 10^7, 10^8; `ss2` rows: 2 x 2 antithetic pairs per replicate). Time is
pbdrr's preprocess + render (s), error the NRMSE against the 8 x 8-ray exact pixel average. Needs matplotlib.
"""
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402


def read_rows(path):
    """(setting, total seconds, NRMSE) for every row of the markdown table."""
    rows = []
    for line in open(path, encoding="utf-8"):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 5 or not re.match(r"^[0-9.]+$", cells[3]):
            continue
        rows.append((cells[0], float(cells[3]), float(cells[4])))
    return rows


def family(setting):
    """The series a row belongs to."""
    if setting.startswith("exact"):
        return "exact Siddon (1, 2 x 2, 4 x 4 rays)"
    if setting.startswith("stratified"):
        return "plain stratified"
    match = re.match(r"cv(\d+)( ss2)? stratified", setting)
    if match:
        return "control variate F = %s%s, stratified" % (match.group(1), ", 2 x 2 pairs" if match.group(2) else "")
    return None


def main(table, output):
    series = {}
    for setting, seconds, error in read_rows(table):
        name = family(setting)
        if name:
            series.setdefault(name, []).append((seconds, error * 100.0, setting))
    figure, axes = plt.subplots(figsize=(7.5, 5))
    for name, points in series.items():  # in the table's order: increasing N, or rays
        style = "k-o" if name.startswith("exact") else ("s--" if name.startswith("plain") else "^-")
        axes.plot([p[0] for p in points], [p[1] for p in points], style, label=name)
    axes.set_xscale("log")
    axes.set_yscale("log")
    for axis in (axes.xaxis, axes.yaxis):
        axis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        axis.set_minor_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
    axes.set_xlabel("pbdrr preprocess + render (s), median of 3")
    axes.set_ylabel("NRMSE against the exact pixel average (%)")
    axes.set_title("Chest AP, 256 x 256 at 2.4 mm: control variate against exact and plain")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(output, dpi=110)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: plot_control_variate.py TABLE.md OUTPUT.png")
    main(sys.argv[1], sys.argv[2])
