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
#include "itkDRRRenderPlan.h"
#include "itkDRRCompilerBuiltins.h"
#include "itkDRRPolicies.h"

#include <algorithm>
#include <cmath>

namespace itk
{
namespace DRRRendering
{
Strata::Strata(uint64_t numberOfSamples, uint64_t numberOfStrata, bool interleaved)
  : m_NumberOfStrata(numberOfStrata), m_Interleaved(interleaved && numberOfStrata > 1)
{
  if (m_Interleaved)
  {
    m_InterleavedSize = (numberOfSamples + numberOfStrata - 1) / numberOfStrata;
    m_First = { 0, m_InterleavedSize * numberOfStrata };
    return;
  }
  for (uint64_t r = 0; r <= numberOfStrata; ++r)
  {
    m_First.push_back(DRRMultiplyDivide64(numberOfSamples, r, numberOfStrata));
  }
}

uint64_t
Strata::RunOfSample(uint64_t sample) const
{
  return static_cast<uint64_t>(std::upper_bound(m_First.begin(), m_First.end(), sample) - m_First.begin()) - 1;
}

Strata
MakeStrata(const DRRSamplerTraits & traits, const DRRPointRenderer::Settings & settings)
{
  // Dependent points (stratified, Markov chains): independent strata, whose spread gives the standard error.
  const uint64_t requestedStrata = DRRPointRenderer::RequestedNumberOfStrata(traits, settings.NumberOfStrata);
  const bool     useStrata =
    requestedStrata > 1 && DRRPointRenderer::HasEnoughSamplesPerStratum(settings.NumberOfSamples, requestedStrata);
  return Strata(settings.NumberOfSamples, useStrata ? requestedStrata : 1, traits.InterleavesStrata);
}

namespace
{
/** Largest k with count * bound * 2^k <= 2^62, so that no sum of count contributions <= bound overflows. */
int
FixedPointExponent(double count, double bound)
{
  return static_cast<int>(std::floor(62.0 - std::log2(std::max(count * bound, 1e-300))));
}
} // namespace

/** With a source, the weight grows as (SID / z)^2 (a localizer: SID / z) near the source; if the points (inside the
 * continuous-index box [lower, upper]) come that close, drops those nearer than the depth that keeps at least 20
 * fractional bits (the dropped part of each ray is shorter than that depth), through the projection's minimum depth,
 * and says so in the result. */
FixedPoint
PlanFixedPoint(double                        numberOfSamples,
               double                        maximumWeight,
               const std::array<double, 3> & lower,
               const std::array<double, 3> & upper,
               bool                          unbiased,
               DRRPointProjection &          projection,
               DRRPointRenderer::Result &    result)
{
  const double N = numberOfSamples;
  double       contributionBound = maximumWeight;
  if (projection.IsPerspective() && unbiased)
  {
    double nearest, farthest;
    projection.ComputeDepthRange(lower, upper, nearest, farthest);
    const double largestAffordableWeight = std::ldexp(1.0, 42) / (N * maximumWeight);
    const double depthCut = projection.GetDepthOfWeight(largestAffordableWeight);
    // Only a volume whose depth range reaches into (0, depthCut) comes near the source; one wholly behind it does not.
    result.SourceNearVolume = nearest < depthCut && farthest > 0.0;
    const double minimumDepth = std::max(depthCut, nearest);
    projection.SetMinimumDepth(result.SourceNearVolume ? depthCut : 0.0);
    result.MinimumDepth = result.SourceNearVolume ? depthCut : 0.0;
    contributionBound *= projection.GetWeightBound(minimumDepth);
  }
  FixedPoint fixedPoint;
  fixedPoint.SumExponent = FixedPointExponent(N, contributionBound);
  fixedPoint.SquareExponent = FixedPointExponent(N, contributionBound * contributionBound);
  // Each contribution is at most 2^62 / N in fixed point (both sums): below 2^51 from N = 2^11 on.
  fixedPoint.Small = N >= 4096.0;
  return fixedPoint;
}

void
VerifyNumberOfSamples(const DRRPointRenderer::Settings & settings)
{
  if (settings.NumberOfSamples < DRRPointRenderer::MinimumNumberOfSamples)
  {
    itkGenericExceptionMacro("DRRPointRenderer: the number of samples must be at least 1");
  }
}

void
VerifyChannels(const DRRPointRenderer::Settings & settings)
{
  if (settings.NumberOfChannels < 1 || settings.NumberOfChannels > 256)
  {
    itkGenericExceptionMacro("DRRPointRenderer: the number of channels must be 1 to 256, not "
                             << settings.NumberOfChannels);
  }
  if (settings.NumberOfChannels > 1 && !settings.VoxelChannels)
  {
    itkGenericExceptionMacro("DRRPointRenderer: " << settings.NumberOfChannels
                                                  << " channels need the channel of every voxel (VoxelChannels)");
  }
}

DRRPointRenderer::Result
ZeroResult(const DRRPointProjection & projection, unsigned int numberOfChannels)
{
  const size_t numberOfPixels =
    static_cast<size_t>(projection.GetNumberOfColumns()) * static_cast<size_t>(projection.GetNumberOfRows());
  DRRPointRenderer::Result result;
  result.LineIntegral.assign(numberOfPixels, 0.0);
  result.StandardError.assign(numberOfPixels, 0.0);
  if (numberOfChannels > 1)
  {
    result.NumberOfChannels = numberOfChannels;
    result.ChannelLineIntegral.assign(numberOfPixels * numberOfChannels, 0.0);
    result.ChannelCovariance.assign(numberOfPixels * numberOfChannels * (numberOfChannels + 1) / 2, 0.0);
  }
  return result;
}

void
KernelSupport(PointBasedDRREnums::ReconstructionKernel kernel,
              const std::array<uint64_t, 3> &          size,
              std::array<double, 3> &                  lower,
              std::array<double, 3> &                  upper)
{
  const double reach = KernelReach(kernel);
  for (unsigned int a = 0; a < 3; ++a)
  {
    lower[a] = -reach;
    upper[a] = static_cast<double>(size[a]) - 1.0 + reach;
  }
}

double
KernelReach(PointBasedDRREnums::ReconstructionKernel kernel)
{
  return DRRPolicies::Kernels::Visit(kernel, [](auto policy) { return decltype(policy)::Reach; });
}

double
SplatReach(PointBasedDRREnums::Splat splat)
{
  return DRRPolicies::Splats::Visit(splat, [](auto policy) { return decltype(policy)::Reach; });
}
} // namespace DRRRendering
} // namespace itk
