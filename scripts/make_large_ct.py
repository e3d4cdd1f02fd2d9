#!/usr/bin/python3
"""A larger CT from a real one: the volume upsampled K times per axis, with noise (issue 27, "Scale with the CT").

    /usr/bin/python3 scripts/make_large_ct.py INPUT OUTPUT.mha [--factor K] [--noise HU] [--seed S] [--mu]

INPUT is a DICOM series directory (converted first with `plastimatch convert`) or a MetaImage. OUTPUT.mha is a
MetaImage header with its voxels in OUTPUT.raw: int16 HU, or with --mu float32 mu = 0.02059 max(0, 1 + HU/1000)
in 1/mm (pbdrr's default conversion, for `plastimatch drr -P none`). Data like this is never committed.

Why: a chest of 512 x 512 x 275 voxels is small beside what scanners now make (0.25 mm, photon-counting), and
pbdrr's preprocessing and memory grow with the voxels. The same chest at K = 2 (1024 x 1024 x 550, 577 M voxels,
1.2 GB) or K = 4 (2048 x 2048 x 1100, 4.6 G voxels, 9.2 GB) shows how the tools scale on the same anatomy and the
same view. The new voxels come from trilinear interpolation plus independent Gaussian noise of --noise HU
(default 20) per voxel, with a fixed seed: a finer scan is a noisier one, and nearest-neighbour copies would make
every K^3 block constant, so a control variate built on a coarser level would be exact there and have no residual
left to sample, which no real scan gives.

Geometry: the same box. Spacing / K; voxel centres at (j + 0.5) / K - 0.5 in the input's index units, so
origin_new = origin_old + D (spacing_new - spacing_old) / 2; the outer half-voxel repeats the edge voxel.
It works a few output slices at a time (the input is memory-mapped, the output appended slab by slab), so even
K = 4 needs well under 3 GB of memory. Each output slice draws its noise from its own seed (seed, slice), so the
volume does not depend on the slab size.
"""
import argparse
import os
import subprocess
import tempfile

import numpy as np

MU_WATER = 0.02059  # 1/mm at 60 keV: pbdrr's default
TYPES = {"MET_FLOAT": "f4", "MET_DOUBLE": "f8", "MET_SHORT": "i2", "MET_USHORT": "u2", "MET_INT": "i4",
         "MET_UCHAR": "u1", "MET_CHAR": "i1"}


def open_mha(path):
    """(memory-mapped voxels [z, y, x], header dict) of an uncompressed MetaImage, LOCAL or with a data file."""
    with open(path, "rb") as f:
        hdr, offset = {}, 0
        for line in f:
            offset += len(line)
            k, v = line.decode("latin1").split("=", 1)
            hdr[k.strip()] = v.strip()
            if k.strip() == "ElementDataFile":
                break
    if hdr.get("CompressedData", "False") == "True":
        raise SystemExit("%s: compressed MetaImage not supported" % path)
    data = hdr["ElementDataFile"]
    if data != "LOCAL":
        path, offset = os.path.join(os.path.dirname(path), data), 0
    dims = [int(x) for x in hdr["DimSize"].split()]
    msb = hdr.get("BinaryDataByteOrderMSB", hdr.get("ElementByteOrderMSB", "False")) == "True"
    dtype = (">" if msb else "<") + TYPES[hdr["ElementType"]]
    return np.memmap(path, dtype=dtype, mode="r", offset=offset, shape=tuple(dims[::-1])), hdr


def axis_weights(n_old, k):
    """Trilinear weights along one axis: output j lies at (j + 0.5) / k - 0.5 of the input, clamped to the edge."""
    x = np.clip((np.arange(n_old * k) + 0.5) / k - 0.5, 0, n_old - 1)
    i0 = np.floor(x).astype(np.intp)
    return i0, np.minimum(i0 + 1, n_old - 1), (x - i0).astype(np.float32)


def upsample_slice(a, wy, wx):
    """One input slice, bilinear in y then x."""
    (y0, y1, fy), (x0, x1, fx) = wy, wx
    a = a[y0] * (1 - fy)[:, None] + a[y1] * fy[:, None]
    return a[:, x0] * (1 - fx) + a[:, x1] * fx


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("input", help="DICOM series directory or MetaImage (HU)")
    p.add_argument("output", help="OUTPUT.mha (voxels in OUTPUT.raw)")
    p.add_argument("--factor", "-k", type=int, default=2, help="upsampling factor per axis (default 2)")
    p.add_argument("--noise", type=float, default=20.0, help="Gaussian noise per voxel, HU (default 20)")
    p.add_argument("--seed", type=int, default=27, help="noise seed (default 27)")
    p.add_argument("--mu", action="store_true", help="write float32 mu (1/mm) instead of int16 HU")
    p.add_argument("--slab", type=int, default=4, help="output slices per write (default 4)")
    args = p.parse_args()
    k = args.factor

    with tempfile.TemporaryDirectory(dir=os.path.dirname(os.path.abspath(args.output))) as tmp:
        src = args.input
        if os.path.isdir(src):
            src = os.path.join(tmp, "input.mha")
            subprocess.run(["plastimatch", "convert", "--input", args.input, "--output-img", src], check=True,
                           stdout=subprocess.DEVNULL)
        a, hdr = open_mha(src)
        nz, ny, nx = a.shape
        sp = np.array([float(x) for x in hdr["ElementSpacing"].split()])
        org = np.array([float(x) for x in hdr["Offset"].split()])
        tm = hdr.get("TransformMatrix", "1 0 0 0 1 0 0 0 1")
        d = np.array([float(x) for x in tm.split()]).reshape(3, 3).T  # MetaImage stores the direction by columns
        new_sp = sp / k
        new_org = org + d @ ((new_sp - sp) / 2)

        base = os.path.splitext(args.output)[0]
        raw = base + ".raw"
        with open(args.output, "w") as f:
            f.write("ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n"
                    "CompressedData = False\nTransformMatrix = %s\nOffset = %s\nCenterOfRotation = 0 0 0\n"
                    "AnatomicalOrientation = RAI\nElementSpacing = %s\nDimSize = %d %d %d\nElementType = %s\n"
                    "ElementDataFile = %s\n"
                    % (tm, " ".join(repr(float(o)) for o in new_org), " ".join(repr(float(s)) for s in new_sp),
                       nx * k, ny * k, nz * k, "MET_FLOAT" if args.mu else "MET_SHORT", os.path.basename(raw)))

        wz, wy, wx = axis_weights(nz, k), axis_weights(ny, k), axis_weights(nx, k)
        cache = {}  # upsampled input slices still needed
        with open(raw, "wb") as out:
            for z0 in range(0, nz * k, args.slab):
                zs = range(z0, min(z0 + args.slab, nz * k))
                for i in set(wz[0][zs.start:zs.stop]) | set(wz[1][zs.start:zs.stop]):
                    if i not in cache:
                        cache[i] = upsample_slice(np.asarray(a[i], np.float32), wy, wx)
                slab = np.empty((len(zs), ny * k, nx * k), np.float32)
                for j, z in enumerate(zs):
                    slab[j] = cache[wz[0][z]] * (1 - wz[2][z]) + cache[wz[1][z]] * wz[2][z]
                    if args.noise > 0:
                        rng = np.random.default_rng([args.seed, z])
                        slab[j] += args.noise * rng.standard_normal(slab[j].shape, np.float32)
                hu = np.clip(np.rint(slab), -32768, 32767).astype("<i2")
                if args.mu:
                    hu = (MU_WATER * np.maximum(0.0, 1.0 + hu / np.float32(1000))).astype("<f4")
                out.write(hu.tobytes())
                for i in [i for i in cache if i < wz[0][zs.stop - 1]]:
                    del cache[i]
    print("%s: %d x %d x %d voxels of %s mm, origin %s" % (args.output, nx * k, ny * k, nz * k,
                                                          " x ".join("%g" % s for s in new_sp),
                                                          " ".join("%g" % o for o in new_org)))


if __name__ == "__main__":
    main()
