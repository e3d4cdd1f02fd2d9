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
// One radiograph rendered three ways, and how far each is from the exact image:
//
//   CompareWithRayCast CT|--phantom [-o PREFIX] [--gantry DEGREES] [--size PIXELS] [--spacing MM] [--samples N]
//                      [--seed S] [--rays K]
//
// - itk::ExactDRRImageFilter, the reference: the exact line integral through the trilinear (tent) model of the
//   volume, averaged over K x K rays per pixel (default 4 x 4);
// - itk::PointBasedDRRImageFilter: N points (default 10^7) drawn with density proportional to mu, tent kernel: an
//   unbiased estimate of the same pixel averages, with its own standard-error image;
// - ITK's ray caster as ITK's DRR example uses it: itk::RayCastInterpolateImageFunction through
//   itk::ResampleImageFilter, one ray per pixel centre through the trilinear interpolation of the volume.
//
// CT: a volume ITK reads, in HU; --phantom: a coarse built-in torso. All three renderers get the same volume: the CT
// converted to linear attenuation mu (1/mm, water at 60 keV) by the module's transfer function, its voxels re-indexed
// to an identity direction matrix, because ITK's ray caster ignores the direction (the module's filters honour it and
// need no such step). The view: perspective, source to isocenter (SAD) 1000 mm, source to detector (SID) 1500 mm,
// isocenter at the volume centre, gantry angle in degrees (default 90: AP), PIXELS x PIXELS pixels (default 128) of
// MM (default: the volume's shadow with a 10% margin). Pixels hold line integrals of mu (mm x 1/mm: no unit).
//
// Writes PREFIX_exact.mha, PREFIX_pointbased.mha, PREFIX_raycast.mha and the error images (method minus exact)
// PREFIX_pointbased_error.mha and PREFIX_raycast_error.mha (PREFIX default: CompareWithRayCast), and prints a table:
// wall time (each method's whole update: the point-based one includes its preprocessing), RMSE, NRMSE (RMSE / range
// of the exact image), max |error| and image-sum ratio of each method against the exact image, with the NRMSE each
// method is expected to stay below, and why:
// - point-based: Monte Carlo noise, which its standard-error image SE measures: the squared error has the expectation
//   mean(SE^2) and, over n_eff = (sum SE^2)^2 / sum SE^4 independent pixels, a relative spread of sqrt(2 / n_eff);
//   the bound allows 5 such spreads, plus the reference's own error, at most 1/K of its one-ray error (the K x K
//   average converges as 1/K^2 where the image is smooth, 1/K at worst).
// - ray caster: it differs from the exact image by design, not by noise, in three ways, each measured or bounded by
//   a render: it shoots one ray at the pixel centre instead of averaging over the pixel (measured: the exact image
//   with one ray per pixel); it integrates the trilinear model by the rectangle rule, one sample per voxel plane
//   (measured: the ray caster on the volume padded with one layer of zero voxels against the one-ray exact image);
//   and it integrates only between the outermost voxel centres, dropping the outer half voxel of the volume and the
//   model's ramp to zero beyond (bounded: at most the exact projection of the volume's outer layer of voxels alone).
//   The bound is their sum (the triangle inequality): exceeding it, the ray caster would drop more than that layer.
#include "itkExactDRRImageFilter.h"
#include "itkPointBasedDRRImageFilter.h"

#include "itkConstantPadImageFilter.h"
#include "itkIdentityTransform.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "itkOrientImageFilter.h"
#include "itkRayCastInterpolateImageFunction.h"
#include "itkResampleImageFilter.h"

#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>

namespace
{
using CTImageType = itk::Image<float, 3>;  // HU
using MuImageType = itk::Image<float, 3>;  // linear attenuation, 1/mm
using DRRImageType = itk::Image<float, 2>; // line integrals of mu, no unit
using KernelEnum = itk::PointBasedDRREnums::ReconstructionKernel;
using TransferEnum = itk::PointBasedDRREnums::TransferFunction;

struct Options
{
  std::string Input;
  bool        Phantom{ false };
  std::string OutputPrefix{ "CompareWithRayCast" };
  double      GantryInDegrees{ 90.0 };
  unsigned    DetectorPixels{ 128 };
  double      PixelSpacingInMillimeters{ 0.0 }; // 0: the volume's shadow with a 10% margin
  double      Samples{ 1e7 };
  uint64_t    Seed{ 1 };
  unsigned    RaysPerPixelSide{ 4 };
};

Options
ParseOptions(int argc, char * argv[])
{
  Options options;
  for (int a = 1; a < argc; ++a)
  {
    const std::string argument = argv[a];
    const auto        value = [&]() -> std::string {
      if (a + 1 >= argc)
        throw std::runtime_error(argument + " needs a value");
      return argv[++a];
    };
    if (argument == "--phantom")
      options.Phantom = true;
    else if (argument == "-o")
      options.OutputPrefix = value();
    else if (argument == "--gantry")
      options.GantryInDegrees = std::stod(value());
    else if (argument == "--size")
      options.DetectorPixels = static_cast<unsigned>(std::stoul(value()));
    else if (argument == "--spacing")
      options.PixelSpacingInMillimeters = std::stod(value());
    else if (argument == "--samples")
      options.Samples = std::stod(value());
    else if (argument == "--seed")
      options.Seed = std::stoull(value());
    else if (argument == "--rays")
      options.RaysPerPixelSide = static_cast<unsigned>(std::stoul(value()));
    else if (!argument.empty() && argument[0] == '-')
      throw std::runtime_error("unknown option " + argument);
    else
      options.Input = argument;
  }
  if (options.Input.empty() == !options.Phantom)
    throw std::runtime_error("give a CT volume or --phantom");
  if (options.DetectorPixels < 2 || !(options.Samples >= 1.0) || options.RaysPerPixelSide < 2)
    throw std::runtime_error("--size needs at least 2 pixels, --samples at least 1, --rays at least 2 (the reference "
                             "is a pixel average)");
  return options;
}

/** A coarse torso in HU, cut by the first and last slices as a CT is: a water cylinder of elliptic section, a spine
 * and a block of rib bone through every slice, a dense marker, in air. 48 x 40 x 32 voxels of 5 mm. */
CTImageType::Pointer
MakePhantom()
{
  auto                     ct = CTImageType::New();
  CTImageType::SizeType    size{ { 48, 40, 32 } };
  CTImageType::SpacingType spacing(5.0); // mm
  CTImageType::PointType   origin;
  for (unsigned axis = 0; axis < 3; ++axis)
    origin[axis] = -0.5 * (size[axis] - 1) * spacing[axis];
  ct->SetRegions(size);
  ct->SetSpacing(spacing);
  ct->SetOrigin(origin);
  ct->Allocate();
  for (itk::ImageRegionIteratorWithIndex<CTImageType> it(ct, ct->GetLargestPossibleRegion()); !it.IsAtEnd(); ++it)
  {
    CTImageType::PointType p; // mm
    ct->TransformIndexToPhysicalPoint(it.GetIndex(), p);
    const double x = p[0], y = p[1], z = p[2];
    float        hu = -1000.0f; // air
    if ((x / 100) * (x / 100) + (y / 80) * (y / 80) < 1.0)
      hu = 20.0f; // soft tissue
    if ((x - 5) * (x - 5) + (y - 45) * (y - 45) < 14 * 14)
      hu = 700.0f; // spine, posterior
    if (x > 40 && x < 75 && y > -40 && y < 20)
      hu = 400.0f; // rib block, one side
    if ((x + 50) * (x + 50) + (y + 30) * (y + 30) + (z - 40) * (z - 40) < 12 * 12)
      hu = 1500.0f; // marker
    it.Set(hu);
  }
  return ct;
}

/** mu (1/mm) of every voxel by the module's transfer function: water at 60 keV times (1 + HU / 1000). */
MuImageType::Pointer
ToMu(const CTImageType * ct)
{
  auto transfer = itk::DRRTransferFunction::New();
  auto mu = MuImageType::New();
  mu->CopyInformation(ct);
  mu->SetRegions(ct->GetLargestPossibleRegion());
  mu->Allocate();
  const float * hu = ct->GetBufferPointer();
  for (size_t v = 0; v < ct->GetBufferedRegion().GetNumberOfPixels(); ++v)
    mu->GetBufferPointer()[v] = static_cast<float>(transfer->Evaluate(hu[v]));
  return mu;
}

/** The same voxels at the same places with an identity direction matrix (axes permuted and flipped). */
MuImageType::Pointer
WithIdentityDirection(MuImageType * mu)
{
  MuImageType::DirectionType identity;
  identity.SetIdentity();
  if (mu->GetDirection() == identity)
    return mu;
  auto orient = itk::OrientImageFilter<MuImageType, MuImageType>::New();
  orient->SetInput(mu);
  orient->UseImageDirectionOn();
  orient->SetDesiredCoordinateDirection(identity);
  orient->Update();
  if (!(orient->GetOutput()->GetDirection() == identity))
    throw std::runtime_error("the CT's direction is not a permutation of its axes: ITK's ray caster cannot take it");
  return orient->GetOutput();
}

/** The volume's outer layer of voxels alone (every other voxel zeroed). */
MuImageType::Pointer
OuterLayer(const MuImageType * mu)
{
  auto layer = MuImageType::New();
  layer->CopyInformation(mu);
  layer->SetRegions(mu->GetLargestPossibleRegion());
  layer->Allocate();
  const auto region = mu->GetLargestPossibleRegion();
  for (itk::ImageRegionIteratorWithIndex<MuImageType> it(layer, region); !it.IsAtEnd(); ++it)
  {
    bool outer = false;
    for (unsigned axis = 0; axis < 3; ++axis)
      outer =
        outer || it.GetIndex()[axis] == region.GetIndex()[axis] || it.GetIndex()[axis] == region.GetUpperIndex()[axis];
    it.Set(outer ? mu->GetPixel(it.GetIndex()) : 0.0f);
  }
  return layer;
}

/** The volume with one more layer of zero voxels on every side: the same trilinear model, but ITK's ray caster then
 * integrates all of it. Its first voxel keeps index 0 (the origin moves instead): the ray caster ignores the start
 * index of the region, as it ignores the direction. */
MuImageType::Pointer
PadWithZeros(const MuImageType * mu)
{
  MuImageType::SizeType oneVoxel;
  oneVoxel.Fill(1);
  auto pad = itk::ConstantPadImageFilter<MuImageType, MuImageType>::New();
  pad->SetInput(mu);
  pad->SetPadBound(oneVoxel);
  pad->SetConstant(0.0f);
  pad->Update();
  MuImageType::Pointer padded = pad->GetOutput();
  padded->DisconnectPipeline();
  MuImageType::PointType firstVoxel;
  padded->TransformIndexToPhysicalPoint(padded->GetLargestPossibleRegion().GetIndex(), firstVoxel);
  padded->SetRegions(padded->GetLargestPossibleRegion().GetSize());
  padded->SetOrigin(firstVoxel);
  return padded;
}

template <typename TRender>
double
WallSeconds(TRender && render)
{
  const auto start = std::chrono::steady_clock::now();
  render();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/** The exact projection of a mu volume: trilinear model, K x K rays per pixel. */
DRRImageType::Pointer
RenderExact(const MuImageType * mu, itk::DRRProjectionGeometry * geometry, unsigned raysPerPixelSide)
{
  auto exact = itk::ExactDRRImageFilter<MuImageType, DRRImageType>::New();
  exact->SetInput(mu);
  exact->SetGeometry(geometry);
  exact->GetTransferFunction()->SetMode(TransferEnum::Identity); // the input is mu already
  exact->SetReconstructionKernel(KernelEnum::Tent);
  exact->SetRaysPerPixelSide(raysPerPixelSide);
  exact->Update();
  return exact->GetOutput();
}

/** ITK's ray caster as ITK's DRR example (Examples/Filtering/DigitallyReconstructedRadiograph1.cxx) uses it: a
 * ResampleImageFilter evaluates an itk::RayCastInterpolateImageFunction at every pixel centre of a one-slice image,
 * which integrates (value - threshold) above the threshold along the line from that point to the focal point. The
 * example turns the volume and keeps the camera on its z axis; here the volume stays put (identity transform) and the
 * camera goes where the geometry puts it: focal point at the source, the one-slice image on the detector (origin at
 * the centre of pixel (0, 0), axes u, v and -n: the module's 3D output placement). The result is copied onto the
 * pixel grid of the module's 2D output (`layout`). */
DRRImageType::Pointer
RayCast(const MuImageType * mu, const itk::DRRProjectionGeometry * geometry, const DRRImageType * layout)
{
  auto identity = itk::IdentityTransform<double, 3>::New();
  auto rayCaster = itk::RayCastInterpolateImageFunction<MuImageType, double>::New();
  rayCaster->SetTransform(identity);
  rayCaster->SetThreshold(0.0); // mu - 0 wherever mu > 0: the line integral of mu
  rayCaster->SetFocalPoint(geometry->GetSourcePosition());

  auto resample = itk::ResampleImageFilter<MuImageType, MuImageType>::New();
  resample->SetInput(mu);
  resample->SetTransform(identity);
  resample->SetInterpolator(rayCaster);
  resample->SetDefaultPixelValue(0.0f);
  const auto detectorSize = geometry->GetDetectorSize();
  resample->SetSize({ { detectorSize[0], detectorSize[1], 1 } });
  MuImageType::SpacingType spacing; // mm
  spacing[0] = geometry->GetDetectorSpacing()[0];
  spacing[1] = geometry->GetDetectorSpacing()[1];
  spacing[2] = 1.0;
  resample->SetOutputSpacing(spacing);
  MuImageType::DirectionType direction;
  for (unsigned row = 0; row < 3; ++row)
  {
    direction[row][0] = geometry->GetColumnDirection()[row];
    direction[row][1] = geometry->GetRowDirection()[row];
    direction[row][2] = -geometry->GetNormal()[row];
  }
  resample->SetOutputDirection(direction);
  resample->SetOutputOrigin(geometry->GetPixelCenter(0.0, 0.0));
  resample->Update();

  auto image = DRRImageType::New();
  image->CopyInformation(layout);
  image->SetRegions(layout->GetLargestPossibleRegion());
  image->Allocate();
  std::copy_n(resample->GetOutput()->GetBufferPointer(),
              image->GetBufferedRegion().GetNumberOfPixels(),
              image->GetBufferPointer());
  return image;
}

size_t
NumberOfPixels(const DRRImageType * image)
{
  return image->GetBufferedRegion().GetNumberOfPixels();
}

/** The pixel-wise difference a - b. */
DRRImageType::Pointer
Difference(const DRRImageType * a, const DRRImageType * b)
{
  auto difference = DRRImageType::New();
  difference->CopyInformation(a);
  difference->SetRegions(a->GetLargestPossibleRegion());
  difference->Allocate();
  for (size_t p = 0; p < NumberOfPixels(a); ++p)
    difference->GetBufferPointer()[p] = a->GetBufferPointer()[p] - b->GetBufferPointer()[p];
  return difference;
}

/** Root mean square over the pixels of an image, or of its difference from another. */
double
RootMeanSquare(const DRRImageType * image, const DRRImageType * minus = nullptr)
{
  double sumOfSquares = 0.0;
  for (size_t p = 0; p < NumberOfPixels(image); ++p)
  {
    const double value = image->GetBufferPointer()[p] - (minus ? minus->GetBufferPointer()[p] : 0.0);
    sumOfSquares += value * value;
  }
  return std::sqrt(sumOfSquares / NumberOfPixels(image));
}

struct Comparison
{
  double Rmse{ 0 }, Range{ 0 }, MaxAbsoluteError{ 0 }, SumRatio{ 1 }; // Range: of the reference
};

Comparison
Compare(const DRRImageType * image, const DRRImageType * reference)
{
  const float * value = image->GetBufferPointer();
  const float * exact = reference->GetBufferPointer();
  double        sum = 0.0, referenceSum = 0.0;
  double        minimum = exact[0], maximum = exact[0];
  Comparison    comparison;
  for (size_t p = 0; p < NumberOfPixels(image); ++p)
  {
    sum += value[p];
    referenceSum += exact[p];
    minimum = std::min<double>(minimum, exact[p]);
    maximum = std::max<double>(maximum, exact[p]);
    comparison.MaxAbsoluteError = std::max<double>(comparison.MaxAbsoluteError, std::abs(value[p] - exact[p]));
  }
  comparison.Rmse = RootMeanSquare(image, reference);
  comparison.Range = maximum - minimum;
  comparison.SumRatio = sum / referenceSum;
  return comparison;
}

/** The RMSE the point-based image should stay below: its standard error (5 spreads of the squared error above its
 * expectation) plus the reference's own error (referenceError). */
double
ExpectedPointBasedRmse(const DRRImageType * standardError, double referenceError, double * effectivePixels)
{
  double sumOfVariances = 0.0, sumOfSquaredVariances = 0.0;
  for (size_t p = 0; p < NumberOfPixels(standardError); ++p)
  {
    const double variance = std::pow(standardError->GetBufferPointer()[p], 2);
    sumOfVariances += variance;
    sumOfSquaredVariances += variance * variance;
  }
  *effectivePixels = sumOfVariances * sumOfVariances / sumOfSquaredVariances;
  const double meanVariance = sumOfVariances / NumberOfPixels(standardError);
  return std::sqrt(meanVariance * (1.0 + 5.0 * std::sqrt(2.0 / *effectivePixels))) + referenceError;
}

void
PrintRow(const std::string & method, double seconds, const Comparison & comparison, double expectedRmse)
{
  std::cout << "| " << std::left << std::setw(26) << method << std::right << " | " << std::fixed << std::setprecision(3)
            << std::setw(13) << seconds << " | " << std::defaultfloat << std::setprecision(4) << std::setw(10)
            << comparison.Rmse << " | " << std::setw(9) << 100.0 * comparison.Rmse / comparison.Range << " | ";
  if (expectedRmse > 0.0)
    std::cout << "<= " << std::setw(15) << 100.0 * expectedRmse / comparison.Range;
  else
    std::cout << std::setw(18) << "";
  std::cout << " | " << std::setw(13) << comparison.MaxAbsoluteError << " | " << std::setprecision(6) << std::setw(9)
            << comparison.SumRatio << " |\n";
}
} // namespace

int
main(int argc, char * argv[])
{
  try
  {
    const Options options = ParseOptions(argc, argv);
    const auto    ct = options.Phantom ? MakePhantom() : itk::ReadImage<CTImageType>(options.Input);
    const auto    mu = WithIdentityDirection(ToMu(ct));

    // The view, shared by the module's two filters and copied into the ray caster's set-up.
    const auto volumeSize = mu->GetLargestPossibleRegion().GetSize();
    double     extent = 0.0, diagonal = 0.0; // mm
    for (unsigned axis = 0; axis < 3; ++axis)
    {
      extent = std::max(extent, volumeSize[axis] * mu->GetSpacing()[axis]);
      diagonal += std::pow(volumeSize[axis] * mu->GetSpacing()[axis], 2);
    }
    auto geometry = itk::DRRProjectionGeometry::New();
    geometry->SetGantryAngleInDegrees(options.GantryInDegrees);
    geometry->SetSourceToIsocenterDistance(1000.0); // mm
    geometry->SetSourceToDetectorDistance(1500.0);  // mm
    geometry->SetIsocenterToImageCenter(mu);
    geometry->SetDetectorSize({ { options.DetectorPixels, options.DetectorPixels } });
    const double largestMagnification = 1500.0 / (1000.0 - 0.5 * std::sqrt(diagonal)); // at the volume's nearest point
    const double pixelSpacing = options.PixelSpacingInMillimeters > 0.0
                                  ? options.PixelSpacingInMillimeters
                                  : 1.1 * extent * largestMagnification / options.DetectorPixels;
    geometry->SetDetectorSpacing(itk::Vector<double, 2>(pixelSpacing));
    geometry->VerifyGeometry();

    // 1. The reference.
    DRRImageType::Pointer exact;
    const double exactSeconds = WallSeconds([&] { exact = RenderExact(mu, geometry, options.RaysPerPixelSide); });

    // 2. Point-based, same model (tent kernel).
    auto pointBased = itk::PointBasedDRRImageFilter<MuImageType, DRRImageType>::New();
    pointBased->SetInput(mu);
    pointBased->SetGeometry(geometry);
    pointBased->GetTransferFunction()->SetMode(TransferEnum::Identity);
    pointBased->SetReconstructionKernel(KernelEnum::Tent);
    pointBased->SetNumberOfSamples(static_cast<uint64_t>(options.Samples));
    pointBased->SetSeed(options.Seed);
    const double pointBasedSeconds = WallSeconds([&] { pointBased->Update(); });

    // 3. ITK's ray caster.
    DRRImageType::Pointer rayCast;
    const double          rayCastSeconds = WallSeconds([&] { rayCast = RayCast(mu, geometry, exact); });

    // What to expect (see the comment at the top).
    const auto   oneRay = RenderExact(mu, geometry, 1);
    const double oneRayError = RootMeanSquare(oneRay, exact);
    const double rectangleRuleError = RootMeanSquare(RayCast(PadWithZeros(mu), geometry, exact), oneRay);
    const double outerLayer = RootMeanSquare(RenderExact(OuterLayer(mu), geometry, 1));
    const double referenceError = oneRayError / options.RaysPerPixelSide;
    double       effectivePixels = 0.0;
    const double expectedPointBasedRmse =
      ExpectedPointBasedRmse(pointBased->GetStandardErrorOutput(), referenceError, &effectivePixels);
    const double expectedRayCastRmse = oneRayError + rectangleRuleError + outerLayer;

    const std::string prefix = options.OutputPrefix;
    itk::WriteImage(exact, prefix + "_exact.mha");
    itk::WriteImage(pointBased->GetOutput(), prefix + "_pointbased.mha");
    itk::WriteImage(rayCast, prefix + "_raycast.mha");
    itk::WriteImage(Difference(pointBased->GetOutput(), exact), prefix + "_pointbased_error.mha");
    itk::WriteImage(Difference(rayCast, exact), prefix + "_raycast_error.mha");

    const auto & spacing = mu->GetSpacing();
    std::cout << "volume: " << volumeSize[0] << " x " << volumeSize[1] << " x " << volumeSize[2] << " voxels of "
              << spacing[0] << " x " << spacing[1] << " x " << spacing[2] << " mm, mu of water at 60 keV\n"
              << "view: gantry " << options.GantryInDegrees << " degrees, SAD 1000 mm, SID 1500 mm, "
              << options.DetectorPixels << " x " << options.DetectorPixels << " pixels of " << pixelSpacing << " mm\n"
              << "reference: ExactDRRImageFilter, trilinear model, " << options.RaysPerPixelSide << " x "
              << options.RaysPerPixelSide << " rays per pixel; pixels are line integrals of mu (no unit)\n\n"
              << "| method                     | wall time (s) |       RMSE | NRMSE (%) | expected NRMSE (%) | "
                 "max abs error | sum ratio |\n"
              << "|----------------------------|---------------|------------|-----------|--------------------|"
                 "---------------|-----------|\n";
    PrintRow("exact (reference)", exactSeconds, Compare(exact, exact), 0.0);
    std::ostringstream pointBasedName;
    pointBasedName << "point-based, " << std::setprecision(3) << options.Samples << " points";
    PrintRow(pointBasedName.str(), pointBasedSeconds, Compare(pointBased->GetOutput(), exact), expectedPointBasedRmse);
    PrintRow("ITK ray caster", rayCastSeconds, Compare(rayCast, exact), expectedRayCastRmse);
    std::cout << std::setprecision(3) << "\nexpected RMSE, point-based: its standard-error image (RMS "
              << RootMeanSquare(pointBased->GetStandardErrorOutput()) << ") over " << std::llround(effectivePixels)
              << " effective pixels, + 5 spreads,\n  + the reference's own error (one-ray error / "
              << options.RaysPerPixelSide << ": " << referenceError << ")\n"
              << "expected RMSE, ray caster: one ray per pixel, not the pixel average (RMS " << oneRayError
              << ") + its rectangle rule (RMS " << rectangleRuleError
              << ")\n  + the outer half voxel it drops (at most the projection of the outer voxel layer: RMS "
              << outerLayer << ")\n"
              << "wrote " << prefix << "_{exact,pointbased,raycast,pointbased_error,raycast_error}.mha\n";
  }
  catch (const std::exception & error)
  {
    std::cerr << "CompareWithRayCast: " << error.what() << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
