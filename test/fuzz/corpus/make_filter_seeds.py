#!/usr/bin/env python3
"""Writes the seeds of PointBasedDRRFilterFuzzer into corpus/Filter/ (docs/fuzzing.md).

Each seed is a readable case: the decisions PointBasedDRRFilterFuzzer.cxx decodes, in its order, encoded as
FuzzedDataProvider reads them (ConsumeIntegralInRange takes bytes from the end of the data, most significant first).
A decision left out takes its first value (what an exhausted input decodes to). Check what a seed decodes to with
  PBDRR_FUZZ_PRINT=1 PointBasedDRRFilterFuzzer corpus/Filter/<seed>
Run from anywhere: python3 test/fuzz/corpus/make_filter_seeds.py
"""
import math
import os

SPACINGS = [1.0, 0.5, 2.5, 1e-6, 1e-3, 0.1, 10.0, 1e3, 1e6, 1e9, -1.0, 0.7]
ORIGINS = [0.0, -100.0, 100.0, 1e7, -1e9, 0.5]
ANGLES = [0.0, 90.0, 180.0, 270.0, 45.0, -30.0, 360.0, 1e9, 1e20, 0.001]
UNIT = [0.0, 1.0, -1.0, 1e-300, 1e300, 0.5]
SHORT = [0, 1000, -1000, -1024, -3024, 3071, 32767, -32768, -1, 1, 2000, -500]
FLOAT = [0.02, 0.0, math.nan, math.inf, -math.inf, -0.0, 1e-30, 1e30, 3e38, -1.0, 1e3, -1e3, 3071.0, -3024.0,
         1e-45, 0.5]
DISTANCES = [1000.0, 1e-6, 1e-3, 0.5, 10.0, 100.0, 1e4, 1e7, 1e8, 0.0, -100.0, 5.0]
FACTORS = [1.5, 1.0, 2.0, 0.5, 1e-3, 1e3, 0.0, 1e-9]
LENGTHS = [0.0, 1.0, -1.0, 10.0, -50.0, 1e4, 1e7, -1e8]
DETECTOR_SPACINGS = [1.0, 1e-6, 0.01, 0.1, 10.0, 1e3, 1e7, 2e7, 0.0, -1.0]
SAMPLERS = ["level-alias", "paper-hybrid", "metropolis", "stratified", "mcvr"]


class Encoder:
    def __init__(self):
        self.consumed = []  # bytes in the order the fuzzer consumes them

    def choice(self, count, value):
        assert 0 <= value < count, (value, count)
        top = count - 1
        nbytes = 0
        while nbytes < 4 and (top >> (8 * nbytes)) > 0:
            nbytes += 1
        for i in reversed(range(nbytes)):  # most significant byte first
            self.consumed.append((value >> (8 * i)) & 0xFF)

    def flag(self, value):
        self.choice(2, 1 if value else 0)

    def real(self, table, low, high, value):
        """A table entry if the value is in the table, else its 16-bit fraction of [low, high]."""
        for i, t in enumerate(table):
            if t == value or (math.isnan(t) and isinstance(value, float) and math.isnan(value)):
                self.choice(256, i)
                return
        assert low <= value <= high, (value, low, high)
        self.choice(256, 255)
        self.choice(65536, round((value - low) / (high - low) * 65535))

    def short(self, value):
        self.choice(65536, value + 32768)

    def data(self):
        return bytes(reversed(self.consumed))


def voxel(e, is_float, value):
    if is_float:
        e.real(FLOAT, -1100.0, 3100.0, value)
    elif value in SHORT:
        e.choice(256, SHORT.index(value))
    else:
        e.choice(256, 255)
        e.short(value)


def encode(c):
    """c: a dict of decisions; see the defaults below."""
    e = Encoder()
    is_float = c.get("float", False)
    e.flag(is_float)
    size = c.get("size", (4, 4, 4))
    for s in size:
        e.choice(8, s - 1)
    for s in c.get("spacing", (1.0, 1.0, 1.0)):
        e.real(SPACINGS, 0.05, 5.0, s)
    for o in c.get("origin", (0.0, 0.0, 0.0)):
        e.real(ORIGINS, -500.0, 500.0, o)
    direction = c.get("direction", ("identity",))
    kinds = ["identity", "permutation", "rotation", "rotation-flip", "free", "nearly-singular"]
    e.choice(6, kinds.index(direction[0]))
    if direction[0] == "permutation":
        e.choice(48, direction[1])
    elif direction[0] in ("rotation", "rotation-flip"):
        for a in direction[1]:
            e.real(ANGLES, -180.0, 180.0, a)
        e.flag(direction[0] == "rotation-flip")
    elif direction[0] == "free":
        for d in direction[1]:
            e.real(UNIT, -1.0, 1.0, d)
    elif direction[0] == "nearly-singular":
        e.real([1e-9, 1e-15, 1e-300, 0.0], 0.0, 1e-3, direction[1])

    fill = c.get("fill", ("block", -1000, 0, (1, 1, 1), (2, 2, 2)))
    fills = ["constant", "voxels", "block", "checker"]
    e.choice(4, fills.index(fill[0]))
    if fill[0] == "constant":
        voxel(e, is_float, fill[1])
    elif fill[0] == "voxels":
        assert len(fill[1]) == size[0] * size[1] * size[2]
        for v in fill[1]:
            voxel(e, is_float, v)
    elif fill[0] == "block":
        voxel(e, is_float, fill[1])
        voxel(e, is_float, fill[2])
        for a in range(3):
            e.choice(size[a], fill[3][a])
            e.choice(size[a], fill[4][a])
    else:
        voxel(e, is_float, fill[1])
        voxel(e, is_float, fill[2])

    transfer = c.get("transfer", ("natural",))
    transfers = ["natural", "mu-water", "energy", "identity", "piecewise"]
    e.choice(5, transfers.index(transfer[0]))
    if transfer[0] == "mu-water":
        e.real([0.02059, 0.0, -1.0, 1e-9, 10.0, 11.0, 1e-300, math.nan], 1e-4, 1.0, transfer[1])
    elif transfer[0] == "energy":
        e.real([60.0, 10.0, 1000.0, 9.9, 1001.0, 50.0], 10.0, 1000.0, transfer[1])
    elif transfer[0] == "piecewise":
        points = transfer[1]  # (step, mu) pairs: value = -1000 + sum of steps
        e.choice(4, len(points) - 1)
        for step, mu in points:
            e.real([500.0, 0.0, -1.0, 1e-12, 1e6], 0.0, 2000.0, step)
            e.real([0.02, 0.0, 1e-30, 1e30, -0.01, math.nan], 0.0, 0.1, mu)
    threshold = c.get("air_threshold")
    e.flag(threshold is not None)
    if threshold is not None:
        e.real([-999.5, -1000.0, 0.0, 1e30, -1e30, math.nan, math.inf], -2000.0, 4000.0, threshold)

    g = c.get("geometry", {})
    kinds = ["perspective", "parallel", "explicit-perspective", "explicit-parallel"]
    kind = g.get("kind", "perspective")
    e.choice(4, kinds.index(kind))
    if kind in ("perspective", "parallel"):
        iso = g.get("isocenter", ("centre",))
        e.choice(3, ["centre", "shift", "absolute"].index(iso[0]))
        if iso[0] == "shift":
            for s in iso[1]:
                e.real([0.0, 1.0, -1.0, 0.5], -2.0, 2.0, s)
        elif iso[0] == "absolute":
            for s in iso[1]:
                e.real([0.0, 1e7, -1e7, 1e8, math.nan], -1000.0, 1000.0, s)
        gantry = g.get("gantry", 0.0)
        nrm = g.get("nrm")
        normal = 1 if (nrm is not None and "gantry" not in g) else (2 if nrm is not None else 0)
        e.choice(3, normal)
        if normal != 1:
            e.real(ANGLES, -720.0, 720.0, gantry)
        if normal != 0:
            for x in nrm:
                e.real(UNIT, -1.0, 1.0, x)
        vup = g.get("vup")
        e.flag(vup is not None)
        if vup is not None:
            for x in vup:
                e.real(UNIT, -1.0, 1.0, x)
        inside = g.get("source_inside")  # SAD over the volume's radius
        e.flag(inside is not None)
        if inside is not None:
            e.real([0.5, 0.0, 1e-9, 0.99, 1.0, 1.01], 0.0, 2.0, inside)
        else:
            e.real([10.0, 2.0, 1.5, 100.0, 1e4], 1.0, 50.0, g.get("sad_over_radius", 10.0))
            sad = g.get("sad")
            e.flag(sad is not None)
            if sad is not None:
                e.real(DISTANCES, 1.0, 2000.0, sad)
        sid = g.get("sid", ("1.5 sad",))
        e.choice(3, ["1.5 sad", "factor", "absolute"].index(sid[0]))
        if sid[0] == "factor":
            e.real(FACTORS, 0.01, 4.0, sid[1])
        elif sid[0] == "absolute":
            e.real(DISTANCES, 1.0, 3000.0, sid[1])
    else:
        for a in g.get("angles", (0.0, 0.0, 0.0)):
            e.real(ANGLES, -180.0, 180.0, a)
        skew = g.get("skew")
        e.flag(skew is not None)
        if skew is not None:
            e.real([1e-7, 1e-5, 1.0], 0.0, 1e-3, skew)
        e.real([3.0, 0.0, 0.5, 1e-9, 1e4, -3.0], -5.0, 50.0, g.get("distance", 3.0))
        if kind == "explicit-perspective":
            e.real([6.0, 1.0, 1e-6, 0.0], 0.0, 50.0, g.get("sid_over_radius", 6.0))
    cols, rows = g.get("detector", (8, 8))
    e.choice(16, cols - 1)
    e.choice(16, rows - 1)
    spacing = g.get("spacing", ("fit",))
    e.choice(3, ["fit", "each", "both"].index(spacing[0]))
    if spacing[0] == "each":
        e.real(DETECTOR_SPACINGS, 0.05, 50.0, spacing[1])
        e.real(DETECTOR_SPACINGS, 0.05, 50.0, spacing[2])
    elif spacing[0] == "both":
        e.real(DETECTOR_SPACINGS, 0.05, 50.0, spacing[1])
    offset = g.get("offset")
    e.flag(offset is not None)
    if offset is not None:
        for o in offset:
            e.real(LENGTHS, -100.0, 100.0, o)

    s = c.get("settings", {})
    e.choice(5, SAMPLERS.index(s.get("sampler", "level-alias")))
    e.flag(s.get("kernel", "box") == "tent")
    e.flag(s.get("splat", "nearest") == "bilinear")
    e.flag(s.get("weighting", "unbiased") == "paper-count")
    strata = s.get("strata", 0)
    if strata == 0:
        e.choice(4, 0)
    elif strata == 2:
        e.choice(4, 1)
    elif strata == 256:
        e.choice(4, 2)
    else:
        e.choice(4, 3)
        e.choice(255, strata - 2)
    e.choice(65536, s.get("seed", 0))
    samples = s.get("samples", 1000)
    if samples in (1000, 1, 5000):
        e.choice(4, [1000, 1, 5000].index(samples))
    else:
        e.choice(4, 3)
        e.choice(5000, samples - 1)
    e.choice(4, ["line-integral", "transmission", "gray8", "gray16"].index(s.get("output", "line-integral")))
    window = s.get("window")
    e.flag(window is not None)
    if window is not None:
        e.real([1.0, 0.0, -1.0, math.nan, math.inf, 1e300], -5.0, 5.0, window[0])
        e.real([2.0, 0.0, -1.0, math.nan, math.inf, 1e-300], 0.0, 10.0, window[1])
    reuse = s.get("reuse")  # the gantry change of the second pose
    e.flag(reuse is not None)
    e.choice(3, s.get("threads", 1) - 1)
    e.choice(2, s.get("rays", 1) - 1)
    refine = s.get("refine")
    e.flag(refine is not None)
    if refine is not None:
        e.choice(2000, refine - 1)
    if reuse is not None:
        e.real([10.0, 0.0, 180.0, 1e-9], -90.0, 90.0, reuse)
    e.flag(s.get("unsigned_char_output", False))

    t = c.get("transform", ("none",))
    e.choice(3, ["none", "rigid", "affine"].index(t[0]))
    if t[0] == "rigid":
        for a in t[1]:
            e.real(ANGLES, -180.0, 180.0, a)
        for x in t[2]:
            e.real(LENGTHS, -20.0, 20.0, x)
    elif t[0] == "affine":
        for m in t[1]:  # added to the identity
            e.real([0.0, 1.0, -1.0, -2.0, 1e-9, 1e9, -1e-300], -1.0, 1.0, m)
        for x in t[2]:
            e.real(LENGTHS, -20.0, 20.0, x)
    return e.data()


WATER_CUBE = ("block", -1000, 0, (1, 1, 1), (2, 2, 2))
BONE_IN_WATER = ("block", 0, 1000, (0, 1, 1), (3, 2, 2))
SEEDS = {
    "default_water_cube": {},
    "empty": None,
    # Every sampler, box and tent, nearest and bilinear.
    "sampler_paper_hybrid": {"fill": BONE_IN_WATER, "settings": {"sampler": "paper-hybrid"}},
    "sampler_metropolis_strata2": {"fill": BONE_IN_WATER, "settings": {"sampler": "metropolis", "strata": 2}},
    "sampler_stratified_tent_bilinear": {"fill": BONE_IN_WATER,
                                         "settings": {"sampler": "stratified", "kernel": "tent", "splat": "bilinear"}},
    "sampler_mcvr_strata256": {"fill": BONE_IN_WATER, "settings": {"sampler": "mcvr", "strata": 256}},
    "sampler_level_alias_tent_3threads": {"settings": {"kernel": "tent", "threads": 3, "rays": 2, "seed": 77}},
    # Geometries.
    "parallel_gantry90": {"geometry": {"kind": "parallel", "gantry": 90.0}, "settings": {"sampler": "stratified"}},
    "explicit_perspective_oblique": {"geometry": {"kind": "explicit-perspective", "angles": (45.0, -30.0, 90.0)}},
    "explicit_parallel_oblique": {"geometry": {"kind": "explicit-parallel", "angles": (-30.0, 45.0, 0.0)},
                                  "settings": {"splat": "bilinear"}},
    "source_inside_volume": {"size": (5, 5, 5), "fill": ("constant", 0),
                             "geometry": {"source_inside": 0.5, "detector": (16, 16)},
                             "settings": {"sampler": "stratified", "kernel": "tent"}},
    "source_at_volume_centre": {"size": (3, 3, 3), "fill": ("constant", 500),
                                "geometry": {"source_inside": 0.0}, "settings": {"samples": 5000}},
    "oblique_nrm_vup_offset": {"geometry": {"nrm": (1.0, 1.0, 0.5), "vup": (0.0, 1.0, 1.0), "offset": (10.0, -1.0),
                                            "detector": (16, 3)}},
    "tiny_sad_sid": {"geometry": {"sad": 1e-6, "sid": ("absolute", 1e-3), "spacing": ("both", 1e-6)}},
    "huge_sad_sid": {"geometry": {"sad": 1e7, "sid": ("factor", 2.0), "spacing": ("each", 0.1, 10.0)}},
    "far_off_axis_detector": {"geometry": {"offset": (1e4, -50.0), "detector": (16, 16)}},
    "one_pixel_detector": {"geometry": {"detector": (1, 1)}, "settings": {"samples": 1}},
    # Volumes.
    "hu_extremes": {"size": (2, 2, 2), "fill": ("voxels", [-32768, -3024, 3071, 32767, -1024, 0, 1000, 1234])},
    "all_air_is_zero": {"fill": ("constant", -1000), "settings": {"sampler": "stratified"}},
    "all_padding_is_zero_transmission": {"fill": ("constant", -3024), "settings": {"output": "transmission"}},
    "single_voxel": {"size": (1, 1, 1), "fill": ("constant", 3071), "settings": {"samples": 1}},
    "anisotropic_rotated": {"size": (8, 3, 5), "spacing": (1e-3, 1.0, 1e3),
                            "direction": ("rotation", (45.0, -30.0, 90.0)), "fill": BONE_IN_WATER},
    "left_handed_permutation": {"direction": ("permutation", 7), "spacing": (0.5, 2.5, 0.7),
                                "settings": {"kernel": "tent"}},
    "left_handed_rotation": {"direction": ("rotation-flip", (45.0, 0.0, -30.0)), "settings": {"sampler": "mcvr"}},
    "nearly_singular_direction": {"direction": ("nearly-singular", 1e-9)},
    "huge_origin_spacing": {"origin": (1e7, -1e9, 0.5), "spacing": (1e6, 1e9, 1e3)},
    "float_mu_identity": {"float": True, "fill": ("checker", 0.02, 0.5), "transfer": ("identity",)},
    "float_nan_voxel_refused": {"float": True, "size": (2, 1, 1), "fill": ("voxels", [0.02, math.nan])},
    "float_inf_voxel_refused": {"float": True, "size": (1, 2, 1), "fill": ("voxels", [math.inf, 1e3])},
    "float_huge_mu": {"float": True, "fill": ("block", 0.0, 1e30, (0, 0, 0), (3, 3, 3)), "transfer": ("identity",)},
    "float_tiny_mu": {"float": True, "fill": ("constant", 1e-30), "transfer": ("identity",)},
    # Transfer functions.
    "piecewise_linear_and_air_threshold": {"fill": BONE_IN_WATER,
                                           "transfer": ("piecewise", [(500.0, 0.0), (500.0, 0.02), (1000.0, 0.05)]),
                                           "air_threshold": -999.5},
    "mu_water_and_energy": {"transfer": ("energy", 10.0), "air_threshold": 0.0},
    # Transforms.
    "rigid_transform": {"transform": ("rigid", (90.0, 45.0, 0.0), (10.0, -1.0, 0.0))},
    "affine_transform": {"transform": ("affine", (0.5, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, -0.5), (1.0, 0.0, 0.0))},
    "singular_affine_refused": {"transform": ("affine", (-1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
                                              (0.0, 0.0, 0.0))},
    # Settings.
    "paper_count_perspective": {"fill": BONE_IN_WATER, "settings": {"weighting": "paper-count", "samples": 5000}},
    "reuse_second_pose_and_refine": {"fill": BONE_IN_WATER,
                                     "settings": {"sampler": "stratified", "reuse": 10.0, "refine": 500}},
    "reuse_half_turn": {"settings": {"sampler": "level-alias", "reuse": 180.0, "kernel": "tent"}},
    "gray8_window": {"settings": {"output": "gray8", "window": (1.0, 2.0)}},
    "gray16_own_range": {"fill": BONE_IN_WATER, "settings": {"output": "gray16"}},
    "gray8_unsigned_char": {"fill": BONE_IN_WATER, "settings": {"output": "gray8", "unsigned_char_output": True}},
    "gray16_unsigned_char_refused": {"settings": {"output": "gray16", "unsigned_char_output": True}},
    "line_integral_unsigned_char_refused": {"settings": {"unsigned_char_output": True}},
    "transmission": {"settings": {"output": "transmission", "splat": "bilinear", "samples": 1234}},
}


def main():
    directory = os.path.join(os.path.dirname(os.path.abspath(__file__)), "Filter")
    os.makedirs(directory, exist_ok=True)
    for name, case in SEEDS.items():
        data = b"" if case is None else encode(case)
        with open(os.path.join(directory, name), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main()
