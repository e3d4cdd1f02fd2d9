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
    "ct_dir/": ("copy", "dicom_good"),  # a DICOM series folder
    "CT": ("copy", "dicom_good"),  # a CT of no format named: a DICOM series folder needs no extension
    "CT.mha": ("copy", "phantom.mha"),
    "ct.mha": ("copy", "phantom.mha"),
    "chest_x4.mha": ("copy", "phantom.mha"),  # the streaming examples: 12 slices, one slab of 32
    "out/demo/head.mha": ("copy", "phantom.mha"),  # scripts/demo.sh's head CT
    "ct.nii.gz": ("made", "phantom.mha"),  # NIfTI-1, gzipped
    "seg.nii.gz": ("made", "labels.mha"),  # the phantom's labels as NIfTI
    "mu.mha": ("made", "phantom.mha"),  # float attenuation per mm
    "view.txt": ("copy", "geometry_32.txt"),  # a geometry file (a 32 x 32 detector)
    "P.txt": ("copy", "matrix_view.P.txt"),  # a 3 x 4 projection matrix
    "S1000/I10": ("copy", "localizer_lateral.dcm"),  # a DICOM localizer without an extension, as scanners write them
    "ap.mha": ("made", None),  # X-rays of the series for pbdrr register: exact DRRs, and their views
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


def write_nifti(mha, path):
    """The MetaImage mha as a gzipped NIfTI-1 file: the same voxels, and its LPS grid as NIfTI's RAS sform/qform."""
    header, pixels = read_mha(mha)
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
        elif name.endswith(".nii.gz"):
            write_nifti(os.path.join(data, source), path)
        elif name == "mu.mha":
            write_mu(os.path.join(data, source), path)
    series = os.path.join(data, "dicom_good")
    # The X-rays: exact DRRs of the series (what pbdrr register is to find the pose of), their views in .txt.
    for view, gantry in (("ap", "90"), ("lat", "0")):
        pbdrr(executable, series, "-o", f"{view}.mha", "--exact", "siddon", "--gantry", gantry, "--size", "48", "48",
              "--spacing", "1", "1", cwd=stage)
        os.replace(os.path.join(stage, f"{view}.geometry.txt"), os.path.join(stage, f"{view}.txt"))
    with open(os.path.join(stage, "poses.csv"), "w") as f:
        f.write("gantry,tx,ty,tz,rx,ry,rz\n90,0,0,0,0,0,0\n90,2,-1,0,0,0,5\n0,0,0,1.5,3,0,0\n")
    pbdrr(executable, os.path.join(data, "phantom.mha"), "--angles", "4", "--angle-step", "90", "--size", "16", "16",
          "--samples", "1e4", "-o", "rtk/v_%d.mha", "--write-rtk-geometry", "geometry.xml", cwd=stage)
    shutil.rmtree(os.path.join(stage, "rtk"))
    with open(os.path.join(stage, "volumes.csv"), "w") as f:
        f.write("volume,output,angles\n"
                f"{os.path.join(data, 'phantom.mha')},phantom/v_%d.mha,4\n"
                f"{os.path.join(data, 'register_phantom.mha')},register/v_%d.mha,4\n")
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
