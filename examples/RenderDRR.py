#!/usr/bin/env python3
# Copyright NumFOCUS and the PointBasedDRR contributors
# Licensed under the Apache License, Version 2.0 (http://www.apache.org/licenses/LICENSE-2.0.txt).
"""RenderDRR.cxx in Python: an AP radiograph of a CT (HU), written as float line integrals of mu.

    python3 RenderDRR.py CT_VOLUME OUTPUT_IMAGE [--samples N] [--seed S] [--gantry DEGREES] [--stderr FILE]
    python3 RenderDRR.py --phantom OUTPUT_IMAGE

Needs ITK's Python package built with this module wrapped (ITK_WRAP_PYTHON=ON, PointBasedDRR as a remote module):
`python3 -c "import itk; itk.PointBasedDRRImageFilter"` must work. The wrapped filters take a 3D short or float
volume and write a 2D float image; the names are the C++ API's.

Each pixel of the output is the pixel-averaged line integral of mu (1/mm) from the source to the detector: no
unit (100 mm of water at 60 keV is about 2). The CT is read as HU and converted to mu by the module's transfer
function (water at 60 keV). The view: gantry angle in degrees (90: AP, the source anterior), source to isocenter
1000 mm, source to detector 1500 mm, isocenter at the centre of the volume, 256 x 256 pixels of 1.5 mm.
"""
import argparse

import itk


def make_phantom():
    """A coarse torso in HU: a water cylinder of 100 mm radius with a bone rod, in air; 64 x 64 x 48 voxels of 4 mm."""
    import numpy as np  # ITK's Python package depends on NumPy

    _, y, x = np.mgrid[0:48, 0:64, 0:64] * 4.0  # mm from the first voxel, in NumPy's z, y, x order
    x -= 126.0  # mm from the centre
    y -= 126.0
    hu = np.full(x.shape, -1000, dtype=np.int16)
    hu[x**2 + y**2 < 100.0**2] = 0
    hu[(x - 40.0) ** 2 + (y - 20.0) ** 2 < 15.0**2] = 1000
    ct = itk.image_from_array(hu)  # NumPy's z, y, x order becomes ITK's x, y, z
    ct.SetSpacing([4.0, 4.0, 4.0])  # mm
    ct.SetOrigin([-126.0, -126.0, -94.0])  # mm: the volume centred on (0, 0, 0)
    return ct


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("input", nargs="?", help="CT volume in HU (any format ITK reads)")
    parser.add_argument("output", help="output image: float line integrals (.mha, .nrrd, .nii, .tif)")
    parser.add_argument("--phantom", action="store_true", help="render a built-in phantom instead of a CT")
    parser.add_argument("--samples", type=float, default=2e7, help="number of points (default 2e7)")
    parser.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    parser.add_argument("--gantry", type=float, default=90.0, help="gantry angle, degrees (default 90: AP)")
    parser.add_argument("--stderr", help="also write the per-pixel standard error (line-integral units)")
    arguments = parser.parse_args()
    if (arguments.input is None) == (not arguments.phantom):
        parser.error("give a CT volume or --phantom")

    CTImageType = itk.Image[itk.SS, 3]
    ct = make_phantom() if arguments.phantom else itk.imread(arguments.input, itk.SS)

    drr = itk.PointBasedDRRImageFilter[CTImageType, itk.Image[itk.F, 2]].New()
    drr.SetInput(ct)
    geometry = drr.GetGeometry()  # an itk.DRRProjectionGeometry: plastimatch's convention, mm and degrees
    geometry.SetGantryAngleInDegrees(arguments.gantry)
    geometry.SetSourceToIsocenterDistance(1000.0)  # mm
    geometry.SetSourceToDetectorDistance(1500.0)  # mm
    geometry.SetIsocenterToImageCenter(ct)  # the centre of the voxel grid, the direction matrix honoured
    detector_size = itk.Size[2]()
    detector_size[0] = 256  # columns
    detector_size[1] = 256  # rows
    geometry.SetDetectorSize(detector_size)
    pixel_spacing = itk.Vector[itk.D, 2]()
    pixel_spacing.Fill(1.5)  # mm
    geometry.SetDetectorSpacing(pixel_spacing)
    drr.SetNumberOfSamples(int(arguments.samples))
    drr.SetSeed(arguments.seed)
    drr.Update()

    itk.imwrite(drr.GetOutput(), arguments.output)
    print("wrote", arguments.output)
    if arguments.stderr:
        itk.imwrite(drr.GetStandardErrorOutput(), arguments.stderr)
        print("wrote", arguments.stderr)


if __name__ == "__main__":
    main()
