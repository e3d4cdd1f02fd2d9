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
// ITK's classic 2D-3D registration, the third method of benchmark/registration.sh, on the X-rays pbdrr register takes,
// and the bone points the benchmark's target registration error is measured over.
//
//   PointBasedDRRRegistrationClassic CT --xray X --geometry G [--xray X --geometry G] --start TX TY TZ RX RY RZ
//                                    [--iterations 6] [--threads N]
//   PointBasedDRRRegistrationClassic CT --bone-points N [--bone-hu 300] [--seed S] -o POINTS.txt
//
// The registration: the CT converted to mu (1/mm) exactly as the DRR filters convert it, re-oriented to an identity
// direction (ITK's ray caster ignores the direction); per X-ray, a NormalizedCorrelationImageToImageMetric between the
// X-ray, as a one-slice 3D image placed on its detector plane, and the CT seen through an
// itk::RayCastInterpolateImageFunction (threshold 0) whose focal point is the view's source: one ray per X-ray pixel
// per evaluation, as in ITK's 2D-3D registration examples; their sum as the cost, minimized by itk::PowellOptimizer,
// the classic framework's derivative-free optimizer (the ray caster has no derivative), over an Euler3DTransform
// centred on the CT (one optimizer unit: 1 mm or 1 degree; steps of 2, tolerance 0.02, at most --iterations
// iterations). The transform maps the room to the CT, as the interpolator takes it; the pose printed is its inverse,
// the CT moved in the room as pbdrr register prints it:
//   pose: tx ty tz rx ry rz
//   time: T s, E evaluations, D DRRs
//
// The bone points: N voxels of HU >= --bone-hu drawn at random (seeded) from the CT, their physical points (mm, the
// CT's frame), one "x y z" a line, after a line "# centre x y z": the centre of the CT's grid, about which poses turn.
#include "pbdrrBenchmarkSupport.h"
#include "pbdrrRegistration.h"
#include "pbdrrVolumeLoader.h"

#include "itkDRRImageToAttenuationVolumeFilter.h"
#include "itkEuler3DTransform.h"
#include "itkNormalizedCorrelationImageToImageMetric.h"
#include "itkOrientImageFilter.h"
#include "itkPowellOptimizer.h"
#include "itkRayCastInterpolateImageFunction.h"
#include "itkSingleValuedCostFunction.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using pbdrr::bench::MuImageType;
using FixedImageType = itk::Image<float, 3>; // an X-ray as a one-slice image on its detector plane
using TransformType = itk::Euler3DTransform<double>;
using MetricType = itk::NormalizedCorrelationImageToImageMetric<FixedImageType, MuImageType>;
using InterpolatorType = itk::RayCastInterpolateImageFunction<MuImageType, double>;
constexpr double degree = 3.14159265358979323846 / 180.0;

struct Options
{
  std::string              Input;
  std::vector<std::string> XRays, Geometries;
  std::vector<double>      Start;
  unsigned                 Iterations{ 6 }, Threads{ 0 }, BonePoints{ 0 }, Seed{ 1 };
  double                   BoneHU{ 300.0 };
  std::string              Output;
};

Options
ParseOptions(int argc, char * argv[])
{
  Options options;
  for (int a = 1; a < argc; ++a)
  {
    const std::string arg = argv[a];
    const auto        value = [&]() -> std::string {
      if (a + 1 >= argc)
        throw std::runtime_error(arg + " needs a value");
      return argv[++a];
    };
    if (arg == "--xray")
      options.XRays.push_back(value());
    else if (arg == "--geometry")
      options.Geometries.push_back(value());
    else if (arg == "--start")
      for (int k = 0; k < 6; ++k)
        options.Start.push_back(std::stod(value()));
    else if (arg == "--iterations")
      options.Iterations = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--threads")
      options.Threads = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--bone-points")
      options.BonePoints = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--bone-hu")
      options.BoneHU = std::stod(value());
    else if (arg == "--seed")
      options.Seed = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "-o")
      options.Output = value();
    else if (!arg.empty() && arg[0] == '-')
      throw std::runtime_error("unknown option " + arg);
    else
      options.Input = arg;
  }
  if (options.Input.empty())
    throw std::runtime_error("give a CT (a DICOM series directory or a volume)");
  if (options.BonePoints > 0 ? options.Output.empty() : (options.XRays.empty() || options.Start.size() != 6))
    throw std::runtime_error("give --xray X --geometry G ... --start (6 numbers), or --bone-points N -o FILE");
  if (options.XRays.size() != options.Geometries.size())
    throw std::runtime_error("give one --geometry per --xray");
  return options;
}

/** The CT as float values (HU), whatever it was read as. */
pbdrr::VolumeType::Pointer
ReadHU(const std::string & input)
{
  return pbdrr::LoadVolume(input, "").AsFloat();
}

/** N bone voxels' physical points, drawn at random (seeded) among the voxels of HU >= the threshold. */
void
WriteBonePoints(const pbdrr::VolumeType * ct, const Options & options)
{
  std::vector<size_t> bone;
  const float *       hu = ct->GetBufferPointer();
  for (size_t v = 0; v < ct->GetBufferedRegion().GetNumberOfPixels(); ++v)
    if (hu[v] >= options.BoneHU)
      bone.push_back(v);
  if (bone.empty())
    throw std::runtime_error("no voxel of the CT reaches " + std::to_string(options.BoneHU) + " HU");
  std::mt19937                          random(options.Seed);
  std::uniform_int_distribution<size_t> pick(0, bone.size() - 1);
  std::ofstream                         out(options.Output);
  const auto                            size = ct->GetLargestPossibleRegion().GetSize();
  const auto                            centre = itk::DRRProjectionGeometry::ComputeImageCenter(ct);
  out << std::setprecision(10) << "# centre " << centre[0] << " " << centre[1] << " " << centre[2] << "\n";
  for (unsigned k = 0; k < options.BonePoints; ++k)
  {
    const size_t                 v = bone[pick(random)];
    pbdrr::VolumeType::IndexType index{ { static_cast<itk::IndexValueType>(v % size[0]),
                                          static_cast<itk::IndexValueType>(v / size[0] % size[1]),
                                          static_cast<itk::IndexValueType>(v / (size[0] * size[1])) } };
    for (unsigned a = 0; a < 3; ++a)
      index[a] += ct->GetLargestPossibleRegion().GetIndex()[a];
    pbdrr::VolumeType::PointType point;
    ct->TransformIndexToPhysicalPoint(index, point);
    out << std::setprecision(10) << point[0] << " " << point[1] << " " << point[2] << "\n";
  }
  out.close();
  if (!out)
    throw std::runtime_error("cannot write " + options.Output);
}

/** mu (1/mm) as the DRR filters compute it, on an identity direction (the same voxels at the same places). */
MuImageType::Pointer
MuWithIdentityDirection(const pbdrr::VolumeType * ct)
{
  auto stage = itk::DRRImageToAttenuationVolumeFilter<pbdrr::VolumeType>::New();
  stage->SetInput(ct);
  stage->Update();
  MuImageType::Pointer       mu = pbdrr::bench::MuImage(ct, stage->GetOutput());
  MuImageType::DirectionType identity;
  identity.SetIdentity();
  if (mu->GetDirection() == identity)
    return mu;
  auto orient = itk::OrientImageFilter<MuImageType, MuImageType>::New();
  orient->SetInput(mu);
  orient->UseImageDirectionOn();
  orient->SetDesiredCoordinateDirection(identity);
  orient->Update();
  MuImageType::Pointer oriented = orient->GetOutput();
  if (!(oriented->GetDirection() == identity))
    throw std::runtime_error("the CT's direction is not a permutation of the axes: ITK's ray caster cannot take it");
  return oriented;
}

/** An X-ray as a one-slice 3D image on its detector plane: origin at the centre of pixel (0, 0), direction (u, v, -n),
 * spacing (du, dv, 1), so that the ray from the source through a pixel's point is the view's ray. */
FixedImageType::Pointer
PlacedOnDetector(const itk::Image<float, 2> * xray, const itk::DRRProjectionGeometry * geometry)
{
  auto                          placed = FixedImageType::New();
  const auto                    size = geometry->GetDetectorSize();
  FixedImageType::SizeType      size3{ { size[0], size[1], 1 } };
  FixedImageType::SpacingType   spacing;
  FixedImageType::PointType     origin;
  FixedImageType::DirectionType direction;
  const auto                    pixel00 = geometry->GetPixelCenter(0.0, 0.0);
  const auto u = geometry->GetColumnDirection(), v = geometry->GetRowDirection(), n = geometry->GetNormal();
  for (unsigned r = 0; r < 3; ++r)
  {
    origin[r] = pixel00[r];
    direction[r][0] = u[r];
    direction[r][1] = v[r];
    direction[r][2] = -n[r];
  }
  spacing[0] = geometry->GetDetectorSpacing()[0];
  spacing[1] = geometry->GetDetectorSpacing()[1];
  spacing[2] = 1.0;
  placed->SetRegions(size3);
  placed->SetSpacing(spacing);
  placed->SetOrigin(origin);
  placed->SetDirection(direction);
  placed->Allocate();
  std::copy(xray->GetBufferPointer(), xray->GetBufferPointer() + size[0] * size[1], placed->GetBufferPointer());
  return placed;
}

/** The sum of the views' metrics, counting evaluations. */
class MultiViewCost : public itk::SingleValuedCostFunction
{
public:
  ITK_DISALLOW_COPY_AND_MOVE(MultiViewCost);
  using Self = MultiViewCost;
  using Superclass = itk::SingleValuedCostFunction;
  using Pointer = itk::SmartPointer<Self>;
  itkNewMacro(Self);

  std::vector<MetricType::Pointer> Metrics;
  mutable unsigned                 Evaluations{ 0 };

  MeasureType
  GetValue(const ParametersType & parameters) const override
  {
    ++Evaluations;
    MeasureType sum = 0.0;
    for (const auto & metric : Metrics)
      sum += metric->GetValue(parameters);
    return sum;
  }
  void
  GetDerivative(const ParametersType &, DerivativeType &) const override
  {
    itkExceptionMacro("no derivative: the ray caster has none");
  }
  unsigned
  GetNumberOfParameters() const override
  {
    return 6;
  }

protected:
  MultiViewCost() = default;
};

/** The pose (pbdrr's: the CT moved in the room, tx ty tz mm, rx ry rz degrees) as a transform about centre. */
TransformType::Pointer
PoseTransform(const std::vector<double> & pose, const itk::Point<double, 3> & centre)
{
  auto transform = TransformType::New();
  transform->SetCenter(centre);
  TransformType::ParametersType parameters(6);
  for (unsigned k = 0; k < 3; ++k)
  {
    parameters[k] = pose[k + 3] * degree;
    parameters[k + 3] = pose[k];
  }
  transform->SetParameters(parameters);
  return transform;
}

void
Register(const pbdrr::VolumeType * ct, const Options & options)
{
  const MuImageType::Pointer mu = MuWithIdentityDirection(ct);
  const auto                 centre = itk::DRRProjectionGeometry::ComputeImageCenter(ct);
  // The room-to-CT transform the metric and the interpolator share: the inverse of the start pose.
  auto transform = TransformType::New();
  PoseTransform(options.Start, centre)->GetInverse(transform);

  auto cost = MultiViewCost::New();
  for (size_t x = 0; x < options.XRays.size(); ++x)
  {
    const pbdrr::XRay xray = pbdrr::ReadXRay(options.XRays[x], options.Geometries[x], "", ct);
    auto              interpolator = InterpolatorType::New();
    interpolator->SetTransform(transform);
    interpolator->SetThreshold(0.0);
    InterpolatorType::InputPointType focal;
    const auto                       source = xray.Geometry->GetSourcePosition();
    for (unsigned r = 0; r < 3; ++r)
      focal[r] = source[r];
    interpolator->SetFocalPoint(focal);
    const FixedImageType::Pointer fixed = PlacedOnDetector(xray.Image, xray.Geometry);
    auto                          metric = MetricType::New();
    metric->SetFixedImage(fixed);
    metric->SetFixedImageRegion(fixed->GetLargestPossibleRegion());
    metric->SetMovingImage(mu);
    metric->SetTransform(transform);
    metric->SetInterpolator(interpolator);
    metric->SetSubtractMean(true);
    metric->Initialize();
    cost->Metrics.push_back(metric);
  }

  auto optimizer = itk::PowellOptimizer::New();
  optimizer->SetCostFunction(cost);
  optimizer->SetInitialPosition(transform->GetParameters());
  itk::PowellOptimizer::ScalesType scales(6);
  for (unsigned k = 0; k < 6; ++k)
    scales[k] = k < 3 ? 1.0 / degree : 1.0; // one unit: one degree or one millimetre
  optimizer->SetScales(scales);
  optimizer->SetMaximize(false);
  optimizer->SetStepLength(2.0);
  optimizer->SetStepTolerance(0.02);
  optimizer->SetValueTolerance(1e-6);
  optimizer->SetMaximumIteration(options.Iterations);
  const double begin = pbdrr::bench::Now();
  optimizer->StartOptimization();
  const double seconds = pbdrr::bench::Now() - begin;

  transform->SetParameters(optimizer->GetCurrentPosition());
  auto pose = TransformType::New();
  transform->GetInverse(pose);
  // The inverse's parameters about its own centre: re-expressed about the CT's centre.
  auto about = TransformType::New();
  about->SetCenter(centre);
  about->SetMatrix(pose->GetMatrix());
  about->SetOffset(pose->GetOffset());
  const auto p = about->GetParameters();
  std::cout << std::fixed << std::setprecision(4) << "pose: " << p[3] << " " << p[4] << " " << p[5] << " "
            << p[0] / degree << " " << p[1] / degree << " " << p[2] / degree << "\n"
            << std::setprecision(2) << "time: " << seconds << " s, " << cost->Evaluations << " evaluations, "
            << cost->Evaluations * options.XRays.size() << " DRRs" << std::endl;
}
} // namespace

int
main(int argc, char * argv[])
{
  try
  {
    const Options options = ParseOptions(argc, argv);
    if (options.Threads > 0)
      itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(options.Threads);
    const pbdrr::VolumeType::Pointer ct = ReadHU(options.Input);
    if (options.BonePoints > 0)
      WriteBonePoints(ct, options);
    else
      Register(ct, options);
    return 0;
  }
  catch (const std::exception & error)
  {
    std::cerr << "PointBasedDRRRegistrationClassic: " << error.what() << std::endl;
    return 1;
  }
}
