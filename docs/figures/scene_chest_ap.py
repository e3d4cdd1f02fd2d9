#!/usr/bin/python3
"""The README's picture of issue 16: the chest's AP view four ways, from examples/RenderScene's four images.

    build/examples/RenderScene ../shared/data/ct/lidc-idri-0314-chest /tmp/scene
    /usr/bin/python3 docs/figures/scene_chest_ap.py /tmp/scene docs/images/scene_chest_ap.png
"""
import sys
import zlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_mha(path):
    """A 2D float MetaImage with its data inline (what itk::WriteImage writes for .mha)."""
    data = open(path, "rb").read()
    marker = b"ElementDataFile = LOCAL\n"
    end = data.index(marker) + len(marker)
    header = dict(line.split(" = ", 1) for line in data[:end].decode().splitlines() if " = " in line)
    raw = data[end:]
    if header.get("CompressedData") == "True":
        raw = zlib.decompress(raw)
    columns, rows = (int(v) for v in header["DimSize"].split())
    return np.frombuffer(raw, dtype=np.float32).reshape(rows, columns)


prefix, output = sys.argv[1], sys.argv[2]
panels = [
    ("line_integral", "line integral of mu (60 keV)"),
    ("bone", "bone label only"),
    ("70kvp", "70 kVp, 10^4 photons/pixel"),
    ("120kvp", "120 kVp, 10^4 photons/pixel"),
]
figure, axes = plt.subplots(1, 4, figsize=(16, 4.6))
for axis, (name, title) in zip(axes, panels):
    image = read_mha(f"{prefix}_{name}.mha")
    low, high = np.percentile(image, [0.5, 99.5])
    # Detector rows run along -z in the module's AP view: the head is at row 0, shown at the top.
    axis.imshow(image, cmap="gray", vmin=low, vmax=high)
    axis.set_title(title)
    axis.set_axis_off()
figure.tight_layout()
figure.savefig(output, dpi=80)
