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
// DRRs per second across poses, as registration renders them (issue 6): one volume, many rigid poses (rotations up to
// 5 degrees and translations up to 10 mm about the volume centre), PBDRR re-projecting kept points (ReusePoints)
// against ITK's ray caster (ResampleImageFilter + RayCastInterpolateImageFunction, the same transform object in
// both, as ITK's 2D-3D registration uses it) at the same detector sizes, in the same run. Accuracy: NRMSE (RMSE over
// the range of the reference) against the exact pixel-averaged line integral (ExactDRRImageFilter, box model, R x R
// rays per pixel) at the first few poses.
//
//   PointBasedDRRPoseRate INPUT [--sizes 128,256] [--field-mm 614.4] [--samples 1e6,3e6,1e7] [--poses 20]
//                         [--error-poses 3] [--reference-rays 4] [--sampler stratified] [--splat bilinear]
//                         [--kernel box] [--gantry 90] [--ray-caster-poses 3] [--control-variate 0,2,8]
//                         [--markdown FILE] [--no-standard-error]
// --control-variate: coarsening factors F of the control variate, 0 for off (default 0): the residual's points are
// kept, the coarse image is traced again at every pose (DESIGN 10).
// --no-standard-error: render without the standard-error image, as a registration's metric does (the coarse image is
// then one replicate of rays per pixel, not two).
#include "itkPointBasedDRRImageFilter.h"
#include "itkExactDRRImageFilter.h"
#include "itkDRRSamplerFactory.h"
#include "pbdrrVolumeLoader.h"
#include "pbdrrBenchmarkSupport.h"

#include "itkEuler3DTransform.h"
#include "itkOrientImageFilter.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using pbdrr::bench::CpuSeconds;
using pbdrr::bench::Image;
using pbdrr::bench::Median;
using pbdrr::bench::MuImageType;
using pbdrr::bench::Now;
using pbdrr::bench::ProjectionType;
using pbdrr::bench::ToVector;
using VolumeType = pbdrr::VolumeType;
using TransformType = itk::Euler3DTransform<double>;
using KernelEnum = itk::PointBasedDRREnums::ReconstructionKernel;
using SplatEnum = itk::PointBasedDRREnums::Splat;

struct Options
{
  std::string           Input, Markdown;
  std::vector<unsigned> Sizes{ 128, 256 };
  std::vector<double>   Samples{ 1e6, 3e6, 1e7 };
  double                FieldMillimetres{ 614.4 }; // detector side: 256 pixels of 2.4 mm
  unsigned              Poses{ 20 }, ErrorPoses{ 3 }, ReferenceRays{ 4 }, RayCasterPoses{ 3 };
  std::string           Sampler{ "stratified" };
  SplatEnum             Splat{ SplatEnum::Bilinear };
  KernelEnum            Kernel{ KernelEnum::Box };
  double                Gantry{ 90.0 };
  std::vector<unsigned> ControlVariates{ 0 };  // coarsening factors F (0: off), each a row per size and samples
  bool                  StandardError{ true }; // off: what a registration's metric renders (no error image)
};

Options
Parse(int argc, char * argv[])
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
    if (arg == "--sizes")
    {
      options.Sizes.clear();
      for (const auto & s : pbdrr::bench::SplitList(value(), true))
        options.Sizes.push_back(static_cast<unsigned>(std::stoul(s)));
    }
    else if (arg == "--samples")
    {
      options.Samples.clear();
      for (const auto & s : pbdrr::bench::SplitList(value(), true))
        options.Samples.push_back(std::stod(s));
    }
    else if (arg == "--field-mm")
      options.FieldMillimetres = std::stod(value());
    else if (arg == "--poses")
      options.Poses = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--error-poses")
      options.ErrorPoses = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--reference-rays")
      options.ReferenceRays = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--ray-caster-poses")
      options.RayCasterPoses = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--sampler")
      options.Sampler = value();
    else if (arg == "--splat")
      options.Splat = value() == "nearest" ? SplatEnum::Nearest : SplatEnum::Bilinear;
    else if (arg == "--kernel")
      options.Kernel = value() == "tent" ? KernelEnum::Tent : KernelEnum::Box;
    else if (arg == "--gantry")
      options.Gantry = std::stod(value());
    else if (arg == "--control-variate")
    {
      options.ControlVariates.clear();
      for (const auto & s : pbdrr::bench::SplitList(value(), true))
        options.ControlVariates.push_back(static_cast<unsigned>(std::stoul(s)));
    }
    else if (arg == "--markdown")
      options.Markdown = value();
    else if (arg == "--no-standard-error")
      options.StandardError = false;
    else if (!arg.empty() && arg[0] == '-')
      throw std::runtime_error("unknown option " + arg);
    else
      options.Input = arg;
  }
  if (options.Input.empty())
    throw std::runtime_error("usage: PointBasedDRRPoseRate INPUT [options] (see the source's header)");
  options.ErrorPoses = std::min(options.ErrorPoses, options.Poses);
  options.RayCasterPoses = std::min(options.RayCasterPoses, options.Poses);
  return options;
}

/** The same voxels at the same places with an identity direction matrix (axes permuted and flipped): ITK's ray caster
 * ignores the direction; both methods get this volume. */
VolumeType::Pointer
WithIdentityDirection(VolumeType * volume)
{
  VolumeType::DirectionType identity;
  identity.SetIdentity();
  if (volume->GetDirection() == identity)
    return volume;
  auto orient = itk::OrientImageFilter<VolumeType, VolumeType>::New();
  orient->SetInput(volume);
  orient->UseImageDirectionOn();
  orient->SetDesiredCoordinateDirection(identity);
  orient->Update();
  if (!(orient->GetOutput()->GetDirection() == identity))
    throw std::runtime_error(
      "the volume's direction is not a permutation of the axes: ITK's ray caster cannot take it");
  return orient->GetOutput();
}

/** Rigid poses about the volume centre: rotations uniform in +-5 degrees, translations in +-10 mm per axis (fixed
 * seed); pose 0 is the identity. */
std::vector<TransformType::ParametersType>
MakePoses(unsigned count)
{
  std::mt19937                               random(20261121u);
  std::uniform_real_distribution<double>     unit(-1.0, 1.0);
  std::vector<TransformType::ParametersType> poses;
  for (unsigned p = 0; p < count; ++p)
  {
    TransformType::ParametersType parameters(6);
    for (unsigned k = 0; k < 6; ++k)
      parameters[k] = p == 0 ? 0.0 : (k < 3 ? 5.0 * M_PI / 180.0 : 10.0) * unit(random);
    poses.push_back(parameters);
  }
  return poses;
}

double
Nrmse(const Image & image, const Image & reference)
{
  return pbdrr::bench::Compare(image, reference).Nrmse;
}

struct Row
{
  std::string Method;
  unsigned    Size{ 0 };
  double      Samples{ 0 }, DrawSeconds{ 0 }, PerDrr{ 0 }, CpuPerDrr{ 0 }, Nrmse{ 0 }, BytesPerPoint{ 0 };
  unsigned    Poses{ 0 };
};

class PoseRate
{
public:
  explicit PoseRate(Options options) : m_Options(std::move(options)) {}

  int
  Run()
  {
    m_Volume = WithIdentityDirection(pbdrr::LoadVolume(m_Options.Input, "").AsFloat());
    m_Centre = itk::DRRProjectionGeometry::ComputeImageCenter(m_Volume);
    m_Poses = MakePoses(m_Options.Poses);
    for (unsigned size : m_Options.Sizes)
    {
      auto geometry = this->MakeGeometry(size);
      this->References(geometry);
      if (m_Options.RayCasterPoses > 0)
        this->RayCaster(geometry, size);
      for (unsigned controlVariate : m_Options.ControlVariates)
        for (double samples : m_Options.Samples)
          this->PointBased(geometry, size, samples, controlVariate);
    }
    this->Report();
    return 0;
  }

private:
  itk::DRRProjectionGeometry::Pointer
  MakeGeometry(unsigned size) const
  {
    auto geometry = itk::DRRProjectionGeometry::New();
    geometry->SetGantryAngleInDegrees(m_Options.Gantry);
    geometry->SetSourceToIsocenterDistance(1000.0);
    geometry->SetSourceToDetectorDistance(1500.0);
    geometry->SetIsocenter(m_Centre);
    geometry->SetDetectorSize({ { size, size } });
    geometry->SetDetectorSpacing(itk::Vector<double, 2>(m_Options.FieldMillimetres / size));
    return geometry;
  }

  TransformType::Pointer
  MakeTransform(const TransformType::ParametersType & pose) const
  {
    auto transform = TransformType::New();
    transform->SetCenter(m_Centre);
    transform->SetParameters(pose);
    return transform;
  }

  /** Exact pixel averages (box model) at the first ErrorPoses poses. */
  void
  References(itk::DRRProjectionGeometry * geometry)
  {
    auto exact = itk::ExactDRRImageFilter<VolumeType, ProjectionType>::New();
    exact->SetInput(m_Volume);
    exact->SetGeometry(geometry);
    exact->SetReconstructionKernel(KernelEnum::Box);
    exact->SetRaysPerPixelSide(m_Options.ReferenceRays);
    m_References.clear();
    for (unsigned p = 0; p < m_Options.ErrorPoses; ++p)
    {
      exact->SetTransform(this->MakeTransform(m_Poses[p]));
      exact->Update();
      m_References.push_back(ToVector(exact->GetOutput()));
    }
    m_Mu = pbdrr::bench::MuImage(m_Volume, exact->GetAttenuationVolume());
  }

  /** ITK's ray caster as its 2D-3D registration uses it: one transform object for the resampler and the
   * interpolator, focal point at the source, a one-slice output on the detector plane. */
  void
  RayCaster(itk::DRRProjectionGeometry * geometry, unsigned size)
  {
    auto transform = TransformType::New();
    transform->SetCenter(m_Centre);
    auto resample = pbdrr::bench::MakeRayCaster(m_Mu, geometry, transform);
    Row  row;
    row.Method = "ITK ray caster";
    row.Size = size;
    this->TimePoses(transform, resample.GetPointer(), m_Options.RayCasterPoses, row);
    this->Add(row);
  }

  void
  PointBased(itk::DRRProjectionGeometry * geometry, unsigned size, double samples, unsigned controlVariate)
  {
    auto drr = itk::PointBasedDRRImageFilter<VolumeType, ProjectionType>::New();
    drr->SetInput(m_Volume);
    drr->SetGeometry(geometry);
    drr->SetSampler(itk::DRRSamplerFactory::Create(m_Options.Sampler));
    drr->SetSplat(m_Options.Splat);
    drr->SetReconstructionKernel(m_Options.Kernel);
    drr->SetNumberOfSamples(static_cast<uint64_t>(samples));
    drr->SetSeed(1);
    drr->SetReusePoints(true);
    drr->SetControlVariateFactor(controlVariate);
    drr->SetComputeStandardError(m_Options.StandardError);
    drr->PrepareSampling(); // tables: once per volume, not part of the per-pose cost
    auto transform = this->MakeTransform(m_Poses[0]);
    drr->SetTransform(transform);
    Row          row;
    const double start = Now();
    drr->Update(); // draws the points (and renders pose 0)
    row.DrawSeconds = Now() - start;
    this->TimePoses(transform, drr.GetPointer(), m_Options.Poses, row);
    if (drr->GetNumberOfPointCloudDraws() != 1)
      throw std::runtime_error("the points were drawn more than once");
    row.Method = "PBDRR " + m_Options.Sampler + (controlVariate > 0 ? " cv" + std::to_string(controlVariate) : "") +
                 " re-projected";
    row.Size = size;
    row.Samples = samples;
    row.BytesPerPoint = drr->GetPointCloud()->GetBytesPerPoint();
    this->Add(row);
  }

  /** Renders the first `poses` poses (the transform set to each, then Update): the median wall and CPU time per DRR,
   * and the median NRMSE at the poses that have a reference, into `row`. */
  template <typename TFilter>
  void
  TimePoses(TransformType * transform, TFilter * filter, unsigned poses, Row & row) const
  {
    std::vector<double> walls, cpus, errors;
    for (unsigned p = 0; p < poses; ++p)
    {
      transform->SetParameters(m_Poses[p]);
      const double wall = Now(), cpu = CpuSeconds();
      filter->Update();
      walls.push_back(Now() - wall);
      cpus.push_back(CpuSeconds() - cpu);
      if (p < m_References.size())
        errors.push_back(Nrmse(ToVector(filter->GetOutput()), m_References[p]));
    }
    row.PerDrr = Median(walls);
    row.CpuPerDrr = Median(cpus);
    row.Nrmse = errors.empty() ? NAN : Median(errors);
    row.Poses = poses;
  }

  void
  Add(const Row & row)
  {
    std::cerr << row.Method << " " << row.Size << " N=" << row.Samples << ": " << row.PerDrr * 1e3 << " ms/DRR, NRMSE "
              << row.Nrmse * 100 << "%" << std::endl;
    m_Rows.push_back(row);
  }

  void
  Report() const
  {
    std::ostringstream out;
    const auto         size = m_Volume->GetLargestPossibleRegion().GetSize();
    out << "Volume " << m_Options.Input << " (" << size[0] << " x " << size[1] << " x " << size[2]
        << " voxels), gantry " << m_Options.Gantry << " deg, SAD 1000 / SID 1500 mm, detector field "
        << m_Options.FieldMillimetres << " mm; " << m_Options.Poses << " poses (+-5 deg, +-10 mm), sampler "
        << m_Options.Sampler << ", " << (m_Options.Splat == SplatEnum::Bilinear ? "bilinear" : "nearest") << " splat, "
        << (m_Options.Kernel == KernelEnum::Box ? "box" : "tent") << " kernel; ITK threads "
        << itk::MultiThreaderBase::GetGlobalDefaultNumberOfThreads() << ". NRMSE: median over " << m_Options.ErrorPoses
        << " poses against the exact " << m_Options.ReferenceRays << " x " << m_Options.ReferenceRays
        << "-ray pixel average (box model).\n\n";
    out << "| method | detector | points | draw (s) | ms per DRR (median) | CPU ms per DRR | DRRs per s | x ray caster "
           "| NRMSE | bytes per point |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const Row & row : m_Rows)
    {
      double rayCaster = NAN;
      for (const Row & other : m_Rows)
        if (other.Method == "ITK ray caster" && other.Size == row.Size)
          rayCaster = other.PerDrr;
      out << "| " << row.Method << " | " << row.Size << " x " << row.Size << " | "
          << (row.Samples > 0 ? std::to_string(static_cast<uint64_t>(row.Samples)) : "-") << " | "
          << (row.Samples > 0 ? std::to_string(row.DrawSeconds).substr(0, 5) : "-") << " | " << std::fixed
          << std::setprecision(1) << row.PerDrr * 1e3 << " | " << row.CpuPerDrr * 1e3 << " | " << 1.0 / row.PerDrr
          << " | " << rayCaster / row.PerDrr << " | " << std::setprecision(2) << row.Nrmse * 100 << "% | "
          << (row.Samples > 0 ? std::to_string(row.BytesPerPoint).substr(0, 5) : "-") << " |\n"
          << std::defaultfloat;
    }
    std::cout << out.str();
    if (!m_Options.Markdown.empty())
      std::ofstream(m_Options.Markdown) << out.str();
  }

  Options                                    m_Options;
  VolumeType::Pointer                        m_Volume;
  MuImageType::Pointer                       m_Mu;
  itk::Point<double, 3>                      m_Centre;
  std::vector<TransformType::ParametersType> m_Poses;
  std::vector<Image>                         m_References;
  std::vector<Row>                           m_Rows;
};
} // namespace

int
main(int argc, char * argv[])
{
  try
  {
    return PoseRate(Parse(argc, argv)).Run();
  }
  catch (const std::exception & error)
  {
    std::cerr << "PointBasedDRRPoseRate: " << error.what() << std::endl;
    return 1;
  }
}
