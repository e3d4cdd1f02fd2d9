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
// PointBasedDRRBenchmark --mode trade: the exact references of one view, the exact projectors, ITK's ray caster,
// plastimatch and every point sampler with every kernel and splat along the sample ladder; and the point-sampler
// rows (preprocessing and the sample ladder) the other modes share.
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
Benchmark::Trade()
{
  Row              base = StartView();
  const Geometry & g = m_Geometry;
  auto             geometry = MakeGeometry(m_Volume, g.Columns, g.Rows, g.Spacing);
  base.Sweep = "trade";
  base.Voxels = m_Volume->GetLargestPossibleRegion().GetNumberOfPixels();

  std::cerr << "references (" << m_Options.ReferenceRays << " x " << m_Options.ReferenceRays << " rays per pixel)"
            << std::endl;
  MuImageType::Pointer mu;
  Reference(m_Volume, geometry, KernelEnum::Box, m_BoxReference, &m_Siddon1, &mu, base);
  Reference(m_Volume, geometry, KernelEnum::Tent, m_TentReference, &m_Trilinear1, nullptr, base);
  m_Mu = WithIdentityDirection(mu);
  mu = nullptr;
  Agreement("exact Siddon, 1 ray per pixel", "exact trilinear, 1 ray per pixel", m_Siddon1, m_Trilinear1);
  Agreement("reference box", "reference tent", m_BoxReference, m_TentReference);
  if (m_Options.SaveImages)
  {
    WriteProjection(m_BoxReference, g.Columns, g.Rows, g.Spacing, m_Options.WorkDirectory + "/reference_box.mha");
    WriteProjection(m_TentReference, g.Columns, g.Rows, g.Spacing, m_Options.WorkDirectory + "/reference_tent.mha");
    WriteProjection(m_Siddon1, g.Columns, g.Rows, g.Spacing, m_Options.WorkDirectory + "/siddon1.mha");
  }

  std::cerr << "exact projectors" << std::endl;
  for (KernelEnum kernel : { KernelEnum::Box, KernelEnum::Tent })
    ExactRows(m_Volume, geometry, kernel, base);

  if (m_Options.Itk)
    ItkRows(base, geometry);
  if (m_Mu)
    PlastimatchRows(base);
  m_Mu = nullptr;

  std::cerr << "point samplers" << std::endl;
  for (const auto & sampler : m_Options.Samplers)
  {
    try
    {
      SamplerRows(sampler, m_Volume, base);
    }
    catch (const std::exception & e)
    {
      Row row = base;
      row.Method = "points";
      row.Sampler = sampler;
      row.Status = "failed";
      row.Note = e.what();
      Add(row);
    }
  }
}

/** ITK's ray caster on the mu volume, and on the same padded with one layer of zeros (agreement only). */
void
Benchmark::ItkRows(const Row & base, itk::DRRProjectionGeometry * geometry)
{
  const Geometry & g = m_Geometry;
  std::cerr << "ITK ray caster" << std::endl;
  Row row = base;
  row.Method = "itk-raycast";
  row.Model = "tent";
  if (!m_Mu)
  {
    row.Status = "failed";
    row.Note = "the volume's direction is not axis-aligned: ITK's ray caster ignores it";
    Add(row);
    return;
  }
  const Image image = ItkRayCast(m_Mu, geometry, &row.Time);
  row.Note = "ResampleImageFilter + RayCastInterpolateImageFunction, threshold 0, float mu volume";
  Add(row, &image, &m_TentReference);
  Agreement("ITK ray caster", "exact Siddon, 1 ray per pixel", image, m_Siddon1);
  Agreement("ITK ray caster", "exact trilinear, 1 ray per pixel", image, m_Trilinear1);
  // the outer half-voxel shell: ITK's ray caster on the volume padded with one layer of zeros
  const Image padded = ItkRayCast(PadWithZeros(m_Mu), geometry, nullptr);
  Agreement("ITK ray caster, volume padded with zeros", "exact Siddon, 1 ray per pixel", padded, m_Siddon1);
  Agreement("ITK ray caster, volume padded with zeros", "exact trilinear, 1 ray per pixel", padded, m_Trilinear1);
  if (m_Options.SaveImages)
  {
    WriteProjection(image, g.Columns, g.Rows, g.Spacing, m_Options.WorkDirectory + "/itk_raycast.mha");
    WriteProjection(padded, g.Columns, g.Rows, g.Spacing, m_Options.WorkDirectory + "/itk_raycast_padded.mha");
  }
}

/** The preprocessing of a point filter (HU -> mu, sampling tables), timed once: the row's method is "preprocess". */
Row
Benchmark::Preprocess(PointFilterType * filter, Row row) const
{
  double huToMu = NaN, tables = NaN;
  row.Method = "preprocess";
  row.Time = Measure(
    [&] {
      double start = Now();
      filter->GetAttenuationVolume();
      huToMu = Now() - start;
      start = Now();
      filter->PrepareSampling();
      tables = Now() - start;
    },
    1,
    0.0);
  row.HuToMu = huToMu;
  row.Tables = tables;
  row.TableBytes = static_cast<double>(filter->GetSampler()->GetTableSizeInBytes());
  return row;
}

/** Preprocessing and the sample ladder of one sampler with every kernel and splat. */
void
Benchmark::SamplerRows(const std::string & samplerName, const VolumeType * volume, Row base)
{
  auto filter = PointFilterType::New();
  filter->SetInput(volume);
  filter->SetGeometry(MakeGeometry(volume, m_Geometry.Columns, m_Geometry.Rows, m_Geometry.Spacing));
  filter->SetSampler(itk::DRRSamplerFactory::Create(samplerName));
  filter->SetSeed(m_Options.Seed);
  base.Sampler = samplerName;
  {
    Row row = Preprocess(filter, base);
    if (m_NonAirVoxels == 0)
      m_NonAirVoxels = CountNonAir(volume, filter->GetTransferFunction());
    row.TableBytesPerVoxel = row.TableBytes / std::max<uint64_t>(1, m_NonAirVoxels);
    row.Note = "HU->mu + sampling tables, once per volume";
    Add(row);
  }
  const auto ladder = SampleLadder(m_Options.MinSamples, m_Options.MaxSamples);
  for (KernelEnum kernel : m_Options.Kernels)
  {
    const Image & own = kernel == KernelEnum::Box ? m_BoxReference : m_TentReference;
    for (SplatEnum splat : m_Options.Splats)
    {
      filter->SetReconstructionKernel(kernel);
      filter->SetSplat(splat);
      Row row = base;
      row.Kernel = KernelName(kernel);
      row.Splat = SplatName(splat);
      row.Model = KernelName(kernel);
      LadderRows(filter, ladder, row, own, LadderStyle{});
    }
  }
}

/** The sample ladder of a point filter set up but for the number of samples: one untimed first render, then a row a
 * rung; a rung predicted (from the last one timed or predicted) to take longer than --budget is skipped. */
void
Benchmark::LadderRows(PointFilterType *             filter,
                      const std::vector<uint64_t> & ladder,
                      const Row &                   base,
                      const Image &                 own,
                      const LadderStyle &           style)
{
  filter->SetNumberOfSamples(ladder.empty() ? 1 : ladder.front());
  const double first = WarmUp(filter);
  double       previousTime = NaN;
  uint64_t     previousSamples = 0;
  const auto   render = [&](Row & row) {
    row.Time = TimeRenders(filter);
    Image image = ToVector(filter->GetOutput());
    if (style.View)
      image = style.View(image);
    previousTime = row.Time.Wall;
    previousSamples = row.Samples;
    Add(row, &image, own.empty() ? nullptr : &own);
  };
  for (uint64_t samples : ladder)
  {
    Row row = base;
    row.Method = "points";
    row.Samples = samples;
    row.FirstRender = samples == ladder.front() ? first : NaN;
    const double predicted = previousTime * samples / std::max<uint64_t>(1, previousSamples);
    if (std::isfinite(predicted) && predicted > m_Options.Budget)
    {
      row.Status = "skipped";
      row.Note = "predicted " + Format(predicted, "%.3g") + " s > budget" +
                 (style.BudgetInNote ? " " + Format(m_Options.Budget, "%g") + " s" : std::string());
      previousTime = predicted; // the next rungs are predicted from this one
      previousSamples = samples;
      Add(row);
      continue;
    }
    filter->SetNumberOfSamples(samples);
    if (!style.CatchErrors)
    {
      render(row);
      continue;
    }
    try
    {
      render(row);
    }
    catch (const std::exception & e)
    {
      row.Status = "failed";
      row.Note = e.what();
      Add(row);
    }
  }
}
} // namespace bench
} // namespace pbdrr
