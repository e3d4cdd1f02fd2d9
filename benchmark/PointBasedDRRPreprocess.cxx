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

// The preprocessing of the default render (issue 41, item 4), stage by stage, in ns per voxel of the CT: the
// attenuation model (HU -> mu keys, levels), then the control variate's coarse volume (F 2 by default) and the
// stratified sampler's tables of the residual, made in one pass as the filter makes them and, beside it, one after the
// other. What `pbdrr -v` prints as "preprocess ... ns per voxel" is the model and the one pass.
//
//   PointBasedDRRPreprocess CT.mha [repeats (5)] [threads (2)] [factor (2)]
//
// Prints one line per repeat and the medians. The CT is read as int16 (an .mha of integer HU).

#include "itkDRRAttenuationVolume.h"
#include "itkDRRControlVariate.h"
#include "itkDRRImageToAttenuationVolumeFilter.h"
#include "itkDRRStratifiedSampler.h"
#include "itkDRRTransferFunction.h"
#include "itkImage.h"
#include "itkImageFileReader.h"
#include "itkMultiThreaderBase.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <vector>

namespace
{
using Clock = std::chrono::steady_clock;
using CTType = itk::Image<int16_t, 3>;

double
SecondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double
Median(std::vector<double> values)
{
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}
} // namespace

int
main(int argc, char * argv[])
{
  if (argc < 2)
  {
    std::cerr << "usage: " << argv[0] << " CT.mha [repeats (5)] [threads (2)] [factor (2)]" << std::endl;
    return 2;
  }
  const int          repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  const unsigned int threads = argc > 3 ? static_cast<unsigned int>(std::max(1, std::atoi(argv[3]))) : 2;
  const unsigned int factor = argc > 4 ? static_cast<unsigned int>(std::atoi(argv[4])) : 2;
  itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(threads);
  itk::MultiThreaderBase::SetGlobalMaximumNumberOfThreads(threads);

  auto reader = itk::ImageFileReader<CTType>::New();
  reader->SetFileName(argv[1]);
  reader->Update();
  CTType::Pointer ct = reader->GetOutput();
  ct->DisconnectPipeline();
  const double voxels = static_cast<double>(ct->GetLargestPossibleRegion().GetNumberOfPixels());

  // Each repeat times the split and the tables both ways, side by side: one pass (InitializeWithControlVariate(), what
  // the filter does), first, then one after the other (Build(), then Initialize() of the residual). Both give the
  // same tables.
  std::vector<double> model, split, tables, separate, fused, total;
  for (int r = 0; r < repeats; ++r)
  {
    auto stage = itk::DRRImageToAttenuationVolumeFilter<CTType>::New();
    stage->SetInput(ct);
    stage->SetTransferFunction(itk::DRRTransferFunction::New());
    stage->SetNumberOfWorkUnits(threads);

    auto start = Clock::now();
    stage->Update();
    model.push_back(SecondsSince(start));
    auto controlVariate = itk::DRRControlVariate::New();
    auto sampler = itk::DRRStratifiedSampler::New();
    start = Clock::now();
    sampler->InitializeWithControlVariate(*controlVariate, *stage->GetOutput(), factor, stage->GetMultiThreader());
    fused.push_back(SecondsSince(start));
    {
      auto controlVariate = itk::DRRControlVariate::New();
      auto sampler = itk::DRRStratifiedSampler::New();
      start = Clock::now();
      controlVariate->Build(*stage->GetOutput(), factor, stage->GetMultiThreader());
      split.push_back(SecondsSince(start));
      start = Clock::now();
      sampler->Initialize(controlVariate->GetResidualVolume());
      tables.push_back(SecondsSince(start));
      separate.push_back(split.back() + tables.back());
    }
    total.push_back(model.back() + fused.back());
    std::cout << "repeat " << r << ": model " << 1e9 * model.back() / voxels
              << "; one after the other: control variate " << 1e9 * split.back() / voxels << ", sampler tables "
              << 1e9 * tables.back() / voxels << "; in one pass " << 1e9 * fused.back() / voxels << "; preprocess "
              << 1e9 * total.back() / voxels << " ns per voxel (M " << controlVariate->GetTotalMass() << " mm^2, M_r "
              << sampler->GetTotalMass() << " mm^2, " << sampler->GetNumberOfBricks() << " bricks)" << std::endl;
  }
  std::cout << "median of " << repeats << ", " << threads << " threads, " << voxels << " voxels, F " << factor
            << ": model " << 1e9 * Median(model) / voxels << "; one after the other: control variate "
            << 1e9 * Median(split) / voxels << ", sampler tables " << 1e9 * Median(tables) / voxels << ", both "
            << 1e9 * Median(separate) / voxels << "; in one pass " << 1e9 * Median(fused) / voxels
            << " (one pass / one after the other " << Median(fused) / Median(separate) << "); preprocess "
            << 1e9 * Median(total) / voxels << " ns per voxel" << std::endl;
  return EXIT_SUCCESS;
}
