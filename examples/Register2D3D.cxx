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
// Rigid 2D-3D registration of a CT to one or two X-ray projections, two ways:
//
// - `--method class` (the default): itk::PointBasedDRRRegistrationMethod, the library's registration, the one
//   `pbdrr register` runs: kept points (`--drr pbdrr`) or the exact projector (`--drr exact`), gradient correlation
//   or NCC (`--metric`), Powell's method on a multi-resolution schedule (`--shrink`). See Register().
// - `--method classic`: ITK's classic registration components with the DRRs cast by ITK's ray caster or rendered by
//   PointBasedDRR, and the two differ by one type (see RegisterClassic()). ITK's DRR interpolator,
//   itk::RayCastInterpolateImageFunction, is an InterpolateImageFunction evaluated by a classic ImageToImageMetric,
//   one ray per fixed-image pixel, and it has no derivative; the ITKv4 metrics need the moving image's gradient. So: a
//   MeanSquaresImageToImageMetric per view (fixed image: the projection as a one-slice 3D image placed on the detector
//   plane; moving image: the CT in mu; the interpolator: the DRR), their sum as the cost, Powell's derivative-free
//   optimizer over the 6 parameters of an Euler3DTransform centred on the volume. MeanSquares (not
//   NormalizedCorrelation) because it is multi-threaded in ITK's classic framework, which keeps the ray caster's
//   timing fair, and the synthetic target has the DRRs' units. scripts/registration-benchmark.sh measures this way.
//
//   Register2D3D CT|--phantom [--method class|classic] [--drr pbdrr|exact|raycast] [--views 1|2] [--size 128]
//                [--pixel-mm MM] [--samples 2e6] [--control-variate F] [--metric gc|ncc] [--shrink 2,1]
//                [--start tx,ty,tz,rx,ry,rz | --random-start SEED] [--max-translation 10] [--max-rotation 5]
//                [--max-tre MM] [--iterations 6] [--threads N]
//                [--fixed AP.mha --focal x,y,z [--fixed LAT.mha --focal x,y,z]]
//
// --drr: pbdrr (default) or exact with the class, pbdrr or raycast with the classic components; --metric and
// --shrink are the class's, --iterations, --control-variate and --fixed the classic components'.
//
// CT: a DICOM series directory or a volume ITK reads (HU); --phantom: a coarse built-in CT. The CT is converted to
// linear attenuation mu (1/mm, water at 60 keV), which every DRR method integrates along its rays (threshold 0; the
// class with the identity transfer function and the targets' trilinear model).
// Synthetic X-ray mode (the default): the target projections are rendered at the true pose (the identity: the CT
// where it lies) by the exact projector (ExactDRRImageFilter, trilinear model, 2 x 2 rays per pixel), AP and lateral,
// SAD 1000 mm, SID 1500 mm; the registration starts at the given or random offset (translation up to
// --max-translation mm, rotation up to --max-rotation degrees about a random axis) and its error is known. With
// --fixed, real projections (line integrals, one-slice 3D images placed in the room) and their focal points are used
// and the result is printed without an error (classic components only: the class needs each projection's view, a
// DRRProjectionGeometry, not only its focal point).
//
// Prints one line `result key=value ...`: the start and final mean target registration error (mTRE, mm; over 27
// points on a grid spanning the central 80% of the CT), success (final mTRE < 2 mm), the number of cost evaluations
// and of DRRs rendered, and the wall time. With --max-tre, exits non-zero if the final mTRE exceeds it.
#include "itkPointBasedDRRInterpolateImageFunction.h"
#include "itkPointBasedDRRRegistrationMethod.h"
#include "itkDRRImageSimilarity.h"
#include "itkExactDRRImageFilter.h"

#include "itkEuler3DTransform.h"
#include "itkGDCMImageIO.h"
#include "itkGDCMSeriesFileNames.h"
#include "itkImageFileReader.h"
#include "itkImageSeriesReader.h"
#include "itkMeanSquaresImageToImageMetric.h"
#include "itkOrientImageFilter.h"
#include "itkPowellOptimizer.h"
#include "itkRayCastInterpolateImageFunction.h"
#include "itkSingleValuedCostFunction.h"
#include "itksys/SystemTools.hxx"

#include <chrono>
#include <ctime>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using CTType = itk::Image<float, 3>;         // HU as read
using MuImageType = itk::Image<float, 3>;    // mu, 1/mm
using ProjectionType = itk::Image<float, 3>; // one slice on the detector plane, line integrals
using TransformType = itk::Euler3DTransform<double>;
using MetricType = itk::MeanSquaresImageToImageMetric<ProjectionType, MuImageType>;

struct View
{
  ProjectionType::Pointer             Image; // for the classic components
  itk::Point<double, 3>               FocalPoint;
  itk::Image<float, 2>::Pointer       XRay; // for the class: the same pixels, and their view
  itk::DRRProjectionGeometry::Pointer Geometry;
};

struct Options
{
  std::string              Input;
  bool                     Phantom{ false };
  std::string              Method{ "class" };
  std::string              Drr{ "pbdrr" };
  std::string              Metric{ "gc" };
  std::vector<unsigned>    Shrink{ 2, 1 };
  unsigned                 Views{ 2 }, Size{ 128 }, Iterations{ 6 }, Threads{ 0 };
  unsigned                 ControlVariate{ 0 }; // PBDRR: coarsening factor F (0: off); box kernel then
  double                   PixelMillimetres{ 0.0 }, Samples{ 2e6 }, MaxTranslation{ 10.0 }, MaxRotation{ 5.0 };
  double                   MaxTre{ -1.0 };
  std::vector<double>      Start;
  long                     RandomStart{ -1 };
  std::vector<std::string> Fixed;
  std::vector<std::string> Focal;
};

std::vector<double>
ParseList(const std::string & text, size_t count, const std::string & what)
{
  std::vector<double> values;
  std::stringstream   in(text);
  for (std::string item; std::getline(in, item, ',');)
  {
    values.push_back(std::stod(item));
  }
  if (count > 0 ? values.size() != count : values.empty())
  {
    throw std::runtime_error(what + " needs " + std::to_string(count) + " comma-separated numbers: " + text);
  }
  return values;
}

Options
ParseOptions(int argc, char * argv[])
{
  Options options;
  for (int a = 1; a < argc; ++a)
  {
    const std::string arg = argv[a];
    const auto        value = [&]() -> std::string {
      if (a + 1 >= argc)
      {
        throw std::runtime_error(arg + " needs a value");
      }
      return argv[++a];
    };
    if (arg == "--phantom")
      options.Phantom = true;
    else if (arg == "--method")
      options.Method = value();
    else if (arg == "--drr")
      options.Drr = value();
    else if (arg == "--metric")
      options.Metric = value();
    else if (arg == "--shrink")
    {
      options.Shrink.clear();
      for (const double factor : ParseList(value(), 0, "--shrink"))
        options.Shrink.push_back(static_cast<unsigned>(factor));
    }
    else if (arg == "--views")
      options.Views = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--size")
      options.Size = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--pixel-mm")
      options.PixelMillimetres = std::stod(value());
    else if (arg == "--samples")
      options.Samples = std::stod(value());
    else if (arg == "--control-variate")
      options.ControlVariate = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--start")
      options.Start = ParseList(value(), 6, "--start");
    else if (arg == "--random-start")
      options.RandomStart = std::stol(value());
    else if (arg == "--max-translation")
      options.MaxTranslation = std::stod(value());
    else if (arg == "--max-rotation")
      options.MaxRotation = std::stod(value());
    else if (arg == "--max-tre")
      options.MaxTre = std::stod(value());
    else if (arg == "--iterations")
      options.Iterations = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--threads")
      options.Threads = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--fixed")
      options.Fixed.push_back(value());
    else if (arg == "--focal")
      options.Focal.push_back(value());
    else if (!arg.empty() && arg[0] == '-')
      throw std::runtime_error("unknown option " + arg);
    else
      options.Input = arg;
  }
  if (options.Input.empty() == !options.Phantom)
    throw std::runtime_error("give a CT (DICOM directory or volume) or --phantom");
  if (options.Method != "class" && options.Method != "classic")
    throw std::runtime_error("--method is class or classic, not " + options.Method);
  if (options.Method == "class" && options.Drr != "pbdrr" && options.Drr != "exact")
    throw std::runtime_error("--method class renders with --drr pbdrr or exact, not " + options.Drr);
  if (options.Method == "classic" && options.Drr != "pbdrr" && options.Drr != "raycast")
    throw std::runtime_error("--method classic renders with --drr pbdrr or raycast, not " + options.Drr);
  if (options.Method == "class" && !options.Fixed.empty())
    throw std::runtime_error("--fixed gives focal points, not views: use --method classic");
  if (!itk::DRRImageSimilarity::IsMetricName(options.Metric))
    throw std::runtime_error("--metric is " + itk::DRRImageSimilarity::JoinMetricNames(" or ") + ", not " +
                             options.Metric);
  if (options.Views < 1 || options.Views > 2)
    throw std::runtime_error("--views is 1 or 2");
  if (options.Fixed.size() != options.Focal.size())
    throw std::runtime_error("give one --focal per --fixed image");
  if (!(options.Samples >= 1.0) || options.Size < 8)
    throw std::runtime_error("--samples must be at least 1 and --size at least 8");
  return options;
}

/** A DICOM series directory (its first series) or any volume ITK reads. */
CTType::Pointer
ReadCT(const std::string & input)
{
  if (!itksys::SystemTools::FileIsDirectory(input))
  {
    return itk::ReadImage<CTType>(input);
  }
  auto names = itk::GDCMSeriesFileNames::New();
  names->SetUseSeriesDetails(true);
  names->SetDirectory(input);
  const auto & series = names->GetSeriesUIDs();
  if (series.empty())
  {
    throw std::runtime_error("no DICOM series in " + input);
  }
  auto reader = itk::ImageSeriesReader<CTType>::New();
  reader->SetImageIO(itk::GDCMImageIO::New());
  reader->SetFileNames(names->GetFileNames(series.front()));
  reader->Update();
  return reader->GetOutput();
}

/** The same voxels at the same places with an identity direction matrix (axes permuted and flipped): ITK's ray caster
 * ignores the direction. */
CTType::Pointer
WithIdentityDirection(CTType * ct)
{
  CTType::DirectionType identity;
  identity.SetIdentity();
  if (ct->GetDirection() == identity)
  {
    return ct;
  }
  auto orient = itk::OrientImageFilter<CTType, CTType>::New();
  orient->SetInput(ct);
  orient->UseImageDirectionOn();
  orient->SetDesiredCoordinateDirection(identity);
  orient->Update();
  CTType::Pointer oriented = orient->GetOutput();
  if (!(oriented->GetDirection() == identity))
  {
    throw std::runtime_error("the CT's direction is not a permutation of the axes: ITK's ray caster cannot take it");
  }
  return oriented;
}

/** A coarse CT of a torso (HU): a water ellipse cylinder with an off-centre spine, a rib block on one side and a dense
 * marker, in air; asymmetric so that every rotation shows. 48 x 40 x 36 voxels of 5 mm. */
CTType::Pointer
MakePhantom()
{
  auto                ct = CTType::New();
  CTType::SizeType    size{ { 48, 40, 36 } };
  CTType::SpacingType spacing(5.0);
  CTType::PointType   origin;
  for (unsigned a = 0; a < 3; ++a)
    origin[a] = -0.5 * (size[a] - 1) * spacing[a];
  ct->SetRegions(size);
  ct->SetSpacing(spacing);
  ct->SetOrigin(origin);
  ct->Allocate();
  for (itk::ImageRegionIteratorWithIndex<CTType> it(ct, ct->GetLargestPossibleRegion()); !it.IsAtEnd(); ++it)
  {
    CTType::PointType p;
    ct->TransformIndexToPhysicalPoint(it.GetIndex(), p);
    const double x = p[0], y = p[1], z = p[2];
    float        hu = -1000.0f;
    if ((x / 100) * (x / 100) + (y / 80) * (y / 80) < 1.0 && std::abs(z) < 80)
      hu = 20.0f;
    if ((x - 5) * (x - 5) + (y - 45) * (y - 45) < 14 * 14 && std::abs(z) < 75)
      hu = 700.0f; // spine, posterior
    if (x > 40 && x < 75 && y > -40 && y < 20 && z > -30 && z < 50)
      hu = 400.0f; // rib block, one side
    if ((x + 50) * (x + 50) + (y + 30) * (y + 30) + (z - 40) * (z - 40) < 12 * 12)
      hu = 1500.0f; // marker
    it.Set(hu);
  }
  return ct;
}

/** mu (1/mm) of water at 60 keV times (1 + HU / 1000), zero below -1000 HU: PointBasedDRR's natural transfer. */
MuImageType::Pointer
ToMu(const CTType * ct)
{
  auto transfer = itk::DRRTransferFunction::New();
  auto mu = MuImageType::New();
  mu->CopyInformation(ct);
  mu->SetRegions(ct->GetLargestPossibleRegion());
  mu->Allocate();
  const float * in = ct->GetBufferPointer();
  float *       out = mu->GetBufferPointer();
  for (size_t v = 0; v < ct->GetBufferedRegion().GetNumberOfPixels(); ++v)
    out[v] = static_cast<float>(transfer->Evaluate(in[v]));
  return mu;
}

/** Synthetic X-rays: AP (gantry 90) and lateral (gantry 0) exact projections of the CT at the true pose. */
std::vector<View>
RenderTargets(const MuImageType * mu, const Options & options)
{
  const auto size = mu->GetLargestPossibleRegion().GetSize();
  double     extent = 0.0;
  for (unsigned a = 0; a < 3; ++a)
    extent = std::max(extent, size[a] * mu->GetSpacing()[a]);
  const double      pixel = options.PixelMillimetres > 0 ? options.PixelMillimetres : 1.5 * 1.1 * extent / options.Size;
  std::vector<View> views;
  for (unsigned v = 0; v < options.Views; ++v)
  {
    auto exact = itk::ExactDRRImageFilter<MuImageType, ProjectionType>::New();
    exact->SetInput(mu);
    exact->GetTransferFunction()->SetMode(itk::PointBasedDRREnums::TransferFunction::Identity);
    exact->SetReconstructionKernel(itk::PointBasedDRREnums::ReconstructionKernel::Tent);
    exact->SetRaysPerPixelSide(2);
    auto geometry = exact->GetGeometry();
    geometry->SetGantryAngleInDegrees(v == 0 ? 90.0 : 0.0);
    geometry->SetSourceToIsocenterDistance(1000.0);
    geometry->SetSourceToDetectorDistance(1500.0);
    geometry->SetIsocenterToImageCenter(mu);
    geometry->SetDetectorSize({ { options.Size, options.Size } });
    geometry->SetDetectorSpacing(itk::Vector<double, 2>(pixel));
    exact->Update();
    View view;
    view.Image = exact->GetOutput();
    view.FocalPoint = geometry->GetSourcePosition();
    // The same pixels as a 2D image (a one-slice image's buffer is the 2D image's), with their view.
    view.XRay = itk::Image<float, 2>::New();
    view.XRay->SetRegions(itk::Size<2>{ { options.Size, options.Size } });
    view.XRay->Allocate();
    std::copy(view.Image->GetBufferPointer(),
              view.Image->GetBufferPointer() + view.XRay->GetBufferedRegion().GetNumberOfPixels(),
              view.XRay->GetBufferPointer());
    view.Geometry = geometry;
    views.push_back(view);
  }
  return views;
}

std::vector<View>
ReadTargets(const Options & options)
{
  std::vector<View> views;
  for (size_t v = 0; v < options.Fixed.size(); ++v)
  {
    View view;
    view.Image = itk::ReadImage<ProjectionType>(options.Fixed[v]);
    const auto focal = ParseList(options.Focal[v], 3, "--focal");
    for (unsigned r = 0; r < 3; ++r)
      view.FocalPoint[r] = focal[r];
    views.push_back(view);
  }
  return views;
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
    itkExceptionMacro("no derivative: use a derivative-free optimizer");
  }
  unsigned
  GetNumberOfParameters() const override
  {
    return 6;
  }

protected:
  MultiViewCost() = default;
};

/** Mean distance (mm) between where two poses put 27 points spanning the central 80% of the CT. */
double
MeanTargetError(const MuImageType * mu, const TransformType * pose, const TransformType * truth)
{
  const auto size = mu->GetLargestPossibleRegion().GetSize();
  double     sum = 0.0;
  for (int i = 0; i < 27; ++i)
  {
    itk::ContinuousIndex<double, 3> index;
    for (unsigned a = 0; a < 3; ++a)
    {
      const int step = (a == 0 ? i : a == 1 ? i / 3 : i / 9) % 3;
      index[a] = (size[a] - 1) * (0.1 + 0.4 * step);
    }
    itk::Point<double, 3> p;
    mu->TransformContinuousIndexToPhysicalPoint(index, p);
    sum += (pose->TransformPoint(p) - truth->TransformPoint(p)).GetNorm();
  }
  return sum / 27.0;
}

/** The start: the given offset, or a random translation (uniform direction, length up to the maximum) and rotation
 * (uniform axis, angle up to the maximum). */
TransformType::Pointer
StartPose(const Options & options, const itk::Point<double, 3> & centre)
{
  auto start = TransformType::New();
  start->SetCenter(centre);
  TransformType::ParametersType parameters(6);
  parameters.Fill(0.0);
  if (!options.Start.empty())
  {
    for (unsigned k = 0; k < 6; ++k)
      parameters[k] = k < 3 ? options.Start[k + 3] * M_PI / 180.0 : options.Start[k - 3];
    start->SetParameters(parameters);
    return start;
  }
  if (options.RandomStart >= 0)
  {
    std::mt19937                           random(static_cast<unsigned>(options.RandomStart) * 7919u + 17u);
    std::normal_distribution<double>       normal;
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    itk::Vector<double, 3>                 axis, shift;
    for (unsigned r = 0; r < 3; ++r)
    {
      axis[r] = normal(random);
      shift[r] = normal(random);
    }
    axis.Normalize();
    shift.Normalize();
    shift *= options.MaxTranslation * uniform(random);
    const double        angle = options.MaxRotation * uniform(random) * M_PI / 180.0;
    itk::Versor<double> versor;
    versor.Set(axis, angle);
    start->SetMatrix(versor.GetMatrix());
    start->SetTranslation(shift);
  }
  return start;
}

struct Result
{
  double                        StartTre{ 0 }, FinalTre{ 0 }, Seconds{ 0 }, CpuSeconds{ 0 };
  unsigned                      Evaluations{ 0 }, Drrs{ 0 };
  TransformType::ParametersType Final;
};

/** The registration by the library's class: the CT (mu, identity transfer, the targets' trilinear model) moved
 * from the start pose to the one whose DRRs match the views. The class's pose moves the CT in the room (from its frame
 * to the room); the truth is the identity either way. */
Result
Register(const MuImageType * mu, const std::vector<View> & views, const Options & options)
{
  using MethodType = itk::PointBasedDRRRegistrationMethod<MuImageType>;
  const auto centre = itk::DRRProjectionGeometry::ComputeImageCenter(mu);
  const auto truth = TransformType::New();
  truth->SetCenter(centre);
  const auto start = StartPose(options, centre);

  auto method = MethodType::New();
  method->SetVolume(mu);
  for (const View & view : views)
  {
    method->AddXRay(view.XRay, view.Geometry);
  }
  MethodType::PoseType pose;
  for (unsigned k = 0; k < 3; ++k)
  {
    pose[k] = start->GetParameters()[k + 3];                // mm
    pose[k + 3] = start->GetParameters()[k] * 180.0 / M_PI; // degrees
  }
  method->SetStartPose(pose);
  auto identity = itk::DRRTransferFunction::New();
  identity->SetMode(itk::PointBasedDRREnums::TransferFunction::Identity);
  auto * metric = method->GetModifiableMetric();
  metric->SetTransferFunction(identity);
  metric->SetReconstructionKernel(itk::PointBasedDRREnums::ReconstructionKernel::Tent);
  metric->SetExactRaysPerPixelSide(options.Drr == "exact" ? 2 : 0);
  metric->SetNumberOfSamples(static_cast<uint64_t>(options.Samples));
  metric->SetSimilarity(itk::DRRImageSimilarity::FromName(options.Metric));
  method->SetShrinkFactorsPerLevel(options.Shrink);
  method->AddObserver(itk::IterationEvent(), [&method](const itk::EventObject &) {
    std::cerr << "level 1/" << method->GetCurrentShrinkFactor() << ": similarity "
              << method->GetCurrentLevelSimilarity() << " after " << method->GetCurrentLevelEvaluations() << " poses"
              << std::endl;
  });

  Result        result;
  const clock_t cpuBegin = std::clock();
  result.StartTre = MeanTargetError(mu, MethodType::MakePoseTransform(mu, pose), truth);
  method->Update();
  result.Seconds = method->GetElapsedSeconds();
  result.CpuSeconds = static_cast<double>(std::clock() - cpuBegin) / CLOCKS_PER_SEC;
  result.FinalTre = MeanTargetError(mu, method->GetTransform(), truth);
  result.Final = method->GetTransform()->GetParameters();
  result.Evaluations = static_cast<unsigned>(method->GetNumberOfEvaluations());
  result.Drrs = result.Evaluations * static_cast<unsigned>(views.size());
  return result;
}

/** The registration by ITK's classic components, for either interpolator: the same code but for the interpolator's
 * type. */
template <typename TInterpolator>
Result
RegisterClassic(const MuImageType * mu, const std::vector<View> & views, const Options & options)
{
  const auto centre = itk::DRRProjectionGeometry::ComputeImageCenter(mu);
  const auto truth = TransformType::New();
  truth->SetCenter(centre);
  const auto start = StartPose(options, centre);
  auto       transform = TransformType::New();
  transform->SetCenter(centre);
  transform->SetParameters(start->GetParameters());

  auto                                         cost = MultiViewCost::New();
  std::vector<typename TInterpolator::Pointer> interpolators;
  for (const View & view : views)
  {
    auto interpolator = TInterpolator::New();
    interpolator->SetTransform(transform);
    interpolator->SetFocalPoint(view.FocalPoint);
    interpolator->SetThreshold(0.0);
    if constexpr (std::is_same<TInterpolator, itk::PointBasedDRRInterpolateImageFunction<MuImageType, double>>::value)
    {
      // Optional: render on the fixed image's own pixel grid (without it, an automatic virtual detector).
      interpolator->SetDetectorFromImage(view.Image);
      if (interpolators.empty())
      {
        interpolator->GetDRRFilter()->SetNumberOfSamples(static_cast<uint64_t>(options.Samples));
        if (options.ControlVariate > 0)
        {
          // The control variate is built for the box model: an exact coarse image per pose plus the kept residual.
          interpolator->GetDRRFilter()->SetReconstructionKernel(itk::PointBasedDRREnums::ReconstructionKernel::Box);
          interpolator->GetDRRFilter()->SetControlVariateFactor(options.ControlVariate);
        }
      }
      else
      {
        interpolator->SetDRRFilter(interpolators.front()->GetDRRFilter()); // the views share one set of points
      }
    }
    auto metric = MetricType::New();
    metric->SetFixedImage(view.Image);
    metric->SetFixedImageRegion(view.Image->GetBufferedRegion());
    metric->SetMovingImage(mu);
    metric->SetTransform(transform);
    metric->SetInterpolator(interpolator);
    metric->UseAllPixelsOn();
    metric->ComputeGradientOff(); // Powell needs no gradient: skip the CT's (costly) gradient image
    metric->Initialize();
    cost->Metrics.push_back(metric);
    interpolators.push_back(interpolator);
  }

  auto optimizer = itk::PowellOptimizer::New();
  optimizer->SetCostFunction(cost);
  optimizer->SetInitialPosition(transform->GetParameters());
  itk::PowellOptimizer::ScalesType scales(6);
  for (unsigned k = 0; k < 6; ++k)
    scales[k] = k < 3 ? 180.0 / M_PI : 1.0; // one optimizer unit: one degree or one millimetre
  optimizer->SetScales(scales);
  optimizer->SetStepLength(2.0);
  optimizer->SetStepTolerance(0.02);
  optimizer->SetValueTolerance(1e-12);
  optimizer->SetMaximumIteration(options.Iterations);
  optimizer->SetMaximumLineIteration(12);

  Result        result;
  const auto    begin = std::chrono::steady_clock::now();
  const clock_t cpuBegin = std::clock();
  result.StartTre = MeanTargetError(mu, transform, truth);
  optimizer->StartOptimization();
  result.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  result.CpuSeconds = static_cast<double>(std::clock() - cpuBegin) / CLOCKS_PER_SEC;
  result.Final = optimizer->GetCurrentPosition();
  transform->SetParameters(result.Final);
  result.FinalTre = MeanTargetError(mu, transform, truth);
  result.Evaluations = cost->Evaluations;
  result.Drrs = cost->Evaluations * static_cast<unsigned>(views.size());
  if constexpr (std::is_same<TInterpolator, itk::PointBasedDRRInterpolateImageFunction<MuImageType, double>>::value)
  {
    result.Drrs = 0;
    for (const auto & interpolator : interpolators)
      result.Drrs += static_cast<unsigned>(interpolator->GetNumberOfRenders());
  }
  return result;
}
} // namespace

int
main(int argc, char * argv[])
{
  try
  {
    const Options options = ParseOptions(argc, argv);
    if (options.Threads > 0)
    {
      itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(options.Threads);
      itk::MultiThreaderBase::SetGlobalMaximumNumberOfThreads(options.Threads);
    }
    const auto ct = options.Phantom ? MakePhantom() : WithIdentityDirection(ReadCT(options.Input));
    const auto mu = ToMu(ct);
    const bool synthetic = options.Fixed.empty();
    const auto views = synthetic ? RenderTargets(mu, options) : ReadTargets(options);
    // The class, or the classic components with the one-type difference:
    const Result result =
      options.Method == "class" ? Register(mu, views, options)
      : options.Drr == "pbdrr"
        ? RegisterClassic<itk::PointBasedDRRInterpolateImageFunction<MuImageType, double>>(mu, views, options)
        : RegisterClassic<itk::RayCastInterpolateImageFunction<MuImageType, double>>(mu, views, options);
    std::cout << "result method=" << options.Method << " drr=" << options.Drr << " views=" << views.size()
              << " size=" << options.Size;
    if (options.Drr == "pbdrr")
      std::cout << " samples=" << static_cast<uint64_t>(options.Samples);
    std::cout << " seed=" << options.RandomStart << " evaluations=" << result.Evaluations << " drrs=" << result.Drrs
              << " seconds=" << result.Seconds << " cpu_seconds=" << result.CpuSeconds
              << " drrs_per_second=" << result.Drrs / result.Seconds;
    if (synthetic)
      std::cout << " start_tre_mm=" << result.StartTre << " final_tre_mm=" << result.FinalTre
                << " success=" << (result.FinalTre < 2.0 ? 1 : 0);
    std::cout << " parameters_deg_mm=";
    for (unsigned k = 0; k < 6; ++k)
      std::cout << (k ? "," : "") << (k < 3 ? result.Final[k] * 180.0 / M_PI : result.Final[k]);
    std::cout << std::endl;
    if (synthetic && options.MaxTre >= 0.0 && !(result.FinalTre <= options.MaxTre))
    {
      std::cerr << "Register2D3D: final mTRE " << result.FinalTre << " mm exceeds --max-tre " << options.MaxTre << " mm"
                << std::endl;
      return EXIT_FAILURE;
    }
  }
  catch (const std::exception & error)
  {
    std::cerr << "Register2D3D: " << error.what() << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
