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
#include "itkDRRPointRenderer.h"
#include "itkDRRBilinearSplat.h"
#include "itkDRRBoxKernel.h"
#include "itkDRRNearestSplat.h"
#include "itkDRRTentKernel.h"
#include "itkDRRWorkScheduler.h"

#include <algorithm>
#include <cmath>
#include <memory>

namespace itk
{
namespace
{
constexpr uint64_t samplesPerBatch = 512;

/** Integer fixed-point accumulators of one worker: per pixel the sum of contributions of every stratum (stratum
 * major), and, with a single stratum, the sum of their squares. */
struct Accumulator
{
  std::vector<int64_t> Sum;
  std::vector<int64_t> SumOfSquares;
  uint64_t             PointsOnDetector{ 0 };
};

/** Where one chunk deposits: its stratum's sums, and the squares (null with several strata). */
struct Target
{
  int64_t *  Sum;
  int64_t *  SumOfSquares;
  uint64_t * PointsOnDetector;
};

/** The strata of a render: R runs of consecutive samples, of N / R samples each (up to one). */
class Strata
{
public:
  Strata(uint64_t numberOfSamples, uint64_t numberOfStrata)
  {
    for (uint64_t r = 0; r <= numberOfStrata; ++r)
    {
      m_First.push_back(static_cast<uint64_t>((static_cast<unsigned __int128>(numberOfSamples) * r) / numberOfStrata));
    }
  }
  uint64_t
  GetNumberOfStrata() const
  {
    return m_First.size() - 1;
  }
  uint64_t
  StratumOfSample(uint64_t sample) const
  {
    return static_cast<uint64_t>(std::upper_bound(m_First.begin(), m_First.end(), sample) - m_First.begin()) - 1;
  }
  uint64_t
  FirstSample(uint64_t stratum) const
  {
    return m_First[stratum];
  }
  uint64_t
  Size(uint64_t stratum) const
  {
    return m_First[stratum + 1] - m_First[stratum];
  }

private:
  std::vector<uint64_t> m_First;
};

/** Largest k with count * bound * 2^k <= 2^62, so that no sum of count contributions <= bound overflows. */
int
FixedPointExponent(double count, double bound)
{
  return static_cast<int>(std::floor(62.0 - std::log2(std::max(count * bound, 1e-300))));
}

/** Renders whole chunks; one instantiation per reconstruction kernel and splat, chosen once per render. */
class ChunkRendererBase
{
public:
  virtual ~ChunkRendererBase() = default;
  virtual void
  Render(uint64_t chunk, const Strata & strata, Accumulator & accumulator) const = 0;
};

template <typename TKernel, typename TSplat>
class ChunkRenderer : public ChunkRendererBase
{
public:
  ChunkRenderer(const DRRAttenuationVolume &       volume,
                const DRRPointSampler &            sampler,
                const DRRPointProjection &         projection,
                const DRRPointRenderer::Settings & settings,
                double                             sumScale,
                double                             squareScale)
    : m_Sampler(sampler)
    , m_Projection(projection)
    , m_Settings(settings)
    , m_NX(volume.GetSize()[0])
    , m_NXY(volume.GetSize()[0] * volume.GetSize()[1])
    , m_Columns(static_cast<int64_t>(projection.GetNumberOfColumns()))
    , m_Rows(static_cast<int64_t>(projection.GetNumberOfRows()))
    , m_SumScale(sumScale)
    , m_SquareScale(squareScale)
  {}

  void
  Render(uint64_t chunk, const Strata & strata, Accumulator & accumulator) const override
  {
    const uint64_t  pixels = static_cast<uint64_t>(m_Columns * m_Rows);
    const uint64_t  end = std::min((chunk + 1) * DRRPointRenderer::SamplesPerChunk, m_Settings.NumberOfSamples);
    DRRPhiloxRandom samplerStream(m_Settings.Seed, chunk, 0);
    DRRPhiloxRandom kernelStream(m_Settings.Seed, chunk, 1);
    uint64_t        voxels[samplesPerBatch];
    double          weights[samplesPerBatch];
    uint32_t        jitter[3 * samplesPerBatch];
    const bool      providesJitter = m_Sampler.ProvidesJitter();
    DRRPointSampler::SampleRange range;
    range.Seed = m_Settings.Seed;
    for (range.First = chunk * DRRPointRenderer::SamplesPerChunk; range.First < end; range.First += range.Count)
    {
      // A batch never straddles two strata.
      range.Stratum = strata.StratumOfSample(range.First);
      range.StratumFirst = strata.FirstSample(range.Stratum);
      range.StratumSize = strata.Size(range.Stratum);
      range.Count =
        std::min({ samplesPerBatch, end - range.First, range.StratumFirst + range.StratumSize - range.First });
      const Target target{ accumulator.Sum.data() + (strata.GetNumberOfStrata() > 1 ? range.Stratum * pixels : 0),
                           accumulator.SumOfSquares.empty() ? nullptr : accumulator.SumOfSquares.data(),
                           &accumulator.PointsOnDetector };
      m_Sampler.GenerateBatch(samplerStream, range, voxels, weights);
      if (providesJitter)
      {
        m_Sampler.GenerateJitter(range, jitter);
      }
      for (uint64_t i = 0; i < range.Count; ++i)
      {
        double point[3];
        this->PlaceInVoxel(voxels[i],
                           providesJitter
                             ? DRRPhiloxRandom::BlockType{ { jitter[3 * i], jitter[3 * i + 1], jitter[3 * i + 2], 0 } }
                             : kernelStream.Next(),
                           point);
        double column, row, perspectiveWeight;
        if (!m_Projection.Project(point, column, row, perspectiveWeight))
        {
          continue;
        }
        const double weight =
          weights[i] * (m_Settings.Weighting == PointBasedDRREnums::PointWeighting::Unbiased ? perspectiveWeight : 1.0);
        const bool landed = TSplat::Deposit(column, row, weight, m_Columns, m_Rows, [&](int64_t pixel, double share) {
          this->Add(pixel, share, target);
        });
        *target.PointsOnDetector += landed ? 1 : 0;
      }
    }
  }

private:
  void
  PlaceInVoxel(uint64_t voxel, const DRRPhiloxRandom::BlockType & bits, double point[3]) const
  {
    const uint64_t k = voxel / m_NXY;
    const uint64_t rest = voxel - k * m_NXY;
    const uint64_t j = rest / m_NX;
    const uint64_t i = rest - j * m_NX;
    const double   centre[3] = { static_cast<double>(i), static_cast<double>(j), static_cast<double>(k) };
    for (unsigned int a = 0; a < 3; ++a)
    {
      point[a] = centre[a] + TKernel::Offset(bits[a]);
    }
  }

  void
  Add(int64_t pixel, double contribution, const Target & target) const
  {
    target.Sum[pixel] += std::llrint(contribution * m_SumScale);
    if (target.SumOfSquares)
    {
      target.SumOfSquares[pixel] += std::llrint(contribution * contribution * m_SquareScale);
    }
  }

  const DRRPointSampler &            m_Sampler;
  const DRRPointProjection &         m_Projection;
  const DRRPointRenderer::Settings & m_Settings;
  const uint64_t                     m_NX;
  const uint64_t                     m_NXY;
  const int64_t                      m_Columns;
  const int64_t                      m_Rows;
  const double                       m_SumScale;
  const double                       m_SquareScale;
};
/** The registered splats: calls visit with a value of the splat policy's type. One case per splat. */
template <typename TVisit>
auto
WithSplat(PointBasedDRREnums::Splat splat, TVisit && visit)
{
  switch (splat)
  {
    case PointBasedDRREnums::Splat::Nearest:
      return visit(DRRNearestSplat{});
    case PointBasedDRREnums::Splat::Bilinear:
      return visit(DRRBilinearSplat{});
  }
  itkGenericExceptionMacro("DRRPointRenderer: unknown splat " << splat);
}

/** The registered reconstruction kernels: calls visit with a value of the kernel policy's type. One case per kernel. */
template <typename TVisit>
auto
WithKernel(PointBasedDRREnums::ReconstructionKernel kernel, TVisit && visit)
{
  switch (kernel)
  {
    case PointBasedDRREnums::ReconstructionKernel::Box:
      return visit(DRRBoxKernel{});
    case PointBasedDRREnums::ReconstructionKernel::Tent:
      return visit(DRRTentKernel{});
  }
  itkGenericExceptionMacro("DRRPointRenderer: unknown reconstruction kernel " << kernel);
}
} // namespace

void
DRRPointRenderer::ComputeKernelSupport(const DRRAttenuationVolume & volume,
                                       KernelEnum                   kernel,
                                       std::array<double, 3> &      lower,
                                       std::array<double, 3> &      upper)
{
  const double reach = WithKernel(kernel, [](auto policy) { return decltype(policy)::Reach; });
  for (unsigned int a = 0; a < 3; ++a)
  {
    lower[a] = -reach;
    upper[a] = static_cast<double>(volume.GetSize()[a]) - 1.0 + reach;
  }
}

DRRPointRenderer::Result
DRRPointRenderer::Render(const DRRAttenuationVolume & volume,
                         const DRRPointSampler &      sampler,
                         DRRPointProjection           projection,
                         const Settings &             settings,
                         MultiThreaderBase *          threader,
                         ProcessObject *              progressFilter)
{
  if (settings.NumberOfSamples == 0)
  {
    itkGenericExceptionMacro("DRRPointRenderer: the number of samples must be at least 1");
  }
  const size_t numberOfPixels =
    static_cast<size_t>(projection.GetNumberOfColumns()) * static_cast<size_t>(projection.GetNumberOfRows());
  Result result;
  result.LineIntegral.assign(numberOfPixels, 0.0);
  result.StandardError.assign(numberOfPixels, 0.0);
  result.RoomMass = sampler.GetTotalMass() * projection.GetRoomMassScale();
  if (!(result.RoomMass > 0.0))
  {
    return result; // all air: the exact answer is a zero image
  }

  // Bound the contributions so the fixed-point sums cannot overflow. In perspective, the weight grows as
  // (SID / z)^2 near the source; if the volume comes that close, drop the points nearer than the depth that keeps
  // at least 20 fractional bits (the dropped part of each ray is shorter than that depth).
  const double N = static_cast<double>(settings.NumberOfSamples);
  double       contributionBound = sampler.GetMaximumWeight();
  if (projection.IsPerspective() && settings.Weighting == WeightingEnum::Unbiased)
  {
    std::array<double, 3> lower, upper;
    ComputeKernelSupport(volume, settings.Kernel, lower, upper);
    double nearest, farthest;
    projection.ComputeDepthRange(lower, upper, nearest, farthest);
    const double sid = projection.GetSourceToDetectorDistance();
    const double obliquity = projection.GetMaximumObliquity();
    const double largestAffordableWeight = std::ldexp(1.0, 42) / (N * sampler.GetMaximumWeight());
    const double depthCut = sid * std::sqrt(obliquity / largestAffordableWeight);
    // Only a volume whose depth range reaches into (0, depthCut) comes near the source; one wholly behind it does not.
    result.SourceNearVolume = nearest < depthCut && farthest > 0.0;
    const double minimumDepth = std::max(depthCut, nearest);
    projection.SetMinimumDepth(result.SourceNearVolume ? depthCut : 0.0);
    result.MinimumDepth = result.SourceNearVolume ? depthCut : 0.0;
    contributionBound *= (sid / minimumDepth) * (sid / minimumDepth) * obliquity;
  }
  const int    sumExponent = FixedPointExponent(N, contributionBound);
  const int    squareExponent = FixedPointExponent(N, contributionBound * contributionBound);
  const double sumScale = std::ldexp(1.0, sumExponent);
  const double squareScale = std::ldexp(1.0, squareExponent);
  const std::unique_ptr<ChunkRendererBase> chunkRenderer = WithKernel(settings.Kernel, [&](auto kernel) {
    return WithSplat(settings.Splat, [&](auto splat) -> std::unique_ptr<ChunkRendererBase> {
      return std::make_unique<ChunkRenderer<decltype(kernel), decltype(splat)>>(
        volume, sampler, projection, settings, sumScale, squareScale);
    });
  });

  const uint64_t numberOfChunks = (settings.NumberOfSamples + SamplesPerChunk - 1) / SamplesPerChunk;
  // Dependent points (stratified, Markov chains): independent strata, whose spread gives the standard error.
  const uint64_t requestedStrata =
    settings.NumberOfStrata > 0 ? settings.NumberOfStrata : sampler.GetPreferredNumberOfStrata();
  const bool useStrata =
    !sampler.HasIndependentSamples() && requestedStrata > 1 && settings.NumberOfSamples >= 16 * requestedStrata;
  const Strata             strata(settings.NumberOfSamples, useStrata ? requestedStrata : 1);
  const uint64_t           numberOfStrata = strata.GetNumberOfStrata();
  std::vector<Accumulator> accumulators(DRRWorkScheduler::GetNumberOfWorkers(threader, numberOfChunks));
  for (Accumulator & accumulator : accumulators)
  {
    accumulator.Sum.assign(numberOfPixels * numberOfStrata, 0);
    if (numberOfStrata == 1)
    {
      accumulator.SumOfSquares.assign(numberOfPixels, 0);
    }
  }
  DRRWorkScheduler::Run(
    threader,
    numberOfChunks,
    [&](unsigned int worker, uint64_t chunk) { chunkRenderer->Render(chunk, strata, accumulators[worker]); },
    progressFilter);

  // Integer reduction: exact, hence independent of the order and of the worker that held each chunk.
  const double        valueScale = result.RoomMass / (N * projection.GetPixelArea());
  const double        inverseSumScale = std::ldexp(1.0, -sumExponent);
  const double        inverseSquareScale = std::ldexp(1.0, -squareExponent);
  std::vector<double> stratumSums(numberOfStrata);
  for (size_t p = 0; p < numberOfPixels; ++p)
  {
    double s = 0.0;
    for (uint64_t r = 0; r < numberOfStrata; ++r)
    {
      int64_t sum = 0;
      for (const Accumulator & accumulator : accumulators)
      {
        sum += accumulator.Sum[r * numberOfPixels + p];
      }
      stratumSums[r] = static_cast<double>(sum) * inverseSumScale;
      s += stratumSums[r];
    }
    result.LineIntegral[p] = valueScale * s;
    if (numberOfStrata == 1)
    {
      int64_t sumOfSquares = 0;
      for (const Accumulator & accumulator : accumulators)
      {
        sumOfSquares += accumulator.SumOfSquares[p];
      }
      const double s2 = static_cast<double>(sumOfSquares) * inverseSquareScale;
      const double variance = settings.NumberOfSamples > 1 ? N / (N - 1.0) * std::max(0.0, s2 - s * s / N) : s2;
      result.StandardError[p] = valueScale * std::sqrt(variance);
    }
    else
    {
      // Each stratum is an independent estimate L_r = M / (n_r a) S_r of the same image; the variance of their
      // combination is estimated from their spread.
      double squaredDeviations = 0.0;
      for (uint64_t r = 0; r < numberOfStrata; ++r)
      {
        const double estimate = result.RoomMass / (strata.Size(r) * projection.GetPixelArea()) * stratumSums[r];
        squaredDeviations += (estimate - result.LineIntegral[p]) * (estimate - result.LineIntegral[p]);
      }
      result.StandardError[p] = std::sqrt(squaredDeviations / (numberOfStrata * (numberOfStrata - 1.0)));
    }
  }
  result.NumberOfStrata = numberOfStrata;
  for (const Accumulator & accumulator : accumulators)
  {
    result.PointsOnDetector += accumulator.PointsOnDetector;
  }
  return result;
}
} // namespace itk
