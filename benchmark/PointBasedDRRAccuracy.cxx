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
// Error against the exact pixel-averaged reference and wall time of one DRR view, for the point-based filter at
// several sample counts and for the exact projectors. Prints a Markdown table.
//
//   PointBasedDRRAccuracy CT_DIR_OR_FILE [cols] [spacing_mm] [gantry_deg] [reference_rays_per_side] [runs]
//                         [sampler,sampler,...] [box|tent|both]
//
// Geometry: SAD 1000 mm, SID 1500 mm, isocenter at the volume centre, square detector.
#include "itkPointBasedDRRImageFilter.h"
#include "itkExactDRRImageFilter.h"
#include "pbdrrVolumeLoader.h"
#include "itkDRRSamplerFactory.h"
#include "pbdrrBenchmarkSupport.h"

#include <algorithm>
#include <iomanip>
#include <iostream>

namespace
{
using pbdrr::bench::Errors;
using pbdrr::bench::Now;
using pbdrr::bench::ProjectionType;
using VolumeType = pbdrr::VolumeType;
using KernelEnum = itk::PointBasedDRREnums::ReconstructionKernel;

template <typename TFilter>
double
MedianSeconds(TFilter * filter, unsigned int runs)
{
  std::vector<double> times;
  for (unsigned int r = 0; r < runs; ++r)
  {
    filter->Modified();
    const double start = Now();
    filter->Update();
    times.push_back(Now() - start);
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

/** The errors of a rendered image against the reference. */
Errors
Compare(const ProjectionType * image, const pbdrr::bench::Image & reference)
{
  return pbdrr::bench::Compare(pbdrr::bench::ToVector(image), reference);
}

using ExactType = itk::ExactDRRImageFilter<VolumeType, ProjectionType>;
using PointType = itk::PointBasedDRRImageFilter<VolumeType, ProjectionType>;

/** One sampler: its preprocessing, then 1e6, 1e7 and 1e8 samples against the reference `truth`. */
void
SamplerRows(const VolumeType *           volume,
            itk::DRRProjectionGeometry * geometry,
            KernelEnum                   kernel,
            const std::string &          samplerName,
            unsigned int                 runs,
            const pbdrr::bench::Image &  truth)
{
  const char * kernelName = kernel == KernelEnum::Box ? "box (Siddon)" : "tent (trilinear)";
  auto         drr = PointType::New();
  drr->SetInput(volume);
  drr->SetGeometry(geometry);
  drr->SetReconstructionKernel(kernel);
  drr->SetSampler(itk::DRRSamplerFactory::Create(samplerName));
  drr->SetNumberOfSamples(1);
  const double start = Now();
  drr->Update();
  const double preprocessSeconds = Now() - start;
  std::cout << "| " << samplerName
            << ": preprocessing (HU->mu, sampling tables: " << drr->GetSampler()->GetTableSizeInBytes() / 1048576.0
            << " MiB) | " << kernelName << " | | " << preprocessSeconds << " | | | | |\n";
  for (double samples : { 1e6, 1e7, 1e8 })
  {
    drr->SetNumberOfSamples(static_cast<uint64_t>(samples));
    drr->SetSeed(1);
    const double seconds = MedianSeconds(drr.GetPointer(), runs);
    const Errors e = Compare(drr->GetOutput(), truth);
    std::cout << "| " << samplerName << " | " << kernelName << " | " << samples << " | " << seconds << " | " << e.Nrmse
              << " | " << e.RelativeRmse << " | " << e.MaxError << " | " << e.SumRatio << " |\n";
  }
}

/** The rows of one kernel: the reference, the exact projector at 1, 4 and 16 rays per pixel, every sampler. */
void
KernelRows(const VolumeType *               volume,
           itk::DRRProjectionGeometry *     geometry,
           KernelEnum                       kernel,
           unsigned int                     referenceRays,
           unsigned int                     runs,
           const std::vector<std::string> & samplers)
{
  const char * kernelName = kernel == KernelEnum::Box ? "box (Siddon)" : "tent (trilinear)";
  auto         reference = ExactType::New();
  reference->SetInput(volume);
  reference->SetGeometry(geometry);
  reference->SetReconstructionKernel(kernel);
  reference->SetRaysPerPixelSide(referenceRays);
  const double start = Now();
  reference->Update();
  const double              referenceSeconds = Now() - start;
  const pbdrr::bench::Image truth = pbdrr::bench::ToVector(reference->GetOutput());
  std::cout << "| exact (reference) | " << kernelName << " | " << referenceRays * referenceRays << " | "
            << referenceSeconds << " | 0 | 0 | 0 | 1 |\n";
  for (unsigned int rays : { 1u, 2u, 4u })
  {
    auto exact = ExactType::New();
    exact->SetInput(volume);
    exact->SetGeometry(geometry);
    exact->SetReconstructionKernel(kernel);
    exact->SetRaysPerPixelSide(rays);
    exact->Update(); // builds the attenuation volume once
    const double seconds = MedianSeconds(exact.GetPointer(), runs);
    const Errors e = Compare(exact->GetOutput(), truth);
    std::cout << "| exact | " << kernelName << " | " << rays * rays << " | " << seconds << " | " << e.Nrmse << " | "
              << e.RelativeRmse << " | " << e.MaxError << " | " << e.SumRatio << " |\n";
  }
  for (const std::string & samplerName : samplers)
    SamplerRows(volume, geometry, kernel, samplerName, runs, truth);
}
} // namespace

int
main(int argc, char * argv[])
{
  if (argc < 2)
  {
    std::cerr << "usage: " << argv[0] << " CT_DIR_OR_FILE [cols] [spacing_mm] [gantry_deg] [reference_rays] [runs]\n";
    return 1;
  }
  const unsigned int cols = argc > 2 ? std::stoul(argv[2]) : 256;
  const double       spacing = argc > 3 ? std::stod(argv[3]) : 2.4;
  const double       gantry = argc > 4 ? std::stod(argv[4]) : 90.0;
  const unsigned int referenceRays = argc > 5 ? std::stoul(argv[5]) : 8;
  const unsigned int runs = argc > 6 ? std::stoul(argv[6]) : 3;
  // Samplers to measure: a comma-separated list, or every registered one.
  std::vector<std::string> samplers;
  for (const auto & entry : itk::DRRSamplerFactory::GetEntries())
  {
    samplers.push_back(entry.Name);
  }
  if (argc > 7)
  {
    samplers = pbdrr::bench::SplitList(argv[7], true);
  }
  const std::vector<KernelEnum> kernels =
    argc > 8 && std::string(argv[8]) == "box"    ? std::vector<KernelEnum>{ KernelEnum::Box }
    : argc > 8 && std::string(argv[8]) == "tent" ? std::vector<KernelEnum>{ KernelEnum::Tent }
                                                 : std::vector<KernelEnum>{ KernelEnum::Box, KernelEnum::Tent };
  try
  {
    const double start = Now();
    const auto   volume = pbdrr::LoadVolume(argv[1], "").AsFloat();
    const double loadSeconds = Now() - start;

    auto geometry = itk::DRRProjectionGeometry::New();
    geometry->SetGantryAngleInDegrees(gantry);
    geometry->SetIsocenterToImageCenter(volume);
    geometry->SetDetectorSize({ { cols, cols } });
    geometry->SetDetectorSpacing(itk::Vector<double, 2>(spacing));

    std::cout << "Volume " << volume->GetLargestPossibleRegion().GetSize() << " spacing " << volume->GetSpacing()
              << " loaded in " << loadSeconds << " s; detector " << cols << " x " << cols << " at " << spacing
              << " mm, gantry " << gantry << " deg, SAD 1000 mm, SID 1500 mm; threads "
              << itk::MultiThreaderBase::GetGlobalDefaultNumberOfThreads() << "; median of " << runs << " runs\n\n";

    std::cout << "| method | kernel | samples or rays/pixel | wall time (s) | NRMSE (range) | RMSE / mean | max error "
                 "(range) | sum ratio |\n|---|---|---|---|---|---|---|---|\n";
    std::cout << std::setprecision(4);
    for (KernelEnum kernel : kernels)
      KernelRows(volume, geometry, kernel, referenceRays, runs, samplers);
  }
  catch (const std::exception & e)
  {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
