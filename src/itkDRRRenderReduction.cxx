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
#include "itkDRRRenderReduction.h"
#include "itkDRRCompilerBuiltins.h"

#include <algorithm>
#include <cmath>

namespace itk
{
namespace DRRRendering
{
namespace
{
/** total[i] += sum[i], sum[i] = 0 for i < n. */
PointBasedDRR_VECTOR_CLONES void
AddAndClear(int64_t * PointBasedDRR_RESTRICT sum, int64_t * PointBasedDRR_RESTRICT total, size_t n)
{
  for (size_t i = 0; i < n; ++i)
  {
    total[i] += sum[i];
    sum[i] = 0;
  }
}

struct ReduceConstants
{
  double N;                  // samples
  double ValueScale;         // M / (N a)
  double InverseSumScale;    // of the fixed point
  double InverseSquareScale; // of the fixed point
};

/** The line integrals and standard errors of n pixels from their integer sums (pixel major, as the workers'). Each
 * step a loop over the pixels, so that it vectorizes; every pixel adds its terms in the same order as one loop over
 * its strata would. */
PointBasedDRR_VECTOR_CLONES void
ReducePixels(const int64_t *                 total,
             const int64_t *                 totalOfSquares,
             size_t                          n,
             uint64_t                        numberOfStrata,
             const double *                  stratumScale,
             const ReduceConstants &         constants,
             double * PointBasedDRR_RESTRICT lineIntegral,
             double * PointBasedDRR_RESTRICT standardError)
{
  const double        N = constants.N;
  std::vector<double> stratumSums(n * numberOfStrata); // stratum major
  for (uint64_t r = 0; r < numberOfStrata; ++r)
  {
    double * PointBasedDRR_RESTRICT stratumSum = stratumSums.data() + r * n;
    for (size_t p = 0; p < n; ++p)
    {
      stratumSum[p] = static_cast<double>(total[p * numberOfStrata + r]) * constants.InverseSumScale;
    }
  }
  std::vector<double> sums(n, 0.0);
  for (uint64_t r = 0; r < numberOfStrata; ++r)
  {
    const double * stratumSum = stratumSums.data() + r * n;
    for (size_t p = 0; p < n; ++p)
    {
      sums[p] += stratumSum[p];
    }
  }
  for (size_t p = 0; p < n; ++p)
  {
    lineIntegral[p] = constants.ValueScale * sums[p];
  }
  if (numberOfStrata == 1)
  {
    for (size_t p = 0; p < n; ++p)
    {
      const double s = sums[p];
      const double s2 = static_cast<double>(totalOfSquares[p]) * constants.InverseSquareScale;
      const double variance = N > 1.0 ? N / (N - 1.0) * std::max(0.0, s2 - s * s / N) : s2;
      standardError[p] = constants.ValueScale * std::sqrt(variance);
    }
    return;
  }
  // Each stratum is an independent estimate L_r = M / (n_r a) S_r of the same image; the variance of their
  // combination is estimated from their spread.
  std::vector<double> squaredDeviations(n, 0.0);
  for (uint64_t r = 0; r < numberOfStrata; ++r)
  {
    const double * stratumSum = stratumSums.data() + r * n;
    const double   scale = stratumScale[r];
    for (size_t p = 0; p < n; ++p)
    {
      const double estimate = scale * stratumSum[p];
      squaredDeviations[p] += (estimate - lineIntegral[p]) * (estimate - lineIntegral[p]);
    }
  }
  const double pairs = numberOfStrata * (numberOfStrata - 1.0);
  for (size_t p = 0; p < n; ++p)
  {
    standardError[p] = std::sqrt(squaredDeviations[p] / pairs);
  }
}
/** sums[g] = sum over k < K of sums[g K + k], for g < groups: the K channels of every group (a pixel's stratum, or a
 * pixel) added into its first groups entries, in place (entry g is read before it is written, for K > 1). */
void
AddChannelsInPlace(int64_t * sums, size_t groups, size_t K)
{
  for (size_t g = 0; g < groups; ++g)
  {
    int64_t sum = 0;
    for (size_t k = 0; k < K; ++k)
    {
      sum += sums[g * K + k];
    }
    sums[g] = sum;
  }
}

/** The line integral and covariance of K channels of n pixels from their integer sums (slot stratum * K + channel,
 * pixel major); channelLineIntegral holds K values per pixel, channelCovariance K (K + 1) / 2 (upper triangle, row
 * major). Each channel is reduced as a render of its own (ReducePixels()). Between channels: with one stratum, a
 * point adds to one channel only, so sum c_m c_m' = 0 and the covariance estimate from the same sums is
 * -L_m L_m' / (N - 1); with strata, from the spread of the strata's estimates, like a variance. */
void
ReduceChannels(const int64_t *         total,
               const int64_t *         totalOfSquares,
               size_t                  n,
               uint64_t                numberOfStrata,
               unsigned int            numberOfChannels,
               const double *          stratumScale,
               const ReduceConstants & constants,
               double *                channelLineIntegral,
               double *                channelCovariance)
{
  const unsigned int   K = numberOfChannels;
  const size_t         pairsPerPixel = static_cast<size_t>(K) * (K + 1) / 2;
  std::vector<double>  lineIntegral(static_cast<size_t>(K) * n); // channel major
  std::vector<double>  standardError(n);
  std::vector<int64_t> channelTotal(n * numberOfStrata);
  std::vector<int64_t> channelSquares(numberOfStrata == 1 ? n : 0);
  for (unsigned int k = 0; k < K; ++k)
  {
    for (size_t i = 0; i < n * numberOfStrata; ++i)
    {
      channelTotal[i] = total[i * K + k];
    }
    for (size_t p = 0; p < channelSquares.size(); ++p)
    {
      channelSquares[p] = totalOfSquares[p * K + k];
    }
    double * own = lineIntegral.data() + k * n;
    ReducePixels(channelTotal.data(),
                 channelSquares.data(),
                 n,
                 numberOfStrata,
                 stratumScale,
                 constants,
                 own,
                 standardError.data());
    for (size_t p = 0; p < n; ++p)
    {
      channelLineIntegral[p * K + k] = own[p];
      // The diagonal entry of channel k: (k, k) is entry k K - k (k - 1) / 2 of the row-major upper triangle.
      channelCovariance[p * pairsPerPixel + k * K - k * (k - 1) / 2] = standardError[p] * standardError[p];
    }
  }
  const double N = constants.N;
  for (size_t p = 0; p < n; ++p)
  {
    size_t entry = p * pairsPerPixel;
    for (unsigned int m = 0; m < K; ++m)
    {
      ++entry; // (m, m), written above
      for (unsigned int m2 = m + 1; m2 < K; ++m2, ++entry)
      {
        const double Lm = lineIntegral[m * n + p];
        const double Lm2 = lineIntegral[m2 * n + p];
        if (numberOfStrata == 1)
        {
          channelCovariance[entry] = N > 1.0 ? -Lm * Lm2 / (N - 1.0) : 0.0;
          continue;
        }
        double sum = 0.0;
        for (uint64_t r = 0; r < numberOfStrata; ++r)
        {
          const double scale = stratumScale[r] * constants.InverseSumScale;
          const double em = scale * static_cast<double>(total[(p * numberOfStrata + r) * K + m]);
          const double em2 = scale * static_cast<double>(total[(p * numberOfStrata + r) * K + m2]);
          sum += (em - Lm) * (em2 - Lm2);
        }
        channelCovariance[entry] = sum / (numberOfStrata * (numberOfStrata - 1.0));
      }
    }
  }
}
} // namespace

void
Reduce(DRRPointRenderer::Workspace & workspace,
       const Strata &                strata,
       unsigned int                  numberOfChannels,
       const FixedPoint &            fixedPoint,
       double                        pixelArea,
       MultiThreaderBase *           threader,
       DRRPointRenderer::Result &    result)
{
  std::vector<Worker> & workers = workspace.Workers;
  const uint64_t        numberOfStrata = strata.GetNumberOfStrata();
  const double          N = static_cast<double>(strata.GetNumberOfSamples());
  const double          valueScale = result.SampledRoomMass / (N * pixelArea);
  const double          inverseSumScale = std::ldexp(1.0, -fixedPoint.SumExponent);
  const double          inverseSquareScale = std::ldexp(1.0, -fixedPoint.SquareExponent);
  std::vector<double>   stratumScale(numberOfStrata); // M / (n_r a), the same for every pixel
  for (uint64_t r = 0; r < numberOfStrata; ++r)
  {
    stratumScale[r] = result.SampledRoomMass / (strata.Size(r) * pixelArea);
  }
  const ReduceConstants constants{ N, valueScale, inverseSumScale, inverseSquareScale };
  const size_t          numberOfPixels = result.LineIntegral.size();
  const size_t          K = numberOfChannels;
  const size_t          slots = numberOfStrata * K;
  const auto            reduceBlock = [&](size_t firstPixel, size_t endPixel) {
    // First the workers' sums of the block, added (and cleared) in one pass over contiguous memory, then the pixels.
    const size_t         n = endPixel - firstPixel;
    std::vector<int64_t> total(n * slots, 0);
    std::vector<int64_t> totalOfSquares(numberOfStrata == 1 ? n * K : 0, 0);
    for (Worker & worker : workers)
    {
      AddAndClear(worker.Sums.Sum.data() + firstPixel * slots, total.data(), total.size());
      if (numberOfStrata == 1)
      {
        AddAndClear(worker.Sums.SumOfSquares.data() + firstPixel * K, totalOfSquares.data(), totalOfSquares.size());
      }
    }
    if (K > 1)
    {
      ReduceChannels(total.data(),
                     totalOfSquares.data(),
                     n,
                     numberOfStrata,
                     numberOfChannels,
                     stratumScale.data(),
                     constants,
                     result.ChannelLineIntegral.data() + firstPixel * K,
                     result.ChannelCovariance.data() + firstPixel * K * (K + 1) / 2);
      // The image: the channels' integer sums added, the same integers as a render without channels.
      AddChannelsInPlace(total.data(), n * numberOfStrata, K);
      AddChannelsInPlace(totalOfSquares.data(), totalOfSquares.size() / K, K);
    }
    ReducePixels(total.data(),
                 totalOfSquares.data(),
                 n,
                 numberOfStrata,
                 stratumScale.data(),
                 constants,
                 result.LineIntegral.data() + firstPixel,
                 result.StandardError.data() + firstPixel);
  };
  constexpr size_t pixelsPerBlock = 2048;
  const size_t     numberOfBlocks = (numberOfPixels + pixelsPerBlock - 1) / pixelsPerBlock;
  if (numberOfBlocks > 1)
  {
    threader->ParallelizeArray(
      0,
      numberOfBlocks,
      [&](SizeValueType block) {
        reduceBlock(block * pixelsPerBlock, std::min(numberOfPixels, (block + 1) * pixelsPerBlock));
      },
      nullptr);
  }
  else
  {
    reduceBlock(0, numberOfPixels);
  }
  result.NumberOfStrata = numberOfStrata;
  result.NumberOfChannels = numberOfChannels > 1 ? numberOfChannels : 0;
  result.NumberOfSamples = strata.GetNumberOfSamples();
  for (Worker & worker : workers)
  {
    result.PointsOnDetector += worker.Sums.PointsOnDetector;
    // The trash slots, past the pixels.
    std::fill(worker.Sums.Sum.begin() + numberOfPixels * slots, worker.Sums.Sum.end(), 0);
    std::fill(worker.Sums.SumOfSquares.begin() + std::min(numberOfPixels * K, worker.Sums.SumOfSquares.size()),
              worker.Sums.SumOfSquares.end(),
              0);
  }
  workspace.Cleared = true;
}
} // namespace DRRRendering
} // namespace itk
