#!/usr/bin/python3
"""Helper of compare_plastimatch.sh: pbdrr against `plastimatch drr` (run it through the .sh).

Needs only numpy (and matplotlib for the picture). Subcommands:

  phantoms OUT           write the synthetic volumes of the convention check (mu in 1/mm, MetaImage)
  conventions OUT        read the convention-check renders, print what plastimatch does, write OUT/conventions.env
  prepare CT_MHA OUT     mu = 0.02059 * max(0, 1 + HU/1000) (1/mm) as OUT/mu.mha, the same with one layer of
                         zero voxels all around as OUT/mu_pad.mha; print the volume centre (pbdrr's isocenter)
  compare OUT PNG        numbers of the chest comparison (Markdown), the side-by-side picture, OUT/nmatch.txt
  timing OUT             the timing table from OUT/times.tsv (Markdown)

Images: pbdrr writes float line integrals L (.mha); plastimatch writes PFM whose rows are stored top row first
(row 0 = the +vup edge, as pbdrr), values L / 10 with -P none and mu in 1/mm (checked by `conventions`).
"""
import math
import os
import sys

import numpy as np

MU_WATER = 0.02059  # 1/mm at 60 keV (NIST XCOM): pbdrr's default


# ----------------------------------------------------------------------------------------------- I/O
def read_mha(path):
    """MetaImage with LOCAL data (what pbdrr and plastimatch write). Returns (array [z,]y,x, header dict)."""
    with open(path, "rb") as f:
        data = f.read()
    key = b"ElementDataFile = LOCAL\n"
    i = data.index(key) + len(key)
    hdr = dict(l.split(" = ", 1) for l in data[:i].decode("latin1").strip().split("\n"))
    if hdr.get("CompressedData", "False") == "True":
        raise SystemExit("%s: compressed MetaImage not supported here" % path)
    dims = [int(x) for x in hdr["DimSize"].split()]
    types = {"MET_FLOAT": "f4", "MET_DOUBLE": "f8", "MET_SHORT": "i2", "MET_USHORT": "u2", "MET_INT": "i4",
             "MET_UINT": "u4", "MET_CHAR": "i1", "MET_UCHAR": "u1"}
    order = ">" if hdr.get("BinaryDataByteOrderMSB", hdr.get("ElementByteOrderMSB", "False")) == "True" else "<"
    a = np.frombuffer(data[i:], dtype=order + types[hdr["ElementType"]], count=int(np.prod(dims)))
    return a.reshape(dims[::-1]), hdr


def write_mha(path, arr, spacing, origin, direction=(1, 0, 0, 0, 1, 0, 0, 0, 1)):
    """3D float (or short) MetaImage, arr indexed [z, y, x]."""
    arr = np.ascontiguousarray(arr)
    et = {"f": "MET_FLOAT", "i": "MET_SHORT"}[arr.dtype.kind]
    arr = arr.astype("<f4" if et == "MET_FLOAT" else "<i2")
    nz, ny, nx = arr.shape
    hdr = ("ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
           "CompressedData = False\nTransformMatrix = %s\nOffset = %r %r %r\nCenterOfRotation = 0 0 0\n"
           "AnatomicalOrientation = RAI\nElementSpacing = %r %r %r\nDimSize = %d %d %d\nElementType = %s\n"
           "ElementDataFile = LOCAL\n" % (" ".join(repr(float(d)) for d in direction), *[float(o) for o in origin],
                                          *[float(s) for s in spacing], nx, ny, nz, et))
    with open(path, "wb") as f:
        f.write(hdr.encode())
        f.write(arr.tobytes())


def read_pfm(path):
    """plastimatch's PFM: 'Pf', 'width height', scale (<0: little endian), then rows top first."""
    with open(path, "rb") as f:
        if f.readline().strip() != b"Pf":
            raise SystemExit("%s: not a grey PFM" % path)
        w, h = (int(x) for x in f.readline().split())
        s = float(f.readline())
        a = np.frombuffer(f.read(), dtype="<f4" if s < 0 else ">f4", count=w * h)
    return a.reshape(h, w)


def volume_centre(hdr):
    """Centre of the voxel-index box in mm: origin + D diag(spacing) (size - 1) / 2 (pbdrr's default isocenter)."""
    dims = np.array([int(x) for x in hdr["DimSize"].split()], float)
    sp = np.array([float(x) for x in hdr["ElementSpacing"].split()])
    org = np.array([float(x) for x in hdr["Offset"].split()])
    d = np.array([float(x) for x in hdr.get("TransformMatrix", "1 0 0 0 1 0 0 0 1").split()]).reshape(3, 3).T
    return org + d @ (sp * (dims - 1) / 2)


# ---------------------------------------------------------------------------------------------- stats
def stats(a, ref):
    """Sum ratio a/ref, Pearson r, NRMSE = RMSE / (max - min of ref), max |a - ref|."""
    a = np.asarray(a, float)
    ref = np.asarray(ref, float)
    d = a - ref
    return dict(ratio=a.sum() / ref.sum(), r=np.corrcoef(a.ravel(), ref.ravel())[0, 1],
                nrmse=math.sqrt(np.mean(d * d)) / (ref.max() - ref.min()), maxabs=np.abs(d).max())


def row(name, s):
    return "| %s | %.6f | %.8f | %.2e | %.4f |" % (name, s["ratio"], s["r"], s["nrmse"], s["maxabs"])


HEAD = ("| image | sum ratio | Pearson r | NRMSE | max abs diff |\n"
        "|---|---:|---:|---:|---:|")


# ------------------------------------------------------------------------------------ convention check
# Volume of the convention check: 60 x 50 x 40 voxels of 2 x 2.5 x 3 mm (anisotropic, off the origin), a bright
# cube left-anterior-superior and a small denser block right-posterior-inferior: no symmetry to hide a flip.
PH_SIZE = (60, 50, 40)
PH_SPACING = (2.0, 2.5, 3.0)
PH_ORIGIN = (-50.0, 20.0, 100.0)


def cmd_phantoms(out):
    nx, ny, nz = PH_SIZE
    a = np.zeros((nz, ny, nx), np.float32)
    a[25:35, 5:15, 40:55] = 0.02
    a[5:10, 35:45, 5:12] = 0.04
    write_mha(os.path.join(out, "phantom.mha"), a, PH_SPACING, PH_ORIGIN)
    write_mha(os.path.join(out, "cube.mha"), np.full((nz, ny, nx), 0.02, np.float32), PH_SPACING, PH_ORIGIN)
    slab = np.zeros((nz, ny, nx), np.float32)
    slab[:, :, 0] = 0.02  # only the layer farthest from a source on +x (gantry 0): the exit voxel of every ray
    write_mha(os.path.join(out, "slab0.mha"), slab, PH_SPACING, PH_ORIGIN)
    # HU conversion of plastimatch's default (-P preprocess): uniform 20^3 volumes at a few HU, and mu = 1.
    for hu in (-1000, -801, -800, -799, -500, 0, 1000, 2000):
        write_mha(os.path.join(out, "hu_%d.mha" % hu), np.full((20, 20, 20), hu, np.int16), (2, 2, 2), (-19,) * 3)
    write_mha(os.path.join(out, "one.mha"), np.full((20, 20, 20), 1.0, np.float32), (2, 2, 2), (-19,) * 3)
    c = volume_centre({"DimSize": "%d %d %d" % PH_SIZE, "ElementSpacing": "%r %r %r" % PH_SPACING,
                       "Offset": "%r %r %r" % PH_ORIGIN})
    print("%r %r %r" % tuple(c))


def cmd_conventions(out):
    p = lambda f: os.path.join(out, f)
    pb = read_mha(p("pb_g30.mha"))[0].astype(float)          # pbdrr --gantry 30, --size 80 60 (cols rows)
    cands = {}
    for unit in ("deg", "rad"):
        for order in ("colrow", "rowcol"):
            a = read_pfm(p("pl_%s_%s_0000.pfm" % (unit, order))).astype(float)
            if a.shape != pb.shape:
                a = a.T  # only to be able to score it; such a candidate does not match anyway
                if a.shape != pb.shape:
                    continue
            scale = pb.sum() / a.sum() if a.sum() else float("nan")
            err = np.abs(a * scale - pb).max() / pb.max()
            cands[(unit, order)] = (err, scale, a.shape)
    (unit, order), (err, scale, _) = min(cands.items(), key=lambda kv: kv[1][0])
    print("Convention check on a synthetic asymmetric mu volume (60 x 50 x 40 voxels of 2 x 2.5 x 3 mm), "
          "pbdrr `--gantry 30 --size 80 60 --spacing 2 2 --exact siddon --input-units mu`:\n")
    print("| plastimatch `-y` | `-r`/`-z`/`-c` order | max abs diff / max (after scale) |\n|---|---|---:|")
    for (u, o), (e, s, sh) in sorted(cands.items()):
        print("| %s (`-y %s`) | %s | %.1e |" % ({"deg": "degrees", "rad": "radians"}[u],
                                               "30" if u == "deg" else "0.5235988",
                                               {"colrow": "cols rows", "rowcol": "rows cols"}[o], e))
    ok = err < 1e-5
    # the scale: plastimatch's value times `scale` is pbdrr's line integral
    scale_r = round(scale, 3)
    # exit voxel: a full cube of mu = 0.02/mm seen at gantry 0 (source on +x): 60 voxels of 2 mm = 2.4 exactly.
    cube_pb = read_mha(p("pb_cube_g0.mha"))[0].astype(float)
    cube_pl = read_pfm(p("pl_cube_g0_0000.pfm")).astype(float) * scale
    c = tuple(s // 2 for s in cube_pb.shape)
    deficit_mm = (cube_pb[c] - cube_pl[c]) / 0.02
    slab = read_pfm(p("pl_slab0_0000.pfm")).astype(float)[c] * scale  # only the exit layer (x index 0) is 0.02
    slab_pb = read_mha(p("pb_slab0.mha"))[0].astype(float)[c]
    # -P none units and the default HU conversion
    one = read_pfm(p("pl_one_0000.pfm")).astype(float)[5, 5]   # mu = 1 everywhere: path (mm) / 10 - exit voxel
    conv = []
    for hu in (-1000, -801, -800, -799, -500, 0, 1000, 2000):
        conv.append((hu, read_pfm(p("pl_hu_%d_0000.pfm" % hu)).astype(float)[5, 5] / one))
    water = dict(conv)[0]
    print()
    print("| what | found |\n|---|---|")
    print("| `-y` unit | %s (plastimatch %s's `--help` says degrees) |"
          % ({"deg": "degrees", "rad": "**radians**"}[unit], os.environ.get("PLM_VERSION", "?")))
    print("| `-r`, `-z`, `-c` order | %s |" % {"colrow": "**columns first** (`--help` says \"row col\")",
                                              "rowcol": "rows first"}[order])
    print("| image orientation | PFM rows stored top row (+vup edge) first, columns along u: same as pbdrr, "
          "no flip (max abs diff %.1e of max) |" % err)
    print("| scale | pbdrr L = %.4f x plastimatch value (`-P none`, mu in 1/mm): plastimatch gives "
          "sum(value x length in mm) / 10, i.e. `-P none` expects mu in **1/cm** |" % scale)
    print("| exit voxel | full cube of 0.02/mm at gantry 0: plastimatch short by %.3f mm of path = one 2 mm voxel; "
          "a volume whose only non-zero layer is the exit layer (x index 0): plastimatch %.4f, pbdrr %.4f |"
          % (deficit_mm, slab, slab_pb))
    print("| `-P none` vs mu = 1 | centre ray of a 40 mm cube of 1.0: %.4f = (40 - 2 mm exit voxel) / 10 |" % one)
    thr = [h for h, v in conv if v == 0]
    print("| default HU conversion (`-P preprocess`, same as `inline`) | value = %.4f (1 + HU/1000) for HU > %d, "
          "0 at or below (HU -799: %.5f); i.e. mu_water 0.022/mm, everything at or below -800 HU is air; pbdrr: "
          "0.02059 (1 + HU/1000), HU >= -1000 (`--mu-water 0.022 --air-threshold -799.5` mimics plastimatch) |"
          % (water, max(thr), dict(conv)[-799]))
    with open(p("conventions.env"), "w") as f:
        f.write("PLM_Y_UNIT=%s\nPLM_ORDER=%s\nPLM_SCALE=%r\nPLM_OK=%d\n" % (unit, order, scale_r, ok))
    if not ok:
        print("\nNo plastimatch flag combination reproduces pbdrr on the phantom (best %.2e): see the table." % err)


# ----------------------------------------------------------------------------------------------- prepare
def cmd_prepare(ct, out):
    a, hdr = read_mha(ct)
    mu = (MU_WATER * np.maximum(0.0, 1.0 + a.astype(np.float64) / 1000.0)).astype(np.float32)
    sp = [float(x) for x in hdr["ElementSpacing"].split()]
    org = [float(x) for x in hdr["Offset"].split()]
    d = [float(x) for x in hdr.get("TransformMatrix", "1 0 0 0 1 0 0 0 1").split()]
    write_mha(os.path.join(out, "mu.mha"), mu, sp, org, d)
    pad = np.zeros([n + 2 for n in mu.shape], np.float32)
    pad[1:-1, 1:-1, 1:-1] = mu
    dm = np.array(d).reshape(3, 3).T
    write_mha(os.path.join(out, "mu_pad.mha"), pad, sp, np.array(org) - dm @ np.array(sp), d)
    c = volume_centre(read_mha(os.path.join(out, "mu.mha"))[1])
    sys.stderr.write("prepare: HU %g .. %g, mu %g .. %g /mm, %s voxels\n"
                     % (a.min(), a.max(), mu.min(), mu.max(), hdr["DimSize"]))
    print("%r %r %r" % tuple(c))


# ----------------------------------------------------------------------------------------------- compare
def cmd_compare(out, png):
    p = lambda f: os.path.join(out, f)
    scale = float(dict(l.strip().split("=") for l in open(p("conventions.env")))["PLM_SCALE"])
    samples = os.environ.get("SAMPLES", "1e8")
    s1 = read_mha(p("pb_siddon1.mha"))[0].astype(float)
    s8 = read_mha(p("pb_siddon8.mha"))[0].astype(float)
    pts = read_mha(p("pb_points.mha"))[0].astype(float)
    pe = read_pfm(p("pl_exact_0000.pfm")).astype(float) * scale
    pu = read_pfm(p("pl_uniform_0000.pfm")).astype(float) * scale
    pp = read_pfm(p("pl_exact_pad_0000.pfm")).astype(float) * scale
    pb_hu = read_mha(p("pb_hu_default.mha"))[0].astype(float)
    pb_hu_plm = read_mha(p("pb_hu_plmconv.mha"))[0].astype(float)
    pl_hu = read_pfm(p("pl_hu_default_0000.pfm")).astype(float) * scale

    print("Against `plastimatch drr -i exact` (its value x %g), same mu volume, same geometry:\n" % scale)
    print(HEAD)
    print(row("pbdrr `--exact siddon` (1 ray/pixel)", stats(s1, pe)))
    print(row("pbdrr `--exact siddon --ss 8` (pixel average)", stats(s8, pe)))
    print(row("pbdrr points, %s samples" % samples, stats(pts, pe)))
    print(row("plastimatch `-i uniform`", stats(pu, pe)))
    print()
    print("Exit voxel: plastimatch `-i exact` on the volume padded with one layer of zero voxels, "
          "against pbdrr `--exact siddon` on the unpadded volume:\n")
    print(HEAD)
    print(row("plastimatch `-i exact`, unpadded", stats(pe, s1)))
    print(row("plastimatch `-i exact`, padded", stats(pp, s1)))
    print()
    print("Against the exact pixel-averaged reference (pbdrr `--exact siddon --ss 8`, 64 rays per pixel; "
          "what a pbdrr pixel estimates):\n")
    print(HEAD)
    e_plm = stats(pe, s8)
    e_pts = stats(pts, s8)
    print(row("plastimatch `-i exact`", e_plm))
    print(row("plastimatch `-i uniform`", stats(pu, s8)))
    print(row("pbdrr `--exact siddon` (1 ray/pixel)", stats(s1, s8)))
    print(row("pbdrr points, %s samples" % samples, e_pts))
    print()
    print("HU input, each tool's own conversion (plastimatch reads the converted ct.mha, pbdrr the DICOM series):\n")
    print(HEAD)
    print(row("pbdrr DICOM default (0.02059, HU>=-1000) vs plastimatch default", stats(pb_hu, pl_hu)))
    print(row("pbdrr `--mu-water 0.022 --air-threshold -799.5` vs plastimatch default", stats(pb_hu_plm, pl_hu)))
    print(row("pbdrr DICOM default vs pbdrr on mu.mha (`--input-units mu`)", stats(pb_hu, s1)))
    print()
    # point sampling is unbiased: its NRMSE against the reference falls as 1/sqrt(N)
    n = float(samples)
    nmatch = n * (e_pts["nrmse"] / e_plm["nrmse"]) ** 2
    mant = 10 ** (math.floor(math.log10(nmatch)) - 1)
    nmatch = int(math.ceil(nmatch / mant) * mant)
    print("NRMSE of %s points against the reference: %.3e; plastimatch `-i exact`: %.3e; at 1/sqrt(N) the points "
          "match plastimatch at N = %.3g." % (samples, e_pts["nrmse"], e_plm["nrmse"], nmatch))
    with open(p("nmatch.txt"), "w") as f:
        f.write("%d\n" % nmatch)
    if png:
        picture(png, pe, s1, pts, s8, samples)


def picture(png, pe, s1, pts, s8, samples):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    lo, hi = np.percentile(pe, [0.5, 99.8])
    fig, ax = plt.subplots(2, 3, figsize=(11.2, 7.9))
    gray = dict(cmap="gray", vmin=lo, vmax=hi, interpolation="nearest")

    def diff(a, d, title):
        m = max(np.abs(d).max(), 1e-12)
        im = a.imshow(d, cmap="RdBu_r", vmin=-m, vmax=m, interpolation="nearest")
        a.set_title(title, fontsize=9)
        fig.colorbar(im, ax=a, fraction=0.046, pad=0.02).ax.tick_params(labelsize=7)

    ax[0, 0].imshow(pe, **gray)
    ax[0, 0].set_title("plastimatch drr -i exact (x10)", fontsize=9)
    ax[0, 1].imshow(s1, **gray)
    ax[0, 1].set_title("pbdrr --exact siddon (1 ray/pixel)", fontsize=9)
    s = stats(s1, pe)
    diff(ax[0, 2], s1 - pe, "pbdrr siddon - plastimatch: r=%.7f, NRMSE %.1e\n"
         "(plastimatch drops the exit voxel)" % (s["r"], s["nrmse"]))
    ax[1, 0].imshow(pts, **gray)
    ax[1, 0].set_title("pbdrr points, %s samples" % samples, fontsize=9)
    s = stats(pts, pe)
    diff(ax[1, 1], pts - pe, "pbdrr points - plastimatch: r=%.5f, NRMSE %.1e" % (s["r"], s["nrmse"]))
    s = stats(pts, s8)
    diff(ax[1, 2], pts - s8, "pbdrr points - exact pixel average (Siddon 8x8):\n"
         "Monte Carlo noise, NRMSE %.1e" % s["nrmse"])
    for a in ax.ravel():
        a.set_xticks([])
        a.set_yticks([])
    fig.suptitle("LIDC-IDRI-0314 chest, AP (gantry 90), 256 x 256 at 2.4 mm, SAD 1000, SID 1500: "
                 "line integrals of mu (1/mm), same mu volume", fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    import io
    buf = io.BytesIO()
    fig.savefig(buf, dpi=72)
    try:  # 256-colour palette: a third of the bytes, no visible change
        from PIL import Image
        Image.open(buf).convert("RGB").quantize(colors=256).save(png, optimize=True)
    except ImportError:
        open(png, "wb").write(buf.getvalue())
    print("Picture: %s (%d KB)" % (png, os.path.getsize(png) // 1024))


# ------------------------------------------------------------------------------------------------ timing
def cmd_timing(out):
    """times.tsv: label, run, wall s, load s, preprocess s, render s (empty: not reported), image, command."""
    runs = {}
    info = {}
    num = lambda x: float(x) if x else float("nan")
    for l in open(os.path.join(out, "times.tsv")):
        f = l.rstrip("\n").split("\t")
        runs.setdefault(f[0], []).append([num(x) for x in f[2:6]])
        info[f[0]] = (f[6], f[7])
    s8 = read_mha(os.path.join(out, "pb_siddon8.mha"))[0].astype(float)
    scale = float(dict(l.strip().split("=") for l in open(os.path.join(out, "conventions.env")))["PLM_SCALE"])
    print("| program | runs | wall s, median | wall s, min .. max | load s | preprocess s | render s "
          "| NRMSE vs Siddon 8x8 |\n|---|---:|---:|---:|---:|---:|---:|---:|")
    med = lambda v: ("%.2f" % np.median(v)) if np.all(np.isfinite(v)) else "-"
    for label, r in runs.items():
        r = np.array(r)
        img = os.path.join(out, info[label][0])
        if img.endswith(".mha"):
            e = "%.2e" % stats(read_mha(img)[0], s8)["nrmse"]
        else:
            e = "%.2e" % stats(read_pfm(img).astype(float) * scale, s8)["nrmse"]
        print("| %s | %d | **%.2f** | %.2f .. %.2f | %s | %s | %s | %s |"
              % (label, len(r), np.median(r[:, 0]), r[:, 0].min(), r[:, 0].max(), med(r[:, 1]), med(r[:, 2]),
                 med(r[:, 3]), e))
    print()
    for label, (img, c) in info.items():
        print("- %s: `%s`" % (label, c))


def main(argv):
    if len(argv) < 3:
        raise SystemExit(__doc__)
    cmd = argv[1]
    if cmd == "phantoms":
        cmd_phantoms(argv[2])
    elif cmd == "conventions":
        cmd_conventions(argv[2])
    elif cmd == "prepare":
        cmd_prepare(argv[2], argv[3])
    elif cmd == "compare":
        cmd_compare(argv[2], argv[3] if len(argv) > 3 else "")
    elif cmd == "timing":
        cmd_timing(argv[2])
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    main(sys.argv)
