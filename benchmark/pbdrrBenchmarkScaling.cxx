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
// PointBasedDRRBenchmark --mode scaling: time against the number of samples, the volume size (the volume resampled
// to fractions of its voxels over the same box) and the detector size (the same field of view); no errors.
#include "pbdrrBenchmark.h"

#include "itkDRRSamplerFactory.h"

#include <algorithm>
#include <cmath>
#include <iostream>

namespace pbdrr
{
namespace bench
{
void
Benchmark::Scaling()
{
  Row            base = StartView();
  const uint64_t samples = static_cast<uint64_t>(std::llround(m_Options.ScalingSamples));

  // 1. time against the number of samples (box kernel, nearest splat; no error computed)
  std::cerr << "scaling: samples" << std::endl;
  base.Sweep = "samples";
  base.Voxels = m_Volume->GetLargestPossibleRegion().GetNumberOfPixels();
  ScalingSamples(base);

  // 2. time against the volume size: the volume resampled to a fraction of its voxels over the same box
  std::cerr << "scaling: volume size" << std::endl;
  for (double fraction : m_Options.VolumeFractions)
    ScalingVolume(fraction, base, samples);

  // 3. time against the detector size, same field of view (one sampler's filter alive at a time, so that the peak
  // memory is that sampler's)
  std::cerr << "scaling: detector size" << std::endl;
  ScalingDetector(base, samples);
}

/** Every sampler's preprocessing and sample ladder with the first kernel and splat; x: the number of samples. */
void
Benchmark::ScalingSamples(const Row & base)
{
  Options saved = m_Options;
  m_Options.Kernels = { m_Options.Kernels.front() };
  m_Options.Splats = { m_Options.Splats.front() };
  for (const auto & sampler : m_Options.Samplers)
    SamplerRows(sampler, m_Volume, base);
  m_Options = saved;
  for (Row & r : m_Rows)
    r.X = static_cast<double>(r.Samples);
}

/** Every sampler (preprocessing and one render), the exact projectors (1 ray) and ITK's ray caster on the volume
 * resampled to `fraction` of its voxels; x: the number of voxels. */
void
Benchmark::ScalingVolume(double fraction, const Row & base, uint64_t samples)
{
  const Geometry &    g = m_Geometry;
  VolumeType::Pointer volume = ResampleToFraction(m_Volume, fraction);
  Row                 row = base;
  row.Sweep = "volume";
  row.Voxels = volume->GetLargestPossibleRegion().GetNumberOfPixels();
  row.X = static_cast<double>(row.Voxels);
  const auto size = volume->GetLargestPossibleRegion().GetSize();
  row.Note = std::to_string(size[0]) + "x" + std::to_string(size[1]) + "x" + std::to_string(size[2]);
  std::cerr << " volume " << row.Note << " (fraction " << fraction << ")" << std::endl;
  auto geometry = MakeGeometry(volume, g.Columns, g.Rows, g.Spacing);
  for (const auto & samplerName : m_Options.Samplers)
  {
    auto filter = PointFilterType::New();
    filter->SetInput(volume);
    filter->SetGeometry(geometry);
    filter->SetSampler(itk::DRRSamplerFactory::Create(samplerName));
    filter->SetSeed(m_Options.Seed);
    filter->SetReconstructionKernel(m_Options.Kernels.front());
    filter->SetSplat(m_Options.Splats.front());
    Row pre = row;
    pre.Sampler = samplerName;
    pre = Preprocess(filter, pre);
    pre.TableBytesPerVoxel = pre.TableBytes / std::max<uint64_t>(1, CountNonAir(volume, filter->GetTransferFunction()));
    Add(pre);
    Row render = row;
    render.Method = "points";
    render.Sampler = samplerName;
    render.Kernel = KernelName(m_Options.Kernels.front());
    render.Splat = SplatName(m_Options.Splats.front());
    render.Samples = samples;
    filter->SetNumberOfSamples(samples);
    render.FirstRender = WarmUp(filter.GetPointer());
    render.Time = TimeRenders(filter);
    Add(render);
  }
  auto exact = ExactType::New();
  exact->SetInput(volume);
  exact->SetGeometry(geometry);
  exact->GetAttenuationVolume();
  for (KernelEnum kernel : { KernelEnum::Box, KernelEnum::Tent })
  {
    Row r = row;
    r.Method = kernel == KernelEnum::Box ? "exact-siddon" : "exact-trilinear";
    r.Kernel = KernelName(kernel);
    r.Rays = 1;
    exact->SetReconstructionKernel(kernel);
    r.FirstRender = WarmUp(exact.GetPointer());
    r.Time = TimeRenders(exact);
    Add(r);
  }
  if (m_Options.Itk)
  {
    auto                 mu = MuImage(volume, exact->GetAttenuationVolume());
    MuImageType::Pointer oriented = WithIdentityDirection(mu);
    if (oriented)
    {
      Row r = row;
      r.Method = "itk-raycast";
      ItkRayCast(oriented, geometry, &r.Time);
      Add(r);
    }
  }
}

/** Every sampler, the exact Siddon projector and ITK's ray caster at every --detector-cols size over the same field
 * of view; x: the detector columns. */
void
Benchmark::ScalingDetector(const Row & base, uint64_t samples)
{
  const double fieldOfView = m_Geometry.Columns * m_Geometry.Spacing;
  Row          detectorBase = base;
  detectorBase.Sweep = "detector";
  detectorBase.Voxels = m_Volume->GetLargestPossibleRegion().GetNumberOfPixels();
  const auto detectorRow = [&](unsigned cols) {
    Row row = detectorBase;
    row.Columns = cols;
    row.DetectorRows = cols;
    row.X = cols;
    row.Note = "pixel " + Format(fieldOfView / cols, "%.4g") + " mm";
    return row;
  };
  for (const auto & samplerName : m_Options.Samplers)
  {
    auto filter = PointFilterType::New();
    filter->SetInput(m_Volume);
    filter->SetSampler(itk::DRRSamplerFactory::Create(samplerName));
    filter->SetSeed(m_Options.Seed);
    filter->SetReconstructionKernel(m_Options.Kernels.front());
    filter->SetSplat(m_Options.Splats.front());
    filter->PrepareSampling();
    filter->SetNumberOfSamples(samples);
    double first = NaN;
    for (unsigned cols : m_Options.DetectorColumns)
    {
      filter->SetGeometry(MakeGeometry(m_Volume, cols, cols, fieldOfView / cols));
      if (!std::isfinite(first))
        first = WarmUp(filter.GetPointer());
      Row r = detectorRow(cols);
      r.Method = "points";
      r.Sampler = samplerName;
      r.Kernel = KernelName(m_Options.Kernels.front());
      r.Splat = SplatName(m_Options.Splats.front());
      r.Samples = samples;
      r.FirstRender = cols == m_Options.DetectorColumns.front() ? first : NaN;
      r.Time = TimeRenders(filter);
      Add(r);
    }
  }
  auto exact = ExactType::New();
  exact->SetInput(m_Volume);
  for (unsigned cols : m_Options.DetectorColumns)
  {
    Row r = detectorRow(cols);
    r.Method = "exact-siddon";
    r.Kernel = "box";
    r.Rays = 1;
    exact->SetGeometry(MakeGeometry(m_Volume, cols, cols, fieldOfView / cols));
    if (cols == m_Options.DetectorColumns.front())
      r.FirstRender = WarmUp(exact.GetPointer()); // HU -> mu and any first-render work, outside the timings
    r.Time = TimeRenders(exact);
    Add(r);
  }
  if (m_Options.Itk)
  {
    MuImageType::Pointer oriented = WithIdentityDirection(MuImage(m_Volume, exact->GetAttenuationVolume()));
    exact = nullptr;
    for (unsigned cols : m_Options.DetectorColumns)
    {
      if (!oriented)
        break;
      Row r = detectorRow(cols);
      r.Method = "itk-raycast";
      ItkRayCast(oriented, MakeGeometry(m_Volume, cols, cols, fieldOfView / cols), &r.Time);
      Add(r);
    }
  }
}
} // namespace bench
} // namespace pbdrr
