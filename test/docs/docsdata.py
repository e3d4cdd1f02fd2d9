"""The small data that stands in for the reader's in the documented commands (RunDocumentedCommands.py), and the pbdrr
wrapper that checks a run's output files.

PLACEHOLDERS maps each name the docs' commands use for the reader's data to what is put there: the CLI tests' data
(made by test/cli/MakeTestVolumes.cxx into build/test/cli/data: a 16 x 16 x 12 int16 phantom, its labels, an 8-slice
int16 DICOM series, a lateral DICOM localizer, geometry files), converted where the docs name another format (NIfTI,
attenuation in mu), or written here (a views CSV, a manifest, an RTK geometry and X-rays, both by pbdrr itself).
"""
import glob
import gzip
import os
import re
import shutil
import struct
import subprocess

# name in the docs -> (how it is made, its source): "copy" a file or folder of the CLI data, or "made" here.
PLACEHOLDERS = {
    # A DICOM series folder: the registration phantom (48 x 40 x 32 mm, large enough for pbdrr register's default
    # smoothing of 5 mm) written here as a CT series, a file per slice.
    "ct_dir/": ("made", "register_phantom.mha"),
    "CT": ("made", "register_phantom.mha"),  # a CT of no format named: a DICOM series folder needs no extension
    "CT.mha": ("copy", "phantom.mha"),
    "ct.mha": ("copy", "phantom.mha"),
    "chest_x4.mha": ("copy", "phantom.mha"),  # the streaming examples: 12 slices, one slab of 32
    "chest1.mha": ("copy", "phantom.mha"),  # the preprocessing's chest (scripts/make_large_ct.py --factor 1)
    "out/demo/head.mha": ("copy", "phantom.mha"),  # scripts/demo.sh's head CT
    "ct.nii.gz": ("made", "phantom.mha"),  # NIfTI-1, gzipped
    "seg.nii.gz": ("made", "labels.mha"),  # the phantom's labels 0, 1, 2 as NIfTI, 2 as 3 (bone, as --keep-labels 3)
    "mu.mha": ("made", "phantom.mha"),  # float attenuation per mm
    "view.txt": ("copy", "geometry_32.txt"),  # a geometry file (a 32 x 32 detector)
    "P.txt": ("made", None),  # a C-arm's 3 x 4 matrix: 1024 x 768 pixels of 0.3 mm (numpy.savetxt's format)
    "S1000/I10": ("copy", "localizer_lateral.dcm"),  # a DICOM localizer without an extension, as scanners write them
    "ap.mha": ("made", None),  # X-rays of ct_dir/ for pbdrr register: exact DRRs, and their views
    "ap.txt": ("made", None),
    "lat.mha": ("made", None),
    "lat.txt": ("made", None),
    "poses.csv": ("made", None),  # --views: three views, each with a pose
    "geometry.xml": ("made", None),  # --rtk-geometry: four views, written by pbdrr --write-rtk-geometry
    "volumes.csv": ("made", None),  # --manifest: two volumes of four views each
}


def link(target, name):
    os.makedirs(os.path.dirname(name), exist_ok=True)
    if not os.path.lexists(name):
        os.symlink(target, name)


def read_mha(path):
    """(header dict, pixel bytes) of an uncompressed MetaImage with its data LOCAL (what MakeTestVolumes writes)."""
    with open(path, "rb") as f:
        data = f.read()
    header, position = {}, 0
    while True:
        end = data.index(b"\n", position)
        key, _, value = data[position:end].decode().partition("=")
        header[key.strip()] = value.strip()
        position = end + 1
        if key.strip() == "ElementDataFile":
            break
    if header.get("ElementDataFile") != "LOCAL" or header.get("CompressedData", "False") != "False":
        raise RuntimeError(f"{path}: only uncompressed MetaImages with LOCAL data are read here")
    return header, data[position:]


NIFTI_TYPES = {"MET_UCHAR": (2, 8), "MET_SHORT": (4, 16), "MET_INT": (8, 32), "MET_FLOAT": (16, 32),
               "MET_CHAR": (256, 8), "MET_USHORT": (512, 16), "MET_UINT": (768, 32)}


def write_nifti(mha, path, relabel=None):
    """The MetaImage mha as a gzipped NIfTI-1 file: the same voxels (bytes relabelled by the dict relabel), and its
    LPS grid as NIfTI's RAS sform/qform."""
    header, pixels = read_mha(mha)
    if relabel:
        pixels = bytes(relabel.get(v, v) for v in pixels)
    if [float(v) for v in header.get("TransformMatrix", "1 0 0 0 1 0 0 0 1").split()] != [1, 0, 0, 0, 1, 0, 0, 0, 1]:
        raise RuntimeError(f"{mha}: only an identity direction is converted here")
    size = [int(v) for v in header["DimSize"].split()]
    spacing = [float(v) for v in header["ElementSpacing"].split()]
    origin = [float(v) for v in header["Offset"].split()]
    code, bits = NIFTI_TYPES[header["ElementType"]]
    # LPS to RAS: x and y change sign; the qform is the rotation by 180 degrees about z (quaternion b, c, d = 0, 0, 1).
    ras = [-origin[0], -origin[1], origin[2]]
    h = struct.pack("<i10s18sihcb8h3fhhhh8ffffhcbffffii80s24shh6f4f4f4f16s4s", 348, b"", b"", 0, 0, b"r", 0,
                    3, *size, 1, 1, 1, 1, 0.0, 0.0, 0.0, 0, code, bits, 0, 1.0, *spacing, 1.0, 1.0, 1.0, 1.0, 352.0,
                    1.0, 0.0, 0, b"\0", 2, 0.0, 0.0, 0.0, 0.0, 0, 0, b"docsdata.py", b"", 1, 1, 0.0, 0.0, 1.0, *ras,
                    -spacing[0], 0.0, 0.0, ras[0], 0.0, -spacing[1], 0.0, ras[1], 0.0, 0.0, spacing[2], ras[2],
                    b"", b"n+1\0")
    assert len(h) == 348, len(h)
    with gzip.open(path, "wb") as f:
        f.write(h + b"\0\0\0\0" + pixels)


def write_mu(mha, path):
    """The HU phantom as attenuation per mm (water 0.02 /mm, air 0): the input of `pbdrr --input-units mu`."""
    header, pixels = read_mha(mha)
    if header["ElementType"] != "MET_SHORT":
        raise RuntimeError(f"{mha}: an int16 volume expected")
    hu = struct.unpack(f"<{len(pixels) // 2}h", pixels)
    mu = struct.pack(f"<{len(hu)}f", *(max(0.0, 0.02 * (1.0 + v / 1000.0)) for v in hu))
    text = "".join(f"{k} = {v}\n" for k, v in header.items() if k not in ("ElementType", "ElementDataFile"))
    with open(path, "wb") as f:
        f.write((text + "ElementType = MET_FLOAT\nElementDataFile = LOCAL\n").encode() + mu)


def element(group, number, vr, value):
    """One data element in explicit VR little endian, its value padded to an even length."""
    if isinstance(value, str):
        value = value.encode() + (b"\0" if vr == "UI" else b" ") * (len(value) % 2)
    if vr in ("OB", "OW", "UN", "SQ", "UT"):
        return struct.pack("<HH2sHI", group, number, vr.encode(), 0, len(value)) + value
    return struct.pack("<HH2sH", group, number, vr.encode(), len(value)) + value


def write_dicom_series(mha, folder, series_uid):
    """The int16 MetaImage mha as a CT DICOM series, a file per slice (what a scanner's export folder holds)."""
    header, pixels = read_mha(mha)
    if header["ElementType"] != "MET_SHORT":
        raise RuntimeError(f"{mha}: an int16 volume expected")
    columns, rows, slices = (int(v) for v in header["DimSize"].split())
    spacing = [float(v) for v in header["ElementSpacing"].split()]
    origin = [float(v) for v in header["Offset"].split()]
    os.makedirs(folder)
    ct_storage, explicit_little = "1.2.840.10008.5.1.4.1.1.2", "1.2.840.10008.1.2.1"
    plane = columns * rows * 2
    for k in range(slices):
        instance = f"{series_uid}.{k + 1}"
        meta = (element(2, 1, "OB", b"\0\1") + element(2, 2, "UI", ct_storage) + element(2, 3, "UI", instance)
                + element(2, 0x10, "UI", explicit_little))
        data = b"".join([
            element(8, 0x16, "UI", ct_storage), element(8, 0x18, "UI", instance), element(8, 0x60, "CS", "CT"),
            element(0x18, 0x50, "DS", f"{spacing[2]:g}"), element(0x20, 0xD, "UI", series_uid + ".0"),
            element(0x20, 0xE, "UI", series_uid), element(0x20, 0x13, "IS", str(k + 1)),
            element(0x20, 0x32, "DS", "\\".join(f"{v:g}" for v in (origin[0], origin[1], origin[2] + k * spacing[2]))),
            element(0x20, 0x37, "DS", "1\\0\\0\\0\\1\\0"), element(0x28, 2, "US", struct.pack("<H", 1)),
            element(0x28, 4, "CS", "MONOCHROME2"), element(0x28, 0x10, "US", struct.pack("<H", rows)),
            element(0x28, 0x11, "US", struct.pack("<H", columns)),
            element(0x28, 0x30, "DS", f"{spacing[1]:g}\\{spacing[0]:g}"),
            element(0x28, 0x100, "US", struct.pack("<H", 16)), element(0x28, 0x101, "US", struct.pack("<H", 16)),
            element(0x28, 0x102, "US", struct.pack("<H", 15)), element(0x28, 0x103, "US", struct.pack("<H", 1)),
            element(0x28, 0x1052, "DS", "0"), element(0x28, 0x1053, "DS", "1"),
            element(0x7FE0, 0x10, "OW", pixels[k * plane:(k + 1) * plane])])
        with open(os.path.join(folder, f"IM{k + 1:04d}"), "wb") as f:
            f.write(b"\0" * 128 + b"DICM" + element(2, 0, "UL", struct.pack("<I", len(meta))) + meta + data)


def pbdrr(executable, *arguments, cwd):
    subprocess.run([executable, *arguments, "-q"], cwd=cwd, check=True, stdout=subprocess.DEVNULL)


def make_stage(stage, data, executable):
    """Makes every placeholder under the folder stage; returns their names."""
    os.makedirs(stage)
    for name, (how, source) in PLACEHOLDERS.items():
        path = os.path.join(stage, name.rstrip("/"))
        os.makedirs(os.path.dirname(path), exist_ok=True)
        if how == "copy":
            (shutil.copytree if os.path.isdir(os.path.join(data, source)) else shutil.copy)(
                os.path.join(data, source), path)
        elif name == "seg.nii.gz":
            write_nifti(os.path.join(data, source), path, relabel={2: 3})
        elif name.endswith(".nii.gz"):
            write_nifti(os.path.join(data, source), path)
        elif name in ("ct_dir/", "CT"):
            write_dicom_series(os.path.join(data, source), path, "2.25.4000000001")
        elif name == "mu.mha":
            write_mu(os.path.join(data, source), path)
    # The X-rays: exact DRRs of the series (what pbdrr register is to find the pose of), their views in .txt.
    for view, gantry in (("ap", "90"), ("lat", "0")):
        pbdrr(executable, "ct_dir/", "-o", f"{view}.mha", "--exact", "siddon", "--gantry", gantry, "--size", "64", "64",
              "--spacing", "2", "2", cwd=stage)
        os.replace(os.path.join(stage, f"{view}.geometry.txt"), os.path.join(stage, f"{view}.txt"))
    # P.txt: the matrix pbdrr writes (commented) in the .geometry.txt of a 1024 x 768 view of 0.3 mm pixels.
    pbdrr(executable, "ct.mha", "-o", "c_arm.mha", "--size", "1024", "768", "--spacing", "0.3", "0.3",
          "--samples", "1e3", cwd=stage)
    with open(os.path.join(stage, "c_arm.geometry.txt")) as f:
        lines = f.read().split("\n")
    first = lines.index("# 3 x 4 projection matrix: room point X (mm) -> pixel (column, row) = (p0 / p2, p1 / p2), "
                        "p = P [X; 1]") + 1
    with open(os.path.join(stage, "P.txt"), "w") as f:
        f.write("".join(line.lstrip("# ") + "\n" for line in lines[first:first + 3]))
    for name in ("c_arm.mha", "c_arm.geometry.txt"):
        os.remove(os.path.join(stage, name))
    with open(os.path.join(stage, "poses.csv"), "w") as f:
        f.write("gantry,tx,ty,tz,rx,ry,rz\n90,0,0,0,0,0,0\n90,2,-1,0,0,0,5\n0,0,0,1.5,3,0,0\n")
    os.makedirs(os.path.join(stage, "rtk"))  # pbdrr writes into a folder, and does not make it
    pbdrr(executable, os.path.join(data, "phantom.mha"), "--angles", "4", "--angle-step", "90", "--size", "16", "16",
          "--samples", "1e4", "-o", "rtk/v_%d.mha", "--write-rtk-geometry", "geometry.xml", cwd=stage)
    shutil.rmtree(os.path.join(stage, "rtk"))
    with open(os.path.join(stage, "volumes.csv"), "w") as f:
        f.write("volume,output,angles\n"
                f"{os.path.join(data, 'phantom.mha')},phantom_v_%d.mha,4\n"
                f"{os.path.join(data, 'register_phantom.mha')},register_v_%d.mha,4\n")
    return list(PLACEHOLDERS)


def put(stage, name, folder):
    """Puts a fresh copy of the placeholder name into folder (replacing what a command may have written there)."""
    source, target = os.path.join(stage, name.rstrip("/")), os.path.join(folder, name.rstrip("/"))
    if os.path.isdir(target) and not os.path.islink(target):
        shutil.rmtree(target)
    os.makedirs(os.path.dirname(target), exist_ok=True)
    (shutil.copytree if os.path.isdir(source) else shutil.copy)(source, target)


# pbdrr's options that name a file it writes.
OUTPUT_OPTIONS = ("-o", "--output", "--stderr", "--label-channels", "--write-rtk-geometry")


def written(path):
    """Whether the output path is there: a printf counter matches any number, and X.png also names X.1.png, ..."""
    pattern = re.sub(r"%0?\d*d", "[0-9]*", glob.escape(path))
    if glob.glob(pattern):
        return True
    stem, extension = os.path.splitext(pattern)
    return bool(glob.glob(f"{stem}.*{extension}"))


def run_pbdrr(executable, arguments):
    """Runs the built pbdrr with arguments; after a success, checks that each output file it names is there."""
    result = subprocess.run([executable, *arguments])
    if result.returncode != 0:
        if result.returncode < 0:
            print(f"pbdrr {' '.join(arguments)}: killed by signal {-result.returncode}", flush=True)
            return 128 - result.returncode
        return result.returncode
    outputs = [arguments[i + 1] for i, a in enumerate(arguments[:-1]) if a in OUTPUT_OPTIONS]
    if "--manifest" in arguments:  # the manifest's outputs: the column output of its rows
        with open(arguments[arguments.index("--manifest") + 1]) as f:
            rows = [line.rstrip("\n").split(",") for line in f if line.strip()]
        column = rows[0].index("output")
        outputs += [row[column] for row in rows[1:]]
    missing = [o for o in outputs if not written(o)]
    if "--manifest" in arguments and len(missing) < len(outputs):
        missing = []  # a shard of a manifest writes some of its volumes' views, not every volume's
    if missing:
        print(f"pbdrr {' '.join(arguments)}: exit 0, but it did not write {', '.join(missing)}", flush=True)
        return 97
    return 0


def run_plastimatch(executable, arguments):
    """Runs plastimatch; after a success, checks that `plastimatch drr -O PREFIX` wrote PREFIX*: plastimatch exits 0
    on an input it cannot read, having written nothing."""
    result = subprocess.run([executable, *arguments])
    if result.returncode != 0 or "-O" not in arguments[:-1]:
        return result.returncode if result.returncode >= 0 else 128 - result.returncode
    prefix = arguments[arguments.index("-O") + 1]
    if not glob.glob(glob.escape(prefix) + "*"):
        print(f"plastimatch {' '.join(arguments)}: exit 0, but it wrote no {prefix}* file", flush=True)
        return 97
    return 0
