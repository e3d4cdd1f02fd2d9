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
// PointBasedDRRBenchmark --mode collimated: a small detector (--collimated-cols) centred on the view against the same
// crop of the full detector's render, for the exact projectors and every point sampler.
#include "pbdrrBenchmark.h"

#include "itkDRRSamplerFactory.h"

#include <iostream>
#include <stdexcept>

namespace pbdrr
{
namespace bench
{
void
Benchmark::Collimated()
{
  const Geometry full{ m_Options.Columns, m_Options.Rows, m_Options.Spacing };
  const unsigned c = m_Options.CollimatedColumns;
  if (c > full.Columns || c > full.Rows || (full.Columns - c) % 2 || (full.Rows - c) % 2)
    throw std::runtime_error("the collimated detector must be smaller than the full one by an even number of pixels");
  const Geometry small{ c, c, m_Options.Spacing };
  const unsigned c0 = (full.Columns - c) / 2, r0 = (full.Rows - c) / 2;
  m_Geometry = small;
  auto            fullGeometry = MakeGeometry(m_Volume, full.Columns, full.Rows, full.Spacing);
  auto            smallGeometry = MakeGeometry(m_Volume, c, c, small.Spacing);
  const ImageView crop = [&](const Image & image) { return Crop(image, full.Columns, c0, r0, c, c); };
  Row             base;
  base.Config = m_Options.Name;
  base.Voxels = m_Volume->GetLargestPossibleRegion().GetNumberOfPixels();

  // references of the collimated view (the same pixels as the crop of the full view)
  Row refBase = base;
  refBase.Sweep = "collimated";
  refBase.Columns = refBase.DetectorRows = c;
  Reference(m_Volume, smallGeometry, KernelEnum::Box, m_BoxReference, &m_Siddon1, nullptr, refBase);
  Reference(m_Volume, smallGeometry, KernelEnum::Tent, m_TentReference, nullptr, nullptr, refBase);
  {
    // check: the crop of the full view's one-ray image is the collimated view's one-ray image
    auto exact = ExactType::New();
    exact->SetInput(m_Volume);
    exact->SetGeometry(fullGeometry);
    exact->Update();
    Agreement("crop of the full view, Siddon 1 ray",
              "collimated view, Siddon 1 ray",
              crop(ToVector(exact->GetOutput())),
              m_Siddon1);
  }
  for (const std::string view : { "collimated", "crop" })
  {
    Row viewBase = base;
    viewBase.Sweep = view;
    viewBase.Columns = view == std::string("collimated") ? c : full.Columns;
    viewBase.DetectorRows = view == std::string("collimated") ? c : full.Rows;
    itk::DRRProjectionGeometry * geometry = view == std::string("collimated") ? smallGeometry : fullGeometry;
    const ImageView              map = view == std::string("collimated") ? ImageView() : crop;
    for (KernelEnum kernel : m_Options.Kernels)
      ExactRows(m_Volume, geometry, kernel, viewBase, map);
  }
  for (const auto & samplerName : m_Options.Samplers)
    CollimatedPoints(samplerName, smallGeometry, fullGeometry, base, crop);
}

/** The sample ladder of one sampler with every kernel and splat on the collimated detector and on the crop of the
 * full one (one sampling table for both). */
void
Benchmark::CollimatedPoints(const std::string &          samplerName,
                            itk::DRRProjectionGeometry * smallGeometry,
                            itk::DRRProjectionGeometry * fullGeometry,
                            const Row &                  base,
                            const ImageView &            crop)
{
  const auto ladder = SampleLadder(m_Options.MinSamples, m_Options.MaxSamples);
  auto       filter = PointFilterType::New();
  filter->SetInput(m_Volume);
  filter->SetSampler(itk::DRRSamplerFactory::Create(samplerName));
  filter->SetSeed(m_Options.Seed);
  filter->PrepareSampling();
  for (KernelEnum kernel : m_Options.Kernels)
  {
    const Image & own = kernel == KernelEnum::Box ? m_BoxReference : m_TentReference;
    for (SplatEnum splat : m_Options.Splats)
    {
      filter->SetReconstructionKernel(kernel);
      filter->SetSplat(splat);
      for (const std::string view : { "collimated", "crop" })
      {
        const bool collimated = view == std::string("collimated");
        filter->SetGeometry(collimated ? smallGeometry : fullGeometry);
        Row row = base;
        row.Sweep = view;
        row.Columns = collimated ? m_Options.CollimatedColumns : m_Options.Columns;
        row.DetectorRows = collimated ? m_Options.CollimatedColumns : m_Options.Rows;
        row.Sampler = samplerName;
        row.Kernel = KernelName(kernel);
        row.Splat = SplatName(splat);
        row.Model = KernelName(kernel);
        LadderStyle style;
        style.View = collimated ? ImageView() : crop;
        style.BudgetInNote = false;
        style.CatchErrors = false;
        LadderRows(filter, ladder, row, own, style);
      }
    }
  }
}
} // namespace bench
} // namespace pbdrr
