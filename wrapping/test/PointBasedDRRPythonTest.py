#!/usr/bin/env python3
# Copyright NumFOCUS and the PointBasedDRR contributors
# Licensed under the Apache License, Version 2.0 (http://www.apache.org/licenses/LICENSE-2.0.txt).
"""The module from Python, on ITK's Python wrapping (issue 31; docs/wrapping.md).

    python3 PointBasedDRRPythonTest.py RENDER_DRR_PROGRAM RENDER_DRR_PY WORK_DIR

RENDER_DRR_PROGRAM is examples/RenderDRR.cxx built (the C++ filter), RENDER_DRR_PY examples/RenderDRR.py (its
phantom). Prints "SKIPPED: <why>" and exits 0 where no wrapped ITK with this module imports (CTest's
SKIP_REGULAR_EXPRESSION); any failed check exits 1, naming it.

Checks, each on the phantom of RenderDRR.py (64 x 64 x 48 voxels of 4 mm, HU):
1. itk.PointBasedDRRImageFilter renders the DRR of the C++ program bit for bit: same settings, same seed.
2. NumPy views of the outputs (itk.array_view_from_image) share the image's memory.
3. The standard-error output is honest: it matches the spread of 8 seeds (median ratio), and the seeds' mean matches
   ExactDRRImageFilter's pixel average in those standard errors (bounds from their own count).
4. The geometry: a gantry view's 3 x 4 projection matrix (GetProjectionMatrix) maps the isocenter to the detector's
   centre, and a geometry set from that matrix (SetProjectionMatrix) renders the same exact image.
5. PointBasedDRRInterpolateImageFunction, asked as ITK's classic metrics ask it (MeanSquaresImageToImageMetric: each
   pixel centre moved by the transform), in a short Python registration loop, finds a 6 mm shift of the CT.
6. PointBasedDRRMetricv4 (issue 38): its derivative (ITK's v4 sign) is the central difference of its value along a
   translation, and QuasiNewtonOptimizerv4 (ITKOptimizersv4's wrapping), with the metric's scales estimator
   (PointBasedDRRParameterScalesEstimator), takes the CT from 5 mm and 2 degrees off to within 0.5 mm of where the
   X-rays were rendered.
"""
import importlib.util
import math
import subprocess
import sys
import tempfile


def skip(why):
    print("SKIPPED: " + why)
    sys.exit(0)


def fail(check, why):
    print("FAILED: " + check + ": " + why)
    sys.exit(1)


try:
    import numpy as np
    import itk

    itk.PointBasedDRRImageFilter  # ITK's lazy loading imports the module's wrapping here
except Exception as error:  # ImportError, or AttributeError from ITK's lazy loader
    skip(f"{sys.executable} cannot import itk.PointBasedDRRImageFilter ({type(error).__name__}: {error})")

CT = itk.Image[itk.SS, 3]
MU = itk.Image[itk.F, 3]
PROJECTION = itk.Image[itk.F, 2]
SLICE = itk.Image[itk.F, 3]  # ITK's classic 2D-3D registration: the X-ray as a one-slice 3D image


def load_phantom(render_drr_py):
    spec = importlib.util.spec_from_file_location("RenderDRR", render_drr_py)
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    return example.make_phantom()


def set_view(geometry, volume, gantry_degrees=90.0, size=256, spacing=1.5):
    """RenderDRR.cxx's view: source to isocenter 1000 mm, to detector 1500 mm (the defaults), the volume's centre."""
    geometry.SetGantryAngleInDegrees(gantry_degrees)
    geometry.SetIsocenterToImageCenter(volume)
    detector_size = itk.Size[2]()
    detector_size.Fill(size)
    geometry.SetDetectorSize(detector_size)
    detector_spacing = itk.Vector[itk.D, 2]()
    detector_spacing.Fill(spacing)  # mm
    geometry.SetDetectorSpacing(detector_spacing)


def check_same_as_cxx(ct, program, work):
    """1 and 2: the C++ program's image, bit for bit; NumPy views."""
    phantom = work + "/phantom.mha"
    cxx = work + "/cxx.mha"
    itk.imwrite(ct, phantom)
    subprocess.run([program, phantom, cxx], check=True)
    drr = itk.PointBasedDRRImageFilter[CT, PROJECTION].New(Input=ct)
    set_view(drr.GetGeometry(), ct)
    drr.SetNumberOfSamples(20000000)  # RenderDRR.cxx's
    drr.SetSeed(1)
    drr.Update()
    python_image = itk.array_view_from_image(drr.GetOutput())
    cxx_image = itk.array_from_image(itk.imread(cxx, itk.F))
    if python_image.shape != (256, 256) or cxx_image.shape != (256, 256):
        fail("same as C++", f"shapes {python_image.shape} and {cxx_image.shape}, not 256 x 256")
    if not python_image.max() > 1.0:
        fail("same as C++", f"the phantom's DRR is empty (max {python_image.max()})")
    differing = int(np.count_nonzero(python_image.view(np.uint32) != cxx_image.view(np.uint32)))
    if differing:
        fail("same as C++", f"{differing} of 65536 pixels differ from the C++ filter's at seed 1")
    print(f"1. Python's DRR equals the C++ filter's bit for bit (65536 pixels, max {python_image.max():.4f})")

    # A view, not a copy: writing through it changes the image.
    index = itk.Index[2]()
    index.Fill(0)
    before = drr.GetOutput().GetPixel(index)
    python_image[0, 0] = before + 1.0
    after = drr.GetOutput().GetPixel(index)
    python_image[0, 0] = before
    if after != before + 1.0:
        fail("NumPy view", "array_view_from_image() did not share the image's buffer")
    print("2. itk.array_view_from_image() views the output's buffer (a write through it is seen by GetPixel)")


def check_standard_error(ct, seeds=8):
    """3: the standard error against the spread of seeds, and the seeds' mean against the exact projector."""
    exact = itk.ExactDRRImageFilter[CT, PROJECTION].New(Input=ct)
    set_view(exact.GetGeometry(), ct, size=64, spacing=6.0)
    exact.SetRaysPerPixelSide(16)  # the pixel's average, which the nearest splat estimates
    exact.Update()
    reference = itk.array_from_image(exact.GetOutput()).astype(np.float64)
    renders, errors = [], []
    for seed in range(1, seeds + 1):
        drr = itk.PointBasedDRRImageFilter[CT, PROJECTION].New(Input=ct)
        set_view(drr.GetGeometry(), ct, size=64, spacing=6.0)
        drr.SetSplat(itk.PointBasedDRREnums.Splat_Nearest)
        drr.SetNumberOfSamples(400000)
        drr.SetSeed(seed)
        drr.Update()
        renders.append(itk.array_from_image(drr.GetOutput()).astype(np.float64))
        errors.append(itk.array_from_image(drr.GetStandardErrorOutput()).astype(np.float64))
    renders, errors = np.array(renders), np.array(errors)
    if not (np.all(np.isfinite(errors)) and np.all(errors >= 0.0)):
        fail("standard error", "not finite, or negative")
    body = errors.min(axis=0) > 0.0
    n = int(np.count_nonzero(body))
    if n < 500:
        fail("standard error", f"only {n} pixels have a standard error")
    reported = errors.mean(axis=0)[body]
    # Spread: the seeds' sample standard deviation over the reported standard error. For normal errors its median
    # over pixels is the median of chi(seeds - 1) / sqrt(seeds - 1), 0.977 for 8 seeds, known to about
    # 1.25 * 0.27 / sqrt(n) (0.007 here); 0.1 leaves room for the tails of a Monte Carlo error.
    spread = float(np.median(renders.std(axis=0, ddof=1)[body] / reported))
    # Mean: the seeds' mean against the exact pixel average, in its own standard errors; their mean over n pixels.
    z = (renders.mean(axis=0)[body] - reference[body]) / (reported / math.sqrt(seeds))
    mean = float(z.mean())
    if abs(spread - 0.977) > 0.1 or abs(mean) > 5.0 / math.sqrt(n):
        fail("standard error", f"over {n} pixels and {seeds} seeds: spread / standard error {spread:.3f} (0.977 "
             f"expected), mean z against the exact projector {mean:+.3f} (bound {5.0 / math.sqrt(n):.3f})")
    print(f"3. {seeds} seeds over {n} pixels: their spread / the standard error output {spread:.3f} (0.977 expected); "
          f"their mean against ExactDRRImageFilter, in standard errors: {mean:+.3f} (bound {5.0 / math.sqrt(n):.3f})")


def check_geometry(ct):
    """4: the projection matrix of a gantry view, and a view set from it."""
    by_gantry = itk.ExactDRRImageFilter[CT, PROJECTION].New(Input=ct)
    set_view(by_gantry.GetGeometry(), ct, gantry_degrees=30.0, size=64, spacing=6.0)
    geometry = by_gantry.GetGeometry()
    matrix = itk.array_from_matrix(geometry.GetProjectionMatrix())
    if matrix.shape != (3, 4):
        fail("geometry", f"GetProjectionMatrix() is {matrix.shape}, not 3 x 4")
    isocenter = np.array(list(geometry.GetIsocenter()) + [1.0])
    pixel = matrix @ isocenter
    pixel = pixel[:2] / pixel[2]
    if np.max(np.abs(pixel - 31.5)) > 1e-9:
        fail("geometry", f"the isocenter projects to pixel {pixel}, not the centre (31.5, 31.5)")
    by_matrix = itk.ExactDRRImageFilter[CT, PROJECTION].New(Input=ct)
    # The detector's pitch first: the matrix gives the rays, the pitch where they end (SetProjectionMatrix()'s doc).
    by_matrix.GetGeometry().SetDetectorSpacing(geometry.GetDetectorSpacing())
    by_matrix.GetGeometry().SetProjectionMatrix(geometry.GetProjectionMatrix(), geometry.GetDetectorSize())
    by_gantry.Update()
    by_matrix.Update()
    a = itk.array_from_image(by_gantry.GetOutput())
    b = itk.array_from_image(by_matrix.GetOutput())
    worst = float(np.max(np.abs(a - b)))
    if not a.max() > 1.0 or worst > 1e-4 * float(a.max()):
        fail("geometry", f"the view set from its matrix differs by {worst} (max {a.max()})")
    print(f"4. gantry 30: the isocenter projects to pixel ({pixel[0]:.6f}, {pixel[1]:.6f}); the view set from the "
          f"3 x 4 matrix renders the same exact image (largest difference {worst:.2e})")


def check_registration(ct):
    """5: the interpolator, asked as ITK's classic metric asks it, in a Python loop over the shift along x (mm)."""
    hu = itk.array_from_image(ct).astype(np.float32)
    mu_array = np.maximum(0.0, 0.0194 * (1.0 + hu / 1000.0)).astype(np.float32)  # 1/mm, water at about 70 keV
    mu = itk.image_from_array(mu_array)
    mu.CopyInformation(ct)

    target = itk.ExactDRRImageFilter[MU, SLICE].New(Input=mu)
    target.GetTransferFunction().SetMode(itk.PointBasedDRREnums.TransferFunction_Identity)
    set_view(target.GetGeometry(), mu, size=64, spacing=6.0)
    target.Update()
    xray = target.GetOutput()

    transform = itk.Euler3DTransform[itk.D].New()
    transform.SetCenter(itk.DRRProjectionGeometry.ComputeImageCenter(mu))
    interpolator = itk.PointBasedDRRInterpolateImageFunction[MU, itk.D].New()
    interpolator.SetInputImage(mu)
    interpolator.SetTransform(transform)
    interpolator.SetFocalPoint(target.GetGeometry().GetSourcePosition())
    interpolator.SetThreshold(0.0)
    interpolator.SetDetectorFromImage(xray)
    interpolator.GetDRRFilter().SetNumberOfSamples(500000)

    # ITK's classic metric, as MeanSquaresImageToImageMetric computes it: each pixel centre of the X-ray, moved by the
    # transform, asked of the interpolator (which moves the focal point by the same transform).
    target_values = itk.array_from_image(xray).ravel().astype(np.float64)
    pixel_centres = []
    size = xray.GetLargestPossibleRegion().GetSize()
    for j in range(size[1]):
        for i in range(size[0]):
            pixel_centres.append(xray.TransformIndexToPhysicalPoint([i, j, 0]))
    parameters = transform.GetParameters()  # 3 angles (radians), 3 translations (mm)

    def cost(shift_x):
        parameters.SetElement(3, shift_x)
        transform.SetParameters(parameters)
        values = np.array([interpolator.Evaluate(transform.TransformPoint(p)) for p in pixel_centres])
        return float(np.mean((values - target_values) ** 2))

    # A pattern search on the shift along x from 6 mm: step to the better neighbour, halve the step when neither is.
    shift, step, evaluations = 6.0, 4.0, 0
    value = cost(shift)
    while step >= 0.25:
        left, right = cost(shift - step), cost(shift + step)
        evaluations += 2
        if min(left, right) < value:
            shift, value = (shift - step, left) if left < right else (shift + step, right)
        else:
            step /= 2.0
    if abs(shift) > 0.5:
        fail("registration", f"the loop stopped at a shift of {shift} mm, not 0")
    print(f"5. a Python loop over the mean squares of PointBasedDRRInterpolateImageFunction's values: from 6 mm "
          f"to {shift:+.2f} mm in {evaluations} evaluations, {interpolator.GetNumberOfRenders()} renders")


def check_metric(ct):
    """6: the v4 metric: its derivative against a central difference, and an ITK v4 optimizer."""
    metric = itk.PointBasedDRRMetricv4[CT].New()
    metric.SetVolume(ct)
    for gantry in (90.0, 0.0):  # AP and lateral: a second view fixes the depth one view sees as magnification
        target = itk.ExactDRRImageFilter[CT, PROJECTION].New(Input=ct)
        set_view(target.GetGeometry(), ct, gantry_degrees=gantry, size=64, spacing=6.0)
        target.SetRaysPerPixelSide(2)
        target.Update()
        metric.AddXRay(target.GetOutput(), target.GetGeometry())
    transform = itk.Euler3DTransform[itk.D].New()
    transform.SetCenter(itk.DRRProjectionGeometry.ComputeImageCenter(ct))
    parameters = transform.GetParameters()
    for k, value in enumerate((0.02, -0.025, 0.03, 3.0, -3.0, 2.5)):  # radians, then mm
        parameters.SetElement(k, value)
    transform.SetParameters(parameters)
    metric.SetMovingTransform(transform)
    metric.SetNumberOfSamples(500000)
    metric.Initialize()

    derivative = itk.Array[itk.D](6)
    metric.GetDerivative(derivative)
    h = 0.05  # mm along x
    moved = itk.OptimizerParameters[itk.D](transform.GetParameters())
    moved.SetElement(3, parameters.GetElement(3) + h)
    metric.SetParameters(moved)
    forward = metric.GetValue()
    moved.SetElement(3, parameters.GetElement(3) - h)
    metric.SetParameters(moved)
    backward = metric.GetValue()
    metric.SetParameters(parameters)
    difference = (forward - backward) / (2.0 * h)
    # v4: the derivative returned is minus the value's; 1% and a floor for the kinks of the bilinear splat.
    if abs(-derivative.GetElement(3) - difference) > 0.01 * abs(difference) + 1e-5:
        fail("metric", f"d value / d tx = {-derivative.GetElement(3)} analytic, {difference} by central difference")

    estimator = itk.PointBasedDRRParameterScalesEstimator[CT].New()
    estimator.SetMetric(metric)
    optimizer = itk.QuasiNewtonOptimizerv4.New()
    optimizer.SetScalesEstimator(estimator)
    optimizer.SetNumberOfIterations(100)
    optimizer.SetMetric(metric)
    optimizer.StartOptimization()
    found = transform.GetParameters()
    shift = math.sqrt(sum(found.GetElement(k) ** 2 for k in range(3, 6)))
    angle = math.degrees(math.sqrt(sum(found.GetElement(k) ** 2 for k in range(3))))
    if shift > 0.5 or angle > 0.3:
        fail("metric", f"QuasiNewtonOptimizerv4 stopped {shift:.2f} mm and {angle:.2f} degrees from the truth: "
             + optimizer.GetStopConditionDescription())
    print(f"6. PointBasedDRRMetricv4: derivative {-derivative.GetElement(3):.6g} against central difference "
          f"{difference:.6g}; QuasiNewtonOptimizerv4 from 5 mm / 2.5 degrees to {shift:.2f} mm / {angle:.2f} degrees "
          f"in {metric.GetNumberOfDerivativeEvaluations()} evaluations")


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        sys.exit(2)
    program, render_drr_py, work = sys.argv[1:]
    print(f"ITK {itk.Version.GetITKVersion()} from {itk.__file__}")
    ct = load_phantom(render_drr_py)
    with tempfile.TemporaryDirectory(dir=work) as folder:
        check_same_as_cxx(ct, program, folder)
    check_standard_error(ct)
    check_geometry(ct)
    check_registration(ct)
    check_metric(ct)
    print("PASSED")


if __name__ == "__main__":
    main()
