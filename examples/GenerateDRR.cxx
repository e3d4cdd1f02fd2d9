/*=========================================================================
 *
 *  Copyright NumFOCUS and the PointBasedDRR contributors
 *
 *  Licensed under the Apache License, Version 2.0 (the "License");
 *  you may not use this file except in compliance with the License.
 *  You may obtain a copy of the License at
 *
 *         http://www.apache.org/licenses/LICENSE-2.0.txt
 *
 *  Unless required by applicable law or agreed to in writing, software
 *  distributed under the License is distributed on an "AS IS" BASIS,
 *  WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
 *  See the License for the specific language governing permissions and
 *  limitations under the License.
 *
 *=========================================================================*/
// ITK's classic DRR example, Examples/Filtering/DigitallyReconstructedRadiograph1.cxx, rewritten on this module: the
// same command line and the same view, rendered by itk::PointBasedDRRImageFilter (or, with -exact,
// itk::ExactDRRImageFilter) instead of itk::RayCastInterpolateImageFunction, and written as float line integrals.
//
//   GenerateDRR [options] [CT]
//
//   -h                   this help
//   -v                   verbose: the volume, the transform, the geometry and the render statistics
//   -res du dv           detector pixel spacing, mm (default 1 1)
//   -size cols rows      detector size, pixels (default 501 501)
//   -sid SID             source to detector distance, mm (default 400)
//   -scd SCD             source to centre (isocenter) distance, mm (default SID / 2: the volume halfway, as ITK's)
//   -rx RX -ry RY -rz RZ the transform's rotation about x, y, z, degrees (default 0; about x first, then y, then z)
//   -t tx ty tz          the transform's translation, mm (default 0 0 0): ITK's "translation of the camera", the
//                        volume seen shifted by -t
//   -cor cx cy cz        centre of rotation relative to the volume centre, mm (default 0 0 0)
//   -normal ox oy        detector centre relative to the foot of the normal from the source, mm (default 0 0)
//   -threshold HU        voxels below HU are air, mu = 0 (default: none; the transfer function zeroes -1000 and below)
//   -o FILE              output: float line integrals (.mha, .nrrd, .nii, .tif; no output: render only)
//   -samples N           number of points (default 1e7)
//   -seed S              seed of the random streams (default 1): the same image, bit for bit, on any thread count
//   -se FILE             also write the per-pixel standard error of the image (same units)
//   -exact               the noise-free exact projector (Siddon through the voxels) instead of points
//   -rays K              with -exact: K x K rays per pixel (default 1, one ray per pixel as ITK's ray caster)
//   CT                   a volume ITK reads, in HU; without it, ITK's cube phantom (see below)
//
// How ITK's example maps onto the module:
// - The camera is ITK's: the source on the -z side of the volume centre, the detector plane perpendicular to z on
//   the other side, its columns along +x and rows along +y. As a DRRProjectionGeometry: isocenter at the volume
//   centre, normal (isocenter to source) (0, 0, -1), view-up (0, -1, 0) (row 0 at the -y edge), source to isocenter
//   distance (SAD) from -scd, source to detector distance (SID) from -sid, detector offset from -normal. ITK's
//   example has only -sid and puts the volume halfway between source and detector (SAD = SID / 2): the default of
//   -scd here. The volume centre is the centre of the voxel grid, with the direction matrix honoured (ITK's example
//   takes origin + spacing x size / 2, half a voxel off, and ignores the direction).
// - The transform is ITK's: an Euler3DTransform (ITK's example uses the CenteredEuler3DTransform subclass) with
//   ComputeZYX on (matrix Rz Ry Rx), the rotation -rx, -ry, -rz (degrees, converted to radians), the translation -t
//   and the centre volume centre + -cor, given to the filter by SetTransform(). It means what it means for ITK's ray
//   caster and ResampleImageFilter: it maps a room point to the volume's frame, so the camera moves by it and the
//   volume, as seen, by its inverse. The camera looks along the volume's z axis, as ITK's: through the slices of a CT
//   (LPS); -rx -90 turns it to an AP view (source anterior, head up, the patient's left on the right), -rx 90 to PA.
// - The output is placed as ITK's: a 3D image of one slice on the detector plane (origin at the centre of pixel
//   (0, 0), spacing -res, axes x, y, z). ITK's example integrates (value - threshold) above -threshold (default 0) and
//   rescales the result to 8 bits (0 to 255, RescaleIntensityImageFilter); here the output is quantitative: each pixel
//   is the pixel-averaged line integral of mu (mm x 1/mm: no unit; 100 mm of water is about 2), HU converted to mu
//   (1/mm) by the module's transfer function, mu = mu_water (1 + HU / 1000), water at 60 keV. For 8-bit pictures,
//   use pbdrr (it windows PNG output) or RescaleIntensityImageFilter as ITK's example does.
// - Without a CT, ITK's phantom: 61 x 61 x 61 voxels of 3 mm, two nested cube frames and a centre voxel of values 10,
//   60 and 100 in 0, written as HU = 20 v - 1000 (-800, 200 and 1000 HU in air) so that mu is proportional to ITK's v.
#include "itkExactDRRImageFilter.h"
#include "itkPointBasedDRRImageFilter.h"

#include "itkEuler3DTransform.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "itkImageRegionIteratorWithIndex.h"

#include <chrono>
#include <cmath>
#include <iostream>
#include <string>

namespace
{
using CTImageType = itk::Image<short, 3>;  // HU, as ITK's example reads
using DRRImageType = itk::Image<float, 3>; // one slice on the detector plane: line integrals of mu
using TransformType = itk::Euler3DTransform<double>;

struct Options
{
  bool        Verbose{ false };
  std::string Input, Output, StandardErrorOutput;
  double      PixelSpacing[2]{ 1.0, 1.0 };           // mm
  unsigned    DetectorSize[2]{ 501, 501 };           // pixels
  double      SourceToDetector{ 400.0 };             // mm
  double      SourceToCentre{ -1.0 };                // mm; negative: SourceToDetector / 2
  double      RotationInDegrees[3]{ 0.0, 0.0, 0.0 }; // about x, y, z
  double      Translation[3]{ 0.0, 0.0, 0.0 };       // mm
  double      CentreOfRotation[3]{ 0.0, 0.0, 0.0 };  // mm, relative to the volume centre
  double      DetectorOffset[2]{ 0.0, 0.0 };         // mm
  bool        HasThreshold{ false };
  double      ThresholdInHU{ 0.0 };
  double      Samples{ 1e7 };
  uint64_t    Seed{ 1 };
  bool        Exact{ false };
  unsigned    RaysPerPixelSide{ 1 };
};

void
PrintUsage()
{
  std::cout << "usage: GenerateDRR [options] [CT]   (CT in HU; without it, ITK's cube phantom)\n"
               "  -v                    verbose\n"
               "  -res du dv            detector pixel spacing, mm (default 1 1)\n"
               "  -size cols rows       detector size, pixels (default 501 501)\n"
               "  -sid SID              source to detector distance, mm (default 400)\n"
               "  -scd SCD              source to centre (isocenter) distance, mm (default SID / 2)\n"
               "  -rx/-ry/-rz DEGREES   the transform's rotation about x, y, z, degrees (default 0)\n"
               "  -t tx ty tz           the transform's translation, mm (default 0 0 0; the volume is seen at -t)\n"
               "  -cor cx cy cz         centre of rotation relative to the volume centre, mm (default 0 0 0)\n"
               "  -normal ox oy         detector centre relative to the foot of the normal, mm (default 0 0)\n"
               "  -threshold HU         voxels below HU are air (default: none)\n"
               "  -o FILE               output: float line integrals of mu (no unit)\n"
               "  -samples N            number of points (default 1e7)\n"
               "  -seed S               random seed (default 1)\n"
               "  -se FILE              standard-error image (line-integral units)\n"
               "  -exact                exact projector (Siddon) instead of points\n"
               "  -rays K               with -exact: K x K rays per pixel (default 1)\n";
}

Options
ParseOptions(int argc, char * argv[])
{
  Options options;
  for (int a = 1; a < argc; ++a)
  {
    const std::string argument = argv[a];
    const auto        number = [&]() -> double {
      if (a + 1 >= argc)
        throw std::runtime_error(argument + " needs more values");
      return std::stod(argv[++a]);
    };
    const auto text = [&]() -> std::string {
      if (a + 1 >= argc)
        throw std::runtime_error(argument + " needs a value");
      return argv[++a];
    };
    const auto count = [&]() -> unsigned {
      const double value = number();
      if (!(value >= 1.0 && value <= 1e6))
        throw std::runtime_error(argument + " takes counts from 1 to 10^6");
      return static_cast<unsigned>(value);
    };
    if (argument == "-h" || argument == "--help")
    {
      PrintUsage();
      std::exit(EXIT_SUCCESS);
    }
    else if (argument == "-v")
      options.Verbose = true;
    else if (argument == "-res")
      for (double & spacing : options.PixelSpacing)
        spacing = number();
    else if (argument == "-size")
      for (unsigned & size : options.DetectorSize)
        size = count();
    else if (argument == "-sid")
      options.SourceToDetector = number();
    else if (argument == "-scd")
      options.SourceToCentre = number();
    else if (argument == "-rx" || argument == "-ry" || argument == "-rz")
      options.RotationInDegrees[argument[2] - 'x'] = number();
    else if (argument == "-t")
      for (double & translation : options.Translation)
        translation = number();
    else if (argument == "-cor")
      for (double & centre : options.CentreOfRotation)
        centre = number();
    else if (argument == "-normal")
      for (double & offset : options.DetectorOffset)
        offset = number();
    else if (argument == "-threshold")
    {
      options.HasThreshold = true;
      options.ThresholdInHU = number();
    }
    else if (argument == "-o")
      options.Output = text();
    else if (argument == "-samples")
      options.Samples = number();
    else if (argument == "-seed")
      options.Seed = std::stoull(text());
    else if (argument == "-se")
      options.StandardErrorOutput = text();
    else if (argument == "-exact")
      options.Exact = true;
    else if (argument == "-rays")
      options.RaysPerPixelSide = count();
    else if (!argument.empty() && argument[0] == '-')
      throw std::runtime_error("unknown option " + argument + " (-h lists them)");
    else if (options.Input.empty())
      options.Input = argument;
    else
      throw std::runtime_error("one CT only: " + argument);
  }
  if (options.SourceToCentre < 0.0)
    options.SourceToCentre = 0.5 * options.SourceToDetector; // ITK's example: the volume halfway
  if (!(options.Samples >= 1.0))
    throw std::runtime_error("-samples must be at least 1");
  if (options.Exact && !options.StandardErrorOutput.empty())
    throw std::runtime_error("-se needs points: the exact projector has no noise");
  return options;
}

/** ITK's example phantom: two nested cube frames and a centre voxel (ITK's values 10, 60, 100 in 0) as HU = 20 v -
 * 1000, so that mu = mu_water v / 50 is proportional to ITK's values. 61^3 voxels of 3 mm, origin at 0. */
CTImageType::Pointer
MakeCubePhantom()
{
  auto ct = CTImageType::New();
  ct->SetRegions(CTImageType::SizeType{ { 61, 61, 61 } });
  ct->SetSpacing(CTImageType::SpacingType(3.0)); // mm
  ct->Allocate();
  const auto inFrame = [](const CTImageType::IndexType & i, int first, int last, int width) {
    bool inside = true, edge[3];
    for (unsigned axis = 0; axis < 3; ++axis)
    {
      inside = inside && i[axis] >= first && i[axis] <= last;
      edge[axis] = i[axis] < first + width || i[axis] > last - width;
    }
    return inside && ((edge[0] && edge[1]) || (edge[0] && edge[2]) || (edge[1] && edge[2]));
  };
  for (itk::ImageRegionIteratorWithIndex<CTImageType> it(ct, ct->GetLargestPossibleRegion()); !it.IsAtEnd(); ++it)
  {
    const auto & i = it.GetIndex();
    int          value = 0; // ITK's phantom value
    if (inFrame(i, 6, 54, 6))
      value = 10;
    else if (inFrame(i, 18, 42, 6))
      value = 60;
    else if (i[0] == 30 && i[1] == 30 && i[2] == 30)
      value = 100;
    it.Set(static_cast<short>(20 * value - 1000));
  }
  return ct;
}

/** What both DRR filters share: the input, the geometry, the transform and the HU-to-mu transfer function. */
template <typename TFilter>
void
SetUpFilter(TFilter *                    drr,
            const CTImageType *          ct,
            itk::DRRProjectionGeometry * geometry,
            const TransformType *        transform,
            const Options &              options)
{
  drr->SetInput(ct);
  drr->SetGeometry(geometry);
  drr->SetTransform(transform);
  if (options.HasThreshold)
    drr->GetTransferFunction()->SetAirThreshold(options.ThresholdInHU); // HU
}
} // namespace

int
main(int argc, char * argv[])
{
  try
  {
    const Options options = ParseOptions(argc, argv);
    const auto    ct = options.Input.empty() ? MakeCubePhantom() : itk::ReadImage<CTImageType>(options.Input);
    const auto    centre = itk::DRRProjectionGeometry::ComputeImageCenter(ct);

    // ITK's transform: rotation about the volume centre + -cor, then translation; room -> volume frame.
    constexpr double degreesToRadians = itk::Math::pi / 180.0;
    auto             transform = TransformType::New();
    transform->SetComputeZYX(true);
    transform->SetRotation(options.RotationInDegrees[0] * degreesToRadians,
                           options.RotationInDegrees[1] * degreesToRadians,
                           options.RotationInDegrees[2] * degreesToRadians);
    TransformType::OutputVectorType translation; // mm
    TransformType::InputPointType   centreOfRotation;
    for (unsigned axis = 0; axis < 3; ++axis)
    {
      translation[axis] = options.Translation[axis];
      centreOfRotation[axis] = centre[axis] + options.CentreOfRotation[axis];
    }
    transform->SetTranslation(translation);
    transform->SetCenter(centreOfRotation);

    // ITK's camera: source at centre - SCD z, detector plane at centre + (SID - SCD) z, columns +x, rows +y.
    auto geometry = itk::DRRProjectionGeometry::New();
    geometry->SetIsocenter(centre);
    const double towardsSource[3]{ 0.0, 0.0, -1.0 }, viewUp[3]{ 0.0, -1.0, 0.0 };
    geometry->SetNormal(itk::Vector<double, 3>(towardsSource));
    geometry->SetViewUp(itk::Vector<double, 3>(viewUp));
    geometry->SetSourceToIsocenterDistance(options.SourceToCentre);  // mm
    geometry->SetSourceToDetectorDistance(options.SourceToDetector); // mm
    geometry->SetDetectorSize({ { options.DetectorSize[0], options.DetectorSize[1] } });
    geometry->SetDetectorSpacing(itk::Vector<double, 2>(options.PixelSpacing));  // mm
    geometry->SetDetectorOffset(itk::Vector<double, 2>(options.DetectorOffset)); // mm
    geometry->VerifyGeometry();

    if (options.Verbose)
    {
      const auto & region = ct->GetLargestPossibleRegion();
      std::cout << "input: " << (options.Input.empty() ? "ITK's cube phantom" : options.Input) << ", "
                << region.GetSize() << " voxels of " << ct->GetSpacing() << " mm, origin " << ct->GetOrigin()
                << " mm, centre " << centre << " mm\n"
                << "transform: rotation " << options.RotationInDegrees[0] << ", " << options.RotationInDegrees[1]
                << ", " << options.RotationInDegrees[2] << " degrees (matrix Rz Ry Rx) about " << centreOfRotation
                << " mm, translation " << translation << " mm\n"
                << "source " << geometry->GetSourcePosition() << " mm, detector centre "
                << geometry->GetDetectorCenter() << " mm, " << options.DetectorSize[0] << " x "
                << options.DetectorSize[1] << " pixels of " << options.PixelSpacing[0] << " x "
                << options.PixelSpacing[1] << " mm, SCD " << options.SourceToCentre << " mm, SID "
                << options.SourceToDetector << " mm\n";
    }

    const auto            start = std::chrono::steady_clock::now();
    DRRImageType::Pointer drr, standardError;
    if (options.Exact)
    {
      auto exact = itk::ExactDRRImageFilter<CTImageType, DRRImageType>::New();
      SetUpFilter(exact.GetPointer(), ct, geometry, transform, options);
      exact->SetRaysPerPixelSide(options.RaysPerPixelSide);
      exact->Update();
      drr = exact->GetOutput();
    }
    else
    {
      auto pointBased = itk::PointBasedDRRImageFilter<CTImageType, DRRImageType>::New();
      SetUpFilter(pointBased.GetPointer(), ct, geometry, transform, options);
      pointBased->SetNumberOfSamples(static_cast<uint64_t>(options.Samples));
      pointBased->SetSeed(options.Seed);
      pointBased->Update();
      drr = pointBased->GetOutput();
      standardError = pointBased->GetStandardErrorOutput();
      if (options.Verbose)
        std::cout << "points: " << pointBased->GetNumberOfSamples() << " drawn, " << pointBased->GetPointsOnDetector()
                  << " on the detector; attenuation mass " << pointBased->GetTotalMass() << " mm^2\n";
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    if (options.Verbose)
    {
      const size_t pixels = drr->GetBufferedRegion().GetNumberOfPixels();
      double       maximum = 0.0, sumOfVariances = 0.0;
      for (size_t p = 0; p < pixels; ++p)
      {
        maximum = std::max<double>(maximum, drr->GetBufferPointer()[p]);
        if (standardError)
          sumOfVariances += std::pow(standardError->GetBufferPointer()[p], 2);
      }
      std::cout << (options.Exact ? "exact projector" : "point-based") << ": " << seconds << " s; line integrals up to "
                << maximum;
      if (standardError)
        std::cout << ", RMS standard error " << std::sqrt(sumOfVariances / pixels) << " ("
                  << 100.0 * std::sqrt(sumOfVariances / pixels) / maximum << "% of the maximum)";
      std::cout << "\noutput: one slice on the detector plane, origin " << drr->GetOrigin() << " mm, spacing "
                << drr->GetSpacing() << " mm\n";
    }
    if (!options.Output.empty())
    {
      itk::WriteImage(drr, options.Output);
      std::cout << "wrote " << options.Output << std::endl;
    }
    if (!options.StandardErrorOutput.empty())
    {
      itk::WriteImage(standardError, options.StandardErrorOutput);
      std::cout << "wrote " << options.StandardErrorOutput << std::endl;
    }
  }
  catch (const std::exception & error)
  {
    std::cerr << "GenerateDRR: " << error.what() << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
