"""Tabulates the bias of the paper's estimators (see paper_bias.sh) and draws difference images."""
import os
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def read_mha(path):
    raw = open(path, "rb").read()
    marker = b"ElementDataFile = LOCAL\n"
    start = raw.index(marker) + len(marker)
    header = dict(line.split(" = ", 1) for line in raw[:start].decode().strip().split("\n"))
    dims = [int(x) for x in header["DimSize"].split()]
    return np.frombuffer(raw[start:], dtype=np.float32).reshape(dims[::-1]).astype(np.float64)


out = sys.argv[1]
variants = [
    ("unbiased", "level-alias, unbiased weights"),
    ("count", "level-alias, paper's unweighted perspective count"),
    ("hybrid", "paper-hybrid, exact weights"),
    ("paper", "paper-hybrid as published (no weights)"),
]
print("| volume | estimator (10^8 points) | image sum / exact | NRMSE (range) | mean error / exact mean | worst pixel error / range |")
print("|---|---|---|---|---|---|")
for name in ("chest", "head"):
    ref_path = os.path.join(out, name + ".ref.mha")
    if not os.path.exists(ref_path):
        continue
    ref = read_mha(ref_path)
    span = ref.max() - ref.min()
    images = {}
    for key, label in variants:
        img = read_mha(os.path.join(out, "%s.%s.mha" % (name, key)))
        images[key] = img
        err = img - ref
        print("| %s | %s | %.4f | %.4f | %+.4f | %.3f |" % (
            name, label, img.sum() / ref.sum(), np.sqrt(np.mean(err ** 2)) / span, err.mean() / ref.mean(),
            np.abs(err).max() / span))
    fig, axes = plt.subplots(1, 4, figsize=(16, 4.4))
    panels = [(ref, "exact (Siddon, 16 rays/pixel)", "gray"),
              (images["unbiased"] - ref, "unbiased - exact", "RdBu_r"),
              (images["count"] - ref, "paper count (perspective) - exact", "RdBu_r"),
              (images["paper"] - ref, "paper-hybrid as published - exact\n(clipped: its spikes reach %.0f)" % np.abs(images["paper"] - ref).max(), "RdBu_r")]
    limit = np.abs(images["count"] - ref).max()
    for axis, (img, title, cmap) in zip(axes, panels):
        if cmap == "gray":
            shown = axis.imshow(img, cmap=cmap)
        else:
            shown = axis.imshow(img, cmap=cmap, vmin=-limit, vmax=limit)
        axis.set_title(title, fontsize=9)
        axis.axis("off")
        fig.colorbar(shown, ax=axis, fraction=0.046)
    fig.suptitle("%s: line-integral error of the paper's estimators, 10^8 points (one color scale)" % name)
    fig.savefig(os.path.join(out, name + "_paper_bias.png"), dpi=70, bbox_inches="tight")
    print("difference image: %s" % os.path.join(out, name + "_paper_bias.png"), file=sys.stderr)
